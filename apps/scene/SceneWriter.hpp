// Scene dumps: a culler's scene (grid, objects with their roles, shapes, insets and motion where known)
// and a camera, written in the scene format (/work/shared/scene-format.md), so that a game can attach a
// frame to a bug report and `rgvc cull FILE` replays it.
//
//   rgvc::writeSceneFile("frame-1234.json", culler, camera);          // throws rgvc::SceneError on IO
//   std::string json = rgvc::sceneToJson(culler, camera, &velocities); // motion, where the game knows it
//
// What is written: every object of Culler::objects() (sorted by id) at the placement the culler knows,
// `static` for objects added static, `max_speed` for the others (their TBVs are sized from it), a
// `velocity` where the caller gives one (oriented boxes and hulls as `hull` of their vertices), `role` and `occluder_inset` when not the defaults; the camera
// in full (3D: `up` as the culler reads it, cameraUp, so that a top view with the default up replays;
// `far` when finite). Numbers are written to round trip exactly (the shortest decimal that reads back as
// the same double), so loading the file and culling the same camera gives the same PVS (test_scene_file).
// Meshes (MeshSolid): writeSceneFile writes each mesh object's placed triangles to
// "<scene name without .json>.mesh-<id>.obj" next to the scene (replaced if it exists) and the object as
// `"shape": "mesh", "file": ...` without a transform; sceneToJson alone cannot (it throws InvalidInput
// naming the object), since the format keeps meshes in files.
// Not written: what the culler learnt over frames (hidden objects' TBVs, hysteresis): a replay starts
// from frame 0 with every object where the dump put it.
#pragma once

#include "SceneFile.hpp"

#include "rgvc/dynamics/Culler.hpp"

#include <string>
#include <unordered_map>
#include <vector>

namespace rgvc {

/// [World units per frame] per object id: the `velocity` to write (objects not in it get none).
template <int D> using SceneVelocities = std::unordered_map<ObjectId, Vec<D>>;

/// The scene file's text for these objects and this camera.
/// @throws InvalidInput on an invalid camera, shape or grid, or a velocity that the format would refuse
///         (on a static object, longer than the object's max_speed, not finite), naming the object; on a
///         mesh object (use writeSceneFile).
template <int D>
std::string sceneToJson(const GridGeometry<D>& grid, const std::vector<ObjectDesc<D>>& objects, const Camera<D>& camera,
                        const SceneVelocities<D>* velocities = nullptr);
/// sceneToJson(culler.grid(), culler.objects(), camera, velocities).
template <int D>
std::string sceneToJson(const Culler<D>& culler, const Camera<D>& camera, const SceneVelocities<D>* velocities = nullptr);
/// Writes sceneToJson(culler, camera, velocities) to `path` (replaced if it exists), and each mesh
/// object's OBJ file next to it (see above).
/// @throws SceneError (field "file") when the file cannot be written; InvalidInput as sceneToJson.
template <int D>
void writeSceneFile(const std::string& path, const Culler<D>& culler, const Camera<D>& camera,
                    const SceneVelocities<D>* velocities = nullptr);

} // namespace rgvc
