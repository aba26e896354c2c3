"""benchmarks/bench_engines.py's own check of box-LCP answers (no engine needed).  Its bridge
to DART's boxed LCP solvers needs dartpy (the ``bench`` extra) and is tested with the
benchmarks: ``pip install ".[bench]" && pytest benchmarks``."""
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "benchmarks"))
import bench_engines as be  # noqa: E402


def test_coupled_residual_uses_the_bounds_at_the_answer():
    # one contact: normal row 0, friction row 1 with mu = 0.5; z_t = 0.6 > mu z_n = 0.5
    M, q = np.eye(2), np.array([-1.0, -0.6])
    lo, hi, fi = np.array([0.0, -0.5]), np.array([np.inf, 0.5]), np.array([-1, 0])
    assert be.coupled_residual(M, q, lo, hi, fi, np.array([1.0, 0.5])) == 0.0
    assert be.coupled_residual(M, q, lo, hi, fi, np.array([1.0, 0.6])) > 0.05
