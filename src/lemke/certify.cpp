#include "certify.hpp"

namespace lemke {

namespace {

// The largest z_i that counts as zero: min_j (t rows[j] + floors[j]) / |M_ji| over M_ji != 0.
double zero_size(Mat<const double> M, const double* rows, idx i, double t, const double* floors) {
    double s = INF;
    for (idx j = 0; j < M.rows; ++j) {
        double a = std::fabs(M(j, i));
        if (a > 0.0) s = pmin(s, (t * rows[j] + floors[j]) / a);
    }
    return s < INF ? s : 0.0;
}

}  // namespace

bool check_rows(Mat<const double> M, const double* q, const double* z, double tol, double* w,
                const double* R, double* work, bool early, double& residual) {
    idx n = M.rows;
    double t = tol + static_cast<double>(n + 2) * EPS;
    double* rows = work;
    double* floors = work + n;
    double big = 0.0, data = 1.0, q_top = 0.0;
    residual = 0.0;
    for (idx i = 0; i < n; ++i) q_top = pmax(q_top, R[i] * std::fabs(q[i]));
    for (idx i = 0; i < n; ++i) {
        double mz, size;
        row_dot_and_size(M.row(i), z, n, mz, size);
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

}  // namespace lemke
