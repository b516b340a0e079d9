// Culler2D against the exact reference: thousands of random scenes and cameras, zero misses allowed.
//
// A miss (an exactly visible object absent from the PVS) is the one thing a conservative culler must
// never do, so every case REQUIREs none; overestimation is allowed and only measured and printed.
// Every failure prints the seed, the camera's index for that seed, the scene as a scene-format JSON file
// (replayable with `rgvc cull`), the missed ids, the point where the reference saw each one and the
// culler's state of the voxel holding that point.
#include "ExactVisibility2D.hpp"
#include "RandomScenes2D.hpp"

#include "rgvc/dynamics/Culler.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

using namespace rgvc;
namespace ref = rgvc::reference;

namespace {

// Figures of one test case, printed at its end.
struct Tally {
    std::size_t frames = 0, framesWithVisible = 0, misses = 0, failedFrames = 0, outsideFallbacks = 0;
    double sumPvsRatio = 0, sumVfcRatio = 0;
    // The same over frames with the camera in the grid (no fallback): the grid algorithm's own figure,
    // not diluted by the camera-outside fallback, which reports the whole view-region set.
    std::size_t framesInGrid = 0;
    double sumPvsRatioInGrid = 0, sumVfcRatioInGrid = 0;
    std::size_t sumPvs = 0, sumVisible = 0, sumVfc = 0;
    double cullMs = 0, referenceMs = 0;

    void print(const std::string& name) const {
        std::ostringstream os;
        os.precision(4);
        os << "[culler2d] " << name << ": " << frames << " scene/camera pairs, " << misses << " misses; "
           << "mean |PVS|/|visible| = " << (framesWithVisible ? sumPvsRatio / framesWithVisible : 0.0)
           << ", mean |VFC|/|visible| = " << (framesWithVisible ? sumVfcRatio / framesWithVisible : 0.0)
           << " (over " << framesWithVisible << " frames with something visible; pooled "
           << (sumVisible ? double(sumPvs) / double(sumVisible) : 0.0) << " and "
           << (sumVisible ? double(sumVfc) / double(sumVisible) : 0.0) << "); cameras in the grid only: "
           << (framesInGrid ? sumPvsRatioInGrid / framesInGrid : 0.0) << " and "
           << (framesInGrid ? sumVfcRatioInGrid / framesInGrid : 0.0) << " over " << framesInGrid
           << " frames; camera-outside fallbacks " << outsideFallbacks << "; cull " << cullMs << " ms, reference " << referenceMs << " ms in all\n";
        std::cout << os.str() << std::flush;
    }
};

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

bool contains(const std::vector<ObjectId>& sorted, ObjectId id) { return std::binary_search(sorted.begin(), sorted.end(), id); }

std::string describeVoxel(const Culler2D& culler, const Vec2& world) {
    IVec2 v = culler.grid().voxelOf(world);
    VoxelState s = culler.voxelState(v);
    std::ostringstream os;
    os << "voxel (" << v.x << ", " << v.y << ")";
    if (!s.inGrid) return os.str() + " outside the grid";
    os << " opaque=" << s.opaque << " occluded=" << s.occluded << " visited=" << s.visited
       << " occluder=" << s.occluder << " hasIds=" << s.hasIds;
    return os.str();
}

// Writes a failing scene to the temp directory; returns its path, or "" when it cannot.
std::string saveScene(const std::string& json, const std::string& origin) {
    std::string name = "rgvc-culler2d-";
    for (char ch : origin) {
        const char c = std::isalnum(static_cast<unsigned char>(ch)) ? ch : '-';
        if (c != '-' || name.back() != '-') name += c;
    }
    std::error_code ec;
    std::filesystem::path dir = std::filesystem::temp_directory_path(ec);
    if (ec) return "";
    std::filesystem::path p = dir / (name + ".json");
    std::ofstream f(p);
    f << json;
    return f ? p.string() : "";
}

// Culls `cam` on a culler holding exactly `objects` and compares with the reference. Adds to the tally;
// reports (INFO + FAIL_CHECK) the first few failing frames of a case in full.
void checkFrame(Culler2D& culler, const std::vector<ObjectDesc<2>>& objects, const Camera2& cam,
                const std::string& origin, Tally& tally) {
    const std::vector<Shape<2>> shapes = ref::shapesOf(objects);
    auto t0 = std::chrono::steady_clock::now();
    ref::ExactStats stats;
    const std::vector<bool> visible = ref::exactVisible2D(shapes, cam, {}, &stats);
    const std::vector<bool> inView = ref::inViewRegion2D(shapes, cam);
    tally.referenceMs += msSince(t0);

    t0 = std::chrono::steady_clock::now();
    const CullResult& result = culler.cull(cam);
    tally.cullMs += msSince(t0);
    const std::vector<ObjectId>& pvs = result.pvs;

    std::size_t nVisible = 0, nVfc = 0;
    std::vector<std::size_t> missed;
    for (std::size_t i = 0; i < objects.size(); ++i) {
        nVisible += visible[i];
        nVfc += inView[i];
        if (visible[i] && !contains(pvs, objects[i].id)) missed.push_back(i);
    }
    ++tally.frames;
    tally.outsideFallbacks += result.stats.fallback == Fallback::CameraOutsideGrid;
    if (nVisible > 0) {
        ++tally.framesWithVisible;
        tally.sumPvsRatio += double(pvs.size()) / double(nVisible);
        tally.sumVfcRatio += double(nVfc) / double(nVisible);
        tally.sumPvs += pvs.size();
        tally.sumVisible += nVisible;
        tally.sumVfc += nVfc;
        if (result.stats.fallback == Fallback::None) {
            ++tally.framesInGrid;
            tally.sumPvsRatioInGrid += double(pvs.size()) / double(nVisible);
            tally.sumVfcRatioInGrid += double(nVfc) / double(nVisible);
        }
    }
    const bool sortedUnique = std::adjacent_find(pvs.begin(), pvs.end(), std::greater_equal<ObjectId>()) == pvs.end();
    if (missed.empty() && sortedUnique) return;

    tally.misses += missed.size();
    if (++tally.failedFrames > 3) return; // the count says the rest; three full reports are plenty
    std::ostringstream os;
    os << origin << ": " << missed.size() << " visible object(s) missing from the PVS (" << pvs.size()
       << " reported, " << nVisible << " visible, fallback " << toString(result.stats.fallback) << ")\n";
    for (std::size_t i : missed) {
        const Vec2 w = stats.witness[i];
        const Vec2 wl = culler.grid().toLocal(w);
        os.precision(17);
        os << "  missed id " << objects[i].id << " (object index " << i << "), seen at world (" << w.x << ", " << w.y
           << ") = voxel units (" << wl.x << ", " << wl.y << "), " << describeVoxel(culler, w) << "\n";
    }
    os << "camera voxel units (" << culler.grid().toLocal(cam.position).x << ", " << culler.grid().toLocal(cam.position).y << ")\n";
    // Catch wraps long messages at 80 columns, which breaks numbers apart; the replayable file is written
    // whole (and the JSON goes into the message only when the file cannot be written).
    const std::string json = ref::toJson(culler.grid(), objects, cam);
    const std::string path = saveScene(json, origin);
    if (!path.empty()) os << "scene written to " << path << " (replay: rgvc cull " << path << ")";
    else os << "scene:\n" << json;
    INFO(os.str());
    if (!sortedUnique) FAIL_CHECK("the PVS is not sorted ascending without duplicates");
    if (!missed.empty()) FAIL_CHECK("culler missed a visible object");
}

// Runs `scenes` seeds from `firstSeed`, `camerasPerScene` cameras each (the scene's own, then more drawn
// from the same seed), one culler per scene.
Tally runRandomScenes(const std::string& name, std::uint64_t firstSeed, int scenes, int camerasPerScene,
                      const ref::SceneOptions& opt, const CullerOptions& cullerOptions = {}) {
    Tally tally;
    for (std::uint64_t seed = firstSeed; seed < firstSeed + std::uint64_t(scenes); ++seed) {
        ref::Scene2D s = ref::randomScene2D(seed, opt);
        Culler2D culler(s.grid, cullerOptions);
        for (const ObjectDesc<2>& o : s.objects) culler.addObject(o);
        REQUIRE(culler.objectCount() == s.objects.size());
        std::mt19937_64 rng(seed ^ 0x9e3779b97f4a7c15ull);
        for (int c = 0; c < camerasPerScene; ++c) {
            Camera2 cam = c == 0 ? s.camera : ref::randomCamera2D(rng, s.grid, s.objects, s.snapped, opt);
            checkFrame(culler, s.objects, cam, name + ", seed " + std::to_string(seed) + ", camera " + std::to_string(c), tally);
        }
    }
    tally.print(name);
    return tally;
}

// One hand-made scene on a 32 x 32 grid of unit voxels; ids are 1, 2, ... in order.
Tally checkHandScene(const std::string& name, const std::vector<Shape<2>>& shapes, const Camera2& cam) {
    GridGeometry2 grid({0, 0}, 1.0, {32, 32});
    Culler2D culler(grid);
    std::vector<ObjectDesc<2>> objects;
    for (std::size_t i = 0; i < shapes.size(); ++i) {
        ObjectDesc<2> o;
        o.id = i + 1;
        o.shape = shapes[i];
        o.isStatic = true;
        objects.push_back(o);
        culler.addObject(o);
    }
    Tally tally;
    checkFrame(culler, objects, cam, name, tally);
    return tally;
}

Camera2 makeCamera(Vec2 pos, Vec2 dir, double fov, double far = std::numeric_limits<double>::infinity()) {
    Camera2 c;
    c.position = pos;
    c.direction = dir;
    c.fovDeg = fov;
    c.far = far;
    return c;
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

TEST_CASE("culler2d: no misses on mixed random scenes", "[culler]") {
    Tally t = runRandomScenes("mixed", 1, 1500, 3, ref::SceneOptions{});
    REQUIRE(t.frames == 4500);
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
    Tally tally;
    for (std::uint64_t seed = 500001; seed < 500151; ++seed) {
        ref::Scene2D s = ref::randomScene2D(seed);
        std::mt19937_64 rng(seed * 31 + 7);
        Culler2D culler(s.grid);
        for (const ObjectDesc<2>& o : s.objects) culler.addObject(o);
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
