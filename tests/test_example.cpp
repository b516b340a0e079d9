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

// --- README dynamic example begins ---
#include <rgvc/rgvc.hpp>

#include <cmath>
#include <cstdio>

// The application owns the motion: walkers circle around their homes, and the placement of one is
// computed only when somebody asks.
struct Walkers {
    int frame = 0;
    rgvc::Shape<2> placement(rgvc::ObjectId id) const {
        const double angle = 0.02 * frame + double(id); // 0.02 rad per frame on a 3-unit circle: 0.06 units/frame
        const rgvc::Vec2 home{8.0 + 12.0 * double(id % 10), 8.0 + 12.0 * double(id / 10)};
        return rgvc::Ball<2>{home + 3.0 * rgvc::Vec2{std::cos(angle), std::sin(angle)}, 1.0};
    }
};

rgvc::CullStats dynamicExample() {
    rgvc::Culler2D culler(rgvc::GridGeometry2({0, 0}, 1.0, {128, 128}));
    culler.addObject({.id = 1000, .shape = rgvc::Box<2>{{25, 2}, {27, 126}}, .isStatic = true}); // a long wall
    Walkers walkers;
    for (rgvc::ObjectId id = 0; id < 100; ++id)
        culler.addObject({.id = id, .shape = walkers.placement(id), .maxSpeed = 0.061});

    rgvc::CullStats stats;
    for (; walkers.frame < 300; ++walkers.frame) {
        const rgvc::Camera2 camera{.position = {2.5 + 0.05 * walkers.frame, 64.5}, .direction = {1, 0}, .fovDeg = 100};
        // Asked for: last frame's PVS, TBVs that expired, TBVs that came into view. Never the others.
        const rgvc::CullResult& r = culler.cull(camera, [&](rgvc::ObjectId id) { return walkers.placement(id); });
        stats = r.stats;
    }
    std::printf("%u objects hidden by TBVs, %u placements asked for in the last frame\n", stats.hiddenObjects,
                stats.placementQueries);
    return stats;
}
// --- README dynamic example ends ---

// --- README views example begins ---
#include <rgvc/rgvc.hpp>

#include <vector>

std::vector<std::vector<rgvc::ObjectId>> viewsExample() {
    rgvc::Culler3D culler(rgvc::GridGeometry3({0, 0, 0}, 1.0, {64, 32, 64}));
    culler.addObject({.id = 1, .shape = rgvc::Box<3>{{0, 0, 30}, {64, 20, 32}}, .isStatic = true}); // a wall
    culler.addObject({.id = 2, .shape = rgvc::Ball<3>{{32, 5, 50}, 2}, .maxSpeed = 0.5});          // behind it
    culler.addObject({.id = 3, .shape = rgvc::Ball<3>{{32, 5, 10}, 2}, .maxSpeed = 0.5});          // in front

    // Split screen: one scene update, both players' views culled in parallel (on a TBB task arena).
    const std::vector<rgvc::Camera3> players = {{.position = {32, 5, 2}, .direction = {0, 0, 1}, .fovDeg = 60},
                                                {.position = {32, 10, 40}, .direction = {0, 0, 1}, .fovDeg = 60}};
    const rgvc::MultiCullResult& r = culler.cullViews(players);
    std::vector<std::vector<rgvc::ObjectId>> pvs;
    for (const rgvc::CullResult& view : r.views) pvs.push_back(view.pvs); // {1, 3} and {2}

    // The same on the engine's own threads: any rgvc::TaskExecutor (here: the calling thread only).
    rgvc::SerialExecutor sameThread;
    const rgvc::MultiCullResult& again = culler.cullViews(players, &sameThread);
    return again.views[0].pvs == pvs[0] && again.views[1].pvs == pvs[1] ? pvs : std::vector<std::vector<rgvc::ObjectId>>{};
}
// --- README views example ends ---

TEST_CASE("the README views example: one wall, two players, the same PVS on every executor", "[example][views]") {
    const std::vector<std::vector<rgvc::ObjectId>> pvs = viewsExample();
    REQUIRE(pvs.size() == 2);
    CHECK(pvs[0] == std::vector<rgvc::ObjectId>{1, 3});
    CHECK(pvs[1] == std::vector<rgvc::ObjectId>{2});
}

TEST_CASE("the README dynamic example keeps the walkers behind the wall in TBVs", "[example][tbv]") {
    const rgvc::CullStats s = dynamicExample();
    CHECK(s.hiddenObjects >= 60);     // 80 walkers live behind the wall
    CHECK(s.placementQueries <= 40);  // far fewer than the 100 walkers
    CHECK(s.speedViolations == 0);
}

TEST_CASE("the README example compiles, runs and hides the ball behind the wall", "[example]") {
    CHECK(cullExample() == 2); // the moved ball is still behind the wall (the ray to it crosses x = 21 below y = 50)
    rgvc::Culler2D culler(rgvc::GridGeometry2({0, 0}, 1.0, {64, 64}));
    culler.addObject({.id = 1, .shape = rgvc::Box<2>{{20, 10}, {22, 50}}, .isStatic = true});
    culler.addObject({.id = 2, .shape = rgvc::Ball<2>{{40, 30}, 3}, .maxSpeed = 0.5});
    const rgvc::CullResult& r = culler.cull({.position = {5.5, 30.25}, .direction = {1, 0}, .fovDeg = 90});
    CHECK(r.pvs == std::vector<rgvc::ObjectId>{1});
}
