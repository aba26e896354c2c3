"""The degenerate families under numba's bounds checking, in a child process.

An index out of range in a kernel normally reads or writes memory outside the array: a
wrong answer, a crash later, or nothing visible.  With ``NUMBA_BOUNDSCHECK=1`` it raises
IndexError.  The child (boundscheck_run.py) gets its own empty ``NUMBA_CACHE_DIR``, so that
every kernel is compiled there with the checks, and the bounds-checked machine code is
never stored next to, or loaded from, the normal on-disk cache; the test checks both (the
child's compile statistics, and the normal cache directory before and after).

Compiling every kernel with bounds checks takes about 35 s of CPU (50 s on a shared
2-core machine); the test is marked ``slow`` (``pytest -m "not slow"`` leaves it out) but
runs under a plain ``pytest``.
"""
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

import lemke.kernels

HERE = Path(__file__).resolve().parent


def _snapshot(directory):
    """Name, size and modification time of every file under ``directory``."""
    if not directory.exists():
        return {}
    return {str(p.relative_to(directory)): (p.stat().st_size, p.stat().st_mtime_ns)
            for p in directory.rglob("*") if p.is_file()}


@pytest.mark.slow
def test_degenerate_families_under_bounds_checking(tmp_path):
    cache = tmp_path / "numba-cache"
    cache.mkdir()
    kernels_dir = Path(lemke.kernels.__file__).resolve().parent
    normal_cache = kernels_dir / "__pycache__"
    before = _snapshot(normal_cache)

    env = dict(os.environ, NUMBA_BOUNDSCHECK="1", NUMBA_CACHE_DIR=str(cache), PYTHONFAULTHANDLER="1")
    env.pop("NUMBA_DISABLE_JIT", None)
    out = subprocess.run([sys.executable, str(HERE / "boundscheck_run.py")], capture_output=True, text=True,
                         env=env, cwd=str(HERE), timeout=600)
    assert out.stdout.strip(), f"no summary from the child (exit code {out.returncode}):\n{out.stderr[-3000:]}"
    summary = json.loads(out.stdout.strip().splitlines()[-1])

    # The child really ran bounds-checked code compiled into the fresh cache directory.
    assert summary["boundscheck_probe"], "NUMBA_BOUNDSCHECK=1 was not in force in the child"
    assert Path(summary["kernels_dir"]).resolve() == kernels_dir, "the child imported another lemke"
    used = summary["dispatchers"]
    assert len(used) >= 10, f"too few kernels were compiled: {sorted(used)}"
    for name, stats in used.items():
        assert stats["hits"] == 0, f"{name} was loaded from a cache instead of compiled with bounds checks"
        assert stats["misses"] > 0 and Path(stats["cache_path"]).resolve().is_relative_to(cache.resolve()), (
            f"{name} was cached in {stats['cache_path']}, not in the fresh NUMBA_CACHE_DIR")
    assert any(cache.rglob("*.nbi")), "nothing was written to the fresh cache directory"
    assert _snapshot(normal_cache) == before, f"the normal cache {normal_cache} changed"

    errors = summary["errors"]
    index_errors = [e for e in errors if "IndexError" in e["error"]]
    assert not index_errors and out.returncode == 0, (
        f"{len(index_errors)} IndexError(s), {len(errors) - len(index_errors)} other exception(s) in "
        f"{summary['solves']} solves (exit code {out.returncode}):\n"
        + "\n".join(f"{e['case']}: {e['error']}" for e in errors)
        + ("\n\nfirst traceback:\n" + errors[0]["traceback"] if errors else ""))
    assert "IndexError" not in out.stderr, out.stderr[-3000:]
