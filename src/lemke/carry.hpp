// Carrying a basis across a change of rows by integer labels: open-addressing hash tables with linear probing and Fibonacci
// hashing, O(n + m).
#pragma once
#include <cstdint>

#include "span.hpp"

namespace lemke {

// New row j gets z basic when new_[j] is old[i] for an old row i with z basic (basic[:nb],
// each in [0, n)). Writes those j, ascending, into out (m entries at most) and returns
// their count; -1 when old holds a label twice, -2 when new_ does (carry.relabel_ids).
idx relabel_ids(const std::int64_t* old, idx n, const std::int64_t* new_, idx m,
                const idx* basic, idx nb, idx* out);

}  // namespace lemke
