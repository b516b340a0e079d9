// T, the temporal-bounding-volume matrix (seed 004 §3, §4.1, §5.2), and how a TBV is discretized into it.
//
// A TBV bounds where a hidden moving object can be until the TBV expires (Sudarsky and Gotsman): a disc
// (2D) or an axis-aligned cube (3D) around the object's position when it was hidden, of radius (cube:
// half-side) R + maxSpeed * validity. The culler chooses the validity; this file only stores regions.
// A region's id goes into T only on its *boundary*, the paper's choice:
//
//   2D: every voxel the circle touches (closed voxels, with kConservativeSlack). The paper draws this ring
//       with a Bresenham circle modified for 4-connected curves; we compute it row by row from the exact
//       touch predicate instead, because the argument below needs exactly "every voxel the circle
//       touches", and a Bresenham walk decides by voxel centres, which can skip a voxel that the circle
//       clips at a corner. The result is a 4-connected ring, one or two voxels thick.
//   3D: the outer shell of the cube's voxel box [lo, hi]^3: the voxels of the box with some coordinate on
//       a bound. The paper stores it as the rectangle outlines of its three orthographic projections in
//       Txy, Txz and Tyz (§5.2), 12 (hi - lo + 1) writes instead of 6 (hi - lo + 1)^2, a voxel holding the
//       TBV iff two of its three projections do. We store the same voxel set, per brick of 8^3 voxels as a
//       list of TBVs and a bitmap (TbvMatrix<3> says why: the projections made lookups slow).
//
// Why the boundary suffices (§4.1 and its reference [3]). Let the camera's voxel lie outside the region
// (2D: it does not touch the disc; 3D: its index is outside [lo, hi] on some axis). A visible point p of
// the object lies inside the region; the open segment from the camera to p is unobstructed, so it crosses
// the region's boundary (2D: the circle; 3D: the surface of the voxel box) at some point q before p.
// Every voxel containing q is in T, touches the view region (q is on a view ray), and is not in H (q is
// visible, and H holds only voxels hidden at all their points), so the traversal visits it and reveals
// the TBV, in a layer no farther than p's (along a ray leaving the camera's voxel, the chess distance of
// the voxels met never decreases). The condition on the camera survives frame to frame if the camera's
// voxel moves by at most one voxel per axis: it cannot enter the region without standing on the
// boundary, where layer 0 reveals it (2D: a voxel sharing a point with a voxel that misses the disc
// either misses the disc or touches the circle; 3D: an index enters [lo, hi] only at lo or hi). For
// larger moves the culler checks every TBV against the new camera voxel (CullStats::cameraJump).
//
// The filled variant stores the whole region (2D: every voxel the disc touches; 3D: the voxel box). It needs no condition on the camera and costs area
// instead of perimeter; it is kept as an option to compare against (CullerOptions::tbvDiscretization).
//
// The shell variant (3D) stores the same shell voxels as Boundary, but in one list per voxel: 6 n^2 list
// nodes instead of a few per brick, and a lookup reads that voxel's list. Kept as an option to compare.
//
// Regions may reach outside the grid: only in-grid voxels are stored. For a camera and an object point
// inside the grid this stays correct, since the segment between them stays in the (convex) grid and
// crosses the clipped region's boundary there.
//
// This header holds the region, its discretization and the helpers both matrices share;
// TbvMatrix2D.hpp and TbvMatrix3D.hpp store them (TbvMatrix.hpp includes both).
#pragma once

#include "rgvc/grid/Math.hpp"
#include "rgvc/grid/TbvListPool.hpp"
#include "rgvc/grid/VoxelStorage.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace rgvc {

/// A TBV's region. [Units] voxel units of the grid. 2D: closed disc; 3D: closed axis-aligned cube.
template <int D> struct TbvRegion {
    Vec<D> centre{0.0};
    double radius = 0; ///< [Voxel units] disc radius or cube half-side, >= 0, slack included
};

enum class TbvDiscretization : std::uint8_t {
    Boundary, ///< ring (2D) or the voxel box's outer shell (3D): the paper's choice
    Filled,   ///< the whole region: no condition on the camera, more T writes
    Shell,    ///< 3D: the outer shell's voxels in a per-voxel T (2D: the ring, as Boundary)
};

/// Whether a discretization stores only a boundary, which needs the camera outside the region.
inline bool tbvBoundaryOnly(TbvDiscretization d) { return d != TbvDiscretization::Filled; }

/// [Voxel units] Distance from c to the closed voxel v in the region's metric: Euclidean in 2D (discs),
/// Chebyshev in 3D (cubes). A region touches v iff tbvGap(centre, v) <= radius (+ slack).
inline double tbvGap(const Vec2& c, const IVec2& v) {
    const double dx = std::max({double(v.x) - c.x, c.x - double(v.x + 1), 0.0});
    const double dy = std::max({double(v.y) - c.y, c.y - double(v.y + 1), 0.0});
    return std::sqrt(dx * dx + dy * dy);
}
inline double tbvGap(const Vec3& c, const IVec3& v) {
    double g = 0;
    for (int a = 0; a < 3; ++a) g = std::max({g, double(v[a]) - c[a], c[a] - double(v[a] + 1)});
    return g;
}
template <int D> inline bool tbvTouches(const TbvRegion<D>& r, const IVec<D>& v) {
    return tbvGap(r.centre, v) <= r.radius + kConservativeSlack;
}

/// Calls fn(x0, x1) for at most two runs of voxels, clipped to x in [0, res.x), that together hold every
/// run of the disc's discretization in the rows yA..yB (yA <= yB): for one row (tbvRowRuns2D) exactly its
/// runs, for a band of rows which tiles its rows meet, for two square roots instead of two per row
/// (TbvMatrix<2>'s inserts; computing every row was a third of the 2D room's instructions).
/// A row's runs: Boundary, the voxels touched by the circle (touched by the disc and not entirely inside
/// its open interior), i.e. its outer span [t0, t1] (the voxels touching the disc) less its hole [i0, i1]
/// (the voxels inside the open disc); Filled, the outer span.
/// Why a band's runs hold its rows' runs. Both the span and the hole are centred on c.x and shrink as the
/// row's distance from c.y grows, through monotone operations (products, sqrt, floor, ceil), so every
/// row's span lies in the span of the band's nearest row and every row's hole holds the hole of its
/// farthest row: each row's runs lie in the one less the other. The band's nearest and farthest
/// distances below (dyMin over [yA, yB + 1]; dyMax at its ends, where |t - c.y| is largest) are the same
/// floating expressions as those two rows' own (a row is the band yA = yB), so the bounds are the very
/// values those rows compute.
/// How tight. The ring is the set of voxels touching the closed annulus between the radii (a voxel is
/// connected, so it holds every distance between its nearest and farthest), and the closed voxels that
/// a connected set touches are 4-connected (passing to a diagonal neighbour through a corner touches all
/// four voxels there). So the runs of consecutive rows on one side overlap, and each side's union is the
/// one interval from the nearest row's outer end to the farthest row's inner end: the runs given here are
/// the rows' union, but for rounding within kConservativeSlack of a voxel corner (where they are larger).
template <class Fn> void tbvBandRuns2D(const TbvRegion<2>& r, const IVec2& res, TbvDiscretization mode, std::int32_t yA,
                                       std::int32_t yB, Fn&& fn) {
    const Vec2 c = r.centre;
    const double outer = r.radius + kConservativeSlack; // touch test errs towards touching
    const double inner = r.radius - kConservativeSlack; // "entirely inside" errs towards not
    const double dyMin = std::max({double(yA) - c.y, c.y - double(yB + 1), 0.0});
    if (dyMin > outer) return;
    const double wOut = std::sqrt(outer * outer - dyMin * dyMin);
    // Voxel x touches [c.x - w, c.x + w] iff x <= c.x + w and x + 1 >= c.x - w.
    const std::int32_t t0 = std::max<std::int32_t>(0, std::int32_t(std::ceil(c.x - wOut)) - 1);
    const std::int32_t t1 = std::min<std::int32_t>(res.x - 1, std::int32_t(std::floor(c.x + wOut)));
    if (t0 > t1) return;
    const double dyMax = std::max(std::abs(double(yA) - c.y), std::abs(double(yB + 1) - c.y));
    if (mode == TbvDiscretization::Filled || !(inner > dyMax)) {
        fn(t0, t1);
        return;
    }
    // Entirely inside the open disc: every corner is, i.e. x > c.x - w and x + 1 < c.x + w.
    const double wIn = std::sqrt(inner * inner - dyMax * dyMax);
    const std::int32_t i0 = std::int32_t(std::floor(c.x - wIn)) + 1;
    const std::int32_t i1 = std::int32_t(std::ceil(c.x + wIn)) - 2;
    if (i0 > i1) {
        fn(t0, t1);
        return;
    }
    if (t0 <= i0 - 1) fn(t0, std::min(t1, i0 - 1));
    if (i1 + 1 <= t1) fn(std::max(t0, i1 + 1), t1);
}

/// Calls fn(y, x0, x1) for the runs of voxels [x0, x1] of row y that the disc's discretization covers
/// (at most two), clipped to x in [0, res.x) (tbvBandRuns2D says which).
template <class Fn> void tbvRowRuns2D(const TbvRegion<2>& r, const IVec2& res, TbvDiscretization mode, std::int32_t y, Fn&& fn) {
    tbvBandRuns2D(r, res, mode, y, y, [&](std::int32_t x0, std::int32_t x1) { fn(y, x0, x1); });
}

/// The rows a disc's discretization can reach, clipped to [0, res.y).
inline void tbvRows2D(const TbvRegion<2>& r, const IVec2& res, std::int32_t& y0, std::int32_t& y1) {
    const double outer = r.radius + kConservativeSlack;
    y0 = std::max<std::int32_t>(0, std::int32_t(std::ceil(r.centre.y - outer)) - 1);
    y1 = std::min<std::int32_t>(res.y - 1, std::int32_t(std::floor(r.centre.y + outer)));
}

/// Calls fn(y, x0, x1) for each run of voxels of the disc's discretization (tbvRowRuns2D, every row).
template <class Fn> void forEachTbvRun2D(const TbvRegion<2>& r, const IVec2& res, TbvDiscretization mode, Fn&& fn) {
    std::int32_t y0, y1;
    tbvRows2D(r, res, y0, y1);
    for (std::int32_t y = y0; y <= y1; ++y) tbvRowRuns2D(r, res, mode, y, fn);
}

/// Whether the disc's discretization holds voxel v (the same computation as forEachTbvRun2D).
inline bool tbvCovers2D(const TbvRegion<2>& r, const IVec2& res, TbvDiscretization mode, const IVec2& v) {
    std::int32_t y0, y1;
    tbvRows2D(r, res, y0, y1);
    if (v.y < y0 || v.y > y1) return false;
    bool in = false;
    tbvRowRuns2D(r, res, mode, v.y, [&](std::int32_t, std::int32_t x0, std::int32_t x1) { in = in || (v.x >= x0 && v.x <= x1); });
    return in;
}

/// The voxel box [lo, hi] touched by a region (the disc's or the cube's bounding box), clipped to the
/// grid; false if it misses the grid.
template <int D> inline bool tbvVoxelBox(const TbvRegion<D>& r, const IVec<D>& res, IVec<D>& lo, IVec<D>& hi) {
    const double outer = r.radius + kConservativeSlack;
    for (int a = 0; a < D; ++a) {
        lo[a] = std::max<std::int32_t>(0, std::int32_t(std::ceil(r.centre[a] - outer)) - 1);
        hi[a] = std::min<std::int32_t>(res[a] - 1, std::int32_t(std::floor(r.centre[a] + outer)));
        if (lo[a] > hi[a]) return false;
    }
    return true;
}
inline bool tbvVoxelBox3D(const TbvRegion<3>& r, const IVec3& res, IVec3& lo, IVec3& hi) { return tbvVoxelBox<3>(r, res, lo, hi); }

template <int D> class TbvMatrix;

} // namespace rgvc
