// Mesh files for scene-format.md's `"shape": "mesh"`: Wavefront OBJ (tinyobjloader, double precision) and
// glTF 2.0 (.gltf / .glb, tinygltf) read into the core's TriangleMesh. The IO lives here, in the scene
// library, so that rgvc::grid stays free of file formats (TriangleMesh.hpp).
//
//   rgvc::TriangleMesh m = rgvc::readMeshFile("scenes/meshes/house.obj");   // throws rgvc::MeshFileError
//
// What is read:
//   OBJ:  every `v` and every face of every group, polygons fan-triangulated by tinyobjloader; materials,
//         normals and texture coordinates are ignored (a missing .mtl is not an error).
//   glTF: every primitive of every mesh instanced by the nodes of the default scene (scene 0 when the
//         file names none), with the nodes' transforms (matrix, or T * R * S) composed from the root
//         down; a file without scenes contributes each mesh once, untransformed. Primitives must be
//         TRIANGLES (mode 4, the default) with a float VEC3 POSITION accessor; indices of any unsigned
//         component type, or none (then every three vertices are a triangle). Images are never decoded.
// Triangles that repeat a vertex index (zero area) are dropped; everything else goes to validateMesh.
#pragma once

#include "rgvc/grid/TriangleMesh.hpp"

#include <cstdint>
#include <stdexcept>
#include <string>

namespace rgvc {

/// [Limit] the largest mesh file read (bytes): 1 GiB, far above what 2^24 triangles need as .glb.
inline constexpr std::uintmax_t kMaxMeshFileBytes = std::uintmax_t(1) << 30;

/// A mesh file that cannot be used. what() is one line saying what is wrong (without the file name:
/// the scene loader puts the scene file, the field and the mesh file's name in front).
class MeshFileError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Reads the triangles of an .obj, .gltf or .glb file (the extension decides, case-insensitively).
/// [Units] the file's own (the scene's transform is applied by the caller).
/// [Limit] kMaxMeshFileBytes; kMaxMeshVertices / kMaxMeshTriangles (validateMesh).
/// @throws MeshFileError: missing or unreadable file, wrong extension, parse errors (truncated files),
///         unsupported primitive modes or accessors, out-of-range indices, NaN/inf positions, no triangles.
TriangleMesh readMeshFile(const std::string& path);

} // namespace rgvc
