"""The resvg test suite as a ratchet: every test named in resvg_passing.txt must keep passing.

The suite (the ``crates/resvg/tests`` folder of the resvg repository) is found at
$VECMSAA_RESVG_SUITE, else ../shared/resvg-suite; the tests skip when it is absent. Tests are
rendered with the default mode at their reference PNG's size and compared with the project
criterion, in worker processes; a test with an exact reference (``exact-refs/``) passes when it
matches either. After an improvement, regenerate the list (it only ever grows by intent)::

    vecmsaa suite ../shared/resvg-suite --jobs 2 --write-passing tests/resvg_passing.txt
"""
import os
from pathlib import Path

import pytest

from vecmsaa.tools.suite import suite_from_environment

HERE = Path(__file__).resolve().parent
SUITE = Path(suite_from_environment(HERE.parent.parent / "shared" / "resvg-suite"))
PASSING = HERE / "resvg_passing.txt"


def listed_tests():
    if not PASSING.exists():
        return []
    return [line.strip() for line in PASSING.read_text().splitlines()
            if line.strip() and not line.startswith("#")]


@pytest.fixture(scope="module")
def suite_results():
    if not (SUITE / "tests").is_dir():
        pytest.skip(f"the resvg suite is not present at {SUITE}")
    from vecmsaa.tools.suite import run_suite

    names = [n for n in listed_tests() if (SUITE / "tests" / (n + ".svg")).exists()]
    if not names:
        pytest.skip("no listed tests found in the suite")
    return run_suite(str(SUITE), names, jobs=os.cpu_count() or 1)


def test_ratchet_list_is_sorted_and_unique():
    names = listed_tests()
    assert names == sorted(set(names))


def test_listed_resvg_tests_still_pass(suite_results):
    failed = {n: r.detail for n, r in suite_results.items() if not r.passed}
    assert not failed, "previously passing resvg tests now fail:\n" + "\n".join(
        f"  {n}: {d}" for n, d in sorted(failed.items()))
