// lemke._core.lcp_front: solve_lcp's common call whole in one native call (issue 31's thin
// front): plain float64 arrays, either method, no covering vector, cold or warm from a
// WarmStart (its int64 index array), default options. It reads the two ndarrays' fields directly (no DLPack capsule, no buffer view:
// those cost more than a small solve), allocates the output buffer as numpy.empty does
// (new_array: through NumPy's C API), runs lemke::first_run for the tableau or
// lemke::solve_one for the unrevised method (method 1; without the GIL) and builds the
// LCPResult as LCPResult._lazy does.
//
// Returns the LCPResult when first_run settles the solve (solved and checked, q >= 0, or
// a checked ray); the tuple (code, pivots, k, ok, residual, recoveries, stage, buf) when
// the Python front must go on from the core's answer (the same as _core.first_run's or
// _core.solve_one's and its buffer); None when the arguments are not of that plain kind (the Python front then
// does everything). The same solve, the same bits as the Python fast path.
//
// The ndarray fields are those of NumPy's PyArrayObject (data, nd, dimensions, strides,
// base, descr, flags; the same in NumPy 1.x and 2.x) and of its descr (type_num). Before
// the first use, lcp_front_init checks that layout on probe arrays against what Python
// reports; if anything disagrees the fast front stays off (every call returns None).
#include <nanobind/nanobind.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <exception>
#include <limits>
#include <new>
#include <type_traits>

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
    PyObject* zero = nullptr;  // 0
    // The result's __dict__ of each kind (recoveries | warm start << 1): its keys in _lazy's
    // order, status SOLVED; lcp_front copies one.
    PyObject* templates[4] = {};
    int int64_num = -1;  // NumPy's type number of int64 here (7 or 9 by platform)
    double pivot_tol = 0, tie_tol = 0, tol = 0;
    // NumPy's PyArray_NewFromDescr (its C API table's entry 94, the same in NumPy 1.x and
    // 2.x) and the float64 and int64 dtypes it is given (stolen: a reference each call);
    // new_from_descr stays null (numpy.empty is called) unless its probe array is right.
    using NewFromDescr = PyObject* (*)(PyTypeObject*, PyObject*, int, const Py_ssize_t*,
                                       const Py_ssize_t*, void*, int, PyObject*);
    NewFromDescr new_from_descr = nullptr;
    bool views = false;  // new_view's arrays checked on a probe (else it declines)
    PyObject *f64 = nullptr, *i64 = nullptr;
} front;

constexpr int OWNDATA = 0x0004;
constexpr int kNewFromDescr = 94;  // PyArray_NewFromDescr's index in NumPy's API table

PyObject* new_from_descr(Py_ssize_t len, PyObject* descr) {
    Py_INCREF(descr);  // (stolen by NumPy)
    return front.new_from_descr(front.ndarray, descr, 1, &len, nullptr, nullptr, 0, nullptr);
}

// new_view's array, unchecked: PyArray_NewFromDescr on base's data (not owned, not
// writable), base set as slicing sets it (NumPy's dealloc releases it).
PyObject* view_of(PyObject* base, Py_ssize_t offset, Py_ssize_t len) {
    Py_INCREF(front.f64);  // (stolen by NumPy)
    char* data = reinterpret_cast<const ArrayFields*>(base)->data + offset * sizeof(double);
    PyObject* a = front.new_from_descr(front.ndarray, front.f64, 1, &len, nullptr, data,
                                       C_CONTIGUOUS | ALIGNED, nullptr);
    if (a != nullptr) {
        Py_INCREF(base);
        reinterpret_cast<ArrayFields*>(a)->base = base;
    }
    return a;
}

// NumPy's C API from its _ARRAY_API capsule (None: not found), kept when a probe array it
// makes is what numpy.empty(3) makes: a 1-D float64 array of 3 that owns its data, C-
// contiguous, aligned and writable.
void find_new_from_descr(nb::handle api) {
    front.new_from_descr = nullptr;
    if (!PyCapsule_CheckExact(api.ptr())) return;
    auto** table = static_cast<void**>(PyCapsule_GetPointer(api.ptr(), nullptr));
    if (table == nullptr) {
        PyErr_Clear();
        return;
    }
    front.new_from_descr = reinterpret_cast<Front::NewFromDescr>(table[kNewFromDescr]);
    nb::object probe = nb::steal(new_from_descr(3, front.f64));
    auto* a = probe.is_valid() ? plain_f64(probe.ptr(), 1, front.ndarray) : nullptr;
    if (a == nullptr || a->dimensions[0] != 3 || a->strides[0] != 8 || a->base != nullptr ||
        (a->flags & OWNDATA) == 0 || (a->flags & WRITEABLE) == 0) {
        PyErr_Clear();
        front.new_from_descr = nullptr;
        return;
    }
    // a view of the probe's last two doubles: what probe[1:3] of a read-only probe is
    nb::object v = nb::steal(view_of(probe.ptr(), 1, 2));
    auto* w = reinterpret_cast<const ArrayFields*>(v.ptr());
    front.views = v.is_valid() && Py_TYPE(v.ptr()) == front.ndarray && w->nd == 1 &&
                  w->dimensions[0] == 2 && w->strides[0] == 8 && w->descr == front.f64 &&
                  w->data == a->data + 8 && w->base == probe.ptr() &&
                  (w->flags & (OWNDATA | WRITEABLE)) == 0 &&
                  (w->flags & (C_CONTIGUOUS | ALIGNED)) == (C_CONTIGUOUS | ALIGNED);
    if (!front.views) PyErr_Clear();
}

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
          nb::handle probe_swapped, nb::handle api) {
    front.on = false;
    front.new_from_descr = nullptr;
    front.views = false;
    front.ndarray = reinterpret_cast<PyTypeObject*>(ndarray.ptr());
    if (!layout_agrees(probe2, address, probe_ro, probe_int, probe_swapped)) return;
    for (nb::handle h : {ndarray, result_cls, solved, ray, empty}) h.inc_ref();  // kept for good
    front.f64 = reinterpret_cast<const ArrayFields*>(probe2.ptr())->descr;
    front.i64 = reinterpret_cast<const ArrayFields*>(probe_int.ptr())->descr;
    Py_INCREF(front.f64);
    Py_INCREF(front.i64);
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
    front.zero = PyLong_FromLong(0);
    front.on = front.k_status && front.k_pivots && front.k_residual && front.k_recoveries &&
               front.k_src && front.k_warm_start && front.zero;
    for (int v = 0; v < 4 && front.on; ++v) {
        PyObject* t = front.templates[v] = PyDict_New();
        front.on = t != nullptr && PyDict_SetItem(t, front.k_status, solved.ptr()) == 0 &&
                   PyDict_SetItem(t, front.k_pivots, Py_None) == 0 &&
                   PyDict_SetItem(t, front.k_residual, Py_None) == 0 &&
                   ((v & 1) == 0 || PyDict_SetItem(t, front.k_recoveries, Py_None) == 0) &&
                   PyDict_SetItem(t, front.k_src, Py_None) == 0 &&
                   ((v & 2) == 0 || PyDict_SetItem(t, front.k_warm_start, Py_None) == 0);
    }
    if (!front.on) PyErr_Clear();
    if (front.on) find_new_from_descr(api);
}

nb::object lcp_front(nb::handle M_h, nb::handle q_h, nb::handle ws, nb::handle beta_h,
                     int method = lemke::TABLEAU) {
    using lemke::idx;
    if (!front.on || (method != lemke::TABLEAU && method != lemke::UNREVISED)) return nb::none();
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
    nb::object buf = new_array(at + n);
    auto* b = reinterpret_cast<const ArrayFields*>(buf.ptr());
    double* out = reinterpret_cast<double*>(b->data);
    idx* basic = reinterpret_cast<idx*>(out + at);
    const double* Md = reinterpret_cast<const double*>(M->data);
    const double* qd = reinterpret_cast<const double*>(q->data);
    // the whole solve, as the Python fast path and _go_on make it in two calls: the
    // tableau's first run and, from its stage -1 (a cycle, a ray to check, a failed check)
    // or -2 (a warm restart), solve_one from where it stopped (lemke::solve, the batch's
    // path: the same calls, so the same bits); the unrevised method's solve_one. A run
    // whose answer is not settled (stage 1 or 2, not ok) goes on in _after_front's _outcome.
    auto run = [&] {
        return lemke::solve(static_cast<lemke::Method>(method), lemke::Mat<const double>(Md, n, n),
                            qd, nullptr, beta, k, 100 * (n + 1), front.pivot_tol, front.tie_tol,
                            front.tol, out, basic);
    };
    lemke::RunResult r;
    {
        // every solve releases the GIL (the project's rule), even a solve of one row, whose
        // release and retake (~0.1 us) is a fifth of the call: another Python thread never
        // waits on a solve
        nb::gil_scoped_release release;
        r = run();
    }
    bool settled = lemke::lcp_settled(r.code, r.ok);
    if (!settled)
        return nb::make_tuple(r.code, r.pivots, r.k, r.ok, r.residual, r.recoveries, r.stage, buf);
    // LCPResult._lazy: the status, pivots, residual, recoveries (when not 0), the source of
    // the fields made when first read, (buf, 0, None, at, n, k), and the warm start when its
    // own basis solved it; in a copy of the template of its kind (its keys in that order:
    // the values replaced, no dict growth).
    auto* cls = reinterpret_cast<PyTypeObject*>(front.result_cls);
    nb::object res = nb::steal(cls->tp_alloc(cls, 0));
    if (!res.is_valid()) throw nb::python_error();
    bool warm = r.stage == 0;  // the warm start's own basis solved it: the result keeps it
    nb::object dict = nb::steal(PyDict_Copy(front.templates[int(r.recoveries != 0) | int(warm) << 1]));
    if (!dict.is_valid()) throw nb::python_error();
    PyObject* d = dict.ptr();
    PyObject* src = PyTuple_New(6);
    if (src != nullptr) {
        PyObject* items[] = {buf.release().ptr(), front.zero, Py_None, PyLong_FromSsize_t(at),
                             PyLong_FromSsize_t(n), PyLong_FromSsize_t(r.k)};
        Py_INCREF(front.zero);
        Py_INCREF(Py_None);
        for (int i = 0; i < 6; ++i) PyTuple_SET_ITEM(src, i, items[i]);  // (a null: error below)
        if (!items[3] || !items[4] || !items[5]) Py_CLEAR(src);
    }
    bool ok = (r.code != lemke::RAY_TERMINATION ||
               PyDict_SetItem(d, front.k_status, front.ray) == 0) &&
              put(d, front.k_pivots, PyLong_FromLongLong(r.pivots)) &&
              put(d, front.k_residual, PyFloat_FromDouble(r.residual)) &&
              (r.recoveries == 0 || put(d, front.k_recoveries, PyLong_FromLongLong(r.recoveries))) &&
              put(d, front.k_src, src) &&
              (!warm || PyDict_SetItem(d, front.k_warm_start, ws.ptr()) == 0) &&
              PyObject_GenericSetDict(res.ptr(), d, nullptr) == 0;
    if (!ok) throw nb::python_error();
    return res;
}

// lemke._lcp.solve_lcp itself: a callable object whose calls solve_lcp(M, q) and
// solve_lcp(M, q, warm_start=ws), either also with method="tableau" or "unrevised" (exact
// str), go to lcp_front without a Python frame (the frame of a
// function of six keyword-only arguments, their defaults looked up one by one, costs a
// fifth of such a call at n = 1); any other call, and any that lcp_front declines, is the
// Python function's (_lcp._solve_lcp), which the entry wraps (functools.update_wrapper:
// its name, docstring, signature). A run that first_run did not settle goes on in
// _lcp._after_front (with the method when it is the unrevised one), as in the Python front. The entry steps aside (the Python function
// does it all) when _lcp._FRONT is no longer _core.lcp_front (a test that switches the
// front off) or when the warm start is not a WarmStart of q's size with its index array.
struct Entry {
    PyObject_HEAD
    PyObject* dict;  // __doc__, __wrapped__, ... (set by functools.update_wrapper)
    vectorcallfunc vectorcall;
    PyObject* py;       // _lcp._solve_lcp
    PyObject* after;    // _lcp._after_front(M, q, warm_start, beta, r) (or _games', _blcp's)
    PyObject* globals;  // _lcp's namespace (its _FRONT read each call)
    PyObject* front;    // _core.lcp_front as first bound
    PyObject* ws_cls;   // WarmStart
    PyObject *k_front, *k_warm_start, *k_beta, *k_n, *k_init_label, *k_findex, *k_method;
    PyObject *s_tableau, *s_unrevised;  // solve_lcp's method= values its front takes
    // solve_lcp_many's entry only (null in solve_lcp's): _batch's namespace (its FEW read
    // each call), LCPManyResult, the key of what LCPManyResult._of sets and () for its
    // object.__new__
    PyObject *many_globals, *many_cls, *k_few, *k_items, *no_args;
};

// The index array of a warm start ws for a problem of size n: true when ws is a WarmStart of
// that size with its index array (WarmStart._beta), as the Python front asks; else false
// (no error set), and the Python front does it (and makes _beta).
// Both are read from the instance's __dict__ (where WarmStart keeps them: the class has no
// descriptor of either name), two lookups instead of two attribute reads through the type.
bool warm_beta(Entry* e, PyObject* ws, Py_ssize_t n, nb::object& beta) {
    if (Py_TYPE(ws) != reinterpret_cast<PyTypeObject*>(e->ws_cls)) return false;
    nb::object dict = nb::steal(PyObject_GenericGetDict(ws, nullptr));
    PyObject* size = dict.is_valid() ? PyDict_GetItemWithError(dict.ptr(), e->k_n) : nullptr;
    PyObject* b = size != nullptr ? PyDict_GetItemWithError(dict.ptr(), e->k_beta) : nullptr;
    if (b != nullptr && PyLong_CheckExact(size) && PyLong_AsSsize_t(size) == n) {
        beta = nb::borrow(b);
        return true;
    }
    PyErr_Clear();
    return false;
}

// Whether a keyword of a call is `name` (an interned string; a keyword is a str).
bool is_key(PyObject* key, PyObject* name) {
    return key == name || PyUnicode_Compare(key, name) == 0;
}

// Whether kwnames (of a call with two positional arguments) is only warm_start.
bool only_warm_start(Entry* e, PyObject* kwnames) {
    return PyTuple_GET_SIZE(kwnames) == 1 && is_key(PyTuple_GET_ITEM(kwnames, 0), e->k_warm_start);
}

// solve_lcp's method= value as the core's code, when it is the str "tableau" or
// "unrevised" (false for anything else: the Python function's, which says what is wrong).
bool method_code(Entry* e, PyObject* v, int& method) {
    if (!PyUnicode_CheckExact(v)) return false;
    if (is_key(v, e->s_tableau)) method = lemke::TABLEAU;
    else if (is_key(v, e->s_unrevised)) method = lemke::UNREVISED;
    else return false;
    return true;
}

// The exception in flight (in a catch block) set as Python's error; Py_None, which the
// entries' helpers return for "an error, set".
PyObject* error_set() {
    try {
        throw;
    } catch (nb::python_error& err) {
        err.restore();
    } catch (const std::bad_alloc&) {
        PyErr_NoMemory();
    } catch (const std::exception& err) {
        PyErr_SetString(PyExc_RuntimeError, err.what());
    } catch (...) {
        PyErr_SetString(PyExc_RuntimeError, "unknown C++ exception");
    }
    return Py_None;
}

// One entry of a list given for a float64 array, as np.asarray(x).astype(float64) has it:
// a Python float (or a subclass: its value), a bool (1.0 or 0.0) or an int that fits in
// int64 (rounded to the nearest double, as NumPy casts its int64 array; a bigger one makes
// NumPy's array another dtype: declined). False (no error set) for anything else.
// (The exact types first: a subclass check walks the type's bases.)
bool list_entry(PyObject* v, double& out) {
    if (PyFloat_CheckExact(v)) {
        out = PyFloat_AS_DOUBLE(v);
        return true;
    }
    if (!PyLong_CheckExact(v)) {
        if (PyBool_Check(v)) {
            out = v == Py_True ? 1.0 : 0.0;
            return true;
        }
        if (!PyFloat_Check(v)) return false;
        out = PyFloat_AS_DOUBLE(v);
        return true;
    }
    // an int of one digit read as it lies (CPython's layout of the version built for)
#if PY_VERSION_HEX >= 0x030C0000
    if (PyUnstable_Long_IsCompact(reinterpret_cast<PyLongObject*>(v))) {
        out = static_cast<double>(PyUnstable_Long_CompactValue(reinterpret_cast<PyLongObject*>(v)));
        return true;
    }
#elif PY_VERSION_HEX >= 0x030B0000
    Py_ssize_t size = Py_SIZE(v);
    if (size >= -1 && size <= 1) {  // (ob_digit[0] undefined for 0)
        auto d = static_cast<long long>(reinterpret_cast<PyLongObject*>(v)->ob_digit[0]);
        out = static_cast<double>(size == 0 ? 0 : size * d);
        return true;
    }
#endif
    int overflow = 0;
    long long i = PyLong_AsLongLongAndOverflow(v, &overflow);
    if (overflow != 0 || (i == -1 && PyErr_Occurred())) {
        PyErr_Clear();
        return false;
    }
    out = static_cast<double>(i);
    return true;
}

// NumPy's type numbers of the array dtypes made_f64 casts (NumPy's own, 1.x and 2.x).
enum : int { T_BOOL = 0, T_BYTE, T_UBYTE, T_SHORT, T_USHORT, T_INT, T_UINT, T_LONG, T_ULONG,
             T_LONGLONG, T_ULONGLONG, T_FLOAT, T_DOUBLE };

// The entries of an nd-dimensional array (rows x cols, strides s0, s1 in bytes, any
// alignment) of the C type T, as float64 in C order: NumPy's cast (astype), the C
// conversion of each value (exact but for 64-bit ints, rounded to nearest as NumPy's).
// (Bool: NumPy's bool, one byte, any non-zero value true as NumPy's cast reads it.)
struct Bool {
    unsigned char v;
};
template <class T>
void cast_rows(const char* data, Py_ssize_t rows, Py_ssize_t cols, Py_ssize_t s0, Py_ssize_t s1,
               double* out) {
    for (Py_ssize_t i = 0; i < rows; ++i)
        for (Py_ssize_t j = 0; j < cols; ++j) {
            T v;
            std::memcpy(&v, data + i * s0 + j * s1, sizeof(T));
            if constexpr (std::is_same_v<T, Bool>)
                out[i * cols + j] = v.v != 0 ? 1.0 : 0.0;
            else
                out[i * cols + j] = static_cast<double>(v);
        }
}

}  // namespace

// (new_rows, bound_value, pack_form and pack_into: declared in python_arrays.hpp, for qp_front.)
// The new float64 C array made_f64 fills (rows x cols; 1-D when nd is 1).
nb::object new_rows(int nd, Py_ssize_t rows, Py_ssize_t cols) {
    Py_ssize_t dims[2] = {rows, cols};
    Py_INCREF(front.f64);  // (stolen by NumPy)
    nb::object a = nb::steal(front.new_from_descr(front.ndarray, front.f64, nd, dims, nullptr,
                                                  nullptr, 0, nullptr));
    if (!a.is_valid()) throw nb::python_error();
    return a;
}

namespace {

// The entries of the ndarray a (nd dimensions) as float64 in C order into out, NumPy's
// astype (cast_rows), when its dtype is bool, a signed int, an unsigned int up to 32 bits,
// float32 or float64; false for another dtype (float16, long double, uint64, complex,
// object...). out nullptr: the dtype judged only.
bool cast_into(const ArrayFields* a, int nd, double* out) {
    Py_ssize_t rows = a->dimensions[0], cols = nd == 2 ? a->dimensions[1] : 1;
    Py_ssize_t s0 = a->strides[0], s1 = nd == 2 ? a->strides[1] : 0;
    auto make = [&](auto tag) {
        if (out != nullptr) cast_rows<decltype(tag)>(a->data, rows, cols, s0, s1, out);
        return true;
    };
    switch (reinterpret_cast<const DescrFields*>(a->descr)->type_num) {
        case T_BOOL: return make(Bool{});
        case T_BYTE: return make(static_cast<signed char>(0));
        case T_UBYTE: return make(static_cast<unsigned char>(0));
        case T_SHORT: return make(short{});
        case T_USHORT: return make(static_cast<unsigned short>(0));
        case T_INT: return make(int{});
        case T_UINT: return make(0u);
        case T_LONG: return make(0L);
        case T_LONGLONG: return make(0LL);
        case T_FLOAT: return make(0.0f);
        case T_DOUBLE: return make(0.0);
        default: return false;
    }
}

// Whether the ndarray x of nd dimensions (none 0) is one cast_array casts: not plain
// float64, a dtype cast_into knows in the machine's byte order (any strides: Fortran
// order, a slice, unaligned); its rows and cols (1 for nd 1).
bool castable(PyObject* x, int nd, Py_ssize_t& rows, Py_ssize_t& cols) {
    auto* a = reinterpret_cast<const ArrayFields*>(x);
    auto* t = reinterpret_cast<const DescrFields*>(a->descr);
    if (a->nd != nd || plain(x, nd) != nullptr || (t->byteorder != '=' && t->byteorder != '|'))
        return false;
    rows = a->dimensions[0];
    cols = nd == 2 ? a->dimensions[1] : 1;
    return rows != 0 && cols != 0 && cast_into(a, nd, nullptr);
}

// An ndarray x of nd dimensions that is not plain float64 made a float64 C array as
// NumPy's astype makes it, when castable; else x itself (the front declines it, the
// Python function converts or refuses it).
nb::object cast_array(PyObject* x, int nd) {
    Py_ssize_t rows, cols;
    if (!castable(x, nd, rows, cols)) return nb::borrow(x);
    nb::object out = new_rows(nd, rows, cols);
    cast_into(reinterpret_cast<const ArrayFields*>(x), nd,
              reinterpret_cast<double*>(reinterpret_cast<const ArrayFields*>(out.ptr())->data));
    return out;
}

bool exact_seq(PyObject* o) { return PyList_CheckExact(o) || PyTuple_CheckExact(o); }

// Whether x is a list or tuple of nd levels (1 or 2; rows, lists or tuples, of one length;
// no dimension 0) as made_f64 converts them; its rows and cols (1 for nd 1). Its entries
// are list_into's to judge.
bool list_shape(PyObject* x, int nd, Py_ssize_t& rows, Py_ssize_t& cols) {
    if (!exact_seq(x)) return false;
    rows = PySequence_Fast_GET_SIZE(x);
    cols = 1;
    if (rows == 0) return false;
    if (nd == 2) {
        PyObject** row = PySequence_Fast_ITEMS(x);
        if (!exact_seq(row[0]) || (cols = PySequence_Fast_GET_SIZE(row[0])) == 0) return false;
        for (Py_ssize_t i = 1; i < rows; ++i)
            if (!exact_seq(row[i]) || PySequence_Fast_GET_SIZE(row[i]) != cols) return false;
    }
    return true;
}

// The entries of x (list_shape's, rows x cols) by list_entry into out in C order; false at
// the first one list_entry declines (out then partly written).
bool list_into(PyObject* x, int nd, Py_ssize_t rows, Py_ssize_t cols, double* out) {
    PyObject** row = PySequence_Fast_ITEMS(x);
    for (Py_ssize_t i = 0; i < rows; ++i) {
        if (nd == 1) {
            if (!list_entry(row[i], out[i])) return false;
            continue;
        }
        PyObject** v = PySequence_Fast_ITEMS(row[i]);
        for (Py_ssize_t j = 0; j < cols; ++j)
            if (!list_entry(v[j], out[i * cols + j])) return false;
    }
    return true;
}

// x made a float64 C array when it is a list or tuple of list_shape's of list_entry's
// numbers, or an ndarray cast_array casts: the values that the Python fronts' conversion
// (_validate.plain: np.asarray, then float64 and C order) gives. Else x itself when it is an
// ndarray (the front judges it), or an invalid object (declined: the Python function
// converts or refuses it).
nb::object made_f64(PyObject* x, int nd) {
    if (nd != 1 && nd != 2) return nb::object();  // (new_rows makes 1-D and 2-D arrays only)
    if (front.new_from_descr == nullptr) return Py_TYPE(x) == front.ndarray ? nb::borrow(x) : nb::object();
    if (Py_TYPE(x) == front.ndarray) return cast_array(x, nd);
    Py_ssize_t rows, cols;
    if (!list_shape(x, nd, rows, cols)) return nb::object();
    nb::object a = new_rows(nd, rows, cols);
    if (!list_into(x, nd, rows, cols,
                   reinterpret_cast<double*>(reinterpret_cast<const ArrayFields*>(a.ptr())->data)))
        return nb::object();
    return a;
}

}  // namespace

bool bound_value(PyObject* x, int side, double wrong, double& v) {
    return list_entry(x, v) && v == v && -side * v < wrong;
}

namespace {

// solve_blcp's bound lo (side -1) or hi (side 1) as _validate.plain_blcp makes it: made_f64's
// array, or a Python float or int64-sized int spread over q's n rows (np.full(n, float(x))),
// q an ndarray; NaN and an infinity of the wrong side declined (bound_value; invalid: the
// validation's message then).
nb::object made_bound(PyObject* x, PyObject* q, int side) {
    if (!PyFloat_CheckExact(x) && !PyLong_CheckExact(x)) return made_f64(x, 1);
    auto* qa = reinterpret_cast<const ArrayFields*>(q);
    double v;
    if (Py_TYPE(q) != front.ndarray || qa->nd != 1 || qa->dimensions[0] == 0 ||
        front.new_from_descr == nullptr ||
        !bound_value(x, side, std::numeric_limits<double>::infinity(), v))
        return nb::object();
    Py_ssize_t n = qa->dimensions[0];
    nb::object out = new_rows(1, n, 1);
    double* d = reinterpret_cast<double*>(reinterpret_cast<const ArrayFields*>(out.ptr())->data);
    for (Py_ssize_t i = 0; i < n; ++i) d[i] = v;
    return out;
}

// The entries' arguments args[0..k) made float64 C arrays by made_f64 (ranks nd): true
// when one was made and every one is now an ndarray (kept in `keep`, their pointers in
// `out`), else false (the front's decline stands).
bool made_arrays(PyObject* const* args, const int* nd, int k, nb::object* keep, PyObject** out) {
    bool some = false;
    for (int i = 0; i < k; ++i) {
        keep[i] = made_f64(args[i], nd[i]);
        if (!keep[i].is_valid()) return false;
        some = some || keep[i].ptr() != args[i];
        out[i] = keep[i].ptr();
    }
    return some;
}

PyObject* entry_front(Entry* e, PyObject* M, PyObject* q, PyObject* ws, PyObject* beta,
                      int method) {
    try {
        nb::object r = lcp_front(M, q, ws, beta, method);
        if (r.is_none()) return nullptr;  // (no error set: the Python function's to do)
        if (!PyTuple_CheckExact(r.ptr())) return r.release().ptr();
        // _after_front(M, q, ws, beta, r), with the method when it is not the tableau
        PyObject* args[] = {M, q, ws, beta, r.ptr(), e->s_unrevised};
        PyObject* res = PyObject_Vectorcall(e->after, args, method == lemke::TABLEAU ? 5 : 6,
                                            nullptr);
        return res != nullptr ? res : Py_None;  // (Py_None, not owned: an error is set)
    } catch (...) {
        return error_set();
    }
}

PyObject* entry_call(PyObject* self, PyObject* const* args, std::size_t nargsf,
                     PyObject* kwnames) {
    auto* e = reinterpret_cast<Entry*>(self);
    Py_ssize_t nargs = PyVectorcall_NARGS(nargsf);
    if (nargs == 2 && front.on) {
        // the keywords taken: warm_start= and method= ("tableau" or "unrevised")
        PyObject* ws = Py_None;
        int method = lemke::TABLEAU;
        bool plain = true;
        Py_ssize_t nk = kwnames == nullptr ? 0 : PyTuple_GET_SIZE(kwnames);
        for (Py_ssize_t i = 0; i < nk && plain; ++i) {
            PyObject* key = PyTuple_GET_ITEM(kwnames, i);
            if (is_key(key, e->k_warm_start))
                ws = args[2 + i];
            else
                plain = is_key(key, e->k_method) && method_code(e, args[2 + i], method);
        }
        PyObject* now = plain ? PyDict_GetItemWithError(e->globals, e->k_front) : nullptr;
        if (now == e->front) {
            // M and q as given, then (when the front declines and either needs converting)
            // as made_f64 makes them
            PyObject* Mq[2] = {args[0], args[1]};
            nb::object keep[2];
            static const int ranks[2] = {2, 1};
            for (int pass = 0; pass < 2; ++pass) {
                PyObject* res = nullptr;
                nb::object beta;
                if (ws == Py_None) {
                    res = entry_front(e, Mq[0], Mq[1], Py_None, Py_None, method);
                } else if (Py_TYPE(Mq[1]) == front.ndarray &&
                           reinterpret_cast<const ArrayFields*>(Mq[1])->nd == 1 &&
                           warm_beta(e, ws, reinterpret_cast<const ArrayFields*>(Mq[1])->dimensions[0],
                                     beta)) {
                    res = entry_front(e, Mq[0], Mq[1], ws, beta.ptr(), method);
                }
                if (res == Py_None) return nullptr;  // an error, set
                if (res != nullptr) return res;
                try {
                    if (pass == 1 || !made_arrays(args, ranks, 2, keep, Mq)) break;
                } catch (...) {
                    error_set();
                    return nullptr;
                }
            }
        } else if (now == nullptr && PyErr_Occurred()) {
            return nullptr;
        }
    }
    return PyObject_Vectorcall(e->py, args, nargsf, kwnames);
}

// solve_lcp_many(Ms, qs) and solve_lcp_many(Ms, qs, warm_start=ws) of 1..FEW problems, lists
// or tuples of plain arrays (n >= 1; or array-likes made_f64 converts) and of None or
// WarmStart: each problem's lcp_front, as
// _batch._few calls solve_lcp, and the LCPManyResult that LCPManyResult._of makes of them.
// nullptr: declined (the Python function does it all: any problem that lcp_front declines
// or does not settle, a WarmStartBatch, ...); Py_None: an error, set.
PyObject* many_front(Entry* e, PyObject* M, PyObject* q, PyObject* wss) {
    auto seq = [](PyObject* o) { return PyList_CheckExact(o) || PyTuple_CheckExact(o); };
    if (!seq(M) || !seq(q)) return nullptr;
    Py_ssize_t B = PySequence_Fast_GET_SIZE(M);
    if (B < 1 || PySequence_Fast_GET_SIZE(q) != B) return nullptr;
    if (wss != Py_None && (!seq(wss) || PySequence_Fast_GET_SIZE(wss) != B)) return nullptr;
    PyObject* now = PyDict_GetItemWithError(e->globals, e->k_front);
    PyObject* few = now == e->front ? PyDict_GetItemWithError(e->many_globals, e->k_few) : nullptr;
    if (few == nullptr || !PyLong_CheckExact(few)) return PyErr_Occurred() ? Py_None : nullptr;
    if (B > PyLong_AsSsize_t(few)) {
        PyErr_Clear();  // (an overflow)
        return nullptr;
    }
    PyObject** Ms = PySequence_Fast_ITEMS(M);
    PyObject** qs = PySequence_Fast_ITEMS(q);
    PyObject** ws = wss == Py_None ? nullptr : PySequence_Fast_ITEMS(wss);
    try {
        nb::object items = nb::steal(PyList_New(B));
        if (!items.is_valid()) return Py_None;
        for (Py_ssize_t b = 0; b < B; ++b) {
            // the problem as given, or made float64 C arrays by made_f64 (as _batch._few's
            // caller converts it); else declined
            PyObject *Mo = Ms[b], *qo = qs[b];
            nb::object Mk, qk;
            if (plain(Mo, 2) == nullptr && (Mk = made_f64(Mo, 2)).is_valid()) Mo = Mk.ptr();
            if (plain(qo, 1) == nullptr && (qk = made_f64(qo, 1)).is_valid()) qo = qk.ptr();
            auto* qb = reinterpret_cast<const ArrayFields*>(qo);
            if (Py_TYPE(qo) != front.ndarray || qb->nd != 1 || qb->dimensions[0] < 1)
                return nullptr;
            PyObject* w = ws == nullptr ? Py_None : ws[b];
            nb::object beta = nb::none();
            if (w != Py_None && !warm_beta(e, w, qb->dimensions[0], beta)) return nullptr;
            nb::object r = lcp_front(Mo, qo, w, beta);
            if (r.is_none() || PyTuple_CheckExact(r.ptr())) return nullptr;
            PyList_SET_ITEM(items.ptr(), b, r.release().ptr());
        }
        // LCPManyResult._of(items): object.__new__ (the instance's attribute values inline,
        // no dictionary made) and _items set (_off is the class's None, _special made when
        // first read)
        auto* cls = reinterpret_cast<PyTypeObject*>(e->many_cls);
        nb::object res = nb::steal(PyBaseObject_Type.tp_new(cls, e->no_args, nullptr));
        bool ok = res.is_valid() && PyObject_SetAttr(res.ptr(), e->k_items, items.ptr()) == 0;
        return ok ? res.release().ptr() : Py_None;
    } catch (...) {
        return error_set();
    }
}

PyObject* many_call(PyObject* self, PyObject* const* args, std::size_t nargsf,
                    PyObject* kwnames) {
    auto* e = reinterpret_cast<Entry*>(self);
    if (PyVectorcall_NARGS(nargsf) == 2 && front.on &&
        (kwnames == nullptr || only_warm_start(e, kwnames))) {
        PyObject* res = many_front(e, args[0], args[1], kwnames == nullptr ? Py_None : args[2]);
        if (res == Py_None) return nullptr;  // an error, set
        if (res != nullptr) return res;
    }
    return PyObject_Vectorcall(e->py, args, nargsf, kwnames);
}

// solve_bimatrix(A, B) and solve_bimatrix(A, B, init_label=k): games_front without a Python
// frame, as entry_call does lcp_front; a run games_front does not settle goes on in
// _games._after_front(A, B, k, (code, pivots, restarts, buf)); any other call, and any
// that games_front declines, is the Python function's (_games._solve_bimatrix).
PyObject* games_call(PyObject* self, PyObject* const* args, std::size_t nargsf,
                     PyObject* kwnames) {
    auto* e = reinterpret_cast<Entry*>(self);
    bool plain = kwnames == nullptr ||
                 (PyTuple_GET_SIZE(kwnames) == 1 &&
                  is_key(PyTuple_GET_ITEM(kwnames, 0), e->k_init_label));
    if (PyVectorcall_NARGS(nargsf) == 2 && plain && front.on) {
        PyObject* now = PyDict_GetItemWithError(e->globals, e->k_front);
        if (now == nullptr && PyErr_Occurred()) return nullptr;
        if (now == e->front) {
            PyObject* k = kwnames == nullptr ? front.zero : args[2];
            try {
                // A and B as given, then (when the front declines and either needs
                // converting) as made_f64 makes them
                PyObject* AB[2] = {args[0], args[1]};
                nb::object keep[2];
                static const int ranks[2] = {2, 2};
                for (int pass = 0; pass < 2; ++pass) {
                    nb::object r = games_front(AB[0], AB[1], k);
                    if (!r.is_none() && !PyTuple_CheckExact(r.ptr())) return r.release().ptr();
                    if (!r.is_none()) {
                        PyObject* after[] = {AB[0], AB[1], k, r.ptr()};
                        return PyObject_Vectorcall(e->after, after, 4, nullptr);
                    }
                    if (pass == 1 || !made_arrays(args, ranks, 2, keep, AB)) break;
                }
            } catch (...) {
                error_set();
                return nullptr;
            }
        }
    }
    return PyObject_Vectorcall(e->py, args, nargsf, kwnames);
}

// solve_blcp(M, q, lo, hi) with no keyword but findex= and/or warm_start=: blcp_front without
// a Python frame, as games_call does games_front; a run blcp_front does not settle (a tuple
// for _finish, False for _general) goes on in _blcp._after_front(M, q, lo, hi, findex,
// warm_start, r); any other call, and any that blcp_front declines, is the Python
// function's (_blcp._solve_blcp).
PyObject* blcp_call(PyObject* self, PyObject* const* args, std::size_t nargsf,
                    PyObject* kwnames) {
    auto* e = reinterpret_cast<Entry*>(self);
    Py_ssize_t nargs = PyVectorcall_NARGS(nargsf);
    Py_ssize_t nk = kwnames == nullptr ? 0 : PyTuple_GET_SIZE(kwnames);
    bool plain = nargs == 4 && front.on;
    PyObject *fi = Py_None, *ws = Py_None;
    for (Py_ssize_t i = 0; i < nk && plain; ++i) {
        PyObject* key = PyTuple_GET_ITEM(kwnames, i);
        if (is_key(key, e->k_findex))
            fi = args[4 + i];
        else if (is_key(key, e->k_warm_start))
            ws = args[4 + i];
        else
            plain = false;
    }
    if (plain) {
        PyObject* now = PyDict_GetItemWithError(e->globals, e->k_front);
        if (now == nullptr && PyErr_Occurred()) return nullptr;
        if (now == e->front) {
            try {
                // M, q, lo, hi as given, then (when the front declines and any needs
                // converting) as made_f64 and made_bound make them
                PyObject* a[4] = {args[0], args[1], args[2], args[3]};
                nb::object keep[4];
                auto made = [&] {
                    bool some = false;
                    for (int i = 0; i < 4; ++i) {
                        keep[i] = i < 2 ? made_f64(args[i], 2 - i) : made_bound(args[i], a[1], 2 * i - 5);
                        if (!keep[i].is_valid()) return false;
                        some = some || keep[i].ptr() != args[i];
                        a[i] = keep[i].ptr();
                    }
                    return some;
                };
                for (int pass = 0; pass < 2; ++pass) {
                    nb::object r = blcp_front(a[0], a[1], a[2], a[3], fi, ws);
                    if (!r.is_none()) {
                        if (r.ptr() != Py_False && !PyTuple_CheckExact(r.ptr())) return r.release().ptr();
                        PyObject* after[] = {a[0], a[1], a[2], a[3], fi, ws, r.ptr()};
                        return PyObject_Vectorcall(e->after, after, 7, nullptr);
                    }
                    if (pass == 1 || !made()) break;
                }
            } catch (...) {
                error_set();
                return nullptr;
            }
        }
    }
    return PyObject_Vectorcall(e->py, args, nargsf, kwnames);
}

PyObject* entry_get(PyObject* self, PyObject*, PyObject*) {  // (not bound, as a function)
    Py_INCREF(self);
    return self;
}

PyObject* entry_repr(PyObject* self) {  // the wrapped function's
    return PyObject_Repr(reinterpret_cast<Entry*>(self)->py);
}

PyObject* entry_reduce(PyObject* self, PyObject*) {  // pickled by name, as a function
    return PyObject_GetAttrString(self, "__name__");
}

PyMethodDef entry_methods[] = {
    {"__reduce__", entry_reduce, METH_NOARGS, nullptr},
    {nullptr, nullptr, 0, nullptr},
};

PyGetSetDef entry_getset[] = {
    {"__dict__", PyObject_GenericGetDict, PyObject_GenericSetDict, nullptr, nullptr},
    {nullptr, nullptr, nullptr, nullptr, nullptr},
};

PyTypeObject entry_type = [] {
    PyTypeObject t{PyVarObject_HEAD_INIT(nullptr, 0)};
    t.tp_name = "lemke._core.LCPEntry";
    t.tp_basicsize = sizeof(Entry);
    t.tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_HAVE_VECTORCALL;
    t.tp_doc = "solve_lcp's, solve_lcp_many's, solve_bimatrix's or solve_blcp's entry (src/python_front.cpp)";
    t.tp_call = PyVectorcall_Call;
    t.tp_vectorcall_offset = offsetof(Entry, vectorcall);
    t.tp_dictoffset = offsetof(Entry, dict);
    t.tp_getattro = PyObject_GenericGetAttr;
    t.tp_setattro = PyObject_GenericSetAttr;
    t.tp_descr_get = entry_get;
    t.tp_methods = entry_methods;
    t.tp_getset = entry_getset;
    t.tp_repr = entry_repr;
    return t;
}();

// An entry wrapping py: solve_lcp's (many_globals and many_cls None), or solve_lcp_many's.
nb::object make_entry(nb::handle py, nb::handle after, nb::handle globals, nb::handle front_fn,
                      nb::handle ws_cls, nb::handle many_globals, nb::handle many_cls) {
    if (PyType_Ready(&entry_type) < 0) throw nb::python_error();
    auto* e = PyObject_New(Entry, &entry_type);
    if (e == nullptr) throw nb::python_error();
    e->dict = nullptr;
    bool many = !many_cls.is_none();
    e->vectorcall = many ? many_call : entry_call;
    PyObject** keep[] = {&e->py, &e->after, &e->globals, &e->front, &e->ws_cls,
                         &e->many_globals, &e->many_cls};
    nb::handle given[] = {py, after, globals, front_fn, ws_cls, many_globals, many_cls};
    for (int i = 0; i < 7; ++i) *keep[i] = given[i].inc_ref().ptr();  // kept for good
    PyObject** keys[] = {&e->k_front, &e->k_warm_start, &e->k_beta, &e->k_n, &e->k_few,
                         &e->k_items, &e->k_init_label, &e->k_findex, &e->k_method,
                         &e->s_tableau, &e->s_unrevised};
    const char* names[] = {"_FRONT", "warm_start", "_beta", "n", "FEW", "_items", "init_label",
                           "findex", "method", "tableau", "unrevised"};
    nb::object res = nb::steal(reinterpret_cast<PyObject*>(e));
    for (int i = 0; i < 11; ++i)
        if ((*keys[i] = PyUnicode_InternFromString(names[i])) == nullptr) throw nb::python_error();
    if ((e->no_args = PyTuple_New(0)) == nullptr) throw nb::python_error();
    return res;
}

nb::object lcp_entry(nb::handle py, nb::handle after, nb::handle globals, nb::handle front_fn,
                     nb::handle ws_cls) {
    return make_entry(py, after, globals, front_fn, ws_cls, nb::none(), nb::none());
}

// solve_bimatrix's entry (games_call).
nb::object games_entry(nb::handle py, nb::handle after, nb::handle globals, nb::handle front_fn) {
    nb::object res = make_entry(py, after, globals, front_fn, nb::none(), nb::none(), nb::none());
    reinterpret_cast<Entry*>(res.ptr())->vectorcall = games_call;
    return res;
}

// solve_blcp's entry (blcp_call).
nb::object blcp_entry(nb::handle py, nb::handle after, nb::handle globals, nb::handle front_fn) {
    nb::object res = make_entry(py, after, globals, front_fn, nb::none(), nb::none(), nb::none());
    reinterpret_cast<Entry*>(res.ptr())->vectorcall = blcp_call;
    return res;
}

nb::object lcp_many_entry(nb::handle py, nb::handle globals, nb::handle front_fn,
                          nb::handle ws_cls, nb::handle many_globals, nb::handle many_cls) {
    return make_entry(py, nb::none(), globals, front_fn, ws_cls, many_globals, many_cls);
}

// An island of n rows added to a pack's running lengths (m_len += n * n, q_len += n): false,
// the lengths as they were, where a length's bytes as float64 would pass the largest
// Py_ssize_t (array views of a huge shape, as np.lib.stride_tricks.as_strided makes with
// strides 0: islands whose sum of n * n wraps around would allocate too little): the pack
// declines.
template <class T>
bool add_island(T n, T& m_len, T& q_len) {
    constexpr T top = std::numeric_limits<T>::max() / static_cast<T>(sizeof(double));
    if (n > 0 && (n > top / n || n * n > top - m_len || n > top - q_len)) return false;
    m_len += n * n;
    q_len += n;
    return true;
}

}  // namespace

// How lcp_pack takes x (M, nd 2, or q, nd 1; its rows and cols): 0 a plain array, copied; 1
// an array-like made_f64 converts (a castable ndarray, or a list or tuple of list_shape's),
// its values written in place as made_f64 makes them; -1 anything else (declined).
int pack_form(PyObject* x, int nd, Py_ssize_t& rows, Py_ssize_t& cols) {
    if (const ArrayFields* a = plain(x, nd)) {
        rows = a->dimensions[0];
        cols = nd == 2 ? a->dimensions[1] : 1;
        return 0;
    }
    if (front.new_from_descr == nullptr) return -1;
    if (Py_TYPE(x) == front.ndarray) return castable(x, nd, rows, cols) ? 1 : -1;
    return list_shape(x, nd, rows, cols) ? 1 : -1;
}

// x (pack_form's 0 or 1) written to out, rows x cols in C order: false where a list entry
// is declined (list_entry).
bool pack_into(PyObject* x, int nd, Py_ssize_t rows, Py_ssize_t cols, double* out) {
    if (const ArrayFields* a = plain(x, nd)) {
        std::size_t bytes = static_cast<std::size_t>(rows * cols) * sizeof(double);
        if (bytes) std::memcpy(out, a->data, bytes);
        return true;
    }
    if (Py_TYPE(x) == front.ndarray) return cast_into(reinterpret_cast<const ArrayFields*>(x), nd, out);
    return list_into(x, nd, rows, cols, out);
}

namespace {

// solve_lcp_many's problems given as lists: (Mflat, qflat, n_b) with every M's rows and
// every q end to end in two new float64 arrays and the sizes in an int64 array, when M and
// q are lists (or tuples) of the same length B >= 1 whose items are ready for the kernels
// as they are (plain(): float64 ndarrays in the machine's byte order, C arrays) or
// array-likes that made_f64 converts (lists or tuples of numbers, other dtypes, other
// strides: converted here into the packed arrays, the same values), M square of q's size;
// else None: the Python path then checks and converts them and names what is wrong. One
// pass of checks, then the copies and conversions (a few nanoseconds per island, where
// Python's checks and joins took about half a microsecond). Finiteness is the kernels'
// when every item was plain; when any was converted, a NaN or an infinity anywhere
// declines the lot (None), so that the Python path checks every problem in order and raises
// at the first fault, as it does for such input.
nb::object lcp_pack(nb::handle M_h, nb::handle q_h) {
    using lemke::idx;
    PyObject *M = M_h.ptr(), *q = q_h.ptr();
    if (!front.on || !exact_seq(M) || !exact_seq(q)) return nb::none();
    Py_ssize_t B = PySequence_Fast_GET_SIZE(M);
    if (B < 1 || PySequence_Fast_GET_SIZE(q) != B) return nb::none();
    PyObject** Ms = PySequence_Fast_ITEMS(M);
    PyObject** qs = PySequence_Fast_ITEMS(q);
    nb::object sizes = new_array(B, true);
    auto data = [](const nb::object& a) { return reinterpret_cast<const ArrayFields*>(a.ptr())->data; };
    auto* no = reinterpret_cast<std::int64_t*>(data(sizes));
    idx m_len = 0, q_len = 0;
    bool converted = false;
    for (Py_ssize_t b = 0; b < B; ++b) {
        Py_ssize_t mr, mc, n, one;
        int mf = pack_form(Ms[b], 2, mr, mc), qf = pack_form(qs[b], 1, n, one);
        if (mf < 0 || qf < 0 || mr != n || mc != n) return nb::none();
        if (!add_island<idx>(n, m_len, q_len)) return nb::none();
        converted = converted || mf != 0 || qf != 0;
        no[b] = n;
    }
    nb::object Mf = new_array(m_len), qf = new_array(q_len);
    auto* mo = reinterpret_cast<double*>(data(Mf));
    auto* qo = reinterpret_cast<double*>(data(qf));
    for (Py_ssize_t b = 0; b < B; ++b) {
        idx n = no[b];
        if (!converted) {  // (all plain: the copies alone)
            auto src = [](PyObject* a) { return reinterpret_cast<const ArrayFields*>(a)->data; };
            if (n) std::memcpy(mo, src(Ms[b]), static_cast<std::size_t>(n * n) * sizeof(double));
            if (n) std::memcpy(qo, src(qs[b]), static_cast<std::size_t>(n) * sizeof(double));
        } else if (!pack_into(Ms[b], 2, n, n, mo) || !pack_into(qs[b], 1, n, 1, qo)) {
            return nb::none();
        }
        mo += n * n;
        qo += n;
    }
    if (converted) {
        const double* m0 = reinterpret_cast<const double*>(data(Mf));
        const double* q0 = reinterpret_cast<const double*>(data(qf));
        for (idx i = 0; i < m_len; ++i)
            if (!std::isfinite(m0[i])) return nb::none();
        for (idx i = 0; i < q_len; ++i)
            if (!std::isfinite(q0[i])) return nb::none();
    }
    return nb::make_tuple(Mf, qf, sizes);
}


// A new C array of rows x cols float64 (int64 with ints), uninitialized, as numpy.empty((rows,
// cols)) makes it (new_array's 2-D form).
nb::object new_array2(Py_ssize_t rows, Py_ssize_t cols, bool ints) {
    PyObject* a;
    PyObject* descr = ints ? front.i64 : front.f64;
    if (front.new_from_descr != nullptr) {
        Py_ssize_t dims[2] = {rows, cols};
        Py_INCREF(descr);  // (stolen by NumPy)
        a = front.new_from_descr(front.ndarray, descr, 2, dims, nullptr, nullptr, 0, nullptr);
    } else {
        nb::object shape = nb::make_tuple(rows, cols);
        PyObject* args[] = {shape.ptr(), descr};
        a = PyObject_Vectorcall(front.empty, args, 2, nullptr);
    }
    if (a == nullptr) throw nb::python_error();
    return nb::steal(a);
}

template <class T>
T* data_of(const nb::object& a) {
    return reinterpret_cast<T*>(reinterpret_cast<const ArrayFields*>(a.ptr())->data);
}

// A bound of solve_blcp_many's island b (side -1: lo, 1: hi) as blcp_pack takes it: 0 a
// plain array of n numbers, 1 one Python float or int64-sized int for every row (spread as
// _validate._scalar_bound spreads it; *v its value), 2 an array-like made_f64 converts (as
// pack_form's 1), -1 anything else (declined).
int bound_form(PyObject* x, Py_ssize_t n, double* v) {
    if (PyFloat_CheckExact(x) || PyLong_CheckExact(x)) return list_entry(x, *v) ? 1 : -1;
    Py_ssize_t rows, cols;
    int f = pack_form(x, 1, rows, cols);
    return f < 0 || rows != n ? -1 : f == 0 ? 0 : 2;
}

// An island's findex as blcp_pack takes it: 0 a plain int64 array of n entries, 1 a list
// or tuple of n exact Python ints within int64 (what np.asarray makes int64), -1 else.
int findex_form(PyObject* x, Py_ssize_t n) {
    if (const ArrayFields* a = plain_i64(x, front.ndarray, front.int64_num))
        return a->dimensions[0] == n ? 0 : -1;
    if (!exact_seq(x) || PySequence_Fast_GET_SIZE(x) != n || n == 0) return -1;
    PyObject** v = PySequence_Fast_ITEMS(x);
    for (Py_ssize_t i = 0; i < n; ++i)
        if (!PyLong_CheckExact(v[i])) return -1;
    return 1;
}

// Whether island data that _validate.blcp would convert passes its checks as it stands
// (M, q finite; lo not NaN nor +inf, hi not NaN nor -inf, lo <= hi; each friction row as
// _validate._findex wants it): else blcp_pack declines, and the Python path raises its error.
bool blcp_valid(const double* M, const double* q, const double* lo, const double* hi,
                const std::int64_t* f, Py_ssize_t n) {
    constexpr double inf = std::numeric_limits<double>::infinity();
    for (Py_ssize_t i = 0; i < n * n; ++i)
        if (!std::isfinite(M[i])) return false;
    for (Py_ssize_t i = 0; i < n; ++i)
        if (!std::isfinite(q[i]) || lo[i] != lo[i] || hi[i] != hi[i] || lo[i] == inf ||
            hi[i] == -inf || lo[i] > hi[i])
            return false;
    if (f == nullptr) return true;
    for (Py_ssize_t i = 0; i < n; ++i) {
        std::int64_t fi = f[i];
        if (fi == -1) continue;
        if (fi < 0 || fi >= n || fi == i || f[fi] != -1 || hi[i] < 0 || !std::isfinite(hi[i]) ||
            lo[i] != -hi[i] || lo[fi] < 0)
            return false;
    }
    return true;
}

// solve_blcp_many's islands given as sequences (M, q, lo, hi: lists or tuples of B >= 1,
// lo and hi also one Python number for all; findex None or a list or tuple of None or
// int64 arrays or lists of ints): (Mflat, qflat, loflat, hiflat, fiflat or None, fflag
// (int64), n_b), every island's laid end to end as _blcp_many._islands and _flat lay them
// (a scalar bound spread over its rows, an island without findex -1 on its rows; fiflat
// None when no island has one), when each is plain (float64 C arrays; int64 findex) or an
// array-like made_f64 converts (pack_form, pack_into: the same values); else None, and the
// Python path checks them and names what is wrong. As for lcp_pack, data that is all plain
// is the kernels' to judge; when any was converted, anything _validate.blcp would refuse
// declines the lot (None), so that the Python path raises at the first fault as before.
nb::object blcp_pack(nb::handle M_h, nb::handle q_h, nb::handle lo_h, nb::handle hi_h,
                     nb::handle f_h) {
    PyObject *M = M_h.ptr(), *q = q_h.ptr(), *lo = lo_h.ptr(), *hi = hi_h.ptr(), *fi = f_h.ptr();
    if (!front.on || front.new_from_descr == nullptr || !exact_seq(M) || !exact_seq(q))
        return nb::none();
    Py_ssize_t B = PySequence_Fast_GET_SIZE(M);
    auto each = [B](PyObject* v) -> PyObject** {  // (nullptr: not a sequence of B)
        return exact_seq(v) && PySequence_Fast_GET_SIZE(v) == B ? PySequence_Fast_ITEMS(v) : nullptr;
    };
    bool lo_one = PyFloat_CheckExact(lo) || PyLong_CheckExact(lo);
    bool hi_one = PyFloat_CheckExact(hi) || PyLong_CheckExact(hi);
    PyObject** los = lo_one ? nullptr : each(lo);
    PyObject** his = hi_one ? nullptr : each(hi);
    PyObject** fis = fi == Py_None ? nullptr : each(fi);
    if (B < 1 || PySequence_Fast_GET_SIZE(q) != B || (!lo_one && los == nullptr) ||
        (!hi_one && his == nullptr) || (fi != Py_None && fis == nullptr))
        return nb::none();
    PyObject** Ms = PySequence_Fast_ITEMS(M);
    PyObject** qs = PySequence_Fast_ITEMS(q);
    nb::object sizes = new_array(B, true), flags = new_array(B, true);
    auto* no = data_of<std::int64_t>(sizes);
    auto* fl = data_of<std::int64_t>(flags);
    Py_ssize_t m_len = 0, q_len = 0;
    bool converted = false, friction = false;
    for (Py_ssize_t b = 0; b < B; ++b) {
        Py_ssize_t mr, mc, n, one;
        double v;
        int mf = pack_form(Ms[b], 2, mr, mc), qf = pack_form(qs[b], 1, n, one);
        if (mf < 0 || qf < 0 || mr != n || mc != n) return nb::none();
        int lf = bound_form(lo_one ? lo : los[b], n, &v), hf = bound_form(hi_one ? hi : his[b], n, &v);
        PyObject* f = fis == nullptr ? Py_None : fis[b];
        int ff = f == Py_None ? 0 : findex_form(f, n);
        if (lf < 0 || hf < 0 || ff < 0 || !add_island(n, m_len, q_len)) return nb::none();
        converted = converted || mf != 0 || qf != 0 || lf != 0 || hf != 0 || ff != 0;
        fl[b] = f != Py_None;
        friction = friction || fl[b] != 0;
        no[b] = n;
    }
    nb::object Mf = new_array(m_len), qf = new_array(q_len), lf = new_array(q_len),
               hf = new_array(q_len), ff = friction ? new_array(q_len, true) : nb::none();
    double *mo = data_of<double>(Mf), *qo = data_of<double>(qf), *lo_o = data_of<double>(lf),
           *hi_o = data_of<double>(hf);
    std::int64_t* fo = friction ? data_of<std::int64_t>(ff) : nullptr;
    auto bound_into = [](PyObject* x, Py_ssize_t n, double* out) {
        double v;
        if (PyFloat_CheckExact(x) || PyLong_CheckExact(x)) {
            if (!list_entry(x, v)) return false;
            for (Py_ssize_t i = 0; i < n; ++i) out[i] = v;
            return true;
        }
        return pack_into(x, 1, n, 1, out);
    };
    for (Py_ssize_t b = 0; b < B; ++b) {
        Py_ssize_t n = no[b];
        PyObject* f = fis == nullptr ? Py_None : fis[b];
        if (!pack_into(Ms[b], 2, n, n, mo) || !pack_into(qs[b], 1, n, 1, qo) ||
            !bound_into(lo_one ? lo : los[b], n, lo_o) || !bound_into(hi_one ? hi : his[b], n, hi_o))
            return nb::none();
        if (fo != nullptr) {
            if (f == Py_None) {
                for (Py_ssize_t i = 0; i < n; ++i) fo[i] = -1;
            } else if (const ArrayFields* a = plain_i64(f, front.ndarray, front.int64_num)) {
                if (n) std::memcpy(fo, a->data, static_cast<std::size_t>(n) * sizeof(std::int64_t));
            } else {
                PyObject** v = PySequence_Fast_ITEMS(f);
                for (Py_ssize_t i = 0; i < n; ++i) {
                    int overflow = 0;
                    long long x = PyLong_AsLongLongAndOverflow(v[i], &overflow);
                    if (overflow != 0 || (x == -1 && PyErr_Occurred())) {
                        PyErr_Clear();
                        return nb::none();
                    }
                    fo[i] = x;
                }
            }
        }
        if (converted && !blcp_valid(mo, qo, lo_o, hi_o, fo != nullptr && f != Py_None ? fo : nullptr, n))
            return nb::none();
        mo += n * n;
        qo += n;
        lo_o += n;
        hi_o += n;
        if (fo != nullptr) fo += n;
    }
    return nb::make_tuple(Mf, qf, lf, hf, ff, flags, sizes);
}

// solve_lcp_many's set-up for B >= 1 problems of sizes n_b (`sizes`: a 1-D int64 array, each
// >= 0) with M and q packed (1-D float64 C arrays, writable, of sum n_b^2 and sum n_b
// numbers: what _batch._packed and lcp_pack give): the offsets (int64 (3, B + 1), from 0:
// of q and the basic z's, of M, of the output buffers, as _batch._offsets gives them
// summed), the pivot caps (100 (n_b + 1) as Options.pivot_limit, or max_pivots when it is
// >= 0), the batch's work (the sum of n_b^3, as _batch._cubes), the sizes as a list, and the
// kernels' outputs uninitialized (bufs, basics, out_i (B, 5), out_f (B, 2)). None when the
// arguments are not of that kind: the Python steps then check them and say what is wrong.
nb::object many_setup(nb::handle sizes_h, nb::handle M_h, nb::handle q_h, std::int64_t max_pivots) {
    using lemke::idx;
    if (!front.on) return nb::none();
    const ArrayFields* s = plain_i64(sizes_h.ptr(), front.ndarray, front.int64_num);
    const ArrayFields* M = plain_f64(M_h.ptr(), 1, front.ndarray);
    const ArrayFields* q = plain_f64(q_h.ptr(), 1, front.ndarray);
    if (s == nullptr || M == nullptr || q == nullptr || (M->flags & WRITEABLE) == 0 ||
        (q->flags & WRITEABLE) == 0)
        return nb::none();
    Py_ssize_t B = s->dimensions[0];
    if (B < 1) return nb::none();
    const auto* n_b = reinterpret_cast<const std::int64_t*>(s->data);
    idx m_len = 0, q_len = 0;
    double work = 0.0;
    for (Py_ssize_t b = 0; b < B; ++b) {
        idx n = n_b[b];
        if (n < 0 || n > (idx{1} << 20)) return nb::none();  // (n * n cannot overflow)
        q_len += n;
        m_len += n * n;
        if (m_len > M->dimensions[0]) return nb::none();  // (no sum can overflow)
        double nf = static_cast<double>(n);
        work += nf * nf * nf;
    }
    if (m_len != M->dimensions[0] || q_len != q->dimensions[0]) return nb::none();
    nb::object off = new_array2(3, B + 1, true), limits = new_array(B, true);
    nb::object list = nb::steal(PyList_New(B));
    if (!list.is_valid()) throw nb::python_error();
    auto* o = data_of<std::int64_t>(off);
    auto* lim = data_of<std::int64_t>(limits);
    std::int64_t *qo = o, *mo = o + (B + 1), *bo = o + 2 * (B + 1);
    qo[0] = mo[0] = bo[0] = 0;
    for (Py_ssize_t b = 0; b < B; ++b) {
        idx n = n_b[b];
        qo[b + 1] = qo[b] + n;
        mo[b + 1] = mo[b] + n * n;
        bo[b + 1] = bo[b] + lemke::BufferLayout{n}.length();
        lim[b] = max_pivots >= 0 ? max_pivots : 100 * (n + 1);
        PyObject* v = PyLong_FromLongLong(n);
        if (v == nullptr) throw nb::python_error();
        PyList_SET_ITEM(list.ptr(), b, v);
    }
    nb::object bufs = new_array(bo[B]), basics = new_array(qo[B], true);
    nb::object out_i = new_array2(B, 5, true), out_f = new_array2(B, 2, false);
    return nb::make_tuple(off, limits, work, list, bufs, basics, out_i, out_f);
}

// o when it is a 1-D uint8 ndarray, C-contiguous and aligned (BLCPManyResult's friction
// flags), else nullptr.
const ArrayFields* plain_u8(PyObject* o) {
    constexpr int need = C_CONTIGUOUS | ALIGNED;
    constexpr int NPY_UBYTE = 2;
    if (Py_TYPE(o) != front.ndarray) return nullptr;
    auto* a = reinterpret_cast<const ArrayFields*>(o);
    return a->nd == 1 && (a->flags & need) == need &&
                   reinterpret_cast<const DescrFields*>(a->descr)->type_num == NPY_UBYTE
               ? a
               : nullptr;
}

// Whether o is a 2-D (B, cols) ndarray of NumPy's type type_num in the machine's byte order,
// C-contiguous and aligned (the kernels' out_i and out_f; read through typed pointers).
bool native_rows(PyObject* o, Py_ssize_t cols, int type_num) {
    constexpr int need = C_CONTIGUOUS | ALIGNED;
    if (Py_TYPE(o) != front.ndarray) return false;
    auto* a = reinterpret_cast<const ArrayFields*>(o);
    auto* t = reinterpret_cast<const DescrFields*>(a->descr);
    return a->nd == 2 && a->dimensions[1] == cols && (a->flags & need) == need &&
           t->type_num == type_num && t->byteorder == '=';
}

// The problems b of a batch (solve_lcp_many) whose answers the Python front must build:
// (those whose code is NOT_FINITE, those not settled: not ok, or a code other than SOLVED,
// TRIVIAL and RAY_TERMINATION), two lists (out_i (B, 5) and out_f (B, 2), the kernels').
// This and the two below return None where lcp_front_init found another NumPy layout (the
// front off): the Python steps then do it with numpy.
nb::object many_unsettled(nb::handle out_i_h, nb::handle out_f_h) {
    if (!front.on) return nb::none();
    auto* oi = reinterpret_cast<const ArrayFields*>(out_i_h.ptr());
    auto* of = reinterpret_cast<const ArrayFields*>(out_f_h.ptr());
    if (!native_rows(out_i_h.ptr(), 5, front.int64_num) || !native_rows(out_f_h.ptr(), 2, NPY_DOUBLE) ||
        oi->dimensions[0] != of->dimensions[0])
        throw nb::type_error("many_unsettled: out_i must be int64 (B, 5), out_f float64 (B, 2)");
    const auto* code = reinterpret_cast<const std::int64_t*>(oi->data);
    const auto* ok = reinterpret_cast<const double*>(of->data);
    nb::list not_finite, special;
    for (Py_ssize_t b = 0; b < oi->dimensions[0]; ++b) {
        std::int64_t c = code[5 * b];
        if (c == lemke::NOT_FINITE) not_finite.append(b);
        if (!lemke::lcp_settled(static_cast<int>(c), ok[2 * b] != 0.0))
            special.append(b);
    }
    return nb::make_tuple(not_finite, special);
}

// Every problem's span [a n + c_b, a n + c_b + n) of its output buffer (bufs from buff[b]; n
// from qoff) end to end, a new float64 array (LCPManyResult's z and w: a = 0, c = 0 and a =
// 2, c = 2, _layout.BUFFER). c_b is c, plus answer[b] where `answer` (int64, B) is given
// (BLCPManyResult: where island b's answer sits in its buffer, boxed.islands). Where `flag`
// (uint8, B) is given, a problem whose flag is 0 takes its span [qoff[b], qoff[b + 1]) of
// `flat` (float64) instead (BLCPManyResult's lo and hi: the buffer's with a friction index,
// else the caller's flat bounds).
nb::object many_field(nb::handle bufs_h, nb::handle buff_h, nb::handle qoff_h, std::int64_t a,
                      std::int64_t c, nb::handle answer_h, nb::handle flag_h, nb::handle flat_h) {
    const ArrayFields* bufs = plain_f64(bufs_h.ptr(), 1, front.ndarray);
    const ArrayFields* buff = plain_i64(buff_h.ptr(), front.ndarray, front.int64_num);
    const ArrayFields* qoff = plain_i64(qoff_h.ptr(), front.ndarray, front.int64_num);
    const ArrayFields* answer = answer_h.is_none() ? nullptr
                                                   : plain_i64(answer_h.ptr(), front.ndarray, front.int64_num);
    const ArrayFields* flag = flag_h.is_none() ? nullptr : plain_u8(flag_h.ptr());
    const ArrayFields* flat = flag_h.is_none() ? nullptr : plain_f64(flat_h.ptr(), 1, front.ndarray);
    if (!front.on) return nb::none();
    if (bufs == nullptr || buff == nullptr || qoff == nullptr ||
        buff->dimensions[0] != qoff->dimensions[0] || qoff->dimensions[0] < 1 ||
        (!answer_h.is_none() && (answer == nullptr || answer->dimensions[0] + 1 != qoff->dimensions[0])) ||
        (!flag_h.is_none() && (flag == nullptr || flat == nullptr || flag->dimensions[0] + 1 != qoff->dimensions[0])))
        throw nb::type_error("many_field: bufs float64, buff and qoff int64 of B + 1, answer int64 of B or None, "
                             "flag uint8 of B and flat float64, or None");
    Py_ssize_t B = qoff->dimensions[0] - 1;
    const auto* qo = reinterpret_cast<const std::int64_t*>(qoff->data);
    const auto* bo = reinterpret_cast<const std::int64_t*>(buff->data);
    const auto* src = reinterpret_cast<const double*>(bufs->data);
    const auto* ans = answer == nullptr ? nullptr : reinterpret_cast<const std::int64_t*>(answer->data);
    const auto* fl = flag == nullptr ? nullptr : reinterpret_cast<const std::uint8_t*>(flag->data);
    Py_ssize_t len = bufs->dimensions[0];
    // Each span [bo[b] + a n + c_b, + n) inside [bo[b], bo[b + 1]) inside bufs (or, flag 0,
    // [qo[b], qo[b + 1]) inside flat); every bound checked before the next is computed from
    // it, so that no sum or product overflows (an empty span reads nothing: its answer[b] is
    // not read).
    for (Py_ssize_t b = 0; b < B; ++b) {
        if (a < 0 || c < 0 || qo[b] < 0 || qo[b + 1] < qo[b] || bo[b] < 0 || bo[b + 1] < bo[b] ||
            bo[b + 1] > len)
            throw nb::value_error("many_field: the offsets do not fit the buffers");
        std::int64_t n = qo[b + 1] - qo[b], room = bo[b + 1] - bo[b];
        if (fl != nullptr && fl[b] == 0) {
            if (qo[b + 1] > flat->dimensions[0])
                throw nb::value_error("many_field: the offsets do not fit the buffers");
            continue;
        }
        if (n > room || c > room - n || (ans != nullptr && n > 0 && (ans[b] < 0 || ans[b] > room - n - c)))
            throw nb::value_error("many_field: the offsets do not fit the buffers");
        std::int64_t cb = c + (ans == nullptr || n == 0 ? 0 : ans[b]);  // (<= room - n)
        if (n > 0 && a > (room - n - cb) / n)
            throw nb::value_error("many_field: the offsets do not fit the buffers");
    }
    nb::object out = new_array(qo[B] - qo[0]);
    double* dst = data_of<double>(out);
    const double* other = flat == nullptr ? nullptr : reinterpret_cast<const double*>(flat->data);
    for (Py_ssize_t b = 0; b < B; ++b) {
        std::int64_t n = qo[b + 1] - qo[b];
        if (n == 0) continue;
        const double* from = fl != nullptr && fl[b] == 0
                                 ? other + qo[b]
                                 : src + bo[b] + a * n + c + (ans == nullptr ? 0 : ans[b]);
        std::memcpy(dst + (qo[b] - qo[0]), from, static_cast<std::size_t>(n) * sizeof(double));
    }
    return out;
}

// Every problem's final basic z's end to end (basics from qoff[b], k = out_i[b, 2] of them),
// their offsets (int64 B + 1) and the problems' sizes (int64 B, qoff's differences):
// LCPManyResult.warm_start's arrays.
nb::object many_bases(nb::handle basics_h, nb::handle qoff_h, nb::handle out_i_h) {
    const ArrayFields* basics = plain_i64(basics_h.ptr(), front.ndarray, front.int64_num);
    const ArrayFields* qoff = plain_i64(qoff_h.ptr(), front.ndarray, front.int64_num);
    auto* oi = reinterpret_cast<const ArrayFields*>(out_i_h.ptr());
    if (!front.on) return nb::none();
    if (basics == nullptr || qoff == nullptr || !native_rows(out_i_h.ptr(), 5, front.int64_num) ||
        oi->dimensions[0] + 1 != qoff->dimensions[0])
        throw nb::type_error("many_bases: basics, qoff (B + 1) and out_i (B, 5) int64");
    Py_ssize_t B = oi->dimensions[0];
    const auto* qo = reinterpret_cast<const std::int64_t*>(qoff->data);
    const auto* code = reinterpret_cast<const std::int64_t*>(oi->data);
    const auto* src = reinterpret_cast<const std::int64_t*>(basics->data);
    nb::object off = new_array(B + 1, true), sizes = new_array(B, true);
    auto* o = data_of<std::int64_t>(off);
    auto* n_b = data_of<std::int64_t>(sizes);
    o[0] = 0;
    for (Py_ssize_t b = 0; b < B; ++b) {
        std::int64_t k = code[5 * b + 2];
        // (qo[b] >= 0 and qo[b + 1] >= qo[b] first: the difference cannot overflow)
        if (k < 0 || qo[b] < 0 || qo[b + 1] < qo[b] || k > qo[b + 1] - qo[b] ||
            qo[b + 1] > basics->dimensions[0])
            throw nb::value_error("many_bases: the offsets do not fit the arrays");
        o[b + 1] = o[b] + k;
        n_b[b] = qo[b + 1] - qo[b];
    }
    nb::object out = new_array(o[B], true);
    auto* dst = data_of<std::int64_t>(out);
    for (Py_ssize_t b = 0; b < B; ++b)
        if (o[b + 1] > o[b])
            std::memcpy(dst + o[b], src + qo[b], static_cast<std::size_t>(o[b + 1] - o[b]) * sizeof(std::int64_t));
    return nb::make_tuple(out, off, sizes);
}

}  // namespace

NumpyLayout numpy_layout() {
    return {front.on, front.ndarray, front.int64_num, front.empty};
}

nb::object new_array(Py_ssize_t len, bool ints) {
    PyObject* a;
    if (front.new_from_descr != nullptr) {
        a = new_from_descr(len, ints ? front.i64 : front.f64);
    } else {
        nb::object size = nb::steal(PyLong_FromSsize_t(len));
        if (!size.is_valid()) throw nb::python_error();
        PyObject* args[] = {size.ptr(), front.i64};
        a = PyObject_Vectorcall(front.empty, args, ints ? 2 : 1, nullptr);
    }
    if (a == nullptr) throw nb::python_error();
    return nb::steal(a);
}

nb::object new_view(nb::handle base, Py_ssize_t offset, Py_ssize_t len) {
    if (!front.views) return nb::object();
    PyObject* a = view_of(base.ptr(), offset, len);
    if (a == nullptr) throw nb::python_error();
    return nb::steal(a);
}

void bind_front(nb::module_& m) {
    m.def("lcp_front_init", &init, "ndarray"_a, "result_cls"_a, "solved"_a, "ray"_a, "empty"_a,
          "pivot_tol"_a, "tie_tol"_a, "tol"_a, "probe2"_a, "address"_a, "probe_ro"_a,
          "probe_int"_a, "probe_swapped"_a, "api"_a.none());
    m.def("lcp_front", &lcp_front, "M"_a, "q"_a, "ws"_a.none(), "beta"_a.none(),
          "method"_a = static_cast<int>(lemke::TABLEAU));
    m.def("lcp_front_on", [] { return front.on; });
    m.def("lcp_pack", &lcp_pack, "M"_a, "q"_a);
    m.def("blcp_pack", &blcp_pack, "M"_a, "q"_a, "lo"_a.none(), "hi"_a.none(), "findex"_a.none());
    m.def("many_setup", &many_setup, "sizes"_a, "M"_a, "q"_a, "max_pivots"_a);
    m.def("many_unsettled", &many_unsettled, "out_i"_a, "out_f"_a);
    m.def("many_field", &many_field, "bufs"_a, "buff"_a, "qoff"_a, "a"_a, "c"_a,
          "answer"_a.none() = nb::none(), "flag"_a.none() = nb::none(), "flat"_a.none() = nb::none());
    m.def("many_bases", &many_bases, "basics"_a, "qoff"_a, "out_i"_a);
    // made_f64 for the Python fronts' conversion (_validate.plain): the float64 C array it
    // makes of x, or None (x is plain already, or of another kind)
    m.def("as_f64", [](nb::handle x, int nd) -> nb::object {
        if (!front.on || (nd != 1 && nd != 2)) return nb::none();
        nb::object a = made_f64(x.ptr(), nd);
        return a.is_valid() && a.ptr() != x.ptr() ? a : nb::none();
    }, "x"_a, "nd"_a);
    // _validate.plain_all's common case in one call: args (a tuple; None for an argument
    // not given) with every one made_f64 makes made a float64 C array (its rank in ranks)
    // and every other given one a plain float64 array kept; False when every given one is
    // a plain array already (nothing to convert), None when any is of another kind
    // (plain_all's Python steps then)
    m.def("all_f64", [](nb::tuple args, nb::tuple ranks) -> nb::object {
        Py_ssize_t k = args.size();
        if (!front.on || static_cast<Py_ssize_t>(ranks.size()) != k) return nb::none();
        nb::list out;
        bool some = false;
        for (Py_ssize_t i = 0; i < k; ++i) {
            PyObject* x = PyTuple_GET_ITEM(args.ptr(), i);
            int nd = nb::cast<int>(ranks[i]);
            nb::object a = x == Py_None ? nb::none() : made_f64(x, nd);
            if (!a.is_valid() || (a.ptr() == x && x != Py_None && plain(x, nd) == nullptr))
                return nb::none();  // (an ndarray or a list made_f64 declines)
            some = some || a.ptr() != x;
            out.append(a);
        }
        return some ? nb::object(out) : nb::bool_(false);
    }, "args"_a, "ranks"_a);
    m.def("lcp_entry", &lcp_entry, "py"_a, "after"_a, "globals"_a, "front"_a, "ws_cls"_a);
    m.def("games_entry", &games_entry, "py"_a, "after"_a, "globals"_a, "front"_a);
    m.def("blcp_entry", &blcp_entry, "py"_a, "after"_a, "globals"_a, "front"_a);
    m.def("lcp_many_entry", &lcp_many_entry, "py"_a, "globals"_a, "front"_a, "ws_cls"_a,
          "many_globals"_a, "many_cls"_a);
}
