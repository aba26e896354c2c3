"""Stress suite for the pivoting rule: degenerate, tied, badly scaled and redundant LCPs.

Every case must end in one of two ways, in both methods:

* ``SOLVED``, with z checked by :func:`helpers.assert_lcp_solution` (numpy code of the tests,
  not lemke's acceptance test), or
* ``RAY_TERMINATION``, with the ray checked by :func:`helpers.assert_ray`,

and which of the two is allowed is fixed per case (``expect``): a problem known to have a
solution for which Lemke's method is guaranteed to find one (P-matrices, the copositive
contact LCPs, the peer problems whose peers solve them) must be SOLVED; the few that are
infeasible, or on which Lemke with d = 1 provably ends on a ray, must end on a checked ray;
the random integer family without guarantee may end either way.  ``MAX_PIVOTS`` and
``NUMERICAL_FAILURE`` are failures everywhere.

Families (see the module-level registry ``CASES``):

* ``dart``: the five LCPs of DART's Lemke test (tests/data/dart), 12D among them; default
  options and ``tie_tol`` in 0, 1e-14, ..., 1e-6;
* ``murty``: Murty's exponential example, n = 12 (2^12 pivots: ``max_pivots`` raised);
* ``siconos``: the Siconos LCP files, with the expectations of test_peer_siconos.py;
* ``drake``: Drake's LCP unit-test cases;
* ``int`` / ``int-p``: random integer matrices with entries in {-1, 0, 1, 2} and
  q in {-1, 0, 1} (many ties), n = 4..12; ``int-p`` adds ``(row abs sum + 1) I``, which
  makes M strictly diagonally dominant with a positive diagonal (a P-matrix: one solution,
  and Lemke must find it);
* ``contact``: step LCPs of the 2-D rigid-body simulation with friction in contact_sim.py;
* ``scaled``: copies of a subset of the above, ``D1 M D2`` / ``D1 q`` with factors in
  1e-6..1e6, constant scalings and symmetric permutations ``P M P'`` / ``P q``; their
  pivot counts may exceed the original's by at most a factor 2 (n + 1).

The sweep over ``tie_tol`` runs on dart, murty, siconos and drake.  Tableau and unrevised
must follow the same path on every case (``test_methods_follow_the_same_path``).  A
hypothesis test draws P-matrices under row and column scalings 10^k, |k| <= 8, and checks
the answer row by row (:func:`helpers.assert_lcp_solution_rowwise`).  Extreme option
values run in a child process, so that a crash of a kernel is a failure of that test and
not the end of the test session.
"""
from __future__ import annotations

import atexit
import functools
import json
import os
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import lemke
from helpers import assert_lcp_solution, assert_lcp_solution_rowwise, assert_ray, enumerate_solutions
from lemke import Status, _core, _layout
from stress_cases import ALL, BASE_CASES, BY_KEY, CASES, DATA, MURTY_N, SCALED_CASES, p_matrix, scaling
from stress_worker import Solver

TIE_TOLS = [0.0] + [10.0**-k for k in range(14, 5, -1)]  # 0, 1e-14, ..., 1e-6
SWEEP = [None] + TIE_TOLS  # None: the default options


# --- solving (in a separate process) and checking ---------------------------------------

_SOLVER = Solver()
atexit.register(_SOLVER.close)


def _options(case, tie_tol=None):
    opts = dict(case.options)
    if tie_tol is not None:
        opts["tie_tol"] = tie_tol
    return tuple(sorted(opts.items()))


@functools.lru_cache(maxsize=None)
def problem(key):
    """``(M, q)`` of case ``key``; the cases built with lemke's answers come from the
    solver process, so that the test process never runs a kernel."""
    if ALL[key].uses_lemke:
        return _SOLVER.problem(key)
    import stress_cases

    return stress_cases.problem(key)


@functools.lru_cache(maxsize=None)
def solve(key, method, options=()):
    """lemke's result for case ``key`` (memoized: the checks and the comparison of the
    methods share one solve), from the solver process."""
    return _SOLVER.solve(key, method, options)


def check(case, res, M=None, q=None):
    """The answer is one the case allows, and it passes the independent check."""
    if M is None:
        M, q = problem(case.key)
    if res.status == Status.SOLVED and case.expect in ("solved", "either"):
        assert_lcp_solution(M, q, res.z)
    elif res.status == Status.RAY_TERMINATION and case.expect in ("ray", "either"):
        assert_ray(M, q, res.covering, res.z, res.z0, res.ray)
    else:
        want = {"solved": "SOLVED", "ray": "RAY_TERMINATION", "either": "SOLVED or RAY_TERMINATION"}[case.expect]
        pytest.fail(f"{case.key} (n = {q.size}): expected {want}, got {res.describe()}")


def _ids(cases):
    return [c.key for c in cases]


def _tie_id(t):
    return "default" if t is None else f"tie{t:g}"


# --- DART and the tie_tol sweep -------------------------------------------------------

DART = [c for c in BASE_CASES if c.family == "dart"]
SWEPT = [c for c in BASE_CASES if c.family in ("murty", "siconos", "drake")]


@pytest.mark.parametrize("tie_tol", SWEEP, ids=_tie_id)
@pytest.mark.parametrize("case", DART, ids=_ids(DART))
def test_dart(case, tie_tol, method):
    # Lemke_12D (q mixes entries of about 1e-2 and 1e-10) has solutions (see below);
    # Lemke's method must reach one of them whatever the tie tolerance.
    check(case, solve(case.key, method, _options(case, tie_tol)))


def test_dart_12d_has_solutions():
    # By enumeration of its 2^12 complementary bases, independently of lemke: several give
    # a point that passes the tests' check (10 at rtol 1e-8; more at looser tolerances).
    M, q = problem("dart/Lemke_12D")
    assert enumerate_solutions(M, q)


@pytest.mark.parametrize("tie_tol", SWEEP, ids=_tie_id)
@pytest.mark.parametrize("case", SWEPT, ids=_ids(SWEPT))
def test_tie_tol_sweep(case, tie_tol, method):
    check(case, solve(case.key, method, _options(case, tie_tol)))


@pytest.mark.parametrize("tie_tol", SWEEP, ids=_tie_id)
def test_murty_takes_2_to_the_n_pivots(tie_tol, method):
    # Murty's example is non-degenerate (no ties in any ratio test), so no tie rule may
    # change the path: Lemke with d = 1 takes exactly 2^n pivots.
    case = BY_KEY[f"murty/murty-{MURTY_N}"]
    res = solve(case.key, method, _options(case, tie_tol))
    assert res.status == Status.SOLVED and res.pivots == 2**MURTY_N, res.describe()


# --- random integer matrices ------------------------------------------------------------

INTEGER = [c for c in BASE_CASES if c.family in ("int", "int-p")]


@pytest.mark.parametrize("case", INTEGER, ids=_ids(INTEGER))
def test_integer_matrices(case, method):
    check(case, solve(case.key, method, _options(case)))


# --- scaled and permuted copies ---------------------------------------------------------


@pytest.mark.parametrize("case", SCALED_CASES, ids=_ids(SCALED_CASES))
def test_scaled_copies(case, method):
    _scaled_copy(case, method)


def _scaled_copy(case, method):
    how, base_key = case.name.split(":", 1)
    base = BY_KEY[base_key]
    Ms, qs = problem(case.key)
    res = solve(case.key, method, _options(case))
    check(case, res, Ms, qs)
    # The copy's answer, taken back to the original's coordinates (z = P' D2 z'), must be
    # an answer of the original, checked at the original's scale.
    M, q = problem(base.key)
    p, d1, d2 = scaling(q.size, how, base.key)
    z = np.empty_like(res.z)
    z[p] = d2 * res.z
    if res.status == Status.SOLVED:
        assert_lcp_solution(M, q, z)
    else:  # a checked ray (check passed): the same ray of the original
        ray = np.empty_like(res.ray)
        ray[p], ray[-1] = d2 * res.ray[:-1], res.ray[-1]
        d = np.empty_like(res.covering)
        d[p] = res.covering / d1
        assert_ray(M, q, d, z, res.z0, ray)
    ref = solve(base.key, method, _options(base))
    assert ref.status is not None, f"the original {base.key}: {ref.describe()}"
    n = q.size
    assert res.pivots <= 2 * (n + 1) * ref.pivots, (
        f"{res.pivots} pivots on the copy, {ref.pivots} on the original (bound 2 (n + 1) x {ref.pivots})")


# Copies on which the tableau's first run ends solved on a point that fails the check, and
# the point of its final basis passes (found by scanning CASES).
FIRST_BASIS_RIGHT = ["scaled/perm-rowcol:dart/Lemke_2D", "scaled/rowcol-a:dart/Lemke_6D",
                     "scaled/rowcol-a:int-p/n5-s0", "scaled/times1e-6:contact/pile-step020"]


@pytest.mark.parametrize("key", FIRST_BASIS_RIGHT)
def test_a_first_run_with_the_right_basis_needs_no_recovery_run(key):
    """The driver (lcp.cpp's checked): when the first run ends SOLVED on a point that fails the check,
    the point of its final basis (one LU solve on the data) is tried before any recovery
    run; where it passes, that is the answer: recoveries 0, and the pivots are the first
    run's.  The answer is checked here independently."""
    M, q = (np.ascontiguousarray(a, dtype=float) for a in problem(key))
    n = q.size
    buf = np.empty(_layout.buffer_length(n) + n)
    none_i, none_f = np.zeros(0, dtype=np.int64), np.zeros(0)
    code, pivots, _, ok, _, _, stage = _core.first_run(
        _core.TABLEAU, M, q, none_f, none_i, 0, 10**6, 1e-12, 1e-10, 1e-9, buf, np.empty(n, dtype=np.int64))
    assert code == 0 and not ok and stage == -1, "the first run no longer fails its check here"
    res = lemke.solve_lcp(M, q)
    assert res.status == Status.SOLVED and res.recoveries == 0 and res.pivots == pivots
    # Taken back to the original's coordinates (as in _scaled_copy), an answer of the original.
    how, base_key = key.split("/", 1)[1].split(":", 1)
    p, _, d2 = scaling(n, how, base_key)
    z = np.empty_like(res.z)
    z[p] = d2 * res.z
    assert_lcp_solution(*problem(base_key), z)


def test_a_first_run_one_basis_off_is_restarted_from_its_basis():
    """The driver, n >= RESTART_FROM: when the first run ends SOLVED on a point
    that fails the check and so does the point of its final basis, Lemke's method restarts
    from that basis (lcp.cpp's restart) before the recovery runs: on this contact step (196 rows)
    the first run's basis was a few pivots off, and the restart's 10 pivots end it
    (recoveries 1; 10 as the former kernel's restart counted them).  The answer is checked
    here independently."""
    from lemke import Options
    o = Options()
    M, q = (np.ascontiguousarray(a, dtype=float) for a in problem("contact/mixed-step055"))
    n = q.size
    assert n >= _core.RESTART_FROM
    buf = np.empty(_layout.buffer_length(n) + n)
    basic = np.empty(n, dtype=np.int64)
    code, first, k, ok, _, _, stage = _core.first_run(
        _core.TABLEAU, M, q, np.zeros(0), np.zeros(0, dtype=np.int64), 0, 10**6, o.pivot_tol,
        o.tie_tol, o.tol, buf, basic)
    assert code == 0 and not ok and stage == -1
    beta = basic[:k]
    z = np.zeros(n)  # the point of its final basis (numpy's LU here): no answer either
    z[beta] = np.linalg.solve(M[np.ix_(beta, beta)], -q[beta])
    assert not lemke.is_lcp_solution(M, q, z)
    res = lemke.solve_lcp(M, q)
    assert res.status == Status.SOLVED and res.recoveries == 1 and res.pivots == first + 10
    assert_lcp_solution(M, q, res.z)


# --- contact simulation -----------------------------------------------------------------

CONTACT = [c for c in BASE_CASES if c.family == "contact"]


@pytest.mark.parametrize("case", CONTACT, ids=_ids(CONTACT))
def test_contact_steps(case, method):
    # Copositive, with z'q >= 0 on SOL(0, M) (contact_sim's docstring): Lemke with a
    # lexicographic rule cannot end on a ray, so every step must be SOLVED.
    check(case, solve(case.key, method, _options(case)))


def test_contact_generator_is_deterministic_and_varied():
    a = _SOLVER.contact(5, 12, 30)
    b = _SOLVER.contact(5, 12, 30)
    assert all(np.array_equal(Ma, Mb) and np.array_equal(qa, qb) for (Ma, qa), (Mb, qb) in zip(a, b))
    sizes = {q.size for _, q in a}
    assert len(sizes) > 3 and max(sizes) > 0
    for M, q in a:
        m = q.size // 4
        assert M.shape == (4 * m, 4 * m)
        if m:
            # Not symmetric, and not positive semidefinite (z'Mz < 0 for some z).
            assert not np.allclose(M, M.T)
            assert np.linalg.eigvalsh(0.5 * (M + M.T)).min() < 0


# --- both methods follow the same path ----------------------------------------------------

SAME_PATH = [pytest.param(c.key, _options(c, t), id=f"{c.key}-{_tie_id(t)}")
             for c in CASES for t in (SWEEP if c.family in ("dart", "murty", "siconos", "drake") else [None])]


def _may_diverge(key, options=()):
    """The cases where the README allows the two methods different paths: degenerate,
    rank-deficient problems (the contact steps, with their redundant contacts, and Siconos'
    lcp_tobenna), where an entry of the driving column that is exactly zero comes out exact
    in the tableau but as +-1e-17 from the unrevised method's basis inverse; and copies whose rows or
    columns were scaled (``scaled/``), where the default covering vector is uneven after
    equilibration and the recovery runs (src/lemke/lcp.cpp) may be needed by one method and
    not the other; and DART's Lemke_12D with a tie window of 1e-9 or wider, where ratios
    that differ in exact arithmetic count as tied and the choice then rests on the last
    bits of each method's arithmetic: since the dot products sum in a fixed order (the
    C++ core's, without fused multiply-adds) the unrevised method's first run there meets a
    repeated basis and its recovery (exact ties) ends in the tableau's basis after 28
    pivots in all, against the tableau's 10 (it took the tableau's path before, with the
    host's reordered, fused sums)."""
    loose = dict(options).get("tie_tol", 0.0) >= 1e-9
    return (key.startswith(("contact/", "scaled/")) or key == "siconos/lcp_tobenna"
            or (key == "dart/Lemke_12D" and loose))


@pytest.mark.parametrize("key, options", SAME_PATH)
def test_methods_follow_the_same_path(key, options):
    _same_path(key, options)


def _same_path(key, options):
    a = solve(key, "tableau", options)
    b = solve(key, "unrevised", options)
    if _may_diverge(key, options):
        # The bound the README states: the same status (each answer checked), and neither
        # takes more than 2 (n + 1) times the other's pivots.
        M, q = problem(key)
        assert a.status == b.status, f"tableau: {a.short()}; unrevised: {b.short()}"
        assert max(a.pivots, b.pivots) <= 2 * (q.size + 1) * max(1, min(a.pivots, b.pivots))
        return
    assert (a.status, a.pivots) == (b.status, b.pivots), f"tableau: {a.short()}; unrevised: {b.short()}"
    assert a.z_basic == b.z_basic, f"final bases differ: tableau {a.z_basic}, unrevised {b.z_basic}"


# --- P-matrices under row and column scaling ------------------------------------------------


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(2, 8), kind=st.sampled_from(["pd", "dd"]), data=st.data())
def test_p_matrix_under_row_and_column_scaling(seed, n, kind, data):
    rng = np.random.default_rng(seed)
    M = p_matrix(kind, n, rng)
    powers = st.lists(st.integers(-8, 8), min_size=n, max_size=n)
    d1 = 10.0 ** np.array(data.draw(powers, label="row powers"))
    d2 = 10.0 ** np.array(data.draw(powers, label="column powers"))
    q = np.array(data.draw(st.lists(st.floats(-1e3, 1e3, allow_subnormal=False), min_size=n, max_size=n),
                           label="q"))
    # Entries of q are 0 or of size 1e-6 ... 1e3: assert_lcp_solution_rowwise has no rounding
    # floor, and a q_j of 1e-252 next to a q_i of 1 (hypothesis' favourite) asks for z ~ 1e-253
    # to 8 digits in rows that are rounding next to the others; lemke's own check allows the
    # rounding of q's largest entry there (src/lemke/certify.cpp), this independent one does not.
    q[np.abs(q) < 1e-6] = 0.0
    Ms, qs = d1[:, None] * M * d2[None, :], d1 * q  # still a P-matrix: exactly one solution
    for method in lemke.METHODS:
        res = _SOLVER.solve_data(Ms, qs, method)
        assert res.status == Status.SOLVED, (method, res.describe())
        assert_lcp_solution_rowwise(Ms, qs, res.z)


@pytest.mark.parametrize("diag", [[1e6, 1e-6], [1e12, 1e-12], [1e-12, 1e12]], ids=str)
def test_badly_scaled_diagonal(diag, method):
    # z = 1 / diag is the only solution.
    M, q = np.diag(diag), np.array([-1.0, -1.0])
    res = _SOLVER.solve_data(M, q, method)
    assert res.status == Status.SOLVED, res.describe()
    assert_lcp_solution_rowwise(M, q, res.z)


def test_solved_means_rowwise_solved_on_tiny_row(method):
    # With diag(1e-12, 1e12), z = (1e12, 0) gives w = (0, -1): it passes a test against
    # max|M| max|z| = 1e24, yet row 2 is violated by its full size.  Whatever the status,
    # SOLVED must mean the row-wise test holds.
    M, q = np.diag([1e-12, 1e12]), np.array([-1.0, -1.0])
    res = _SOLVER.solve_data(M, q, method)
    assert res.status is not None, res.describe()
    if res.status == Status.SOLVED:
        assert_lcp_solution_rowwise(M, q, res.z)


# --- extreme option values in a child process -------------------------------------------------

OPTION_CHILD = r"""
import itertools, json, sys
import numpy as np
import lemke
from lemke import problems

cases = json.loads(open(sys.argv[1]).read())
start = int(sys.argv[2])
dart = next(c for c in cases if c["name"] == "Lemke_12D")
murty = problems.murty(12)
data = {"dart12d": (np.array(dart["M"], float).reshape(12, 12), np.array(dart["q"], float)),
        "murty12": (np.array(murty.M), np.array(murty.q))}
tiny = [0.0, 5e-324, 1e-300, 0.5, float(np.nextafter(1.0, 0.0))]
combos = [(name, method, how, t, p, mp)
          for name in data for method in lemke.METHODS for how in ("solve", "batch", "warm")
          for t, p, mp in itertools.product(tiny, tiny, [None, 0, 1, 2])]
combos += [(name, method, "solve", None, None, mp, tol) for name in data for method in lemke.METHODS
           for tol in tiny for mp in [None, 1]]
print("TOTAL", len(combos), flush=True)
for i in range(start, len(combos)):
    c = combos[i]
    name, method, how, t, p, mp = c[:6]
    opts = {"max_pivots": mp}
    if t is not None:
        opts.update(tie_tol=t, pivot_tol=p)
    if len(c) > 6:
        opts["tol"] = c[6]
    M, q = data[name]
    print("START", i, json.dumps([name, method, how, opts]), flush=True)
    try:
        if how == "solve":
            r = lemke.solve_lcp(M, q, method=method, options=opts)
        elif how == "batch":
            r = lemke.solve_lcp_batch(M, np.stack([q, q[::-1]]), method=method, options=opts)
        else:
            ws = lemke.solve_lcp(M, q + 1e-3, method=method).warm_start
            r = lemke.solve_lcp(M, q, method=method, warm_start=ws, options=opts)
        status = [int(s) for s in np.atleast_1d(r.status)]
        pivots = [int(s) for s in np.atleast_1d(r.pivots)]
        print("DONE", i, json.dumps([status, pivots]), flush=True)
    except Exception as e:
        print("EXC", i, json.dumps(repr(e)), flush=True)
print("END", flush=True)
"""


@pytest.mark.slow
def test_option_values_do_not_crash(tmp_path):
    """Every value Options accepts for tie_tol, pivot_tol and tol (0, the tiniest, 0.5 and
    the largest double below 1) and max_pivots 0, 1, 2, in every combination, through
    solve_lcp (both methods), solve_lcp_batch and the warm-start restart, on DART's 12D
    problem and Murty's: any status, but no exception and no crash.  The child process
    resumes after a crash, so that every crashing combination is listed."""
    script = tmp_path / "options_child.py"
    script.write_text(OPTION_CHILD)
    crashes, errors, over_cap, start, total = [], [], [], 0, None
    while True:
        out = subprocess.run([sys.executable, str(script), str(DATA / "dart" / "lemke_cases.json"), str(start)],
                             capture_output=True, text=True, timeout=600, env=dict(os.environ))
        current = None
        for line in out.stdout.splitlines():
            tag, _, rest = line.partition(" ")
            if tag == "TOTAL":
                total = int(rest)
            elif tag == "START":
                current = rest
            elif tag == "DONE":
                i, payload = rest.split(" ", 1)
                status, pivots = json.loads(payload)
                mp = json.loads(current.split(" ", 1)[1])[3]["max_pivots"]
                if mp is not None and max(pivots) > mp:
                    over_cap.append(f"{current}: {pivots} pivots")
                current = None
            elif tag == "EXC":
                errors.append(f"{current}: {json.loads(rest.split(' ', 1)[1])}")
                current = None
        if out.returncode == 0 and out.stdout.rstrip().endswith("END"):
            break
        assert current is not None, f"child failed before any case: rc {out.returncode}\n{out.stderr[-2000:]}"
        crashes.append(f"{current}: exit code {out.returncode}")
        start = int(current.split(" ", 1)[0]) + 1
        if len(crashes) >= 10 or start >= total:  # enough to see; each restart costs a second
            break
    assert not crashes and not errors and not over_cap, (
        f"{len(crashes)} crash(es), {len(errors)} exception(s), {len(over_cap)} over max_pivots "
        f"out of {total} combinations:\n" + "\n".join(crashes + errors + over_cap))
