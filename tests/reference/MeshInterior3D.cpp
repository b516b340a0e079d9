// Where a line from the camera runs inside a closed mesh's solid (the 3D reference's mesh blocker; see
// SegmentClip3D.hpp's meshInterior and ExactVisibility3D.hpp).
//
// The solid is the set of points of non-zero winding number (TriangleMesh.hpp), its interior what the
// contract's segments must miss. Along the line t*u the winding number of the point at t is the signed
// number of triangles the line crosses beyond t, so it is constant between consecutive crossings and the
// interior intervals are the gaps between crossings where the running count is non-zero.
//
// Counting crossings exactly. A line through a vertex or along an edge meets several triangles at one
// point; counted naively it may count that crossing twice or not at all. The test is the one
// grid/src/MeshVoxelize.cpp uses for the culler's own rows, in the plane perpendicular to u: every vertex
// is projected once (so the triangles sharing an edge see bit-identical coordinates), the edge function of
// a -> b is evaluated with the lower vertex index first and negated for the other direction (exactly
// opposite values in the two triangles of an edge: Woop, Benthin, Wald, JCGT 2013), and an exact zero is
// broken by a symbolic perturbation of the line (simulation of simplicity), itself antisymmetric. So a
// closed mesh is crossed a consistent number of times, and the signs sum to zero; when they do not (an
// open mesh, or a mesh whose orientation is inconsistent) the line gets no interior: the mesh blocks
// nothing along it, which can only report more objects visible.
//
// The depth of a crossing is interpolated barycentrically (rounding ~1e-16 of the coordinates, far below
// the eta the caller shrinks each interval by: the reference's eps, 1e-12 of the scene's magnitude). An
// interval shorter than 2 eta (a line grazing an edge of the solid) blocks nothing.
#include "SegmentClip3D.hpp"

#include <algorithm>

namespace rgvc::reference::detail {

namespace {

struct Crossing {
    double t;
    int sign;
};

/// Edge function of the projected a -> b at the origin, lower index first, with the symbolic tie-break
/// of the origin perturbed to (e, e^2): w(p) = (b - a) x (p - a), dw/dpx = -(b.y - a.y), dw/dpy = b.x - a.x.
int edgeSign(const Vec2& pa, std::uint32_t ia, const Vec2& pb, std::uint32_t ib, double& raw) {
    const bool swap = ia > ib;
    const Vec2& a = swap ? pb : pa;
    const Vec2& b = swap ? pa : pb;
    double w = (b.x - a.x) * (0 - a.y) - (b.y - a.y) * (0 - a.x);
    raw = swap ? -w : w;
    if (w == 0) w = -(b.y - a.y);
    if (w == 0) w = b.x - a.x;
    const int s = w > 0 ? 1 : (w < 0 ? -1 : 0);
    return swap ? -s : s;
}

} // namespace

Interval meshInterior(const Obj& o, const Vec3& u, double eta) {
    if (!o.isMesh || !o.meshClosed) return {};
    const Vec3 e1 = normalized(glm::cross(u, std::abs(u.x) < 0.6 ? Vec3{1.0, 0.0, 0.0} : Vec3{0.0, 1.0, 0.0}));
    const Vec3 e2 = glm::cross(u, e1);
    // Scratch per thread: the reference is called from one thread per test, and reused across rays.
    thread_local std::vector<Vec2> proj;
    thread_local std::vector<double> depth;
    thread_local std::vector<Crossing> cross;
    proj.resize(o.meshVerts.size());
    depth.resize(o.meshVerts.size());
    for (std::size_t i = 0; i < o.meshVerts.size(); ++i) {
        const Vec3& v = o.meshVerts[i];
        proj[i] = Vec2(glm::dot(v, e1), glm::dot(v, e2));
        depth[i] = glm::dot(v, u);
    }
    cross.clear();
    for (const auto& t : o.meshTris) {
        double r0, r1, r2;
        const int s0 = edgeSign(proj[t[1]], t[1], proj[t[2]], t[2], r0); // opposite vertex t[0]
        const int s1 = edgeSign(proj[t[2]], t[2], proj[t[0]], t[0], r1);
        const int s2 = edgeSign(proj[t[0]], t[0], proj[t[1]], t[1], r2);
        if (s0 == 0 || s0 != s1 || s1 != s2) continue;
        const double sum = r0 + r1 + r2;
        const double lo = std::min({depth[t[0]], depth[t[1]], depth[t[2]]});
        const double hi = std::max({depth[t[0]], depth[t[1]], depth[t[2]]});
        double d = sum != 0 ? (r0 * depth[t[0]] + r1 * depth[t[1]] + r2 * depth[t[2]]) / sum : 0.5 * (lo + hi);
        if (!(d >= lo)) d = lo; // also NaN
        if (d > hi) d = hi;
        cross.push_back({d, s0});
    }
    std::sort(cross.begin(), cross.end(), [](const Crossing& a, const Crossing& b) { return a.t < b.t; });
    int total = 0;
    for (const Crossing& c : cross) total += c.sign;
    if (total != 0) return {}; // the crossings do not pair up: no verdict, no block
    int w = 0;
    for (std::size_t k = 0; k + 1 < cross.size(); ++k) {
        w += cross[k].sign;
        if (w == 0) continue;
        const double lo = cross[k].t + eta, hi = cross[k + 1].t - eta;
        if (lo < hi && hi > 0) return {lo, hi};
    }
    return {};
}

} // namespace rgvc::reference::detail
