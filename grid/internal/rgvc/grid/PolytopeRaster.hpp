// Row spans of a convex polytope's conservative discretization (ConservativeRaster.hpp's rows for
// ConvexPolytope). Voxel units.
//
// Touched (I). The voxels of row (y, z) that the closed polytope P touches are those whose x range meets
// the x extent of P n S, S = [y, y+1] x [z, z+1] x R the row's slab. P n S is a convex polytope; its x
// extremes are at its vertices, and each vertex is the meeting point of three of its bounding planes:
//   - three facets of P: a vertex of P inside S;
//   - two facets and a slab plane: an edge of P crossing a side of S;
//   - one facet and two slab planes (one y and one z plane; two y planes are parallel): a point on one of
//     the four lines y = y0|y1, z = z0|z1 where the line's chord through P ends.
// So the extent is the union of every edge of P clipped to S and the four corner lines' chords, which is
// what touchedRow computes, exactly. Everything is grown by slack + the polytope's tolerance (the slab
// and the planes), so rounding and the hull's epsilon only add voxels.
//
// Inner (O). A voxel lies in the convex P iff its 8 corners do; the row's voxels [x, x+1] with all 8
// corners inside are those inside all four corner lines' chords: the intersection of the four chords,
// with the planes shrunk by the tolerance (and the usual 1e-9 snapping of faces on voxel boundaries).
//
// Cost per row: O(edges + 4 planes); nothing is allocated.
#pragma once

#include "rgvc/grid/ConvexPolytope.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rgvc::raster_detail {

/// The chord [lo, hi] of the line {(x, y, z): x real} through the polytope whose planes are moved out by
/// grow (in by -grow). False when the line misses it.
inline bool polytopeChord(const ConvexPolytope& p, double y, double z, double grow, double& lo, double& hi) {
    lo = -std::numeric_limits<double>::infinity();
    hi = std::numeric_limits<double>::infinity();
    for (const HalfSpace& h : p.planes) {
        const double r = h.offset + grow - h.normal.y * y - h.normal.z * z; // nx x <= r
        if (h.normal.x > 0) hi = std::min(hi, r / h.normal.x);
        else if (h.normal.x < 0) lo = std::max(lo, r / h.normal.x);
        else if (r < 0) return false;
    }
    return lo <= hi;
}

/// x extent of the polytope grown by `grow` inside the slab [y0, y1] x [z0, z1] (already grown by the
/// caller); false when they miss. See the header comment.
inline bool polytopeSlabExtent(const ConvexPolytope& p, double y0, double y1, double z0, double z1, double grow,
                               double& xl, double& xr) {
    xl = std::numeric_limits<double>::infinity();
    xr = -xl;
    for (const auto& e : p.edges) {
        const Vec3& a = p.vertices[e[0]];
        const Vec3& b = p.vertices[e[1]];
        const Vec3 d = b - a;
        double t0 = 0, t1 = 1;
        auto clipAxis = [&](double pa, double dd, double lo, double hi) {
            if (dd == 0) return pa >= lo && pa <= hi;
            double s0 = (lo - pa) / dd, s1 = (hi - pa) / dd;
            if (s0 > s1) std::swap(s0, s1);
            t0 = std::max(t0, s0);
            t1 = std::min(t1, s1);
            return t0 <= t1;
        };
        if (!clipAxis(a.y, d.y, y0, y1) || !clipAxis(a.z, d.z, z0, z1)) continue;
        const double xa = a.x + d.x * t0, xb = a.x + d.x * t1;
        xl = std::min({xl, xa, xb});
        xr = std::max({xr, xa, xb});
    }
    for (double y : {y0, y1})
        for (double z : {z0, z1}) {
            double lo, hi;
            if (!polytopeChord(p, y, z, grow, lo, hi)) continue;
            xl = std::min(xl, lo);
            xr = std::max(xr, hi);
        }
    return xl <= xr;
}

} // namespace rgvc::raster_detail
