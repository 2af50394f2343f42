"""Progress on a terminal only: a tqdm bar for batches and for a single render that takes
more than about a second; when stderr is not a terminal, only the lines that matter (failures,
warnings) are printed. tqdm is imported only when a bar is shown."""
from __future__ import annotations

import contextlib
import sys
import threading

#: seconds a single render runs before it gets a bar
SINGLE_RENDER_DELAY = 1.0


def _on_terminal(quiet: bool) -> bool:
    return not quiet and sys.stderr.isatty()


class Progress:
    """A batch of ``total`` items: ``advance(name)`` after each, ``write(line)`` for messages
    (printed above the bar on a terminal, plainly otherwise)."""

    def __init__(self, total: int, what: str, quiet: bool = False):
        self.bar = None
        if _on_terminal(quiet):
            from tqdm import tqdm
            self.bar = tqdm(total=total, desc=what, unit="file", file=sys.stderr,
                            dynamic_ncols=True)

    def write(self, line: str, file=None) -> None:
        """Print ``line`` (to stderr unless ``file``) without breaking the bar."""
        file = file or sys.stderr
        if self.bar is not None:
            self.bar.write(line, file=file)
        else:
            print(line, file=file, flush=True)

    def advance(self, name: str = "") -> None:
        if self.bar is not None:
            self.bar.set_postfix_str(name[-40:], refresh=False)
            self.bar.update(1)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        if self.bar is not None:
            self.bar.close()


@contextlib.contextmanager
def single_render(name: str, quiet: bool = False):
    """Within the block, a render of ``name``; yields ``report(rows done, rows)`` for the
    renderer's ``progress``. After SINGLE_RENDER_DELAY seconds a bar appears on a terminal:
    the elapsed time while the drawing is read and prepared, then the image rows drawn; it
    goes when the block ends."""
    state = {"done": 0, "rows": 0}

    def report(done: int, rows: int) -> None:
        state["done"], state["rows"] = done, rows
    if not _on_terminal(quiet):
        yield report
        return
    finished = threading.Event()

    def show():
        if finished.wait(SINGLE_RENDER_DELAY):
            return
        from tqdm import tqdm
        with tqdm(desc=f"rendering {name}", total=None, file=sys.stderr, leave=False,
                  unit="row", bar_format="{desc}: {elapsed}") as bar:
            while not finished.wait(0.25):
                if state["rows"] and bar.total is None:   # the bands have begun
                    bar.total, bar.bar_format = state["rows"], None
                if bar.total is not None:
                    bar.n = state["done"]
                bar.refresh()
    thread = threading.Thread(target=show, daemon=True)
    thread.start()
    try:
        yield report
    finally:
        finished.set()
        thread.join()
