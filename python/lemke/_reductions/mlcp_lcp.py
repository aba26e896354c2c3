r"""MLCP -> LCP: exchange pivots that make the free variables basic, and the LCP left.

The mixed LCP in Siconos' form: find u (free, n of them) and v (m of them) with
``A u + C v + a = 0``, ``w = D u + B v + b``, ``0 <= v ⊥ w >= 0``; stacked,
``E x + e = (0, w)`` with ``x = (u, v)``.  The reduction (:class:`MLCPToLCP`):

1. equilibrate E (row and column scaling; a pair's row and column get the same factor,
   which keeps v ⊥ w);
2. exchange pivots make every u basic and every equation's slack non-basic
   (the C++ core's ``src/lemke/mlcp.cpp``): the free variables enter and
   stay basic, never split into two signs;
3. what is left is an LCP in the m pairs (some swapped: v_k basic, w_k the LCP's variable).

Its recovery maps the LCP's answer back, or recomputes the point of the final basis from
the caller's data (one dense solve, refined with residuals in double-double).
"""
from __future__ import annotations

import functools

import numpy as np

from .. import _core
from .._certify import absmax as _size
from .._npc import filled, nz, sub
from .._validate import c_aligned

RANK_TOL = 1e-9  # an exchange pivot must exceed this on the equilibrated data
EPS = float(np.finfo(np.float64).eps)


def equilibrate(E, n, iterations=10):
    """Scaling vectors ``(r, s)`` that bring every row and column of ``r E s`` near size 1
    (Ruiz's method): free rows and columns get their own factors, and a pair's row and
    column the same one, so that v ⊥ w is kept.  The sweeps run in the C++ core
    (``mlcp_equilibrate``: numpy's operations in numpy's order, the same bits);
    ``_equilibrate_numpy`` is the same in numpy, for the tests."""
    N = E.shape[0]
    r = np.ones(N)
    s = np.ones(N)
    if N == 0:  # an empty system: nothing to scale (and max over no entries is undefined)
        return r, s
    _core.mlcp_equilibrate(np.ascontiguousarray(E, dtype=np.float64), n, iterations, r, s)
    return r, s


def _equilibrate_numpy(E, n, iterations=10):
    """:func:`equilibrate` in numpy (the reference of the kernel's bits)."""
    N = E.shape[0]
    r = np.ones(N)
    s = np.ones(N)
    if N == 0:
        return r, s
    absE = np.abs(E)
    for _ in range(iterations):
        S = absE * r[:, None] * s[None, :]
        rows = S.max(axis=1)
        cols = S.max(axis=0)
        rows[rows == 0.0] = 1.0
        cols[cols == 0.0] = 1.0
        r[:n] /= np.sqrt(rows[:n])
        s[:n] /= np.sqrt(cols[:n])
        f = 1.0 / np.sqrt(np.maximum(rows[n:], cols[n:]))
        r[n:] *= f
        s[n:] *= f
        if np.all(np.abs(rows - 1.0) < 0.1) and np.all(np.abs(cols - 1.0) < 0.1):
            break
    return r, s


class MLCPToLCP:
    """The reduction of a stacked MLCP ``E x + e = (0, w)`` (n free variables first) to an
    LCP in its m pairs.

    ``apply``: building it equilibrates E and makes every free variable basic by exchange
    pivots; ``code`` says whether that worked (``_core.MLCP_OK``, ``MLCP_INCONSISTENT``: the
    equations contradict each other, ``SINGULAR``), and ``M, q`` is the LCP left
    (``M_clean`` the same with its rounding noise zeroed).  ``recover``: :meth:`point` turns
    the LCP's z (or a direction) into the MLCP's x; :meth:`to_reduced`/:meth:`v_basic`
    translate bases; :meth:`basis_point` recomputes the point of a basis from the caller's
    data."""

    def __init__(self, E, e, n):
        N = e.size
        self.n, self.N, self.m = n, N, N - n
        self.r, self.s = equilibrate(E, n)
        T = np.empty((N, N + 1))  # [E * (r s') | e * r], numpy's bits (the core's mlcp_scale)
        _core.mlcp_scale(np.ascontiguousarray(E, dtype=np.float64), e, self.r, self.s, T)
        self.row_label = np.empty(N, dtype=np.int64)
        self.col_label = np.empty(N, dtype=np.int64)
        self.code, self.bad_row = _core.mlcp_reduce(
            T, n, RANK_TOL, _size(T[:, N]), self.row_label, self.col_label
        )
        self.T = T
        if self.code != _core.MLCP_OK:
            return
        # Constants that cancel to zero in exact arithmetic come out at rounding level: a
        # -1e-16 would make Lemke's method start where the exchanged point already solves
        # the problem.  The data is equilibrated, so the exchanges' rounding is below
        # N eps max|T|.
        const = T[:, N]
        const[np.abs(const) < N * EPS * _size(e * self.r)] = 0.0
        # Pair k: output label n + k (w_k), input label N + n + k (v_k).  Where is each?
        where_row = filled(2 * N, -1, int)
        where_row[self.row_label] = np.arange(N)
        where_col = filled(2 * N, -1, int)
        where_col[self.col_label] = np.arange(N)
        k = np.arange(self.m)
        w_row, v_row = where_row[n + k], where_row[N + n + k]
        self.swapped = v_row >= 0  # v_k basic (in the row), w_k the LCP variable (column)
        self.posr = np.where(self.swapped, v_row, w_row)
        self.posc = np.where(self.swapped, where_col[n + k], where_col[N + n + k])
        self.M = np.ascontiguousarray(sub(T, self.posr, self.posc))
        self.q = T[self.posr, N].copy()
        # Rows where a free variable is basic, and what stayed behind (redundant pairs).
        self.free_rows = nz((self.row_label >= N) & (self.row_label < N + n))
        self.redundant = np.sort(self.row_label[self.row_label < n])  # equations left out
        undetermined = self.col_label[(self.col_label >= N) & (self.col_label < N + n)] - N
        self.undetermined = np.sort(undetermined)  # free variables set to 0

    @functools.cached_property
    def M_clean(self):
        """M with its rounding noise zeroed, the ladder's second try (see solve_stacked): left
        in, noise can be pivoted on (a column of pure noise passes any test relative to its own
        size), but zeroing it changes the tie-breaking of degenerate paths, so it is not the
        first try.  Made when first read (most solves end on the first try; an m x m pass):
        M and T are not written after the reduction, so it has the bits it had when made at
        once."""
        N = self.N
        return np.where(np.abs(self.M) < N * EPS * max(1.0, _size(self.T[:, :N])), 0.0, self.M)

    def to_reduced(self, v_basic: np.ndarray) -> np.ndarray:
        """Which LCP z's are basic, for the basis where v_k is basic when v_basic[k]."""
        return v_basic ^ self.swapped

    def v_basic(self, z_basic: np.ndarray) -> np.ndarray:
        return z_basic ^ self.swapped

    def point(self, z, z_dir=False):
        """The stacked x = (u, v) of the MLCP from the reduced LCP's z (a direction when
        z_dir: no constant term), in the caller's units."""
        N, n = self.N, self.n
        col = np.zeros(N)
        col[self.posc] = z
        basic = self.T[:, self.posc] @ z
        if not z_dir:
            basic += self.T[:, N]
        xs = np.zeros(N)
        for labels, values in ((self.row_label, basic), (self.col_label, col)):
            inputs = labels >= N
            xs[labels[inputs] - N] = values[inputs]
        return xs * self.s

    def basis_point(self, E, e, v_basic):
        """The MLCP point of the basis where v_k is basic when v_basic[k], from the caller's
        data (see :func:`basis_point`); None if singular."""
        return basis_point(E, e, self.n, v_basic, self)


def basis_point(E, e, n, v_basic, red):
    """The point of the basis (all determined u basic, v_k basic where v_basic[k]) from the
    caller's data: one dense solve and two steps of iterative refinement on the block of the
    kept equations and determined u and the basic v's (the seam's MLCP basis system,
    ``MlcpBasis`` in ``src/lemke/basis.hpp``, through ``_core.mlcp_basis``; v clipped at 0).
    None if there is no square block, it is singular or the point is not finite."""
    code, x, _, _, _ = _core.mlcp_basis(
        c_aligned(E, dtype=np.float64), c_aligned(e, dtype=np.float64), int(n),
        c_aligned(red.redundant, dtype=np.int64), c_aligned(red.undetermined, dtype=np.int64),
        np.ascontiguousarray(v_basic, dtype=bool))
    return None if code == 2 else x


def refined_solve(K, rhs, steps=2, given=None, low=False):
    """Solve K x = rhs with iterative refinement whose residuals are summed in double-double
    (``refined_solve`` of the C++ core, ``src/lemke/linalg.cpp``: one LU
    factorization on one thread, reused by every
    step; x carried in double-double, so that it comes out as the rounding of the exact
    solution): on a degenerate basis a variable that is zero comes out zero to the last
    digits instead of at cond(K) eps.  ``given``: the values of K's last ``given.size``
    unknowns (K then has that many more columns than rows), which enter every residual as
    they are; the others are returned.  None if K's square block is singular or x is not
    finite; with ``low``, ``(x, lo)``: x + lo is the exact solution to about eps^2."""
    k = rhs.size
    x = np.empty(k if given is None else k + given.size)  # the kernel checks K's shape
    x[k:] = () if given is None else given
    lo = np.empty(k)
    ok = _core.refined_solve(np.ascontiguousarray(K, dtype=np.float64),
                               np.ascontiguousarray(rhs, dtype=np.float64), steps, x, lo)
    if not ok:
        return None
    return (x[:k], lo) if low else x[:k]
