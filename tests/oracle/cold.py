"""A cold solve in one kernel call: check the data, equilibrate, pivot (recovering from a
cycle), check the answer on the caller's data.  ``solve_lcp`` and ``solve_lcp_batch`` both go
through these kernels, so a problem in a batch gets exactly the same answer as on its own.
The common calls, cold or warm solves by the tableau, go to the lean :func:`first_run`,
which compiles in about 60 % of the time of :func:`solve_one` and hands a solve that it
cannot finish (a cycle, a ray to check, recovery runs, a restart from a warm basis) to
solve_one, which goes on from there.

Every output goes into one float64 buffer of length 6n + 2 (the front makes read-only views
of it), laid out as ``[z | z0 | ray (n + 1) | w | covering d | row scales | column scales]``
(see :func:`layout`), and the indices of the basic z's into an int64 array of length n.

**Recovery from a cycle.**  The pivoting rule (``kernels.pivoting``) is lexicographic, so in
exact arithmetic no basis repeats; rounding can still make a near-tie come out differently
from one visit to the next.  When the kernel detects a repeated basis it stops with
CYCLING, and the solve is restarted, with the pivots left of the budget:

1. with exact ties only (``tie_tol = 0``), unless that was already the setting;
2. then with the covering vector perturbed by a relative 1e-6 (a fixed pseudo-random
   factor per row, so the run is reproducible), which separates the first key of rows that
   the problem's data tie exactly.

If the last one cycles too, the status is CYCLING, never a silent pivot cap.

**Recovery from a failed check.**  A first run that ends SOLVED on a point that fails the
check gets the point of its final basis first (:func:`basis_point`: one LU solve of the
basic block on the caller's data, the recomputation the front would make); when that point
passes, it is the answer and no recovery run follows.  Over hundreds of pivots the
tableau's values drift while its basis stays right: on the reduced LCP of Maros-Meszaros'
QGROW15 (1245 pairs) the first run's basis was right and its point failed, and the runs
below then took 1000 more pivots (2.4 s against 0.45 s).  When that point fails too and n
>= RESTART_FROM, Lemke's method is restarted from that basis (:func:`restart`, as a warm
start whose basis fails; a recovery), in a buffer of its own that is kept only when its
point passes: on QSCSD1's (760 pairs) the first run ended after 1316 pivots one basis
off, the restart took 9 (0.09 s; the runs below took 750 more and 0.55 s).  Otherwise,
with the default covering vector, a run whose point fails
the check on the caller's data, or whose ray fails the ray check, or that met a numerical
failure, is followed by up to four more runs (their pivots counted, within the same cap),
until one ends solved and checked.  Recovery runs of the tableau are *careful*: they test
"zero to rounding" with the exact |B^-1| |q| of the rows under a running bound (see
``tableau.careful_sizes``), which the first run skips for speed.  The runs:

1. the covering vector that is all ones in the *equilibrated* coordinates (d = 1 / R).  The
   default d = 1 is all ones in the caller's coordinates; when the rows of M come in very
   different scales (1e-8 next to 1e8), it is very uneven after equilibration, and the
   relative pivot tolerance then hides the small rows' entries;
2. d proportional to |q| in the equilibrated coordinates (each entry at least 1e-3 of the
   largest), with exact tests (``pivot_tol = tie_tol = 0``): z0 then starts near 1 in every
   row, so rows of q that differ by many orders of magnitude are not lost to rounding in
   q + d z0;
3. a covering vector with fixed pseudo-random factors in [1, 2) in the equilibrated
   coordinates: on degenerate contact problems (piles with deep overlaps) the path of a
   constant covering vector can run into rounding that a generic one avoids;
4. the other method (tableau <-> unrevised) with d = 1 / R: the two compute their columns
   differently (updated in place / from the basis inverse), and rounding rarely
   defeats both on one problem.

A run that ends solved replaces one that did not even when its check fails (the front then
recomputes the point from its final basis); it also replaces one that ended solved and
failed the check when only its own final basis gives a point that passes (the recomputation
the front would do, :func:`basis_point`, tried here on both: on a scaled copy of a contact
pile step, issue 11, the first run's basis was wrong and the first recovery run's right,
and the later one was thrown away); a run that ends on a checked ray replaces a
failed one (with its covering vector, which the result reports), but the ladder goes on in
case a later run solves.  A checked ray of the first run stops the ladder: it is the
verdict on the default covering vector.  A run that stops otherwise (a ray, the pivot cap, a cycle) at a point that passes
the check (z0 zero to rounding) is SOLVED: the check, not the path, decides.

The number of restarts of both kinds is returned (``LCPResult.recoveries``).
"""
import numpy as np

from . import inline_kernel, kernel, pivoting, tableau, unrevised
from .certify import lcp_check_early, lcp_check_sized, lcp_ray_check_scaled
from .linalg import (borrow, copy, equilibrate, false_flags, finite_absmax, nan_probe, no_matrix,
                     solve_gathered, solve_work)

from lemke._layout import (BUFFER, METHODS, NOT_FINITE, RESTART_FROM, TABLEAU, TRIVIAL, UNREVISED,  # noqa: F401
                       buffer_length, fields)

PERTURBATION = 1e-6  # the relative size of the covering vector's perturbation (step 2)


@kernel
def buffer_size(n):
    """:func:`buffer_length` for the kernels (the same count; a test checks it)."""
    return 6 * n + 2


@kernel
def layout(n, buf):
    """The views ``(x, ray, w, cov, R, C)`` of the output buffer (x = z followed by z0), as
    :data:`BUFFER` lays it out; borrowed (``linalg.borrow``: no reference counts, six
    atomic pairs a call saved), so valid only while ``buf`` is referenced: every buffer
    given here is a kernel's argument, or a recovery run's own buffer, live through the
    loop that uses it (:func:`checked`)."""
    return (borrow(buf, 0, n + 1, np.float64), borrow(buf, n + 1, n + 1, np.float64),
            borrow(buf, 2 * n + 2, n, np.float64), borrow(buf, 3 * n + 2, n, np.float64),
            borrow(buf, 4 * n + 2, n, np.float64), borrow(buf, 5 * n + 2, n, np.float64))


@inline_kernel
def prologue(M, q, d, buf, scaled):
    """Check that M and q are finite, fill the equilibration scales and the covering vector
    (an empty d stands for all ones).  Returns code NOT_FINITE, TRIVIAL (q >= 0: z = 0
    and w = q written) or 0.  ``scaled``: the check and the scales are done already (by
    :func:`old_basis`), and are not made again."""
    n = q.shape[0]
    x, ray, w, cov, R, C = layout(n, buf)
    if not scaled:
        finite, m_max = finite_absmax(M)
        finite &= nan_probe(q, n) == 0.0
        if not finite:
            return NOT_FINITE
        equilibrate(M, q, R, C)
    q_min = 0.0
    for i in range(n):
        q_min = min(q_min, q[i])
        cov[i] = d[i] if d.shape[0] else 1.0
    if q_min >= 0.0:
        x[:] = 0.0
        ray[:] = 0.0
        copy(w, q)
        return TRIVIAL
    return 0


@inline_kernel
def pivot_once(method, M, q, tie_tol, max_pivots, pivot_tol, buf, z_basic, careful):
    """One run of the chosen method from the all-w basis; returns ``(status, pivots)``."""
    n = q.shape[0]
    x, ray, w, cov, R, C = layout(n, buf)
    if method == TABLEAU:
        return tableau.solve(M, q, cov, R, C, max_pivots, pivot_tol, tie_tol, x, ray, z_basic,
                             careful)
    return unrevised.solve(M, q, cov, R, C, false_flags(n), no_matrix(),
                           max_pivots, pivot_tol, tie_tol, x, ray, z_basic)


@inline_kernel
def pivot_recovering(method, M, q, max_pivots, pivot_tol, tie_tol, buf, z_basic, careful,
                     start, code, pivots):
    """:func:`pivot_once`, then the recoveries of the module docstring while it cycles.
    Returns ``(status, pivots, recoveries)``; the pivots of every run are counted.  One
    call site of :func:`pivot_once` in a loop over the attempts: each site inlines both
    methods' set-up, and three of them made this the largest part of the compile.
    ``start`` 0 runs from the start (``code`` and ``pivots`` are not read); 1 goes on after
    a first run (attempt 0, of :func:`first_run`) that ended with ``code`` after ``pivots``
    pivots, its output in ``buf`` and ``z_basic``."""
    recoveries = start - 1
    tt = tie_tol
    for attempt in range(start, 3):
        if attempt > 0:
            if code != pivoting.CYCLING or (attempt == 1 and tie_tol <= 0.0):
                continue  # attempt 1 only with a tie tolerance to drop; 2 while it cycles
            tt = 0.0
            if attempt == 2:
                n = q.shape[0]
                cov = layout(n, buf)[3]
                keys = pivoting.label_keys(n)
                for i in range(n):
                    cov[i] *= 1.0 + PERTURBATION * pivoting.unit_random(keys, i)
        recoveries += 1
        code, p = pivot_once(method, M, q, tt, max_pivots - pivots, pivot_tol, buf, z_basic,
                             careful)
        pivots += p
    return code, pivots, recoveries


RETRIES = 4


@kernel
def retry_covering(step, q, R, cov):
    """The covering vector of recovery run ``step`` (see the module docstring), written in
    ``cov``; returns whether that run uses exact tests.  0: all ones in the equilibrated
    coordinates (1 / R); 1: |q| in them, each entry at least 1e-3 of the largest (exact
    tests); 2: fixed pseudo-random factors in [1, 2) in them; 3 (the other method): all
    ones in the equilibrated coordinates again."""
    n = q.shape[0]
    if step == 1:
        top = 0.0
        for i in range(n):
            top = max(top, R[i] * abs(q[i]))
        for i in range(n):
            cov[i] = max(R[i] * abs(q[i]), 1e-3 * top) / R[i] if top > 0.0 else 1.0 / R[i]
        return True
    if step == 2:
        keys = pivoting.label_keys(n)
        for i in range(n):
            cov[i] = (1.0 + pivoting.unit_random(keys, i)) / R[i]
        return False
    for i in range(n):
        cov[i] = 1.0 / R[i]
    return False


@kernel
def basis_checks(M, q, z_basic, tol, R):
    """Whether the point of the complementary basis with z_i basic where ``z_basic[i]``
    (:func:`basis_point`, one LU solve on the caller's data) passes the check: what the
    front does with a run that ends SOLVED on a point that fails it."""
    n = q.shape[0]
    z = np.empty(2 * n)
    return basis_point_checked(M, q, z_basic, tol, R, z[:n], z[n:])[0]


@kernel
def basis_point_checked(M, q, z_basic, tol, R, z, w):
    """The point of the complementary basis with z_i basic where ``z_basic[i]``
    (:func:`basis_point`) into z, and ``(ok, residual)`` of its check on (M, q), w = M z + q
    into w."""
    beta = np.empty(q.shape[0], dtype=np.int64)
    if not basis_point(M, q, beta, np.int64(basic_indices(z_basic, beta)), z):
        return False, 0.0
    return lcp_check_sized(M, q, z, tol, w, R)


@inline_kernel
def checked(method, M, q, d, max_pivots, pivot_tol, tie_tol, tol, buf, basic, first_code,
            first_pivots, scaled):
    """Solve LCP(M, q) cold by ``method`` (TABLEAU or UNREVISED) with covering vector d
    (empty: all ones), then check the answer on (M, q).

    Returns ``(code, pivots, k, ok, residual, recoveries)``: code is a status of the
    kernels, or NOT_FINITE (nothing else done) or TRIVIAL (z = 0, w = q); the first k
    entries of ``basic`` are the basic z's; ok and residual are the result of
    ``certify.lcp_check`` on the point -- except on RAY_TERMINATION, where ok is the
    verdict of ``certify.lcp_ray_check`` on the ray (the point never passes there);
    recoveries counts the restarts (after a cycle or a failed check, see the module
    docstring).

    ``first_code`` < 0 solves from the start (``scaled``: the finite check and the
    equilibration are done already, by :func:`old_basis`, and the scales are in ``buf``).
    Otherwise :func:`first_run` has made the
    first run (the prologue and the attempt 0 of :func:`pivot_recovering`), which ended
    with ``first_code`` after ``first_pivots`` pivots; ``buf`` holds its output and
    ``basic`` its flags of the basic z's, and the solve goes on from there, with the same
    bits as from the start.
    """
    n = q.shape[0]
    z_basic = np.empty(n, dtype=np.bool_)
    start = np.int64(0)  # not a literal 0: see kernels/__init__.py
    if first_code < 0:
        code = prologue(M, q, d, buf, scaled)
        if code < 0:
            return code, 0, 0, code == TRIVIAL, 0.0, 0
    else:
        start = np.int64(1)
        for i in range(n):
            z_basic[i] = basic[i] != 0
    x, ray, w, cov, R, C = layout(n, buf)
    code, ok, residual = pivoting.MAX_PIVOTS, False, 0.0
    pivots = 0
    recoveries = 0
    other = UNREVISED if method == TABLEAU else TABLEAU
    buf2, z_basic2 = buf, z_basic  # the recovery runs' own, allocated only when one runs
    have_ray = False  # buf holds a checked ray of a retry
    # The verdict of the ray check on buf's ray, once made (the check is deterministic, and
    # the scales R, C in buf are the equilibration's of (M, q) in every run).
    ray_known, ray_ok = False, False
    # The first run (step -1) and the recovery runs (steps 0 .. RETRIES - 1) share one call
    # of pivot_recovering: every call site inlines both methods' set-up.
    for step in range(-1, RETRIES):
        if step == -1:
            run_method, run_buf, run_basic, ptol, ttol, careful = (
                method, buf, z_basic, pivot_tol, tie_tol, np.False_)
            run_start, run_code, run_pivots = start, first_code, first_pivots
        else:
            if d.shape[0] != 0 or (code == pivoting.SOLVED and ok) or pivots >= max_pivots:
                break  # a caller's covering vector gets no recovery runs
            if step == 0 and code == pivoting.RAY_TERMINATION:
                ray_known = True
                ray_ok = lcp_ray_check_scaled(M, q, cov, x[:n], x[n], ray, tol, R, C)
                if ray_ok:
                    break  # a checked ray of the first run: a verdict, not a failure
            if step == 0:
                buf2 = np.empty(buf.shape[0])  # only on the failure path: none when solved
                z_basic2 = np.empty(n, dtype=np.bool_)
            copy(buf2, buf)
            exact = retry_covering(step, q, R, layout(n, buf2)[3])
            run_method = other if step == RETRIES - 1 else method
            ptol = 0.0 if exact else pivot_tol
            ttol = 0.0 if exact else tie_tol
            run_buf, run_basic, careful = buf2, z_basic2, np.True_
            run_start, run_code, run_pivots = np.int64(0), np.int64(pivoting.CYCLING), np.int64(0)
        code2, pivots2, rec2, ok2, residual2 = run_checked(
            run_method, M, q, max_pivots - pivots, ptol, ttol, tol, run_buf, run_basic, careful,
            run_start, run_code, run_pivots)
        pivots += pivots2
        x2, ray2, w2, cov2, R2, C2 = layout(n, run_buf)
        if step == -1:
            code, ok, residual, recoveries = code2, ok2, residual2, rec2
            if code == pivoting.SOLVED and not ok and d.shape[0] == 0:
                # Solved, on a point that fails the check: the point of its final basis
                # first (one LU solve on the caller's data), before any recovery run.
                zw = np.empty(2 * n)
                okb, rb = basis_point_checked(M, q, z_basic, tol, R, zw[:n], zw[n:])
                if okb:
                    copy(x[:n], zw[:n])
                    x[n] = 0.0
                    copy(w, zw[n:])
                    ok, residual = okb, rb
                elif n >= RESTART_FROM and pivots < max_pivots:
                    # Then Lemke's method restarted from that basis (as a warm start whose
                    # basis fails), in a buffer of its own, kept only when it passes.
                    buf2 = np.empty(buf.shape[0])
                    z_basic2 = np.empty(n, dtype=np.bool_)
                    copy(buf2, buf)
                    beta = np.empty(n, dtype=np.int64)
                    kb = basic_indices(z_basic, beta)
                    p3, ok3, r3 = restart(M, q, z_basic, beta, kb, finite_absmax(M)[1],
                                          max_pivots - pivots, pivot_tol, tie_tol, tol, buf2,
                                          z_basic2)
                    pivots += p3
                    recoveries += 1
                    if ok3:
                        copy(buf, buf2)
                        copy(z_basic, z_basic2)
                        ok, residual = ok3, r3
            continue
        recoveries += rec2 + 1
        take = code2 == pivoting.SOLVED and (ok2 or code != pivoting.SOLVED)
        if (not take and code2 == pivoting.SOLVED and code == pivoting.SOLVED and not ok
                and not basis_checks(M, q, z_basic, tol, R)
                and basis_checks(M, q, z_basic2, tol, R)):
            take = True  # both failed the check, only this one's basis gives a point
        if (not take and not have_ray and code2 == pivoting.RAY_TERMINATION
                and lcp_ray_check_scaled(M, q, cov2, x2[:n], x2[n], ray2, tol, R2, C2)):
            take = have_ray = True  # kept while no later run solves
            ray_known, ray_ok = True, True
        elif take:
            have_ray = False
        if take:
            copy(buf, buf2)
            copy(z_basic, z_basic2)
            code, ok, residual = code2, ok2, residual2
    if code == pivoting.RAY_TERMINATION:  # ok: the verdict on the ray (the point failed)
        ok = ray_ok if ray_known else lcp_ray_check_scaled(M, q, cov, x[:n], x[n], ray, tol, R, C)
    return code, pivots, basic_indices(z_basic, basic), ok, residual, recoveries


@inline_kernel
def run_checked(method, M, q, max_pivots, pivot_tol, tie_tol, tol, buf, z_basic, careful, start,
                code, pivots):
    """:func:`pivot_recovering` (its arguments), then the check of the point on (M, q).
    Returns ``(code, pivots, recoveries, ok, residual)``, code SOLVED when the point
    passes: where the method stopped (a "ray" or a cap reached with z0 zero to rounding)
    the check on the caller's data, not the path, decides."""
    n = q.shape[0]
    code, pivots, recoveries = pivot_recovering(method, M, q, max_pivots, pivot_tol, tie_tol,
                                                buf, z_basic, careful, start, code, pivots)
    x, ray, w, cov, R, C = layout(n, buf)
    ok, residual = lcp_check_sized(M, q, x[:n], tol, w, R)
    return pivoting.SOLVED if ok else code, pivots, recoveries, ok, residual


@inline_kernel
def checked_once(method, M, q, d, max_pivots, pivot_tol, tie_tol, tol, buf, basic):
    """:func:`checked` with a covering vector d given (so no recovery runs) for a caller
    that takes only a checked solution: the same ``(code, pivots, k, ok, residual,
    recoveries)`` except that a ray is not judged (ok False), so that none of the recovery
    runs' code (the ray check, the other covering vectors' runs, the points of final
    bases) is compiled into it."""
    n = q.shape[0]
    code = prologue(M, q, d, buf, np.False_)
    if code < 0:
        return code, 0, 0, code == TRIVIAL, 0.0, 0
    z_basic = np.empty(n, dtype=np.bool_)
    code, pivots, recoveries, ok, residual = run_checked(
        method, M, q, max_pivots, pivot_tol, tie_tol, tol, buf, z_basic, np.False_, np.int64(0),
        np.int64(pivoting.CYCLING), np.int64(0))
    return code, pivots, basic_indices(z_basic, basic), ok, residual, recoveries


@inline_kernel
def basic_indices(z_basic, basic):
    """The indices i with ``z_basic[i]`` into the first entries of ``basic``; returns how
    many."""
    k = 0
    for i in range(z_basic.shape[0]):
        if z_basic[i]:
            basic[k] = i
            k += 1
    return k


@inline_kernel
def own_basic(n, buf, basic):
    """``basic``, or, when it is empty and n > 0, the n int64 that follow the buffer's
    fields (``buffer_size(n)`` floats): ``solve_lcp`` allocates one buffer of
    ``buffer_size(n) + n`` floats for both (an allocation and an argument fewer a call)."""
    if basic.shape[0] == 0 and n > 0:
        return borrow(buf, 6 * n + 2, n, np.int64)
    return basic


@kernel
def first_run(method, M, q, d, beta, k, max_pivots, pivot_tol, tie_tol, tol, buf, basic):
    """The common first calls, compiled alone: :func:`solve_one` by the tableau (``method`` is
    not read: it takes solve_one's arguments, so that the front calls either the same way),
    cold or warm, as far as the first stage of a warm start (:func:`old_basis`) and one cold
    run go -- the prologue, attempt 0 of :func:`pivot_recovering` and its check. When that
    decides the solve (the old basis solves it; solved and checked, q >= 0, a caller's
    covering vector, the pivots spent: no recovery run follows), it returns what solve_one
    returns.  When it does not (a cycle, a ray to check, recovery runs to make), it returns
    stage -1 with that run's code, pivots and residual (of the point's check; 0 after a
    cycle), and ``basic`` holds its flags of the basic z's: solve_one called with ``beta =
    [code, pivots]`` and ``k = -1`` goes on from there with the same bits.  A warm start whose old basis fails at n >= RESTART_FROM returns
    stage -2 at once: solve_one from that basis with ``k = -2 - k`` restarts Lemke there
    (without trying the point again).  Below RESTART_FROM a failed old basis goes cold here,
    as in solve_one.  So the first solves compile none of the rest (the unrevised method,
    the restart, the recoveries, the ray check: about two thirds of the compile of
    solve_one).  M and q of sizes that do not match (the front's fast path leaves the
    comparison to the kernels): code NOT_FINITE, nothing read (the front's validation then
    says what is wrong)."""
    n = q.shape[0]
    if M.shape[0] != n or M.shape[1] != n:
        return NOT_FINITE, 0, 0, False, 0.0, 0, 2
    basic = own_basic(n, buf, basic)
    if k > 0:  # a warm start: its first stage here, the restart in solve_one
        found, m_max, residual = old_basis(M, q, d, beta, k, tol, buf, basic)
        if found == 0:
            return pivoting.SOLVED, 0, k, True, residual, 0, 0
        if found < 0:
            return NOT_FINITE, 0, 0, False, 0.0, 0, 2
        if found == 1 and n >= RESTART_FROM:
            return 0, 0, 0, False, 0.0, 0, -2
    code = prologue(M, q, d, buf, k > 0)  # k > 0: old_basis scaled
    if code < 0:
        return code, 0, 0, code == TRIVIAL, 0.0, 0, 2
    x, ray, w, cov, R, C = layout(n, buf)
    z_basic = np.empty(n, dtype=np.bool_)
    code, pivots = tableau.solve(M, q, cov, R, C, max_pivots, pivot_tol, tie_tol, x, ray,
                                 z_basic, np.False_)
    ok, residual = False, 0.0
    if code != pivoting.CYCLING:
        ok, residual = lcp_check_sized(M, q, x[:n], tol, w, R)
        if ok:
            code = pivoting.SOLVED  # as in checked
    if code == pivoting.CYCLING or not ok and (
            code == pivoting.RAY_TERMINATION or (d.shape[0] == 0 and pivots < max_pivots)):
        for i in range(n):
            basic[i] = z_basic[i]
        return code, pivots, 0, False, residual, 0, -1
    return code, pivots, basic_indices(z_basic, basic), ok, residual, 0, 2


@kernel
def basis_point(M, q, beta, k, z):
    """z of the complementary basis with z_i basic for i in beta[:k]: ``z_beta = -M_bb^-1
    q_beta`` by LU (``linalg.solve_principal``), negative entries clipped to 0, the others
    0.  False when M_bb is singular or the point is not finite."""
    return basis_point_in(M, q, beta, k, z, np.empty(k * (k + 2)))


@inline_kernel
def basis_point_in(M, q, beta, k, z, work):
    """:func:`basis_point` with its work array given (at least k (k + 2) floats)."""
    z[:] = 0.0
    if k == 0:
        return True
    A, y, zb = solve_work(work, k)
    for i in range(k):
        y[i] = -q[beta[i]]
    if not solve_gathered(M, beta, A, y, zb, k):
        return False
    for i in range(k):
        z[beta[i]] = max(zb[i], 0.0)
    return True


#: The smallest n at which a warm start whose basis fails is restarted from that basis;
#: below it the problem goes cold (after the old basis's point was tried: 1.1-1.2x a cold
#: solve).  Remeasured after the tableau's pivots got cheaper (its loop without reference
#: counting), whole solve_lcp calls, restart / cold of the same q on seeded PD and
#: contact-like M, q moved by a relative 1e-3, 1e-2 and 0.3 (medians over problems and
#: moves): 1.4-1.7x at n = 24-48, PD 1.3 and contact 1.9 at 64, PD 1.0 and contact 1.4 at
#: 100, PD 0.63 and contact 1.3 at 150 (the restart often takes more pivots than a cold
#: solve on contact problems), then 0.3-0.9x at n = 200 and 300 (contact 1.1x for the
#: largest move at 300).  At 100 the PD problems and P-matrices moved a little (a few
#: pivots instead of a cold solve's 40-70) gain and the contact problems lose: the
#: threshold is there.  The earlier one, 24, was measured when a tableau pivot cost twice
#: as much.  Tried again at 48 after the unrevised method's updates got 1.2-2x cheaper
#: (2026-11-25): per solve the restart then tied with going cold on PD problems and took
#: 0.75-1.0x on contact ones at n = 48-64, but the pile of benchmarks/bench_small.py
#: settled into bases with 110 basic z's instead of 68 (restarts end in bases that keep
#: more z's basic at zero), and every later zero-pivot step paid the larger LU: 78 us a
#: step instead of 48 at n = 144.  So 100 stays.
#: (RESTART_FROM = 100: see lemke/_layout.py, which states it for the core and the fronts.)


@inline_kernel
def old_basis(M, q, d, beta, k, tol, buf, basic):
    """The first stage of a warm start: the point of the old basis (z_i basic for i in
    beta[:k], :func:`basis_point`), checked on (M, q), after the finite check and the
    equilibration (R and C in ``buf``).  Returns ``(found, m_max, residual)``: found 0 when
    the point passes (it is in ``buf``, ``basic`` holds beta, residual is its check's), 1
    when it fails (the check stopped at the first failed row: residual 0, w in ``buf``
    partly written; the caller solves again, which writes both), 2 when the old block is
    singular, -1 when M or q has a NaN or an infinity; m_max = max |M|."""
    n = q.shape[0]
    x, ray, w, cov, R, C = layout(n, buf)
    finite, m_max = finite_absmax(M)
    if not finite or nan_probe(q, n) != 0.0:
        return -1, m_max, 0.0
    equilibrate(M, q, R, C)
    x[n] = 0.0
    # One work array for the LU and then the check (2n floats), the only allocation here.
    work = np.empty(max(k * (k + 2), 2 * n))
    if not basis_point_in(M, q, beta, k, x[:n], work):
        return 2, m_max, 0.0
    # The check stops at the first row that fails (a wrong basis mostly fails in the first
    # rows it reads, and the full check's zero_size reads a column of M per failed row).
    ok, residual = lcp_check_early(M, q, x[:n], tol, w, R, work)
    if not ok:
        return 1, m_max, 0.0
    for i in range(n):
        cov[i] = d[i] if d.shape[0] else 1.0
    ray[:] = 0.0
    for i in range(k):
        basic[i] = beta[i]
    return 0, m_max, residual


@inline_kernel
def warm_stages(M, q, d, beta, k, max_pivots, pivot_tol, tie_tol, tol, buf, basic, tried):
    """The first two stages of a warm start: the point of the old basis (z_i basic for i in
    beta[:k]), checked on (M, q); if it fails, Lemke's method restarted from that basis (the
    unrevised method on the principal pivoting transform, with a constant covering vector
    there: ``c e_alpha - M[:, beta] 1``, c = max|M|, so z rows and w rows get the same
    constant), checked.

    The restart only from n = RESTART_FROM on: below, it costs more than a cold solve.

    Returns ``(stage, code, pivots, k, ok, residual)``: stage 0 (the old basis solved it: 0
    pivots) or 1 (the restart solved it) with code SOLVED; stage 2 when neither did (then
    only ``pivots``, those spent, counts: :func:`solve_one` goes on cold); stage -1 with
    code NOT_FINITE when M or q has a NaN or an infinity.  ``tried``: :func:`first_run` has
    made the first stage already, and its point failed (R and C are in ``buf``)."""
    n = q.shape[0]
    x, ray, w, cov, R, C = layout(n, buf)
    if tried:
        found, m_max, residual = 1, finite_absmax(M)[1], 0.0
    else:
        found, m_max, residual = old_basis(M, q, d, beta, k, tol, buf, basic)
    if found == 0:
        return 0, pivoting.SOLVED, 0, k, True, residual
    if found < 0:
        return -1, NOT_FINITE, 0, 0, False, 0.0
    if found == 2 or n < RESTART_FROM:
        return 2, 0, 0, 0, False, 0.0  # singular; or small: a cold solve costs less
    # the restart from the old basis
    flags = false_flags(2 * n)  # one allocation for both
    z_start, z_basic = flags[:n], flags[n:]
    for i in range(k):
        z_start[beta[i]] = True
    pivots, ok, residual = restart(M, q, z_start, beta, k, m_max, max_pivots, pivot_tol, tie_tol,
                                   tol, buf, z_basic)
    if ok:
        return 1, pivoting.SOLVED, pivots, basic_indices(z_basic, basic), True, residual
    return 2, 0, pivots, 0, False, 0.0


@inline_kernel
def restart(M, q, z_start, beta, k, m_max, max_pivots, pivot_tol, tie_tol, tol, buf, z_basic):
    """Lemke's method restarted from the complementary basis with z_i basic where
    ``z_start[i]``, that is for i in ``beta[:k]`` (ascending; the unrevised method on the principal pivoting transform, with a
    constant covering vector there: ``c e_alpha - M[:, beta] 1``, c = max|M| = m_max, so z
    rows and w rows get the same constant), its point checked on (M, q).  R and C must be
    in ``buf``, which gets the run's output; ``z_basic`` its final basic z's.  Returns
    ``(pivots, ok, residual)``; ok only when the run ended on a point that passes."""
    n = q.shape[0]
    x, ray, w, cov, R, C = layout(n, buf)
    m_scale = m_max if m_max > 0.0 else 1.0
    for i in range(n):
        acc = 0.0 if z_start[i] else m_scale
        for j in range(k):
            acc -= M[i, beta[j]]
        cov[i] = acc
    code, pivots = unrevised.solve(M, q, cov, R, C, z_start, no_matrix(), max_pivots,
                                   pivot_tol, tie_tol, x, ray, z_basic)
    if code == pivoting.NUMERICAL_FAILURE and pivots == 0:  # a singular start
        return pivots, False, 0.0
    ok, residual = lcp_check_sized(M, q, x[:n], tol, w, R)
    return pivots, ok, residual


@kernel
def solve_one(method, M, q, d, beta, k, max_pivots, pivot_tol, tie_tol, tol, buf, basic):
    """What ``solve_lcp`` runs for one problem, warm or cold, and what every batch runs per
    problem: :func:`warm_stages` from the basis ``beta[:k]`` when k > 0, then, unless they
    solved it, :func:`checked` cold with the pivots left (d: the covering vector, empty for
    all ones).  Returns ``(code, pivots, k, ok, residual, recoveries, stage)`` as
    :func:`checked` with the stage (0, 1 warm; 2 cold); code NOT_FINITE: M or q has a NaN or
    an infinity.  ``k = -1``: go on after :func:`first_run`, which ended with stage -1, the
    code ``beta[0]`` and ``beta[1]`` pivots (``checked``'s ``first_code`` and
    ``first_pivots``).  ``k < -1``: the warm start ``beta[:-2 - k]`` whose old basis's
    point :func:`first_run` tried (stage -2, its buffer as first_run left it): the restart
    from there.  M and q of sizes that do not match: code NOT_FINITE (see :func:`first_run`)."""
    if M.shape[0] != q.shape[0] or M.shape[1] != q.shape[0]:
        return NOT_FINITE, 0, 0, False, 0.0, 0, 2
    basic = own_basic(q.shape[0], buf, basic)
    pivots = 0
    first_code, first_pivots = np.int64(-1), np.int64(0)
    scaled = np.False_  # the finite check and the equilibration made (by old_basis)
    if k == -1:
        first_code, first_pivots = beta[0], beta[1]
    elif k != 0:
        tried = k < 0  # k = -2 - (the basis's size): first_run tried the old basis's point
        if tried:
            k = -2 - k
        stage, code, pivots, kk, ok, residual = warm_stages(M, q, d, beta, k, max_pivots, pivot_tol,
                                                            tie_tol, tol, buf, basic, tried)
        if stage < 2:
            return code, pivots, kk, ok, residual, 0, stage if stage >= 0 else 2
        scaled = np.True_  # stage 2: M and q finite, R and C in buf (not touched since)
    code, p, kk, ok, residual, recoveries = checked(method, M, q, d, max(0, max_pivots - pivots),
                                                   pivot_tol, tie_tol, tol, buf, basic,
                                                   first_code, first_pivots, scaled)
    return code, p + pivots, kk, ok, residual, recoveries, 2


@kernel
def _record(b, out_i, out_f, code, pivots, k, ok, residual, recoveries, stage):
    out_i[b, 0] = code
    out_i[b, 1] = pivots
    out_i[b, 2] = k
    out_i[b, 3] = recoveries
    out_i[b, 4] = stage
    out_f[b, 0] = 1.0 if ok else 0.0
    out_f[b, 1] = residual


@kernel
def batch(method, Ms, mstart, qs, qoff, beta, boff, lo, hi, max_pivots, pivot_tol, tie_tol, tol,
          bufs, buff, basics, out_i, out_f):
    """:func:`solve_one` on problems ``lo..hi-1`` laid end to end, of one size or of
    different sizes: problem b has n = ``qoff[b + 1] - qoff[b]``, q = ``qs[qoff[b]:qoff[b +
    1]]``, M = the n x n row-major block of ``Ms`` from ``mstart[b]`` (so that problems can
    share one M), warm start ``beta[boff[b]:boff[b + 1]]`` (empty: cold), output buffer
    ``bufs[buff[b]:buff[b + 1]]``, basic indices ``basics[qoff[b]:qoff[b + 1]]`` and pivot
    cap ``max_pivots[b]``.  Row b of ``out_i`` gets (code, pivots, k, recoveries, stage), of
    ``out_f`` (ok, residual).  By the tableau, each problem takes the path of ``solve_lcp``:
    :func:`first_run`, then :func:`solve_one` from where it stopped (stage -1 or -2), so the
    common solves skip solve_one's recovery machinery (at n = 3 it cost as much as the
    solve), with the same bits.  A first run that ended on a ray whose point failed the
    check (stage -1, code RAY_TERMINATION) gets the ray check here: when the ray passes,
    solve_one would return it at once (:func:`checked`: a checked ray of the first run is
    the verdict), and the result is made as it would (the basic z's, the residual of the
    point's check, 0 recoveries, stage 2); else solve_one goes on (the recovery runs)."""
    d = np.empty(0)
    resume = np.empty(2, dtype=np.int64)  # solve_one's beta after a first run (stage -1)
    for b in range(lo, hi):
        n = qoff[b + 1] - qoff[b]
        M = Ms[mstart[b]:mstart[b] + n * n].reshape((n, n))
        q = qs[qoff[b]:qoff[b + 1]]
        beta_b = beta[boff[b]:boff[b + 1]]
        k = boff[b + 1] - boff[b]
        buf = bufs[buff[b]:buff[b + 1]]
        basic = basics[qoff[b]:qoff[b + 1]]
        if method == TABLEAU:
            r = first_run(method, M, q, d, beta_b, k, max_pivots[b], pivot_tol, tie_tol, tol,
                          buf, basic)
            if r[6] >= 0:
                _record(b, out_i, out_f, *r)
                continue
            if r[6] == -1 and r[0] == pivoting.RAY_TERMINATION:
                x, ray, w, cov, R, C = layout(n, buf)
                if lcp_ray_check_scaled(M, q, cov, x[:n], x[n], ray, tol, R, C):
                    kk = np.int64(0)  # the flags in basic to indices, in place (kk <= i)
                    for i in range(n):
                        if basic[i] != 0:
                            basic[kk] = i
                            kk += 1
                    _record(b, out_i, out_f, r[0], r[1], kk, np.True_, r[4], np.int64(0), np.int64(2))
                    continue
            if r[6] == -1:  # go on from the first run
                resume[0] = r[0]
                resume[1] = r[1]
                beta_b = resume
                k = np.int64(-1)
            else:  # -2: restart from the old basis, whose point first_run tried
                k = -2 - k
        r = solve_one(method, M, q, d, beta_b, k, max_pivots[b], pivot_tol, tie_tol, tol, buf,
                      basic)
        _record(b, out_i, out_f, *r)
