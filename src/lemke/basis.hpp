// The seam (issue 31, item 2): a basis on the caller's data. Each problem kind supplies one
// basis system with the same members: its basic block built from (M, q, basis) and factored
// once by the kernels' LU (linalg's eliminate: partial pivoting, two pivots per pass; no
// LAPACK), solved with it and with its transpose, the point mapped back to z (and w) and
// checked row by row by the kind's acceptance code. Built so far: the LCP kind (LcpBasis,
// used by lcp.cpp's basis_point and basis_point_checked and by _core.lcp_basis). Gradients
// and a sparse engine are to plug in here: hence the transpose solve.
#pragma once
#include <cstdint>

#include "certify.hpp"
#include "linalg.hpp"

namespace lemke {

// The indices i with z_basic[i] set into basic (in order); their count (the caller's basis
// as the block's rows).
inline idx basic_indices(const std::uint8_t* z_basic, idx n, idx* basic) {
    idx k = 0;
    for (idx i = 0; i < n; ++i)
        if (z_basic[i]) basic[k++] = i;
    return k;
}

// The basic block B = M[index, index] (k x k) of a basis on the caller's M, factored by the
// first solve. factor_solve: the bits of solve_gathered (or, with `kept`, of
// solve_gathered_kept: a block of the same rows of the same kept matrix is not factored
// again). solve and solve_transpose reuse the factors: those in `a` when `piv` was given
// (2k entries), those the kept matrix holds with `kept`; without either (the engines' point
// alone) there are none, and they answer false.
struct BasisBlock {
    Mat<const double> M;
    const idx* index;
    idx k;
    double* a;                 // k * k doubles: the block, then its factors
    idx* piv = nullptr;        // 2k: the pivots, or nullptr
    KeptMatrix* kept = nullptr;
    const double* factors = nullptr;  // after factor_solve: the factors and pivots, if any
    const idx* pivots = nullptr;

    // a = M[index, index] (row-major, k x k).
    void build() const {
        for (idx r = 0; r < k; ++r) {
            const double* mrow = M.row(index[r]);
            double* ar = a + r * k;
            for (idx c = 0; c < k; ++c) ar[c] = mrow[index[c]];
        }
    }

    // B x = y, B factored here; y is overwritten. False when B or y is not finite, B is
    // singular (a pivot exactly zero) or x is not finite.
    bool factor_solve(double* y, double* x) {
        factors = nullptr;
        pivots = nullptr;
        if (kept != nullptr) {
            if (!solve_gathered_kept(M, index, a, y, x, k, kept)) return false;
            kept_factors(kept, index, k, factors, pivots);
            return true;
        }
        build();
        if (!solve_in_place(Mat<double>(a, k, k), y, x, k, piv)) return false;
        if (piv != nullptr) {
            factors = a;
            pivots = piv;
        }
        return true;
    }

    // B x = y (solve) or B' x = y (solve_transpose) with the factors; y is overwritten.
    // False when there are none (k > 0), y is not finite or x is not.
    bool solve(double* y, double* x) const {
        if (k == 0) return true;
        if (factors == nullptr || !all_finite(y, k)) return false;
        return lu_solve(Mat<const double>(factors, k, k), pivots, y, x, k);
    }
    bool solve_transpose(double* y, double* x) const {
        if (k == 0) return true;
        if (factors == nullptr || !all_finite(y, k)) return false;
        return lu_solve_transpose(Mat<const double>(factors, k, k), pivots, y, x, k);
    }
};

// The LCP kind: w = M z + q, z_i basic for i in beta[:k] and w_i basic for the others, so
// B = M[beta, beta] and the point is z_beta = -B^-1 q_beta clipped at 0 (recover), z_i = 0
// elsewhere, w = M z + q (check: certify's check_rows, the kernels' row-wise acceptance,
// relative to the row scales R of equilibrate(M, q)). No refinement: the engines' point of a
// basis has none (lcp.cpp's basis_point). work: work_size(k) doubles (the block, y, x);
// piv: nullptr or 2k entries (needed for solve and solve_transpose after point).
struct LcpBasis {
    Mat<const double> M;
    const double* q;
    BasisBlock block;

    static idx work_size(idx k) { return k * (k + 2); }

    LcpBasis(Mat<const double> M_, const double* q_, const idx* beta, idx k, double* work,
             idx* piv = nullptr, KeptMatrix* kept = nullptr)
        : M(M_), q(q_), block{M_, beta, k, work, piv, kept} {}

    double* y() const { return block.a + block.k * block.k; }
    double* x() const { return block.a + block.k * (block.k + 1); }

    // The point of the basis into z (n entries): factor B, solve B x = -q_beta, recover.
    // False when B is singular or the point is not finite (z is then 0 off beta).
    bool point(double* z) {
        idx n = M.rows, k = block.k;
        for (idx i = 0; i < n; ++i) z[i] = 0.0;
        if (k == 0) return true;
        double *yb = y(), *xb = x();
        for (idx i = 0; i < k; ++i) yb[i] = -q[block.index[i]];
        if (!block.factor_solve(yb, xb)) return false;
        recover(xb, z);
        return true;
    }

    // x_beta mapped back to z: z_beta = max(x, 0) (the other entries left as they are).
    void recover(const double* xb, double* z) const {
        for (idx i = 0; i < block.k; ++i) z[block.index[i]] = pmax(xb[i], 0.0);
    }

    // B x = rhs, B' x = rhs (k entries each, in beta's order) after point, by its factors.
    bool solve(const double* rhs, double* out) const { return with(rhs, out, false); }
    bool solve_transpose(const double* rhs, double* out) const { return with(rhs, out, true); }

    // w = M z + q and the verdict of the row-wise check (up to the first failed row when
    // `early`); residual = max |min(z_i, w_i)|. work: 2n doubles.
    bool check(const double* z, double tol, const double* R, double* w, double* work, bool early,
               double& residual) const {
        return check_rows(M, q, z, tol, w, R, work, early, residual);
    }

  private:
    bool with(const double* rhs, double* out, bool transpose) const {
        double* yb = y();
        for (idx i = 0; i < block.k; ++i) yb[i] = rhs[i];
        return transpose ? block.solve_transpose(yb, out) : block.solve(yb, out);
    }
};

}  // namespace lemke
