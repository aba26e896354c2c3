"""benchmarks/bench_engines.py's bridge to DART's boxed LCP solvers (skipped without dartpy)."""
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("dartpy")
sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "benchmarks"))
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


def test_coupled_residual_uses_the_bounds_at_the_answer():
    # one contact: normal row 0, friction row 1 with mu = 0.5; z_t = 0.6 > mu z_n = 0.5
    M, q = np.eye(2), np.array([-1.0, -0.6])
    lo, hi, fi = np.array([0.0, -0.5]), np.array([np.inf, 0.5]), np.array([-1, 0])
    assert be.coupled_residual(M, q, lo, hi, fi, np.array([1.0, 0.5])) == 0.0
    assert be.coupled_residual(M, q, lo, hi, fi, np.array([1.0, 0.6])) > 0.05
