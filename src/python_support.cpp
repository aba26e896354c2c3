// lemke._core's support functions: what the Python fronts call besides the LCP driver (the
// checks of _certify, the dense solves of _pivot_column and the MLCP reduction, the MLCP
// exchanges, WarmStart.relabel's hash tables, _lcp's principal block), each with the
// arguments and results the tests record (tests/data/frozen/). Sizes are checked here: a
// mis-sized array raises ValueError (or gives False where the function answers for itself), an array of the
// wrong dtype or layout TypeError (outputs are never converted: they must be float64 or
// int64, C-contiguous and writable), so no call reads or writes out of bounds. The GIL is
// released around the work.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/tuple.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "lemke/basis.hpp"
#include "lemke/carry.hpp"
#include "lemke/certify.hpp"
#include "lemke/linalg.hpp"
#include "lemke/mlcp.hpp"
#include "python_arrays.hpp"

namespace nb = nanobind;
using namespace nb::literals;

namespace {

using lemke::idx;

using NewMatrix = nb::ndarray<nb::numpy, double, nb::ndim<2>>;

template <class A>
idx len(const A& a, std::size_t d = 0) {
    return static_cast<idx>(a.shape(d));
}

template <class A>
lemke::Mat<const double> mat(const A& a) {
    return lemke::Mat<const double>(a.data(), len(a, 0), len(a, 1));
}

// A new float64 array of `count` entries owned by Python (freed with its last reference).
double* new_block(idx count, nb::capsule& owner) {
    double* data = new double[count > 0 ? count : 1];
    owner = nb::capsule(data, [](void* p) noexcept { delete[] static_cast<double*>(p); });
    return data;
}

// certify.lcp_check(M, q, z, tol, w): w = M z + q, (ok, residual).
std::tuple<bool, double> lcp_check(In2 M, In1 q, In1 z, double tol, Out1 w) {
    idx n = len(q);
    if (len(M, 0) != n || len(M, 1) != n || len(z) != n || len(w) != n)
        throw nb::value_error("lcp_check: M must be n x n, q, z and w of length n");
    double residual = 0.0;
    bool ok;
    {
        nb::gil_scoped_release release;
        ok = lemke::lcp_check(mat(M), q.data(), z.data(), tol, w.data(), residual);
    }
    return {ok, residual};
}

using FlagsIn = nb::ndarray<nb::ro, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using SeamOut = std::tuple<int, nb::object, nb::object, double, nb::object>;

const std::uint8_t* seam_flags(const FlagsIn& a, idx n, const char* what) {
    if (len(a) != n)
        throw nb::value_error((std::string(what) + " must hold n flags").c_str());
    if (a.dtype() != nb::dtype<bool>() && a.dtype() != nb::dtype<std::uint8_t>())
        throw nb::type_error((std::string(what) + " must be bool or uint8").c_str());
    return static_cast<const std::uint8_t*>(a.data());
}

// The seam's entries' answer (code, z, w, residual, x): code 0 the point of the basis passes
// its kind's check, 1 it fails, 2 the block is singular or the point not finite (z, w None),
// below 0 the kernels' code for data they refuse (not finite, bad bounds; z, w None); x the
// solve with rhs (B x = rhs, or B' x = rhs with transpose, by the point's factors), None
// without rhs or when that solve is not finite.
struct SeamAnswer {
    idx n, k;
    nb::capsule z_owner, w_owner, x_owner;
    double *z, *w, *x;
    int code = 0;
    bool solved = false, checked = true;  // (w None when not checked)
    double residual = 0.0;
    SeamAnswer(idx n_, idx k_, const std::optional<In1>& rhs, const char* fn) : n(n_), k(k_) {
        if (rhs && len(*rhs) != k)
            throw nb::value_error((std::string(fn) + ": rhs must have one entry per block row").c_str());
        z = new_block(n, z_owner);
        w = new_block(n, w_owner);
        x = rhs ? new_block(k, x_owner) : nullptr;
    }
    // After the point: the solve asked for.
    template <class Basis>
    void solve(const Basis& basis, const std::optional<In1>& rhs, bool transpose) {
        if (x != nullptr)
            solved = transpose ? basis.solve_transpose(rhs->data(), x) : basis.solve(rhs->data(), x);
    }
    SeamOut out() {
        auto vec = [](double* data, idx size, nb::capsule& owner) -> nb::object {
            return nb::cast(NewVector(data, {static_cast<std::size_t>(size)}, owner));
        };
        bool point = code == 0 || code == 1;
        return {code, point ? vec(z, n, z_owner) : nb::none(),
                point && checked ? vec(w, n, w_owner) : nb::none(), residual,
                solved ? vec(x, k, x_owner) : nb::none()};
    }
};

// The seam's LCP basis system (basis.hpp's LcpBasis) on the caller's data: the basis
// z_basic (n flags, bool or uint8; k of them set), its block M[beta, beta] factored, the
// point z and w = M z + q checked on every row (check_rows, the scales of equilibrate(M,
// q)), rhs (k entries, in beta's order) solved by the same factors. -1: M or q not finite.
SeamOut lcp_basis(In2 M, In1 q, FlagsIn z_basic, double tol, std::optional<In1> rhs,
                  bool transpose) {
    idx n = len(q);
    if (len(M, 0) != n || len(M, 1) != n)
        throw nb::value_error("lcp_basis: M must be n x n, q of length n");
    const std::uint8_t* flags = seam_flags(z_basic, n, "lcp_basis: z_basic");
    std::vector<idx> beta(static_cast<std::size_t>(n));
    idx k = lemke::basic_indices(flags, n, beta.data());
    SeamAnswer a(n, k, rhs, "lcp_basis");
    {
        nb::gil_scoped_release release;
        std::vector<double> work(static_cast<std::size_t>(lemke::LcpBasis::work_size(k) + 4 * n));
        std::vector<idx> piv(static_cast<std::size_t>(2 * k));
        double* R = work.data() + lemke::LcpBasis::work_size(k);
        double* C = R + n;
        lemke::LcpBasis basis(mat(M), q.data(), beta.data(), k, work.data(), piv.data());
        if (!lemke::equilibrate_finite(mat(M), q.data(), R, C, C + n)) {
            a.code = -1;
        } else if (!basis.point(a.z)) {
            a.code = 2;
        } else {
            a.solve(basis, rhs, transpose);
            a.code = basis.check(a.z, tol, R, a.w, C + n, false, a.residual) ? 0 : 1;
        }
    }
    return a.out();
}

// The seam's box basis system (basis.hpp's BoxBasis, no friction index) on the caller's
// data: zb basic, zh at hi (n flags each), the warm rule or not (boxed::basis_point's), the
// block of the basic rows (k: the basic z's, and with the warm rule the free ones) factored,
// the point checked by boxed::box_check (the scales of check_scales, n_round 0), rhs (k
// entries, in the rows' order) solved by the same factors. Below 0: boxed::prologue's code.
SeamOut box_basis(In2 M, In1 q, In1 lo, In1 hi, FlagsIn zb, FlagsIn zh, bool warm_rule,
                  double tol, std::optional<In1> rhs, bool transpose) {
    idx n = len(q);
    if (len(M, 0) != n || len(M, 1) != n || len(lo) != n || len(hi) != n)
        throw nb::value_error("box_basis: M must be n x n, q, lo and hi of length n");
    const std::uint8_t* b = seam_flags(zb, n, "box_basis: zb");
    const std::uint8_t* h = seam_flags(zh, n, "box_basis: zh");
    std::vector<double> work(static_cast<std::size_t>(lemke::BoxBasis::work_size(n) + 3 * n));
    std::vector<idx> index(static_cast<std::size_t>(n)), piv(static_cast<std::size_t>(2 * n));
    lemke::BoxBasis basis(mat(M), q.data(), lo.data(), hi.data(), index.data(), work.data(),
                          piv.data());
    double* z0 = work.data() + lemke::BoxBasis::work_size(n);
    basis.apply(b, h, warm_rule, z0);  // (the block's rows, for rhs's length)
    SeamAnswer a(n, basis.block.k, rhs, "box_basis");
    {
        nb::gil_scoped_release release;
        double* R = z0 + n;
        int code = lemke::boxed::prologue(mat(M), q.data(), lo.data(), hi.data());
        if (code != 0) {
            a.code = code;
        } else if (!basis.point(b, h, warm_rule, a.z)) {
            a.code = 2;
        } else {
            a.solve(basis, rhs, transpose);
            lemke::boxed::check_scales(mat(M), q.data(), lo.data(), hi.data(), R, R + n);
            a.code = basis.check(a.z, tol, R, a.w, 0, a.residual) ? 0 : 1;
        }
    }
    return a.out();
}

// The seam's friction basis system (basis.hpp's FrictionBasis) on the caller's data: F the
// friction rows then their normal rows (2 nf: the friction rows distinct, no normal a
// friction row, as extend writes them), zb basic and zh at hi (n + 2 nf flags each: extend's
// variables), the block of the caller's rows with w_i = 0 (each sliding row's +-mu M[:, i]
// in its normal's column) factored, the point z checked by boxed::coupled_check
// (friction_check's verdict; z and w returned as that check leaves them: z clipped into the
// coupled bounds at it, w = M z + q), rhs (k entries, in the block rows' order) solved by
// the same factors. Below 0: boxed::prologue's code, or BAD_FINDEX where a friction row's
// bounds are not -+mu (mu finite, >= 0) or its normal's lo < 0 (front's rule); 2 also
// where the extended block is singular by its pattern.
SeamOut friction_basis(In2 M, In1 q, In1 lo, In1 hi, IdxIn F, FlagsIn zb, FlagsIn zh,
                       double tol, std::optional<In1> rhs, bool transpose) {
    idx n = len(q), nf = len(F) / 2;
    if (len(M, 0) != n || len(M, 1) != n || len(lo) != n || len(hi) != n || len(F) != 2 * nf)
        throw nb::value_error("friction_basis: M must be n x n, q, lo and hi of length n, F "
                              "of even length");
    const std::int64_t* f = F.data();
    std::vector<std::uint8_t> kind(static_cast<std::size_t>(n));
    {
        if (!lemke::FrictionBasis::rows_valid(f, nf, n, kind.data()))
            throw nb::value_error("friction_basis: F must hold nf distinct friction rows of M, "
                                  "then nf normal rows that are not friction rows");
    }
    idx N = n + 2 * nf;
    const std::uint8_t* b = seam_flags(zb, N, "friction_basis: zb (n + 2 nf)");
    const std::uint8_t* h = seam_flags(zh, N, "friction_basis: zh (n + 2 nf)");
    lemke::boxed::FrontLayout L{n, nf, true};
    std::vector<double> work(static_cast<std::size_t>(lemke::FrictionBasis::work_size(n) + n));
    std::vector<double> buf(static_cast<std::size_t>(L.length()));
    std::vector<idx> ints(static_cast<std::size_t>(lemke::FrictionBasis::index_size(n)));
    std::vector<idx> piv(static_cast<std::size_t>(2 * n));
    lemke::FrictionBasis basis(mat(M), q.data(), lo.data(), hi.data(), f, nf, work.data(),
                               ints.data(), kind.data(), piv.data());
    double* z = work.data() + lemke::FrictionBasis::work_size(n);
    // (the block's rows, for rhs's length; a refused pattern: no block, rhs not read)
    bool pattern = basis.apply(b, h, z);
    idx k = pattern ? basis.block.k : (rhs ? len(*rhs) : 0);
    SeamAnswer a(n, k, rhs, "friction_basis");
    {
        nb::gil_scoped_release release;
        int code = lemke::boxed::prologue(mat(M), q.data(), lo.data(), hi.data());
        for (idx c = 0; c < nf && code == 0; ++c) {
            idx i = f[c];
            const double *l = lo.data(), *u = hi.data();
            if (!(u[i] >= 0.0 && u[i] < lemke::INF && l[i] == -u[i] && l[f[nf + c]] >= 0.0))
                code = lemke::boxed::BAD_FINDEX;
        }
        if (code != 0) {
            a.code = code;
        } else if (!pattern || !basis.point(b, h, z)) {
            a.code = 2;
        } else {
            a.solve(basis, rhs, transpose);
            bool ok = basis.check(z, tol, buf.data(), a.residual);
            std::copy(buf.begin() + L.z(), buf.begin() + L.z() + n, a.z);
            std::copy(buf.begin() + L.w(), buf.begin() + L.w() + n, a.w);
            a.code = ok ? 0 : 1;
        }
    }
    return a.out();
}

// The seam's MLCP basis system (basis.hpp's MlcpBasis) on the caller's stacked data (E N x
// N, e N, n equations first): the reduction's redundant equations and undetermined u
// (indices in [0, n)) left out, v_k basic where v_basic[k] (N - n flags), the block E[rows,
// cols] refined-solved (MLCPToLCP.basis_point's point, bit for bit), x (N entries) and, with
// tol, y = E x + e (N entries: w is y[n:]) and check_mlcp's verdict (code 0 or 1; without
// tol code 0 and w None), rhs (k entries) solved by the same LU. Code 2: no square block,
// B singular or x not finite (x, w None).
SeamOut mlcp_basis(In2 E, In1 e, std::int64_t n, IdxIn redundant, IdxIn undetermined,
                   FlagsIn v_basic, std::optional<double> tol, std::optional<In1> rhs,
                   bool transpose) {
    idx N = len(e);
    if (len(E, 0) != N || len(E, 1) != N || n < 0 || n > N)
        throw nb::value_error("mlcp_basis: E must be N x N, e of length N, 0 <= n <= N");
    const std::uint8_t* vb = seam_flags(v_basic, N - n, "mlcp_basis: v_basic (N - n)");
    std::vector<std::uint8_t> drop(static_cast<std::size_t>(2 * n), 0);
    for (int t = 0; t < 2; ++t) {
        const IdxIn& a = t == 0 ? redundant : undetermined;
        for (idx i = 0; i < len(a); ++i) {
            std::int64_t r = a.data()[i];
            if (r < 0 || r >= n) throw nb::value_error("mlcp_basis: an index is out of [0, n)");
            drop[static_cast<std::size_t>(t * n + r)] = 1;
        }
    }
    std::vector<double> work(static_cast<std::size_t>(lemke::MlcpBasis::work_size(N)));
    std::vector<idx> ints(static_cast<std::size_t>(lemke::MlcpBasis::index_size(N)));
    std::vector<idx> piv(static_cast<std::size_t>(2 * N));
    lemke::MlcpBasis basis(mat(E), e.data(), n, ints.data(), work.data(), piv.data());
    bool square = basis.apply(drop.data(), drop.data() + n, vb);
    idx k = square ? basis.block.k : (rhs ? len(*rhs) : 0);
    SeamAnswer a(N, k, rhs, "mlcp_basis");
    {
        nb::gil_scoped_release release;
        if (!square || !basis.point(a.z)) {
            a.code = 2;
        } else {
            a.solve(basis, rhs, transpose);
            if (tol)
                a.code = basis.check(a.z, *tol, a.w, a.residual) ? 0 : 1;
            else
                a.checked = false;
        }
    }
    return a.out();
}

// certify.lcp_ray_check(M, q, d, z, z0, ray, tol): whether the ray is a secondary ray.
bool lcp_ray_check(In2 M, In1 q, In1 d, In1 z, double z0, In1 ray, double tol) {
    idx n = len(q);
    if (len(M, 0) != n || len(M, 1) != n || len(d) != n || len(z) != n || len(ray) != n + 1)
        throw nb::value_error("lcp_ray_check: M must be n x n, q, d and z of length n, ray n + 1");
    nb::gil_scoped_release release;
    return lemke::lcp_ray_check(mat(M), q.data(), d.data(), z.data(), z0, ray.data(), tol);
}

// linalg.residual2(E, x, e, y): y = E x + e in double-double.
void residual2(In2 E, In1 x, In1 e, Out1 y) {
    idx rows = len(E, 0);
    if (len(E, 1) != len(x) || len(e) != rows || len(y) != rows)
        throw nb::value_error("residual2: E must be r x len(x), e and y of length r");
    nb::gil_scoped_release release;
    lemke::residual2(mat(E), x.data(), len(x), e.data(), y.data());
}

// _certify.check_mlcp's numbers: y = E x + e (double-double), (ok, residual).
std::tuple<bool, double> check_mlcp(In2 E, In1 e, std::int64_t n, In1 x, double tol, Out1 y) {
    idx N = len(e);
    if (len(E, 0) != N || len(E, 1) != N || len(x) != N || len(y) != N || n < 0 || n > N)
        throw nb::value_error("check_mlcp: E must be N x N, e, x and y of length N, 0 <= n <= N");
    double residual = 0.0;
    bool ok;
    {
        nb::gil_scoped_release release;
        ok = lemke::check_mlcp(mat(E), e.data(), n, x.data(), tol, y.data(), residual);
    }
    return {ok, residual};
}

// linalg.refined_solve(K, rhs, steps, x, lo) -> ok; False on mismatched sizes, as there.
bool refined_solve(In2 K, In1 rhs, std::int64_t steps, Out1 x, Out1 lo) {
    idx k = len(rhs), cols = len(K, 1);
    if (len(K, 0) != k || cols < k || len(x) != cols || len(lo) != k) return false;
    nb::gil_scoped_release release;
    return lemke::refined_solve(mat(K), rhs.data(), steps, x.data(), lo.data());
}

// linalg.solve(H, b) -> (ok, x); False (x zeros) when H is not len(b) x len(b), as there.
std::tuple<bool, NewVector> linalg_solve(In2 H, In1 b) {
    idx k = len(b);
    nb::capsule owner;
    double* x = new_block(k, owner);
    bool ok;
    {
        nb::gil_scoped_release release;
        ok = lemke::solve(mat(H), b.data(), x, k);
    }
    return {ok, NewVector(x, {static_cast<std::size_t>(k)}, owner)};
}

// linalg.invert_in_place(G, k) -> ok: G[:k, :k] replaced by its inverse.
bool invert_in_place(Out2 G, std::int64_t k) {
    idx rows = len(G, 0), cols = len(G, 1);
    if (k < 0 || k > rows || k > cols) return false;
    nb::gil_scoped_release release;
    return lemke::invert_in_place(lemke::Mat<double>(G.data(), rows, cols), k);
}

// linalg.principal_block(M, idx) -> M[idx][:, idx] (a new C-contiguous array).
NewMatrix principal_block(In2 M, IdxIn index) {
    idx k = len(index);
    const std::int64_t* ix = index.data();
    for (idx i = 0; i < k; ++i)
        if (ix[i] < 0 || ix[i] >= len(M, 0) || ix[i] >= len(M, 1))
            throw nb::value_error("principal_block: an index is out of range");
    nb::capsule owner;
    double* out = new_block(k * k, owner);
    {
        nb::gil_scoped_release release;
        lemke::principal_block(mat(M), ix, k, out);
    }
    return NewMatrix(out, {static_cast<std::size_t>(k), static_cast<std::size_t>(k)}, owner);
}

// equilibrate(M, q, R, C): the LCP's Ruiz scales (lemke::equilibrate, as the driver's
// prologue computes them) into R and C; for the tests that call an engine directly.
void equilibrate(In2 M, In1 q, Out1 R, Out1 C) {
    idx n = len(q);
    if (len(M, 0) != n || len(M, 1) != n || len(R) != n || len(C) != n)
        throw nb::value_error("equilibrate: M must be n x n, q, R and C of length n");
    std::vector<double> work(static_cast<std::size_t>(2 * n));
    nb::gil_scoped_release release;
    lemke::equilibrate(mat(M), q.data(), R.data(), C.data(), work.data());
}

// mlcp.equilibrate(E, n, iterations, r, s): Ruiz scaling into r, s (all ones on entry).
void mlcp_equilibrate(In2 E, std::int64_t n, std::int64_t iterations, Out1 r, Out1 s) {
    idx N = len(E, 0);
    if (len(E, 1) != N || len(r) != N || len(s) != N || n < 0 || n > N)
        throw nb::value_error("mlcp_equilibrate: E must be N x N, r and s of length N, 0 <= n <= N");
    nb::gil_scoped_release release;
    lemke::mlcp_equilibrate(mat(E), n, iterations, r.data(), s.data());
}

// mlcp.scale(E, e, r, s, T): T = [E * (r s') | e * r] (N x (N + 1)).
void mlcp_scale(In2 E, In1 e, In1 r, In1 s, Out2 T) {
    idx N = len(E, 0);
    if (len(E, 1) != N || len(e) != N || len(r) != N || len(s) != N || len(T, 0) != N ||
        len(T, 1) != N + 1)
        throw nb::value_error("mlcp_scale: E must be N x N, e, r and s of length N, T N x (N + 1)");
    nb::gil_scoped_release release;
    lemke::mlcp_scale(mat(E), e.data(), r.data(), s.data(),
                      lemke::Mat<double>(T.data(), N, N + 1));
}

// mlcp.reduce(T, n, rank_tol, e_size, row_label, col_label) -> (code, row).
std::tuple<int, std::int64_t> mlcp_reduce(Out2 T, std::int64_t n, double rank_tol,
                                          double e_size, IdxOut row_label, IdxOut col_label) {
    idx N = len(T, 0);
    if (len(T, 1) != N + 1 || len(row_label) != N || len(col_label) != N || n < 0 || n > N)
        throw nb::value_error("mlcp_reduce: T must be N x (N + 1), the labels of length N, "
                              "0 <= n <= N");
    lemke::ReduceResult r;
    {
        nb::gil_scoped_release release;
        r = lemke::mlcp_reduce(lemke::Mat<double>(T.data(), N, N + 1), n, rank_tol, e_size,
                               row_label.data(), col_label.data());
    }
    return {r.code, r.row};
}

// carry.relabel_ids(old, new, basic, out) -> count (-1, -2: a label twice in old, new).
std::int64_t relabel_ids(IdxIn old, IdxIn new_, IdxIn basic, IdxOut out) {
    idx n = len(old), m = len(new_), nb_ = len(basic);
    if (len(out) < m) throw nb::value_error("relabel_ids: out must have len(new) entries");
    const std::int64_t* b = basic.data();
    for (idx t = 0; t < nb_; ++t)
        if (b[t] < 0 || b[t] >= n) throw nb::value_error("relabel_ids: a basic row is out of range");
    nb::gil_scoped_release release;
    return lemke::relabel_ids(old.data(), n, new_.data(), m, b, nb_, out.data());
}


// The seam's KKT basis system of a QP (basis.hpp's KktBasis, _qp._polished's point) on the
// validated data (P n x n, q n, G m0 x n, h m0, A p0 x n, b p0, lb, ub n; absent bounds
// infinite): basic (int64, distinct, in [0, pairs)) the KKT MLCP's basic pairs
// (QPToMLCP's numbering: the shifted x', the rows of G, the boxed variables' upper
// multipliers), the active set's KKT rows refined-solved with x_B given, (x, y, z, zb) and,
// with tol, qp::kkt_check's verdict (code 0 or 1) and stats (primal, dual, gap, obj); without
// tol code 0 and stats None. rhs (rows() entries: rows F, A, G_S) solved by the same LU (B x
// = rhs, or B' x = rhs with transpose), None without rhs or when not finite. Code 2: the
// block singular or the solution not finite (point and stats None).
std::tuple<int, nb::object, nb::object, nb::object> kkt_basis(
    In2 P, In1 q, In2 G, In1 h, In2 A, In1 b, In1 lb, In1 ub, IdxIn basic,
    std::optional<double> tol, std::optional<In1> rhs, bool transpose) {
    idx n = len(q), m0 = len(G, 0), p0 = len(A, 0);
    if (len(P, 0) != n || len(P, 1) != n || len(G, 1) != n || len(h) != m0 || len(A, 1) != n ||
        len(b) != p0 || len(lb) != n || len(ub) != n)
        throw nb::value_error("kkt_basis: P must be n x n, G m x n, A p x n, h m, b p, q, lb "
                              "and ub n");
    lemke::qp::Data d{mat(P), q.data(), mat(G), h.data(), mat(A), b.data(), lb.data(),
                      ub.data()};
    std::vector<idx> ints(static_cast<std::size_t>(lemke::KktBasis::index_size(n, m0)));
    std::vector<double> bound(static_cast<std::size_t>(n));
    lemke::KktBasis basis(d, ints.data(), bound.data());
    idx pairs = basis.pairs();
    std::vector<std::uint8_t> v(static_cast<std::size_t>(pairs), 0);
    for (idx t = 0; t < len(basic); ++t) {
        std::int64_t i = basic.data()[t];
        if (i < 0 || i >= pairs || v[static_cast<std::size_t>(i)])
            throw nb::value_error("kkt_basis: basic must hold distinct pairs in [0, pairs)");
        v[static_cast<std::size_t>(i)] = 1;
    }
    basis.apply(v.data());
    idx s = basis.rows();
    if (rhs && len(*rhs) != s)
        throw nb::value_error("kkt_basis: rhs must have one entry per block row");
    std::unique_ptr<double[]> work(new double[static_cast<std::size_t>(basis.work_size() + 1)]);
    std::vector<idx> piv(static_cast<std::size_t>(2 * s + 1));
    basis.work = work.get();  // (not zeroed: point writes what it reads)
    basis.piv = piv.data();
    nb::capsule owner, x_owner;
    double* out = new_block(2 * n + p0 + m0 + 4, owner);  // x, y, z, zb, stats
    double *x = out, *y = x + n, *z = y + p0, *zb = z + m0, *stats = zb + n;
    double* sol = rhs ? new_block(s, x_owner) : nullptr;
    int code = 0;
    bool solved = false;
    {
        nb::gil_scoped_release release;
        if (!basis.point(x, y, z, zb)) {
            code = 2;
        } else {
            if (sol != nullptr)
                solved = transpose ? basis.solve_transpose(rhs->data(), sol)
                                   : basis.solve(rhs->data(), sol);
            if (tol) code = basis.check(x, y, z, zb, *tol, stats) ? 0 : 1;
        }
    }
    auto vec = [&owner](double* data, idx size) -> nb::object {
        return nb::cast(NewVector(data, {static_cast<std::size_t>(size)}, owner));
    };
    nb::object point = nb::none(), st = nb::none(), xs = nb::none();
    if (code != 2) {
        point = nb::make_tuple(vec(x, n), vec(y, p0), vec(z, m0), vec(zb, n));
        if (tol) st = vec(stats, 4);
    }
    if (solved) xs = nb::cast(NewVector(sol, {static_cast<std::size_t>(s)}, x_owner));
    return {code, point, st, xs};
}
}  // namespace

void bind_support(nb::module_& m) {
    m.def("lcp_check", &lcp_check, "M"_a, "q"_a, "z"_a, "tol"_a, nb::arg("w").noconvert());
    m.def("lcp_basis", &lcp_basis, "M"_a, "q"_a, "z_basic"_a, "tol"_a, "rhs"_a = nb::none(),
          "transpose"_a = false);
    m.def("box_basis", &box_basis, "M"_a, "q"_a, "lo"_a, "hi"_a, "zb"_a, "zh"_a, "warm_rule"_a,
          "tol"_a, "rhs"_a = nb::none(), "transpose"_a = false);
    m.def("friction_basis", &friction_basis, "M"_a, "q"_a, "lo"_a, "hi"_a, "F"_a, "zb"_a, "zh"_a,
          "tol"_a, "rhs"_a = nb::none(), "transpose"_a = false);
    m.def("mlcp_basis", &mlcp_basis, "E"_a, "e"_a, "n"_a, "redundant"_a, "undetermined"_a,
          "v_basic"_a, "tol"_a = nb::none(), "rhs"_a = nb::none(), "transpose"_a = false);
    m.def("lcp_ray_check", &lcp_ray_check, "M"_a, "q"_a, "d"_a, "z"_a, "z0"_a, "ray"_a, "tol"_a);
    m.def("residual2", &residual2, "E"_a, "x"_a, "e"_a, nb::arg("y").noconvert());
    m.def("check_mlcp", &check_mlcp, "E"_a, "e"_a, "n"_a, "x"_a, "tol"_a,
          nb::arg("y").noconvert());
    m.def("refined_solve", &refined_solve, "K"_a, "rhs"_a, "steps"_a, nb::arg("x").noconvert(),
          nb::arg("lo").noconvert());
    m.def("linalg_solve", &linalg_solve, "H"_a, "b"_a);
    m.def("invert_in_place", &invert_in_place, nb::arg("G").noconvert(), "k"_a);
    m.def("principal_block", &principal_block, "M"_a, "idx"_a);
    m.def("equilibrate", &equilibrate, "M"_a, "q"_a, nb::arg("R").noconvert(),
          nb::arg("C").noconvert());
    m.def("mlcp_equilibrate", &mlcp_equilibrate, "E"_a, "n"_a, "iterations"_a,
          nb::arg("r").noconvert(), nb::arg("s").noconvert());
    m.def("mlcp_scale", &mlcp_scale, "E"_a, "e"_a, "r"_a, "s"_a, nb::arg("T").noconvert());
    m.def("mlcp_reduce", &mlcp_reduce, nb::arg("T").noconvert(), "n"_a, "rank_tol"_a,
          "e_size"_a, nb::arg("row_label").noconvert(), nb::arg("col_label").noconvert());
    m.def("relabel_ids", &relabel_ids, "old"_a, "new"_a, "basic"_a, nb::arg("out").noconvert());
    m.attr("MLCP_OK") = lemke::MLCP_OK;
    m.attr("MLCP_INCONSISTENT") = lemke::MLCP_INCONSISTENT;
    m.attr("MLCP_SINGULAR") = lemke::MLCP_SINGULAR;
    m.def("kkt_basis", &kkt_basis, "P"_a, "q"_a, "G"_a, "h"_a, "A"_a, "b"_a, "lb"_a, "ub"_a,
          "basic"_a, "tol"_a = nb::none(), "rhs"_a = nb::none(), "transpose"_a = false);
}
