// The acceptance test of an LCP point, row by row (the rule: componentwise backward error relative to each row's own
// size, a rounding floor for q, the certifiability bound).
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

}  // namespace lemke
