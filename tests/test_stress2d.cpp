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
#include "ExactVisibility2D.hpp"
#include "RandomScenes2D.hpp"

#include "rgvc/dynamics/Culler.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

using namespace rgvc;
namespace ref = rgvc::reference;
namespace sd = rgvc::reference::scene_detail;

namespace {

constexpr double kPi = 3.141592653589793;
const double kInf = std::numeric_limits<double>::infinity();

struct Tally {
    std::size_t frames = 0, framesWithVisible = 0, misses = 0, failedFrames = 0, sumVisible = 0, sumPvs = 0;
    std::size_t fallbacks = 0, unshifted = 0;

    void print(const std::string& name) const {
        std::ostringstream os;
        os.precision(4);
        os << "[stress2d] " << name << ": " << frames << " frames (" << framesWithVisible << " with something visible, "
           << fallbacks << " camera-outside fallbacks), " << misses << " misses; pooled |PVS|/|visible| = "
           << (sumVisible ? double(sumPvs) / double(sumVisible) : 0.0);
        if (unshifted) os << "; " << unshifted << " frames checked unshifted";
        os << "\n";
        std::cout << os.str() << std::flush;
    }
};

std::string saveScene(const std::string& json, const std::string& label) {
    std::string name = "rgvc-stress2d-";
    for (char ch : label) {
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

/// x - shift, when that difference is exact (Sterbenz: same sign, within a factor of two; or shift 0).
bool exactDifference(double x, double shift, double& out) {
    out = x - shift;
    if (shift == 0) return true;
    const double a = std::abs(x), b = std::abs(shift);
    return (x > 0) == (shift > 0) && a >= 0.5 * b && a <= 2 * b;
}

/// The scene moved by -shift for the reference, when every coordinate moves exactly (false otherwise).
///
/// The reference's tolerance is 1e-12 of the largest coordinate magnitude: 1e-6 world units for a scene
/// at 1e6, a thousandth of a 1e-3 voxel, so it would call objects that miss the view region by less than
/// that "visible" (the culler, working in voxel units, is far more precise). Moved next to the origin
/// *exactly*, the scene is the same geometric problem, and the reference's tolerance shrinks with it.
bool shiftedForReference(const Vec2& shift, std::vector<Shape<2>>& shapes, Camera2& cam) {
    bool exact = true;
    auto move = [&](Vec2& p) {
        Vec2 q;
        for (int a = 0; a < 2; ++a) exact = exactDifference(p[a], shift[a], q[a]) && exact;
        p = q;
    };
    for (Shape<2>& s : shapes)
        std::visit(
            [&](auto& x) {
                using T = std::decay_t<decltype(x)>;
                if constexpr (std::is_same_v<T, Ball<2>>) move(x.center);
                else if constexpr (std::is_same_v<T, Box<2>>) move(x.min), move(x.max);
                else
                    for (Vec2& q : x.points) move(q);
            },
            s);
    move(cam.position);
    return exact;
}

/// Culls `cam` on `culler` (which holds exactly `objects`) and compares with the reference, computed on
/// the scene moved by -referenceShift where that is exact (see shiftedForReference).
void checkFrame(Culler2D& culler, const std::vector<ObjectDesc<2>>& objects, const Camera2& cam, const std::string& label,
                Tally& tally, const Vec2& referenceShift = Vec2(0.0)) {
    std::vector<Shape<2>> shapes = ref::shapesOf(objects);
    Camera2 refCam = cam;
    if (referenceShift != Vec2(0.0) && !shiftedForReference(referenceShift, shapes, refCam)) {
        shapes = ref::shapesOf(objects);
        refCam = cam;
        ++tally.unshifted;
    }
    ref::ExactStats stats;
    const std::vector<bool> visible = ref::exactVisible2D(shapes, refCam, {}, &stats);
    for (Vec2& w : stats.witness) w += cam.position - refCam.position; // back to the culler's coordinates
    const CullResult& result = culler.cull(cam);
    const std::vector<ObjectId>& pvs = result.pvs;

    std::size_t nVisible = 0;
    std::vector<std::size_t> missed;
    for (std::size_t i = 0; i < objects.size(); ++i) {
        nVisible += visible[i];
        if (visible[i] && !std::binary_search(pvs.begin(), pvs.end(), objects[i].id)) missed.push_back(i);
    }
    std::vector<ObjectId> known;
    for (const ObjectDesc<2>& o : objects) known.push_back(o.id);
    std::sort(known.begin(), known.end());
    const bool sortedUnique = std::adjacent_find(pvs.begin(), pvs.end(), std::greater_equal<ObjectId>()) == pvs.end();
    const bool allKnown = std::includes(known.begin(), known.end(), pvs.begin(), pvs.end());

    ++tally.frames;
    tally.fallbacks += result.stats.fallback != Fallback::None;
    if (nVisible > 0) {
        ++tally.framesWithVisible;
        tally.sumVisible += nVisible;
        tally.sumPvs += pvs.size();
    }
    if (missed.empty() && sortedUnique && allKnown) return;

    tally.misses += missed.size();
    if (++tally.failedFrames > 3) return; // three full reports are plenty; the count says the rest
    std::ostringstream os;
    os.precision(17);
    os << label << ": " << missed.size() << " visible object(s) missing from the PVS (" << pvs.size() << " reported, "
       << nVisible << " visible, fallback " << toString(result.stats.fallback) << ")\n";
    for (std::size_t i : missed) {
        const Vec2 w = stats.witness[i];
        const Vec2 wl = culler.grid().toLocal(w);
        const IVec2 v = culler.grid().voxelOf(w);
        const VoxelState s = culler.voxelState(v);
        os << "  missed id " << objects[i].id << " (index " << i << "), seen at world (" << w.x << ", " << w.y
           << ") = voxel units (" << wl.x << ", " << wl.y << "), voxel (" << v.x << ", " << v.y << ") inGrid=" << s.inGrid
           << " opaque=" << s.opaque << " occluded=" << s.occluded << " visited=" << s.visited << " hasIds=" << s.hasIds << "\n";
    }
    const Vec2 cl = culler.grid().toLocal(cam.position);
    os << "camera at voxel units (" << cl.x << ", " << cl.y << "), direction (" << cam.direction.x << ", "
       << cam.direction.y << "), fov " << cam.fovDeg << "\n";
    const std::string json = ref::toJson(culler.grid(), objects, cam);
    const std::string path = saveScene(json, label);
    if (!path.empty()) os << "scene written to " << path << " (replay: rgvc cull " << path << ")";
    else os << "scene:\n" << json;
    INFO(os.str());
    if (!sortedUnique) FAIL_CHECK("the PVS is not sorted ascending without duplicates");
    if (!allKnown) FAIL_CHECK("the PVS holds an id that is not in the culler");
    if (!missed.empty()) FAIL_CHECK("culler missed a visible object");
}

/// A culler holding `objects`.
Culler2D makeCuller(const GridGeometry2& grid, const std::vector<ObjectDesc<2>>& objects) {
    Culler2D culler(grid);
    for (const ObjectDesc<2>& o : objects) culler.addObject(o);
    return culler;
}

bool isValid(const Shape<2>& s) {
    Shape<2> copy = s;
    try {
        validateShape<2>(copy, "stress");
        return true;
    } catch (const InvalidInput&) {
        return false;
    }
}

/// Appends `shape` with a fresh id (some ids beyond 32 bits); drops shapes that rounding made invalid.
void push(std::vector<ObjectDesc<2>>& objects, const Shape<2>& shape, std::mt19937_64& rng) {
    if (!isValid(shape)) return;
    ObjectDesc<2> o;
    o.id = ObjectId(objects.size()) * 11 + 5 + (objects.size() % 4 == 1 ? (ObjectId(1) << 41) : 0);
    o.shape = shape;
    o.isStatic = sd::chance(rng, 0.5);
    o.maxSpeed = o.isStatic ? 0.0 : 1.0;
    objects.push_back(o);
}

/// `count` random objects of the RandomScenes2D mixture (snapped: every coordinate on voxel faces).
void addRandomObjects(std::mt19937_64& rng, const GridGeometry2& grid, bool snapped, int count,
                      std::vector<ObjectDesc<2>>& objects) {
    const sd::Placer pl{grid};
    const Vec2 r = Vec2(grid.resolution());
    std::vector<Shape<2>> shapes;
    while (int(shapes.size()) < count) {
        Vec2 c{sd::uniform(rng, -0.1 * r.x, 1.1 * r.x), sd::uniform(rng, -0.1 * r.y, 1.1 * r.y)};
        sd::addObjects(rng, pl, snapped, c, std::min(r.x, r.y) / 3, shapes);
    }
    shapes.resize(std::size_t(count));
    for (const Shape<2>& s : shapes) push(objects, s, rng);
}

/// A grid whose voxel faces are exact doubles: dyadic voxel size, origin a multiple of it.
GridGeometry2 exactGrid(std::mt19937_64& rng, int minRes, int maxRes) {
    static const std::vector<double> sizes = {1.0, 0.5, 0.25, 2.0, 0.125, 4.0};
    const double d = sd::pick(rng, sizes);
    const IVec2 res{sd::uniformInt(rng, minRes, maxRes), sd::uniformInt(rng, minRes, maxRes)};
    const Vec2 origin = Vec2{sd::uniformInt(rng, -64, 64), sd::uniformInt(rng, -64, 64)} * d;
    return GridGeometry2(origin, d, res);
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

Camera2 makeCamera(const Vec2& pos, const Vec2& dir, double fov, double far = kInf) {
    Camera2 c;
    c.position = pos;
    c.direction = dir;
    c.fovDeg = fov;
    c.far = far;
    return c;
}

Vec2 rotated(const Vec2& v, double rad) {
    const double c = std::cos(rad), s = std::sin(rad);
    return {c * v.x - s * v.y, s * v.x + c * v.y};
}

std::string where(const std::string& name, std::uint64_t seed, int camera) {
    return name + ", seed " + std::to_string(seed) + ", camera " + std::to_string(camera);
}

} // namespace

TEST_CASE("stress2d: cameras on voxel corners, faces and grid bounds looking along axes and diagonals", "[stress]") {
    Tally tally;
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
            checkFrame(culler, objects, cam, where(std::string("on-grid spots (") + spotName(spot) + ")", seed, camera++), tally);
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
    Tally tally;
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
        push(objects, Box<2>{pl.world(glm::min(b0, b1)), pl.world(glm::max(b0, b1))}, rng);
        const double radius = sd::pick(rng, std::vector<double>{0.5, 2, 1e-3, 0.1});
        push(objects, Ball<2>{pl.world(q + out * radius), pl.length(radius)}, rng);
        const double tri = sd::pick(rng, std::vector<double>{1, 0.01, 4});
        push(objects, ConvexPolygon{{pl.world(q), pl.world(q + (out + e) * tri), pl.world(q + (out - e) * tri)}}, rng);
        addRandomObjects(rng, grid, sd::chance(rng, 0.5), sd::uniformInt(rng, 0, 12), objects);

        Culler2D culler = makeCuller(grid, objects);
        const Camera2 cam = makeCamera(pl.world(p), dir, fov);
        checkFrame(culler, objects, cam,
                   where(std::string("grazing edge (camera on ") + spotName(spot) + ", fov " + std::to_string(fov) + ")", seed, 0),
                   tally);
        // The same objects with the other edge on q (they now lie inside the wedge or beyond it).
        const Camera2 other = makeCamera(pl.world(p), rotated(toQ, ccwEdge ? half : -half), fov);
        checkFrame(culler, objects, other, where("grazing edge, other side", seed, 1), tally);
    }
    tally.print("grazing wedge edges");
    REQUIRE(tally.frames > 3000);
    REQUIRE(tally.misses == 0);
    REQUIRE(tally.failedFrames == 0);
}

TEST_CASE("stress2d: object faces on voxel boundaries and one ulp off them", "[stress]") {
    Tally tally;
    auto nudge = [](std::mt19937_64& rng, double v) {
        const int m = sd::uniformInt(rng, 0, 2);
        return m == 0 ? v : std::nextafter(v, m == 1 ? kInf : -kInf);
    };
    for (std::uint64_t seed = 7001; seed <= 7800; ++seed) {
        std::mt19937_64 rng(seed);
        const GridGeometry2 grid = exactGrid(rng, 6, 32);
        std::vector<ObjectDesc<2>> snapped, nudged;
        addRandomObjects(rng, grid, true, sd::uniformInt(rng, 2, 25), snapped);
        for (const ObjectDesc<2>& o : snapped) {
            ObjectDesc<2> n = o;
            if (auto* b = std::get_if<Box<2>>(&n.shape)) {
                for (int a = 0; a < 2; ++a) {
                    b->min[a] = nudge(rng, b->min[a]);
                    b->max[a] = nudge(rng, b->max[a]);
                }
            } else if (auto* c = std::get_if<Ball<2>>(&n.shape)) {
                c->center = {nudge(rng, c->center.x), nudge(rng, c->center.y)};
                c->radius = nudge(rng, c->radius);
            } else {
                for (Vec2& pt : std::get<ConvexPolygon>(n.shape).points) pt = {nudge(rng, pt.x), nudge(rng, pt.y)};
            }
            if (isValid(n.shape)) nudged.push_back(n);
        }
        Culler2D exact = makeCuller(grid, snapped), off = makeCuller(grid, nudged);
        for (int c = 0; c < 4; ++c) {
            const Spot spot = kSpots[rng() % std::size(kSpots)];
            const Camera2 cam = makeCamera(grid.toWorld(spotLocal(rng, grid.resolution(), spot)), axisDirection(rng),
                                           sd::pick(rng, kAxisFovs));
            checkFrame(exact, snapped, cam, where("faces on voxel boundaries", seed, c), tally);
            checkFrame(off, nudged, cam, where("faces one ulp off voxel boundaries", seed, c), tally);
        }
    }
    tally.print("faces on and next to voxel boundaries");
    REQUIRE(tally.frames == 800 * 8);
    REQUIRE(tally.misses == 0);
    REQUIRE(tally.failedFrames == 0);
}

TEST_CASE("stress2d: objects much smaller than a voxel and much larger than the grid", "[stress]") {
    Tally tally;
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
            if (kind == 0) push(objects, Ball<2>{pl.world(at), pl.length(s)}, rng);
            else if (kind == 1) push(objects, Box<2>{pl.world(at - s), pl.world(at + s)}, rng);      // straddles
            else if (kind == 2) push(objects, Box<2>{pl.world(at), pl.world(at + Vec2{s, 2 * s})}, rng); // from the corner
            else push(objects, ConvexPolygon{{pl.world(at), pl.world(at + Vec2{s, 0}), pl.world(at + Vec2{0, s})}}, rng);
        }
        const std::size_t tiny = objects.size();
        // Huge objects: far larger than the grid, partly covering it (walls, discs, slabs), or enclosing it.
        for (int i = 0, n = tinyScene ? 0 : sd::uniformInt(rng, 1, 3); i < n; ++i) {
            const double big = sd::logUniform(rng, 10, 1e4) * std::max(r.x, r.y);
            const int kind = sd::uniformInt(rng, 0, 3);
            const double cut = std::floor(sd::uniform(rng, 0, r.x)); // on a voxel face
            if (kind == 0) push(objects, Box<2>{pl.world({-big, -big}), pl.world({cut, big})}, rng);
            else if (kind == 1) push(objects, Ball<2>{pl.world({r.x + big - cut, 0.5 * r.y}), pl.length(big)}, rng);
            else if (kind == 2) push(objects, ConvexPolygon{{pl.world({cut, -big}), pl.world({big, big}), pl.world({cut, big})}}, rng);
            else push(objects, Box<2>{pl.world({-big, cut}), pl.world({big, cut + 1})}, rng); // a slab one voxel thick
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
            checkFrame(culler, objects, cam, where("tiny and huge objects", seed, c), tally);
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
    Tally tally;
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
            checkFrame(culler, objects, cam, where("large offsets and tiny voxels", seed, c), tally, f.origin);
        }
    }
    tally.print("large offsets, tiny voxels");
    REQUIRE(tally.frames == 800 * 4);
    REQUIRE(tally.misses == 0);
    REQUIRE(tally.failedFrames == 0);
}

TEST_CASE("stress2d: extreme fields of view", "[stress]") {
    Tally tally;
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
            checkFrame(culler, objects, cam, where("fov " + std::to_string(fov), seed, camera++), tally);
            // The same fov with a finite far a few voxels away.
            cam.far = grid.voxelSize() * sd::uniform(rng, 0.5, 20);
            checkFrame(culler, objects, cam, where("fov " + std::to_string(fov) + " with far", seed, camera++), tally);
        }
    }
    tally.print("extreme fields of view");
    REQUIRE(tally.frames == 600 * 12);
    REQUIRE(tally.misses == 0);
    REQUIRE(tally.failedFrames == 0);
}
