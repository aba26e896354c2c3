#include "certify.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

#include "boxed.hpp"
#include "games.hpp"
#include "multiversion.hpp"
#include "qp.hpp"
#include "reductions.hpp"
#include "simd.hpp"

namespace lemke {

// The largest z_i that counts as zero: min_j (t rows[j] + floors[j]) / |M_ji| over M_ji != 0.
double zero_size(Mat<const double> M, const double* rows, idx i, double t, const double* floors) {
    double s = INF;
    for (idx j = 0; j < M.rows; ++j) {
        double a = std::fabs(M(j, i));
        if (a > 0.0) s = pmin(s, (t * rows[j] + floors[j]) / a);
    }
    return s < INF ? s : 0.0;
}

// Compiled per instruction set, with each row's dot product inlined (dot_and_size_lanes,
// the same operations): every solve ends here.
LEMKE_CLONES
bool check_rows(Mat<const double> M, const double* q, const double* z, double tol, double* w,
                const double* R, double* work, bool early, double& residual) {
    idx n = M.rows;
    double t = tol + static_cast<double>(n + 2) * EPS;
    double* rows = work;
    double* floors = work + n;
    double big = 0.0, data = 1.0, q_top = 0.0;
    residual = 0.0;
    for (idx i = 0; i < n; ++i) q_top = pmax(q_top, R[i] * std::fabs(q[i]));
    double pair[4];  // rows i and i + 1: their dot products and sizes (dot_and_size_lanes2)
    for (idx i = 0; i < n; ++i) {
        double mz, size;
        if (i % 2 == 0 && i + 1 < n) {
            dot_and_size_lanes2(M.row(i), M.row(i + 1), z, n, pair);
            mz = pair[0];
            size = pair[2];
        } else if (i % 2 == 1) {
            mz = pair[1];
            size = pair[3];
        } else {
            dot_and_size_lanes(M.row(i), z, n, mz, size);
        }
        w[i] = q[i] + mz;
        rows[i] = size + std::fabs(q[i]);
        floors[i] = static_cast<double>(n + 2) * EPS * q_top / R[i];
        big = pmax(big, R[i] * size);
        data = pmax(data, R[i] * std::fabs(q[i]));
        if (early) {
            double wi = w[i];
            if (wi < -(t * rows[i] + floors[i]) || !(wi == wi && z[i] == z[i])) return false;
        }
    }
    bool ok = EPS * big <= CERTIFIABLE * t * data;
    if (early && !ok) return false;
    for (idx i = 0; i < n; ++i) {
        double zi = z[i], wi = w[i];
        residual = pmax(residual, std::fabs(pmin(zi, wi)));
        double s_w = t * rows[i] + floors[i];
        if (wi < -s_w || !(wi == wi && zi == zi)) {
            ok = false;
        } else if (zi < 0.0 || (zi > 0.0 && std::fabs(wi) > s_w)) {
            if (std::fabs(zi) > zero_size(M, rows, i, t, floors)) ok = false;
        }
        if (early && !ok) {
            residual = 0.0;
            return false;
        }
    }
    return ok;
}

bool lcp_check(Mat<const double> M, const double* q, const double* z, double tol, double* w,
               double& residual) {
    idx n = M.rows;
    thread_local std::vector<double> work;
    work.resize(static_cast<std::size_t>(6 * n));
    double* R = work.data();
    double* C = R + n;
    double* scratch = C + n;  // equilibrate's 2n, then check_rows' 2n
    equilibrate(M, q, R, C, scratch);
    return check_rows(M, q, z, tol, w, R, scratch + 2 * n, false, residual);
}

bool lcp_ray_check(Mat<const double> M, const double* q, const double* d, const double* z,
                   double z0, const double* ray, double tol) {
    idx n = M.rows;
    thread_local std::vector<double> work;
    work.resize(static_cast<std::size_t>(4 * n));
    double* R = work.data();
    double* C = R + n;
    equilibrate(M, q, R, C, C + n);
    return ray_check(M, q, d, z, z0, ray, tol, R, C);
}

namespace {

// numpy's np.abs(a).max() (0 for no entries): a NaN anywhere gives NaN (the first one's
// absolute value, as numpy's reduction returns the NaN it meets).
double np_absmax(const double* a, idx k, double m = 0.0) {
    for (idx i = 0; i < k; ++i) {
        double v = std::fabs(a[i]);
        if (v != v) return v;
        m = pmax(m, v);
    }
    return m;
}

}  // namespace

bool check_mlcp(Mat<const double> E, const double* e, idx n, const double* x, double tol,
                double* y, double& residual) {
    idx N = E.rows;
    residual2(E, x, N, e, y);
    double e_max = np_absmax(e, N);
    double E_max = 0.0;
    for (idx r = 0; r < N && E_max == E_max; ++r) E_max = np_absmax(E.row(r), N, E_max);
    double x_max = np_absmax(x, N);
    double s_z = tol * pmax(x_max, E_max > 0.0 ? e_max / E_max : 0.0);
    double s_w = tol * pmax(e_max, E_max) + 4.0 * static_cast<double>(N) * EPS_EXT * E_max * x_max;
    double res_eq = np_absmax(y, n);
    // A point so large that rounding it to double moves E x by far more than the tolerance
    // cannot be certified.
    bool certifiable = EPS * E_max * x_max <= CERTIFIABLE * tol * pmax(e_max, E_max);
    bool all = true;
    double mins = 0.0;
    bool mins_nan = false;
    for (idx i = n; i < N; ++i) {
        double v = x[i], w = y[i];
        all &= v >= -s_z && w >= -s_w && (v <= s_z || std::fabs(w) <= s_w);
        double m = std::fabs(v <= w || v != v ? v : w);  // np.minimum's NaN rule
        if (!mins_nan) {
            if (m != m) {
                mins = m;
                mins_nan = true;
            } else {
                mins = pmax(mins, m);
            }
        }
    }
    residual = pmax(res_eq, mins);
    return certifiable && res_eq <= s_w && all;
}

bool ray_check(Mat<const double> M, const double* q, const double* d, const double* z, double z0,
               const double* ray, double tol, const double* R, const double* C) {
    idx n = M.rows;
    double g = static_cast<double>(n + 3) * EPS;
    double t = tol + g;
    if (!(z0 == z0)) return false;
    for (idx j = 0; j < n + 1; ++j)
        if (!(std::fabs(ray[j]) < INF)) return false;
    thread_local std::vector<double> work;
    work.resize(static_cast<std::size_t>(8 * n + 1));
    double* dz = work.data();
    double* floors = dz + n + 1;
    double* no_floor = floors + n;
    double* ru = no_floor + n;
    double* rdu = ru + n;
    double* u = rdu + n;
    double* w = u + n;
    double* du = w + n;
    double d_max = 0.0, d_top = 0.0;
    for (idx i = 0; i < n; ++i) {
        d_max = pmax(d_max, std::fabs(d[i]));
        d_top = pmax(d_top, R[i] * std::fabs(d[i]));
    }
    double top = std::fabs(ray[n]) * d_top;
    for (idx j = 0; j < n; ++j) top = pmax(top, std::fabs(ray[j]) / C[j]);
    bool nonzero = false;
    for (idx j = 0; j < n; ++j) {
        dz[j] = std::fabs(ray[j]) / C[j] > g * top ? ray[j] : 0.0;
        nonzero |= dz[j] != 0.0;
    }
    if (!nonzero) return false;  // the primary ray: no certificate
    double mdz = 0.0;
    for (idx i = 0; i < n; ++i) {  // (M dz and its sizes, kept in du and rdu for below)
        row_dot_and_size(M.row(i), dz, n, du[i], rdu[i]);
        mdz = pmax(mdz, rdu[i]);
    }
    dz[n] = std::fabs(ray[n]) * d_max > g * mdz ? ray[n] : 0.0;
    double dz0 = dz[n];
    if (dz0 < 0.0) return false;
    double q_top = 0.0;
    for (idx i = 0; i < n; ++i) q_top = pmax(q_top, R[i] * std::fabs(q[i]));
    for (idx i = 0; i < n; ++i) {
        floors[i] = g * q_top / R[i];
        no_floor[i] = 0.0;
    }
    for (idx i = 0; i < n; ++i) {
        double mz, sz;
        row_dot_and_size(M.row(i), z, n, mz, sz);
        w[i] = q[i] + mz;
        u[i] = w[i] + d[i] * z0;
        ru[i] = std::fabs(q[i]) + sz + std::fabs(d[i] * z0);
        du[i] = du[i] + d[i] * dz0;
        rdu[i] = rdu[i] + std::fabs(d[i] * dz0);
    }
    for (idx i = 0; i < n; ++i) {
        double s_u = t * ru[i] + floors[i];
        double s_du = t * rdu[i];
        if (!(u[i] >= -s_u && du[i] >= -s_du)) return false;
        bool flat = std::fabs(u[i]) <= s_u && std::fabs(du[i]) <= s_du;
        double zi = z[i], di = dz[i];
        if ((zi < 0.0 || (zi > 0.0 && !flat)) && std::fabs(zi) > zero_size(M, ru, i, t, floors))
            return false;
        if ((di < 0.0 || (di > 0.0 && !flat)) && std::fabs(di) > zero_size(M, rdu, i, t, no_floor))
            return false;
        if (di > 0.0 && !(w[i] < -s_u) && std::fabs(di) > zero_size(M, rdu, i, t, no_floor))
            return false;
    }
    return true;
}

// ----------------------------------------------------------------------------- box LCPs
// (moved whole from boxed.cpp: the same operations in the same order)
namespace boxed {

namespace {

// The rows whose rounding box_check allows for; the check itself (see the header). Compiled
// per instruction set, as check_rows: every box solve ends here.
LEMKE_CLONES
bool box_check_in(Mat<const double> M, const double* q, const double* lo, const double* hi,
                  const double* z, double tol, double* w, const double* R, idx n_round,
                  double& residual, double* work3) {
    idx n = M.rows;
    idx nr = n > n_round ? n : n_round;
    double t = tol + static_cast<double>(nr + 2) * EPS;
    double* rows = work3;
    double* floors = work3 + n;
    double* p = work3 + 2 * n;
    bool p_zero = true;
    double q_top = 0.0;
    for (idx i = 0; i < n; ++i) {
        p[i] = pmin(pmax(0.0, lo[i]), hi[i]);
        p_zero = p_zero && p[i] == 0.0;
        q_top = pmax(q_top, R[i] * std::fabs(q[i]));
    }
    double big = 0.0, data = 1.0;
    bool z_zero = !nonzero(z, n);
    double mz[2] = {0.0, 0.0}, size[2] = {0.0, 0.0}, pd[2], psize[2] = {0.0, 0.0};
    for (idx i = 0; i < n; ++i) {
        idx h = i % 2;  // rows i and i + 1 from even i (pair_rows)
        if (h == 0) {
            if (!z_zero) pair_rows(M, z, i, mz, size);
            if (!p_zero) pair_rows(M, p, i, pd, psize);
        }
        w[i] = q[i] + mz[h];
        rows[i] = size[h] + std::fabs(q[i]);
        floors[i] = div_exact(static_cast<double>(nr + 2) * EPS * q_top, R[i]);
        big = pmax(big, R[i] * size[h]);
        data = pmax(data, R[i] * (std::fabs(q[i]) + psize[h]));
    }
    bool ok = EPS * big <= CERTIFIABLE * t * data;
    residual = 0.0;
    for (idx i = 0; i < n; ++i) {
        double zi = z[i], wi = w[i];
        if (!(zi == zi && wi == wi)) {
            ok = false;
            residual = NAN;
            continue;
        }
        residual = pmax(residual, std::fabs(zi - pmin(pmax(zi - wi, lo[i]), hi[i])));
        if (lo[i] == hi[i]) {
            if (zi != lo[i]) ok = false;
            continue;
        }
        double s_w = t * rows[i] + floors[i];
        double off = pmax(lo[i] - zi, zi - hi[i]);
        if (wi > s_w) off = pmax(off, zi - lo[i]);
        if (wi < -s_w) off = pmax(off, hi[i] - zi);
        if (off > 0.0 && off > zero_size(M, rows, i, t, floors)) ok = false;
    }
    return ok;
}

// check_scales with its 4n doubles of work given; `kept` (not null): through
// equilibrate_finite_kept (the same scales: M is finite here, prologue), M's entry in *kept.
void check_scales_in(Mat<const double> M, const double* q, const double* lo, const double* hi,
                     double* R, double* C, double* work4, KeptMatrix** kept = nullptr) {
    idx n = M.rows;
    double* qs = work4;
    double* p = work4 + n;
    bool p_zero = true;
    for (idx i = 0; i < n; ++i) {
        p[i] = pmin(pmax(0.0, lo[i]), hi[i]);
        p_zero = p_zero && p[i] == 0.0;
    }
    // p = 0 (every lo <= 0 <= hi): q itself, no copy (q + M 0 is q: the same scales)
    if (!p_zero)
        for (idx i = 0; i < n; ++i) qs[i] = q[i] + dot(M.row(i), p, n);
    const double* qe = p_zero ? q : qs;
    // (qe not finite: equilibrate_finite_kept refuses before any sweep; equilibrate's scales)
    if (!(kept && equilibrate_finite_kept(M, qe, R, C, work4 + 2 * n, *kept)))
        equilibrate(M, qe, R, C, work4 + 2 * n);
}

}  // namespace

bool box_check(Mat<const double> M, const double* q, const double* lo, const double* hi,
               const double* z, double tol, double* w, const double* R, idx n_round,
               double& residual) {
    double* work3 = thread_work().check_area(3 * M.rows);
    return box_check_in(M, q, lo, hi, z, tol, w, R, n_round, residual, work3);
}

void check_scales(Mat<const double> M, const double* q, const double* lo, const double* hi,
                  double* R, double* C) {
    double* work4 = thread_work().check_area(4 * M.rows);
    check_scales_in(M, q, lo, hi, R, C, work4);
}

void check_scales_kept(Mat<const double> M, const double* q, const double* lo,
                       const double* hi, double* R, double* C, KeptMatrix*& kept) {
    double* work4 = thread_work().check_area(4 * M.rows);
    check_scales_in(M, q, lo, hi, R, C, work4, &kept);
}

bool is_ray(Mat<const double> M, const double* q, const double* lo, const double* hi,
            const double* d, const double* z, double z0, const double* ray, double tol) {
    idx n = M.rows;
    if (!(all_finite(ray, n + 1) && std::fabs(z0) < INF && z0 >= 0.0)) return false;
    double g = static_cast<double>(n + 3) * EPS;
    double t = tol + g;
    double* dz = thread_work().check_area(n);
    double top = 0.0;
    for (idx i = 0; i < n; ++i) top = pmax(top, std::fabs(ray[i]));
    for (idx i = 0; i < n; ++i) dz[i] = std::fabs(ray[i]) > g * top ? ray[i] : 0.0;
    double dz0 = std::fabs(ray[n]) > g * pmax(top, 1.0) ? ray[n] : 0.0;
    if (dz0 < 0.0 || (top == 0.0 && dz0 == 0.0)) return false;
    double q_top = 0.0;
    for (idx i = 0; i < n; ++i) q_top = pmax(q_top, std::fabs(q[i]));
    double m_top;
    finite_absmax(M, m_top);
    for (idx i = 0; i < n; ++i) {
        double mz, size, mdz, dsize;
        row_dot_and_size(M.row(i), z, n, mz, size);
        row_dot_and_size(M.row(i), dz, n, mdz, dsize);
        double u = (mz + q[i]) + d[i] * z0;
        double du = mdz + d[i] * dz0;
        double su = t * ((size + std::fabs(q[i])) + std::fabs(d[i] * z0)) + g * q_top;
        double sdu = t * (dsize + std::fabs(d[i] * dz0)) + g * top * m_top;
        if (lo[i] == hi[i]) {
            if (dz[i] != 0.0) return false;
            continue;
        }
        bool at_lo = lo[i] > -INF && std::fabs(z[i] - lo[i]) <= t * pmax(std::fabs(lo[i]), 1.0) * 10;
        bool at_hi = hi[i] < INF && std::fabs(z[i] - hi[i]) <= t * pmax(std::fabs(hi[i]), 1.0) * 10;
        if (dz[i] != 0.0) {
            if ((dz[i] > 0.0 && hi[i] < INF) || (dz[i] < 0.0 && lo[i] > -INF)) return false;
            if (std::fabs(u) > su || std::fabs(du) > sdu) return false;
        } else if (at_lo) {
            if (u < -su || du < -sdu) return false;
        } else if (at_hi) {
            if (u > su || du > sdu) return false;
        } else if (std::fabs(u) > su || std::fabs(du) > sdu) {
            return false;
        }
    }
    return true;
}

// The caller's z (buf's, FrontLayout) judged with the coupled bounds at it: friction_check's
// verdict, once z is mapped back (the thread's workspace given).
bool coupled_check(Mat<const double> M, const double* q, const double* lo, const double* hi,
                   const idx* F, idx nf, idx N, double tol, double* buf, double& residual,
                   BoxedWork& W) {
    idx n = M.rows;
    FrontLayout L{n, nf, true};
    double *z = buf + L.z(), *w = buf + L.w(), *lo_in = buf + L.lo(), *hi_in = buf + L.hi();
    double *R = buf + L.row_scale(), *C = buf + L.col_scale();
    for (idx i = 0; i < n; ++i) {
        lo_in[i] = lo[i];
        hi_in[i] = hi[i];
    }
    for (idx c = 0; c < nf; ++c) {
        idx i = F[c];
        double mu = hi[i];
        lo_in[i] = -mu * z[F[nf + c]];
        hi_in[i] = mu * z[F[nf + c]];
    }
    // (check_scales then box_check, their work area looked up once: the same area)
    double* work4 = W.check_area(4 * n);
    check_scales_in(M, q, lo, hi, R, C, work4);
    for (idx i = 0; i < n; ++i) z[i] = pmin(pmax(z[i], pmin(lo_in[i], hi_in[i])), hi_in[i]);
    return box_check_in(M, q, lo_in, hi_in, z, tol, w, R, N, residual, work4);
}

// The friction index's answer from the extended one zx, judged on the caller's data
// (boxed.friction_check), into buf's caller's fields (FrontLayout).
bool friction_check(Mat<const double> M, const double* q, const double* lo, const double* hi,
                    const idx* F, idx nf, const double* zx, idx N, double tol, double* buf,
                    double& residual) {
    idx n = M.rows;
    double* z = buf + FrontLayout{n, nf, true}.z();
    reductions::FrictionBox{M, q, lo, hi, nullptr, nf}.recover(F, zx, z);
    return coupled_check(M, q, lo, hi, F, nf, N, tol, buf, residual, thread_work());
}

bool coupled_check(Mat<const double> M, const double* q, const double* lo, const double* hi,
                   const idx* F, idx nf, idx N, double tol, double* buf, double& residual) {
    return coupled_check(M, q, lo, hi, F, nf, N, tol, buf, residual, thread_work());
}

}  // namespace boxed

// ----------------------------------------------------------------------------- QPs
// (moved whole from qp.cpp: the same operations in the same order)
namespace qp {

namespace {

// dot2 of every row of M with x, c_i = -rhs[i] (with every_row false only the rows where
// rhs[i] < INF; the others are left as they are), into out: four rows at a time, each row's chains of dependent double-double
// steps in dot2's order (the same bits), the four interleaved (one row's chain is latency-bound:
// the check's rows of A and G were a tenth of a first solve at n = 100).
LEMKE_CLONES
void dot2_rows(Mat<const double> M, const double* x, const double* rhs, bool every_row, Dot2* out) {
    idx n = M.cols, i = 0;
    thread_local std::vector<idx> rows;
    rows.clear();
    for (idx t = 0; t < M.rows; ++t)
        if (every_row || rhs[t] < INF) rows.push_back(t);
    idx k = static_cast<idx>(rows.size());
    // the rows after the last four first, by dot2: a call after the vector loop left the
    // vector registers' upper halves dirty on return (GCC takes the call to have cleaned
    // them, dot2 does not), and every SSE instruction of the caller's next library then
    // paid for it (daqp 2.5x slower in the same process)
    for (idx t = k - k % 4; t < k; ++t) {
        idx row = rows[static_cast<std::size_t>(t)];
        out[row] = dot2(M.row(row), x, n, -rhs[row]);
    }
    k -= k % 4;
    for (; i + 4 <= k; i += 4) {
        const double* r[4];
        double s[4], err[4], size[4], norm[4];
        for (int q = 0; q < 4; ++q) {
            r[q] = M.row(rows[static_cast<std::size_t>(i + q)]);
            double c = -rhs[rows[static_cast<std::size_t>(i + q)]];
            s[q] = c;
            err[q] = 0.0;
            size[q] = std::fabs(c);
            norm[q] = 0.0;
        }
#ifdef LEMKE_SIMD
        // (the four rows' lanes of one vector: each lane's operations are acc2's and dot2's,
        // the fused multiply-add std::fma's, rounded once, lane by lane)
        using simd::v4d;
        auto abs4 = [](v4d v) {
            const std::int64_t m = 0x7FFFFFFFFFFFFFFFLL;
            return reinterpret_cast<v4d>(reinterpret_cast<simd::v4l>(v) & simd::v4l{m, m, m, m});
        };
        v4d vs = {s[0], s[1], s[2], s[3]}, ve = {0.0, 0.0, 0.0, 0.0};
        v4d vz = {size[0], size[1], size[2], size[3]}, vn = ve;
        for (idx j = 0; j < n; ++j) {
            v4d a = {r[0][j], r[1][j], r[2][j], r[3][j]};
            v4d b = simd::splat4(x[j]);
            v4d p = a * b, e;
            for (int q = 0; q < 4; ++q) e[q] = std::fma(a[q], b[q], -p[q]);
            v4d t = vs + p;
            v4d z = t - vs;
            v4d f = (vs - (t - z)) + (p - z);
            vs = t;
            ve = ve + (e + f);
            vz += abs4(p);
            vn += abs4(a);
        }
        for (int q = 0; q < 4; ++q) {
            s[q] = vs[q];
            err[q] = ve[q];
            size[q] = vz[q];
            norm[q] = vn[q];
        }
#else
        for (idx j = 0; j < n; ++j) {
            double xj = x[j];
            for (int q = 0; q < 4; ++q) {
                acc2(s[q], err[q], r[q][j], xj);
                size[q] += std::fabs(r[q][j] * xj);
                norm[q] += std::fabs(r[q][j]);
            }
        }
#endif
        for (int q = 0; q < 4; ++q) out[rows[static_cast<std::size_t>(i + q)]] = {s[q] + err[q], size[q], norm[q]};
    }
}

// acc[j] += a |M_ij| for every row i of M, in row order (qp.add_abs_rows): a times the
// absolute column sums of M, the floor's weights in kkt_check. Nothing when a is 0.
LEMKE_CLONES
void add_abs_rows(double* acc, idx n, double a, Mat<const double> M) {
    if (!(a > 0.0)) return;
    for (idx i = 0; i < M.rows; ++i) {
        const double* Mi = M.row(i);
        for (idx j = 0; j < n; ++j) acc[j] += a * std::fabs(Mi[j]);
    }
}

// Whether multiplier a of row Gi counts as zero: removing it moves no stationarity row j by
// more than allow[j] (qp.counts_as_zero).
inline bool counts_as_zero(double a, const double* Gi, const double* allow, idx n) {
    for (idx j = 0; j < n; ++j)
        if (!(std::fabs(a * Gi[j]) <= allow[j])) return false;
    return true;
}

// add_abs_rows, over M's nonzeros only when sp is given (the terms skipped add +0).
void add_abs(double* acc, idx n, double a, Mat<const double> M, const SparseRows* sp) {
    if (sp == nullptr) {
        add_abs_rows(acc, n, a, M);
        return;
    }
    if (!(a > 0.0)) return;
    for (idx i = 0; i < M.rows; ++i)
        for (idx t = sp->start[i]; t < sp->start[i + 1]; ++t) acc[sp->col[t]] += a * std::fabs(sp->val[t]);
}

// dot2(M_i, x, n, c), over M_i's nonzeros only when sp is given (the same size and norm; the
// same sum but perhaps the sign of a zero one, which kkt_rows reads only through |.| and
// comparisons).
LEMKE_CLONES
Dot2 row_dot2(Mat<const double> M, const SparseRows* sp, idx i, const double* x, double c) {
    const double* Mi = M.row(i);
    if (sp == nullptr) return dot2(Mi, x, M.cols, c);
    double s = c, err = 0.0, size = std::fabs(c), norm = 0.0;
    for (idx t = sp->start[i]; t < sp->start[i + 1]; ++t) {
        idx j = sp->col[t];
        double a = sp->val[t];
        acc2(s, err, a, x[j]);
        size += std::fabs(a * x[j]);
        norm += std::fabs(a);
    }
    return {s + err, size, norm};
}

}  // namespace

// kkt_check; with spP, spA, spG (solve's cache's, QPWork's, whose Ps, A, G are dt's P, A, G:
// same_matrices) the sums over P, A and G take only their nonzeros (where on) when x, y, z, zb
// are finite: a skipped term is an exact +-0 (a finite number times 0), which changes no sum
// and no error term (the errors never hold -0), only perhaps the sign of a sum that is zero,
// and no sign of a zero reaches a verdict or a stat: the residuals are read through |.|,
// comparisons and pmax from +0, and the gap's double-double sum starts at +0, to which
// x_j s_j = +-0 adds +0. The same bits as the dense loops (tests/test_qp_kkt_sparse.py
// compares them).
// (cloned: its double-double sums' std::fma is an instruction in the AVX-512 clone, a libm
// call in the others, ~250 a call; the same exact product error either way)
LEMKE_CLONES
bool kkt_rows(const Data& dt, const SparseRows* spP, const SparseRows* spA,
              const SparseRows* spG, const double* x, const double* y, const double* z,
              const double* zb, double tol, double* stats) {
    idx n = dt.n();
    double t = tol + 4.0 * EPS;
    thread_local std::vector<double> work;
    work.resize(static_cast<std::size_t>(4 * n + 1));
    double* s = work.data();
    double* err = s + n;
    double* size = s + 2 * n;
    double* allow = s + 3 * n;
    for (idx j = 0; j < n; ++j) {
        s[j] = dt.q[j];
        err[j] = 0.0;
        size[j] = std::fabs(dt.q[j]);
    }
    const SparseRows *sP = nullptr, *sA = nullptr, *sG = nullptr;
    if (spP != nullptr && all_finite(x, n) && all_finite(y, dt.p0()) && all_finite(z, dt.m0()) &&
        all_finite(zb, n)) {
        if (spP->on) sP = spP;
        if (spA->on) sA = spA;
        if (spG->on) sG = spG;
    }
    if (sP != nullptr) axpy2_sparse(s, err, size, x, dt.P, *sP);
    else axpy2_matrix(s, err, size, n, x, dt.P);
    double gap_hi = 0.0, gap_lo = 0.0;
    for (idx j = 0; j < n; ++j) {
        acc2(gap_hi, gap_lo, x[j], s[j]);
        gap_lo += x[j] * err[j];
    }
    double xPq_hi = gap_hi, xPq_lo = gap_lo;
    if (sA != nullptr) axpy2_sparse(s, err, size, y, dt.A, *sA);
    else axpy2_matrix(s, err, size, n, y, dt.A);
    if (sG != nullptr) axpy2_sparse(s, err, size, z, dt.G, *sG);
    else axpy2_matrix(s, err, size, n, z, dt.G);
    // The rounding floor (qp.kkt_check states the rule): each of x, y, z, zb is exact only to
    // f = 4 (n + 2) eps times its own largest entry; allow[j] first holds what those errors
    // move stationarity row j by, divided by f.
    double f = 4.0 * static_cast<double>(n + 2) * EPS;
    double x_top = 0.0, y_top = 0.0, z_top = 0.0, zb_top = 0.0;
    for (idx j = 0; j < n; ++j) x_top = pmax(x_top, std::fabs(x[j]));
    for (idx i = 0; i < dt.p0(); ++i) y_top = pmax(y_top, std::fabs(y[i]));
    for (idx i = 0; i < dt.m0(); ++i) z_top = pmax(z_top, std::fabs(z[i]));
    for (idx j = 0; j < n; ++j) zb_top = pmax(zb_top, std::fabs(zb[j]));
    for (idx j = 0; j < n; ++j) allow[j] = zb_top;
    add_abs(allow, n, x_top, dt.P, sP);
    add_abs(allow, n, y_top, dt.A, sA);
    add_abs(allow, n, z_top, dt.G, sG);
    bool ok = true;
    double dual = 0.0;
    for (idx j = 0; j < n; ++j) {
        double r, e;
        two_sum(s[j], zb[j], r, e);
        r += e + err[j];
        allow[j] = t * (size[j] + std::fabs(zb[j])) + f * allow[j];
        dual = pmax(dual, std::fabs(r));
        if (!(std::fabs(r) <= allow[j])) ok = false;
    }
    double floor = f * x_top;
    double primal = 0.0;
    // (the dense rows' dot2 four at a time first: the same sums, the same bits)
    thread_local std::vector<Dot2> rd;
    rd.resize(static_cast<std::size_t>(std::max(dt.p0(), dt.m0())));
    if (sA == nullptr) dot2_rows(dt.A, x, dt.b, true, rd.data());
    for (idx i = 0; i < dt.p0(); ++i) {
        Dot2 d = sA == nullptr ? rd[static_cast<std::size_t>(i)] : row_dot2(dt.A, sA, i, x, -dt.b[i]);
        primal = pmax(primal, std::fabs(d.sum));
        acc2(gap_hi, gap_lo, dt.b[i], y[i]);
        if (!(std::fabs(d.sum) <= t * d.size + floor * d.norm)) ok = false;
    }
    if (sG == nullptr) dot2_rows(dt.G, x, dt.h, false, rd.data());
    for (idx i = 0; i < dt.m0(); ++i) {
        if (!(dt.h[i] < INF)) {  // no constraint: its z_i must count as zero (either sign)
            if (z[i] != 0.0 && !counts_as_zero(z[i], dt.G.row(i), allow, n)) ok = false;
            continue;
        }
        Dot2 d = sG == nullptr ? rd[static_cast<std::size_t>(i)] : row_dot2(dt.G, sG, i, x, -dt.h[i]);
        double r = d.sum;
        double sz = t * d.size + floor * d.norm;
        primal = pmax(primal, r);
        acc2(gap_hi, gap_lo, dt.h[i], z[i]);
        double zi = z[i];
        if (!(r <= sz && zi >= 0.0)) {
            ok = false;
        } else if (zi > 0.0 && -r > sz && !counts_as_zero(zi, dt.G.row(i), allow, n)) {
            ok = false;
        }
    }
    for (idx j = 0; j < n; ++j) {
        double zj = zb[j];
        bool lo = dt.lb[j] > -INF, up = dt.ub[j] < INF;
        double s_lo = t * (std::fabs(dt.lb[j]) + std::fabs(x[j])) + floor;
        double s_up = t * (std::fabs(dt.ub[j]) + std::fabs(x[j])) + floor;
        if (lo) {
            double r = dt.lb[j] - x[j];
            primal = pmax(primal, r);
            if (zj < 0.0) acc2(gap_hi, gap_lo, dt.lb[j], zj);
            if (r > s_lo) ok = false;
        }
        if (up) {
            double r = x[j] - dt.ub[j];
            primal = pmax(primal, r);
            if (zj > 0.0) acc2(gap_hi, gap_lo, dt.ub[j], zj);
            if (r > s_up) ok = false;
        }
        bool active;
        if (dt.lb[j] == dt.ub[j]) active = true;
        else if (zj < 0.0) active = lo && x[j] - dt.lb[j] <= s_lo;
        else if (zj > 0.0) active = up && dt.ub[j] - x[j] <= s_up;
        else active = true;
        if (!active && std::fabs(zj) > allow[j]) ok = false;
        if (!(x[j] == x[j])) ok = false;
    }
    double obj_hi = xPq_hi, obj_lo = xPq_lo;
    for (idx j = 0; j < n; ++j) acc2(obj_hi, obj_lo, dt.q[j], x[j]);
    stats[0] = primal;
    stats[1] = dual;
    stats[2] = std::fabs(gap_hi + gap_lo);
    stats[3] = 0.5 * (obj_hi + obj_lo);
    return ok;
}

bool kkt_check(const Data& dt, const double* x, const double* y, const double* z,
               const double* zb, double tol, double* stats) {
    return kkt_rows(dt, nullptr, nullptr, nullptr, x, y, z, zb, tol, stats);
}

bool kkt_check_sparse(const Data& dt, const double* x, const double* y, const double* z,
                      const double* zb, double tol, double* stats) {
    SparseRows spP, spA, spG;
    spP.build(dt.P.p, dt.n(), dt.n(), true);
    spA.build(dt.A.p, dt.p0(), dt.n(), true);
    spG.build(dt.G.p, dt.m0(), dt.n(), true);
    return kkt_rows(dt, &spP, &spA, &spG, x, y, z, zb, tol, stats);
}

}  // namespace qp

// ----------------------------------------------------------------------------- games
// (moved whole from games.cpp: the same operations in the same order)
namespace games {

namespace {

idx support(const double* v, idx len, idx* index) {
    idx k = 0;
    for (idx i = 0; i < len; ++i)
        if (v[i] != 0.0) index[k++] = i;
    return k;
}

struct Regrets {
    double ra, rb, pa, pb;
};

// games.regrets: acc (n), index (max(m, n)) scratch.
Regrets regrets(Mat<const double> A, Mat<const double> B, const double* x, const double* y,
                double* acc, idx* index) {
    idx m = A.rows, n = A.cols;
    idx k = support(y, n, index);
    double best_a = -INF, pay_a = 0.0;
    for (idx i = 0; i < m; ++i) {
        const double* a = A.row(i);
        double t = 0.0;
        for (idx q = 0; q < k; ++q) {
            idx j = index[q];
            t += a[j] * y[j];
        }
        best_a = pmax(best_a, t);
        pay_a += x[i] * t;
    }
    for (idx j = 0; j < n; ++j) acc[j] = 0.0;
    k = support(x, m, index);
    for (idx q = 0; q < k; ++q) {
        idx i = index[q];
        double xi = x[i];
        const double* b = B.row(i);
        for (idx j = 0; j < n; ++j) acc[j] += b[j] * xi;
    }
    double best_b = -INF, pay_b = 0.0;
    for (idx j = 0; j < n; ++j) {
        best_b = pmax(best_b, acc[j]);
        pay_b += y[j] * acc[j];
    }
    return {best_a - pay_a, best_b - pay_b, pay_a, pay_b};
}

}  // namespace

double allowance(double lo, double hi, idx m, idx n, double tol) {
    double big = pmax(std::fabs(lo), std::fabs(hi));
    return tol * (hi - lo) + ROUNDING_SLACK * 2.2e-16 * static_cast<double>(m + n) * big;
}

// games.verdict.
bool verdict(Mat<const double> A, Mat<const double> B, const double* x, const double* y,
             double allow_a, double allow_b, double* out, double* acc, idx* index) {
    idx m = A.rows, n = A.cols;
    bool ok = true;
    double sx = 0.0;
    for (idx i = 0; i < m; ++i) {
        ok &= x[i] >= 0.0;
        sx += x[i];
    }
    double sy = 0.0;
    for (idx j = 0; j < n; ++j) {
        ok &= y[j] >= 0.0;
        sy += y[j];
    }
    ok &= std::fabs(sx - 1.0) <= 1e-12 * static_cast<double>(m) &&
          std::fabs(sy - 1.0) <= 1e-12 * static_cast<double>(n);
    Regrets r = regrets(A, B, x, y, acc, index);
    out[0] = pmax(r.ra, r.rb);
    out[1] = r.pa;
    out[2] = r.pb;
    return ok && r.ra <= allow_a && r.rb <= allow_b;
}

bool check(Mat<const double> A, Mat<const double> B, const double* x, const double* y,
           double tol, double* out) {
    idx m = A.rows, n = A.cols;
    Range ra = payoff_range(A), rb = payoff_range(B);
    thread_local std::vector<double> acc;
    thread_local std::vector<idx> index;
    acc.resize(static_cast<std::size_t>(std::max<idx>(n, 1)));
    index.resize(static_cast<std::size_t>(std::max<idx>(std::max(m, n), 1)));
    return verdict(A, B, x, y, allowance(ra.lo, ra.hi, m, n, tol),
                   allowance(rb.lo, rb.hi, m, n, tol), out, acc.data(), index.data());
}

}  // namespace games

}  // namespace lemke
