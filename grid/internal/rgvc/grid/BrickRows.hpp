// Range operations on brick-row words (VoxelStorage.hpp, "Brick rows"): whether a run of voxels along x is
// all opaque, a word (8 voxels) at a time. Internal to the brick walks' occluder fusion
// (BrickTraversal2D/3D.hpp), which grows boxes of opaque voxels up to 129 voxels on a side: voxel by
// voxel, that growth cost the volume of every box (a building of the game world of rgvc_bench_classes is
// tens of thousands of voxels), word by word an eighth of it. (The boxes are marked used per brick:
// DenseStorage::markUsedBox.)
#pragma once

#include "rgvc/grid/VoxelStorage.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>

namespace rgvc::brick_rows {

/// Calls fn(word, mask) for the words holding voxels x0..x1 (inclusive, x0 <= x1, both in the grid) of row
/// rowIndex (its key / res.x), with the mask of those voxels' bits in each, in order of x, while fn returns true.
/// Returns false if fn stopped it.
template <VoxelStorage S, class Fn> bool forEachWord(const S& s, std::uint32_t rowIndex, std::int32_t x0, std::int32_t x1, Fn&& fn) {
    // Only the end words are partial: the masks once, not per word (the per-word clamps were a third of
    // the fused boxes' growth on rgvc_bench_classes' game world, whose buildings' rows span many words).
    const std::int32_t b0 = x0 >> 3, b1 = x1 >> 3;
    const std::uint32_t first = (0xFFu << (x0 & 7)) & 0xFFu, last = 0xFFu >> (7 - (x1 & 7));
    if (b0 == b1) return fn(s.rowWord(rowIndex, x0), first & last);
    if (!fn(s.rowWord(rowIndex, x0), first)) return false;
    for (std::int32_t bx = b0 + 1; bx < b1; ++bx)
        if (!fn(s.rowWord(rowIndex, bx * 8), 0xFFu)) return false;
    return fn(s.rowWord(rowIndex, x1), last);
}

/// Whether voxel x of row rowIndex is opaque.
template <VoxelStorage S> bool opaqueAt(const S& s, std::uint32_t rowIndex, std::int32_t x) {
    return ((s.opaqueBits(s.rowWord(rowIndex, x)) >> (x & 7)) & 1u) != 0;
}

/// The opaque run through opaque voxel x of row rowIndex (of a grid resX voxels along x), a word at a time:
/// its ends, each at most `grow` voxels from x. Bits past the grid's last voxel are never set.
template <VoxelStorage S>
void opaqueRun(const S& s, std::uint32_t rowIndex, std::int32_t resX, std::int32_t x, std::int32_t grow, std::int32_t& lo,
               std::int32_t& hi) {
    // Up: the ones from bit x & 7 of each word; a word that is opaque to its end continues into the next.
    std::int32_t e = x;
    while (true) {
        const std::int32_t b = e & 7;
        const int ones = std::countr_one(s.opaqueBits(s.rowWord(rowIndex, e)) >> b); // >= 1 at e = x
        if (ones == 0) {
            --e;
            break;
        }
        e += ones;
        if (b + ones < 8 || e >= resX || e - x > grow) { // (the next word would be the next row's)
            --e;
            break;
        }
    }
    hi = std::min(e, x + grow);
    // Down: the ones below and at bit x & 7, counted from the word's top.
    e = x;
    while (true) {
        const std::int32_t b = e & 7;
        const int ones = std::countl_one(std::uint8_t(s.opaqueBits(s.rowWord(rowIndex, e)) << (7 - b)));
        if (ones == 0) {
            ++e;
            break;
        }
        e -= ones;
        if (ones <= b || e < 0 || x - e > grow) {
            ++e;
            break;
        }
    }
    lo = std::max(e, x - grow);
}

/// Whether voxels x0..x1 (inclusive) of row rowIndex are all opaque.
template <VoxelStorage S> bool allOpaque(const S& s, std::uint32_t rowIndex, std::int32_t x0, std::int32_t x1) {
    if ((x0 >> 3) == (x1 >> 3)) { // one word (a wall one voxel thick along x: most rows of its boxes)
        const std::uint32_t m = ((2u << (x1 - x0)) - 1u) << (x0 & 7);
        return (s.opaqueBits(s.rowWord(rowIndex, x0)) & m) == m;
    }
    return forEachWord(s, rowIndex, x0, x1, [&](std::size_t w, std::uint32_t m) { return (s.opaqueBits(w) & m) == m; });
}

} // namespace rgvc::brick_rows
