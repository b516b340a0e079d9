// `"shape": "mesh"` objects (scene-format.md) turned into what the culler takes today: the convex hull
// of the placed mesh, as an occludee. Internal to the scene library (SceneFile.cpp).
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

/// Reads `file` (readMeshFile), places it, and returns the shape the culler gets for it, filling `info`.
/// [Limit] as readMeshFile; the hull is built from at most kMaxHullPoints distinct placed vertices (more:
/// a box around them, see SceneMesh.cpp).
/// @throws MeshFileError for the file; InvalidInput naming `field` if the placed mesh is not usable.
Shape<3> meshOccludeeShape(const std::string& file, const MeshPlacement& placement, const std::string& field,
                           SceneMeshInfo& info);

} // namespace rgvc
