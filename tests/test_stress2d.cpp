// Numerical stress for Culler2D: the degenerate placements floating point gets wrong, every frame checked
// against the exact reference (rgvc::reference::exactVisible2D) with zero misses allowed.
//
//   - cameras exactly on voxel corners, on voxel faces, on the grid's bounds and corners, one ulp outside;
//   - view directions along the axes and the diagonals (wedge edges along voxel faces and diagonals);
//   - wedge edges grazing a voxel corner that is also the corner of an object lying just outside;
//   - object faces on voxel boundaries, and one ulp off them on either side;
//   - objects far smaller than a voxel and far larger than the grid;
//   - world coordinates around 1e6 with 1e-3 voxels;
//   - fields of view of 1e-3, 179.999, 180, 180.001, 359.999 and 360 degrees.
//
// Every case is drawn from a seed; a failure prints the case name, the seed and the camera index, the
// missed ids with the point where the reference saw each, and writes the scene as a scene-format file
// (replayable with `rgvc cull`). Runs in a few seconds in Release.
#include "CullerTestSupport.hpp"

#include "rgvc/dynamics/Culler.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <variant>
#include <vector>

using namespace rgvc;
using namespace rgvc::culler_test;
namespace sd = rgvc::reference::scene_detail;

namespace {

// Every frame is checked against the exact reference, ids included; no view-region figures.
const CheckOptions kCheck{.suite = "stress2d", .viewRegion = false, .checkIdsKnown = true};

/// A grid whose voxel faces are exact doubles (dyadic voxel size, origin a multiple of it).
GridGeometry2 exactGrid(std::mt19937_64& rng, int minRes, int maxRes) {
    static const std::vector<double> sizes = {1.0, 0.5, 0.25, 2.0, 0.125, 4.0};
    return culler_test::exactGrid<2>(rng, minRes, maxRes, sizes);
}

/// The camera placements under test, in voxel units.
enum class Spot { VoxelCorner, VerticalFace, HorizontalFace, GridEdge, GridCorner, VoxelCentre, JustOutside, Anywhere };
constexpr Spot kSpots[] = {Spot::VoxelCorner, Spot::VerticalFace, Spot::HorizontalFace, Spot::GridEdge,
                           Spot::GridCorner,  Spot::VoxelCentre,  Spot::JustOutside,    Spot::Anywhere};
const char* spotName(Spot s) {
    switch (s) {
    case Spot::VoxelCorner: return "voxel corner";
    case Spot::VerticalFace: return "vertical voxel face";
    case Spot::HorizontalFace: return "horizontal voxel face";
    case Spot::GridEdge: return "grid edge";
    case Spot::GridCorner: return "grid corner";
    case Spot::VoxelCentre: return "voxel centre";
    case Spot::JustOutside: return "one ulp outside the grid";
    case Spot::Anywhere: return "anywhere";
    }
    return "?";
}

Vec2 spotLocal(std::mt19937_64& rng, const IVec2& res, Spot spot) {
    const Vec2 r = Vec2(res);
    const Vec2 corner{double(sd::uniformInt(rng, 0, res.x)), double(sd::uniformInt(rng, 0, res.y))};
    switch (spot) {
    case Spot::VoxelCorner: return corner;
    case Spot::VerticalFace: return {corner.x, sd::uniform(rng, 0, r.y)};
    case Spot::HorizontalFace: return {sd::uniform(rng, 0, r.x), corner.y};
    case Spot::GridEdge: {
        const int side = sd::uniformInt(rng, 0, 3);
        const bool onVoxelCorner = sd::chance(rng, 0.5);
        const double along = onVoxelCorner ? corner[side % 2 == 0 ? 1 : 0] : sd::uniform(rng, 0, r[side % 2 == 0 ? 1 : 0]);
        if (side == 0) return {0.0, along};
        if (side == 1) return {along, 0.0};
        if (side == 2) return {r.x, along};
        return {along, r.y};
    }
    case Spot::GridCorner: return {sd::chance(rng, 0.5) ? 0.0 : r.x, sd::chance(rng, 0.5) ? 0.0 : r.y};
    case Spot::VoxelCentre: return glm::min(corner, r - 1.0) + 0.5;
    case Spot::JustOutside: {
        Vec2 p = spotLocal(rng, res, Spot::GridEdge);
        for (int a = 0; a < 2; ++a) {
            if (p[a] == 0.0) p[a] = -std::numeric_limits<double>::denorm_min();
            else if (p[a] == r[a]) p[a] = std::nextafter(r[a], kInf);
        }
        return p;
    }
    case Spot::Anywhere: return {sd::uniform(rng, -0.2 * r.x, 1.2 * r.x), sd::uniform(rng, -0.2 * r.y, 1.2 * r.y)};
    }
    return corner;
}

/// Axes, diagonals, then a few others; scaled by powers of two (exact) or by anything.
Vec2 axisDirection(std::mt19937_64& rng) {
    static const std::vector<Vec2> dirs = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {-1, 1}, {1, -1}, {-1, -1}, {2, 1}, {1, -2}};
    static const std::vector<double> scales = {1.0, 0.25, 1024.0, 1.0 / 1024};
    Vec2 d = sd::pick(rng, dirs) * sd::pick(rng, scales);
    if (sd::chance(rng, 0.15)) { // any direction
        const double a = sd::uniform(rng, 0, 2 * kPi);
        d = {std::cos(a), std::sin(a)};
    }
    return d;
}

const std::vector<double> kExtremeFovs = {1e-3, 179.999, 180, 180.001, 359.999, 360};
const std::vector<double> kAxisFovs = {90, 45, 180, 270, 360, 1e-3, 179.999, 180.001, 359.999, 30};

Vec2 rotated(const Vec2& v, double rad) {
    const double c = std::cos(rad), s = std::sin(rad);
    return {c * v.x - s * v.y, s * v.x + c * v.y};
}

} // namespace

TEST_CASE("stress2d: cameras on voxel corners, faces and grid bounds looking along axes and diagonals", "[stress]") {
    Tally tally(kCheck);
    for (std::uint64_t seed = 1; seed <= 640; ++seed) {
        std::mt19937_64 rng(seed);
        const GridGeometry2 grid = exactGrid(rng, 6, 40);
        std::vector<ObjectDesc<2>> objects;
        addRandomObjects(rng, grid, sd::chance(rng, 0.6), sd::uniformInt(rng, 1, 25), objects);
        Culler2D culler = makeCuller(grid, objects);
        int camera = 0;
        for (Spot spot : kSpots) {
            const Vec2 local = spotLocal(rng, grid.resolution(), spot);
            const Camera2 cam = makeCamera(grid.toWorld(local), axisDirection(rng), sd::pick(rng, kAxisFovs),
                                           sd::chance(rng, 0.1) ? grid.voxelSize() * sd::uniform(rng, 1, 30) : kInf);
            checkFrame(culler, objects, cam, frameLabel(std::string("on-grid spots (") + spotName(spot) + ")", seed, camera++), tally);
        }
    }
    tally.print("cameras on voxel corners/faces/grid bounds");
    REQUIRE(tally.frames == 640 * 8);
    REQUIRE(tally.misses == 0);
    REQUIRE(tally.failedFrames == 0);
}

TEST_CASE("stress2d: wedge edges grazing voxel corners and object corners", "[stress]") {
    // The direction is chosen so that one edge ray passes through a voxel corner q (up to the rounding of
    // the rotation). Objects placed just outside that edge touch the wedge only at q: a box with a corner at
    // q, a circle tangent to the edge ray at q, a triangle with a vertex at q. The reference sees them at q.
    Tally tally(kCheck);
    for (std::uint64_t seed = 1001; seed <= 2600; ++seed) {
        std::mt19937_64 rng(seed);
        const GridGeometry2 grid = exactGrid(rng, 8, 40);
        const sd::Placer pl{grid};
        const IVec2 res = grid.resolution();
        const Spot spot = kSpots[rng() % std::size(kSpots)];
        const Vec2 p = spotLocal(rng, res, spot);
        Vec2 q{double(sd::uniformInt(rng, 0, res.x)), double(sd::uniformInt(rng, 0, res.y))};
        if (glm::length(q - p) < 0.5) q.x = q.x < 0.5 * res.x ? res.x : 0; // a corner away from the camera
        static const std::vector<double> fovs = {1e-3, 1, 30, 45, 60, 90, 120, 179.999, 180, 180.001, 270, 359.999};
        const double fov = sd::pick(rng, fovs);
        const bool ccwEdge = sd::chance(rng, 0.5);
        const double half = 0.5 * fov * kPi / 180;
        const Vec2 toQ = q - p;
        const Vec2 dir = rotated(toQ, ccwEdge ? -half : half);
        const Vec2 e = glm::normalize(toQ);
        const Vec2 out = ccwEdge ? Vec2{-e.y, e.x} : Vec2{e.y, -e.x}; // away from the wedge
        // Box quadrant at q on the outer side of the edge line (see the comment above).
        const double sx = out.x >= 0 ? 1 : -1, sy = out.y >= 0 ? 1 : -1;

        std::vector<ObjectDesc<2>> objects;
        const double w = sd::pick(rng, std::vector<double>{1, 2, 0.5, 1e-3});
        const Vec2 b0 = q, b1 = q + Vec2{sx * w, sy * w * sd::pick(rng, std::vector<double>{1, 3, 0.25})};
        pushObject(objects, Box<2>{pl.world(glm::min(b0, b1)), pl.world(glm::max(b0, b1))}, rng);
        const double radius = sd::pick(rng, std::vector<double>{0.5, 2, 1e-3, 0.1});
        pushObject(objects, Ball<2>{pl.world(q + out * radius), pl.length(radius)}, rng);
        const double tri = sd::pick(rng, std::vector<double>{1, 0.01, 4});
        pushObject(objects, ConvexPolygon{{pl.world(q), pl.world(q + (out + e) * tri), pl.world(q + (out - e) * tri)}}, rng);
        addRandomObjects(rng, grid, sd::chance(rng, 0.5), sd::uniformInt(rng, 0, 12), objects);

        Culler2D culler = makeCuller(grid, objects);
        const Camera2 cam = makeCamera(pl.world(p), dir, fov);
        checkFrame(culler, objects, cam,
                   frameLabel(std::string("grazing edge (camera on ") + spotName(spot) + ", fov " + std::to_string(fov) + ")", seed, 0),
                   tally);
        // The same objects with the other edge on q (they now lie inside the wedge or beyond it).
        const Camera2 other = makeCamera(pl.world(p), rotated(toQ, ccwEdge ? half : -half), fov);
        checkFrame(culler, objects, other, frameLabel("grazing edge, other side", seed, 1), tally);
    }
    tally.print("grazing wedge edges");
    REQUIRE(tally.frames > 3000);
    REQUIRE(tally.misses == 0);
    REQUIRE(tally.failedFrames == 0);
}

TEST_CASE("stress2d: object faces on voxel boundaries and one ulp off them", "[stress]") {
    Tally tally(kCheck);
    for (std::uint64_t seed = 7001; seed <= 7800; ++seed) {
        std::mt19937_64 rng(seed);
        const GridGeometry2 grid = exactGrid(rng, 6, 32);
        std::vector<ObjectDesc<2>> snapped, nudged;
        addRandomObjects(rng, grid, true, sd::uniformInt(rng, 2, 25), snapped);
        for (const ObjectDesc<2>& o : snapped) {
            ObjectDesc<2> n = o;
            if (auto* b = std::get_if<Box<2>>(&n.shape)) {
                for (int a = 0; a < 2; ++a) {
                    b->min[a] = nudgeUlp(rng, b->min[a]);
                    b->max[a] = nudgeUlp(rng, b->max[a]);
                }
            } else if (auto* c = std::get_if<Ball<2>>(&n.shape)) {
                c->center = {nudgeUlp(rng, c->center.x), nudgeUlp(rng, c->center.y)};
                c->radius = nudgeUlp(rng, c->radius);
            } else {
                for (Vec2& pt : std::get<ConvexPolygon>(n.shape).points) pt = {nudgeUlp(rng, pt.x), nudgeUlp(rng, pt.y)};
            }
            if (isValidShape<2>(n.shape)) nudged.push_back(n);
        }
        Culler2D exact = makeCuller(grid, snapped), off = makeCuller(grid, nudged);
        for (int c = 0; c < 4; ++c) {
            const Spot spot = kSpots[rng() % std::size(kSpots)];
            const Camera2 cam = makeCamera(grid.toWorld(spotLocal(rng, grid.resolution(), spot)), axisDirection(rng),
                                           sd::pick(rng, kAxisFovs));
            checkFrame(exact, snapped, cam, frameLabel("faces on voxel boundaries", seed, c), tally);
            checkFrame(off, nudged, cam, frameLabel("faces one ulp off voxel boundaries", seed, c), tally);
        }
    }
    tally.print("faces on and next to voxel boundaries");
    REQUIRE(tally.frames == 800 * 8);
    REQUIRE(tally.misses == 0);
    REQUIRE(tally.failedFrames == 0);
}

TEST_CASE("stress2d: objects much smaller than a voxel and much larger than the grid", "[stress]") {
    Tally tally(kCheck);
    for (std::uint64_t seed = 3001; seed <= 3800; ++seed) {
        std::mt19937_64 rng(seed);
        const GridGeometry2 grid = exactGrid(rng, 6, 32);
        const sd::Placer pl{grid};
        const Vec2 r = Vec2(grid.resolution());
        std::vector<ObjectDesc<2>> objects;
        // Tiny and huge objects go into different scenes: the reference's tolerance is 1e-12 of the largest
        // coordinate, so next to an object of 1e4 grids it would see a 1e-7 voxel object from too far.
        const bool tinyScene = seed % 2 == 0;
        // Tiny objects at voxel corners, on faces and anywhere: radius / size 1e-7 .. 1e-2 voxel.
        for (int i = 0, n = tinyScene ? sd::uniformInt(rng, 1, 10) : 0; i < n; ++i) {
            const Vec2 at = spotLocal(rng, grid.resolution(), kSpots[rng() % std::size(kSpots)]);
            const double s = sd::logUniform(rng, 1e-7, 1e-2);
            const int kind = sd::uniformInt(rng, 0, 3);
            if (kind == 0) pushObject(objects, Ball<2>{pl.world(at), pl.length(s)}, rng);
            else if (kind == 1) pushObject(objects, Box<2>{pl.world(at - s), pl.world(at + s)}, rng);      // straddles
            else if (kind == 2) pushObject(objects, Box<2>{pl.world(at), pl.world(at + Vec2{s, 2 * s})}, rng); // from the corner
            else pushObject(objects, ConvexPolygon{{pl.world(at), pl.world(at + Vec2{s, 0}), pl.world(at + Vec2{0, s})}}, rng);
        }
        const std::size_t tiny = objects.size();
        // Huge objects: far larger than the grid, partly covering it (walls, discs, slabs), or enclosing it.
        for (int i = 0, n = tinyScene ? 0 : sd::uniformInt(rng, 1, 3); i < n; ++i) {
            const double big = sd::logUniform(rng, 10, 1e4) * std::max(r.x, r.y);
            const int kind = sd::uniformInt(rng, 0, 3);
            const double cut = std::floor(sd::uniform(rng, 0, r.x)); // on a voxel face
            if (kind == 0) pushObject(objects, Box<2>{pl.world({-big, -big}), pl.world({cut, big})}, rng);
            else if (kind == 1) pushObject(objects, Ball<2>{pl.world({r.x + big - cut, 0.5 * r.y}), pl.length(big)}, rng);
            else if (kind == 2) pushObject(objects, ConvexPolygon{{pl.world({cut, -big}), pl.world({big, big}), pl.world({cut, big})}}, rng);
            else pushObject(objects, Box<2>{pl.world({-big, cut}), pl.world({big, cut + 1})}, rng); // a slab one voxel thick
        }
        addRandomObjects(rng, grid, sd::chance(rng, 0.5), sd::uniformInt(rng, 0, 10), objects);
        Culler2D culler = makeCuller(grid, objects);
        for (int c = 0; c < 4; ++c) {
            Camera2 cam = makeCamera(grid.toWorld(spotLocal(rng, grid.resolution(), kSpots[rng() % std::size(kSpots)])),
                                     axisDirection(rng), sd::pick(rng, kAxisFovs));
            // Aim at a tiny object now and then, so that thin wedges see one.
            if (tiny > 0 && sd::chance(rng, 0.4)) {
                const Box<2> b = boundsOf<2>(objects[rng() % tiny].shape);
                const Vec2 d = 0.5 * (b.min + b.max) - cam.position;
                if (lengthSquared<2>(d) > 0) cam.direction = d;
            }
            checkFrame(culler, objects, cam, frameLabel("tiny and huge objects", seed, c), tally);
        }
    }
    tally.print("tiny and huge objects");
    REQUIRE(tally.frames == 800 * 4);
    REQUIRE(tally.misses == 0);
    REQUIRE(tally.failedFrames == 0);
}

TEST_CASE("stress2d: world coordinates around 1e6 and tiny voxels", "[stress]") {
    struct Frame {
        Vec2 origin;
        double voxel;
    };
    const std::vector<Frame> frames = {
        {{1e6, 1e6}, 1e-3},          {{1e6, -1e6}, 0x1.0p-10},   {{0, 0}, 1e-3},         {{-1e6, 3e5}, 1.0},
        {{123456.789, -987654.321}, 1e-3}, {{1e6 + 0.5, 1e6}, 0x1.0p-12}, {{-2.5e6, 2.5e6}, 0.01}, {{1e6, 1e6}, 1e3},
    };
    Tally tally(kCheck);
    for (std::uint64_t seed = 4001; seed <= 4800; ++seed) {
        std::mt19937_64 rng(seed);
        const Frame f = frames[std::size_t(seed) % frames.size()];
        const IVec2 res{sd::uniformInt(rng, 8, 64), sd::uniformInt(rng, 8, 64)};
        const GridGeometry2 grid(f.origin, f.voxel, res);
        std::vector<ObjectDesc<2>> objects;
        addRandomObjects(rng, grid, sd::chance(rng, 0.5), sd::uniformInt(rng, 1, 25), objects);
        Culler2D culler = makeCuller(grid, objects);
        for (int c = 0; c < 4; ++c) {
            const Camera2 cam = makeCamera(grid.toWorld(spotLocal(rng, res, kSpots[rng() % std::size(kSpots)])),
                                           axisDirection(rng), sd::pick(rng, kAxisFovs),
                                           sd::chance(rng, 0.15) ? f.voxel * sd::uniform(rng, 2, 40) : kInf);
            checkFrame(culler, objects, cam, frameLabel("large offsets and tiny voxels", seed, c), tally, f.origin);
        }
    }
    tally.print("large offsets, tiny voxels");
    REQUIRE(tally.frames == 800 * 4);
    REQUIRE(tally.misses == 0);
    REQUIRE(tally.failedFrames == 0);
}

TEST_CASE("stress2d: extreme fields of view", "[stress]") {
    Tally tally(kCheck);
    for (std::uint64_t seed = 5001; seed <= 5600; ++seed) {
        std::mt19937_64 rng(seed);
        const GridGeometry2 grid = exactGrid(rng, 6, 40);
        std::vector<ObjectDesc<2>> objects;
        addRandomObjects(rng, grid, sd::chance(rng, 0.5), sd::uniformInt(rng, 1, 25), objects);
        Culler2D culler = makeCuller(grid, objects);
        int camera = 0;
        for (double fov : kExtremeFovs) {
            const Vec2 local = spotLocal(rng, grid.resolution(), kSpots[rng() % std::size(kSpots)]);
            Camera2 cam = makeCamera(grid.toWorld(local), axisDirection(rng), fov);
            // A 1e-3 degree wedge sees nothing when aimed at random: aim it at an object's centre or a vertex.
            if (fov < 1 && sd::chance(rng, 0.7)) {
                const Box<2> b = boundsOf<2>(objects[rng() % objects.size()].shape);
                const Vec2 aim = sd::chance(rng, 0.5) ? 0.5 * (b.min + b.max) : b.min;
                if (lengthSquared<2>(aim - cam.position) > 0) cam.direction = aim - cam.position;
            }
            checkFrame(culler, objects, cam, frameLabel("fov " + std::to_string(fov), seed, camera++), tally);
            // The same fov with a finite far a few voxels away.
            cam.far = grid.voxelSize() * sd::uniform(rng, 0.5, 20);
            checkFrame(culler, objects, cam, frameLabel("fov " + std::to_string(fov) + " with far", seed, camera++), tally);
        }
    }
    tally.print("extreme fields of view");
    REQUIRE(tally.frames == 600 * 12);
    REQUIRE(tally.misses == 0);
    REQUIRE(tally.failedFrames == 0);
}
