// Views over caller-owned memory: a 1-D span and a row-major matrix view. Indexing is
// checked when LEMKE_CHECKED is defined (debug and sanitizer builds): an index out of range
// aborts with the file and line, so a bug never reads or writes past an array silently.
#pragma once
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <type_traits>

namespace lemke {

using idx = std::int64_t;

#ifdef LEMKE_CHECKED
[[noreturn]] inline void out_of_range(idx i, idx n, const char* what) {
    std::fprintf(stderr, "lemke: %s index %lld out of range [0, %lld)\n", what,
                 static_cast<long long>(i), static_cast<long long>(n));
    std::abort();
}
#define LEMKE_CHECK_INDEX(i, n, what) \
    do { if ((i) < 0 || (i) >= (n)) ::lemke::out_of_range((i), (n), (what)); } while (0)
#else
#define LEMKE_CHECK_INDEX(i, n, what) ((void)0)
#endif

template <class T>
struct Span {
    T* p = nullptr;
    idx n = 0;
    Span() = default;
    Span(T* data, idx size) : p(data), n(size) {}
    T& operator[](idx i) const { LEMKE_CHECK_INDEX(i, n, "span"); return p[i]; }
    idx size() const { return n; }
    T* data() const { return p; }
    Span sub(idx start, idx len) const {
        LEMKE_CHECK_INDEX(len == 0 ? 0 : start, len == 0 ? 1 : n, "sub-span start");
        LEMKE_CHECK_INDEX(start + len - 1, len == 0 ? start + len : n, "sub-span end");
        return Span(p + start, len);
    }
    void fill(T v) const { for (idx i = 0; i < n; ++i) p[i] = v; }
};

// A row-major matrix (rows x cols) with row stride ld.
template <class T>
struct Mat {
    T* p = nullptr;
    idx rows = 0, cols = 0, ld = 0;
    Mat() = default;
    Mat(T* data, idx r, idx c) : p(data), rows(r), cols(c), ld(c) {}
    Mat(T* data, idx r, idx c, idx stride) : p(data), rows(r), cols(c), ld(stride) {}
    // A read-only view of a writable matrix.
    template <class U, class = typename std::enable_if<std::is_same<const U, T>::value &&
                                                       !std::is_same<U, T>::value>::type>
    Mat(const Mat<U>& o) : p(o.p), rows(o.rows), cols(o.cols), ld(o.ld) {}
    T& operator()(idx i, idx j) const {
        LEMKE_CHECK_INDEX(i, rows, "matrix row");
        LEMKE_CHECK_INDEX(j, cols, "matrix column");
        return p[i * ld + j];
    }
    T* row(idx i) const { LEMKE_CHECK_INDEX(i, rows, "matrix row"); return p + i * ld; }
};

// A bump allocator over one caller-provided block of doubles: each engine's workspace is
// carved from it in one place (the engine's `layout`), so sizes and offsets derive from
// one statement.
struct Carver {
    double* base;
    idx used = 0;
    explicit Carver(double* b) : base(b) {}
    Span<double> take(idx len) { Span<double> s(base + used, len); used += len; return s; }
};

}  // namespace lemke
