// The open part of an image row: the pixels an occludee test still has to bound, shared by the tests of
// OcclusionTests3D.cpp (scanFootprint) and OcclusionExact3D.cpp (hiddenBall, hiddenBoxExact). Private to
// the grid library's sources.
#pragma once

#include "rgvc/grid/OcclusionBuffer3D.hpp"

#include <algorithm>
#include <cstddef>

namespace rgvc {

/// Narrows [i0, i1] of an image row to its first and last pixel not covered nearer than `nearest`; false
/// when every pixel is. Such a pixel passes an occludee's per-pixel test whatever its bound (each bound
/// is at least the occludee's nearest distance), so hiddenBall and hiddenBoxExact bound only the rest.
inline bool uncoveredSpan(const double* row, double nearest, int& i0, int& i1) {
    while (i0 <= i1 && row[i0] < nearest) ++i0;
    if (i0 > i1) return false;
    while (row[i1] < nearest) --i1; // stops at i0
    return true;
}

inline bool OcclusionBuffer3D::openRowSpan(const Footprint& f, int j, double nearest, int& i0, int& i1) const {
    // The rectangle's row first: where all of it is covered nearer (behind a wall, most rows), the
    // polygon's span (a clip per edge, two divisions each) is not needed.
    const double* row = m_depth.data() + std::size_t(j) * std::size_t(m_cols);
    int u0 = f.rect.i0, u1 = f.rect.i1;
    if (!uncoveredSpan(row, nearest, u0, u1) || !rowSpan(f, j, i0, i1)) return false;
    i0 = std::max(i0, u0);
    i1 = std::min(i1, u1);
    return i0 <= i1 && uncoveredSpan(row, nearest, i0, i1);
}

} // namespace rgvc
