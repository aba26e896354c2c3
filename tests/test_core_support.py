"""The C++ core's support functions (src/python_support.cpp) against their frozen references
(tests/frozen.py: the outputs of the kernels they were ported from), bit for bit: every
returned number and every byte of every array argument after the call (outputs, and inputs
that must stay as they were).

* the checks: ``lcp_check``, ``lcp_ray_check``, ``check_mlcp``, ``residual2``;
* the dense solves: ``refined_solve``, ``linalg_solve``, ``invert_in_place``,
  ``principal_block``;
* the MLCP reduction: ``mlcp_equilibrate``, ``mlcp_reduce``;
* ``relabel_ids``.

Two kinds of input.  The fronts' own calls: every call that solve_mlcp, solve_qp,
solve_lcp, pivot_column, is_lcp_solution, is_lcp_ray and WarmStart.relabel make on the
goldens' problems (Siconos MLCP files, Maros-Meszaros and random QPs, the LCPs) is
recorded and replayed.  And families made here: QP KKT systems, the linear
algebra tests' matrices, solved and perturbed LCP points and rays, random id arrays."""
from __future__ import annotations

import collections
import struct
import importlib
import sys
from pathlib import Path

import numpy as np
import pytest

import frozen
import lemke
from lemke import _certify, _core

sys.path.insert(0, str(Path(__file__).parent))
import golden  # noqa: E402
from siconos_mlcp import LARGE_MLCP, read_mlcp  # noqa: E402


#: core name -> family (the report's rows)
FAMILY = {"lcp_check": "check", "lcp_ray_check": "ray check", "check_mlcp": "check_mlcp",
          "residual2": "residual2", "refined_solve": "refined_solve", "linalg_solve": "solve",
          "invert_in_place": "invert_in_place", "principal_block": "principal_block",
          "mlcp_equilibrate": "mlcp equilibrate", "mlcp_reduce": "mlcp reduce",
          "relabel_ids": "relabel"}

COUNTS: collections.Counter = collections.Counter()


def _bits(v):
    """v as comparable bits: arrays by dtype, shape and bytes, floats by their IEEE bits (the
    form the frozen digests were recorded in)."""
    if isinstance(v, np.ndarray):
        return ("array", v.dtype.str, v.shape, v.tobytes())
    if isinstance(v, (tuple, list)):
        return tuple(_bits(u) for u in v)
    if isinstance(v, (bool, np.bool_)):
        return ("bool", bool(v))
    if isinstance(v, (int, np.integer)):
        return ("int", int(v))
    if isinstance(v, (float, np.floating)):
        return ("float", struct.pack("<d", float(v)))
    if v is None:
        return None
    raise TypeError(type(v))


def _copy(args):
    return [a.copy() if isinstance(a, np.ndarray) else a for a in args]


#: The oracle's numbers for the MLCP reduction's failures (1, 2: public statuses' numbers,
#: MAX_PIVOTS and RAY_TERMINATION; the core's are negative, src/lemke/status.hpp); the frozen
#: references record them.
ORACLE_MLCP = {_core.MLCP_INCONSISTENT: 1, _core.MLCP_SINGULAR: 2}


def as_recorded(name, rb):
    """The core's result as the oracle returned it (its codes of mlcp_reduce)."""
    if name == "mlcp_reduce":
        return (ORACLE_MLCP.get(rb[0], rb[0]), *rb[1:])
    return rb


def same(name, *args, source="made here"):
    """Run the core's ``name`` on a copy of args; check its results and the bytes of every
    argument afterwards against the frozen references; count it."""
    b = _copy(args)
    rb = getattr(_core, name)(*b)
    frozen.check((_bits(as_recorded(name, rb)), [_bits(x) for x in b]), (name, source))
    COUNTS[(FAMILY[name], source)] += 1
    return rb


@pytest.fixture(scope="module", autouse=True)
def _report():
    yield
    print("\ncalls checked bit for bit (family, input):")
    for (family, source), count in sorted(COUNTS.items()):
        print(f"  {family:18s} {source:24s} {count}")


# ----------------------------------------------------------------------------- the fronts' calls

class _Recorder:
    """Stands in for ``_core`` in the fronts: records the support calls (arguments copied
    before the call), passes everything through."""

    def __init__(self):
        self.calls = []

    def __getattr__(self, name):
        real = getattr(_core, name)
        if name == "mlcp_basis":
            return self._mlcp_basis
        if name == "kkt_basis":
            return self._kkt_basis
        if name not in FAMILY:
            return real

        def call(*args):
            self.calls.append((name, _copy(args)))
            return real(*args)
        return call


    def _mlcp_basis(self, E, e, n, redundant, undetermined, v_basic, *rest):
        """The seam's MLCP point (MLCPToLCP.basis_point since branch seam3) recorded as the
        refined_solve call the point made before (the block E[rows, cols] and -e[rows] as
        the front gathered them, x and lo fresh from np.empty), so that the frozen
        references still judge those solves; and its answer checked to be that solve's x
        scattered to cols and its v clipped at 0, bit for bit."""
        got = _core.mlcp_basis(E, e, n, redundant, undetermined, v_basic, *rest)
        keep_eq, keep_u = np.setdiff1d(np.arange(n), redundant), np.setdiff1d(np.arange(n), undetermined)
        vb = n + np.flatnonzero(v_basic)
        rows, cols = np.concatenate([keep_eq, vb]), np.concatenate([keep_u, vb])
        if rows.size != cols.size or not rows.size:  # (no solve made)
            assert got[0] == 2 or (not rows.size and not got[1].any())
            return got
        k = rows.size
        args = [np.ascontiguousarray(E[np.ix_(rows, cols)]), np.ascontiguousarray(-e[rows]), 2,
                frozen.empty(k), frozen.empty(k)]
        self.calls.append(("refined_solve", _copy(args)))
        if not _core.refined_solve(*args):
            assert got[0] == 2
            return got
        x = np.zeros(e.size)
        x[cols] = args[3]
        x[n:] = np.maximum(x[n:], 0.0)
        assert got[0] == 0 and got[1].tobytes() == x.tobytes()
        return got


    def _kkt_basis(self, P, q, G, h, A, b, lb, ub, basic, *rest):
        """The seam's KKT point (_qp._polished since branch polish) recorded as the
        refined_solve call _polished made before (its K, rhs, 3 steps, x with x_B given
        after np.empty's bytes, lo from np.empty), so that the frozen references still
        judge those solves; and its answer's x checked to be that solve's, bit for bit (the
        rest: tests/test_basis_seam.py's comparison with the former code)."""
        from helpers import kkt_blocks
        from lemke._reductions.qp_mlcp import QPToMLCP
        got = _core.kkt_basis(P, q, G, h, A, b, lb, ub, basic, *rest)
        F, B, _, bound, K, rhs = kkt_blocks(QPToMLCP(P, q, G, h, A, b, lb, ub), basic)
        k = rhs.size
        x = frozen.empty(k + B.size)
        x[k:] = bound[B]
        args = [np.ascontiguousarray(K), np.ascontiguousarray(rhs), 3, x, frozen.empty(k)]
        self.calls.append(("refined_solve", _copy(args)))
        if not _core.refined_solve(*args):
            assert got[0] == 2
            return got
        point = np.empty(q.size)
        point[F], point[B] = x[:F.size], bound[B]
        assert got[0] in (0, 1) and got[1][0].tobytes() == point.tobytes()
        return got

FRONTS = ["lemke._certify", "lemke._pivot_column", "lemke._reductions.mlcp_lcp", "lemke._mlcp",
          "lemke._result", "lemke._lcp"]


@pytest.fixture
def recorder(monkeypatch):
    rec = _Recorder()
    for mod in FRONTS:
        monkeypatch.setattr(importlib.import_module(mod), "_core", rec)  # (lemke imports lazily)
        if hasattr(importlib.import_module(mod), "np"):  # fixed bytes where no kernel writes
            monkeypatch.setattr(importlib.import_module(mod), "np", frozen.FixedEmpty())
    return rec


def _replay(rec, source):
    assert rec.calls
    for name, args in rec.calls:
        same(name, *args, source=source)


def test_the_mlcp_front_on_the_siconos_files(recorder):
    """solve_mlcp on the goldens' Siconos MLCP files (and the two big ones, compressed in
    tests/data/siconos/mlcp-large) by both methods, and the small cases of test_mlcp: equilibrate, reduce,
    refined_solve (the basis points) and check_mlcp, as the front calls them."""
    cases = [args for _, args in golden.mlcp_cases()]
    for path in LARGE_MLCP:  # the big ones, compressed in tests/data (the same arrays as ../shared's)
        cases.append(list(read_mlcp(path)))
    E1 = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 1.0], [-1.0, -1.0, 0.0]])
    cases += [
        [[[1.0]], [[2.0]], [[-1.0]], [[1.0]], [-1.0], [-3.0]],
        [E1[:2, :2], E1[2:, 2:], E1[:2, 2:], E1[2:, :2], [1.0, -1.0], [0.5]],  # singular free block
        [[[1.0, 1.0], [1.0, 1.0]], [[1.0]], [[0.0], [0.0]], [[1.0, 0.0]], [1.0, 2.0], [0.0]],
        [[[1.0]], [[0.0]], [[0.0]], [[0.0]], [-1.0], [-1.0]],
    ]
    for args in cases:
        for method in golden.METHODS:
            r = lemke.solve_mlcp(*args, method=method)
            if r.warm_start is not None:
                lemke.solve_mlcp(*args, method=method, warm_start=r.warm_start)
    _replay(recorder, "solve_mlcp")


def test_the_qp_front(recorder, monkeypatch):
    """solve_qp on the goldens' QPs (the small Maros-Meszaros files, HS21, random convex
    QPs): the KKT systems' reduction, refined_solve with given unknowns (_polished's, now
    the seam's kkt_basis: recorded as the solve it made), check_mlcp.  On
    the Python path with step 8 as it was when the references were recorded (its own rule,
    after NOT_DEFINITE only: ``_qp._RELAXED`` off), so that the QPs that step 8 now answers
    (QAFIRO, QPCBLEND, random/20/10, ...) still reach the KKT-MLCP path here."""
    from lemke import _qp

    monkeypatch.setattr(_qp, "_QP_FRONT", lambda *a: None)
    monkeypatch.setattr(_qp, "_RELAXED", False)
    monkeypatch.setattr(_qp, "_core", recorder)  # (_polished's kkt_basis; no other call recorded)
    for _, args in golden.qp_cases():
        for method in golden.METHODS:
            lemke.solve_qp(*args, method=method)
    rng = np.random.default_rng(5)
    for n, m, p, rank in [(6, 4, 2, 3), (10, 6, 3, None), (12, 0, 4, 5), (8, 10, 0, 0)]:
        B = rng.standard_normal((n, rank if rank is not None else n))
        P = B @ B.T
        G, h = rng.standard_normal((m, n)), rng.random(m)
        A = rng.standard_normal((p, n))
        b = A @ rng.standard_normal(n)
        lemke.solve_qp(P, rng.standard_normal(n), G, h, A, b, lb=-np.ones(n), ub=np.ones(n))
        lemke.solve_qp(P, rng.standard_normal(n), G, h, A, b)
    _replay(recorder, "solve_qp")


def test_the_lcp_fronts(recorder):
    """solve_lcp on the goldens' LCPs by both methods (its check of a recomputed basis
    point: principal_block, lcp_check), is_lcp_solution on their answers and perturbed
    ones, is_lcp_ray on the rays of random LCPs, pivot_column, WarmStart.relabel."""
    rng = np.random.default_rng(8)
    for _, M, q in golden.lcp_cases():
        for method in golden.METHODS:
            r = lemke.solve_lcp(M, q, method=method)
            lemke.is_lcp_solution(M, q, r.z)
            lemke.is_lcp_solution(M, q, r.z * (1.0 + 1e-9 * rng.standard_normal(q.size)))
            if r.ray is not None:
                lemke.is_lcp_ray(M, q, r.covering, r.z, r.z0, r.ray)
    for t in range(40):
        n = int(rng.integers(1, 12))
        M, q = rng.standard_normal((n, n)), rng.standard_normal(n)
        r = lemke.solve_lcp(M, q)
        if r.ray is not None:
            lemke.is_lcp_ray(M, q, r.covering, r.z, r.z0, r.ray)
            lemke.is_lcp_ray(M, q, r.covering, r.z, r.z0, r.ray + 1e-7 * rng.standard_normal(n + 1))
        ws = r.warm_start
        ids = rng.choice(1000, size=n, replace=False).astype(np.int64)
        ws.relabel(ids, rng.permutation(np.concatenate([ids[: n // 2], [5000, 5001]])))
    M = np.array([[0, -1, 2, 1], [2, 0, -2, 1], [-1, 1, 0, 1]], float)
    q = np.array([-3.0, 6.0, -1.0])
    lemke.pivot_column(M, q, ["z4", "w2", "z3"], ["w1", "w3", "z2", "z1"], "w1")
    lemke.pivot_column(M, q, ["z4", "w2", "z3"], ["w1", "w3", "z2", "z1"], "z2")
    for n in (3, 6, 10):
        Mn = rng.standard_normal((n, n + 1))
        qn = rng.standard_normal(n)
        for _ in range(5):
            zb = rng.random(n) < 0.5
            basic = [f"z{i + 1}" if zb[i] else f"w{i + 1}" for i in range(n)]
            nonbasic = [f"w{i + 1}" if zb[i] else f"z{i + 1}" for i in range(n)] + [f"z{n + 1}"]
            try:
                lemke.pivot_column(Mn, qn, basic, nonbasic, nonbasic[0])
            except np.linalg.LinAlgError:
                pass
    _replay(recorder, "the LCP fronts")


# ----------------------------------------------------------------------------- families made here

def _matrix(rng, k, kind):
    """tests/test_linalg.py's matrices."""
    H = rng.standard_normal((k, k))
    if kind == "sparse":
        H[np.abs(H) < 1.0] = 0.0
    elif kind == "zero diagonal":
        np.fill_diagonal(H, 0.0)
    elif kind == "graded":
        H *= np.logspace(-6, 6, k)[:, None]
    elif kind == "banded":
        H = np.triu(np.tril(H, 2), -2)
    return H


KINDS = ["dense", "sparse", "zero diagonal", "graded", "banded"]

SINGULAR_OR_NOT_FINITE = [
    np.zeros((3, 3)),
    np.array([[1.0, 2.0], [2.0, 4.0]]),
    np.array([[1.0, 2.0, 3.0], [4.0, 5.0, 6.0], [1.0, 2.0, 3.0]]),
    np.array([[np.nan, 1.0], [1.0, 1.0]]),
    np.array([[np.inf, 1.0], [1.0, 1.0]]),
    np.array([[1.0, 1.0], [1.0, -np.inf]]),
    np.array([[1e-310, 0.0], [0.0, 1.0]]),
]


def _kkt(rng, n, p, rank=None, sparse=False):
    """The KKT matrix [[P, A'], [A, 0]] of a random convex QP and its right-hand side."""
    B = rng.standard_normal((n, n if rank is None else rank))
    P = B @ B.T
    A = rng.standard_normal((p, n))
    if sparse:
        P[np.abs(P) < 1.0] = 0.0
        P = (P + P.T) / 2
        A[np.abs(A) < 0.8] = 0.0
    K = np.zeros((n + p, n + p))
    K[:n, :n], K[:n, n:], K[n:, :n] = P, A.T, A
    return K, rng.standard_normal(n + p)


def test_dense_solves_on_the_linalg_tests_matrices():
    rng = np.random.default_rng(11)
    for kind in KINDS:
        for k in [0, 1, 2, 3, 4, 5, 7, 16, 33, 40, 64, 101]:
            H = _matrix(rng, k, kind)
            b = rng.standard_normal(k)
            same("linalg_solve", H, b)
            for pad in (0, 1, 2):
                G = np.full((k + pad, k + pad), 7.0)
                G[:k, :k] = H
                same("invert_in_place", G, k)
            for steps in (0, 1, 2, 3):
                same("refined_solve", H, b, steps, np.full(k, np.nan), np.full(k, 3.0))
    for H in SINGULAR_OR_NOT_FINITE:
        k = H.shape[0]
        same("linalg_solve", H, np.ones(k))
        same("invert_in_place", H.copy(), k)
        same("refined_solve", H, np.ones(k), 2, np.zeros(k), np.zeros(k))
    # sizes that do not fit: False (no exception)
    same("invert_in_place", np.eye(3), 4)
    same("invert_in_place", np.eye(3), -1)
    same("linalg_solve", np.eye(3), np.ones(2))
    same("linalg_solve", np.ones((2, 3)), np.ones(2))
    same("linalg_solve", np.eye(2), np.array([np.nan, 1.0]))
    lo2 = np.zeros(2)
    same("refined_solve", np.eye(2), np.array([1.0, np.inf]), 2, np.zeros(2), lo2)
    same("refined_solve", np.eye(3), np.ones(2), 2, np.zeros(2), lo2)
    same("refined_solve", np.eye(2), np.ones(2), 2, np.zeros(3), lo2)
    same("refined_solve", np.eye(2), np.ones(2), 2, np.zeros(2), np.zeros(3))
    same("refined_solve", np.ones((2, 3)), np.ones(2), 2, np.array([0.0, 0.0, np.inf]), lo2)
    k = 8  # Hilbert: the refinement does its work
    H = 1.0 / (np.arange(k)[:, None] + np.arange(k)[None, :] + 1.0)
    same("refined_solve", H, H @ np.arange(1.0, k + 1.0), 3, np.zeros(k), np.zeros(k))


def test_refined_solve_and_residual2_on_kkt_systems():
    """QP KKT systems (full rank, rank-deficient P, sparse), with given unknowns (a QP's
    active bounds) and without, at 0-3 refinement steps; residual2 on the same systems and
    on the front's doubled form [K K] (x, lo)."""
    rng = np.random.default_rng(16)
    for t in range(60):
        n, p = int(rng.integers(1, 30)), int(rng.integers(0, 10))
        rank = None if t % 3 == 0 else int(rng.integers(max(1, n - p), n + 1))
        K, rhs = _kkt(rng, n, p, rank, sparse=t % 2 == 1)
        k = n + p
        for j in (0, 1, 4):
            Kj = np.hstack([K, rng.standard_normal((k, j)) * (rng.random((k, j)) < 0.5)])
            x = frozen.empty(k + j)
            x[k:] = rng.standard_normal(j) * 10.0
            for steps in (0, 2, 3):
                same("refined_solve", Kj, rhs, steps, x, frozen.empty(k))
            xs = rng.standard_normal(k + j) * 10.0 ** rng.integers(-3, 4)
            same("residual2", Kj, xs, rhs, frozen.empty(k))
            same("residual2", np.hstack([Kj, Kj]), np.concatenate([xs, xs * 1e-17]), rhs, frozen.empty(k))
    for k, j in [(1, 1), (3, 2), (6, 5), (9, 1)]:  # test_linalg's given-unknowns systems
        K = rng.standard_normal((k, k + j))
        x = frozen.empty(k + j)
        x[k:] = rng.standard_normal(j) * 1e3
        same("refined_solve", K, rng.standard_normal(k), 3, x, frozen.empty(k))
    E = np.array([[1.0, np.inf], [np.nan, 0.0]])
    same("residual2", E, np.array([1.0, 2.0]), np.zeros(2), frozen.empty(2))
    same("residual2", E, np.array([0.0, np.nan]), np.zeros(2), frozen.empty(2))
    same("residual2", np.zeros((0, 3)), np.ones(3), np.zeros(0), frozen.empty(0))


def _mlcp_systems(rng):
    """Stacked MLCPs ``(E, e, n)``: the goldens' Siconos files, monotone ones with free
    variables (QP KKT systems, some with a singular free block), redundant and
    inconsistent equations."""
    for _, args in golden.mlcp_cases():
        A, B, C, D, a, b = args
        n = a.size
        E = np.block([[A, C], [D, B]]) if n and b.size else (A if n else B)
        yield np.ascontiguousarray(E, float), np.concatenate([a, b]).astype(float), n
    for t in range(40):
        nx, p, m = int(rng.integers(1, 10)), int(rng.integers(0, 5)), int(rng.integers(0, 8))
        Bx = rng.standard_normal((nx, int(rng.integers(0, nx + 1))))
        P = Bx @ Bx.T
        A = rng.standard_normal((p, nx))
        if t % 4 == 1 and p > 1:
            A[-1] = A[0]  # a redundant equation
        G = rng.standard_normal((m, nx))
        N = nx + p + m
        E = np.zeros((N, N))
        E[:nx, :nx], E[:nx, nx:nx + p], E[nx:nx + p, :nx] = P, A.T, -A
        E[:nx, nx + p:], E[nx + p:, :nx] = G.T, -G
        e = rng.standard_normal(N)
        if t % 4 == 1 and p > 1:
            e[nx + p - 1] = e[nx] + (1.0 if t % 8 == 1 else 0.0)  # inconsistent, or redundant
        yield E, e, nx + p
        yield np.ascontiguousarray(E[::-1, ::-1]), e[::-1].copy(), m  # v's first: free last
    yield np.zeros((3, 3)), np.array([0.0, 1.0, -1.0]), 2
    yield np.zeros((3, 3)), np.zeros(3), 1


def test_mlcp_reduction_on_stacked_systems():
    """equilibrate and reduce on the stacked MLCPs, as MLCPToLCP builds T; check_mlcp at
    the front's answers, at zero and at perturbed points."""
    rng = np.random.default_rng(21)
    from lemke._reductions import mlcp_lcp
    for E, e, n in _mlcp_systems(rng):
        N = e.size
        for iterations in (0, 1, 10):
            same("mlcp_equilibrate", E, n, iterations, np.ones(N), np.ones(N))
        r, s = mlcp_lcp.equilibrate(E, n)
        T = frozen.empty((N, N + 1))
        np.multiply(E, r[:, None] * s[None, :], out=T[:, :N])
        T[:, N] = e * r
        for rank_tol in (mlcp_lcp.RANK_TOL, 1e-3):
            same("mlcp_reduce", T, n, rank_tol, _certify.absmax(T[:, N]), frozen.empty(N, np.int64),
                 frozen.empty(N, np.int64))
        x = np.zeros(N)
        same("check_mlcp", E, e, n, x, 1e-9, frozen.empty(N))
        if N:
            from lemke._mlcp import solve_stacked
            from lemke._options import as_options
            res = solve_stacked(E, e, n, "tableau", as_options(None))
            x = np.concatenate([res.u, res.v])
            for xp in (x, x * (1 + 1e-9 * rng.standard_normal(N)), x + 1e-6, x * 1e17):
                same("check_mlcp", E, e, n, xp, 1e-9, frozen.empty(N))
            xn = x.copy()
            xn[-1] = np.nan
            same("check_mlcp", E, e, n, xn, 1e-9, frozen.empty(N))


def test_mlcp_reduce_when_the_swap_leaves_no_free_column():
    """A 2 x 2 exchange whose first pivot cancels the pair's row in every free column
    exactly (powers of two): reduce then exchanges with column -1, which it reads from the
    end (T's constant column, col_label's last entry), as the frozen references record."""
    a, p, b, f = 2.0**-34, 1.0, 2.0**-26, 2.0**8
    for e1 in (0.5, 0.0):
        T = np.array([[a, p, 0.25], [b, f, e1]])
        code, _ = same("mlcp_reduce", T, 1, 1e-9, 1.0, frozen.empty(2, np.int64), frozen.empty(2, np.int64))
        assert code == _core.MLCP_SINGULAR


def test_lcp_checks_on_solved_and_perturbed_points():
    """lcp_check on the goldens' LCP answers, moved by 1e-12..1e-3, with negative and zero
    entries, huge, NaN and infinite; lcp_ray_check on rays of random LCPs, perturbed, with
    the z0 part alone (the primary ray) and non-finite."""
    rng = np.random.default_rng(9)
    for _, M, q in golden.lcp_cases():
        M, q = np.ascontiguousarray(M, float), np.ascontiguousarray(q, float)
        n = q.size
        z = lemke.solve_lcp(M, q).z.copy()
        points = [z, np.zeros(n), z * 1e16]
        points += [z + eps * rng.standard_normal(n) for eps in (1e-12, 1e-9, 1e-6, 1e-3)]
        points += [np.maximum(z - 1e-10, 0.0), -z]
        for p in points:
            same("lcp_check", M, q, p, 1e-9, frozen.empty(n))
        if n:
            for bad in (np.nan, np.inf, -np.inf):
                p = z.copy()
                p[rng.integers(n)] = bad
                same("lcp_check", M, q, p, 1e-9, frozen.empty(n))
            same("lcp_check", M, q, z, 0.0, frozen.empty(n))
            same("lcp_check", M, q, z, 1e-3, frozen.empty(n))
    rays = 0
    for t in range(300):
        n = int(rng.integers(1, 16))
        M, q = rng.standard_normal((n, n)), rng.standard_normal(n)
        if t % 3 == 0:
            B = rng.standard_normal((n, max(1, n // 2)))
            M = B @ B.T
            M[0, :] = M[:, 0] = 0.0
            M[0, 0] = 0.0
            q[0] = -1.0
        r = lemke.solve_lcp(M, q)
        d = np.ascontiguousarray(r.covering)
        if r.ray is None:
            same("lcp_ray_check", M, q, d, r.z.copy(), 0.0, np.concatenate([r.z, [1.0]]), 1e-9)
            continue
        rays += 1
        ray = r.ray.copy()
        same("lcp_ray_check", M, q, d, r.z.copy(), float(r.z0), ray, 1e-9)
        same("lcp_ray_check", M, q, d, r.z.copy(), float(r.z0), ray + 1e-8 * rng.standard_normal(n + 1), 1e-9)
        primary = np.zeros(n + 1)
        primary[n] = 1.0
        same("lcp_ray_check", M, q, d, np.zeros(n), 1.0, primary, 1e-9)
        bad = ray.copy()
        bad[0] = np.inf
        same("lcp_ray_check", M, q, d, r.z.copy(), float(r.z0), bad, 1e-9)
        same("lcp_ray_check", M, q, d, r.z.copy(), np.nan, ray, 1e-9)
        same("lcp_ray_check", M, q, d, r.z.copy(), float(r.z0), -ray, 1e-9)
    assert rays > 50


def test_principal_block():
    rng = np.random.default_rng(4)
    for n in (0, 1, 5, 30):
        M = rng.standard_normal((n, n))
        for k in range(0, n + 1, max(1, n // 4)):
            same("principal_block", M, np.sort(rng.choice(n, size=k, replace=False)).astype(np.int64))
            same("principal_block", M, rng.integers(0, max(n, 1), size=k).astype(np.int64))  # repeats


def test_relabel_on_random_ids():
    """Random id arrays: kept, dropped, permuted and new rows; duplicates in either (-1,
    -2); ids that share low bits, negative ids, uint64 ids above 2**63 (as int64), empty
    arrays, and sizes across the tables' growth (16 slots up to thousands)."""
    rng = np.random.default_rng(12)
    for t in range(600):
        n = int(rng.integers(0, 40 if t < 500 else 3000))
        fresh = int(rng.integers(0, 8))
        ids = rng.choice(10**6, size=n + fresh, replace=False).astype(np.int64) * 4
        if t % 3 == 1:
            ids -= 2 * 10**6
        if t % 7 == 3:
            ids = (ids.astype(np.uint64) + np.uint64(2**63)).astype(np.int64)
        old, extra = rng.permutation(ids[:n]), ids[n:]
        kept = old[rng.permutation(n)[: int(rng.integers(0, n + 1))]]
        new = rng.permutation(np.concatenate([kept, extra]))
        if t % 10 == 4 and n > 1:
            old[-1] = old[0]
        if t % 10 == 5 and new.size > 1:
            new[-1] = new[0]
        basic = np.sort(rng.permutation(n)[: int(rng.integers(0, n + 1))]).astype(np.int64)
        same("relabel_ids", old, new, basic, np.full(new.size, -7, np.int64))


def test_bad_input_raises_and_never_crashes():
    """Mis-sized arrays raise ValueError; outputs of the wrong dtype, read-only or strided
    TypeError (never converted, so never written to a copy); kernels that answer False on
    bad sizes do so."""
    M, q = np.eye(3), np.ones(3)
    with pytest.raises(ValueError):
        _core.lcp_check(M, q, np.ones(2), 1e-9, frozen.empty(3))
    with pytest.raises(ValueError):
        _core.lcp_check(M, q, q, 1e-9, frozen.empty(4))
    with pytest.raises(TypeError):
        _core.lcp_check(M, q, q, 1e-9, frozen.empty(3, np.float32))
    with pytest.raises(TypeError):
        _core.lcp_check(M, q, q, 1e-9, frozen.empty(6)[::2])
    ro = frozen.empty(3)
    ro.setflags(write=False)
    with pytest.raises(TypeError):
        _core.lcp_check(M, q, q, 1e-9, ro)
    with pytest.raises(ValueError):
        _core.lcp_ray_check(M, q, q, q, 0.0, np.ones(3), 1e-9)
    with pytest.raises(ValueError):
        _core.residual2(M, np.ones(2), q, frozen.empty(3))
    with pytest.raises(ValueError):
        _core.check_mlcp(M, q, 4, q, 1e-9, frozen.empty(3))
    with pytest.raises(ValueError):
        _core.mlcp_equilibrate(M, -1, 10, np.ones(3), np.ones(3))
    with pytest.raises(ValueError):
        _core.mlcp_reduce(np.zeros((3, 3)), 1, 1e-9, 1.0, frozen.empty(3, np.int64), frozen.empty(3, np.int64))
    with pytest.raises(TypeError):
        _core.mlcp_reduce(np.zeros((3, 4)), 1, 1e-9, 1.0, frozen.empty(3, np.int32), frozen.empty(3, np.int64))
    with pytest.raises(ValueError):
        _core.principal_block(M, np.array([0, 3]))
    with pytest.raises(ValueError):
        _core.principal_block(M, np.array([-1]))
    with pytest.raises(ValueError):
        _core.relabel_ids(np.arange(3), np.arange(3), np.array([3]), frozen.empty(3, np.int64))
    with pytest.raises(ValueError):
        _core.relabel_ids(np.arange(3), np.arange(3), np.array([0]), frozen.empty(2, np.int64))
    with pytest.raises(TypeError):
        _core.invert_in_place(np.eye(4)[::2, ::2], 2)
    assert not _core.refined_solve(np.eye(3), np.ones(2), 2, np.zeros(2), np.zeros(2))
    # inputs are converted (a copy): a non-contiguous array gives the bits of its contiguous copy
    H = np.random.default_rng(13).standard_normal((10, 10))
    ok, x = _core.linalg_solve(H[::2, ::2], np.ones(5))
    assert ok and x.tobytes() == _core.linalg_solve(np.ascontiguousarray(H[::2, ::2]), np.ones(5))[1].tobytes()
    assert _core.lcp_check(np.eye(2, dtype=int), np.array([-1, -1]), np.ones(2), 1e-9, frozen.empty(2))[0]
