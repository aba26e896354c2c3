"""Each reduction alone (lemke/_reductions): applied to a problem with a known answer, its
reduced problem is solved independently and the recovered answer is checked on the
original problem's own conditions, with plain numpy."""
import numpy as np
import pytest
import quadprog

from helpers import enumerate_solutions
from lemke._reductions.mlcp_lcp import MLCPToLCP
from lemke._reductions.qp_mlcp import QPToMLCP
from lemke import _core


def _random_qp(seed, n=6, m=4, p=2):
    rng = np.random.default_rng(seed)
    B = rng.standard_normal((n, n))
    P = B @ B.T + 0.1 * np.eye(n)
    x0 = rng.standard_normal(n)
    G = rng.standard_normal((m, n))
    A = rng.standard_normal((p, n))
    lb = np.where(rng.random(n) < 0.5, x0 - rng.uniform(0.1, 1, n), -np.inf)
    ub = np.where(rng.random(n) < 0.5, x0 + rng.uniform(0.1, 1, n), np.inf)
    return P, rng.standard_normal(n), G, G @ x0 + rng.uniform(0, 1, m), A, A @ x0, lb, ub


def _quadprog(P, q, G, h, A, b, lb, ub):
    """x and qpsolvers-signed multipliers (y, z, z_box) from quadprog (an independent
    active-set solver): quadprog solves min 1/2 x'Px - a'x s.t. C'x >= c0, first meq rows
    equalities."""
    n = q.size
    lo, up = np.isfinite(lb), np.isfinite(ub)
    C = np.vstack([A, -G, np.eye(n)[lo], -np.eye(n)[up]]).T
    c0 = np.concatenate([b, -h, lb[lo], -ub[up]])
    x, _, _, _, lam, _ = quadprog.solve_qp(P, -q, C, c0, A.shape[0])
    p, m = A.shape[0], G.shape[0]
    y, z = -lam[:p], lam[p:p + m]
    z_box = np.zeros(n)
    z_box[lo] -= lam[p + m:p + m + lo.sum()]
    z_box[up] += lam[p + m + lo.sum():]
    return x, y, z, z_box


@pytest.mark.parametrize("seed", range(8))
def test_qp_to_mlcp_alone(seed):
    data = _random_qp(seed)
    P, q, G, h, A, b, lb, ub = data
    red = QPToMLCP(*data)
    x, y, z, z_box = _quadprog(*data)
    # apply: the KKT point of quadprog, mapped forward, solves the MLCP E (u, v) + e = (0, w)
    xm = red.forward(x, y, z, z_box)
    r = red.E @ xm + red.e
    scale = 1e-7 * (1 + np.abs(red.E) @ np.abs(xm) + np.abs(red.e))
    nf = red.n_free
    v, w = xm[nf:], r[nf:]
    assert np.all(np.abs(r[:nf]) <= scale[:nf])
    assert np.all(v >= -scale[nf:]) and np.all(w >= -scale[nf:])
    assert np.all(np.minimum(np.abs(v), np.abs(w)) <= scale[nf:])
    # monotone: the symmetric part of E is positive semidefinite
    assert np.linalg.eigvalsh(red.E + red.E.T).min() >= -1e-9 * np.abs(red.E).max()
    # recover: back to the QP's point and multipliers
    x2, y2, z2, zb2 = red.recover(xm, r[nf:])
    for a, c in ((x2, x), (y2, y), (z2, z), (zb2, z_box)):
        np.testing.assert_allclose(a, c, atol=1e-7 * (1 + np.abs(c).max(initial=0)))


def _mlcp_with_solution(seed, n=3, m=5):
    """A monotone MLCP and, through its reduction, every solution checked directly."""
    rng = np.random.default_rng(seed)
    K = rng.standard_normal((n + m, n + m))
    E = K @ K.T + (K - K.T)  # positive definite symmetric part: monotone, a unique solution
    e = rng.standard_normal(n + m)
    return E, e, n


@pytest.mark.parametrize("seed", range(8))
def test_mlcp_to_lcp_alone(seed):
    E, e, n = _mlcp_with_solution(seed)
    red = MLCPToLCP(E, e, n)
    assert red.code == _core.MLCP_OK
    sols = enumerate_solutions(red.M, red.q)  # the reduced LCP, solved by enumeration
    assert sols
    for zr in sols:
        x = red.point(zr)
        r = E @ x + e
        scale = 1e-8 * (1 + np.abs(E) @ np.abs(x) + np.abs(e))
        v, w = x[n:], r[n:]
        assert np.all(np.abs(r[:n]) <= scale[:n])
        assert np.all(v >= -scale[n:]) and np.all(w >= -scale[n:])
        assert np.all(np.minimum(np.abs(v), np.abs(w)) <= scale[n:])


def test_mlcp_to_lcp_finds_contradictory_equations():
    # u1 + u2 = 1 and u1 + u2 = 2 (n = 2, m = 1): no x satisfies the equations
    E = np.array([[1.0, 1.0, 0.0], [1.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    e = np.array([-1.0, -2.0, 0.0])
    assert MLCPToLCP(E, e, 2).code == _core.MLCP_INCONSISTENT


@pytest.mark.parametrize("seed", range(60))
def test_equilibrate_kernel_matches_numpy_bit_for_bit(seed):
    """The MLCP reduction's Ruiz scaling runs in a kernel (lemke::mlcp_equilibrate); it
    must give numpy's bits (the QP goldens depend on them), zero rows and columns, wide
    ranges of magnitudes and every split of free and paired variables included; dense E
    and E under a third non-zero (the kernel's sweeps over the non-zeros alone, up to
    N = 200)."""
    from lemke._reductions.mlcp_lcp import _equilibrate_numpy, equilibrate

    rng = np.random.default_rng(seed)
    N = int(rng.integers(1, 30 if seed % 3 == 0 else 200))
    n = int(rng.integers(0, N + 1))
    E = rng.standard_normal((N, N)) * np.exp(rng.uniform(-10, 10, (N, N)))
    E[rng.random((N, N)) < (0.4, 0.8, 0.97)[seed % 3]] = 0.0
    if seed % 4 == 0:
        E[int(rng.integers(N))] = 0.0  # a zero row
    if seed % 5 == 0:
        E[:, int(rng.integers(N))] = 0.0  # a zero column
    for a, b in zip(equilibrate(E, n), _equilibrate_numpy(E, n)):
        assert np.array_equal(a.view(np.int64), b.view(np.int64))


@pytest.mark.parametrize("seed", range(10))
def test_mlcp_scale_matches_numpy_bit_for_bit(seed):
    """The reduction's scaled dictionary T = [E * (r s') | e * r] comes from a kernel
    (lemke::mlcp_scale): numpy's bits, signed zeros included."""
    from lemke import _core

    rng = np.random.default_rng(seed)
    N = int(rng.integers(0, 40))
    E = rng.standard_normal((N, N)) * np.exp(rng.uniform(-300, 300, (N, N)))
    E[rng.random((N, N)) < 0.5] = rng.choice([0.0, -0.0])
    e = rng.standard_normal(N)
    r, s = np.exp(rng.uniform(-20, 20, N)), np.exp(rng.uniform(-20, 20, N))
    T = np.empty((N, N + 1))
    _core.mlcp_scale(E, e, r, s, T)
    assert np.array_equal(T[:, :N].view(np.int64), (E * (r[:, None] * s[None, :])).view(np.int64))
    assert np.array_equal(T[:, N].view(np.int64), (e * r).view(np.int64))
