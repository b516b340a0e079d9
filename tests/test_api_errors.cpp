// Every public entry point against bad input: GridGeometry, Culler2D (constructor, addObject,
// updateObject, removeObject, cull), validateShape, validateCamera, parseScene and loadScene.
//
// Each rejection must be an rgvc::InvalidInput (library) or rgvc::SceneError (scene files) naming the
// field, with what() = "<field>: <problem>" (SceneError: "<file>: <field>: <problem>", one line). And a
// rejected call must leave its culler exactly as it was (Error.hpp's strong guarantee): the PVS and the
// stats of several cameras, and the state of every voxel, are compared before and after.
#include "CullerTestSupport.hpp"
#include "SceneFile.hpp"
#include "reference/TestMeshes.hpp"

#include "rgvc/dynamics/Culler.hpp"
#include "rgvc/grid/Camera.hpp"
#include "rgvc/grid/GridGeometry.hpp"
#include "rgvc/grid/Shapes.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <variant>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

using namespace rgvc;
using rgvc::culler_test::makeCamera;

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();
const std::vector<double> kNonFinite = {kNaN, kInf, -kInf};

/// Runs f, which must throw InvalidInput; checks the "<field>: <problem>" form and returns the field.
std::string fieldOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const InvalidInput& e) {
        const std::string what = e.what();
        CHECK(what.rfind(e.field() + ": ", 0) == 0);
        CHECK(what.size() > e.field().size() + 2);
        return e.field();
    } catch (const std::exception& e) {
        FAIL_CHECK("not an InvalidInput: " << e.what());
        return "<wrong exception>";
    }
    return "<accepted>";
}

/// Everything observable about a culler: PVS and stats (less the wall time) of a few cameras, and the
/// state of every voxel (and a margin around the grid) after each.
struct Snapshot {
    std::size_t objectCount = 0;
    std::vector<std::vector<ObjectId>> pvs;
    std::vector<std::uint64_t> numbers;
    std::vector<int> voxels;
    bool operator==(const Snapshot&) const = default;
};

const std::vector<Camera2>& probeCameras() {
    static const std::vector<Camera2> cams = {
        makeCamera({2, 16}, {1, 0}, 90),  makeCamera({16, 16}, {0, 1}, 360), makeCamera({31, 1}, {-1, 1}, 60, 20),
        makeCamera({-5, 16}, {1, 0}, 90), // outside the grid: the fallback path
    };
    return cams;
}

Snapshot snapshot(Culler2D& culler) {
    Snapshot s;
    s.objectCount = culler.objectCount();
    for (const Camera2& cam : probeCameras()) {
        const CullResult& r = culler.cull(cam);
        s.pvs.push_back(r.pvs);
        const CullStats& st = r.stats;
        s.numbers.insert(s.numbers.end(), {st.objectCount, st.pvsSize, st.layers, st.voxelsVisited, st.voxelsOccluded,
                                           st.occludersExtended, st.occluderVoxels, st.shadows, st.voxelsMarkedOccluded,
                                           std::uint64_t(st.earlyTermination), std::uint64_t(st.occlusionSkipped),
                                           std::uint64_t(st.fallback), st.objectsOutsideGrid});
        const IVec2 res = culler.grid().resolution();
        for (int y = -1; y <= res.y; ++y)
            for (int x = -1; x <= res.x; ++x) {
                const VoxelState v = culler.voxelState({x, y});
                s.voxels.push_back(v.inGrid | v.opaque << 1 | v.occluded << 2 | v.visited << 3 | v.occluder << 4 | v.hasIds << 5);
            }
    }
    return s;
}

/// A 32 x 32 culler with a few objects of every kind, some partly outside the grid.
Culler2D makeCuller() {
    Culler2D c(GridGeometry2({0, 0}, 1.0, {32, 32}));
    c.addObject({1, Ball<2>{{10, 10}, 2}, true, 0});
    c.addObject({2, Box<2>{{20, 5}, {22, 25}}, false, 1});
    c.addObject({3, ConvexPolygon{{{5, 20}, {8, 20}, {6, 24}}}, false, 0.5});
    c.addObject({4, Box<2>{{28, 28}, {40, 30}}, true, 0});
    c.addObject({ObjectId(1) << 50, Ball<2>{{26, 16}, 1}, false, 2});
    return c;
}

/// Shapes that validateShape must reject, with the field suffix it must name.
struct BadShape {
    Shape<2> shape;
    std::string field;
    const char* why;
};
std::vector<BadShape> badShapes() {
    std::vector<BadShape> v;
    for (double x : kNonFinite) {
        v.push_back({Ball<2>{{x, 5}, 1}, ".center", "non-finite centre x"});
        v.push_back({Ball<2>{{5, x}, 1}, ".center", "non-finite centre y"});
        v.push_back({Ball<2>{{5, 5}, x}, ".radius", "non-finite radius"});
        v.push_back({Box<2>{{x, 0}, {1, 1}}, ".min", "non-finite min"});
        v.push_back({Box<2>{{0, 0}, {1, x}}, ".max", "non-finite max"});
        v.push_back({ConvexPolygon{{{0, 0}, {1, 0}, {x, 1}}}, ".points", "non-finite point"});
    }
    v.push_back({Ball<2>{{5, 5}, 0}, ".radius", "zero radius"});
    v.push_back({Ball<2>{{5, 5}, -1}, ".radius", "negative radius"});
    v.push_back({Ball<2>{{5, 5}, -0.0}, ".radius", "negative zero radius"});
    v.push_back({Box<2>{{5, 5}, {5, 6}}, ".max", "zero width"});
    v.push_back({Box<2>{{5, 5}, {6, 5}}, ".max", "zero height"});
    v.push_back({Box<2>{{5, 5}, {4, 6}}, ".max", "min > max"});
    v.push_back({ConvexPolygon{}, ".points", "no points"});
    v.push_back({ConvexPolygon{{{0, 0}, {1, 0}}}, ".points", "two points"});
    v.push_back({ConvexPolygon{{{0, 0}, {1, 1}, {2, 2}}}, ".points", "collinear"});
    v.push_back({ConvexPolygon{{{1, 1}, {1, 1}, {1, 1}}}, ".points", "one point thrice"});
    v.push_back({ConvexPolygon{{{0, 0}, {2, 0}, {1, 0.5}, {1, 2}, {0, 2}}}, ".points", "not convex"});
    v.push_back({ConvexPolygon{{{0, 2}, {1, 2}, {1, 0.5}, {2, 0}, {0, 0}}}, ".points", "not convex, clockwise"});
    // A pentagram: every turn is to the left, but it winds twice.
    std::vector<Vec2> star;
    for (int i = 0; i < 5; ++i) {
        const double a = 2 * 3.141592653589793 * (2 * i) / 5;
        star.push_back({10 + 3 * std::cos(a), 10 + 3 * std::sin(a)});
    }
    v.push_back({ConvexPolygon{star}, ".points", "self-intersecting star"});
    return v;
}

/// Bitwise equality of two shapes (NaN coordinates included).
bool sameBits(const Shape<2>& a, const Shape<2>& b) {
    if (a.index() != b.index()) return false;
    auto bits = [](const Shape<2>& s) {
        std::vector<double> v;
        std::visit(
            [&](const auto& x) {
                using T = std::decay_t<decltype(x)>;
                if constexpr (std::is_same_v<T, Ball<2>>) v = {x.center.x, x.center.y, x.radius};
                else if constexpr (std::is_same_v<T, Box<2>>) v = {x.min.x, x.min.y, x.max.x, x.max.y};
                else
                    for (const Vec2& q : x.points) v.insert(v.end(), {q.x, q.y});
            },
            s);
        return v;
    };
    const std::vector<double> x = bits(a), y = bits(b);
    return x.size() == y.size() && (x.empty() || std::memcmp(x.data(), y.data(), x.size() * sizeof(double)) == 0);
}

/// Cameras that validateCamera must reject, with the field suffix it must name.
struct BadCamera {
    Camera2 camera;
    std::string field;
};
std::vector<BadCamera> badCameras() {
    const Camera2 good = makeCamera({2, 16}, {1, 0}, 90);
    std::vector<BadCamera> v;
    auto with = [&](auto mutate, const char* field) {
        Camera2 c = good;
        mutate(c);
        v.push_back({c, field});
    };
    for (double x : kNonFinite) {
        with([&](Camera2& c) { c.position.x = x; }, ".position");
        with([&](Camera2& c) { c.position.y = x; }, ".position");
        with([&](Camera2& c) { c.direction.x = x; }, ".direction");
        with([&](Camera2& c) { c.direction.y = x; }, ".direction");
        with([&](Camera2& c) { c.fovDeg = x; }, ".fov_deg");
    }
    with([](Camera2& c) { c.direction = {0, 0}; }, ".direction");
    with([](Camera2& c) { c.direction = {-0.0, 0}; }, ".direction");
    for (double fov : {0.0, -0.0, -1.0, -360.0, 360.5, 720.0, std::nextafter(360.0, 361.0), 1e300})
        with([&](Camera2& c) { c.fovDeg = fov; }, ".fov_deg");
    for (double far : {0.0, -0.0, -1.0, kNaN, -kInf}) with([&](Camera2& c) { c.far = far; }, ".far");
    return v;
}

} // namespace

TEST_CASE("GridGeometry rejects bad origins, voxel sizes and resolutions", "[errors]") {
    for (double x : kNonFinite) {
        CHECK(fieldOf([&] { GridGeometry2({x, 0}, 1, {4, 4}); }) == "grid.origin");
        CHECK(fieldOf([&] { GridGeometry2({0, x}, 1, {4, 4}); }) == "grid.origin");
        CHECK(fieldOf([&] { GridGeometry3({0, 0, x}, 1, {4, 4, 4}); }) == "grid.origin");
        CHECK(fieldOf([&] { GridGeometry2({0, 0}, x, {4, 4}); }) == "grid.voxel_size");
    }
    for (double d : {0.0, -0.0, -1.0, -1e-300})
        CHECK(fieldOf([&] { GridGeometry2({0, 0}, d, {4, 4}); }) == "grid.voxel_size");
    // Too small for the origin's magnitude (the far corner rounds onto the origin), or overflowing.
    CHECK(fieldOf([&] { GridGeometry2({1e6, 0}, std::numeric_limits<double>::denorm_min(), {4, 4}); }) == "grid.voxel_size");
    CHECK(fieldOf([&] { GridGeometry2({1e20, 0}, 1e-10, {4, 4}); }) == "grid.voxel_size");
    CHECK(fieldOf([&] { GridGeometry2({0, 0}, 1e308, {4, 4}); }) == "grid.voxel_size");
    CHECK(fieldOf([&] { GridGeometry2({1e308, 0}, 1e307, {100, 4}); }) == "grid.voxel_size");

    for (int bad : {0, -1, std::numeric_limits<std::int32_t>::min()}) {
        CHECK(fieldOf([&] { GridGeometry2({0, 0}, 1, {bad, 4}); }) == "grid.resolution");
        CHECK(fieldOf([&] { GridGeometry2({0, 0}, 1, {4, bad}); }) == "grid.resolution");
        CHECK(fieldOf([&] { GridGeometry3({0, 0, 0}, 1, {4, 4, bad}); }) == "grid.resolution");
    }
    // More than 2^31 - 1 voxels in all.
    CHECK(fieldOf([&] { GridGeometry2({0, 0}, 1, {65536, 32768}); }) == "grid.resolution");
    CHECK(fieldOf([&] { GridGeometry2({0, 0}, 1, {46341, 46341}); }) == "grid.resolution");
    CHECK(fieldOf([&] { GridGeometry2({0, 0}, 1, {std::numeric_limits<std::int32_t>::max(), 2}); }) == "grid.resolution");
    CHECK(fieldOf([&] { GridGeometry3({0, 0, 0}, 1, {2048, 1024, 1024}); }) == "grid.resolution");
    CHECK(fieldOf([&] { GridGeometry3({0, 0, 0}, 1, {65536, 65536, 65536}); }) == "grid.resolution");
    // The limits themselves are accepted (a geometry allocates nothing).
    CHECK_NOTHROW(GridGeometry2({0, 0}, 1, {std::numeric_limits<std::int32_t>::max(), 1}));
    CHECK_NOTHROW(GridGeometry2({0, 0}, 1, {46340, 46340}));
    CHECK_NOTHROW(GridGeometry3({0, 0, 0}, 1, {1290, 1290, 1290}));
    CHECK_NOTHROW(GridGeometry2({1e6, -1e6}, 1e-3, {4096, 4096}));
}

TEST_CASE("Culler2D's constructor rejects grids over 2^20 voxels per axis", "[errors]") {
    const std::int32_t limit = 1 << 20;
    CHECK(fieldOf([&] { Culler2D c(GridGeometry2({0, 0}, 1, {limit + 1, 4})); }) == "grid.resolution");
    CHECK(fieldOf([&] { Culler2D c(GridGeometry2({0, 0}, 1, {4, limit + 1})); }) == "grid.resolution");
    CHECK(fieldOf([&] { Culler2D c(GridGeometry2({0, 0}, 1, {std::numeric_limits<std::int32_t>::max(), 1})); }) == "grid.resolution");
    // Exactly 2^20 is accepted and culls (with a far limit: the traversal of such thin grids is slow).
    Culler2D wide(GridGeometry2({0, 0}, 1, {limit, 2}));
    wide.addObject({1, Box<2>{{10, 0}, {11, 2}}, true, 0});
    wide.addObject({2, Ball<2>{{20.5, 1}, 0.5}, true, 0});
    wide.addObject({3, Ball<2>{{5.5, 1}, 0.5}, true, 0});
    wide.addObject({4, Ball<2>{{limit - 0.5, 1}, 0.5}, true, 0});
    const std::vector<ObjectId> wpvs = wide.cull(makeCamera({5, 1}, {1, 0}, 90, 100)).pvs;
    CHECK(std::binary_search(wpvs.begin(), wpvs.end(), ObjectId(1)));
    CHECK(std::binary_search(wpvs.begin(), wpvs.end(), ObjectId(3)));
    CHECK_FALSE(std::binary_search(wpvs.begin(), wpvs.end(), ObjectId(4))); // beyond far
    Culler2D tall(GridGeometry2({0, 0}, 1, {1, limit}));
    tall.addObject({1, Box<2>{{0, 1000}, {1, 1001}}, true, 0});
    tall.addObject({2, Ball<2>{{0.5, 3.5}, 0.5}, true, 0});
    const std::vector<ObjectId> tpvs = tall.cull(makeCamera({0.5, 0.5}, {0, 1}, 10, 2000)).pvs;
    // The ball fills the 10-degree view (it spans 19 degrees at distance 3): the occlusion buffer hides
    // the box behind it.
    CHECK(tpvs == std::vector<ObjectId>{2});
}

TEST_CASE("Culler options: TBV limits are checked with their field", "[errors][tbv]") {
    const GridGeometry2 g({0, 0}, 1, {16, 16});
    auto withOptions = [&](auto change) {
        CullerOptions o;
        change(o);
        return fieldOf([&] { Culler2D c(g, o); });
    };
    CHECK(withOptions([](CullerOptions& o) { o.tbvMaxFrames = 0; }) == "options.tbvMaxFrames");
    CHECK(withOptions([](CullerOptions& o) { o.tbvMaxFrames = 65537; }) == "options.tbvMaxFrames");
    CHECK(withOptions([](CullerOptions& o) { o.tbvMaxGrowth = -1; }) == "options.tbvMaxGrowth");
    CHECK(withOptions([](CullerOptions& o) { o.tbvMaxGrowth = std::nan(""); }) == "options.tbvMaxGrowth");
    CHECK(withOptions([](CullerOptions& o) { o.tbvMaxGrowth = INFINITY; }) == "options.tbvMaxGrowth");
    CHECK(withOptions([](CullerOptions& o) { o.tbvDiscretization = TbvDiscretization(7); }) == "options.tbvDiscretization");
    CHECK(fieldOf([&] { Culler3D c(GridGeometry3({0, 0, 0}, 1, {4, 4, 4}), CullerOptions{.tbvMaxFrames = 0}); }) ==
          "options.tbvMaxFrames");
    // Limits themselves are accepted.
    CHECK(withOptions([](CullerOptions& o) { o.tbvMaxFrames = 65536; o.tbvMaxGrowth = 1e-9; }) == "<accepted>");
    // The image sizes: 0 rows of the traversal image is "from the view", negative or above 2048 is refused.
    CHECK(withOptions([](CullerOptions& o) { o.traversalImageRows = -1; }) == "options.traversalImageRows");
    CHECK(withOptions([](CullerOptions& o) { o.traversalImageRows = 2049; }) == "options.traversalImageRows");
    CHECK(withOptions([](CullerOptions& o) { o.occlusionBufferRows = -1; }) == "options.occlusionBufferRows");
    CHECK(withOptions([](CullerOptions& o) { o.traversalImageRows = 0; }) == "<accepted>");
    CHECK(withOptions([](CullerOptions& o) { o.traversalImageRows = 2048; }) == "<accepted>");

    // An empty placement query is a bad argument, refused before the frame starts.
    Culler2D culler(g);
    culler.addObject({1, Ball<2>{{8, 8}, 1}, false, 0.5});
    CHECK(fieldOf([&] { culler.cull(makeCamera({1.5, 1.5}, {1, 1}, 90, INFINITY), PlacementQuery<2>{}); }) == "placementOf");
}

TEST_CASE("Culler misuse: a moved-from culler and calls from inside the placement query are logic errors", "[errors]") {
    const GridGeometry3 g({0, 0, 0}, 1, {16, 16, 16});
    const Camera3 cam = makeCamera({1.5, 8.5, 8.5}, {1, 0, 0}, 60);
    // Moved from: every member says so, none crashes.
    Culler3D a(g);
    a.addObject({1, Ball<3>{{8, 8, 8}, 1}, false, 0.5});
    Culler3D b(std::move(a));
    auto movedFrom = [](auto&& call) {
        try {
            call();
        } catch (const std::logic_error& e) {
            return std::string(e.what()).find("moved from") != std::string::npos;
        }
        return false;
    };
    CHECK(movedFrom([&] { a.cull(cam); }));
    CHECK(movedFrom([&] { a.addObject({2, Ball<3>{{4, 4, 4}, 1}}); }));
    CHECK(movedFrom([&] { a.updateObject(1, Ball<3>{{4, 4, 4}, 1}); }));
    CHECK(movedFrom([&] { a.removeObject(1); }));
    CHECK(movedFrom([&] { (void)a.hasObject(1); }));
    CHECK(movedFrom([&] { (void)a.objectCount(); }));
    CHECK(movedFrom([&] { (void)a.lastResult(); }));
    CHECK(movedFrom([&] { (void)a.voxelState({1, 1, 1}); }));
    CHECK(movedFrom([&] { (void)a.grid(); }));
    CHECK(b.hasObject(1));
    a = Culler3D(g); // assigning a new culler makes the variable usable again
    CHECK(a.objectCount() == 0);

    // From inside the placement query: removing the object being asked for (it used to leave a ghost in
    // the PVS for good) is refused; the frame completes, cull() rethrows, and the object is untouched.
    for (int what = 0; what < 4; ++what) {
        INFO("call " << what);
        Culler3D c(g);
        c.addObject({7, Ball<3>{{8, 8, 8}, 1}, false, 0.5});
        bool sawConst = false;
        const PlacementQuery<3> query = [&](ObjectId id) -> Shape<3> {
            sawConst = c.hasObject(id) && c.objectCount() == 1 && c.grid().resolution().x == 16; // allowed
            if (what == 0) c.removeObject(id);
            if (what == 1) c.updateObject(id, Ball<3>{{9, 8, 8}, 1});
            if (what == 2) c.addObject({8, Ball<3>{{4, 4, 4}, 1}});
            if (what == 3) c.cull(cam);
            return Ball<3>{{8, 8, 8}, 1};
        };
        c.cull(cam); // frame 1: object 7 is in the PVS, so frame 2 asks for it
        try {
            c.cull(cam, query);
            FAIL("no error");
        } catch (const std::logic_error& e) {
            CHECK(std::string(e.what()).find("placement query") != std::string::npos);
        }
        CHECK(sawConst);
        CHECK(c.hasObject(7));
        CHECK_FALSE(c.hasObject(8));
        CHECK(c.lastResult().pvs == std::vector<ObjectId>{7}); // reported conservatively (parked)
        c.cull(cam, [](ObjectId) -> Shape<3> { return Ball<3>{{8, 8, 8}, 1}; });
        CHECK(c.lastResult().pvs == std::vector<ObjectId>{7});
        c.removeObject(7); // outside the query: fine
        CHECK(c.cull(cam).pvs.empty());
    }
}

TEST_CASE("validateShape and validateCamera name the field under the caller's prefix", "[errors]") {
    for (const BadShape& b : badShapes()) {
        INFO(b.why);
        Shape<2> s = b.shape;
        CHECK(fieldOf([&] { validateShape<2>(s, "objects[7]"); }) == "objects[7]" + b.field);
        // Strong guarantee: a rejected shape is not half-normalised. (A clockwise polygon rejected after
        // it was reversed is a known issue, checked in "known issues" below.)
        if (std::string(b.why) != "not convex, clockwise") CHECK(sameBits(s, b.shape));
    }
    for (const BadCamera& b : badCameras()) {
        INFO("position (" << b.camera.position.x << ", " << b.camera.position.y << ") direction (" << b.camera.direction.x
                          << ", " << b.camera.direction.y << ") fov " << b.camera.fovDeg << " far " << b.camera.far);
        CHECK(fieldOf([&] { validateCamera<2>(b.camera); }) == "camera" + b.field);
        CHECK(fieldOf([&] { validateCamera<2>(b.camera, "camera_path[3]"); }) == "camera_path[3]" + b.field);
    }
    // 3D cameras: the 3D fov range and the 3D-only fields.
    Camera3 c3;
    c3.direction = {0, 0, 1};
    c3.fovDeg = 60;
    CHECK_NOTHROW(validateCamera<3>(c3));
    for (double fov : {0.0, 180.0, 200.0, kNaN}) {
        Camera3 c = c3;
        c.fovDeg = fov;
        CHECK(fieldOf([&] { validateCamera<3>(c); }) == "camera.fov_deg");
    }
    for (double aspect : {0.0, -1.0, kNaN, kInf}) {
        Camera3 c = c3;
        c.aspect = aspect;
        CHECK(fieldOf([&] { validateCamera<3>(c); }) == "camera.aspect");
    }
    Camera3 badUp = c3;
    badUp.up = {0, kNaN, 0};
    CHECK(fieldOf([&] { validateCamera<3>(badUp); }) == "camera.up");
    // Valid edge values are accepted.
    CHECK_NOTHROW(validateCamera<2>(makeCamera({0, 0}, {1, 0}, 360)));
    CHECK_NOTHROW(validateCamera<2>(makeCamera({0, 0}, {1, 0}, 1e-9)));
    CHECK_NOTHROW(validateCamera<2>(makeCamera({0, 0}, {1, 0}, 90, 1e-300)));
    CHECK_NOTHROW(validateCamera<2>(makeCamera({1e300, -1e300}, {-1e-3, 1e3}, 90)));
    // Any non-zero length, including lengths whose square over- or underflows.
    CHECK_NOTHROW(validateCamera<2>(makeCamera({0, 0}, {1e300, 1e300}, 90)));
    CHECK_NOTHROW(validateCamera<2>(makeCamera({0, 0}, {1e-200, 0}, 90)));
    CHECK_NOTHROW(validateCamera<2>(makeCamera({0, 0}, {0, -std::numeric_limits<double>::denorm_min()}, 90)));
    // A polygon that runs along a line and back (behind a repeated point) is refused, not treated as
    // its hull (found by fuzz_culler2d: the culler and the reference disagreed on its interior).
    Shape<2> doubled = ConvexPolygon{{{1.5, 1.5}, {1.5, 1.5}, {-2.5, 1.5}, {1.5, 1.5}, {5, 1.5}, {21.25, 45.25}}};
    CHECK(fieldOf([&] { validateShape<2>(doubled, "p"); }) == "p.points");
    // Repeated points alone are dropped.
    Shape<2> repeated = ConvexPolygon{{{0, 0}, {0, 0}, {4, 0}, {4, 3}, {0, 0}}};
    validateShape<2>(repeated, "p");
    CHECK(std::get<ConvexPolygon>(repeated).points.size() == 3);
}

TEST_CASE("Culler2D::addObject rejects bad objects and changes nothing", "[errors]") {
    Culler2D culler = makeCuller();
    const Snapshot before = snapshot(culler);
    for (const BadShape& b : badShapes()) {
        INFO(b.why);
        CHECK(fieldOf([&] { culler.addObject({77, b.shape, false, 1}); }) == "object 77" + b.field);
        CHECK_FALSE(culler.hasObject(77));
    }
    for (double speed : {-1.0, -1e-300, kNaN, kInf, -kInf})
        CHECK(fieldOf([&] { culler.addObject({77, Ball<2>{{5, 5}, 1}, false, speed}); }) == "object 77.max_speed");
    for (double inset : {-1.0, -1e-300, kNaN, kInf, -kInf})
        CHECK(fieldOf([&] { culler.addObject({77, Ball<2>{{5, 5}, 1}, false, 1, inset}); }) == "object 77.occluder_inset");
    // Duplicate ids, whatever the new shape (valid or not).
    CHECK(fieldOf([&] { culler.addObject({1, Ball<2>{{5, 5}, 1}, true, 0}); }) == "object 1.id");
    CHECK(fieldOf([&] { culler.addObject({ObjectId(1) << 50, Box<2>{{0, 0}, {1, 1}}, false, 0}); }) ==
          "object " + std::to_string(ObjectId(1) << 50) + ".id");
    CHECK(fieldOf([&] { culler.addObject({2, Ball<2>{{5, 5}, -1}, true, 0}); }).rfind("object 2.", 0) == 0);
    CHECK_FALSE(culler.hasObject(77));
    CHECK(snapshot(culler) == before);
}

TEST_CASE("Culler2D::updateObject rejects unknown ids and bad shapes and changes nothing", "[errors]") {
    Culler2D culler = makeCuller();
    const Snapshot before = snapshot(culler);
    CHECK(fieldOf([&] { culler.updateObject(99, Ball<2>{{5, 5}, 1}); }) == "object 99.id");
    CHECK(fieldOf([&] { culler.updateObject(99, Ball<2>{{5, 5}, -1}); }) == "object 99.id");
    for (ObjectId id : {ObjectId(1), ObjectId(2), ObjectId(3), ObjectId(1) << 50}) {
        for (const BadShape& b : badShapes()) {
            INFO("id " << id << ": " << b.why);
            CHECK(fieldOf([&] { culler.updateObject(id, b.shape); }) == "object " + std::to_string(id) + b.field);
        }
    }
    CHECK(snapshot(culler) == before);
    // A removed id is unknown again.
    culler.removeObject(3);
    CHECK(fieldOf([&] { culler.updateObject(3, Ball<2>{{5, 5}, 1}); }) == "object 3.id");
}

TEST_CASE("Culler2D::removeObject rejects unknown ids and changes nothing", "[errors]") {
    Culler2D culler = makeCuller();
    const Snapshot before = snapshot(culler);
    for (ObjectId id : {ObjectId(0), ObjectId(5), ObjectId(99), ~ObjectId(0), (ObjectId(1) << 50) + 1})
        CHECK(fieldOf([&] { culler.removeObject(id); }) == "object " + std::to_string(id) + ".id");
    CHECK(snapshot(culler) == before);
    culler.removeObject(2);
    // Removals clear the brick tree lazily (BrickPyramid.hpp): the first culls after one visit the
    // bricks left empty and clear them, so the answer is compared once they have.
    snapshot(culler);
    const Snapshot removed = snapshot(culler);
    CHECK(fieldOf([&] { culler.removeObject(2); }) == "object 2.id"); // twice
    CHECK(snapshot(culler) == removed);
}

TEST_CASE("Culler2D::cull rejects bad cameras and keeps the last result", "[errors]") {
    Culler2D culler = makeCuller();
    const Snapshot before = snapshot(culler);
    const CullResult last = culler.lastResult();
    for (const BadCamera& b : badCameras()) {
        INFO("position (" << b.camera.position.x << ", " << b.camera.position.y << ") direction (" << b.camera.direction.x
                          << ", " << b.camera.direction.y << ") fov " << b.camera.fovDeg << " far " << b.camera.far);
        CHECK(fieldOf([&] { culler.cull(b.camera); }) == "camera" + b.field);
        // lastResult is untouched, wall time included.
        CHECK(culler.lastResult().pvs == last.pvs);
        CHECK(culler.lastResult().stats.cullMs == last.stats.cullMs);
        CHECK(culler.lastResult().stats.voxelsVisited == last.stats.voxelsVisited);
    }
    CHECK(snapshot(culler) == before);
}

TEST_CASE("Culler2D accepts extreme but valid input and keeps the PVS well formed", "[errors]") {
    // Valid by every rule: finite, positive, in range. None of it may crash, hang or trip a sanitizer.
    Culler2D culler = makeCuller();
    std::vector<ObjectDesc<2>> extreme = {
        {100, Ball<2>{{16, 16}, 1e-300}, true, 0},
        {101, Ball<2>{{1e300, -1e300}, 1e300}, false, 1e300},
        {102, Box<2>{{-1e300, -1e300}, {1e300, 3}}, true, 0},
        {103, Box<2>{{16, 16}, {std::nextafter(16.0, 17.0), std::nextafter(16.0, 17.0)}}, true, 0},
        {104, ConvexPolygon{{{0, 0}, {1e-150, 0}, {0, 1e-150}}}, true, 0},
        {105, ConvexPolygon{{{-1e150, -1e150}, {1e150, -1e150}, {0, 1e150}}}, true, 0},
        {106, Ball<2>{{std::numeric_limits<double>::max(), 0}, std::numeric_limits<double>::max()}, true, 0},
        {std::numeric_limits<ObjectId>::max(), Ball<2>{{16, 16}, 3}, false, std::numeric_limits<double>::max()},
    };
    for (const ObjectDesc<2>& o : extreme) {
        INFO("object " << o.id);
        CHECK_NOTHROW(culler.addObject(o));
    }
    const std::vector<Camera2> cams = {
        makeCamera({16, 16}, {1, 0}, 360),
        makeCamera({16, 16}, {1e-3, -1e3}, 1e-9),
        makeCamera({1e300, 1e300}, {-1, -1}, 90),
        makeCamera({-1e300, 16}, {1, 0}, 359.999999),
        makeCamera({16, 16}, {1e150, 1e150}, 180, 1e-300),
        makeCamera({16, 16}, {1e300, -1e300}, 90),
        makeCamera({16, 16}, {std::numeric_limits<double>::denorm_min(), 0}, 45),
        makeCamera({16, 16}, {-1e-150, 1e-150}, 90),
        makeCamera({16, 16}, {-1, 0}, 180, 1e300),
        makeCamera({std::numeric_limits<double>::max(), 0}, {-1, 0}, 360),
    };
    for (const Camera2& cam : cams) {
        INFO("camera (" << cam.position.x << ", " << cam.position.y << ") dir (" << cam.direction.x << ", "
                        << cam.direction.y << ") fov " << cam.fovDeg << " far " << cam.far);
        std::vector<ObjectId> pvs;
        CHECK_NOTHROW(pvs = culler.cull(cam).pvs);
        CHECK(std::adjacent_find(pvs.begin(), pvs.end(), std::greater_equal<ObjectId>()) == pvs.end());
        for (ObjectId id : pvs) CHECK(culler.hasObject(id));
    }
    for (const ObjectDesc<2>& o : extreme) CHECK_NOTHROW(culler.updateObject(o.id, Ball<2>{{8, 8}, 0.5}));
    for (const ObjectDesc<2>& o : extreme) CHECK_NOTHROW(culler.removeObject(o.id));
    // Back to the original five: the same answers as a fresh culler.
    Culler2D fresh = makeCuller();
    snapshot(culler); // the bricks the removals left empty are cleared on their first visit (BrickPyramid.hpp)
    CHECK(snapshot(culler) == snapshot(fresh));
}

// ---------------------------------------------------------------------------------------------------
// Scene files.

namespace {

const char* kBaseScene = R"({"dimensions": 2,
 "grid": {"origin": [0, 0], "voxel_size": 1, "resolution": [32, 32]},
 "camera": {"position": [2, 16], "direction": [1, 0], "fov_deg": 90, "far": 100},
 "objects": [
  {"id": 1, "shape": "circle", "center": [10, 10], "radius": 2},
  {"id": 2, "shape": "box", "min": [20, 5], "max": [22, 25], "velocity": [0.5, 0], "max_speed": 1},
  {"id": 3, "shape": "polygon", "points": [[5, 20], [8, 20], [6, 24]]}
 ]})";

/// kBaseScene with the first occurrence of `from` replaced by `to` (which must be there).
std::string mutated(const std::string& from, const std::string& to) {
    std::string s = kBaseScene;
    const std::size_t at = s.find(from);
    REQUIRE(at != std::string::npos);
    return s.replace(at, from.size(), to);
}

/// Parses text that must be rejected with a SceneError; checks its form and returns the field.
std::string sceneFieldOf(const std::string& text) {
    try {
        parseScene(text, "api.json");
    } catch (const SceneError& e) {
        const std::string what = e.what();
        CHECK(what.find('\n') == std::string::npos);
        CHECK(e.file() == "api.json");
        CHECK(what.rfind("api.json: " + e.field() + ": ", 0) == 0);
        CHECK_FALSE(e.problem().empty());
        return e.field();
    } catch (const std::exception& e) {
        FAIL_CHECK("not a SceneError: " << e.what());
        return "<wrong exception>";
    }
    return "<accepted>";
}

} // namespace

TEST_CASE("parseScene rejects bad numbers, sizes, ranges and ids with their field", "[errors]") {
    REQUIRE_NOTHROW(parseScene(kBaseScene, "api.json"));
    struct Case {
        std::string from, to, field;
    };
    const std::vector<Case> cases = {
        // JSON has no NaN or infinity: the literals are syntax errors (a position), 1e999 overflows (a field).
        {"\"voxel_size\": 1", "\"voxel_size\": NaN", "line"},
        {"\"voxel_size\": 1", "\"voxel_size\": Infinity", "line"},
        {"\"voxel_size\": 1", "\"voxel_size\": 1e999", "grid.voxel_size"},
        {"\"voxel_size\": 1", "\"voxel_size\": -1e999", "grid.voxel_size"},
        {"\"voxel_size\": 1", "\"voxel_size\": 0", "grid.voxel_size"},
        {"\"voxel_size\": 1", "\"voxel_size\": -0.5", "grid.voxel_size"},
        {"\"voxel_size\": 1", "\"voxel_size\": \"1\"", "grid.voxel_size"},
        {"\"origin\": [0, 0]", "\"origin\": [1e999, 0]", "grid.origin[0]"},
        {"\"origin\": [0, 0]", "\"origin\": [0, null]", "grid.origin[1]"},
        {"\"origin\": [0, 0]", "\"origin\": [0]", "grid.origin"},
        {"\"resolution\": [32, 32]", "\"resolution\": [0, 32]", "grid.resolution[0]"},
        {"\"resolution\": [32, 32]", "\"resolution\": [32, -1]", "grid.resolution[1]"},
        {"\"resolution\": [32, 32]", "\"resolution\": [2.5, 32]", "grid.resolution[0]"},
        {"\"resolution\": [32, 32]", "\"resolution\": [3000000000, 1]", "grid.resolution[0]"},
        {"\"resolution\": [32, 32]", "\"resolution\": [1e300, 1]", "grid.resolution[0]"},
        {"\"resolution\": [32, 32]", "\"resolution\": [65536, 65536]", "grid.resolution"},
        {"\"resolution\": [32, 32]", "\"resolution\": [46341, 46341]", "grid.resolution"},
        {"\"resolution\": [32, 32]", "\"resolution\": [32]", "grid.resolution"},
        {"\"position\": [2, 16]", "\"position\": [1e999, 16]", "camera.position[0]"},
        {"\"position\": [2, 16]", "\"position\": [2, -1e999]", "camera.position[1]"},
        {"\"direction\": [1, 0]", "\"direction\": [0, 0]", "camera.direction"},
        {"\"direction\": [1, 0]", "\"direction\": [-0.0, 0.0]", "camera.direction"},
        {"\"direction\": [1, 0]", "\"direction\": [1e999, 0]", "camera.direction[0]"},
        {"\"fov_deg\": 90", "\"fov_deg\": 0", "camera.fov_deg"},
        {"\"fov_deg\": 90", "\"fov_deg\": -10", "camera.fov_deg"},
        {"\"fov_deg\": 90", "\"fov_deg\": 360.0000001", "camera.fov_deg"},
        {"\"fov_deg\": 90", "\"fov_deg\": 1e999", "camera.fov_deg"},
        {"\"far\": 100", "\"far\": 0", "camera.far"},
        {"\"far\": 100", "\"far\": -1", "camera.far"},
        {"\"far\": 100", "\"far\": 1e999", "camera.far"},
        {"\"center\": [10, 10]", "\"center\": [10, 1e999]", "objects[0].center[1]"},
        {"\"radius\": 2", "\"radius\": 0", "objects[0].radius"},
        {"\"radius\": 2", "\"radius\": -2", "objects[0].radius"},
        {"\"radius\": 2", "\"radius\": 1e999", "objects[0].radius"},
        {"\"min\": [20, 5]", "\"min\": [22, 5]", "objects[1].max"},
        {"\"max\": [22, 25]", "\"max\": [22, 5]", "objects[1].max"},
        {"\"velocity\": [0.5, 0]", "\"velocity\": [1e999, 0]", "objects[1].velocity[0]"},
        {"\"velocity\": [0.5, 0]", "\"velocity\": [1e308, 1e308]", "objects[1].velocity"},
        {"\"max_speed\": 1", "\"max_speed\": -1", "objects[1].max_speed"},
        {"\"max_speed\": 1", "\"max_speed\": 0.1", "objects[1].max_speed"},
        {"[[5, 20], [8, 20], [6, 24]]", "[[5, 20], [8, 20]]", "objects[2].points"},
        {"[[5, 20], [8, 20], [6, 24]]", "[[5, 20], [6, 20], [7, 20]]", "objects[2].points"},
        {"[[5, 20], [8, 20], [6, 24]]", "[[5, 20], [8, 20], [6, 1e999]]", "objects[2].points[2][1]"},
        {"[[5, 20], [8, 20], [6, 24]]", "[[0, 0], [2, 0], [1, 0.5], [1, 2], [0, 2]]", "objects[2].points"},
        {"\"id\": 2", "\"id\": 1", "objects[1].id"},
        {"\"id\": 1", "\"id\": -1", "objects[0].id"},
        {"\"id\": 1", "\"id\": 1.5", "objects[0].id"},
        {"\"id\": 1", "\"id\": 1e999", "objects[0].id"},
        {"\"id\": 1", "\"id\": 18446744073709551615", "objects[0].id"},
        {"\"shape\": \"circle\"", "\"shape\": \"hexagon\"", "objects[0].shape"},
        {"\"shape\": \"circle\"", "\"shape\": \"sphere\"", "objects[0].shape"},
        {"\"dimensions\": 2", "\"dimensions\": 4", "dimensions"},
        {"\"dimensions\": 2", "\"dimensions\": 3", "grid.origin"},
    };
    for (const Case& c : cases) {
        INFO(c.from << " -> " << c.to);
        const std::string field = sceneFieldOf(mutated(c.from, c.to));
        if (c.field == "line") CHECK(field.rfind("line ", 0) == 0);
        else CHECK(field == c.field);
    }
    CHECK(sceneFieldOf("") .rfind("line ", 0) == 0);
    CHECK(sceneFieldOf("[]") == "(root)");
}

TEST_CASE("a 2D scene over 2^20 voxels per axis parses, Culler2D rejects its grid", "[errors]") {
    // The file format allows it (3D grids may be that wide); the 2D culler's limit names the field.
    const Scene s = parseScene(mutated("\"resolution\": [32, 32]", "\"resolution\": [1048577, 2]"), "api.json");
    const SceneData2* d = s.as<2>();
    REQUIRE(d != nullptr);
    CHECK(fieldOf([&] { Culler2D c(d->grid); }) == "grid.resolution");
}

TEST_CASE("loadScene names the file and the field", "[errors]") {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "rgvc_test_api_errors";
    std::filesystem::create_directories(dir);
    auto fieldOfFile = [](const std::string& path) -> std::string {
        try {
            loadScene(path);
        } catch (const SceneError& e) {
            CHECK(e.file() == path);
            CHECK(std::string(e.what()).rfind(path + ": " + e.field() + ": ", 0) == 0);
            return e.field();
        } catch (const std::exception& e) {
            FAIL_CHECK("not a SceneError: " << e.what());
        }
        return "<accepted>";
    };
    CHECK(fieldOfFile((dir / "does-not-exist.json").string()) == "file");
    CHECK(fieldOfFile(dir.string()) == "file");
    const std::string bad = (dir / "bad-radius.json").string();
    {
        std::ofstream f(bad);
        f << mutated("\"radius\": 2", "\"radius\": -2");
    }
    CHECK(fieldOfFile(bad) == "objects[0].radius");
    const std::string good = (dir / "good.json").string();
    {
        std::ofstream f(good);
        f << kBaseScene;
    }
    CHECK_NOTHROW(loadScene(good));
    std::filesystem::remove_all(dir);
}

// ---------------------------------------------------------------------------------------------------
// Known issues in code outside the tests, found by these tests and reported. [!mayfail]: the failures are
// printed but do not fail the suite; once fixed, these checks pass and the tag can go.

TEST_CASE("known issues: rejected or mishandled input", "[errors][!mayfail]") {
    SECTION("validateShape reverses a clockwise polygon before rejecting it as not convex") {
        // Shapes.hpp validateShape: std::reverse runs before the convexity and winding checks, so the
        // caller's rejected shape comes back modified (Error.hpp promises the strong guarantee).
        const Shape<2> original = ConvexPolygon{{{0, 2}, {1, 2}, {1, 0.5}, {2, 0}, {0, 0}}};
        Shape<2> s = original;
        CHECK(fieldOf([&] { validateShape<2>(s, "objects[0]"); }) == "objects[0].points");
        CHECK(sameBits(s, original));
    }
    SECTION("GridGeometry accepts a voxel size whose reciprocal overflows") {
        // GridGeometry.hpp: voxel_size 1e-320 passes (origin + d * n != origin), but 1 / d = inf, so
        // toLocal returns inf and NaN (0 * inf) and everything downstream sees non-finite voxel coordinates.
        CHECK(fieldOf([&] { GridGeometry2({0, 0}, 1e-320, {32, 32}); }) == "grid.voxel_size");
        CHECK(sceneFieldOf(mutated("\"voxel_size\": 1", "\"voxel_size\": 1e-320")) == "grid.voxel_size");
    }
    SECTION("parseScene ignores everything after a NUL byte") {
        // nlohmann's lexer takes '\0' for the end of input: "{...}\0garbage" parses as "{...}".
        CHECK(sceneFieldOf(std::string(kBaseScene) + std::string("\0garbage", 8)).rfind("line ", 0) == 0);
    }
}

TEST_CASE("an open mesh can only be an occludee: addObject and updateObject say so and lose nothing", "[api][mesh]") {
    // Issue 13: "a mesh that is not closed can only be an occludee (its outer bound) and says so".
    const GridGeometry3 grid({0, 0, 0}, 1.0, {32, 32, 32});
    TriangleMesh box = reference::cellMeshTriangles(reference::kBoxCells, {12, 12, 2}, {10, 10, 14});
    TriangleMesh open = box;
    open.triangles.pop_back(); // one face half gone: three boundary edges
    const MeshSolid closedWall = reference::meshShape(box), openWall = reference::meshShape(open);
    REQUIRE(closedWall.closed());
    REQUIRE(!openWall.closed());
    Culler3D culler(grid);
    for (ObjectRole role : {ObjectRole::Both, ObjectRole::Occluder}) {
        CHECK(fieldOf([&] { culler.addObject({.id = 1, .shape = openWall, .role = role}); }) == "object 1.role");
        CHECK(culler.objectCount() == 0);
    }
    CHECK_THROWS_WITH(culler.addObject({.id = 1, .shape = openWall}),
                      Catch::Contains("an open mesh hides nothing (3 boundary") && Catch::Contains("role Occludee"));
    CHECK_NOTHROW(culler.addObject({.id = 2, .shape = openWall, .role = ObjectRole::Occludee}));
    // A closed wall hides the ball behind it; moving it to an open mesh is refused and the wall stays.
    culler.addObject({.id = 3, .shape = closedWall, .isStatic = true});
    culler.addObject({.id = 4, .shape = Ball<3>{{16, 16, 24}, 1}, .isStatic = true});
    const Camera3 cam = makeCamera(Vec3{16, 16, 4}, Vec3{0, 0, 1}, 40);
    const std::vector<ObjectId> before = culler.cull(cam).pvs;
    CHECK(std::find(before.begin(), before.end(), ObjectId(4)) == before.end());
    CHECK(fieldOf([&] { culler.updateObject(3, openWall); }) == "object 3.role");
    CHECK(culler.cull(cam).pvs == before);
    // The occludee may become any mesh, open or closed.
    CHECK_NOTHROW(culler.updateObject(2, closedWall.translated(Vec3{0, 0, -6})));
    CHECK_NOTHROW(culler.updateObject(2, openWall));
}
