// The scene classes of rgvc_bench_classes (issue #10's benchmark, BenchClasses.cpp): each built here from
// a fixed seed, with its camera path and its motion. Objects are moved by the application (stepWorld):
// per axis, a step that would leave the grid or overlap one of the scene's obstacles (the room's outer
// box, the buildings) flips that velocity component instead, so moving objects never enter an obstacle
// and move at most |velocity| = their maxSpeed per frame.
#pragma once

#include "rgvc/dynamics/Culler.hpp"

#include <functional>
#include <string>
#include <vector>

namespace rgvc::bench {

template <int D> struct World {
    std::string name;
    std::string description;
    GridGeometry<D> grid;
    std::vector<ObjectDesc<D>> objects;   ///< id = index; shape = current placement
    std::vector<Vec<D>> velocity;         ///< per object, zero for still ones; |velocity| = maxSpeed
    std::vector<Box<D>> obstacles;        ///< moving objects bounce off these and off the grid bounds
    std::function<Camera<D>(int)> camera; ///< frame index, warm-up included
    std::function<void(World&)> step;     ///< replaces the default motion (the paper's scene)
    int maxFrames = 0;                    ///< 0: as many as asked
};

/// One frame of motion: the scene's own (`step`), or the default bounce described above.
template <int D> void stepWorld(World<D>& w);

/// The 3D classes. [Limit] object counts >= 0; the rooms' `name` is the scene's label.
World<3> roomScene(const std::string& name, int spheres);
World<3> clustersScene(int count);
World<3> gameScene(int buildings, int spheres);
World<3> largeScene(int perCluster);
World<3> emptyScene(int side);
World<3> city3dScene(int spheres);
World<3> paperScene(int count);
/// The 2D classes.
World<2> city2dScene(int circles);
World<2> random2dScene(int count);
World<2> room2dScene(int circles);
World<2> large2dScene(int perCluster, const char* name = "large2d");

} // namespace rgvc::bench
