"""Worker processes for batches that survive the death of a worker.

``multiprocessing.Pool`` waits forever for the result of a worker killed by a signal (kill -9,
the kernel's OOM killer), and ``ProcessPoolExecutor`` fails every job in flight with it. Here
each worker takes one job at a time over its own pipe, so when a worker dies the parent knows
which job it had: that job is reported as failed, a new worker takes its place, and the rest
of the batch goes on.
"""
from __future__ import annotations

import multiprocessing as mp
import os
import signal
from collections import deque
from multiprocessing.connection import wait
from typing import Callable, Iterable, Iterator


def default_jobs() -> int:
    """One worker per core (what ``--jobs 0`` means)."""
    return os.cpu_count() or 1


class WorkerDied(Exception):
    """The worker process running a job ended before returning its result."""


def _serve(func, conn) -> None:
    while True:
        try:
            message = conn.recv()
        except EOFError:
            return
        if message is None:
            return
        index, item = message
        try:
            conn.send((index, True, func(item)))
        except BaseException as exc:   # reported to the parent, the worker lives on
            conn.send((index, False, f"{type(exc).__name__}: {exc}"))


def _death(process) -> str:
    process.join()
    code = process.exitcode
    if code is not None and code < 0:
        try:
            name = signal.Signals(-code).name
        except ValueError:
            name = f"signal {-code}"
        return f"worker process killed by {name}"
    return f"worker process exited with status {code}"


def imap_unordered(func: Callable, items: Iterable, jobs: int) -> Iterator[tuple]:
    """``(index, result)`` for each item as its job finishes; ``result`` is ``func(item)``, or a
    :class:`WorkerDied` (or, when ``func`` raised, an ``Exception`` carrying its message) for a
    job that did not return. ``func`` runs in ``jobs`` forked worker processes (spawned where
    fork is not available, so it must then be picklable)."""
    todo = deque(enumerate(items))
    if not todo:
        return
    ctx = mp.get_context("fork" if "fork" in mp.get_all_start_methods() else "spawn")
    idle, busy = [], {}   # busy: connection → (process, index)
    processes = {}

    def start():
        parent, child = ctx.Pipe()
        process = ctx.Process(target=_serve, args=(func, child), daemon=True)
        process.start()
        child.close()
        processes[parent] = process
        idle.append(parent)

    for _ in range(max(1, min(jobs, len(todo)))):
        start()
    try:
        while todo or busy:
            while todo and idle:
                conn = idle.pop()
                index, item = todo.popleft()
                conn.send((index, item))
                busy[conn] = index
            for conn in wait(list(busy)):
                index = busy.pop(conn)
                try:
                    _index, ok, result = conn.recv()
                except (EOFError, OSError):
                    process = processes.pop(conn)
                    conn.close()
                    yield index, WorkerDied(_death(process))
                    if todo:
                        start()
                    continue
                idle.append(conn)
                yield index, (result if ok else Exception(result))
    finally:
        for conn, process in processes.items():
            try:
                conn.send(None)
            except OSError:
                pass
        for conn, process in processes.items():
            process.join(timeout=5)
            if process.is_alive():
                process.kill()
                process.join()
            conn.close()
