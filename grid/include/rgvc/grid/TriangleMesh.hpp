// Triangle meshes as occluders and occludees (issue #13, scene-format.md's `mesh`): the mesh type, its
// validation, the closedness check and its conservative voxelization (MeshVoxelize.cpp).
//
// A *closed* mesh (every edge shared by exactly two triangles that run along it in opposite directions)
// bounds a solid: the points of non-zero winding number, plus the surface. It is discretized like the
// analytic shapes (seed 004 §4.1, §5.1):
//   O (inner):   voxels whose centre has non-zero winding number AND whose box (shrunk by the 1e-9 face
//                snapping the other shapes use, see ConservativeRaster.hpp's innerRange) meets no
//                triangle. The winding number is constant on a connected set the surface does not meet,
//                so such a voxel lies entirely inside the solid.
//   I (touched): voxels whose box grown by the slack meets a triangle, plus the voxels of O's centre
//                rule (a voxel that meets the solid either meets its surface or lies inside it).
// An *open* mesh is a surface: no O at all (it can never hide anything), I = the touched voxels.
//
// No IO here: files are read by the apps' loaders (apps/scene/MeshFile.cpp).
#pragma once

#include "rgvc/grid/Math.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace rgvc {

/// [Limit] the most vertices / triangles a mesh may have (validateMesh refuses more). 16.7M each: the
/// voxelizer's scratch is O(triangles + touched rows), so a 1M-triangle mesh is within reach; above
/// this a hostile file could make it allocate without bound.
inline constexpr std::size_t kMaxMeshVertices = std::size_t(1) << 24;
inline constexpr std::size_t kMaxMeshTriangles = std::size_t(1) << 24;

/// An indexed triangle mesh. [Units] world or voxel, as the context says.
/// Triangles are counter-clockwise seen from outside for a closed mesh (either consistent orientation is
/// accepted: the winding number is then +1 or -1 inside, and the solid is where it is non-zero).
struct TriangleMesh {
    std::vector<Vec3> positions;
    std::vector<std::array<std::uint32_t, 3>> triangles;
};

/// How the mesh's edges pair up (analyzeMeshTopology).
struct MeshTopology {
    std::size_t edges = 0;            ///< distinct undirected edges
    std::size_t boundaryEdges = 0;    ///< used by one triangle
    std::size_t nonManifoldEdges = 0; ///< used by more than two triangles
    std::size_t misorientedEdges = 0; ///< used by two triangles running along it the same way
    /// Closed (watertight and consistently oriented): every edge is used by exactly two triangles, once
    /// in each direction. Meshes where two separate surfaces touch at a vertex are accepted (a vertex is
    /// not required to have a single fan): the winding number is still well defined.
    bool closed() const { return edges > 0 && boundaryEdges == 0 && nonManifoldEdges == 0 && misorientedEdges == 0; }
};

/// Throws InvalidInput naming `field` (+ ".positions", ".indices") unless the mesh is usable: at least one
/// triangle, at most kMaxMeshVertices / kMaxMeshTriangles, finite positions, indices < positions.size(),
/// no triangle repeating a vertex index. Degenerate (zero-area) triangles with distinct indices are allowed.
void validateMesh(const TriangleMesh& mesh, const std::string& field);

/// Edge pairing of a validated mesh. O(triangles log triangles), one allocation of 3 x triangles keys.
/// Edges are matched by vertex index: a mesh whose seams repeat positions under different indices is
/// open here (weld it first, weldMeshVertices).
MeshTopology analyzeMeshTopology(const TriangleMesh& mesh);

/// Merges vertices with bit-identical positions (file formats split vertices at seams for normals or
/// texture coordinates) and rewrites the indices. O(n log n).
void weldMeshVertices(TriangleMesh& mesh);

/// The bounding box of the referenced positions. [Limit] a validated mesh.
void meshBounds(const TriangleMesh& mesh, Vec3& lo, Vec3& hi);

/// One run of voxels x0..x1 of row (y, z). [Voxels]
struct VoxelRowSpan {
    std::int32_t y = 0, z = 0, x0 = 0, x1 = 0;
};

/// The voxelization's output and scratch: reuse one across calls so that nothing is allocated once the
/// vectors have grown (nothing is ever allocated per voxel: memory is O(triangles' rows)).
struct MeshVoxelization {
    std::vector<VoxelRowSpan> spans; ///< the answer, rows in increasing linear order (z, then y), x0 ascending, disjoint, not adjacent
    // Scratch (kept so that a reused object does not reallocate).
    std::vector<VoxelRowSpan> touchedScratch, insideScratch;
    struct Crossing {
        std::int64_t row; ///< z * resolution.y + y
        double x;
        int sign;
    };
    std::vector<Crossing> crossings;
    std::vector<std::int64_t> uncertainRows;
    std::vector<Vec3> placed; ///< voxelizeMeshSolid's mapped positions
};

/// Conservative voxelization of a mesh given in voxel units, clipped to the grid [0, resolution).
/// @param solid   true for a closed mesh (analyzeMeshTopology(...).closed()): inner voxels exist and
///                touched includes the inside; false: a surface (inner is empty).
/// @param inner   true: O (see the file comment); false: I.
/// @param slack   [Voxel units] growth of the shape for I and the face snapping for O, as the other
///                shapes take it (>= kConservativeSlack; the grid's conversionSlack()).
/// Cost: O(sum over triangles of the rows their bounding box covers + crossings log crossings).
/// Triangles are tested against rows of voxels by clipping them to the row's slab (exact, see
/// MeshVoxelize.cpp), not voxel by voxel. Never throws on a validated mesh.
void voxelizeMesh(const TriangleMesh& local, const IVec3& resolution, bool solid, bool inner, double slack,
                  MeshVoxelization& out);

} // namespace rgvc
