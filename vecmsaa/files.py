"""Files written whole or not at all: a reader never sees half an image, cache or report, and
a process killed on the way leaves a temporary file the next write into that folder removes.
Every stage may use it (it imports nothing of the package)."""
from __future__ import annotations

import errno
import os
import stat
import sys


#: temporary files are named ``.<target>.<pid>`` + this; one left by a killed process is
#: removed by the next process that writes into its folder (see :func:`write_bytes_atomic`)
TEMP_SUFFIX = ".vecmsaa-tmp"
#: folders this process has removed stale temporary files from: each is listed once, not at
#: every write (a batch of 2000 icons into one folder listed it 2000 times, a third of the
#: batch's CPU)
_swept: set[str] = set()


def write_bytes_atomic(data: bytes, path, make_folders: bool = False) -> None:
    """Write ``data`` to ``path`` whole or not at all; ``-`` is stdout.

    A regular file (or a new name) is written to a temporary file beside it and renamed into
    place, so a reader never sees half a file. A symbolic link is followed: its target is
    written, the link stays. Anything else that exists and is not a folder (a FIFO, a device
    such as ``/dev/null`` or ``/dev/stdout``) is written through, never replaced. A missing
    folder is an error (as for rsvg-convert) unless ``make_folders``. A process killed between
    write and rename leaves ``.<name>.<pid>.vecmsaa-tmp``; the first write into that folder by
    a later process removes it."""
    if str(path) == "-":
        sys.stdout.buffer.write(data)
        sys.stdout.buffer.flush()
        return
    path = os.path.realpath(os.fspath(path))   # a symlink's target, not the link
    try:
        st = os.stat(path)
    except FileNotFoundError:
        st = None
    if st is not None and stat.S_ISDIR(st.st_mode):
        raise IsADirectoryError(errno.EISDIR, "is a folder", path)
    if st is not None and not stat.S_ISREG(st.st_mode):
        with open(path, "wb") as f:   # FIFO, device: write through
            f.write(data)
        return
    folder, name = os.path.split(path)
    if make_folders:
        os.makedirs(folder, exist_ok=True)
    elif not os.path.isdir(folder):
        raise FileNotFoundError(errno.ENOENT, "no such folder", folder)
    if folder not in _swept:
        _swept.add(folder)
        _remove_stale_temps(folder)
    tmp = os.path.join(folder, f".{name}.{os.getpid()}{TEMP_SUFFIX}")
    # O_EXCL: never write through a file (or link) someone else put at that name; the mode
    # is the one a plain open() would give (0666 less the umask)
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0), 0o666)
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def _remove_stale_temps(folder: str) -> None:
    """Remove the ``.<name>.<pid>.vecmsaa-tmp`` files in ``folder`` whose process no longer
    exists."""
    try:
        entries = os.listdir(folder)
    except OSError:
        return
    for entry in entries:
        if not (entry.startswith(".") and entry.endswith(TEMP_SUFFIX)):
            continue
        pid = entry[:-len(TEMP_SUFFIX)].rpartition(".")[2]
        if not pid.isdigit() or _process_exists(int(pid)):
            continue
        try:
            os.unlink(os.path.join(folder, entry))
        except OSError:
            pass


def _process_exists(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OSError):
        return True
    return True
