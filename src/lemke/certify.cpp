#include "certify.hpp"

#include <vector>

#include "multiversion.hpp"

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

}  // namespace lemke
