// The scene classes of rgvc_bench_classes (ClassScenes.hpp).
#include "ClassScenes.hpp"

#include "RandomScenes3D.hpp"
#include "SeededRandom.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace rgvc::bench {

namespace {

namespace ref = rgvc::reference;
using rgvc::reference::seeded::chance;
using rgvc::reference::seeded::logUniform;
using rgvc::reference::seeded::uniform;
using rgvc::reference::seeded::uniform01;
using rgvc::reference::seeded::uniformInt;

constexpr double kPi = 3.14159265358979323846;



template <int D> bool overlapsOpen(const Box<D>& a, const Box<D>& b) {
    for (int k = 0; k < D; ++k)
        if (!(a.min[k] < b.max[k] && a.max[k] > b.min[k])) return false;
    return true;
}

template <int D> Box<D> gridBox(const GridGeometry<D>& g) {
    Box<D> b{g.origin(), g.origin()};
    for (int k = 0; k < D; ++k)
        b.max[k] += g.voxelSize() * g.resolution()[k];
    return b;
}

/// True when the bounds lie inside the grid and overlap no obstacle.
template <int D> bool freePlace(const World<D>& w, const Box<D>& b) {
    const Box<D> g = gridBox(w.grid);
    for (int k = 0; k < D; ++k)
        if (b.min[k] < g.min[k] || b.max[k] > g.max[k]) return false;
    for (const Box<D>& o : w.obstacles)
        if (overlapsOpen(b, o)) return false;
    return true;
}

/// One frame of the default motion: per axis, move by the velocity unless that leaves the grid or
/// overlaps an obstacle, in which case that component flips (and the object stays put on that axis).
template <int D> void defaultStep(World<D>& w) {
    for (std::size_t i = 0; i < w.objects.size(); ++i) {
        Vec<D>& v = w.velocity[i];
        bool moving = false;
        for (int k = 0; k < D; ++k)
            moving = moving || v[k] != 0;
        if (!moving) continue;
        Box<D> b = boundsOf<D>(w.objects[i].shape);
        Vec<D> delta{0.0};
        for (int k = 0; k < D; ++k) {
            if (v[k] == 0) continue;
            Box<D> c = b;
            c.min[k] += v[k];
            c.max[k] += v[k];
            if (freePlace(w, c)) {
                b = c;
                delta[k] = v[k];
            } else {
                v[k] = -v[k];
            }
        }
        w.objects[i].shape = translated<D>(w.objects[i].shape, delta);
    }
}



Vec3 unitVector3(std::mt19937_64& rng) {
    for (;;) {
        const Vec3 v{uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)};
        const double l2 = lengthSquared<3>(v);
        if (l2 > 1e-4 && l2 <= 1) return v / std::sqrt(l2);
    }
}

Vec2 unitVector2(std::mt19937_64& rng) {
    const double a = uniform(rng, 0, 2 * kPi);
    return {std::cos(a), std::sin(a)};
}

template <int D> void addStatic(World<D>& w, const Shape<D>& s) {
    ObjectDesc<D> o;
    o.id = ObjectId(w.objects.size());
    o.shape = s;
    o.isStatic = true;
    w.objects.push_back(o);
    w.velocity.push_back(Vec<D>{0.0});
}

/// A moving object at `shape` with velocity v (maxSpeed = |v|), or a still non-static one when v = 0.
template <int D> void addMoving(World<D>& w, const Shape<D>& s, const Vec<D>& v) {
    ObjectDesc<D> o;
    o.id = ObjectId(w.objects.size());
    o.shape = s;
    o.isStatic = false;
    o.maxSpeed = std::sqrt(lengthSquared<D>(v));
    w.objects.push_back(o);
    w.velocity.push_back(v);
}

/// Places a moving sphere of radius r uniformly in [lo, hi] (centres), clear of the obstacles; false after
/// many failed tries.
bool placeSphere(World<3>& w, std::mt19937_64& rng, double r, const Vec3& lo, const Vec3& hi, double speed) {
    for (int attempt = 0; attempt < 1000; ++attempt) {
        const Vec3 c{uniform(rng, lo.x, hi.x), uniform(rng, lo.y, hi.y), uniform(rng, lo.z, hi.z)};
        const Ball<3> b{c, r};
        if (!freePlace(w, boundsOf<3>(b))) continue;
        addMoving<3>(w, b, unitVector3(rng) * speed);
        return true;
    }
    return false;
}

Camera3 camera3(const Vec3& pos, const Vec3& dir) {
    Camera3 c;
    c.position = pos;
    c.direction = dir;
    c.fovDeg = 60;
    c.aspect = 16.0 / 9.0;
    return c;
}

} // namespace

template <int D> void stepWorld(World<D>& w) {
    if (w.step) w.step(w);
    else defaultStep(w);
}
template void stepWorld<2>(World<2>&);
template void stepWorld<3>(World<3>&);


/// 1. A closed room of six 1-voxel walls; `spheres` moving spheres outside it; the camera turns in place
/// at the room's centre (a full turn every 120 frames, pitch +-0.2 rad).
World<3> roomScene(const std::string& name, int spheres) {
    World<3> w;
    w.name = name;
    w.grid = GridGeometry3(Vec3(0.0), 1.0, {128, 64, 128});
    const Vec3 lo{39, 7, 39}, hi{89, 41, 89}; // outer box; interior [40,88] x [8,40] x [40,88]
    addStatic<3>(w, Box<3>{lo, {lo.x + 1, hi.y, hi.z}});
    addStatic<3>(w, Box<3>{{hi.x - 1, lo.y, lo.z}, hi});
    addStatic<3>(w, Box<3>{lo, {hi.x, lo.y + 1, hi.z}});
    addStatic<3>(w, Box<3>{{lo.x, hi.y - 1, lo.z}, hi});
    addStatic<3>(w, Box<3>{lo, {hi.x, hi.y, lo.z + 1}});
    addStatic<3>(w, Box<3>{{lo.x, lo.y, hi.z - 1}, hi});
    w.obstacles.push_back(Box<3>{lo, hi});
    std::mt19937_64 rng(0x500d + std::uint64_t(spheres));
    for (int i = 0; i < spheres; ++i) {
        const double r = logUniform(rng, 0.3, 1.5);
        placeSphere(w, rng, r, Vec3(r), Vec3{128 - r, 64 - r, 128 - r}, uniform(rng, 0.1, 0.5));
    }
    w.camera = [](int f) {
        const double yaw = 2 * kPi * f / 120.0, pitch = 0.2 * std::sin(2 * kPi * f / 45.0);
        return camera3({64.3, 24.2, 64.1},
                       {std::cos(yaw) * std::cos(pitch), std::sin(pitch), std::sin(yaw) * std::cos(pitch)});
    };
    w.description = "closed room (6 static walls), " + std::to_string(w.objects.size() - 6) +
                    " moving spheres outside it, camera turning in place";
    return w;
}

/// Spheres (60 %) and boxes in `clusters` bell-shaped clusters; `movingShare` of them move.
void addClusters(World<3>& w, std::mt19937_64& rng, int count, int clusters, double movingShare, double scattered,
                 const Vec3& cLo, const Vec3& cHi, double spreadLo, double spreadHi, double maxSize) {
    const Box<3> g = gridBox(w.grid);
    std::vector<Vec3> centres;
    std::vector<double> spreads;
    for (int k = 0; k < clusters; ++k) {
        centres.push_back({uniform(rng, cLo.x, cHi.x), uniform(rng, cLo.y, cHi.y), uniform(rng, cLo.z, cHi.z)});
        spreads.push_back(uniform(rng, spreadLo, spreadHi));
    }
    for (int i = 0; i < count; ++i) {
        Vec3 c;
        if (chance(rng, scattered)) {
            c = {uniform(rng, g.min.x, g.max.x), uniform(rng, g.min.y, g.max.y), uniform(rng, g.min.z, g.max.z)};
        } else {
            const std::size_t k = std::size_t(rng() % centres.size());
            for (int a = 0; a < 3; ++a)
                c[a] = centres[k][a] + (uniform01(rng) + uniform01(rng) + uniform01(rng) - 1.5) * spreads[k];
        }
        Shape<3> s;
        if (chance(rng, 0.6)) {
            const double r = logUniform(rng, 0.3, 0.5 * maxSize);
            for (int a = 0; a < 3; ++a)
                c[a] = std::clamp(c[a], g.min[a] + r, g.max[a] - r);
            s = Ball<3>{c, r};
        } else {
            Vec3 half{logUniform(rng, 0.25, 0.5 * maxSize), logUniform(rng, 0.25, 0.5 * maxSize),
                      logUniform(rng, 0.25, 0.5 * maxSize)};
            for (int a = 0; a < 3; ++a)
                c[a] = std::clamp(c[a], g.min[a] + half[a], g.max[a] - half[a]);
            s = Box<3>{c - half, c + half};
        }
        if (chance(rng, movingShare)) addMoving<3>(w, s, unitVector3(rng) * uniform(rng, 0.1, 0.5));
        else addStatic<3>(w, s);
    }
}

/// 2. 5,000 spheres and boxes in 8 clusters, 30 % moving; the camera circles the world looking inward.
World<3> clustersScene(int count) {
    World<3> w;
    w.name = "clusters";
    w.grid = GridGeometry3(Vec3(0.0), 1.0, {100, 60, 100});
    std::mt19937_64 rng(0xc105);
    addClusters(w, rng, count, 8, 0.3, 0.05, {25, 15, 25}, {75, 45, 75}, 4, 9, 4);
    w.camera = [](int f) {
        const double t = 0.3 + f / 45.0; // 1 unit per frame on a circle of radius 45
        const Vec3 p{50 + 45 * std::cos(t), 30 + 8 * std::sin(2 * t), 50 + 45 * std::sin(t)};
        return camera3(p, Vec3{50, 25, 50} - p);
    };
    w.description = std::to_string(count) + " spheres and boxes in 8 clusters, 30 % moving, camera circling inward";
    return w;
}

/// A smooth flying path (a Lissajous curve) and its tangent.
struct Flight {
    Vec3 centre, radius;
    double omega;
    Vec3 at(double f) const {
        const double t = omega * f;
        return {centre.x + radius.x * std::sin(t), centre.y + radius.y * std::sin(1.7 * t + 0.5),
                centre.z + radius.z * std::sin(2 * t + 0.3)};
    }
    Camera3 camera(int f, double pitch) const {
        Vec3 d = at(f + 2.0) - at(f);
        d.y += pitch * std::sqrt(d.x * d.x + d.z * d.z);
        return camera3(at(f), d);
    }
};

/// 3. A game level: ground, 50 box buildings (footprints 6-16, heights 10-50) clear of the camera's path,
/// 2,000 spheres moving at 0.05-0.5 among them, a flying camera at 5-20 units altitude.
World<3> gameScene(int buildings, int spheres) {
    World<3> w;
    w.name = "game";
    w.grid = GridGeometry3(Vec3(0.0), 1.0, {128, 64, 128});
    const Flight path{{64, 12.5, 64}, {46, 7.5, 46}, 0.011};
    addStatic<3>(w, Box<3>{{0, 0, 0}, {128, 1, 128}});
    w.obstacles.push_back(Box<3>{{0, 0, 0}, {128, 1, 128}});
    std::mt19937_64 rng(0x9a3e);
    for (int b = 0, tries = 0; b < buildings && tries < 100000; ++tries) {
        const int sx = uniformInt(rng, 6, 16), sz = uniformInt(rng, 6, 16), h = uniformInt(rng, 10, 50);
        const int x0 = uniformInt(rng, 0, 128 - sx), z0 = uniformInt(rng, 0, 128 - sz);
        const Box<3> box{{double(x0), 1, double(z0)}, {double(x0 + sx), double(1 + h), double(z0 + sz)}};
        const Box<3> grown{box.min - Vec3(2.0), box.max + Vec3(2.0)};
        bool clear = true;
        for (const Box<3>& o : w.obstacles)
            if (o.min.y > 0 && overlapsOpen(grown, o)) clear = false; // 2 units between buildings
        for (int s = 0; s < 3000 && clear; ++s) {                     // and 3 units from the camera's path (one period)
            const Vec3 p = path.at(s * (2 * kPi / path.omega) / 3000);
            if (p.x > box.min.x - 3 && p.x < box.max.x + 3 && p.z > box.min.z - 3 && p.z < box.max.z + 3 &&
                p.y < box.max.y + 3)
                clear = false;
        }
        if (!clear) continue;
        addStatic<3>(w, box);
        w.obstacles.push_back(box);
        ++b;
    }
    for (int i = 0; i < spheres; ++i) {
        const double r = logUniform(rng, 0.3, 1.5);
        placeSphere(w, rng, r, Vec3{r, 1 + r, r}, Vec3{128 - r, 64 - r, 128 - r}, uniform(rng, 0.05, 0.5));
    }
    w.camera = [path](int f) { return path.camera(f, -0.15); };
    w.description = std::to_string(w.obstacles.size() - 1) + " box buildings on a ground, " +
                    std::to_string(w.objects.size() - w.obstacles.size()) + " moving spheres, flying camera";
    return w;
}

/// 4. 512 x 128 x 512, mostly empty: four clusters of `perCluster` objects (half of them moving); the
/// camera flies over the whole world.
World<3> largeScene(int perCluster) {
    World<3> w;
    w.name = "large";
    w.grid = GridGeometry3(Vec3(0.0), 1.0, {512, 128, 512});
    std::mt19937_64 rng(0x1a29e);
    addClusters(w, rng, 4 * perCluster, 4, 0.5, 0.0, {100, 30, 100}, {412, 98, 412}, 12, 25, 6);
    const Flight path{{256, 64, 256}, {210, 40, 210}, 0.0024};
    w.camera = [path](int f) { return path.camera(f, -0.1); };
    w.description = "four clusters of " + std::to_string(perCluster) + " objects (half moving), flying camera";
    return w;
}

/// 5. An empty side^3 grid (512^3; 256^3 with --quick) holding one tiny static sphere; the camera sits in
/// a corner looking across.
World<3> emptyScene(int side) {
    World<3> w;
    w.name = "empty";
    w.grid = GridGeometry3(Vec3(0.0), 1.0, {side, side, side});
    addStatic<3>(w, Ball<3>{Vec3(0.5 * side + 0.5), 0.25});
    w.camera = [](int f) {
        const double a = 0.02 * f;
        return camera3({1.5, 1.5, 1.5}, {std::cos(kPi / 4 + a), 0.8, std::sin(kPi / 4 + a)});
    };
    w.maxFrames = 5;
    w.description = "empty but for one tiny static sphere, camera in a corner looking across (at most 5 frames)";
    return w;
}

/// A closed walk along street centre lines: the square with corners (a, a) and (b, b), parameterised by
/// arc length s; the view looks 4 units ahead along the walk.
struct StreetWalk {
    double a, b;
    Vec2 at(double s) const {
        const double side = b - a;
        s = std::fmod(s, 4 * side);
        if (s < 0) s += 4 * side;
        if (s < side) return {a + s, a};
        if (s < 2 * side) return {b, a + (s - side)};
        if (s < 3 * side) return {b - (s - 2 * side), b};
        return {a, b - (s - 3 * side)};
    }
    /// The walk's camera in frame f: 0.75 per frame from arc length `start`, looking 4 ahead, the heading
    /// swayed sideways by up to `sway` (relative) so that the view is never exactly along a street.
    /// d: the unswayed heading (its length sets the 3D camera's downward tilt).
    struct Pose {
        Vec2 position, direction, d;
    };
    Pose pose(int f, double start, double sway) const {
        const double s = start + 0.75 * f;
        const Vec2 p = at(s), q = at(s + 4);
        const double wobble = sway * std::sin(f / 7.0);
        const Vec2 d = q - p;
        return {p, {d.x - wobble * d.y, d.y + wobble * d.x}, d};
    }
};

/// 6. A 96 x 24 x 96 box city: 8 x 8 blocks of 9 x 9 (streets 3 wide), each block four abutting buildings
/// 6-20 high on a ground slab; the camera walks the streets at eye height 1.5; small spheres move in the
/// streets (below an invisible ceiling at y = 5, so never over a roof).
World<3> city3dScene(int spheres) {
    World<3> w;
    w.name = "city3d";
    w.grid = GridGeometry3(Vec3(0.0), 1.0, {96, 24, 96});
    addStatic<3>(w, Box<3>{{0, 0, 0}, {96, 1, 96}});
    w.obstacles.push_back(Box<3>{{0, 0, 0}, {96, 1, 96}});
    w.obstacles.push_back(Box<3>{{0, 5, 0}, {96, 24, 96}});
    std::mt19937_64 rng(0xc17e);
    for (int bx = 0; bx < 8; ++bx)
        for (int bz = 0; bz < 8; ++bz)
            for (int q = 0; q < 4; ++q) {
                const double x0 = 12 * bx + 3 + (q & 1 ? 4.5 : 0), z0 = 12 * bz + 3 + (q & 2 ? 4.5 : 0);
                const Box<3> box{{x0, 1, z0}, {x0 + 4.5, 1.0 + uniformInt(rng, 6, 20), z0 + 4.5}};
                addStatic<3>(w, box);
                w.obstacles.push_back(box);
            }
    for (int i = 0; i < spheres; ++i) {
        const double r = logUniform(rng, 0.2, 0.6);
        placeSphere(w, rng, r, Vec3{r, 1 + r, r}, Vec3{96 - r, 5 - r, 96 - r}, uniform(rng, 0.05, 0.3));
    }
    const StreetWalk walk{13.5, 73.5};
    w.camera = [walk](int f) {
        const StreetWalk::Pose v = walk.pose(f, 30, 0.15);
        return camera3({v.position.x, 1.5, v.position.y},
                       {v.direction.x, -0.05 * std::sqrt(lengthSquared<2>(v.d)), v.direction.y});
    };
    w.description = "box city, 256 buildings in 64 blocks, " + std::to_string(w.objects.size() - 257) +
                    " small moving spheres in the streets, camera walking at eye height";
    return w;
}

/// 7. The paper's scene (reference::movingSpheres3D, as rgvc_bench3d): 5,000 spheres of radius 0.3-3 in
/// 8 clusters + 20 % scattered, all moving up to 0.5 per frame, camera on its Lissajous walk at 480 frames
/// per loop (rgvc_bench3d runs the loop in its --frames, 80 by default: 6x faster).
World<3> paperScene(int count) {
    World<3> w;
    w.name = "paper";
    auto b = std::make_shared<ref::MovingSpheres3D>(ref::movingSpheres3D(2004, count));
    w.grid = b->grid;
    w.objects = b->objects;
    w.velocity.assign(w.objects.size(), Vec3(0.0)); // unused: the paper's own motion below
    w.step = [b](World<3>& self) {
        ref::stepMovingSpheres(*b);
        for (std::size_t i = 0; i < self.objects.size(); ++i)
            self.objects[i].shape = b->objects[i].shape;
    };
    w.camera = [b](int f) { return ref::movingSpheresCamera(*b, f, 480); };
    w.description = std::to_string(count) + " moving spheres (reference::movingSpheres3D, seed 2004), Lissajous walk";
    return w;
}

/// 8. A 128 x 128 box city in 2D: 8 x 8 blocks of 12 x 12 (streets 4 wide), each four abutting buildings;
/// small circles move in the streets; the camera walks the streets, fov 90.
World<2> city2dScene(int circles) {
    World<2> w;
    w.name = "city2d";
    w.grid = GridGeometry2(Vec2(0.0), 1.0, {128, 128});
    for (int bx = 0; bx < 8; ++bx)
        for (int bz = 0; bz < 8; ++bz) {
            for (int q = 0; q < 4; ++q) {
                const double x0 = 16 * bx + 4 + (q & 1 ? 6 : 0), z0 = 16 * bz + 4 + (q & 2 ? 6 : 0);
                addStatic<2>(w, Box<2>{{x0, z0}, {x0 + 6, z0 + 6}});
            }
            w.obstacles.push_back(Box<2>{{16.0 * bx + 4, 16.0 * bz + 4}, {16.0 * bx + 16, 16.0 * bz + 16}});
        }
    std::mt19937_64 rng(0xc172d);
    for (int i = 0; i < circles; ++i)
        for (int attempt = 0; attempt < 1000; ++attempt) {
            const double r = logUniform(rng, 0.3, 0.8);
            const Ball<2> c{{uniform(rng, r, 128 - r), uniform(rng, r, 128 - r)}, r};
            if (!freePlace(w, boundsOf<2>(c))) continue;
            addMoving<2>(w, c, unitVector2(rng) * uniform(rng, 0.05, 0.3));
            break;
        }
    const StreetWalk walk{18, 98};
    w.camera = [walk](int f) {
        const StreetWalk::Pose v = walk.pose(f, 40, 0.2);
        Camera2 c;
        c.position = v.position;
        c.direction = v.direction;
        c.fovDeg = 90;
        return c;
    };
    w.description = "2D box city, 256 buildings in 64 blocks, " + std::to_string(w.objects.size() - 256) +
                    " moving circles in the streets, camera walking, fov 90";
    return w;
}

/// 9. A random dense 2D scene in the manner of rgvc_bench2d's Figure 1 setting (written anew here: that
/// generator is private to Bench2D.cpp): circles (55 %, moving at 0.1-0.5), boxes (30 %) and convex
/// polygons (static), sizes 1.5-7, uniform over 256 x 256; the camera on a Lissajous walk, fov 90.
World<2> random2dScene(int count) {
    World<2> w;
    w.name = "random2d";
    w.grid = GridGeometry2(Vec2(0.0), 1.0, {256, 256});
    std::mt19937_64 rng(0x2a2d);
    for (int i = 0; i < count; ++i) {
        const double size = uniform(rng, 1.5, 7.0), kind = uniform01(rng);
        Vec2 c{uniform(rng, 0, 256), uniform(rng, 0, 256)};
        if (kind < 0.55) {
            const double r = 0.6 * size;
            c = glm::clamp(c, Vec2(r), Vec2(256 - r));
            addMoving<2>(w, Ball<2>{c, r}, unitVector2(rng) * uniform(rng, 0.1, 0.5));
        } else if (kind < 0.85) {
            const Vec2 half{size * uniform(rng, 0.3, 1.3), size * uniform(rng, 0.3, 1.3)};
            addStatic<2>(w, Box<2>{c - half, c + half});
        } else {
            ConvexPolygon p;
            const int n = uniformInt(rng, 3, 7);
            const double a0 = uniform(rng, 0, 2 * kPi);
            for (int k = 0; k < n; ++k)
                p.points.push_back(c + Vec2{std::cos(a0 + 2 * kPi * k / n), std::sin(a0 + 2 * kPi * k / n)} * size);
            addStatic<2>(w, p);
        }
    }
    w.camera = [](int f) {
        const double t = 2 * kPi * f / 600.0;
        Camera2 c;
        c.position = {128 + 100 * std::sin(t), 128 + 100 * std::sin(2 * t + 0.3)};
        c.direction = {std::cos(t), 2 * std::cos(2 * t + 0.3)};
        c.fovDeg = 90;
        return c;
    };
    w.description = std::to_string(count) + " random circles (moving), boxes and polygons, Lissajous walk, fov 90";
    return w;
}

/// 10. A closed 2D room (four static walls 1 voxel thick, interior [40,88]^2 in 128^2) with `circles`
/// moving circles outside it; the camera turns in place inside, fov 90.
World<2> room2dScene(int circles) {
    World<2> w;
    w.name = "room2d";
    w.grid = GridGeometry2(Vec2(0.0), 1.0, {128, 128});
    const Vec2 lo{39, 39}, hi{89, 89};
    addStatic<2>(w, Box<2>{lo, {lo.x + 1, hi.y}});
    addStatic<2>(w, Box<2>{{hi.x - 1, lo.y}, hi});
    addStatic<2>(w, Box<2>{lo, {hi.x, lo.y + 1}});
    addStatic<2>(w, Box<2>{{lo.x, hi.y - 1}, hi});
    w.obstacles.push_back(Box<2>{lo, hi});
    std::mt19937_64 rng(0x2007 + std::uint64_t(circles));
    for (int i = 0; i < circles; ++i)
        for (int attempt = 0; attempt < 1000; ++attempt) {
            const double r = logUniform(rng, 0.3, 1.5);
            const Ball<2> c{{uniform(rng, r, 128 - r), uniform(rng, r, 128 - r)}, r};
            if (!freePlace(w, boundsOf<2>(c))) continue;
            addMoving<2>(w, c, unitVector2(rng) * uniform(rng, 0.1, 0.5));
            break;
        }
    w.camera = [](int f) {
        const double yaw = 2 * kPi * f / 120.0;
        Camera2 c;
        c.position = {64.3, 64.1};
        c.direction = {std::cos(yaw), std::sin(yaw)};
        c.fovDeg = 90;
        return c;
    };
    w.description = "closed 2D room (4 static walls), " + std::to_string(w.objects.size() - 4) +
                    " moving circles outside it, camera turning in place, fov 90";
    return w;
}

/// 11. A large, mostly empty 2D world: 2048 x 2048 unit voxels, four clusters of `perCluster` circles and
/// boxes (half the circles moving), the camera flying across it looking ahead, fov 90. (`side` 0: the
/// same grid with nothing but one tiny circle: the empty world.)
World<2> large2dScene(int perCluster, const char* name) {
    World<2> w;
    w.name = name;
    const double side = 2048;
    w.grid = GridGeometry2(Vec2(0.0), 1.0, {2048, 2048});
    std::mt19937_64 rng(0x1a2e);
    if (perCluster == 0) addStatic<2>(w, Ball<2>{{1024.5, 1024.5}, 0.25});
    const Vec2 centres[4] = {{400, 500}, {1500, 400}, {1200, 1500}, {500, 1600}};
    for (const Vec2& c0 : centres)
        for (int i = 0; i < perCluster; ++i)
            for (int attempt = 0; attempt < 1000; ++attempt) {
                const Vec2 c = c0 + Vec2{uniform(rng, -60, 60), uniform(rng, -60, 60)};
                if (chance(rng, 0.6)) {
                    const double r = logUniform(rng, 0.5, 3.0);
                    const Ball<2> b{c, r};
                    if (!freePlace(w, boundsOf<2>(b))) continue;
                    if (chance(rng, 0.5)) addMoving<2>(w, b, unitVector2(rng) * uniform(rng, 0.1, 0.5));
                    else addStatic<2>(w, b);
                } else {
                    const Vec2 half{uniform(rng, 1, 6), uniform(rng, 1, 6)};
                    const Box<2> b{c - half, c + half};
                    if (!freePlace(w, b)) continue;
                    addStatic<2>(w, b);
                }
                break;
            }
    w.camera = [side](int f) {
        const double t = 2 * kPi * f / 400.0;
        Camera2 c;
        c.position = {0.5 * side + 0.4 * side * std::sin(t), 0.5 * side + 0.4 * side * std::sin(2 * t + 0.3)};
        c.direction = {std::cos(t), 2 * std::cos(2 * t + 0.3)};
        c.fovDeg = 90;
        return c;
    };
    w.description = perCluster == 0 ? "an empty 2048^2 2D world but for one tiny circle, camera flying across, fov 90"
                                     : "large 2D world 2048^2, four clusters of " + std::to_string(perCluster) +
                                           " circles and boxes, camera flying across, fov 90";
    return w;
}

} // namespace rgvc::bench
