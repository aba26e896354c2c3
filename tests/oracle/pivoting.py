"""The pivoting rule shared by every Lemke kernel: status codes, the first pivot, the ratio
test, the lexicographic tie-break, and the cycle detector.

A method (the tableau, the unrevised method) only supplies numbers: for each basic variable
its current value ``vals[i]`` and its change ``col[i]`` per unit of the entering variable,
and on a tie the entries of its basis inverse (relative to the starting basis).  Every
choice is made here, so both methods follow the same rule.

**The rule** is the lexicographic minimum ratio test: among the rows that block the entering
variable (``col[i] < 0``), choose the lexicographic minimum of the row vectors

    [vals[i] | Binv[i, :]] / -col[i],

the right-hand side first, then the columns of the basis inverse in the order of the
starting basis.  In exact arithmetic those rows are distinct (B^-1 is non-singular), the
order is strict, every row of [vals | B^-1] stays lexicographically positive, so no basis
repeats and the method cannot cycle.  Before the lexicographic keys, the artificial variable
wins any tie of the first key (it ends the method).

**Ties, in floating point.**  Two keys count as equal only when they agree to rounding,
relative to their own size: ``x`` ties the minimum ``m`` when ``x <= m + tie_tol *
max(|x|, |m|)``.  A key is a quotient b / a of two computed numbers; each carries the
rounding of the pivots that formed it, a relative error that grows from the unit roundoff
(1.1e-16) by the growth of the pivots, so quotients that are equal in exact arithmetic agree
to a relative 1e-14 ... 1e-12 on well-conditioned bases; ``tie_tol = 1e-11`` leaves a margin
above that and stays far below any real difference of two ratios.  Two values are never tied
merely because both are small: a basic variable of size 1e-10 is not tied with one of size
0 (both count as what they are), which is what keeps the right-hand side the first key even
when q mixes entries of 1e-2 and 1e-10.  What is zero is decided per row: a value counts as
zero when it is below ``VALUE_ROUNDING`` times the size of the terms it was formed from,
i.e. when it is rounding of an exact zero.  That size is |B^-1| |q| for a value B^-1 q.  Both
methods update their values in place (the unrevised method checks them against its basis
every few pivots); a running bound on that size grows with every pivot and would zero real
values, and the exact size costs O(n) a row (tried: 10x slower), so the first runs give the
values themselves as their size, and only negative values count as zero there; the
tableau's recovery runs (kernels.cold) compute the exact size for the few rows under a
running bound.  The tableau keeps exact zeros of its columns exact far more often than the
unrevised method's basis inverse (+-1e-17 there): one source of the differences between the
two methods that the README lists.  ``tie_tol = 0`` asks for exact ties only; the row
of the minimum always ties itself, so the candidate list is never empty.

The entries of the basis inverse that are zero in exact arithmetic come out as rounding
noise in the tableau; an entry below ``pivot_tol`` (in the kernels' units, where the largest
entry of every row and column of the equilibrated M is about 1) counts as zero.

**Entries of the entering column** take part only when ``col[i] < -pivot_tol * max|col|``.

**Cycle detection.**  The basis is fingerprinted by a 64-bit hash (the XOR of a fixed random
key per basic label, updated by two XORs a pivot), and Brent's algorithm compares the
fingerprint with one saved at powers of two: a repeated basis (a cycle of period p, after a
lead-in of l pivots) is detected within l + 2p pivots, in O(1) memory and O(1) time a
pivot.  A kernel that detects a cycle stops with ``CYCLING``; the driver
(``kernels.cold``) then recovers (see there).
"""
import numpy as np

from . import inline_kernel, kernel

SOLVED = 0
MAX_PIVOTS = 1
RAY_TERMINATION = 2
NUMERICAL_FAILURE = 3
CYCLING = 6  # the codes are those of lemke.Status (4, 5 are QP verdicts)
VALUE_ROUNDING = 1e-13  # a basic value is zero below this fraction of its terms' size
Z0_ROUNDING = 1e-11  # z0 is zero when below this fraction of its largest value (min_ratio)


@kernel
def first_row(vals, col, m, tie_tol):
    """The row that leaves when the artificial variable enters first (``col > 0``): the one
    that needs the largest increase ``-vals[i] / col[i]`` to become non-negative.  Ties (in
    the relative sense of the module docstring) go to the highest row, the lexicographic
    choice when the starting basis is the identity.  -1 when no entry is usable."""
    need = -np.inf
    for i in range(m):
        if col[i] > 0.0:
            need = max(need, -vals[i] / col[i])
    if need == -np.inf:
        return -1
    r = -1
    for i in range(m):
        if col[i] > 0.0:
            t = -vals[i] / col[i]
            if t >= need - tie_tol * max(abs(t), abs(need)):
                r = i
    return r


@kernel
def min_ratio(vals, mags, col, m, pivot_tol, tie_tol, cand, art, z0_max):
    """The blocking rows tied at the minimum ratio, in increasing order, in ``cand``;
    returns how many (0: nothing blocks, a ray).

    ``mags[i]`` is the size of the terms that formed ``vals[i]`` (sum |terms|, from the
    method): a value below ``VALUE_ROUNDING * mags[i]`` is zero to rounding (a
    degenerate row that came out as +-1e-17 instead of 0), and counts as 0, as do negative
    values.

    ``art`` is the artificial variable's row (-1 when it is not basic) and ``z0_max`` the
    largest value it has had.  z0 is formed from terms of that size, so after many pivots
    its rounding error is some 1e4 eps of z0_max (Z0_ROUNDING = 1e-11, whatever tie_tol
    is); when it blocks within that of the minimum ratio it is tied, and then leaves: a z0
    that is zero to rounding ends the method instead of driving on through pivots whose
    ratios are all rounding.  Only if the basis it leaves behind is still feasible to
    rounding (:func:`z0_leaves_harmlessly`): otherwise z0's value is read as it is, not as
    zero, and the ratio test takes its row like any other (the plain minimum ratio rule)."""
    cmax = 0.0
    for i in range(m):
        cmax = max(cmax, abs(col[i]))
    return blocking_rows(vals, mags, col, m, -pivot_tol * cmax, tie_tol, cand, art, z0_max)


@kernel
def blocking_rows(vals, mags, col, m, thr, tie_tol, cand, art, z0_max):
    """:func:`min_ratio` given ``thr = -pivot_tol * max|col|`` (a method that has just read
    the column computes it on the way), in one pass over the rows: the candidates tied with
    the running minimum are kept and filtered when the minimum drops, which gives the same
    rows in the same order as a pass for the minimum followed by a pass for the ties (a
    row rejected against the running minimum is rejected against the final one; the
    ratios are the same quotients, recomputed bit for bit)."""
    # One return at the end: numba's reference-count pruning then removes the array
    # arguments' increments (an early return with a loop defeats it: 8 atomic operations a call).
    theta = np.inf
    lim = np.inf
    nc = 0
    if art >= 0 and vals[art] <= Z0_ROUNDING * z0_max and abs(col[art]) > -thr:
        if z0_leaves_harmlessly(vals, mags, col, m, art, z0_max):
            # z0 is zero to rounding: the current point already solves the LCP; z0 leaves
            # by a degenerate pivot whatever the sign of its entry (the entering variable
            # moves by rounding only).
            cand[0] = art
            theta = 0.0
            nc = 1
            m = 0  # skip the ratio test
        else:
            z0_max = 0.0  # not rounding after all: z0's own value takes part in the test
    for i in range(m):
        # Every row's quotient is formed and the blocking test folded into one branch that
        # is almost never taken (only by a new minimum or a tie): a branch on the sign of
        # each entry would be mispredicted half the time.  A row that does not block gives
        # any quotient (inf or NaN too), never used.
        c = col[i]
        t = row_value(vals, mags, i, art, z0_max) / -c
        if (c < thr) & (t <= lim):
            if t < theta:
                theta = t
                lim = theta + tie_tol * theta
                kept = 0
                for q in range(nc):
                    j = cand[q]
                    if row_value(vals, mags, j, art, z0_max) / -col[j] <= lim:
                        cand[kept] = j
                        kept += 1
                nc = kept
            cand[nc] = i  # t <= lim still: t is the new minimum, or it was not one
            nc += 1
    return nc if theta < np.inf else 0


@kernel
def z0_leaves_harmlessly(vals, mags, col, m, art, z0_max):
    """Whether z0, small enough to be rounding (below ``Z0_ROUNDING z0_max``), may leave at
    once.  Pivoting it out moves the entering variable by ``t = z0 / -col[art]``, and the
    basis it leaves behind is feasible only if that moves no other basic variable below
    zero by more than rounding: by more than its own (``VALUE_ROUNDING mags_i``) or than
    z0's (``Z0_ROUNDING z0_max``, the level at which z0 itself was read as zero; the
    kernels' units are equilibrated, so every row has the same scale).  Then
    ``max(v_i, 0) + t col_i >= -(VALUE_ROUNDING mags_i + Z0_ROUNDING z0_max)`` for every
    row.  It fails when col[art] is tiny next to the other rows' entries: on the contact
    piles (issue 11) z0 = 3e-11 with col[art] = -3e-10 moved the entering variable by 0.1
    and drove a degenerate row to -0.1; the final basis was then singular to working
    precision (cond 2e11) and its point failed the check.  Then z0 is not read as rounding
    (see min_ratio) and the ratio test decides as for any other row."""
    t = vals[art] / -col[art]
    slack = Z0_ROUNDING * z0_max
    for i in range(m):
        if i != art:
            change = t * col[i]
            if change < 0.0 and max(vals[i], 0.0) + VALUE_ROUNDING * max(mags[i], 0.0) + slack < -change:
                return False
    return True


@inline_kernel
def row_value(vals, mags, i, art, z0_max):
    """Row i's value for the ratio test: 0 when negative or zero to rounding (below
    VALUE_ROUNDING of its terms' size; for the artificial variable's row ``art``, below
    Z0_ROUNDING of the largest value z0 has had)."""
    v = vals[i]
    if i == art:
        return v if v > Z0_ROUNDING * z0_max else 0.0
    return v if v > VALUE_ROUNDING * mags[i] else 0.0


@kernel
def lex_key(b, piv, pivot_tol):
    """One lexicographic key: the basis-inverse entry b divided by the pivot entry's size
    (``piv < 0``), with rounding noise on an exact zero read as zero."""
    if abs(b) <= pivot_tol:
        b = 0.0
    return b / -piv


@kernel
def keep_lowest(cand, keys, nc, tie_tol):
    """Keep (in place, in order) the candidates whose key ties the lowest; returns how many
    remain (at least one, unless a key is NaN)."""
    kmin = np.inf
    for c in range(nc):
        kmin = min(kmin, keys[c])
    kept = 0
    for c in range(nc):
        if keys[c] <= kmin + tie_tol * max(abs(keys[c]), abs(kmin)):
            cand[kept] = cand[c]
            keys[kept] = keys[c]
            kept += 1
    return kept


@kernel
def largest_pivot(cand, col, nc):
    """Still tied after every key (possible only through rounding): the candidate with the
    largest pivot, the first one on equal pivots."""
    best = cand[0]
    for c in range(1, nc):
        if col[cand[c]] < col[best]:
            best = cand[c]
    return best


@kernel
def label_keys(n_labels):
    """A fixed pseudo-random 64-bit key per label (splitmix64 of the label), for the basis
    fingerprint."""
    keys = np.empty(n_labels, dtype=np.uint64)
    fill_label_keys(keys)
    return keys


@kernel
def fill_label_keys(keys):
    """:func:`label_keys` into ``keys`` (one per label)."""
    for lab in range(keys.shape[0]):
        x = np.uint64(lab + 1) * np.uint64(0x9E3779B97F4A7C15)
        x = (x ^ (x >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
        x = (x ^ (x >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
        keys[lab] = x ^ (x >> np.uint64(31))


@kernel
def unit_random(keys, i):
    """A fixed pseudo-random number in [0, 1) from key i (its top 53 bits)."""
    return (keys[i] >> np.uint64(11)) * (1.0 / 9007199254740992.0)


@kernel
def fingerprint(keys, labels, m):
    """The fingerprint of the basis whose basic labels are ``labels[:m]``."""
    h = np.uint64(0)
    for i in range(m):
        h ^= keys[labels[i]]
    return h


@kernel
def new_detector():
    """Brent's cycle detector's state: [saved fingerprint, power, steps since saved]."""
    return np.zeros(3, dtype=np.uint64)


@kernel
def repeats(state, h):
    """Feed the fingerprint h of the basis after a pivot; True when a basis repeated."""
    if state[1] > 0 and h == state[0]:
        return True
    if state[2] == state[1]:
        state[0] = h
        state[1] = np.uint64(1) if state[1] == 0 else state[1] * np.uint64(2)
        state[2] = np.uint64(0)
    state[2] += np.uint64(1)
    return False


@kernel
def after_pivot(leaving, entering, artificial, h, hkeys, detector):
    """The end of every pivot, in both methods: ``(h, stop)`` with the basis fingerprint h
    updated for ``entering`` replacing ``leaving``, and stop SOLVED when the artificial
    variable left, CYCLING when the basis repeats (the detector), else -1."""
    if leaving == artificial:
        return h, SOLVED
    h ^= hkeys[leaving] ^ hkeys[entering]
    if repeats(detector, h):
        return h, CYCLING
    return h, -1


@kernel
def swap_labels(basis, nonbasic, pos, is_basic, r, s):
    """The bookkeeping of a pivot on row r and column s: the label of column s enters the
    basis at row r, the label of row r leaves for column s.  Returns the leaving label."""
    leaving = basis[r]
    entering = nonbasic[s]
    basis[r] = entering
    nonbasic[s] = leaving
    pos[entering] = r
    is_basic[entering] = True
    pos[leaving] = s
    is_basic[leaving] = False
    return leaving
