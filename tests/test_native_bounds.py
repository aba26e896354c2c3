"""The private native helpers that read Python-supplied arrays (src/python_front.cpp) refuse
inconsistent or malformed arguments instead of reading or writing outside them: offsets whose
differences overflow int64, spans that wrap, unaligned or byte-swapped outputs, ranks other
than 1 and 2.  (tests/sanitized_run.py drives the same calls under ASan and UBSan.)"""
import numpy as np
import pytest

import lemke
from lemke import problems
from lemke import _core

I64_MIN, I64_MAX = np.iinfo(np.int64).min, np.iinfo(np.int64).max

pytestmark = pytest.mark.skipif(not _core.lcp_front_on(), reason="native fronts off")


def _unaligned(a):
    """A copy of a C array whose data starts one byte past an aligned address."""
    raw = np.frombuffer(b"\0" + np.ascontiguousarray(a).tobytes(), dtype=a.dtype, offset=1)
    out = raw.reshape(a.shape)
    assert not out.flags.aligned
    return out


def test_all_f64_refuses_ranks_other_than_1_and_2():
    # a list given rank 0 or 3 made a 0-d (or 3-d from a 2-long shape) array and filled it
    # as if it were 1-D: a write past a one-double array
    for nd in (0, 3, -1, 7):
        assert _core.all_f64(([1.0] * 64,), (nd,)) is None
        assert _core.all_f64((np.arange(5, dtype=np.int32),), (nd,)) is None
        assert _core.as_f64([1.0] * 64, nd) is None
    got = _core.all_f64(([1.0, 2.0], None), (1, 0))
    assert got[0].tolist() == [1.0, 2.0] and got[1] is None


def test_many_field_answer_and_flat_spans_checked():
    """The box batch's gathers (BLCPManyResult): a per-island answer offset added to c, the
    flat bounds for islands flagged 0; offsets that wrap or leave the arrays refused."""
    bufs = np.arange(32.0)
    bo = np.array([0, 16, 32], dtype=np.int64)
    qo = np.array([0, 4, 6], dtype=np.int64)
    ans = np.array([3, 1], dtype=np.int64)
    flat = -np.arange(6.0)
    assert _core.many_field(bufs, bo, qo, 2, 1, ans).tolist() == [12.0, 13.0, 14.0, 15.0, 22.0, 23.0]
    flag = np.array([0, 1], dtype=np.uint8)
    got = _core.many_field(bufs, bo, qo, 2, 1, ans, flag, flat)
    assert got.tolist() == [0.0, -1.0, -2.0, -3.0, 22.0, 23.0]
    flag = np.array([1, 0], dtype=np.uint8)
    assert _core.many_field(bufs, bo, qo, 0, 0, None, flag, flat).tolist() == [0.0, 1.0, 2.0, 3.0, -4.0, -5.0]
    # the answer past its span, negative, wrapping with c or a * n; flat too short
    for a, c, an in ((2, 1, [4, 1]), (0, 0, [-1, 0]), (0, 0, [I64_MAX, 0]), (0, 1, [0, I64_MAX]),
                     (0, 13, [0, 1 << 62]), (1 << 62, 0, [1, 0]), (3, 0, [1, 0])):
        with pytest.raises(ValueError):
            _core.many_field(bufs, bo, qo, a, c, np.array(an, dtype=np.int64))
    with pytest.raises(ValueError):
        _core.many_field(bufs, bo, qo, 0, 0, None, np.array([1, 0], dtype=np.uint8), flat[:5])
    # an empty island reads nothing: its answer is not read
    qe = np.array([0, 4, 4], dtype=np.int64)
    assert _core.many_field(bufs, bo, qe, 0, 0, np.array([0, I64_MAX], dtype=np.int64)).tolist() == [0.0, 1.0, 2.0, 3.0]
    # wrong kinds and lengths: TypeError
    for args in ((np.array([3], dtype=np.int64),), (ans.astype(np.int32),), (None, flag.astype(bool), flat),
                 (None, flag, flat.astype(np.float32)), (None, flag[:1], flat), (None, flag, None)):
        with pytest.raises(TypeError):
            _core.many_field(bufs, bo, qo, 0, 0, *args)


def test_many_bases_refuses_offsets_whose_difference_overflows():
    basics = np.arange(2, dtype=np.int64)
    out_i = np.zeros((1, 5), dtype=np.int64)
    out_i[0, 2] = 1000  # k: read from basics[qoff[0]:] (2 numbers there)
    with pytest.raises(ValueError):
        _core.many_bases(basics, np.array([1, I64_MIN], dtype=np.int64), out_i)
    with pytest.raises(ValueError):
        _core.many_bases(basics, np.array([0, 3], dtype=np.int64), out_i)


def test_many_field_refuses_spans_that_wrap():
    bufs = np.arange(16.0)
    bo = np.array([0, 16], dtype=np.int64)
    qo = np.array([0, 4], dtype=np.int64)
    assert _core.many_field(bufs, bo, qo, 2, 2).tolist() == [10.0, 11.0, 12.0, 13.0]
    # a * n wraps to 0 (2^62 * 4), a * n + c past the span, a negative a or c
    for a, c in ((1 << 62, 0), (1 << 61, 1), (I64_MAX, 0), (0, I64_MAX), (-1, 4), (0, -1), (4, 0)):
        with pytest.raises(ValueError):
            _core.many_field(bufs, bo, qo, a, c)
    for qo2, bo2 in (([1, I64_MIN], [0, 16]), ([0, I64_MAX], [0, 16]), ([0, 4], [I64_MAX, 16]),
                     ([0, 4], [-8, 16]), ([0, 4], [0, 17]), ([I64_MIN, 0], [0, 16])):
        with pytest.raises(ValueError):
            _core.many_field(bufs, np.array(bo2, dtype=np.int64), np.array(qo2, dtype=np.int64), 0, 0)


def test_many_outputs_must_be_aligned_native_arrays():
    rng = np.random.default_rng(3)
    Ms = [problems.random_psd(n, rng)[0] for n in (2, 3)]
    qs = [-np.ones(n) for n in (2, 3)]
    sizes = np.array([2, 3], dtype=np.int64)
    rs = lemke.solve_lcp_many(np.concatenate([M.ravel() for M in Ms]), np.concatenate(qs), sizes=sizes)
    out_i, out_f = rs._out_i, rs._out_f
    assert _core.many_unsettled(out_i, out_f) is not None
    for bad_i, bad_f in ((_unaligned(out_i), out_f), (out_i, _unaligned(out_f)),
                         (out_i.astype(out_i.dtype.newbyteorder()), out_f),
                         (out_i, out_f.astype(out_f.dtype.newbyteorder()))):
        with pytest.raises(TypeError):
            _core.many_unsettled(bad_i, bad_f)
    for bad_i in (_unaligned(out_i), out_i.astype(out_i.dtype.newbyteorder())):
        with pytest.raises(TypeError):
            _core.many_bases(rs._basics, rs._off[0], bad_i)
    z, off, n = _core.many_bases(rs._basics, rs._off[0], out_i)
    assert n.tolist() == [2, 3] and off[-1] == len(z)


def _refcounts_unchanged(calls, objs, rounds=50):
    """Each call made once, then rounds times over: objs' reference counts as after the first
    (answering or refusing with TypeError / ValueError)."""
    import sys

    def each():
        for f in calls:
            try:
                f()
            except (TypeError, ValueError):
                pass
    each()
    before = [sys.getrefcount(o) for o in objs]
    for _ in range(rounds):
        each()
    assert [sys.getrefcount(o) for o in objs] == before


def test_native_paths_keep_no_reference_to_their_inputs():
    """The entries' conversions and the batch helpers, answering or refusing, leave every
    input's reference count as it was (a reference leaked per call would show here)."""
    rng = np.random.default_rng(5)
    M, q = problems.random_psd(4, rng)
    Ml, ql, Mi = M.tolist(), q.tolist(), M.astype(np.int32)
    ws = lemke.solve_lcp(M, q).warm_start
    sizes = np.array([3, 1, 2], dtype=np.int64)
    Mp = np.concatenate([problems.random_psd(int(n), rng)[0].ravel() for n in sizes])
    qp = -np.ones(int(sizes.sum()))
    rs = lemke.solve_lcp_many(Mp, qp, sizes=sizes)
    wrap = np.array([1, I64_MIN], dtype=np.int64)
    calls = [lambda: lemke.solve_lcp(Ml, ql), lambda: lemke.solve_lcp(Mi, q, warm_start=ws),
             lambda: lemke.solve_lcp([[1.0], [1.0, 2.0]], ql[:2]), lambda: lemke.solve_blcp(Ml, ql, -1.0, 2),
             lambda: lemke.solve_blcp(Ml, ql, float("nan"), 2), lambda: lemke.solve_bimatrix(Ml, Mi),
             lambda: lemke.solve_lcp_many([Ml, Mi], [ql, q]), lambda: _core.as_f64(Ml, 2),
             lambda: _core.all_f64((Ml, ql, None), (2, 1, 0)), lambda: _core.all_f64((Ml, "x"), (2, 1)),
             lambda: _core.many_setup(sizes, Mp, qp, -1), lambda: _core.many_unsettled(rs._out_i, rs._out_f),
             lambda: _core.many_field(rs._bufs, rs._off[2], rs._off[0], 2, 2),
             lambda: _core.many_bases(rs._basics, rs._off[0], rs._out_i),
             lambda: _core.many_bases(rs._basics, wrap, rs._out_i[:1]),
             lambda: _core.many_field(rs._bufs, rs._off[2], rs._off[0], 1 << 62, 0)]
    objs = [M, q, Mi, ws, Mp, qp, sizes, rs._bufs, rs._basics, rs._out_i, rs._out_f, rs._off, Ml, ql, wrap, *Ml]
    _refcounts_unchanged(calls, objs)


def _huge(n, nd):
    """A bool view of n rows (n x n for nd 2) over one byte (strides 0): castable, no memory."""
    from numpy.lib.stride_tricks import as_strided
    return as_strided(np.zeros(1, np.bool_), shape=(n,) * nd, strides=(0,) * nd)


def test_packs_decline_islands_whose_lengths_overflow():
    # the sum of n * n over the islands wrapped around: two islands of 3037000499 rows gave a
    # negative length (NumPy's "negative dimensions"), four of 2^31 a length 0 for M's
    # 2^64 numbers (a 64 GiB q allocated, then M written past an empty array where memory
    # allows); now the packs decline (None) before allocating
    for n, k in ((3037000499, 2), (1 << 31, 4), (1 << 31, 1)):
        M, q = _huge(n, 2), _huge(n, 1)
        assert _core.lcp_pack([M] * k, [q] * k) is None
        assert _core.blcp_pack([M] * k, [q] * k, -1.0, 1.0, None) is None
        assert _core.blcp_pack([M] * k, [q] * k, [q] * k, 1, [None] * k) is None


def test_blcp_pack_keeps_no_reference_to_its_inputs():
    """blcp_pack, packing or declining (any argument's form, a findex list or array, a huge
    int, a NaN, a ragged list), leaves every input's reference count as it was."""
    rng = np.random.default_rng(6)
    M, q = problems.random_psd(3, rng)
    Ml, ql, Mi = M.tolist(), q.tolist(), M.astype(np.int32)
    lo, hi = -np.ones(3), np.ones(3)
    lol, fl, fa = lo.tolist(), [-1, 0, -1], np.array([-1, 0, -1], dtype=np.int64)
    big, nan, one = 2 ** 70, float("nan"), 1.5
    flo = [0.0, -one, -1.0]  # (row 1 a friction row of row 0)
    Ms, qs, los, his = [M, Ml, Mi], [q, ql, q], [lo, lol, -1], [hi, 1.0, 2]
    calls = [lambda: _core.blcp_pack(Ms, qs, los, his, None),
             lambda: _core.blcp_pack(Ms, qs, [flo] * 3, one, [fl, fa, None]),
             lambda: _core.blcp_pack([M, M], [q, q], lo, hi, None),
             lambda: _core.blcp_pack(Ms, qs, big, one, None),
             lambda: _core.blcp_pack(Ms, qs, nan, one, None),
             lambda: _core.blcp_pack(Ms, qs, -one, one, [[big, 0, -1], fa, None]),
             lambda: _core.blcp_pack([Ml[:2] + [[1.0]]], [ql], lol, hi, None),
             lambda: _core.blcp_pack(Ms, qs, los, his[:2], None),
             lambda: _core.blcp_pack(Ms, qs, "x", hi, None)]
    objs = [M, q, Ml, ql, Mi, lo, hi, lol, fl, fa, big, nan, one, flo, Ms, qs, los, his, *Ml]
    _refcounts_unchanged(calls, objs)
    assert calls[0]() is not None and calls[1]() is not None and calls[4]() is None
