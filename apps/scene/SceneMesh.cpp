// Meshes as convex-hull occludees: why this is conservative.
//
// The contract (scene-format.md) calls an object visible when some point p of it lies in the view
// region and the open segment camera-p misses the interior of the union of the *other* objects that
// occlude. Let M be the placed mesh (its triangles; for a closed mesh, the solid they bound) and H the
// convex hull of its vertices. Every triangle is the convex hull of three vertices, so it lies in H,
// and so does the solid a closed surface bounds (a bounded set whose boundary lies in the convex set H
// lies in H). Hence M is a subset of H. The culler gets H with role occludee:
//   * M itself: if p in M is visible, p is a point of H in the view region whose segment misses the
//     other occluders' interiors; those occluders are the same objects in both scenes (M's role does
//     not change what the others are), so H is visible in the culler's scene and the culler, which
//     is conservative for its own shapes, reports it.
//   * Every other object X: in the file's scene M may hide parts of X; in the culler's scene H hides
//     nothing (occludee). Removing an occluder only shrinks the blocked set, so every point of X that
//     is visible in the file's scene is visible in the culler's, and X is reported.
// So the PVS holds every object visible in the file's scene; what is lost is tightness: M is reported
// whenever any part of H may be seen, and M occludes nothing (a role "occluder" in the file becomes
// occludee too: reporting a pure occluder is allowed overestimation). Occlusion by meshes needs the
// core's mesh voxelizer (grid/src/MeshVoxelize.cpp) wired into the culler; it is not yet.
//
// Motion needs nothing new: the hull is a ConvexPolytope and moves as a `hull` object does.
#include "SceneMesh.hpp"

#include "MeshFile.hpp"

#include "rgvc/grid/ConvexPolytope.hpp"
#include "rgvc/grid/Error.hpp"

#include <algorithm>
#include <cmath>

namespace rgvc {

namespace {

// A box containing every point, grown by a relative margin so that it has positive thickness on every
// axis (a flat mesh has a flat hull, which makeConvexHull refuses: it needs an interior). The growth
// only adds overestimation.
Box<3> grownBounds(const std::vector<Vec3>& pts) {
    Box<3> b;
    b.min = pts.front();
    b.max = pts.front();
    double scale = 1.0;
    for (const Vec3& p : pts)
        for (int a = 0; a < 3; ++a) {
            b.min[a] = std::min(b.min[a], p[a]);
            b.max[a] = std::max(b.max[a], p[a]);
            scale = std::max(scale, std::abs(p[a]));
        }
    // 1e-7 of the coordinates' magnitude: far above double rounding (2e-16) at that magnitude, far
    // below a voxel in any sensible scene.
    const double g = 1e-7 * scale;
    for (int a = 0; a < 3; ++a) {
        b.min[a] -= g;
        b.max[a] += g;
    }
    return b;
}

} // namespace

Shape<3> meshOccludeeShape(const std::string& file, const MeshPlacement& placement, const std::string& field,
                           SceneMeshInfo& info) {
    TriangleMesh mesh = readMeshFile(file);
    // Closedness on the welded mesh: file formats split vertices at seams (glTF at every normal crease),
    // which would otherwise make every cube open.
    TriangleMesh welded = mesh;
    weldMeshVertices(welded);
    info.file = file;
    info.triangles = mesh.triangles.size();
    info.vertices = welded.positions.size();
    info.closed = analyzeMeshTopology(welded).closed();

    const std::array<Vec3, 3> r = rotationColumns(placement.rotation);
    std::vector<char> used(welded.positions.size(), 0);
    for (const auto& t : welded.triangles)
        for (std::uint32_t v : t) used[v] = 1;
    std::vector<Vec3> pts;
    pts.reserve(welded.positions.size());
    for (std::size_t i = 0; i < welded.positions.size(); ++i) {
        if (!used[i]) continue; // not part of any triangle: not part of the mesh
        const Vec3& p = welded.positions[i];
        const double x = placement.scale.x * p.x, y = placement.scale.y * p.y, z = placement.scale.z * p.z;
        const Vec3 q(placement.translation.x + r[0].x * x + r[1].x * y + r[2].x * z,
                     placement.translation.y + r[0].y * x + r[1].y * y + r[2].y * z,
                     placement.translation.z + r[0].z * x + r[1].z * y + r[2].z * z);
        if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z))
            throw InvalidInput(field, "the placed mesh has a vertex that overflows double precision");
        pts.push_back(q);
    }
    // Distinct points only (welding merged equal file positions; placement can merge more).
    std::sort(pts.begin(), pts.end(), [](const Vec3& a, const Vec3& b) {
        return a.x != b.x ? a.x < b.x : a.y != b.y ? a.y < b.y : a.z < b.z;
    });
    pts.erase(std::unique(pts.begin(), pts.end(), [](const Vec3& a, const Vec3& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }),
              pts.end());
    if (pts.size() >= 4 && pts.size() <= kMaxHullPoints) {
        try {
            return makeConvexHull(pts, field);
        } catch (const InvalidInput&) {
            // Flat (or nearly flat) point set: no interior for a polytope. The grown box below contains
            // the points all the same.
        }
    }
    // Fewer than 4 points (one flat triangle), a flat mesh, or more than makeConvexHull takes: the
    // bounding box, which contains the hull.
    return grownBounds(pts);
}

} // namespace rgvc
