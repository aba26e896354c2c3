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


def same_bits(a, b, what):
    for name in ("z", "w"):
        x, y = np.asarray(getattr(a, name)), np.asarray(getattr(b, name))
        if x.shape != y.shape or x.tobytes() != y.tobytes() or a.status != b.status or a.pivots != b.pivots:
            raise AssertionError(f"{what}: {name} differs from a fresh thread's solve")


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


def fuzz(run):
    rng = np.random.default_rng(2026)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # (complex inputs cast, NaN in lists, ...)
        conversions(run, rng)
        batch_helpers(run, rng)
        kept_matrices(run, rng)
        box_islands(run, rng)


# --- the box batch's gathers (branch boxisl): many_field with a per-island answer offset and
# the flat bounds of islands flagged 0 (BLCPManyResult._gather), called directly with random
# and extreme offsets, answers, flags and dtypes: None, a ValueError / TypeError, or the
# spans; never a read outside the arrays.

def box_gathers(run, rng):
    sizes = np.array([3, 0, 4, 2, 6], dtype=np.int64)
    isl = [problems.random_psd(int(n), rng) for n in sizes]
    Mp = np.concatenate([M.ravel() for M, _ in isl])
    qp = np.concatenate([q for _, q in isl])
    lo, hi = np.full(qp.size, -1.0), np.full(qp.size, 2.0)
    fi = np.full(qp.size, -1, dtype=np.int64)
    fi[[4, 5]] = 0  # island 2 (rows 3-6): its rows 1, 2 friction rows of its row 0
    lo[[3, 4, 5]] = 0.0, -2.0, -2.0
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


_fuzz_before_box_gathers = fuzz


def fuzz(run):  # (the blocks above, then the box batch's gathers)
    _fuzz_before_box_gathers(run)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        box_gathers(run, np.random.default_rng(2032))
