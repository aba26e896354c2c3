// NumPy arrays read directly (no DLPack capsule, no buffer view: those cost more than a
// small solve), for the native fronts (src/python_front.cpp). The fields are those of
// NumPy's PyArrayObject (data, nd, dimensions, strides, base, descr, flags; the same in
// NumPy 1.x and 2.x) and of its descr up to type_num; lcp_front_init checks them on probe
// arrays against what Python reports, and a front that finds them different stays off.
#pragma once
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <cstdint>
#include <type_traits>
#include <utility>

// Aligned<A>: an nb::ndarray argument A that an entry reads through typed pointers (double,
// int64), taken only when its data is aligned for its scalar (or it holds no entry).
// nanobind passes a C-contiguous array through whatever its address (e.g.
// np.frombuffer(bytearray(8 * n + 1), offset=1)), and reading that as doubles is undefined
// behaviour (UBSan's alignment check); Aligned declines it, and the call raises TypeError
// (incompatible function arguments), as for an argument of another dtype. The one check of
// alignment for every _core entry that takes typed arrays (src/python*.cpp's aliases); the
// Python callers hand them aligned arrays (_validate's conversions copy unaligned ones).
template <class A>
struct Aligned : A {
    Aligned() = default;
    explicit Aligned(A&& a) : A(std::move(a)) {}
};

// The typed array arguments and results the _core entries share (python_qp.cpp,
// python_support.cpp): C-contiguous CPU arrays, aligned for their scalar.
template <class T, int D>
using CArray = Aligned<nanobind::ndarray<T, nanobind::ndim<D>, nanobind::c_contig,
                                         nanobind::device::cpu>>;
using In1 = CArray<const double, 1>;
using In2 = CArray<const double, 2>;
using Out1 = CArray<double, 1>;
using Out2 = CArray<double, 2>;
using IdxIn = CArray<const std::int64_t, 1>;
using IdxOut = CArray<std::int64_t, 1>;
using NewVector = nanobind::ndarray<nanobind::numpy, double, nanobind::ndim<1>>;

// Whether the array a's data may be read as its scalar type.
template <class A>
bool data_aligned(const A& a) {
    using T = std::remove_pointer_t<decltype(a.data())>;
    return a.size() == 0 || reinterpret_cast<std::uintptr_t>(a.data()) % alignof(T) == 0;
}

namespace nanobind::detail {
template <class A>
struct type_caster<Aligned<A>> {
    using Inner = make_caster<A>;
    NB_TYPE_CASTER(Aligned<A>, Inner::Name)
    bool from_python(handle src, uint8_t flags, cleanup_list* cleanup) noexcept {
        Inner inner;
        if (!inner.from_python(src, flags, cleanup)) return false;
        if (!data_aligned(inner.value)) return false;
        value = Aligned<A>(std::move(inner.value));
        return true;
    }
    static handle from_cpp(const Aligned<A>& a, rv_policy policy, cleanup_list* cleanup) noexcept {
        return Inner::from_cpp(static_cast<const A&>(a), policy, cleanup);
    }
};
}  // namespace nanobind::detail

// NumPy's array object, as far as read here.
struct ArrayFields {
    PyObject_HEAD
    char* data;
    int nd;
    Py_ssize_t* dimensions;
    Py_ssize_t* strides;
    PyObject* base;
    PyObject* descr;
    int flags;
};

// NumPy's dtype object up to type_num.
struct DescrFields {
    PyObject_HEAD
    PyTypeObject* typeobj;
    char kind, type, byteorder, former_flags;
    int type_num;
};

constexpr int NPY_DOUBLE = 12;
constexpr int C_CONTIGUOUS = 0x0001;
constexpr int ALIGNED = 0x0100;
constexpr int WRITEABLE = 0x0400;
constexpr int CARRAY = C_CONTIGUOUS | ALIGNED | WRITEABLE;  // ndarray.flags.carray

// o when it is an ndarray (exactly) of nd dimensions, float64 in the machine's byte order
// ('=': NumPy writes '<' or '>' only for the other), C-contiguous and aligned, writable or
// not (the fronts only read their inputs: a read-only array, e.g. pandas' copy-on-write
// to_numpy() or lemke.problems' arrays, is taken as it is); else nullptr.
inline const ArrayFields* plain_f64(PyObject* o, int nd, PyTypeObject* ndarray) {
    constexpr int need = C_CONTIGUOUS | ALIGNED;
    if (Py_TYPE(o) != ndarray) return nullptr;
    auto* a = reinterpret_cast<const ArrayFields*>(o);
    if (a->nd != nd || (a->flags & need) != need) return nullptr;
    auto* t = reinterpret_cast<const DescrFields*>(a->descr);
    if (t->type_num != NPY_DOUBLE || t->byteorder != '=') return nullptr;
    return a;
}

// A 1-D int64 ndarray in the machine's byte order with the flags `need` (C-contiguous and
// aligned; CARRAY: writable too), else nullptr. int64_num: NumPy's type number of int64
// here (NumpyLayout).
inline const ArrayFields* plain_i64(PyObject* o, PyTypeObject* ndarray, int int64_num,
                                    int need = C_CONTIGUOUS | ALIGNED) {
    if (Py_TYPE(o) != ndarray) return nullptr;
    auto* a = reinterpret_cast<const ArrayFields*>(o);
    if (a->nd != 1 || (a->flags & need) != need) return nullptr;
    auto* t = reinterpret_cast<const DescrFields*>(a->descr);
    if (t->type_num != int64_num || t->byteorder != '=') return nullptr;
    return a;
}

// d[key] = value, stealing value (the fronts build their results' __dict__ with it);
// false on an error (set).
inline bool put(PyObject* d, PyObject* key, PyObject* value) {
    if (value == nullptr) return false;
    int e = PyDict_SetItem(d, key, value);
    Py_DECREF(value);
    return e == 0;
}

// A new instance of a result class (its __init__ skipped, as object.__new__ does) and its
// __dict__, which the fronts fill as the classes' own lazy builders do.
struct NewResult {
    nanobind::object res, dict;
};
inline NewResult new_result(PyObject* result_cls) {
    auto* cls = reinterpret_cast<PyTypeObject*>(result_cls);
    nanobind::object res = nanobind::steal(cls->tp_alloc(cls, 0));
    if (!res.is_valid()) throw nanobind::python_error();
    nanobind::object dict = nanobind::steal(PyObject_GenericGetDict(res.ptr(), nullptr));
    if (!dict.is_valid()) throw nanobind::python_error();
    return {res, dict};
}

// What lcp_front_init found (src/python_front.cpp): whether the layout above holds (false
// until it has run: every native front then declines), numpy.ndarray, NumPy's type number
// of int64 here, numpy.empty.
struct NumpyLayout {
    bool ok;
    PyTypeObject* ndarray;
    int int64_num;
    PyObject* empty;
};
NumpyLayout numpy_layout();

// A new 1-D array of len float64 (int64 with ints), uninitialized, as numpy.empty(len) (or
// numpy.empty(len, int64)) makes it: through NumPy's C API (PyArray_NewFromDescr, read
// from its _ARRAY_API capsule: about half of numpy.empty's cost, which parses its
// arguments) when lcp_front_init found it makes such arrays, else numpy.empty itself.
// Raises (nb::python_error) when NumPy does.
nanobind::object new_array(Py_ssize_t len, bool ints = false);

// A read-only 1-D float64 view of the doubles [offset, offset + len) of the float64 array
// base, as base[offset:offset + len] of a read-only base makes it (base its base), through
// NumPy's C API; an invalid object (nothing made, no error) when lcp_front_init did not find
// that API making such views (the caller slices). Raises when NumPy does.
nanobind::object new_view(nanobind::handle base, Py_ssize_t offset, Py_ssize_t len);

// The native fronts' conversion of array-likes (src/python_front.cpp, branch arraylike), for
// src/python_front_qp.cpp (branch qpfront): the forms made_f64 converts (lists or tuples of
// Python floats, bools and int64-sized ints, rows of one length, no dimension 0; ndarrays of
// bool, int, uint up to 32 bits, float32 or float64 in the machine's byte order with other
// strides), the values np.asarray(x).astype(float64) holds.
// pack_form: how x (of nd dimensions, 1 or 2) is taken: 0 a plain float64 C array, 1 an
// array-like made_f64 converts, -1 anything else (declined); its rows and cols (1 for nd 1).
int pack_form(PyObject* x, int nd, Py_ssize_t& rows, Py_ssize_t& cols);
// pack_into: x (pack_form's 0 or 1) written to out, rows x cols in C order; false where a
// list entry is declined.
bool pack_into(PyObject* x, int nd, Py_ssize_t rows, Py_ssize_t cols, double* out);
// new_rows: a new float64 C array of rows x cols (1-D of rows when nd is 1), uninitialized.
nanobind::object new_rows(int nd, Py_ssize_t rows, Py_ssize_t cols);
// bound_value: a Python float or int64-sized int given for a bound lo (side -1) or hi (side
// 1) as its value v; false for anything else, NaN, or a value of the wrong side with
// -side v >= wrong (an infinity for solve_blcp, 1e20 for solve_qp, whose validation makes
// such a bound an infinity and refuses it).
bool bound_value(PyObject* x, int side, double wrong, double& v);

// _core.games_front (src/python_games.cpp): solve_bimatrix(A, B, init_label=k)'s common
// call, the BimatrixResult, the kernel's (code, pivots, restarts, buf) to go on from, or
// None (arguments of another kind).
nanobind::object games_front(nanobind::handle A, nanobind::handle B, nanobind::handle k);

// _core.blcp_front (src/python_front_box.cpp): solve_blcp(M, q, lo, hi, findex=, warm_start=)'s
// common calls, the BLCPResult, what is left to do (a tuple for _blcp._finish, False for
// _blcp._general), or None (arguments of another kind).
nanobind::object blcp_front(nanobind::handle M, nanobind::handle q, nanobind::handle lo,
                            nanobind::handle hi, nanobind::handle findex, nanobind::handle ws);
