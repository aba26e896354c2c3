// Acceptance, every kind's, in one module (issue 31, item 2; the rules and what tol means in
// each: python/lemke/_certify.py's docstring): the test of an LCP point, row by row (the
// rule: componentwise backward error relative to each row's own size, a rounding floor for
// q, the certifiability bound), of an LCP ray, of an MLCP point; below them the box LCP's
// (boxed::box_check, coupled_check, friction_check, is_ray), the QP's (qp::kkt_check) and
// the games' (games::check), each defined in certify.cpp under its engine's namespace with
// the operations, in the order, it had beside its engine.
#pragma once
#include "linalg.hpp"

namespace lemke {

constexpr double CERTIFIABLE = 1e3;

// The largest z_i that counts as zero: zeroing it moves no w_j by more than that row's
// allowance t rows[j] + floors[j] (certify.zero_size; also the box check's, boxed.cpp).
double zero_size(Mat<const double> M, const double* rows, idx i, double t, const double* floors);

// w = M z + q (all rows, or up to the first failed row when `early`) and the verdict;
// residual = max |min(z_i, w_i)|. R: the row scales of equilibrate. work: 2n doubles.
bool check_rows(Mat<const double> M, const double* q, const double* z, double tol, double* w,
                const double* R, double* work, bool early, double& residual);

// certify.lcp_check: check_rows on all rows with the row scales of equilibrate(M, q)
// computed here; w gets M z + q.
bool lcp_check(Mat<const double> M, const double* q, const double* z, double tol, double* w,
               double& residual);

// certify.lcp_ray_check: ray_check with the scales of equilibrate(M, q) computed here.
bool lcp_ray_check(Mat<const double> M, const double* q, const double* d, const double* z,
                   double z0, const double* ray, double tol);

// _certify.check_mlcp on the stacked N x N system E x + e = (0, w), n equations first: y
// (N) gets E x + e summed in double-double (residual2), so w is y + n; returns ok and the
// residual, numpy's NaN rules included (a maximum with a NaN in it is NaN).
constexpr double EPS_EXT = 1.0842021724855044e-19;  // 2^-63
bool check_mlcp(Mat<const double> E, const double* e, idx n, const double* x, double tol,
                double* y, double& residual);

// Whether (z, z0) + t ray (t >= 0) is a secondary ray of u = M z + q + d z0, judged row by
// row (certify.lcp_ray_check_scaled, whose docstring states the rule). R, C: the scales
// of equilibrate(M, q).
bool ray_check(Mat<const double> M, const double* q, const double* d, const double* z, double z0,
               const double* ray, double tol, const double* R, const double* C);

// ----------------------------------------------------------------------------- box LCPs
namespace boxed {

struct BoxedWork;  // boxed.hpp

// w = M z + q and the verdict on the caller's data (boxed.box_check); n_round: the size
// whose rounding is allowed for (max with n).
bool box_check(Mat<const double> M, const double* q, const double* lo, const double* hi,
               const double* z, double tol, double* w, const double* R, idx n_round,
               double& residual);

// The scales box_check judges with when no run made them (boxed.check_scales).
void check_scales(Mat<const double> M, const double* q, const double* lo, const double* hi,
                  double* R, double* C);
// check_scales, the same scales, through linalg.equilibrate_finite_kept (a warm start's
// 0-pivot re-solve on the same M: the sweeps' records of M); `kept`: M's entry, or nullptr.
void check_scales_kept(Mat<const double> M, const double* q, const double* lo,
                       const double* hi, double* R, double* C, KeptMatrix*& kept);

// The caller's z (buf's z, FrontLayout{n, nf, true}) judged with the coupled bounds at it
// (friction_check's verdict once its zx is mapped back; FrictionBasis::check): the friction
// rows' bounds -+mu z_f into buf's lo and hi, R and C of check_scales on the caller's data,
// z clipped into those bounds, w = M z + q, box_check with n_round N (= n + 2 nf).
bool coupled_check(Mat<const double> M, const double* q, const double* lo, const double* hi,
                   const idx* F, idx nf, idx N, double tol, double* buf, double& residual);
// coupled_check with the thread's workspace given (front looks it up once for the point
// and this check).
bool coupled_check(Mat<const double> M, const double* q, const double* lo, const double* hi,
                   const idx* F, idx nf, idx N, double tol, double* buf, double& residual,
                   BoxedWork& W);

// The friction index's answer from the extended one zx (N = n + 2 nf entries), judged on
// the caller's data (boxed.friction_check): z mapped back into buf's z, then coupled_check.
bool friction_check(Mat<const double> M, const double* q, const double* lo, const double* hi,
                    const idx* F, idx nf, const double* zx, idx N, double tol, double* buf,
                    double& residual);

// Whether (z, z0) + t ray is a ray of the augmented box problem (boxed.is_ray; the sizes
// of d, z, ray are the binding's to check).
bool is_ray(Mat<const double> M, const double* q, const double* lo, const double* hi,
            const double* d, const double* z, double z0, const double* ray, double tol);

}  // namespace boxed

// ----------------------------------------------------------------------------- QPs
namespace qp {

struct Data;        // qp.hpp
struct SparseRows;  // qp.hpp

// qp.kkt_check: whether (x, y, z, zb) passes the row-wise KKT check (each row against its
// terms' sizes times tol + 4 eps, plus the rounding floor: each of x, y, z, zb exact only to
// 4 (n + 2) eps times its largest entry; tests/test_qp_kkt_check.py states the rule); stats (4)
// gets (primal, dual, gap, obj).
bool kkt_check(const Data& d, const double* x, const double* y, const double* z,
               const double* zb, double tol, double* stats);
// kkt_check as solve runs it on its cached matrices: the sums over P, A and G over their
// nonzeros only (every matrix, however dense); the same verdict and stats bit for bit (for
// tests/test_qp_kkt_sparse.py, which compares the two).
bool kkt_check_sparse(const Data& d, const double* x, const double* y, const double* z,
                      const double* zb, double tol, double* stats);
// kkt_check's body; spP, spA, spG (all three or none): solve's cache's nonzeros of P, A and G
// by rows (QPWork's), whose sums then skip the exact zeros where on and x, y, z, zb are
// finite (the same bits). Cloned per instruction set.
bool kkt_rows(const Data& dt, const SparseRows* spP, const SparseRows* spA,
              const SparseRows* spG, const double* x, const double* y, const double* z,
              const double* zb, double tol, double* stats);

}  // namespace qp

// ----------------------------------------------------------------------------- games
namespace games {

// games.check: is (x, y) an equilibrium of (A, B)? out (3) gets (regret, row payoff, column
// payoff).
bool check(Mat<const double> A, Mat<const double> B, const double* x, const double* y,
           double tol, double* out);

// The regret a player may have (games.allowance): tol times the range of its payoffs
// [lo, hi], plus ROUNDING_SLACK eps (m + n) times their largest size.
double allowance(double lo, double hi, idx m, idx n, double tol);

// games.verdict: x and y distributions (each sums to 1 within 1e-12 times its length, no
// negative entry) and each player's regret within its allowance; out (3) as check's. acc
// (n), index (max(m, n)): scratch.
bool verdict(Mat<const double> A, Mat<const double> B, const double* x, const double* y,
             double allow_a, double allow_b, double* out, double* acc, idx* index);

}  // namespace games

}  // namespace lemke
