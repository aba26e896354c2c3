// The seam (issue 31, item 2): a basis on the caller's data. Each problem kind supplies one
// basis system with the same members: its basic block built from (M, q, basis) and factored
// once by the kernels' LU (linalg's eliminate: partial pivoting, two pivots per pass; no
// LAPACK), solved with it and with its transpose, the point mapped back to z (and w) and
// checked row by row by the kind's acceptance code. Built so far: the LCP kind (LcpBasis,
// used by lcp.cpp's basis_point and basis_point_checked and by _core.lcp_basis), the box
// kind without friction (BoxBasis, used by boxed.cpp's basis_point) and with a friction index
// (FrictionBasis, used by boxed.cpp's friction_point and the box front's warm start; private
// entry _core.friction_basis) and the MLCP kind (MlcpBasis, used by MLCPToLCP.basis_point
// through _core.mlcp_basis; its solve refined, as that routine's was). Gradients and a sparse
// engine are to plug in here: hence the transpose solve.
#pragma once
#include <cstdint>

#include "boxed.hpp"
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
// (2k entries), those the kept matrix holds with `kept` (looked up when asked for: valid
// until the thread's next kept solve); without either (the engines' point alone) there are
// none, and they answer false.
struct BasisBlock {
    Mat<const double> M;
    const idx* index;
    idx k;
    double* a;                 // k * k doubles: the block, then its factors
    idx* piv = nullptr;        // 2k: the pivots, or nullptr
    KeptMatrix* kept = nullptr;
    const double* factors = nullptr;  // after factor_solve with piv: `a` and piv (the factors
    const idx* pivots = nullptr;      // and pivots); else nullptr

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
        if (kept != nullptr) return solve_gathered_kept(M, index, a, y, x, k, kept);
        build();
        return factor_solve_built(y, x);
    }

    // The same with the block already in `a` (a kind whose block is not M[index, index]:
    // FrictionBasis builds its own).
    bool factor_solve_built(double* y, double* x) {
        factors = nullptr;
        pivots = nullptr;
        if (!solve_in_place(Mat<double>(a, k, k), y, x, k, piv)) return false;
        if (piv != nullptr) {
            factors = a;
            pivots = piv;
        }
        return true;
    }

    // The right-hand side's and the solution's places after the block in `a` (k each).
    double* y() const { return a + k * k; }
    double* x() const { return a + k * (k + 1); }

    // B x = rhs (solve) or B' x = rhs (solve_transpose) with the factors (rhs copied into
    // y() first). False when there are none (k > 0), rhs is not finite or x is not.
    bool solve(const double* rhs, double* out) const { return with(rhs, out, false); }
    bool solve_transpose(const double* rhs, double* out) const { return with(rhs, out, true); }

  private:
    bool with(const double* rhs, double* out, bool transpose) const {
        if (k == 0) return true;
        double* yb = y();
        for (idx i = 0; i < k; ++i) yb[i] = rhs[i];
        const double* f = factors;
        const idx* p = pivots;
        // (a kept matrix's factors looked up only here: the point alone needs none)
        if (f == nullptr && kept != nullptr) kept_factors(kept, index, k, f, p);
        if (f == nullptr || !all_finite(yb, k)) return false;
        Mat<const double> F(f, k, k);
        return transpose ? lu_solve_transpose(F, p, yb, out, k) : lu_solve(F, p, yb, out, k);
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

    // The point of the basis into z (n entries): factor B, solve B x = -q_beta, recover.
    // False when B is singular or the point is not finite (z is then 0 off beta).
    bool point(double* z) {
        idx n = M.rows, k = block.k;
        for (idx i = 0; i < n; ++i) z[i] = 0.0;
        if (k == 0) return true;
        double *yb = block.y(), *xb = block.x();
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
    bool solve(const double* rhs, double* out) const { return block.solve(rhs, out); }
    bool solve_transpose(const double* rhs, double* out) const {
        return block.solve_transpose(rhs, out);
    }

    // w = M z + q and the verdict of the row-wise check (up to the first failed row when
    // `early`); residual = max |min(z_i, w_i)|. work: 2n doubles (basis_point_checked gives
    // the block's own: its factors are then gone, and solve answers garbage).
    bool check(const double* z, double tol, const double* R, double* w, double* work, bool early,
               double& residual) const {
        return check_rows(M, q, z, tol, w, R, work, early, residual);
    }
};

// The box kind (no friction index): z_i basic where zb[i] (and, by the warm rule, where z_i
// is free), the others at a bound (apply), so B = M[index, index] with index the basic rows
// and the point x = B^-1 (-(q + M z_fixed))[index] put into z (recover; outside the warm rule
// clipped to [lo, hi]); check: boxed::box_check on the caller's data. No refinement (the
// engines' box point has none). work: work_size(n) doubles (the block, y, x); index: n.
struct BoxBasis {
    Mat<const double> M;
    const double *q, *lo, *hi;
    idx* index;  // the block's rows (apply)
    BasisBlock block;

    static idx work_size(idx n) { return n * (n + 2); }

    BoxBasis(Mat<const double> M_, const double* q_, const double* lo_, const double* hi_,
             idx* index_, double* work, idx* piv = nullptr, KeptMatrix* kept = nullptr)
        : M(M_), q(q_), lo(lo_), hi(hi_), index(index_), block{M_, index_, 0, work, piv, kept} {}

    // The rows' states into the block's rows and z: a basic z_i (or, with warm_rule, a free
    // one) 0 here, the others at a bound: with warm_rule hi when zh[i] and hi finite, else lo
    // when finite, else hi when finite, else 0; without it zh[i] ? hi : lo, 0 when infinite.
    void apply(const std::uint8_t* zb, const std::uint8_t* zh, bool warm_rule, double* z) {
        idx n = M.rows, nb = 0;
        for (idx i = 0; i < n; ++i) {
            bool free = warm_rule && lo[i] == -INF && hi[i] == INF;
            double v;
            if (warm_rule) {
                if (zh[i] && hi[i] < INF) {
                    v = hi[i];
                } else if (lo[i] > -INF) {
                    v = lo[i];
                } else if (hi[i] < INF) {
                    v = hi[i];
                } else {
                    v = 0.0;
                }
            } else {
                v = zh[i] ? hi[i] : lo[i];
                if (!(std::fabs(v) < INF)) v = 0.0;
            }
            if (zb[i] || free) {
                index[nb++] = i;
                v = 0.0;  // no part in the right-hand side
            }
            z[i] = v;
        }
        block.k = nb;
    }

    // The point of the basis (zb basic, zh at hi) into z (n entries): apply, factor B, solve
    // B x = -(q + M z)[index], recover. False when B is singular or z is not finite.
    bool point(const std::uint8_t* zb, const std::uint8_t* zh, bool warm_rule, double* z) {
        apply(zb, zh, warm_rule, z);
        idx n = M.rows, nb = block.k;
        if (nb > 0) {
            double *yb = block.y(), *xb = block.x();
            for (idx c = 0; c < nb; ++c) {
                idx r = index[c];
                yb[c] = -(q[r] + dot(M.row(r), z, n));
            }
            if (!block.factor_solve(yb, xb)) return false;
        }
        return recover(block.x(), warm_rule, z);
    }

    // x put into z at the block's rows; outside the warm rule z clipped to [lo, hi]. False
    // when z is not finite.
    bool recover(const double* xb, bool warm_rule, double* z) const {
        idx n = M.rows;
        for (idx c = 0; c < block.k; ++c) z[index[c]] = xb[c];
        if (!all_finite(z, n)) return false;
        if (!warm_rule)
            for (idx i = 0; i < n; ++i) z[i] = pmin(pmax(z[i], lo[i]), hi[i]);
        return true;
    }

    // B x = rhs, B' x = rhs (one entry per block row) after point, by its factors.
    bool solve(const double* rhs, double* out) const { return block.solve(rhs, out); }
    bool solve_transpose(const double* rhs, double* out) const {
        return block.solve_transpose(rhs, out);
    }

    // w = M z + q and the verdict of the box check on the caller's data (boxed::box_check;
    // R: check_scales', n_round as there).
    bool check(const double* z, double tol, const double* R, double* w, idx n_round,
               double& residual) const {
        return boxed::box_check(M, q, lo, hi, z, tol, w, R, n_round, residual);
    }
};

// c ? a : b by bit masks (no branch: bit for bit a or b)
inline double pick_bits(bool c, double a, double b) {
    std::int64_t m = -static_cast<std::int64_t>(c);
    return bits_float((float_bits(a) & m) | (float_bits(b) & ~m));
}

// The box kind with a friction index: a basis of boxed::extend's extended problem (zb
// basic, zh at hi: N = n + 2 nf flags, extend's variables) solved on the caller's n rows.
// Each row is one equation read from its variables' states (apply): an ordinary row w_i = 0
// when z_i is basic or free, else z_i at its bound by BoxBasis's warm rule; a friction row
// z_i = +-mu z_f (sliding) when λ and one of β+, β- are basic, z_i = 0 when neither is, else
// w_i = 0. The block (build) is M[index, index] with each sliding row's slope_i M[r, i]
// added into its normal's column (when the normal is in the block; else z_i is fixed by the
// normal's z), so B is of the LCP's size and there is no extended matrix; the right-hand
// side -(q + M z_fixed)[index]. recover puts x into z and each coupled z_i = slope_i z_f;
// check: boxed::coupled_check, friction_check's verdict on the caller's z (the coupled
// bounds at it). F: the friction rows, then their normal rows (2 nf, extend's F). No
// refinement (friction_point had none). work: work_size(n) doubles (the block, y, x, the
// slopes); ints: index_size(n); kind: n flags; piv: nullptr or 2n entries.
struct FrictionBasis {
    Mat<const double> M;
    const double *q, *lo, *hi;
    const idx* F;
    idx nf;
    double* slope;                // a sliding row's z_i = slope_i z_f (+-mu)
    idx *coupled, *index, *pos;   // the ranks of the sliding rows whose normal is in the
    std::uint8_t* kind;           // block; the block's rows (w_i = 0); a row's place (-1)
    idx ns = 0;                   // (the coupled count)
    BasisBlock block;
    static constexpr std::uint8_t FIXED = 0, EQUATION = 1, SLIDING = 2;

    static idx work_size(idx n) { return n * (n + 3); }
    static idx index_size(idx n) { return 3 * n; }

    // Whether F is as extend writes it: nf distinct friction rows in [0, n), then nf normal
    // rows in [0, n), none a friction row (so nf <= n/2 and the coupled rows fit `ints`;
    // the bindings refuse any other F). seen: n flags (overwritten).
    static bool rows_valid(const idx* F, idx nf, idx n, std::uint8_t* seen) {
        for (idx i = 0; i < n; ++i) seen[i] = 0;
        for (idx c = 0; c < 2 * nf; ++c)
            if (F[c] < 0 || F[c] >= n) return false;
        for (idx c = 0; c < nf; ++c)
            if (seen[F[c]]++) return false;
        for (idx c = nf; c < 2 * nf; ++c)
            if (seen[F[c]]) return false;
        return true;
    }

    FrictionBasis(Mat<const double> M_, const double* q_, const double* lo_, const double* hi_,
                  const idx* F_, idx nf_, double* work, idx* ints, std::uint8_t* kind_,
                  idx* piv = nullptr)
        : M(M_), q(q_), lo(lo_), hi(hi_), F(F_), nf(nf_), slope(work + M_.rows * (M_.rows + 2)),
          coupled(ints), index(ints + M_.rows), pos(ints + 2 * M_.rows), kind(kind_),
          block{M_, ints + M_.rows, 0, work, piv} {}

    // The rows' states into kind, the fixed z's, the block's rows and the coupled ones.
    // (Selects rather than branches where the row states decide: they follow the data.)
    // False where the extended block is singular by its pattern (λ basic with β+ and β- at
    // 0; β+ and β- both basic with λ at 0).
    bool apply(const std::uint8_t* zb, const std::uint8_t* zh, double* z) {
        idx n = M.rows;
        for (idx i = 0; i < n; ++i) {  // an ordinary row: BoxBasis's warm rule
            // (bit masks, not branches: the compiler branched on zb and zh here, mispredicted
            // from row to row)
            bool hf = hi[i] < INF, lf = lo[i] > -INF;
            bool eq = (zb[i] != 0) | (!lf & (hi[i] == INF));
            double v = pick_bits(hf, hi[i], 0.0);
            v = pick_bits(lf, lo[i], v);
            v = pick_bits((zh[i] != 0) & hf, hi[i], v);
            z[i] = pick_bits(eq, 0.0, v);
            kind[i] = static_cast<std::uint8_t>(eq);  // (EQUATION 1, FIXED 0)
        }
        for (idx c = 0; c < nf; ++c) {  // a friction row: β+ (the row), β- (n + c), λ (n + nf + c)
            idx i = F[c];
            bool bp = zb[i] != 0, bm = zb[n + c] != 0, lam = zb[n + nf + c] != 0;
            if (lam ? !(bp || bm) : (bp && bm)) return false;  // (a singular extended block)
            slope[i] = pick_bits(bp, hi[i], -hi[i]);
            bool sliding = lam & (bp != bm);
            kind[i] = sliding ? SLIDING : static_cast<std::uint8_t>(bp | bm);  // (EQUATION or FIXED)
            z[i] = 0.0;
        }
        idx nb = 0;
        for (idx i = 0; i < n; ++i) {
            idx eq = kind[i] == EQUATION;
            index[nb] = i;
            pos[i] = eq * (nb + 1) - 1;  // (nb, or -1)
            nb += eq;
        }
        block.k = nb;
        ns = 0;
        for (idx c = 0; c < nf; ++c) {
            idx i = F[c], f = F[nf + c];
            bool sliding = kind[i] == SLIDING, in_block = kind[f] == EQUATION;
            z[i] = pick_bits(sliding & !in_block, slope[i] * z[f], z[i]);
            coupled[ns] = c;
            ns += sliding & in_block;
        }
        return true;
    }

    // The block (nb x nb) into block.a and its right-hand side -(q + M z)[index] into y().
    void build(const double* z) const {
        idx n = M.rows, nb = block.k;
        double *A = block.a, *y = block.y();
        for (idx t = 0; t < nb; ++t) {
            idx r = index[t];
            const double* row = M.row(r);
            y[t] = -(q[r] + dot(row, z, n));
            double* br = A + t * nb;
            for (idx u = 0; u < nb; ++u) br[u] = row[index[u]];
            for (idx k = 0; k < ns; ++k) {
                idx c = coupled[k], i = F[c];
                br[pos[F[nf + c]]] += slope[i] * row[i];
            }
        }
    }

    // The point of the basis into z (n entries): apply, build, factor B, solve, recover.
    // False where apply is, when B is singular or z is not finite.
    bool point(const std::uint8_t* zb, const std::uint8_t* zh, double* z) {
        if (!apply(zb, zh, z)) return false;
        if (block.k > 0) {
            build(z);
            if (!block.factor_solve_built(block.y(), block.x())) return false;
            recover(block.x(), z);
        }
        return all_finite(z, M.rows);
    }

    // x put into z at the block's rows, then each coupled z_i = slope_i z_f.
    void recover(const double* xb, double* z) const {
        for (idx t = 0; t < block.k; ++t) z[index[t]] = xb[t];
        for (idx k = 0; k < ns; ++k) {
            idx c = coupled[k];
            z[F[c]] = slope[F[c]] * z[F[nf + c]];
        }
    }

    // B x = rhs, B' x = rhs (one entry per block row) after point, by its factors.
    bool solve(const double* rhs, double* out) const { return block.solve(rhs, out); }
    bool solve_transpose(const double* rhs, double* out) const {
        return block.solve_transpose(rhs, out);
    }

    // The verdict of friction_check on the caller's z (n entries: copied into buf's z,
    // FrontLayout{n, nf, true}, then clipped there into the coupled bounds at it; w = M z + q
    // into buf's w; R and C: check_scales', there too; N = n + 2 nf as n_round).
    bool check(const double* z, double tol, double* buf, double& residual) const {
        idx n = M.rows;
        boxed::FrontLayout L{n, nf, true};
        double* zc = buf + L.z();
        if (zc != z)
            for (idx i = 0; i < n; ++i) zc[i] = z[i];
        return boxed::coupled_check(M, q, lo, hi, F, nf, L.N(), tol, buf, residual);
    }
};

// The MLCP kind: the stacked N x N system E x + e = (0, w) of _mlcp (n equations and free
// u first, then the m = N - n pairs v >= 0, w >= 0), a basis of MLCPToLCP's reduction: every
// determined u basic (all but the reduction's undetermined ones, set to 0), v_k basic where
// v_basic[k], the equations kept (all but the redundant ones) and w_k = 0 for each basic v_k
// (apply), so B = E[rows, cols], a block of kept rows and columns, not principal. The point
// (MLCPToLCP.basis_point's): B x = -e[rows] by linalg's refined_solve (one LU of B, two steps
// of refinement in double-double; the same function and operations as that Python routine
// called, so the same bits), x put at cols, 0 elsewhere, v clipped at 0 (recover, numpy's
// maximum's bits: +0.0 for -0.0); check: certify's check_mlcp (_certify.check_mlcp's
// numbers). solve and solve_transpose: by the LU refined_solve left (no refinement).
// work: work_size(N) doubles; ints: index_size(N); piv: 2N entries.
struct MlcpBasis {
    Mat<const double> E;
    const double* e;
    idx n;
    idx *rows, *cols;  // the block's rows and columns (apply)
    double* work;      // the block, refined_solve's work (its factors), rhs, x, lo
    idx* piv;
    BasisBlock block;  // the factors, for solve and solve_transpose

    static idx work_size(idx N) { return N * (2 * N + 5); }
    static idx index_size(idx N) { return 2 * N; }

    MlcpBasis(Mat<const double> E_, const double* e_, idx n_, idx* ints, double* work_,
              idx* piv_)
        : E(E_), e(e_), n(n_), rows(ints), cols(ints + E_.rows), work(work_), piv(piv_),
          block{E_, ints, 0, nullptr, piv_} {}

    // The block's rows and columns: redundant[i] (n flags) drops equation i, undetermined[i]
    // (n flags) drops u_i, v_basic (N - n flags) adds row and column n + k. False when the
    // counts differ (no square block).
    bool apply(const std::uint8_t* redundant, const std::uint8_t* undetermined,
               const std::uint8_t* v_basic) {
        idx N = E.rows, nr = 0, nc = 0;
        for (idx i = 0; i < n; ++i) {
            if (!redundant[i]) rows[nr++] = i;
            if (!undetermined[i]) cols[nc++] = i;
        }
        for (idx i = n; i < N; ++i)
            if (v_basic[i - n]) {
                rows[nr++] = i;
                cols[nc++] = i;
            }
        block.k = nr;
        return nr == nc;
    }

    // The point of the basis into x (N entries) after apply: build B and -e[rows], refined
    // solve, recover. False when B is singular or x is not finite (x is then 0 or garbage).
    bool point(double* x) {
        idx N = E.rows, k = block.k;
        block.factors = nullptr;
        block.pivots = nullptr;
        for (idx i = 0; i < N; ++i) x[i] = 0.0;
        if (k > 0) {
            double* K = work;
            double* f = K + k * k;  // refined_solve's k (k + 2)
            double *rhs = f + k * (k + 2), *xb = rhs + k, *lo = xb + k;
            for (idx r = 0; r < k; ++r) {
                const double* er = E.row(rows[r]);
                double* kr = K + r * k;
                for (idx c = 0; c < k; ++c) kr[c] = er[cols[c]];
                rhs[r] = -e[rows[r]];
            }
            if (!refined_solve(Mat<const double>(K, k, k), rhs, 2, xb, lo, f, piv)) return false;
            block.a = f;
            block.factors = f;
            block.pivots = piv;
            for (idx c = 0; c < k; ++c) x[cols[c]] = xb[c];
        }
        recover(x);
        return true;
    }

    // v = max(v, 0) in place (numpy's maximum's bits: 0 > v ? 0 : v, so -0.0 becomes +0.0).
    void recover(double* x) const {
        for (idx i = n; i < E.rows; ++i) x[i] = pmax(0.0, x[i]);
    }

    // B x = rhs, B' x = rhs (k entries, in rows' and cols' order) after point, by its LU.
    bool solve(const double* rhs, double* out) const { return block.solve(rhs, out); }
    bool solve_transpose(const double* rhs, double* out) const {
        return block.solve_transpose(rhs, out);
    }

    // y = E x + e (N entries, double-double) and check_mlcp's verdict.
    bool check(const double* x, double tol, double* y, double& residual) const {
        return check_mlcp(E, e, n, x, tol, y, residual);
    }
};

// The QP kind's basis system (QpBasis: apply, point, point_given, recover, solve,
// solve_transpose, numbering, check) is in qp.cpp, not here: it is a view on that file's
// QPWork and Rows (the engine's factors and caches, internal to it), its solve a null-space
// solve through them, not an LU of a block (private entry _core.qp_basis: qp::basis_seam).

}  // namespace lemke
