// The README's library example, compiled and run as a test so that the documentation cannot rot.
#include <catch2/catch.hpp>

#include <algorithm>

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

// --- README game example begins ---
#include <rgvc/rgvc.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

// A small 3D game loop: a street of buildings (boxes, a turned tower as an oriented box, a rock as a
// convex hull, an L-shaped hall as a closed triangle mesh) that hide what is behind them, a glass shop
// window that hides nothing, 200 movers, and two views per frame (the player, and a security camera)
// culled in one call.

// A closed prism over a polygon outline in the ground plane (x, z), from y = 0 to y = height: a fan from
// outline[0] for the roof and the floor (the outline must be star-shaped from it), two triangles per wall.
// Any consistent winding is a solid for rgvc (the winding number is +1 or -1 inside).
rgvc::TriangleMesh prism(const std::vector<rgvc::Vec2>& outline, double height) {
    rgvc::TriangleMesh m;
    const auto n = std::uint32_t(outline.size());
    for (const rgvc::Vec2& p : outline) m.positions.push_back({p.x, 0, p.y});      // floor: 0 .. n-1
    for (const rgvc::Vec2& p : outline) m.positions.push_back({p.x, height, p.y}); // roof: n .. 2n-1
    for (std::uint32_t i = 1; i + 1 < n; ++i) {
        m.triangles.push_back({n, n + i, n + i + 1}); // roof
        m.triangles.push_back({0, i + 1, i});         // floor, the other way round
    }
    for (std::uint32_t i = 0; i < n; ++i) {
        const std::uint32_t j = (i + 1) % n;
        m.triangles.push_back({i, j, n + j});
        m.triangles.push_back({i, n + j, n + i});
    }
    return m;
}

struct Game {
    rgvc::Culler3D culler{rgvc::GridGeometry3({0, 0, 0}, 1.0, {128, 32, 128})};
    std::vector<rgvc::Vec3> moverAt, moverVelocity;
    const rgvc::MultiCullResult* last = nullptr;
    static constexpr rgvc::ObjectId kFirstMover = 100;

    Game() {
        // Buildings: occluders and occludees (the default role), static.
        for (int i = 0; i < 6; ++i) {
            const double x = 8 + 20 * i;
            culler.addObject({.id = rgvc::ObjectId(1 + i), .shape = rgvc::Box<3>{{x, 0, 40}, {x + 16, 24, 56}}, .isStatic = true});
        }
        const double s = std::sqrt(0.5); // 90 degrees about y, as a quaternion [x, y, z, w]
        culler.addObject({.id = 10, .shape = rgvc::makeOrientedBox({64, 14, 80}, {10, 14, 3}, {0, s * 0.5, 0, std::sqrt(1 - 0.125)}, "tower"),
                          .isStatic = true});
        const std::array<rgvc::Vec3, 5> rock = {{{30, 0, 20}, {36, 0, 21}, {33, 0, 26}, {33, 5, 22}, {31, 1, 23}}};
        culler.addObject({.id = 11, .shape = rgvc::makeConvexHull(rock, "rock"), .isStatic = true});
        // An L-shaped hall as a closed mesh (from a level file, in a game): its solid voxels hide what is
        // behind it, its convex hull is where it may be seen. Its notch hides nothing.
        const std::vector<rgvc::Vec2> hall = {{14, 24}, {26, 24}, {26, 28}, {19, 28}, {19, 34}, {14, 34}};
        culler.addObject({.id = 13, .shape = rgvc::MeshSolid(rgvc::makeMeshModel(prism(hall, 10), "hall")), .isStatic = true});
        // A shop window: reported when seen, never hides what is behind it.
        culler.addObject({.id = 12, .shape = rgvc::Box<3>{{60, 0, 30}, {70, 6, 30.5}}, .isStatic = true,
                          .role = rgvc::ObjectRole::Occludee});
        // Movers on both sides of the street, at most 0.4 units a frame.
        for (int i = 0; i < 200; ++i) {
            const rgvc::Vec3 at{4.0 + (i * 37) % 120, 1.5, i % 2 == 0 ? 10.0 + (i * 13) % 25 : 62.0 + (i * 17) % 60};
            moverAt.push_back(at);
            moverVelocity.push_back({0.3 * std::cos(i), 0, 0.3 * std::sin(i)});
            culler.addObject({.id = kFirstMover + rgvc::ObjectId(i), .shape = rgvc::Ball<3>{at, 1.0}, .maxSpeed = 0.4});
        }
    }

    // One frame: move, tell the culler (updateObject), cull both views, draw what each sees.
    std::size_t frame(int f) {
        for (std::size_t i = 0; i < moverAt.size(); ++i) {
            rgvc::Vec3 next = moverAt[i] + moverVelocity[i];
            for (int a : {0, 2})
                if (next[a] < 2 || next[a] > 126) moverVelocity[i][a] = -moverVelocity[i][a], next = moverAt[i];
            moverAt[i] = next;
            culler.updateObject(kFirstMover + rgvc::ObjectId(i), rgvc::Ball<3>{next, 1.0});
        }
        const std::array<rgvc::Camera3, 2> views = {{
            {.position = {10.0 + 0.2 * f, 1.7, 5}, .direction = {0.3, 0, 1}, .fovDeg = 70, .aspect = 16.0 / 9},
            {.position = {100, 20, 2}, .direction = {-1, -0.6, 1}, .fovDeg = 50},
        }};
        const rgvc::MultiCullResult& r = culler.cullViews(views);
        last = &r;
        std::size_t drawn = 0;
        for (const rgvc::CullResult& view : r.views) drawn += view.pvs.size(); // draw view.pvs here
        return drawn;
    }
};

std::size_t gameExample() {
    Game game;
    std::size_t drawn = 0;
    for (int f = 0; f < 30; ++f) drawn = game.frame(f);
    std::printf("last frame: %zu objects drawn in two views, of %zu\n", drawn, game.culler.objectCount());
    return drawn;
}
// --- README game example ends ---

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

TEST_CASE("the README game example: buildings hide the movers behind them, the glass hides nothing", "[example][game]") {
    Game game;
    for (int f = 0; f < 30; ++f) game.frame(f);
    REQUIRE(game.last != nullptr);
    REQUIRE(game.last->views.size() == 2);
    const std::vector<rgvc::ObjectId>& player = game.last->views[0].pvs;
    auto inPvs = [&](rgvc::ObjectId id) { return std::find(player.begin(), player.end(), id) != player.end(); };
    // Boxes that contain every occluder (the buildings, the tower's and the rock's bounds; not the glass).
    std::vector<rgvc::Box<3>> occluders;
    for (int b = 0; b < 6; ++b) occluders.push_back({{8.0 + 20 * b, 0, 40}, {24.0 + 20 * b, 24, 56}});
    occluders.push_back({{50, 0, 67}, {78, 28, 93}}); // the tower's bounds (half extents 10 x 14 x 3, turned)
    occluders.push_back({{30, 0, 20}, {36, 5, 26}});  // the rock's bounds
    occluders.push_back({{14, 0, 24}, {26, 10, 28}}); // the hall: its L is these two boxes, not its hull
    occluders.push_back({{14, 0, 28}, {19, 10, 34}});
    auto crosses = [](const rgvc::Box<3>& b, const rgvc::Vec3& from, const rgvc::Vec3& to) {
        for (int k = 1; k < 800; ++k) {
            const rgvc::Vec3 p = from + (to - from) * (k / 800.0);
            if (p.x > b.min.x && p.x < b.max.x && p.y > b.min.y && p.y < b.max.y && p.z > b.min.z && p.z < b.max.z) return true;
        }
        return false;
    };
    const rgvc::Vec3 eye{10.0 + 0.2 * 29, 1.7, 5};
    const rgvc::Vec3 d = rgvc::Vec3{0.3, 0, 1} / std::sqrt(1.09);
    std::size_t visible = 0, behind = 0, behindCulled = 0, behindHall = 0, behindHallCulled = 0;
    for (std::size_t i = 0; i < game.moverAt.size(); ++i) {
        const rgvc::Vec3 c = game.moverAt[i];
        const rgvc::ObjectId id = Game::kFirstMover + rgvc::ObjectId(i);
        bool open = true;
        for (const rgvc::Box<3>& b : occluders) open = open && !crosses(b, eye, c);
        const double along = (c - eye).x * d.x + (c - eye).z * d.z;
        const bool wellInView = along > 3 && std::abs((c - eye).x * d.z - (c - eye).z * d.x) < 0.5 * along;
        // Conservative: a mover whose centre the player sees down an open line is in the PVS.
        if (open && wellInView) {
            ++visible;
            CHECK(inPvs(id));
        }
        // Effective: movers whose centre and top lie behind a building, seen from the player, are culled.
        bool hiddenByBuilding = false;
        for (int b = 0; b < 6; ++b)
            hiddenByBuilding = hiddenByBuilding || (crosses(occluders[std::size_t(b)], eye, c) &&
                                                    crosses(occluders[std::size_t(b)], eye, c + rgvc::Vec3{0, 1, 0}));
        if (c.z > 58 && wellInView && hiddenByBuilding) {
            ++behind;
            behindCulled += !inPvs(id);
        }
        // The same for the hall's solid, behind either arm of its L.
        bool hiddenByHall = false;
        for (std::size_t b = occluders.size() - 2; b < occluders.size(); ++b)
            hiddenByHall = hiddenByHall || (crosses(occluders[b], eye, c) && crosses(occluders[b], eye, c + rgvc::Vec3{0, 1, 0}) &&
                                            crosses(occluders[b], eye, c - rgvc::Vec3{0, 1, 0}));
        if (hiddenByHall && (c - eye).z > 0) {
            ++behindHall;
            behindHallCulled += !inPvs(id);
        }
    }
    INFO("visible " << visible << ", behind a building " << behind << ", of them culled " << behindCulled
                    << "; behind the hall " << behindHall << ", culled " << behindHallCulled);
    CHECK(visible > 0);
    CHECK(behind > 10);
    CHECK(behindCulled * 10 >= behind * 8);
    CHECK(inPvs(13)); // the hall, right in front of the player
    CHECK(behindHall >= 3);
    CHECK(behindHallCulled * 10 >= behindHall * 8);
    CHECK(gameExample() > 0);
}
