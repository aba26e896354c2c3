// lemke._core's games functions: the bimatrix games engine (src/lemke/games.*) with the
// arguments and return values lemke/_games.py expects (lemke_howson, games_trace,
// games_check). Every
// size and label is checked before the GIL is released (ValueError otherwise), so bad input
// never reaches the engine.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/vector.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "lemke/basis.hpp"
#include "lemke/games.hpp"
#include "python_arrays.hpp"

namespace nb = nanobind;
using namespace nb::literals;

namespace {

using lemke::idx;
using Payoffs = Aligned<nb::ndarray<const double, nb::ndim<2>, nb::c_contig, nb::device::cpu>>;
using VecIn = Aligned<nb::ndarray<const double, nb::ndim<1>, nb::c_contig, nb::device::cpu>>;
using VecOut = Aligned<nb::ndarray<double, nb::ndim<1>, nb::c_contig, nb::device::cpu>>;
using LabelsIn = Aligned<nb::ndarray<const std::int64_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>>;
using LabelsOut = Aligned<nb::ndarray<std::int64_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>>;

idx len(std::size_t s) { return static_cast<idx>(s); }

void payoffs_ok(const char* fn, const Payoffs& A, const Payoffs& B, bool nonempty) {
    if (A.shape(0) != B.shape(0) || A.shape(1) != B.shape(1))
        throw nb::value_error((std::string(fn) + ": A and B must have the same shape").c_str());
    if (nonempty && (A.shape(0) == 0 || A.shape(1) == 0))
        throw nb::value_error((std::string(fn) + ": the game has an empty strategy set").c_str());
}

// games.lemke_howson(A, B, k, start, params, buf) -> (status, pivots, restarts).
std::tuple<int, std::int64_t, std::int64_t> lemke_howson(Payoffs A, Payoffs B, std::int64_t k,
                                                         LabelsIn start, VecIn params,
                                                         VecOut buf) {
    payoffs_ok("lemke_howson", A, B, true);
    idx m = len(A.shape(0)), n = len(A.shape(1)), L = m + n;
    if (k < 0 || k >= L) throw nb::value_error("lemke_howson: k must be a label in [0, m + n)");
    if (len(start.shape(0)) != L)
        throw nb::value_error("lemke_howson: start must hold n + m labels");
    // Each label basic in exactly one tableau: the path then always enters a non-basic
    // label (one that is basic in both would be read as a column: out of bounds).
    const idx* s = start.data();
    thread_local std::vector<std::uint8_t> seen;
    seen.assign(static_cast<std::size_t>(L), 0);
    for (idx i = 0; i < L; ++i) {
        if (s[i] < 0 || s[i] >= L || seen[s[i]])
            throw nb::value_error("lemke_howson: start must hold each label in [0, m + n) once");
        seen[s[i]] = 1;
    }
    if (len(params.shape(0)) < 4)
        throw nb::value_error("lemke_howson: params must be (max_pivots, pivot_tol, tie_tol, tol)");
    if (len(buf.shape(0)) < lemke::games::lh_buffer_length(m, n))
        throw nb::value_error("lemke_howson: buf must hold games_layout(m, n)'s length");
    lemke::games::LHResult r;
    {
        nb::gil_scoped_release release;
        r = lemke::games::lemke_howson(lemke::Mat<const double>(A.data(), m, n),
                                       lemke::Mat<const double>(B.data(), m, n), k, s,
                                       params.data(), buf.data());
    }
    return {r.status, r.pivots, r.restarts};
}

// games.trace(A, B, p, q, max_pivots, pivot_tol, tie_tol, tol, x, y, basis_out, out)
// -> (status, pivots).
std::tuple<int, std::int64_t> trace(Payoffs A, Payoffs B, VecIn p, VecIn q,
                                    std::int64_t max_pivots, double pivot_tol, double tie_tol,
                                    double tol, VecOut x, VecOut y, LabelsOut basis_out,
                                    VecOut out) {
    payoffs_ok("games_trace", A, B, true);
    idx m = len(A.shape(0)), n = len(A.shape(1));
    if (len(p.shape(0)) != m || len(q.shape(0)) != n || len(x.shape(0)) != m ||
        len(y.shape(0)) != n || len(basis_out.shape(0)) < lemke::games::trace_labels(m, n) ||
        len(out.shape(0)) < 3)
        throw nb::value_error("games_trace: p and x must have length m, q and y length n, "
                              "basis_out m + n + 2, out 3");
    lemke::games::TraceResult r;
    {
        nb::gil_scoped_release release;
        r = lemke::games::trace(lemke::Mat<const double>(A.data(), m, n),
                                lemke::Mat<const double>(B.data(), m, n), p.data(), q.data(),
                                max_pivots, pivot_tol, tie_tol, tol, x.data(), y.data(),
                                basis_out.data(), out.data());
    }
    return {r.status, r.pivots};
}

// games.check(A, B, x, y, tol, out) -> bool.
bool check(Payoffs A, Payoffs B, VecIn x, VecIn y, double tol, VecOut out) {
    payoffs_ok("games_check", A, B, false);
    idx m = len(A.shape(0)), n = len(A.shape(1));
    if (len(x.shape(0)) != m || len(y.shape(0)) != n || len(out.shape(0)) < 3)
        throw nb::value_error("games_check: x must have length m, y length n, out 3");
    nb::gil_scoped_release release;
    return lemke::games::check(lemke::Mat<const double>(A.data(), m, n),
                               lemke::Mat<const double>(B.data(), m, n), x.data(), y.data(), tol,
                               out.data());
}

// --- solve_bimatrix's native front ---------------------------------------------------------
//
// games_front(A, B, init_label): solve_bimatrix's commonest call whole in one native call
// (reached with no Python frame through solve_bimatrix's entry, games_entry in python_front.cpp),
// as lcp_front does solve_lcp's (src/python_front.cpp): A and B plain float64 (numpy_layout's
// plain_f64: C-contiguous, aligned, the machine's byte order, writable or not), of one non-empty
// shape, init_label an int in [0, m + n), Lemke-Howson from the artificial equilibrium,
// default options, no exact certificate. The buffer from numpy.empty, the slack start, the
// kernel without the GIL (the check on the caller's payoffs included), then:
//  - SOLVED: the BimatrixResult as BimatrixResult._lazy builds it (x and y made at once, as
//    read-only views of the buffer: new_view, NumPy's C API, else slices);
//  - any other code: the tuple (code, pivots, restarts, buf), for the Python front to go on
//    from (_finish, or the error naming a payoff that is not finite), as after its own call;
//  - None: arguments of another kind; the Python front does everything (the same call).

struct GamesFront {
    bool on = false;
    PyObject* result_cls = nullptr;  // BimatrixResult
    PyObject* solved = nullptr;      // Status.SOLVED
    PyObject* method = nullptr;      // "lemke-howson"
    PyObject *k_status, *k_pivots, *k_init_label, *k_method, *k_restarts, *k_lazy, *k_x, *k_y;
    // The result's __dict__: its keys in _lazy's order (then x, y), status SOLVED and method
    // set; games_front copies it and replaces the other values (no dict growth).
    PyObject* dict = nullptr;
    double params[4] = {0, 0, 0, 0};  // the defaults' (max_pivots, pivot_tol, tie_tol, tol)
} gf;

void front_init(nb::handle result_cls, nb::handle solved, nb::handle method, VecIn params) {
    gf.on = false;
    if (len(params.shape(0)) != 4) throw nb::value_error("games_front_init: 4 parameters");
    for (nb::handle h : {result_cls, solved, method}) h.inc_ref();  // kept for good
    gf.result_cls = result_cls.ptr();
    gf.solved = solved.ptr();
    gf.method = method.ptr();
    PyObject** keys[] = {&gf.k_status, &gf.k_pivots, &gf.k_init_label, &gf.k_method,
                         &gf.k_restarts, &gf.k_lazy, &gf.k_x, &gf.k_y};
    const char* names[] = {"status", "pivots", "init_label", "method", "restarts", "_lazy",
                           "x", "y"};
    for (std::size_t i = 0; i < 8; ++i) {
        *keys[i] = PyUnicode_InternFromString(names[i]);
        if (*keys[i] == nullptr) throw nb::python_error();
    }
    for (int i = 0; i < 4; ++i) gf.params[i] = params.data()[i];
    nb::object d = nb::steal(PyDict_New());
    if (!d.is_valid()) throw nb::python_error();
    for (std::size_t i = 0; i < 8; ++i) {
        PyObject* value = i == 0 ? solved.ptr() : i == 3 ? method.ptr() : Py_None;
        if (PyDict_SetItem(d.ptr(), *keys[i], value) != 0) throw nb::python_error();
    }
    Py_XDECREF(gf.dict);
    gf.dict = d.release().ptr();
    gf.on = numpy_layout().ok;
}

// The seam's games basis system (basis.hpp's SupportBasis) on the caller's payoffs, for
// _games._resolve_float: the vertex pair x_basic (P's n labels) and y_basic (Q's m labels),
// each label in [0, m + n) (ValueError otherwise; repeats make the blocks not square), its
// two bordered blocks factored, the point (x, y) and, with tol, games::check's verdict and
// out = (regret, row payoff, column payoff). Returns (code, x, y, out, v): code 0 the point
// passes the check (or no tol given: out None), 1 it fails, 2 no square blocks (|S| != |J|,
// |T| != |I| or an empty support), a block singular or its solution not finite, 3 a weight
// below -SupportBasis::CLIP (x, y None with 2 and 3), games::NOT_FINITE a payoff is not
// finite; v: rhs (one entry per row of x's block, then of y's) solved by diag(x's block,
// y's block), or with transpose by its transpose, None without rhs or a point or when that
// solve is not finite.
std::tuple<int, nb::object, nb::object, nb::object, nb::object> game_basis(
    Payoffs A, Payoffs B, const std::vector<std::int64_t>& x_basic,
    const std::vector<std::int64_t>& y_basic, std::optional<double> tol, std::optional<VecIn> rhs,
    bool transpose) {
    payoffs_ok("game_basis", A, B, true);
    idx m = len(A.shape(0)), n = len(A.shape(1));
    if (len(x_basic.size()) != n || len(y_basic.size()) != m)
        throw nb::value_error("game_basis: x_basic must hold n labels, y_basic m");
    std::vector<idx> labels(static_cast<std::size_t>(m + n));
    for (idx t = 0; t < m + n; ++t) {
        std::int64_t v = t < n ? x_basic[static_cast<std::size_t>(t)]
                               : y_basic[static_cast<std::size_t>(t - n)];
        if (v < 0 || v >= m + n) throw nb::value_error("game_basis: a label is out of [0, m + n)");
        labels[static_cast<std::size_t>(t)] = v;
    }
    lemke::Mat<const double> Am(A.data(), m, n), Bm(B.data(), m, n);
    std::vector<double> work(static_cast<std::size_t>(lemke::SupportBasis::work_size(m, n)));
    std::vector<idx> ints(static_cast<std::size_t>(lemke::SupportBasis::index_size(m, n)));
    std::vector<idx> piv(static_cast<std::size_t>(lemke::SupportBasis::piv_size(m, n)));
    lemke::SupportBasis basis(Am, Bm, work.data(), ints.data(), piv.data());
    bool square = basis.apply(labels.data());
    idx k = basis.bx.k + basis.by.k;
    if (square && rhs && len(rhs->shape(0)) != k)
        throw nb::value_error("game_basis: rhs must have one entry per row of the two blocks");
    nb::object x = new_array(m), y = new_array(n), out = new_array(3);
    nb::object v = rhs && square ? new_array(k) : nb::none();
    auto data = [](const nb::object& a) {
        return reinterpret_cast<double*>(reinterpret_cast<const ArrayFields*>(a.ptr())->data);
    };
    double *xd = data(x), *yd = data(y), *od = data(out), *vd = v.is_none() ? nullptr : data(v);
    int code;
    bool solved = false;
    {
        nb::gil_scoped_release release;
        if (!lemke::all_finite(A.data(), m * n) || !lemke::all_finite(B.data(), m * n)) {
            code = lemke::games::NOT_FINITE;
        } else if (!square || !basis.point(xd, yd)) {
            code = basis.negative ? 3 : 2;
        } else {
            if (vd != nullptr)
                solved = transpose ? basis.solve_transpose(rhs->data(), vd)
                                   : basis.solve(rhs->data(), vd);
            code = !tol || basis.check(xd, yd, *tol, od) ? 0 : 1;
        }
    }
    bool point = code == 0 || code == 1;
    return {code, point ? x : nb::none(), point ? y : nb::none(),
            point && tol ? out : nb::none(), solved ? v : nb::none()};
}

}  // namespace

// (declared in python_arrays.hpp: solve_bimatrix's entry calls it too)
nb::object games_front(nb::handle A_h, nb::handle B_h, nb::handle k_h) {
    if (!gf.on) return nb::none();
    NumpyLayout np = numpy_layout();
    const ArrayFields* A = plain_f64(A_h.ptr(), 2, np.ndarray);
    const ArrayFields* B = plain_f64(B_h.ptr(), 2, np.ndarray);
    if (A == nullptr || B == nullptr || !PyLong_CheckExact(k_h.ptr())) return nb::none();
    idx m = A->dimensions[0], n = A->dimensions[1];
    if (m == 0 || n == 0 || B->dimensions[0] != m || B->dimensions[1] != n) return nb::none();
    int overflow = 0;
    long long k = PyLong_AsLongLongAndOverflow(k_h.ptr(), &overflow);
    if (overflow != 0 || k < 0 || k >= m + n) return nb::none();
    lemke::games::LHLayout at{m, n};
    nb::object buf = new_array(at.length());
    double* out = reinterpret_cast<double*>(reinterpret_cast<const ArrayFields*>(buf.ptr())->data);
    thread_local std::vector<idx> start;
    start.resize(static_cast<std::size_t>(m + n));
    for (idx j = 0; j < n; ++j) start[j] = m + j;  // _games._slack_start
    for (idx i = 0; i < m; ++i) start[n + i] = i;
    lemke::games::LHResult r;
    {
        nb::gil_scoped_release release;
        r = lemke::games::lemke_howson(
            lemke::Mat<const double>(reinterpret_cast<const double*>(A->data), m, n),
            lemke::Mat<const double>(reinterpret_cast<const double*>(B->data), m, n), k,
            start.data(), gf.params, out);
    }
    if (r.status != lemke::SOLVED) return nb::make_tuple(r.status, r.pivots, r.restarts, buf);
    // BimatrixResult._lazy(buf, m, n, pivots, init_label, restarts), with x and y made at
    // once (every caller reads them; _FromKernel would make the same read-only views, the
    // buffer made read-only first, as NumPy's PyArray_CLEARFLAGS does, so views copy it).
    reinterpret_cast<ArrayFields*>(buf.ptr())->flags &= ~WRITEABLE;
    nb::object x = new_view(buf, at.x(), m);
    nb::object y = new_view(buf, at.y(), n);
    if (!x.is_valid() || !y.is_valid()) {  // (NumPy's C API not found: slices)
        x = buf[nb::slice(at.x(), at.x() + m)];
        y = buf[nb::slice(at.y(), at.y() + n)];
    }
    auto* cls = reinterpret_cast<PyTypeObject*>(gf.result_cls);
    nb::object res = nb::steal(cls->tp_alloc(cls, 0));
    if (!res.is_valid()) throw nb::python_error();
    nb::object dict = nb::steal(PyDict_Copy(gf.dict));
    if (!dict.is_valid()) throw nb::python_error();
    PyObject* d = dict.ptr();
    nb::object lazy = nb::make_tuple(buf, m, n);
    bool ok = put(d, gf.k_pivots, PyLong_FromLongLong(r.pivots)) &&
              PyDict_SetItem(d, gf.k_init_label, k_h.ptr()) == 0 &&
              put(d, gf.k_restarts, PyLong_FromLongLong(r.restarts)) &&
              PyDict_SetItem(d, gf.k_lazy, lazy.ptr()) == 0 &&
              PyDict_SetItem(d, gf.k_x, x.ptr()) == 0 && PyDict_SetItem(d, gf.k_y, y.ptr()) == 0 &&
              PyObject_GenericSetDict(res.ptr(), d, nullptr) == 0;
    if (!ok) throw nb::python_error();
    return res;
}

void bind_games(nb::module_& m) {
    m.def("games_front_init", &front_init, "result_cls"_a, "solved"_a, "method"_a, "params"_a);
    m.def("games_front", &games_front, "A"_a, "B"_a, "init_label"_a);
    // The games engine's buffer layout (games.hpp LHLayout; lemke/_games.py reads it here):
    // (x, y, regret, payoffs, labels, state, length) for lemke_howson's buffer of an m x n
    // game, then trace's (floats, labels) lengths.
    m.def("games_layout", [](std::int64_t rows, std::int64_t cols) {
        lemke::games::LHLayout L{rows, cols};
        return std::make_tuple(L.x(), L.y(), L.regret(), L.payoffs(), L.labels(), L.state(),
                               L.length(), lemke::games::trace_floats(rows, cols),
                               lemke::games::trace_labels(rows, cols));
    }, "m"_a, "n"_a);
    m.def("lemke_howson", &lemke_howson, "A"_a, "B"_a, "k"_a, "start"_a, "params"_a, "buf"_a);
    m.def("games_trace", &trace, "A"_a, "B"_a, "p"_a, "q"_a, "max_pivots"_a, "pivot_tol"_a,
          "tie_tol"_a, "tol"_a, "x"_a, "y"_a, "basis_out"_a, "out"_a);
    m.def("games_check", &check, "A"_a, "B"_a, "x"_a, "y"_a, "tol"_a, "out"_a);
    m.attr("GAMES_STATE") = lemke::games::STATE;
    m.attr("GAMES_HISTORY") = lemke::games::HISTORY;
    m.attr("GAMES_NOT_FINITE") = lemke::games::NOT_FINITE;
    m.attr("GAMES_UNCHECKED") = lemke::games::UNCHECKED;
    m.def("game_basis", &game_basis, "A"_a, "B"_a, "x_basic"_a, "y_basic"_a, "tol"_a = nb::none(),
          "rhs"_a = nb::none(), "transpose"_a = false);
}
