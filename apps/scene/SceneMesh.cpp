// Meshes of scene files: the file's mesh placed and made a MeshSolid, and why each role is sound.
//
// The contract (scene-format.md) calls an object visible when some point p of it lies in the view region
// and the open segment camera-p misses the interior of the union of the *other* objects that occlude. Let
// M be the placed mesh (its triangles; for a closed mesh, the solid they bound). The culler gets M as a
// MeshSolid (grid/MeshSolid.hpp), whose outer model is the convex hull H of M's vertices (M lies in H)
// and whose inner model is, for a closed mesh, its conservative solid voxelization (voxels entirely inside
// M's solid):
//   * M itself: if p in M is visible, p is a point of H in the view region whose segment misses the other
//     occluders' interiors, so the culler, conservative for its shapes' outer models, reports it.
//   * Every other object X, behind a closed M with role both or occluder: what the culler takes as M's
//     occluder lies inside M's solid, so it hides only what M hides: every point of X visible in the
//     file's scene is visible in the culler's (a smaller occluder blocks fewer segments).
//   * An open M is a surface: it has no interior, so by the contract it hides nothing whatever its role
//     says; the loader gives it the role occludee (SceneMeshInfo::requestedRole keeps the file's) and the
//     culler's inner model of an open mesh is empty anyway.
// Motion: the placement (rotation, scale) is baked into the model once; a moving mesh is translated
// (MeshSolid::translated), which moves the hull and, when voxelized, the mesh.
#include "SceneMesh.hpp"

#include "MeshFile.hpp"

#include "rgvc/grid/ConvexPolytope.hpp"
#include "rgvc/grid/Error.hpp"
#include "rgvc/grid/MeshSolid.hpp"

#include <cmath>

namespace rgvc {

Shape<3> sceneMeshShape(const std::string& file, const MeshPlacement& placement, const std::string& field, SceneMeshInfo& info) {
    TriangleMesh mesh = readMeshFile(file);
    info.file = file;
    info.triangles = mesh.triangles.size();

    const std::array<Vec3, 3> r = rotationColumns(placement.rotation);
    for (Vec3& p : mesh.positions) {
        const double x = placement.scale.x * p.x, y = placement.scale.y * p.y, z = placement.scale.z * p.z;
        const Vec3 q(placement.translation.x + r[0].x * x + r[1].x * y + r[2].x * z,
                     placement.translation.y + r[0].y * x + r[1].y * y + r[2].y * z,
                     placement.translation.z + r[0].z * x + r[1].z * y + r[2].z * z);
        if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z))
            throw InvalidInput(field, "the placed mesh has a vertex that overflows double precision");
        p = q;
    }
    // Welded inside (file formats split vertices at seams, glTF at every normal crease, which would
    // otherwise make every cube open), analysed, its hull built.
    std::shared_ptr<const MeshModel> model = makeMeshModel(std::move(mesh), field);
    info.vertices = model->mesh.positions.size();
    info.closed = model->closed();
    return MeshSolid(std::move(model), field);
}

} // namespace rgvc
