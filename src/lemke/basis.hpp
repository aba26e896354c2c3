// The seam (issue 31, item 2): a basis on the caller's data. Each problem kind supplies one
// basis system with the same members: its basic block built from (M, q, basis) and factored
// once by the kernels' LU (linalg's eliminate: partial pivoting, two pivots per pass; no
// LAPACK), solved with it and with its transpose, the point mapped back to z (and w) and
// checked row by row by the kind's acceptance code. The systems: LcpBasis (lcp.cpp's
// basis_point and basis_point_checked; _core.lcp_basis), BoxBasis (boxed.cpp's basis_point;
// _core.box_basis), FrictionBasis (boxed.cpp's friction_point and the box front's warm
// start; _core.friction_basis), MlcpBasis (MLCPToLCP.basis_point through _core.mlcp_basis;
// refined), SupportBasis (games: _games._resolve_float through _core.game_basis) and
// KktBasis (a QP's KKT rows of an active set: _qp._polished through _core.kkt_basis;
// refined, the held variables' columns given); the QP kind's QpBasis is in qp.cpp (see the
// end of this file). Gradients and a sparse engine are to plug in here: hence the transpose
// solve.
#pragma once
#include <algorithm>
#include <cstdint>

#include "boxed.hpp"
#include "certify.hpp"
#include "games.hpp"
#include "linalg.hpp"
#include "qp.hpp"

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

// numpy's sum of a float64 vector (add.reduce's pairwise_sum, numpy 2.x: under 8 entries a
// running sum from 0.0; up to 128 eight running sums, added ((0+1)+(2+3))+((4+5)+(6+7)), the
// rest one by one; beyond, halves of multiples of 8 summed apart), bit for bit: the games
// kind's point is normalized by it, as _games._resolve_float's numpy code was.
inline double numpy_sum(const double* a, idx n) {
    if (n < 8) {
        double res = 0.0;
        for (idx i = 0; i < n; ++i) res += a[i];
        return res;
    }
    if (n <= 128) {
        double r[8];
        for (idx j = 0; j < 8; ++j) r[j] = a[j];
        idx i = 8;
        for (; i < n - n % 8; i += 8)
            for (idx j = 0; j < 8; ++j) r[j] += a[i + j];
        double res = ((r[0] + r[1]) + (r[2] + r[3])) + ((r[4] + r[5]) + (r[6] + r[7]));
        for (; i < n; ++i) res += a[i];
        return res;
    }
    idx n2 = n / 2;
    n2 -= n2 % 8;
    return numpy_sum(a, n2) + numpy_sum(a + n2, n - n2);
}

// The games kind (named so as not to clash with Python's GameBasis): a vertex pair of the
// best-response polytopes (A, B m x n; labels 0..m-1 the row actions, m..m+n-1 the column
// actions), given as P's n basic labels then Q's m (the kernels' final labels, or a
// GameBasis's x_basic + y_basic). apply reads the supports and tight sets off them: S the
// row actions basic in P (x's support) and J the columns whose slack is not basic in P (the
// column player's best responses), T the columns basic in Q (y's support) and I the rows
// whose slack is not basic in Q, each ascending (as _games._supports). It refuses |S| != |J|,
// |T| != |I| or an empty support. The two bordered blocks (build), one per player:
//   x's: [B[S, J]' -1; 1' 0] (rows J then the sum row, columns S then the value v), and
//   y's: [A[I, T]  -1; 1' 0] (rows I then the sum row, columns T then u),
// each solved for the right-hand side (0, ..., 0, 1) by the kernels' LU (BasisBlock: no
// LAPACK, no refinement). recover: x_S, y_T put into x, y (0 elsewhere); a weight below
// -CLIP refuses the point, the others clipped at 0 (numpy's maximum: -0.0 gives +0.0) and
// each strategy divided by its numpy_sum. check: games::check on the caller's payoffs.
// solve and solve_transpose: the block-diagonal system diag(x's block, y's block) on a
// stacked vector (|S| + 1 entries, then |T| + 1). The point's bits are not those of the
// numpy routine it replaced (numpy.linalg.solve: OpenBLAS's LAPACK, whose kernels, and so
// bits, depend on the CPU); they are the same on every instruction set.
// work: work_size(m, n) doubles; ints: index_size(m, n); piv: nullptr or piv_size(m, n).
struct SupportBasis {
    Mat<const double> A, B;
    idx *S, *J, *T, *I;  // the supports and tight sets (apply)
    idx ks = 0, kt = 0;  // |S| = |J|, |T| = |I|
    bool negative = false;  // point refused by recover: a weight below -CLIP
    BasisBlock bx, by;      // the bordered blocks, ks + 1 and kt + 1 rows
    static constexpr double CLIP = 1e-12;

    static idx work_size(idx m, idx n) {
        idx k = std::min(m, n) + 1;
        return 2 * k * (k + 2);
    }
    static idx index_size(idx m, idx n) { return 3 * (m + n); }
    static idx piv_size(idx m, idx n) { return 4 * (std::min(m, n) + 1); }

    SupportBasis(Mat<const double> A_, Mat<const double> B_, double* work, idx* ints,
                 idx* piv = nullptr)
        : A(A_), B(B_), S(ints + (A_.rows + A_.cols)), J(S + A_.rows), T(J + A_.cols),
          I(T + A_.cols), bx{B_, S, 0, work, piv}, by{A_, T, 0, work, piv}, marks(ints) {
        idx k = std::min(A_.rows, A_.cols) + 1;
        by.a = work + k * (k + 2);
        if (piv != nullptr) by.piv = piv + 2 * k;
    }

    // S, J, T, I from P's n labels and Q's m (each in [0, m + n): the caller checks).
    // False when |S| != |J|, |T| != |I| or a support is empty (no square blocks).
    bool apply(const idx* labels) {
        idx m = A.rows, n = A.cols, L = m + n;
        for (idx c = 0; c < L; ++c) marks[c] = 0;
        for (idx t = 0; t < n; ++t) marks[labels[t]] |= 1;      // basic in P
        for (idx t = n; t < L; ++t) marks[labels[t]] |= 2;      // basic in Q
        ks = kt = 0;
        idx kj = 0, ki = 0;
        for (idx i = 0; i < m; ++i) {
            if (marks[i] & 1) S[ks++] = i;
            if (!(marks[i] & 2)) I[ki++] = i;
        }
        for (idx j = 0; j < n; ++j) {
            if (!(marks[m + j] & 1)) J[kj++] = j;
            if (marks[m + j] & 2) T[kt++] = j;
        }
        bool square = ks == kj && kt == ki && ks > 0 && kt > 0;
        bx.k = square ? ks + 1 : 0;
        by.k = square ? kt + 1 : 0;
        return square;
    }

    // The two bordered blocks into bx.a and by.a and their right-hand sides into y().
    void build() const {
        bordered(B, J, S, ks, true, bx);
        bordered(A, I, T, kt, false, by);
    }

    // The point of the basis into x (m) and y (n) after apply: build, factor and solve each
    // block, recover. False when a block is singular or its solution not finite, or recover
    // refuses (negative is then set).
    bool point(double* x, double* y) {
        negative = false;
        build();
        if (!bx.factor_solve_built(bx.y(), bx.x())) return false;
        if (!by.factor_solve_built(by.y(), by.x())) return false;
        return recover(bx.x(), by.x(), x, y);
    }

    // x_S and y_T (the blocks' solutions, their last entries the values) mapped back to x
    // and y: refused (false, negative set) when a weight is below -CLIP; else clipped at 0
    // and normalized.
    bool recover(const double* xs, const double* yt, double* x, double* y) {
        idx m = A.rows, n = A.cols;
        for (idx i = 0; i < m; ++i) x[i] = 0.0;
        for (idx j = 0; j < n; ++j) y[j] = 0.0;
        for (idx c = 0; c < ks; ++c) x[S[c]] = xs[c];
        for (idx c = 0; c < kt; ++c) y[T[c]] = yt[c];
        for (idx c = 0; c < ks; ++c) negative |= xs[c] < -CLIP;
        for (idx c = 0; c < kt; ++c) negative |= yt[c] < -CLIP;
        if (negative) return false;
        normalize(x, m);
        normalize(y, n);
        return true;
    }

    // diag(x's block, y's block) v = rhs, or its transpose (ks + kt + 2 entries: x's block's
    // rows first), after point, by its factors.
    bool solve(const double* rhs, double* out) const {
        return bx.solve(rhs, out) && by.solve(rhs + bx.k, out + bx.k);
    }
    bool solve_transpose(const double* rhs, double* out) const {
        return bx.solve_transpose(rhs, out) && by.solve_transpose(rhs + bx.k, out + bx.k);
    }

    // games::check on the caller's payoffs: out (3) gets (regret, row payoff, column payoff).
    bool check(const double* x, const double* y, double tol, double* out) const {
        return games::check(A, B, x, y, tol, out);
    }

  private:
    idx* marks;  // m + n label marks (apply's)

    // A block [P[rows, cols] or its transpose, -1; 1' 0] and the right-hand side (0, 1):
    // with `transposed` the entry (r, c) is P[cols[c], rows[r]] (x's block, B[S, J]'), else
    // P[rows[r], cols[c]] (y's block, A[I, T]).
    static void bordered(Mat<const double> P, const idx* rows, const idx* cols, idx k,
                         bool transposed, const BasisBlock& b) {
        idx K = k + 1;
        double* a = b.a;
        for (idx r = 0; r < k; ++r) {
            double* ar = a + r * K;
            if (transposed) {
                for (idx c = 0; c < k; ++c) ar[c] = P.row(cols[c])[rows[r]];
            } else {
                const double* pr = P.row(rows[r]);
                for (idx c = 0; c < k; ++c) ar[c] = pr[cols[c]];
            }
            ar[k] = -1.0;
        }
        double* last = a + k * K;
        for (idx c = 0; c < k; ++c) last[c] = 1.0;
        last[k] = 0.0;
        double* yb = b.y();
        for (idx r = 0; r < k; ++r) yb[r] = 0.0;
        yb[k] = 1.0;
    }

    // v clipped at 0 (numpy's maximum(v, 0.0): +0.0 for -0.0) and divided by its numpy_sum.
    static void normalize(double* v, idx len) {
        for (idx i = 0; i < len; ++i) v[i] = pmax(0.0, v[i]);
        double s = numpy_sum(v, len);
        for (idx i = 0; i < len; ++i) v[i] /= s;
    }
};

// The QP's KKT rows of an active set on the caller's data (_qp._polished's system): a basis
// of QPToMLCP's KKT MLCP (v flags over its pairs: the shifted x' (nn), the rows of G (m0),
// the boxed variables' upper multipliers (nbox); _reductions.qp_mlcp numbers them) says
// which constraints hold with equality (apply): a row of G whose multiplier is basic (S), a
// bound whose shifted x' is not basic (x at x0: lb where finite, else ub) or whose upper
// multiplier is basic (x at ub), every fixed variable (lb = ub); the variables held (B) at
// their bound, the others free here (F). The KKT rows
//     P x + A'y + G_S'z_S + I_B'zb_B = -q,   A x = b,   G_S x = h_S,   x_B = bound_B
// are solved for x_F, y, z_S with x_B given: the rows of F, A and G_S (K: columns x_F, y,
// z_S, then x_B, given), by linalg's refined_solve with `given` (one LU of the square block,
// three steps of refinement in double-double, x_B's columns in every residual; the same
// function, operations and order as _polished's numpy code called, so the same bits). The
// point (recover): x, the bound multipliers zb_B = -(P_B. x + q_B + A_B'y + G_SB'z_S) at the
// exact solution (sol + lo, summed in double-double by residual2 over the row [KB, KB]),
// the multipliers at the solve's rounding level (|.| <= eps max|.|) made +0.0; check:
// qp::kkt_check (the row-wise KKT check, and kkt's statistics). solve and solve_transpose:
// by the LU refined_solve left (the square block K[:, :s], s = |F| + p0 + |S|; no
// refinement). ints: index_size(n, m0); bound: n doubles; work: work_size() doubles after
// apply; piv: 2 rows() entries.
struct KktBasis {
    qp::Data d;
    idx nn = 0, nbox = 0;        // the shifted variables, the boxed ones among them
    idx nf = 0, nh = 0, ns = 0;  // |F|, |B|, |S| (apply)
    idx *F, *B, *S;              // the free and the held variables, the active rows of G
    double* bound;               // the bound x_j is held at, NaN where it is free
    double* work = nullptr;
    idx* piv = nullptr;
    BasisBlock block;            // the factors, for solve and solve_transpose

    static idx index_size(idx n, idx m0) { return 2 * n + m0; }

    KktBasis(const qp::Data& d_, idx* ints, double* bound_)
        : d(d_), F(ints), B(ints + d_.n()), S(ints + 2 * d_.n()), bound(bound_),
          block{Mat<const double>(), nullptr, 0, nullptr} {
        for (idx j = 0; j < d.n(); ++j) {  // (QPToMLCP._kinds)
            bool lo = std::fabs(d.lb[j]) < INF, up = std::fabs(d.ub[j]) < INF;
            if ((lo || up) && !(lo && up && d.lb[j] == d.ub[j])) {
                ++nn;
                nbox += lo && up;
            }
        }
    }

    // The KKT MLCP's pairs (v's length); the block's rows s and K's columns (s + |B|).
    idx pairs() const { return nn + d.m0() + nbox; }
    idx rows() const { return nf + d.p0() + ns; }
    idx cols() const { return d.n() + d.p0() + ns; }
    // K, rhs, x (the solution, then x_B), lo, refined_solve's work, a row of [KB, KB], the
    // point and exact lo (2 cols each), the multipliers.
    idx work_size() const {
        idx s = rows(), c = cols();
        return s * c + 2 * s + c + s * (s + 2) + 4 * c + (c - nf);
    }

    // The active set of the basis v (pairs() flags): bound, F, B and S.
    void apply(const std::uint8_t* v) {
        idx n = d.n(), m0 = d.m0(), t = 0, box = 0;
        for (idx j = 0; j < n; ++j) {
            double l = d.lb[j], u = d.ub[j];
            bool lo = std::fabs(l) < INF, up = std::fabs(u) < INF;
            double at = std::numeric_limits<double>::quiet_NaN();
            if (lo && up && l == u) {
                at = l;  // fixed
            } else if (lo || up) {
                if (!v[t]) at = lo ? l : u;  // x' not basic: x at x0
                if (lo && up) {
                    if (v[nn + m0 + box]) at = u;  // the upper multiplier basic
                    ++box;
                }
                ++t;
            }
            bound[j] = at;
        }
        ns = 0;
        for (idx i = 0; i < m0; ++i)
            if (v[nn + i]) S[ns++] = i;
        nf = nh = 0;
        for (idx j = 0; j < n; ++j) {
            if (bound[j] != bound[j])
                F[nf++] = j;
            else
                B[nh++] = j;
        }
        block.k = rows();
    }

    // The point of the active set into x (n), y (p0), z (m0), zb (n) after apply: K and its
    // right-hand side (-q_F, b, h_S), x_B given, refined_solve (3 steps), recover. False
    // when K's square block is singular or the solution is not finite.
    bool point(double* x, double* y, double* z, double* zb) {
        idx p = d.p0(), s = rows(), c = cols();
        block.factors = nullptr;
        block.pivots = nullptr;
        double* K = work;
        double *rhs = K + s * c, *xs = rhs + s, *lo = xs + c, *f = lo + s;
        for (idx r = 0; r < nf; ++r) {  // stationarity on F: P_FF, A_F', G_SF', P_FB (whole rows)
            idx j = F[r];
            const double* pr = d.P.row(j);
            double* kr = K + r * c;
            for (idx t = 0; t < nf; ++t) kr[t] = pr[F[t]];
            for (idx i = 0; i < p; ++i) kr[nf + i] = d.A(i, j);
            for (idx i = 0; i < ns; ++i) kr[nf + p + i] = d.G(S[i], j);
            for (idx t = 0; t < nh; ++t) kr[s + t] = pr[B[t]];
            rhs[r] = -d.q[j];
        }
        for (idx i = 0; i < p + ns; ++i) {  // A x = b, G_S x = h_S: A_F, A_B (G_S's)
            bool eq = i < p;
            const double* ar = eq ? d.A.row(i) : d.G.row(S[i - p]);
            double* kr = K + (nf + i) * c;
            for (idx t = 0; t < nf; ++t) kr[t] = ar[F[t]];
            for (idx t = nf; t < s; ++t) kr[t] = 0.0;  // (y's and z_S's columns)
            for (idx t = 0; t < nh; ++t) kr[s + t] = ar[B[t]];
            rhs[nf + i] = eq ? d.b[i] : d.h[S[i - p]];
        }
        for (idx t = 0; t < nh; ++t) xs[s + t] = bound[B[t]];
        if (!refined_solve(Mat<const double>(K, s, c), rhs, 3, xs, lo, f, piv)) return false;
        block.a = f;
        block.factors = f;
        block.pivots = piv;
        recover(xs, lo, x, y, z, zb);
        return true;
    }

    // The solution (xs: x_F, y, z_S; lo its low parts) mapped to (x, y, z, zb): x_B its
    // bounds, zb_B from the rows of B at xs + lo, the multipliers at rounding level zeroed.
    void recover(const double* xs, const double* lo, double* x, double* y, double* z,
                 double* zb) const {
        idx n = d.n(), p = d.p0(), s = rows(), c = cols(), nm = c - nf;
        double* row = work + s * c + 2 * s + c + s * (s + 2);  // 2c
        double* xx = row + 2 * c;                             // 2c: x, y, z_S, then their lo
        double* mult = xx + 2 * c;                            // y, z_S, -zb_B
        for (idx r = 0; r < nf; ++r) x[F[r]] = xs[r];
        for (idx t = 0; t < nh; ++t) x[B[t]] = bound[B[t]];
        for (idx j = 0; j < n; ++j) {
            xx[j] = x[j];
            xx[c + j] = 0.0;
        }
        for (idx r = 0; r < nf; ++r) xx[c + F[r]] = lo[r];
        for (idx i = 0; i < p + ns; ++i) {
            xx[n + i] = xs[nf + i];
            xx[c + n + i] = lo[nf + i];
            mult[i] = xs[nf + i];
        }
        for (idx t = 0; t < nh; ++t) {  // zb_B = -(row of [KB, KB]) . xx - q_j
            idx j = B[t];
            const double* pr = d.P.row(j);
            for (idx k = 0; k < n; ++k) row[k] = pr[k];
            for (idx i = 0; i < p; ++i) row[n + i] = d.A(i, j);
            for (idx i = 0; i < ns; ++i) row[n + p + i] = d.G(S[i], j);
            for (idx k = 0; k < c; ++k) row[c + k] = row[k];
            double g;
            residual2(Mat<const double>(row, 1, 2 * c), xx, 2 * c, d.q + j, &g);
            mult[p + ns + t] = -g;
        }
        // (_npc.absmax's NaN: nothing zeroed)
        bool nan = false;
        for (idx i = 0; i < nm; ++i) nan |= mult[i] != mult[i];
        if (!nan) {
            double floor = EPS * absmax(mult, nm);
            for (idx i = 0; i < nm; ++i)
                if (std::fabs(mult[i]) <= floor) mult[i] = 0.0;
        }
        for (idx i = 0; i < p; ++i) y[i] = mult[i];
        for (idx i = 0; i < d.m0(); ++i) z[i] = 0.0;
        for (idx i = 0; i < ns; ++i) z[S[i]] = mult[p + i];
        for (idx j = 0; j < n; ++j) zb[j] = 0.0;
        for (idx t = 0; t < nh; ++t) zb[B[t]] = mult[p + ns + t];
    }

    // K[:, :s] x = rhs, K[:, :s]' x = rhs (s entries: rows F, A, G_S; columns x_F, y, z_S)
    // after point, by its LU.
    bool solve(const double* rhs, double* out) const { return block.solve(rhs, out); }
    bool solve_transpose(const double* rhs, double* out) const {
        return block.solve_transpose(rhs, out);
    }

    // qp::kkt_check's verdict at tol, stats (4): primal, dual, gap, obj.
    bool check(const double* x, const double* y, const double* z, const double* zb, double tol,
               double* stats) const {
        return qp::kkt_check(d, x, y, z, zb, tol, stats);
    }
};

// The QP kind's basis system (QpBasis: apply, point, point_given, recover, solve,
// solve_transpose, numbering, check) is in qp.cpp, not here: it is a view on that file's
// QPWork and Rows (the engine's factors and caches, internal to it), its solve a null-space
// solve through them, not an LU of a block (private entry _core.qp_basis: qp::basis_seam).

}  // namespace lemke
