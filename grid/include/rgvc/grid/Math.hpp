// Vector types and small numeric helpers shared by every module.
//
// World coordinates are `double` everywhere at the API boundary: a scene placed at 1e6 world units with
// 1e-3 voxels still resolves a voxel to ~1e-7 of its width (double has 53 bits; 1e9 voxel units need 30).
// Inside the grid, geometry is converted once to *voxel units* (see GridGeometry) and the occlusion
// rasterization runs on integer voxel-centre coordinates, where it is exact.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace rgvc {

/// A point or direction in D dimensions (D = 2 or 3), in double precision.
template <int D> using Vec = glm::vec<D, double, glm::defaultp>;
/// Integer voxel coordinates in D dimensions.
template <int D> using IVec = glm::vec<D, std::int32_t, glm::defaultp>;

using Vec2 = Vec<2>;
using Vec3 = Vec<3>;
using IVec2 = IVec<2>;
using IVec3 = IVec<3>;

/// Slack used by the conservative tests, in voxel units. Every test that decides "inside" for O or H
/// must clear it; every test that decides "touches" for I or the view region may be off by it.
/// 1e-9 voxel is far above double rounding for grids up to 2^31 voxels per axis and far below anything
/// a scene can express meaningfully.
inline constexpr double kConservativeSlack = 1e-9;

/// Cells in a box of `dims` cells (x fastest): their number, the row-major index of cell c, and the
/// cell of index i. Shared by the brick pyramid's levels and T's bricks and blocks.
template <int D> inline std::size_t cellCount(const IVec<D>& dims) {
    std::size_t n = 1;
    for (int a = 0; a < D; ++a) n *= std::size_t(dims[a]);
    return n;
}
template <int D> inline std::size_t cellIndex(const IVec<D>& dims, const IVec<D>& c) {
    std::size_t i = 0;
    for (int a = D - 1; a >= 0; --a) i = i * std::size_t(dims[a]) + std::size_t(c[a]);
    return i;
}
template <int D> inline IVec<D> cellOf(const IVec<D>& dims, std::size_t i) {
    IVec<D> c;
    for (int a = 0; a < D; ++a) {
        c[a] = std::int32_t(i % std::size_t(dims[a]));
        i /= std::size_t(dims[a]);
    }
    return c;
}

template <int D> inline bool allFinite(const Vec<D>& v) {
    for (int i = 0; i < D; ++i)
        if (!std::isfinite(v[i])) return false;
    return true;
}

template <int D> inline double lengthSquared(const Vec<D>& v) {
    double s = 0;
    for (int i = 0; i < D; ++i) s += v[i] * v[i];
    return s;
}

/// Unit vector along v, computed without overflow or underflow for any finite non-zero v (scales by the
/// largest component first: |(1e300, 1e300)|^2 would overflow to infinity).
template <int D> inline Vec<D> safeNormalize(const Vec<D>& v) {
    double m = 0;
    for (int i = 0; i < D; ++i) m = std::max(m, std::abs(v[i]));
    const Vec<D> s = v / m;
    return s / std::sqrt(lengthSquared<D>(s));
}

/// floor(x) as an int. [Limit] finite, |x| < 2^31. std::floor is a library call on x86-64 without SSE4.1
/// (the project builds for the baseline ISA), and the occlusion image rounds every footprint's bounds.
inline int floorToInt(double x) {
    const int t = int(x); // truncation toward zero
    return t - int(double(t) > x);
}

/// 2D cross product (z component of the 3D cross product).
inline double cross2(const Vec2& a, const Vec2& b) { return a.x * b.y - a.y * b.x; }
inline std::int64_t cross2(const IVec2& a, const IVec2& b) {
    return std::int64_t(a.x) * b.y - std::int64_t(a.y) * b.x;
}

} // namespace rgvc
