// The simulator's world: the objects of a 2D scene, their motion, spawning and dragging.
//
// Why not SceneSimulator2 (apps/scene/SceneMotion.hpp): it holds a fixed copy of a scene file's objects,
// while the simulator adds objects (a click spawns one) and moves them by hand (a drag). The motion
// itself is the scene format's, through the same reflectStep, so a scene file moves here exactly as
// `rgvc cull` moves it.
#pragma once

#include "SceneFile.hpp"

#include "rgvc/dynamics/Culler.hpp"

#include <cstddef>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

namespace rgvc::sim {

/// One object of the world. Its placement is its frame-0 shape translated (the scene format's motion).
struct SimObject {
    ObjectId id = 0;
    Shape<2> shape0;                ///< [World units] placement at translation zero
    Vec2 translation{0.0};          ///< [World units]
    Vec2 velocity{0.0};             ///< [World units per frame]
    double maxSpeed = 0;            ///< [World units per frame] >= |velocity|
    bool isStatic = true;
    ObjectRole role = ObjectRole::Both;

    Shape<2> shape() const { return translated(shape0, translation); }
    ObjectDesc<2> desc() const { return {id, shape(), isStatic, maxSpeed, 0.0, role}; }
};

/// What a click spawns.
enum class SpawnKind { Circle, Box, Polygon };
const char* toString(SpawnKind k);

class SimWorld {
public:
    /// @throws InvalidInput when an id repeats, a shape is invalid or the camera is invalid.
    SimWorld(std::string name, const GridGeometry2& grid, const Camera2& camera, std::vector<SimObject> objects);
    /// The objects of a loaded 2D scene (its frame-0 camera; a camera_path is not followed).
    static SimWorld fromScene(const std::string& name, const SceneData2& scene);

    const std::string& name() const { return m_name; }
    const GridGeometry2& grid() const { return m_grid; }
    /// [World units] the grid's box, where motion reflects.
    const Box<2>& bounds() const { return m_bounds; }
    const Camera2& startCamera() const { return m_camera; }
    const std::vector<SimObject>& objects() const { return m_objects; }
    std::size_t indexOf(ObjectId id) const { return m_index.at(id); }
    std::size_t frame() const { return m_frame; }

    /// One frame of motion: every moving object steps by its velocity, reflecting at the grid bounds.
    void step();
    /// Adds an object of `kind` centred at `at`, sized in voxels of the grid (a circle of radius 3, a
    /// 6 x 4 box, a pentagon of radius 3), not static and with maxSpeed 0: it moves only when dragged.
    /// @return its index; its id is one more than the largest id so far.
    std::size_t spawn(SpawnKind kind, const Vec2& at);
    /// Sets an object's translation (a drag). Static objects may be dragged too.
    void moveTo(std::size_t index, const Vec2& translation);
    /// The last object (drawn on top) whose shape contains `p`, if any.
    std::optional<std::size_t> pick(const Vec2& p) const;

    /// Whether the motion keeps every moving object inside the grid (CullerOptions::objectsStayInGrid):
    /// the rule of motionStaysInGrid over the current objects.
    bool staysInGrid() const;

private:
    std::string m_name;
    GridGeometry2 m_grid;
    Box<2> m_bounds;
    Camera2 m_camera;
    std::vector<SimObject> m_objects;
    std::unordered_map<ObjectId, std::size_t> m_index;
    std::size_t m_frame = 0;
};

/// Whether the closed shape contains point p [world units].
bool shapeContains(const Shape<2>& s, const Vec2& p);

} // namespace rgvc::sim
