// The pivoting rule shared by every engine: the first pivot, the ratio test with relative ties, the
// lexicographic tie-break and Brent's cycle detector on a 64-bit basis fingerprint. A method
// supplies only numbers: the values, the entering column, entries of its basis inverse.
#pragma once
#include <cmath>
#include <cstdint>
#include <limits>

#include "budget.hpp"
#include "linalg.hpp"
#include "status.hpp"  // Status, is_stop: the one status vocabulary

namespace lemke {

constexpr double VALUE_ROUNDING = 1e-13;
constexpr double Z0_ROUNDING = 1e-11;

// The row that leaves when z0 enters first: the largest -vals[i] / col[i] over col[i] > 0,
// ties (relative) to the highest row; -1 when no entry is usable.
inline idx first_row(const double* vals, const double* col, idx m, double tie_tol) {
    double need = -INF;
    for (idx i = 0; i < m; ++i)
        if (col[i] > 0.0) need = pmax(need, -vals[i] / col[i]);
    if (need == -INF) return -1;
    idx r = -1;
    for (idx i = 0; i < m; ++i) {
        if (col[i] > 0.0) {
            double t = -vals[i] / col[i];
            if (t >= need - tie_tol * pmax(std::fabs(t), std::fabs(need))) r = i;
        }
    }
    return r;
}

inline double row_value(const double* vals, const double* mags, idx i, idx art, double z0_max) {
    double v = vals[i];
    if (i == art) return v > Z0_ROUNDING * z0_max ? v : 0.0;
    return v > VALUE_ROUNDING * mags[i] ? v : 0.0;
}

inline bool z0_leaves_harmlessly(const double* vals, const double* mags, const double* col, idx m,
                                 idx art, double z0_max) {
    double t = vals[art] / -col[art];
    double slack = Z0_ROUNDING * z0_max;
    for (idx i = 0; i < m; ++i) {
        if (i != art) {
            double change = t * col[i];
            if (change < 0.0 &&
                pmax(vals[i], 0.0) + VALUE_ROUNDING * pmax(mags[i], 0.0) + slack < -change)
                return false;
        }
    }
    return true;
}

// Each row's ratio into ratios (m doubles): NaN where the row does not block, else the
// same operations as row_value and the division.
LEMKE_ALWAYS_INLINE void blocking_ratios(const double* vals, const double* mags, const double* col,
                                         idx m, double thr, idx art, double z0_max, double* ratios) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    // a plain loop, which GCC makes a vector loop on every instruction set (masked compares
    // and selects, one vector division; written on v8d, the AVX-512F clones made the
    // compares and selects a lane at a time); the division runs in every lane, its result
    // kept where the row blocks (the number of the row-by-row rule)
    for (idx i = 0; i < m; ++i) {
        double c = col[i], v = vals[i];
        double value = v > VALUE_ROUNDING * mags[i] ? v : 0.0;
        double t = value / -c;
        ratios[i] = c < thr ? t : nan;
    }
    if (art >= 0 && art < m) {
        double c = col[art];
        ratios[art] = c < thr ? row_value(vals, mags, art, art, z0_max) / -c : nan;
    }
}

// The one-pass rule (blocking_rows) on the ratios: a branch only where a row is within the
// running bound (a few rows per ratio test), not on each row's sign (half the rows, at random).
LEMKE_ALWAYS_INLINE idx blocking_rows_scan(const double* ratios, idx m, double tie_tol, idx* cand) {
    double theta = INF, lim = INF;
    idx nc = 0;
    for (idx i = 0; i < m; ++i) {
        double t = ratios[i];
        if (t <= lim) {
            if (t < theta) {
                theta = t;
                lim = theta + tie_tol * theta;
                idx kept = 0;
                for (idx q = 0; q < nc; ++q)
                    if (ratios[cand[q]] <= lim) cand[kept++] = cand[q];
                nc = kept;
            }
            cand[nc++] = i;
        }
    }
    return theta < INF ? nc : 0;
}

// blocking_rows' answer from the ratios (blocking_ratios): below 64 rows by the one-pass
// rule on them (blocking_rows_scan), else in two more passes, their minimum theta, then the
// rows with ratio <= theta + tie_tol theta. The one-pass rule keeps exactly those rows:
// every ratio is >= 0 or NaN, so the bound only falls as theta does, a row it drops stays
// above the final bound and a row it keeps is below it; a NaN ratio never blocks.
LEMKE_ALWAYS_INLINE idx blocking_rows_vector(const double* vals, const double* mags, const double* col,
                                idx m, double thr, double tie_tol, idx* cand, idx art,
                                double z0_max, double* ratios) {
    blocking_ratios(vals, mags, col, m, thr, art, z0_max, ratios);
    if (m < 64) return blocking_rows_scan(ratios, m, tie_tol, cand);
    double theta = INF;  // (a minimum of numbers that are not NaN: exact in any order)
    idx i = 0;
#ifdef LEMKE_SIMD
    {
        simd::v8d vt = simd::splat8(INF);
        for (; i + 8 <= m; i += 8) {
            simd::v8d t = simd::load8(ratios + i);
            vt = t < vt ? t : vt;
        }
        for (int l = 0; l < 8; ++l) theta = pmin(theta, vt[l]);
    }
#endif
    for (; i < m; ++i) theta = pmin(theta, ratios[i]);
    if (!(theta < INF)) return 0;
    double lim = theta + tie_tol * theta;
    idx nc = 0;
    for (i = 0; i < m; ++i)
        if (ratios[i] <= lim) cand[nc++] = i;
    return nc;
}

// The blocking rows tied at the minimum ratio, in increasing order, into cand; returns how
// many (0: a ray). thr = -pivot_tol * max|col|. ratios: m doubles of work for the vector
// pass (blocking_rows_vector), or nullptr (one pass, row by row). Always inlined: a copy of
// its own would be baseline x86-64 in the engines' clones.
LEMKE_ALWAYS_INLINE idx blocking_rows(const double* vals, const double* mags, const double* col, idx m,
                         double thr, double tie_tol, idx* cand, idx art, double z0_max,
                         double* ratios = nullptr) {
    double theta = INF, lim = INF;
    idx nc = 0;
    if (art >= 0 && vals[art] <= Z0_ROUNDING * z0_max && std::fabs(col[art]) > -thr) {
        if (z0_leaves_harmlessly(vals, mags, col, m, art, z0_max)) {
            cand[0] = art;
            theta = 0.0;
            nc = 1;
            m = 0;
        } else {
            z0_max = 0.0;
        }
    }
    if (ratios != nullptr && m > 0)
        return blocking_rows_vector(vals, mags, col, m, thr, tie_tol, cand, art, z0_max, ratios);
    for (idx i = 0; i < m; ++i) {
        double c = col[i];
        double t = row_value(vals, mags, i, art, z0_max) / -c;
        if ((c < thr) & (t <= lim)) {
            if (t < theta) {
                theta = t;
                lim = theta + tie_tol * theta;
                idx kept = 0;
                for (idx q = 0; q < nc; ++q) {
                    idx j = cand[q];
                    if (row_value(vals, mags, j, art, z0_max) / -col[j] <= lim) cand[kept++] = j;
                }
                nc = kept;
            }
            cand[nc++] = i;
        }
    }
    return theta < INF ? nc : 0;
}

inline double lex_key(double b, double piv, double pivot_tol) {
    if (std::fabs(b) <= pivot_tol) b = 0.0;
    return b / -piv;
}

inline idx keep_lowest(idx* cand, double* keys, idx nc, double tie_tol) {
    double kmin = INF;
    for (idx c = 0; c < nc; ++c) kmin = pmin(kmin, keys[c]);
    idx kept = 0;
    for (idx c = 0; c < nc; ++c) {
        if (keys[c] <= kmin + tie_tol * pmax(std::fabs(keys[c]), std::fabs(kmin))) {
            cand[kept] = cand[c];
            keys[kept] = keys[c];
            ++kept;
        }
    }
    return kept;
}

inline idx largest_pivot(const idx* cand, const double* col, idx nc) {
    idx best = cand[0];
    for (idx c = 1; c < nc; ++c)
        if (col[cand[c]] < col[best]) best = cand[c];
    return best;
}

// A fixed pseudo-random 64-bit key per label (splitmix64 of label + 1).
inline std::uint64_t label_key(idx lab) {
    std::uint64_t x = static_cast<std::uint64_t>(lab + 1) * 0x9E3779B97F4A7C15ULL;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
    return x ^ (x >> 31);
}

inline double unit_random(std::uint64_t key) {
    return static_cast<double>(key >> 11) * (1.0 / 9007199254740992.0);
}

// Brent's cycle detector over basis fingerprints.
struct Detector {
    std::uint64_t saved = 0, power = 0, steps = 0;
    bool repeats(std::uint64_t h) {
        if (power > 0 && h == saved) return true;
        if (steps == power) {
            saved = h;
            power = power == 0 ? 1 : power * 2;
            steps = 0;
        }
        steps += 1;
        return false;
    }
};

// The end of every pivot (pivoting.after_pivot): SOLVED when the artificial variable left,
// else the fingerprint h updated for `entering` replacing `leaving` and CYCLING when the
// basis repeats, else -1 (go on).
inline int after_pivot(idx leaving, idx entering, idx artificial, std::uint64_t& h,
                       Detector& detector) {
    if (leaving == artificial) return SOLVED;
    h ^= label_key(leaving) ^ label_key(entering);
    return detector.repeats(h) ? CYCLING : -1;
}

// The labels of a basis: basis[r] (rows), nonbasic[s] (columns), pos[label] (its row or
// column), is_basic[label].
inline idx swap_labels(idx* basis, idx* nonbasic, idx* pos, std::uint8_t* is_basic, idx r, idx s) {
    idx leaving = basis[r];
    idx entering = nonbasic[s];
    basis[r] = entering;
    nonbasic[s] = leaving;
    pos[entering] = r;
    is_basic[entering] = 1;
    pos[leaving] = s;
    is_basic[leaving] = 0;
    return leaving;
}

}  // namespace lemke
