// Seeded random 2D scenes for the culler tests and the benchmarks (header-only).
//
//   rgvc::reference::Scene2D s = rgvc::reference::randomScene2D(seed);       // grid + objects + camera
//   rgvc::Camera2 another = rgvc::reference::randomCamera2D(rng, s.grid, s.objects, snapped);
//   std::cout << rgvc::reference::toJson(s);    // the scene-format file, to replay with `rgvc cull`
//
// Everything is drawn from std::mt19937_64 through our own integer-to-double mapping (not the standard
// distributions, whose output differs between standard libraries), so a seed names the same scene on
// every machine. The mixture aims at the cases a grid culler gets wrong: objects from 1/20 of a voxel to
// a third of the grid, long walls, rows and blocks of boxes that abut exactly (occluder fusion across
// objects), coordinates snapped to voxel faces and corners, cameras on voxel corners and edges, inside
// objects and outside the grid, directions along axes and diagonals, fov from 0.5 to 360 degrees.
#pragma once

#include "SeededRandom.hpp"
#include "rgvc/dynamics/Culler.hpp"
#include "rgvc/grid/Camera.hpp"
#include "rgvc/grid/GridGeometry.hpp"
#include "rgvc/grid/Shapes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace rgvc::reference {

struct SceneOptions {
    int minResolution = 8, maxResolution = 128; ///< per axis
    int minObjects = 1, maxObjects = 60;
    /// Probability that a scene puts every coordinate on voxel faces/corners (and cameras on corners).
    double snapProbability = 0.35;
    /// Probability of a finite `far` per camera.
    double farProbability = 0.15;
    /// Probability of a camera outside the grid bounds.
    double cameraOutsideProbability = 0.1;
};

struct Scene2D {
    std::uint64_t seed = 0;
    bool snapped = false;
    GridGeometry2 grid;
    std::vector<ObjectDesc<2>> objects;
    Camera2 camera;
};

namespace scene_detail {

using seeded::chance;
using seeded::logUniform;
using seeded::pick;
using seeded::uniform;
using seeded::uniform01;
using seeded::uniformInt;

/// Builds world-unit shapes from voxel-unit numbers, so that "snapped" means on voxel faces.
struct Placer {
    const GridGeometry2& grid;
    Vec2 world(const Vec2& local) const { return grid.origin() + local * grid.voxelSize(); }
    double length(double local) const { return local * grid.voxelSize(); }
};

inline Shape<2> makeBox(const Placer& pl, Vec2 lo, Vec2 hi) { return Box<2>{pl.world(lo), pl.world(hi)}; }

/// Convex polygon of 3..8 points on an ellipse (points on an ellipse in angular order are in strictly
/// convex position), rotated at random. Snapped: vertices rounded to voxel corners, then the convex hull.
inline Shape<2> makePolygon(std::mt19937_64& rng, const Placer& pl, Vec2 centre, double size, bool snapped) {
    const double kTwoPi = 6.283185307179586;
    for (int attempt = 0; attempt < 20; ++attempt) {
        int n = uniformInt(rng, 3, 8);
        std::vector<double> angles;
        for (int i = 0; i < n; ++i) angles.push_back(uniform(rng, 0, kTwoPi));
        std::sort(angles.begin(), angles.end());
        bool spread = true; // very close angles give nearly collinear triples, which validation rejects
        for (int i = 0; i < n; ++i) {
            double gap = (i + 1 < n ? angles[i + 1] : angles[0] + kTwoPi) - angles[i];
            spread = spread && gap > 0.15;
        }
        if (!spread) continue;
        double ax = size, ay = size * uniform(rng, 0.3, 1.0), rot = uniform(rng, 0, kTwoPi);
        std::vector<Vec2> local;
        for (double a : angles) {
            Vec2 p{ax * std::cos(a), ay * std::sin(a)};
            Vec2 q = centre + Vec2{p.x * std::cos(rot) - p.y * std::sin(rot), p.x * std::sin(rot) + p.y * std::cos(rot)};
            if (snapped) q = glm::round(q);
            local.push_back(q);
        }
        if (snapped) { // convex hull (monotone chain) of the rounded points
            std::sort(local.begin(), local.end(), [](const Vec2& a, const Vec2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
            local.erase(std::unique(local.begin(), local.end()), local.end());
            std::vector<Vec2> hull(2 * local.size());
            std::size_t k = 0;
            for (std::size_t pass = 0; pass < 2; ++pass) {
                std::size_t start = k;
                for (std::size_t i = 0; i < local.size(); ++i) {
                    const Vec2& p = pass == 0 ? local[i] : local[local.size() - 1 - i];
                    while (k >= start + 2 && cross2(hull[k - 1] - hull[k - 2], p - hull[k - 1]) <= 0) --k;
                    hull[k++] = p;
                }
                --k;
            }
            hull.resize(k);
            local = hull;
        }
        if (local.size() < 3) continue;
        ConvexPolygon poly;
        for (const Vec2& q : local) poly.points.push_back(pl.world(q));
        if (chance(rng, 0.5)) std::reverse(poly.points.begin(), poly.points.end()); // either winding
        Shape<2> s = poly;
        try {
            validateShape<2>(s, "generated");
        } catch (const InvalidInput&) {
            continue;
        }
        return poly; // the input winding, not the normalised one
    }
    return makeBox(pl, centre - size * 0.5, centre + size * 0.5);
}

/// One random object (or a group of abutting boxes) in voxel units around `centre`.
inline void addObjects(std::mt19937_64& rng, const Placer& pl, bool snapped, Vec2 centre, double maxSize,
                       std::vector<Shape<2>>& out) {
    double r = uniform01(rng);
    double size = logUniform(rng, snapped ? 1.0 : 0.05, std::max(maxSize, 1.5));
    if (snapped) centre = glm::round(centre);
    if (r < 0.28) { // circle
        double radius = snapped ? 0.5 * std::max(1.0, std::round(size)) : 0.5 * size;
        Vec2 c = snapped && chance(rng, 0.5) ? centre + 0.5 : centre; // voxel corner or voxel centre
        out.push_back(Ball<2>{pl.world(c), pl.length(radius)});
    } else if (r < 0.55) { // box
        Vec2 ext{size, size * logUniform(rng, 0.2, 5.0)};
        if (snapped) ext = glm::max(glm::round(ext), Vec2(1.0));
        Vec2 lo = snapped ? glm::round(centre - 0.5 * ext) : centre - 0.5 * ext;
        out.push_back(makeBox(pl, lo, lo + ext));
    } else if (r < 0.78) {
        out.push_back(makePolygon(rng, pl, centre, std::max(0.5 * size, snapped ? 2.0 : 0.03), snapped));
    } else if (r < 0.9) { // wall: long and thin, axis-aligned
        double len = uniform(rng, 4, std::max(5.0, 2 * maxSize)), thick = snapped ? uniformInt(rng, 1, 3) : uniform(rng, 0.3, 3);
        if (snapped) len = std::round(len);
        Vec2 ext = chance(rng, 0.5) ? Vec2{len, thick} : Vec2{thick, len};
        Vec2 lo = snapped ? glm::round(centre - 0.5 * ext) : centre - 0.5 * ext;
        out.push_back(makeBox(pl, lo, lo + ext));
    } else { // a row or block of boxes that abut exactly: only fused do they occlude as one
        int nx = uniformInt(rng, 1, 4), ny = uniformInt(rng, 1, 3);
        if (nx * ny == 1) nx = 2;
        double w = snapped ? uniformInt(rng, 1, 3) : uniform(rng, 0.4, 3), h = snapped ? uniformInt(rng, 1, 3) : uniform(rng, 0.4, 3);
        Vec2 lo = centre;
        for (int i = 0; i < nx; ++i)
            for (int j = 0; j < ny; ++j) {
                // Shared faces come from the same expression, so abutting boxes share the exact double.
                Vec2 a = lo + Vec2{i * w, j * h}, b = lo + Vec2{(i + 1) * w, (j + 1) * h};
                out.push_back(makeBox(pl, a, b));
            }
    }
}

} // namespace scene_detail

/// A random camera for `grid`: positions inside, on voxel corners/edges/centres (when snapped or by
/// chance), inside or on an object, outside the grid; directions along axes, diagonals or anywhere
/// (any length); fov from 0.5 to 360 degrees; sometimes a finite far.
inline Camera2 randomCamera2D(std::mt19937_64& rng, const GridGeometry2& grid, const std::vector<ObjectDesc<2>>& objects,
                              bool snapped, const SceneOptions& opt = {}) {
    using namespace scene_detail;
    const Placer pl{grid};
    const Vec2 res = Vec2(grid.resolution());
    Camera2 cam;
    Vec2 local{uniform(rng, 0, res.x), uniform(rng, 0, res.y)};
    double mode = uniform01(rng);
    if (mode < 0.2) local = glm::floor(local);                                   // voxel corner
    else if (mode < 0.3) local.x = std::floor(local.x);                          // on a vertical voxel edge
    else if (mode < 0.4) local = glm::floor(local) + 0.5;                        // voxel centre
    else if (mode < 0.55 && !objects.empty()) {                                  // in or on an object
        const Shape<2>& s = objects[rng() % objects.size()].shape;
        Box<2> b = boundsOf<2>(s);
        Vec2 lo = grid.toLocal(b.min), hi = grid.toLocal(b.max);
        double pickMode = uniform01(rng);
        if (pickMode < 0.5) local = 0.5 * (lo + hi);                             // centre: inside
        else if (pickMode < 0.75) local = lo;                                    // a bounding corner
        else local = Vec2{lo.x, uniform(rng, lo.y, hi.y)};                       // on the bounding edge
    }
    if (snapped && mode >= 0.4 && chance(rng, 0.5)) local = glm::round(local);
    if (chance(rng, opt.cameraOutsideProbability)) { // outside the grid on one or both axes
        int axis = uniformInt(rng, 0, 2);
        for (int a = 0; a < 2; ++a)
            if (axis == 2 || axis == a)
                local[a] = chance(rng, 0.5) ? -uniform(rng, 0.01, 0.5) * res[a] : res[a] * (1 + uniform(rng, 0.01, 0.5));
        if (snapped) local = glm::round(local);
    }
    cam.position = pl.world(local);

    const std::vector<Vec2> axes = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {-1, 1}, {1, -1}, {-1, -1}, {2, 1}, {1, -3}};
    double dmode = uniform01(rng);
    if (dmode < 0.45) cam.direction = pick(rng, axes);
    else {
        double a = uniform(rng, 0, 6.283185307179586);
        cam.direction = {std::cos(a), std::sin(a)};
    }
    cam.direction *= logUniform(rng, 1e-3, 1e3); // any non-zero length

    const std::vector<double> fovs = {0.5, 1, 5, 30, 45, 60, 89.5, 90, 90.5, 120, 179.5, 180, 180.5, 270, 359, 360};
    cam.fovDeg = chance(rng, 0.6) ? pick(rng, fovs) : uniform(rng, 0.5, 360);
    if (chance(rng, opt.farProbability)) cam.far = pl.length(uniform(rng, 0.05, 1.2) * std::max(res.x, res.y));
    return cam;
}

/// A random scene (grid, objects with unique ids, camera) fully determined by `seed`.
inline Scene2D randomScene2D(std::uint64_t seed, const SceneOptions& opt = {}) {
    using namespace scene_detail;
    std::mt19937_64 rng(seed);
    Scene2D scene;
    scene.seed = seed;
    scene.snapped = chance(rng, opt.snapProbability);

    IVec2 res{uniformInt(rng, opt.minResolution, opt.maxResolution), 0};
    res.y = chance(rng, 0.5) ? res.x : uniformInt(rng, opt.minResolution, opt.maxResolution);
    // Dyadic voxel sizes keep snapped coordinates exact in voxel units; 0.1 and random ones do not.
    const std::vector<double> sizes = {1.0, 0.5, 0.25, 2.0, 0.1, 3.0};
    double d = chance(rng, 0.8) ? pick(rng, sizes) : logUniform(rng, 0.05, 5.0);
    Vec2 origin{0.0};
    double omode = uniform01(rng);
    if (omode < 0.3) origin = Vec2{uniformInt(rng, -100, 100), uniformInt(rng, -100, 100)} * d;
    else if (omode < 0.6) origin = Vec2{uniform(rng, -1000, 1000), uniform(rng, -1000, 1000)};
    scene.grid = GridGeometry2(origin, d, res);

    const Placer pl{scene.grid};
    const Vec2 r = Vec2(res);
    int count = uniformInt(rng, opt.minObjects, opt.maxObjects);
    std::vector<Shape<2>> shapes;
    while (int(shapes.size()) < count) {
        // Centres up to 10% beyond the grid on each side: some objects lie partly or wholly outside.
        Vec2 c{uniform(rng, -0.1 * r.x, 1.1 * r.x), uniform(rng, -0.1 * r.y, 1.1 * r.y)};
        addObjects(rng, pl, scene.snapped, c, std::min(r.x, r.y) / 3, shapes);
    }
    shapes.resize(std::size_t(count));

    // Unique ids, not contiguous and not in index order, some beyond 32 bits.
    std::vector<ObjectId> ids;
    for (int i = 0; i < count; ++i) ids.push_back(ObjectId(i) * 7 + (i % 3 == 0 ? (ObjectId(1) << 40) : 3));
    std::shuffle(ids.begin(), ids.end(), rng);
    for (int i = 0; i < count; ++i) {
        ObjectDesc<2> o;
        o.id = ids[std::size_t(i)];
        o.shape = shapes[std::size_t(i)];
        o.isStatic = chance(rng, 0.5);
        o.maxSpeed = o.isStatic ? 0.0 : pl.length(uniform(rng, 0, 2));
        scene.objects.push_back(o);
    }
    scene.camera = randomCamera2D(rng, scene.grid, scene.objects, scene.snapped, opt);
    return scene;
}

inline std::vector<Shape<2>> shapesOf(const std::vector<ObjectDesc<2>>& objects) {
    std::vector<Shape<2>> out;
    out.reserve(objects.size());
    for (const ObjectDesc<2>& o : objects) out.push_back(o.shape);
    return out;
}

/// The scene as a scene-format JSON file (17 significant digits: it replays bit for bit).
inline std::string toJson(const GridGeometry2& grid, const std::vector<ObjectDesc<2>>& objects, const Camera2& cam) {
    auto num = [](double v) {
        char buf[40];
        std::snprintf(buf, sizeof buf, "%.17g", v);
        return std::string(buf);
    };
    auto vec = [&](const Vec2& v) {
        std::string r = "["; // appended piecewise: GCC 12 warns (-Wrestrict, falsely) on "[" + std::string
        r += num(v.x);
        r += ", ";
        r += num(v.y);
        r += "]";
        return r;
    };
    std::string s = "{\n  \"dimensions\": 2,\n";
    s += "  \"grid\": { \"origin\": " + vec(grid.origin()) + ", \"voxel_size\": " + num(grid.voxelSize()) +
         ", \"resolution\": [" + std::to_string(grid.resolution().x) + ", " + std::to_string(grid.resolution().y) + "] },\n";
    s += "  \"camera\": { \"position\": " + vec(cam.position) + ", \"direction\": " + vec(cam.direction) +
         ", \"fov_deg\": " + num(cam.fovDeg) + (std::isfinite(cam.far) ? ", \"far\": " + num(cam.far) : "") + " },\n";
    s += "  \"objects\": [\n";
    for (std::size_t i = 0; i < objects.size(); ++i) {
        const ObjectDesc<2>& o = objects[i];
        s += "    { \"id\": " + std::to_string(o.id) + ", ";
        if (const auto* b = std::get_if<Ball<2>>(&o.shape))
            s += "\"shape\": \"circle\", \"center\": " + vec(b->center) + ", \"radius\": " + num(b->radius);
        else if (const auto* x = std::get_if<Box<2>>(&o.shape))
            s += "\"shape\": \"box\", \"min\": " + vec(x->min) + ", \"max\": " + vec(x->max);
        else {
            const auto& p = std::get<ConvexPolygon>(o.shape);
            s += "\"shape\": \"polygon\", \"points\": [";
            for (std::size_t k = 0; k < p.points.size(); ++k) s += (k ? ", " : "") + vec(p.points[k]);
            s += "]";
        }
        if (!o.isStatic) s += ", \"max_speed\": " + num(o.maxSpeed);
        s += " }" + std::string(i + 1 < objects.size() ? "," : "") + "\n";
    }
    return s + "  ]\n}\n";
}

inline std::string toJson(const Scene2D& scene) { return toJson(scene.grid, scene.objects, scene.camera); }

} // namespace rgvc::reference
