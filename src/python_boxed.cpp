// lemke._core.boxed: the box LCP engine (src/lemke/boxed.*) for the Python front
// (lemke/_blcp.py and _blcp_many.py). Sizes are checked before the GIL is released: where
// the engine checks a size itself its code comes back (NOT_FINITE, BAD_FINDEX), every other
// mismatch (one the engine would read past) raises ValueError. Output arrays are
// never converted (a float32 or non-contiguous buffer raises instead of being copied).
#include <algorithm>
#include <vector>

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/tuple.h>

#include "lemke/basis.hpp"
#include "lemke/boxed.hpp"
#include "lemke/boxed_batch.hpp"
#include "lemke/reductions.hpp"
#include "python_arrays.hpp"

namespace nb = nanobind;
using namespace nb::literals;

namespace {

using lemke::idx;
using CMatrix = Aligned<nb::ndarray<const double, nb::ndim<2>, nb::c_contig, nb::device::cpu>>;
using CVector = Aligned<nb::ndarray<const double, nb::ndim<1>, nb::c_contig, nb::device::cpu>>;
using OutVector = Aligned<nb::ndarray<double, nb::ndim<1>, nb::c_contig, nb::device::cpu>>;
using CIndices = Aligned<nb::ndarray<const std::int64_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>>;
using OutIndices = Aligned<nb::ndarray<std::int64_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>>;
using CFlags = nb::ndarray<nb::ro, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using NumpyVector = nb::ndarray<nb::numpy, double, nb::ndim<1>>;
using NumpyMatrix = nb::ndarray<nb::numpy, double, nb::ndim<2>>;

const std::uint8_t* flag_data(const CFlags& a, const char* fn, const char* name) {
    if (a.dtype() != nb::dtype<bool>() && a.dtype() != nb::dtype<std::uint8_t>())
        throw nb::value_error((std::string(fn) + ": " + name + " must be bool or uint8").c_str());
    return static_cast<const std::uint8_t*>(a.data());
}

// Python's truth of a flag argument (True, False, numpy.bool_, 0, 1).
bool truth(nb::handle h) {
    int t = PyObject_IsTrue(h.ptr());
    if (t < 0) nb::raise_python_error();
    return t != 0;
}

// The problem's arrays: M n x n, q, lo, hi of length n (ValueError otherwise).
idx problem_size(const CMatrix& M, const CVector& q, const CVector& lo, const CVector& hi,
                 const char* fn) {
    idx n = static_cast<idx>(q.shape(0));
    if (static_cast<idx>(M.shape(0)) != n || static_cast<idx>(M.shape(1)) != n ||
        static_cast<idx>(lo.shape(0)) != n || static_cast<idx>(hi.shape(0)) != n)
        throw nb::value_error((std::string(fn) + ": M must be n x n and q, lo, hi of length n").c_str());
    return n;
}

lemke::Mat<const double> mat(const CMatrix& M, idx n) {
    return lemke::Mat<const double>(M.data(), n, n);
}

using SolveTuple = std::tuple<int, std::int64_t, double, bool, double, std::int64_t, std::int64_t>;

SolveTuple solve(CMatrix M, CVector q, CVector lo, CVector hi, CFlags warm, int cov_mode,
                 std::int64_t max_pivots, double pivot_tol, double tie_tol, double tol,
                 OutVector buf, OutIndices final) {
    idx n = problem_size(M, q, lo, hi, "solve");
    const std::uint8_t* wf = flag_data(warm, "solve", "warm");
    if (static_cast<idx>(warm.shape(0)) < 2 * n ||
        static_cast<idx>(buf.shape(0)) < lemke::boxed::BoxLayout{n}.length() ||
        static_cast<idx>(final.shape(0)) < n)
        return {lemke::boxed::NOT_FINITE, 0, 0.0, false, lemke::INF, 0, 0};  // (the kernel's)
    lemke::boxed::SolveResult r;
    {
        nb::gil_scoped_release release;
        r = lemke::boxed::solve(mat(M, n), q.data(), lo.data(), hi.data(), wf, cov_mode,
                                max_pivots, pivot_tol, tie_tol, tol, buf.data(), final.data());
    }
    return {r.code, r.pivots, r.z0, r.ok, r.residual, r.k, r.m};
}

std::tuple<bool, double> box_check(CMatrix M, CVector q, CVector lo, CVector hi, CVector z,
                                   double tol, OutVector w, CVector R, std::int64_t n_round) {
    idx n = problem_size(M, q, lo, hi, "box_check");
    if (static_cast<idx>(z.shape(0)) != n || static_cast<idx>(w.shape(0)) != n ||
        static_cast<idx>(R.shape(0)) != n)
        throw nb::value_error("box_check: z, w and R must be of length n");
    double residual;
    bool ok;
    {
        nb::gil_scoped_release release;
        ok = lemke::boxed::box_check(mat(M, n), q.data(), lo.data(), hi.data(), z.data(), tol,
                                     w.data(), R.data(), n_round, residual);
    }
    return {ok, residual};
}

void check_scales(CMatrix M, CVector q, CVector lo, CVector hi, OutVector R, OutVector C) {
    idx n = problem_size(M, q, lo, hi, "check_scales");
    if (static_cast<idx>(R.shape(0)) != n || static_cast<idx>(C.shape(0)) != n)
        throw nb::value_error("check_scales: R and C must be of length n");
    nb::gil_scoped_release release;
    lemke::boxed::check_scales(mat(M, n), q.data(), lo.data(), hi.data(), R.data(), C.data());
}

bool basis_point(CMatrix M, CVector q, CVector lo, CVector hi, CFlags zb, CFlags zh,
                 nb::handle warm_rule, OutVector z) {
    idx n = problem_size(M, q, lo, hi, "basis_point");
    const std::uint8_t* b = flag_data(zb, "basis_point", "zb");
    const std::uint8_t* h = flag_data(zh, "basis_point", "zh");
    if (static_cast<idx>(zb.shape(0)) < n || static_cast<idx>(zh.shape(0)) < n ||
        static_cast<idx>(z.shape(0)) != n)
        throw nb::value_error("basis_point: zb and zh must hold n flags, z be of length n");
    bool rule = truth(warm_rule);
    nb::gil_scoped_release release;
    return lemke::boxed::basis_point(mat(M, n), q.data(), lo.data(), hi.data(), b, h, rule,
                                     z.data());
}

bool friction_point(CMatrix M, CVector q, CVector lo, CVector hi, CIndices F, CFlags zb,
                    CFlags zh, OutVector z) {
    idx n = problem_size(M, q, lo, hi, "friction_point");
    idx nf = static_cast<idx>(F.shape(0)) / 2;
    const std::uint8_t* b = flag_data(zb, "friction_point", "zb");
    const std::uint8_t* h = flag_data(zh, "friction_point", "zh");
    const idx* f = F.data();
    // (F as extend writes it: a friction row given twice made more coupled rows than the
    // work holds)
    std::vector<std::uint8_t> seen(static_cast<std::size_t>(n));
    bool rows_ok = static_cast<idx>(F.shape(0)) == 2 * nf &&
                   lemke::FrictionBasis::rows_valid(f, nf, n, seen.data());
    if (!rows_ok || static_cast<idx>(zb.shape(0)) < n + 2 * nf ||
        static_cast<idx>(zh.shape(0)) < n + 2 * nf || static_cast<idx>(z.shape(0)) != n)
        throw nb::value_error("friction_point: F must hold nf distinct friction rows of M, then nf normal "
                              "rows that are not friction rows, zb and zh n + 2 nf "
                              "flags, z be of length n");
    nb::gil_scoped_release release;
    return lemke::boxed::friction_point(mat(M, n), q.data(), lo.data(), hi.data(), f, nf, b, h,
                                        z.data());
}

bool is_ray(CMatrix M, CVector q, CVector lo, CVector hi, CVector d, CVector z, double z0,
            CVector ray, double tol) {
    idx n = problem_size(M, q, lo, hi, "is_ray");
    if (static_cast<idx>(ray.shape(0)) != n + 1 || static_cast<idx>(d.shape(0)) != n ||
        static_cast<idx>(z.shape(0)) != n)
        return false;  // (the kernel's)
    nb::gil_scoped_release release;
    return lemke::boxed::is_ray(mat(M, n), q.data(), lo.data(), hi.data(), d.data(), z.data(),
                                z0, ray.data(), tol);
}

// boxed.extend: the views (Mx, qx, lox, hix) of `work` (they keep it alive).
std::tuple<NumpyMatrix, NumpyVector, NumpyVector, NumpyVector> extend(
    CMatrix M, CVector q, CVector lo, CVector hi, CIndices findex, std::int64_t nf,
    nb::object work_obj, OutIndices F) {
    idx n = problem_size(M, q, lo, hi, "extend");
    OutVector work;
    if (!nb::try_cast(work_obj, work, false))
        throw nb::value_error("extend: work must be a writable, C-contiguous float64 vector");
    idx N = n + 2 * nf;
    idx count = 0;
    bool ok = nf >= 0 && static_cast<idx>(findex.shape(0)) == n;
    for (idx i = 0; ok && i < n; ++i) {
        idx f = findex.data()[i];
        if (f >= 0) {
            ++count;
            ok = f < n;
        }
    }
    if (!ok || count != nf || static_cast<idx>(work.shape(0)) < N * N + 3 * N ||
        static_cast<idx>(F.shape(0)) < 2 * nf)
        throw nb::value_error("extend: findex must be of length n with entries below n, nf of "
                              "them >= 0, work of length >= N N + 3 N (N = n + 2 nf), F >= 2 nf");
    {
        nb::gil_scoped_release release;
        lemke::boxed::extend(mat(M, n), q.data(), lo.data(), hi.data(), findex.data(), nf,
                             work.data(), F.data());
    }
    double* p = work.data();
    std::size_t Ns = static_cast<std::size_t>(N);
    std::size_t rest = work.shape(0) - Ns * Ns - 2 * Ns;  // hix: the rest of work
    return {NumpyMatrix(p, {Ns, Ns}, work_obj), NumpyVector(p + Ns * Ns, {Ns}, work_obj),
            NumpyVector(p + Ns * Ns + Ns, {Ns}, work_obj),
            NumpyVector(p + Ns * Ns + 2 * Ns, {rest}, work_obj)};
}

// reductions.hpp's FrictionBox::check (recover, then the caller's check with the coupled
// bounds): the extended answer zx (N = n + 2 nf entries) mapped back with F as extend writes
// it, or the caller's z already (n entries, nf > 0: the check alone, FrictionBasis::check's
// verdict); (passed, residual, z, w, lo, hi, R, C: the caller's answer, the bounds in force
// and check_scales' scales, as the check leaves them, in one new buffer).
std::tuple<bool, double, NumpyVector, NumpyVector, NumpyVector, NumpyVector, NumpyVector,
           NumpyVector>
friction_recover(CMatrix M, CVector q, CVector lo, CVector hi, CIndices F, CVector zx,
                 double tol) {
    idx n = problem_size(M, q, lo, hi, "friction_recover");
    idx nf = static_cast<idx>(F.shape(0)) / 2;
    idx len = static_cast<idx>(zx.shape(0));
    std::vector<std::uint8_t> seen(static_cast<std::size_t>(n));
    if (static_cast<idx>(F.shape(0)) != 2 * nf ||
        !lemke::FrictionBasis::rows_valid(F.data(), nf, n, seen.data()) ||
        (len != n + 2 * nf && len != n))
        throw nb::value_error("friction_recover: F must hold nf distinct friction rows of M, then "
                              "nf normal rows that are not friction rows, zx n + 2 nf or n "
                              "entries");
    lemke::boxed::FrontLayout L{n, nf, true};
    // The check's buffer is the front's (FrontLayout: the run's area first, unused here), kept
    // per thread; the six fields returned (z, w, lo, hi, R, C: 6 n doubles from L.z(), in that
    // order) are copied out into a buffer of their own.
    static thread_local std::vector<double> scratch;
    if (scratch.size() < static_cast<std::size_t>(L.length()))
        scratch.resize(static_cast<std::size_t>(L.length()));
    double* full = scratch.data();
    std::size_t six = 6 * static_cast<std::size_t>(n);
    double* buf = new double[six + 1];
    nb::capsule owner(buf, [](void* p) noexcept { delete[] static_cast<double*>(p); });
    double residual = 0.0;
    bool passed;
    {
        nb::gil_scoped_release release;
        std::fill(full + L.z(), full + L.z() + six, 0.0);
        lemke::reductions::FrictionBox red{mat(M, n), q.data(), lo.data(), hi.data(), nullptr, nf};
        if (len == red.N()) {
            passed = red.check(F.data(), zx.data(), tol, full, residual);
        } else {
            double* z = full + L.z();
            for (idx i = 0; i < n; ++i) z[i] = zx.data()[i];
            passed = lemke::boxed::coupled_check(red.M, red.q, red.lo, red.hi, F.data(), nf,
                                                 red.N(), tol, full, residual);
        }
        std::copy(full + L.z(), full + L.z() + six, buf);
    }
    std::size_t un = static_cast<std::size_t>(n);
    return {passed,
            residual,
            NumpyVector(buf, {un}, owner),
            NumpyVector(buf + un, {un}, owner),
            NumpyVector(buf + 2 * un, {un}, owner),
            NumpyVector(buf + 3 * un, {un}, owner),
            NumpyVector(buf + 4 * un, {un}, owner),
            NumpyVector(buf + 5 * un, {un}, owner)};
}

// reductions.hpp's FrictionBox::recover alone: the caller's z (n) from the extended answer
// zx (N = n + 2 nf; F as extend writes it, 2 nf entries), unclipped, into z.
void friction_z(CIndices F, CVector zx, OutVector z) {
    idx n = static_cast<idx>(z.shape(0));
    idx nf = static_cast<idx>(F.shape(0)) / 2;
    std::vector<std::uint8_t> seen(static_cast<std::size_t>(n));
    if (static_cast<idx>(F.shape(0)) != 2 * nf ||
        !lemke::FrictionBasis::rows_valid(F.data(), nf, n, seen.data()) ||
        static_cast<idx>(zx.shape(0)) != n + 2 * nf)
        throw nb::value_error("friction_z: F must hold nf distinct friction rows of z, then nf "
                              "normal rows that are not friction rows, zx n + 2 nf entries");
    lemke::reductions::FrictionBox red{lemke::Mat<const double>(nullptr, n, n), nullptr, nullptr,
                                       nullptr, nullptr, nf};
    red.recover(F.data(), zx.data(), z.data());
}

std::tuple<int, double> front(int phase, CMatrix M, CVector q, CVector lo, CVector hi,
                              CIndices findex, CFlags warm, nb::handle has_warm, double tol,
                              OutVector buf, OutIndices ints, OutVector work) {
    idx n = problem_size(M, q, lo, hi, "front");
    const std::uint8_t* wf = flag_data(warm, "front", "warm");
    idx fl = static_cast<idx>(findex.shape(0));
    if (fl != 0 && fl != n) throw nb::value_error("front: findex must be of length n or 0");
    bool hw = truth(has_warm);
    double residual;
    int code;
    {
        nb::gil_scoped_release release;
        code = lemke::boxed::front(phase, mat(M, n), q.data(), lo.data(), hi.data(),
                                   findex.data(), fl, wf, static_cast<idx>(warm.shape(0)), hw,
                                   tol, buf.data(), static_cast<idx>(buf.shape(0)), ints.data(),
                                   static_cast<idx>(ints.shape(0)), work.data(),
                                   static_cast<idx>(work.shape(0)), residual);
    }
    return {code, residual};
}

using Flat = Aligned<nb::ndarray<const double, nb::ndim<1>, nb::c_contig, nb::device::cpu>>;
using Bytes = nb::ndarray<const std::uint8_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using States = nb::ndarray<const std::int8_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using StatesOut = nb::ndarray<std::int8_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using IntOut2 = Aligned<nb::ndarray<std::int64_t, nb::ndim<2>, nb::c_contig, nb::device::cpu>>;

// lemke::boxed::batch (solve_blcp_many): islands lo..hi-1 laid end to end. Every offset is
// checked against its array before the GIL is released (ValueError otherwise).
void batch(Flat Ms, CIndices mstart, Flat qs, Flat los, Flat his, CIndices qoff,
           CIndices findex, Bytes fflag, States state, Bytes wflag, std::int64_t lo,
           std::int64_t hi, CIndices max_pivots, double pivot_tol, double tie_tol, double tol,
           OutVector bufs, CIndices buff, OutIndices ints, CIndices ioff, StatesOut state_out,
           IntOut2 out_i, OutVector out_f) {
    idx B = static_cast<idx>(qoff.shape(0)) - 1;
    auto len = [](const auto& a) { return static_cast<idx>(a.shape(0)); };
    if (lo < 0 || hi < lo || hi > B || len(mstart) < hi || len(fflag) < hi || len(wflag) < hi ||
        len(buff) < hi + 1 || len(ioff) < hi + 1 || len(max_pivots) < hi ||
        static_cast<idx>(out_i.shape(0)) < hi || out_i.shape(1) != 7 || len(out_f) < hi)
        throw nb::value_error("batch: offsets and outputs do not cover the problems");
    const idx *qo = qoff.data(), *ms = mstart.data(), *bf = buff.data(), *io = ioff.data();
    const idx* fi = findex.data();
    const std::uint8_t *ff = fflag.data(), *wf = wflag.data();
    const std::int8_t* st = state.data();
    // the rows' arrays' common length, M's, the friction index's, the buffers' (read once)
    const idx rows = std::min({len(qs), len(los), len(his), len(state), len(state_out)});
    const idx m_len = len(Ms), f_len = len(findex), b_len = len(bufs), i_len = len(ints);
    for (idx b = lo; b < hi; ++b) {
        idx o = qo[b], e = qo[b + 1];
        bool fr = ff[b] != 0;
        // (every difference taken once its operands are ordered, n * n once n <= m_len / n:
        // no overflow)
        bool ok = o >= 0 && e >= o && e <= rows;
        idx n = ok ? e - o : 0;
        ok = ok && ms[b] >= 0 && (n == 0 || n <= m_len / n) && ms[b] <= m_len - n * n &&
             (!fr || e <= f_len);
        // its friction rows counted and, warm, its row states judged, in one pass over it
        idx nf = 0;
        bool bad = false;
        if (ok && fr) {
            if (wf[b] != 0) {
                for (idx i = o; i < e; ++i) {
                    int c = st[i];
                    bool f = fi[i] >= 0;
                    nf += f;
                    bad |= (c < 0) | (c > 29) | ((c >= lemke::boxed::FRICTION_STATE) != f);
                }
            } else {
                for (idx i = o; i < e; ++i) nf += fi[i] >= 0;
            }
        } else if (ok && wf[b] != 0) {
            for (idx i = o; i < e; ++i) {
                int c = st[i];
                bad |= (c < 0) | (c >= lemke::boxed::FRICTION_STATE);
            }
        }
        lemke::boxed::FrontLayout FL{n, nf, fr && n > 0};
        ok = ok && bf[b] >= 0 && bf[b + 1] >= bf[b] && bf[b + 1] <= b_len &&
             bf[b + 1] - bf[b] == FL.length() && io[b] >= 0 && io[b + 1] >= io[b] &&
             io[b + 1] <= i_len && io[b + 1] - io[b] == FL.ints_length();
        if (!ok) throw nb::value_error("batch: a problem's offsets lie outside its arrays");
        if (bad) throw nb::value_error("batch: a warm row state does not fit its row");
    }
    nb::gil_scoped_release release;
    lemke::boxed::batch(Ms.data(), ms, qs.data(), los.data(), his.data(), qo, fi,
                        fflag.data(), state.data(), wflag.data(), lo, hi, max_pivots.data(),
                        pivot_tol, tie_tol, tol, bufs.data(), bf, ints.data(), io,
                        state_out.data(), out_i.data(), out_f.data());
}

// The layout of the one-call buffers (boxed.hpp FrontLayout, BoxLayout), for the Python
// fronts: {name: (start, stop)} of each field and each length, for n rows with nf friction
// rows (friction: a friction index is given). Run fields (the run's BoxLayout(N)): z, w,
// covering, row_scale, col_scale, ray; the caller's (friction only): caller_z, caller_w,
// caller_lo, caller_hi, caller_row_scale, caller_col_scale; ints: final, friction_rows,
// normal_rows; work (nf > 0): work_M, work_q, work_lo, work_hi; and N, run_length, length,
// ints_length, work_length, answer (where the answer's z starts).
nb::dict layout(std::int64_t n, std::int64_t nf, bool friction) {
    if (n < 0 || nf < 0 || nf > n) throw nb::value_error("layout: 0 <= nf <= n");
    lemke::boxed::FrontLayout F{n, nf, friction && n > 0};
    lemke::boxed::BoxLayout R = F.run();
    idx N = F.N();
    nb::dict d;
    auto span = [&](const char* name, idx at, idx len) { d[name] = nb::make_tuple(at, at + len); };
    span("z", R.z(), N);
    span("w", R.w(), N);
    span("covering", R.covering(), N);
    span("row_scale", R.row_scale(), N);
    span("col_scale", R.col_scale(), N);
    span("ray", R.ray(), N + 1);
    if (F.friction) {
        span("caller_z", F.z(), n);
        span("caller_w", F.w(), n);
        span("caller_lo", F.lo(), n);
        span("caller_hi", F.hi(), n);
        span("caller_row_scale", F.row_scale(), n);
        span("caller_col_scale", F.col_scale(), n);
    }
    span("final", F.final(), N);
    span("friction_rows", F.friction_rows(), nf);
    span("normal_rows", F.normal_rows(), nf);
    if (nf > 0) {
        span("work_M", F.work_M(), N * N);
        span("work_q", F.work_q(), N);
        span("work_lo", F.work_lo(), N);
        span("work_hi", F.work_hi(), N);
    }
    d["N"] = N;
    d["run_length"] = R.length();
    d["length"] = F.length();
    d["ints_length"] = F.ints_length();
    d["work_length"] = F.work_length();
    d["answer"] = F.answer();
    return d;
}

// solve_blcp_many's islands laid out (FrontLayout), in one pass: island b has the rows
// qoff[b]..qoff[b + 1] of findex (read when fflag[b]) and of the warm row states (when
// wflag[b]); into buff and ioff (B + 1 each, from 0) its buffers' offsets, laid end to end,
// into answer (B) where its answer's z sits in its buffer, into limits (B) its pivot cap
// (max_pivots, or the default 100 (N + 1) when max_pivots < 0). Returns the first warm row
// whose state is not of its row's kind (a friction row's code for an ordinary row or the
// other way round), -1 when none is (the front then says which, in its words).
std::int64_t islands(CIndices qoff, CIndices findex, Bytes fflag, States state, Bytes wflag,
                     std::int64_t max_pivots, OutIndices buff, OutIndices ioff,
                     OutIndices answer, OutIndices limits) {
    idx B = static_cast<idx>(qoff.shape(0)) - 1;
    auto len = [](const auto& a) { return static_cast<idx>(a.shape(0)); };
    if (B < 0 || len(fflag) != B || len(wflag) != B || len(buff) != B + 1 ||
        len(ioff) != B + 1 || len(answer) != B || len(limits) != B)
        throw nb::value_error("islands: B flags and outputs, B + 1 offsets");
    const idx *qo = qoff.data(), *fi = findex.data();
    const std::int8_t* st = state.data();
    idx *bf = buff.data(), *io = ioff.data(), *an = answer.data(), *lim = limits.data();
    bf[0] = io[0] = 0;
    idx bad = -1;
    const idx f_len = len(findex), s_len = len(state);
    // (no array holds more rows: the offsets summed below stay far from overflow)
    constexpr idx ROWS_MAX = idx(1) << 40;
    for (idx b = 0; b < B; ++b) {
        idx o = qo[b], e = qo[b + 1];
        bool fr = fflag.data()[b] != 0, warm = wflag.data()[b] != 0;
        if (o < 0 || e < o || e > ROWS_MAX || (fr && e > f_len) || (warm && e > s_len))
            throw nb::value_error("islands: an island's rows lie outside its arrays");
        idx n = e - o;
        // its friction rows counted and, warm (until a row is found), the first row whose
        // state is of the other kind, in one pass over it
        idx nf = 0;
        if (fr && warm && bad < 0) {
            for (idx i = o; i < e; ++i) {
                bool f = fi[i] >= 0;
                nf += f;
                if (bad < 0 && (st[i] >= lemke::boxed::FRICTION_STATE) != f) bad = i;
            }
        } else if (fr) {
            for (idx i = o; i < e; ++i) nf += fi[i] >= 0;
        } else if (warm && bad < 0) {
            for (idx i = o; i < e; ++i)
                if (st[i] >= lemke::boxed::FRICTION_STATE) {
                    bad = i;
                    break;
                }
        }
        lemke::boxed::FrontLayout F{n, nf, fr && n > 0};
        bf[b + 1] = bf[b] + F.length();
        io[b + 1] = io[b] + F.ints_length();
        an[b] = F.answer();
        lim[b] = max_pivots < 0 ? 100 * (F.N() + 1) : max_pivots;  // Options.pivot_limit(N)
    }
    return bad;
}

}  // namespace

void bind_boxed(nb::module_& m) {
    nb::module_ b = m.def_submodule(
        "boxed", "The box LCP engine (src/lemke/boxed.*): solve, front, extend and the "
                 "checks, for lemke._blcp.");
    b.def("solve", &solve, "M"_a, "q"_a, "lo"_a, "hi"_a, "warm"_a, "cov_mode"_a, "max_pivots"_a,
          "pivot_tol"_a, "tie_tol"_a, "tol"_a, "buf"_a.noconvert(), "final"_a.noconvert());
    b.def("box_check", &box_check, "M"_a, "q"_a, "lo"_a, "hi"_a, "z"_a, "tol"_a,
          "w"_a.noconvert(), "R"_a, "n_round"_a = 0);
    b.def("check_scales", &check_scales, "M"_a, "q"_a, "lo"_a, "hi"_a, "R"_a.noconvert(),
          "C"_a.noconvert());
    b.def("basis_point", &basis_point, "M"_a, "q"_a, "lo"_a, "hi"_a, "zb"_a, "zh"_a,
          "warm_rule"_a, "z"_a.noconvert());
    b.def("friction_point", &friction_point, "M"_a, "q"_a, "lo"_a, "hi"_a, "F"_a, "zb"_a, "zh"_a,
          "z"_a.noconvert());
    b.def("is_ray", &is_ray, "M"_a, "q"_a, "lo"_a, "hi"_a, "d"_a, "z"_a, "z0"_a, "ray"_a,
          "tol"_a);
    b.def("extend", &extend, "M"_a, "q"_a, "lo"_a, "hi"_a, "findex"_a, "nf"_a, "work"_a,
          "F"_a.noconvert());
    b.def("friction_recover", &friction_recover, "M"_a, "q"_a, "lo"_a, "hi"_a, "F"_a, "zx"_a,
          "tol"_a);
    b.def("friction_z", &friction_z, "F"_a, "zx"_a, "z"_a.noconvert());
    b.def("front", &front, "phase"_a, "M"_a, "q"_a, "lo"_a, "hi"_a, "findex"_a, "warm"_a,
          "has_warm"_a, "tol"_a, "buf"_a.noconvert(), "ints"_a.noconvert(),
          "work"_a.noconvert());
    b.def("batch", &batch, "Ms"_a, "mstart"_a, "qs"_a, "los"_a, "his"_a, "qoff"_a, "findex"_a,
          "fflag"_a, "state"_a, "wflag"_a, "lo"_a, "hi"_a, "max_pivots"_a, "pivot_tol"_a,
          "tie_tol"_a, "tol"_a, "bufs"_a.noconvert(), "buff"_a, "ints"_a.noconvert(), "ioff"_a,
          "state_out"_a.noconvert(), "out_i"_a.noconvert(), "out_f"_a.noconvert());
    b.def("layout", &layout, "n"_a, "nf"_a = 0, "friction"_a = false);
    b.def("islands", &islands, "qoff"_a, "findex"_a, "fflag"_a, "state"_a, "wflag"_a,
          "max_pivots"_a, "buff"_a.noconvert(), "ioff"_a.noconvert(), "answer"_a.noconvert(),
          "limits"_a.noconvert());
    b.attr("NOT_FINITE") = lemke::boxed::NOT_FINITE;
    b.attr("BAD_BOUNDS") = lemke::boxed::BAD_BOUNDS;
    b.attr("SINGULAR") = lemke::boxed::SINGULAR;
    b.attr("BAD_FINDEX") = lemke::boxed::BAD_FINDEX;
    b.attr("UNDECIDED") = lemke::boxed::UNDECIDED;
    b.attr("NEED_RUN") = lemke::boxed::NEED_RUN;
    b.attr("PARTIAL") = lemke::boxed::PARTIAL;
    b.attr("PREPARE") = lemke::boxed::PREPARE;
    b.attr("SOLVED_RUN") = lemke::boxed::SOLVED_RUN;
}
