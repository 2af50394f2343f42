"""Batches on a Dask distributed cluster: ``--scheduler tcp://HOST:8786`` of ``vecmsaa render``,
``golden`` and ``suite`` (the optional extra ``vecmsaa[dask]``; docs/cluster.md).

No shared file system is needed. The client reads each SVG and the files it may load (the
``href`` targets that lie in the folders the renderer allows: the document's folder and
``resources_dir``) and sends them as bytes; a worker writes them into a private temporary folder
laid out as on the client, renders there and sends PNG bytes back. A fonts folder goes to every
worker once (scattered) and is unpacked once per worker process, so the font database, like the
numba kernels, is loaded once per worker and reused for every file it renders.

Outputs equal a local batch byte for byte as long as workers run the same vecmsaa code, which
:class:`Cluster` checks when it connects. A file that fails to render, or whose worker dies,
fails alone: its result is the exception, the batch goes on.
"""
from __future__ import annotations

import atexit
import functools
import gzip
import hashlib
import html
import io
import os
import re
import shutil
import tempfile
import threading
from collections import deque
from dataclasses import dataclass
from pathlib import Path, PurePosixPath
from typing import Callable, Iterable, Iterator

# numpy, distributed and the renderer are imported where used (a batch that runs on a cluster
# imports this module; the --scheduler option itself is vecmsaa.cli.options').

CONNECT_TIMEOUT = 10          # seconds to reach the scheduler
WORKER_WAIT = 60              # seconds to wait for the first worker
MAX_SCANNED_BYTES = 64 << 20  # of a compressed (.svgz) document, for finding its references
#: tasks kept in flight per worker thread: enough to keep workers busy, few enough that a batch
#: of many thousand drawings is not held in the scheduler's memory at once
IN_FLIGHT_PER_THREAD = 4

_HREF = re.compile(rb"""href\s*=\s*(?:"([^"]*)"|'([^']*)')""")


class ClusterError(Exception):
    """The batch cannot run on the cluster at all (no dask, unreachable scheduler, no workers,
    workers with other vecmsaa code, lost connection), as opposed to one file failing."""


class WorkerDied(RuntimeError):
    """The worker rendering a file died (crash, killed for memory) more often than the
    scheduler retries."""


# --- what goes to a worker -----------------------------------------------------------------------

@dataclass(frozen=True)
class Bundle:
    """A document and the files it may load, as relative paths → bytes, laid out as on the
    client relative to their common folder."""
    files: dict
    document: str
    resources_dir: str | None

    def unpack(self, folder) -> tuple[str, str | None]:
        """Write the files under ``folder``: (path of the document, of resources_dir)."""
        root = os.path.realpath(folder)
        for rel, data in self.files.items():
            path = os.path.realpath(os.path.join(root, rel))
            if not path.startswith(root + os.sep):
                raise ValueError(f"bundle path escapes its folder: {rel!r}")
            os.makedirs(os.path.dirname(path), exist_ok=True)
            with open(path, "wb") as f:
                f.write(data)
        resources = None
        if self.resources_dir is not None:
            resources = os.path.join(root, self.resources_dir)
            os.makedirs(resources, exist_ok=True)
        return os.path.join(root, self.document), resources


def _references(data: bytes) -> list[str]:
    """Every ``href``/``xlink:href`` value of a document (over-inclusive: a match in text or
    a comment only sends one file too many)."""
    if data[:2] == b"\x1f\x8b":
        try:
            with gzip.GzipFile(fileobj=io.BytesIO(data)) as f:
                data = f.read(MAX_SCANNED_BYTES)
        except (OSError, EOFError):
            return []   # the renderer reports the broken file
    found = []
    for match in _HREF.finditer(data):
        value = html.unescape((match.group(1) or match.group(2) or b"").decode("utf-8", "replace"))
        if value.strip() and not value.lstrip().startswith("#") \
                and value.strip()[:5].lower() != "data:":
            found.append(value)
    return found


def bundle_svg(svg_path, resources_dir=None) -> Bundle:
    """The bundle of the SVG file ``svg_path``: the document, and the files its references
    name that the renderer would be allowed to read (vecmsaa.svg.resources)."""
    from ..api import _read_source
    from ..svg.resources import Resources

    data, folder = _read_source(os.fspath(svg_path))
    folder = os.path.realpath(folder)
    document = os.path.join(folder, os.path.basename(os.fspath(svg_path)))
    resources = Resources(folder, resources_dir)
    files = {document: data}
    for url in _references(data):
        real = resources.locate(url)
        if real is not None and real not in files:
            with open(real, "rb") as f:
                files[real] = f.read()
    anchors = [folder] + list(files) + ([resources.resources_dir] if resources_dir else [])
    root = os.path.commonpath(anchors)

    def rel(path):
        return PurePosixPath(Path(os.path.relpath(path, root)).as_posix()).as_posix()

    return Bundle({rel(p): b for p, b in files.items()}, rel(document),
                  rel(resources.resources_dir) if resources_dir else None)


def fonts_bundle(folder) -> dict:
    """The font files of ``folder`` (as the font database reads them: recursively, by
    extension) as relative POSIX paths → bytes."""
    from ..fonts.db import FONT_EXTENSIONS

    files = {}
    for base, dirs, names in os.walk(folder):
        dirs.sort()
        for name in sorted(names):
            if name.lower().endswith(FONT_EXTENSIONS):
                path = os.path.join(base, name)
                with open(path, "rb") as f:
                    files[Path(os.path.relpath(path, folder)).as_posix()] = f.read()
    return files


def _digest(files: dict) -> str:
    h = hashlib.sha256()
    for name in sorted(files):
        h.update(name.encode() + b"\0" + hashlib.sha256(files[name]).digest())
    return h.hexdigest()


# --- on a worker ---------------------------------------------------------------------------------

# One render at a time per worker process: the renderer's caches (fonts, kernels' dispatch) are
# per process and not made for concurrent use; run workers with --nthreads 1 (docs/cluster.md).
_RENDER_LOCK = threading.Lock()
_FONT_FOLDERS: dict = {}


def _font_folder(digest: str, files: dict) -> str:
    """The fonts unpacked once per worker process (same folder every time, so the font
    database cache of vecmsaa.fonts.db is hit)."""
    folder = _FONT_FOLDERS.get(digest)
    if folder is None:
        folder = tempfile.mkdtemp(prefix="vecmsaa-fonts-")
        atexit.register(shutil.rmtree, folder, True)
        for rel, data in files.items():
            path = os.path.join(folder, rel)
            os.makedirs(os.path.dirname(path), exist_ok=True)
            with open(path, "wb") as f:
                f.write(data)
        _FONT_FOLDERS[digest] = folder
    return folder


def render_bundle(renderer, bundle: Bundle, fonts, options: dict) -> bytes:
    """Run on a worker: unpack ``bundle``, render it with ``renderer(path, **options)`` (with
    resources_dir and use_fonts_dir pointing into the unpacked files) and return the PNG."""
    import numpy as np

    from ..output.png import encode_png

    with _RENDER_LOCK, tempfile.TemporaryDirectory(prefix="vecmsaa-task-") as tmp:
        svg, resources = bundle.unpack(tmp)
        options = dict(options, resources_dir=resources)
        if fonts is not None:
            options["use_fonts_dir"] = _font_folder(*fonts)
        rgba = np.asarray(renderer(svg, **options))
    if rgba.dtype != np.uint8 or rgba.ndim != 3 or rgba.shape[2] != 4:
        raise TypeError(f"renderer returned {rgba.dtype} array of shape {rgba.shape}, "
                        "expected (H, W, 4) uint8")
    return encode_png(rgba)


@functools.lru_cache(maxsize=None)
def code_fingerprint() -> str:
    """vecmsaa's version and a hash of its Python sources: equal on client and workers means
    equal output bytes. Computed once per process, so it describes the code that process
    loaded (a worker started before an upgrade keeps the old code)."""
    from .. import __version__

    package = Path(__file__).resolve().parents[1]
    h = hashlib.sha256(__version__.encode())
    for path in sorted(package.rglob("*.py")):
        h.update(path.relative_to(package).as_posix().encode() + b"\0" + path.read_bytes())
    return f"{__version__}/{h.hexdigest()[:16]}"


def _default_renderer(source, **options):
    from ..api import render_svg_array
    return render_svg_array(source, **options)


# --- on the client -------------------------------------------------------------------------------

class Cluster:
    """A connection to a Dask scheduler for rendering batches (a context manager)."""

    def __init__(self, address: str, timeout: float = CONNECT_TIMEOUT):
        try:
            # Imported here: distributed takes over a second to import and only batches on a
            # cluster need it.
            import distributed
        except ImportError:
            raise ClusterError("--scheduler needs Dask: pip install 'vecmsaa[dask]'") from None
        self._distributed = distributed
        self.address = address
        try:
            self.client = distributed.Client(address, timeout=f"{timeout}s",
                                             set_as_default=False)
        except (OSError, TimeoutError, ValueError) as exc:
            raise ClusterError(f"cannot reach the Dask scheduler at {address}: "
                               f"{' '.join(str(exc).split()) or type(exc).__name__}") from None
        try:
            self.client.wait_for_workers(1, timeout=WORKER_WAIT)
            mine = code_fingerprint()
            theirs = self.client.run(code_fingerprint)
        except (OSError, TimeoutError) as exc:
            self.close()
            raise ClusterError(f"no Dask worker joined {address} within {WORKER_WAIT} s "
                               f"({type(exc).__name__})") from None
        other = sorted(w for w, f in theirs.items() if f != mine)
        if other:
            self.close()
            raise ClusterError(f"worker {other[0]} runs other vecmsaa code ({theirs[other[0]]}) "
                               f"than this client ({mine}); install the same version everywhere")
        threads = sum(self.client.nthreads().values()) or 1
        self.in_flight = max(2, IN_FLIGHT_PER_THREAD * threads)
        self._fonts: dict = {}

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def close(self) -> None:
        self.client.close()

    def _fonts_for(self, folder):
        """(digest, future of the files) of a fonts folder, sent to every worker once."""
        if folder is None:
            return None
        key = os.path.realpath(folder)
        if key not in self._fonts:
            files = fonts_bundle(key)
            digest = _digest(files)
            # One object (a dict given alone would be scattered as one datum per font file)
            [future] = self.client.scatter([files], broadcast=True, hash=False)
            self._fonts[key] = (digest, future)
        return self._fonts[key]

    def render_pngs(self, items: Iterable[tuple], renderer: Callable | None = None) \
            -> Iterator[bytes | BaseException]:
        """For each ``(svg_path, options)``: the PNG bytes, or the exception its render (or
        reading its files) raised, in order. ``renderer`` (default render_svg_array) runs on
        the workers."""
        renderer = renderer or _default_renderer
        pending: deque = deque()
        for svg_path, options in items:
            try:
                bundle = bundle_svg(svg_path, options.get("resources_dir"))
                fonts = self._fonts_for(options.get("use_fonts_dir"))
            except Exception as exc:   # an unreadable file fails alone, like a failed render
                pending.append(exc)
            else:
                pending.append(self._submit(renderer, bundle, fonts, options))
            while len(pending) >= self.in_flight:
                yield self._result(pending.popleft())
        while pending:
            yield self._result(pending.popleft())

    def render_arrays(self, items, renderer=None) -> Iterator:
        """:meth:`render_pngs` decoded to straight RGBA uint8 arrays (or the exceptions)."""
        import numpy as np
        from PIL import Image

        for result in self.render_pngs(items, renderer):
            if isinstance(result, BaseException):
                yield result
            else:
                with Image.open(io.BytesIO(result)) as image:
                    yield np.asarray(image.convert("RGBA"))

    def _submit(self, renderer, bundle, fonts, options):
        arguments = (render_bundle, renderer, bundle, None if fonts is None else tuple(fonts),
                     {k: v for k, v in options.items() if k != "resources_dir"})
        return self.client.submit(*arguments, pure=False), arguments

    def _result(self, entry):
        """The PNG bytes of a submitted task, or the exception that is its file's failure. A
        task whose worker died is tried once more: the scheduler fails every task that was
        running or queued on a dying worker, and only one of them caused it."""
        if isinstance(entry, BaseException):
            return entry
        future, arguments = entry
        for attempt in range(2):
            try:
                return future.result()
            except self._distributed.KilledWorker:
                if attempt:
                    return WorkerDied("the worker rendering it died (crash or out of memory)")
                future.release()
                future = self.client.submit(*arguments, pure=False)
            except (OSError, self._distributed.comm.CommClosedError) as exc:
                if future.status != "error":     # not the render raising an OSError
                    raise ClusterError(f"lost the Dask scheduler at {self.address}: "
                                       f"{exc}") from None
                return exc
            except Exception as exc:   # the render raised: this file's failure
                return exc
            finally:
                if future.done():
                    future.release()

def render_files(jobs: list, address: str, failure_text: Callable[[BaseException], str]) \
        -> Iterator[tuple[str, str | None]]:
    """``vecmsaa render ... --scheduler``: for each ``(svg path, png path, options)`` render on
    the cluster and write the PNG here; yields (svg path, None or the failure as one line)."""
    from ..files import write_bytes_atomic

    with Cluster(address) as cluster:
        pngs = cluster.render_pngs((src, options) for src, _dst, options in jobs)
        for (src, dst, _options), png in zip(jobs, pngs):
            if isinstance(png, BaseException):
                yield src, failure_text(png)
                continue
            try:
                write_bytes_atomic(png, dst)
            except OSError as exc:
                yield src, failure_text(exc)
            else:
                yield src, None
