"""Islands of the 3-D contact scene (examples/contact_3d.py, issue 32) that solve_blcp once
refused or paid a cold solve for, kept in tests/data/contact3d/islands.npz:

* ``ray_cold``, ``refused_cold``, ``refused_cold_warm`` (75-108 rows): answers that pass an
  independent check, refused by the row-wise check (RAY_TERMINATION, NUMERICAL_FAILURE)
  because the extended problem's final basis is singular and the tableau's point carries
  its rounding into rows whose own terms are ~1e-11; now SOLVED by the same basis solved
  on the caller's rows (``_blcp._caller_point``), whose refusal of a wrong basis is tested
  too;
* ``singular_warm``: a carried basis whose extended block is singular (a λ basic with β+
  and β- at 0), once SINGULAR and a cold solve, now a warm run from the rest of it
  (``boxed.PARTIAL``);
* ``warm_ray``: a warm run that ends on a secondary ray; the basis with its friction rows
  cold (``_blcp._reset``) then solves it;
* ``failed_cold`` (192 rows): no answer before, cold or from the final basis; the restart
  from that basis goes on with its friction rows cold and solves it.

Every answer is checked here with numpy, row by row in the friction pyramid's terms."""
from pathlib import Path

import numpy as np
import pytest

import lemke
from lemke import _blcp
from lemke._core import boxed

DATA = np.load(Path(__file__).resolve().parent / "data" / "contact3d" / "islands.npz")


def island(name):
    A, b, fi = DATA[f"{name}_A"], DATA[f"{name}_b"], DATA[f"{name}_findex"]
    mu = float(DATA[f"{name}_mu"][0])
    lo = np.where(fi >= 0, -mu, 0.0)
    hi = np.where(fi >= 0, mu, np.inf)
    ws = lemke.BoxWarmStart.from_row_states(DATA[f"{name}_states"])
    return A, b, lo, hi, fi, ws


def pyramid_rows(A, b, lo, hi, fi, z, rtol=1e-9):
    """Independent check, row by row: the largest violation of a row's conditions relative
    to that row's own terms |A_i||z| + |b_i| plus rtol * max|b| (the data's rounding floor):
    normal rows 0 <= z, w >= 0, z w = 0; friction rows |z_i| <= mu z_f, w_i = 0 inside,
    w_i <= 0 at +mu z_f, w_i >= 0 at -mu z_f (any w_i where mu z_f is below z's rounding
    floor, rtol max|z|).  Returns the worst ratio (<= 1 passes)."""
    w = A @ z + b
    scale = rtol * (np.abs(A) @ np.abs(z) + np.abs(b)) + rtol * np.abs(b).max()
    zs = rtol * max(np.abs(z).max(), 1e-300)
    worst = 0.0
    for i in range(z.size):
        f = fi[i]
        if f < 0:
            bad = max(-z[i] / zs, -w[i] / scale[i], min(z[i] / zs, abs(w[i]) / scale[i]))
        else:
            cap = hi[i] * z[f]
            over = (abs(z[i]) - cap) / zs
            inside = abs(z[i]) < cap - zs
            bad = over
            if cap <= zs:  # a contact without load: any w_i
                pass
            elif inside:
                bad = max(bad, abs(w[i]) / scale[i])
            elif z[i] > 0:
                bad = max(bad, w[i] / scale[i])
            elif z[i] < 0:
                bad = max(bad, -w[i] / scale[i])
        worst = max(worst, bad)
    return worst


@pytest.mark.parametrize("name", ["ray_cold", "refused_cold", "refused_cold_warm"])
@pytest.mark.parametrize("warm", [False, True])
def test_islands_once_refused_are_solved(name, warm):
    A, b, lo, hi, fi, ws = island(name)
    r = lemke.solve_blcp(A, b, lo, hi, findex=fi, warm_start=ws if warm else None)
    assert r.status == lemke.Status.SOLVED
    z = np.asarray(r.z)
    assert pyramid_rows(A, b, lo, hi, fi, z) <= 1.0
    wrong = z.copy()
    wrong[np.argmax(wrong)] *= 1.001
    assert pyramid_rows(A, b, lo, hi, fi, wrong) > 1.0  # (the check can fail)
    # the one-call batch gives the same answer
    many = lemke.solve_blcp_many([A], [b], [lo], [hi], findex=[fi], warm_start=[ws] if warm else None)
    assert many[0].status == lemke.Status.SOLVED and np.asarray(many[0].z).tobytes() == z.tobytes()


def _final_flags(name):
    A, b, lo, hi, fi, _ = island(name)
    r = lemke.solve_blcp(A, b, lo, hi, findex=fi)
    Mx, qx, lox, hix, F, normal = _blcp.friction_lcp(A, b, lo, hi, fi)
    flags = r.warm_start._kernel_flags()
    N = qx.size
    return A, b, lo, hi, fi, F, normal, flags[:N].copy(), flags[N:].copy()


@pytest.mark.parametrize("name", ["ray_cold", "refused_cold_warm"])
def test_caller_point_accepts_the_right_basis_and_refuses_wrong_ones(name):
    A, b, lo, hi, fi, F, normal, zb, zh = _final_flags(name)
    n = b.size
    got = _blcp._caller_point(A, b, lo, hi, F, normal, zb, zh, 1e-9)
    assert got is not None
    z, w, residual, lo_in, hi_in = got
    assert pyramid_rows(A, b, lo, hi, fi, z) <= 1.0
    assert np.allclose(w, A @ z + b, rtol=0, atol=1e-14)
    # a loaded contact made to slide (its tangent rows at +mu z_f) is a wrong basis: refused
    loaded = int(np.argmax(np.where(fi < 0, z, -1.0)))
    t = np.flatnonzero(fi == loaded)
    c = np.searchsorted(F, t)
    zb2 = zb.copy()
    zb2[t], zb2[n + c], zb2[n + F.size + c] = True, False, True
    assert _blcp._caller_point(A, b, lo, hi, F, normal, zb2, zh, 1e-9) is None
    # and so is a resting contact lifted off (its normal row at 0)
    zb3 = zb.copy()
    zb3[loaded] = False
    assert _blcp._caller_point(A, b, lo, hi, F, normal, zb3, zh, 1e-9) is None


def test_a_singular_warm_basis_is_kept_in_part():
    A, b, lo, hi, fi, ws = island("singular_warm")
    Mx, qx, lox, hix, F, normal = _blcp.friction_lcp(A, b, lo, hi, fi)
    N = qx.size
    flags = ws._kernel_flags()
    out = []
    for mode in (1, 1 | boxed.PARTIAL):
        buf, final = np.empty(6 * N + 1), np.empty(N, dtype=np.int64)
        out.append(boxed.solve(Mx, qx, lox, hix, flags, mode, 100 * (N + 1), 1e-11, 1e-11, 1e-9,
                               buf, final))
    assert out[0][0] == boxed.SINGULAR and out[0][1] == 0  # the whole basis: refused
    assert out[1][0] == 0 and out[1][3]  # kept in part: solved from it
    cold = lemke.solve_blcp(A, b, lo, hi, findex=fi)
    r = lemke.solve_blcp(A, b, lo, hi, findex=fi, warm_start=ws)
    assert r.status == lemke.Status.SOLVED and r.recoveries == 0
    assert r.pivots < cold.pivots
    assert pyramid_rows(A, b, lo, hi, fi, np.asarray(r.z)) <= 1.0


def test_a_warm_ray_is_followed_by_the_basis_with_friction_rows_cold():
    A, b, lo, hi, fi, ws = island("warm_ray")
    r = lemke.solve_blcp(A, b, lo, hi, findex=fi, warm_start=ws)
    assert r.status == lemke.Status.SOLVED and r.recoveries == 1
    assert pyramid_rows(A, b, lo, hi, fi, np.asarray(r.z)) <= 1.0
    # the runs it made: from the warm basis (a ray), then _reset's basis
    Mx, qx, lox, hix, F, normal = _blcp.friction_lcp(A, b, lo, hi, fi)
    N, n = qx.size, b.size
    buf, final = np.empty(6 * N + 1), np.empty(N, dtype=np.int64)
    first = boxed.solve(Mx, qx, lox, hix, ws._kernel_flags(), _blcp._WARM, 100 * (N + 1), 1e-11,
                        1e-11, 1e-9, buf, final)
    assert first[0] == lemke.Status.RAY_TERMINATION
    flags = _blcp._reset(ws._kernel_flags(), N, _blcp._friction_vars(F, n))
    assert not flags[F].any() and not flags[n:N].any() and not flags[N + F].any()
    second = boxed.solve(Mx, qx, lox, hix, flags, _blcp._WARM, 100 * (N + 1), 1e-11, 1e-11, 1e-9,
                         buf, final)
    assert second[0] == 0 and second[3] and first[1] + second[1] == r.pivots
    many = lemke.solve_blcp_many([A], [b], [lo], [hi], findex=[fi], warm_start=[ws])
    assert np.asarray(many[0].z).tobytes() == np.asarray(r.z).tobytes()
    assert many[0].pivots == r.pivots and many[0].recoveries == r.recoveries
    # the general path (lists) takes the same runs
    g = lemke.solve_blcp(A.tolist(), b.tolist(), lo.tolist(), hi.tolist(), findex=fi.tolist(),
                         warm_start=ws)
    assert g.status == lemke.Status.SOLVED and np.asarray(g.z).tobytes() == np.asarray(r.z).tobytes()


def test_a_cold_failure_is_solved_by_the_restart_with_friction_rows_cold():
    """``failed_cold`` (192 rows, step 694 of a run whose J W J' came from a threaded BLAS):
    every cold run ended on a wrong point (residual 3e-3) and so did the restart from
    their final basis (_from_final); that restart now goes on with the friction rows cold
    (``_reset``) and solves it."""
    A, b, lo, hi, fi, _ = island("failed_cold")
    r = lemke.solve_blcp(A, b, lo, hi, findex=fi)
    assert r.status == lemke.Status.SOLVED and r.recoveries >= 1
    assert pyramid_rows(A, b, lo, hi, fi, np.asarray(r.z)) <= 1.0
    many = lemke.solve_blcp_many([A], [b], [lo], [hi], findex=[fi])
    assert np.asarray(many[0].z).tobytes() == np.asarray(r.z).tobytes()
