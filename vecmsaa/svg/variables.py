"""CSS custom properties (``--name: value``) and ``var()`` (CSS Custom Properties for Cascading
Variables Module Level 1).

The cascade (document._specified) keeps custom properties with the other declarations and
leaves every value holding a ``var()`` as an :class:`Unresolved` string. They are resolved
here, per element, against the custom properties it inherits: first down the document tree
when the document is loaded (:func:`substitute_document`: what paint servers, markers, masks
and clip paths, which inherit from where they are defined, and every reader of an element's
``specified`` values see), then again for content instantiated by ``<use>`` whose
``<use>`` gives other values (document.Style.child, through :class:`Pending`).

Custom properties are always inherited; their values are token sequences kept as written
(trimmed). ``var(--name)`` and ``var(--name, fallback)`` are replaced by the value; a missing
or invalid variable without fallback, a reference cycle (§2.3, only through the references
actually followed: a fallback not taken makes no cycle, as in Chromium 150), or a result over
MAX_VAR_LENGTH makes the property invalid at computed-value time: it is then unset (its
inherited value if inherited, else its initial one, §3.1), and a custom property gets the
guaranteed-invalid value (``initial`` too), which ``var()`` cannot use. Substituted tokens do
not join their neighbours (``var(--n)px`` is a number then an identifier).
"""
from __future__ import annotations

import functools
import re

#: characters one substituted value may have: Chromium 150 takes a doubling chain of
#: custom properties to 2,097,151 characters and refuses the next (4,194,303), so its
#: limit is about this (docs/svg.md, session 25, custom properties)
MAX_VAR_LENGTH = 2 * 1024 * 1024
#: characters substituted in one document at most (each substitution's result counted):
#: past it the document is refused, so no chain of variables, however repeated over
#: elements, costs unbounded time or memory
MAX_VAR_EXPANSION = 64 * 1024 * 1024

#: a var() function (the function name is ASCII case-insensitive)
VAR = re.compile(r"var\(", re.I)
#: a custom property's guaranteed-invalid value (its initial value) in a specified dict:
#: no value text can hold a NUL (XML forbids it; CSS reads an escaped one as U+FFFD)
INVALID = "\0"
_CSS_WIDE = frozenset(("inherit", "unset", "revert", "revert-layer"))
#: characters of a token that would run on into the next one (an identifier, number,
#: dimension or hash); a substituted value is kept apart from such neighbours by a space
_JOINING = re.compile(r"[\w\-.%#\\\x80-\U0010ffff]")


class Unresolved(str):
    """A declared value holding var(): resolved for each element that uses it.
    ``shorthand``: the shorthand (marker, font) this longhand's value is part of."""

    shorthand = None


def unresolved(name, value):
    """``value`` as an Unresolved string, None when one of its var() is malformed (the
    declaration is then invalid when parsed, and ignored by the cascade, §3)."""
    return None if template(value) is None else Unresolved(value)


def shorthand_pending(shorthand, value, longhands):
    """The longhands of a shorthand whose value holds var(): each waits for the
    shorthand's substituted value (CSS Variables 1 §3, "pending-substitution value")."""
    out = []
    for name in longhands:
        v = Unresolved(value)
        v.shorthand = shorthand
        out.append((name, v))
    return out


@functools.lru_cache(maxsize=4096)
def template(value):
    """``value`` as a tuple of strings and references ``(name, fallback template or
    None)``; None when a var() in it is malformed."""
    import tinycss2

    try:
        return _template(tinycss2.parse_component_value_list(value, skip_comments=True))
    except _Malformed:
        return None


class _Malformed(Exception):
    pass


def _template(tokens):
    import tinycss2
    from tinycss2.ast import FunctionBlock
    from tinycss2.serializer import serialize_name

    out = []
    run = []

    def flush():
        if run:
            out.append(tinycss2.serialize(run))
            run.clear()
    for tok in tokens:
        if tok.type == "error":     # a bad string or url: the declaration is invalid
            raise _Malformed
        if tok.type == "function" and tok.lower_name == "var":
            flush()
            out.append(_reference(tok.arguments))
            continue
        inner = getattr(tok, "arguments", None)
        if inner is None:
            inner = getattr(tok, "content", None)
        if inner is not None and _has_var(inner):
            flush()
            if isinstance(tok, FunctionBlock):
                out.append(serialize_name(tok.name) + "(")
            else:
                out.append({"() block": "(", "[] block": "[", "{} block": "{"}[tok.type])
            out.extend(_template(inner))
            out.append({"[] block": "]", "{} block": "}"}.get(tok.type, ")"))
            continue
        run.append(tok)
    flush()
    return tuple(out)


def _has_var(tokens):
    for tok in tokens:
        if tok.type == "function" and tok.lower_name == "var":
            return True
        inner = getattr(tok, "arguments", None)
        if inner is None:
            inner = getattr(tok, "content", None)
        if inner is not None and _has_var(inner):
            return True
    return False


def _reference(args):
    """(name, fallback template or None) of var()'s arguments: a custom property name,
    then nothing or a comma and the fallback (any tokens, none too)."""
    i = 0
    while i < len(args) and args[i].type in ("whitespace", "comment"):
        i += 1
    if i == len(args) or args[i].type != "ident" or not args[i].value.startswith("--") \
            or len(args[i].value) < 3:
        raise _Malformed
    name = args[i].value
    i += 1
    while i < len(args) and args[i].type in ("whitespace", "comment"):
        i += 1
    if i == len(args):
        return (name, None)
    if args[i].type != "literal" or args[i].value != ",":
        raise _Malformed
    return (name, _template(args[i + 1:]))


def references(tmpl, out):
    """Add the names ``tmpl`` references (fallbacks' too) to the set ``out``."""
    for piece in tmpl:
        if piece.__class__ is not str:
            out.add(piece[0])
            if piece[1] is not None:
                references(piece[1], out)
    return out


class Budget:
    """The characters a document may still substitute (MAX_VAR_EXPANSION)."""

    __slots__ = ("left",)

    def __init__(self):
        self.left = MAX_VAR_EXPANSION

    def charge(self, n):
        self.left -= n
        if self.left < 0:
            from . import SvgError
            raise SvgError(f"custom properties expand to more than {MAX_VAR_EXPANSION} "
                           f"characters (vecmsaa.svg.variables.MAX_VAR_EXPANSION)")


def _expand(tmpl, budget):
    """A generator substituting ``tmpl``: it yields each name it needs and is sent its
    value (None: none, or guaranteed-invalid); it returns the text, or None when the
    result is invalid. Fallbacks are followed only when needed."""
    out = []
    size = 0
    joined = False      # whether the last piece was substituted
    for piece in tmpl:
        substituted = piece.__class__ is not str
        if substituted:
            value = yield piece[0]
            if value is None:
                if piece[1] is None:
                    return None
                value = yield from _expand(piece[1], budget)
                if value is None:
                    return None
        else:
            value = piece
        if not value:
            continue
        if (substituted or joined) and out and _JOINING.match(value[0]) \
                and _JOINING.match(out[-1][-1]):
            value = " " + value        # the tokens stay apart
        size += len(value)
        if size > MAX_VAR_LENGTH:
            return None
        out.append(value)
        joined = substituted
    text = "".join(out)
    budget.charge(len(text))
    return text


def _custom_generator(raw, inherited, name, budget):
    keyword = raw.strip().lower() if len(raw) < 16 else ""
    if keyword in _CSS_WIDE:
        return _constant(inherited(name))
    if keyword == "initial":
        return _constant(None)
    tmpl = template(raw) if VAR.search(raw) else None
    if tmpl is None:    # (a malformed var() never gets here: the cascade drops it)
        return _constant(raw)
    return _stripped(_expand(tmpl, budget))


def _constant(value):
    return value
    yield   # a generator that returns at once


def _stripped(gen):
    value = yield from gen
    return None if value is None else value.strip()


def custom_values(own, inherited, budget):
    """{name: computed value or None (guaranteed-invalid)} of an element's custom property
    declarations ``own`` ({name: declared value}), ``inherited(name)`` giving its parent's.
    References among them are followed without recursion (a chain of thousands is fine),
    and every property on a cycle is invalid (§2.3)."""
    done = {}
    cyclic = set()
    for first in own:
        if first in done:
            continue
        active = {first: 0}
        stack = [(first, _custom_generator(own[first], inherited, first, budget))]
        value = None
        while stack:
            name, gen = stack[-1]
            try:
                wanted = gen.send(value)
            except StopIteration as stop:
                result = stop.value
                if name in cyclic:
                    result = None
                done[name] = result
                del active[name]
                stack.pop()
                value = result
                continue
            if wanted in done:
                value = done[wanted]
            elif wanted in active:
                for n, _ in stack[active[wanted]:]:
                    cyclic.add(n)
                value = None
            elif wanted in own:
                active[wanted] = len(stack)
                stack.append((wanted, _custom_generator(own[wanted], inherited, wanted, budget)))
                value = None
            else:
                value = inherited(wanted)
    return done


def substitute(value, lookup, budget):
    """The text of an Unresolved ``value`` with its var() replaced, ``lookup(name)``
    giving a custom property's computed value (None when it has none); None when invalid
    at computed-value time."""
    tmpl = template(value)
    if tmpl is None:
        return None
    gen = _expand(tmpl, budget)
    sent = None
    try:
        while True:
            sent = lookup(gen.send(sent))
    except StopIteration as stop:
        return None if stop.value is None else stop.value.strip()


def resolve(base, own, props, inherited, budget, warnings):
    """(specified values, {custom name: computed value or None}) of an element: ``base``
    (its values without var()) with its custom properties ``own`` computed and its
    Unresolved values ``props`` substituted; a property invalid at computed-value time is
    left out (unset). ``inherited(name)``: the parent's custom property."""
    customs, values = _resolved(own, props, inherited, budget, warnings)
    out = dict(base)
    for name, value in customs.items():
        out[name] = INVALID if value is None else value
    out.update(values)
    return out, customs


def _resolved(own, props, inherited, budget, warnings):
    """resolve's computed custom properties and substituted values."""
    from .document import INHERITED, _expand_shorthand, _specified

    customs = custom_values(own, inherited, budget) if own else {}

    def lookup(name):
        return customs[name] if name in customs else inherited(name)
    values = {}
    shorthands = {}
    for name, raw in props.items():
        if raw.shorthand is None:
            text = substitute(raw, lookup, budget)
            if text and _valid(name, text):     # (no property takes an empty value)
                values[name] = text
        else:
            key = (raw.shorthand, str(raw))
            expanded = shorthands.get(key)
            if expanded is None:
                text = substitute(raw, lookup, budget)
                expanded = shorthands[key] = dict(_expand_shorthand(raw.shorthand, text)) \
                    if text else {}
            if name in expanded:
                values[name] = expanded[name]
        if name not in values and name in INHERITED:
            # invalid at computed-value time: unset (§3.1), which for an inherited property
            # is its parent's value, over what lies outside the cascade (xml:space, which
            # white-space's reader falls back on when the property is absent)
            values[name] = "inherit"
    return customs, _specified(values, None, None, warnings)


#: properties whose values are a colour (``currentColor`` included)
_COLOR_PROPERTIES = frozenset(("color", "stop-color", "flood-color", "lighting-color"))
_OPACITY_PROPERTIES = frozenset(("opacity", "fill-opacity", "stroke-opacity", "stop-opacity",
                                 "flood-opacity"))


def _valid(name, value):
    """Whether a substituted value is valid for the property ``name``, for the paint, colour,
    opacity and stroke number properties, whose invalid values vecmsaa otherwise reads as
    resvg does (a fill black, an opacity 1, a stroke width 1). A var() is checked once substituted, and an invalid result
    unsets the property (§3.1): an invalid fill inherits its parent's. The other
    properties' readers take substituted values as they take declared ones."""
    if name in ("fill", "stroke"):
        from .builder import valid_paint
        return valid_paint(value)
    if name in _COLOR_PROPERTIES:
        from .color import parse_svg_color
        return parse_svg_color(value) is not None
    if name in _OPACITY_PROPERTIES:
        from .units import valid_opacity
        return valid_opacity(value)
    if name in ("stroke-width", "stroke-dashoffset"):
        from .units import UNIT_PX, eval_calc, split_length

        def length(v, unit):
            return v if unit.lower() in UNIT_PX or unit in ("%", "em", "ex") else None
        return split_length(value) is not None or eval_calc(value, length) is not None
    if name == "stroke-miterlimit":
        from .units import parse_number
        return parse_number(value) is not None
    return True


class Pending:
    """An element's declarations that hold custom properties or var(), as declared, and the
    inherited custom properties its values in the document tree were computed with."""

    __slots__ = ("base", "own", "props", "deps")

    def __init__(self, base, own, props, deps):
        self.base, self.own, self.props, self.deps = base, own, props, deps

    def specified_under(self, element, style):
        """The element's specified values under the Style ``style`` (its parent in the
        rendering tree): those of the document tree unless ``style`` gives another value
        to a custom property they use (content instantiated by <use>)."""
        lookup = style.custom
        for name, value in self.deps.items():
            if lookup(name) != value:
                break
        else:
            return element.specified
        return resolve(self.base, self.own, self.props, lookup, element.source.var_budget,
                       [])[0]


def substitute_document(doc, warnings):
    """Resolve the custom properties and var() of every element down the document tree
    (the SVG elements inside foreign ones from the element around them), recording what
    Style.child needs to resolve them again under a <use> in ``doc.var_raw``."""
    budget = doc.var_budget = Budget()
    visible = {}        # id(element) -> the custom properties its children inherit
    # _resolved by what it depends on: elements repeat the same declarations under the same
    # custom properties (a rule matching thousands), and substitute them once
    memo = {}

    def above(el):
        node = el.parent
        while node is not None:
            found = visible.get(id(node))
            if found is not None:
                return found
            node = node.parent
        return {}
    for top in (doc.root, *doc.detached):
        stack = [(top, above(top))]
        while stack:
            el, inherited = stack.pop()
            own = {}
            props = {}
            for name, value in el.specified.items():
                if name[:2] == "--":
                    own[name] = value
                elif value.__class__ is Unresolved:
                    props[name] = value
            if own or props:
                base = {n: v for n, v in el.specified.items()
                        if n not in own and n not in props}
                names = set(own)
                for raw in (*own.values(), *props.values()):
                    if VAR.search(raw):
                        references(template(raw), names)
                deps = {n: inherited.get(n) for n in names}
                key = (tuple(own.items()), tuple((n, v, v.shorthand) for n, v in props.items()),
                       tuple(deps.items()))
                got = memo.get(key)
                if got is None:
                    got = memo[key] = _resolved(own, props, inherited.get, budget, warnings)
                customs, values = got
                el.specified = dict(base)
                for name, value in customs.items():
                    el.specified[name] = INVALID if value is None else value
                el.specified.update(values)
                doc.var_raw[id(el)] = Pending(base, own, props, deps)
                if customs:
                    inherited = visible[id(el)] = {**inherited, **customs}
            for child in el.children:
                stack.append((child, inherited))
