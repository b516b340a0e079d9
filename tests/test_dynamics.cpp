// Object bookkeeping over many moves: after any sequence of updateObject/removeObject calls, the grid
// (O and I) and the PVS are exactly those of a culler built fresh from the final placements. This pins
// down the incremental footprint update (only the difference of old and new footprints is written).
#include <catch2/catch.hpp>

#include "rgvc/dynamics/Culler.hpp"

#include "rgvc/grid/RowFootprint.hpp"

#include <algorithm>
#include <map>
#include <random>
#include <set>

using namespace rgvc;

namespace {

template <int D> Shape<D> randomShape(std::mt19937_64& rng, double extent) {
    std::uniform_real_distribution<double> pos(-2, extent + 2), size(0.2, 4.0), coin(0, 1);
    Vec<D> c;
    for (int a = 0; a < D; ++a) c[a] = pos(rng);
    if (coin(rng) < 0.5) return Ball<D>{c, size(rng)};
    Vec<D> h;
    for (int a = 0; a < D; ++a) h[a] = size(rng);
    return Box<D>{c - h, c + h};
}

template <int D> void checkSameGrid(const Culler<D>& a, const Culler<D>& b, std::uint64_t seed) {
    const IVec<D> res = a.grid().resolution();
    IVec<D> v{0};
    std::size_t mismatches = 0;
    const std::size_t n = a.grid().voxelCount();
    for (std::size_t i = 0; i < n; ++i) {
        std::size_t r = i;
        for (int ax = 0; ax < D; ++ax) {
            v[ax] = std::int32_t(r % std::size_t(res[ax]));
            r /= std::size_t(res[ax]);
        }
        const VoxelState sa = a.voxelState(v), sb = b.voxelState(v);
        mismatches += sa.opaque != sb.opaque || sa.hasIds != sb.hasIds;
    }
    INFO("seed " << seed);
    CHECK(mismatches == 0);
}

template <int D> void runMoves(std::uint64_t seed, const IVec<D>& res, const Camera<D>& camera) {
    std::mt19937_64 rng(seed);
    const GridGeometry<D> grid(Vec<D>(0.0), 1.0, res);
    Culler<D> culler(grid);
    std::vector<Shape<D>> shapes;
    const int count = 40;
    for (int i = 0; i < count; ++i) {
        shapes.push_back(randomShape<D>(rng, res.x));
        culler.addObject({ObjectId(i), shapes.back(), false, 1.0});
    }
    std::uniform_real_distribution<double> step(-0.7, 0.7), coin(0, 1);
    std::vector<bool> alive(count, true);
    for (int frame = 0; frame < 200; ++frame) {
        for (int i = 0; i < count; ++i) {
            if (!alive[i]) continue;
            if (coin(rng) < 0.01) { // a few objects leave for good
                culler.removeObject(ObjectId(i));
                alive[i] = false;
                continue;
            }
            Vec<D> t;
            for (int a = 0; a < D; ++a) t[a] = step(rng);
            shapes[i] = coin(rng) < 0.05 ? randomShape<D>(rng, res.x) : translated<D>(shapes[i], t);
            culler.updateObject(ObjectId(i), shapes[i]);
        }
    }
    Culler<D> fresh(grid);
    for (int i = 0; i < count; ++i)
        if (alive[i]) fresh.addObject({ObjectId(i), shapes[i], false, 1.0});
    checkSameGrid(culler, fresh, seed);
    const std::vector<ObjectId> pvs = culler.cull(camera).pvs;
    INFO("seed " << seed);
    CHECK(pvs == fresh.cull(camera).pvs);
}

} // namespace

TEST_CASE("dynamics: 200 frames of moves leave the 2D grid as a fresh build would", "[dynamics]") {
    for (std::uint64_t seed = 1; seed <= 6; ++seed)
        runMoves<2>(seed, IVec2{48, 40}, Camera2{.position = {3.5, 20.2}, .direction = {1, 0.1}, .fovDeg = 120});
}

TEST_CASE("dynamics: 200 frames of moves leave the 3D grid as a fresh build would", "[dynamics]") {
    for (std::uint64_t seed = 11; seed <= 14; ++seed)
        runMoves<3>(seed, IVec3{20, 16, 24},
                    Camera3{.position = {10.3, 8.2, 1.5}, .direction = {0, 0, 1}, .fovDeg = 70});
}

TEST_CASE("a scene without moving objects allocates no T and writes nothing per frame", "[dynamics][tbv]") {
    for (int dims : {2, 3}) {
        INFO("dimensions " << dims);
        auto run = [&](auto& culler, auto cameraAt) {
            for (int f = 0; f < 40; ++f) {
                const CullStats& s = culler.cull(cameraAt(f)).stats;
                CHECK_FALSE(s.tbvMatrixAllocated);
                CHECK(s.tbvLookupsSkipped);
                CHECK(s.hiddenObjects == 0);
                CHECK(s.placementQueries == 0);
                CHECK(s.gridWrites == 0); // O and H cost what was written: nothing moved
            }
        };
        if (dims == 2) {
            Culler2D c(GridGeometry2({0, 0}, 1.0, {64, 64}));
            std::mt19937_64 rng(7);
            // Static objects, and non-static ones without a speed (they move only by updateObject).
            for (ObjectId id = 0; id < 60; ++id) c.addObject({id, randomShape<2>(rng, 64), id % 2 == 0, 0});
            run(c, [](int f) { return Camera2{.position = {2.5 + 0.5 * f, 30.5}, .direction = {1, 0.1}, .fovDeg = 90}; });
            // A moving object changes that once it is hidden behind something.
            c.addObject({100, Ball<2>{{62, 62}, 0.5}, false, 0.1});
            c.addObject({101, Box<2>{{50, 40}, {52, 64}}, true, 0});
            const Camera2 cam{.position = {2.5, 2.5}, .direction = {1, 0}, .fovDeg = 30};
            c.cull(cam);
            const CullStats& s = c.cull(cam).stats;
            CHECK(s.tbvMatrixAllocated);
            CHECK(s.hiddenObjects == 1);
        } else {
            Culler3D c(GridGeometry3({0, 0, 0}, 1.0, {32, 32, 32}));
            std::mt19937_64 rng(8);
            for (ObjectId id = 0; id < 40; ++id) c.addObject({id, randomShape<3>(rng, 32), id % 2 == 0, 0});
            run(c, [](int f) {
                return Camera3{.position = {2.5 + 0.5 * f, 16.5, 3.5}, .direction = {0.2, 0, 1}, .fovDeg = 60};
            });
        }
    }
}

TEST_CASE("dynamics: the grid's frame stamps pass their range (65,535 frames) without changing the answer", "[dynamics]") {
    for (const bool hierarchical : {true, false}) {
        INFO("hierarchical " << hierarchical);
        Culler2D culler(GridGeometry2({0, 0}, 1.0, {16, 16}), CullerOptions{.hierarchical = hierarchical});
        culler.addObject({.id = 1, .shape = Box<2>{{8, 0}, {9, 16}}, .isStatic = true});   // a wall across the grid
        culler.addObject({.id = 2, .shape = Ball<2>{{5.5, 8.5}, 1}, .isStatic = true});    // in front of it
        culler.addObject({.id = 3, .shape = Ball<2>{{12.5, 8.5}, 1}, .isStatic = true});   // behind it
        const Camera2 cam{.position = {1.5, 8.5}, .direction = {1, 0}, .fovDeg = 60};
        const std::vector<ObjectId> first = culler.cull(cam).pvs;
        CHECK(first == std::vector<ObjectId>{1, 2});
        std::size_t differing = 0;
        for (int f = 1; f < 70000; ++f) differing += culler.cull(cam).pvs != first;
        CHECK(differing == 0);
        // The stamps still mean "this frame" after the clear: in front of the wall visited; behind it not
        // visible (the rings stop at the wall, or H holds it; the bricks read the voxels of a brick they
        // visit, so only the rings say it per voxel).
        CHECK(culler.voxelState({3, 8}).visited);
        const VoxelState behind = culler.voxelState({12, 8});
        if (!hierarchical) CHECK_FALSE((behind.visited && !behind.occluded));
    }
}

// ---- RowFootprint: incremental moves against from-scratch rasterization, exactly -------------------

namespace {

/// I as exact sets and O as exact counts, with every write checked: an id is never added twice to a
/// voxel or removed from one that lacks it, and no count goes below zero.
struct ExactStorage {
    std::map<VoxelKey, std::set<ObjectSlot>> ids;
    std::map<VoxelKey, std::int64_t> counts;
    std::size_t badWrites = 0;
    void addId(VoxelKey k, ObjectSlot o) { badWrites += !ids[k].insert(o).second; }
    void removeId(VoxelKey k, ObjectSlot o) {
        auto it = ids.find(k);
        if (it == ids.end() || it->second.erase(o) == 0) ++badWrites;
        else if (it->second.empty()) ids.erase(it);
    }
    void addOpaque(VoxelKey k, std::int32_t delta) {
        const std::int64_t n = counts[k] += delta;
        badWrites += n < 0;
        if (n == 0) counts.erase(k);
    }
};

/// A shape near the grid (partly outside now and then), 2D polygons included: radius 0.05..4 voxels.
template <int D> Shape<D> footprintShape(std::mt19937_64& rng, const IVec<D>& res) {
    std::uniform_real_distribution<double> coin(0, 1), size(0.05, 4.0);
    Vec<D> c;
    for (int a = 0; a < D; ++a) c[a] = std::uniform_real_distribution<double>(-3, res[a] + 3)(rng);
    const double kind = coin(rng);
    if (kind < 0.1) { // integer-aligned box: faces on voxel boundaries
        Box<D> b;
        for (int a = 0; a < D; ++a) {
            b.min[a] = std::floor(c[a]);
            b.max[a] = b.min[a] + std::floor(size(rng)) + 1;
        }
        return b;
    }
    if constexpr (D == 2) {
        if (kind < 0.3) {
            const double r = size(rng), phase = coin(rng);
            ConvexPolygon p;
            for (int k = 0; k < 5; ++k) {
                const double t = (k + phase) * 2 * 3.141592653589793 / 5;
                p.points.push_back(c + Vec2{std::cos(t), std::sin(t)} * r);
            }
            return p;
        }
    }
    if (kind < 0.6) return Ball<D>{c, size(rng)};
    Vec<D> h;
    for (int a = 0; a < D; ++a) h[a] = size(rng) * 0.5;
    return Box<D>{c - h, c + h};
}

template <int D> void runFootprintMoves(std::uint64_t seed, const IVec<D>& res) {
    std::mt19937_64 rng(seed);
    const GridGeometry<D> grid(Vec<D>(0.0), 1.0, res);
    const double slack = grid.conversionSlack();
    const int count = 30;
    std::vector<Shape<D>> shapes(count);
    std::vector<RowFootprint> held(count);
    std::vector<bool> alive(count, false);
    ExactStorage storage;
    RowFootprint next;
    std::uniform_real_distribution<double> coin(0, 1), small(-0.5, 0.5), tiny(-0.02, 0.02);
    std::size_t checks = 0;
    for (int step = 0; step < 3000; ++step) {
        const int i = int(rng() % count);
        const double what = coin(rng);
        if (!alive[i]) { // add
            shapes[i] = footprintShape<D>(rng, res);
            held[i].build<D>(shapes[i], grid, slack);
            held[i].write(storage, ObjectSlot(i), +1);
            alive[i] = true;
        } else if (what < 0.05) { // remove
            held[i].write(storage, ObjectSlot(i), -1);
            held[i].release();
            alive[i] = false;
        } else { // move by a fraction of a voxel (often within the same voxels), or jump elsewhere
            Vec<D> t;
            for (int a = 0; a < D; ++a) t[a] = what < 0.5 ? tiny(rng) : small(rng);
            shapes[i] = what > 0.97 ? footprintShape<D>(rng, res) : translated<D>(shapes[i], t);
            next.build<D>(shapes[i], grid, slack);
            const std::uint64_t written = held[i].moveTo(storage, ObjectSlot(i), next);
            CHECK(held[i] == next);
            if (written == 0) CHECK(storage.badWrites == 0);
        }
        if (step % 100 != 99) continue;
        // From scratch: every live object's voxels, straight from the voxel rasterizers.
        ExactStorage fresh;
        for (int k = 0; k < count; ++k) {
            if (!alive[k]) continue;
            forEachTouchedVoxel<D>(shapes[k], res, [&](const IVec<D>& v) { fresh.addId(grid.linearIndex(v), ObjectSlot(k)); }, slack);
            forEachInnerVoxel<D>(shapes[k], res, [&](const IVec<D>& v) { fresh.addOpaque(grid.linearIndex(v), +1); }, slack);
        }
        INFO("seed " << seed << ", step " << step);
        REQUIRE(storage.badWrites == 0);
        REQUIRE(fresh.badWrites == 0);
        REQUIRE(storage.ids == fresh.ids);
        REQUIRE(storage.counts == fresh.counts);
        ++checks;
    }
    // Removing everything leaves nothing behind.
    for (int k = 0; k < count; ++k)
        if (alive[k]) held[k].write(storage, ObjectSlot(k), -1);
    INFO("seed " << seed);
    CHECK(storage.badWrites == 0);
    CHECK(storage.ids.empty());
    CHECK(storage.counts.empty());
    CHECK(checks == 30);
}

} // namespace

TEST_CASE("RowFootprint: random add/move/remove sequences leave exactly the from-scratch I sets and O counts",
          "[dynamics][raster]") {
    for (std::uint64_t seed = 101; seed <= 106; ++seed) runFootprintMoves<2>(seed, IVec2{24, 17});
    for (std::uint64_t seed = 201; seed <= 204; ++seed) runFootprintMoves<3>(seed, IVec3{12, 9, 14});
}

TEST_CASE("RowFootprint: a move within the same voxels writes nothing, a row shift writes only its ends",
          "[dynamics][raster]") {
    const GridGeometry3 grid(Vec3(0.0), 1.0, IVec3{10, 10, 10});
    ExactStorage s;
    RowFootprint a, b;
    a.build<3>(Box<3>{{2.2, 3.2, 4.2}, {4.8, 5.8, 6.8}}, grid, grid.conversionSlack());
    a.write(s, 0, +1);
    b.build<3>(Box<3>{{2.3, 3.1, 4.3}, {4.7, 5.9, 6.7}}, grid, grid.conversionSlack()); // same voxels
    CHECK(a.moveTo(s, 0, b) == 0);
    // Touched 2..4 x 3..5 x 4..6 -> 3..5: each of the 9 rows loses x = 2 and gains x = 5. Inner: the box
    // 3.2..5.8 holds x = 4 (y 4, z 5), as 2.2..4.8 held x = 3: one voxel out, one in.
    b.build<3>(Box<3>{{3.2, 3.2, 4.2}, {5.8, 5.8, 6.8}}, grid, grid.conversionSlack());
    CHECK(a.moveTo(s, 0, b) == 9 * 2 + 2);
    CHECK(s.badWrites == 0);
    CHECK(s.ids.size() == 27);
    CHECK(s.counts.size() == 1);
}

// ---- the culler: object updates in every state against a culler built fresh ----------------------

namespace {

template <int D> bool sameGridEverywhere(const Culler<D>& a, const Culler<D>& b) {
    const IVec<D> res = a.grid().resolution();
    for (std::size_t i = 0, n = a.grid().voxelCount(); i < n; ++i) {
        IVec<D> v;
        std::size_t r = i;
        for (int ax = 0; ax < D; ++ax) {
            v[ax] = std::int32_t(r % std::size_t(res[ax]));
            r /= std::size_t(res[ax]);
        }
        const VoxelState sa = a.voxelState(v), sb = b.voxelState(v);
        if (sa.opaque != sb.opaque || sa.hasIds != sb.hasIds) return false;
    }
    return true;
}

/// Adds, moves (mostly by fractions of a voxel), removes and re-adds balls and boxes, static and
/// moving, by updateObject and by the placement query of cull(). With TBVs off every object stays in O and
/// I: the objects are then removed one by one in random order, and after each removal the grid must equal
/// that of a culler built fresh from the final placements with the same removals (equal O flags after
/// every removal pin the O counts; equal I flags pin which objects hold each voxel), ending empty. With
/// TBVs on, objects also pass through TBVs and back (their footprints are dropped and rebuilt): the PVS
/// must contain the fresh culler's, and removing everything must leave an empty grid.
template <int D> void runCullerUpdates(std::uint64_t seed, const IVec<D>& res, const std::vector<Camera<D>>& cameras,
                                       bool tbvs) {
    std::mt19937_64 rng(seed);
    const GridGeometry<D> grid(Vec<D>(0.0), 1.0, res);
    CullerOptions options;
    options.temporalBoundingVolumes = tbvs;
    // The walk's image every frame in both cullers: CullerOptions::adaptiveImage schedules it from each
    // culler's own history, and a frame of one without it and of the other with it report different
    // (both conservative) sets, whatever their grids hold.
    options.adaptiveImage = false;
    Culler<D> culler(grid, options);
    const int count = 30;
    std::vector<Shape<D>> shapes(count);
    std::vector<bool> alive(count, false), fixed(count, false);
    std::uniform_real_distribution<double> coin(0, 1), step(-0.4, 0.4);
    const auto query = [&](ObjectId id) { return shapes[std::size_t(id)]; };
    for (int frame = 0; frame < 120; ++frame) {
        for (int i = 0; i < count; ++i) {
            const double what = coin(rng);
            if (!alive[i]) {
                if (what < 0.3) {
                    shapes[i] = randomShape<D>(rng, res.x);
                    fixed[i] = coin(rng) < 0.2;
                    culler.addObject({ObjectId(i), shapes[i], fixed[i], fixed[i] ? 0.0 : 0.5});
                    alive[i] = true;
                }
                continue;
            }
            if (what < 0.02) {
                culler.removeObject(ObjectId(i));
                alive[i] = false;
                continue;
            }
            Vec<D> t;
            for (int a = 0; a < D; ++a) t[a] = step(rng);
            shapes[i] = what > 0.98 ? randomShape<D>(rng, res.x) : translated<D>(shapes[i], t);
            if (what < 0.5 || fixed[i]) culler.updateObject(ObjectId(i), shapes[i]); // else: cull() asks for it
        }
        culler.cull(cameras[std::size_t(frame) % cameras.size()], query);
    }
    Culler<D> fresh(grid, options);
    std::vector<int> order;
    for (int i = 0; i < count; ++i)
        if (alive[i]) {
            order.push_back(i);
            fresh.addObject({ObjectId(i), shapes[i], fixed[i], fixed[i] ? 0.0 : 0.5});
        }
    INFO("seed " << seed << (tbvs ? ", TBVs on" : ", TBVs off"));
    for (const Camera<D>& cam : cameras) {
        const std::vector<ObjectId> got = culler.cull(cam, query).pvs;
        const std::vector<ObjectId> want = fresh.cull(cam, query).pvs;
        if (tbvs) CHECK(std::includes(got.begin(), got.end(), want.begin(), want.end()));
        else CHECK(got == want);
    }
    std::shuffle(order.begin(), order.end(), rng);
    std::size_t differing = 0;
    for (int i : order) {
        culler.removeObject(ObjectId(i));
        fresh.removeObject(ObjectId(i));
        if (!tbvs) differing += !sameGridEverywhere(culler, fresh);
    }
    CHECK(differing == 0);
    CHECK(sameGridEverywhere(culler, fresh)); // both empty now
}

} // namespace

TEST_CASE("dynamics: add/move/remove of balls and boxes in every state leave the grid a fresh build would",
          "[dynamics]") {
    const std::vector<Camera2> cams2{{.position = {3.5, 20.2}, .direction = {1, 0.1}, .fovDeg = 120},
                                     {.position = {40.5, 5.5}, .direction = {-1, 1}, .fovDeg = 60}};
    const std::vector<Camera3> cams3{{.position = {10.3, 8.2, 1.5}, .direction = {0, 0, 1}, .fovDeg = 70},
                                     {.position = {18.5, 2.5, 20.5}, .direction = {-1, 0.5, -1}, .fovDeg = 50}};
    for (bool tbvs : {false, true}) {
        for (std::uint64_t seed = 31; seed <= 34; ++seed) runCullerUpdates<2>(seed, IVec2{48, 40}, cams2, tbvs);
        for (std::uint64_t seed = 41; seed <= 43; ++seed) runCullerUpdates<3>(seed, IVec3{20, 16, 24}, cams3, tbvs);
    }
}
