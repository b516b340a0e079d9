// Seeded random 3D scenes for the culler tests and the benchmarks (header-only), the 3D counterpart of
// RandomScenes2D.hpp.
//
//   rgvc::reference::Scene3D s = rgvc::reference::randomScene3D(seed);       // grid + objects + camera
//   rgvc::Camera3 another = rgvc::reference::randomCamera3D(rng, s.grid, s.objects, s.snapped);
//   std::cout << rgvc::reference::toJson(s);    // the scene-format file, to replay with `rgvc cull`
//
//   rgvc::reference::MovingSpheres3D b = rgvc::reference::movingSpheres3D(seed, 2000);  // §6 benchmark
//   for (int f = 0; f < frames; ++f) { cam = movingSpheresCamera(b, f, frames); ...; stepMovingSpheres(b); }
//
// Everything is drawn from std::mt19937_64 through our own integer-to-double mapping (not the standard
// distributions, whose output differs between standard libraries), so a seed names the same scene on
// every machine. The mixture aims at the cases a 3D grid culler gets wrong: spheres and boxes from 1/20
// of a voxel to a third of the grid, long thin walls, walls of small boxes that share faces exactly
// (occluder fusion across objects), walls of touching spheres (which must NOT fuse), blocks of boxes,
// coordinates snapped to voxel faces, cameras on voxel corners, edges and faces, inside objects and
// outside the grid, directions along axes, grid-plane and space diagonals, fov 1..170 degrees, aspect
// 0.3..3, explicit `up` vectors, sometimes a finite far.
//
// The helpers live in scene3d_detail (not scene_detail) so that this header and RandomScenes2D.hpp can be
// included together.
#pragma once

#include "SeededRandom.hpp"
#include "TestMeshes.hpp"
#include "rgvc/dynamics/Culler.hpp"
#include "rgvc/grid/Camera.hpp"
#include "rgvc/grid/GridGeometry.hpp"
#include "rgvc/grid/Shapes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace rgvc::reference {

struct SceneOptions3D {
    int minResolution = 8, maxResolution = 64; ///< per axis
    int minObjects = 1, maxObjects = 80;
    /// Probability that a scene puts every coordinate on voxel faces/corners (and cameras on corners).
    double snapProbability = 0.35;
    /// Probability of a finite `far` per camera.
    double farProbability = 0.15;
    /// Probability of a camera outside the grid bounds.
    double cameraOutsideProbability = 0.1;
    /// Probability that an object (group) is a convex polytope instead: an oriented box (turned, or
    /// axis-aligned on voxel faces next to boxes), a thin turned wall, or a hull of 4 to 16 points.
    /// 0 (the default) leaves the scenes of every seed exactly as they were before polytopes existed.
    double polytopeProbability = 0;
    /// Probability that an object is a closed triangle mesh (TestMeshes.hpp: a box, an L, a U, a ring, an
    /// octahedron; turned unless snapped): an occluder through its solid voxelization. 0 (the default)
    /// leaves the scenes of every seed as they were.
    double meshProbability = 0;
};

struct Scene3D {
    std::uint64_t seed = 0;
    bool snapped = false;
    GridGeometry3 grid;
    std::vector<ObjectDesc<3>> objects;
    Camera3 camera;
};

namespace scene3d_detail {

using seeded::chance;
using seeded::logUniform;
using seeded::pick;
using seeded::uniform;
using seeded::uniform01;
using seeded::uniformInt;
/// A direction uniform on the unit sphere (rejection from the cube).
inline Vec3 unitVector(std::mt19937_64& rng) {
    for (;;) {
        Vec3 v{uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)};
        double l2 = lengthSquared<3>(v);
        if (l2 > 1e-4 && l2 <= 1) return v / std::sqrt(l2);
    }
}

/// Builds world-unit shapes from voxel-unit numbers, so that "snapped" means on voxel faces.
struct Placer3 {
    const GridGeometry3& grid;
    Vec3 world(const Vec3& local) const { return grid.origin() + local * grid.voxelSize(); }
    double length(double local) const { return local * grid.voxelSize(); }
};

inline Shape<3> makeBox(const Placer3& pl, Vec3 lo, Vec3 hi) { return Box<3>{pl.world(lo), pl.world(hi)}; }

/// Three distinct axes: a = the normal of a wall, b and c span it.
inline void pickAxes(std::mt19937_64& rng, int& a, int& b, int& c) {
    a = uniformInt(rng, 0, 2);
    b = (a + 1) % 3;
    c = (a + 2) % 3;
    if (chance(rng, 0.5)) std::swap(b, c);
}

/// One random object (or a group: a wall or block of boxes sharing faces, a wall of touching spheres)
/// in voxel units around `centre`.
inline void addObjects(std::mt19937_64& rng, const Placer3& pl, bool snapped, Vec3 centre, double maxSize,
                       std::vector<Shape<3>>& out) {
    double r = uniform01(rng);
    double size = logUniform(rng, snapped ? 1.0 : 0.05, std::max(maxSize, 1.5));
    if (snapped) centre = glm::round(centre);
    if (r < 0.25) { // sphere
        double radius = snapped ? 0.5 * std::max(1.0, std::round(size)) : 0.5 * size;
        Vec3 c = snapped && chance(rng, 0.5) ? centre + 0.5 : centre; // voxel centre or voxel corner
        out.push_back(Ball<3>{pl.world(c), pl.length(radius)});
    } else if (r < 0.5) { // box
        Vec3 ext{size, size * logUniform(rng, 0.2, 5.0), size * logUniform(rng, 0.2, 5.0)};
        for (int k = 2; k > 0; --k) std::swap(ext[k], ext[uniformInt(rng, 0, k)]); // the long axis anywhere
        if (snapped) ext = glm::max(glm::round(ext), Vec3(1.0));
        Vec3 lo = snapped ? glm::round(centre - 0.5 * ext) : centre - 0.5 * ext;
        out.push_back(makeBox(pl, lo, lo + ext));
    } else if (r < 0.62) { // long thin wall
        int a, b, c;
        pickAxes(rng, a, b, c);
        Vec3 ext{0.0};
        ext[a] = snapped ? uniformInt(rng, 1, 2) : uniform(rng, 0.1, 2);
        ext[b] = uniform(rng, 4, std::max(5.0, 2 * maxSize));
        ext[c] = uniform(rng, 2, std::max(3.0, 1.5 * maxSize));
        if (snapped) ext = glm::max(glm::round(ext), Vec3(1.0));
        Vec3 lo = snapped ? glm::round(centre - 0.5 * ext) : centre - 0.5 * ext;
        out.push_back(makeBox(pl, lo, lo + ext));
    } else if (r < 0.8) { // a wall of small boxes sharing faces: only fused do they occlude as one
        int a, b, c;
        pickAxes(rng, a, b, c);
        int nb = uniformInt(rng, 2, 6), nc = uniformInt(rng, 1, 6);
        double w = snapped ? uniformInt(rng, 1, 2) : logUniform(rng, 0.1, 2.5);
        double h = snapped ? uniformInt(rng, 1, 2) : (chance(rng, 0.5) ? w : logUniform(rng, 0.1, 2.5));
        double thick = snapped ? 1.0 : logUniform(rng, 0.05, 1.5);
        Vec3 lo = centre;
        for (int i = 0; i < nb; ++i)
            for (int j = 0; j < nc; ++j) {
                // Shared faces come from the same expression, so abutting boxes share the exact double.
                Vec3 p = lo, q = lo;
                p[b] = lo[b] + i * w;
                q[b] = lo[b] + (i + 1) * w;
                p[c] = lo[c] + j * h;
                q[c] = lo[c] + (j + 1) * h;
                q[a] = lo[a] + thick;
                out.push_back(makeBox(pl, p, q));
            }
    } else if (r < 0.9) { // a wall of touching spheres (square lattice, spacing = diameter): pinholes stay
        int a, b, c;
        pickAxes(rng, a, b, c);
        int nb = uniformInt(rng, 2, 6), nc = uniformInt(rng, 1, 5);
        double rad = snapped ? 0.5 * uniformInt(rng, 1, 2) : logUniform(rng, 0.05, 1.5);
        for (int i = 0; i < nb; ++i)
            for (int j = 0; j < nc; ++j) {
                Vec3 p = centre;
                p[b] += (2 * i + 1) * rad;
                p[c] += (2 * j + 1) * rad;
                out.push_back(Ball<3>{pl.world(p), pl.length(rad)});
            }
    } else { // a block of boxes sharing faces in all three directions
        int n[3] = {uniformInt(rng, 1, 3), uniformInt(rng, 1, 3), uniformInt(rng, 1, 3)};
        if (n[0] * n[1] * n[2] == 1) n[0] = 2;
        Vec3 e{0.0};
        for (int k = 0; k < 3; ++k) e[k] = snapped ? uniformInt(rng, 1, 2) : logUniform(rng, 0.1, 2);
        for (int i = 0; i < n[0]; ++i)
            for (int j = 0; j < n[1]; ++j)
                for (int k = 0; k < n[2]; ++k) {
                    Vec3 p = centre + Vec3{i * e.x, j * e.y, k * e.z};
                    Vec3 q = centre + Vec3{(i + 1) * e.x, (j + 1) * e.y, (k + 1) * e.z};
                    out.push_back(makeBox(pl, p, q));
                }
    }
}

/// A random unit quaternion [x, y, z, w]; snapped: the identity or a quarter turn about an axis.
inline std::array<double, 4> randomRotation(std::mt19937_64& rng, bool snapped) {
    if (snapped) {
        std::array<double, 4> q{0, 0, 0, 1};
        if (chance(rng, 0.5)) {
            q[3] = std::sqrt(0.5);
            q[std::size_t(uniformInt(rng, 0, 2))] = std::sqrt(0.5);
        }
        return q;
    }
    const Vec3 a = unitVector(rng);
    const double angle = uniform(rng, 0, 6.283185307179586);
    return {a.x * std::sin(angle / 2), a.y * std::sin(angle / 2), a.z * std::sin(angle / 2), std::cos(angle / 2)};
}

/// One convex polytope (SceneOptions3D::polytopeProbability) in voxel units around `centre`.
inline void addPolytope(std::mt19937_64& rng, const Placer3& pl, bool snapped, Vec3 centre, double maxSize,
                        std::vector<Shape<3>>& out) {
    const double r = uniform01(rng);
    const double size = logUniform(rng, snapped ? 1.0 : 0.1, std::max(maxSize, 1.5));
    if (snapped) centre = glm::round(centre);
    try {
        if (r < 0.4) { // an oriented box
            Vec3 half{0.5 * size, 0.5 * size * logUniform(rng, 0.2, 5.0), 0.5 * size * logUniform(rng, 0.2, 5.0)};
            if (snapped) half = glm::max(glm::round(2.0 * half) / 2.0, Vec3(0.5));
            out.push_back(makeOrientedBox(pl.world(centre), half * pl.grid.voxelSize(), randomRotation(rng, snapped), "obb"));
        } else if (r < 0.6) { // a thin turned wall
            Vec3 half{uniform(rng, 0.05, 1.0), uniform(rng, 2, std::max(3.0, maxSize)), uniform(rng, 1, std::max(2.0, 0.75 * maxSize))};
            if (snapped) half = glm::max(glm::round(2.0 * half) / 2.0, Vec3(0.5));
            out.push_back(makeOrientedBox(pl.world(centre), half * pl.grid.voxelSize(), randomRotation(rng, snapped), "wall"));
        } else { // a hull of 4 to 16 points in a ball, some on its sphere; snapped: on the lattice
            std::vector<Vec3> pts;
            const int n = uniformInt(rng, 4, 16);
            for (int k = 0; k < n; ++k) {
                Vec3 q = unitVector(rng) * (chance(rng, 0.5) ? 1.0 : uniform(rng, 0, 1));
                Vec3 local = centre + 0.5 * size * Vec3(q.x, q.y * logUniform(rng, 0.3, 3.0), q.z);
                if (snapped) local = glm::round(local);
                pts.push_back(pl.world(local));
            }
            out.push_back(makeConvexHull(pts, "hull"));
        }
    } catch (const InvalidInput&) {
        // a flat draw (snapped lattice points on one plane): a box instead
        out.push_back(makeBox(pl, centre - 0.5, centre + 0.5));
    }
}

/// A valid `up` for direction `dir`: the default (zero = (0, 1, 0)) when allowed and `preferDefault`,
/// otherwise an axis or a random vector clearly not parallel to dir.
inline Vec3 pickUp(std::mt19937_64& rng, const Vec3& dir, bool preferDefault) {
    const Vec3 unit = dir / std::sqrt(lengthSquared<3>(dir));
    auto ok = [&](const Vec3& up) {
        Vec3 u = up / std::sqrt(lengthSquared<3>(up));
        return std::abs(glm::dot(u, unit)) < 0.999;
    };
    if (preferDefault && ok(Vec3{0.0, 1.0, 0.0})) return Vec3(0.0);
    const std::vector<Vec3> axes = {{0, 1, 0}, {0, -1, 0}, {1, 0, 0}, {0, 0, 1}, {0, 0, -1}, {1, 1, 0}};
    for (int attempt = 0; attempt < 50; ++attempt) {
        Vec3 up = chance(rng, 0.6) ? pick(rng, axes) : unitVector(rng) * logUniform(rng, 0.01, 100);
        if (ok(up)) return up;
    }
    return std::abs(unit.x) < 0.9 ? Vec3{1.0, 0.0, 0.0} : Vec3{0.0, 0.0, 1.0};
}

} // namespace scene3d_detail

/// A random 3D camera for `grid`: positions anywhere, on voxel corners, edges (two coordinates on voxel
/// faces), faces (one coordinate), voxel centres, inside an object's voxel or on its bounding box, outside
/// the grid; directions along axes, grid-plane diagonals, space diagonals or anywhere (any length); fov
/// 1..170 degrees, aspect 0.3..3, sometimes an explicit up, sometimes a finite far.
inline Camera3 randomCamera3D(std::mt19937_64& rng, const GridGeometry3& grid, const std::vector<ObjectDesc<3>>& objects,
                              bool snapped, const SceneOptions3D& opt = {}) {
    using namespace scene3d_detail;
    const Placer3 pl{grid};
    const Vec3 res = Vec3(grid.resolution());
    Camera3 cam;
    Vec3 local{uniform(rng, 0, res.x), uniform(rng, 0, res.y), uniform(rng, 0, res.z)};
    double mode = uniform01(rng);
    const int axis = uniformInt(rng, 0, 2);
    if (mode < 0.15) local = glm::floor(local); // voxel corner
    else if (mode < 0.25) {                     // on a voxel edge: two coordinates integral
        Vec3 f = glm::floor(local);
        f[axis] = local[axis];
        local = f;
    } else if (mode < 0.35) { // on a voxel face: one coordinate integral
        local[axis] = std::floor(local[axis]);
    } else if (mode < 0.42) { // voxel centre
        local = glm::floor(local) + 0.5;
    } else if (mode < 0.58 && !objects.empty()) { // in or on an object
        const Shape<3>& s = objects[rng() % objects.size()].shape;
        Box<3> b = boundsOf<3>(s);
        Vec3 lo = grid.toLocal(b.min), hi = grid.toLocal(b.max);
        double pickMode = uniform01(rng);
        if (pickMode < 0.35) local = 0.5 * (lo + hi);                         // centre: inside
        else if (pickMode < 0.55) local = glm::floor(0.5 * (lo + hi)) + 0.5;   // centre of the voxel holding it
        else if (pickMode < 0.75) local = lo;                                  // a bounding corner
        else {                                                                 // on a bounding face
            local = Vec3{uniform(rng, lo.x, hi.x), uniform(rng, lo.y, hi.y), uniform(rng, lo.z, hi.z)};
            local[axis] = chance(rng, 0.5) ? lo[axis] : hi[axis];
        }
    }
    if (snapped && mode >= 0.42 && chance(rng, 0.5)) local = glm::round(local);
    if (chance(rng, opt.cameraOutsideProbability)) { // outside the grid on one or more axes
        for (int a = 0; a < 3; ++a)
            if (a == axis || chance(rng, 0.3))
                local[a] = chance(rng, 0.5) ? -uniform(rng, 0.01, 0.5) * res[a] : res[a] * (1 + uniform(rng, 0.01, 0.5));
        if (snapped) local = glm::round(local);
    }
    cam.position = pl.world(local);

    static const std::vector<Vec3> dirs = {
        {1, 0, 0},  {-1, 0, 0}, {0, 1, 0},  {0, -1, 0}, {0, 0, 1},   {0, 0, -1},                            // axes
        {1, 1, 0},  {1, -1, 0}, {-1, 0, 1}, {0, 1, 1},  {0, -1, -1}, {1, 0, -1},                            // grid-plane diagonals
        {1, 1, 1},  {-1, 1, 1}, {1, -1, 1}, {-1, -1, -1},                                                   // space diagonals
        {2, 1, 0},  {1, -3, 2}, {0.001, 0, 1}};
    double dmode = uniform01(rng);
    cam.direction = dmode < 0.5 ? pick(rng, dirs) : unitVector(rng);
    cam.direction *= logUniform(rng, 1e-3, 1e3); // any non-zero length
    cam.up = pickUp(rng, cam.direction, chance(rng, 0.75));

    static const std::vector<double> fovs = {1, 5, 30, 45, 60, 89.5, 90, 90.5, 120, 150, 170};
    cam.fovDeg = chance(rng, 0.6) ? pick(rng, fovs) : uniform(rng, 1, 170);
    static const std::vector<double> aspects = {1, 1, 1, 0.3, 0.5, 4.0 / 3.0, 16.0 / 9.0, 2, 3};
    cam.aspect = chance(rng, 0.7) ? pick(rng, aspects) : logUniform(rng, 0.3, 3);
    if (chance(rng, opt.farProbability))
        cam.far = pl.length(uniform(rng, 0.05, 1.2) * std::max({res.x, res.y, res.z}));
    return cam;
}

/// A random 3D scene (grid, objects with unique ids, camera) fully determined by `seed`.
inline Scene3D randomScene3D(std::uint64_t seed, const SceneOptions3D& opt = {}) {
    using namespace scene3d_detail;
    std::mt19937_64 rng(seed ^ 0x3d3d3d3d3d3d3d3dULL);
    Scene3D scene;
    scene.seed = seed;
    scene.snapped = chance(rng, opt.snapProbability);

    IVec3 res{uniformInt(rng, opt.minResolution, opt.maxResolution), 0, 0};
    if (chance(rng, 0.5)) {
        res.y = res.z = res.x;
    } else {
        res.y = uniformInt(rng, opt.minResolution, opt.maxResolution);
        res.z = uniformInt(rng, opt.minResolution, opt.maxResolution);
    }
    // Dyadic voxel sizes keep snapped coordinates exact in voxel units; 0.1 and random ones do not.
    static const std::vector<double> sizes = {1.0, 0.5, 0.25, 2.0, 0.1, 3.0};
    double d = chance(rng, 0.8) ? pick(rng, sizes) : logUniform(rng, 0.05, 5.0);
    Vec3 origin{0.0};
    double omode = uniform01(rng);
    if (omode < 0.3) origin = Vec3{uniformInt(rng, -100, 100), uniformInt(rng, -100, 100), uniformInt(rng, -100, 100)} * d;
    else if (omode < 0.6) origin = Vec3{uniform(rng, -1000, 1000), uniform(rng, -1000, 1000), uniform(rng, -1000, 1000)};
    scene.grid = GridGeometry3(origin, d, res);

    const Placer3 pl{scene.grid};
    const Vec3 r = Vec3(res);
    int count = uniformInt(rng, opt.minObjects, opt.maxObjects);
    std::vector<Shape<3>> shapes;
    while (int(shapes.size()) < count) {
        // Centres up to 10% beyond the grid on each side: some objects lie partly or wholly outside.
        Vec3 c{uniform(rng, -0.1 * r.x, 1.1 * r.x), uniform(rng, -0.1 * r.y, 1.1 * r.y), uniform(rng, -0.1 * r.z, 1.1 * r.z)};
        if (opt.meshProbability > 0 && chance(rng, opt.meshProbability)) {
            const double size = logUniform(rng, scene.snapped ? 2.0 : 0.5, std::max(std::min({r.x, r.y, r.z}) / 2, 3.0));
            TriangleMesh m = randomMeshTriangles(rng, c, size, scene.snapped);
            for (Vec3& p : m.positions) p = pl.world(p);
            shapes.push_back(meshShape(std::move(m)));
        } else if (opt.polytopeProbability > 0 && chance(rng, opt.polytopeProbability))
            addPolytope(rng, pl, scene.snapped, c, std::min({r.x, r.y, r.z}) / 3, shapes);
        else
            addObjects(rng, pl, scene.snapped, c, std::min({r.x, r.y, r.z}) / 3, shapes);
    }
    shapes.resize(std::size_t(count));

    // Unique ids, not contiguous and not in index order, some beyond 32 bits.
    std::vector<ObjectId> ids;
    for (int i = 0; i < count; ++i) ids.push_back(ObjectId(i) * 7 + (i % 3 == 0 ? (ObjectId(1) << 40) : 3));
    std::shuffle(ids.begin(), ids.end(), rng);
    for (int i = 0; i < count; ++i) {
        ObjectDesc<3> o;
        o.id = ids[std::size_t(i)];
        o.shape = shapes[std::size_t(i)];
        o.isStatic = chance(rng, 0.5);
        o.maxSpeed = o.isStatic ? 0.0 : pl.length(uniform(rng, 0, 2));
        scene.objects.push_back(o);
    }
    scene.camera = randomCamera3D(rng, scene.grid, scene.objects, scene.snapped, opt);
    return scene;
}

inline std::vector<Shape<3>> shapesOf(const std::vector<ObjectDesc<3>>& objects) {
    std::vector<Shape<3>> out;
    out.reserve(objects.size());
    for (const ObjectDesc<3>& o : objects) out.push_back(o.shape);
    return out;
}

/// The scene as a scene-format JSON file (17 significant digits: it replays bit for bit). `velocities`
/// (optional, one per object) are written as "velocity"; otherwise moving objects get their max_speed.
inline std::string toJson(const GridGeometry3& grid, const std::vector<ObjectDesc<3>>& objects, const Camera3& cam,
                          const std::vector<Vec3>* velocities = nullptr) {
    auto num = [](double v) {
        char buf[40];
        std::snprintf(buf, sizeof buf, "%.17g", v);
        return std::string(buf);
    };
    auto vec = [&](const Vec3& v) {
        std::string r = "["; // appended piecewise: GCC 12 warns (-Wrestrict, falsely) on "[" + std::string
        r += num(v.x);
        r += ", ";
        r += num(v.y);
        r += ", ";
        r += num(v.z);
        r += "]";
        return r;
    };
    std::string s = "{\n  \"dimensions\": 3,\n";
    s += "  \"grid\": { \"origin\": " + vec(grid.origin()) + ", \"voxel_size\": " + num(grid.voxelSize()) +
         ", \"resolution\": [" + std::to_string(grid.resolution().x) + ", " + std::to_string(grid.resolution().y) +
         ", " + std::to_string(grid.resolution().z) + "] },\n";
    s += "  \"camera\": { \"position\": " + vec(cam.position) + ", \"direction\": " + vec(cam.direction) +
         ", \"fov_deg\": " + num(cam.fovDeg) + ", \"aspect\": " + num(cam.aspect);
    if (cam.up.x != 0 || cam.up.y != 0 || cam.up.z != 0) s += ", \"up\": " + vec(cam.up);
    if (std::isfinite(cam.far)) s += ", \"far\": " + num(cam.far);
    s += " },\n  \"objects\": [\n";
    for (std::size_t i = 0; i < objects.size(); ++i) {
        const ObjectDesc<3>& o = objects[i];
        s += "    { \"id\": " + std::to_string(o.id) + ", ";
        if (const auto* b = std::get_if<Ball<3>>(&o.shape))
            s += "\"shape\": \"sphere\", \"center\": " + vec(b->center) + ", \"radius\": " + num(b->radius);
        else if (const auto* x = std::get_if<Box<3>>(&o.shape))
            s += "\"shape\": \"box\", \"min\": " + vec(x->min) + ", \"max\": " + vec(x->max);
        else { // a polytope (obb or hull) as the hull of its vertices: the same shape; a mesh as its hull
            // (a mesh needs a file: the replayed scene then has the mesh's outer model only)
            s += "\"shape\": \"hull\", \"points\": [";
            const auto* mesh = std::get_if<MeshSolid>(&o.shape);
            const auto& p = mesh != nullptr ? mesh->hull() : std::get<ConvexPolytope>(o.shape);
            for (std::size_t k = 0; k < p.vertices.size(); ++k) s += (k ? ", " : "") + vec(p.vertices[k]);
            s += "]";
        }
        if (velocities && i < velocities->size() && lengthSquared<3>((*velocities)[i]) > 0) {
            s += ", \"velocity\": " + vec((*velocities)[i]);
            if (o.maxSpeed > 0) s += ", \"max_speed\": " + num(o.maxSpeed);
        } else if (!o.isStatic) {
            s += ", \"max_speed\": " + num(o.maxSpeed);
        }
        s += " }" + std::string(i + 1 < objects.size() ? "," : "") + "\n";
    }
    return s + "  ]\n}\n";
}

inline std::string toJson(const Scene3D& scene) { return toJson(scene.grid, scene.objects, scene.camera); }

// ---------------------------------------------------------------------------------------------------
// The "moving spheres" benchmark (the paper's §6): N spheres of varying size, clustered, moving in a grid.

struct MovingSpheres3D {
    GridGeometry3 grid;
    std::vector<ObjectDesc<3>> objects;
    std::vector<Vec3> velocity;         ///< [World units per frame] per object; flipped by reflections
    std::vector<Vec3> translation;      ///< [World units] from the frame-0 placement
    std::vector<Shape<3>> frame0;       ///< frame-0 shapes (the reflection rule works on these + translation)
};

/// `count` spheres with radii log-uniform in [minRadius, maxRadius] voxels, placed in `clusters` Gaussian-like
/// clusters (plus 20% spread uniformly) inside a grid of `resolution` unit voxels at the origin; every sphere
/// moves with a random velocity of length up to `maxSpeed` voxels per frame (max_speed set to it).
inline MovingSpheres3D movingSpheres3D(std::uint64_t seed, int count, IVec3 resolution = {100, 60, 100}, int clusters = 8,
                                       double minRadius = 0.3, double maxRadius = 3.0, double maxSpeed = 0.5) {
    using namespace scene3d_detail;
    std::mt19937_64 rng(seed ^ 0x5fe4e5ULL);
    MovingSpheres3D b;
    b.grid = GridGeometry3(Vec3(0.0), 1.0, resolution);
    const Vec3 res = Vec3(resolution);
    std::vector<Vec3> centres;
    std::vector<double> spreads;
    for (int k = 0; k < std::max(clusters, 1); ++k) {
        centres.push_back(Vec3{uniform(rng, 0.1, 0.9) * res.x, uniform(rng, 0.1, 0.9) * res.y, uniform(rng, 0.1, 0.9) * res.z});
        spreads.push_back(uniform(rng, 0.03, 0.12) * std::min({res.x, res.y, res.z}) + 2);
    }
    for (int i = 0; i < count; ++i) {
        double radius = logUniform(rng, minRadius, maxRadius);
        Vec3 c;
        if (chance(rng, 0.2)) {
            c = Vec3{uniform(rng, 0, res.x), uniform(rng, 0, res.y), uniform(rng, 0, res.z)};
        } else {
            std::size_t k = rng() % centres.size();
            // Sum of three uniforms: a cheap, portable bell shape.
            Vec3 off{0.0};
            for (int a = 0; a < 3; ++a) off[a] = (uniform01(rng) + uniform01(rng) + uniform01(rng) - 1.5) * spreads[k];
            c = centres[k] + off;
        }
        for (int a = 0; a < 3; ++a) c[a] = std::clamp(c[a], radius, std::max(radius, res[a] - radius));
        ObjectDesc<3> o;
        o.id = ObjectId(i);
        o.shape = Ball<3>{c, radius};
        o.isStatic = false;
        o.maxSpeed = maxSpeed;
        b.objects.push_back(o);
        b.frame0.push_back(o.shape);
        b.velocity.push_back(unitVector(rng) * uniform(rng, 0.2, 1.0) * maxSpeed);
        b.translation.push_back(Vec3(0.0));
    }
    return b;
}

/// One frame of motion by the scene format's reflection rule (apps/scene/SceneMotion.hpp): per axis, a
/// step that would carry the frame-0 bounding box + translation past the grid bound it moves towards
/// flips that velocity component first. Updates objects[i].shape.
inline void stepMovingSpheres(MovingSpheres3D& b) {
    const Vec3 glo = b.grid.origin();
    Vec3 ghi;
    for (int a = 0; a < 3; ++a) ghi[a] = b.grid.origin()[a] + b.grid.voxelSize() * b.grid.resolution()[a];
    for (std::size_t i = 0; i < b.objects.size(); ++i) {
        const Box<3> b0 = boundsOf<3>(b.frame0[i]);
        for (int a = 0; a < 3; ++a) {
            double lo = b0.min[a] + b.translation[i][a], hi = b0.max[a] + b.translation[i][a];
            double& v = b.velocity[i][a];
            if ((v > 0 && hi + v > ghi[a]) || (v < 0 && lo + v < glo[a])) v = -v;
            b.translation[i][a] += v;
        }
        b.objects[i].shape = translated<3>(b.frame0[i], b.translation[i]);
    }
}

/// A smooth camera walk through the benchmark's grid: a Lissajous curve at mid height, looking along its
/// tangent, slightly downwards.
inline Camera3 movingSpheresCamera(const MovingSpheres3D& b, int frame, int frames, double fovDeg = 60, double aspect = 16.0 / 9.0) {
    const double kTwoPi = 6.283185307179586;
    const double t = kTwoPi * frame / std::max(frames, 1);
    const Vec3 res = Vec3(b.grid.resolution());
    const Vec3 c = 0.5 * res, R = 0.4 * res;
    Camera3 cam;
    cam.position = b.grid.toWorld(Vec3{c.x + R.x * std::sin(t), c.y + 0.5 * R.y * std::sin(3 * t), c.z + R.z * std::sin(2 * t + 0.3)});
    Vec3 dir{R.x * std::cos(t), -0.15 * std::max(R.x, R.z), 2 * R.z * std::cos(2 * t + 0.3)};
    if (lengthSquared<3>(dir) == 0) dir = {1, 0, 0};
    cam.direction = dir;
    cam.fovDeg = fovDeg;
    cam.aspect = aspect;
    return cam;
}

} // namespace rgvc::reference
