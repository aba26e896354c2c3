"""Seeded random and adversarial inputs for the native code that reads Python-supplied arrays
and objects (run by sanitized_run.run_all, so under ASan + UBSan in test_sanitized.py's child
and again in the test's own process, fingerprint against fingerprint).

* made_f64 / as_f64 / all_f64 and the entries' conversion retries (src/python_front.cpp):
  ragged and nested lists, huge ints, bools, NaN and infinities in lists, sizes 0, byte-
  swapped, strided, unaligned and non-native-dtype arrays, through solve_lcp, solve_blcp,
  solve_bimatrix and solve_lcp_many, and the private helpers with any rank;
* the batch helpers many_setup, many_unsettled, many_field and many_bases called directly
  with random and extreme offsets, sizes and dtypes: they must answer None or raise
  ValueError / TypeError, never read outside their arrays;
* the kept-matrix table's large slot (src/lemke/linalg.cpp memo_matches): warm starts on
  matrices of 250-300 rows, alternated, and on copies that differ in one entry and copies
  with two entries swapped (matrix_hash's sum and xor do not see a swap: a forced hash
  collision); each answer also compared bit for bit with the same solve in a fresh thread
  (an empty table);
* the box batch's grow-only workspace (src/lemke/boxed.cpp BoxedWork::layout): islands of
  varying sizes in one call, each compared bit for bit with its solve alone in a fresh
  thread.
* the seam's _core.lcp_basis and _core.box_basis (src/lemke/basis.hpp's LcpBasis, BoxBasis)
  on every size 0-40 and some larger, with random, full, empty and singular bases, rhs of
  the right length and one off, and malformed flags, M, q and rhs: each answer's arrays of
  the basis's sizes, or a ValueError / TypeError;
* blcp_pack (solve_blcp_many's islands packed natively from made_f64's forms), directly and
  through solve_blcp_many: islands of 0-45 rows given as lists, tuples, int lists, Fortran-
  ordered, strided, unaligned and byte-swapped arrays (answers and packed bytes bit for bit the
  float64 arrays'), and malformed ones (ragged and nested lists, M, q, lo, hi, findex of
  mismatched sizes or counts, findex out of range, negative, pointing at its own row, huge
  ints, scalar bounds of every Python type, NaN and infinities in every argument, lo > hi):
  each call answers, gives None or raises ValueError / TypeError.
* qp_front's own conversion (solve_qp's array-likes, branch qpfront): every argument in each
  of those forms, cold, warm and from a guess, bit for bit the float64 arrays' answer;
  Python-number bounds of every type and value; malformed data, rows and bounds; junk warm
  starts and guesses with converted data: an answer, None or ValueError / TypeError.
* the seam's QP basis system _core.qp_basis (src/lemke/qp.cpp's QpBasis) on QPs of 0-30
  variables with equalities, inequalities, bounds and fixed variables, random, empty, full
  and dependent active sets, z given or not, rhs of the right length and one off, both
  solves, and malformed arguments: an answer of the QP's sizes, or a ValueError / TypeError;
* the box batch's bindings boxed.islands and boxed.batch called directly (each island's rows
  judged in one pass, branch boxsmall) with random and extreme offsets, friction indices,
  flags, row states and island ranges: an answer or a ValueError / TypeError.
* the seam's games basis system _core.game_basis (basis.hpp's SupportBasis, branch
  gamesbasis) on games of 1-40 actions a side with random, final and malformed vertex
  pairs: an answer of the game's sizes or a ValueError / TypeError.
* the seam's _core.kkt_basis (basis.hpp's KktBasis, _qp._polished's system, branch polish) on
  QPs of 0-40 variables and more with every kind of bound, random, empty and full bases,
  rhs of the right length and one off, and malformed indices, arrays and data (see its
  block at the end).
* the core's reductions' private ends (src/lemke/reductions.hpp, branch reductions):
  boxed.friction_recover, boxed.friction_z, qp_box_apply, qp_box_recover, qp_multiplier_lcp and
  qp_multiplier_recover on sizes 0-20 and some larger, with answers of the right length and
  one off, random and extreme basic indices and final bases, and malformed arrays: an answer,
  None or ValueError / TypeError.

A mismatch with the fresh thread raises (a finding, reported as an exception by the Runner).
"""
from __future__ import annotations

import threading
import warnings

import numpy as np

import lemke
from lemke import _core, problems

REFUSED = (ValueError, TypeError, OverflowError, IndexError)
I64 = np.iinfo(np.int64)


def refused_or(fn):
    """fn's answer, or the name of the refusal it raised (so both builds' answers compare)."""
    def call():
        try:
            return fn()
        except REFUSED as e:
            return f"refused {type(e).__name__}"
    return call


def fresh_thread(fn):
    """fn() run in a new thread (empty thread-local tables and workspaces)."""
    out = {}

    def go():
        try:
            out["r"] = fn()
        except BaseException as e:  # (re-raised here)
            out["e"] = e
    t = threading.Thread(target=go)
    t.start()
    t.join()
    if "e" in out:
        raise out["e"]
    return out["r"]


def same_bits(a, b, what, than="a fresh thread's solve"):
    for name in ("z", "w"):
        x, y = np.asarray(getattr(a, name)), np.asarray(getattr(b, name))
        if x.shape != y.shape or x.tobytes() != y.tobytes() or a.status != b.status or a.pivots != b.pivots:
            raise AssertionError(f"{what}: {name} differs from {than}")


def conversions(run, rng):
    M, q = problems.random_psd(4, rng)
    swapped = M.astype(M.dtype.newbyteorder())
    raw = np.frombuffer(b"\0" + M.tobytes(), dtype=np.float64, offset=1).reshape(4, 4)
    inputs = {
        "ragged": ([[1.0, 2.0], [3.0]], [-1.0, -1.0]),
        "nested": ([[[1.0]]], [-1.0]),
        "row not a list": ([[1.0, 0.0], 5.0], [-1.0, -1.0]),
        "huge int": ([[2 ** 70, 0], [0, 1]], [-1, -1]),
        "int64 edge": ([[I64.max, I64.min], [0, 1]], [-1, 1]),
        "bools": ([[True, False], [False, True]], [True, -1]),
        "nan inf": ([[np.nan, 1.0], [np.inf, 1.0]], [-1.0, -np.inf]),
        "str": ([["1", 0], [0, 1]], [-1, -1]),
        "empty": ([], []),
        "empty rows": ([[], []], [-1.0, -1.0]),
        "float subclass": ([[np.float64(2.0), 0.0], [0.0, np.float32(1.0)]], [-1.0, -2.0]),
        "swapped": (swapped, q.astype(q.dtype.newbyteorder())),
        "unaligned": (raw, q),
        "strided": (np.repeat(np.repeat(M, 2, 0), 3, 1)[::2, ::3], q),
        "float16": (M.astype(np.float16), q.astype(np.float16)),
        "uint64": (np.eye(4, dtype=np.uint64), q),
        "complex": (M.astype(complex), q),
        "object": (M.astype(object), q.astype(object)),
        "0-size array": (np.zeros((0, 0)), np.zeros(0)),
        "1-D M": (q, q),
        "3-D M": (M[None], q),
        "int8 strided": (np.eye(8, dtype=np.int8)[::2, ::2], np.arange(-4, 0, dtype=np.int16)),
        "big list": ([[float(i == j) + 0.1 for j in range(40)] for i in range(40)], [-1.0] * 40),
    }
    for name, (Mx, qx) in inputs.items():
        run.attempt(f"fuzz conv {name} lcp", refused_or(lambda: lemke.solve_lcp(Mx, qx)))
        run.attempt(f"fuzz conv {name} lcp unrevised", refused_or(
            lambda: lemke.solve_lcp(Mx, qx, method="unrevised")))
        run.attempt(f"fuzz conv {name} blcp", refused_or(lambda: lemke.solve_blcp(Mx, qx, -1.0, 2)))
        run.attempt(f"fuzz conv {name} blcp list bounds", refused_or(
            lambda: lemke.solve_blcp(Mx, qx, [0.0, np.nan], [np.inf, 2 ** 80])))
        run.attempt(f"fuzz conv {name} game", refused_or(lambda: lemke.solve_bimatrix(Mx, Mx)))
        run.attempt(f"fuzz conv {name} many", refused_or(lambda: list(lemke.solve_lcp_many([Mx, Mx], [qx, qx]))))
        for nd in (-1, 0, 1, 2, 3):
            run.attempt(f"fuzz conv {name} as_f64 {nd}", refused_or(lambda: _core.as_f64(Mx, nd)))
            run.attempt(f"fuzz conv {name} all_f64 {nd}", refused_or(lambda: _core.all_f64((Mx, qx, None), (nd, 1, 0))))
    # random nested lists: random depth, lengths and leaves
    leaves = [0, 1, -1, 2 ** 63, -2 ** 63, 2 ** 63 - 1, True, False, 0.5, np.nan, -np.inf, None, "x", 1e308]
    for t in range(60):
        n = int(rng.integers(0, 4))
        def leaf():
            return leaves[int(rng.integers(len(leaves)))] if rng.random() < 0.3 else float(rng.normal())
        rows = [[leaf() for _ in range(n + int(rng.random() < 0.1))] for _ in range(n)]
        if rng.random() < 0.2 and rows:
            rows[int(rng.integers(n))] = tuple(rows[0])
        qv = [leaf() for _ in range(n)]
        run.attempt(f"fuzz conv random {t}", refused_or(lambda: lemke.solve_lcp(rows, qv)))
        run.attempt(f"fuzz conv random {t} box", refused_or(lambda: lemke.solve_blcp(rows, qv, leaf(), leaf())))
        run.attempt(f"fuzz conv random {t} game", refused_or(lambda: lemke.solve_bimatrix(rows, rows)))
        run.attempt(f"fuzz conv random {t} all_f64", refused_or(lambda: _core.all_f64((rows, qv), (2, 1))))


def batch_helpers(run, rng):
    sizes = np.array([3, 1, 4, 2], dtype=np.int64)
    Ms = [problems.random_psd(int(n), rng)[0] for n in sizes]
    Mp = np.concatenate([M.ravel() for M in Ms])
    qp = -np.ones(int(sizes.sum()))
    rs = lemke.solve_lcp_many(Mp, qp, sizes=sizes)
    off, out_i, out_f, bufs, basics = rs._off, rs._out_i, rs._out_f, rs._bufs, rs._basics
    qo, bo = off[0], off[2]
    extremes = np.array([0, 1, -1, 7, I64.max, I64.min, I64.max // 2, 1 << 62, len(bufs), len(basics)], dtype=np.int64)
    for t in range(120):
        q2, b2 = qo.copy(), bo.copy()
        def spoil(a, i):  # an extreme value, or one near the right one
            a[i] = extremes[int(rng.integers(len(extremes)))] if rng.random() < 0.5 else (
                int(a[i]) + int(rng.integers(-2, 3)) if I64.min + 2 <= a[i] <= I64.max - 2 else a[i])
        for a in (q2, b2):
            for _ in range(int(rng.integers(1, 3))):
                spoil(a, int(rng.integers(len(a))))
        o2 = out_i.copy()
        spoil(o2[int(rng.integers(len(o2)))], 2)
        a, c = (int(x) for x in rng.choice(extremes[:8], 2))
        run.attempt(f"fuzz many_field {t}", refused_or(lambda: _core.many_field(bufs, b2, q2, a, c)))
        run.attempt(f"fuzz many_field {t} ok offsets", refused_or(lambda: _core.many_field(bufs, bo, qo, a, c)))
        run.attempt(f"fuzz many_bases {t}", refused_or(lambda: _core.many_bases(basics, q2, o2)))
        run.attempt(f"fuzz many_bases {t} k", refused_or(lambda: _core.many_bases(basics, qo, o2)))
        s2 = sizes.copy()
        s2[int(rng.integers(len(s2)))] = extremes[int(rng.integers(len(extremes)))]
        run.attempt(f"fuzz many_setup {t}", refused_or(lambda: _core.many_setup(s2, Mp, qp, -1)))
    unaligned = lambda a: np.frombuffer(b"\0" + a.tobytes(), dtype=a.dtype, offset=1).reshape(a.shape)
    odd = {"unaligned": unaligned, "swapped": lambda a: a.astype(a.dtype.newbyteorder()),
           "fortran": np.asfortranarray, "strided": lambda a: np.repeat(a, 2, axis=0)[::2],
           "int32": lambda a: a.astype(np.int32), "transposed": lambda a: a.T, "short": lambda a: a[:-1],
           "empty": lambda a: a[:0]}
    for name, f in odd.items():
        run.attempt(f"fuzz many_unsettled {name} i", refused_or(lambda: _core.many_unsettled(f(out_i), out_f)))
        run.attempt(f"fuzz many_unsettled {name} f", refused_or(lambda: _core.many_unsettled(out_i, f(out_f))))
        run.attempt(f"fuzz many_bases {name}", refused_or(lambda: _core.many_bases(f(basics), f(qo), f(out_i))))
        run.attempt(f"fuzz many_field {name}", refused_or(lambda: _core.many_field(f(bufs), f(bo), f(qo), 0, 0)))
        run.attempt(f"fuzz many_setup {name}", refused_or(lambda: _core.many_setup(f(sizes), f(Mp), f(qp), -1)))


def kept_matrices(run, rng):
    """Warm starts through the large slot: 250-300 rows, alternated, one entry changed, two
    entries swapped (the same hash), each compared with a fresh thread's solve."""
    base = {}
    for n in (250, 260, 300):
        A = rng.normal(size=(n, n)) / n
        M = A @ A.T + np.eye(n)
        q = np.abs(rng.normal(size=n)) + 0.1
        q[rng.choice(n, 3, replace=False)] = -1.0  # a few basic z's: a small block
        base[n] = (M, q)
    one = {}
    for n, (M, q) in base.items():
        Mc = M.copy()
        Mc[5, 7] += 1e-9
        Ms = M.copy()
        Ms[1, 2], Ms[3, 4] = M[3, 4], M[1, 2]  # swapped: matrix_hash unchanged
        one[n] = (Mc, Ms)
    ws = {n: lemke.solve_lcp(M, q).warm_start for n, (M, q) in base.items()}
    order = [300, 300, 260, 300, 250, 300, "s300", "s300", 300, "c300", 300, 300, "s260", 260, 260, "c250", 250, 300]
    for t, key in enumerate(order):
        n = int(str(key).lstrip("sc"))
        M, q = base[n]
        if str(key)[0] == "c":
            M = one[n][0]
        elif str(key)[0] == "s":
            M = one[n][1]
        qq = q + 1e-7 * t
        r = run.attempt(f"fuzz kept {t} {key}", lambda: lemke.solve_lcp(M, qq, warm_start=ws[n]))
        if r is not None:
            run.attempt(f"fuzz kept {t} {key} vs fresh", lambda: same_bits(
                r, fresh_thread(lambda: lemke.solve_lcp(M, qq, warm_start=ws[n])), f"kept {key}"))


def box_islands(run, rng):
    """Islands of varying sizes through the box batch (BoxedWork grown, never shrunk): each
    answer bit for bit the island's solve alone in a fresh thread."""
    isl = []
    for n in (30, 2, 11, 1, 45, 5, 17, 3):
        M, q = problems.random_psd(n, rng)
        isl.append((M, q, np.full(n, -1.0), np.where(rng.random(n) < 0.5, 1.0, np.inf)))
    for order in (range(len(isl)), reversed(range(len(isl))), rng.permutation(len(isl))):
        order = [int(i) for i in order]
        args = [[isl[i][j] for i in order] for j in range(4)]
        res = run.attempt(f"fuzz box islands {order}", lambda: list(lemke.solve_blcp_many(*args, workers=1)))
        for i, r in zip(order, res or ()):
            run.attempt(f"fuzz box island {i} vs fresh", lambda: same_bits(
                r, fresh_thread(lambda: lemke.solve_blcp(*isl[i])), f"island {i}"))


BOX_REFUSED = (ValueError, TypeError)


def box_call(fn):
    """fn's answer (a list when it is a generator of results), or the name of its ValueError /
    TypeError (anything else raises: a finding)."""
    def call():
        try:
            out = fn()
            return list(out) if out is not None and not isinstance(out, tuple) else out
        except BOX_REFUSED as e:
            return f"refused {type(e).__name__}"
    return call


def same_pack(a, b, what):
    if a is None or b is None or len(a) != len(b):
        raise AssertionError(f"{what}: packed {a is None}, float64 arrays packed {b is None}")
    for x, y in zip(a, b):
        if (x is None) != (y is None) or (x is not None and (x.dtype != y.dtype or x.tobytes() != y.tobytes())):
            raise AssertionError(f"{what}: packed bytes differ from the float64 arrays'")


def _pack_vs(args, ref_pack, what):
    """blcp_pack of the islands args (float64 arrays in other forms): None (declined) or the
    float64 arrays' packed bytes; whether it packed them."""
    packed = _core.blcp_pack(*args)
    if packed is not None:
        same_pack(packed, ref_pack, what)
    return packed is not None


def _solve_vs(args, ref, what):
    """solve_blcp_many of args, each island's answer bit for bit ref's (the float64 arrays');
    the statuses."""
    res = list(lemke.solve_blcp_many(*args[:4], findex=args[4], workers=1))
    if len(res) != len(ref):
        raise AssertionError(f"{what}: {len(res)} answers, {len(ref)} for the float64 arrays")
    for i, (r, r0) in enumerate(zip(res, ref)):
        same_bits(r, r0, f"{what} island {i}", "the float64 arrays' solve")
    return [r.status.name for r in res]


def _int_island(n, rng, friction):
    """An island of n rows with integer entries (M = A^T A + I, symmetric positive definite):
    every form below (int lists, int32 arrays) carries the same values. With friction, rows
    1, 3, ... are friction rows of rows 0, 2, ... (lo = -hi, the normal row's lo >= 0)."""
    A = rng.integers(-2, 3, size=(n, n))
    M = (A.T @ A + np.eye(n, dtype=np.int64)).astype(np.float64)
    q = rng.integers(-4, 4, size=n).astype(np.float64)
    lo, hi = 0.0 - rng.integers(0, 3, size=n).astype(np.float64), rng.integers(1, 4, size=n).astype(np.float64)
    f = np.full(n, -1, dtype=np.int64)
    if friction:
        for i in range(1, n, 2):
            f[i], lo[i - 1], lo[i] = i - 1, 0.0, -hi[i]
    return M, q, lo, hi, f


def _forms(x):
    """x (a float64 array) in forms that made_f64 converts, or that blcp_pack declines and the
    Python path converts, all of x's values."""
    if x.size == 0:
        return {"list": x.tolist()}
    big = np.zeros((2,) + x.shape, dtype=x.dtype)
    big[0] = x
    raw = np.frombuffer(b"\0" + x.tobytes(), dtype=x.dtype, offset=1).reshape(x.shape)
    out = {"list": x.tolist(), "tuple": tuple(map(tuple, x)) if x.ndim == 2 else tuple(x.tolist()),
           "int list": x.astype(np.int64).tolist(), "int32": x.astype(np.int32),
           "strided": np.moveaxis(big, 0, -1)[..., 0], "unaligned": raw,
           "swapped": x.astype(x.dtype.newbyteorder())}
    if x.ndim == 2:
        out["fortran"] = np.asfortranarray(x)
        out["int rows"] = [np.asarray(r, dtype=np.int16) for r in x]  # (a list of arrays: declined)
    return out


def box_packs(run, rng):
    """blcp_pack directly and through solve_blcp_many (see the module's docstring)."""
    sizes = (1, 2, 0, 7, 45, 3)
    isl = [_int_island(n, rng, friction=n in (2, 7)) for n in sizes]
    ref_args = [[x[j] for x in isl] for j in range(4)]
    ref_f = [x[4] if n in (2, 7) else None for x, n in zip(isl, sizes)]
    ref_pack = _core.blcp_pack(*ref_args, ref_f)
    ref = run.attempt("fuzz box pack float64", lambda: list(lemke.solve_blcp_many(*ref_args, findex=ref_f, workers=1)))
    for j, name in enumerate(("M", "q", "lo", "hi", "findex")):
        for form in ("list", "tuple", "int list", "int32", "strided", "unaligned", "swapped", "fortran", "int rows"):
            args = [list(a) for a in ref_args] + [list(ref_f)]
            changed = False
            for b, x in enumerate(isl):
                if j == 4 and args[4][b] is None:
                    continue
                fx = _forms(x[j]) if j < 4 else {"list": x[4].tolist(), "tuple": tuple(x[4].tolist()),
                                                 "int32": x[4].astype(np.int32)}
                if form in fx:  # (else the float64 array: the 0-row island's, findex's)
                    args[j][b], changed = fx[form], True
            if changed:
                what = f"fuzz box pack {name} {form}"
                run.attempt(what, lambda: _pack_vs(args, ref_pack, what))
                run.attempt(what + " solve", lambda: _solve_vs(args, ref, what))
    # malformed and extreme islands (1-3 rows, lists): each call answers, declines or refuses
    M, q, lo, hi, f = _int_island(2, rng, friction=True)
    Ml, ql, lol, hil, fl = M.tolist(), q.tolist(), lo.tolist(), hi.tolist(), f.tolist()
    nan, inf = float("nan"), float("inf")
    cases = {
        "ragged M": ([[[1.0, 0.0], [0.0]]], [ql], lol, hil, None),
        "nested M": ([[[[1.0]]]], [[-1.0]], -1.0, 1.0, None),
        "M short": ([[[1.0]]], [ql], lol, hil, None),
        "M long": ([M.tolist() + [[0.0, 0.0]]], [ql], lol, hil, None),
        "M not square": ([[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]], [ql], -1.0, 1.0, None),
        "q short": ([Ml], [ql[:1]], -1.0, 1.0, None),
        "q long": ([Ml], [ql + [0.0]], -1.0, 1.0, None),
        "lo short": ([Ml], [ql], [lol[:1]], hil, None),
        "hi long": ([Ml], [ql], lol, [hil + [1.0]], None),
        "lo empty": ([Ml], [ql], [[]], 1.0, None),
        "findex short": ([Ml], [ql], [lol], [hil], [fl[:1]]),
        "findex long": ([Ml], [ql], [lol], [hil], [fl + [-1]]),
        "findex empty": ([Ml], [ql], [lol], [hil], [[]]),
        "findex row n": ([Ml], [ql], [lol], [hil], [[-1, 2]]),
        "findex -2": ([Ml], [ql], [lol], [hil], [[-1, -2]]),
        "findex int64 min": ([Ml], [ql], [lol], [hil], [[-1, int(I64.min)]]),
        "findex huge": ([Ml], [ql], [lol], [hil], [[-1, 2 ** 70]]),
        "findex self": ([Ml], [ql], [lol], [hil], [[-1, 1]]),
        "findex self array": ([M], [q], [lo], [hi], [np.array([-1, 1], dtype=np.int64)]),
        "findex out array": ([M], [q], [lo], [hi], [np.array([-1, I64.max], dtype=np.int64)]),
        "findex chain": ([Ml], [ql], [lol], [hil], [[1, 0]]),
        "findex floats": ([Ml], [ql], [lol], [hil], [[-1.0, 0.0]]),
        "findex bools": ([Ml], [ql], [lol], [hil], [[False, True]]),
        "findex not a list": ([Ml], [ql], [lol], [hil], fl),
        "findex count": ([Ml, Ml], [ql, ql], lol[0], 2, [fl]),
        "lo count": ([Ml, Ml], [ql, ql], [lol], 2, None),
        "q count": ([Ml, Ml], [ql], -1, 2, None),
        "no islands": ([], [], -1.0, 1.0, None),
        "lo > hi": ([Ml], [ql], [[2.0, 0.0]], [[1.0, 1.0]], None),
        "lo > hi scalar": ([Ml], [ql], 3, 2.5, None),
        "lo +inf": ([Ml], [ql], inf, inf, None),
        "hi -inf": ([Ml], [ql], -inf, -inf, None),
        "infinite bounds": ([Ml], [ql], -inf, inf, None),
        "huge int M": ([[[2 ** 70, 0], [0, 1]]], [ql], -1.0, 1.0, None),
        "int64 edge M": ([[[int(I64.max), int(I64.min)], [0, 1]]], [ql], -1.0, 1.0, None),
        "huge int q": ([Ml], [[2 ** 64, -1]], -1.0, 1.0, None),
        "huge int lo": ([Ml], [ql], -(2 ** 63) - 1, 1.0, None),
        "huge int hi list": ([Ml], [ql], -1.0, [[2 ** 65, 1]], None),
        "bools": ([[[True, False], [False, True]]], [[False, True]], [[False, False]], True, None),
        "zero rows lists": ([[]], [[]], -1.0, 1.0, None),
        "zero rows arrays": ([np.zeros((0, 0))], [np.zeros(0)], [np.zeros(0)], [np.zeros(0)],
                             [np.zeros(0, dtype=np.int64)]),
        "zero rows mixed": ([np.zeros((0, 0)), Ml], [np.zeros(0), ql], -1, 1.5, None),
        "strings": ([Ml], [ql], "-1", "1", None),
        "None bounds": ([Ml], [ql], None, None, None),
        "generator": ((m for m in [Ml]), [ql], -1.0, 1.0, None),
        "object array": ([np.array(Ml, dtype=object)], [ql], -1.0, 1.0, None),
    }
    for where in range(5):  # a NaN and the infinities in every argument
        for bad in (nan, inf, -inf):
            args = [[[list(r) for r in Ml]], [list(ql)], [list(lol)], [list(hil)], [list(fl)]]
            if where == 0:
                args[0][0][1][0] = bad
            elif where == 4:
                args[4][0][1] = bad
            else:
                args[where][0][1] = bad
            cases[f"{bad} in {('M', 'q', 'lo', 'hi', 'findex')[where]}"] = tuple(args)
    scalars = [0, 1, -1, True, False, 2.5, -2.5, 2 ** 63, -(2 ** 63), 2 ** 70, nan, inf, -inf, 0.0, -0.0,
               np.float64(1.5), np.float32(1.5), np.int32(2), np.int64(-1), np.bool_(True), 1 + 0j,
               __import__("fractions").Fraction(3, 2), __import__("decimal").Decimal("1.5"),
               type("F", (float,), {})(1.5), type("I", (int,), {})(2), [1.0], b"1", object()]
    for k, v in enumerate(scalars):
        cases[f"scalar lo {k} {type(v).__name__}"] = ([Ml], [ql], v, 3.0, None)
        cases[f"scalar hi {k} {type(v).__name__}"] = ([Ml], [ql], -3.0, v, None)
    for n, k in ((3037000499, 2), (1 << 31, 4)):  # lengths that overflow (bool views, strides 0)
        Mh = np.lib.stride_tricks.as_strided(np.zeros(1, np.bool_), shape=(n, n), strides=(0, 0))
        qh = np.lib.stride_tricks.as_strided(np.zeros(1, np.bool_), shape=(n,), strides=(0,))
        run.attempt(f"fuzz box pack huge views {n} x {k}", lambda: _core.blcp_pack([Mh] * k, [qh] * k, -1, 1, None))
    for name, args in cases.items():
        run.attempt(f"fuzz box pack {name}", box_call(lambda: _core.blcp_pack(*args)))
        run.attempt(f"fuzz box pack {name} solve", box_call(lambda: lemke.solve_blcp_many(
            *args[:4], findex=args[4], workers=1)))


def fuzz(run):
    rng = np.random.default_rng(2026)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # (complex inputs cast, NaN in lists, ...)
        conversions(run, rng)
        batch_helpers(run, rng)
        kept_matrices(run, rng)
        box_islands(run, rng)
        box_packs(run, rng)
        box_gathers(run, np.random.default_rng(2032))
        qp_conversions(run, np.random.default_rng(2041))
        basis_seam(run, np.random.default_rng(2033))
        box_batch_checks(run, np.random.default_rng(2033))
        unaligned_entries(run)
        friction_seam(run, np.random.default_rng(2034))
        mlcp_seam(run, np.random.default_rng(2035))
        games_seam(run, np.random.default_rng(2036))
        kkt_seam(run, np.random.default_rng(2036))
        qp_seam(run, np.random.default_rng(2036))
        reductions_core(run, np.random.default_rng(2037))


# --- the box batch's gathers (branch boxisl): many_field with a per-island answer offset and
# the flat bounds of islands flagged 0 (BLCPManyResult._gather), called directly with random
# and extreme offsets, answers, flags and dtypes: None, a ValueError / TypeError, or the
# spans; never a read outside the arrays.

def box_gathers(run, rng):
    sizes = np.array([3, 0, 4, 2, 6], dtype=np.int64)
    Mp, qp, lo, hi, fi = friction_islands(sizes, rng)
    rb = lemke.solve_blcp_many(Mp, qp, lo, hi, findex=fi, sizes=sizes, workers=1)
    bufs, bo, qo, ans, flag = rb._bufs, rb._buff, rb._qoff, rb._answer, rb._fflag
    run.attempt("fuzz box gathers ok", refused_or(lambda: [_core.many_field(bufs, bo, qo, s, 0, ans,
                                                                            flag if s > 1 else None, lo)
                                                           for s in range(4)]))
    extremes = np.array([0, 1, -1, 7, I64.max, I64.min, I64.max // 2, 1 << 62, len(bufs)], dtype=np.int64)
    for t in range(120):
        a2, q2, b2 = ans.copy(), qo.copy(), bo.copy()
        for arr in (a2, q2, b2)[: int(rng.integers(1, 4))]:
            i = int(rng.integers(len(arr)))
            arr[i] = extremes[int(rng.integers(len(extremes)))] if rng.random() < 0.5 else (
                int(arr[i]) + int(rng.integers(-2, 3)) if I64.min + 2 <= arr[i] <= I64.max - 2 else arr[i])
        a, c = (int(x) for x in rng.choice(extremes[:8], 2))
        f2 = rng.integers(0, 2, size=flag.size).astype(np.uint8)
        short = lo[: int(rng.integers(0, lo.size + 1))]
        run.attempt(f"fuzz box gathers {t}", refused_or(lambda: _core.many_field(bufs, b2, q2, a, c, a2)))
        run.attempt(f"fuzz box gathers {t} flat", refused_or(lambda: _core.many_field(bufs, b2, q2, a, c, a2, f2, short)))
        run.attempt(f"fuzz box gathers {t} ok offsets", refused_or(lambda: _core.many_field(bufs, bo, qo, a, c, a2, f2, lo)))
    unaligned = lambda a: np.frombuffer(b"\0" + a.tobytes(), dtype=a.dtype, offset=1).reshape(a.shape)
    odd = {"unaligned": unaligned, "swapped": lambda a: a.astype(a.dtype.newbyteorder()),
           "strided": lambda a: np.repeat(a, 2)[::2], "int32": lambda a: a.astype(np.int32),
           "2-D": lambda a: a.reshape(1, -1), "short": lambda a: a[:-1], "empty": lambda a: a[:0]}
    for name, f in odd.items():
        run.attempt(f"fuzz box gathers {name} answer", refused_or(lambda: _core.many_field(bufs, bo, qo, 1, 0, f(ans))))
        run.attempt(f"fuzz box gathers {name} flag", refused_or(lambda: _core.many_field(bufs, bo, qo, 2, 0, ans, f(flag), lo)))
        run.attempt(f"fuzz box gathers {name} flat", refused_or(lambda: _core.many_field(bufs, bo, qo, 2, 0, ans, flag, f(lo))))


# --- solve_qp's native conversion (branch qpfront): qp_front converting its arguments by
# made_f64 (and Python-number bounds by made_bound) when the plain front declines them, through
# solve_qp (cold, warm, initvals) and _core.qp_front directly: every form of made_f64's (and
# the ones it declines: byte-swapped, unaligned...) bit for bit the float64 arrays' answer;
# malformed ones (ragged and nested lists, mismatched sizes, NaN and infinities in every
# argument, scalar bounds of every Python type, huge ints, junk warm starts and guesses) an
# answer, None from the front, or a ValueError / TypeError.

def _qp_same(a, b, what):
    if type(a) is not type(b) or fingerprint_of(a) != fingerprint_of(b):
        raise AssertionError(f"{what}: differs from the float64 arrays' answer")


def fingerprint_of(r):
    if not isinstance(r, lemke.QPResult):
        return repr(r)
    return (r.status, r.pivots, *(np.asarray(getattr(r, k)).tobytes() for k in ("x", "y", "z", "z_box")))


def qp_conversions(run, rng):
    n = 4
    P, q, G, h, A, b, lb, ub = problems.random_convex_qp(n, rng, 3, 1)
    data = [P, q, G, h, A, b, lb, ub]
    want = lemke.solve_qp(*data)
    ws = want.warm_start
    x0 = want.x + 0.01
    f64 = lambda x: None if x is None else np.ascontiguousarray(np.asarray(x).astype(np.float64))
    for i, x in enumerate(data):
        for name, form in _forms(x).items():
            args = list(data)
            args[i] = form
            plain = [f64(a) for a in args] if name not in ("int rows",) else None
            what = f"fuzz qp conv arg {i} {name}"
            run.attempt(what, refused_or(lambda: lemke.solve_qp(*args)))
            run.attempt(what + " warm", refused_or(lambda: lemke.solve_qp(*args, warm_start=ws)))
            run.attempt(what + " initvals", refused_or(lambda: lemke.solve_qp(*args, initvals=list(x0))))
            run.attempt(what + " front", refused_or(lambda: _core.qp_front(*args, 0, None, None)))
            if plain is not None:
                run.attempt(what + " same", lambda: _qp_same(lemke.solve_qp(*args), lemke.solve_qp(*plain), what))
    scalars = [0, -1, 1.5, -2.5, True, None, 2 ** 70, -2 ** 70, np.nan, np.inf, -np.inf, 1e20, -1e20,
               1e300, -1e300, "1", 1 + 0j, np.float32(1.0), np.int64(-1), [], [0.0], (0.0,) * n]
    for lo in scalars:
        for up in scalars:
            run.attempt(f"fuzz qp scalar bounds {lo!r} {up!r}", refused_or(
                lambda: lemke.solve_qp(P.tolist(), q, G, h, A, b, lo, up)))
            run.attempt(f"fuzz qp scalar bounds {lo!r} {up!r} front", refused_or(
                lambda: _core.qp_front(P, q.tolist(), None, None, None, None, lo, up, 0, None, None)))
    bad = {
        "ragged P": ([[1.0, 0.0], [0.0]], [1.0, 1.0]),
        "nested P": ([[[1.0]]], [1.0]),
        "empty": ([], []),
        "empty rows": ([[], []], [1.0, 1.0]),
        "1-D P": ([1.0, 2.0], [1.0, 2.0]),
        "short q": (P.tolist(), q[:-1].tolist()),
        "nan P": ([[np.nan, 0.0], [0.0, 1.0]], [1.0, 1.0]),
        "inf q": ([[1.0, 0.0], [0.0, 1.0]], [np.inf, 1.0]),
        "huge int": ([[2 ** 70, 0], [0, 1]], [1, 1]),
        "int64 edge": ([[I64.max, 0], [0, I64.min]], [1, -1]),
        "str": ([["1", 0], [0, 1]], [1, 1]),
        "object": (np.eye(2, dtype=object), [1, 1]),
        "float16": (np.eye(2, dtype=np.float16), np.ones(2, np.float16)),
    }
    rows = {"none": (None, None), "G only": ([[1.0, 1.0]], None), "h only": (None, [1.0]),
            "ok": ([[1.0, 1.0]], [1.0]), "short h": ([[1.0, 1.0]], []), "nan h": ([[1.0, 1.0]], [np.nan]),
            "wide G": ([[1.0, 1.0, 1.0]], [1.0]), "ragged G": ([[1.0], [1.0, 2.0]], [1.0, 1.0]),
            "1-D G": ([1.0, 1.0], [1.0]), "scalar h": ([[1.0, 1.0]], 1.0), "int G": ([[1, -1]], [0])}
    for name, (Px, qx) in bad.items():
        for rname, (Gx, hx) in rows.items():
            for lo in (None, 0, [0, 0], -np.inf):
                what = f"fuzz qp bad {name} {rname} {lo!r}"
                run.attempt(what, refused_or(lambda: lemke.solve_qp(Px, qx, Gx, hx, lb=lo)))
                run.attempt(what + " eq", refused_or(lambda: lemke.solve_qp(Px, qx, A=Gx, b=hx, ub=lo)))
                run.attempt(what + " front", refused_or(
                    lambda: _core.qp_front(Px, qx, Gx, hx, None, None, lo, None, 0, None, None)))
    # junk warm starts and guesses with converted data
    extremes = [0, 1, -1, 3, n, n + 4, I64.max, I64.min]
    Pl, ql, Gl, hl = P.tolist(), q.tolist(), G.tolist(), h.tolist()
    for t in range(40):
        pairs = int(extremes[int(rng.integers(len(extremes)))])
        beta = np.sort(rng.choice(np.array(extremes, dtype=np.int64), size=int(rng.integers(0, 4)), replace=False))
        guess = [float(v) for v in rng.standard_normal(int(rng.integers(n - 1, n + 2)))]
        if rng.random() < 0.3 and guess:
            guess[0] = [np.nan, np.inf, 2 ** 70, "x", None][int(rng.integers(5))]
        run.attempt(f"fuzz qp junk warm {t}", refused_or(
            lambda: _core.qp_front(Pl, ql, Gl, hl, A, b, lb, ub, pairs, beta, None)))
        run.attempt(f"fuzz qp junk guess {t}", refused_or(
            lambda: _core.qp_front(Pl, ql, Gl, hl, A, b, lb, ub, 0, None, guess)))
        run.attempt(f"fuzz qp junk guess {t} solve", refused_or(
            lambda: lemke.solve_qp(Pl, ql, Gl, hl, A, b, lb, ub, initvals=guess)))


# --- the seam's basis systems (branch seam): _core.lcp_basis and _core.box_basis called
# directly on every size 0-40 and some larger, with random, empty, full and singular bases,
# rhs of the right length and one off, both solves, and malformed arguments (flags of other
# dtypes, layouts and lengths, M not square, q short, NaN and infinities): an answer whose
# arrays have the sizes the basis gives (z and w n entries, x one per block row), or a
# ValueError / TypeError; never a read or write outside the arrays.

def _seam_sizes(n, flags, got):
    """got (lcp_basis's or box_basis's answer) checked for its sizes (flags: the block's
    rows); the answer."""
    code, z, w, residual, x = got
    k = int(np.count_nonzero(flags))
    if code in (0, 1):
        if z.shape != (n,) or w.shape != (n,):
            raise AssertionError(f"lcp_basis: z, w of shapes {z.shape}, {w.shape} for n = {n}")
    elif z is not None or w is not None:
        raise AssertionError(f"lcp_basis: code {code} with a point")
    if x is not None and x.shape != (k,):
        raise AssertionError(f"lcp_basis: x of shape {x.shape} for k = {k}")
    return got


def _seam_problems(rng):
    """(n, M, q) on every size 0-40 and some larger, M well conditioned."""
    for n in list(range(41)) + [63, 64, 65, 130]:
        A = rng.normal(size=(n, n))
        M = A + np.sqrt(max(n, 1)) * np.eye(n)
        yield n, M, rng.normal(size=n)


# an array in the forms the seam's entries refuse or convert
ODD = {"unaligned": lambda a: np.frombuffer(b"\0" + a.tobytes(), dtype=a.dtype, offset=1).reshape(a.shape),
       "swapped": lambda a: a.astype(a.dtype.newbyteorder()),
       "strided": lambda a: np.repeat(a, 2, axis=0)[::2], "int32": lambda a: a.astype(np.int32),
       "float": lambda a: a.astype(float), "2-D": lambda a: a.reshape(1, -1), "short": lambda a: a[:-1],
       "long": lambda a: np.concatenate([a, a[:1]]), "empty": lambda a: a[:0]}


def basis_seam(run, rng):
    for n, M, q in _seam_problems(rng):
        for t in range(4):
            flags = (rng.random(n) < (0.2, 0.6, 1.0, 0.0)[t]).astype(np.uint8 if t % 2 else bool)
            k = int(np.count_nonzero(flags))
            Ms = M
            if t == 1 and k >= 2:  # a singular block: two basic rows equal
                b = np.flatnonzero(flags)
                Ms = M.copy()
                Ms[b[1]] = Ms[b[0]]
            for length in (k, k + 1, max(k - 1, 0)):
                rhs = rng.normal(size=length)
                for tr in (False, True):
                    run.attempt(f"fuzz seam {n} {t} {length - k} {tr}", refused_or(
                        lambda: _seam_sizes(n, flags, _core.lcp_basis(Ms, q, flags, 1e-9, rhs, tr))))
            run.attempt(f"fuzz seam {n} {t} no rhs", refused_or(
                lambda: _seam_sizes(n, flags, _core.lcp_basis(Ms, q, flags, 1e-9))))
            lo = np.where(rng.random(n) < 0.7, -rng.random(n), -np.inf)
            hi = np.where(rng.random(n) < 0.7, rng.random(n), np.inf)
            zh = (rng.random(n) < 0.5).astype(flags.dtype)
            rows = flags.astype(bool) | ((t % 2 == 1) & np.isneginf(lo) & np.isposinf(hi))
            for length in (int(rows.sum()), int(rows.sum()) + 1):
                rhs = rng.normal(size=length)
                run.attempt(f"fuzz seam box {n} {t} {length}", refused_or(
                    lambda: _seam_sizes(n, rows, _core.box_basis(Ms, q, lo, hi, flags, zh, t % 2 == 1,
                                                                 1e-9, rhs, t > 1))))
    M, q = problems.random_psd(5, rng)
    f = np.array([1, 0, 1, 1, 0], dtype=np.uint8)
    rhs = np.ones(3)
    for name, g in ODD.items():
        run.attempt(f"fuzz seam {name} flags", refused_or(lambda: _core.lcp_basis(M, q, g(f), 1e-9, rhs)))
        run.attempt(f"fuzz seam {name} q", refused_or(lambda: _core.lcp_basis(M, g(q), f, 1e-9, rhs)))
        run.attempt(f"fuzz seam {name} rhs", refused_or(lambda: _core.lcp_basis(M, q, f, 1e-9, g(rhs), True)))
        run.attempt(f"fuzz seam {name} M", refused_or(lambda: _core.lcp_basis(g(M), q, f, 1e-9, rhs)))
        run.attempt(f"fuzz seam box {name} zh", refused_or(lambda: _core.box_basis(M, q, -q, q * q, f, g(f), True, 1e-9, rhs)))
        run.attempt(f"fuzz seam box {name} lo", refused_or(lambda: _core.box_basis(M, q, g(-q), q * q, f, f, False, 1e-9, rhs)))
    for bad in (np.nan, np.inf, -np.inf):
        for where in ("M", "q", "rhs"):
            M2, q2, r2 = M.copy(), q.copy(), rhs.copy()
            {"M": M2[2], "q": q2, "rhs": r2}[where][1] = bad
            run.attempt(f"fuzz seam {bad} in {where}", refused_or(
                lambda: _seam_sizes(5, f, _core.lcp_basis(M2, q2, f, 1e-9, r2, where == "rhs"))))

# --- the box batch's bindings (branch boxsmall): boxed.islands and boxed.batch called
# directly with random and extreme offsets, friction indices, flags, row states and island
# ranges (each island's rows judged in one pass before any read): an answer, or a ValueError /
# TypeError; never a read outside the arrays.

def friction_islands(sizes, rng):
    """Islands of these sizes (the third of at least 3 rows) packed: M, q, lo, hi, findex;
    the third island's rows 1, 2 friction rows of its row 0."""
    isl = [problems.random_psd(int(n), rng) for n in sizes]
    Mp = np.concatenate([M.ravel() for M, _ in isl])
    qp = np.concatenate([q for _, q in isl])
    lo, hi = np.full(qp.size, -1.0), np.full(qp.size, 2.0)
    fi = np.full(qp.size, -1, dtype=np.int64)
    r = int(sizes[:2].sum())  # (the third island's first row)
    fi[[r + 1, r + 2]] = 0
    lo[[r, r + 1, r + 2]] = 0.0, -2.0, -2.0
    return Mp, qp, lo, hi, fi


def box_batch_checks(run, rng):
    boxed = _core.boxed
    sizes = np.array([3, 0, 4, 2], dtype=np.int64)
    Ms, qs, lo, hi, fi = friction_islands(sizes, rng)
    qoff = np.zeros(sizes.size + 1, dtype=np.int64)
    np.cumsum(sizes, out=qoff[1:])
    mstart = np.zeros(sizes.size, dtype=np.int64)
    np.cumsum(sizes[:-1] ** 2, out=mstart[1:])
    fflag = np.array([0, 0, 1, 1], dtype=np.uint8)
    state = np.zeros(qs.size, dtype=np.int8)
    state[[4, 5]] = 3
    wflag = np.array([1, 0, 1, 1], dtype=np.uint8)
    opts = lemke.Options()
    B = sizes.size

    def islands(qoff, fi, fflag, state, wflag):
        k = max(qoff.size - 1, 0)
        out = [np.zeros(m, dtype=np.int64) for m in (k + 1, k + 1, k, k)]
        bad = boxed.islands(qoff, fi, fflag, state, wflag, -1, *out)
        return bad, out

    _, (buff, ioff, _, limits) = islands(qoff, fi, fflag, state, wflag)

    def batch(a):
        bufs, ints = np.zeros(int(buff[-1])), np.zeros(int(ioff[-1]), dtype=np.int64)
        out_i, out_f, state_out = np.zeros((B, 7), np.int64), np.zeros(B), np.zeros(qs.size, np.int8)
        boxed.batch(a["Ms"], a["mstart"], qs, lo, hi, a["qoff"], a["fi"], a["fflag"], a["state"],
                    a["wflag"], a["lo"], a["hi"], limits, opts.pivot_tol, opts.tie_tol, opts.tol,
                    bufs, a["buff"], ints, a["ioff"], state_out, out_i, out_f)
        return out_i, out_f, state_out, bufs, ints

    base = {"Ms": Ms, "mstart": mstart, "qoff": qoff, "fi": fi, "fflag": fflag, "state": state,
            "wflag": wflag, "lo": 0, "hi": B, "buff": buff, "ioff": ioff}
    run.attempt("fuzz box batch checks ok", refused_or(lambda: batch(base)))
    extremes = np.array([0, 1, -1, 3, 7, I64.max, I64.min, I64.max // 2, 1 << 31, 1 << 62], dtype=np.int64)
    for t in range(160):
        a = dict(base)
        for name in rng.choice(["mstart", "qoff", "fi", "state", "fflag", "wflag", "buff", "ioff", "range", "short"],
                               size=int(rng.integers(1, 3)), replace=False):
            if name == "range":
                a["lo"], a["hi"] = (int(x) for x in rng.integers(-1, B + 2, size=2))
            elif name == "short":
                a["Ms"] = Ms[: int(rng.integers(0, Ms.size))]
            elif name == "state":
                st = state.copy()
                st[int(rng.integers(st.size))] = int(rng.integers(-3, 33))
                a["state"] = st
            elif name in ("fflag", "wflag"):
                a[name] = rng.integers(0, 2, size=B).astype(np.uint8)
            else:
                arr = base[name].copy()
                i = int(rng.integers(arr.size))
                arr[i] = extremes[int(rng.integers(extremes.size))] if rng.random() < 0.5 else (
                    int(arr[i]) + int(rng.integers(-2, 3)))
                a[name] = arr
        run.attempt(f"fuzz box batch checks {t}", refused_or(lambda: batch(a)))
        run.attempt(f"fuzz box islands checks {t}",
                    refused_or(lambda: islands(a["qoff"], a["fi"], a["fflag"], a["state"], a["wflag"])))

# --- unaligned arrays on every _core entry that reads typed arrays (branch align): nanobind
# passes a C-contiguous array through whatever its address, and reading it as doubles or int64
# is undefined (UBSan's alignment check, in -fsanitize=undefined). Every entry whose signature
# takes float64 or int64 ndarrays (typed_entries: read from the signatures, so a new entry is
# in) is called with small arrays of consistent shapes (3 entries a dimension), then with each
# such argument in turn, and all at once, unaligned (writable, one byte into a bytearray):
# TypeError (src/python_arrays.hpp's Aligned refuses it) or the aligned call's answer.

ENTRY_INITS = ("lcp_front_init", "games_front_init", "qp_front_init", "blcp_front_init")  # (state)


def _split_params(text):
    """The parameters of a nanobind signature's argument list, split at top-level commas."""
    out, depth, cur = [], 0, ""
    for ch in text:
        depth += ch in "[(" and 1 or (ch in "])" and -1 or 0)
        if ch == "," and depth == 0:
            out.append(cur.strip())
            cur = ""
        else:
            cur += ch
    return out + ([cur.strip()] if cur.strip() else [])


def typed_entries():
    """[(name, function, params)] of the _core (and _core.boxed) functions whose signature
    takes float64 or int64 ndarrays; params [(kind, ndim)]: kind a dtype name, 'flags' (an
    ndarray of no dtype: bool flags), or the Python type's name."""
    import re
    found = []
    for prefix, mod in (("", _core), ("boxed.", _core.boxed)):
        for name in sorted(dir(mod)):
            fn = getattr(mod, name)
            sig = (getattr(fn, "__doc__", None) or "").split("\n")[0]
            if name.startswith("_") or not callable(fn) or name in ENTRY_INITS or not sig.startswith(name + "("):
                continue
            if not re.search(r"ndarray\[dtype=(float64|int64)", sig):
                continue
            body = sig[len(name) + 1: sig.rindex(") ->")]
            params = []
            for p in _split_params(body):
                t = p.split(":", 1)[1].split(" = ")[0].strip() if ":" in p else "object"
                if t.startswith("ndarray["):
                    m = re.search(r"dtype=(\w+)", t)
                    shape = re.search(r"shape=\(([^)]*)\)", t)
                    params.append((m.group(1) if m else "flags", shape.group(1).count("*") if shape else 1))
                else:
                    params.append((t.split("|")[0].strip(), 0))
            found.append((prefix + name, fn, params))
    return found


def entry_args(params):
    """Fresh arguments for params: arrays of 3 entries a dimension, ints 3, floats 1e-9."""
    out = []
    for kind, nd in params:
        if kind == "float64":
            out.append(np.eye(3) * 2.0 + 0.25 if nd == 2 else np.linspace(0.5, 1.5, 3 ** nd).reshape((3,) * nd))
        elif kind == "int64":
            out.append(np.arange(3 ** nd, dtype=np.int64).reshape((3,) * nd) % 3)
        elif kind in ("uint8", "int8"):
            out.append(np.zeros((3,) * nd, dtype=kind))
        elif kind == "flags":
            out.append(np.zeros(3, dtype=bool))
        else:
            out.append({"int": 3, "float": 1e-9, "bool": False}.get(kind))
    return out


def writable_unaligned(a):
    """a's values in a writable C-contiguous array of a's dtype, one byte off alignment."""
    u = np.frombuffer(bytearray(b"\0" + np.ascontiguousarray(a).tobytes()), dtype=a.dtype,
                      offset=1).reshape(a.shape)
    return u


def _entry_answer(fn, args):
    """fn(*args)'s answer and the arguments' bytes after it (outputs written), or the name of
    the refusal it raised."""
    try:
        got = fn(*args)
    except REFUSED as e:
        return f"refused {type(e).__name__}"
    return repr(got), [a.tobytes() if isinstance(a, np.ndarray) else a for a in args]


def unaligned_calls(fn, params):
    """[(which, answer)]: the aligned call's answer (which None), then each float64 / int64
    argument's unaligned call (which its index) and all of them at once (which 'all')."""
    want = _entry_answer(fn, entry_args(params))
    out = [(None, want)]
    typed = [i for i, (kind, nd) in enumerate(params) if kind in ("float64", "int64")]
    for pick in [[i] for i in typed] + [typed]:
        args = entry_args(params)
        for i in pick:
            args[i] = writable_unaligned(args[i])
        out.append((pick[0] if len(pick) == 1 else "all", _entry_answer(fn, args)))
    return out


def unaligned_entries(run):
    entries = typed_entries()
    if len(entries) < 50:
        raise AssertionError(f"only {len(entries)} typed _core entries found")
    for name, fn, params in entries:
        def check(fn=fn, params=params, name=name):
            calls = unaligned_calls(fn, params)
            want = calls[0][1]
            for which, got in calls[1:]:
                if got != "refused TypeError" and got != want:
                    raise AssertionError(f"{name}: unaligned argument {which}: {got!r:.200} (aligned: {want!r:.200})")
            return [got if isinstance(got, str) else "answer" for _, got in calls]
        run.attempt(f"fuzz unaligned {name}", check)
# --- the seam's friction basis system (branch seam2): _core.friction_basis called directly
# on sizes 0-40 and some larger, with random friction rows and normals, random extended flags
# (patterns singular by themselves among them), rhs of the right length and one off, both
# solves, and malformed arguments (F with extreme, repeated, out-of-range or friction-row
# normals, odd lengths, other dtypes and layouts; flags of other lengths): an answer whose
# arrays have the sizes the basis gives, or a ValueError / TypeError; never a read or write
# outside the arrays.

def _friction_rows(n, rng):
    """F (friction rows then normals, int64) and bounds that the friction rule allows."""
    perm = rng.permutation(n)
    nf = int(rng.integers(0, n // 2 + 1))
    fr, rest = perm[:nf], perm[nf:]
    normal = rng.choice(rest, size=nf) if nf and rest.size else np.zeros(0, np.int64)
    lo = np.where(rng.random(n) < 0.7, -rng.random(n), -np.inf)
    hi = np.where(rng.random(n) < 0.7, rng.random(n), np.inf)
    mu = rng.random(nf)
    lo[fr], hi[fr] = -mu, mu
    lo[normal] = 0.0
    return np.concatenate([fr, normal]).astype(np.int64), lo, hi


def friction_seam(run, rng):
    for n, M, q in _seam_problems(rng):
        for t in range(4):
            F, lo, hi = _friction_rows(n, rng)
            N = n + F.size
            zb = (rng.random(N) < (0.2, 0.6, 1.0, 0.0)[t]).astype(np.uint8 if t % 2 else bool)
            zh = (rng.random(N) < 0.5).astype(zb.dtype)
            for length in (int(rng.integers(0, n + 1)), n + 1):
                rhs = rng.normal(size=length)
                run.attempt(f"fuzz seam friction {n} {t} {length}", refused_or(
                    lambda: _friction_sizes(n, _core.friction_basis(M, q, lo, hi, F, zb, zh, 1e-9,
                                                                    rhs, t > 1))))
            run.attempt(f"fuzz seam friction {n} {t} no rhs", refused_or(
                lambda: _friction_sizes(n, _core.friction_basis(M, q, lo, hi, F, zb, zh, 1e-9))))
    M, q = problems.random_psd(6, rng)
    F = np.array([1, 3, 0, 0], dtype=np.int64)
    lo, hi = np.array([0.0, -0.5, 0.0, -0.3, -1.0, -1.0]), np.array([np.inf, 0.5, 1.0, 0.3, 1.0, 2.0])
    zb = np.array([1, 1, 0, 0, 1, 0, 0, 1, 1, 0], dtype=np.uint8)
    zh = np.zeros(10, dtype=np.uint8)
    extremes = [0, 5, 6, -1, I64.max, I64.min, 1 << 31, 1 << 62]
    for t in range(40):
        Fb = F.copy()
        Fb[int(rng.integers(4))] = extremes[int(rng.integers(len(extremes)))] if t % 2 else F[int(rng.integers(4))]
        run.attempt(f"fuzz seam friction F {t}", refused_or(
            lambda: _friction_sizes(6, _core.friction_basis(M, q, lo, hi, Fb, zb, zh, 1e-9, np.ones(3)))))
    for name, g in ODD.items():
        run.attempt(f"fuzz seam friction {name} F", refused_or(lambda: _core.friction_basis(M, q, lo, hi, g(F), zb, zh, 1e-9)))
        run.attempt(f"fuzz seam friction {name} zb", refused_or(lambda: _core.friction_basis(M, q, lo, hi, F, g(zb), zh, 1e-9)))
        run.attempt(f"fuzz seam friction {name} zh", refused_or(lambda: _core.friction_basis(M, q, lo, hi, F, zb, g(zh), 1e-9)))
        run.attempt(f"fuzz seam friction {name} hi", refused_or(lambda: _core.friction_basis(M, q, lo, g(hi), F, zb, zh, 1e-9)))
        run.attempt(f"fuzz seam friction {name} M", refused_or(lambda: _core.friction_basis(g(M), q, lo, hi, F, zb, zh, 1e-9)))
        run.attempt(f"fuzz seam friction {name} rhs", refused_or(
            lambda: _core.friction_basis(M, q, lo, hi, F, zb, zh, 1e-9, g(np.ones(3)), True)))


def _friction_sizes(n, got):
    """friction_basis's answer checked for its sizes (z and w n entries, x at most n)."""
    return _point_sizes("friction_basis", n, got)


def _point_sizes(name, n, got, w_optional=False):
    """A seam entry's answer (code, z, w, residual, x) checked for its sizes: z and w n
    entries (w None allowed with w_optional), x at most n; the answer."""
    code, z, w, residual, x = got
    if code in (0, 1):
        if z.shape != (n,) or (w is None and not w_optional) or (w is not None and w.shape != (n,)):
            raise AssertionError(f"{name}: z, w of shapes {z.shape}, {w is not None and w.shape} for n = {n}")
    elif z is not None or w is not None:
        raise AssertionError(f"{name}: code {code} with a point")
    if x is not None and (x.ndim != 1 or x.size > n):
        raise AssertionError(f"{name}: x of shape {x.shape} for n = {n}")
    return got


# --- the seam's MLCP basis system (branch seam3): _core.mlcp_basis called directly on
# stacked systems of n free rows and m pairs (n + m from 0 to 40 and some larger), with
# random, extreme and repeated redundant / undetermined indices, random v_basic flags
# (blocks not square, singular and empty among them), rhs of the right length and one off,
# both solves, with and without tol, and malformed arguments (other dtypes, layouts and
# lengths, NaN and infinities): an answer whose arrays have the sizes the basis gives (x and
# w N entries, the solve one per block row), or a ValueError / TypeError; never a read or
# write outside the arrays.

def _mlcp_sizes(N, got):
    """mlcp_basis's answer checked for its sizes (x N entries, w N or None, the solve at
    most N)."""
    return _point_sizes("mlcp_basis", N, got, w_optional=True)


def mlcp_seam(run, rng):
    for N, E, e in _seam_problems(rng):
        for t in range(4):
            n = int(rng.integers(0, N + 1))
            drop = lambda: rng.integers(0, n, size=int(rng.integers(0, 3))).astype(np.int64) if n else np.zeros(0, np.int64)
            red, und = drop(), drop()
            vb = (rng.random(N - n) < (0.2, 0.6, 1.0, 0.0)[t]).astype(np.uint8 if t % 2 else bool)
            Es = E
            if t == 1 and N - n >= 1:  # a zero column: singular where v_0 is basic
                Es = E.copy()
                Es[:, n] = 0.0
            k = n - np.unique(red).size + int(np.count_nonzero(vb))
            for length in (k, k + 1):
                rhs = rng.normal(size=max(length, 0))
                for tol in (None, 1e-9):
                    run.attempt(f"fuzz seam mlcp {N} {n} {t} {length - k} {tol}", refused_or(
                        lambda: _mlcp_sizes(N, _core.mlcp_basis(Es, e, n, red, und, vb, tol, rhs, t > 1))))
            run.attempt(f"fuzz seam mlcp {N} {n} {t} no rhs", refused_or(
                lambda: _mlcp_sizes(N, _core.mlcp_basis(Es, e, n, red, und, vb, 1e-9))))
    E, e = problems.random_psd(6, rng)
    red, und = np.array([1], np.int64), np.array([0], np.int64)
    vb = np.array([1, 0, 1, 1], dtype=np.uint8)
    extremes = [0, 1, 2, -1, 6, I64.max, I64.min, 1 << 31, 1 << 62]
    for t in range(30):
        bad = np.array([extremes[int(rng.integers(len(extremes)))]], np.int64)
        run.attempt(f"fuzz seam mlcp index {t}", refused_or(
            lambda: _mlcp_sizes(6, _core.mlcp_basis(E, e, 2, bad if t % 2 else red, und if t % 2 else bad, vb, 1e-9, np.ones(3)))))
    for n in (-1, 7, I64.max, I64.min):
        run.attempt(f"fuzz seam mlcp n {n}", refused_or(lambda: _core.mlcp_basis(E, e, n, red, und, vb)))
    for name, g in ODD.items():
        run.attempt(f"fuzz seam mlcp {name} E", refused_or(lambda: _core.mlcp_basis(g(E), e, 2, red, und, vb, 1e-9)))
        run.attempt(f"fuzz seam mlcp {name} e", refused_or(lambda: _core.mlcp_basis(E, g(e), 2, red, und, vb, 1e-9)))
        run.attempt(f"fuzz seam mlcp {name} redundant", refused_or(lambda: _core.mlcp_basis(E, e, 2, g(red), und, vb, 1e-9)))
        run.attempt(f"fuzz seam mlcp {name} v_basic", refused_or(lambda: _core.mlcp_basis(E, e, 2, red, und, g(vb), 1e-9)))
        run.attempt(f"fuzz seam mlcp {name} rhs", refused_or(
            lambda: _core.mlcp_basis(E, e, 2, red, und, vb, 1e-9, g(np.ones(3)), True)))
    for bad in (np.nan, np.inf, -np.inf):
        for where in ("E", "e", "rhs"):
            E2, e2, r2 = E.copy(), e.copy(), np.ones(3)
            {"E": E2[2], "e": e2, "rhs": r2}[where][1] = bad
            run.attempt(f"fuzz seam mlcp {bad} in {where}", refused_or(
                lambda: _mlcp_sizes(6, _core.mlcp_basis(E2, e2, 2, red, und, vb, 1e-9, r2, where == "rhs"))))


# --- the seam's games basis system (branch gamesbasis): _core.game_basis called directly on
# games of 1-40 actions a side (and some larger), with the kernels' final vertex pairs,
# random ones (supports of unequal sizes, empty and singular blocks among them), labels
# repeated, extreme and out of range, label lists of other lengths, rhs of the right length
# and one off, both solves, with and without tol, NaN and infinite payoffs and malformed
# payoff arrays: an answer whose arrays have the game's sizes (x m, y n, out 3, the solve
# one entry per row of the two blocks), or a ValueError / TypeError; never a read or write
# outside the arrays.

def _game_sizes(m, n, got):
    """game_basis's answer (code, x, y, out, v) checked for its sizes."""
    code, x, y, out, v = got
    if code in (0, 1):
        if x.shape != (m,) or y.shape != (n,) or (out is not None and out.shape != (3,)):
            raise AssertionError(f"game_basis: x, y of shapes {x.shape}, {y.shape} for {m} x {n}")
    elif x is not None or y is not None or out is not None or v is not None:
        raise AssertionError(f"game_basis: code {code} with a point")
    if v is not None and (v.ndim != 1 or v.size > 2 * (min(m, n) + 1)):
        raise AssertionError(f"game_basis: v of shape {v.shape} for {m} x {n}")
    return got


def games_seam(run, rng):
    from lemke import _games
    sizes = [(m, n) for m in (1, 2, 3, 5, 8) for n in (1, 2, 4, 7)]
    sizes += [(int(rng.integers(1, 41)), int(rng.integers(1, 41))) for _ in range(12)] + [(64, 65), (130, 3)]
    for m, n in sizes:
        A = rng.integers(0, 3, (m, n)).astype(float) if (m + n) % 2 else rng.normal(size=(m, n))
        B = rng.integers(0, 3, (m, n)).astype(float) if (m + n) % 3 == 0 else rng.normal(size=(m, n))
        at = _games._layout(m, n)
        pairs = []
        for k in range(0, m + n, max(1, (m + n) // 4)):
            buf = np.empty(at["length"])
            _core.lemke_howson(A, B, k, _games._slack_start(m, n), _games._DEFAULT_PARAMS, buf)
            lab = buf[at["labels"]:].view(np.int64)
            pairs.append((lab[:n].copy(), lab[n : n + m].copy()))
        for _ in range(4):
            p = rng.permutation(m + n)
            pairs.append((p[:n], p[n:]))
        for t, (xb, yb) in enumerate(pairs):
            ks = int(np.count_nonzero(xb < m))
            kt = int(np.count_nonzero(yb >= m))
            for length in (ks + kt + 2, ks + kt + 3):
                rhs = rng.normal(size=length)
                for tol in (None, 1e-9):
                    run.attempt(f"fuzz seam games {m} {n} {t} {length} {tol}", refused_or(
                        lambda: _game_sizes(m, n, _core.game_basis(A, B, xb, yb, tol, rhs, t % 2 == 1))))
    m, n = 3, 4
    A, B = rng.normal(size=(m, n)), rng.normal(size=(m, n))
    xb, yb = np.array([0, 1, 5, 6]), np.array([2, 3, 4])
    extremes = [0, 6, 7, -1, I64.max, I64.min, 1 << 31, 1 << 62]
    for t in range(30):
        xs, ys = xb.copy(), yb.copy()
        (xs if t % 2 else ys)[int(rng.integers(3))] = extremes[int(rng.integers(len(extremes)))]
        run.attempt(f"fuzz seam games labels {t}", refused_or(
            lambda: _game_sizes(m, n, _core.game_basis(A, B, xs, ys, 1e-9, np.ones(7)))))
    for name, g in ODD.items():
        run.attempt(f"fuzz seam games {name} A", refused_or(lambda: _core.game_basis(g(A), B, xb, yb, 1e-9)))
        run.attempt(f"fuzz seam games {name} B", refused_or(lambda: _core.game_basis(A, g(B), xb, yb, 1e-9)))
        run.attempt(f"fuzz seam games {name} x_basic", refused_or(lambda: _core.game_basis(A, B, g(xb), yb, 1e-9)))
        run.attempt(f"fuzz seam games {name} rhs", refused_or(
            lambda: _core.game_basis(A, B, xb, yb, 1e-9, g(np.ones(7)), True)))
    for bad in (np.nan, np.inf, -np.inf):
        for where in ("A", "B", "rhs"):
            A2, B2, r2 = A.copy(), B.copy(), np.ones(7)
            {"A": A2[2], "B": B2[1], "rhs": r2}[where][1] = bad
            run.attempt(f"fuzz seam games {bad} in {where}", refused_or(
                lambda: _game_sizes(m, n, _core.game_basis(A2, B2, xb, yb, 1e-9, r2, where == "rhs"))))
# --- the seam's KKT basis system of a QP (branch polish): _core.kkt_basis called directly on
# QPs of n = 0-40 variables and some more (every kind of bound: free, one-sided, boxed,
# fixed), p equalities and m inequalities, with random, empty and full bases of their pairs
# (singular systems among them), rhs of the right length and one off, both solves, with and
# without tol, and malformed arguments (basic indices out of range, repeated or extreme;
# other dtypes, layouts and lengths; P, G, A of other shapes; NaN and infinities in the data,
# bounds and rhs): an answer whose arrays have the sizes the QP gives (x and zb n, y p, z m,
# stats 4 or None, the solve one per block row), or a ValueError / TypeError; never a read
# or write outside the arrays.

def _kkt_qp(n, p, m, rng):
    """(P, q, G, h, A, b, lb, ub) with every kind of bound, the KKT MLCP's pair count, and
    the block's row count of a basis (a function of the basic pairs)."""
    L = rng.normal(size=(n, max(n // 2, 1)))
    kinds = rng.integers(0, 5, size=n)
    lb = np.where(np.isin(kinds, (1, 3, 4)), -rng.random(n), -np.inf)
    ub = np.where(np.isin(kinds, (2, 3)), rng.random(n), np.inf)
    ub[kinds == 4] = lb[kinds == 4]
    shifted = (kinds > 0) & (kinds < 4)
    nn, nbox = int(np.count_nonzero(shifted)), int(np.count_nonzero(kinds == 3))

    def rows(basic):  # |F| + p + |S|: F the shifted x' basic and not at an upper bound, free x
        v = np.zeros(nn + m + nbox, bool)
        v[basic] = True
        up = np.zeros(n, bool)
        up[kinds == 3] = v[nn + m:]
        x_basic = np.zeros(n, bool)
        x_basic[shifted] = v[:nn]
        free = (kinds == 0) | (x_basic & ~up)
        return int(np.count_nonzero(free)) + p + int(np.count_nonzero(v[nn:nn + m]))
    return (L @ L.T, rng.normal(size=n), rng.normal(size=(m, n)), rng.random(m),
            rng.normal(size=(p, n)), rng.normal(size=p), lb, ub), nn + m + nbox, rows


def _kkt_sizes(n, p, m, got):
    """kkt_basis's answer (code, point, stats, x) checked for its sizes; the answer."""
    code, point, stats, x = got
    if code in (0, 1):
        shapes = tuple(a.shape for a in point)
        if shapes != ((n,), (p,), (m,), (n,)) or (stats is not None and stats.shape != (4,)):
            raise AssertionError(f"kkt_basis: point of shapes {shapes} for {n}, {p}, {m}")
    elif point is not None or stats is not None:
        raise AssertionError(f"kkt_basis: code {code} with a point")
    if x is not None and (x.ndim != 1 or x.size > n + p + m):
        raise AssertionError(f"kkt_basis: x of shape {x.shape}")
    return got


def kkt_seam(run, rng):
    for n in list(range(41)) + [64, 97]:
        for t in range(4):
            p, m = int(rng.integers(0, n // 2 + 2)), int(rng.integers(0, n + 3))
            data, pairs, rows = _kkt_qp(n, p, m, rng)
            basic = np.flatnonzero(rng.random(pairs) < (0.3, 0.7, 1.0, 0.0)[t]).astype(np.int64)
            k = rows(basic)
            for length in (k, k + 1, max(k - 1, 0)):
                rhs = rng.normal(size=length)
                for tol in (None, 1e-9):
                    run.attempt(f"fuzz seam kkt {n} {p} {m} {t} {length} {tol}", refused_or(
                        lambda: _kkt_sizes(n, p, m, _core.kkt_basis(*data, basic, tol, rhs, t > 1))))
            run.attempt(f"fuzz seam kkt {n} {p} {m} {t} no rhs", refused_or(
                lambda: _kkt_sizes(n, p, m, _core.kkt_basis(*data, basic, 1e-9))))
    data, pairs, rows = _kkt_qp(6, 2, 4, rng)
    basic = np.arange(min(pairs, 3), dtype=np.int64)
    k = rows(basic)
    extremes = [0, pairs - 1, pairs, -1, I64.max, I64.min, 1 << 31, 1 << 62]
    for t in range(30):
        bad = np.array([extremes[int(rng.integers(len(extremes)))]] * (1 + t % 2), np.int64)
        run.attempt(f"fuzz seam kkt index {t}", refused_or(
            lambda: _kkt_sizes(6, 2, 4, _core.kkt_basis(*data, bad, 1e-9, np.ones(k)))))
    for name, g in ODD.items():
        for i, what in enumerate(("P", "q", "G", "h", "A", "b", "lb", "ub")):
            args = list(data)
            args[i] = g(args[i])
            run.attempt(f"fuzz seam kkt {name} {what}", refused_or(
                lambda: _core.kkt_basis(*args, basic, 1e-9)))
        run.attempt(f"fuzz seam kkt {name} basic", refused_or(lambda: _core.kkt_basis(*data, g(basic), 1e-9)))
        run.attempt(f"fuzz seam kkt {name} rhs", refused_or(
            lambda: _core.kkt_basis(*data, basic, 1e-9, g(np.ones(k)), True)))
    for bad in (np.nan, np.inf, -np.inf):
        for i, what in enumerate(("P", "q", "G", "h", "A", "b", "lb", "ub", "rhs")):
            args, r2 = [a.copy() for a in data], np.ones(k)
            (args[i] if i < 8 else r2).reshape(-1)[1] = bad
            run.attempt(f"fuzz seam kkt {bad} in {what}", refused_or(
                lambda: _kkt_sizes(6, 2, 4, _core.kkt_basis(*args, basic, 1e-9, r2, what == "rhs"))))
# --- the seam's QP basis system (branch qpbasis): _core.qp_basis called directly on QPs of
# 0-30 variables (equalities, inequalities, bounds, fixed variables), with random, empty,
# full and dependent active sets (two equal rows of G), z given or not, rhs of the right
# length and one off, both solves, and malformed arguments (flags, z and rhs of other dtypes,
# layouts and lengths, P not definite, NaN and infinities): an answer whose arrays have the
# QP's sizes (x and zb n, y p0, z m0, stats 4, the solve n + p + k), or a ValueError /
# TypeError; never a read or write outside the arrays.

def _qp_seam_sizes(n, p0, m0, got):
    """qp_basis's answer checked for its sizes; the answer."""
    code, x, y, z, zb, stats, sol = got
    if code in (0, 1):
        if (x.shape, y.shape, z.shape, zb.shape, stats.shape) != ((n,), (p0,), (m0,), (n,), (4,)):
            raise AssertionError(f"qp_basis: shapes {x.shape} {y.shape} {z.shape} {zb.shape} for {n} {p0} {m0}")
    elif any(a is not None for a in (x, y, z, zb, stats, sol)):
        raise AssertionError(f"qp_basis: code {code} with a point")
    if sol is not None and (sol.ndim != 1 or sol.size < n):
        raise AssertionError(f"qp_basis: sol of shape {sol.shape} for n = {n}")
    return got


def _qp_seam_data(n, rng):
    """A strictly convex QP of n variables (equalities, inequalities, some bounds, one fixed
    variable when n > 2) and its multiplier LCP's row count m and equality count p."""
    B = rng.normal(size=(n, n))
    P = B @ B.T / max(n, 1) + 0.1 * np.eye(n)
    x0 = rng.normal(size=n)
    p0, m0 = int(rng.integers(0, n // 2 + 1)), int(rng.integers(0, 2 * n + 2))
    A, G = rng.normal(size=(p0, n)), rng.normal(size=(m0, n))
    lb = np.where(rng.random(n) < 0.3, x0 - 1.0, -np.inf)
    ub = np.where(rng.random(n) < 0.3, x0 + 1.0, np.inf)
    if n > 2:
        lb[0] = ub[0] = x0[0]
    fixed = lb == ub
    m = m0 + int((~fixed & (ub < np.inf)).sum() + (~fixed & (lb > -np.inf)).sum())
    return (P, rng.normal(size=n), G, G @ x0 + rng.random(m0), A, A @ x0, lb, ub), m, p0 + int(fixed.sum())


def qp_seam(run, rng):
    for n in list(range(31)):
        data, m, p = _qp_seam_data(n, rng)
        p0, m0 = data[4].shape[0], data[2].shape[0]
        for t in range(4):
            active = (rng.random(m) < (0.2, 0.6, 1.0, 0.0)[t]).astype(np.uint8 if t % 2 else bool)
            d = data
            if t == 1 and m0 >= 2:  # dependent rows where both are active
                G2 = data[2].copy()
                G2[1] = G2[0]
                d = data[:2] + (G2,) + data[3:]
                active[:2] = 1
            k = int(np.count_nonzero(active))
            z = rng.random(m) * active if t % 2 else None
            for length in (n + p + k, n + p + k + 1):
                rhs = rng.normal(size=length)
                run.attempt(f"fuzz seam qp {n} {t} {length - n - p - k}", refused_or(
                    lambda: _qp_seam_sizes(n, p0, m0, _core.qp_basis(*d, active, 1e-9, 2, z, rhs, t > 1))))
            run.attempt(f"fuzz seam qp {n} {t} no rhs", refused_or(
                lambda: _qp_seam_sizes(n, p0, m0, _core.qp_basis(*d, active, 1e-9, t))))
    data, m, p = _qp_seam_data(6, rng)
    active = np.zeros(m, dtype=np.uint8)
    active[:2] = 1
    rhs, z = np.ones(6 + p + 2), np.zeros(m)
    for name, g in ODD.items():
        run.attempt(f"fuzz seam qp {name} active", refused_or(lambda: _core.qp_basis(*data, g(active), 1e-9)))
        run.attempt(f"fuzz seam qp {name} z", refused_or(lambda: _core.qp_basis(*data, active, 1e-9, 0, g(z))))
        run.attempt(f"fuzz seam qp {name} rhs", refused_or(
            lambda: _core.qp_basis(*data, active, 1e-9, 2, None, g(rhs), True)))
        run.attempt(f"fuzz seam qp {name} P", refused_or(lambda: _core.qp_basis(g(data[0]), *data[1:], active, 1e-9)))
        run.attempt(f"fuzz seam qp {name} h", refused_or(
            lambda: _core.qp_basis(*data[:3], g(data[3]), *data[4:], active, 1e-9)))
    for steps in (-1, 17, I64.max):
        run.attempt(f"fuzz seam qp steps {steps}", refused_or(lambda: _core.qp_basis(*data, active, 1e-9, steps)))
    run.attempt("fuzz seam qp not definite", refused_or(
        lambda: _qp_seam_sizes(6, data[4].shape[0], data[2].shape[0], _core.qp_basis(-data[0], *data[1:], active, 1e-9))))
    for bad in (np.nan, np.inf, -np.inf):
        for where in (0, 1, 3, 5, "z", "rhs"):
            d, z2, r2 = [a.copy() for a in data], z.copy(), rhs.copy()
            arr = {"z": z2, "rhs": r2}[where] if isinstance(where, str) else d[where]
            if arr.size == 0:
                continue
            arr.reshape(-1)[min(1, arr.size - 1)] = bad
            run.attempt(f"fuzz seam qp {bad} in {where}", refused_or(
                lambda: _qp_seam_sizes(6, d[4].shape[0], d[2].shape[0], _core.qp_basis(
                    *d, active, 1e-9, 2, z2 if where == "z" else None, r2, True))))


# --- the core's reductions as apply/recover pairs (branch reductions, src/lemke/reductions.hpp):
# boxed.friction_recover (FrictionBox's recover and check; on the caller's z: the check),
# boxed.friction_z (FrictionBox's recover alone), qp_box_apply / qp_box_recover
# (BoxQp), qp_multiplier_lcp / qp_multiplier_recover (qp.cpp's MultiplierLcp) called directly
# on sizes 0-20 and some larger, with random data (friction rows and normals, bounds of every
# kind, G, A and fixed variables), random and extreme basic indices and final bases, answers
# of the right length and one off, and malformed arguments (ODD's forms): an answer, None or
# a ValueError / TypeError; never a read or write outside the arrays.

def _reduction_qp(rng, n, m, p):
    B = rng.normal(size=(n, n))
    P = B @ B.T + 0.1 * np.eye(n)
    lb = np.where(rng.random(n) < 0.5, -rng.random(n), -np.inf)
    ub = np.where(rng.random(n) < 0.5, rng.random(n), np.inf)
    fixed = rng.random(n) < 0.1
    ub[fixed] = lb[fixed] = 0.0
    h = rng.random(m) + 0.1
    h[rng.random(m) < 0.2] = np.inf
    return P, rng.normal(size=n), rng.normal(size=(m, n)), h, rng.normal(size=(p, n)), np.zeros(p), lb, ub


def reductions_core(run, rng):
    for n in list(range(0, 21)) + [40, 65]:
        A_ = rng.normal(size=(n, n))
        M, q = A_ @ A_.T + np.eye(n), rng.normal(size=n)
        if n:
            F, lo, hi = _friction_rows(n, rng)
            nf = F.size // 2
            for length in (n + 2 * nf, n + 2 * nf + 1, n):
                zx = np.abs(rng.normal(size=length))
                run.attempt(f"fuzz reductions friction {n} {length}", refused_or(
                    lambda: _core.boxed.friction_recover(M, q, lo, hi, F, zx, 1e-9)))
                for zn in (n, n - 1, n + 1):
                    zo = np.empty(zn)
                    run.attempt(f"fuzz reductions friction z {n} {length} {zn}", refused_or(
                        lambda: (_core.boxed.friction_z(F, zx, zo), zo.tobytes())))
        data = _reduction_qp(rng, n, 0, 0)
        run.attempt(f"fuzz reductions box apply {n}", refused_or(lambda: _core.qp_box_apply(*data)))
        z, w = rng.normal(size=n), rng.normal(size=n)
        final = rng.permutation(n).astype(np.int64)
        for k, m in ((0, 0), (n // 2, n), (n, n), (0, n + 1), (n, n - 1)):
            run.attempt(f"fuzz reductions box recover {n} {k} {m}", refused_or(
                lambda: _core.qp_box_recover(*data, z, w, final, k, m, 1e-9)))
        for mg, p in ((0, 0), (n, n // 3), (2 * n, 1 if n else 0)):
            qd = _reduction_qp(rng, n, mg, p)
            got = run.attempt(f"fuzz reductions multipliers {n} {mg} {p}", refused_or(
                lambda: _core.qp_multiplier_lcp(*qd)))
            mm = got[2].size if isinstance(got, tuple) else 0
            L = _core.qp_layout(n, p, mg)
            for zl, basic in ((mm, np.arange(mm // 2, dtype=np.int64)), (mm + 1, np.zeros(0, np.int64)),
                              (mm, np.array([mm, -1], np.int64)[: 1 + (mm % 2)]),
                              (mm, np.array([I64.max, I64.min], np.int64))):
                zz = np.abs(rng.normal(size=zl))
                out, bo = np.zeros(L[-1]), np.empty(mg + 2 * n, np.int64)
                run.attempt(f"fuzz reductions multipliers recover {n} {mg} {p} {zl - mm} {basic.size}", refused_or(
                    lambda: (_core.qp_multiplier_recover(*qd, zz, basic, 1e-9, out, bo), out.tobytes())))
            run.attempt(f"fuzz reductions multipliers short {n} {mg} {p}", refused_or(
                lambda: _core.qp_multiplier_recover(*qd, np.zeros(mm), np.zeros(0, np.int64), 1e-9,
                                                    np.empty(max(L[4], 1) - 1), np.empty(mg + 2 * n, np.int64))))
    M, q = problems.random_psd(6, rng)
    F, lo, hi = np.array([1, 3, 0, 0], np.int64), np.array([0.0, -0.5, 0.0, -0.3, -1.0, -1.0]), np.array([np.inf, 0.5, 1.0, 0.3, 1.0, 2.0])
    zx = np.ones(10)
    data = _reduction_qp(rng, 6, 0, 0)
    qd = _reduction_qp(rng, 6, 5, 2)
    L = _core.qp_layout(6, 2, 5)
    final = np.arange(6, dtype=np.int64)
    for name, g in ODD.items():
        run.attempt(f"fuzz reductions friction {name} F", refused_or(lambda: _core.boxed.friction_recover(M, q, lo, hi, g(F), zx, 1e-9)))
        run.attempt(f"fuzz reductions friction {name} zx", refused_or(lambda: _core.boxed.friction_recover(M, q, lo, hi, F, g(zx), 1e-9)))
        run.attempt(f"fuzz reductions friction {name} M", refused_or(lambda: _core.boxed.friction_recover(g(M), q, lo, hi, F, zx, 1e-9)))
        run.attempt(f"fuzz reductions friction z {name} F", refused_or(lambda: _core.boxed.friction_z(g(F), zx, np.empty(6))))
        run.attempt(f"fuzz reductions friction z {name} zx", refused_or(lambda: _core.boxed.friction_z(F, g(zx), np.empty(6))))
        run.attempt(f"fuzz reductions friction z {name} z", refused_or(lambda: _core.boxed.friction_z(F, zx, g(np.empty(6)))))
        run.attempt(f"fuzz reductions box {name} P", refused_or(lambda: _core.qp_box_apply(g(data[0]), *data[1:])))
        run.attempt(f"fuzz reductions box {name} lb", refused_or(lambda: _core.qp_box_apply(*data[:6], g(data[6]), data[7])))
        run.attempt(f"fuzz reductions box recover {name} final", refused_or(
            lambda: _core.qp_box_recover(*data, np.zeros(6), np.zeros(6), g(final), 2, 4, 1e-9)))
        run.attempt(f"fuzz reductions box recover {name} w", refused_or(
            lambda: _core.qp_box_recover(*data, np.zeros(6), g(np.zeros(6)), final, 2, 4, 1e-9)))
        run.attempt(f"fuzz reductions multipliers {name} G", refused_or(lambda: _core.qp_multiplier_lcp(*qd[:2], g(qd[2]), *qd[3:])))
        run.attempt(f"fuzz reductions multipliers recover {name} zz", refused_or(
            lambda: _core.qp_multiplier_recover(*qd, g(np.zeros(9)), np.zeros(0, np.int64), 1e-9,
                                                np.empty(L[-1]), np.empty(17, np.int64))))
        run.attempt(f"fuzz reductions multipliers recover {name} basic", refused_or(
            lambda: _core.qp_multiplier_recover(*qd, np.zeros(9), g(np.array([0, 1], np.int64)), 1e-9,
                                                np.empty(L[-1]), np.empty(17, np.int64))))
        run.attempt(f"fuzz reductions multipliers recover {name} out", refused_or(
            lambda: _core.qp_multiplier_recover(*qd, np.zeros(9), np.zeros(0, np.int64), 1e-9,
                                                g(np.empty(L[-1])), np.empty(17, np.int64))))
