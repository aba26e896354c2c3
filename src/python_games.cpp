// lemke._core's games functions: the bimatrix games engine (src/lemke/games.*) with the
// arguments and return values lemke/_games.py expects (lemke_howson, games_trace,
// games_check). Every
// size and label is checked before the GIL is released (ValueError otherwise), so bad input
// never reaches the engine.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/tuple.h>

#include <cstdint>
#include <string>
#include <vector>

#include "lemke/games.hpp"

namespace nb = nanobind;
using namespace nb::literals;

namespace {

using lemke::idx;
using Payoffs = nb::ndarray<const double, nb::ndim<2>, nb::c_contig, nb::device::cpu>;
using VecIn = nb::ndarray<const double, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using VecOut = nb::ndarray<double, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using LabelsIn = nb::ndarray<const std::int64_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using LabelsOut = nb::ndarray<std::int64_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>;

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
        throw nb::value_error("lemke_howson: buf must hold 2 (m + n) + 3 + STATE floats");
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
        len(y.shape(0)) != n || len(basis_out.shape(0)) < m + n + 2 || len(out.shape(0)) < 3)
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

}  // namespace

void bind_games(nb::module_& m) {
    m.def("lemke_howson", &lemke_howson, "A"_a, "B"_a, "k"_a, "start"_a, "params"_a, "buf"_a);
    m.def("games_trace", &trace, "A"_a, "B"_a, "p"_a, "q"_a, "max_pivots"_a, "pivot_tol"_a,
          "tie_tol"_a, "tol"_a, "x"_a, "y"_a, "basis_out"_a, "out"_a);
    m.def("games_check", &check, "A"_a, "B"_a, "x"_a, "y"_a, "tol"_a, "out"_a);
    m.attr("GAMES_STATE") = lemke::games::STATE;
    m.attr("GAMES_HISTORY") = lemke::games::HISTORY;
    m.attr("GAMES_NOT_FINITE") = lemke::games::NOT_FINITE;
    m.attr("GAMES_UNCHECKED") = lemke::games::UNCHECKED;
}
