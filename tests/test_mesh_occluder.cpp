// Closed triangle meshes as occluders (MeshSolid.hpp), end to end: the reference's mesh blocker against
// brute force (boxes, unions of boxes), the culler against the reference on random scenes full of meshes
// (boxes, L's, U's, rings, octahedra, turned or on voxel faces; static and moving), and effectiveness: a
// closed mesh wall or room hides what is behind it, an open one hides nothing, a U's notch shows what is
// seen through it.
#include "CullerTestSupport.hpp"
#include "reference/SegmentClip3D.hpp"
#include "reference/TestMeshes.hpp"
#include "rgvc/dynamics/Culler.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

using namespace rgvc;
using namespace rgvc::culler_test;
namespace ref = rgvc::reference;
namespace sd = rgvc::reference::scene3d_detail;

namespace {

const CheckOptions kCheck{.suite = "mesh-occluder"};

bool inPvs(const CullResult& r, ObjectId id) { return std::find(r.pvs.begin(), r.pvs.end(), id) != r.pvs.end(); }

/// The first interval (ending after 0) of the union of the boxes' open intervals along t*u, cam-relative:
/// the brute force for a mesh made of those boxes (touching boxes fuse: their union's interior holds the
/// shared face).
ref::Interval unionInterior(const std::vector<Box<3>>& boxes, const Vec3& cam, const Vec3& u) {
    std::vector<ref::Interval> in;
    for (const Box<3>& b : boxes) {
        ref::detail::Obj o = ref::detail::prepare(b, cam);
        ref::Interval i = ref::detail::clip(o, u, 0.0);
        if (!i.empty() && i.lo < i.hi) in.push_back(i);
    }
    std::sort(in.begin(), in.end(), [](const ref::Interval& a, const ref::Interval& b) { return a.lo < b.lo; });
    std::vector<ref::Interval> merged;
    for (const ref::Interval& i : in) {
        if (!merged.empty() && i.lo <= merged.back().hi + 1e-12) merged.back().hi = std::max(merged.back().hi, i.hi);
        else merged.push_back(i);
    }
    for (const ref::Interval& i : merged)
        if (i.hi > 0) return i;
    return {};
}

/// A run of random scenes: its tally and how many meshes its scenes held.
struct Runs {
    Tally tally;
    std::size_t meshes = 0;
};

Runs randomScenes(const std::string& name, std::uint64_t firstSeed, int scenes, int cameras, const ref::SceneOptions3D& opt);

} // namespace

TEST_CASE("mesh occluder: the reference's mesh blocker is the brute-force union of the boxes it is made of", "[mesh][reference]") {
    // Meshes made of lattice cells (a box, an L, a U, a ring), turned or not, against the union of the
    // same cells as boxes in the mesh's frame: along random lines through random camera positions the
    // first interior interval is the same (to 1e-9), or both are empty. Lines that graze (an interval
    // shorter than 1e-6, or a boundary within 1e-6 of the line) are skipped: there the two may differ by
    // the tolerances only.
    std::mt19937_64 rng(1301);
    std::size_t compared = 0, blocked = 0;
    for (int trial = 0; trial < 60; ++trial) {
        const std::vector<ref::Cell>& cells =
            trial % 4 == 0 ? ref::kBoxCells : trial % 4 == 1 ? ref::kLCells : trial % 4 == 2 ? ref::kUCells : ref::kRingCells;
        const Vec3 size{sd::uniform(rng, 0.5, 3), sd::uniform(rng, 0.5, 3), sd::uniform(rng, 0.5, 3)};
        const Vec3 at{sd::uniform(rng, -5, 5), sd::uniform(rng, -5, 5), sd::uniform(rng, -5, 5)};
        // The brute force works on axis-aligned boxes: the line is turned into the mesh's frame instead.
        const std::array<Vec3, 3> axes = ref::randomAxes(rng, trial % 2 == 1);
        const MeshSolid mesh = ref::cellMesh(cells, size, at, axes);
        std::vector<Box<3>> boxes;
        for (const ref::Cell& c : cells) {
            const Vec3 lo{c[0] * size.x, c[1] * size.y, c[2] * size.z};
            boxes.push_back({lo, lo + size});
        }
        for (int k = 0; k < 200; ++k) {
            const Vec3 cam = at + Vec3{sd::uniform(rng, -12, 12), sd::uniform(rng, -12, 12), sd::uniform(rng, -12, 12)};
            const Vec3 target = at + 1.5 * (size.x * axes[0] + size.y * axes[1] + size.z * axes[2]) +
                                Vec3{sd::uniform(rng, -4, 4), sd::uniform(rng, -4, 4), sd::uniform(rng, -4, 4)};
            const Vec3 u = ref::detail::normalized(target - cam);
            const ref::detail::Obj o = ref::detail::prepare(mesh, cam);
            const ref::Interval got = ref::detail::meshInterior(o, u, 0.0);
            // The same line in the mesh's frame (x -> R^T (x - at)): camera and direction.
            auto local = [&](const Vec3& v) { return Vec3{glm::dot(v, axes[0]), glm::dot(v, axes[1]), glm::dot(v, axes[2])}; };
            const ref::Interval want = unionInterior(boxes, local(cam - at), local(u));
            // Grazing lines: skip when shrinking or growing the boxes by 1e-6 changes the answer's emptiness.
            bool grazing = false;
            for (double off : {-1e-6, 1e-6}) {
                std::vector<Box<3>> b2 = boxes;
                for (Box<3>& b : b2) b = {b.min - off, b.max + off};
                grazing = grazing || unionInterior(b2, local(cam - at), local(u)).empty() != want.empty();
            }
            if (grazing) continue;
            ++compared;
            INFO("trial " << trial << ", line " << k);
            REQUIRE(got.empty() == want.empty());
            if (want.empty()) continue;
            ++blocked;
            CHECK(std::abs(got.lo - want.lo) < 1e-9);
            CHECK(std::abs(got.hi - want.hi) < 1e-9);
        }
    }
    CHECK(compared > 10000);
    CHECK(blocked > 2000);
}

TEST_CASE("mesh occluder: an open mesh blocks nothing in the reference, a closed one like its solid", "[mesh][reference]") {
    // A box mesh in front of a sphere: closed, the sphere is hidden; with one face's two triangles removed
    // (open: a surface, no interior) it is seen. Also checked with the camera inside the closed box.
    TriangleMesh m = ref::cellMeshTriangles(ref::kBoxCells, {4, 4, 1}, {-2, -2, 5});
    const MeshSolid closed = ref::meshShape(m);
    REQUIRE(closed.closed());
    m.triangles.resize(m.triangles.size() - 2);
    const MeshSolid open = ref::meshShape(m);
    REQUIRE_FALSE(open.closed());
    const Ball<3> ball{{0, 0, 12}, 0.5};
    const Camera3 cam = makeCamera({0, 0, 0}, {0, 0, 1}, 40);
    CHECK(ref::visible3D({closed, ball}, cam) == std::vector<bool>{true, false});
    CHECK(ref::visible3D({open, ball}, cam) == std::vector<bool>{true, true});
    const Camera3 inside = makeCamera({0, 0, 5.5}, {0, 0, 1}, 40);
    CHECK(ref::visible3D({closed, ball}, inside) == std::vector<bool>{true, false});
}

TEST_CASE("mesh occluder: no misses on random scenes with closed meshes", "[mesh][culler3d]") {
    ref::SceneOptions3D opt;
    opt.meshProbability = 0.4;
    opt.polytopeProbability = 0.2;
    // Half the scenes under ASan (kSanitized), here and below.
    Runs t = randomScenes("meshes", 810001, sanitizedShare(100), 3, opt);
    REQUIRE(t.tally.framesWithOcclusion > 0);
    REQUIRE(t.tally.misses == 0);
    REQUIRE(t.meshes > std::size_t(sanitizedShare(100)));
    ref::SceneOptions3D snapped = opt;
    snapped.snapProbability = 1.0; // meshes with every face on voxel faces, next to snapped boxes
    Runs t2 = randomScenes("meshes, snapped", 820001, sanitizedShare(60), 3, snapped);
    REQUIRE(t2.tally.misses == 0);
    ref::SceneOptions3D crowded = opt;
    crowded.minResolution = 8;
    crowded.maxResolution = 20;
    crowded.minObjects = 20;
    crowded.maxObjects = 50;
    crowded.meshProbability = 0.6;
    Runs t3 = randomScenes("meshes, crowded", 830001, sanitizedShare(60), 3, crowded);
    REQUIRE(t3.tally.framesWithOcclusion > 0);
    REQUIRE(t3.tally.misses == 0);
}

TEST_CASE("mesh occluder: moving meshes keep the PVS conservative", "[mesh][culler3d]") {
    // Every object of a mesh-rich scene moves (translation only, as scene-format.md's motion) by up to 2
    // voxels per frame, some while hidden (a moving mesh is re-voxelized: MeshSolid.hpp); every frame is
    // checked against the reference.
    Tally tally(kCheck);
    for (std::uint64_t seed = 840001; seed < 840041; ++seed) {
        ref::SceneOptions3D opt;
        opt.meshProbability = 0.5;
        opt.minResolution = 8;
        opt.maxResolution = 24;
        opt.minObjects = 10;
        opt.maxObjects = 40;
        ref::Scene3D s = ref::randomScene3D(seed, opt);
        std::mt19937_64 rng(seed * 31 + 7);
        Culler3D culler = makeCuller(s.grid, s.objects);
        std::vector<ObjectDesc<3>> objects = s.objects;
        runMovingFrames(culler, objects, s, opt, rng, 5, "moving meshes, seed " + std::to_string(seed), tally);
    }
    tally.print("moving meshes");
    REQUIRE(tally.frames == 200);
    REQUIRE(tally.misses == 0);
}

TEST_CASE("mesh occluder: a closed mesh wall hides what is behind it, the same wall open hides nothing", "[mesh][culler3d]") {
    // A wall 3 voxels thick, turned by 20 degrees about y, across the grid; 30 spheres behind it, 10 in front.
    // Closed, it hides all those behind it (the reference agrees), with both cores; open (two triangles
    // gone: a surface), it hides nothing, and the reference sees some of them.
    const GridGeometry3 grid({0, 0, 0}, 1.0, {64, 32, 64});
    const double a = 20 * M_PI / 180;
    const std::array<Vec3, 3> axes = {Vec3{std::cos(a), 0, -std::sin(a)}, Vec3{0, 1, 0}, Vec3{std::sin(a), 0, std::cos(a)}};
    const Vec3 centre{32, 16, 32};
    TriangleMesh wall = ref::cellMeshTriangles(ref::kBoxCells, {120, 80, 3}, centre - (60.0 * axes[0] + 40.0 * axes[1] + 1.5 * axes[2]), axes);
    std::mt19937_64 rng(4242);
    std::vector<Shape<3>> shapes{ref::meshShape(wall)};
    std::vector<std::size_t> behind;
    for (int k = 0; k < 40; ++k) {
        const bool back = k < 30;
        const double u = sd::uniform(rng, -20, 20), v = sd::uniform(rng, 4, 14) * (back ? 1 : -1), y = sd::uniform(rng, 4, 28);
        if (back) behind.push_back(shapes.size());
        shapes.push_back(Ball<3>{centre + u * axes[0] + (y - 16) * axes[1] + v * axes[2], 1.0});
    }
    TriangleMesh holed = wall;
    holed.triangles.resize(holed.triangles.size() - 2);
    for (bool closed : {true, false}) {
        shapes[0] = ref::meshShape(closed ? wall : holed);
        std::vector<ObjectDesc<3>> objects = staticObjects<3>(shapes);
        if (!closed) objects[0].role = ObjectRole::Occludee; // what an open mesh can only be (addObject refuses more)
        for (bool hierarchical : {true, false}) {
            CullerOptions o;
            o.hierarchical = hierarchical;
            Culler3D culler = makeCuller(grid, objects, o);
            Tally tally(kCheck);
            for (double yaw : {-60.0, -30.0, 0.0, 20.0, 45.0}) {
                const double r = yaw * M_PI / 180;
                const Camera3 cam = makeCamera({32.5, 16.5, 12.5}, {std::sin(r), 0.0, std::cos(r)}, 90, kInf, 1.5);
                checkFrame(culler, objects, cam, std::string(closed ? "closed" : "open") + " mesh wall, yaw " + std::to_string(yaw), tally);
                const CullResult& res = culler.cull(cam);
                const std::vector<bool> vis = ref::visible3D(ref::shapesOf(objects), cam);
                std::size_t leaked = 0, seenBehind = 0;
                for (std::size_t i : behind) {
                    leaked += inPvs(res, objects[i].id);
                    seenBehind += vis[i];
                }
                INFO("closed " << closed << ", hierarchical " << hierarchical << ", yaw " << yaw);
                if (closed) {
                    // The brick walk (the default core) hides every one; the shell core, whose occlusion
                    // image draws nothing for a mesh (MeshSolid.hpp), hides most (4 of 30 leak at 3 yaws).
                    if (hierarchical) CHECK(leaked == 0);
                    else CHECK(leaked <= behind.size() / 5);
                    CHECK(seenBehind == 0);
                } else {
                    CHECK(seenBehind > 0); // a surface hides nothing: what is in view behind it is seen
                }
            }
            REQUIRE(tally.misses == 0);
        }
    }
}

TEST_CASE("mesh occluder: a closed mesh room hides what is inside, a U's notch shows what is seen through it", "[mesh][culler3d]") {
    const GridGeometry3 grid({0, 0, 0}, 1.0, {64, 32, 64});
    // A room: 3 x 3 x 3 cells of 4 voxels without the centre cell (a closed surface with an inner cavity),
    // a sphere in the cavity; cameras all around outside.
    std::vector<ref::Cell> shell;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k)
                if (!(i == 1 && j == 1 && k == 1)) shell.push_back({i, j, k});
    const MeshSolid room = ref::cellMesh(shell, {4, 4, 4}, {26.3, 8.3, 26.3});
    REQUIRE(room.closed());
    // A U open towards +y (cells of 4 x 4 x 12 voxels), its notch a channel along z at x 24..28, y 8..12.
    const MeshSolid u = ref::cellMesh(ref::kUCells, {4, 4, 12}, {20, 4, 44});
    REQUIRE(u.closed());
    const std::vector<Shape<3>> shapes{room, Ball<3>{{32.3, 14.3, 32.3}, 1.0}, u, Ball<3>{{26, 10, 60}, 0.8},
                                       Ball<3>{{22, 6, 61}, 0.5}};
    const std::vector<ObjectDesc<3>> objects = staticObjects<3>(shapes);
    Culler3D culler = makeCuller(grid, objects);
    Tally tally(kCheck);
    for (int k = 0; k < 8; ++k) {
        const double r = k * M_PI / 4;
        const Vec3 pos{32.3 + 22 * std::sin(r), 14.5 + (k % 3) * 4.0, 32.3 - 22 * std::cos(r)};
        const Camera3 cam = makeCamera(pos, Vec3{32.3, 14.3, 32.3} - pos, 60);
        checkFrame(culler, objects, cam, "room, camera " + std::to_string(k), tally);
        INFO("camera " << k);
        const CullResult& res = culler.cull(cam);
        CHECK_FALSE(inPvs(res, 2)); // the sphere in the room
        // The image hides one brick behind many it reads, yet a mesh in view keeps it on: the buffer
        // pass's fresh image cannot draw a mesh (CullerOptions::adaptiveImage).
        CHECK_FALSE(res.stats.imageSkipped);
    }
    // Through the notch: the sphere straight behind it is seen (and reported); the one behind the U's
    // lower left cell is hidden by the solid.
    const Camera3 notch = makeCamera({26, 10, 30}, {0, 0, 1}, 50);
    checkFrame(culler, objects, notch, "through the notch", tally);
    const std::vector<bool> vis = ref::visible3D(shapes, notch);
    CHECK(vis[3]);
    CHECK_FALSE(vis[4]);
    const CullResult& res = culler.cull(notch);
    CHECK(inPvs(res, 4));
    CHECK_FALSE(inPvs(res, 5));
    REQUIRE(tally.misses == 0);
}

namespace {

Runs randomScenes(const std::string& name, std::uint64_t firstSeed, int scenes, int cameras, const ref::SceneOptions3D& opt) {
    Runs runs{Tally(kCheck), 0};
    for (bool hierarchical : {true, false})
        for (std::uint64_t seed = firstSeed; seed < firstSeed + std::uint64_t(scenes); ++seed) {
            ref::Scene3D s = ref::randomScene3D(seed, opt);
            for (const ObjectDesc<3>& o : s.objects) runs.meshes += std::holds_alternative<MeshSolid>(o.shape);
            CullerOptions core;
            core.hierarchical = hierarchical;
            Culler3D culler = makeCuller(s.grid, s.objects, core);
            std::mt19937_64 rng(seed ^ 0x5eed5eedull);
            for (int c = 0; c < cameras; ++c) {
                Camera3 cam = c == 0 ? s.camera : ref::randomCamera3D(rng, s.grid, s.objects, s.snapped, opt);
                checkFrame(culler, s.objects, cam, frameLabel(name + (hierarchical ? "" : " (shells)"), seed, c), runs.tally);
            }
        }
    runs.tally.print(name);
    return runs;
}

} // namespace
