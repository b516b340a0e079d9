// Numerical stress for Culler3D: the degenerate placements floating point gets wrong, every frame checked
// against the sampled 3D reference (rgvc::reference::visible3D at its defaults) with zero misses allowed.
//
//   - cameras exactly on voxel corners, edges and faces, on the grid's faces, edges and corners, one ulp
//     outside the grid;
//   - view directions along the axes, the grid-plane diagonals and the space diagonals;
//   - frustum side planes through voxel corners, with boxes touching the frustum only along that corner;
//   - box faces on voxel boundaries, and one ulp off them on either side;
//   - objects far smaller than a voxel and far larger than the grid;
//   - world coordinates around 1e6 with 1e-3 voxels (the reference runs on the scene shifted exactly next
//     to the origin, since its tolerance scales with the coordinates' magnitude);
//   - vertical fields of view of 0.01, 1, 120 and 179.9 degrees, aspects 0.05 and 20.
//
// Every case is drawn from a seed; a failure prints the case, the seed and the camera index, the missed
// ids with the point where the reference saw each and the voxel there, and writes the scene as a
// scene-format JSON file to the temp directory (replayable with `rgvc cull`). A few hundred frames.
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
namespace sd = rgvc::reference::scene3d_detail;

namespace {

// Every frame is checked against the sampled reference, ids included; no view-region figures.
const CheckOptions kCheck{.suite = "stress3d", .viewRegion = false, .checkIdsKnown = true};

/// A grid whose voxel faces are exact doubles (dyadic voxel size, origin a multiple of it).
GridGeometry3 exactGrid(std::mt19937_64& rng, int minRes, int maxRes) {
    static const std::vector<double> sizes = {1.0, 0.5, 0.25, 2.0, 0.125};
    return culler_test::exactGrid<3>(rng, minRes, maxRes, sizes);
}

enum class Spot { VoxelCorner, VoxelEdge, VoxelFace, GridFace, GridEdge, GridCorner, JustOutside, Anywhere };
constexpr Spot kSpots[] = {Spot::VoxelCorner, Spot::VoxelEdge, Spot::VoxelFace,   Spot::GridFace,
                           Spot::GridEdge,    Spot::GridCorner, Spot::JustOutside, Spot::Anywhere};
const char* spotName(Spot s) {
    switch (s) {
    case Spot::VoxelCorner: return "voxel corner";
    case Spot::VoxelEdge: return "voxel edge";
    case Spot::VoxelFace: return "voxel face";
    case Spot::GridFace: return "grid face";
    case Spot::GridEdge: return "grid edge";
    case Spot::GridCorner: return "grid corner";
    case Spot::JustOutside: return "one ulp outside the grid";
    case Spot::Anywhere: return "anywhere";
    }
    return "?";
}

/// A camera position in voxel units.
Vec3 spotLocal(std::mt19937_64& rng, const IVec3& res, Spot spot) {
    const Vec3 r = Vec3(res);
    const Vec3 corner{double(sd::uniformInt(rng, 0, res.x)), double(sd::uniformInt(rng, 0, res.y)),
                      double(sd::uniformInt(rng, 0, res.z))};
    const Vec3 any{sd::uniform(rng, 0, r.x), sd::uniform(rng, 0, r.y), sd::uniform(rng, 0, r.z)};
    const int axis = sd::uniformInt(rng, 0, 2);
    switch (spot) {
    case Spot::VoxelCorner: return corner;
    case Spot::VoxelEdge: {
        Vec3 p = corner;
        p[axis] = any[axis];
        return p;
    }
    case Spot::VoxelFace: {
        Vec3 p = any;
        p[axis] = corner[axis];
        return p;
    }
    case Spot::GridFace: {
        Vec3 p = sd::chance(rng, 0.5) ? corner : any;
        p[axis] = sd::chance(rng, 0.5) ? 0.0 : r[axis];
        return p;
    }
    case Spot::GridEdge: {
        Vec3 p = sd::chance(rng, 0.5) ? corner : any;
        const int b = (axis + 1) % 3;
        p[axis] = sd::chance(rng, 0.5) ? 0.0 : r[axis];
        p[b] = sd::chance(rng, 0.5) ? 0.0 : r[b];
        return p;
    }
    case Spot::GridCorner:
        return {sd::chance(rng, 0.5) ? 0.0 : r.x, sd::chance(rng, 0.5) ? 0.0 : r.y, sd::chance(rng, 0.5) ? 0.0 : r.z};
    case Spot::JustOutside: {
        Vec3 p = spotLocal(rng, res, sd::chance(rng, 0.5) ? Spot::GridFace : Spot::GridEdge);
        for (int a = 0; a < 3; ++a) {
            if (p[a] == 0.0) p[a] = -std::numeric_limits<double>::denorm_min();
            else if (p[a] == r[a]) p[a] = std::nextafter(r[a], kInf);
        }
        return p;
    }
    case Spot::Anywhere: return any * 1.4 - 0.2 * r;
    }
    return corner;
}

/// Axes, grid-plane diagonals, space diagonals (sometimes anything), scaled by powers of two or anything.
Vec3 axisDirection(std::mt19937_64& rng) {
    static const std::vector<Vec3> dirs = {
        {1, 0, 0},  {-1, 0, 0},  {0, 1, 0},  {0, -1, 0}, {0, 0, 1},  {0, 0, -1},                 // axes
        {1, 1, 0},  {-1, 1, 0},  {1, 0, -1}, {0, 1, 1},  {0, -1, 1}, {-1, 0, -1},                // plane diagonals
        {1, 1, 1},  {-1, 1, 1},  {1, -1, 1}, {1, 1, -1}, {-1, -1, -1}, {1, -1, -1}};             // space diagonals
    static const std::vector<double> scales = {1.0, 0.25, 1024.0, 1.0 / 1024};
    Vec3 d = sd::pick(rng, dirs) * sd::pick(rng, scales);
    if (sd::chance(rng, 0.1)) d = sd::unitVector(rng) * sd::logUniform(rng, 1e-3, 1e3);
    return d;
}

/// The default up where valid, otherwise an axis not parallel to dir (so rolls are axis-aligned too).
Vec3 upFor(std::mt19937_64& rng, const Vec3& dir) {
    const Vec3 u = dir / std::sqrt(lengthSquared<3>(dir));
    static const std::vector<Vec3> ups = {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}, {0, -1, 0}, {1, 1, 0}};
    if (sd::chance(rng, 0.6) && std::abs(u.y) < 0.999) return Vec3(0.0);
    for (int attempt = 0; attempt < 20; ++attempt) {
        const Vec3 up = sd::pick(rng, ups);
        if (std::abs(glm::dot(up / std::sqrt(lengthSquared<3>(up)), u)) < 0.999) return up;
    }
    return std::abs(u.x) < 0.9 ? Vec3{1.0, 0.0, 0.0} : Vec3{0.0, 0.0, 1.0};
}

const std::vector<double> kAxisFovs = {90, 60, 1, 120, 179.9, 0.01, 45, 2 * std::atan(0.5) * 180 / kPi};
const std::vector<double> kAspects = {1, 1, 16.0 / 9.0, 0.05, 20, 0.5, 2};

/// The camera, with the arguments in this file's order.
Camera3 makeCamera(const Vec3& pos, const Vec3& dir, const Vec3& up, double fov, double aspect = 1, double far = kInf) {
    return culler_test::makeCamera(pos, dir, fov, far, aspect, up);
}

/// Aims `cam` at an object's centre or bounding corner (narrow frusta see nothing when aimed at random).
void aimAtObject(std::mt19937_64& rng, Camera3& cam, const std::vector<ObjectDesc<3>>& objects) {
    if (objects.empty()) return;
    const Box<3> b = boundsOf<3>(objects[rng() % objects.size()].shape);
    const Vec3 aim = sd::chance(rng, 0.5) ? 0.5 * (b.min + b.max) : b.min;
    const Vec3 d = aim - cam.position;
    if (lengthSquared<3>(d) > 0) {
        cam.direction = d;
        cam.up = upFor(rng, d);
    }
}

} // namespace

TEST_CASE("stress3d: cameras on voxel corners, edges, faces and grid bounds looking along axes and diagonals", "[stress3d]") {
    Tally tally(kCheck);
    for (std::uint64_t seed = 1; seed <= 80; ++seed) {
        std::mt19937_64 rng(seed);
        const GridGeometry3 grid = exactGrid(rng, 4, 20);
        std::vector<ObjectDesc<3>> objects;
        addRandomObjects(rng, grid, sd::chance(rng, 0.6), sd::uniformInt(rng, 1, 25), objects);
        Culler3D culler = makeCuller(grid, objects);
        int camera = 0;
        for (Spot spot : kSpots) {
            const Vec3 dir = axisDirection(rng);
            const Camera3 cam = makeCamera(grid.toWorld(spotLocal(rng, grid.resolution(), spot)), dir, upFor(rng, dir),
                                           sd::chance(rng, 0.7) ? sd::pick(rng, std::vector<double>{90, 60, 45, 120}) : sd::pick(rng, kAxisFovs),
                                           sd::chance(rng, 0.7) ? 1.0 : sd::pick(rng, kAspects),
                                           sd::chance(rng, 0.1) ? grid.voxelSize() * sd::uniform(rng, 1, 20) : kInf);
            checkFrame(culler, objects, cam, frameLabel(std::string("on-grid spots (") + spotName(spot) + ")", seed, camera++), tally);
        }
    }
    tally.print("cameras on voxel corners/edges/faces/grid bounds");
    REQUIRE(tally.frames == 80 * 8);
    REQUIRE(tally.misses == 0);
    REQUIRE(tally.failedFrames == 0);
}

TEST_CASE("stress3d: frustum side planes grazing voxel corners", "[stress3d]") {
    // The camera sits on a voxel corner p looking along axis a with up along axis b; the vertical half
    // angle has tan t in {1, 1/2, 2} (and aspect 1 or 2), so the top/bottom planes hold the voxel corners
    // p + k*(e_a + t e_b) (exactly, in voxel units) and the side planes those with slope aspect*t. A box
    // with its edge on such a corner line, extending outward (away from the axis, towards the camera),
    // touches the frustum only along that line; a sphere tangent to the plane there touches it at a point.
    Tally tally(kCheck);
    for (std::uint64_t seed = 101; seed <= 250; ++seed) {
        std::mt19937_64 rng(seed);
        const GridGeometry3 grid = exactGrid(rng, 12, 24);
        const sd::Placer3 pl{grid};
        const IVec3 res = grid.resolution();
        int a, b, c;
        sd::pickAxes(rng, a, b, c);
        const double sa = sd::chance(rng, 0.5) ? 1 : -1;
        const double t = sd::pick(rng, std::vector<double>{1, 0.5, 2});
        const double aspect = sd::pick(rng, std::vector<double>{1, 2});
        // The grazed plane: top/bottom (axis b, slope t) or left/right (axis c, slope aspect*t).
        const bool vertical = sd::chance(rng, 0.5);
        const int side = vertical ? b : c;
        const double slope = vertical ? t : aspect * t;
        const double sgn = sd::chance(rng, 0.5) ? 1 : -1;
        Vec3 p = Vec3(res) * 0.5;
        p = glm::floor(p);
        p[a] = sa > 0 ? 2 : res[a] - 2;
        const double k = double(sd::uniformInt(rng, 1, 6)) * (slope == 0.5 ? 2 : 1);
        Vec3 q = p;
        q[a] += sa * k;
        q[side] += sgn * slope * k;
        std::vector<ObjectDesc<3>> objects;
        const double w = sd::pick(rng, std::vector<double>{1, 2, 0.5, 1e-3});
        // Box from q outward along `side` and back towards the camera along a, across the other axis.
        Vec3 lo = q, hi = q;
        hi[side] += sgn * w;
        hi[a] -= sa * w;
        const int other = 3 - a - side;
        lo[other] -= sd::pick(rng, std::vector<double>{0.0, 1.0, 3.0});
        hi[other] += sd::pick(rng, std::vector<double>{1e-3, 1.0, 2.0});
        pushObject(objects, Box<3>{pl.world(glm::min(lo, hi)), pl.world(glm::max(lo, hi))}, rng);
        // A sphere tangent to the plane at q from outside.
        Vec3 n{0.0};
        n[side] = sgn;
        n[a] = -sa * slope;
        n /= std::sqrt(lengthSquared<3>(n));
        const double radius = sd::pick(rng, std::vector<double>{0.5, 2, 1e-3});
        pushObject(objects, Ball<3>{pl.world(q + n * radius), pl.length(radius)}, rng);
        addRandomObjects(rng, grid, sd::chance(rng, 0.5), sd::uniformInt(rng, 0, 10), objects);
        Culler3D culler = makeCuller(grid, objects);

        Vec3 dir{0.0}, up{0.0};
        dir[a] = sa;
        up[b] = 1;
        const double fov = 2 * std::atan(t) * 180 / kPi;
        const Camera3 cam = makeCamera(pl.world(p), dir * sd::pick(rng, std::vector<double>{1, 8, 0.125}), up, fov, aspect);
        checkFrame(culler, objects, cam, frameLabel(std::string("grazing ") + (vertical ? "top/bottom" : "left/right") +
                                                   " plane, tan " + std::to_string(slope), seed, 0),
                   tally);
        // The same scene with a slightly wider frustum (the objects now lie inside) and a narrower one.
        Camera3 wide = cam;
        wide.fovDeg = std::min(179.9, fov * 1.01);
        checkFrame(culler, objects, wide, frameLabel("grazing plane, wider", seed, 1), tally);
        Camera3 narrow = cam;
        narrow.fovDeg = fov * 0.99;
        checkFrame(culler, objects, narrow, frameLabel("grazing plane, narrower", seed, 2), tally);
    }
    tally.print("frustum planes grazing voxel corners");
    REQUIRE(tally.frames == 150 * 3);
    REQUIRE(tally.misses == 0);
    REQUIRE(tally.failedFrames == 0);
}

TEST_CASE("stress3d: box faces on voxel boundaries and one ulp off them", "[stress3d]") {
    Tally tally(kCheck);
    for (std::uint64_t seed = 201; seed <= 280; ++seed) {
        std::mt19937_64 rng(seed);
        const GridGeometry3 grid = exactGrid(rng, 4, 16);
        std::vector<ObjectDesc<3>> snapped, nudged;
        addRandomObjects(rng, grid, true, sd::uniformInt(rng, 2, 25), snapped);
        for (const ObjectDesc<3>& o : snapped) {
            ObjectDesc<3> n = o;
            if (auto* bx = std::get_if<Box<3>>(&n.shape)) {
                for (int ax = 0; ax < 3; ++ax) {
                    bx->min[ax] = nudgeUlp(rng, bx->min[ax]);
                    bx->max[ax] = nudgeUlp(rng, bx->max[ax]);
                }
            } else {
                auto& s = std::get<Ball<3>>(n.shape);
                for (int ax = 0; ax < 3; ++ax) s.center[ax] = nudgeUlp(rng, s.center[ax]);
                s.radius = nudgeUlp(rng, s.radius);
            }
            if (isValidShape<3>(n.shape)) nudged.push_back(n);
        }
        Culler3D exact = makeCuller(grid, snapped), off = makeCuller(grid, nudged);
        for (int cam = 0; cam < 4; ++cam) {
            const Spot spot = kSpots[rng() % std::size(kSpots)];
            const Vec3 dir = axisDirection(rng);
            const Camera3 c = makeCamera(grid.toWorld(spotLocal(rng, grid.resolution(), spot)), dir, upFor(rng, dir),
                                         sd::pick(rng, std::vector<double>{90, 60, 45, 120, 1}));
            checkFrame(exact, snapped, c, frameLabel("faces on voxel boundaries", seed, cam), tally);
            checkFrame(off, nudged, c, frameLabel("faces one ulp off voxel boundaries", seed, cam), tally);
        }
    }
    tally.print("faces on and next to voxel boundaries");
    REQUIRE(tally.frames == 80 * 8);
    REQUIRE(tally.misses == 0);
    REQUIRE(tally.failedFrames == 0);
}

TEST_CASE("stress3d: objects much smaller than a voxel and much larger than the grid", "[stress3d]") {
    Tally tally(kCheck);
    for (std::uint64_t seed = 301; seed <= 380; ++seed) {
        std::mt19937_64 rng(seed);
        const GridGeometry3 grid = exactGrid(rng, 4, 16);
        const sd::Placer3 pl{grid};
        const Vec3 r = Vec3(grid.resolution());
        std::vector<ObjectDesc<3>> objects;
        // Tiny and huge objects go into different scenes: the reference's tolerance is 1e-12 of the largest
        // coordinate, so next to a huge object it would see a tiny one from too far.
        const bool tinyScene = seed % 2 == 0;
        for (int i = 0, n = tinyScene ? sd::uniformInt(rng, 1, 8) : 0; i < n; ++i) {
            const Vec3 at = spotLocal(rng, grid.resolution(), kSpots[rng() % 3]); // corner, edge or face
            const double s = sd::logUniform(rng, 1e-6, 1e-2);
            const int kind = sd::uniformInt(rng, 0, 2);
            if (kind == 0) pushObject(objects, Ball<3>{pl.world(at), pl.length(s)}, rng);
            else if (kind == 1) pushObject(objects, Box<3>{pl.world(at - s), pl.world(at + s)}, rng);        // straddles
            else pushObject(objects, Box<3>{pl.world(at), pl.world(at + Vec3{s, 2 * s, 0.5 * s})}, rng); // from the corner
        }
        const std::size_t tiny = objects.size();
        for (int i = 0, n = tinyScene ? 0 : sd::uniformInt(rng, 1, 3); i < n; ++i) {
            const double big = sd::logUniform(rng, 10, 1e4) * std::max({r.x, r.y, r.z});
            const int kind = sd::uniformInt(rng, 0, 2);
            const int ax = sd::uniformInt(rng, 0, 2);
            const double cut = std::floor(sd::uniform(rng, 0, r[ax])); // on a voxel face
            if (kind == 0) { // a half space beyond a voxel face
                Vec3 lo(-big), hi(big);
                hi[ax] = cut;
                pushObject(objects, Box<3>{pl.world(lo), pl.world(hi)}, rng);
            } else if (kind == 1) { // a huge sphere whose surface crosses the grid
                Vec3 c = 0.5 * r;
                c[ax] = r[ax] + big - cut;
                pushObject(objects, Ball<3>{pl.world(c), pl.length(big)}, rng);
            } else { // a slab one voxel thick
                Vec3 lo(-big), hi(big);
                lo[ax] = cut;
                hi[ax] = cut + 1;
                pushObject(objects, Box<3>{pl.world(lo), pl.world(hi)}, rng);
            }
        }
        addRandomObjects(rng, grid, sd::chance(rng, 0.5), sd::uniformInt(rng, 0, 10), objects);
        Culler3D culler = makeCuller(grid, objects);
        for (int cam = 0; cam < 4; ++cam) {
            const Vec3 dir = axisDirection(rng);
            Camera3 c = makeCamera(grid.toWorld(spotLocal(rng, grid.resolution(), kSpots[rng() % std::size(kSpots)])), dir,
                                   upFor(rng, dir), sd::pick(rng, std::vector<double>{90, 60, 1, 120, 20}));
            if (tiny > 0 && sd::chance(rng, 0.5)) {
                const Box<3> bb = boundsOf<3>(objects[rng() % tiny].shape);
                const Vec3 d = 0.5 * (bb.min + bb.max) - c.position;
                if (lengthSquared<3>(d) > 0) c.direction = d, c.up = upFor(rng, d);
            }
            checkFrame(culler, objects, c, frameLabel(tinyScene ? "tiny objects" : "huge objects", seed, cam), tally);
        }
    }
    tally.print("tiny and huge objects");
    REQUIRE(tally.frames == 80 * 4);
    REQUIRE(tally.misses == 0);
    REQUIRE(tally.failedFrames == 0);
}

TEST_CASE("stress3d: world coordinates around 1e6 and tiny voxels", "[stress3d]") {
    struct Frame {
        Vec3 origin;
        double voxel;
    };
    const std::vector<Frame> frames = {
        {{1e6, 1e6, 1e6}, 1e-3},        {{1e6, -1e6, 1e6}, 0x1.0p-10}, {{-1e6, 3e5, 1e6}, 1.0},
        {{123456.789, -987654.321, 5e5}, 1e-3}, {{1e6 + 0.5, 1e6, -1e6}, 0x1.0p-12}, {{1e6, 1e6, 1e6}, 1e3},
    };
    Tally tally(kCheck);
    for (std::uint64_t seed = 401; seed <= 490; ++seed) {
        std::mt19937_64 rng(seed);
        const Frame f = frames[std::size_t(seed) % frames.size()];
        const IVec3 res{sd::uniformInt(rng, 6, 24), sd::uniformInt(rng, 6, 24), sd::uniformInt(rng, 6, 24)};
        const GridGeometry3 grid(f.origin, f.voxel, res);
        std::vector<ObjectDesc<3>> objects;
        addRandomObjects(rng, grid, sd::chance(rng, 0.5), sd::uniformInt(rng, 1, 25), objects);
        Culler3D culler = makeCuller(grid, objects);
        for (int cam = 0; cam < 4; ++cam) {
            const Vec3 dir = axisDirection(rng);
            const Camera3 c = makeCamera(grid.toWorld(spotLocal(rng, res, kSpots[rng() % std::size(kSpots)])), dir,
                                         upFor(rng, dir), sd::pick(rng, std::vector<double>{90, 60, 1, 120, 45}),
                                         sd::pick(rng, kAspects),
                                         sd::chance(rng, 0.15) ? f.voxel * sd::uniform(rng, 2, 30) : kInf);
            checkFrame(culler, objects, c, frameLabel("large offsets and tiny voxels", seed, cam), tally, f.origin);
        }
    }
    tally.print("large offsets, tiny voxels");
    REQUIRE(tally.frames == 90 * 4);
    REQUIRE(tally.misses == 0);
    REQUIRE(tally.failedFrames == 0);
}

TEST_CASE("stress3d: extreme fields of view and aspects", "[stress3d]") {
    const std::vector<double> fovs = {0.01, 1, 120, 179.9};
    const std::vector<double> aspects = {0.05, 20, 1};
    Tally tally(kCheck);
    for (std::uint64_t seed = 501; seed <= 540; ++seed) {
        std::mt19937_64 rng(seed);
        const GridGeometry3 grid = exactGrid(rng, 4, 20);
        std::vector<ObjectDesc<3>> objects;
        addRandomObjects(rng, grid, sd::chance(rng, 0.5), sd::uniformInt(rng, 1, 25), objects);
        Culler3D culler = makeCuller(grid, objects);
        int camera = 0;
        for (double fov : fovs)
            for (double aspect : aspects) {
                if (aspect == 1 && fov > 100) continue; // covered by the pairs with extreme aspects
                const Vec3 dir = axisDirection(rng);
                Camera3 cam = makeCamera(grid.toWorld(spotLocal(rng, grid.resolution(), kSpots[rng() % std::size(kSpots)])),
                                         dir, upFor(rng, dir), fov, aspect,
                                         sd::chance(rng, 0.2) ? grid.voxelSize() * sd::uniform(rng, 0.5, 20) : kInf);
                if ((fov < 2 || aspect < 0.1) && sd::chance(rng, 0.7)) aimAtObject(rng, cam, objects);
                checkFrame(culler, objects, cam,
                           frameLabel("fov " + std::to_string(fov) + " aspect " + std::to_string(aspect), seed, camera++), tally);
            }
    }
    tally.print("extreme fields of view and aspects");
    REQUIRE(tally.frames == 40 * 10);
    REQUIRE(tally.misses == 0);
    REQUIRE(tally.failedFrames == 0);
}
