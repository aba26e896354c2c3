// lemke._core.qp_front: solve_qp's call on plain data whole in one native call, as
// src/python_front.cpp does for solve_lcp: plain float64 arrays (the kinds solve_qp's first
// lines take: ndarrays of the kernel's ranks, C-contiguous, aligned, writable; G with h, A
// with b, or neither; lb, ub or None), the default options and method; cold, or warm (a
// WarmStart, or qpsolvers' initvals). It reads the ndarrays' fields directly
// (src/python_arrays.hpp, the layout that lcp_front_init checked), allocates the output
// buffer with numpy.empty (qp::OutLayout, qp::BoxOutLayout), runs the kernel without the
// GIL and builds the QPResult as _qp._fused_result (or _qp._solve_box_small) does (x,
// status, pivots, certificate now, the rest from _qp._fused_fields / _box_small_fields
// when first read). Cold, it chooses as solve_qp's inline lines do: a box-only QP below
// BOX_FIRST variables qp::solve_box, any other but a larger box-only one _qp._solve_definite's
// kernels (cold(): the factored path first with at least GRAM_RATIO n inequalities, the fused
// kernel, the semidefinite step), the rest None.
//
// Returns the QPResult when the kernel ends OK (solved and checked); the tuple (code,
// pivots, k, pairs) for any other code (the Python front goes on from there, as from
// _core.qp_solve_warm's, qp_solve's or qp_solve_box's answer, without calling the kernel
// again); None when the arguments are not of that plain kind, their shapes do not match,
// the warm start's index array is not rising in [0, pairs), x0 is not finite, or a cold QP
// is not one the inline lines give a kernel (the Python front then does what it did
// before, and says what is wrong). The same solve, the same bits as the Python path.
#include <nanobind/nanobind.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "lemke/budget.hpp"
#include "lemke/ladder.hpp"
#include "lemke/qp.hpp"
#include "python_arrays.hpp"

namespace nb = nanobind;
using namespace nb::literals;

namespace {

using lemke::idx;
namespace qp = lemke::qp;

struct QPFront {
    bool on = false;
    PyObject* result_cls = nullptr;  // QPResult
    PyObject* solved = nullptr;      // Status.SOLVED
    PyObject* fields = nullptr;      // _qp._fused_fields
    PyObject* box_fields = nullptr;  // _qp._box_small_fields
    idx box_first = 0;               // _qp.BOX_FIRST
    PyObject *k_x, *k_status, *k_pivots, *k_certificate, *k_resolve;
    int method = 0;
    double pivot_tol = 0, tie_tol = 0, tol = 0;
} qf;

void init(nb::handle result_cls, nb::handle solved, nb::handle fields, nb::handle box_fields,
          std::int64_t box_first, int method, double pivot_tol, double tie_tol, double tol) {
    qf.on = false;
    if (!numpy_layout().ok) return;  // lcp_front_init found another layout (or has not run)
    for (nb::handle h : {result_cls, solved, fields, box_fields}) h.inc_ref();  // kept for good
    qf.result_cls = result_cls.ptr();
    qf.solved = solved.ptr();
    qf.fields = fields.ptr();
    qf.box_fields = box_fields.ptr();
    qf.box_first = box_first;
    qf.k_x = PyUnicode_InternFromString("x");
    qf.k_status = PyUnicode_InternFromString("status");
    qf.k_pivots = PyUnicode_InternFromString("pivots");
    qf.k_certificate = PyUnicode_InternFromString("certificate");
    qf.k_resolve = PyUnicode_InternFromString("_resolve");
    qf.method = method;
    qf.pivot_tol = pivot_tol;
    qf.tie_tol = tie_tol;
    qf.tol = tol;
    qf.on = qf.k_x && qf.k_status && qf.k_pivots && qf.k_certificate && qf.k_resolve;
}

// The absent bounds of n variables (-inf, then +inf), kept per thread.
const double* absent_bounds(idx n) {
    thread_local std::vector<double> v;
    if (static_cast<idx>(v.size()) != 2 * n) {
        v.assign(static_cast<std::size_t>(2 * n), std::numeric_limits<double>::infinity());
        for (idx j = 0; j < n; ++j) v[static_cast<std::size_t>(j)] = -v[static_cast<std::size_t>(j)];
    }
    return v.data();
}

// An argument as the front reads it: a float64 C array's data and shape (cols 1 for a
// vector), in place or converted; given false for None.
struct Arg {
    const double* data = nullptr;
    idx rows = 0, cols = 1;
    bool given = false;
};

qp::Data data_of(const Arg& P, const Arg& q, const double* G, const double* h, idx m,
                 const double* A, const double* b, idx p, const double* lo, const double* up) {
    idx n = q.rows;
    return {lemke::Mat<const double>(P.data, n, n), q.data, lemke::Mat<const double>(G, m, n), h,
            lemke::Mat<const double>(A, p, n), b, lo, up};
}

// The solved QPResult as _qp._fused_result (or _solve_box_small) builds it: the buffer
// read-only (out.setflags(write=False): NumPy's PyArray_CLEARFLAGS, on the field), x its
// first n entries, status, pivots and certificate now, the rest from fields(*src) when first
// read.
nb::object solved(const nb::object& buf, idx n, idx pivots, PyObject* fields,
                  const nb::object& src) {
    reinterpret_cast<ArrayFields*>(buf.ptr())->flags &= ~WRITEABLE;
    // x = buf[:n]: NumPy's C API (new_view, the view that slice makes), else the slice
    nb::object x = new_view(buf, 0, n);
    if (!x.is_valid()) {
        nb::object stop = nb::steal(PyLong_FromSsize_t(n));
        if (!stop.is_valid()) throw nb::python_error();
        nb::object sl = nb::steal(PySlice_New(nullptr, stop.ptr(), nullptr));
        if (!sl.is_valid()) throw nb::python_error();
        x = nb::steal(PyObject_GetItem(buf.ptr(), sl.ptr()));
        if (!x.is_valid()) throw nb::python_error();
    }
    auto [res, dict] = new_result(qf.result_cls);
    PyObject* d = dict.ptr();
    Py_INCREF(qf.solved);
    Py_INCREF(Py_None);
    bool ok = put(d, qf.k_x, x.release().ptr()) &&
              put(d, qf.k_status, qf.solved) &&
              put(d, qf.k_pivots, PyLong_FromLongLong(pivots)) &&
              put(d, qf.k_certificate, Py_None) &&
              put(d, qf.k_resolve, PyTuple_Pack(2, fields, src.ptr()));
    if (!ok) throw nb::python_error();
    return res;
}

// _qp._solve_box_small: qp::solve_box from no warm start (solve_blcp's pivot budget), one
// buffer (BoxOutLayout, the final bases in its tail); the result, or the kernel's code.
nb::object box_small(const qp::Data& data) {
    idx n = data.n();
    thread_local std::vector<std::uint8_t> no_warm;
    no_warm.assign(static_cast<std::size_t>(2 * n), 0);
    qp::BoxOutLayout L{n};
    nb::object buf = new_array(L.length());
    double* out = reinterpret_cast<double*>(reinterpret_cast<ArrayFields*>(buf.ptr())->data);
    qp::Result r;
    {
        nb::gil_scoped_release release;
        r = qp::solve_box(data, no_warm.data(), 100 * (n + 1), qf.pivot_tol, qf.tie_tol, qf.tol,
                          out, reinterpret_cast<idx*>(out + L.final()));
    }
    if (r.code != qp::OK) return nb::make_tuple(r.code, r.pivots, r.k, r.pairs);
    return solved(buf, n, r.pivots, qf.box_fields, nb::make_tuple(buf, n, r.k, r.pairs));
}

// The kernels the calling thread's last qp_front ran (qp::solve: 0, qp::solve_gram: 1), each
// with its code, in order: qp_front_codes(), the tests' record of which path answered.
thread_local std::vector<std::pair<int, int>> ran;

// _qp._solve_definite (and its _solve_semidefinite) on plain data with the default options,
// the same kernel calls in the same order, a ladder of three rungs (ladder.hpp): with at least GRAM_RATIO n inequalities (bounds
// counted) the factored path first (the kernel's step 7); unless it solved or stopped, the
// fused kernel; where that found P not definite, or its point failed the KKT check, and
// step 7 did not run, the proximal factored path (step 8) unless P has more zero diagonal
// entries than qp::flat_allowed takes on (the kernel would decline at once). One buffer for all of them
// (each kernel writes every entry it reports; solve_gram zeroes it whole first). The
// result when one ends OK; else the last kernel's code, after which the Python steps go
// straight to the KKT-MLCP path (a stop: its result, no other path).
nb::object cold(const qp::Data& data, idx p, idx m, bool many) {
    idx n = data.n();
    qp::OutLayout L{n, p, m};
    nb::object buf = new_array(L.length());
    double* out = reinterpret_cast<double*>(reinterpret_cast<ArrayFields*>(buf.ptr())->data);
    idx* basic = reinterpret_cast<idx*>(out + L.basis());
    auto stopped = [](int code) {
        return code == lemke::STOP_TIME_LIMIT || code == lemke::STOP_INTERRUPTED;
    };
    qp::Result r;
    {
        nb::gil_scoped_release release;
        bool tried = false;  // step 7 ran (it did not answer NOT_APPLICABLE)
        // The ladder (ladder.hpp): solved and checked, or a stop, settles it.
        lemke::ladder::climb(
            [&] { return r.code == qp::OK || stopped(r.code); },
            lemke::ladder::rung("the factored path (step 7)", [&] { return many; }, [&] {
                r = qp::solve_gram(data, -1, qf.pivot_tol, qf.tie_tol, qf.tol, out, L.length(),
                                   basic, false);
                ran.emplace_back(1, r.code);
                tried = r.code != qp::NOT_APPLICABLE;
            }),
            lemke::ladder::rung("the fused kernel", lemke::ladder::Always{}, [&] {
                r = qp::solve(data, qf.method, -1, qf.pivot_tol, qf.tie_tol, qf.tol, out, basic);
                ran.emplace_back(0, r.code);
            }),
            lemke::ladder::rung("the proximal factored path (step 8)", [&] {
                return (r.code == qp::NOT_DEFINITE || r.code == qp::CHECK_FAILED) && !tried &&
                       qp::zero_diagonal(data.P) <=
                           qp::flat_allowed(p, data.h, m, data.lb, data.ub, n);
            }, [&] {
                r = qp::solve_gram(data, -1, qf.pivot_tol, qf.tie_tol, qf.tol, out, L.length(),
                                   basic, true, true, true);
                ran.emplace_back(1, r.code);
            }));
    }
    if (r.code != qp::OK) return nb::make_tuple(r.code, r.pivots, r.k, r.pairs);
    return solved(buf, n, r.pivots, qf.fields, nb::make_tuple(buf, n, p, m, r.k, r.pairs));
}

// The front on the arguments a (P, q, G, h, A, b, lb, ub, x0: float64 C arrays or None).
nb::object front_args(const Arg* a, std::int64_t pairs, nb::handle beta_h) {
    const Arg &P = a[0], &q = a[1], &lb = a[6], &ub = a[7], &x0a = a[8];
    if (!P.given || !q.given) return nb::none();
    idx n = q.rows;
    if (n == 0 || P.rows != n || P.cols != n) return nb::none();
    static const double nothing = 0.0;
    const double *Gd = &nothing, *hd = &nothing, *Ad = &nothing, *bd = &nothing;
    idx m = 0, p = 0;
    // rows (G and h, or A and b): both of matching shapes, or both None
    auto rows = [&](const Arg& Ma, const Arg& va, const double*& M, const double*& v, idx& k) {
        if (!Ma.given && !va.given) return true;
        if (!Ma.given || !va.given) return false;
        k = va.rows;
        if (Ma.rows != k || Ma.cols != n) return false;
        M = Ma.data;
        v = va.data;
        return true;
    };
    if (!rows(a[2], a[3], Gd, hd, m) || !rows(a[4], a[5], Ad, bd, p)) return nb::none();
    const double* absent = nullptr;
    const double *lo, *up;
    if (!lb.given) {
        absent = absent_bounds(n);
        lo = absent;
    } else {
        if (lb.rows != n) return nb::none();
        lo = lb.data;
    }
    if (!ub.given) {
        if (absent == nullptr) absent = absent_bounds(n);
        up = absent + n;
    } else {
        if (ub.rows != n) return nb::none();
        up = ub.data;
    }
    // The warm start's pairs (WarmStart._beta: int64, C-contiguous, aligned; rising in
    // [0, pairs), as _core.qp_solve_warm requires), or the guess x0 (n finite entries), or
    // neither: cold.
    const std::int64_t* warm = nullptr;
    idx kw = 0;
    const double* x0 = nullptr;
    if (!beta_h.is_none()) {
        NumpyLayout lay = numpy_layout();
        auto* w = plain_i64(beta_h.ptr(), lay.ndarray, lay.int64_num);
        if (w == nullptr) return nb::none();
        warm = reinterpret_cast<const std::int64_t*>(w->data);
        kw = w->dimensions[0];
        if (pairs < 0 || kw > pairs) return nb::none();
        for (idx t = 0; t < kw; ++t)
            if (warm[t] < 0 || warm[t] >= pairs || (t > 0 && warm[t] <= warm[t - 1]))
                return nb::none();
    } else if (x0a.given) {
        if (x0a.rows != n || !lemke::all_finite(x0a.data, n)) return nb::none();
        x0 = x0a.data;
        pairs = 0;
    } else {
        // cold, as solve_qp's inline lines choose: a box-only QP with bounds below
        // BOX_FIRST variables takes the box kernel; from there, the Python steps (None);
        // else _solve_definite's kernels (cold)
        bool box = !a[2].given && !a[3].given && !a[4].given && !a[5].given;
        idx bounds = lb.given + ub.given;
        if (box && bounds > 0) {
            if (n >= qf.box_first) return nb::none();
            return box_small(data_of(P, q, Gd, hd, m, Ad, bd, p, lo, up));
        }
        return cold(data_of(P, q, Gd, hd, m, Ad, bd, p, lo, up), p, m,
                    m + n * bounds >= qp::GRAM_RATIO * n);
    }
    qp::OutLayout L{n, p, m};
    nb::object buf = new_array(L.length());
    double* out = reinterpret_cast<double*>(reinterpret_cast<ArrayFields*>(buf.ptr())->data);
    qp::Result r;
    {
        nb::gil_scoped_release release;
        r = qp::solve(data_of(P, q, Gd, hd, m, Ad, bd, p, lo, up), qf.method, -1, qf.pivot_tol,
                      qf.tie_tol, qf.tol, out, reinterpret_cast<idx*>(out + L.basis()), warm,
                      kw, pairs, x0);
    }
    ran.emplace_back(0, r.code);
    if (r.code != qp::OK) return nb::make_tuple(r.code, r.pivots, r.k, r.pairs);
    return solved(buf, n, r.pivots, qf.fields, nb::make_tuple(buf, n, p, m, r.k, r.pairs));
}

nb::object qp_front(nb::handle P_h, nb::handle q_h, nb::handle G_h, nb::handle h_h,
                    nb::handle A_h, nb::handle b_h, nb::handle lb_h, nb::handle ub_h,
                    std::int64_t pairs, nb::handle beta_h, nb::handle x0_h) {
    ran.clear();
    if (!qf.on) return nb::none();
    PyObject* given[9] = {P_h.ptr(), q_h.ptr(), G_h.ptr(), h_h.ptr(), A_h.ptr(),
                          b_h.ptr(), lb_h.ptr(), ub_h.ptr(), x0_h.ptr()};
    static const int ranks[9] = {2, 1, 2, 1, 2, 1, 1, 1, 1};  // (_qp._RANKS)
    // Each argument read in place when it is None or a plain float64 array (read-only or
    // not: the front only reads); else (branch qpfront) converted as the entries of
    // solve_lcp and solve_blcp convert array-likes (pack_form / pack_into: made_f64's forms
    // and values) into one scratch vector, a Python-number bound spread over the rows
    // (bound_value; NaN and a wrong-side value at or beyond 1e20 declined, as _validate.qp
    // refuses them); anything else declines the call (None: the Python conversion,
    // _validate.plain_all, and the validation then).
    Arg a[9];
    int form[9];  // 0 in place (or None), 1 converted, 2 a scalar bound
    double scalar[9];
    idx need = 0;
    for (int i = 0; i < 9; ++i) {
        PyObject* x = given[i];
        form[i] = 0;
        if (x == Py_None) continue;
        a[i].given = true;
        Py_ssize_t rows = 0, cols = 1;
        if ((i == 6 || i == 7) && (PyFloat_CheckExact(x) || PyLong_CheckExact(x))) {
            if (!a[1].given || !bound_value(x, i == 6 ? -1 : 1, qp::INFINITY_BOUND, scalar[i]))
                return nb::none();
            form[i] = 2;
            rows = a[1].rows;
        } else {
            form[i] = pack_form(x, ranks[i], rows, cols);
            if (form[i] < 0) return nb::none();
            if (form[i] == 0)
                a[i].data = reinterpret_cast<const double*>(reinterpret_cast<ArrayFields*>(x)->data);
        }
        a[i].rows = rows;
        a[i].cols = cols;
        if (form[i] != 0) need += rows * cols;
    }
    if (need == 0) return front_args(a, pairs, beta_h);
    std::vector<double> scratch(static_cast<std::size_t>(need));  // (its own: a nested call
    double* at = scratch.data();                                   // cannot reuse it)
    for (int i = 0; i < 9; ++i) {
        if (form[i] == 0) continue;
        a[i].data = at;
        if (form[i] == 2)
            std::fill(at, at + a[i].rows, scalar[i]);
        else if (!pack_into(given[i], ranks[i], a[i].rows, a[i].cols, at))
            return nb::none();
        at += a[i].rows * a[i].cols;
    }
    nb::object r = front_args(a, pairs, beta_h);
    if (!PyTuple_CheckExact(r.ptr())) return r;  // the QPResult, or None
    // the kernel's code with the arguments as converted (new arrays), which the Python steps
    // go on with
    nb::object args = nb::steal(PyTuple_New(9));
    if (!args.is_valid()) throw nb::python_error();
    for (int i = 0; i < 9; ++i) {
        nb::object v = nb::borrow(given[i]);
        if (form[i] != 0) {
            v = new_rows(ranks[i], a[i].rows, a[i].cols);
            std::copy(a[i].data, a[i].data + a[i].rows * a[i].cols,
                      reinterpret_cast<double*>(reinterpret_cast<ArrayFields*>(v.ptr())->data));
        }
        PyTuple_SET_ITEM(args.ptr(), i, v.release().ptr());
    }
    return nb::make_tuple(r[0], r[1], r[2], r[3], args);
}

}  // namespace

void bind_front_qp(nb::module_& m) {
    m.def("qp_front_init", &init, "result_cls"_a, "solved"_a, "fields"_a, "box_fields"_a,
          "box_first"_a, "method"_a, "pivot_tol"_a, "tie_tol"_a, "tol"_a);
    m.def("qp_front", &qp_front, "P"_a.none(), "q"_a.none(), "G"_a.none(), "h"_a.none(),
          "A"_a.none(), "b"_a.none(), "lb"_a.none(), "ub"_a.none(), "pairs"_a, "beta"_a.none(),
          "x0"_a.none());
    m.def("qp_front_on", [] { return qf.on; });
    m.def("qp_front_codes", [] {
        nb::list out;
        for (auto [kernel, code] : ran) out.append(nb::make_tuple(kernel ? "solve_gram" : "solve", code));
        return out;
    });
}
