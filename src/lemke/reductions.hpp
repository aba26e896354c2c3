// The core's reductions as apply/recover pairs (issue 31, item 2), as the Python ones are
// (lemke/_reductions/: QPToMLCP, MLCPToLCP): `apply` builds the reduced problem from the
// caller's data into work the caller provides, `recover` maps the reduced problem's answer
// (its point, its final basis) back to the caller's variables, and `check` judges the
// recovered answer on the caller's data where the check belongs to the map back. Each is
// the code its users ran before, moved here whole (the same operations in the same order:
// the goldens and the frozen references keep every bit).
//
// - FrictionBox: a box LCP with a friction index as the extended box LCP of N = n + 2 nf
//   rows (Stewart-Trinkle rows: β+, β-, λ per friction row; boxed::extend), mapped back by
//   z_i = β+ - β- on a friction row and judged with the coupled bounds (friction_check's
//   verdict, boxed::coupled_check). Users: boxed::front, boxed::extend, and _blcp's general
//   path through the private ends boxed.friction_recover (check) and boxed.friction_z
//   (recover alone).
// - BoxQp: a QP whose only constraints are bounds as the box LCP (Ps, q, lo, up) of n pairs
//   (screen: Ps = (P + P')/2, |bounds| >= 1e20 infinite), mapped back by x = z, zb = -w,
//   the basis by box_basis, judged by qp::kkt_check. User: qp::solve_box.
// - qp.cpp's MultiplierLcp (its work is that file's QPWork, so it is declared there): a
//   strictly convex QP as the LCP of its inequality multipliers (factors: the rows, the
//   substitutions through P's Cholesky factor, the QR of the equalities, the right-hand
//   side g; gram_rows: M = C2 C2' where it is dense), mapped back by the point from the
//   factors, caller_form and mlcp_basis, judged by kkt_rows. Users: qp::solve (cold and the
//   restart's end, finish), qp::solve_gram (apply only: its LCP is solved in factored form
//   and its point by active_solve). multiplier_apply / multiplier_recover below are the
//   pair's ends for the tests (lemke._core.qp_multiplier_lcp, qp_multiplier_recover).
#pragma once
#include <cstdint>
#include <vector>

#include "boxed.hpp"
#include "qp.hpp"

namespace lemke {
namespace reductions {

// A box LCP (M, q, lo, hi) with a friction index (findex: n entries, -1 or the row of the
// friction row's normal; nf of them >= 0; validated by the caller, as boxed::front's
// prologue does) as the extended box LCP of N = n + 2 nf rows.
struct FrictionBox {
    Mat<const double> M;
    const double *q, *lo, *hi;
    const idx* findex;  // (nullptr allowed for recover and check, which read F only)
    idx nf;

    idx n() const { return M.rows; }
    idx N() const { return n() + 2 * nf; }
    // F (2 nf): the friction rows in order, then their normal rows (the reduced problem's
    // map of variables: β+ of friction row F[c] is variable F[c], β- is n + c, λ n + nf + c).
    void rows(idx* F) const;
    // The extended problem into work (boxed::FrontLayout{n, nf, true}'s work: Mx (N x N), qx,
    // lox, hix) and F; with `need`, only the rows of Mx that it flags (the others left as
    // they were; the vectors whole).
    void apply(double* work, idx* F, const std::uint8_t* need = nullptr) const;
    // The caller's z (n) from the extended answer zx (N): zx's first n, a friction row's
    // β+ - β-.
    void recover(const idx* F, const double* zx, double* z) const;
    // recover into buf's caller's z (FrontLayout{n, nf, true}), then judged on the caller's
    // data with the coupled bounds (boxed::coupled_check: buf's w, lo, hi, R, C written);
    // boxed.cpp's friction_check.
    bool check(const idx* F, const double* zx, double tol, double* buf, double& residual) const;
};

// A QP whose only constraints are bounds (qp::Data with no rows of G or A) as the box LCP
// (Ps, q, lo, up).
struct BoxQp {
    const qp::Data& d;

    idx n() const { return d.n(); }
    // work: n (n + 2) doubles, Ps then lo then up.
    static idx work_length(idx n) { return n * (n + 2); }
    // screen into work; false when screen refuses the data (nothing else then holds).
    // (Defined in qp.cpp, after screen: clang refuses a first use of a cloned function
    // before its multiversioned definition.)
    bool apply(double* work) const;
    Mat<const double> M(const double* work) const { return Mat<const double>(work, n(), n()); }
    const double* q() const { return d.q; }
    const double* lo(const double* work) const { return work + n() * n(); }
    const double* up(const double* work) const { return work + n() * (n() + 1); }
    // The data in force (the screened P and bounds; b and h are empty).
    qp::Data data(const double* work) const {
        qp::Data ds = d;
        ds.P = M(work);
        ds.lb = lo(work);
        ds.ub = up(work);
        return ds;
    }
    // x is the box LCP's z (in place: the buffer's z is the QP's x); the bounds' multipliers
    // zb = -w.
    void recover(const double* w, double* zb) const {
        for (idx j = 0; j < n(); ++j) zb[j] = -w[j];
    }
    // The box LCP's final basis (final[:k] basic, final[k:m] at upper) as the KKT-MLCP
    // numbers its pairs (qp::box_basis), into out (2n); (count, pairs).
    void recover_basis(const double* work, const idx* final, idx k, idx m, idx* out,
                       idx& count, idx& pairs) const {
        qp::box_basis(lo(work), up(work), n(), final, k, m, out, count, pairs);
    }
    // qp::kkt_check on the data in force (b and h passed as y and z: empty).
    bool check(const double* work, const double* x, const double* zb, double tol,
               double* stats) const {
        return qp::kkt_check(data(work), x, d.b, d.h, zb, tol, stats);
    }
};

// MultiplierLcp's ends for the tests (qp.cpp). multiplier_apply: screen, P's Cholesky
// factor, apply with the dense M: M (m x m) and g (m) copied out; the code (OK, BAD_INPUT,
// NOT_DEFINITE, DEPENDENT_EQUALITIES, a stop). multiplier_recover: the same, then the LCP's
// answer zz (m entries, clipped at 0 as solve clips it) with its basic z's lcp_basic[:k]
// recovered into out (OutLayout: x, y, z, zb, stats) and basic (the basis as mlcp_basis
// numbers it, room for m0 + 2n; count, pairs) and checked (`passed`); the code as apply's,
// or BAD_INPUT where zz is not m entries or lcp_basic not in [0, m).
int multiplier_apply(const qp::Data& d, std::vector<double>& M, std::vector<double>& g,
                     idx& m);
int multiplier_recover(const qp::Data& d, const double* zz, idx m_given, const idx* lcp_basic,
                       idx k, double tol, double* out, idx* basic, idx& count, idx& pairs,
                       bool& passed);

}  // namespace reductions
}  // namespace lemke
