// Culler2D against the exact reference: thousands of random scenes and cameras, zero misses allowed.
//
// A miss (an exactly visible object absent from the PVS) is the one thing a conservative culler must
// never do, so every case REQUIREs none; overestimation is allowed and only measured and printed.
// Every failure prints the seed, the camera's index for that seed, the scene as a scene-format JSON file
// (replayable with `rgvc cull`), the missed ids, the point where the reference saw each one and the
// culler's state of the voxel holding that point.
#include "CullerTestSupport.hpp"

#include "rgvc/dynamics/Culler.hpp"
#include "rgvc/grid/OcclusionShadow2D.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <numeric>
#include <random>
#include <sstream>
#include <string>
#include <vector>

using namespace rgvc;
using namespace rgvc::culler_test;
namespace ref = rgvc::reference;

namespace {

// Every frame is checked against the exact reference; the view-region set is counted too (|VFC|).
const CheckOptions kCheck{.suite = "culler2d"};

// Runs `scenes` seeds from `firstSeed`, `camerasPerScene` cameras each (the scene's own, then more drawn
// from the same seed), one culler per scene.
// Both traversals (CullerOptions::hierarchical, unless the options turn it off): the scenes run once
// with the brick tree, once with the chess rings.
Tally runRandomScenes(const std::string& name, std::uint64_t firstSeed, int scenes, int camerasPerScene,
                      const ref::SceneOptions& opt, const CullerOptions& cullerOptionsIn = {}) {
    Tally tally(kCheck);
    for (const bool hierarchical : {true, false}) {
    if (!hierarchical && !cullerOptionsIn.hierarchical) break;
    CullerOptions cullerOptions = cullerOptionsIn;
    cullerOptions.hierarchical = cullerOptionsIn.hierarchical && hierarchical;
    for (std::uint64_t seed = firstSeed; seed < firstSeed + std::uint64_t(scenes); ++seed) {
        ref::Scene2D s = ref::randomScene2D(seed, opt);
        Culler2D culler = makeCuller(s.grid, s.objects, cullerOptions);
        REQUIRE(culler.objectCount() == s.objects.size());
        std::mt19937_64 rng(seed ^ 0x9e3779b97f4a7c15ull);
        for (int c = 0; c < camerasPerScene; ++c) {
            Camera2 cam = c == 0 ? s.camera : ref::randomCamera2D(rng, s.grid, s.objects, s.snapped, opt);
            checkFrame(culler, s.objects, cam, frameLabel(name + (cullerOptions.hierarchical ? "" : " (rings)"), seed, c), tally);
        }
    }
    }
    tally.print(name);
    return tally;
}

// One hand-made scene on a 32 x 32 grid of unit voxels; ids are 1, 2, ... in order.
Tally checkHandScene(const std::string& name, const std::vector<Shape<2>>& shapes, const Camera2& cam) {
    const std::vector<ObjectDesc<2>> objects = staticObjects<2>(shapes);
    Culler2D culler = makeCuller(GridGeometry2({0, 0}, 1.0, {32, 32}), objects);
    Tally tally(kCheck);
    checkFrame(culler, objects, cam, name, tally);
    return tally;
}

} // namespace

TEST_CASE("culler2d: hand-made degenerate scenes", "[culler]") {
    // Each is visible (by the reference) only along one ray or in one small place; see test_reference2d.
    const Shape<2> target = Ball<2>{{20, 16}, 0.5};
    SECTION("pinhole between boxes touching at a corner") {
        std::vector<Shape<2>> s = {Box<2>{{9, 14}, {10, 16}}, Box<2>{{10, 16}, {11, 18}}, target};
        REQUIRE(ref::exactVisible2D(s, makeCamera({4, 16}, {1, 0}, 60))[2]);
        REQUIRE(checkHandScene("pinhole", s, makeCamera({4, 16}, {1, 0}, 60)).misses == 0);
    }
    SECTION("grazing ray along a box face to a tangent circle") {
        std::vector<Shape<2>> s = {Box<2>{{9, 11}, {10, 16}}, Ball<2>{{14, 15}, 1}};
        REQUIRE(ref::exactVisible2D(s, makeCamera({4, 16}, {1, 0}, 60))[1]);
        REQUIRE(checkHandScene("grazing", s, makeCamera({4, 16}, {1, 0}, 60)).misses == 0);
    }
    SECTION("seam between abutting boxes, camera on a voxel corner") {
        std::vector<Shape<2>> s = {Box<2>{{9, 14}, {10, 16}}, Box<2>{{9, 16}, {10, 18}}, target};
        REQUIRE_FALSE(ref::exactVisible2D(s, makeCamera({4, 16}, {1, 0}, 60))[2]); // fused
        REQUIRE(checkHandScene("seam", s, makeCamera({4, 16}, {1, 0}, 60)).misses == 0);
    }
    SECTION("camera inside an object") {
        std::vector<Shape<2>> s = {Box<2>{{10, 10}, {20, 20}}, Ball<2>{{15, 15}, 0.25}, Ball<2>{{25, 15}, 1}};
        REQUIRE(checkHandScene("inside", s, makeCamera({15, 15}, {1, 0}, 90)).misses == 0);
    }
    SECTION("a far limit that cuts a ring's corner off splits the visible arc in two") {
        // Camera voxel (10, 10), wedge [0, 90] degrees, far 30: on chess rings k >= 22 the ring's
        // corner (k, k) lies beyond far, so the ring voxels in the view region form two separate arcs,
        // one on each side of the corner. Both circles are in the view region and unoccluded.
        std::vector<Shape<2>> s = {Ball<2>{{38.5, 15.5}, 0.5}, Ball<2>{{15.5, 38.5}, 0.5}};
        GridGeometry2 big({0, 0}, 1.0, {64, 64});
        Culler2D culler(big);
        culler.addObject({1, s[0], true, 0});
        culler.addObject({2, s[1], true, 0});
        const std::vector<ObjectId> pvs = culler.cull(makeCamera({10.5, 10.5}, {1, 1}, 90, 30)).pvs;
        REQUIRE(ref::exactVisible2D(s, makeCamera({10.5, 10.5}, {1, 1}, 90, 30)) == std::vector<bool>{true, true});
        CHECK(contains(pvs, 1));
        CHECK(contains(pvs, 2));
    }
}

TEST_CASE("culler2d: occluderInset: O and the buffer use the shape shrunk by the inset, I the shape", "[culler]") {
    // A wall 1 voxel thick (box or polygon) hides a circle behind it; inset by more than half its
    // thickness it occludes nothing, and the circle must be reported. The wall stays reported.
    GridGeometry2 grid({0, 0}, 1.0, {64, 64});
    const Camera2 cam = makeCamera({5.5, 32.5}, {1, 0}, 60);
    const Shape<2> walls[] = {Box<2>{{12, 2}, {13, 62}}, ConvexPolygon{{{12, 2}, {13, 2}, {13, 62}, {12, 62}}}};
    for (const Shape<2>& wall : walls)
        for (const auto& [inset, hides] : {std::pair{0.0, true}, std::pair{0.2, true}, std::pair{0.6, false}}) {
            INFO("wall " << wall.index() << ", inset " << inset);
            Culler2D culler(grid);
            culler.addObject({1, wall, true, 0, inset});
            culler.addObject({2, Ball<2>{{24, 32}, 1.5}, true});
            const CullResult& r = culler.cull(cam);
            CHECK(contains(r.pvs, ObjectId(1)));
            CHECK(contains(r.pvs, ObjectId(2)) == !hides);
            CHECK(culler.voxelState({12, 32}).opaque == (inset == 0));
        }
}

TEST_CASE("culler2d: the refinement hides what the walk classified before its occluder was drawn", "[culler]") {
    // A thin box (no voxel wholly inside it: O stays empty there) and a small circle behind it share one
    // brick, the camera looking down -x; the walk reads the brick's ids row by row, x ascending, so it
    // meets the circle first, when the image is still empty, and keeps it. The refinement pass hides it: by default (bufferFromTraversalImage) by testing it again
    // against the walk's finished image, without one the fresh buffer drawn nearest first. Both agree with
    // the exact reference, and without any refinement (occlusionBufferBins = 0) the circle stays, which is
    // what makes this a test of the refinement.
    const GridGeometry2 grid({0, 0}, 1.0, {64, 64});
    const std::vector<ObjectDesc<2>> objects = {{1, Ball<2>{{9, 32.5}, 0.3}, true}, {2, Box<2>{{12.05, 32.05}, {12.95, 38.5}}, true}};
    for (const double fov : {90.0, 60.0, 30.0, 20.0}) { // (at 20 degrees the walk has fewer bins than the buffer: a fresh one)
        const Camera2 cam = makeCamera({20.5, 32.5}, {-1, 0}, fov);
        INFO("fov " << fov);
        for (const auto& [bins, fromWalk, hides] : {std::tuple{256, true, true}, std::tuple{256, false, true}, std::tuple{0, true, false}}) {
            INFO("occlusionBufferBins " << bins << ", bufferFromTraversalImage " << fromWalk);
            Culler2D culler = makeCuller(grid, objects, {.bufferFromTraversalImage = fromWalk, .occlusionBufferBins = bins});
            CHECK_FALSE(culler.voxelState({12, 32}).opaque);
            Tally tally(kCheck);
            checkFrame(culler, objects, cam, "refinement", tally);
            const CullResult& r = culler.cull(cam);
            CHECK(contains(r.pvs, ObjectId(2)));
            CHECK(contains(r.pvs, ObjectId(1)) == !hides);
            if (bins > 0) CHECK(r.stats.bufferHidden == 1);
        }
    }
}

TEST_CASE("culler2d: no misses on mixed random scenes", "[culler]") {
    Tally t = runRandomScenes("mixed", 1, 1500, 3, ref::SceneOptions{});
    REQUIRE(t.frames == 9000);
    REQUIRE(t.misses == 0);
}

TEST_CASE("culler2d: no misses with every coordinate on voxel faces and corners", "[culler]") {
    // Exact degeneracies: object edges on voxel faces, cameras on voxel corners, rays along faces and
    // seams between abutting objects.
    ref::SceneOptions opt;
    opt.snapProbability = 1.0;
    Tally t = runRandomScenes("snapped", 100001, 600, 3, opt);
    REQUIRE(t.misses == 0);
}

TEST_CASE("culler2d: no misses on small crowded grids", "[culler]") {
    ref::SceneOptions opt;
    opt.minResolution = 8;
    opt.maxResolution = 16;
    opt.minObjects = 20;
    opt.maxObjects = 60;
    Tally t = runRandomScenes("small crowded", 200001, 200, 3, opt);
    REQUIRE(t.misses == 0);
}

TEST_CASE("culler2d: no misses with cameras outside the grid and far limits", "[culler]") {
    ref::SceneOptions opt;
    opt.cameraOutsideProbability = 0.5;
    opt.farProbability = 0.6;
    Tally t = runRandomScenes("outside and far", 300001, 200, 3, opt);
    REQUIRE(t.outsideFallbacks > 0);
    REQUIRE(t.misses == 0);
}

TEST_CASE("culler2d: no misses without occluder extension", "[culler]") {
    CullerOptions o;
    o.occluderExtension = false;
    Tally t = runRandomScenes("no occluder extension", 400001, 150, 2, ref::SceneOptions{}, o);
    REQUIRE(t.misses == 0);
}

TEST_CASE("culler2d: updateObject and removeObject keep the PVS conservative", "[culler]") {
    // Objects move (some while hidden), change shape, disappear and appear over several frames; every
    // frame is checked against the reference on the current set of objects.
    Tally tally(kCheck);
    for (std::uint64_t seed = 500001; seed < 500151; ++seed) {
        ref::Scene2D s = ref::randomScene2D(seed);
        std::mt19937_64 rng(seed * 31 + 7);
        Culler2D culler = makeCuller(s.grid, s.objects);
        std::vector<ObjectDesc<2>> objects = s.objects;
        ObjectId nextId = 1000000;
        checkFrame(culler, objects, s.camera, "update, seed " + std::to_string(seed) + ", frame 0", tally);
        for (int frame = 1; frame <= 4; ++frame) {
            const double d = s.grid.voxelSize();
            for (std::size_t i = 0; i < objects.size(); ++i) {
                if (ref::scene_detail::chance(rng, 0.4)) { // move by up to 3 voxels
                    Vec2 t{ref::scene_detail::uniform(rng, -3, 3) * d, ref::scene_detail::uniform(rng, -3, 3) * d};
                    objects[i].shape = translated<2>(objects[i].shape, t);
                    culler.updateObject(objects[i].id, objects[i].shape);
                } else if (ref::scene_detail::chance(rng, 0.05)) { // reshape: take another scene's object
                    ref::Scene2D other = ref::randomScene2D(rng());
                    const Shape<2>& sh = other.objects[rng() % other.objects.size()].shape;
                    Box<2> b = boundsOf<2>(sh), mine = boundsOf<2>(objects[i].shape);
                    objects[i].shape = translated<2>(sh, 0.5 * (mine.min + mine.max - b.min - b.max));
                    culler.updateObject(objects[i].id, objects[i].shape);
                }
            }
            if (objects.size() > 1 && ref::scene_detail::chance(rng, 0.7)) { // remove one
                std::size_t k = rng() % objects.size();
                culler.removeObject(objects[k].id);
                REQUIRE_FALSE(culler.hasObject(objects[k].id));
                objects.erase(objects.begin() + std::ptrdiff_t(k));
            }
            if (ref::scene_detail::chance(rng, 0.5)) { // add one from another scene
                ref::Scene2D other = ref::randomScene2D(rng());
                ObjectDesc<2> o = other.objects.front();
                o.id = nextId++;
                // Moved to a random place of this grid (the other scene's grid lies elsewhere).
                Box<2> b = boundsOf<2>(o.shape);
                Vec2 target = s.grid.toWorld(Vec2{ref::scene_detail::uniform(rng, 0, s.grid.resolution().x),
                                                  ref::scene_detail::uniform(rng, 0, s.grid.resolution().y)});
                o.shape = translated<2>(o.shape, target - 0.5 * (b.min + b.max));
                culler.addObject(o);
                objects.push_back(o);
            }
            REQUIRE(culler.objectCount() == objects.size());
            Camera2 cam = ref::randomCamera2D(rng, s.grid, objects, s.snapped);
            checkFrame(culler, objects, cam, "update, seed " + std::to_string(seed) + ", frame " + std::to_string(frame), tally);
        }
    }
    tally.print("update/remove");
    REQUIRE(tally.frames == 750);
    REQUIRE(tally.misses == 0);
}

TEST_CASE("culler2d: without occlusion the PVS is a superset, and holds the whole view-region set", "[culler]") {
    std::size_t frames = 0, extra = 0;
    for (std::uint64_t seed = 600001; seed < 600301; ++seed) {
        ref::Scene2D s = ref::randomScene2D(seed);
        CullerOptions vfcOnly;
        vfcOnly.occlusion = false;
        Culler2D full(s.grid), vfc(s.grid, vfcOnly);
        for (const ObjectDesc<2>& o : s.objects) {
            full.addObject(o);
            vfc.addObject(o);
        }
        std::mt19937_64 rng(seed);
        for (int c = 0; c < 2; ++c) {
            Camera2 cam = c == 0 ? s.camera : ref::randomCamera2D(rng, s.grid, s.objects, s.snapped);
            const std::vector<ObjectId> withOcclusion = full.cull(cam).pvs;
            const std::vector<ObjectId>& without = vfc.cull(cam).pvs;
            const std::vector<bool> inView = ref::inViewRegion2D(ref::shapesOf(s.objects), cam);
            INFO("seed " << seed << ", camera " << c << "\n" << ref::toJson(s.grid, s.objects, cam));
            REQUIRE(std::includes(without.begin(), without.end(), withOcclusion.begin(), withOcclusion.end()));
            for (std::size_t i = 0; i < s.objects.size(); ++i)
                if (inView[i] && !contains(without, s.objects[i].id)) FAIL_CHECK("id " << s.objects[i].id << " touches the view region but is not in the VFC PVS");
            extra += without.size() - withOcclusion.size();
            ++frames;
        }
    }
    std::cout << "[culler2d] occlusion removed " << extra << " objects over " << frames << " frames\n";
    REQUIRE(frames == 600);
}

TEST_CASE("culler2d: invalid input throws InvalidInput and changes nothing", "[culler]") {
    GridGeometry2 grid({0, 0}, 1.0, {32, 32});
    Culler2D culler(grid);
    culler.addObject({1, Ball<2>{{10, 10}, 2}, true, 0});
    culler.addObject({2, Box<2>{{20, 5}, {22, 25}}, false, 1});
    Camera2 good;
    good.position = {2, 16};
    good.direction = {1, 0};
    good.fovDeg = 90;
    const std::vector<ObjectId> before = culler.cull(good).pvs;
    CHECK(before == std::vector<ObjectId>{1, 2});

    SECTION("cameras") {
        const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
        auto bad = [&](auto mutate) {
            Camera2 c = good;
            mutate(c);
            return c;
        };
        CHECK_THROWS_AS(culler.cull(bad([&](Camera2& c) { c.position.x = nan; })), InvalidInput);
        CHECK_THROWS_AS(culler.cull(bad([&](Camera2& c) { c.position.y = inf; })), InvalidInput);
        CHECK_THROWS_AS(culler.cull(bad([&](Camera2& c) { c.direction = {0, 0}; })), InvalidInput);
        CHECK_THROWS_AS(culler.cull(bad([&](Camera2& c) { c.direction = {nan, 1}; })), InvalidInput);
        CHECK_THROWS_AS(culler.cull(bad([&](Camera2& c) { c.fovDeg = 0; })), InvalidInput);
        CHECK_THROWS_AS(culler.cull(bad([&](Camera2& c) { c.fovDeg = 361; })), InvalidInput);
        CHECK_THROWS_AS(culler.cull(bad([&](Camera2& c) { c.fovDeg = -10; })), InvalidInput);
        CHECK_THROWS_AS(culler.cull(bad([&](Camera2& c) { c.fovDeg = nan; })), InvalidInput);
        CHECK_THROWS_AS(culler.cull(bad([&](Camera2& c) { c.far = 0; })), InvalidInput);
        CHECK_NOTHROW(culler.cull(bad([&](Camera2& c) { c.fovDeg = 360; })));
    }
    SECTION("objects") {
        CHECK_THROWS_AS(culler.addObject({1, Ball<2>{{5, 5}, 1}, true, 0}), InvalidInput); // duplicate id
        CHECK_THROWS_AS(culler.addObject({3, Ball<2>{{5, 5}, 0}, true, 0}), InvalidInput);
        CHECK_THROWS_AS(culler.addObject({3, Ball<2>{{5, 5}, -1}, true, 0}), InvalidInput);
        CHECK_THROWS_AS(culler.addObject({3, Box<2>{{5, 5}, {5, 6}}, true, 0}), InvalidInput);
        CHECK_THROWS_AS(culler.addObject({3, ConvexPolygon{{{0, 0}, {2, 0}, {1, 0.5}, {1, 2}, {0, 2}}}, true, 0}), InvalidInput);
        CHECK_THROWS_AS(culler.addObject({3, Ball<2>{{std::nan(""), 5}, 1}, true, 0}), InvalidInput);
        CHECK_THROWS_AS(culler.addObject({3, Ball<2>{{5, 5}, 1}, false, -1}), InvalidInput);
        CHECK_THROWS_AS(culler.updateObject(99, Ball<2>{{5, 5}, 1}), InvalidInput); // unknown id
        CHECK_THROWS_AS(culler.removeObject(99), InvalidInput);
        CHECK_THROWS_AS(culler.updateObject(1, Ball<2>{{5, 5}, 0}), InvalidInput);
        CHECK_THROWS_AS(culler.updateObject(1, Ball<2>{{5, 5}, -2}), InvalidInput);
        CHECK_FALSE(culler.hasObject(3));
    }
    // Strong guarantee: after the failed calls the culler answers exactly as before.
    CHECK(culler.objectCount() == 2);
    CHECK(culler.hasObject(1));
    CHECK(culler.hasObject(2));
    CHECK(culler.cull(good).pvs == before);
}

namespace {

// Closed rooms ([room] cases). The walls close the room all round with at least one layer of voxels
// that lie wholly inside them (O), so every ray from a camera inside to anything outside crosses an
// opaque voxel's interior: nothing outside is visible, and the culler must report none of it, whatever
// the view. These scenes are where shadows cut into per-run cones once leaked: from a camera voxel on a
// diagonal of a room's corner, the centres on the ray through the corner voxel lay in neither cone.
enum class WallKind { OneBoxPerWall, ThickFractional, UnitBoxes };

const char* toString(WallKind k) {
    switch (k) {
    case WallKind::OneBoxPerWall: return "one box per wall";
    case WallKind::ThickFractional: return "thick, fractional";
    case WallKind::UnitBoxes: return "unit boxes";
    }
    return "?";
}

struct Room2D {
    WallKind kind = WallKind::OneBoxPerWall;
    Vec2 lo{0}, hi{0};     // [voxel units] outer box of the walls
    double thickness = 1;  // [voxels]
    IVec2 innerLo{0}, innerHi{0}; // innermost opaque layer: left and bottom, right and top (voxel indices)
    IVec2 camLo{0}, camHi{0};     // camera voxels: every point of them at least 2 voxels from the walls
    Vec2 interiorLo() const { return lo + thickness; }
    Vec2 interiorHi() const { return hi - thickness; }
};

struct RoomScene {
    GridGeometry2 grid;
    Room2D room;
    std::vector<ObjectDesc<2>> objects;
    std::vector<bool> outside;   // per object: outside the room (must never be reported)
    std::vector<Vec2> velocity;  // [world units per frame] of moving objects
};

bool boxesOverlap(const Box<2>& a, const Box<2>& b) {
    return a.min.x < b.max.x && b.min.x < a.max.x && a.min.y < b.max.y && b.min.y < a.max.y;
}

// Where an object outside the room may be: inside the grid, and clear of the walls' outer box by
// `gap` voxels (so no voxel it touches holds a wall's opaque voxel; it may share a voxel that a
// fractional wall covers in part, which lies behind the opaque layer).
bool placeableOutside(const RoomScene& s, const Shape<2>& shape) {
    const Box<2> w = boundsOf<2>(shape);
    const Box<2> b{s.grid.toLocal(w.min), s.grid.toLocal(w.max)};
    const Vec2 res = Vec2(s.grid.resolution());
    const double gap = 0.05, edge = 0.01;
    if (b.min.x < edge || b.min.y < edge || b.max.x > res.x - edge || b.max.y > res.y - edge) return false;
    return !boxesOverlap(b, Box<2>{s.room.lo - gap, s.room.hi + gap});
}

Shape<2> randomSmallShape(std::mt19937_64& rng, const ref::scene_detail::Placer& pl, Vec2 centre, double size) {
    using namespace ref::scene_detail;
    const double r = uniform01(rng);
    if (r < 1.0 / 3) return Ball<2>{pl.world(centre), pl.length(0.5 * size)};
    if (r < 2.0 / 3) {
        const Vec2 ext{size, size * logUniform(rng, 0.3, 3.0)};
        return makeBox(pl, centre - 0.5 * ext, centre + 0.5 * ext);
    }
    return makePolygon(rng, pl, centre, 0.5 * size, false);
}

// A room of random size and place in a random grid, walls of kind seed % 3, objects outside it (static
// and moving) and a few static ones inside, in the band between the walls and the camera's region.
RoomScene randomRoomScene(std::uint64_t seed) {
    using namespace ref::scene_detail;
    std::mt19937_64 rng(seed);
    RoomScene s;
    const IVec2 res{uniformInt(rng, 64, 256), uniformInt(rng, 64, 256)};
    // Dyadic voxel sizes and origins on voxel multiples keep whole-voxel walls exact in voxel units.
    const double d = pick(rng, std::vector<double>{1.0, 0.5, 2.0, 0.25});
    s.grid = GridGeometry2(Vec2{uniformInt(rng, -50, 50), uniformInt(rng, -50, 50)} * d, d, res);
    const Placer pl{s.grid};

    Room2D& room = s.room;
    room.kind = WallKind(seed % 3);
    const double f = room.kind == WallKind::ThickFractional ? (chance(rng, 0.5) ? 0.3 : uniform(rng, 0.05, 0.95)) : 0.0;
    const int t = room.kind == WallKind::ThickFractional ? uniformInt(rng, 2, 3) : room.kind == WallKind::UnitBoxes ? uniformInt(rng, 1, 2) : 1;
    room.thickness = t;
    IVec2 outer; // [voxels] outer size, fractional walls one more voxel
    for (int a = 0; a < 2; ++a) {
        const int interior = std::min(uniformInt(rng, 6, 60), res[a] - 2 * t - 2);
        outer[a] = interior + 2 * t;
        const int x0 = uniformInt(rng, 0, res[a] - outer[a] - (f > 0 ? 1 : 0));
        room.lo[a] = x0 + f;
        room.hi[a] = x0 + f + outer[a];
        // Opaque voxels i of the wall [lo, lo + t] satisfy lo <= i and i + 1 <= lo + t.
        room.innerLo[a] = int(std::floor(room.lo[a] + t)) - 1;
        room.innerHi[a] = int(std::ceil(room.hi[a] - t));
        room.camLo[a] = int(std::ceil(room.lo[a] + t + 2));
        room.camHi[a] = int(std::floor(room.hi[a] - t - 2)) - 1;
    }

    std::vector<Shape<2>> walls;
    if (room.kind == WallKind::UnitBoxes) {
        const IVec2 a = IVec2(glm::floor(room.lo)), b = IVec2(glm::floor(room.hi));
        for (int i = a.x; i < b.x; ++i)
            for (int j = a.y; j < b.y; ++j)
                if (i < a.x + t || i >= b.x - t || j < a.y + t || j >= b.y - t)
                    walls.push_back(makeBox(pl, Vec2{double(i), double(j)}, Vec2{i + 1.0, j + 1.0}));
    } else {
        // Four boxes: the side walls full height, the others full width (overlapping at the corners) or
        // between them (abutting face to face). Shared faces come from the same numbers. Fractional walls
        // always overlap: abutting inside a voxel, the corner voxels would lie wholly inside neither box,
        // so O (voxels inside one object) would have a hole there, through which the culler must assume
        // light passes, although the walls' union is closed.
        const double x[4] = {room.lo.x, room.lo.x + t, room.hi.x - t, room.hi.x};
        const double y[4] = {room.lo.y, room.lo.y + t, room.hi.y - t, room.hi.y};
        const bool overlap = room.kind == WallKind::ThickFractional || chance(rng, 0.5);
        walls.push_back(makeBox(pl, {x[0], y[0]}, {x[1], y[3]}));
        walls.push_back(makeBox(pl, {x[2], y[0]}, {x[3], y[3]}));
        walls.push_back(makeBox(pl, {overlap ? x[0] : x[1], y[0]}, {overlap ? x[3] : x[2], y[1]}));
        walls.push_back(makeBox(pl, {overlap ? x[0] : x[1], y[2]}, {overlap ? x[3] : x[2], y[3]}));
    }
    ObjectId nextId = 1;
    for (const Shape<2>& w : walls) {
        s.objects.push_back({nextId++, w, true, 0});
        s.outside.push_back(false);
        s.velocity.push_back(Vec2(0));
    }

    const int nOutside = uniformInt(rng, 4, 24);
    for (int tries = 0, placed = 0; placed < nOutside && tries < 2000; ++tries) {
        const Vec2 c{uniform(rng, 0, res.x), uniform(rng, 0, res.y)};
        const Shape<2> shape = randomSmallShape(rng, pl, c, logUniform(rng, 0.1, 8.0));
        if (!placeableOutside(s, shape)) continue;
        const bool moving = chance(rng, 0.5);
        const double speed = moving ? pl.length(uniform(rng, 0.2, 2.0)) : 0.0;
        const double a = uniform(rng, 0, 6.283185307179586);
        s.objects.push_back({ObjectId(1000 + 3 * placed), shape, !moving, speed});
        s.outside.push_back(true);
        s.velocity.push_back(Vec2{std::cos(a), std::sin(a)} * speed * uniform(rng, 0.3, 1.0));
        ++placed;
    }
    // Inside: in the band between the walls and the camera voxels, so that no camera is ever in one.
    const Box<2> interior{room.interiorLo() + 0.05, room.interiorHi() - 0.05};
    const Box<2> cameraRegion{Vec2(room.camLo), Vec2(room.camHi + 1)};
    const int nInside = uniformInt(rng, 0, 3);
    for (int tries = 0, placed = 0; placed < nInside && tries < 500; ++tries) {
        const Vec2 c{uniform(rng, interior.min.x, interior.max.x), uniform(rng, interior.min.y, interior.max.y)};
        const Shape<2> shape = randomSmallShape(rng, pl, c, logUniform(rng, 0.1, 1.5));
        const Box<2> w = boundsOf<2>(shape);
        const Box<2> b{s.grid.toLocal(w.min), s.grid.toLocal(w.max)};
        if (b.min.x < interior.min.x || b.min.y < interior.min.y || b.max.x > interior.max.x || b.max.y > interior.max.y ||
            boxesOverlap(b, cameraRegion))
            continue;
        s.objects.push_back({ObjectId(5000 + placed), shape, true, 0});
        s.outside.push_back(false);
        s.velocity.push_back(Vec2(0));
        ++placed;
    }
    return s;
}

// A camera voxel of the room and a point of it: the voxel's centre, corner, a point on one of its
// edges, or anywhere; any direction; any field of view up to 360 degrees; no far limit.
Camera2 roomCamera(std::mt19937_64& rng, const RoomScene& s, const IVec2& voxel) {
    using namespace ref::scene_detail;
    Vec2 offset;
    const double mode = uniform01(rng);
    if (mode < 0.25) offset = Vec2(0.5);
    else if (mode < 0.5) offset = Vec2(0.0);
    else if (mode < 0.625) offset = Vec2{0.0, uniform01(rng)};
    else if (mode < 0.75) offset = Vec2{uniform01(rng), 0.0};
    else offset = Vec2{uniform01(rng), uniform01(rng)};
    Camera2 cam;
    cam.position = s.grid.toWorld(Vec2(voxel) + offset);
    const std::vector<Vec2> axes = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {-1, 1}, {1, -1}, {-1, -1}, {2, 1}, {1, -3}};
    if (chance(rng, 0.4)) {
        cam.direction = pick(rng, axes);
    } else {
        const double a = uniform(rng, 0, 6.283185307179586);
        cam.direction = {std::cos(a), std::sin(a)};
    }
    const std::vector<double> fovs = {0.5, 5, 45, 90, 120, 179.5, 180, 180.5, 270, 359, 360, 360};
    cam.fovDeg = chance(rng, 0.7) ? pick(rng, fovs) : uniform(rng, 0.5, 360);
    return cam;
}

} // namespace

TEST_CASE("culler2d: closed rooms hide everything outside from every camera inside", "[culler2d][room]") {
    // Both traversals (CullerOptions::hierarchical). Per frame, besides zero misses against the exact
    // reference, no object outside the room is in the PVS, and the work stays within the room:
    //   - chess rings: the traversal terminates early, by the ring that reaches the innermost opaque
    //     layer of the farthest wall (R): on that ring every voxel is a wall's opaque voxel or lies behind
    //     a wall; the rings 0..R cover at most (2R + 1)^2 voxels, under 4 times the square on the room's
    //     longer outer side. (For a square room that is 4 times its interior plus its walls; the chess
    //     rings are squares, so an elongated room costs the square on its longer side.)
    //   - bricks: the voxels visited lie in bricks that meet the room's outer box (a brick beyond the
    //     walls is hidden behind them as a whole): at most the area of that box rounded out to whole
    //     8x8 bricks, and one brick more.
    for (const bool hierarchical : {false, true}) {
    INFO("hierarchical " << hierarchical);
    const int scenes = sanitizedShare(600), frames = 4; // 300 under ASan: a minute there (kSanitized)
    Tally tally(kCheck);
    std::size_t outsideReported = 0, notEarly = 0, overBudget = 0, failures = 0;
    std::uint64_t sumVisited = 0, sumRoomArea = 0, sumTbvTests = 0, sumBricks = 0;
    double worstRatio = 0; // voxels visited / (interior + wall voxels)
    std::size_t perKind[3] = {0, 0, 0};
    for (std::uint64_t seed = 700001; seed < 700001 + scenes; ++seed) {
        RoomScene s = randomRoomScene(seed);
        ++perKind[seed % 3];
        Culler2D culler(s.grid, CullerOptions{.hierarchical = hierarchical});
        for (const ObjectDesc<2>& o : s.objects) culler.addObject(o);
        std::mt19937_64 rng(seed * 0x9e3779b97f4a7c15ull + 1);
        IVec2 voxel{ref::scene_detail::uniformInt(rng, s.room.camLo.x, s.room.camHi.x),
                    ref::scene_detail::uniformInt(rng, s.room.camLo.y, s.room.camHi.y)};
        if (ref::scene_detail::chance(rng, 0.4)) {
            // On a diagonal of a corner of the innermost opaque layer, where the corner voxel's ray meets
            // voxel centres: the case that leaked while L corners cast two open cones.
            const IVec2 corner{seed & 1 ? s.room.innerHi.x : s.room.innerLo.x, seed & 2 ? s.room.innerHi.y : s.room.innerLo.y};
            const IVec2 toward{corner.x == s.room.innerHi.x ? -1 : 1, corner.y == s.room.innerHi.y ? -1 : 1};
            for (int m = ref::scene_detail::uniformInt(rng, 1, 80); m > 0; --m) {
                const IVec2 v = corner + toward * m;
                if (v.x >= s.room.camLo.x && v.x <= s.room.camHi.x && v.y >= s.room.camLo.y && v.y <= s.room.camHi.y) {
                    voxel = v;
                    break;
                }
            }
        }
        for (int frame = 0; frame < frames; ++frame) {
            if (frame > 0) {
                // Movers go on in a straight line, turning back where they would touch the room or leave
                // the grid; the camera's voxel steps by at most one per axis (§4.1's 8-connected path).
                for (std::size_t i = 0; i < s.objects.size(); ++i) {
                    if (s.objects[i].isStatic) continue;
                    Shape<2> next = translated<2>(s.objects[i].shape, s.velocity[i]);
                    if (!placeableOutside(s, next)) {
                        s.velocity[i] = -s.velocity[i];
                        next = translated<2>(s.objects[i].shape, s.velocity[i]);
                    }
                    if (!placeableOutside(s, next)) continue;
                    s.objects[i].shape = next;
                    culler.updateObject(s.objects[i].id, next);
                }
                for (int a = 0; a < 2; ++a)
                    voxel[a] = std::clamp(voxel[a] + ref::scene_detail::uniformInt(rng, -1, 1), s.room.camLo[a], s.room.camHi[a]);
            }
            const Camera2 cam = roomCamera(rng, s, voxel);
            const std::string origin = "room, seed " + std::to_string(seed) + ", frame " + std::to_string(frame);
            checkFrame(culler, s.objects, cam, origin, tally);
            const CullResult& r = culler.lastResult();

            const std::int32_t R = std::max(std::max(voxel.x - s.room.innerLo.x, s.room.innerHi.x - voxel.x),
                                            std::max(voxel.y - s.room.innerLo.y, s.room.innerHi.y - voxel.y));
            const IVec2 outerVoxels = IVec2(glm::ceil(s.room.hi)) - IVec2(glm::floor(s.room.lo));
            const std::int64_t side = std::max(outerVoxels.x, outerVoxels.y);
            const std::int64_t roomArea = std::int64_t(outerVoxels.x) * outerVoxels.y; // interior + walls
            std::vector<ObjectId> reported;
            for (std::size_t i = 0; i < s.objects.size(); ++i)
                if (s.outside[i] && contains(r.pvs, s.objects[i].id)) reported.push_back(s.objects[i].id);
            const IVec2 brickLo = IVec2(glm::floor(s.room.lo / 8.0)) * 8, brickHi = IVec2(glm::ceil(s.room.hi / 8.0)) * 8;
            // (+ one brick: a brick beyond a wall in the wall's own chess layer of bricks may be read before
            // the wall's object is drawn; 2 voxels of one frame in 2,400 since TBVs reach past the grid.)
            const std::uint64_t brickBudget = std::uint64_t(brickHi.x - brickLo.x) * std::uint64_t(brickHi.y - brickLo.y) + 64;
            const bool early = hierarchical || (r.stats.earlyTermination && r.stats.fallback == Fallback::None);
            const bool withinRings = hierarchical || r.stats.layers <= std::uint32_t(R) + 1;
            const bool withinBudget = hierarchical ? r.stats.voxelsVisited <= brickBudget
                                                   : r.stats.voxelsVisited <= std::uint64_t((2 * R + 1) * (2 * R + 1)) &&
                                                         r.stats.voxelsVisited <= std::uint64_t(4 * side * side);
            outsideReported += reported.size();
            notEarly += !early;
            overBudget += !(withinRings && withinBudget);
            sumVisited += r.stats.voxelsVisited;
            sumRoomArea += std::uint64_t(roomArea);
            sumTbvTests += r.stats.tbvImageTests;
            sumBricks += r.stats.bricksVisited;
            worstRatio = std::max(worstRatio, double(r.stats.voxelsVisited) / double(roomArea));
            if (reported.empty() && early && withinRings && withinBudget) continue;
            if (++failures > 3) continue;
            std::ostringstream os;
            os << origin << " (" << toString(s.room.kind) << ", outer box [" << s.room.lo.x << ", " << s.room.hi.x << "] x ["
               << s.room.lo.y << ", " << s.room.hi.y << "] voxel units, camera voxel (" << voxel.x << ", " << voxel.y
               << "), fov " << cam.fovDeg << "): " << reported.size() << " outside object(s) reported";
            for (ObjectId id : reported) os << " " << id;
            os << "; earlyTermination " << r.stats.earlyTermination << ", layers " << r.stats.layers << " (at most " << R + 1
               << "), voxels visited " << r.stats.voxelsVisited << " (at most "
               << (hierarchical ? std::int64_t(brickBudget) : std::min<std::int64_t>((2 * R + 1) * (2 * R + 1), 4 * side * side)) << ")\n";
            os << replayNote(kCheck.suite, ref::toJson(s.grid, s.objects, cam), origin);
            INFO(os.str());
            if (!reported.empty()) FAIL_CHECK("an object outside the closed room is in the PVS");
            if (!early) FAIL_CHECK("the traversal did not terminate early inside a closed room");
            if (!(withinRings && withinBudget)) FAIL_CHECK("the traversal went past the ring that closes the room");
        }
    }
    tally.print(hierarchical ? "closed rooms (bricks)" : "closed rooms (chess rings)");
    std::cout << "[culler2d] closed rooms" << (hierarchical ? " (bricks): " : " (chess rings): ") << perKind[0] << " / " << perKind[1] << " / " << perKind[2]
              << " scenes with one box per wall / thick fractional walls / unit boxes, " << frames << " frames each; "
              << "voxels visited per room voxel (interior + walls): pooled " << double(sumVisited) / double(sumRoomArea)
              << ", worst " << worstRatio << "; TBV voxel tests per visited brick " << double(sumTbvTests) / double(std::max<std::uint64_t>(sumBricks, 1)) << "\n";
    std::cout << "[culler2d] closed rooms" << (hierarchical ? " (bricks)" : " (chess rings)") << ": outside objects reported " << outsideReported << ", frames without early termination "
              << notEarly << ", over the ring or voxel budget " << overBudget << "\n";
    REQUIRE(tally.frames == std::size_t(scenes * frames));
    REQUIRE(tally.misses == 0);
    REQUIRE(outsideReported == 0);
    REQUIRE(notEarly == 0);
    REQUIRE(overBudget == 0);
    }
}

TEST_CASE("culler2d: an L corner's ray is in H when the arms lie on both sides of it, and only then", "[culler2d][room]") {
    // Two whole-voxel walls meeting at the corner voxel K, along u and w from it; camera voxel
    // C = K + alpha u + beta w, at least 2 voxels off both walls' lines. The voxels q on the ray from C's
    // centre through K's centre, past K, are the ones whose centres lay in neither of the L's two open
    // cones. H must hold only voxels hidden from every point of C's closed voxel, so each q in H is checked
    // with the exact reference from the four corners and the centre of C's voxel, with q's whole closed
    // voxel as the target. With alpha and beta of one sign (the camera facing the L's concave side, or its
    // convex side, where the ray runs on into the pocket between the arms) the arms lie on opposite sides
    // of the ray and every such q must be in H. With opposite signs both arms lie on one side, light from
    // some corner of C's voxel grazes K's corner, and such a q must stay out of H. Tiny targets at the q
    // and anywhere else check the PVS for misses as well. Only voxels the traversal visited are judged:
    // behind a layer that ended it early, H is not written (nor needed).
    Tally tally(kCheck);
    std::size_t onRay = 0, onRayNotInH = 0, unsound = 0, sameSideOnRay = 0, sameSideLit = 0;
    for (std::uint64_t seed = 800001; seed < 800601; ++seed) {
        using namespace ref::scene_detail;
        std::mt19937_64 rng(seed);
        GridGeometry2 grid({0, 0}, 1.0, {64, 64});
        const IVec2 k{uniformInt(rng, 20, 43), uniformInt(rng, 20, 43)};
        const IVec2 u{chance(rng, 0.5) ? 1 : -1, 0}, w{0, chance(rng, 0.5) ? 1 : -1};
        const int la = uniformInt(rng, 2, 14), lb = uniformInt(rng, 2, 14);
        const int config = int(seed % 3); // 0 concave side, 1 convex side, 2 arms on one side of the ray
        const int alpha = uniformInt(rng, 2, 16), beta = chance(rng, 0.5) ? alpha : uniformInt(rng, 2, 16);
        const IVec2 c = k + u * (config == 1 ? -alpha : alpha) + w * (config == 0 ? beta : -beta);
        auto voxelBox = [](IVec2 p, IVec2 q) {
            const IVec2 lo = glm::min(p, q), hi = glm::max(p, q) + 1;
            return Box<2>{Vec2(lo), Vec2(hi)};
        };
        const std::vector<Shape<2>> walls = {voxelBox(k, k + u * la), voxelBox(k, k + w * lb)};
        std::vector<ObjectDesc<2>> objects = {{1, walls[0], true, 0}, {2, walls[1], true, 0}};
        const IVec2 d = k - c;
        const IVec2 step = d / std::gcd(std::abs(d.x), std::abs(d.y));
        std::vector<IVec2> ray;
        for (IVec2 q = k + step; grid.contains(q) && ray.size() < 6; q += step) {
            ray.push_back(q);
            objects.push_back({ObjectId(100 + ray.size()), Ball<2>{Vec2(q) + 0.5, 0.05}, true, 0});
        }
        for (int i = 0; i < 6; ++i)
            objects.push_back({ObjectId(200 + i), Ball<2>{{uniform(rng, 1, 63), uniform(rng, 1, 63)}, 0.05}, true, 0});
        Culler2D culler(grid, CullerOptions{.hierarchical = false}); // H belongs to the chess-ring traversal
        for (const ObjectDesc<2>& o : objects) culler.addObject(o);
        const double mode = uniform01(rng);
        const Vec2 offset = mode < 0.3 ? Vec2(0.5) : mode < 0.6 ? Vec2(0.0) : mode < 0.8 ? Vec2{0.0, uniform01(rng)} : Vec2{uniform01(rng), uniform01(rng)};
        const Camera2 cam = makeCamera(Vec2(c) + offset, Vec2{uniform(rng, -1, 1), uniform(rng, -1, 1)} + 1e-3, 360);
        const char* names[3] = {"concave side", "convex side", "arms on one side"};
        const std::string origin = std::string("L corner, ") + names[config] + ", seed " + std::to_string(seed);
        checkFrame(culler, objects, cam, origin, tally);

        const Vec2 probes[5] = {Vec2(c), Vec2(c) + Vec2{1, 0}, Vec2(c) + Vec2{0, 1}, Vec2(c) + 1.0, Vec2(c) + 0.5};
        for (const IVec2& q : ray) {
            const VoxelState state = culler.voxelState(q);
            if (!state.visited) continue; // behind a terminating layer: H is not written there
            const bool inH = state.occluded;
            const std::vector<Shape<2>> scene = {walls[0], walls[1], Shape<2>{voxelBox(q, q)}};
            bool lit = false;
            for (const Vec2& p : probes) lit = lit || ref::exactVisible2D(scene, makeCamera(p, Vec2(d), 360))[2];
            if (config == 2) {
                ++sameSideOnRay;
                sameSideLit += lit;
            } else {
                ++onRay;
                onRayNotInH += !inH;
            }
            if (inH && lit) ++unsound;
            if ((inH && lit) || (config != 2 && !inH)) {
                INFO(origin << ": voxel (" << q.x << ", " << q.y << ") on the ray past K = (" << k.x << ", " << k.y
                            << ") from camera voxel (" << c.x << ", " << c.y << "): in H " << inH
                            << ", seen from some point of the camera voxel " << lit << "; "
                            << replayNote(kCheck.suite, ref::toJson(grid, objects, cam), origin));
                if (inH) FAIL_CHECK("H holds a voxel seen from a point of the camera voxel");
                else FAIL_CHECK("a corner ray with arms on both sides is not in H");
            }
        }
    }
    tally.print("L corners");
    std::cout << "[culler2d] L corners: arms on both sides: " << onRay - onRayNotInH << " of " << onRay
              << " voxels on the corner ray in H; arms on one side: " << sameSideLit << " of " << sameSideOnRay
              << " such voxels seen from a corner of the camera voxel; H unsound for " << unsound << "\n";
    REQUIRE(tally.frames == 600);
    REQUIRE(tally.misses == 0);
    REQUIRE(onRay > 0);
    REQUIRE(onRayNotInH == 0);
    REQUIRE(unsound == 0);
}

TEST_CASE("culler2d: merging shadow cones is set union, closing a ray only where a piece holds it", "[culler2d][room]") {
    // Random cones and rays from one apex, with small integer directions so that ends coincide exactly and
    // often; each is added to a set with mergeCone. Every lattice point must be covered by the set exactly
    // when some piece covers it: a merge may neither lose a direction nor close a ray that every piece
    // leaves open (two open cones meeting at a ray). And the L corner's three pieces become one cone.
    using namespace ref::scene_detail;
    const IVec2 apex{3, -2};
    std::size_t cases = 0, pointsChecked = 0, fused = 0;
    for (std::uint64_t seed = 900001; seed < 900301; ++seed) {
        std::mt19937_64 rng(seed);
        std::vector<OcclusionShadow2D> pieces, set;
        const int n = uniformInt(rng, 1, 8);
        while (int(pieces.size()) < n) {
            const IVec2 lo{uniformInt(rng, -3, 3), uniformInt(rng, -3, 3)};
            if (lo == IVec2(0)) continue;
            const bool ray = chance(rng, 0.3);
            const IVec2 hi = ray ? lo * uniformInt(rng, 1, 2) : IVec2{uniformInt(rng, -3, 3), uniformInt(rng, -3, 3)};
            const OcclusionShadow2D c = OcclusionShadow2D::cone(apex, lo, hi, ray || chance(rng, 0.2), ray || chance(rng, 0.2));
            if (!c.valid()) continue;
            pieces.push_back(c);
            mergeCone(set, apex, AngularInterval{c.coneLo(), c.coneHi(), c.loClosed(), c.hiClosed()});
        }
        REQUIRE(set.size() <= pieces.size());
        fused += pieces.size() - set.size();
        for (int x = -25; x <= 25; ++x)
            for (int y = -25; y <= 25; ++y) {
                if (x == 0 && y == 0) continue; // the apex: ring 0, never stamped
                const IVec2 q = apex + IVec2{x, y};
                bool inPiece = false, inSet = false;
                for (const OcclusionShadow2D& p : pieces) inPiece = inPiece || p.contains(q);
                for (const OcclusionShadow2D& p : set) inSet = inSet || p.contains(q);
                ++pointsChecked;
                if (inPiece != inSet) {
                    INFO("seed " << seed << ", point (" << q.x << ", " << q.y << "): in a piece " << inPiece << ", in the merged set " << inSet);
                    FAIL_CHECK("the merged cone set differs from the union of its pieces");
                    x = y = 26; // one report per seed
                }
            }
        ++cases;
    }
    std::cout << "[culler2d] cone merging: " << cases << " sets, " << pointsChecked << " points, " << fused << " merges\n";

    // An L corner K on the room's diagonal: the cones (lo, K) and (K, hi) of its runs, open, and its ray.
    const IVec2 lo{-19, 5}, k{-19, -19}, hi{5, -19};
    std::vector<OcclusionShadow2D> corner;
    mergeCone(corner, apex, AngularInterval{k, hi});
    mergeCone(corner, apex, AngularInterval{lo, k});
    CHECK(corner.size() == 2); // meeting at a ray both leave open: apart
    CHECK_FALSE(corner[0].contains(apex + k * 2));
    CHECK_FALSE(corner[1].contains(apex + k * 2));
    mergeCone(corner, apex, AngularInterval{k, k, true, true});
    REQUIRE(corner.size() == 1);
    CHECK(corner[0].contains(apex + k * 2));
    CHECK_FALSE(corner[0].contains(apex + lo * 2)); // the outer boundaries stay open
    CHECK_FALSE(corner[0].contains(apex + hi * 2));
}
