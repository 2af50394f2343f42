"""The compile-time report of vecmsaa/cli/compile_times.py (docs/bench.md, first run)."""
import time


def test_compile_times_subtracts_nested_compiles_and_lists_respecialisations():
    from numba import njit
    from numba.core import event

    from vecmsaa.cli.compile_times import CompileTimes

    @njit
    def inner(x, n):
        return x + n

    @njit
    def outer(x):
        n = 0
        return inner(x, n) + inner(x, n + 1)    # a literal 0 first, then an int64

    listener = CompileTimes()
    event.register("numba:compile", listener)
    try:
        t0 = time.process_time()
        outer(1.0)
        total = time.process_time() - t0
    finally:
        event.unregister("numba:compile", listener)
    names = {n.rpartition(".")[2]: n for n in listener.seconds}
    assert {"inner", "outer"} <= set(names)
    assert sum(listener.seconds.values()) <= total + 0.05     # nothing counted twice
    report = listener.report()
    assert f"compiled 2 times: {names['inner']}" in report and "Literal[int](0)" in report
