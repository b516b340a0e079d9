// Layers of equal chess distance around the camera's voxel in 2D (seed 004 §4.2).
//
// Layer k >= 1 is the square ring of the 8k voxels c + (x, y) with max(|x|, |y|) = k. We number its
// voxels counter-clockwise by a perimeter index p in [0, 8k), starting at the corner (k, -k):
//   side 0: (k, -k + p)            p in [0, 2k)      x = +k, going +y
//   side 1: (k - (p - 2k), k)      p in [2k, 4k)     y = +k, going -x
//   side 2: (-k, k - (p - 4k))     p in [4k, 6k)     x = -k, going -y
//   side 3: (-k + (p - 6k), -k)    p in [6k, 8k)     y = -k, going +x
// Stepping p +- 1 is exactly the paper's catalogue of traversal directions: along +-y on the sides
// where |x| > |y|, along +-x where |y| > |x|, and turning by 90 degrees at the corners |x| = |y|.
#pragma once

#include "rgvc/grid/Math.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace rgvc {

/// Offset from the ring's centre voxel of perimeter index p (taken modulo 8k) on ring k >= 1.
inline IVec2 ringOffset(std::int32_t k, std::int64_t p) {
    const std::int64_t n = 8 * std::int64_t(k);
    p %= n;
    if (p < 0) p += n;
    const std::int32_t q = std::int32_t(p);
    if (q < 2 * k) return {k, -k + q};
    if (q < 4 * k) return {k - (q - 2 * k), k};
    if (q < 6 * k) return {-k, k - (q - 4 * k)};
    return {-k + (q - 6 * k), -k};
}

/// Perimeter index of offset o, which must satisfy max(|o.x|, |o.y|) = k >= 1.
inline std::int64_t ringIndex(const IVec2& o, std::int32_t k) {
    if (o.x == k && o.y < k) return std::int64_t(o.y) + k;
    if (o.y == k && o.x > -k) return 2 * std::int64_t(k) + (k - o.x);
    if (o.x == -k && o.y > -k) return 4 * std::int64_t(k) + (k - o.y);
    return 6 * std::int64_t(k) + (o.x + k);
}

/// Chess (L-infinity) distance between voxels.
inline std::int32_t chessDistance(const IVec2& a, const IVec2& b) {
    return std::max(std::abs(a.x - b.x), std::abs(a.y - b.y));
}

/// Seed voxel of ring k on the line of sight: the voxel holding the point where the ray from `apex`
/// (voxel units, inside voxel `c`) along `dir` first reaches chess distance k from c's centre.
///
/// The paper discretizes the line of sight with Bresenham's algorithm from the camera voxel's centre.
/// We follow the actual ray from the actual camera point instead: with the camera off-centre (it may sit
/// on a voxel corner) Bresenham's voxel can lie just outside the view wedge, whereas a point of the ray
/// is always inside it. The point at chess distance exactly k from c's centre lies in a voxel of ring k,
/// because ring k covers chess distances (k - 1/2, k + 1/2). Cost: O(1) per ring.
inline IVec2 lineOfSightSeed(const Vec2& apex, const Vec2& dir, const IVec2& c, std::int32_t k) {
    const Vec2 rel = apex - (Vec2(c) + 0.5);
    double t = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 2; ++a) {
        if (dir[a] > 0) t = std::min(t, (k - rel[a]) / dir[a]);
        else if (dir[a] < 0) t = std::min(t, (-k - rel[a]) / dir[a]);
    }
    const Vec2 p = rel + dir * t;
    IVec2 o{std::int32_t(std::lround(p.x)), std::int32_t(std::lround(p.y))};
    // Rounding can leave the point a hair off the ring; project it back onto ring k.
    o = glm::clamp(o, IVec2(-k), IVec2(k));
    if (std::max(std::abs(o.x), std::abs(o.y)) != k) {
        if (std::abs(p.x) >= std::abs(p.y)) o.x = p.x >= 0 ? k : -k;
        else o.y = p.y >= 0 ? k : -k;
    }
    return o;
}

} // namespace rgvc
