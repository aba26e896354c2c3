"""Small dense kernels shared by the others.

No fused multiply-add and no reordered sum anywhere (the same rule as the C++ core's
``-ffp-contract=off``): the dot products keep eight running sums in a fixed order
(:func:`row_dot_and_size`), which runs in vector registers without reordering anything and
gives the same bits on every instruction set, here and in the C++ core.  The NaN probes
(sums of 0 * x: 0 or NaN in any order) may reorder.  The maxima of the equilibration and of
the finite check (``sweep_simd``, ``absmax_simd``) take the no-NaN and no-signed-zero flags
instead, and only where their terms can be neither NaN nor -0: a maximum is exact in any
order, so they give the same bits as the plain loops, 2x faster from n of about 50.
"""
import math
import struct

import numpy as np
from llvmlite import ir
from numba import carray, config, njit, types
from numba.extending import intrinsic, overload

from . import inline_kernel, kernel


@kernel
def dot(x, y, k):
    """sum_{j < k} x[j] * y[j], in the fixed order of :func:`row_dot_and_size` (eight
    running sums, no fused multiply-add), which the C++ core (``src/lemke/linalg.hpp``)
    repeats bit for bit."""
    a0 = a1 = a2 = a3 = a4 = a5 = a6 = a7 = 0.0
    j = 0
    while j + 8 <= k:
        a0 += x[j] * y[j]
        a1 += x[j + 1] * y[j + 1]
        a2 += x[j + 2] * y[j + 2]
        a3 += x[j + 3] * y[j + 3]
        a4 += x[j + 4] * y[j + 4]
        a5 += x[j + 5] * y[j + 5]
        a6 += x[j + 6] * y[j + 6]
        a7 += x[j + 7] * y[j + 7]
        j += 8
    while j < k:
        a0 += x[j] * y[j]
        j += 1
    return ((a0 + a1) + (a2 + a3)) + ((a4 + a5) + (a6 + a7))


@kernel
def row_dot_and_size(M, i, y, k):
    """``(sum M[i, j] y[j], sum |M[i, j] y[j]|)`` over j < k: a row of M z and its size, M
    read in place (a view of each row costs two atomic reference count operations).

    **A fixed order**: eight running sums (lane ``j mod 8`` of the first ``8 floor(k / 8)``
    terms, the rest into lane 0), added pairwise at the end, with no fused multiply-add.
    The lanes are independent, so the loop runs in vector registers without reordering
    anything, and the result is the same bits on every instruction set and in the C++
    core (``src/lemke/linalg.hpp``).  (Before, the sums were compiled with the fastmath
    flags ``reassoc`` and ``contract``: their bits depended on the host's vector width.)"""
    a0 = a1 = a2 = a3 = a4 = a5 = a6 = a7 = 0.0
    s0 = s1 = s2 = s3 = s4 = s5 = s6 = s7 = 0.0
    j = 0
    while j + 8 <= k:
        t0 = M[i, j] * y[j]
        t1 = M[i, j + 1] * y[j + 1]
        t2 = M[i, j + 2] * y[j + 2]
        t3 = M[i, j + 3] * y[j + 3]
        t4 = M[i, j + 4] * y[j + 4]
        t5 = M[i, j + 5] * y[j + 5]
        t6 = M[i, j + 6] * y[j + 6]
        t7 = M[i, j + 7] * y[j + 7]
        a0 += t0
        a1 += t1
        a2 += t2
        a3 += t3
        a4 += t4
        a5 += t5
        a6 += t6
        a7 += t7
        s0 += abs(t0)
        s1 += abs(t1)
        s2 += abs(t2)
        s3 += abs(t3)
        s4 += abs(t4)
        s5 += abs(t5)
        s6 += abs(t6)
        s7 += abs(t7)
        j += 8
    while j < k:
        t = M[i, j] * y[j]
        a0 += t
        s0 += abs(t)
        j += 1
    return (((a0 + a1) + (a2 + a3)) + ((a4 + a5) + (a6 + a7)),
            ((s0 + s1) + (s2 + s3)) + ((s4 + s5) + (s6 + s7)))


@njit(cache=True, nogil=True, error_model="numpy", fastmath={"reassoc", "contract"})
def nan_probe(x, k):
    """sum_{j < k} 0 * x[j]: 0 when every x[j] is finite, NaN otherwise (reordering the sum
    changes neither)."""
    acc = 0.0
    for j in range(k):
        acc += 0.0 * x[j]
    return acc


@kernel
def finite_absmax(M):
    """``(finite, max|M|)`` in one pass over the rows of a square matrix, read in place (a
    view of each row cost two atomic reference count operations a row)."""
    n = M.shape[0]
    probe = 0.0
    m_max = 0.0
    for i in range(n):
        probe += nan_probe_row(M, i, n)
        m_max = max(m_max, absmax_row(M, i, n) if n < SIMD_FROM else absmax_simd(M, i, n))
    return probe == 0.0, m_max


@njit(cache=True, nogil=True, error_model="numpy", fastmath={"nnan", "nsz"})
def absmax_simd(M, i, k):
    """:func:`absmax_row` in SIMD registers (``llvm.maxnum`` under the no-NaN and
    no-signed-zero flags: see :func:`sweep_simd`), for a row that has no NaN; on one that
    has, its value is meaningless (finite_absmax's NaN probe says so, and then its callers
    never read max|M|)."""
    m = 0.0
    for j in range(k):
        m = maxnum(m, abs(M[i, j]))
    return m


@njit(cache=True, nogil=True, error_model="numpy", fastmath={"reassoc", "contract"})
def nan_probe_row(M, i, k):
    """:func:`nan_probe` of row i of M (its first k entries)."""
    acc = 0.0
    for j in range(k):
        acc += 0.0 * M[i, j]
    return acc


@kernel
def absmax_row(M, i, k):
    """:func:`absmax` of row i of M (its first k entries), the same operations in the same
    order."""
    m0 = 0.0
    m1 = 0.0
    m2 = 0.0
    m3 = 0.0
    j = 0
    while j + 4 <= k:
        m0 = max(m0, abs(M[i, j]))
        m1 = max(m1, abs(M[i, j + 1]))
        m2 = max(m2, abs(M[i, j + 2]))
        m3 = max(m3, abs(M[i, j + 3]))
        j += 4
    while j < k:
        m0 = max(m0, abs(M[i, j]))
        j += 1
    return max(max(m0, m1), max(m2, m3))


@kernel
def matvec(G, k, x, out):
    """out[:k] = G[:k, :k] x[:k]."""
    for r in range(k):
        out[r] = dot(row_of(G, r), x, k)


@kernel
def absmax(x, k):
    """max_{j < k} |x[j]| (0 for k = 0), with four running maxima (four short dependency
    chains instead of one long one)."""
    m0 = 0.0
    m1 = 0.0
    m2 = 0.0
    m3 = 0.0
    j = 0
    while j + 4 <= k:
        m0 = max(m0, abs(x[j]))
        m1 = max(m1, abs(x[j + 1]))
        m2 = max(m2, abs(x[j + 2]))
        m3 = max(m3, abs(x[j + 3]))
        j += 4
    while j < k:
        m0 = max(m0, abs(x[j]))
        j += 1
    return max(max(m0, m1), max(m2, m3))


@inline_kernel
def copy(dst, src):
    """dst[:] = src for vectors of one length, as a loop: an array assignment makes numba
    compile the formatting of its shape error (a second of the first call's compile)."""
    for i in range(dst.shape[0]):
        dst[i] = src[i]


@inline_kernel
def false_flags(m):
    """m booleans, all False.  The LCP kernels allocate their arrays with np.empty only:
    every other allocating function (np.zeros, np.empty_like, a tuple shape) is one more
    implementation for numba to compile on the first call."""
    flags = np.empty(m, dtype=np.bool_)
    for i in range(m):
        flags[i] = False
    return flags


@inline_kernel
def no_matrix():
    """An empty 2-D array (see :func:`false_flags`)."""
    return np.empty(0).reshape((0, 0))


@kernel
def principal_block(M, idx):
    """The contiguous copy M[idx][:, idx]."""
    k = idx.shape[0]
    out = np.empty((k, k))
    for r in range(k):
        row = M[idx[r]]
        for c in range(k):
            out[r, c] = row[idx[c]]
    return out


@kernel
def axpy(y, a, x):
    """y += a x, over the length of y."""
    for j in range(y.shape[0]):
        y[j] += a * x[j]


def borrow(buf, start, shape, dtype):
    """A C-contiguous array of ``shape`` (an int or a pair) and ``dtype`` over the memory of
    the C-contiguous array ``buf`` from its element ``start`` on (counted in buf's flat
    order: row i of a matrix with n columns starts at i n), that holds no reference to it: in
    a kernel, a slice of an array takes an atomic reference count operation when made and
    one when dropped (each of tableau.lemke's fifteen work views cost two a call, 0.1 us at
    n = 12); this view costs none.  It is valid only while ``buf`` is alive: borrow only
    from an argument of the kernel that uses the view (its caller holds it), never from an
    array the kernel allocates and could drop first.  In plain Python (``NUMBA_DISABLE_JIT``)
    an ordinary view."""
    shape = (int(shape),) if np.ndim(shape) == 0 else tuple(int(s) for s in shape)
    at = start * buf.itemsize
    nbytes = int(np.prod(shape)) * np.dtype(dtype).itemsize
    return buf.reshape(-1).view(np.uint8)[at : at + nbytes].view(dtype).reshape(shape)


@intrinsic
def _address(typingctx, buf, start):
    """The address of element ``start`` of the C-contiguous ``buf`` (flat order), as a void
    pointer (for :func:`borrow`)."""
    if (not isinstance(buf, types.Array) or buf.layout != "C"
            or not isinstance(start, types.Integer)):
        return None

    def codegen(context, builder, sig, args):
        a = context.make_array(sig.args[0])(context, builder, args[0])
        start = context.cast(builder, args[1], sig.args[1], types.intp)
        return builder.bitcast(builder.gep(a.data, [start]), context.get_value_type(types.voidptr))
    return types.voidptr(buf, start), codegen


@overload(borrow, jit_options={"nogil": True, "error_model": "numpy"})
def _borrow(buf, start, shape, dtype):
    def impl(buf, start, shape, dtype):
        return carray(_address(buf, start), shape, dtype)
    return impl


@kernel
def row_of(M, i):
    """Row i of the C-contiguous float64 matrix M, borrowed (:func:`borrow`): what ``M[i]``
    gives, without its two atomic reference count operations, for loops that take a row at
    a time.  Valid while M is referenced (a kernel's argument, or a local the code uses
    afterwards)."""
    return borrow(M, i * M.shape[1], M.shape[1], np.float64)


if config.DISABLE_JIT:  # plain Python (debugging): the same bits through struct
    def maxnum(a, b):
        """max(a, b) of two numbers that are not NaN."""
        return a if a > b else b

    def float_bits(x):
        """The IEEE 754 bits of the float64 x, as an int64."""
        return struct.unpack("<q", struct.pack("<d", x))[0]

    def bits_float(b):
        """The float64 whose IEEE 754 bits are the int64 b."""
        return struct.unpack("<d", struct.pack("<q", b))[0]
else:
    @intrinsic
    def maxnum(typingctx, a, b):
        """max(a, b) of two float64 that are not NaN, as LLVM's ``llvm.maxnum``: in a function
        compiled with the no-NaN and no-signed-zero flags, a loop of them vectorizes (numba's
        own ``max`` is a compare and select that LLVM keeps scalar in a reduction)."""
        if a != types.float64 or b != types.float64:
            return None

        def codegen(context, builder, sig, args):
            d = ir.DoubleType()
            fn = builder.module.declare_intrinsic("llvm.maxnum", [d], ir.FunctionType(d, [d, d]))
            return builder.call(fn, args)
        return types.float64(types.float64, types.float64), codegen

    @intrinsic
    def float_bits(typingctx, x):
        """The IEEE 754 bits of the float64 x, as an int64 (one register move)."""
        if x != types.float64:
            return None
        return types.int64(types.float64), lambda context, builder, sig, args: builder.bitcast(
            args[0], ir.IntType(64))

    @intrinsic
    def bits_float(typingctx, b):
        """The float64 whose IEEE 754 bits are the int64 b."""
        if b != types.int64:
            return None
        return types.float64(types.int64), lambda context, builder, sig, args: builder.bitcast(
            args[0], ir.DoubleType())


if config.DISABLE_JIT:
    def fma(a, b, c):
        """a b + c rounded once (plain Python: exactly, through fractions)."""
        from fractions import Fraction
        if not all(math.isfinite(v) for v in (a, b, c)):
            return a * b + c
        return float(Fraction(a) * Fraction(b) + Fraction(c))
else:
    @intrinsic
    def fma(typingctx, a, b, c):
        """a b + c rounded once, as LLVM's ``llvm.fma`` (one instruction where the CPU has
        fused multiply-add, a correctly rounded library call where it has not)."""
        if a != types.float64 or b != types.float64 or c != types.float64:
            return None

        def codegen(context, builder, sig, args):
            d = ir.DoubleType()
            fn = builder.module.declare_intrinsic("llvm.fma", [d], ir.FunctionType(d, [d, d, d]))
            return builder.call(fn, args)
        return types.float64(types.float64, types.float64, types.float64), codegen


@kernel
def two_product(a, b):
    """``(p, e)`` with p = fl(a b) and a b = p + e exactly (e by one fused multiply-add;
    exact unless a b over- or underflows)."""
    p = a * b
    return p, fma(a, b, -p)


@kernel
def two_sum(a, b):
    """``(s, e)`` with s = fl(a + b) and a + b = s + e exactly (Knuth)."""
    s = a + b
    z = s - a
    return s, (a - (s - z)) + (b - z)


@kernel
def acc2(hi, lo, a, b):
    """``(hi, lo) += a b`` in double-double: the sum ``hi + lo`` carries the error terms of
    every product and addition (Ogita, Rump and Oishi's Dot2, one term)."""
    p, e = two_product(a, b)
    s, f = two_sum(hi, p)
    return s, lo + (e + f)


SQRT2_FRACTION = 0x6A09E667F3BCD  # the 52 fraction bits of 1.4142135623730951 = 2 * 0.7071067811865476


@kernel
def pow2_scale(x):
    """The power of two nearest to 1 / x (x > 0), or 1 for x = 0 or x not finite: an exact
    scale factor (multiplying by it adds no rounding).

    With x = m 2^e, 0.5 <= m < 1 (``math.frexp``), it is 2^(1 - e) when m < 1/sqrt(2),
    else 2^(-e).  For a normal x whose answer is normal too, that is read off x's bits
    and written as the answer's (m < 1/sqrt(2) is a comparison of fraction bits, as 2m and
    sqrt(2) have the same exponent): ``frexp`` and ``ldexp`` are library calls, and they
    were 40 % of the equilibration at n = 24 (two per row and column per sweep).  The
    other cases (subnormal x, or x >= 2^1022) take the calls; both give the same bits."""
    if not (x > 0.0 and x < np.inf):
        return 1.0
    b = float_bits(x)
    biased = b >> 52  # x > 0: no sign bit; x = (1.f / 2) 2^e with e = biased - 1022
    if biased == 0 or biased >= 2045:
        m, e = math.frexp(x)  # x = m 2**e, 0.5 <= m < 1
        return math.ldexp(1.0, 1 - e) if m < 0.7071067811865476 else math.ldexp(1.0, -e)
    # 2^(1 - e) has the biased exponent 2046 - biased, 2^(-e) one less
    out = 2046 - biased if (b & 0xFFFFFFFFFFFFF) < SQRT2_FRACTION else 2045 - biased
    return bits_float(out << 52)


@kernel
def pow2_rsqrt(x):
    """``pow2_scale(math.sqrt(x))`` without the square root, read off x's exponent: with
    x = 1.f 2^E (normal), sqrt(x) lies in [2^(k - 1/2), 2^(k + 1/2)) exactly when E is
    2k - 1 or 2k, so the power of two nearest to 1 / sqrt(x) is 2^-k, k = floor((E + 1) /
    2); at the boundaries (x a power of two, or the float below one) the rounded sqrt
    falls on the same side (a test compares both on 7 million values, every power of two
    and its neighbours among them).  Subnormal x takes pow2_scale(sqrt(x)) itself.  The
    equilibration takes one per row and column each sweep: measured, with this and the
    balance test fused into the same pass, it takes 0.82x its time at n = 12, 0.85x at 24,
    0.88x at 48 (the same scales, bit for bit, on 3,000 random and extreme matrices)."""
    if not (x > 0.0 and x < np.inf):
        return 1.0
    biased = float_bits(x) >> 52
    if biased == 0:
        return pow2_scale(math.sqrt(x))
    return bits_float((1023 - ((biased - 1022) >> 1)) << 52)


#: The smallest positive normal float64.
DBL_MIN = 2.2250738585072014e-308


@kernel
def pow2_rsqrt_all(x, k):
    """``(fast, balanced)``: balanced says whether every x[i] (i < k) that is not zero lies in
    [0.5, 2]; when every x[i] is zero or a positive normal float (fast), x[i] is replaced
    by :func:`pow2_rsqrt` of it (1 for zero), by the same exponent arithmetic without a
    branch, so the two passes run in vector registers.  Otherwise x is left as it is, and
    the caller takes pow2_rsqrt one by one.  Measured in :func:`equilibrate` with its
    vectorized scale update: 0.73x its time at n = 12, 0.64-0.76x at 24, 0.72x at 48
    (the same scales, bit for bit, on 4,000 random, sparse, subnormal and extreme
    matrices)."""
    fast = True
    balanced = True
    for i in range(k):
        a = x[i]
        fast &= (a == 0.0) | ((a >= DBL_MIN) & (a < np.inf))
        balanced &= not ((a > 0.0) & ((a < 0.5) | (a > 2.0)))
    if not fast:
        return False, balanced
    for i in range(k):
        a = x[i]
        v = bits_float((1023 - (((float_bits(a) >> 52) - 1022) >> 1)) << 52)
        x[i] = 1.0 if a == 0.0 else v
    return True, balanced


EQUILIBRATE_SWEEPS = 16
#: From this n on, equilibrate's sweeps take :func:`sweep_simd`; below, :func:`sweep`
#: (the vector loop is not entered below 4 entries; at n = 3-6 the plain loop was about
#: 5 % faster).
SIMD_FROM = 8


@kernel
def equilibrate(M, q, R, C):
    """Row and column scales of the LCP (M, q), powers of two, such that every non-zero row
    and column of [diag(R) M diag(C) | c diag(R) q] has its largest entry within a factor 2
    of 1, for some constant c: Ruiz's iteration on M with q as one more column (divide each
    row and each column by the square root of its largest entry, rounded to a power of
    two), at most EQUILIBRATE_SWEEPS passes, stopping at the first pass that finds the
    matrix balanced (one pass for a matrix that already is).

    The scales are exact, and Lemke's path does not depend on them in exact arithmetic
    (every ratio and every lexicographic comparison is invariant under positive diagonal
    scaling); they make the kernels' relative tolerances and the acceptance test's rounding
    floor mean the same in every row and column, whatever scaling the caller's rows and
    columns came in.  q takes part so that rows are balanced as whole equations: in
    diag(1e12, 1e-12) z + (-1, -1) both rows keep their -1 (the columns take the scale)."""
    n = M.shape[0]
    R[:] = 1.0
    C[:] = 1.0
    cq = pow2_scale(absmax(q, n))  # q's own size never unbalances anything
    work = np.empty(2 * n)  # one allocation (it costs about as much as a sweep at small n)
    rmax, cmax = work[:n], work[n:]
    extreme = False
    for _ in range(EQUILIBRATE_SWEEPS):
        if n >= SIMD_FROM and not extreme:
            qmax = sweep_simd(M, q, R, C, cq, rmax, cmax)
        else:
            qmax = sweep(M, q, R, C, cq, rmax, cmax)
        # Whether the matrix is balanced, and each maximum replaced by its scale (applied
        # only when it is not balanced): in vector registers (pow2_rsqrt_all) unless a
        # maximum is subnormal or infinite.
        balanced = not (qmax > 0.0 and (qmax < 0.5 or qmax > 2.0))
        fast, all_balanced = pow2_rsqrt_all(work, 2 * n)
        if fast:
            balanced &= all_balanced
        else:
            for i in range(n):
                a = rmax[i]
                b = cmax[i]
                if (a > 0.0 and (a < 0.5 or a > 2.0)) or (b > 0.0 and (b < 0.5 or b > 2.0)):
                    balanced = False
                rmax[i] = pow2_rsqrt(a)
                cmax[i] = pow2_rsqrt(b)
        if balanced:
            break
        finite = True  # (a flag, not a branch per entry: the loop vectorizes)
        for i in range(n):
            r = R[i] * rmax[i]
            c = C[i] * cmax[i]
            R[i] = r
            C[i] = c
            finite &= (r > 0.0) & (r < np.inf) & (c > 0.0) & (c < np.inf)
        if not finite:
            extreme = True  # a scale over- or underflowed: 0 * inf = NaN can come
        cq *= pow2_rsqrt(qmax)


@kernel
def sweep(M, q, R, C, cq, rmax, cmax):
    """One pass of :func:`equilibrate`: the largest entry of each row (q's included, times
    cq) and column of diag(R) M diag(C) into rmax and cmax; returns q's largest."""
    n = M.shape[0]
    cmax[:] = 0.0
    qmax = 0.0
    for i in range(n):
        r = R[i]
        rm = 0.0  # a local running maximum, branch-free; M read in place (no row view)
        for j in range(n):
            a = abs(M[i, j]) * r * C[j]
            rm = max(rm, a)
            cmax[j] = max(cmax[j], a)
        a = abs(q[i]) * r * cq
        rmax[i] = max(rm, a)
        qmax = max(qmax, a)
    return qmax


@njit(cache=True, nogil=True, error_model="numpy", fastmath={"nnan", "nsz"})
def sweep_simd(M, q, R, C, cq, rmax, cmax):
    """:func:`sweep` in SIMD registers.  Its terms are >= +0 (absolute values times powers
    of two) and not NaN where M is finite, which every caller of equilibrate has checked,
    and R and C are positive and finite (equilibrate takes :func:`sweep` once a scale has
    over- or underflowed): so the no-NaN and no-signed-zero flags change no result, and
    with them and ``llvm.maxnum`` (:func:`maxnum`) the loop vectorizes (the maxima are
    exact in any order).  Measured against :func:`sweep`: 0.5x the equilibration of a
    contact step at n = 212 and of a dense n = 300, 0.62x at n = 150, 0.88x at n = 48."""
    n = M.shape[0]
    cmax[:] = 0.0
    qmax = 0.0
    for i in range(n):
        r = R[i]
        rm = 0.0
        for j in range(n):
            a = abs(M[i, j]) * r * C[j]
            rm = maxnum(rm, a)
            cmax[j] = maxnum(cmax[j], a)
        a = abs(q[i]) * r * cq
        rmax[i] = max(rm, a)
        qmax = max(qmax, a)
    return qmax


@kernel
def scaled_system(M, q, d, R, C):
    """``(A, qs, d_scale)``: A = [R M C | R d / d_scale] (n x (n + 1)) and qs = R q, the
    equilibrated system that every Lemke kernel works in (R, C from :func:`equilibrate`;
    d_scale = max |R d|, so that the artificial column has largest entry 1).  z' = z / C
    and z0' = z0 d_scale are its unknowns."""
    n = q.shape[0]
    work = np.empty(n * (n + 2))  # one allocation for both
    A = work[: n * (n + 1)].reshape((n, n + 1))
    qs = work[n * (n + 1) :]
    d_scale = scaled_into(M, q, d, R, C, A, qs)
    return A, qs, d_scale


@inline_kernel
def scaled_into(M, q, d, R, C, A, qs):
    """:func:`scaled_system` into the caller's A (n x (n + 1)) and qs (n); returns d_scale."""
    n = q.shape[0]
    d_scale = 0.0
    for i in range(n):
        d_scale = max(d_scale, abs(d[i]) * R[i])
    inv_d = 1.0 / d_scale
    for i in range(n):
        r = R[i]
        for j in range(n):
            A[i, j] = (M[i, j] * r) * C[j]
        A[i, n] = (d[i] * r) * inv_d
        qs[i] = q[i] * r
    return d_scale



@njit(cache=True, nogil=True, error_model="numpy", fastmath=False)
def _row_update(y, f, x, lo, k):
    """y[lo:k] -= f x[lo:k].  No reduction, so it vectorizes without reordering anything
    (no fused multiply-add: the module docstring).  The loop runs over
    slices from 0 (indexing from ``lo`` keeps numba's negative-index wraparound in the
    loop, which stops vectorization: 3x slower)."""
    ys = y[lo:k]
    xs = x[lo:k]
    for c in range(ys.shape[0]):
        ys[c] -= f * xs[c]


@njit(cache=True, nogil=True, error_model="numpy", fastmath=False)
def _update_next_row(A, j, k, f):
    """A[j + 1, c] -= f A[j, c] for c = j + 1 .. k - 1: :func:`_row_update` of row j + 1 by
    row j (the same operations, so the same bits) without the two row views and their
    reference counts."""
    lo = np.uint64(j + 1)
    hi = np.uint64(k)
    for c in range(lo, hi):
        A[j + 1, c] -= f * A[j, c]


@njit(cache=True, nogil=True, error_model="numpy", fastmath=False)
def _update_below_pair(A, j, k):
    """Rows j + 2 .. k - 1 of A, each r whose multipliers f = A[r, j] and g = A[r, j + 1]
    (in place already) are not both zero: A[r, c] = (A[r, c] - f A[j, c]) - g A[j + 1, c]
    for c = j + 2 .. k - 1.  All rows in one
    call: a row view and a call per row (the earlier form, with the same bits) cost an
    atomic reference count increment and decrement each, more than a short row's update.
    The column index is unsigned, so numba does not wrap it around (a signed one from
    j + 2 would keep the loop scalar); the rows written lie after the two read, so LLVM's
    overlap check passes.  Measured on whole LUs of SPD blocks: 0.72x the time at k = 28,
    0.51x at 100."""
    lo = np.uint64(j + 2)
    hi = np.uint64(k)
    for r in range(j + 2, k):
        f = A[r, j]
        g = A[r, j + 1]
        if f != 0.0 or g != 0.0:
            for c in range(lo, hi):
                A[r, c] = (A[r, c] - f * A[j, c]) - g * A[j + 1, c]


@njit(cache=True, nogil=True, error_model="numpy", fastmath=False)
def _update_all_pair(G, fg, j, k, S):
    """Every row r of G[:k, :k] but j and j + 1, with f = fg[r] and g = fg[k + r] not both
    zero: G[r, c] = (G[r, c] - f G[j, c]) - g G[j + 1, c] for c < k
    (:func:`_update_below_pair` for the Gauss-Jordan passes of :func:`invert_in_place`).
    The pivot rows are read from a copy in S (2k floats): read from G, which the rows
    written surround, LLVM's overlap check (hoisted out of the row loop, over all of G)
    would fail and keep every row's loop scalar.  Measured: 0.60x the inversion's time at
    k = 28 and 60, 0.75x at 150."""
    for c in range(k):
        S[c] = G[j, c]
        S[k + c] = G[j + 1, c]
    for r in range(k):
        if r != j and r != j + 1:
            f = fg[r]
            g = fg[k + r]
            if f != 0.0 or g != 0.0:
                for c in range(k):
                    G[r, c] = (G[r, c] - f * S[c]) - g * S[k + c]


@kernel
def _nonzero_columns(x, u, lo, k, idx):
    """The columns c in lo..k-1 where x[c] or u[c] is not zero, into idx; their count, or -1
    when they are a quarter of the range or more (then a dense pass costs less)."""
    m = 0
    for c in range(lo, k):
        if x[c] != 0.0 or u[c] != 0.0:
            idx[m] = c
            m += 1
    return m if 4 * m < k - lo else -1


@kernel
def _row_update2_at(y, f, x, g, u, idx, m):
    """y[c] = (y[c] - f x[c]) - g u[c] for c in idx[:m] (:func:`_update_below_pair`'s
    update of one row, on a list of columns)."""
    for t in range(m):
        c = idx[t]
        y[c] = (y[c] - f * x[c]) - g * u[c]


@njit(cache=True, nogil=True, error_model="numpy", fastmath={"reassoc", "contract"})
def _block_probe(G, k):
    """0 when every entry of G[:k, :k] is finite, NaN otherwise."""
    probe = 0.0
    for r in range(k):
        probe += nan_probe(G[r], k)
    return probe


@kernel
def _swap_rows(G, i, j, k):
    if i != j:
        for c in range(k):
            t = G[i, c]
            G[i, c] = G[j, c]
            G[j, c] = t


@kernel
def _pivot_row(G, j, k, col_shift):
    """The row r in j..k-1 with the largest |G[r, j] - G[r, j - 1] * col_shift| (with
    col_shift = 0: the largest |G[r, j]|), or -1 when that is 0 or not a number."""
    p = -1
    best = 0.0
    for r in range(j, k):
        a = abs(G[r, j] - G[r, j - 1] * col_shift) if col_shift != 0.0 else abs(G[r, j])
        if a > best:
            best = a
            p = r
        elif a != a:  # NaN
            return -1
    return p


@kernel
def invert_in_place(G, k):
    """Replace G[:k, :k] by its inverse, by Gauss-Jordan elimination with partial pivoting
    on one thread: no BLAS or LAPACK call, so no thread pool is started and nothing
    competes for cores with the caller's threads.  About k^3 multiply-adds in passes over
    contiguous rows, two pivots per pass (half the memory traffic of one at a time).

    Returns False when the block is not finite, a pivot is exactly zero (the block is
    singular in floating point), or the inverse is not finite; G[:k, :k] then holds
    garbage.  Never raises.  G may be larger than k x k (only the leading block is read
    and written)."""
    if k < 0 or k > G.shape[0] or k > G.shape[1]:
        return False
    if _block_probe(G, k) != 0.0:
        return False
    piv = np.empty(k, dtype=np.int64)
    work = np.empty(4 * k)
    fg, S = work[: 2 * k], work[2 * k :]  # a pass's multipliers, and its pivot rows
    j = np.int64(0)  # not a literal 0: see kernels/__init__.py
    start = np.int64(0)
    while j < k:
        # Pivot j: the largest entry of column j (up to date) in rows j..k-1.
        p = _pivot_row(G, j, k, 0.0)
        if p < 0:
            return False
        piv[j] = p
        _swap_rows(G, j, p, k)
        rowj = G[j]
        d = 1.0 / rowj[j]
        rowj[j] = 1.0
        for c in range(k):
            rowj[c] *= d
        if j + 1 == k:  # the last pivot alone
            for r in range(j):
                rowr = G[r]
                f = rowr[j]
                if f != 0.0:
                    rowr[j] = 0.0
                    _row_update(rowr, f, rowj, start, k)
            break
        # Pivot j + 1 from column j + 1 as pivot j will leave it: G[r, j + 1] - G[r, j] h.
        h = rowj[j + 1]
        p = _pivot_row(G, j + 1, k, h)
        if p < 0:
            return False
        piv[j + 1] = p
        _swap_rows(G, j + 1, p, k)
        row1 = G[j + 1]  # eliminate pivot j from it, then scale it
        f1 = row1[j]
        row1[j] = 0.0
        _row_update(row1, f1, rowj, start, k)
        d1 = 1.0 / row1[j + 1]
        row1[j + 1] = 1.0
        for c in range(k):
            row1[c] *= d1
        # Every other row: both eliminations in one pass (the multipliers f and g first,
        # into fg).  Column j of the result is -f rowj[j] - g row1[j], column j + 1 is
        # -g row1[j + 1] (the in-place trick).
        for r in range(k):
            if r != j and r != j + 1:
                f = G[r, j]
                fg[r] = f
                fg[k + r] = G[r, j + 1] - f * h
        _update_all_pair(G, fg, j, k, S)
        for r in range(k):
            if r != j and r != j + 1:
                f = fg[r]
                g = fg[k + r]
                if f != 0.0 or g != 0.0:
                    G[r, j] = -f * rowj[j] - g * row1[j]
                    G[r, j + 1] = -g * row1[j + 1]
        # Row j last (the pass above read it as pivot j left it).
        rowj[j + 1] = 0.0
        _row_update(rowj, h, row1, start, k)
        j += 2
    # The rows were swapped on the way: swap the inverse's columns back, in reverse order.
    for j in range(k - 1, -1, -1):
        p = piv[j]
        if p != j:
            for r in range(k):
                t = G[r, j]
                G[r, j] = G[r, p]
                G[r, p] = t
    return _block_probe(G, k) == 0.0


@kernel
def solve(H, b):
    """``(ok, x)`` with H x = b for a square H, by Gaussian elimination with partial
    pivoting on one thread (no BLAS or LAPACK call), two pivots per pass over the rows
    below them; H and b are not modified.  ok is False when H or b is not finite, a pivot
    is exactly zero (H is singular in floating point), the shapes do not match or x is not
    finite.  Never raises."""
    k = b.shape[0]
    A, y, x = solve_work(np.empty(k * (k + 2)), k)
    if H.shape[0] != k or H.shape[1] != k:
        return False, x
    for r in range(k):
        for c in range(k):
            A[r, c] = H[r, c]
        y[r] = b[r]
    return _eliminate(A, y, x, k, None), x


@kernel
def solve_principal(M, idx, b):
    """:func:`solve` on the principal block ``M[idx][:, idx]``, read straight from M."""
    k = b.shape[0]
    A, y, x = solve_work(np.empty(k * (k + 2)), k)
    if idx.shape[0] != k:
        return False, x
    for r in range(k):
        y[r] = b[r]
    return solve_gathered(M, idx, A, y, x, k), x


@inline_kernel
def solve_gathered(M, idx, A, y, x, k):
    """The solve of :func:`solve_principal` with the right-hand side already in y (the work
    arrays of :func:`solve_work`): the block ``M[idx[:k]][:, idx[:k]]`` gathered into A,
    then eliminated; x gets the solution.  Returns ok."""
    for r in range(k):  # (M indexed directly: a row view per row costs refcounting)
        ir = idx[r]
        for c in range(k):
            A[r, c] = M[ir, idx[c]]
    return _eliminate(A, y, x, k, None)


@inline_kernel
def solve_work(work, k):
    """The work arrays of :func:`solve` carved from ``work`` (at least k (k + 2) floats, one
    allocation): A (k x k), y, and x = 0."""
    x = work[k * (k + 1) : k * (k + 2)]
    x[:] = 0.0
    return work[: k * k].reshape((k, k)), work[k * k : k * (k + 1)], x


@inline_kernel
def _eliminate(A, y, x, k, piv):
    """Solve A x = y in place (A and y are overwritten; x starts at 0): the elimination of
    :func:`solve`.  Returns ok.  A is left holding its LU factors (the multipliers below
    the diagonal, U on and above it, rows in pivot order); ``piv`` is None or 2k int64s:
    its first k get the row swapped into place at each step, so that :func:`_lu_solve` can
    solve again with the same factors (:func:`refined_solve`), and its second half is
    scratch.  Given piv, the updates of the rows below a pair of pivots read only the pivot rows'
    non-zero columns when they are under a quarter (:func:`_nonzero_columns`): a KKT
    system's factors stay a few per cent non-zero.  The same sums on the entries that
    change (no fused multiply-add on either path)."""
    if _block_probe(A, k) != 0.0 or nan_probe(y, k) != 0.0:
        return False
    j = np.int64(0)
    while j < k:
        p = _pivot_row(A, j, k, 0.0)
        if p < 0:
            return False
        if piv is not None:
            piv[j] = p
        _swap_rows(A, j, p, k)
        t = y[j]
        y[j] = y[p]
        y[p] = t
        inv = 1.0 / A[j, j]
        if j + 1 == k:
            break
        for r in range(j + 1, k):  # the multipliers of pivot j, kept in column j
            A[r, j] *= inv
        # Pivot j + 1 from column j + 1 as pivot j leaves it: A[r, j + 1] - l_r A[j, j + 1].
        h = A[j, j + 1]
        p = _pivot_row(A, j + 1, k, h)
        if p < 0:
            return False
        if piv is not None:
            piv[j + 1] = p
        _swap_rows(A, j + 1, p, k)
        t = y[j + 1]
        y[j + 1] = y[p]
        y[p] = t
        l1 = A[j + 1, j]
        _update_next_row(A, j, k, l1)
        y[j + 1] -= l1 * y[j]
        inv1 = 1.0 / A[j + 1, j + 1]
        m = -1  # the pivot rows' non-zero columns (refined_solve only): -1, not listed
        if piv is not None:
            m = _nonzero_columns(A[j], A[j + 1], j + 2, k, piv[k:])
        for r in range(j + 2, k):  # both eliminations in one pass over each row below
            f = A[r, j]
            g = (A[r, j + 1] - f * h) * inv1
            A[r, j + 1] = g  # the multiplier of pivot j + 1, kept in column j + 1
            if f != 0.0 or g != 0.0:
                if m >= 0:
                    _row_update2_at(A[r], f, A[j], g, A[j + 1], piv[k:], m)
                y[r] = (y[r] - f * y[j]) - g * y[j + 1]
        if m < 0:  # the rows' updates, dense
            _update_below_pair(A, j, k)
        j += 2
    return _back_substitute(A, y, x, k)


@inline_kernel
def _back_substitute(A, y, x, k):
    """x = U^-1 y with U the upper triangle of A[:k, :k].  Returns whether x is finite."""
    for r in range(k - 1, -1, -1):  # (A indexed directly: no row view per row)
        acc = y[r]
        for c in range(r + 1, k):
            acc -= A[r, c] * x[c]
        x[r] = acc / A[r, r]
    return nan_probe(x, k) == 0.0


@inline_kernel
def _lu_solve(A, piv, y, x, k):
    """Solve again with the factors :func:`_eliminate` left in A and piv (y is overwritten):
    each row of y gets the same operations in the same order as there, so the first
    solve's x comes out bit for bit.  Returns whether x is finite."""
    for j in range(k):  # the row swaps first: the multipliers moved with their rows
        p = piv[j]
        t = y[j]
        y[j] = y[p]
        y[p] = t
    j = np.int64(0)
    while j + 1 < k:
        y[j + 1] -= A[j + 1, j] * y[j]
        for r in range(j + 2, k):
            f = A[r, j]
            g = A[r, j + 1]
            if f != 0.0 or g != 0.0:
                y[r] = (y[r] - f * y[j]) - g * y[j + 1]
        j += 2
    return _back_substitute(A, y, x, k)


@kernel
def refined_solve(K, rhs, steps, x, lo):
    """x with K x = rhs: one LU factorization with partial pivoting (the elimination of
    :func:`solve`, on one thread: no LAPACK, no thread pool), then ``steps`` steps of
    iterative refinement whose residual ``rhs - K x`` is summed in double-double
    (:func:`residual2`) and solved with the same factors.  On a degenerate basis a
    variable that is zero then comes out zero to the last digits instead of at cond(K)
    eps.

    K is k x (k + j), j >= 0: the last j unknowns are given, in ``x[k:]`` (the bounds a
    QP's active variables are held at), and only ``x[:k]`` is solved for, with the factors
    of K's leading k x k block; their columns take part in every residual, so nothing of
    the given values is rounded away before the sums.

    x is carried in double-double through the refinement, ``x[:k] + lo``: it converges to
    the exact solution, and x[:k] to its rounding, whatever the rounding of the factors;
    ``lo`` (k floats) gets the low parts, for a caller that goes on from the exact solution
    (the bound multipliers of ``_qp._polished``).

    Returns ok: False (x[:k] garbage) when K, rhs or the given entries are not finite, the
    shapes do not match, a pivot is exactly zero (the block is singular in floating point)
    or x is not finite.  K and rhs are not modified.  Never raises."""
    k = rhs.shape[0]
    j = K.shape[1] - k
    if (K.shape[0] != k or j < 0 or x.shape[0] != k + j or lo.shape[0] != k
            or nan_probe(x[k:], j) != 0.0):
        return False
    A, y, d = solve_work(np.empty(k * (k + 2)), k)
    piv = np.empty(2 * k, dtype=np.int64)  # the pivots, then _eliminate's scratch
    for r in range(k):
        for c in range(k):
            A[r, c] = K[r, c]
        y[r] = rhs[r]
    if j > 0:
        residual2(K[:, k:], -x[k:], rhs, y)  # rhs - K_given x_given
    xs = x[:k]
    xs[:] = 0.0
    if not _eliminate(A, y, xs, k, piv):
        return False
    lo[:] = 0.0
    for _ in range(steps):
        for r in range(k):  # rhs - K (x + lo), in double-double (zeros add nothing)
            s = rhs[r]
            err = 0.0
            for c in range(k + j):
                a = K[r, c]
                if a != 0.0:
                    s, err = acc2(s, err, -a, x[c])
                    if c < k:
                        err -= a * lo[c]
            y[r] = s + err
        if not _lu_solve(A, piv, y, d, k):
            return False
        for r in range(k):  # (xs, lo) += d
            t, e = two_sum(xs[r], d[r])
            e += lo[r]
            xs[r] = t + e
            lo[r] = e - (xs[r] - t)
    return nan_probe(xs, k) == 0.0


@kernel
def residual2(E, x, e, y):
    """y = E x + e, each row summed in double-double (:func:`acc2`) and then rounded: the
    value at x to within a unit in its last place plus ``k eps^2 |E| |x|`` -- no rounding of
    the evaluation that grows with |x| beyond that.  (For the MLCP check, ``_certify``.)"""
    k = x.shape[0]
    for r in range(E.shape[0]):
        s = e[r]
        err = 0.0
        for c in range(k):
            a = E[r, c]
            if a != 0.0:  # a zero adds nothing (a KKT system is mostly zeros)
                s, err = acc2(s, err, a, x[c])
        y[r] = s + err
