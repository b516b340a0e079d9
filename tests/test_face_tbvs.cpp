// TBVs that reach past the grid's faces (CullerOptions::objectsStayInGrid, revealFaceTbvs in
// dynamics/src/TbvPolicy.cpp): hand-made 2D and 3D scenes against the exact references, zero misses, and the
// tests' budgets (a closed room's faces, an opaque floor, renewals near a face). The random scenes whose
// objects wander out of the grid are test_dynamic_scenes' (its worlds and sessions).
#include "CullerTestSupport.hpp"

#include "rgvc/dynamics/Culler.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>
#include <vector>

using namespace rgvc;
namespace sr = rgvc::reference::seeded;
using rgvc::culler_test::contains;
using rgvc::culler_test::randomUnit;
using rgvc::culler_test::referenceVisible;

TEST_CASE("dynamic: TBVs reach past the grid's bounds; without objectsStayInGrid the parts beyond are tested", "[dynamics][tbv]") {
    // A slow object hidden 1.5 voxels from the grid's left side, behind a wall across the grid. Its TBV
    // reaches past the bounds with or without the promise (before, without it, the TBV had to fit inside
    // the grid: 25 renewals or more in these 400 frames). Without it each frame tests the slabs beyond the
    // faces the TBV reaches past, which the wall hides whole: no test of the TBV's own parts.
    const GridGeometry2 grid({0, 0}, 1.0, {64, 64});
    const Camera2 cam{.position = {32.5, 5.5}, .direction = {0, 1}, .fovDeg = 90};
    struct Run {
        std::uint64_t renewed = 0, violations = 0, hiddenFrames = 0;
        std::uint32_t maxFaceTests = 0;
    };
    // drift: voxels per frame towards -x (0: the object stays put; it leaves the grid otherwise).
    auto run = [&](bool promise, double drift) {
        CullerOptions o;
        o.objectsStayInGrid = promise;
        Culler2D c(grid, o);
        c.addObject({.id = 1, .shape = Box<2>{{0, 20}, {64, 22}}, .isStatic = true});
        c.addObject({.id = 2, .shape = Ball<2>{{1.5, 50}, 0.5}, .maxSpeed = 0.1});
        Run out;
        for (int f = 0; f < 400; ++f) {
            const Shape<2> now = Ball<2>{{1.5 - drift * f, 50}, 0.5};
            const CullResult& r = c.cull(cam, [&](ObjectId) { return now; });
            out.renewed += r.stats.tbvsRenewed;
            out.violations += r.stats.speedViolations;
            out.hiddenFrames += r.stats.hiddenObjects == 1;
            out.maxFaceTests = std::max(out.maxFaceTests, r.stats.faceTbvTests);
            CHECK(r.pvs.size() <= 1); // the wall only: the object stays behind it, in the grid or out of it
        }
        return out;
    };
    const Run free = run(false, 0), promised = run(true, 0);
    std::cout << "[dynamic] object 1.5 voxels from the grid bound, 400 frames: " << free.renewed << " renewals without "
              << "objectsStayInGrid (at most " << free.maxFaceTests << " face tests a frame), " << promised.renewed << " with it\n";
    CHECK(free.renewed <= 2);
    CHECK(promised.renewed <= 2);
    CHECK(free.hiddenFrames >= 390);
    CHECK(promised.hiddenFrames >= 390);
    CHECK(free.violations + promised.violations == 0);
    // Its TBV reaches past the left and the top faces: their slabs, never the TBV's parts.
    CHECK(free.maxFaceTests >= 1);
    CHECK(free.maxFaceTests <= 2);
    CHECK(promised.maxFaceTests == 0);
    // A broken promise (the object drifts out of the grid at its maxSpeed) is reported once the TBV is
    // renewed; without the promise leaving the grid inside the TBV is allowed (it is then placed every frame).
    CHECK(run(true, 0.099).violations >= 1);
    CHECK(run(false, 0.099).violations == 0);
}

// The case the face tests exist for: a slow object hidden behind a wall just inside a face of the grid
// moves out through the face while its TBV is live, and a camera walking along the wall comes to see it
// past the wall's end, through the grid's side. The ray to it leaves the grid before it enters the TBV,
// so no voxel of T lies on it: only the test of the TBV's part beyond the face reveals it (without it, 5 frames miss it in 2D and 24 in 3D).
template <int D> void leavesThroughFace() {
    IVec<D> res(32); // 2D 32 x 64, 3D 32 x 32 x 64: the last axis is the view's
    res[D - 1] = 64;
    const GridGeometry<D> g(Vec<D>(0.0), 1.0, res);
    // The wall spans x 10..32 (up to the face) and the grid's height; the object starts at x = 31.
    Vec<D> wallLo(0.0), wallHi(32.0), start(16.0);
    wallLo[0] = 10, wallLo[D - 1] = 40, wallHi[D - 1] = 41;
    start[0] = 31, start[D - 1] = 50;
    CullerOptions o;
    o.tbvMaxGrowth = 8; // a TBV of ~80 frames, wholly behind the wall or out of view until the camera is far right
    Culler<D> culler(g, o);
    const ObjectDesc<D> wall{1, Box<D>{wallLo, wallHi}, true, 0.0};
    culler.addObject(wall);
    culler.addObject({2, Ball<D>{start, 0.4}, false, 0.1});
    Camera<D> cam;
    cam.direction = Vec<D>(0.0);
    cam.direction[D - 1] = 1;
    cam.fovDeg = 30;
    int misses = 0, seenFrames = 0, hiddenByTbv = 0;
    for (int f = 0; f < 50; ++f) {
        Vec<D> c = start;
        c[0] += std::min(0.099 * f, 2.0); // out through the face (x = 32) by frame 14, then it stays at 33
        const Shape<D> now = Ball<D>{c, 0.4};
        cam.position = Vec<D>(16.0);
        cam.position[0] = std::min(4 + 0.9 * f, 31.5); // walking right, 2 voxels from the wall's near side
        cam.position[D - 1] = 2;
        const CullResult& r = culler.cull(cam, [&](ObjectId id) { return id == 1 ? wall.shape : now; });
        hiddenByTbv += r.stats.hiddenObjects == 1;
        const std::vector<bool> seen = referenceVisible<D>({wall.shape, now}, cam);
        seenFrames += seen[1];
        if (seen[1] && !contains(r.pvs, 2)) ++misses;
    }
    INFO("D = " << D << ": " << hiddenByTbv << " frames hidden by its TBV, seen in " << seenFrames);
    CHECK(hiddenByTbv >= 15); // it was hidden by its TBV for a while (19 frames; 30 and 49 unrevealed) ...
    CHECK(seenFrames >= 10);  // ... and is seen past the face, through the grid's side
    CHECK(misses == 0);
}

TEST_CASE("dynamic: an object hidden by its TBV that leaves through a face is revealed there", "[dynamics][tbv]") {
    leavesThroughFace<2>();
    leavesThroughFace<3>();
}

// A closed room's walls hide every face of the grid: movers just inside the grid's faces (outside the room)
// keep their TBVs reaching past the faces, and each frame tests the 2D faces' slabs only, none of the TBVs.
template <int D> void closedRoomFaceTbvs(std::uint64_t seed) {
    const int n = D == 2 ? 64 : 40;
    const GridGeometry<D> grid(Vec<D>(0.0), 1.0, IVec<D>(n));
    const double lo = 0.375 * n, hi = 0.625 * n; // the room [lo, hi]^D, walls 1 voxel thick on whole voxels
    std::vector<ObjectDesc<D>> objects;
    for (int a = 0; a < D; ++a)
        for (int side = 0; side < 2; ++side) {
            Box<D> wall{Vec<D>(lo), Vec<D>(hi)};
            if (side == 0) wall.max[a] = lo + 1;
            else wall.min[a] = hi - 1;
            objects.push_back({ObjectId(objects.size() + 1), wall, true, 0.0});
        }
    const std::size_t walls = objects.size();
    std::mt19937_64 rng(seed);
    std::vector<Vec<D>> velocity;
    const int movers = 60;
    for (int i = 0; i < movers; ++i) { // within 3 voxels of a random face of the grid
        Vec<D> c;
        for (int a = 0; a < D; ++a) c[a] = sr::uniform(rng, 1, n - 1);
        const int a = sr::uniformInt(rng, 0, D - 1);
        c[a] = sr::chance(rng, 0.5) ? sr::uniform(rng, 0.5, 3) : n - sr::uniform(rng, 0.5, 3);
        objects.push_back({ObjectId(objects.size() + 1), Ball<D>{c, 0.4}, false, 0.15});
        velocity.push_back(randomUnit<D>(rng) * sr::uniform(rng, 0.02, 0.14));
    }
    CullerOptions o; // objectsStayInGrid off: the movers reflect at the faces, but nothing is promised
    Culler<D> culler(grid, o);
    for (const ObjectDesc<D>& d : objects) culler.addObject(d);
    Camera<D> cam;
    cam.position = Vec<D>(0.5 * n + 0.3);
    int misses = 0, late = 0; // late: hidden movers summed over frames 10..59
    std::uint32_t maxFaceTests = 0;
    for (int f = 0; f < 60; ++f) {
        for (std::size_t i = walls; i < objects.size(); ++i) {
            Ball<D>& b = std::get<Ball<D>>(objects[i].shape);
            Vec<D>& v = velocity[i - walls];
            for (int a = 0; a < D; ++a)
                if (b.center[a] + v[a] < 0.5 || b.center[a] + v[a] > n - 0.5) v[a] = -v[a];
            b.center += v;
        }
        const double t = 0.11 * f;
        if constexpr (D == 2) cam.direction = Vec2{std::cos(t), std::sin(t)}, cam.fovDeg = 120;
        else cam.direction = glm::normalize(Vec3{std::cos(t), 0.3 * std::sin(2 * t), std::sin(t)}), cam.fovDeg = 90;
        const CullResult& r = culler.cull(cam, [&](ObjectId id) { return objects[id - 1].shape; });
        std::vector<Shape<D>> shapes;
        for (const ObjectDesc<D>& d : objects) shapes.push_back(d.shape);
        if (f % 5 == 0) {
            const std::vector<bool> seen = referenceVisible<D>(shapes, cam);
            for (std::size_t i = 0; i < objects.size(); ++i)
                if (seen[i] && !contains(r.pvs, objects[i].id)) ++misses;
        }
        for (std::size_t i = walls; i < objects.size(); ++i) CHECK_FALSE(contains(r.pvs, objects[i].id));
        if (f >= 10) {
            late += int(r.stats.hiddenObjects);
            maxFaceTests = std::max(maxFaceTests, r.stats.faceTbvTests);
        }
    }
    INFO("D = " << D << ", seed " << seed);
    CHECK(misses == 0);
    CHECK(late >= 50 * movers * 95 / 100);   // the movers held by their TBVs from frame 10 on (now and then a
                                             // large 2D TBV reaches into the room, is revealed and comes back)
    CHECK(maxFaceTests >= 1);                // some TBVs reach past the faces ...
    CHECK(maxFaceTests <= std::uint32_t(2 * D)); // ... and only the faces' slabs are tested
}

// A ground under the whole grid: movers on it keep TBVs reaching past the floor, and the floor's layer of
// opaque voxels hides what lies beyond it, with no image test (a street's end shows the image's edge of
// the ground, where its pixels are not exact: tested there, each TBV's part was tested every frame).
TEST_CASE("dynamic: an opaque floor hides the TBVs' parts below it without a test", "[dynamics][tbv]") {
    const GridGeometry3 grid(Vec3(0.0), 1.0, {32, 16, 32});
    std::vector<ObjectDesc<3>> objects{{1, Box<3>{{0, 0, 0}, {32, 1, 32}}, true, 0.0}, // the ground
                                       {2, Box<3>{{12, 1, 20}, {20, 6, 21}}, true, 0.0}}; // a wall on it
    std::mt19937_64 rng(41);
    const int movers = 40;
    std::vector<Vec3> velocity;
    for (int i = 0; i < movers; ++i) { // on the ground, 10 voxels or more from the sides
        objects.push_back({ObjectId(objects.size() + 1), Ball<3>{{sr::uniform(rng, 10, 22), 1.5, sr::uniform(rng, 10, 22)}, 0.4}, false, 0.15});
        velocity.push_back(Vec3{sr::uniform(rng, -0.1, 0.1), 0.0, sr::uniform(rng, -0.1, 0.1)});
    }
    Culler3D culler(grid); // objectsStayInGrid off
    for (const ObjectDesc<3>& o : objects) culler.addObject(o);
    int misses = 0;
    std::uint32_t maxFaceTests = 0, hiddenAtEnd = 0;
    for (int f = 0; f < 60; ++f) {
        for (int i = 0; i < movers; ++i) {
            Ball<3>& b = std::get<Ball<3>>(objects[std::size_t(i) + 2].shape);
            for (int a : {0, 2})
                if (b.center[a] + velocity[std::size_t(i)][a] < 10 || b.center[a] + velocity[std::size_t(i)][a] > 22) velocity[std::size_t(i)][a] *= -1;
            b.center += velocity[std::size_t(i)];
        }
        // Near a corner of the grid at eye height, turning: the ground's far edges are in view.
        const double t = 0.1 * f;
        const Camera3 cam = culler_test::makeCamera(Vec3{3.5, 2.5, 3.5}, glm::normalize(Vec3{std::cos(t), -0.35, std::sin(t)}), 90);
        const CullResult& r = culler.cull(cam, [&](ObjectId id) { return objects[id - 1].shape; });
        std::vector<Shape<3>> shapes;
        for (const ObjectDesc<3>& d : objects) shapes.push_back(d.shape);
        if (f % 4 == 0) {
            const std::vector<bool> seen = referenceVisible<3>(shapes, cam);
            for (std::size_t i = 0; i < objects.size(); ++i) misses += seen[i] && !contains(r.pvs, objects[i].id);
        }
        if (f >= 10) maxFaceTests = std::max(maxFaceTests, r.stats.faceTbvTests);
        hiddenAtEnd = r.stats.hiddenObjects;
    }
    CHECK(misses == 0);
    CHECK(hiddenAtEnd > 0);     // some movers were held by TBVs reaching past the floor ...
    CHECK(maxFaceTests == 1);   // ... and the floor cost one test a frame: its layer, not its slab's tiles and TBVs' parts (6 without)
}

TEST_CASE("dynamic: a closed room hides the grid's faces: TBVs past them cost one test per face", "[dynamics][tbv]") {
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
        closedRoomFaceTbvs<2>(seed);
        closedRoomFaceTbvs<3>(seed);
    }
}
