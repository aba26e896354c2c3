"""The Siconos numerics LCP test files (tests/data/siconos/lcp/*.dat), one test per file.

Data from the Siconos project (INRIA, Apache-2.0); see tests/data/siconos/README.md.  The
files carry no expected solution, so every answer is checked on the data itself.
"""
import importlib.util
import json
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import linprog

import lemke
from helpers import assert_lcp_solution, assert_ray, enumerate_solutions
from siconos_dat import read_lcp

LCP_DIR = Path(__file__).parent / "data" / "siconos" / "lcp"
LCP_FILES = sorted(p.name for p in LCP_DIR.glob("*.dat"))
BLOCK_FILES = [name for name in LCP_FILES if name.endswith("_block.dat")]
# The arrays an independent reader (read_siconos_dat.py, kept with this data outside the
# repository, in ../shared/data/peer-lcp/siconos beside the checkout) gives for LCP_FILES.
REFERENCE = Path(__file__).parent / "data" / "siconos" / "lcp-reference-arrays.json"
SHARED_READER = (Path(__file__).resolve().parents[2] / "shared" / "data" / "peer-lcp" / "siconos"
                 / "read_siconos_dat.py")

# Files on which Lemke's method with the covering vector of ones ends on a secondary ray.
RAY_FILES = {
    # Bimatrix game (Cottle-Pang-Stone Example 4.4.23): M = [[0, A], [B, 0]] with A, B > 0
    # and q = -1.  z0 enters and, all rows tied, w_4 leaves (lexicographic tie-break); then
    # z_4 enters.  Its column M[:, 3] = (30, 15, 0, 0) is >= 0 and z0's row (row 4 of M,
    # (20, 15, 0, 0)) has a 0 in it, so nothing blocks: a ray after one pivot, although a
    # solution (a Nash equilibrium) exists.  Siconos' Lemke ray-terminates too; enumeration
    # and Newton-FB solve it.  Existence is checked below by enumerating complementary bases.
    "lcp_CPS_3.dat": "solvable bimatrix game; Lemke with d = ones rays",
    # Pang's isolated-solution example with q_1 perturbed by -1e-4.  The README says no
    # Siconos solver succeeds; in fact the LCP is infeasible: w_2 = z_1 - 1 >= 0 and
    # w_3 = 1 - z_1 >= 0 force z_1 = 1, and then w_1 = -z_2 - z_3 - 1e-4 < 0 for every
    # z >= 0.  Checked below with an LP feasibility test of {z >= 0, Mz + q >= 0}.
    "lcp_Pang_isolated_sol_perturbed.dat": "infeasible",
}

# lcp_tobenna (n = 40, q = (0 x 32, -1 x 8)) is degenerate with d = ones (z0 = 1 throughout;
# at pivot 54 seven rows tie at ratio 0).  It once ran to MAX_PIVOTS because rounding noise on
# exact zeros of B^-1 decided the lexicographic rule; the kernel now treats such noise as
# zero, and Lemke with the same rule in exact rational arithmetic takes 127 pivots.
KNOWN_BUGS = {}


def _params():
    params = []
    for name in LCP_FILES:
        marks = []
        if name in KNOWN_BUGS:
            bug = pytest.mark.xfail(reason=KNOWN_BUGS[name], raises=AssertionError, strict=True)
            marks.append(bug)
        params.append(pytest.param(name, id=name[: -len(".dat")], marks=marks))
    return params


def _is_feasible(M, q):
    """Whether {z >= 0, M z + q >= 0} is non-empty (an LP feasibility problem)."""
    res = linprog(np.zeros(q.size), A_ub=-M, b_ub=q, bounds=[(0, None)] * q.size)
    assert res.status in (0, 2), res.message
    return res.status == 0


@pytest.mark.parametrize("name", _params())
def test_siconos_lcp(name, method):
    M, q = read_lcp(LCP_DIR / name)
    result = lemke.solve_lcp(M, q, method=method)
    if name in RAY_FILES:
        assert result.status == lemke.Status.RAY_TERMINATION, result.message
        assert_ray(M, q, result.covering, result.z, result.z0, result.ray)
        if RAY_FILES[name] == "infeasible":
            assert not _is_feasible(M, q)
        else:
            assert enumerate_solutions(M, q), "expected a solution to exist"
    else:
        assert result.status == lemke.Status.SOLVED, result.message
        assert_lcp_solution(M, q, result.z)


def test_tobenna_has_a_solution():
    # lcp_tobenna with another covering vector: the solution found is checked on the data,
    # so it shows the LCP is solvable (see KNOWN_BUGS for the d = ones failure).
    M, q = read_lcp(LCP_DIR / "lcp_tobenna.dat")
    result = lemke.solve_lcp(M, q, d=np.arange(1.0, q.size + 1))
    assert result.status == lemke.Status.SOLVED, result.message
    assert_lcp_solution(M, q, result.z)


@pytest.mark.parametrize("name", BLOCK_FILES, ids=[n[: -len(".dat")] for n in BLOCK_FILES])
def test_block_file_matches_dense_twin(name):
    M_block, q_block = read_lcp(LCP_DIR / name)
    M_dense, q_dense = read_lcp(LCP_DIR / name.replace("_block.dat", ".dat"))
    np.testing.assert_array_equal(M_block, M_dense)
    np.testing.assert_array_equal(q_block, q_dense)


def test_dense_storage_is_column_major():
    # lcp_exp_murty.dat prints the lines "1 0 0 ...", "2 1 0 ...", ...: each line is a
    # column, so M is Murty's upper-triangular matrix (1 on the diagonal, 2 above it).
    M, q = read_lcp(LCP_DIR / "lcp_exp_murty.dat")
    expected = np.triu(np.full((6, 6), 2.0), 1) + np.eye(6)
    np.testing.assert_array_equal(M, expected)
    np.testing.assert_array_equal(q, -np.ones(6))


def test_reader_matches_shared_reader():
    """Our reader gives, bit for bit, the M and q of an independent reader: its output for
    every file, recorded in tests/data/siconos/lcp-reference-arrays.json (a fresh clone has
    no ../shared), and, where ../shared/data sits beside the checkout, the reader itself."""
    reference = json.loads(REFERENCE.read_text())
    assert sorted(reference) == LCP_FILES
    shared = None
    if SHARED_READER.exists():
        spec = importlib.util.spec_from_file_location("shared_read_siconos_dat", SHARED_READER)
        shared = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(shared)
    for name in LCP_FILES:
        M, q = read_lcp(LCP_DIR / name)
        np.testing.assert_array_equal(M, np.array(reference[name]["M"]), err_msg=name)
        np.testing.assert_array_equal(q, np.array(reference[name]["q"]), err_msg=name)
        if shared is not None:
            M_ref, q_ref = shared.read_lcp(str(LCP_DIR / name))
            M_ref = M_ref.toarray() if hasattr(M_ref, "toarray") else np.asarray(M_ref)
            np.testing.assert_array_equal(M, M_ref, err_msg=name)
            np.testing.assert_array_equal(q, np.asarray(q_ref), err_msg=name)
