// `"shape": "mesh"` objects (scene-format.md) turned into the culler's mesh shape (MeshSolid: a closed
// mesh occludes through its solid voxelization; see SceneMesh.cpp). Internal to the scene library.
#pragma once

#include "SceneFile.hpp"

#include <array>
#include <string>

namespace rgvc {

/// The object's placement: x -> translation + R(rotation) (scale * x), applied in that order (scale,
/// then rotation, then translation, as a glTF node's TRS).
struct MeshPlacement {
    Vec3 translation{0.0};
    std::array<double, 4> rotation{0, 0, 0, 1}; ///< unit quaternion [x, y, z, w] (normalised by the caller)
    Vec3 scale{1.0, 1.0, 1.0};                  ///< per axis, finite and non-zero
};

/// Reads `file` (readMeshFile), places it (rotation and scale baked into the model) and returns it as a
/// MeshSolid, filling `info`. [Limit] as readMeshFile; the hull is built from at most kMaxHullPoints distinct
/// placed vertices (more, or a flat mesh: a box around them, MeshModel::hull).
/// @throws MeshFileError for the file; InvalidInput naming `field` if the placed mesh is not usable.
Shape<3> sceneMeshShape(const std::string& file, const MeshPlacement& placement, const std::string& field,
                        SceneMeshInfo& info);

} // namespace rgvc
