// The README's library example, compiled and run as a test so that the documentation cannot rot.
#include <catch2/catch.hpp>

// --- README example begins ---
#include <rgvc/rgvc.hpp>

#include <cstdio>

int cullExample() {
    // A 64 x 64 grid of 1-unit voxels with its corner at the origin.
    rgvc::Culler2D culler(rgvc::GridGeometry2({0, 0}, 1.0, {64, 64}));

    // A static wall, a ball hidden behind it and a ball in front of it.
    culler.addObject({.id = 1, .shape = rgvc::Box<2>{{20, 10}, {22, 50}}, .isStatic = true});
    culler.addObject({.id = 2, .shape = rgvc::Ball<2>{{40, 30}, 3}, .maxSpeed = 0.5});
    culler.addObject({.id = 3, .shape = rgvc::Ball<2>{{10, 30}, 1}, .maxSpeed = 0.5});

    const rgvc::Camera2 camera{.position = {5.5, 30.25}, .direction = {1, 0}, .fovDeg = 90};
    const rgvc::CullResult& result = culler.cull(camera);
    for (rgvc::ObjectId id : result.pvs) std::printf("draw %llu\n", (unsigned long long)id); // 1 and 3
    std::printf("%.3f ms, %llu voxels visited\n", result.stats.cullMs,
                (unsigned long long)result.stats.voxelsVisited);

    // The ball moved: tell the culler, and cull the next frame.
    culler.updateObject(2, rgvc::Ball<2>{{40, 55}, 3});
    return int(culler.cull(camera).pvs.size());
}
// --- README example ends ---

TEST_CASE("the README example compiles, runs and hides the ball behind the wall", "[example]") {
    CHECK(cullExample() == 2); // the moved ball is still behind the wall (the ray to it crosses x = 21 below y = 50)
    rgvc::Culler2D culler(rgvc::GridGeometry2({0, 0}, 1.0, {64, 64}));
    culler.addObject({.id = 1, .shape = rgvc::Box<2>{{20, 10}, {22, 50}}, .isStatic = true});
    culler.addObject({.id = 2, .shape = rgvc::Ball<2>{{40, 30}, 3}, .maxSpeed = 0.5});
    const rgvc::CullResult& r = culler.cull({.position = {5.5, 30.25}, .direction = {1, 0}, .fovDeg = 90});
    CHECK(r.pvs == std::vector<rgvc::ObjectId>{1});
}
