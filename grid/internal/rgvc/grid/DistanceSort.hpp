// Sorting (distance, index) pairs nearest first, in the order std::sort gives them, without comparisons.
//
// Why. The occlusion buffer's pass (dynamics/src/BufferPass.cpp) sorts the grid's PVS by each object's
// nearest distance every frame: 2,000-3,000 pairs on rgvc_bench_classes' clusters. std::sort's
// comparisons of unordered keys mispredict about every other branch: 165 / 48 / 12 / 3.3 us for 3,000 /
// 1,000 / 300 / 100 random pairs on this project's machine (AMD EPYC, -O2), against 24 / 8.5 / 2.9 /
// 1.1 us for this sort (11-bit digits: 25 / 10 / 4.3 / 3.1 us, their counters cost more to clear).
// Hand-written because the order must be exactly std::sort's on the pairs (ties broken by index, so the
// pass draws and tests in the same order as before and the PVS does not move), which a radix sort gives
// only when stable; Boost's spreadsort is not stable and hands ranges of this size to std::sort anyway.
//
// How. A non-negative double's bits, read as an unsigned integer, order as the double does; a negative
// one's are flipped (the usual sign trick, which orders every finite double and the infinities). The
// pairs are sorted stably by the key's upper 32 bits (sign, exponent and 20 bits of mantissa) in four
// passes of 8-bit digits, least significant first; a digit every key shares (the top byte, for
// distances of similar magnitude) needs no pass, which one counting pass finds for all four at once.
// Pairs whose keys agree in those 32 bits (distances within a millionth of each other, or equal) are then
// in index order, since the input was; one insertion pass on the full pairs puts them in std::sort's
// order, and costs one comparison per pair when there are none.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cassert>
#include <cstdint>
#include <utility>
#include <vector>

namespace rgvc {

/// The upper 32 bits of the key whose unsigned order is the double's order. [Limit] never NaN. -0.0 gets
/// +0.0's key, as the comparison -0.0 < 0.0 is false.
inline std::uint32_t distanceSortKey(double d) {
    const std::uint64_t bits = std::bit_cast<std::uint64_t>(d + 0.0); // -0.0 + 0.0 == +0.0
    const std::uint64_t key = (bits >> 63) != 0 ? ~bits : bits | (std::uint64_t(1) << 63);
    return std::uint32_t(key >> 32);
}

/// Sorts `pairs` as std::sort would (by distance, then by index). [Limit] The pairs must arrive with
/// strictly increasing indices and no NaN distance. `scratch` is working memory, reused across calls so
/// the sort allocates nothing once it has grown. O(n) time when few distances agree to a millionth: one
/// counting pass, at most four moves and one insertion pass.
inline void sortByDistance(std::vector<std::pair<double, std::uint32_t>>& pairs,
                           std::vector<std::pair<double, std::uint32_t>>& scratch) {
    const std::size_t n = pairs.size();
    if (n < 32) { // a few dozen pairs: comparisons are cheaper than the 4 KB of counters
        std::sort(pairs.begin(), pairs.end());
        return;
    }
#ifndef NDEBUG
    for (std::size_t i = 1; i < n; ++i) assert(pairs[i - 1].second < pairs[i].second);
#endif
    std::array<std::array<std::uint32_t, 256>, 4> count{};
    for (const auto& p : pairs) {
        const std::uint32_t k = distanceSortKey(p.first);
        for (int d = 0; d < 4; ++d) ++count[std::size_t(d)][(k >> (8 * d)) & 0xff];
    }
    scratch.resize(n);
    auto* from = &pairs;
    auto* to = &scratch;
    for (int d = 0; d < 4; ++d) {
        auto& c = count[std::size_t(d)];
        const int shift = 8 * d;
        if (c[(distanceSortKey((*from)[0].first) >> shift) & 0xff] == n) continue; // nothing would move
        std::uint32_t sum = 0;
        for (auto& v : c) sum += std::exchange(v, sum); // counts become each digit's first slot
        for (const auto& p : *from) (*to)[c[(distanceSortKey(p.first) >> shift) & 0xff]++] = p;
        std::swap(from, to);
    }
    if (from != &pairs) pairs.swap(scratch);
    // Equal 32-bit keys: in index order now; the full comparison finishes them.
    for (std::size_t i = 1; i < n; ++i) {
        if (!(pairs[i] < pairs[i - 1])) continue;
        const auto x = pairs[i];
        std::size_t j = i;
        for (; j > 0 && x < pairs[j - 1]; --j) pairs[j] = pairs[j - 1];
        pairs[j] = x;
    }
}

} // namespace rgvc
