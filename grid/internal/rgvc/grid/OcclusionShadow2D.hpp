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
//
// Corner rays: one region per extended occluder. The runs of an L (OccluderExtension2D) share their corner
// voxel K, and their shadows are the open cones either side of the ray C->K. Voxel centres exactly on that
// ray past K lie in neither open cone, so without more a closed room seen from its centre leaks along its
// diagonals through the very voxel that closes it. cornerRay() is the missing piece: the open ray
// {C + t (K - C) : t > 1}. It is sound, i.e. every point of the voxel of such a centre q is hidden from
// every point of C's voxel, when
//   (1) K is the end voxel of two runs that continue from it along perpendicular axis steps u and w, so
//       that K, K + u and K + w are all opaque or occluded (runs have at least two voxels), and
//   (2) the runs lie on opposite sides of the ray: cross(d, u) and cross(d, w) are non-zero with opposite
//       signs, d = K - C. (Then d has both components non-zero: cross(d, +-e_x) = -+d_y, cross(d, +-e_y) = +-d_x.)
// Proof. Take c = C + e1 and p = q + e2, e1, e2 in [-1/2, 1/2]^2, and q = C + t d, t > 1. The centre
// segment C->q passes K's centre at s = 1/t in (0, 1); there the real segment c->p is at K + e,
// e = (1-s) e1 + s e2, a point of K's closed voxel. If K is occluded, that point and hence p is hidden
// from c. Otherwise K is opaque, and a component e_i can reach +-1/2 only if e1_i = e2_i = e_i (a
// convex combination with weights in (0, 1) of two numbers in [-1/2, 1/2]):
//   - |e|inf < 1/2: K + e is interior to K;
//   - exactly one |e_i| = 1/2: the real segment's i-th coordinate is the centre segment's plus e_i, so it
//     crosses the face line of K through K + e transversally (its i-th rate is t d_i != 0), with the other
//     coordinate strictly inside K's range: just to one side of K + e it is interior to K;
//   - both |e_i| = 1/2: e1 = e2 = e and the real segment is the centre segment shifted to the corner P = K + e
//     of K, passing through P (s in (0, 1)) in direction d. Near P it runs through the interiors of the two
//     voxels of the four around P that lie in quadrants +-sign(d). K lies in quadrant -sign(e); when
//     sign(d_x d_y) = sign(e_x e_y) that is one of them. Otherwise the two are K + sx e_x and K + sy e_y,
//     (sx, sy) = 2 e, and one of them is K + u or K + w: if neither were, the x-step among u, w would be
//     -sx e_x and the y-step -sy e_y, so cross(d, u) cross(d, w) = (sx d_y)(-sy d_x) = -sx sy d_x d_y > 0
//     (as sign(d_x d_y) != sign(sx sy)), against (2).
// In every case the segment meets the interior of an opaque voxel or touches an occluded one, so it is
// blocked. Both conditions matter. (2) holds with the camera on the L's concave side and on its convex
// side (C - K = alpha u + beta w, alpha and beta of one sign), and fails with the camera beyond one arm's
// line (opposite signs): there the segment shifted to the bad corner passes between two voxels that are
// not in the occluder and only grazes K, so that light is real and the ray must stay open (the two cones
// then lie on one side of it and overlap). Runs that touch only diagonally, at one voxel corner, give no
// corner ray: from the camera voxel's other points the shifted segments pass through the gap voxels (the
// "pinhole" scene of test_culler2d).
// The corner ray closes its two cones into one region. Open cones are therefore kept with their ends open
// or closed (a ray is a cone with lo = hi, both ends closed), and mergeCone() fuses two of them exactly
// when their union is one angular interval: when they overlap, or meet at a ray that one of them contains.
// Merging is then plain set union, and the outer boundaries of a merged shadow stay open: centres on them
// still count as not occluded.
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

/// a and b point the same way (parallel, not opposite).
inline bool sameDirection(const IVec2& a, const IVec2& b) {
    return cross2(a, b) == 0 && std::int64_t(a.x) * b.x + std::int64_t(a.y) * b.y > 0;
}

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

    /// The cone from `camera` between directions lo and hi (counter-clockwise from lo, cross(lo, hi) > 0,
    /// so narrower than 180 degrees), each bounding ray excluded (open) or included (closed); or, for lo
    /// and hi the same direction with both ends closed, the ray from `camera` along lo. (Whether the apex
    /// belongs to it does not matter: it is the camera's voxel, ring 0, which is never stamped.) A cone is a shadow's trace on the rings past coneFrom(); cones of such shadows may be
    /// merged (mergeCone) and stamped with two or three planes.
    static OcclusionShadow2D cone(const IVec2& camera, const IVec2& lo, const IVec2& hi, bool loClosed = false,
                                  bool hiClosed = false) {
        OcclusionShadow2D s;
        s.m_apex = camera;
        s.m_coneLo = lo;
        s.m_coneHi = hi;
        s.m_loClosed = loClosed;
        s.m_hiClosed = hiClosed;
        s.m_coneFrom = 0;
        if (sameDirection(lo, hi)) {
            s.m_valid = loClosed && hiClosed;
            if (s.m_valid) s.setRayPlanes(camera, lo, camera);
            return s;
        }
        s.m_valid = cross2(lo, hi) > 0;
        if (!s.m_valid) return s;
        s.m_planes[0] = lineThrough(camera, camera + lo);
        if (s.m_planes[0].eval(camera.x + hi.x, camera.y + hi.y) < 0) flip(s.m_planes[0]);
        s.m_planes[1] = lineThrough(camera, camera + hi);
        if (s.m_planes[1].eval(camera.x + lo.x, camera.y + lo.y) < 0) flip(s.m_planes[1]);
        // A closed end: h >= 0, which for integer h is h + 1 > 0. The other plane is strictly positive on
        // the ray itself (cross(lo, hi) > 0) and negative on its opposite, so only the ray is added.
        if (loClosed) s.m_planes[0].c += 1;
        if (hiClosed) s.m_planes[1].c += 1;
        s.m_planeCount = 2;
        return s;
    }

    /// The corner ray of two runs that share their end voxel `k`: the open ray {C + t (k - C) : t > 1}
    /// past k. The caller checks the conditions under which it is hidden from the whole camera voxel (see
    /// the comment at the top: perpendicular runs through k on opposite sides of the ray). Past chess
    /// distance |k - C| every point of the ray is past k (the ray's points at distance m have t = m / |k - C|),
    /// so from that ring on it is the closed ray cone(C, d, d, true, true).
    static OcclusionShadow2D cornerRay(const IVec2& camera, const IVec2& k) {
        OcclusionShadow2D s;
        s.m_apex = camera;
        const IVec2 d = k - camera;
        s.m_valid = d != IVec2(0);
        if (!s.m_valid) return s;
        s.m_coneLo = s.m_coneHi = d;
        s.m_loClosed = s.m_hiClosed = true;
        s.setRayPlanes(camera, d, k);
        s.m_coneFrom = std::max(std::abs(d.x), std::abs(d.y)) + 1;
        return s;
    }

    bool valid() const { return m_valid; }
    const IVec2& coneLo() const { return m_coneLo; }
    const IVec2& coneHi() const { return m_coneHi; }
    /// Whether the bounding rays belong to the shadow (only corner rays and cones merged with them).
    bool loClosed() const { return m_loClosed; }
    bool hiClosed() const { return m_hiClosed; }
    /// First chess ring on which this shadow equals its cone.
    std::int32_t coneFrom() const { return m_coneFrom; }

    bool contains(const IVec2& q) const {
        if (!m_valid) return false;
        for (int i = 0; i < m_planeCount; ++i)
            if (!(m_planes[i].eval(q.x, q.y) > 0)) return false;
        return true;
    }

    /// Range [lo, hi] (empty if lo > hi) of t such that the voxel `origin + t * step` is inside (contains()),
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
    /// The points on the line through `camera` along d (two planes: h >= 0 and -h >= 0, i.e. h = 0),
    /// strictly past `from` along d (third plane: d . (q - from) > 0).
    void setRayPlanes(const IVec2& camera, const IVec2& d, const IVec2& from) {
        m_planes[0] = lineThrough(camera, camera + d);
        m_planes[1] = m_planes[0];
        flip(m_planes[1]);
        m_planes[0].c += 1;
        m_planes[1].c += 1;
        m_planes[2].a = d.x;
        m_planes[2].b = d.y;
        m_planes[2].c = -(WideInt(d.x) * from.x + WideInt(d.y) * from.y);
        m_planeCount = 3;
    }

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
    bool m_loClosed = false, m_hiClosed = false;
    IVec2 m_apex{0}, m_coneLo{0}, m_coneHi{0};
    std::int32_t m_coneFrom = 0;
};

/// An angular interval of directions from the apex: from lo counter-clockwise to hi (narrower than 180
/// degrees, or a single direction when lo = hi), each end included or not.
struct AngularInterval {
    IVec2 lo{0}, hi{0};
    bool loClosed = false, hiClosed = false;

    bool degenerate() const { return sameDirection(lo, hi); }
    /// d lies strictly between lo and hi (never, for a single direction).
    bool strictlyInside(const IVec2& d) const { return cross2(lo, d) > 0 && cross2(d, hi) > 0; }
    /// d lies between lo and hi, both ends included whatever the flags.
    bool spans(const IVec2& d) const { return strictlyInside(d) || sameDirection(d, lo) || sameDirection(d, hi); }
};

namespace shadow_detail {
/// If b starts within a, or where a ends with that ray in a or b, the union of a and b is one interval
/// that starts at a.lo: written to `out`, true. b cannot then end within [a.lo, b.lo) either (that would
/// make b at least 360 degrees less a's width, so wider than 180), so the union ends at the later of
/// a.hi and b.hi.
inline bool unionFrom(const AngularInterval& a, const AngularInterval& b, AngularInterval& out) {
    const bool sameStart = sameDirection(b.lo, a.lo);
    const bool connected = a.strictlyInside(b.lo) || sameStart || (sameDirection(b.lo, a.hi) && (a.hiClosed || b.loClosed));
    if (!connected) return false;
    out.lo = a.lo;
    out.loClosed = a.loClosed || (sameStart && b.loClosed);
    if (sameDirection(b.hi, a.hi)) {
        out.hi = a.hi;
        out.hiClosed = a.hiClosed || b.hiClosed;
    } else if (a.spans(b.hi)) {
        out.hi = a.hi;
        out.hiClosed = a.hiClosed;
    } else {
        out.hi = b.hi;
        out.hiClosed = b.hiClosed;
    }
    return true;
}
} // namespace shadow_detail

/// Adds the cone `c` (valid: see OcclusionShadow2D::cone) to a set of cones from `apex`, merging it with
/// every cone whose union with it is one angular interval narrower than 180 degrees: one that overlaps it,
/// or one that meets it at a ray included in either (a corner ray, see the comment at the top). Each
/// direction of the union lies in one of the two, so a merged cone hides exactly what its parts hide:
/// merging is set union, and it never closes a ray that neither part holds. Cones that merely touch at a
/// ray that both leave open are not merged: voxel centres on that ray lie in neither.
inline void mergeCone(std::vector<OcclusionShadow2D>& cones, const IVec2& apex, AngularInterval c) {
    for (bool merged = true; merged;) {
        merged = false;
        for (std::size_t i = 0; i < cones.size(); ++i) {
            const AngularInterval other{cones[i].coneLo(), cones[i].coneHi(), cones[i].loClosed(), cones[i].hiClosed()};
            AngularInterval u;
            if (!shadow_detail::unionFrom(c, other, u) && !shadow_detail::unionFrom(other, c, u)) continue;
            // The union must stay a cone: one direction (two equal rays), or narrower than 180 degrees. A
            // wider union keeps its parts apart (two planes cannot describe it).
            const bool oneRay = c.degenerate() && other.degenerate();
            if (!oneRay && cross2(u.lo, u.hi) <= 0) continue;
            c = u;
            cones[i] = cones.back();
            cones.pop_back();
            merged = true;
            break;
        }
    }
    cones.push_back(OcclusionShadow2D::cone(apex, c.lo, c.hi, c.loClosed, c.hiClosed));
}

} // namespace rgvc
