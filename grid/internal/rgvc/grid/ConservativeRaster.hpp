// Conservative discretization of shapes into voxels (seed 004 §4.1, §5.1).
//
//   inner voxels   (-> O): voxels whose closed box lies entirely inside the closed shape. O may only
//                          *under*-estimate the opaque region (up to a 1e-9 voxel snapping of faces
//                          to voxel boundaries, see innerRange; balls are shrunk by kConservativeSlack).
//   touched voxels (-> I): voxels whose closed box meets the closed shape, grown by kConservativeSlack.
//                          I may only *over*-estimate the spanned region.
//
// The paper gets these by rasterizing outlines grown and shrunk by the voxel's half-diagonal support
// (|nx|+|ny|)*d/2 and sampling at voxel centres. We compute the same sets exactly, row by row, from the
// shape's analytic description: one span per row of voxels, so the cost is O(rows + voxels written) and
// nothing is allocated. Everything here is in voxel units (see GridGeometry::toLocal) and clipped to the
// grid [0, resolution).
#pragma once

#include "rgvc/grid/Math.hpp"
#include "rgvc/grid/PolytopeRaster.hpp"
#include "rgvc/grid/Shapes.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <variant>

namespace rgvc {

namespace raster_detail {

inline std::int32_t clampIndex(double v, std::int32_t lo, std::int32_t hi) {
    if (!(v > lo)) return lo; // also catches NaN
    if (v > hi) return hi;
    return std::int32_t(v);
}

/// Voxel index range [first, last] of voxels [i, i+1] that meet the closed interval [a, b], clipped to
/// [0, n). Empty when first > last.
inline void touchedRange(double a, double b, std::int32_t n, std::int32_t& first, std::int32_t& last,
                         double slack = kConservativeSlack) {
    a -= slack;
    b += slack;
    first = clampIndex(std::ceil(a) - 1, 0, n);
    last = clampIndex(std::floor(b), -1, n - 1);
    if (std::floor(b) < 0) last = -1;
}

/// Voxel index range of voxels [i, i+1] contained in [a, b], clipped to [0, n).
/// Faces within kConservativeSlack of a voxel boundary count as lying on it: a box from 20 to 22 that
/// the world-to-voxel conversion turned into 20.0000000000004 .. 22 still covers voxels 20 and 21.
/// Otherwise every box aligned with the grid would lose its boundary voxels to rounding; the price is
/// that an O voxel may exceed its object by at most 1e-9 voxel.
/// With a conversion slack above kConservativeSlack (grids far from the origin, see
/// GridGeometry::conversionSlack) the excess shrinks the range instead.
inline void innerRange(double a, double b, std::int32_t n, std::int32_t& first, std::int32_t& last,
                       double slack = kConservativeSlack) {
    const double snap = 2 * kConservativeSlack - slack; // kConservativeSlack for ordinary grids
    a -= snap;
    b += snap;
    first = clampIndex(std::ceil(a), 0, n);
    last = clampIndex(std::floor(b) - 1, -1, n - 1);
    if (std::floor(b) - 1 < 0) last = -1;
}

/// Calls fn(IVec<D> rowStart, x0, x1) for every row (all coordinates but x) of the index box [lo, hi]
/// where rowFn(row) produces a non-empty x span [x0, x1].
template <int D, class RowFn, class Fn>
void forEachRow(const IVec<D>& lo, const IVec<D>& hi, RowFn&& rowFn, Fn&& fn) {
    if constexpr (D == 2) {
        for (std::int32_t y = lo.y; y <= hi.y; ++y) {
            std::int32_t x0, x1;
            if (rowFn(IVec2{0, y}, x0, x1) && x0 <= x1) fn(IVec2{0, y}, x0, x1);
        }
    } else {
        for (std::int32_t z = lo.z; z <= hi.z; ++z)
            for (std::int32_t y = lo.y; y <= hi.y; ++y) {
                std::int32_t x0, x1;
                if (rowFn(IVec3{0, y, z}, x0, x1) && x0 <= x1) fn(IVec3{0, y, z}, x0, x1);
            }
    }
}

/// Distance from c to the nearest / farthest point of [i, i+1].
inline double nearestDistance(double c, std::int32_t i) { return c < i ? i - c : (c > i + 1 ? c - i - 1 : 0.0); }
inline double farthestDistance(double c, std::int32_t i) { return std::max(std::abs(c - i), std::abs(c - i - 1)); }

/// x-extent of a convex polygon inside the closed horizontal strip [y0, y1]; false when they miss.
inline bool polygonStripExtent(const ConvexPolygon& p, double y0, double y1, double& xl, double& xr) {
    xl = std::numeric_limits<double>::infinity();
    xr = -xl;
    const std::size_t n = p.points.size();
    for (std::size_t k = 0; k < n; ++k) {
        const Vec2& a = p.points[k];
        const Vec2& b = p.points[(k + 1) % n];
        if (a.y >= y0 && a.y <= y1) {
            xl = std::min(xl, a.x);
            xr = std::max(xr, a.x);
        }
        for (double y : {y0, y1}) {
            if ((a.y < y && b.y > y) || (a.y > y && b.y < y)) {
                double x = a.x + (b.x - a.x) * ((y - a.y) / (b.y - a.y));
                xl = std::min(xl, x);
                xr = std::max(xr, x);
            }
        }
    }
    return xl <= xr;
}

/// x-interval of a convex polygon on the line y; false when it misses.
inline bool polygonLineExtent(const ConvexPolygon& p, double y, double& xl, double& xr) {
    return polygonStripExtent(p, y, y, xl, xr);
}

} // namespace raster_detail

/// Calls fn(IVec<D> voxel) for every in-grid voxel whose closed box the closed shape touches (I).
/// @param local       shape in voxel units.
/// @param resolution  [Voxels] grid size; voxels outside [0, resolution) are skipped.
/// @param slack       [Voxel units] growth of the shape, >= kConservativeSlack; pass the grid's
///                    conversionSlack() for shapes converted from world units.
/// Visits each voxel once, rows in increasing order. Never allocates.
template <int D, class Fn>
void forEachTouchedVoxel(const Shape<D>& local, const IVec<D>& resolution, Fn&& fn, double slack = kConservativeSlack);

/// Calls fn(IVec<D> voxel) for every in-grid voxel whose closed box lies inside the closed shape (O),
/// shrunk by slack - kConservativeSlack (faces within kConservativeSlack of a voxel boundary snap to it).
template <int D, class Fn>
void forEachInnerVoxel(const Shape<D>& local, const IVec<D>& resolution, Fn&& fn, double slack = kConservativeSlack);

/// The same sets as spans: calls fn(IVec<D> row, x0, x1) once per row (row.x = 0) whose voxels
/// x0..x1 (x0 <= x1) are touched / inner, rows in increasing linear order. What the voxel functions
/// visit is exactly the union of these spans: they are built on them. Never allocates.
template <int D, class RowFn>
void forEachTouchedRow(const Shape<D>& local, const IVec<D>& resolution, RowFn&& fn, double slack = kConservativeSlack);
template <int D, class RowFn>
void forEachInnerRow(const Shape<D>& local, const IVec<D>& resolution, RowFn&& fn, double slack = kConservativeSlack);

/// True when the closed shape (voxel units) has points outside the closed grid box [0, resolution].
template <int D> bool extendsOutsideGrid(const Shape<D>& local, const IVec<D>& resolution) {
    Box<D> b = boundsOf<D>(local);
    for (int i = 0; i < D; ++i)
        if (b.min[i] < 0 || b.max[i] > resolution[i]) return true;
    return false;
}

// ---------------------------------------------------------------------------------------------------

namespace raster_detail {

/// The rows of a ball's footprint, with squares of plain lengths (no per-row scaling; see rasterize).
/// A voxel row (all coordinates but x fixed) meets the ball grown to rr iff the nearest distances along
/// the other axes satisfy sum d_a^2 <= rr^2 (touched), and then its x chord has half-width
/// w = sqrt(rr^2 - sum d_a^2); inner rows take the farthest distances instead (the whole row cross-section
/// [y, y+1] x [z, z+1] inside), after which the x range inside the chord is the 1D rule. The squared budget
/// left over by the outer axes is computed once per outer row (once per z, not once per (y, z)), so a row
/// costs one square, one subtraction and one sqrt.
template <int D, int A, bool kInner, class RowFn>
void ballRows(const Vec<D>& c, double budget, const IVec<D>& lo, const IVec<D>& hi, IVec<D>& row, RowFn& rowFn) {
    for (row[A] = lo[A]; row[A] <= hi[A]; ++row[A]) {
        const double d = kInner ? farthestDistance(c[A], row[A]) : nearestDistance(c[A], row[A]);
        const double left = budget - d * d; // -inf when d*d overflows: the row misses (d > rr)
        if (left < 0) continue;
        if constexpr (A == 1) rowFn(row, std::sqrt(left));
        else ballRows<D, A - 1, kInner>(c, left, lo, hi, row, rowFn);
    }
}

/// Calls rowFn(IVec<D> row, x0, x1) (row.x = 0) for the non-empty x span of every row of the footprint,
/// rows in increasing linear order. Each row holds one span (every shape here is convex), except a mesh's
/// inner voxels (its solid voxelization, MeshSolid.hpp): spans ascending and disjoint, several per row
/// where the solid is concave. A mesh's touched voxels are the voxels its triangles (and, closed, its solid)
/// touch, one span per row from the row's first to its last (MeshSolid.hpp: the voxels a point of the mesh
/// can lie in, and the row's gaps filled so that I keeps one span per row).
template <int D, bool kInner, class RowFn>
void rasterize(const Shape<D>& local, const IVec<D>& res, RowFn&& rowFn, double slack) {
    Box<D> bounds = boundsOf<D>(local);
    IVec<D> lo, hi;
    for (int i = 0; i < D; ++i) touchedRange(bounds.min[i], bounds.max[i], res[i], lo[i], hi[i], slack);
    for (int i = 0; i < D; ++i)
        if (lo[i] > hi[i]) return;

    std::visit(
        [&](const auto& s) {
            using T = std::decay_t<decltype(s)>;
            if constexpr (std::is_same_v<T, Box<D>>) {
                IVec<D> rlo = lo, rhi = hi;
                if constexpr (kInner) {
                    for (int i = 0; i < D; ++i) innerRange(s.min[i], s.max[i], res[i], rlo[i], rhi[i], slack);
                    for (int i = 0; i < D; ++i)
                        if (rlo[i] > rhi[i]) return;
                }
                forEachRow<D>(
                    rlo, rhi,
                    [&](const IVec<D>&, std::int32_t& a, std::int32_t& b) {
                        a = rlo.x;
                        b = rhi.x;
                        return true;
                    },
                    rowFn);
            } else if constexpr (std::is_same_v<T, Ball<D>>) {
                const double r = s.radius;
                const double rr = kInner ? (r - slack) : (r + slack);
                if (rr <= 0) return;
                // A voxel's closed box lies in the ball only if its farthest corner does, and every point
                // has a corner of the unit box at least half its diagonal, sqrt(D) / 2, away: a smaller
                // ball holds no inner voxel, whatever its centre. The rows below would find none either
                // (they are conservative); this skips them for the small movers that are most of a crowd
                // (a moving sphere's O footprint is rebuilt every frame).
                if (kInner && rr * rr < 0.25 * D) return;
                auto chord = [&](const IVec<D>& row, double w) {
                    std::int32_t a, b;
                    if constexpr (kInner) innerRange(s.center.x - w, s.center.x + w, res.x, a, b, slack);
                    else touchedRange(s.center.x - w, s.center.x + w, res.x, a, b, slack);
                    if (a <= b) rowFn(row, a, b);
                };
                if (rr < 1e150) {
                    // rr^2 < 1e300 is finite, so every budget is finite or -inf, never NaN.
                    IVec<D> row = lo;
                    row.x = 0;
                    ballRows<D, D - 1, kInner>(s.center, rr * rr, lo, hi, row, chord);
                    return;
                }
                // Huge balls: squares are taken after scaling by the largest length, so that a finite ball
                // of radius 1e200 does not overflow to inf - inf = NaN.
                forEachRow<D>(
                    lo, hi,
                    [&](const IVec<D>& row, std::int32_t& a, std::int32_t& b) {
                        double dist[D > 1 ? D - 1 : 1];
                        double scale = rr;
                        for (int i = 1; i < D; ++i) {
                            dist[i - 1] = kInner ? farthestDistance(s.center[i], row[i])
                                                 : nearestDistance(s.center[i], row[i]);
                            scale = std::max(scale, dist[i - 1]);
                        }
                        double w2 = (rr / scale) * (rr / scale);
                        for (int i = 1; i < D; ++i) w2 -= (dist[i - 1] / scale) * (dist[i - 1] / scale);
                        if (w2 < 0) return false;
                        const double w = scale * std::sqrt(w2);
                        if constexpr (kInner)
                            innerRange(s.center.x - w, s.center.x + w, res.x, a, b, slack);
                        else
                            touchedRange(s.center.x - w, s.center.x + w, res.x, a, b, slack);
                        return true;
                    },
                    rowFn);
            } else if constexpr (D == 2 && std::is_same_v<T, ConvexPolygon>) {
                forEachRow<2>(
                    lo, hi,
                    [&](const IVec2& row, std::int32_t& a, std::int32_t& b) {
                        double xl, xr;
                        if constexpr (kInner) {
                            // All four corners inside: both horizontal voxel edges lie on chords of the polygon.
                            double l0, r0, l1, r1;
                            if (!polygonLineExtent(s, row.y, l0, r0) || !polygonLineExtent(s, row.y + 1.0, l1, r1))
                                return false;
                            xl = std::max(l0, l1);
                            xr = std::min(r0, r1);
                            if (xl > xr) return false;
                            // Chord endpoints carry rounding of ~1e-16 of the coordinates, far inside
                            // innerRange's 1e-9 snapping tolerance.
                            innerRange(xl, xr, res.x, a, b, slack);
                        } else {
                            if (!polygonStripExtent(s, row.y - slack, row.y + 1.0 + slack,
                                                    xl, xr))
                                return false;
                            const double rounding = 1e-12 * (std::abs(xl) + std::abs(xr));
                            touchedRange(xl - rounding, xr + rounding, res.x, a, b, slack);
                        }
                        return true;
                    },
                    rowFn);
            } else if constexpr (std::is_same_v<T, ConvexPolytope> || std::is_same_v<T, MeshSolid>) {
                if constexpr (std::is_same_v<T, MeshSolid> && kInner) {
                    // O: only voxels entirely inside the closed solid (MeshVoxelize.cpp derives the rule).
                    for (const VoxelRowSpan& sp : meshInnerSpans(s, res, slack)) {
                        IVec<D> row{0};
                        row[1] = sp.y;
                        row[D - 1] = sp.z; // D == 3 here; indexed, not .z, so that clang accepts D = 2's discarded branch
                        rowFn(row, sp.x0, sp.x1);
                    }
                    return;
                }
                if constexpr (std::is_same_v<T, MeshSolid> && !kInner) {
                    // I: every voxel a point of the mesh lies in meets a triangle or (closed) lies in the solid,
                    // so it is among the touched spans; the gaps between a row's spans are filled (a superset:
                    // the footprint writers keep one span per row for I).
                    const std::vector<VoxelRowSpan>& spans = meshTouchedSpans(s, res, slack);
                    for (std::size_t i = 0; i < spans.size();) {
                        const VoxelRowSpan& first = spans[i];
                        std::int32_t x1 = first.x1;
                        std::size_t j = i + 1;
                        for (; j < spans.size() && spans[j].y == first.y && spans[j].z == first.z; ++j) x1 = std::max(x1, spans[j].x1);
                        IVec<D> row{0};
                        row[1] = first.y;
                        row[D - 1] = first.z;
                        rowFn(row, first.x0, x1);
                        i = j;
                    }
                    return;
                }
                const ConvexPolytope* pp = nullptr;
                if constexpr (std::is_same_v<T, MeshSolid>) pp = &s.hull();
                else pp = &s;
                const ConvexPolytope& p = *pp;
                // PolytopeRaster.hpp derives both rules.
                forEachRow<3>(
                    lo, hi,
                    [&](const IVec3& row, std::int32_t& a, std::int32_t& b) {
                        double xl, xr;
                        if constexpr (kInner) {
                            const double snap = 2 * kConservativeSlack - slack; // as innerRange snaps faces
                            const double grow = snap - p.tolerance;
                            xl = -std::numeric_limits<double>::infinity();
                            xr = -xl;
                            for (double y : {double(row.y), row.y + 1.0})
                                for (double z : {double(row.z), row.z + 1.0}) {
                                    double l, r;
                                    if (!polytopeChord(p, y, z, grow, l, r)) return false;
                                    xl = std::max(xl, l);
                                    xr = std::min(xr, r);
                                }
                            if (!(xl <= xr)) return false;
                            innerRange(xl, xr, res.x, a, b, slack);
                        } else {
                            const double g = slack + p.tolerance;
                            if (!polytopeSlabExtent(p, row.y - g, row.y + 1.0 + g, row.z - g, row.z + 1.0 + g, g, xl, xr))
                                return false;
                            const double rounding = 1e-12 * (std::abs(xl) + std::abs(xr));
                            touchedRange(xl - rounding - p.tolerance, xr + rounding + p.tolerance, res.x, a, b, slack);
                        }
                        return true;
                    },
                    rowFn);
            } else if constexpr (!std::is_same_v<T, ConvexPolygon>) {
                static_assert(kUnhandledShape<T>);
            }
        },
        local);
}

template <int D, class Fn> auto voxelsOfRows(Fn& fn) {
    return [&fn](const IVec<D>& row, std::int32_t x0, std::int32_t x1) {
        IVec<D> v = row;
        for (std::int32_t x = x0; x <= x1; ++x) {
            v.x = x;
            fn(v);
        }
    };
}

} // namespace raster_detail

template <int D, class Fn>
void forEachTouchedVoxel(const Shape<D>& local, const IVec<D>& resolution, Fn&& fn, double slack) {
    raster_detail::rasterize<D, false>(local, resolution, raster_detail::voxelsOfRows<D>(fn), slack);
}

template <int D, class Fn>
void forEachInnerVoxel(const Shape<D>& local, const IVec<D>& resolution, Fn&& fn, double slack) {
    raster_detail::rasterize<D, true>(local, resolution, raster_detail::voxelsOfRows<D>(fn), slack);
}

template <int D, class RowFn>
void forEachTouchedRow(const Shape<D>& local, const IVec<D>& resolution, RowFn&& fn, double slack) {
    raster_detail::rasterize<D, false>(local, resolution, fn, slack);
}

template <int D, class RowFn>
void forEachInnerRow(const Shape<D>& local, const IVec<D>& resolution, RowFn&& fn, double slack) {
    raster_detail::rasterize<D, true>(local, resolution, fn, slack);
}

} // namespace rgvc
