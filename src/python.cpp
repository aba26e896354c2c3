// lemke._core: the Python binding of the C++ core (nanobind). Each function converts its
// arguments once, releases the GIL around the solve and returns plain numbers; the Python
// front (lemke/_lcp.py) builds the result.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/tuple.h>

#include <cstring>

#include "capi_status.hpp"
#include "lemke/budget.hpp"
#include "lemke/certify.hpp"
#include "lemke/lcp.hpp"
#include "lemke/unrevised.hpp"
#include "python_arrays.hpp"

namespace nb = nanobind;
using namespace nb::literals;

void bind_support(nb::module_& m);  // src/python_support.cpp
void bind_boxed(nb::module_& m);  // src/python_boxed.cpp
void bind_front(nb::module_& m);  // src/python_front.cpp
void bind_front_box(nb::module_& m);  // src/python_front_box.cpp

using Matrix = Aligned<nb::ndarray<const double, nb::ndim<2>, nb::c_contig, nb::device::cpu>>;
using Vector = Aligned<nb::ndarray<const double, nb::ndim<1>, nb::c_contig, nb::device::cpu>>;
using Buffer = Aligned<nb::ndarray<double, nb::ndim<1>, nb::c_contig, nb::device::cpu>>;
using Indices = Aligned<nb::ndarray<const std::int64_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>>;
using IndexOut = Aligned<nb::ndarray<std::int64_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>>;

// The length of an optional array argument (None: 0).
template <class A>
static lemke::idx len_of(const A& a) {
    return a.is_valid() ? static_cast<lemke::idx>(a.shape(0)) : 0;
}

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
    idx d_len = len_of(d), beta_len = len_of(beta), basic_len = len_of(basic);
    bool own = basic_len == 0 && n > 0;
    bool sizes_ok = static_cast<idx>(M.shape(0)) == n && static_cast<idx>(M.shape(1)) == n &&
                    (d_len == 0 || d_len == n) && k >= 0 && k <= n && beta_len >= k &&
                    static_cast<idx>(buf.shape(0)) >= L.length() + (own ? n : 0) &&
                    (own || n == 0 || basic_len >= n);
    if (!sizes_ok) return {lemke::NOT_FINITE, 0, 0, false, 0.0, 0, 2};
    const idx* b = beta_len ? beta.data() : nullptr;
    for (idx i = 0; i < k; ++i)
        if (b[i] < 0 || b[i] >= n) return {lemke::NOT_FINITE, 0, 0, false, 0.0, 0, 2};
    double* out = buf.data();
    idx* basic_out = own ? reinterpret_cast<idx*>(out + L.length()) : basic_len ? basic.data() : nullptr;
    lemke::RunResult r;
    {
        nb::gil_scoped_release release;
        r = lemke::first_run(lemke::Mat<const double>(M.data(), n, n), q.data(),
                             d_len ? d.data() : nullptr, b, k, max_pivots, pivot_tol,
                             tie_tol, tol, out, basic_out);
    }
    return {r.code, r.pivots, r.k, r.ok, r.residual, r.recoveries, r.stage};
}

using FlagsIn = nb::ndarray<nb::ro, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using Flags = nb::ndarray<nb::ndim<1>, nb::c_contig, nb::device::cpu>;

// A 1-D array of bool or uint8 (one byte a flag).
template <class A>
static bool is_flags(const A& a) {
    return a.dtype() == nb::dtype<bool>() || a.dtype() == nb::dtype<std::uint8_t>();
}

// The unrevised method on (M, q, d) equilibrated by (R, C) from z_start (for the tests that
// run the engine directly): (status, pivots). z_start: n flags or empty (all w basic). Mis-sized or mistyped
// arrays raise ValueError.
static std::tuple<int, std::int64_t> unrevised_solve(Matrix M, Vector q, Vector d, Vector R,
                                                     Vector C, FlagsIn z_start,
                                                     std::int64_t max_pivots, double pivot_tol,
                                                     double tie_tol, Buffer x_out, Buffer ray_out,
                                                     Flags z_basic_out) {
    using lemke::idx;
    idx n = static_cast<idx>(q.shape(0));
    auto is = [](std::size_t got, idx want) { return static_cast<idx>(got) == want; };
    if (!is(M.shape(0), n) || !is(M.shape(1), n) || !is(d.shape(0), n) || !is(R.shape(0), n) ||
        !is(C.shape(0), n) || !(z_start.shape(0) == 0 || is(z_start.shape(0), n)) ||
        !is(x_out.shape(0), n + 1) || !is(ray_out.shape(0), n + 1) ||
        !is(z_basic_out.shape(0), n))
        throw nb::value_error("unrevised_solve: M must be n x n, q, d, R, C and z_basic_out "
                              "of length n, z_start of length n or 0, x_out and ray_out n + 1");
    if (!is_flags(z_start) || !is_flags(z_basic_out))
        throw nb::value_error("unrevised_solve: z_start and z_basic_out must be bool or uint8 "
                              "(z_basic_out writable)");
    const auto* zs = z_start.shape(0) ? static_cast<const std::uint8_t*>(z_start.data()) : nullptr;
    auto* zb = static_cast<std::uint8_t*>(z_basic_out.data());
    idx pivots = 0;
    lemke::Status status;
    {
        nb::gil_scoped_release release;
        status = lemke::unrevised_solve(lemke::Mat<const double>(M.data(), n, n), q.data(),
                                        d.data(), R.data(), C.data(), zs, max_pivots, pivot_tol,
                                        tie_tol, x_out.data(), ray_out.data(), zb, pivots);
    }
    return {static_cast<int>(status), pivots};
}

using Tuple7 = std::tuple<int, std::int64_t, std::int64_t, bool, double, std::int64_t, int>;

// cold.solve_one's arguments and return value, for either method: k = -1 goes on after
// first_run's stage -1 (beta = [code, pivots]), k < -1 restarts from the warm basis
// beta[:-2 - k] whose point first_run tried.
static Tuple7 solve_one(int method, Matrix M, Vector q, Vector d, Indices beta, std::int64_t k,
                        std::int64_t max_pivots, double pivot_tol, double tie_tol, double tol,
                        Buffer buf, IndexOut basic, bool stop_at_ray) {
    using lemke::idx;
    idx n = static_cast<idx>(q.shape(0));
    lemke::BufferLayout L{n};
    idx d_len = len_of(d), beta_len = len_of(beta), basic_len = len_of(basic);
    bool own = basic_len == 0 && n > 0;
    idx kb = k >= 0 ? k : (k == -1 ? 0 : -2 - k);
    bool sizes_ok = static_cast<idx>(M.shape(0)) == n && static_cast<idx>(M.shape(1)) == n &&
                    (d_len == 0 || d_len == n) && (method == 0 || method == 1) && kb <= n &&
                    beta_len >= (k == -1 ? 2 : kb) &&
                    static_cast<idx>(buf.shape(0)) >= L.length() + (own ? n : 0) &&
                    (own || n == 0 || basic_len >= n);
    if (!sizes_ok) return {lemke::NOT_FINITE, 0, 0, false, 0.0, 0, 2};
    const idx* b = beta_len ? beta.data() : nullptr;
    if (k != -1)
        for (idx i = 0; i < kb; ++i)
            if (b[i] < 0 || b[i] >= n) return {lemke::NOT_FINITE, 0, 0, false, 0.0, 0, 2};
    double* out = buf.data();
    idx* basic_out = own ? reinterpret_cast<idx*>(out + L.length()) : basic_len ? basic.data() : nullptr;
    lemke::RunResult r;
    {
        nb::gil_scoped_release release;
        r = lemke::solve_one(static_cast<lemke::Method>(method),
                             lemke::Mat<const double>(M.data(), n, n), q.data(),
                             d_len ? d.data() : nullptr, b, k, max_pivots, pivot_tol,
                             tie_tol, tol, out, basic_out, true, stop_at_ray);
    }
    return {r.code, r.pivots, r.k, r.ok, r.residual, r.recoveries, r.stage};
}

using Flat = Aligned<nb::ndarray<const double, nb::ndim<1>, nb::c_contig, nb::device::cpu>>;
using FlatOut = Aligned<nb::ndarray<double, nb::ndim<1>, nb::c_contig, nb::device::cpu>>;
using IntOut2 = Aligned<nb::ndarray<std::int64_t, nb::ndim<2>, nb::c_contig, nb::device::cpu>>;
using FloatOut2 = Aligned<nb::ndarray<double, nb::ndim<2>, nb::c_contig, nb::device::cpu>>;

// cold.batch's arguments: problems lo..hi-1 laid end to end (see lemke::batch). Every
// offset is checked against its array before the GIL is released (ValueError otherwise).
static void batch(int method, Flat Ms, Indices mstart, Flat qs, Indices qoff, Indices beta,
                  Indices boff, std::int64_t lo, std::int64_t hi, Indices max_pivots,
                  double pivot_tol, double tie_tol, double tol, FlatOut bufs, Indices buff,
                  IndexOut basics, IntOut2 out_i, FloatOut2 out_f) {
    using lemke::idx;
    idx nb_ = static_cast<idx>(qoff.shape(0)) - 1;
    if (method != 0 && method != 1) throw nb::value_error("batch: method must be 0 or 1");
    if (lo < 0 || hi < lo || hi > nb_ || static_cast<idx>(mstart.shape(0)) < hi ||
        static_cast<idx>(boff.shape(0)) < hi + 1 || static_cast<idx>(buff.shape(0)) < hi + 1 ||
        static_cast<idx>(max_pivots.shape(0)) < hi || static_cast<idx>(out_i.shape(0)) < hi ||
        out_i.shape(1) != 5 || static_cast<idx>(out_f.shape(0)) < hi || out_f.shape(1) != 2)
        throw nb::value_error("batch: offsets and outputs do not cover the problems");
    const idx *qo = qoff.data(), *ms = mstart.data(), *bo = boff.data(), *bf = buff.data();
    const idx* be = beta.data();
    for (idx b = lo; b < hi; ++b) {
        idx n = qo[b + 1] - qo[b];
        bool ok = n >= 0 && qo[b] >= 0 && qo[b + 1] <= static_cast<idx>(qs.shape(0)) &&
                  qo[b + 1] <= static_cast<idx>(basics.shape(0)) && ms[b] >= 0 &&
                  ms[b] + n * n <= static_cast<idx>(Ms.shape(0)) && bo[b] >= 0 &&
                  bo[b + 1] >= bo[b] && bo[b + 1] <= static_cast<idx>(beta.shape(0)) &&
                  bo[b + 1] - bo[b] <= n && bf[b] >= 0 &&
                  bf[b + 1] - bf[b] >= lemke::BufferLayout{n}.length() &&
                  bf[b + 1] <= static_cast<idx>(bufs.shape(0));
        if (!ok) throw nb::value_error("batch: a problem's offsets lie outside its arrays");
        for (idx i = bo[b]; i < bo[b + 1]; ++i)
            if (be[i] < 0 || be[i] >= n) throw nb::value_error("batch: a basis index is out of range");
    }
    nb::gil_scoped_release release;
    lemke::batch(static_cast<lemke::Method>(method), Ms.data(), ms, qs.data(), qo, be, bo, lo, hi,
                 max_pivots.data(), pivot_tol, tie_tol, tol, bufs.data(), bf, basics.data(),
                 out_i.data(), out_f.data());
}

void bind_games(nb::module_& m);  // src/python_games.cpp
void bind_qp(nb::module_& m);     // src/python_qp.cpp
void bind_front_qp(nb::module_& m);  // src/python_front_qp.cpp

NB_MODULE(_core, m) {
    m.doc() = "The C++ core of lemke (see ARCHITECTURE.md).";
    // d, beta and basic may be None (no covering vector, no warm start, the buffer's own
    // basic z's): each array argument's conversion costs about 0.14 us.
    m.def("first_run", &first_run, "method"_a, "M"_a, "q"_a, "d"_a.none(), "beta"_a.none(),
          "k"_a, "max_pivots"_a, "pivot_tol"_a, "tie_tol"_a, "tol"_a, "buf"_a,
          "basic"_a.none());
    m.def("unrevised_solve", &unrevised_solve, "M"_a, "q"_a, "d"_a, "R"_a, "C"_a, "z_start"_a,
          "max_pivots"_a, "pivot_tol"_a, "tie_tol"_a, "x_out"_a, "ray_out"_a, "z_basic_out"_a);
    // stop_at_ray: the MLCP ladder's rule for a ray in the recovery runs (lemke::solve_one)
    m.def("solve_one", &solve_one, "method"_a, "M"_a, "q"_a, "d"_a.none(), "beta"_a.none(),
          "k"_a, "max_pivots"_a, "pivot_tol"_a, "tie_tol"_a, "tol"_a, "buf"_a,
          "basic"_a.none(), "stop_at_ray"_a = false);
    m.def("batch", &batch, "method"_a, "Ms"_a, "mstart"_a, "qs"_a, "qoff"_a, "beta"_a, "boff"_a,
          "lo"_a, "hi"_a, "max_pivots"_a, "pivot_tol"_a, "tie_tol"_a, "tol"_a, "bufs"_a,
          "buff"_a, "basics"_a, "out_i"_a, "out_f"_a);
    // The layout of the output buffer and the driver's codes (lemke/_layout.py states them
    // for the fronts; tests/test_structure.py checks that the two agree).
    m.def("buffer_layout", [](std::int64_t n) {
        lemke::BufferLayout L{n};
        return std::make_tuple(L.z(), L.z0(), L.ray(), L.w(), L.covering(), L.row_scale(),
                               L.col_scale(), L.length());
    }, "n"_a);
    // Budgets (src/lemke/budget.hpp): the calling thread's deadline, the interrupt, and the
    // SIGINT listener that long runs arm (chained to Python's handler).
    lemke::enable_sigint_listener(true);
    m.def("tighten_deadline", &lemke::tighten_thread_deadline, "seconds"_a,
          "The calling thread's deadline: at most `seconds` from now; returns the one before.");
    m.def("restore_deadline", &lemke::restore_thread_deadline, "deadline"_a,
          "Sets the calling thread's deadline (steady-clock ns; 0: none).");
    m.def("deadline", &lemke::thread_deadline, "The calling thread's deadline (0: none).");
    m.def("interrupt", &lemke::interrupt_all, "Stop every running solve (INTERRUPTED).");
    m.def("interrupts", &lemke::interrupts_seen, "How many interrupts so far.");
    // A progress probe (budget.hpp ProgressHook): attach() in the solving thread, pivots()
    // and stop() from the reporting one.
    nb::class_<lemke::ProgressHook>(m, "ProgressProbe")
        .def(nb::init<>())
        .def("attach", [](lemke::ProgressHook& h) { lemke::set_thread_progress(&h); })
        .def("detach", [](lemke::ProgressHook&) { lemke::set_thread_progress(nullptr); })
        .def("pivots", [](const lemke::ProgressHook& h) {
            return h.pivots.load(std::memory_order_relaxed);
        })
        .def("stop", [](lemke::ProgressHook& h) { h.stop.store(true, std::memory_order_relaxed); });
    m.attr("TIME_LIMIT") = static_cast<int>(lemke::TIME_LIMIT);
    m.attr("INTERRUPTED") = static_cast<int>(lemke::INTERRUPTED);
    m.attr("NOT_FINITE") = lemke::NOT_FINITE;
    m.attr("TRIVIAL") = lemke::TRIVIAL;
    m.attr("RESTART_FROM") = lemke::RESTART_FROM;
    m.attr("TABLEAU") = static_cast<int>(lemke::TABLEAU);
    m.attr("UNREVISED") = static_cast<int>(lemke::UNREVISED);
    m.attr("CERTIFIABLE") = lemke::CERTIFIABLE;
    // status.hpp's every kernel code by name, and the C API's mapping of a code to its
    // LEMKE_* status (capi_status.hpp): for tests/test_status_codes.py
    m.def("_kernel_codes", [] {
        nb::list out;
        for (const lemke::KernelCode& k : lemke::KERNEL_CODES) out.append(nb::make_tuple(k.name, k.code));
        return out;
    });
    m.def("_c_status", [](int code) { return lemke::c_status(code); });
    m.def("_lcp_status", [](int code) { return lemke::lcp_status(code); });
    bind_support(m);
    bind_games(m);
    bind_boxed(m);
    bind_front(m);
    bind_front_box(m);
    bind_qp(m);
    bind_front_qp(m);
}
