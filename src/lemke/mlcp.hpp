// From a mixed LCP to a plain LCP: the Ruiz scaling of the stacked E, and the exchange pivots that make
// every free variable basic on the dictionary T = [E | e].
#pragma once
#include "span.hpp"
#include "status.hpp"  // the reduction's codes: MLCP_OK, MLCP_INCONSISTENT, MLCP_SINGULAR

namespace lemke {

// kmlcp.equilibrate: `iterations` Ruiz sweeps on the N x N E (n free rows and columns
// first) into r and s (all ones on entry), numpy's operations in numpy's order.
void mlcp_equilibrate(Mat<const double> E, idx n, idx iterations, double* r, double* s);

// The dictionary T = [E | e] scaled (N x (N + 1)): T_ij = E_ij (r_i s_j), T_iN = e_i r_i,
// numpy's `E * (r[:, None] * s[None, :])` and `e * r` bit for bit, without the N x N
// temporary.
void mlcp_scale(Mat<const double> E, const double* e, const double* r, const double* s,
                Mat<double> T);

struct ReduceResult {
    int code;  // MLCP_OK, MLCP_INCONSISTENT or MLCP_SINGULAR
    idx row;   // the offending row, -1 when OK
};

// kmlcp.reduce on T (N x (N + 1)): exchanges until every free variable is basic.
// row_label, col_label (N each) get the labels of the rows' basic and the columns'
// non-basic variables.
ReduceResult mlcp_reduce(Mat<double> T, idx n, double rank_tol, double e_size, idx* row_label,
                         idx* col_label);

}  // namespace lemke
