"""Independent checks used by the tests (deliberately not lemke's own certify code)."""
import contextlib
import itertools

import numpy as np


def assert_lcp_solution(M, q, z, rtol=1e-8):
    """Assert z >= 0, w = Mz + q >= 0 and z'w = 0, each relative to the problem's scale."""
    M = np.asarray(M, dtype=float)
    q = np.asarray(q, dtype=float)
    z = np.asarray(z, dtype=float)
    assert z.shape == q.shape
    if q.size == 0:
        return
    w = M @ z + q
    z_scale = max(np.abs(z).max(), np.finfo(float).tiny)
    w_scale = max(np.abs(q).max(), np.abs(M).max() * np.abs(z).max())
    assert z.min() >= -rtol * z_scale, f"z has a negative entry {z.min()}"
    assert w.min() >= -rtol * w_scale, f"w = Mz + q has a negative entry {w.min()} (scale {w_scale})"
    worst = np.max(np.abs(z * w))
    assert worst <= rtol * z_scale * w_scale, f"z'w is not 0: max |z_i w_i| = {worst}"


def assert_lcp_solution_rowwise(M, q, z, rtol=1e-8):
    """Assert that z solves LCP(M, q) row by row, each row against its own size.

    With ``s_i = |M_i.| |z| + |q_i|`` (the size of the terms that make up w_i):
    w_i >= -rtol s_i for every i, and |w_i| <= rtol s_i wherever z_i > 0.  Unlike
    :func:`assert_lcp_solution` this is unchanged by row and column scalings
    (``D1 M D2``, ``D1 q``, z -> D2^-1 z), so a row whose entries are tiny next to the
    others' is held to its own scale.  z must be >= 0: a negative z_j is allowed only when
    it is rounding noise on a zero, i.e. its column of M is not zero and it moves no row by
    more than that row's tolerance (|M_rj z_j| <= rtol s_r for all r).

    Meant for problems such as P-matrices with dense rows.  On a degenerate problem whose
    solution leaves a row with nothing but rounding noise in it (a friction-cone row
    mu c_n - beta+ - beta- of an idle contact, all three ~1e-16) that noise is the row's
    whole size, and the test fails although the answer is right to working precision.
    """
    M = np.asarray(M, dtype=float)
    q = np.asarray(q, dtype=float)
    z = np.asarray(z, dtype=float)
    assert z.shape == q.shape and np.all(np.isfinite(z)), "z has the wrong shape or is not finite"
    if q.size == 0:
        return
    w = M @ z + q
    s = np.abs(M) @ np.abs(z) + np.abs(q)
    # A negative z_j passes when it moves no row by more than that row's tolerance.
    negligible = np.any(M != 0, axis=0) & np.all(np.abs(M) * np.abs(z)[None, :] <= rtol * s[:, None], axis=0)
    bad = np.flatnonzero((z < 0) & ~negligible)
    assert bad.size == 0, f"z has negative entries {z[bad][:5]} at {bad[:5]}"
    low = np.flatnonzero(w < -rtol * s)
    assert low.size == 0, (f"w = Mz + q is negative in rows {low[:5]}: w = {w[low][:5]}, "
                           f"row sizes {s[low][:5]}")
    open_ = np.flatnonzero((z > 0) & (np.abs(w) > rtol * s))
    assert open_.size == 0, (f"z_i > 0 with w_i != 0 in rows {open_[:5]}: z = {z[open_][:5]}, "
                             f"w = {w[open_][:5]}, row sizes {s[open_][:5]}")


def assert_ray(M, q, d, z, z0, ray, rtol=1e-8):
    """Assert that (z, z0) + t * ray stays almost complementary and feasible for all t >= 0."""
    M = np.asarray(M, dtype=float)
    q, d, z = (np.asarray(a, dtype=float) for a in (q, d, z))
    n = len(q)
    ray = np.asarray(ray, dtype=float)
    dz, dz0 = ray[:n], ray[n]
    scale = np.abs(ray).max()
    assert scale > 0, "the ray direction is zero"
    # dz = 0 is the primary ray (z = 0, z0 growing), which every LCP has: no certificate.
    # Measured where dz acts, on du = M dz + d dz0, row by row (so that no scaling of the
    # rows or columns changes the verdict): in some row |M_i.| |dz| must not be negligible
    # next to d_i dz0.  (A genuine ray with dz0 > 0 has du_i = 0 where dz_i > 0, so there
    # |M_i.| |dz| >= d_i dz0.)
    assert np.abs(dz).max() > 0, "the ray only moves z0 (dz = 0: the primary ray)"
    if dz0 > 0:
        reach = np.abs(M) @ np.abs(dz)
        assert np.any(reach > rtol * np.abs(d) * dz0), "the ray only moves z0 (dz is rounding next to dz0: the primary ray)"
    assert dz.min() >= -rtol * scale and dz0 >= -rtol * scale, "the ray leaves z >= 0"
    u = M @ z + q + d * z0
    du = M @ dz + d * dz0
    u_scale = max(np.abs(q).max(), np.abs(M).max() * max(np.abs(z).max(), 1e-300), np.abs(d).max() * z0)
    du_scale = max(np.abs(M).max(), np.abs(d).max()) * scale
    assert u.min() >= -rtol * u_scale, "the ray's start is infeasible"
    assert du.min() >= -rtol * du_scale, "w decreases along the ray"
    for a, b, sa, sb in ((z, u, 1.0, u_scale), (z, du, 1.0, du_scale), (dz, u, scale, u_scale), (dz, du, scale, du_scale)):
        assert np.max(np.abs(a * b)) <= rtol * max(sa, np.abs(z).max()) * sb, "complementarity fails along the ray"
    # Where the ray moves z (dz_i > 0), u_i = 0, so w_i = (M z + q)_i = -d_i z0 < 0: z0 is
    # what keeps the start from being a solution there, and the infeasibility proof rests
    # on it (dz'q + dz'M z = -z0 dz'd).  A w_i that is not clearly negative (z0 rounding in
    # that row) certifies nothing.
    w = M @ z + q
    moved = np.flatnonzero(dz > rtol * np.abs(dz).max())
    size = np.abs(M[moved]) @ np.abs(z) + np.abs(q[moved]) + np.abs(d[moved]) * z0
    assert np.all(w[moved] < -rtol * size), f"z0 is rounding in rows {moved[w[moved] >= -rtol * size][:5]} that the ray moves"


def _bounds(n, lb, ub):
    lb = np.full(n, -np.inf) if lb is None else np.asarray(lb, dtype=float)
    ub = np.full(n, np.inf) if ub is None else np.asarray(ub, dtype=float)
    return np.where(lb <= -1e20, -np.inf, lb), np.where(ub >= 1e20, np.inf, ub)


def _rows(M, v, n):
    if M is None:
        return np.zeros((0, n)), np.zeros(0)
    return np.atleast_2d(np.asarray(M, dtype=float)), np.asarray(v, dtype=float).reshape(-1)


def assert_qp_kkt(P, q, G, h, A, b, lb, ub, res, rtol=1e-8):
    """Assert the KKT conditions of min 1/2 x'Px + q'x s.t. Gx <= h, Ax = b, lb <= x <= ub
    at (res.x, res.y, res.z, res.z_box), each relative to the sizes involved."""
    P = np.asarray(P, dtype=float)
    q = np.asarray(q, dtype=float)
    n = q.size
    G, h = _rows(G, h, n)
    A, b = _rows(A, b, n)
    lb, ub = _bounds(n, lb, ub)
    x, y, z, zb = (np.asarray(a, dtype=float) for a in (res.x, res.y, res.z, res.z_box))
    assert x.shape == (n,) and y.shape == b.shape and z.shape == h.shape and zb.shape == (n,)
    xs = max(1.0, np.abs(x).max(initial=0.0))
    data = max([1.0] + [np.abs(a).max() for a in (P, q, G, h, A, b) if a.size])
    mult = max([1.0] + [np.abs(a).max() for a in (y, z, zb) if a.size])
    # primal feasibility
    if h.size:
        assert (G @ x - h).max() <= rtol * data * xs, "G x <= h fails"
    if b.size:
        assert np.abs(A @ x - b).max() <= rtol * data * xs, "A x = b fails"
    assert np.all(x >= lb - rtol * xs) and np.all(x <= ub + rtol * xs), "bounds fail"
    # dual feasibility and stationarity
    assert np.all(z >= -rtol * mult), "a multiplier of G x <= h is negative"
    stat = np.abs(P @ x + q + A.T @ y + G.T @ z + zb).max(initial=0.0)
    assert stat <= rtol * data * max(xs, mult), f"stationarity fails: {stat}"
    # complementarity: inactive constraints and bounds have zero multipliers
    if h.size:
        slack = h - G @ x
        assert np.max(np.abs(z * slack)) <= rtol * data * xs * mult, "z'(h - Gx) is not 0"
    lo_gap = np.where(np.isfinite(lb), x - lb, np.inf)
    up_gap = np.where(np.isfinite(ub), ub - x, np.inf)
    tol_b = rtol * data * xs * mult
    assert np.all((zb >= -rtol * mult) | (np.minimum(lo_gap, 1e300) * -zb <= tol_b)), "z_box < 0 off a lower bound"
    assert np.all((zb <= rtol * mult) | (np.minimum(up_gap, 1e300) * zb <= tol_b)), "z_box > 0 off an upper bound"
    assert np.isclose(res.obj, 0.5 * x @ P @ x + q @ x, rtol=1e-12, atol=1e-12 * data * xs * xs)


def assert_farkas(G, h, A, b, lb, ub, cert, n, rtol=1e-8):
    """Assert that (y, z, z_box) proves {Gx <= h, Ax = b, lb <= x <= ub} empty:
    z >= 0, z_box signs allowed by finite bounds, G'z + A'y + z_box = 0 and
    h'z + b'y + lb'min(z_box, 0) + ub'max(z_box, 0) < 0."""
    G, h = _rows(G, h, n)
    A, b = _rows(A, b, n)
    lb, ub = _bounds(n, lb, ub)
    y, z, zb = (np.asarray(a, dtype=float) for a in (cert.y, cert.z, cert.z_box))
    scale = max(np.abs(y).max(initial=0), np.abs(z).max(initial=0), np.abs(zb).max(initial=0))
    assert scale > 0
    y, z, zb = y / scale, z / scale, zb / scale
    assert np.all(z >= 0), "Farkas z must be >= 0"
    assert np.all(zb[~np.isfinite(lb)] >= 0) and np.all(zb[~np.isfinite(ub)] <= 0), "z_box sign without a bound"
    data = max([1.0] + [np.abs(a).max() for a in (G, A) if a.size])
    assert np.abs(G.T @ z + A.T @ y + zb).max(initial=0.0) <= rtol * data
    lo, up = np.isfinite(lb), np.isfinite(ub)
    value = h @ z + b @ y + lb[lo] @ np.minimum(zb[lo], 0) + ub[up] @ np.maximum(zb[up], 0)
    assert value < -rtol * data, f"the Farkas value {value} is not negative"


def assert_unbounded_direction(P, q, G, A, lb, ub, cert, rtol=1e-8):
    """Assert that dx is a direction of unbounded descent: P dx = 0, A dx = 0, G dx <= 0,
    dx within the bounds' recession cone and q'dx < 0."""
    P = np.asarray(P, dtype=float)
    q = np.asarray(q, dtype=float)
    n = q.size
    G, _ = _rows(G, np.zeros(0 if G is None else np.atleast_2d(G).shape[0]), n)
    A, _ = _rows(A, np.zeros(0 if A is None else np.atleast_2d(A).shape[0]), n)
    lb, ub = _bounds(n, lb, ub)
    d = np.asarray(cert.dx, dtype=float)
    d = d / np.abs(d).max()
    data = max([1.0] + [np.abs(a).max() for a in (P, G, A, q) if a.size])
    assert np.abs(P @ d).max() <= rtol * data
    if A.size:
        assert np.abs(A @ d).max() <= rtol * data
    if G.size:
        assert (G @ d).max() <= rtol * data
    assert np.all(d[np.isfinite(lb)] >= 0) and np.all(d[np.isfinite(ub)] <= 0)
    assert q @ d < -rtol * data


def enumerate_solutions(M, q):
    """Every solution at a complementary basis with a non-singular M_aa, by trying all 2^n
    of them (small n only), each accepted by :func:`assert_lcp_solution`."""
    M = np.asarray(M, dtype=float)
    q = np.asarray(q, dtype=float)
    n = q.size
    found = []
    for k in range(n + 1):
        for a in itertools.combinations(range(n), k):
            a = list(a)
            z = np.zeros(n)
            if a:
                try:
                    z[a] = np.linalg.solve(M[np.ix_(a, a)], -q[a])
                except np.linalg.LinAlgError:
                    continue
            try:
                assert_lcp_solution(M, q, z)
            except AssertionError:
                continue
            found.append(z)
    return found


def assert_nash(A, B, x, y, rtol=1e-9):
    """Assert that (x, y) is a Nash equilibrium of the bimatrix game (A, B) (A the row
    player's payoffs, B the column player's, both m x n), in plain numpy: x and y are
    probability vectors, and every pure strategy in the support of x is a best response to
    y (its payoff ``(A y)_i`` within ``rtol`` times the range of A of the best), and the
    same for y against x with B."""
    A, B = np.asarray(A, dtype=float), np.asarray(B, dtype=float)
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    m, n = A.shape
    assert x.shape == (m,) and y.shape == (n,), f"strategies of shapes {x.shape}, {y.shape} for a {m} x {n} game"
    for v, who in ((x, "x"), (y, "y")):
        assert np.all(np.isfinite(v)) and v.min() >= 0, f"{who} has a negative or non-finite entry"
        assert abs(v.sum() - 1) <= 1e-12 * v.size, f"{who} sums to {v.sum()}, not 1"
    for P, own, other, who in ((A, x, y, "row"), (B.T, y, x, "column")):
        payoff = P @ other  # each pure strategy's payoff against the other's mixed strategy
        tol = rtol * max(np.ptp(P), 1e-300) + 1e-15 * np.abs(P).max()
        support = np.flatnonzero(own > 0)
        worst = payoff.max() - payoff[support].min()
        assert worst <= tol, (f"the {who} player's strategy {int(support[np.argmin(payoff[support])])} is in "
                              f"the support but {worst:.3g} short of a best response")


def interrupt_child(code, *args, wait=1.0):
    """Start ``python -c code *args`` (which prints "ready", then works until SIGINT and
    prints "interrupted <time.time()>" from its KeyboardInterrupt handler), send SIGINT
    after ``wait`` seconds and return ``(line, returncode, sent, exited)``: its last line,
    its exit code, and the times the signal was sent and the process was seen to end."""
    import signal
    import subprocess
    import sys
    import time

    # SIGINT back to Python's handler first: a shell that starts the tests in the background
    # (`cmd &`) hands its children SIGINT ignored, and the child would never be interrupted.
    code = "import signal; signal.signal(signal.SIGINT, signal.default_int_handler)\n" + code
    child = subprocess.Popen([sys.executable, "-c", code, *args], stdout=subprocess.PIPE, text=True)
    try:
        assert child.stdout.readline().strip() == "ready"
        time.sleep(wait)
        assert child.poll() is None, "the child ended before the interrupt"
        sent = time.time()
        child.send_signal(signal.SIGINT)
        line = child.stdout.readline()
        rc = child.wait(timeout=30)
        exited = time.time()
    finally:
        if child.poll() is None:
            child.kill()
            child.wait()
        child.stdout.close()
    return line, rc, sent, exited


@contextlib.contextmanager
def native_fronts_off():
    """The native fronts switched off for the block (lcp_front_init given a wrong data
    address: its layout check fails, as where NumPy lays arrays out otherwise), then on
    again (``_result.native_fronts_init``)."""
    import lemke
    from lemke import _core, _result
    probe = np.zeros((2, 3))
    ro = np.zeros(3)
    ro.setflags(write=False)
    try:
        _core.lcp_front_init(np.ndarray, lemke.LCPResult, lemke.Status.SOLVED,
                             lemke.Status.RAY_TERMINATION, np.empty, 1e-11, 1e-11, 1e-9, probe,
                             probe.__array_interface__["data"][0] + 8, ro,
                             np.zeros(3, dtype=np.int64), np.zeros(3, dtype=">f8"), None)
        assert not _core.lcp_front_on()
        yield
    finally:
        _result.native_fronts_init()
    assert _core.lcp_front_on()


def kkt_blocks(qp, z_basic):
    """The active set of a basis of a QP's KKT MLCP (``qp`` its QPToMLCP; ``z_basic`` the basic
    pairs: the shifted x', the rows of G, the boxed variables' upper multipliers), as
    ``_qp._polished``'s numpy code read it before the seam (src/lemke/basis.hpp's KktBasis
    now): ``(F, B, S, bound, K, rhs)``, F the free variables, B those held at ``bound``, S
    the active rows of G, K the rows of F, A and G_S over the columns x_F, y, z_S, then x_B,
    and rhs = (-q_F, b, h_S)."""
    from lemke._npc import filled, nz, sub
    n, p, mg = qp.n, qp.A.shape[0], qp.G.shape[0]
    nn, nb = qp.shifted.size, qp.boxed.size
    v = np.zeros(nn + mg + nb, dtype=bool)
    v[list(z_basic)] = True
    bound = filled(n, np.nan)
    lower = qp.shifted[~v[:nn]]
    bound[lower] = qp.x0[lower]
    upper = qp.shifted[qp.boxed[v[nn + mg:]]]
    bound[upper] = qp.ub[upper]
    bound[qp.fixed] = qp.lb[qp.fixed]
    S = nz(v[nn:nn + mg])
    held = ~np.isnan(bound)
    B, F = nz(held), nz(~held)
    GS = qp.G[S]
    f, k, s = F.size, F.size + p, F.size + p + S.size
    K = np.zeros((s, s + B.size))
    K[:f, :f] = sub(qp.P, F, F)
    K[:f, f:k] = qp.A[:, F].T
    K[:f, k:s] = GS[:, F].T
    K[f:k, :f] = qp.A[:, F]
    K[k:s, :f] = GS[:, F]
    K[:f, s:] = sub(qp.P, F, B)
    K[f:k, s:] = qp.A[:, B]
    K[k:s, s:] = GS[:, B]
    return F, B, S, bound, K, np.concatenate([-qp.q[F], qp.b, qp.h[S]])
