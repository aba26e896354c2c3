"""solve_mlcp: the Siconos MLCP files, small cases with known answers, bad input."""
import gzip
import hashlib
from pathlib import Path

import numpy as np
import pytest

import lemke
from helpers import assert_lcp_solution
from siconos_mlcp import LARGE_MLCP, read_mlcp

HERE = Path(__file__).resolve().parent
FILES = sorted((HERE / "data" / "siconos" / "mlcp").glob("*.dat"))
BIG = LARGE_MLCP  # deltasigma*_mlcp.dat, gzip-compressed in tests/data/siconos/mlcp-large


def assert_mlcp_solution(A, B, C, D, a, b, res, rtol=1e-8):
    """A u + C v + a = 0, v >= 0, w = D u + B v + b >= 0, v'w = 0, relative to the data."""
    u, v = np.asarray(res.u), np.asarray(res.v)
    eq = A @ u + C @ v + a
    w = D @ u + B @ v + b
    np.testing.assert_allclose(res.w, w, atol=1e-9 * max(1.0, np.abs(w).max()))
    scale = max([1.0] + [np.abs(x).max() for x in (A, B, C, D, a, b) if x.size])
    xs = max([1.0] + [np.abs(x).max() for x in (u, v) if x.size])
    if eq.size:
        assert np.abs(eq).max() <= rtol * scale * xs, f"equations fail by {np.abs(eq).max()}"
    if v.size:
        assert v.min() >= -rtol * xs and w.min() >= -rtol * scale * xs
        assert np.max(np.abs(v * w)) <= rtol * scale * xs * xs


@pytest.mark.parametrize("path", FILES + BIG, ids=lambda p: p.name.split(".")[0])
def test_siconos_mlcp_files(path, method):
    A, B, C, D, a, b = read_mlcp(path)
    res = lemke.solve_mlcp(A, B, C, D, a, b, method=method)
    assert res.status == lemke.Status.SOLVED, res
    assert_mlcp_solution(A, B, C, D, a, b, res)


def test_all_shared_files_are_here():
    # Siconos' numerics/src/MLCP/test/data has 18 files: 16 here, the 2 large ones compressed
    assert len(FILES) == 16
    assert [p.name for p in BIG] == ["deltasigma2_mlcp.dat.gz", "deltasigma_mlcp.dat.gz"]
    # the SHA-256 of Siconos' files (tests/data/README.md): the compressed copies are unchanged
    assert [hashlib.sha256(gzip.decompress(p.read_bytes())).hexdigest() for p in BIG] == [
        "78ea588ee8a09415c66f7a1d8c5f84ecf015da8e86a0ee45624eb4d933f0e469",
        "a3ea1d37e5d2fbc2986b592d8b4504259626b5d054d732fe34153ebc87846bed",
    ]


def test_known_answer():
    # u - v - 1 = 0, w = u + 2 v - 3: u = 5/3, v = 2/3, w = 0
    res = lemke.solve_mlcp([[1.0]], [[2.0]], [[-1.0]], [[1.0]], [-1.0], [-3.0])
    assert res.success
    np.testing.assert_allclose(res.u, [5 / 3], atol=1e-14)
    np.testing.assert_allclose(res.v, [2 / 3], atol=1e-14)


def test_no_free_variables_is_an_lcp(method):
    rng = np.random.default_rng(1)
    M = rng.standard_normal((6, 6))
    M = M @ M.T
    q = rng.standard_normal(6)
    res = lemke.solve_mlcp(np.zeros((0, 0)), M, np.zeros((0, 6)), np.zeros((6, 0)), np.zeros(0), q, method=method)
    ref = lemke.solve_lcp(M, q, method=method)
    assert res.success and ref.success
    np.testing.assert_allclose(res.v, ref.z, atol=1e-12)
    assert_lcp_solution(M, q, res.v)


def test_only_equations():
    A = np.array([[2.0, 1.0], [1.0, 3.0]])
    a = np.array([-1.0, 2.0])
    res = lemke.solve_mlcp(A, np.zeros((0, 0)), np.zeros((2, 0)), np.zeros((0, 2)), a, np.zeros(0))
    assert res.success
    np.testing.assert_allclose(A @ res.u + a, 0.0, atol=1e-14)


def test_singular_free_block_needs_a_swap(method):
    """A = 0 (the equality multipliers of a QP): every free variable must borrow a pair."""
    # min 1/2 |x|^2 - x1 s.t. x1 + x2 = 1, x >= 0, as an MLCP: u = y, v = x
    A = np.zeros((1, 1))
    C = -np.array([[1.0, 1.0]])
    D = np.array([[1.0], [1.0]])
    B = np.eye(2)
    res = lemke.solve_mlcp(A, B, C, D, [1.0], [-1.0, 0.0], method=method)
    assert res.success
    assert_mlcp_solution(A, B, C, D, np.array([1.0]), np.array([-1.0, 0.0]), res)
    np.testing.assert_allclose(res.v, [1.0, 0.0], atol=1e-14)


def test_inconsistent_equations_are_reported():
    A = np.array([[1.0, 1.0], [1.0, 1.0]])
    res = lemke.solve_mlcp(A, np.eye(1), np.zeros((2, 1)), np.zeros((1, 2)), [1.0, 2.0], [0.0])
    assert res.status == lemke.Status.PRIMAL_INFEASIBLE and not res.success


def test_ray_of_an_infeasible_monotone_mlcp(method):
    """u free, v >= 0 with w = -1 - v... infeasible: w = -1 - v < 0 always."""
    res = lemke.solve_mlcp([[1.0]], [[0.0]], [[0.0]], [[0.0]], [0.0], [-1.0], method=method)
    assert res.status == lemke.Status.RAY_TERMINATION


def test_warm_start_round_trip(method):
    A, B, C, D, a, b = read_mlcp(HERE / "data" / "siconos" / "mlcp" / "diodeBridge40_mlcp.dat")
    cold = lemke.solve_mlcp(A, B, C, D, a, b, method=method)
    warm = lemke.solve_mlcp(A, B, C, D, a, b, method=method, warm_start=cold.warm_start)
    assert warm.success and warm.pivots == 0
    assert_mlcp_solution(A, B, C, D, a, b, warm)


@pytest.mark.parametrize("change,match", [
    (dict(A=np.eye(3)), "A must have shape"),
    (dict(B=np.eye(3)), "B must have shape"),
    (dict(C=np.zeros((2, 3))), "C must have shape"),
    (dict(D=np.zeros((3, 3))), "D must have shape"),
    (dict(a=[[1.0, 2.0]]), "a must be a vector"),
    (dict(b=[0.0, np.inf]), "infinite"),
])
def test_bad_input(change, match):
    args = dict(A=np.eye(2), B=np.eye(2), C=np.zeros((2, 2)), D=np.zeros((2, 2)), a=[1.0, 1.0], b=[0.0, 0.0])
    args.update(change)
    with pytest.raises(ValueError, match=match):
        lemke.solve_mlcp(**args)


def test_bad_warm_start():
    with pytest.raises(TypeError, match="warm_start"):
        lemke.solve_mlcp(np.eye(1), np.eye(1), [[0.0]], [[0.0]], [1.0], [0.0], warm_start="basis")
    ws = lemke.WarmStart(3, ())
    with pytest.raises(ValueError, match="pairs"):
        lemke.solve_mlcp(np.eye(1), np.eye(1), [[0.0]], [[0.0]], [1.0], [0.0], warm_start=ws)
