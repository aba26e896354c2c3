// Lemke's method without a tableau: the "unrevised" method of Dai & Drumwright. Only the index sets are
// kept: alpha (the non-basic w's, H's rows) and beta (the basic z's, H's columns; n stands
// for z0), the inverse G of the block H = A[alpha, beta] of A = [M | d], updated per pivot,
// and the basic values, updated in place and checked against the block every CHECK_EVERY
// pivots. Labels: 0..n-1 for w, n..2n-1 for z, 2n for z0.
//
// Two forms: M dense (A = [M | d], kmax = n) and M in
// factored form M = Fs Fs' (A = d alone, n x 1; a column Fs Fs[e]' computed when z_e
// enters; kmax = min(n, r + 1)). The columns of A come through one function (fetch_column,
// over a ColumnSource), and H's arrays are sized by kmax (its largest possible size).
#pragma once
#include <vector>

#include "pivoting.hpp"

namespace lemke {

// Where the columns of A = [M | d] come from, in the scaled units: the dense A (n x (n + 1))
// when Fs and Ms have no rows; else A is d alone (n x 1) and M is Fs Fs' (Fs n x r) or Ms,
// a symmetric M read in place (its column e as its row e).
struct ColumnSource {
    Mat<const double> A;
    Mat<const double> Fs;
    Mat<const double> Ms;
};

// The unrevised method's workspace, laid out once per size (one per thread, reused).
// f:     from `off` (the first 64-byte boundary): AB (n x ld): AB[:, c] = A[:, blist[c]];
//        G (kmax x ld): H^-1; 16 vectors of nv: zb, wv, dzb, dw, lz, lw, tmp, tmp2, row, keys,
//        rv, rc, acol, lcol, coef, ratios (the ratio test's vector passes); then A (n x acols:
//        n + 1 dense, 1 factored) and qs (n): the scaled system; then 4 kmax:
//        invert_in_place's work. ld = kmax and nv = n + 1 rounded up to a multiple of 8: the rows
//        of AB and G and the vectors start on 64-byte boundaries (a row update's vector
//        stores then never straddle two cache lines); the padding is never read.
// i:     alist (n), blist (n), apos (n), bpos (n + 1), cand (n + 1), piv (kmax).
// flags: z_start (n).
struct UnrevisedWork {
    std::vector<double> f;
    std::vector<idx> i;
    std::vector<std::uint8_t> flags;
    idx n = -1, kmax = -1, acols = -1;
    idx ld = 0, nv = 0, off = 0;
    void layout(idx size, idx block_max, idx a_cols);
    Mat<double> AB() { return Mat<double>(f.data() + off, n, kmax, ld); }
    Mat<double> G() { return Mat<double>(f.data() + off + n * ld, kmax, kmax, ld); }
    double* vec(idx which) { return f.data() + off + (n + kmax) * ld + which * nv; }  // < 16
    Mat<double> A() { return Mat<double>(vec(16), n, acols); }
    double* qs() { return vec(16) + n * acols; }
    double* inv_work() { return qs() + n; }
    idx* alist() { return i.data(); }
    idx* blist() { return alist() + n; }
    idx* apos() { return blist() + n; }
    idx* bpos() { return apos() + n; }
    idx* cand() { return bpos() + n + 1; }
    idx* piv() { return cand() + n + 1; }
    std::uint8_t* z_start() { return flags.data(); }
};

// One run on the scaled system in `w` (qs and z_start set) with columns from `src`: Lemke's
// method from the basis z_start. Returns the status,
// pivots in `pivots`; x_out (n + 1) gets z and z0, ray_out (n + 1) the ray on
// RAY_TERMINATION, z_basic_out (n) the final basic z's; all in the scaled units.
Status unrevised_lemke(UnrevisedWork& w, const ColumnSource& src, idx max_pivots,
                       double pivot_tol, double tie_tol, double* x_out, double* ray_out,
                       std::uint8_t* z_basic_out, idx& pivots);

// Lemke's method from the basis z_start (n flags; nullptr: all w basic) on (M, q) with
// covering vector d, on the system equilibrated by (R, C): returns the status, pivots in `pivots`; x_out (n + 1)
// z and z0 and ray_out (n + 1) in the caller's units, z_basic_out (n) the final basic z's.
Status unrevised_solve(Mat<const double> M, const double* q, const double* d, const double* R,
                       const double* C, const std::uint8_t* z_start, idx max_pivots,
                       double pivot_tol, double tie_tol, double* x_out, double* ray_out,
                       std::uint8_t* z_basic_out, idx& pivots);

// Lemke's method from the all-w basis on LCP(Fs Fs', q) with covering vector d, M never
// formed (the LCP of qp.cpp's gram_lcp, whose units it takes as given: no scaling here).
// Outputs as unrevised_lemke.
Status unrevised_factored(Mat<const double> Fs, const double* d, const double* q,
                          idx max_pivots, double pivot_tol, double tie_tol, double* x_out,
                          double* ray_out, std::uint8_t* z_basic_out, idx& pivots);

// Lemke's method from the basis z_start (n flags) on LCP(M, q) with covering vector d, M
// symmetric (to the bit) and read in place, in the units given (no scaling here), H at most
// kmax x kmax (NUMERICAL_FAILURE beyond: M's rank + 1 bounds it). qp.cpp's restart of a
// failed warm start. Outputs as unrevised_lemke.
Status unrevised_symmetric(Mat<const double> M, const double* d, const double* q,
                           const std::uint8_t* z_start, idx kmax, idx max_pivots,
                           double pivot_tol, double tie_tol, double* x_out, double* ray_out,
                           std::uint8_t* z_basic_out, idx& pivots);

}  // namespace lemke
