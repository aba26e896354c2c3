"""The degenerate families under numba's bounds checking, in a child process.

An index out of range in a kernel normally reads or writes memory outside the array: a
wrong answer, a crash later, or nothing visible.  With ``NUMBA_BOUNDSCHECK=1`` it raises
IndexError.  The child (boundscheck_run.py) gets its own empty ``NUMBA_CACHE_DIR``, so that
every kernel is compiled there with the checks, and the bounds-checked machine code is
never stored next to, or loaded from, the normal on-disk cache; the test checks the
child's compile statistics (no kernel loaded from a cache, each one cached in the fresh
directory).  It also runs ``lemke solve`` first, which on that empty cache compiles nothing
(the C++ core solves the default problem) and so prints nothing on stderr.

Compiling every kernel with bounds checks takes a minute and a half on a 2-core machine;
conftest.py starts the child when the test is collected, so that it runs beside the rest
of the suite.  The test is marked ``slow`` (``pytest -m "not slow"`` leaves it out, and then
no child is started) but runs under a plain ``pytest``.
"""
import json
import subprocess
from pathlib import Path

import pytest

import lemke.kernels
from lemke._cli import COMPILE_NOTICE

HERE = Path(__file__).resolve().parent


@pytest.mark.slow
def test_degenerate_families_under_bounds_checking():
    from conftest import start_boundscheck_child

    child, cache = start_boundscheck_child()  # started at collection time by conftest.py
    kernels_dir = Path(lemke.kernels.__file__).resolve().parent
    try:
        stdout, stderr = child.communicate(timeout=900)
    except subprocess.TimeoutExpired:
        child.kill()
        stdout, stderr = child.communicate()
    assert stdout.strip(), f"no summary from the child (exit code {child.returncode}):\n{stderr[-3000:]}"
    summary = json.loads(stdout.strip().splitlines()[-1])

    # The child really ran bounds-checked code compiled into the fresh cache directory (the
    # normal cache beside the kernels is written by this process's tests meanwhile, so it is
    # each kernel's own cache path that shows where the child's machine code went).
    assert summary["boundscheck_probe"], "NUMBA_BOUNDSCHECK=1 was not in force in the child"
    assert Path(summary["kernels_dir"]).resolve() == kernels_dir, "the child imported another lemke"
    used = summary["dispatchers"]
    assert len(used) >= 10, f"too few kernels were compiled: {sorted(used)}"
    for name, stats in used.items():
        assert stats["hits"] == 0, f"{name} was loaded from a cache instead of compiled with bounds checks"
        assert stats["misses"] > 0 and Path(stats["cache_path"]).resolve().is_relative_to(cache.resolve()), (
            f"{name} was cached in {stats['cache_path']}, not in the fresh NUMBA_CACHE_DIR")
    assert any(cache.rglob("*.nbi")), "nothing was written to the fresh cache directory"
    for module in ("boxed", "games", "qp", "cold", "tableau", "unrevised", "mlcp"):
        assert any(name.startswith(module + ".") for name in used), f"no kernel of kernels/{module}.py ran"
    # On an empty cache the command line's default solve (an LCP by the tableau, which the
    # C++ core runs) compiles nothing, so it says nothing (it said COMPILE_NOTICE once
    # before the core; the notice stays for the kinds still in numba).
    assert COMPILE_NOTICE not in summary["cli_stderr"] and summary["cli_stderr"] == "", summary["cli_stderr"]

    errors = summary["errors"]
    index_errors = [e for e in errors if "IndexError" in e["error"]]
    assert not index_errors and child.returncode == 0, (
        f"{len(index_errors)} IndexError(s), {len(errors) - len(index_errors)} other exception(s) in "
        f"{summary['solves']} solves (exit code {child.returncode}):\n"
        + "\n".join(f"{e['case']}: {e['error']}" for e in errors)
        + ("\n\nfirst traceback:\n" + errors[0]["traceback"] if errors else ""))
    assert "IndexError" not in stderr, stderr[-3000:]
