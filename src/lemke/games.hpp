// Bimatrix games: Lemke-Howson on two condensed tableaux and the van den Elzen-Talman tracing procedure,
// both choosing rows by the shared rule of pivoting.hpp, each answer checked by the
// players' regrets on the caller's payoffs. Every sum in a fixed order, so the same bits on
// every instruction set.
//
// Convention: A and B (both m x n, row-major) are the payoffs of the row player and of the
// column player; labels 0..m-1 are the row player's actions, m..m+n-1 the column player's.
#pragma once
#include <cstdint>
#include <vector>

#include "certify.hpp"  // the check (games::check, ...), with every kind's
#include "pivoting.hpp"

namespace lemke {

namespace games {

// The engine's own codes, NOT_FINITE (a payoff is NaN or infinite: nothing done) and
// UNCHECKED (every label present, at a point that fails the check): status.hpp.
constexpr double PERTURBATION = 1e-7;
constexpr double ROUNDING_SLACK = 64.0;
constexpr idx HISTORY = 64;        // leaving labels kept of a path's last pivots (power of 2)
constexpr idx STATE = 3 + HISTORY; // the path state after the labels in the int64 part

// The layout of lemke_howson's output buffer for an m x n game, stated here only (the
// Python front reads it through lemke._core.games_layout): 8-byte slots, doubles first
// [x (m) | y (n) | regret | row payoff | column payoff], then int64 [P's n basic labels |
// Q's m basic labels | the path state (entering label, side, pivots, the HISTORY leaving
// labels)].
struct LHLayout {
    idx m, n;
    idx x() const { return 0; }
    idx y() const { return m; }
    idx regret() const { return m + n; }
    idx payoffs() const { return m + n + 1; }  // the row player's, then the column player's
    idx floats() const { return m + n + 3; }   // the doubles end here
    idx labels() const { return floats(); }    // int64 from here: P's labels, then Q's
    idx state() const { return labels() + m + n; }
    idx length() const { return state() + STATE; }
};

// The length (in doubles) of lemke_howson's output buffer for an m x n game.
inline idx lh_buffer_length(idx m, idx n) { return LHLayout{m, n}.length(); }

// trace's outputs for an m x n game: x, y and out side by side (TRACE_FLOATS doubles, the
// order of LHLayout's doubles) and basis_out (TRACE_LABELS int64: its system's rows).
inline idx trace_floats(idx m, idx n) { return LHLayout{m, n}.floats(); }
inline idx trace_labels(idx m, idx n) { return m + n + 2; }

// The games engine's work arrays, one per thread and reused: the float, index and flag
// arrays that lemke_howson and trace carve in games.cpp (LHViews / TraceViews, each laid
// out in one function there). They only grow.
struct GamesWork {
    std::vector<double> f;
    std::vector<idx> i;
    std::vector<std::uint8_t> z;
    void reserve(idx nf, idx ni, idx nz);
};

struct LHResult {
    int status;
    idx pivots;
    idx restarts;
};

// games.lemke_howson: Lemke-Howson dropping label k (0 <= k < m + n), from the basic labels
// `start` (n of P, then m of Q, each in [0, m + n)), params = (max_pivots, pivot_tol,
// tie_tol, tol), checked on (A, B). buf (lh_buffer_length) gets [x | y | regret, row
// payoff, column payoff], then as int64 the final basic labels of P and Q and the path
// state (entering label, side, pivots, the last HISTORY leaving labels).
LHResult lemke_howson(Mat<const double> A, Mat<const double> B, idx k, const idx* start,
                      const double* params, double* buf);

struct TraceResult {
    int status;
    idx pivots;
};

// games.trace: the tracing procedure from the prior (p, q). x (m), y (n), basis_out
// (m + n + 2), out (3: regret, row payoff, column payoff).
TraceResult trace(Mat<const double> A, Mat<const double> B, const double* p, const double* q,
                  idx max_pivots, double pivot_tol, double tie_tol, double tol, double* x,
                  double* y, idx* basis_out, double* out);

// The check of an equilibrium (check, verdict, allowance): certify.hpp, the acceptance
// module (included above).

// games.payoff_range: the least and the largest payoff, and whether every payoff is finite
// (the engine's scaling and the check's allowance).
struct Range {
    double lo, hi;
    bool finite;
};
Range payoff_range(Mat<const double> A);

}  // namespace games

}  // namespace lemke
