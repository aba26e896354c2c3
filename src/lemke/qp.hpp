// The QP kernels: the
// fused cold path of a strictly convex QP (screen, Cholesky, the rows' substitutions, the
// QR of the equalities, the multiplier LCP by lemke::checked_once, the point, the KKT check
// on the caller's data) and the path for many more inequalities than variables (the LCP in
// factored form by the unrevised method, the active set's point refined in double-double).
// Every sum in a fixed order without fused multiply-adds: the same bits on every instruction
// set (those the goldens and tests/data/frozen/ record).
#pragma once
#include <cstdint>

#include <vector>

#include "certify.hpp"  // the KKT check (kkt_check, ...), with every kind's
#include "linalg.hpp"
#include "status.hpp"  // the kernels' codes: OK, NOT_DEFINITE .. NOT_APPLICABLE, BAD_WARM

namespace lemke {
namespace qp {

constexpr double INFINITY_BOUND = 1e20;  // qp.INFINITY
constexpr double SYMMETRY_TOL = 1e-10;
constexpr double DEFINITE_TOL = 1e-12;
constexpr double RANK_TOL = 1e-10;
constexpr double STRICT_TOL = 1e-12;
constexpr idx GRAM_RATIO = 4;
constexpr double PROXIMAL = 1e-6;
constexpr double FLAT = 1e-3;
constexpr idx SMALL_FLAT = 32;  // step 8 with few rows: any flat directions up to this many variables (flat_allowed)
constexpr idx REFINE = 2;
constexpr idx REFINE_PROXIMAL = 3;
constexpr idx ACTIVE_SET_STEPS = 3;  // a warm start's active-set updates before Lemke (warm_point)
constexpr idx ACTIVE_SET_MORE = 3;   // and up to this many more while each moves a single row
constexpr double ACTIVE_TOL = 1e-9;  // initvals: within this (relative) of tight is active

// The caller's QP, qpsolvers' form: P (n x n), q, G (m0 x n), h, A (p0 x n), b, lb, ub.
struct Data {
    Mat<const double> P;
    const double* q;
    Mat<const double> G;
    const double* h;
    Mat<const double> A;
    const double* b;
    const double* lb;
    const double* ub;
    idx n() const { return P.rows; }
    idx m0() const { return G.rows; }
    idx p0() const { return A.rows; }
};

// The one statement of the fused kernels' output buffer (solve, solve_gram and the warm
// entries; lemke/_qp.py sizes and reads its buffers from _core.qp_layout, and
// tests/test_structure.py checks the two against the kernels' writes): x (n), y (p0),
// z (m0), zb (n), stats (primal, dual, gap, obj), then the final basis as int64 (room for
// m0 + 2n).
struct OutLayout {
    idx n, p0, m0;
    idx x() const { return 0; }
    idx y() const { return n; }
    idx z() const { return n + p0; }
    idx zb() const { return n + p0 + m0; }
    idx stats() const { return 2 * n + p0 + m0; }
    idx basis() const { return stats() + 4; }
    idx length() const { return basis() + m0 + 2 * n; }
};

// solve_box's buffer: boxed::solve's (boxed::BoxLayout, 6n + 1: x its z, w after it), zb
// (n), stats (4), then the final bases as int64 (3n: boxed's, then box_basis's pairs at n).
struct BoxOutLayout {
    idx n;
    idx x() const { return 0; }
    idx zb() const { return 6 * n + 1; }
    idx stats() const { return 7 * n + 1; }
    idx final() const { return 7 * n + 5; }
    idx length() const { return final() + 3 * n; }
};

struct Result {
    int code = OK;
    idx pivots = 0;
    idx k = 0;
    idx pairs = 0;
};

// qp.screen on data of matching shapes (the caller compares them): whether the values are
// plainly valid; Ps (n x n) = (P + P')/2, lo and up the bounds with |entries| >= 1e20
// infinite. Ps, lo, up are complete only when true.
bool screen(const Data& d, double* Ps, double* lo, double* up);

// qp.cholesky: L (n x n, lower, zeros above) with L L' = P; false when a pivot is not
// clearly positive.
bool cholesky(Mat<const double> P, Mat<double> L);
// cholesky of P + shift I (P's diagonal entries plus shift, as a shifted copy of P would
// hold them), without the copy.
bool cholesky_shifted(Mat<const double> P, double shift, Mat<double> L);

// The KKT check (kkt_check, kkt_check_sparse, kkt_rows): certify.hpp, the acceptance
// module (included above).

// qp.solve on data of matching shapes: writes out[:2n + p0 + m0 + 4] (x, y, z, zb,
// stats) and the basis (int64) after it (room for m0 + 2n); method 0 tableau, 1 unrevised.
// The factors of P, A, G (and M) are kept per thread and reused, not recomputed, when the
// next call's P, A, G have the same bits and the same structure (h finite, kinds of
// bounds): the same operations on the same inputs, so the same bits either way.
// warm (not nullptr): a warm start, the KKT-MLCP's basic pairs warm[:k_warm] of warm_pairs
// (as mlcp_basis numbers them): the multiplier LCP is solved (warm_point) from the
// active rows they name (their point checked first, 0 pivots when it solves the LCP; then
// up to ACTIVE_SET_STEPS active-set updates, ACTIVE_SET_MORE more while each moves a single
// row; then Lemke's method restarted from the nearest set those tried, by the unrevised
// method, kept when its point passes the KKT check; else checked_once, cold); BAD_WARM when
// warm_pairs is not this QP's count (Result.pairs).
// x0 (not nullptr, n entries, finite: the caller checks): qpsolvers' initvals, a primal
// guess whose active rows (guess_rows, ACTIVE_TOL) are the warm start instead.
Result solve(const Data& d, int method, idx max_pivots, double pivot_tol, double tie_tol,
             double tol, double* out, idx* basic, const idx* warm = nullptr, idx k_warm = 0,
             idx warm_pairs = 0, const double* x0 = nullptr);

// How this thread's warm solves (solve with warm or x0 and m > 0) ended since it began: on
// the old set or its active-set updates (warm_point), on Lemke's method restarted from the
// nearest set those tried, or on the cold LCP after both failed. For the tests and
// benchmarks/bench_mpc.py (lemke._core.qp_warm_ends); nothing reads it in the solve.
struct WarmEnds {
    idx kept = 0, restarted = 0, cold = 0;
};
WarmEnds& warm_ends();
// How many of this thread's solve calls found the factors of their P, A, G in its cache
// (every entry's bits those the factors were computed from). For tests/test_qp_warm.py
// (lemke._core.qp_cache_hits); nothing reads it in the solve.
idx& cache_hits();

// qp.solve_gram on data of matching shapes: out (2n + p0 + m0 + 4 + out_tail doubles) is
// zeroed first whole, then written as solve's; basic (room for m0 + 2n) may lie in out's
// tail.  semidefinite with few inequalities: P's flat directions taken on are as many as the
// equalities (the kernel's own rule), or with relaxed as many as flat_allowed says (the
// fronts' step 8).  reuse_screen: called right after solve on the same arrays, which ended
// NOT_DEFINITE, its screen of the data is used as it is (the same bits as screening again).
Result solve_gram(const Data& d, idx max_pivots, double pivot_tol, double tie_tol, double tol,
                  double* out, idx out_len, idx* basic, bool semidefinite, bool relaxed = false,
                  bool reuse_screen = false);

// qp.solve_box on data of matching shapes (a QP whose only constraints are bounds): screen,
// P definite (cholesky), one boxed::solve run on the box LCP (Ps, q, lo, up) from warm (2n
// flags), its natural-map verdict, zb = -w, kkt_check at min(tol, STRICT_TOL). Writes out
// (7n + 5: boxed's buffer 6n + 1, zb n, stats 4) and final (3n: boxed's final basis, then
// the basis as box_basis numbers it); Result's k and pairs are box_basis's (count, pairs).
Result solve_box(const Data& d, const std::uint8_t* warm, idx max_pivots, double pivot_tol,
                 double tie_tol, double tol, double* out, idx* final);

// qp.box_basis: the box LCP's final basis (final[:k] basic, final[k:m] at upper) as the
// KKT-MLCP numbers its pairs, into out (room for 2n); (count, pairs).
void box_basis(const double* lo, const double* up, idx n, const idx* final, idx k, idx m,
               idx* out, idx& count, idx& pairs);

// Pieces bound for the tests that check their bits (tests/test_core_qp.py).
void forward_rows(Mat<const double> L, Mat<double> R);
// forward_rows with L's profile given (lstart: row j's first nonzero left of the diagonal).
void forward_rows_from(Mat<const double> L, Mat<double> R, const idx* lstart);
// qp._dot4: the four sums a' r_k, each in linalg's fixed order (dot).
void dot4(const double* a, const double* r0, const double* r1, const double* r2,
          const double* r3, idx len, double* out);
double qr_rows(Mat<double> WE, Mat<double> V, double* beta);
// qp.gram_lcp: (status, pivots); flags (m) the basic z's.
int gram_lcp(Mat<const double> C, const double* g, idx p, idx max_pivots, double pivot_tol,
             double tie_tol, std::uint8_t* flags, idx& pivots);
idx zero_diagonal(Mat<const double> P);
idx flat_directions(Mat<const double> P, Mat<const double> L);
idx equalities(idx p0, const double* lb, const double* ub, idx n);
idx inequalities(const double* h, idx m0, const double* lb, const double* ub, idx n);
// Step 8 with fewer than GRAM_RATIO n inequalities: how many flat directions of P it takes on.
idx flat_allowed(idx p0, const double* h, idx m0, const double* lb, const double* ub, idx n);

// The QP kind's basis system (qp.cpp's QpBasis, the seam) on the caller's data, for
// _core.qp_basis and its tests: screen, L of P (cholesky: P definite), the factors (as
// solve_gram computes them, in a workspace of its own: the thread's solve cache untouched),
// the set `active` applied (m flags over the multiplier LCP's rows in rows_of's order: G's
// rows with h finite, then the upper bounds of the variables not fixed, then their lower
// bounds), the point (with z given, m entries: point_given, unrefined, as warm_point and the
// fused path take it; else point with `steps` refinements, as gram), recovered into out
// (OutLayout's x, y, z, zb and stats: 2n + p0 + m0 + 4 doubles) and checked (check: kkt_rows
// at min(tol, STRICT_TOL)); with rhs (n + p + k: K (x, yy, z_S) = rhs, K the set's KKT
// matrix, p = p0 + the fixed variables, k = the set's rows) the solve (or, with transpose,
// solve_transpose) into sol (the same lengths). code: 0 the point passes the check, 1 it
// fails, 2 apply refused the set (more rows than n - p, or F2_S' below RANK_TOL), 3 active,
// z or rhs of the wrong length (m, p, k say the right ones), else the kernels' BAD_INPUT,
// NOT_DEFINITE, DEPENDENT_EQUALITIES or a stop. solved: sol finite.
struct BasisSeam {
    int code = 0;
    idx p = 0, m = 0, k = 0;
    bool solved = false;
};
BasisSeam basis_seam(const Data& d, const std::uint8_t* active, idx m_active, const double* z,
                     idx m_z, idx steps, double tol, double* out, const double* rhs, idx rhs_len,
                     bool transpose, double* sol);
// --- shared by the kernels and the KKT check (certify.cpp) ---

// The nonzeros of a matrix by rows, in row order, their columns and values (the factor
// cache's Ps, A and G, for kkt_check's sums, which skip their exact zeros with the same
// bits, and read the values here: those of the matrix they were built from, whose bits the
// cache's hit test found the caller's again, packed instead of scattered over its rows): on
// when at most a quarter of the entries are nonzero (else the dense, vectorized loops are
// as quick).
struct SparseRows {
    std::vector<idx> start, col;
    std::vector<double> val;
    bool on = false;
    void build(const double* M, idx rows, idx cols, bool always = false) {
        start.resize(static_cast<std::size_t>(rows + 1));
        col.clear();
        val.clear();
        on = false;
        idx most = always ? rows * cols : rows * cols / 4;  // (a denser one is not kept)
        idx count = 0;  // (counted first: a dense matrix is given up without a push)
        for (idx i = 0; i < rows && count <= most; ++i) {
            const double* Mi = M + i * cols;
            for (idx j = 0; j < cols; ++j) count += Mi[j] != 0.0 ? 1 : 0;
        }
        if (count > most) return;
        col.reserve(static_cast<std::size_t>(count));
        val.reserve(static_cast<std::size_t>(count));
        for (idx i = 0; i < rows; ++i) {
            start[i] = static_cast<idx>(col.size());
            const double* Mi = M + i * cols;
            for (idx j = 0; j < cols; ++j)
                if (Mi[j] != 0.0) {
                    col.push_back(j);
                    val.push_back(Mi[j]);
                }
        }
        start[rows] = static_cast<idx>(col.size());
        on = rows > 0;
    }
};

struct Dot2 {
    double sum, size, norm;
};

// The compensated sums (qp.cpp; the KKT check's too): dot2 (one row's double-double sum,
// its size and norm), axpy2_matrix and axpy2_sparse (stationarity's sums, every row of M,
// or its nonzeros with the rows of coef = 0 skipped).
Dot2 dot2(const double* x, const double* y, idx n, double c);
void axpy2_matrix(double* s, double* err, double* size, idx n, const double* coef,
                  Mat<const double> M);
void axpy2_sparse(double* s, double* err, double* size, const double* coef, Mat<const double> M,
                  const SparseRows& sp);

}  // namespace qp
}  // namespace lemke
