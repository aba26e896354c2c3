"""benchmarks/bench_engines.py's bridge to DART's boxed LCP solvers.

It needs dartpy (the ``bench`` extra: an 18.7 MB wheel, 70 MB installed), which the ``test``
extra leaves out, so it is not in the default test run (``testpaths`` is ``tests``); run it
with ``pip install ".[bench]" && pytest benchmarks``.  The bridge's answer check,
``coupled_residual``, is tested in tests/test_bench_engines.py."""
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("dartpy", reason="the DART bridge needs dartpy: pip install '.[bench]'")
sys.path.insert(0, str(Path(__file__).resolve().parent))
import bench_engines as be  # noqa: E402


def test_dart_solvers_answer_solve_blcps_docstring_example():
    dart = be.Dart()
    M = np.array([[2.0, 1.0], [1.0, 2.0]])
    q = np.array([-5.0, 1.0])
    lo, hi = np.array([0.0, -1.0]), np.array([2.0, 1.0])
    for name, tol in (("DantzigBoxedLcpSolver", 1e-12), ("PgsBoxedLcpSolver", 1e-6)):
        call, x = dart.prepare(name, M, q, lo, hi, None)
        assert call()
        assert np.allclose(x, [2.0, -1.0], atol=tol), (name, x)
        assert be.coupled_residual(M, q, lo, hi, None, x) <= tol
