// lemke._core's QP functions (bind_qp): the kernels lemke/_qp.py calls (qp_screen,
// qp_cholesky, qp_kkt_check, qp_solve, qp_solve_warm, qp_solve_guess, qp_solve_gram, qp_solve_box), and a few pieces whose bits the tests check
// (qp_forward_rows, qp_dot4, qp_qr_rows, qp_gram_lcp, unrevised_factored, the counts,
// qp_warm_ends, qp_cache_hits), the seam's QP basis system (qp_basis: qp::basis_seam), and
// reductions.hpp's pairs (qp_box_apply, qp_box_recover, qp_multiplier_lcp,
// qp_multiplier_recover).
// Sizes are checked here, before the GIL is released: where the kernel answers data
// of mismatched shapes (screen: False; solve, solve_gram: BAD_INPUT) this answers the same;
// where it would read or write out of bounds this raises ValueError. Arrays of the wrong
// dtype or layout raise TypeError (outputs are never converted).
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/tuple.h>

#include <cstdint>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "lemke/qp.hpp"
#include "lemke/reductions.hpp"
#include "lemke/unrevised.hpp"
#include "python_arrays.hpp"

namespace nb = nanobind;
using namespace nb::literals;

namespace {

using lemke::idx;
namespace qp = lemke::qp;

using FlagsOut = nb::ndarray<nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using NewMatrix = nb::ndarray<nb::numpy, double, nb::ndim<2>>;
using Code4 = std::tuple<int, std::int64_t, std::int64_t, std::int64_t>;

template <class A>
idx len(const A& a, std::size_t d = 0) {
    return static_cast<idx>(a.shape(d));
}

template <class A>
lemke::Mat<const double> mat(const A& a) {
    return lemke::Mat<const double>(a.data(), len(a, 0), len(a, 1));
}

qp::Data data(const In2& P, const In1& q, const In2& G, const In1& h, const In2& A, const In1& b,
              const In1& lb, const In1& ub) {
    return {mat(P), q.data(), mat(G), h.data(), mat(A), b.data(), lb.data(), ub.data()};
}

// The shapes screen compares (P n x n, G m x n and h m, A p x n and b p, lb and ub n).
bool shapes_match(const In2& P, const In1& q, const In2& G, const In1& h, const In2& A,
                  const In1& b, const In1& lb, const In1& ub) {
    idx n = len(q);
    return len(P, 0) == n && len(P, 1) == n && len(G, 1) == n && len(h) == len(G, 0) &&
           len(A, 1) == n && len(b) == len(A, 0) && len(lb) == n && len(ub) == n;
}

std::tuple<bool, NewMatrix, NewVector, NewVector> screen(In2 P, In1 q, In2 G, In1 h, In2 A,
                                                         In1 b, In1 lb, In1 ub) {
    idx n = len(q);
    double* block = new double[n * (n + 2) > 0 ? n * (n + 2) : 1];
    nb::capsule owner(block, [](void* p) noexcept { delete[] static_cast<double*>(p); });
    for (idx t = 0; t < n * (n + 2); ++t) block[t] = 0.0;
    bool ok = false;
    if (shapes_match(P, q, G, h, A, b, lb, ub)) {
        nb::gil_scoped_release release;
        ok = qp::screen(data(P, q, G, h, A, b, lb, ub), block, block + n * n, block + n * (n + 1));
    }
    std::size_t un = static_cast<std::size_t>(n);
    return {ok, NewMatrix(block, {un, un}, owner), NewVector(block + n * n, {un}, owner),
            NewVector(block + n * (n + 1), {un}, owner)};
}

bool cholesky(In2 P, Out2 L) {
    idx n = len(P, 0);
    if (len(P, 1) != n || len(L, 0) != n || len(L, 1) != n)
        throw nb::value_error("qp_cholesky: P and L must be n x n");
    nb::gil_scoped_release release;
    return qp::cholesky(mat(P), lemke::Mat<double>(L.data(), n, n));
}

bool kkt_check(In2 P, In1 q, In2 G, In1 h, In2 A, In1 b, In1 lb, In1 ub, In1 x, In1 y, In1 z,
               In1 zb, double tol, Out1 stats, bool sparse) {
    idx n = len(q);
    if (!shapes_match(P, q, G, h, A, b, lb, ub) || len(x) != n || len(y) != len(A, 0) ||
        len(z) != len(G, 0) || len(zb) != n || len(stats) < 4)
        throw nb::value_error("qp_kkt_check: P must be n x n, G m x n, A p x n, h and z of "
                              "length m, b and y p, q, lb, ub, x, zb n, stats at least 4");
    nb::gil_scoped_release release;
    return (sparse ? qp::kkt_check_sparse : qp::kkt_check)(data(P, q, G, h, A, b, lb, ub),
                                                           x.data(), y.data(), z.data(),
                                                           zb.data(), tol, stats.data());
}

// qp.solve, cold (warm nullptr) or warm, for qp_solve and qp_solve_warm.
Code4 fused(const In2& P, const In1& q, const In2& G, const In1& h, const In2& A, const In1& b,
            const In1& lb, const In1& ub, int method, std::int64_t max_pivots, double pivot_tol,
            double tie_tol, double tol, Out1& out, const std::int64_t* warm, idx kw, idx pairs,
            const double* x0 = nullptr) {
    idx n = len(q), p0 = len(A, 0), m0 = len(G, 0);
    qp::OutLayout L{n, p0, m0};
    idx k0 = L.basis();
    if (!shapes_match(P, q, G, h, A, b, lb, ub) || len(out) < L.length()) {
        // out[:k0] = 0 (clamped to out), then BAD_INPUT from the screen; a
        // buffer without room for the basis gets the same answer (it would be written past)
        double* o = out.data();
        for (idx t = 0; t < k0 && t < len(out); ++t) o[t] = 0.0;
        return {qp::BAD_INPUT, 0, 0, 0};
    }
    qp::Result r;
    {
        nb::gil_scoped_release release;
        r = qp::solve(data(P, q, G, h, A, b, lb, ub), method, max_pivots, pivot_tol, tie_tol, tol,
                      out.data(), reinterpret_cast<idx*>(out.data() + k0), warm, kw, pairs, x0);
    }
    return {r.code, r.pivots, r.k, r.pairs};
}

Code4 solve(In2 P, In1 q, In2 G, In1 h, In2 A, In1 b, In1 lb, In1 ub, int method,
            std::int64_t max_pivots, double pivot_tol, double tie_tol, double tol, Out1 out) {
    return fused(P, q, G, h, A, b, lb, ub, method, max_pivots, pivot_tol, tie_tol, tol, out, nullptr,
                 0, 0);
}


// qp.solve from a warm start: warm (int64) the KKT-MLCP's basic pairs, distinct, in
// [0, pairs) (else ValueError); BAD_WARM (with this QP's count of pairs as the last
// entry) when pairs is not this QP's.
Code4 solve_warm(In2 P, In1 q, In2 G, In1 h, In2 A, In1 b, In1 lb, In1 ub, int method,
                 std::int64_t max_pivots, double pivot_tol, double tie_tol, double tol, Out1 out,
                 IdxIn warm, std::int64_t pairs) {
    const std::int64_t* wv = warm.data();
    idx kw = len(warm);
    if (pairs < 0 || kw > pairs)
        throw nb::value_error("qp_solve_warm: warm must hold distinct pairs in [0, pairs)");
    for (idx t = 0; t < kw; ++t)
        if (wv[t] < 0 || wv[t] >= pairs || (t > 0 && wv[t] <= wv[t - 1]))
            throw nb::value_error("qp_solve_warm: warm must hold rising pairs in [0, pairs)");
    return fused(P, q, G, h, A, b, lb, ub, method, max_pivots, pivot_tol, tie_tol, tol, out, wv, kw,
                 pairs);
}

// qp.solve from qpsolvers' initvals x0 (n entries, finite, else ValueError): its active rows
// are the warm start.
Code4 solve_guess(In2 P, In1 q, In2 G, In1 h, In2 A, In1 b, In1 lb, In1 ub, int method,
                  std::int64_t max_pivots, double pivot_tol, double tie_tol, double tol, Out1 out,
                  In1 x0) {
    if (len(x0) != len(q)) throw nb::value_error("qp_solve_guess: x0 must have n entries");
    if (!lemke::all_finite(x0.data(), len(x0)))
        throw nb::value_error("qp_solve_guess: x0 must be finite");
    return fused(P, q, G, h, A, b, lb, ub, method, max_pivots, pivot_tol, tie_tol, tol, out, nullptr,
                 0, 0, x0.data());
}

Code4 solve_gram(In2 P, In1 q, In2 G, In1 h, In2 A, In1 b, In1 lb, In1 ub,
                 std::int64_t max_pivots, double pivot_tol, double tie_tol, double tol, Out1 out,
                 IdxOut basic, bool semidefinite, bool relaxed) {
    idx n = len(q), p0 = len(A, 0), m0 = len(G, 0);
    idx k0 = qp::OutLayout{n, p0, m0}.basis();
    double* o = out.data();
    if (!shapes_match(P, q, G, h, A, b, lb, ub) || len(out) < k0 || len(basic) < m0 + 2 * n) {
        for (idx t = 0; t < len(out); ++t) o[t] = 0.0;
        return {qp::BAD_INPUT, 0, 0, 0};
    }
    qp::Result r;
    {
        nb::gil_scoped_release release;
        r = qp::solve_gram(data(P, q, G, h, A, b, lb, ub), max_pivots, pivot_tol, tie_tol, tol, o,
                           len(out), basic.data(), semidefinite, relaxed);
    }
    return {r.code, r.pivots, r.k, r.pairs};
}

bool is_flags(const FlagsOut& a);

// qp.solve_box: out of length at least 7n + 5, final (int64) at least 3n, warm (bool) at
// least 2n. Shapes that do not match: BAD_INPUT with nothing written (the screen's);
// buffers too short: ValueError (the kernel would write past them).
Code4 solve_box(In2 P, In1 q, In2 G, In1 h, In2 A, In1 b, In1 lb, In1 ub, FlagsOut warm,
                std::int64_t max_pivots, double pivot_tol, double tie_tol, double tol, Out1 out,
                IdxOut final) {
    idx n = len(q);
    if (!shapes_match(P, q, G, h, A, b, lb, ub)) return {qp::BAD_INPUT, 0, 0, 0};
    qp::BoxOutLayout L{n};  // (final apart from out here: out up to L.final())
    if (len(out) < L.final() || len(final) < L.length() - L.final() || len(warm) < 2 * n ||
        !is_flags(warm))
        throw nb::value_error("qp_solve_box: out of length at least 7n + 5, final (int64) 3n, "
                              "warm (bool) 2n");
    qp::Result r;
    {
        nb::gil_scoped_release release;
        r = qp::solve_box(data(P, q, G, h, A, b, lb, ub),
                          static_cast<const std::uint8_t*>(warm.data()), max_pivots, pivot_tol,
                          tie_tol, tol, out.data(), final.data());
    }
    return {r.code, r.pivots, r.k, r.pairs};
}

std::tuple<std::int64_t, std::int64_t> box_basis(In1 lo, In1 up, IdxOut final, std::int64_t k,
                                                 std::int64_t m, IdxOut out) {
    idx n = len(lo);
    if (len(up) != n || k < 0 || m < k || m > len(final) || len(out) < 2 * n)
        throw nb::value_error("qp_box_basis: lo and up of length n, 0 <= k <= m <= len(final), "
                              "out at least 2n");
    const std::int64_t* f = final.data();
    for (idx i = 0; i < m; ++i)
        if (f[i] < 0 || f[i] >= n) throw nb::value_error("qp_box_basis: final[:m] in [0, n)");
    idx count = 0, pairs = 0;
    qp::box_basis(lo.data(), up.data(), n, f, k, m, out.data(), count, pairs);
    return {count, pairs};
}

// reductions.hpp's pairs, for tests/test_reductions_core.py. `count` zeroed doubles that
// `owner` frees (for the new arrays made on them).
double* owned(idx count, nb::capsule& owner) {
    double* p = new double[count > 0 ? static_cast<std::size_t>(count) : 1]();
    owner = nb::capsule(p, [](void* q) noexcept { delete[] static_cast<double*>(q); });
    return p;
}

// BoxQp::apply: (ok, M, lo, up) of the box LCP (M, q, lo, up); q is the caller's. Shapes that
// do not match: (False, ...) with zeros, as qp_screen.
std::tuple<bool, NewMatrix, NewVector, NewVector> box_apply(In2 P, In1 q, In2 G, In1 h, In2 A,
                                                            In1 b, In1 lb, In1 ub) {
    idx n = len(q);
    nb::capsule owner;
    double* work = owned(lemke::reductions::BoxQp::work_length(n), owner);
    bool ok = false;
    if (shapes_match(P, q, G, h, A, b, lb, ub) && len(G, 0) == 0 && len(A, 0) == 0) {
        qp::Data d = data(P, q, G, h, A, b, lb, ub);
        nb::gil_scoped_release release;
        ok = lemke::reductions::BoxQp{d}.apply(work);
    }
    std::size_t un = static_cast<std::size_t>(n);
    return {ok, NewMatrix(work, {un, un}, owner), NewVector(work + n * n, {un}, owner),
            NewVector(work + n * (n + 1), {un}, owner)};
}

// BoxQp's recover, recover_basis and check from the box LCP's answer z, w (n each) and its
// final basis (final[:k] basic, final[k:m] at upper): (passed, zb, stats, basis, count,
// pairs), x being z; None where the data are not a box-only QP that screen takes. ValueError
// on mismatched lengths.
nb::object box_recover(In2 P, In1 q, In2 G, In1 h, In2 A, In1 b, In1 lb, In1 ub, In1 z, In1 w,
                       IdxIn final, std::int64_t k, std::int64_t m, double tol) {
    idx n = len(q);
    if (len(z) != n || len(w) != n || k < 0 || m < k || m > len(final))
        throw nb::value_error("qp_box_recover: z and w of length n, 0 <= k <= m <= len(final)");
    const std::int64_t* f = final.data();
    for (idx i = 0; i < m; ++i)
        if (f[i] < 0 || f[i] >= n) throw nb::value_error("qp_box_recover: final[:m] in [0, n)");
    if (!shapes_match(P, q, G, h, A, b, lb, ub) || len(G, 0) != 0 || len(A, 0) != 0)
        return nb::none();
    qp::Data d = data(P, q, G, h, A, b, lb, ub);
    lemke::reductions::BoxQp red{d};
    std::vector<double> work(static_cast<std::size_t>(red.work_length(n) + 1));
    if (!red.apply(work.data())) return nb::none();
    nb::capsule o1, o2;
    double* zb = owned(n, o1);
    double* stats = owned(4, o2);
    std::int64_t* basis = new std::int64_t[static_cast<std::size_t>(2 * n + 1)]();
    nb::capsule o3(basis, [](void* p) noexcept { delete[] static_cast<std::int64_t*>(p); });
    idx count = 0, pairs = 0;
    bool passed;
    {
        nb::gil_scoped_release release;
        red.recover(w.data(), zb);
        passed = red.check(work.data(), z.data(), zb, tol, stats);
        red.recover_basis(work.data(), f, k, m, basis, count, pairs);
    }
    using Basis = nb::ndarray<nb::numpy, std::int64_t, nb::ndim<1>>;
    return nb::make_tuple(passed, NewVector(zb, {static_cast<std::size_t>(n)}, o1),
                          NewVector(stats, {4}, o2),
                          Basis(basis, {static_cast<std::size_t>(count)}, o3), count, pairs);
}

// reductions::multiplier_apply: (code, M, g) of the multiplier LCP (m x m, m).
std::tuple<int, NewMatrix, NewVector> multiplier_lcp(In2 P, In1 q, In2 G, In1 h, In2 A, In1 b,
                                                     In1 lb, In1 ub) {
    std::vector<double> M, g;
    idx m = 0;
    int code = qp::BAD_INPUT;
    if (shapes_match(P, q, G, h, A, b, lb, ub)) {
        qp::Data d = data(P, q, G, h, A, b, lb, ub);
        nb::gil_scoped_release release;
        code = lemke::reductions::multiplier_apply(d, M, g, m);
    }
    if (code != qp::OK) m = 0;
    nb::capsule oM, og;
    double* Mo = owned(m * m, oM);
    double* go = owned(m, og);
    for (idx t = 0; t < m * m; ++t) Mo[t] = M[static_cast<std::size_t>(t)];
    for (idx t = 0; t < m; ++t) go[t] = g[static_cast<std::size_t>(t)];
    std::size_t um = static_cast<std::size_t>(m);
    return {code, NewMatrix(Mo, {um, um}, oM), NewVector(go, {um}, og)};
}

// reductions::multiplier_recover: the LCP's answer zz (m) with its basic z's lcp_basic into
// out (OutLayout's x, y, z, zb, stats, at least 2n + p0 + m0 + 4) and basic (at least
// m0 + 2n); (code, passed, count, pairs). ValueError on buffers too short.
std::tuple<int, bool, std::int64_t, std::int64_t> multiplier_recover(
    In2 P, In1 q, In2 G, In1 h, In2 A, In1 b, In1 lb, In1 ub, In1 zz, IdxIn lcp_basic, double tol,
    Out1 out, IdxOut basic) {
    idx n = len(q), p0 = len(A, 0), m0 = len(G, 0);
    if (len(out) < qp::OutLayout{n, p0, m0}.basis() || len(basic) < m0 + 2 * n)
        throw nb::value_error("qp_multiplier_recover: out of length at least 2n + p0 + m0 + 4, "
                              "basic (int64) m0 + 2n");
    if (!shapes_match(P, q, G, h, A, b, lb, ub)) return {qp::BAD_INPUT, false, 0, 0};
    qp::Data d = data(P, q, G, h, A, b, lb, ub);
    idx count = 0, pairs = 0;
    bool passed = false;
    int code;
    {
        nb::gil_scoped_release release;
        code = lemke::reductions::multiplier_recover(d, zz.data(), len(zz), lcp_basic.data(),
                                                     len(lcp_basic), tol, out.data(),
                                                     basic.data(), count, pairs, passed);
    }
    return {code, passed, count, pairs};
}

// For the tests: the pieces whose bits the solves depend on.
void forward_rows(In2 L, Out2 R) {
    idx n = len(L, 0);
    if (len(L, 1) != n || len(R, 1) != n)
        throw nb::value_error("qp_forward_rows: L must be n x n, R k x n");
    nb::gil_scoped_release release;
    qp::forward_rows(mat(L), lemke::Mat<double>(R.data(), len(R, 0), n));
}

std::tuple<double, double, double, double> dot4(In1 a, In1 r0, In1 r1, In1 r2, In1 r3) {
    idx k = len(a);
    if (len(r0) < k || len(r1) < k || len(r2) < k || len(r3) < k)
        throw nb::value_error("qp_dot4: r0..r3 must be at least as long as a");
    double o[4];
    qp::dot4(a.data(), r0.data(), r1.data(), r2.data(), r3.data(), k, o);
    return {o[0], o[1], o[2], o[3]};
}

double qr_rows(Out2 WE, Out2 V, Out1 beta) {
    idx p = len(WE, 0), n = len(WE, 1);
    if (p <= n && (len(V, 0) < p || len(V, 1) != n || len(beta) < p))
        throw nb::value_error("qp_qr_rows: V must be p x n and beta of length p (WE p x n)");
    nb::gil_scoped_release release;
    return qp::qr_rows(lemke::Mat<double>(WE.data(), p, n),
                       lemke::Mat<double>(V.data(), len(V, 0), len(V, 1)), beta.data());
}

bool is_flags(const FlagsOut& a) {
    return a.dtype() == nb::dtype<bool>() || a.dtype() == nb::dtype<std::uint8_t>();
}

std::tuple<int, std::int64_t> gram_lcp(In2 C, In1 g, std::int64_t p, std::int64_t max_pivots,
                                       double pivot_tol, double tie_tol, FlagsOut flags) {
    idx m = len(C, 0);
    if (len(g) != m || p < 0 || p > len(C, 1) || len(flags) != m || !is_flags(flags))
        throw nb::value_error("qp_gram_lcp: C m x n, g and flags (bool) of length m, 0 <= p <= n");
    idx pivots = 0;
    int status;
    {
        nb::gil_scoped_release release;
        status = qp::gram_lcp(mat(C), g.data(), p, max_pivots, pivot_tol, tie_tol,
                              static_cast<std::uint8_t*>(flags.data()), pivots);
    }
    return {status, pivots};
}

// unrevised.lemke(d[:, None], Fs, q, false_flags(n), no_matrix(), ...): (status, pivots).
std::tuple<int, std::int64_t> unrevised_factored(In2 Fs, In1 d, In1 q, std::int64_t max_pivots,
                                                 double pivot_tol, double tie_tol, Out1 x_out,
                                                 Out1 ray_out, FlagsOut z_basic_out) {
    idx n = len(q);
    if (n == 0 || len(Fs, 0) != n || len(d) != n || len(x_out) != n + 1 ||
        len(ray_out) != n + 1 || len(z_basic_out) != n || !is_flags(z_basic_out))
        throw nb::value_error("unrevised_factored: Fs n x r (n > 0), d, q and z_basic_out "
                              "(bool) of length n, x_out and ray_out n + 1");
    idx pivots = 0;
    lemke::Status status;
    {
        nb::gil_scoped_release release;
        status = lemke::unrevised_factored(mat(Fs), d.data(), q.data(), max_pivots, pivot_tol,
                                           tie_tol, x_out.data(), ray_out.data(),
                                           static_cast<std::uint8_t*>(z_basic_out.data()), pivots);
    }
    return {static_cast<int>(status), pivots};
}

// The seam's QP basis system (qp.cpp's QpBasis, qp::basis_seam) on the caller's data:
// active (m flags, bool or uint8: the multiplier LCP's rows in rows_of's order, G's rows with
// h finite, then the upper bounds of the variables not fixed, then their lower bounds), the
// point with z given (m entries, unrefined: warm_point's and the fused path's) or refined
// `steps` times (gram's), checked at min(tol, STRICT_TOL); rhs (n + p + k) solved (or, with
// transpose, by solve_transpose) by the set's factors. Returns (code, x, y, z, zb, stats,
// sol): code 0 the point passes the check, 1 it fails, 2 the set refused (x .. stats None),
// below 0 the kernels' code for data they refuse; sol None without rhs or when not finite.
// Flags, z or rhs of the wrong length: ValueError (naming m, p and k).
using FlagsRo = nb::ndarray<nb::ro, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using SeamQp = std::tuple<int, nb::object, nb::object, nb::object, nb::object, nb::object, nb::object>;

SeamQp qp_basis(In2 P, In1 q, In2 G, In1 h, In2 A, In1 b, In1 lb, In1 ub, FlagsRo active,
                double tol, std::int64_t steps, std::optional<In1> z, std::optional<In1> rhs,
                bool transpose) {
    if (!shapes_match(P, q, G, h, A, b, lb, ub))
        throw nb::value_error("qp_basis: P must be n x n, G m x n, A p x n, h m, b p, q, lb, ub n");
    if (active.dtype() != nb::dtype<bool>() && active.dtype() != nb::dtype<std::uint8_t>())
        throw nb::type_error("qp_basis: active must be bool or uint8");
    if (steps < 0 || steps > 16) throw nb::value_error("qp_basis: steps in [0, 16]");
    idx n = len(q), p0 = len(A, 0), m0 = len(G, 0);
    qp::OutLayout L{n, p0, m0};
    std::vector<double> out(static_cast<std::size_t>(L.basis()));
    idx rl = rhs ? len(*rhs) : 0;
    std::vector<double> sol(static_cast<std::size_t>(rl > 0 ? rl : 1));
    qp::BasisSeam a;
    {
        nb::gil_scoped_release release;
        a = qp::basis_seam(data(P, q, G, h, A, b, lb, ub),
                           static_cast<const std::uint8_t*>(active.data()), len(active),
                           z ? z->data() : nullptr, z ? len(*z) : 0, steps, tol, out.data(),
                           rhs ? rhs->data() : nullptr, rl, transpose, sol.data());
    }
    if (a.code == 3)
        throw nb::value_error(("qp_basis: active and z must have m = " + std::to_string(a.m) +
                               " entries, rhs n + p + k = " + std::to_string(n + a.p + a.k))
                                  .c_str());
    auto vec = [](const double* from, idx size) -> nb::object {
        double* data = new double[size > 0 ? size : 1];
        nb::capsule owner(data, [](void* p) noexcept { delete[] static_cast<double*>(p); });
        for (idx t = 0; t < size; ++t) data[t] = from[t];
        return nb::cast(NewVector(data, {static_cast<std::size_t>(size)}, owner));
    };
    bool point = a.code == 0 || a.code == 1;
    nb::object none = nb::none();
    return {a.code, point ? vec(out.data() + L.x(), n) : none,
            point ? vec(out.data() + L.y(), p0) : none, point ? vec(out.data() + L.z(), m0) : none,
            point ? vec(out.data() + L.zb(), n) : none, point ? vec(out.data() + L.stats(), 4) : none,
            point && a.solved ? vec(sol.data(), rl) : none};
}

}  // namespace

void bind_qp(nb::module_& m) {
    m.def("qp_screen", &screen, "P"_a, "q"_a, "G"_a, "h"_a, "A"_a, "b"_a, "lb"_a, "ub"_a);
    m.def("qp_cholesky", &cholesky, "P"_a, nb::arg("L").noconvert());
    m.def("qp_kkt_check", &kkt_check, "P"_a, "q"_a, "G"_a, "h"_a, "A"_a, "b"_a, "lb"_a, "ub"_a,
          "x"_a, "y"_a, "z"_a, "zb"_a, "tol"_a, nb::arg("stats").noconvert(),
          "sparse"_a = false);
    m.def("qp_solve", &solve, "P"_a, "q"_a, "G"_a, "h"_a, "A"_a, "b"_a, "lb"_a, "ub"_a,
          "method"_a, "max_pivots"_a, "pivot_tol"_a, "tie_tol"_a, "tol"_a,
          nb::arg("out").noconvert());
    m.def("qp_solve_warm", &solve_warm, "P"_a, "q"_a, "G"_a, "h"_a, "A"_a, "b"_a, "lb"_a, "ub"_a,
          "method"_a, "max_pivots"_a, "pivot_tol"_a, "tie_tol"_a, "tol"_a,
          nb::arg("out").noconvert(), nb::arg("warm").noconvert(), "pairs"_a);
    m.def("qp_solve_guess", &solve_guess, "P"_a, "q"_a, "G"_a, "h"_a, "A"_a, "b"_a, "lb"_a, "ub"_a,
          "method"_a, "max_pivots"_a, "pivot_tol"_a, "tie_tol"_a, "tol"_a,
          nb::arg("out").noconvert(), "x0"_a);
    m.def("qp_solve_gram", &solve_gram, "P"_a, "q"_a, "G"_a, "h"_a, "A"_a, "b"_a, "lb"_a, "ub"_a,
          "max_pivots"_a, "pivot_tol"_a, "tie_tol"_a, "tol"_a, nb::arg("out").noconvert(),
          nb::arg("basic").noconvert(), "semidefinite"_a, "relaxed"_a = false);
    m.def("qp_solve_box", &solve_box, "P"_a, "q"_a, "G"_a, "h"_a, "A"_a, "b"_a, "lb"_a, "ub"_a,
          nb::arg("warm").noconvert(), "max_pivots"_a, "pivot_tol"_a, "tie_tol"_a, "tol"_a,
          nb::arg("out").noconvert(), nb::arg("final").noconvert());
    m.def("qp_box_basis", &box_basis, "lo"_a, "up"_a, "final"_a, "k"_a, "m"_a,
          nb::arg("out").noconvert());
    m.def("qp_box_apply", &box_apply, "P"_a, "q"_a, "G"_a, "h"_a, "A"_a, "b"_a, "lb"_a, "ub"_a);
    m.def("qp_box_recover", &box_recover, "P"_a, "q"_a, "G"_a, "h"_a, "A"_a, "b"_a, "lb"_a,
          "ub"_a, "z"_a, "w"_a, "final"_a, "k"_a, "m"_a, "tol"_a);
    m.def("qp_multiplier_lcp", &multiplier_lcp, "P"_a, "q"_a, "G"_a, "h"_a, "A"_a, "b"_a,
          "lb"_a, "ub"_a);
    m.def("qp_multiplier_recover", &multiplier_recover, "P"_a, "q"_a, "G"_a, "h"_a, "A"_a,
          "b"_a, "lb"_a, "ub"_a, "zz"_a, "lcp_basic"_a, "tol"_a, nb::arg("out").noconvert(),
          nb::arg("basic").noconvert());
    m.def("qp_forward_rows", &forward_rows, "L"_a, nb::arg("R").noconvert());
    m.def("qp_dot4", &dot4, "a"_a, "r0"_a, "r1"_a, "r2"_a, "r3"_a);
    m.def("qp_qr_rows", &qr_rows, nb::arg("WE").noconvert(), nb::arg("V").noconvert(),
          nb::arg("beta").noconvert());
    m.def("qp_gram_lcp", &gram_lcp, "C"_a, "g"_a, "p"_a, "max_pivots"_a, "pivot_tol"_a,
          "tie_tol"_a, nb::arg("flags").noconvert());
    m.def("unrevised_factored", &unrevised_factored, "Fs"_a, "d"_a, "q"_a, "max_pivots"_a,
          "pivot_tol"_a, "tie_tol"_a, nb::arg("x_out").noconvert(),
          nb::arg("ray_out").noconvert(), nb::arg("z_basic_out").noconvert());
    m.def("qp_warm_ends", []() {
        const qp::WarmEnds& e = qp::warm_ends();
        return std::make_tuple(e.kept, e.restarted, e.cold);
    });
    m.def("qp_cache_hits", []() { return qp::cache_hits(); });
    m.def("qp_zero_diagonal", [](In2 P) {
        if (len(P, 0) != len(P, 1)) throw nb::value_error("qp_zero_diagonal: P must be square");
        return qp::zero_diagonal(mat(P));
    }, "P"_a);
    m.def("qp_equalities", [](In2 A, In1 lb, In1 ub) {
        if (len(lb) != len(ub)) throw nb::value_error("qp_equalities: lb and ub of one length");
        return qp::equalities(len(A, 0), lb.data(), ub.data(), len(lb));
    }, "A"_a, "lb"_a, "ub"_a);
    m.def("qp_flat_allowed", [](In1 h, std::int64_t p, In1 lb, In1 ub) {
        if (len(lb) != len(ub)) throw nb::value_error("qp_flat_allowed: lb and ub of one length");
        return qp::flat_allowed(p, h.data(), len(h), lb.data(), ub.data(), len(lb));
    }, "h"_a, "p"_a, "lb"_a, "ub"_a);
    m.def("qp_inequalities", [](In1 h, In1 lb, In1 ub) {
        if (len(lb) != len(ub)) throw nb::value_error("qp_inequalities: lb and ub of one length");
        return qp::inequalities(h.data(), len(h), lb.data(), ub.data(), len(lb));
    }, "h"_a, "lb"_a, "ub"_a);
    // The output buffers' layouts (qp.hpp OutLayout, BoxOutLayout): lemke/_qp.py sizes and
    // reads its buffers from these (tests/test_structure.py checks them on the kernels).
    m.def("qp_layout", [](std::int64_t n, std::int64_t p0, std::int64_t m0) {
        qp::OutLayout L{n, p0, m0};
        return std::make_tuple(L.x(), L.y(), L.z(), L.zb(), L.stats(), L.basis(), L.length());
    }, "n"_a, "p"_a, "m"_a);
    m.def("qp_box_layout", [](std::int64_t n) {
        qp::BoxOutLayout L{n};
        return std::make_tuple(L.x(), L.zb(), L.stats(), L.final(), L.length());
    }, "n"_a);
    m.def("qp_basis", &qp_basis, "P"_a, "q"_a, "G"_a, "h"_a, "A"_a, "b"_a, "lb"_a, "ub"_a,
          "active"_a, "tol"_a, "steps"_a = qp::REFINE, "z"_a = nb::none(), "rhs"_a = nb::none(),
          "transpose"_a = false);
    m.attr("QP_OK") = qp::OK;
    m.attr("QP_NOT_DEFINITE") = qp::NOT_DEFINITE;
    m.attr("QP_NOT_APPLICABLE") = qp::NOT_APPLICABLE;
    m.attr("QP_CHECK_FAILED") = qp::CHECK_FAILED;
    m.attr("QP_BAD_WARM") = qp::BAD_WARM;
    m.attr("QP_DEPENDENT_EQUALITIES") = qp::DEPENDENT_EQUALITIES;
    m.attr("QP_NOT_SOLVED") = qp::NOT_SOLVED;
    m.attr("QP_BAD_INPUT") = qp::BAD_INPUT;
    m.attr("QP_GRAM_RATIO") = qp::GRAM_RATIO;
}
