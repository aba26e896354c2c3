// The recovery ladder (issue 31, item 2): one mechanism for every kind. A ladder is a named
// table of rungs, each a name, whether it applies (to the state the rungs before it left) and
// its engine call (which runs, charges its pivots to the one cap and leaves its answer in the
// state); one driver, `climb`, tries them in order until the kind's `settled` says the answer
// is accepted by the kind's check, a stop (TIME_LIMIT, INTERRUPTED) came, or a rung ended
// the climb. Its Python twin, with the same shape and vocabulary, is lemke/_ladder.py (the
// ladders that live in the fronts: MLCP/QP, the box front's, the games' exact fallback).
//
// The table is a pack of rungs, not an array of function pointers: `climb` is a fold over
// them, so every rung's calls are inlined where the ladder is written and the first rung's
// path costs what the hand-written code did (the LCP's solve_one is the hottest path).
// Users: lcp.cpp (the warm stages of solve_one, the cold solve's recoveries in `checked` and
// the recoveries from a cycle in `run_checked`), boxed_batch.cpp (one island's runs: warm,
// friction rows cold, cold, covering vectors, exact ties), games.cpp (Lemke-Howson's three
// paths), python_front_qp.cpp (the QP front's kernel order: step 7, fused, step 8).
#pragma once
#include <algorithm>

#include "span.hpp"

namespace lemke {
namespace ladder {

// One rung: its name, whether it applies, the engine call.
template <class Applies, class Run>
struct Rung {
    const char* name;
    Applies applies;  // () -> bool
    Run run;          // () -> void
};

template <class Applies, class Run>
constexpr Rung<Applies, Run> rung(const char* name, Applies applies, Run run) {
    return Rung<Applies, Run>{name, applies, run};
}

// A rung that always applies.
struct Always {
    constexpr bool operator()() const { return true; }
};

// The one pivot cap of a climb: every rung's pivots are charged to it (a kernel's negative
// count, a refused run, charges nothing), and `left` is what the next rung may spend.
struct Cap {
    idx cap = 0;
    idx pivots = 0;
    idx left() const { return cap - pivots; }
    idx left_or_0() const { return std::max<idx>(0, cap - pivots); }
    bool spent() const { return pivots >= cap; }
    void charge(idx p) { pivots += std::max<idx>(p, 0); }
};

// The driver: each rung in order that applies is run; after each that ran, `settled()` (the
// answer accepted by the kind's check, a stop, or the climb ended by a rung) ends the climb.
// Returns the index in the table of the last rung run (-1: none applied); `name_of` gives
// its name.
template <class Settled, class... Rungs>
inline int climb(Settled settled, const Rungs&... rungs) {
    int last = -1, i = 0;
    bool done = false;
    auto step = [&](const auto& r) {
        if (!done && r.applies()) {
            r.run();
            last = i;
            done = settled();
        }
        ++i;
    };
    (step(rungs), ...);
    return last;
}

// The name of rung `index` of a table (nullptr when out of range): for diagnostics.
template <class... Rungs>
inline const char* name_of(int index, const Rungs&... rungs) {
    const char* names[] = {rungs.name...};
    return index >= 0 && index < static_cast<int>(sizeof...(Rungs)) ? names[index] : nullptr;
}

}  // namespace ladder
}  // namespace lemke
