// lemke._core: the Python binding of the C++ core (nanobind). Each function converts its
// arguments once, releases the GIL around the solve and returns plain numbers; the Python
// front (lemke/_lcp.py) builds the result.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/tuple.h>

#include <cstring>

#include "lemke/lcp.hpp"

namespace nb = nanobind;
using namespace nb::literals;

using Matrix = nb::ndarray<const double, nb::ndim<2>, nb::c_contig, nb::device::cpu>;
using Vector = nb::ndarray<const double, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using Buffer = nb::ndarray<double, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using Indices = nb::ndarray<const std::int64_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using IndexOut = nb::ndarray<std::int64_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>;

// cold.first_run's arguments and return value, for the tableau method: (code, pivots, k,
// ok, residual, recoveries, stage). An empty `basic` means: the n int64 after the buffer's
// fields (solve_lcp's single allocation).
static std::tuple<int, std::int64_t, std::int64_t, bool, double, std::int64_t, int> first_run(
    int /*method*/, Matrix M, Vector q, Vector d, Indices beta, std::int64_t k,
    std::int64_t max_pivots, double pivot_tol, double tie_tol, double tol, Buffer buf,
    IndexOut basic) {
    using lemke::idx;
    idx n = static_cast<idx>(q.shape(0));
    lemke::BufferLayout L{n};
    bool own = basic.shape(0) == 0 && n > 0;
    bool sizes_ok = static_cast<idx>(M.shape(0)) == n && static_cast<idx>(M.shape(1)) == n &&
                    (d.shape(0) == 0 || static_cast<idx>(d.shape(0)) == n) &&
                    k >= 0 && k <= n && static_cast<idx>(beta.shape(0)) >= k &&
                    static_cast<idx>(buf.shape(0)) >= L.length() + (own ? n : 0) &&
                    (own || n == 0 || static_cast<idx>(basic.shape(0)) >= n);
    if (!sizes_ok) return {lemke::NOT_FINITE, 0, 0, false, 0.0, 0, 2};
    const idx* b = beta.data();
    for (idx i = 0; i < k; ++i)
        if (b[i] < 0 || b[i] >= n) return {lemke::NOT_FINITE, 0, 0, false, 0.0, 0, 2};
    double* out = buf.data();
    idx* basic_out = own ? reinterpret_cast<idx*>(out + L.length()) : basic.data();
    lemke::RunResult r;
    {
        nb::gil_scoped_release release;
        r = lemke::first_run(lemke::Mat<const double>(M.data(), n, n), q.data(),
                             d.shape(0) ? d.data() : nullptr, b, k, max_pivots, pivot_tol,
                             tie_tol, tol, out, basic_out);
    }
    return {r.code, r.pivots, r.k, r.ok, r.residual, r.recoveries, r.stage};
}

NB_MODULE(_core, m) {
    m.doc() = "The C++ core of lemke (see ARCHITECTURE.md).";
    m.def("first_run", &first_run, "method"_a, "M"_a, "q"_a, "d"_a, "beta"_a, "k"_a,
          "max_pivots"_a, "pivot_tol"_a, "tie_tol"_a, "tol"_a, "buf"_a, "basic"_a);
    m.attr("BUFFER_LENGTH_PER_N") = 6;
    m.attr("BUFFER_LENGTH_FIXED") = 2;
}
