// lemke._core.lcp_front: solve_lcp's common call whole in one native call (issue 31's thin
// front): plain float64 arrays, the tableau, no covering vector, cold or warm from a
// WarmStart (its int64 index array), default options. It reads the two ndarrays' fields directly (no DLPack capsule, no buffer view:
// those cost more than a small solve), allocates the output buffer with numpy.empty, runs
// lemke::first_run without the GIL and builds the LCPResult as LCPResult._lazy does.
//
// Returns the LCPResult when first_run settles the solve (solved and checked, q >= 0, or
// a checked ray); the tuple (code, pivots, k, ok, residual, recoveries, stage, buf) when
// the Python front must go on from first_run's answer (the same as _core.first_run's and
// its buffer); None when the arguments are not of that plain kind (the Python front then
// does everything). The same solve, the same bits as the Python fast path.
//
// The ndarray fields are those of NumPy's PyArrayObject (data, nd, dimensions, strides,
// base, descr, flags; the same in NumPy 1.x and 2.x) and of its descr (type_num). Before
// the first use, lcp_front_init checks that layout on probe arrays against what Python
// reports; if anything disagrees the fast front stays off (every call returns None).
#include <nanobind/nanobind.h>

#include <cstdint>
#include <cstring>

#include "lemke/lcp.hpp"
#include "lemke/pivoting.hpp"
#include "python_arrays.hpp"

namespace nb = nanobind;
using namespace nb::literals;

namespace {

struct Front {
    bool on = false;
    PyTypeObject* ndarray = nullptr;
    PyObject* result_cls = nullptr;  // LCPResult
    PyObject* solved = nullptr;      // Status.SOLVED
    PyObject* ray = nullptr;         // Status.RAY_TERMINATION
    PyObject* empty = nullptr;       // numpy.empty
    PyObject *k_status, *k_pivots, *k_residual, *k_recoveries, *k_src, *k_warm_start;
    int int64_num = -1;  // NumPy's type number of int64 here (7 or 9 by platform)
    double pivot_tol = 0, tie_tol = 0, tol = 0;
} front;

const ArrayFields* plain(PyObject* o, int nd) { return plain_f64(o, nd, front.ndarray); }

// The layout check on probes made by Python: (a 2 x 3 float64 C array, its data address,
// a read-only 1-D float64 array, an int64 array of 3, a float64 array of the other byte
// order).
bool layout_agrees(nb::handle probe2, std::uintptr_t address, nb::handle probe_ro,
                   nb::handle probe_int, nb::handle probe_swapped) {
    if (Py_TYPE(probe2.ptr()) != front.ndarray) return false;
    auto* a = reinterpret_cast<const ArrayFields*>(probe2.ptr());
    if (a->nd != 2 || a->dimensions[0] != 2 || a->dimensions[1] != 3 || a->strides[0] != 24 ||
        a->strides[1] != 8 || reinterpret_cast<std::uintptr_t>(a->data) != address ||
        (a->flags & CARRAY) != CARRAY)
        return false;
    auto* t = reinterpret_cast<const DescrFields*>(a->descr);
    if (t->type_num != NPY_DOUBLE || t->byteorder != '=') return false;
    auto* r = reinterpret_cast<const ArrayFields*>(probe_ro.ptr());
    if (r->nd != 1 || (r->flags & WRITEABLE) != 0 || (r->flags & C_CONTIGUOUS) == 0) return false;
    auto* i = reinterpret_cast<const ArrayFields*>(probe_int.ptr());
    if (i->nd != 1 || reinterpret_cast<const DescrFields*>(i->descr)->type_num == NPY_DOUBLE)
        return false;
    // the other byte order's float64 must be told apart
    return plain(probe_swapped.ptr(), 1) == nullptr;
}

void init(nb::handle ndarray, nb::handle result_cls, nb::handle solved, nb::handle ray,
          nb::handle empty, double pivot_tol, double tie_tol, double tol, nb::handle probe2,
          std::uintptr_t address, nb::handle probe_ro, nb::handle probe_int,
          nb::handle probe_swapped) {
    front.on = false;
    front.ndarray = reinterpret_cast<PyTypeObject*>(ndarray.ptr());
    if (!layout_agrees(probe2, address, probe_ro, probe_int, probe_swapped)) return;
    for (nb::handle h : {ndarray, result_cls, solved, ray, empty}) h.inc_ref();  // kept for good
    front.result_cls = result_cls.ptr();
    front.solved = solved.ptr();
    front.ray = ray.ptr();
    front.empty = empty.ptr();
    front.k_status = PyUnicode_InternFromString("status");
    front.k_pivots = PyUnicode_InternFromString("pivots");
    front.k_residual = PyUnicode_InternFromString("residual");
    front.k_recoveries = PyUnicode_InternFromString("recoveries");
    front.k_src = PyUnicode_InternFromString("_src");
    front.k_warm_start = PyUnicode_InternFromString("warm_start");
    front.int64_num = reinterpret_cast<const DescrFields*>(
        reinterpret_cast<const ArrayFields*>(probe_int.ptr())->descr)->type_num;
    front.pivot_tol = pivot_tol;
    front.tie_tol = tie_tol;
    front.tol = tol;
    front.on = front.k_status && front.k_pivots && front.k_residual && front.k_recoveries &&
               front.k_src && front.k_warm_start;
}

nb::object lcp_front(nb::handle M_h, nb::handle q_h, nb::handle ws, nb::handle beta_h) {
    using lemke::idx;
    if (!front.on) return nb::none();
    const ArrayFields* M = plain(M_h.ptr(), 2);
    const ArrayFields* q = plain(q_h.ptr(), 1);
    if (M == nullptr || q == nullptr) return nb::none();
    idx n = q->dimensions[0];
    if (M->dimensions[0] != n || M->dimensions[1] != n) return nb::none();
    // The warm start's basic z's (WarmStart._beta: int64, C-contiguous), in range.
    const idx* beta = nullptr;
    idx k = 0;
    if (!beta_h.is_none()) {
        auto* b = plain_i64(beta_h.ptr(), front.ndarray, front.int64_num);
        if (b == nullptr) return nb::none();
        beta = reinterpret_cast<const idx*>(b->data);
        k = b->dimensions[0];
        if (k > n) return nb::none();
        for (idx i = 0; i < k; ++i)
            if (beta[i] < 0 || beta[i] >= n) return nb::none();
    }
    lemke::BufferLayout L{n};
    idx at = L.length();
    nb::object size = nb::steal(PyLong_FromSsize_t(at + n));
    if (!size.is_valid()) throw nb::python_error();
    PyObject* args[] = {size.ptr()};
    nb::object buf = nb::steal(PyObject_Vectorcall(front.empty, args, 1, nullptr));
    if (!buf.is_valid()) throw nb::python_error();
    auto* b = reinterpret_cast<const ArrayFields*>(buf.ptr());
    double* out = reinterpret_cast<double*>(b->data);
    idx* basic = reinterpret_cast<idx*>(out + at);
    const double* Md = reinterpret_cast<const double*>(M->data);
    const double* qd = reinterpret_cast<const double*>(q->data);
    lemke::RunResult r;
    {
        nb::gil_scoped_release release;
        r = lemke::first_run(lemke::Mat<const double>(Md, n, n), qd, nullptr, beta, k,
                             100 * (n + 1), front.pivot_tol, front.tie_tol, front.tol, out, basic);
    }
    bool settled = r.ok && (r.code == lemke::SOLVED || r.code == lemke::TRIVIAL ||
                            r.code == lemke::RAY_TERMINATION);
    if (!settled)
        return nb::make_tuple(r.code, r.pivots, r.k, r.ok, r.residual, r.recoveries, r.stage, buf);
    // LCPResult._lazy: the status, pivots, residual, recoveries (when not 0) and the source
    // of the fields made when first read, (buf, 0, None, at, n, k).
    auto [res, dict] = new_result(front.result_cls);
    PyObject* d = dict.ptr();
    PyObject* status = r.code == lemke::RAY_TERMINATION ? front.ray : front.solved;
    Py_INCREF(status);
    bool ok = put(d, front.k_status, status) &&
              put(d, front.k_pivots, PyLong_FromLongLong(r.pivots)) &&
              put(d, front.k_residual, PyFloat_FromDouble(r.residual)) &&
              (r.recoveries == 0 || put(d, front.k_recoveries, PyLong_FromLongLong(r.recoveries)));
    if (ok) {
        nb::object src = nb::make_tuple(buf, 0, nb::none(), at, n, r.k);
        ok = PyDict_SetItem(d, front.k_src, src.ptr()) == 0;
    }
    if (ok && r.stage == 0)  // the warm start's own basis solved it: the result keeps it
        ok = PyDict_SetItem(d, front.k_warm_start, ws.ptr()) == 0;
    if (!ok) throw nb::python_error();
    return res;
}

}  // namespace

NumpyLayout numpy_layout() {
    return {front.on, front.ndarray, front.int64_num, front.empty};
}

void bind_front(nb::module_& m) {
    m.def("lcp_front_init", &init, "ndarray"_a, "result_cls"_a, "solved"_a, "ray"_a, "empty"_a,
          "pivot_tol"_a, "tie_tol"_a, "tol"_a, "probe2"_a, "address"_a, "probe_ro"_a,
          "probe_int"_a, "probe_swapped"_a);
    m.def("lcp_front", &lcp_front, "M"_a, "q"_a, "ws"_a.none(), "beta"_a.none());
    m.def("lcp_front_on", [] { return front.on; });
}
