/* The C API in a few lines: solve the running example of Cottle-Pang-Stone 4.4.7, then the
 * next "time step" warm from the final basis. Build: see CMakeLists.txt (LEMKE_TESTS). */
#include <stdio.h>

#include "lemke.h"

int main(void) {
    const double M[9] = {0.0, -1.0, 2.0,
                         2.0, 0.0, -2.0,
                         -1.0, 1.0, 0.0};
    double q[3] = {-3.0, 6.0, -1.0};
    double z[3], w[3];
    int64_t basis[3], k = 0;
    lemke_info info;
    int s = lemke_lcp_solve(3, M, q, NULL, NULL, 0, z, w, basis, &k, &info);
    printf("%s after %lld pivots: z = (%g, %g, %g)\n", lemke_status_name(s),
           (long long)info.pivots, z[0], z[1], z[2]);
    if (s != LEMKE_SOLVED || z[0] != 0.0 || z[1] != 1.0 || z[2] != 3.0) return 1;

    q[0] += 1e-9; /* the next step: the old basis still solves it */
    s = lemke_lcp_solve(3, M, q, NULL, basis, k, z, w, basis, &k, &info);
    printf("warm: %s after %lld pivots (basis reused: %d)\n", lemke_status_name(s),
           (long long)info.pivots, info.warm);
    return s == LEMKE_SOLVED && info.pivots == 0 && info.warm ? 0 : 1;
}
