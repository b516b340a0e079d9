// Object bookkeeping over many moves: after any sequence of updateObject/removeObject calls, the grid
// (O and I) and the PVS are exactly those of a culler built fresh from the final placements. This pins
// down the incremental footprint update (only the difference of old and new footprints is written).
#include <catch2/catch.hpp>

#include "rgvc/dynamics/Culler.hpp"

#include <random>

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
    Culler2D culler(GridGeometry2({0, 0}, 1.0, {16, 16}));
    culler.addObject({.id = 1, .shape = Box<2>{{8, 0}, {9, 16}}, .isStatic = true});   // a wall across the grid
    culler.addObject({.id = 2, .shape = Ball<2>{{5.5, 8.5}, 1}, .isStatic = true});    // in front of it
    culler.addObject({.id = 3, .shape = Ball<2>{{12.5, 8.5}, 1}, .isStatic = true});   // behind it
    const Camera2 cam{.position = {1.5, 8.5}, .direction = {1, 0}, .fovDeg = 60};
    const std::vector<ObjectId> first = culler.cull(cam).pvs;
    CHECK(first == std::vector<ObjectId>{1, 2});
    std::size_t differing = 0;
    for (int f = 1; f < 70000; ++f) differing += culler.cull(cam).pvs != first;
    CHECK(differing == 0);
    // The stamps still mean "this frame" after the clear: in front of the wall visited, behind it not
    // visible (the traversal stops at the wall, or H holds it).
    CHECK(culler.voxelState({3, 8}).visited);
    const VoxelState behind = culler.voxelState({12, 8});
    CHECK_FALSE((behind.visited && !behind.occluded));
}
