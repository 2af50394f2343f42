import os
import sys
from pathlib import Path

import pytest
from hypothesis import settings

sys.path.insert(0, os.path.dirname(__file__))

# Under CI (the CI variable set, as CI services and .ci/run set it) the property tests draw the
# same examples on every run (derandomize: seeded by each test's own source), so a submission is
# judged on its own changes, not on which random example a run happened to draw; their @example
# cases run always. Everywhere else they explore, and what they find becomes an @example.
settings.register_profile("ci", derandomize=True, database=None)
if os.environ.get("CI"):
    settings.load_profile("ci")

REPO = Path(__file__).resolve().parents[1]
SHARED = REPO.parent / "shared"


@pytest.fixture
def shared_dir():
    if not SHARED.is_dir():
        pytest.skip("../shared is not present")
    return SHARED


@pytest.fixture(scope="session", autouse=True)
def outside_the_source_tree(tmp_path_factory):
    """Run from a scratch folder. Subprocesses such as ``python -m vecmsaa.cli`` put the working
    directory on sys.path; from the repository root ./vecmsaa (whose command-line layer installs
    from ./cli as vecmsaa.cli) would shadow the installed package."""
    old = os.getcwd()
    os.chdir(tmp_path_factory.mktemp("cwd"))
    yield
    os.chdir(old)


@pytest.fixture(scope="session", autouse=True)
def font_cache_in_scratch(tmp_path_factory):
    """The font face cache (vecmsaa/fonts/facecache.py) in a scratch folder, for this process
    and the commands the tests run, so that tests never write the user's ~/.cache."""
    from vecmsaa.fonts.facecache import CACHE_ENV

    old = os.environ.get(CACHE_ENV)
    os.environ[CACHE_ENV] = str(tmp_path_factory.mktemp("font-cache"))
    yield
    if old is None:
        os.environ.pop(CACHE_ENV, None)
    else:
        os.environ[CACHE_ENV] = old
