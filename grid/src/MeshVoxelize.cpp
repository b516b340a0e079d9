// Conservative voxelization of triangle meshes (TriangleMesh.hpp), in voxel units.
//
// Touched voxels. A voxel [x, x+1] x [y, y+1] x [z, z+1] meets a triangle iff the triangle clipped to the
// voxel row's slab [y, y+1] x [z, z+1] (a convex polygon) has an x-projection meeting [x, x+1]. So one
// clip per (triangle, row) gives the exact run of voxels the triangle touches on that row; the grown or
// shrunk boxes are the same clip with the slab moved out by g. This is the separating-axis answer of
// Akenine-Moller's triangle/box test (the tests check it against that test), computed per row instead of
// per voxel so that the cost is O(rows of the triangle's bounds), not O(voxels of its bounds), and the
// output is already in spans. Rounding: slab and x extent are widened by 1e-12 of the coordinates'
// magnitude (the clip's relative error is a few ulps).
//
// Inside voxels (closed meshes). The winding number at the voxel centre c = (x+.5, y+.5, z+.5) is the
// signed count of triangles crossing the ray from (-inf, c.y, c.z) to c. Whether the line of a row meets a
// triangle is decided in the yz projection with edge functions that are (1) evaluated with the edge's
// lower vertex index first and negated for the other direction, so the two triangles sharing an edge get
// bit-identical opposite values (watertight: Woop, Benthin, Wald, "Watertight ray/triangle
// intersection", JCGT 2013, §3), and (2) broken at exact zeros by a symbolic perturbation of the line to
// (c.y + e, c.z + e^2) (Edelsbrunner & Mucke's simulation of simplicity): the perturbed term of edge a->b
// is -(b.z - a.z) e + (b.y - a.y) e^2, itself antisymmetric. A line through a vertex or along an edge
// thus counts every crossing once. The crossing's x is clamped to the triangle's x extent inside the
// row's slab, so a badly conditioned x only moves voxels the triangle touches anyway, which O excludes
// and I includes.
#include "rgvc/grid/TriangleMesh.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rgvc {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Clips a convex polygon (n <= 7 points) to coord[axis] >= v (keepAbove) or <= v.
int clipPolygon(const Vec3* in, int n, Vec3* out, int axis, double v, bool keepAbove) {
    int m = 0;
    for (int i = 0; i < n; ++i) {
        const Vec3& p = in[i];
        const Vec3& q = in[(i + 1) % n];
        const double sp = keepAbove ? p[axis] - v : v - p[axis];
        const double sq = keepAbove ? q[axis] - v : v - q[axis];
        if (sp >= 0) out[m++] = p;
        if ((sp > 0 && sq < 0) || (sp < 0 && sq > 0)) {
            Vec3 r = p + (q - p) * (sp / (sp - sq));
            r[axis] = v;
            out[m++] = r;
        }
    }
    return m;
}

/// The triangle's x extent inside the slab [y0, y1] x [z0, z1]; false when they miss.
bool slabExtent(const Vec3 (&tri)[3], double y0, double y1, double z0, double z1, double& xl, double& xr) {
    Vec3 a[8], b[8];
    int n = 3;
    a[0] = tri[0];
    a[1] = tri[1];
    a[2] = tri[2];
    n = clipPolygon(a, n, b, 1, y0, true);
    if (n == 0) return false;
    n = clipPolygon(b, n, a, 1, y1, false);
    if (n == 0) return false;
    n = clipPolygon(a, n, b, 2, z0, true);
    if (n == 0) return false;
    n = clipPolygon(b, n, a, 2, z1, false);
    if (n == 0) return false;
    xl = kInf;
    xr = -kInf;
    for (int i = 0; i < n; ++i) {
        xl = std::min(xl, a[i].x);
        xr = std::max(xr, a[i].x);
    }
    return xl <= xr;
}

/// Index range of voxels [i, i+1] grown by g meeting [a, b], clipped to [0, n). Empty when first > last.
void rangeOf(double a, double b, double g, std::int32_t n, std::int32_t& first, std::int32_t& last) {
    const double f = std::ceil(a - g) - 1, l = std::floor(b + g);
    first = f < 0 ? 0 : (f >= n ? n : std::int32_t(f));
    last = l < 0 ? -1 : (l >= n - 1 ? n - 1 : std::int32_t(l));
    if (!(f == f) || !(l == l)) last = -1;
}

/// Edge function of a -> b at p in the yz projection, with the tie broken by the symbolic perturbation.
/// Evaluated for the lower index first so that both triangles of an edge get exactly opposite signs.
int edgeSign(const Vec3& pa, std::uint32_t ia, const Vec3& pb, std::uint32_t ib, double py, double pz, double& raw) {
    const bool swap = ia > ib;
    const Vec3& a = swap ? pb : pa;
    const Vec3& b = swap ? pa : pb;
    double w = (b.y - a.y) * (pz - a.z) - (b.z - a.z) * (py - a.y);
    raw = swap ? -w : w;
    if (w == 0) w = -(b.z - a.z);
    if (w == 0) w = b.y - a.y;
    const int s = w > 0 ? 1 : (w < 0 ? -1 : 0);
    return swap ? -s : s;
}

bool spanLess(const VoxelRowSpan& a, const VoxelRowSpan& b) {
    if (a.z != b.z) return a.z < b.z;
    if (a.y != b.y) return a.y < b.y;
    return a.x0 < b.x0;
}

/// Sorts and merges overlapping or adjacent spans of the same row, in place.
void normalizeSpans(std::vector<VoxelRowSpan>& s) {
    std::sort(s.begin(), s.end(), spanLess);
    std::size_t m = 0;
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (m > 0 && s[m - 1].y == s[i].y && s[m - 1].z == s[i].z && s[i].x0 <= s[m - 1].x1 + 1) {
            s[m - 1].x1 = std::max(s[m - 1].x1, s[i].x1);
        } else {
            s[m++] = s[i];
        }
    }
    s.resize(m);
}

} // namespace

namespace mesh_detail {

/// voxelizeMesh on positions held apart from the triangles (voxelizeMeshSolid maps them into a scratch).
void voxelizePositions(const std::vector<Vec3>& positions, const std::vector<std::array<std::uint32_t, 3>>& triangles,
                       const IVec3& res, bool solid, bool inner, double slack, MeshVoxelization& out) {
    out.spans.clear();
    out.touchedScratch.clear();
    out.insideScratch.clear();
    out.crossings.clear();
    out.uncertainRows.clear();
    if (inner && !solid) return;
    if (res.x <= 0 || res.y <= 0 || res.z <= 0) return;

    // O excludes voxels whose box shrunk by the face snap meets a triangle; I takes boxes grown by slack.
    const double snap = 2 * kConservativeSlack - slack;
    const double g0 = inner ? -snap : slack;

    Vec3 lo{kInf}, hi{-kInf};
    for (const auto& t : triangles)
        for (std::uint32_t v : t) {
            lo = glm::min(lo, positions[v]);
            hi = glm::max(hi, positions[v]);
        }
    if (triangles.empty()) return;
    const double magnitude = std::max({std::abs(lo.x), std::abs(lo.y), std::abs(lo.z), std::abs(hi.x), std::abs(hi.y),
                                       std::abs(hi.z), 1.0});
    const double g = g0 + 1e-12 * magnitude;

    for (const auto& t : triangles) {
        const Vec3 tri[3] = {positions[t[0]], positions[t[1]], positions[t[2]]};
        const Vec3 tlo = glm::min(glm::min(tri[0], tri[1]), tri[2]);
        const Vec3 thi = glm::max(glm::max(tri[0], tri[1]), tri[2]);
        std::int32_t y0, y1, z0, z1;
        rangeOf(tlo.y, thi.y, std::max(g, 0.0), res.y, y0, y1);
        rangeOf(tlo.z, thi.z, std::max(g, 0.0), res.z, z0, z1);
        // The plane's x as a function of (y, z), for the crossings: n.x x + n.y y + n.z z = n . p0.
        const Vec3 nrm = glm::cross(tri[1] - tri[0], tri[2] - tri[0]);
        for (std::int32_t z = z0; z <= z1; ++z)
            for (std::int32_t y = y0; y <= y1; ++y) {
                double xl, xr;
                if (!slabExtent(tri, y - g, y + 1.0 + g, z - g, z + 1.0 + g, xl, xr)) continue;
                std::int32_t a, b;
                rangeOf(xl, xr, g, res.x, a, b);
                if (a <= b) out.touchedScratch.push_back({y, z, a, b});
                if (!solid) continue;
                const double py = y + 0.5, pz = z + 0.5;
                double r0, r1, r2;
                const int s0 = edgeSign(tri[1], t[1], tri[2], t[2], py, pz, r0);
                const int s1 = edgeSign(tri[2], t[2], tri[0], t[0], py, pz, r1);
                const int s2 = edgeSign(tri[0], t[0], tri[1], t[1], py, pz, r2);
                if (s0 == 0 || s0 != s1 || s1 != s2) continue;
                double x = nrm.x != 0 ? tri[0].x - (nrm.y * (py - tri[0].y) + nrm.z * (pz - tri[0].z)) / nrm.x : xl;
                if (!(x >= xl)) x = xl; // also NaN
                if (x > xr) x = xr;
                out.crossings.push_back({std::int64_t(z) * res.y + y, x, s0});
            }
    }
    normalizeSpans(out.touchedScratch);

    if (solid) {
        std::sort(out.crossings.begin(), out.crossings.end(), [](const auto& a, const auto& b) {
            return a.row != b.row ? a.row < b.row : a.x < b.x;
        });
        std::int32_t bx0, bx1;
        rangeOf(lo.x, hi.x, slack, res.x, bx0, bx1);
        for (std::size_t i = 0; i < out.crossings.size();) {
            const std::int64_t row = out.crossings[i].row;
            const std::int32_t y = std::int32_t(row % res.y), z = std::int32_t(row / res.y);
            std::size_t j = i;
            int w = 0;
            const std::size_t before = out.insideScratch.size();
            for (; j < out.crossings.size() && out.crossings[j].row == row; ++j) {
                w += out.crossings[j].sign;
                if (w == 0 || j + 1 >= out.crossings.size() || out.crossings[j + 1].row != row) continue;
                // Centres i + .5 strictly between the two crossings.
                const double xa = out.crossings[j].x, xb = out.crossings[j + 1].x;
                double f = std::floor(xa - 0.5) + 1, l = std::ceil(xb - 0.5) - 1;
                f = std::max(f, 0.0);
                l = std::min(l, double(res.x - 1));
                if (f <= l) out.insideScratch.push_back({y, z, std::int32_t(f), std::int32_t(l)});
            }
            if (w != 0) {
                // Inconsistent count (cannot happen for a closed mesh in exact arithmetic): no O on this
                // row, and I takes the row's whole extent.
                out.insideScratch.resize(before);
                if (!inner && bx0 <= bx1) out.insideScratch.push_back({y, z, bx0, bx1});
            }
            i = j;
        }
        normalizeSpans(out.insideScratch);
    }

    if (!inner) {
        out.spans = out.touchedScratch;
        out.spans.insert(out.spans.end(), out.insideScratch.begin(), out.insideScratch.end());
        normalizeSpans(out.spans);
        return;
    }
    // O = inside minus touched (shrunk boxes), row by row; both lists are sorted and disjoint.
    std::size_t k = 0;
    const auto& tch = out.touchedScratch;
    for (const VoxelRowSpan& s : out.insideScratch) {
        auto before = [&](const VoxelRowSpan& t) {
            if (t.z != s.z) return t.z < s.z;
            if (t.y != s.y) return t.y < s.y;
            return t.x1 < s.x0;
        };
        while (k < tch.size() && before(tch[k])) ++k;
        std::int32_t x = s.x0;
        std::size_t m = k;
        for (; m < tch.size() && tch[m].y == s.y && tch[m].z == s.z && tch[m].x0 <= s.x1; ++m) {
            if (tch[m].x0 > x) out.spans.push_back({s.y, s.z, x, tch[m].x0 - 1});
            x = std::max(x, tch[m].x1 + 1);
        }
        if (x <= s.x1) out.spans.push_back({s.y, s.z, x, s.x1});
    }
}

} // namespace mesh_detail

void voxelizeMesh(const TriangleMesh& mesh, const IVec3& res, bool solid, bool inner, double slack,
                  MeshVoxelization& out) {
    mesh_detail::voxelizePositions(mesh.positions, mesh.triangles, res, solid, inner, slack, out);
}

} // namespace rgvc
