// The acceptance test of an LCP point, row by row (the port of lemke/kernels/certify.py,
// whose docstring states the rule: componentwise backward error relative to each row's own
// size, a rounding floor for q, the certifiability bound).
#pragma once
#include "linalg.hpp"

namespace lemke {

constexpr double CERTIFIABLE = 1e3;

// w = M z + q (all rows, or up to the first failed row when `early`) and the verdict;
// residual = max |min(z_i, w_i)|. R: the row scales of equilibrate. work: 2n doubles.
bool check_rows(Mat<const double> M, const double* q, const double* z, double tol, double* w,
                const double* R, double* work, bool early, double& residual);

}  // namespace lemke
