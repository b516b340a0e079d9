// Occlusion polygons behind 2D occluders and their conservative rasterization into H (seed 004 §4.4).
//
// An occluder here is a straight, axis-aligned run of voxels A..B (inclusive), each opaque or occluded.
// Following §4.4, the occlusion polygon takes its vertices at voxel *centres* and its apex at the centre
// C of the camera's voxel, and voxels are sampled at their centres. With voxel indices as centre
// coordinates all of this is integer arithmetic, so the test is exact: no rounding can err either way.
//
// A voxel q is marked occluded iff its centre lies *strictly* inside the region
//     beyond the line AB (away from C)  and  strictly between the rays C->A and C->B.
// Why this is hidden from every point of the camera's voxel (DESIGN.md, "H is from-region"):
// take any camera point c = C + e1 and target point q' = q + e2 with e1, e2 in [-1/2, 1/2]^2. The centre
// segment C->q crosses AB at x strictly between A and B at some parameter s. The real segment c->q' is at
// x + e there, with e = (1-s) e1 + s e2 in [-1/2, 1/2]^2, i.e. inside the union of the run's closed
// voxels (the run is axis-aligned, so that union is AB grown by the unit square). When |e| reaches the
// union's boundary (e1, e2 both at the same face), the real segment is the centre segment shifted by
// half a voxel across the run and so crosses into the union's interior next to x. Either way it meets
// the interior of the occluder's voxels (or touches an occluded voxel, all of whose points are already
// hidden). This is the exact shrink of the from-region umbra by the voxel support (|nx|+|ny|) d/2,
// hence strict inequalities: centres on an edge count as not occluded.
#pragma once

#include "rgvc/grid/Math.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <vector>

namespace rgvc {

/// [Voxels] largest grid extent per axis the exact integer evaluation supports: coefficients stay below
/// 2^22, constants below 2^45 and every evaluation below 2^47, far inside int64 (so no 128-bit division
/// in the per-ring loop, which profiling showed cost a third of the traversal).
inline constexpr std::int32_t kMaxShadowExtent = 1 << 20;

using WideInt = std::int64_t; // exact for coordinates within kMaxShadowExtent

/// Strict half-plane a*x + b*y + c > 0 over integer voxel-centre coordinates.
struct IntHalfPlane {
    std::int64_t a = 0, b = 0;
    WideInt c = 0;
    WideInt eval(std::int64_t x, std::int64_t y) const { return WideInt(a) * x + WideInt(b) * y + c; }
};

class OcclusionShadow2D {
public:
    /// @param camera  camera voxel C; @param a, b  ends of an axis-aligned run of occluder voxels.
    /// valid() is false when the run is a single voxel or C is on the run's line (no from-region shadow).
    OcclusionShadow2D(const IVec2& camera, const IVec2& a, const IVec2& b) : m_apex(camera) {
        const IVec2 ca = a - camera, cb = b - camera;
        const std::int64_t orient = cross2(ca, cb); // 2 * signed area of triangle C, A, B
        m_valid = a != b && orient != 0;
        if (!m_valid) return;
        m_coneLo = orient > 0 ? ca : cb;
        m_coneHi = orient > 0 ? cb : ca;
        // Strictly on B's side of ray C->A and on A's side of ray C->B.
        m_planes[0] = lineThrough(camera, a);
        if (m_planes[0].eval(b.x, b.y) < 0) flip(m_planes[0]);
        m_planes[1] = lineThrough(camera, b);
        if (m_planes[1].eval(a.x, a.y) < 0) flip(m_planes[1]);
        // Beyond AB: the side of line AB not containing C.
        m_planes[2] = lineThrough(a, b);
        if (m_planes[2].eval(camera.x, camera.y) > 0) flip(m_planes[2]);
        m_planeCount = 3;
        // Past chess distance m = max(|A - C|, |B - C|) every point of the open cone is beyond AB: the
        // ray to it crosses AB (strictly between A and B) inside the chess ball of radius m, which
        // contains the segment AB. From that ring on the shadow is just its cone (see cone()).
        m_coneFrom = std::max(std::max(std::abs(ca.x), std::abs(ca.y)), std::max(std::abs(cb.x), std::abs(cb.y))) + 1;
    }

    /// The open cone from `camera` strictly between directions lo and hi (counter-clockwise from lo,
    /// cross(lo, hi) > 0, so narrower than 180 degrees). A cone is a shadow's trace on the rings past
    /// coneFrom(); cones of such shadows may be merged (mergeCones) and stamped with two planes.
    static OcclusionShadow2D cone(const IVec2& camera, const IVec2& lo, const IVec2& hi) {
        OcclusionShadow2D s;
        s.m_apex = camera;
        s.m_valid = cross2(lo, hi) > 0;
        if (!s.m_valid) return s;
        s.m_coneLo = lo;
        s.m_coneHi = hi;
        s.m_planes[0] = lineThrough(camera, camera + lo);
        if (s.m_planes[0].eval(camera.x + hi.x, camera.y + hi.y) < 0) flip(s.m_planes[0]);
        s.m_planes[1] = lineThrough(camera, camera + hi);
        if (s.m_planes[1].eval(camera.x + lo.x, camera.y + lo.y) < 0) flip(s.m_planes[1]);
        s.m_planeCount = 2;
        s.m_coneFrom = 0;
        return s;
    }

    bool valid() const { return m_valid; }
    const IVec2& coneLo() const { return m_coneLo; }
    const IVec2& coneHi() const { return m_coneHi; }
    /// First chess ring on which this shadow equals its open cone.
    std::int32_t coneFrom() const { return m_coneFrom; }

    bool contains(const IVec2& q) const {
        if (!m_valid) return false;
        for (int i = 0; i < m_planeCount; ++i)
            if (!(m_planes[i].eval(q.x, q.y) > 0)) return false;
        return true;
    }

    /// Range [lo, hi] (empty if lo > hi) of t such that the voxel `origin + t * step` is strictly inside,
    /// for t in [tMin, tMax]; `step` is a unit axis vector. Used to rasterize one ring side at a time.
    void spanOnLine(const IVec2& origin, const IVec2& step, std::int64_t tMin, std::int64_t tMax, std::int64_t& lo,
                    std::int64_t& hi) const {
        lo = tMin;
        hi = tMax;
        if (!m_valid) {
            lo = 1;
            hi = 0;
            return;
        }
        for (int i = 0; i < m_planeCount; ++i) {
            const IntHalfPlane& h = m_planes[i];
            // h(origin + t*step) = k*t + r > 0
            const WideInt k = WideInt(h.a) * step.x + WideInt(h.b) * step.y;
            const WideInt r = h.eval(origin.x, origin.y);
            if (k == 0) {
                if (r <= 0) {
                    lo = 1;
                    hi = 0;
                    return;
                }
            } else if (k > 0) {
                // t > -r/k  <=>  t >= floor(-r/k) + 1
                lo = std::int64_t(std::max<WideInt>(lo, std::min<WideInt>(floorDiv(-r, k) + 1, WideInt(hi) + 1)));
            } else {
                // t < -r/k = r/(-k)  <=>  t <= ceil(r/(-k)) - 1
                hi = std::int64_t(std::min<WideInt>(hi, std::max<WideInt>(-floorDiv(-r, -k) - 1, WideInt(lo) - 1)));
            }
            if (lo > hi) return;
        }
    }

private:
    static IntHalfPlane lineThrough(const IVec2& p, const IVec2& q) {
        // Normal (-(q-p).y, (q-p).x); the line is zero at p.
        IntHalfPlane h;
        h.a = -(std::int64_t(q.y) - p.y);
        h.b = std::int64_t(q.x) - p.x;
        h.c = -(WideInt(h.a) * p.x + WideInt(h.b) * p.y);
        return h;
    }
    static void flip(IntHalfPlane& h) {
        h.a = -h.a;
        h.b = -h.b;
        h.c = -h.c;
    }
    static WideInt floorDiv(WideInt n, WideInt d) { // d > 0
        WideInt q = n / d;
        if ((n % d != 0) && (n < 0)) --q;
        return q;
    }

    OcclusionShadow2D() = default;

    IntHalfPlane m_planes[3];
    int m_planeCount = 0;
    bool m_valid = false;
    IVec2 m_apex{0}, m_coneLo{0}, m_coneHi{0};
    std::int32_t m_coneFrom = 0;
};

/// Direction d lies in the half-open angular interval [lo, hi) (lo counter-clockwise to hi, < 180 deg).
inline bool directionInHalfOpenCone(const IVec2& d, const IVec2& lo, const IVec2& hi) {
    const std::int64_t c = cross2(lo, d);
    if (c == 0) return std::int64_t(lo.x) * d.x + std::int64_t(lo.y) * d.y > 0; // along lo itself
    return c > 0 && cross2(d, hi) > 0;
}

/// Adds the open cone (lo, hi) to a set of open cones, merging it with every cone it overlaps as long as
/// the union stays narrower than 180 degrees. The union of two *overlapping* open angular intervals is
/// the open interval from the first start to the last end, and each of its directions lies in one of the
/// two, so a merged cone hides only what its parts hide. Cones that merely touch (share a boundary ray)
/// are not merged: voxel centres on that ray lie in neither open cone.
inline bool sameDirection(const IVec2& a, const IVec2& b) {
    return cross2(a, b) == 0 && std::int64_t(a.x) * b.x + std::int64_t(a.y) * b.y > 0;
}

inline void mergeCone(std::vector<OcclusionShadow2D>& cones, const IVec2& apex, IVec2 lo, IVec2 hi) {
    for (bool merged = true; merged;) {
        merged = false;
        for (std::size_t i = 0; i < cones.size(); ++i) {
            const IVec2 lo2 = cones[i].coneLo(), hi2 = cones[i].coneHi();
            IVec2 first, last;
            if (directionInHalfOpenCone(lo2, lo, hi)) {
                first = lo;
                last = directionInHalfOpenCone(hi2, lo, hi) || sameDirection(hi2, hi) ? hi : hi2;
            } else if (directionInHalfOpenCone(lo, lo2, hi2)) {
                first = lo2;
                last = directionInHalfOpenCone(hi, lo2, hi2) || sameDirection(hi, hi2) ? hi2 : hi;
            } else {
                continue;
            }
            if (cross2(first, last) <= 0) continue; // the union would reach 180 degrees
            lo = first;
            hi = last;
            cones[i] = cones.back();
            cones.pop_back();
            merged = true;
            break;
        }
    }
    cones.push_back(OcclusionShadow2D::cone(apex, lo, hi));
}

} // namespace rgvc
