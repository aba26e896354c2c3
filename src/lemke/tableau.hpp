// Lemke's method on a condensed tableau (the Japanese article's method). Row i says basic[i] = rhs[i] + sum_j T[i, j] nonbasic[j];
// labels 0..n-1 are w, n..2n-1 are z, 2n is z0.
#pragma once
#include <vector>

#include "pivoting.hpp"

namespace lemke {

// Pivots kept pending before they are applied: 1 (no delay) below n = 32, where the
// tableau stays in the first-level cache; from there 8, so that each pass over T applies eight pivots (the row updates are bound by
// the traffic over T: at n = 100 and 300 the delayed updates take 0.8x and 0.65x the time).
// Any block gives the same bits (the pending terms are summed in pivot order; tableau.cpp).
inline idx block_size(idx n) { return n < 32 ? 1 : 8; }

// The tableau engine's workspace, laid out once per size (one per thread, reused). T's rows
// are padded (ld: to a multiple of four doubles below n = 48, of eight from n = 48, where
// each row then starts on a 64-byte boundary), so the row updates run on whole vectors; the
// padding columns hold values nobody reads.
struct TableauWork {
    std::vector<double> f;   // T (n x ld), rhs, col, q0, magb, mags, prow (ld), keys, U, V (block x ld), col2
    std::vector<idx> i;      // basis, nonbasic, pos, start_basis, cand
    std::vector<std::uint8_t> flags;  // is_basic
    idx n = -1;
    idx ld = 0;              // T's row stride: n + 1 rounded up to a multiple of 4 (n < 48) or 8
    idx off = 0;             // T's offset in f: its first row on a 64-byte boundary
    idx nv = 0;              // a vector's length in f: n rounded up to 8 (every one 64-byte aligned)
    idx block = 1;
    void layout(idx size);
    Mat<double> T() { return Mat<double>(f.data() + off, n, n + 1, ld); }
    double* rhs() { return f.data() + off + n * ld; }
    double* col() { return rhs() + nv; }
    double* q0() { return col() + nv; }
    double* magb() { return q0() + nv; }
    double* mags() { return magb() + nv; }
    double* prow() { return mags() + nv; }
    double* keys() { return prow() + ld; }
    double* U() { return keys() + nv; }        // block x n: the pending pivots' columns
    double* V() { return U() + nv * block; }   // block x ld: their rows
    double* col2() { return V() + block * ld; }  // the next entering column
    idx* basis() { return i.data(); }
    idx* nonbasic() { return basis() + n; }
    idx* pos() { return nonbasic() + n + 1; }
    idx* start_basis() { return pos() + 2 * n + 1; }
    idx* cand() { return start_basis() + n; }
};

// The pivot on row r and column s of T (entering column in col, prow: scratch of T.ld),
// rhs and magb updated with it (the same operations in the same order as the goldens
// record; rhs = nullptr: rhs not kept, magb = nullptr: magb not kept -- the box engine
// keeps neither, a run that is not careful only rhs, magb serving careful_sizes alone). The row updates run over T.ld columns: padding columns past T.cols are updated
// too (values nobody reads), each column on its own, so the bits of the others are those of
// the scalar loop. With s_next >= 0 (not s), col_next gets the column s_next after the pivot,
// read as each row is done. Also the box LCP engine's pivot (boxed.cpp).
void pivot_now(const Mat<double>& T, double* rhs, double* magb, idx r, idx s, const double* col,
               double* prow, idx s_next = -1, double* col_next = nullptr);

// The pivots pending (block > 1): the current tableau is
// T + sum_p U[:, p] V[p] over the k pending, summed in pivot order. U is n x b, V b x m.
struct Pending {
    double* U;  // column p of U: U + p n (the factors of pivot p, one per row)
    double* V;
    idx b, m, k, n;
    double u(idx i, idx p) const { return U[p * n + i]; }
    const double* v(idx p) const { return V + p * m; }
};

// The current T[i, j]: T[i, j] plus the k pending terms, in pivot order (tableau.entry).
// Also the box LCP engine's (boxed.cpp), with the same functions below.
inline double entry(Mat<double> T, const Pending& P, idx i, idx j) {
    double t = T(i, j);
    for (idx p = 0; p < P.k; ++p) {
        double f = P.u(i, p);
        if (f != 0.0) t += f * P.v(p)[j];
    }
    return t;
}

// Column s of the current tableau into col: entry() for every row, in one pass per pending
// pivot (tableau.cpp).
void pending_column(Mat<double> T, const Pending& P, idx s, double* col);

// Apply the k pending pivots (each entry gets its row's terms in pivot order, as the
// immediate updates give them); P.k = 0 after.
void flush(Mat<double> T, Pending& P);

// The pivot on row r and column s with P.k pivots pending: the pivot row and column made
// exact in T (and rhs, magb with it; either nullptr: not kept, as in pivot_now), the rank-one
// update kept pending; flushed when P.b are. The same bits as pivot_now once flushed.
void pivot_delayed(Mat<double> T, double* rhs, double* magb, idx r, idx s, const double* col,
                   double* prow, Pending& P);

// One run from the tableau in `w` (T, rhs, basis, nonbasic set up): returns the status and
// the pivots made. x_out (n + 1) gets z and z0, ray_out (n + 1) the ray on RAY_TERMINATION,
// z_basic_out (n) the final basic z's. `careful`: exact sizes of the rows that may be
// rounding (the recovery runs).
Status tableau_lemke(TableauWork& w, idx max_pivots, double pivot_tol, double tie_tol,
                     double* x_out, double* ray_out, std::uint8_t* z_basic_out, bool careful,
                     idx& pivots);

// Back to the caller's units (tableau.unscale): z and its ray times the column scales C,
// z0 and its ray entry times z0_factor; a solved x is clamped at 0.
void unscale(double* x_out, double* ray_out, const double* C, double z0_factor, bool solved,
             idx n);

// A cold run from (M, q, d) with q not >= 0, on the system equilibrated by (R, C); x_out
// and ray_out in the caller's units.
Status tableau_solve(Mat<const double> M, const double* q, const double* d, const double* R,
                     const double* C, idx max_pivots, double pivot_tol, double tie_tol,
                     double* x_out, double* ray_out, std::uint8_t* z_basic_out, bool careful,
                     idx& pivots);

}  // namespace lemke
