// The sampled 3D visibility reference checked on its own: hand-made cases whose answer is known on paper
// (occlusion, seam fusion across boxes sharing faces, cameras inside objects, frustum planes, edges and
// far), symmetry under mirroring and permuting the axes, nested sampling densities, agreement with the
// exact view-region test, and the random scene generators. Every 3D culler test trusts this reference,
// so it gets its own tests first.
#include "CullerTestSupport.hpp"

#if __has_include("SceneFile.hpp")
#include "SceneFile.hpp"
#define RGVC_TEST_HAS_SCENE_FILE 1
#endif

#include <catch2/catch.hpp>

#include <array>
#include <chrono>
#include <cmath>
#include <iostream>
#include <limits>
#include <sstream>
#include <vector>

using namespace rgvc;
using rgvc::culler_test::makeCamera;
namespace ref = rgvc::reference;
using ref::visible3D;
using ref::Visibility3DOptions;
using ref::Visibility3DStats;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();

Shape<3> sphere(Vec3 c, double r) { return Ball<3>{c, r}; }
Shape<3> box(Vec3 lo, Vec3 hi) { return Box<3>{lo, hi}; }

Visibility3DOptions literal() {
    Visibility3DOptions o;
    o.fuseSeams = false;
    return o;
}
Visibility3DOptions density(int grid, int targets, bool fuse = true) {
    Visibility3DOptions o;
    o.gridDivisions = grid;
    o.targetDivisions = targets;
    o.fuseSeams = fuse;
    return o;
}

std::vector<bool> expect(std::initializer_list<bool> v) { return std::vector<bool>(v); }

std::string show(const std::vector<bool>& v) {
    std::string s;
    for (bool b : v) s += b ? '1' : '0';
    return s;
}

// A signed axis permutation: x'[i] = sign[i] * x[perm[i]] (orthogonal; mirror when the signs multiply to -1
// or the permutation is odd).
struct AxisMap {
    std::array<int, 3> perm{0, 1, 2};
    std::array<double, 3> sign{1, 1, 1};
    Vec3 operator()(const Vec3& v) const {
        return {sign[0] * v[perm[0]], sign[1] * v[perm[1]], sign[2] * v[perm[2]]};
    }
    Shape<3> operator()(const Shape<3>& s) const {
        if (const auto* b = std::get_if<Ball<3>>(&s)) return Ball<3>{(*this)(b->center), b->radius};
        const Box<3>& x = std::get<Box<3>>(s);
        Vec3 a = (*this)(x.min), c = (*this)(x.max);
        return Box<3>{glm::min(a, c), glm::max(a, c)};
    }
    Camera3 operator()(const Camera3& c) const {
        Camera3 r = c;
        r.position = (*this)(c.position);
        r.direction = (*this)(c.direction);
        r.up = (*this)(lengthSquared<3>(c.up) > 0 ? c.up : Vec3{0.0, 1.0, 0.0});
        return r;
    }
    std::vector<Shape<3>> operator()(const std::vector<Shape<3>>& v) const {
        std::vector<Shape<3>> out;
        for (const Shape<3>& s : v) out.push_back((*this)(s));
        return out;
    }
};

std::vector<AxisMap> allAxisMaps() {
    std::vector<AxisMap> maps;
    const std::array<std::array<int, 3>, 6> perms = {{{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {1, 0, 2}, {0, 2, 1}, {2, 1, 0}}};
    for (const auto& p : perms)
        for (int s = 0; s < 8; ++s) {
            AxisMap m;
            m.perm = p;
            m.sign = {s & 1 ? -1.0 : 1.0, s & 2 ? -1.0 : 1.0, s & 4 ? -1.0 : 1.0};
            maps.push_back(m);
        }
    return maps;
}

} // namespace

TEST_CASE("reference3d: a big box hides what lies behind it, not what lies beside it", "[reference3d]") {
    Camera3 cam = makeCamera({0, 0, 0}, {1, 0, 0}, 60);
    std::vector<Shape<3>> objs = {
        box({5, -2, -2}, {6, 2, 2}), // the occluder: 21.8 degrees around the view axis
        sphere({10, 0, 0}, 1),       // straight behind it (5.7 degrees)
        sphere({10, 5, 0}, 1),       // beside it, up: its lower rim is at 20.8 degrees, partly hidden
        sphere({3, 0, 0.5}, 0.5),    // in front of it
        sphere({10, 1.5, 1.5}, 0.4), // behind its corner region
        sphere({-5, 0, 0}, 1),       // behind the camera
    };
    const auto want = expect({true, false, true, true, false, false});
    CHECK(show(visible3D(objs, cam)) == show(want));
    CHECK(show(visible3D(objs, cam, literal())) == show(want));
    // Either sampling alone finds these large objects.
    CHECK(show(visible3D(objs, cam, density(256, 0))) == show(want));
    CHECK(show(visible3D(objs, cam, density(0, 16))) == show(want));
    // The exact view-region test ignores occlusion.
    CHECK(show(ref::inViewRegion3D(objs, cam)) == show(expect({true, true, true, true, true, false})));
}

TEST_CASE("reference3d: a wall of boxes sharing faces hides a sphere behind it (seam fusion)", "[reference3d]") {
    // 4x4 tiles of 1x1 in y and z, 0.5 thick; the sphere straight behind is 5.7 degrees wide, the wall
    // 21.8. Rays along y = k or z = k planes run on shared faces, and the ray to the sphere's centre runs
    // along the line where four tiles meet.
    Camera3 cam = makeCamera({0, 0, 0}, {1, 0, 0}, 60);
    auto wall = [](double gap) {
        std::vector<Shape<3>> w;
        for (int i = -2; i < 2; ++i)
            for (int j = -2; j < 2; ++j) {
                // gap > 0 opens slits of width 2*gap around y = 0 and z = 0 only.
                double y0 = i, y1 = i + 1, z0 = j, z1 = j + 1;
                if (i == -1) y1 -= gap;
                if (i == 0) y0 += gap;
                if (j == -1) z1 -= gap;
                if (j == 0) z0 += gap;
                w.push_back(box({5, y0, z0}, {5.5, y1, z1}));
            }
        return w;
    };
    SECTION("shared faces: fused, hidden; taken literally the seams let rays through") {
        std::vector<Shape<3>> objs = wall(0);
        objs.push_back(sphere({10, 0, 0}, 0.5));
        Visibility3DStats st;
        auto fused = visible3D(objs, cam, {}, &st);
        CHECK_FALSE(fused.back());
        CHECK(st.seamBlocked > 0);
        for (std::size_t i = 0; i + 1 < objs.size(); ++i) CHECK(fused[i]); // every tile is seen
        auto lit = visible3D(objs, cam, literal());
        CHECK(lit.back());
    }
    SECTION("a camera exactly on a seam plane, looking along it") {
        std::vector<Shape<3>> objs = wall(0);
        objs.push_back(sphere({10, 0.3, 0.3}, 0.2)); // behind tiles, off every seam line
        objs.push_back(sphere({10, 0, 0.3}, 0.2));   // centred on the seam plane y = 0
        Camera3 c2 = makeCamera({0, 0, 0.3}, {1, 0, 0}, 10);
        auto fused = visible3D(objs, c2);
        CHECK_FALSE(fused[objs.size() - 2]);
        CHECK_FALSE(fused.back());
        CHECK(visible3D(objs, c2, literal()).back());
    }
    SECTION("slits of 2e-3: seen through by both rules") {
        std::vector<Shape<3>> objs = wall(1e-3);
        objs.push_back(sphere({10, 0, 0}, 0.5));
        CHECK(visible3D(objs, cam).back());
        CHECK(visible3D(objs, cam, literal()).back());
    }
    SECTION("boxes touching only along an edge do not fuse") {
        // Slab x in [5, 5.5] holds the quadrants (+y, +z) and (-y, -z), slab [5.5, 6] the other two: every
        // ray towards the target crosses an interior except those in the planes y = 0 and z = 0, which run
        // along single box faces with open space on one side (the x axis itself runs along edges where
        // two boxes touch only along that edge).
        std::vector<Shape<3>> objs = {box({5, 0, 0}, {5.5, 1, 1}), box({5, -1, -1}, {5.5, 0, 0}), box({5.5, -1, 0}, {6, 0, 1}),
                                      box({5.5, 0, -1}, {6, 1, 0}), sphere({10, 0, 0}, 0.05)};
        CHECK(visible3D(objs, cam).back());
        // All four quadrants in one slab: the seams fuse.
        objs = {box({5, 0, 0}, {5.5, 1, 1}), box({5, -1, -1}, {5.5, 0, 0}), box({5, -1, 0}, {5.5, 0, 1}),
                box({5, 0, -1}, {5.5, 1, 0}), sphere({10, 0, 0}, 0.05)};
        CHECK_FALSE(visible3D(objs, cam).back());
        CHECK(visible3D(objs, cam, literal()).back());
    }
    SECTION("a sphere resting on a box does not fuse with it") {
        // The target touches the plane y = 0 at (10, 0, 0) only, below it everything crosses the box; the
        // one ray to that point runs on the box's top face and touches the resting sphere at (5.5, 0, 0).
        std::vector<Shape<3>> objs = {box({5, -5, -5}, {6, 0, 5}), sphere({5.5, 1, 0}, 1), sphere({10, -1, 0}, 1)};
        CHECK(show(visible3D(objs, cam)) == "111");
        // Two boxes sharing that face instead: fused.
        objs[1] = box({5, 0, -5}, {6, 2, 5});
        CHECK(show(visible3D(objs, cam)) == "110");
        CHECK(show(visible3D(objs, cam, literal())) == "111");
    }
    SECTION("a wall of touching spheres does not fuse: the pinholes show what is behind") {
        std::vector<Shape<3>> objs;
        for (int i = -3; i < 3; ++i)
            for (int j = -3; j < 3; ++j) objs.push_back(sphere({5, i + 0.5, j + 0.5}, 0.5));
        objs.push_back(sphere({10, 0, 0}, 0.1)); // behind the hole (radius 0.207) between four spheres around the x axis
        CHECK(visible3D(objs, cam).back());
        // The grid alone has a ray along the view axis (an even number of divisions), straight through it.
        Visibility3DOptions gridOnly = density(64, 0);
        gridOnly.criticalRays = false;
        CHECK(visible3D(objs, cam, gridOnly).back());
    }
}

TEST_CASE("reference3d: a pinhole: critical rays find what sampling misses", "[reference3d]") {
    // A 0.01-thick wall of four boxes around a square hole of side 2e-4 at (y, z) = (0.01, 0.01): the
    // only rays through it lie within about 4e-5 radians of (1, 0.002, 0.002); the grid's spacing is 4e-3
    // and the target sphere's own samples are as coarse. The rays through the hole's corners (box
    // corners, crossings of box edge outlines) graze two boxes and reach the sphere.
    Camera3 cam = makeCamera({0, 0, 0}, {1, 0, 0}, 30);
    const double c = 0.01, h = 1e-4, x0 = 5, x1 = 5.01;
    std::vector<Shape<3>> objs = {
        box({x0, -1, -1}, {x1, c - h, 1}),    box({x0, c + h, -1}, {x1, 1, 1}),    // below and above the hole in y
        box({x0, c - h, -1}, {x1, c + h, c - h}), box({x0, c - h, c + h}, {x1, c + h, 1}), // beside it in z
        sphere({10.2, 0.15, -0.05}, 0.3),     // behind the wall; the ray through the hole meets it off-centre
    };
    Visibility3DStats st;
    CHECK(show(visible3D(objs, cam, {}, &st)) == "11111");
    CHECK(st.seen.back() == ref::Seen3D::CriticalRay);
    CHECK(show(visible3D(objs, cam, literal())) == "11111");
    Visibility3DOptions sampledOnly;
    sampledOnly.criticalRays = false;
    CHECK(show(visible3D(objs, cam, sampledOnly)) == "11110"); // the documented limit of sampling
    // Closed (the side boxes widened to meet): hidden, the seams between the boxes fused.
    objs[2] = box({x0, c - h, -1}, {x1, c + h, c + h});
    objs[3] = box({x0, c - h, c + h}, {x1, c + h, 1});
    CHECK(show(visible3D(objs, cam)) == "11110");
}

TEST_CASE("reference3d: a ray grazing a box face sees a tangent sphere", "[reference3d]") {
    // Every ray into the sphere below y = 0 crosses the box's interior; the ray along y = 0 runs on the
    // box's top face (its boundary) and touches the sphere at (10, 0, 0).
    Camera3 cam = makeCamera({0, 0, 0}, {1, 0, 0}, 60);
    std::vector<Shape<3>> objs = {box({5, -5, -5}, {6, 0, 5}), sphere({10, -1, 0}, 1)};
    CHECK(show(visible3D(objs, cam)) == "11");
    CHECK(show(visible3D(objs, cam, density(0, 16))) == "11"); // the silhouette targets find it
    // Lowered by 1e-6 it no longer reaches the free plane.
    objs[1] = sphere({10, -1 - 1e-6, 0}, 1);
    CHECK(show(visible3D(objs, cam)) == "10");
}

TEST_CASE("reference3d: cameras inside objects", "[reference3d]") {
    std::vector<Shape<3>> objs = {
        sphere({0, 0, 0}, 10),    // holds the camera
        sphere({3, 0, 0}, 0.5),   // inside it: the segment crosses its interior
        sphere({20, 0, 0}, 1),    // outside it
        box({-1, -1, -1}, {1, 1, 1}), // also holds the camera
        box({-20, -1, -1}, {-15, 1, 1}), // behind the camera, outside
    };
    CHECK(show(visible3D(objs, makeCamera({0, 0, 0}, {1, 0, 0}, 90))) == "10010");
    CHECK(show(visible3D(objs, makeCamera({0.5, 0.5, 0.5}, {-1, 0, 0}, 90))) == "10010");
    // On the big sphere's surface looking out: it holds the camera; the box at 20 is free to see.
    CHECK(show(visible3D({objs[0], objs[2]}, makeCamera({10, 0, 0}, {1, 0, 0}, 30))) == "11");
    // On the same point looking in: only the sphere itself (the small one is behind its interior).
    CHECK(show(visible3D({objs[0], objs[1], objs[2]}, makeCamera({10, 0, 0}, {-1, 0, 0}, 30))) == "100");
    // A camera on a box corner looking away sees the box (closed sets) and a sphere in front.
    CHECK(show(visible3D({box({0, 0, 0}, {1, 1, 1}), sphere({-5, -5, -5}, 1)}, makeCamera({0, 0, 0}, {-1, -1, -1}, 20))) == "11");
}

TEST_CASE("reference3d: objects outside the frustum", "[reference3d]") {
    Camera3 cam = makeCamera({0, 0, 0}, {0, 0, -1}, 40, kInf, 2.0); // tanV = 0.364, tanH = 0.728
    std::vector<Shape<3>> objs = {
        sphere({0, 0, 10}, 1),     // behind
        sphere({0, 6, -10}, 1),    // above: 31 degrees > 20
        sphere({6, 0, -10}, 1),    // right: inside the wider horizontal half-angle (36 degrees)
        sphere({9, 0, -10}, 1),    // right, outside it: 42 degrees
        box({-20, -0.1, -10}, {20, 0.1, -9}), // a long thin bar across the view, every corner outside
        box({-20, 5, -10}, {20, 6, -9}),      // the same above the top plane
    };
    const auto want = expect({false, false, true, false, true, false});
    CHECK(show(visible3D(objs, cam)) == show(want));
    CHECK(show(ref::inViewRegion3D(objs, cam)) == show(want));
    CHECK(ref::pointInView3D(cam, {0, 0, -5}));
    CHECK_FALSE(ref::pointInView3D(cam, {0, 0, 5}));
    CHECK(ref::pointInView3D(cam, {0, 0, 0})); // the apex
}

TEST_CASE("reference3d: far limit", "[reference3d]") {
    Camera3 cam = makeCamera({0, 0, 0}, {1, 0, 0}, 90, 10);
    std::vector<Shape<3>> objs = {
        sphere({12, 0, 0}, 1),             // nearest point at 11
        sphere({10.5, 0, 0}, 1),           // nearest point at 9.5
        sphere({10.5, 0, 0}, 0.8),         // inside the previous one: in range (9.7) but hidden by it
        box({7, 7, -0.5}, {8, 8, 0.5}),    // the only point in range and in view: (7, 7, 0), on the top plane at 9.9
        box({7.1, 7.1, -0.5}, {8, 8, 0.5}), // nearest in-view point at 10.04
    };
    CHECK(show(visible3D(objs, cam)) == "01010");
    CHECK(show(ref::inViewRegion3D(objs, cam)) == "01110");
    CHECK(ref::pointInView3D(cam, {10, 0, 0}));
    CHECK_FALSE(ref::pointInView3D(cam, {10.000001, 0, 0}));
}

TEST_CASE("reference3d: frustum planes and edges, grazing", "[reference3d]") {
    // A 1-degree frustum, aspect 1.5. A sphere whose distance to the top plane's line of sight is r -+ 1e-6
    // just meets / just misses the view region; the same at the corner edge ray.
    Camera3 cam = makeCamera({0, 0, 0}, {1, 0, 0}, 1, kInf, 1.5);
    const double tanV = std::tan(0.5 * kPi / 180), tanH = 1.5 * tanV, d = 50, r = 0.2;
    auto nearTop = [&](double gap) { // centre above the top plane at perpendicular distance r + gap
        double beta = std::atan(tanV) + std::asin((r + gap) / d);
        return sphere({d * std::cos(beta), d * std::sin(beta), 0}, r);
    };
    auto nearCorner = [&](double gap) { // beyond the corner edge ray, along the outward bisector
        Vec3 e = glm::normalize(Vec3{1, tanV, tanH});
        Vec3 out = glm::normalize(Vec3{0, 1, 1} - glm::dot(Vec3{0, 1, 1}, e) * e);
        return sphere(d * e + (r + gap) * out, r);
    };
    std::vector<Shape<3>> objs = {sphere({100, 0, 0}, 0.1), nearTop(-1e-6), nearTop(1e-6), nearCorner(-1e-6), nearCorner(1e-6)};
    // The corner sphere's nearest point to the edge ray lies off both side planes (the bisector), so only
    // the edge ray itself reaches it; both sampled rules find it, the exact test agrees.
    CHECK(show(visible3D(objs, cam)) == "11010");
    CHECK(show(visible3D(objs, cam, density(0, 16))) == "11010");
    CHECK(show(ref::inViewRegion3D(objs, cam)) == "11010");
    // Boxes touching a side plane with one face.
    const double x = 20, top = x * tanV;
    CHECK(ref::touchesViewRegion3D(box({x, top, -0.1}, {x + 1, top + 1, 0.1}), cam));
    CHECK_FALSE(ref::touchesViewRegion3D(box({x, (x + 1) * tanV + 1e-6, -0.1}, {x + 1, top + 1, 0.1}), cam));
    CHECK(show(visible3D({box({x, (x + 1) * tanV, -0.1}, {x + 1, top + 1, 0.1})}, cam)) == "1"); // one edge on the plane
}

TEST_CASE("reference3d: an explicit up vector rolls the frustum", "[reference3d]") {
    // Wide horizontally (aspect 3): rolled 90 degrees by up = +z, the wide axis becomes y.
    std::vector<Shape<3>> objs = {sphere({10, 15, 0}, 1), sphere({10, 0, 15}, 1)};
    CHECK(show(visible3D(objs, makeCamera({0, 0, 0}, {1, 0, 0}, 60, kInf, 3.0))) == "01");
    CHECK(show(visible3D(objs, makeCamera({0, 0, 0}, {1, 0, 0}, 60, kInf, 3.0, {0, 0, 1}))) == "10");
    // Looking straight up needs an explicit up.
    CHECK(show(visible3D({sphere({0, 10, 0}, 1)}, makeCamera({0, 0, 0}, {0, 1, 0}, 30, kInf, 1, {0, 0, 1}))) == "1");
    // Any non-zero up counts, as in the library: a denormal one too (its square underflows to zero; the
    // reference once read it as "no up" and disagreed with the culler, found by fuzz_culler3d).
    const double tiny = std::numeric_limits<double>::denorm_min();
    CHECK(show(visible3D(objs, makeCamera({0, 0, 0}, {1, 0, 0}, 60, kInf, 3.0, {0, 0, tiny}))) == "10");
    CHECK(show(visible3D(objs, makeCamera({0, 0, 0}, {1, 0, 0}, 60, kInf, 3.0, {0, 0, -tiny}))) == "10");
}

TEST_CASE("reference3d: mirrored and permuted axes give the same answers", "[reference3d]") {
    // A hand-made scene with occlusion, fusion, far and grazing, under all 48 signed axis permutations.
    std::vector<Shape<3>> objs;
    for (int i = -2; i < 2; ++i)
        for (int j = -2; j < 2; ++j) objs.push_back(box({5, i * 0.5, j * 0.5}, {5.25, (i + 1) * 0.5, (j + 1) * 0.5}));
    objs.push_back(sphere({10, 0, 0}, 0.3));        // behind the fused wall
    objs.push_back(sphere({10, 1.8, 0.5}, 0.5));    // beside it
    objs.push_back(box({7, -3, -3}, {7.5, -2.5, 3})); // a post at the lower edge
    objs.push_back(sphere({3, -1, -1}, 0.2));
    objs.push_back(sphere({17, 0, 0}, 3));          // beyond far
    const Camera3 cam = makeCamera({0.1, 0.05, 0}, {1, 0.02, 0.01}, 50, 14, 1.2);
    const auto want = visible3D(objs, cam, density(96, 8));
    CHECK(show(want) == "1111111111111111" "01110"); // tiles; hidden, beside, post, front, hidden beyond the wall
    for (const AxisMap& m : allAxisMaps()) {
        CAPTURE(m.perm[0], m.perm[1], m.perm[2], m.sign[0], m.sign[1], m.sign[2]);
        CHECK(show(visible3D(m(objs), m(cam), density(96, 8))) == show(want));
        CHECK(show(ref::inViewRegion3D(m(objs), m(cam))) == show(ref::inViewRegion3D(objs, cam)));
    }
}

TEST_CASE("reference3d: symmetry on random scenes", "[reference3d]") {
    ref::SceneOptions3D opt;
    opt.maxObjects = 40;
    const std::vector<AxisMap> maps = allAxisMaps();
    int compared = 0, visibleTotal = 0;
    for (std::uint64_t seed = 100; seed < 300; ++seed) {
        if (seed % 2) { // every other scene dense: a small grid full of objects
            opt.minResolution = 8;
            opt.maxResolution = 16;
            opt.minObjects = 30;
        } else {
            opt = {};
            opt.maxObjects = 40;
        }
        ref::Scene3D s = ref::randomScene3D(seed, opt);
        const auto shapes = ref::shapesOf(s.objects);
        const auto base = visible3D(shapes, s.camera);
        const auto region = ref::inViewRegion3D(shapes, s.camera);
        const AxisMap& m = maps[std::size_t(seed * 7 % maps.size())];
        INFO("seed " << seed << " map " << m.perm[0] << m.perm[1] << m.perm[2] << " " << m.sign[0] << m.sign[1] << m.sign[2]
                     << "\n" << ref::toJson(s));
        CHECK(show(visible3D(m(shapes), m(s.camera))) == show(base));
        CHECK(show(ref::inViewRegion3D(m(shapes), m(s.camera))) == show(region));
        for (bool b : base) visibleTotal += b;
        ++compared;
    }
    std::cout << "[reference3d] symmetry: " << compared << " random scenes, " << visibleTotal << " visible objects\n";
    CHECK(visibleTotal > 0);
}

TEST_CASE("reference3d: denser sampling never loses an object, fusion only hides, visible implies in view", "[reference3d]") {
    ref::SceneOptions3D opt;
    opt.maxObjects = 50;
    int scenes = 0, gained = 0, gainedLast = 0, visibleTotal = 0, targetOnly = 0, literalOnly = 0;
    for (std::uint64_t seed = 1; seed <= 120; ++seed) {
        if (seed % 2) {
            opt.minResolution = 8;
            opt.maxResolution = 16;
            opt.minObjects = 30;
        } else {
            opt = {};
            opt.maxObjects = 50;
        }
        ref::Scene3D s = ref::randomScene3D(seed, opt);
        const auto shapes = ref::shapesOf(s.objects);
        const auto region = ref::inViewRegion3D(shapes, s.camera);
        const auto a = visible3D(shapes, s.camera, density(16, 2));
        const auto b = visible3D(shapes, s.camera, density(32, 4));
        Visibility3DStats st;
        const auto c = visible3D(shapes, s.camera, density(64, 8), &st);
        const auto d = visible3D(shapes, s.camera); // the defaults: (256, 16)
        const auto lit = visible3D(shapes, s.camera, density(256, 16, false));
        Visibility3DOptions unculled = density(64, 8);
        unculled.cullRays = false;
        Visibility3DStats st2;
        CHECK(show(visible3D(shapes, s.camera, unculled, &st2)) == show(c)); // ray culling changes nothing
        CHECK(st2.seen == st.seen);
        INFO("seed " << seed << "\n" << ref::toJson(s));
        for (std::size_t i = 0; i < shapes.size(); ++i) {
            CAPTURE(i);
            CHECK((!a[i] || b[i]));
            CHECK((!b[i] || c[i]));
            CHECK((!c[i] || d[i]));
            CHECK((!d[i] || lit[i]));
            CHECK((!lit[i] || region[i]));
            gained += (d[i] && !a[i]);
            gainedLast += (d[i] && !c[i]);
            visibleTotal += d[i];
            targetOnly += st.seen[i] == ref::Seen3D::TargetRay;
            literalOnly += lit[i] && !d[i];
            if (c[i] && st.seen[i] != ref::Seen3D::ContainsCamera) {
                // The witness is a point of the object (grown by eps) in the view region (loosened by eps).
                CHECK(ref::pointInView3D(s.camera, st.witness[i], 1e3 * st.eps));
            }
        }
        ++scenes;
    }
    std::cout << "[reference3d] nesting: " << scenes << " random scenes, " << visibleTotal << " visible at (256, 16), "
              << gained << " of them not at (16, 2), " << gainedLast << " not at (64, 8); " << targetOnly
              << " found by target rays at (64, 8); " << literalOnly << " more without seam fusion\n";
    CHECK(visibleTotal > 0);
}

TEST_CASE("reference3d: the exact view-region test against sampled points", "[reference3d]") {
    // touchesViewRegion3D must be true whenever some sampled point of the object is in the view region,
    // and one object alone is visible exactly when it touches the view region (sampling may miss slivers).
    std::mt19937_64 rng(77);
    ref::SceneOptions3D opt;
    opt.maxObjects = 30;
    opt.farProbability = 0.5;
    int objects = 0, touching = 0, pointWitnessed = 0, aloneMissed = 0;
    for (std::uint64_t seed = 500; seed < 540; ++seed) {
        ref::Scene3D s = ref::randomScene3D(seed, opt);
        for (const ObjectDesc<3>& o : s.objects) {
            const bool touches = ref::touchesViewRegion3D(o.shape, s.camera);
            bool anyPoint = false;
            for (int k = 0; k < 300 && !anyPoint; ++k) {
                Vec3 p;
                if (const auto* b = std::get_if<Ball<3>>(&o.shape)) {
                    Vec3 dir = ref::scene3d_detail::unitVector(rng);
                    p = b->center + dir * b->radius * (k % 2 ? 1.0 : std::cbrt(ref::scene3d_detail::uniform01(rng)));
                } else {
                    const Box<3>& x = std::get<Box<3>>(o.shape);
                    for (int a = 0; a < 3; ++a) p[a] = ref::scene3d_detail::uniform(rng, x.min[a], x.max[a]);
                }
                anyPoint = ref::pointInView3D(s.camera, p);
            }
            INFO("seed " << seed << " object " << o.id << "\n" << ref::toJson(s));
            if (anyPoint) CHECK(touches);
            const bool alone = visible3D({o.shape}, s.camera, density(32, 8))[0];
            if (alone) CHECK(touches);
            aloneMissed += touches && !alone;
            pointWitnessed += anyPoint;
            touching += touches;
            ++objects;
        }
    }
    std::cout << "[reference3d] view region: " << objects << " objects, " << touching << " touch the view region, "
              << pointWitnessed << " with a random point in it; " << aloneMissed
              << " touching but not found alone by sparse sampling (32, 8)\n";
    CHECK(touching > 0);
}

TEST_CASE("reference3d: random scene generators", "[reference3d]") {
    // Deterministic, valid, and covering the advertised mixture.
    int spheres = 0, boxes = 0, sharedFaces = 0, outsideCams = 0, farCams = 0, upCams = 0;
    for (std::uint64_t seed = 0; seed < 200; ++seed) {
        ref::Scene3D s = ref::randomScene3D(seed), t = ref::randomScene3D(seed);
        REQUIRE(ref::toJson(s) == ref::toJson(t));
        for (int a = 0; a < 3; ++a) {
            CHECK(s.grid.resolution()[a] >= 8);
            CHECK(s.grid.resolution()[a] <= 64);
        }
        CHECK((s.objects.size() >= 1 && s.objects.size() <= 80));
        REQUIRE_NOTHROW(validateCamera<3>(s.camera));
        Vec3 up = lengthSquared<3>(s.camera.up) > 0 ? s.camera.up : Vec3{0, 1, 0};
        CHECK(std::abs(glm::dot(glm::normalize(up), glm::normalize(s.camera.direction))) < 0.9999);
        CHECK(s.camera.fovDeg >= 1);
        CHECK(s.camera.fovDeg <= 170);
        CHECK((s.camera.aspect >= 0.3 && s.camera.aspect <= 3));
        outsideCams += !s.grid.containsLocal(s.grid.toLocal(s.camera.position));
        farCams += std::isfinite(s.camera.far);
        upCams += lengthSquared<3>(s.camera.up) > 0;
        std::vector<Box<3>> bx;
        for (ObjectDesc<3> o : s.objects) {
            REQUIRE_NOTHROW(validateShape<3>(o.shape, "generated"));
            if (const auto* b = std::get_if<Box<3>>(&o.shape)) {
                ++boxes;
                bx.push_back(*b);
            } else {
                ++spheres;
            }
        }
        for (std::size_t i = 0; i + 1 < bx.size(); ++i) // neighbours in a generated wall share a face exactly
            for (int a = 0; a < 3; ++a) sharedFaces += bx[i].max[a] == bx[i + 1].min[a];
#ifdef RGVC_TEST_HAS_SCENE_FILE
        if (seed < 50) {
            INFO(ref::toJson(s));
            REQUIRE_NOTHROW(parseScene(ref::toJson(s), "generated.json"));
            Scene back = parseScene(ref::toJson(s), "generated.json");
            REQUIRE(back.as<3>() != nullptr);
            CHECK(back.as<3>()->objects.size() == s.objects.size());
        }
#endif
    }
    CHECK(spheres > 100);
    CHECK(boxes > 100);
    CHECK(sharedFaces > 50);
    CHECK(outsideCams > 5);
    CHECK(farCams > 10);
    CHECK(upCams > 10);

    // The moving-spheres benchmark: clustered spheres in a 100x60x100 grid, motion by the reflection rule.
    ref::MovingSpheres3D b = ref::movingSpheres3D(42, 500);
    REQUIRE(b.objects.size() == 500);
    CHECK(b.grid.resolution() == IVec3{100, 60, 100});
    for (int f = 0; f < 200; ++f) ref::stepMovingSpheres(b);
    for (std::size_t i = 0; i < b.objects.size(); ++i) {
        const Box<3> bb = boundsOf<3>(b.objects[i].shape);
        for (int a = 0; a < 3; ++a) { // inside the grid up to one step of overshoot
            CHECK(bb.min[a] >= -b.objects[i].maxSpeed);
            CHECK(bb.max[a] <= b.grid.resolution()[a] + b.objects[i].maxSpeed);
        }
        CHECK(std::sqrt(lengthSquared<3>(b.velocity[i])) <= b.objects[i].maxSpeed * (1 + 1e-12));
    }
    const Camera3 c = ref::movingSpheresCamera(b, 10, 100);
    REQUIRE_NOTHROW(validateCamera<3>(c));
    CHECK(b.grid.containsLocal(b.grid.toLocal(c.position)));
}

namespace {

// The literal rule for one segment, written independently of the reference: does the open segment a..b
// meet the interior of s shrunk by eps?
bool segmentMeetsInterior(const Shape<3>& s, const Vec3& a, const Vec3& b, double eps) {
    const Vec3 d = b - a;
    if (const auto* ball = std::get_if<Ball<3>>(&s)) {
        const double r = ball->radius - eps;
        if (r <= 0) return false;
        const Vec3 f = a - ball->center;
        const double A = glm::dot(d, d), B = glm::dot(f, d), C = glm::dot(f, f) - r * r, disc = B * B - A * C;
        if (disc <= 0) return false;
        const double t0 = (-B - std::sqrt(disc)) / A, t1 = (-B + std::sqrt(disc)) / A;
        return t0 < 1 && t1 > 0;
    }
    const Box<3>& x = std::get<Box<3>>(s);
    double lo = 0, hi = 1;
    for (int k = 0; k < 3; ++k) {
        const double l = x.min[k] + eps, h = x.max[k] - eps;
        if (l >= h) return false;
        if (d[k] == 0) {
            if (a[k] <= l || a[k] >= h) return false;
            continue;
        }
        double t0 = (l - a[k]) / d[k], t1 = (h - a[k]) / d[k];
        if (t0 > t1) std::swap(t0, t1);
        lo = std::max(lo, t0);
        hi = std::min(hi, t1);
        if (lo >= hi) return false;
    }
    return true;
}

} // namespace

TEST_CASE("reference3d: random surface points never show an object the reference calls hidden", "[reference3d]") {
    // An independent brute force of the literal rule: for every object in the view region that the
    // (literal) reference calls hidden, 2000 random points of its surface; none may be in view with a
    // free segment. (Offline, 2000 scenes with 20000 points each found none either.)
    std::mt19937_64 rng(11);
    namespace sd = ref::scene3d_detail;
    int checked = 0, points = 0;
    for (std::uint64_t seed = 3000; seed < 3060; ++seed) {
        ref::SceneOptions3D opt;
        if (seed % 2) {
            opt.minResolution = 8;
            opt.maxResolution = 16;
            opt.minObjects = 40;
        }
        ref::Scene3D s = ref::randomScene3D(seed, opt);
        const auto shapes = ref::shapesOf(s.objects);
        const auto vis = visible3D(shapes, s.camera, literal());
        const auto region = ref::inViewRegion3D(shapes, s.camera);
        const double eps = ref::sceneEpsilon3D(shapes, s.camera);
        for (std::size_t i = 0; i < shapes.size(); ++i) {
            if (vis[i] || !region[i]) continue;
            ++checked;
            for (int k = 0; k < 2000; ++k) {
                Vec3 p;
                if (const auto* b = std::get_if<Ball<3>>(&shapes[i])) {
                    p = b->center + sd::unitVector(rng) * b->radius;
                } else {
                    const Box<3>& x = std::get<Box<3>>(shapes[i]);
                    for (int a = 0; a < 3; ++a) p[a] = sd::uniform(rng, x.min[a], x.max[a]);
                    p[k % 3] = sd::chance(rng, 0.5) ? x.min[k % 3] : x.max[k % 3];
                }
                if (!ref::pointInView3D(s.camera, p)) continue;
                ++points;
                bool blocked = false;
                for (std::size_t j = 0; j < shapes.size() && !blocked; ++j)
                    blocked = j != i && segmentMeetsInterior(shapes[j], s.camera.position, p, eps);
                if (!blocked) {
                    INFO("seed " << seed << " object " << i << " seen at " << p.x << " " << p.y << " " << p.z << "\n" << ref::toJson(s));
                    FAIL_CHECK("the reference missed a visible object");
                    break;
                }
            }
        }
    }
    std::cout << "[reference3d] brute force: " << checked << " hidden objects in view, " << points
              << " of their surface points in view, none seen\n";
    CHECK(checked > 50);
}

TEST_CASE("reference3d: cost per call", "[reference3d]") {
    // Not a benchmark (timings live in apps/), just the figure the culler tests budget with.
    struct Row {
        const char* name;
        double ms = 0, msSparse = 0;
        std::size_t rays = 0, targetRays = 0, criticalRays = 0;
        int calls = 0;
    };
    auto measure = [](Row& row, const std::vector<Shape<3>>& shapes, const Camera3& cam) {
        Visibility3DStats st;
        auto t0 = std::chrono::steady_clock::now();
        visible3D(shapes, cam, {}, &st);
        auto t1 = std::chrono::steady_clock::now();
        visible3D(shapes, cam, density(64, 8));
        auto t2 = std::chrono::steady_clock::now();
        row.ms += std::chrono::duration<double, std::milli>(t1 - t0).count();
        row.msSparse += std::chrono::duration<double, std::milli>(t2 - t1).count();
        row.rays += st.gridRays;
        row.targetRays += st.targetRays;
        row.criticalRays += st.criticalRays;
        ++row.calls;
    };
    Row sparse{"random scenes, 8..64 voxels"}, dense{"dense random scenes, 8..16 voxels"}, spheres{"moving spheres 100x60x100"};
    for (std::uint64_t seed = 900; seed < 920; ++seed) {
        ref::SceneOptions3D opt;
        opt.minObjects = opt.maxObjects = 50;
        ref::Scene3D s = ref::randomScene3D(seed, opt);
        measure(sparse, ref::shapesOf(s.objects), s.camera);
        opt.minResolution = 8;
        opt.maxResolution = 16;
        s = ref::randomScene3D(seed, opt);
        measure(dense, ref::shapesOf(s.objects), s.camera);
    }
    ref::MovingSpheres3D b = ref::movingSpheres3D(7, 50);
    for (int f = 0; f < 20; ++f) {
        measure(spheres, ref::shapesOf(b.objects), ref::movingSpheresCamera(b, f, 20));
        ref::stepMovingSpheres(b);
    }
    for (const Row* r : {&sparse, &dense, &spheres}) {
        std::ostringstream os;
        os.precision(3);
        os << "[reference3d] cost, 50 objects, " << r->name << ": " << r->ms / r->calls << " ms per call at the defaults (256, 16; "
           << r->rays / std::size_t(r->calls) << " grid rays, " << double(r->targetRays) / r->calls << " target and " << double(r->criticalRays) / r->calls
           << " critical rays on average), "
           << r->msSparse / r->calls << " ms at (64, 8)\n";
        std::cout << os.str();
        CHECK(r->calls > 0);
    }
}

TEST_CASE("reference3d: polytopes: an axis-aligned obb and a box's corner hull see and hide as the box does", "[reference3d][polytope]") {
    // Random scenes: every box replaced by the same box as an obb (identity rotation) and as the hull
    // of its 8 corners gives the same visibility, object for object.
    int compared = 0, visibleCount = 0;
    for (std::uint64_t seed = 1; seed <= 60; ++seed) {
        ref::SceneOptions3D opt;
        opt.maxObjects = 25;
        const ref::Scene3D s = ref::randomScene3D(seed, opt);
        const std::vector<Shape<3>> shapes = ref::shapesOf(s.objects);
        for (int mode = 0; mode < 2; ++mode) {
            std::vector<Shape<3>> other;
            for (const Shape<3>& sh : shapes) {
                if (const auto* b = std::get_if<Box<3>>(&sh)) {
                    if (mode == 0) {
                        other.push_back(makeOrientedBox(0.5 * (b->min + b->max), 0.5 * (b->max - b->min), {0, 0, 0, 1}, "obb"));
                    } else {
                        std::vector<Vec3> c;
                        for (int k = 0; k < 8; ++k) c.push_back({k & 1 ? b->max.x : b->min.x, k & 2 ? b->max.y : b->min.y, k & 4 ? b->max.z : b->min.z});
                        other.push_back(makeConvexHull(c, "hull"));
                    }
                } else {
                    other.push_back(sh);
                }
            }
            const std::vector<bool> a = visible3D(shapes, s.camera), b = visible3D(other, s.camera);
            // An obb's corners are centre +- half: rounding may move a face by an ulp, which decides only
            // exact grazes; the hull's corners are the box's own.
            if (mode == 1) CHECK(show(a) == show(b));
            std::size_t differ = 0;
            for (std::size_t i = 0; i < a.size(); ++i) differ += a[i] != b[i];
            CHECK(differ <= (mode == 0 ? 1u : 0u));
            compared += int(a.size());
            for (bool v : a) visibleCount += v;
            CHECK(show(ref::inViewRegion3D(shapes, s.camera)) == show(ref::inViewRegion3D(other, s.camera)));
        }
    }
    CHECK(compared > 500);
    CHECK(visibleCount > 100);
}

TEST_CASE("reference3d: a turned obb hides what is behind it and shows what is beside it", "[reference3d][polytope]") {
    const Camera3 cam = makeCamera({0, 0, 0}, {1, 0, 0}, 60);
    const double a = 30 * 3.14159265358979 / 180;
    // A wall at x = 6 turned by 30 degrees about z, 1 thick, 6 high: hides the sphere straight behind it.
    std::vector<Shape<3>> objs = {
        makeOrientedBox({6, 0, 0}, {0.5, 3, 3}, {0, 0, std::sin(a / 2), std::cos(a / 2)}, "wall"),
        sphere({12, 0, 0}, 1),   // behind
        sphere({12, -7, 0}, 1),  // beside (26 to 35 degrees; the wall reaches 22 on this side)
        makeConvexHull(std::vector<Vec3>{{3, -1, -1}, {3, 1, -1}, {3, 0, 1}, {2.5, 0, 0}}, "tetra"), // in front, small
        sphere({6.3, 0, 0}, 0.1), // inside the wall: hidden
    };
    const auto want = expect({true, false, true, true, false});
    CHECK(show(visible3D(objs, cam)) == show(want));
    CHECK(show(visible3D(objs, cam, literal())) == show(want));
    // The tetrahedron hides a small sphere right behind it.
    objs.push_back(sphere({4, 0, 0}, 0.1));
    CHECK(visible3D(objs, cam)[5] == false);
}
