#include "carry.hpp"

#include <vector>

namespace lemke {

namespace {

constexpr std::uint64_t GOLDEN = 0x9E3779B97F4A7C15ULL;

// log2 of a table size at least 2n (and 16): at most half full.
int table_bits(idx n) {
    int bits = 4;
    while ((idx{1} << bits) < 2 * n) ++bits;
    return bits;
}

// The label times 2^64 / golden ratio, its top `bits` bits.
idx slot(std::int64_t label, int bits) {
    return static_cast<idx>((static_cast<std::uint64_t>(label) * GOLDEN) >> (64 - bits));
}

}  // namespace

idx relabel_ids(const std::int64_t* old, idx n, const std::int64_t* new_, idx m,
                const idx* basic, idx nb, idx* out) {
    int bits = table_bits(n > m ? n : m);
    idx size = idx{1} << bits;
    idx mask = size - 1;
    // row[s]: the old row whose label is in slot s (-1: empty); seen[s]: the same for the
    // new rows (the duplicate check); flag[i]: old row i has z basic
    thread_local std::vector<idx> table;
    thread_local std::vector<std::uint8_t> flags;
    table.assign(static_cast<std::size_t>(2 * size), -1);
    flags.assign(static_cast<std::size_t>(n + 1), 0);
    idx* row = table.data();
    idx* seen = row + size;
    std::uint8_t* flag = flags.data();
    for (idx t = 0; t < nb; ++t) flag[basic[t]] = 1;
    for (idx i = 0; i < n; ++i) {
        idx s = slot(old[i], bits);
        while (row[s] >= 0) {
            if (old[row[s]] == old[i]) return -1;
            s = (s + 1) & mask;
        }
        row[s] = i;
    }
    idx count = 0;
    for (idx j = 0; j < m; ++j) {
        std::int64_t label = new_[j];
        idx s = slot(label, bits);
        while (seen[s] >= 0) {
            if (new_[seen[s]] == label) return -2;
            s = (s + 1) & mask;
        }
        seen[s] = j;
        s = slot(label, bits);
        idx i = n;  // not found: a new row (flag[n] is 0)
        while (row[s] >= 0) {
            if (old[row[s]] == label) {
                i = row[s];
                break;
            }
            s = (s + 1) & mask;
        }
        if (flag[i]) out[count++] = j;
    }
    return count;
}

}  // namespace lemke
