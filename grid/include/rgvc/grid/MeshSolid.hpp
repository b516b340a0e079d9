// A triangle mesh as a 3D shape (issue #13, scene-format.md's `mesh`): the Shape<3> alternative that lets
// a closed mesh hide what is behind it.
//
// Separate models (seed 004 §5.1's occlusion-preserving principle). An object's inner model O must lie in
// the object (what it hides), its outer model I must contain it (where it may be seen). For a mesh M:
//   outer: the convex hull H of M's vertices (a ConvexPolytope). Every triangle is the hull of three
//          vertices, so it lies in H, and so does the solid a closed surface bounds (a bounded set whose
//          boundary lies in the convex set H lies in H). So M is a subset of H, and every test that asks
//          "where may the object be" (bounds, TBV sizing, the view-region tests, the occlusion images'
//          occludee tests, the GL stage's proxy) takes H: the mesh behaves as a hull object there.
//   I:     the voxels the mesh touches (voxelizeMesh with inner = false: a voxel whose box, grown by the
//          slack, meets a triangle, or, closed, lies in the solid by the centre rule), each row's gaps
//          filled so that I keeps one span per row like the other shapes. A point of the mesh lies on a
//          triangle or in the solid, so its voxel is in I: the reveal and the traversal's "an object is met
//          in the voxels that hold its visible points" hold as for any shape. Tighter than H's voxels where
//          the hull spans a notch or a hole (an L's corner, a courtyard).
//   inner: for a closed mesh, its conservative solid voxelization (voxelizeMesh with inner = true: only
//          voxels entirely inside the solid, several spans per row where the solid is concave). For an
//          open mesh, nothing: a surface has no interior and hides nothing, whatever its role says
//          (MeshSolid::closed() tells; the scene loader gives an open mesh the role occludee and says so).
// These are the only places where the mesh differs from its hull: ConservativeRaster.hpp writes O and I
// from the voxelizations.
//
// Sharing and motion. The mesh (welded, validated, with its topology and hull in model coordinates) is a
// MeshModel held by shared_ptr<const>: copies of a MeshSolid (placements, a culler's records, the scene's
// frame-0 shapes) share one immutable mesh. A MeshSolid places it by x -> scale * x + offset, the only maps
// the library needs: translation (translated(), motion) and the world-to-voxel map (mapped(), toLocal).
// The placed hull is kept next to the map (O(hull) to move), the mesh is mapped only when voxelized (O(vertices)
// into a reused scratch, MeshVoxelization::placed). Rotations and non-uniform scales are baked into the
// model when it is made (the scene loader places the file's mesh first).
//
// No IO here: files are read by the apps' loaders (apps/scene/MeshFile.cpp).
#pragma once

#include "rgvc/grid/ConvexPolytope.hpp"
#include "rgvc/grid/Math.hpp"
#include "rgvc/grid/TriangleMesh.hpp"

#include <memory>
#include <string>

namespace rgvc {

/// An immutable mesh ready to be placed: made by makeMeshModel only (so its invariants hold).
struct MeshModel {
    /// Validated (validateMesh), welded (weldMeshVertices), then without the triangles welding made
    /// degenerate (two equal indices: segments, no area) unless nothing else is left; model units.
    TriangleMesh mesh;
    MeshTopology topology; ///< analyzeMeshTopology(mesh)
    /// Contains every triangle (the dropped degenerate ones too): the convex hull of the referenced vertices, or, when they are flat or more
    /// than kMaxHullPoints, their bounding box grown by 1e-7 of the coordinates' magnitude (as a polytope).
    ConvexPolytope hull;
    bool closed() const { return topology.closed(); }
};

/// Welds, validates and analyses `mesh` and builds its hull. O(n log n + hull points x facets).
/// @param field  the field path for errors, e.g. "objects[3]".
/// @throws InvalidInput naming the field (validateMesh's reasons).
std::shared_ptr<const MeshModel> makeMeshModel(TriangleMesh mesh, const std::string& field);

/// A placed MeshModel: the points scale * x + offset, x in the model's mesh. [Units] world or voxel, as
/// the context says (like the other shapes). See the file comment for what each culling stage takes.
class MeshSolid {
public:
    /// No model: refused by validateShape (exists so that the variant's copies can be assigned).
    MeshSolid() = default;
    /// The model at its own coordinates. @throws InvalidInput(field) when model is null.
    explicit MeshSolid(std::shared_ptr<const MeshModel> model, const std::string& field = "mesh");

    const MeshModel* model() const { return m_model.get(); }
    const std::shared_ptr<const MeshModel>& sharedModel() const { return m_model; }
    bool closed() const { return m_model != nullptr && m_model->closed(); }
    double scale() const { return m_scale; }
    const Vec3& offset() const { return m_offset; }
    /// A model point placed.
    Vec3 place(const Vec3& x) const { return m_scale * x + m_offset; }
    /// The placed hull: the outer model.
    const ConvexPolytope& hull() const { return m_hull; }

    /// Moved by t (the hull with it).
    MeshSolid translated(const Vec3& t) const;
    /// Under x -> (x - origin) * k (the world-to-voxel map; k > 0).
    MeshSolid mapped(const Vec3& origin, double k) const;

private:
    std::shared_ptr<const MeshModel> m_model;
    double m_scale = 1;
    Vec3 m_offset{0.0};
    ConvexPolytope m_hull;
};

/// Throws InvalidInput (field + ".mesh") unless s has a model and a finite, positive map.
void validateMeshSolid(const MeshSolid& s, const std::string& field);

/// voxelizeMesh of the placed mesh (given in voxel units: after mapped()), its positions mapped into
/// out.placed (reused: no allocation once grown). Open meshes: inner is empty. Never throws.
void voxelizeMeshSolid(const MeshSolid& local, const IVec3& resolution, bool inner, double slack, MeshVoxelization& out);

/// The O spans of a placed closed mesh in voxel units, computed into a per-thread scratch that lives as long
/// as the thread (so that moving meshes re-voxelize without allocating); valid until the thread's next call.
/// Rows in increasing linear order, spans ascending and disjoint within a row.
const std::vector<VoxelRowSpan>& meshInnerSpans(const MeshSolid& local, const IVec3& resolution, double slack);
/// The voxels a placed mesh touches (voxelizeMesh with inner = false: those whose box grown by `slack`
/// meets a triangle, and for a closed mesh the solid's voxels too), the same way into a second per-thread
/// scratch. Same order and validity as meshInnerSpans.
const std::vector<VoxelRowSpan>& meshTouchedSpans(const MeshSolid& local, const IVec3& resolution, double slack);

} // namespace rgvc
