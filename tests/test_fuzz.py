"""Fuzzing: every saved crash input (tests/fuzz_regressions/) and a short bounded fuzz pass.

tools/fuzz.py finds the inputs; a crash is any exception other than the documented errors
(SvgError / ValueError with a message for documents, none at all for path data, FontError for
fonts) or an input that runs too long. Inputs of bugs that are still open are expected to fail
(``xfail``, not strict): the test turns into a pass as soon as the bug is fixed.
"""
import os
import sys

import pytest

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(REPO, "tools"))
import fuzz  # noqa: E402

FOLDER = os.path.join(REPO, "tests", "fuzz_regressions")
#: seconds before an input counts as a hang
HANG = 5

#: still-open bugs found by the fuzzer, by the file (and exception) they escape from; the
#: bounded pass tolerates these signatures so that it reports only new ones
OPEN_BUGS: dict = {}  # (kind, file or "Timeout") -> why it is still open


def signature(key):
    """'svg:AttributeError:masking.py:125' → ('svg', 'masking.py'); 'svg:Timeout' →
    ('svg', 'Timeout')."""
    parts = key.split(":")
    if parts[1] == "Timeout":
        return parts[0], "Timeout"
    return parts[0], parts[2] if len(parts) > 2 else "?"


def regression_inputs():
    if not os.path.isdir(FOLDER):
        return []
    out = []
    for name in sorted(os.listdir(FOLDER)):
        if name.endswith(".why") or name.startswith("."):
            continue
        target = name.split("-", 1)[0]
        if target in fuzz.EXTENSIONS:
            out.append(name)
    return out


def open_bug(name):
    why = os.path.join(FOLDER, name + ".why")
    if not os.path.exists(why):
        return None
    with open(why) as f:
        key = f.readline().strip()
    return OPEN_BUGS.get(signature(key)) if ":" in key else None


@pytest.fixture(scope="module")
def warm():
    fuzz.warm_up()


@pytest.mark.parametrize("name", regression_inputs())
def test_saved_crash_input_fails_only_with_documented_errors(name, warm, request):
    reason = open_bug(name)
    if reason:
        request.applymarker(pytest.mark.xfail(reason=f"open bug: {reason}", strict=False))
    target = name.split("-", 1)[0]
    with open(os.path.join(FOLDER, name), "rb") as f:
        data = f.read()
    item = data.decode("utf-8", "surrogatepass") if target == "pathdata" else data
    result = fuzz.run_one(target, item, HANG)
    assert result is None, f"{name}: {result[0]}: {result[1][:300]}"


def test_regression_folder_has_inputs():
    assert regression_inputs(), "tests/fuzz_regressions/ should hold the fuzzer's finds"


def test_bounded_fuzz_pass_finds_no_new_crash(warm):
    """About 20 s of fuzzing with a fixed seed (suite SVGs when ../shared is present, fixture
    fonts and built-in seeds otherwise); known open bugs are tolerated, anything else fails."""
    report = fuzz.fuzz(seconds=18, targets=("svg", "pathdata", "font"), seed=20261122, save=None,
                       timeout=HANG, log=lambda s: None)
    tried = sum(t["inputs"] for t in report["targets"].values())
    assert tried > 50
    new = {key: info["message"] for t in report["targets"].values()
           for key, info in t["crashes"].items() if signature(key) not in OPEN_BUGS}
    assert not new, f"new crashes: {new}"


def test_tree_mutations_stay_within_their_size_budget():
    """Every copying operation of the svgtree target is cut to fit MAX_TREE_CHARS, measured
    on the serialised tree: a seed holding a 300-deep nest of 300 children, or a few elements
    carrying a 100,000-character attribute, mutated again and again, never outgrows it (runs
    took the fuzzer's own memory serialising a thousand copies of such a nest, and 200,000
    elements with a donor's long path data)."""
    import copy
    import random
    import xml.etree.ElementTree as ET

    wide = ET.Element("g")
    for _ in range(300):
        ET.SubElement(wide, "rect")
    deep = nest = ET.Element("svg")
    for _ in range(300):
        deep = ET.SubElement(deep, "g")
    deep.append(wide)
    long = ET.Element("svg")
    for _ in range(3):
        ET.SubElement(ET.SubElement(long, "g"), "path", d="M0 0 L1 1 " * 10_000)
    for seed, root in ((7, nest), (8, long)):
        rng = random.Random(seed)
        tree = root
        for _ in range(12):        # each reaches the budget within these
            tree = fuzz.mutate_tree(copy.deepcopy(tree), rng, [root])
            assert len(fuzz.serialize_tree(tree)) <= fuzz.MAX_TREE_CHARS * 1.05
