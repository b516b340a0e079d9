// Scene files: the JSON format of /work/shared/scene-format.md, read into rgvc types.
//
//   rgvc::Scene scene = rgvc::loadScene("scenes/small-2d.json");   // throws rgvc::SceneError
//   if (const auto* s = scene.as<2>()) { rgvc::Culler2D culler(s->grid); ... }
//
// Everything the contract calls bad input is rejected here, before any culling starts, so that a
// command can refuse a file without printing a partial answer. Every error is one SceneError whose
// what() is a single line "<file>: <field path>: <what is wrong>", the field path written the way a
// user finds it in the file ("objects[3].radius", "camera_path[12].direction"; array indices count
// from 0 in file order, not by object id).
//
// Defaults (the contract's): velocity zero; max_speed = |velocity|; static = velocity zero and no
// max_speed given; camera aspect 1, up (0, 1, 0), far none. Fields the contract does not name are
// ignored (the format may grow), and so are the 3D-only camera fields `up` and `aspect` in 2D scenes.
//
// Stricter than the contract, because the culler's guarantee depends on it: `max_speed` must be at
// least |velocity| (a hidden object's TBV is sized from max_speed, and the simulated motion moves
// |velocity| per frame), and an object marked `"static": true` must have zero velocity.
#pragma once

#include "rgvc/dynamics/Culler.hpp"
#include "rgvc/grid/Camera.hpp"
#include "rgvc/grid/GridGeometry.hpp"
#include "rgvc/grid/Shapes.hpp"

#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

namespace rgvc {

/// A rejected scene file. what() = "<file>: <field>: <problem>", one line (no '\n' anywhere).
class SceneError : public std::runtime_error {
public:
    SceneError(std::string file, std::string field, std::string problem);

    const std::string& file() const noexcept { return m_file; }
    /// Field path ("objects[3].radius"), or a pseudo-field where the file has none: "file" (cannot be
    /// read), "line L, column C" (not JSON), "--frames" (a command-line value checked against the scene).
    const std::string& field() const noexcept { return m_field; }
    const std::string& problem() const noexcept { return m_problem; }

private:
    std::string m_file, m_field, m_problem;
};

/// What a `"shape": "mesh"` object was read from (3D only). The culler gets the placed mesh as a MeshSolid
/// (grid/MeshSolid.hpp: its hull as the outer model, a closed mesh's solid voxelization as the occluder; see
/// SceneMesh.cpp for why that is conservative); this keeps what the file said.
struct SceneMeshInfo {
    std::string file;          ///< the path as resolved against the scene file's directory
    std::size_t triangles = 0; ///< after dropping triangles that repeat a vertex index
    std::size_t vertices = 0;
    bool closed = false;       ///< analyzeMeshTopology(welded mesh).closed(): a solid; else a surface
    /// `role` as the file gave it (the object's `role` is that for a closed mesh, Occludee for an open one).
    ObjectRole requestedRole = ObjectRole::Both;
};

/// One object of a scene, as the file gives it.
template <int D> struct SceneObject {
    ObjectId id = 0;         ///< Unique within the scene, >= 0.
    Shape<D> shape;          ///< [World units] frame-0 placement, validated (polygons counter-clockwise).
    Vec<D> velocity{0.0};    ///< [World units per frame] initial velocity; finite.
    double maxSpeed = 0;     ///< [World units per frame] >= |velocity|.
    bool isStatic = true;    ///< Never moves; implies velocity == 0.
    ObjectRole role = ObjectRole::Both; ///< `role`: "both" (default), "occludee", "occluder".
    /// [World units] `occluder_inset` (an rgvc addition to the format, default 0): ObjectDesc::occluderInset.
    double occluderInset = 0;
    /// Set for `"shape": "mesh"`: `shape` is then the placed mesh (MeshSolid), and `role` Occludee when
    /// the mesh is open.
    std::optional<SceneMeshInfo> mesh;

    /// The object as the culler wants it at frame 0.
    ObjectDesc<D> desc() const { return {id, shape, isStatic, maxSpeed, occluderInset, role}; }
};

/// One entry of `camera_path`: the fields that change per frame.
template <int D> struct SceneCameraPose {
    Vec<D> position{0.0};  ///< [World units] finite.
    Vec<D> direction{0.0}; ///< Finite, non-zero (and, in 3D, not parallel to camera.up).
};

/// The contents of a scene file of dimension D.
template <int D> struct SceneData {
    GridGeometry<D> grid;
    /// Validated. In 3D `up` is always set (the default (0, 1, 0) when the file omits it).
    Camera<D> camera;
    /// Present when the file has `camera_path` (possibly empty): frame t uses entry t.
    std::optional<std::vector<SceneCameraPose<D>>> cameraPath;
    std::vector<SceneObject<D>> objects; ///< In file order.

    /// Number of frames the scene can drive: camera_path's length, or unlimited (SIZE_MAX) without one.
    std::size_t frameLimit() const;
    /// The camera of frame t: `camera` with position and direction from camera_path[t] when there is a
    /// path. Requires t < frameLimit().
    Camera<D> cameraAt(std::size_t frame) const;
};

using SceneData2 = SceneData<2>;
using SceneData3 = SceneData<3>;

/// A loaded scene of either dimension.
struct Scene {
    std::string name;  ///< The file name used in error messages.
    int dimensions = 2;
    std::variant<SceneData2, SceneData3> data;

    /// The scene's data when it has dimension D, else nullptr.
    template <int D> const SceneData<D>* as() const { return std::get_if<SceneData<D>>(&data); }
    template <int D> SceneData<D>* as() { return std::get_if<SceneData<D>>(&data); }
};

/// Reads and validates a scene file.
/// @param path  file name; also the <file> part of error messages, as given. Mesh `file`s are
///              resolved against its directory.
/// @throws SceneError on any bad input (see the header comment); never anything else except bad_alloc.
Scene loadScene(const std::string& path);

/// Validates a scene given as JSON text.
/// @param jsonText       the whole document (UTF-8).
/// @param nameForErrors  the <file> part of error messages; mesh `file`s are resolved against its directory
///                       (the current directory when it has none).
/// @throws SceneError as loadScene.
Scene parseScene(const std::string& jsonText, const std::string& nameForErrors);

/// Checks that the scene can drive `frames` frames (its camera_path, when present, is long enough).
/// @throws SceneError with field "camera_path".
void requireFrames(const Scene& scene, std::size_t frames);

} // namespace rgvc
