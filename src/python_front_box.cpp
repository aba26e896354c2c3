// lemke._core.blcp_front: solve_blcp's commonest calls whole in one native call, as
// _core.lcp_front does solve_lcp's (src/python_front.cpp): plain float64 M (n x n), q, lo,
// hi (numpy_layout()'s plain_f64: C-contiguous, aligned, the machine's byte order,
// writable or not), method "bounded", default options; then
//  (a) no friction index and no warm start, 0 < n < 257: _blcp's cold fast path, one
//      boxed::solve (GIL released); solved and checked gives the BLCPResult built as that
//      path builds it (lazily: `_src`, read by _blcp._BoxField); any other code >= 0 the
//      tuple (code, pivots, z0, ok, residual, k, m, buf, final) for the Python front's
//      _finish; a code < 0 (data the kernel refuses) None;
//  (b) a friction index (an int64 ndarray, plain, of length n) and/or a BoxWarmStart (its
//      row states, the size and friction rows of the problem): _blcp._one_call's kernel
//      calls, made by lemke::boxed::batch for one island (the same calls in the same order:
//      src/lemke/boxed_batch.hpp); its stage 0 or 1 gives the lazily built BLCPResult as
//      _blcp._lazy builds it, stage -1 (a checked ray, a failed ladder or friction check)
//      False, for the Python front's general path, which _one_call would have reached;
//      stage -2 (refused data) None.
// None: the Python front does everything itself (the same results: every call here is one
// it would make, in the same order, on the same arrays).
#include <nanobind/nanobind.h>

#include <cstdint>
#include <cstring>
#include <unordered_map>
#include <vector>

#include "lemke/boxed.hpp"
#include "lemke/boxed_batch.hpp"
#include "python_arrays.hpp"

namespace nb = nanobind;
using namespace nb::literals;

namespace {

using lemke::idx;

constexpr idx COLD_MAX = 257;  // _blcp._NO's length: the cold fast path's sizes
constexpr int NPY_BYTE = 1;    // int8

struct BoxFront {
    bool on = false;
    PyObject* result_cls = nullptr;  // BLCPResult
    PyObject* ws_cls = nullptr;      // BoxWarmStart
    PyObject* solved = nullptr;      // Status.SOLVED
    PyObject* spans = nullptr;       // _blcp._spans
    PyObject* zero = nullptr;        // 0.0
    PyObject *k_status, *k_pivots, *k_residual, *k_ray, *k_z0, *k_lo, *k_hi, *k_recoveries,
        *k_warm_start, *k_src, *k_n, *k_friction, *k_row_states, *k_codes;
    double pivot_tol = 0, tie_tol = 0, tol = 0;
    // _spans(n, N, friction) by (n, N, friction), kept for good (as _blcp._SPANS keeps them)
    std::unordered_map<std::uint64_t, PyObject*> spans_cache;
    // The result's __dict__ of each kind (friction | recoveries << 1 | warm start << 2): its
    // keys in lazy's order, the constant values set; lazy copies one (no dict growth).
    PyObject* templates[8] = {};
} bf;

void init(nb::handle result_cls, nb::handle ws_cls, nb::handle solved, nb::handle spans,
          double pivot_tol, double tie_tol, double tol) {
    bf.on = false;
    for (nb::handle h : {result_cls, ws_cls, solved, spans}) h.inc_ref();  // kept for good
    bf.result_cls = result_cls.ptr();
    bf.ws_cls = ws_cls.ptr();
    bf.solved = solved.ptr();
    bf.spans = spans.ptr();
    bf.zero = PyFloat_FromDouble(0.0);
    PyObject** keys[] = {&bf.k_status, &bf.k_pivots, &bf.k_residual, &bf.k_ray, &bf.k_z0,
                         &bf.k_lo, &bf.k_hi, &bf.k_recoveries, &bf.k_warm_start, &bf.k_src,
                         &bf.k_n, &bf.k_friction, &bf.k_row_states, &bf.k_codes};
    const char* names[] = {"status", "pivots", "residual", "ray", "z0", "lo", "hi",
                           "recoveries", "warm_start", "_src", "n", "friction", "row_states",
                           "_codes"};
    bool ok = bf.zero != nullptr;
    for (std::size_t i = 0; i < sizeof(keys) / sizeof(keys[0]); ++i) {
        *keys[i] = PyUnicode_InternFromString(names[i]);
        ok = ok && *keys[i] != nullptr;
    }
    if (!ok) throw nb::python_error();
    PyObject* pivots0 = PyLong_FromSsize_t(0);  // (the cached 0: lazy writes no 0 pivots)
    if (pivots0 == nullptr) throw nb::python_error();
    for (int v = 0; v < 8; ++v) {
        PyObject* t = PyDict_New();
        bf.templates[v] = t;
        ok = t != nullptr && PyDict_SetItem(t, bf.k_status, bf.solved) == 0 &&
             PyDict_SetItem(t, bf.k_pivots, pivots0) == 0 &&
             PyDict_SetItem(t, bf.k_residual, Py_None) == 0 &&
             PyDict_SetItem(t, bf.k_ray, Py_None) == 0 &&
             PyDict_SetItem(t, bf.k_z0, bf.zero) == 0 &&
             ((v & 1) || (PyDict_SetItem(t, bf.k_lo, Py_None) == 0 &&
                          PyDict_SetItem(t, bf.k_hi, Py_None) == 0)) &&
             (!(v & 2) || PyDict_SetItem(t, bf.k_recoveries, Py_None) == 0) &&
             (!(v & 4) || PyDict_SetItem(t, bf.k_warm_start, Py_None) == 0) &&
             PyDict_SetItem(t, bf.k_src, Py_None) == 0;
        if (!ok) throw nb::python_error();
    }
    bf.pivot_tol = pivot_tol;
    bf.tie_tol = tie_tol;
    bf.tol = tol;
    bf.on = numpy_layout().ok;
}

template <class T>
T* data_of(const nb::object& a) {
    return reinterpret_cast<T*>(reinterpret_cast<const ArrayFields*>(a.ptr())->data);
}

// _blcp._spans(n, N, friction), kept per (n, N, friction) (sizes below 2^31).
nb::object spans_of(idx n, idx N, bool friction) {
    bool cache = n < (idx(1) << 31) && N < (idx(1) << 31);
    std::uint64_t key = (std::uint64_t(n) << 32 | std::uint64_t(N)) << 1 | std::uint64_t(friction);
    if (cache) {
        auto it = bf.spans_cache.find(key);
        if (it != bf.spans_cache.end()) return nb::borrow(it->second);
    }
    nb::object s = nb::handle(bf.spans)(n, N, friction);
    if (cache) bf.spans_cache.emplace(key, s.inc_ref().ptr());
    return s;
}

// The BLCPResult of a solved and checked answer, as _blcp._lazy builds it (`ints` None: the
// warm start's own point, whose final basis is the warm start the result keeps, never read).
nb::object lazy(const nb::object& buf, const nb::object& ints, idx N, idx k, idx m, idx n,
                nb::handle lo, nb::handle hi, bool friction, idx pivots, double residual,
                idx rec, nb::handle ws) {
    auto* cls = reinterpret_cast<PyTypeObject*>(bf.result_cls);
    nb::object res = nb::steal(cls->tp_alloc(cls, 0));
    if (!res.is_valid()) throw nb::python_error();
    int kind = int(friction) | int(rec != 0) << 1 | int(!ws.is_none()) << 2;
    nb::object dict = nb::steal(PyDict_Copy(bf.templates[kind]));
    if (!dict.is_valid()) throw nb::python_error();
    PyObject* d = dict.ptr();
    nb::object spans = spans_of(n, N, friction);
    bool ok = (pivots == 0 || put(d, bf.k_pivots, PyLong_FromSsize_t(pivots))) &&
              put(d, bf.k_residual, PyFloat_FromDouble(residual)) &&
              (friction || (PyDict_SetItem(d, bf.k_lo, lo.ptr()) == 0 &&
                            PyDict_SetItem(d, bf.k_hi, hi.ptr()) == 0)) &&
              (rec == 0 || put(d, bf.k_recoveries, PyLong_FromSsize_t(rec))) &&
              (ws.is_none() || PyDict_SetItem(d, bf.k_warm_start, ws.ptr()) == 0);
    if (ok) {
        nb::object src = nb::make_tuple(buf, ints, N, k, m, spans);
        ok = PyDict_SetItem(d, bf.k_src, src.ptr()) == 0 &&
             PyObject_GenericSetDict(res.ptr(), d, nullptr) == 0;
    }
    if (!ok) throw nb::python_error();
    return res;
}

// (a) the cold fast path.
nb::object cold(const ArrayFields* M, const ArrayFields* q, const ArrayFields* lo,
                const ArrayFields* hi, nb::handle lo_h, nb::handle hi_h, idx n) {
    nb::object buf = new_array(lemke::boxed::BoxLayout{n}.length(), false);
    nb::object final = new_array(n, true);
    static const std::uint8_t no[2 * COLD_MAX] = {};  // _blcp._NO[n]: no warm start
    const double *Md = reinterpret_cast<const double*>(M->data),
                 *qd = reinterpret_cast<const double*>(q->data),
                 *ld = reinterpret_cast<const double*>(lo->data),
                 *hd = reinterpret_cast<const double*>(hi->data);
    double* out = data_of<double>(buf);
    idx* fin = data_of<idx>(final);
    lemke::boxed::SolveResult r;
    {
        nb::gil_scoped_release release;
        r = lemke::boxed::solve(lemke::Mat<const double>(Md, n, n), qd, ld, hd, no, 0,
                                100 * (n + 1), bf.pivot_tol, bf.tie_tol, bf.tol, out, fin);
    }
    if (r.code == 0 && r.ok)
        return lazy(buf, final, n, r.k, r.m, n, lo_h, hi_h, false, r.pivots, r.residual, 0,
                    nb::none());
    if (r.code < 0) return nb::none();
    return nb::make_tuple(r.code, r.pivots, r.z0, r.ok, r.residual, r.k, r.m, buf, final);
}

// (b) a friction index and/or a warm start: _one_call by boxed::batch for one island.
nb::object one_call(const ArrayFields* M, const ArrayFields* q, const ArrayFields* lo,
                    const ArrayFields* hi, nb::handle lo_h, nb::handle hi_h,
                    nb::handle findex_h, nb::handle ws, idx n) {
    const NumpyLayout L = numpy_layout();
    const idx* fi = nullptr;
    if (!findex_h.is_none()) {
        auto* f = plain_i64(findex_h.ptr(), L.ndarray, L.int64_num, CARRAY);
        if (f == nullptr || f->dimensions[0] != n) return nb::none();
        fi = reinterpret_cast<const idx*>(f->data);
    }
    bool friction = fi != nullptr;
    idx nf = 0;
    if (friction)
        for (idx i = 0; i < n; ++i) nf += fi[i] >= 0;
    idx N = n + 2 * nf;
    // The warm start: of this size and these friction rows (else the Python front, which
    // says what is wrong or goes its general way), its row states.
    nb::object states;
    const std::int8_t* st = nullptr;
    if (!ws.is_none()) {
        if (Py_TYPE(ws.ptr()) != reinterpret_cast<PyTypeObject*>(bf.ws_cls)) return nb::none();
        nb::object d = nb::steal(PyObject_GenericGetDict(ws.ptr(), nullptr));
        if (!d.is_valid()) throw nb::python_error();
        PyObject* wn = PyDict_GetItemWithError(d.ptr(), bf.k_n);
        PyObject* wf = PyDict_GetItemWithError(d.ptr(), bf.k_friction);
        if (wn == nullptr || wf == nullptr || !PyLong_CheckExact(wn) || !PyTuple_CheckExact(wf)) {
            if (PyErr_Occurred()) throw nb::python_error();
            return nb::none();
        }
        idx wsn = PyLong_AsSsize_t(wn);
        if (wsn == -1 && PyErr_Occurred()) PyErr_Clear();
        if (wsn != N || PyTuple_GET_SIZE(wf) != nf) return nb::none();
        // its friction rows (sorted) must be the rows with findex >= 0, in order
        idx r = 0;
        for (idx i = 0; i < n && r < nf; ++i) {
            if (fi[i] < 0) continue;
            PyObject* e = PyTuple_GET_ITEM(wf, r);
            if (!PyLong_CheckExact(e)) return nb::none();
            idx v = PyLong_AsSsize_t(e);
            if (v == -1 && PyErr_Occurred()) PyErr_Clear();
            if (v != i) return nb::none();
            ++r;
        }
        // row_states(): the codes it keeps in its __dict__, else the method (which makes them)
        PyObject* kept = PyDict_GetItemWithError(d.ptr(), bf.k_codes);
        if (kept != nullptr && kept != Py_None) {
            states = nb::borrow(kept);
        } else {
            if (PyErr_Occurred()) throw nb::python_error();
            states = nb::steal(PyObject_CallMethodNoArgs(ws.ptr(), bf.k_row_states));
            if (!states.is_valid()) throw nb::python_error();
        }
        if (Py_TYPE(states.ptr()) != L.ndarray) return nb::none();
        auto* s = reinterpret_cast<const ArrayFields*>(states.ptr());
        if (s->nd != 1 || s->dimensions[0] != n ||
            (s->flags & (C_CONTIGUOUS | ALIGNED)) != (C_CONTIGUOUS | ALIGNED) ||
            reinterpret_cast<const DescrFields*>(s->descr)->type_num != NPY_BYTE)
            return nb::none();
        st = reinterpret_cast<const std::int8_t*>(s->data);
        for (idx i = 0; i < n; ++i) {  // (as the batch binding checks them)
            int c = st[i];
            if (c < 0 || c > 29 || (c >= lemke::boxed::FRICTION_STATE) != (friction && fi[i] >= 0))
                return nb::none();
        }
    }
    lemke::boxed::FrontLayout FL{n, nf, friction};
    idx buf_len = FL.length(), ints_len = FL.ints_length();
    // The final basis goes to a scratch of this thread, copied into an array only when the
    // result reads it (stage 1): the warm start's own point (stage 0) keeps the warm start.
    nb::object buf = new_array(buf_len, false);
    thread_local std::vector<idx> ints_scratch;
    if (ints_scratch.size() < static_cast<std::size_t>(ints_len))
        ints_scratch.resize(static_cast<std::size_t>(ints_len));
    const double *Md = reinterpret_cast<const double*>(M->data),
                 *qd = reinterpret_cast<const double*>(q->data),
                 *ld = reinterpret_cast<const double*>(lo->data),
                 *hd = reinterpret_cast<const double*>(hi->data);
    double* out = data_of<double>(buf);
    idx* in = ints_scratch.data();
    const idx mstart[1] = {0}, qoff[2] = {0, n}, buff[2] = {0, buf_len}, ioff[2] = {0, ints_len};
    const idx max_pivots[1] = {100 * (N + 1)};  // Options.pivot_limit(N), the default
    const std::uint8_t fflag[1] = {std::uint8_t(friction)}, wflag[1] = {std::uint8_t(st != nullptr)};
    thread_local std::vector<std::int8_t> state_out;  // (not read here: batch's output)
    if (state_out.size() < static_cast<std::size_t>(n) + 1) state_out.resize(n + 1);
    idx out_i[7] = {0, 0, 0, 0, 0, 0, 0};
    double out_f[1] = {0.0};
    {
        nb::gil_scoped_release release;
        lemke::boxed::batch(Md, mstart, qd, ld, hd, qoff, fi, fflag, st, wflag, 0, 1, max_pivots,
                            bf.pivot_tol, bf.tie_tol, bf.tol, out, buff, in, ioff,
                            state_out.data(), out_i, out_f);
    }
    idx stage = out_i[5];
    if (stage == 0)  // the warm start's own point: 0 pivots, the result keeps it
        return lazy(buf, nb::none(), N, 0, 0, n, lo_h, hi_h, friction, 0, out_f[0], 0, ws);
    if (stage == 1) {
        nb::object ints = new_array(ints_len, true);
        std::memcpy(data_of<idx>(ints), in, static_cast<std::size_t>(ints_len) * sizeof(idx));
        return lazy(buf, ints, N, out_i[2], out_i[3], n, lo_h, hi_h, friction, out_i[1],
                    out_f[0], out_i[4], nb::none());
    }
    if (stage == -1) return nb::bool_(false);
    return nb::none();
}

}  // namespace

nb::object blcp_front(nb::handle M_h, nb::handle q_h, nb::handle lo_h, nb::handle hi_h,
                      nb::handle findex, nb::handle ws) {
    if (!bf.on) return nb::none();
    const NumpyLayout L = numpy_layout();
    const ArrayFields* M = plain_f64(M_h.ptr(), 2, L.ndarray);
    const ArrayFields* q = plain_f64(q_h.ptr(), 1, L.ndarray);
    const ArrayFields* lo = plain_f64(lo_h.ptr(), 1, L.ndarray);
    const ArrayFields* hi = plain_f64(hi_h.ptr(), 1, L.ndarray);
    if (M == nullptr || q == nullptr || lo == nullptr || hi == nullptr) return nb::none();
    idx n = q->dimensions[0];
    if (n <= 0 || M->dimensions[0] != n || M->dimensions[1] != n || lo->dimensions[0] != n ||
        hi->dimensions[0] != n)
        return nb::none();
    if (findex.is_none() && ws.is_none())
        return n < COLD_MAX ? cold(M, q, lo, hi, lo_h, hi_h, n) : nb::none();
    return one_call(M, q, lo, hi, lo_h, hi_h, findex, ws, n);
}

namespace {

// solve_blcp_many's few path (_blcp_many._few): blcp_front of each island of M, q, lo, hi
// (lists or tuples of B islands), findex and ws (None, or such sequences of B: an island's
// friction index or None, its BoxWarmStart or None), in order; the list of the B results
// when each call gives one, else None (the Python front then does it all as before, each
// island's first call the same call).
nb::object blcp_front_many(nb::handle M, nb::handle q, nb::handle lo, nb::handle hi,
                           nb::handle findex, nb::handle ws) {
    auto seq = [](nb::handle o) { return PyList_CheckExact(o.ptr()) || PyTuple_CheckExact(o.ptr()); };
    if (!bf.on || !seq(M) || !seq(q) || !seq(lo) || !seq(hi)) return nb::none();
    Py_ssize_t B = PySequence_Fast_GET_SIZE(M.ptr());
    auto sized = [&](nb::handle o) { return PySequence_Fast_GET_SIZE(o.ptr()) == B; };
    if (B < 1 || !sized(q) || !sized(lo) || !sized(hi) ||
        (!findex.is_none() && (!seq(findex) || !sized(findex))) ||
        (!ws.is_none() && (!seq(ws) || !sized(ws))))
        return nb::none();
    PyObject** Ms = PySequence_Fast_ITEMS(M.ptr());
    PyObject** qs = PySequence_Fast_ITEMS(q.ptr());
    PyObject** los = PySequence_Fast_ITEMS(lo.ptr());
    PyObject** his = PySequence_Fast_ITEMS(hi.ptr());
    PyObject** fis = findex.is_none() ? nullptr : PySequence_Fast_ITEMS(findex.ptr());
    PyObject** wss = ws.is_none() ? nullptr : PySequence_Fast_ITEMS(ws.ptr());
    nb::object items = nb::steal(PyList_New(B));
    if (!items.is_valid()) throw nb::python_error();
    for (Py_ssize_t b = 0; b < B; ++b) {
        nb::object r = blcp_front(Ms[b], qs[b], los[b], his[b], fis ? fis[b] : Py_None,
                                  wss ? wss[b] : Py_None);
        if (r.is_none() || r.ptr() == Py_False || PyTuple_CheckExact(r.ptr())) return nb::none();
        PyList_SET_ITEM(items.ptr(), b, r.release().ptr());
    }
    return items;
}

}  // namespace

void bind_front_box(nb::module_& m) {
    m.def("blcp_front_init", &init, "result_cls"_a, "ws_cls"_a, "solved"_a, "spans"_a,
          "pivot_tol"_a, "tie_tol"_a, "tol"_a);
    m.def("blcp_front", &blcp_front, "M"_a, "q"_a, "lo"_a, "hi"_a, "findex"_a.none(),
          "ws"_a.none());
    m.def("blcp_front_many", &blcp_front_many, "M"_a, "q"_a, "lo"_a, "hi"_a, "findex"_a.none(),
          "ws"_a.none());
    m.def("blcp_front_on", [] { return bf.on; });
}
