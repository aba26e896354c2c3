import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

import lemke

HERE = Path(__file__).resolve().parent
BOUNDSCHECK_TEST = "test_degenerate_families_under_bounds_checking"
_boundscheck = {}  # "child": the running child process, "cache": its fresh numba cache directory


@pytest.fixture(params=lemke.METHODS)
def method(request):
    """Every test that takes ``method`` runs once per Lemke method."""
    return request.param


@pytest.hookimpl(trylast=True)  # after -m and -k have deselected: `-m "not slow"` starts no child
def pytest_collection_modifyitems(config, items):
    """Start the bounds-checked child process (tests/boundscheck_run.py) as soon as its test is
    selected, so that it compiles every kernel with bounds checks beside the rest of the suite
    (on two cores that hides most of its minute and a half) instead of before the tests after it."""
    if any(item.name == BOUNDSCHECK_TEST for item in items):
        start_boundscheck_child()


def start_boundscheck_child():
    """The bounds-checked child, started once per session: ``(process, cache directory)``.
    It gets ``NUMBA_BOUNDSCHECK=1`` and its own empty ``NUMBA_CACHE_DIR``."""
    if "child" not in _boundscheck:
        cache = Path(tempfile.mkdtemp(prefix="lemke-boundscheck-"))
        env = dict(os.environ, NUMBA_BOUNDSCHECK="1", NUMBA_CACHE_DIR=str(cache), PYTHONFAULTHANDLER="1")
        env.pop("NUMBA_DISABLE_JIT", None)
        _boundscheck["cache"] = cache
        _boundscheck["child"] = subprocess.Popen(
            [sys.executable, str(HERE / "boundscheck_run.py")], stdout=subprocess.PIPE,
            stderr=subprocess.PIPE, text=True, env=env, cwd=str(HERE))
    return _boundscheck["child"], _boundscheck["cache"]


def pytest_unconfigure(config):
    child = _boundscheck.pop("child", None)
    if child is not None and child.poll() is None:
        child.kill()
        child.communicate()
    if "cache" in _boundscheck:
        shutil.rmtree(_boundscheck.pop("cache"), ignore_errors=True)
