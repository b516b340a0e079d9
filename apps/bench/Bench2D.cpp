// rgvc_bench2d: culling time and accuracy of the 2D regular-grid culler.
//
// Speed is measured here, never asserted in tests. Every scenario prints the median (and p90) per-frame
// culling time over a camera walk, for the full algorithm and, in the same run and on the same frames,
// the baselines it must beat: grid view-frustum culling only (no occlusion) and occlusion without
// occluder extension. The accuracy scenario compares every PVS with the exact analytic reference.
//
//   rgvc_bench2d [--scenario fig1|large|accuracy|all] [--frames N] [--repeats R] [--seed S]
#include "rgvc/dynamics/Culler.hpp"

#include "BenchSupport.hpp"

#include "ExactVisibility2D.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <random>
#include <string>
#include <vector>

using namespace rgvc;
using namespace rgvc::bench;

namespace {

struct BenchObject {
    ObjectDesc<2> desc;
    Vec2 velocity{0.0};
};

struct BenchScene {
    GridGeometry2 grid;
    std::vector<BenchObject> objects;
};

/// Random dense 2D scene in the spirit of the paper's Figure 1: circles (two thirds moving), boxes and
/// convex polygons (static), sizes 1.5 to 7 voxels, placed uniformly over the grid.
BenchScene makeScene(int resolution, int objectCount, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> pos(0, resolution), size(1.5, 7.0), unit(0, 1), ang(0, 2 * M_PI);
    BenchScene s{GridGeometry2({0, 0}, 1.0, {resolution, resolution}), {}};
    for (int i = 0; i < objectCount; ++i) {
        BenchObject o;
        o.desc.id = ObjectId(i);
        const Vec2 c{pos(rng), pos(rng)};
        const double r = size(rng);
        const double kind = unit(rng);
        if (kind < 0.55) {
            o.desc.shape = Ball<2>{c, r * 0.6};
            const double a = ang(rng), speed = 0.1 + 0.4 * unit(rng);
            o.velocity = Vec2{std::cos(a), std::sin(a)} * speed;
            o.desc.maxSpeed = speed;
        } else if (kind < 0.85) {
            const Vec2 half{r * (0.3 + unit(rng)), r * (0.3 + unit(rng))};
            o.desc.shape = Box<2>{c - half, c + half};
            o.desc.isStatic = true;
        } else {
            ConvexPolygon p;
            const int n = 3 + int(unit(rng) * 5);
            const double a0 = ang(rng);
            for (int k = 0; k < n; ++k) {
                const double a = a0 + 2 * M_PI * k / n;
                p.points.push_back(c + Vec2{std::cos(a), std::sin(a)} * r);
            }
            o.desc.shape = p;
            o.desc.isStatic = true;
        }
        s.objects.push_back(o);
    }
    return s;
}

/// A smooth camera walk: position on a Lissajous curve inside the grid, looking along its tangent.
Camera2 cameraAt(int resolution, int frame, int frames, double fovDeg) {
    const double t = 2 * M_PI * frame / frames;
    const double R = 0.4 * resolution, c = 0.5 * resolution;
    Camera2 cam;
    cam.position = {c + R * std::sin(t), c + R * std::sin(2 * t + 0.3)};
    cam.direction = {R * std::cos(t), 2 * R * std::cos(2 * t + 0.3)};
    if (lengthSquared<2>(cam.direction) == 0) cam.direction = {1, 0};
    cam.fovDeg = fovDeg;
    return cam;
}

/// Moves circles by their velocity, reflecting at the grid border.
void stepMotion(BenchScene& s, Culler2D* cullers[], int cullerCount, double& updateMs) {
    const auto t0 = std::chrono::steady_clock::now();
    const double n = s.grid.resolution().x;
    for (BenchObject& o : s.objects) {
        if (o.desc.isStatic) continue;
        Ball<2>& b = std::get<Ball<2>>(o.desc.shape);
        for (int a = 0; a < 2; ++a)
            if (b.center[a] + o.velocity[a] - b.radius < 0 || b.center[a] + o.velocity[a] + b.radius > n)
                o.velocity[a] = -o.velocity[a];
        b.center += o.velocity;
        for (int k = 0; k < cullerCount; ++k) cullers[k]->updateObject(o.desc.id, o.desc.shape);
    }
    updateMs += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / cullerCount;
}

struct Variant {
    const char* name;
    CullerOptions options;
};

void runTiming(const char* title, int resolution, int objectCount, int frames, int repeats, std::uint64_t seed) {
    std::printf("\n== %s: %dx%d grid, %d objects, %d frames x %d repeats, fov 90, camera walk ==\n", title, resolution,
                resolution, objectCount, frames, repeats);
    const Variant variants[] = {{"rgvc (occlusion + extension)", {true, true}},
                                {"rgvc, no occluder extension", {true, false}},
                                {"grid VFC only (baseline)", {false, false}}};
    constexpr int kVariants = 3;
    std::vector<double> ms[kVariants];
    double pvsSum[kVariants] = {}, visitedSum[kVariants] = {};
    double updateMs = 0;
    for (int rep = 0; rep < repeats; ++rep) {
        BenchScene scene = makeScene(resolution, objectCount, seed);
        std::vector<Culler2D> cullers;
        for (const Variant& v : variants) {
            cullers.emplace_back(scene.grid, v.options);
            for (const BenchObject& o : scene.objects) cullers.back().addObject(o.desc);
        }
        Culler2D* ptrs[kVariants] = {&cullers[0], &cullers[1], &cullers[2]};
        for (int f = 0; f < frames; ++f) {
            const Camera2 cam = cameraAt(resolution, f, frames, 90);
            for (int k = 0; k < kVariants; ++k) {
                const CullResult& r = cullers[k].cull(cam);
                ms[k].push_back(r.stats.cullMs);
                pvsSum[k] += r.stats.pvsSize;
                visitedSum[k] += double(r.stats.voxelsVisited);
            }
            stepMotion(scene, ptrs, kVariants, updateMs);
            if ((f + 1) % 100 == 0) std::fprintf(stderr, "\r  repeat %d/%d frame %d/%d", rep + 1, repeats, f + 1, frames);
        }
        std::fprintf(stderr, "\r%60s\r", "");
    }
    const double n = double(frames) * repeats;
    std::printf("%-32s %10s %10s %10s %12s\n", "variant", "median ms", "p90 ms", "mean |PVS|", "voxels/frame");
    for (int k = 0; k < kVariants; ++k)
        std::printf("%-32s %10.4f %10.4f %10.1f %12.0f\n", variants[k].name, percentile(ms[k], 0.5),
                    percentile(ms[k], 0.9), pvsSum[k] / n, visitedSum[k] / n);
    std::printf("object updates (re-rasterizing every moving object): %.4f ms per frame\n", updateMs / n);
}

void runAccuracy(int scenes, std::uint64_t seed) {
    std::printf("\n== accuracy: %d random scenes (64..256 grid, 50..300 objects, random cameras, fov 30..360) ==\n",
                scenes);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(0, 1);
    double overSum = 0, vfcSum = 0, pvsSum = 0, visSum = 0;
    int counted = 0;
    std::uint64_t misses = 0;
    for (int i = 0; i < scenes; ++i) {
        const int res = 64 + int(unit(rng) * 193);
        const int count = 50 + int(unit(rng) * 251);
        BenchScene s = makeScene(res, count, rng());
        Culler2D culler(s.grid);
        std::vector<Shape<2>> shapes;
        for (const BenchObject& o : s.objects) {
            culler.addObject(o.desc);
            shapes.push_back(o.desc.shape);
        }
        Camera2 cam;
        do {
            cam.position = {unit(rng) * res, unit(rng) * res};
        } while (false);
        const double a = unit(rng) * 2 * M_PI;
        cam.direction = {std::cos(a), std::sin(a)};
        cam.fovDeg = 30 + unit(rng) * 330;
        const CullResult& r = culler.cull(cam);
        const std::vector<bool> vis = reference::exactVisible2D(shapes, cam);
        const std::vector<bool> vfc = reference::inViewRegion2D(shapes, cam);
        std::size_t visible = 0, inView = 0;
        for (std::size_t k = 0; k < shapes.size(); ++k) {
            visible += vis[k];
            inView += vfc[k];
            if (vis[k] && !std::binary_search(r.pvs.begin(), r.pvs.end(), s.objects[k].desc.id)) ++misses;
        }
        pvsSum += double(r.pvs.size());
        visSum += double(visible);
        if (visible > 0) {
            overSum += double(r.pvs.size()) / double(visible);
            vfcSum += double(inView) / double(visible);
            ++counted;
        }
        if ((i + 1) % 20 == 0) std::fprintf(stderr, "\r  scene %d/%d", i + 1, scenes);
    }
    std::fprintf(stderr, "\r%40s\r", "");
    std::printf("misses: %llu (must be 0)\n", (unsigned long long)misses);
    std::printf("mean |PVS|/|visible| = %.3f   mean |VFC|/|visible| = %.3f   (mean |PVS| %.1f, mean |visible| %.1f)\n",
                overSum / std::max(1, counted), vfcSum / std::max(1, counted), pvsSum / scenes, visSum / scenes);
}

} // namespace

int main(int argc, char** argv) {
    std::string scenario = "all";
    int frames = 400, repeats = 3, accuracyScenes = 300;
    std::uint64_t seed = 2002;
    for (int i = 1; i < argc; ++i) {
        auto need = [&](const char* flag) {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "rgvc_bench2d: %s needs a value\n", flag);
                std::exit(2);
            }
            return std::string(argv[++i]);
        };
        const std::string a = argv[i];
        if (a == "--scenario") scenario = need("--scenario");
        else if (a == "--frames") frames = std::max(1, std::atoi(need("--frames").c_str()));
        else if (a == "--repeats") repeats = std::max(1, std::atoi(need("--repeats").c_str()));
        else if (a == "--scenes") accuracyScenes = std::max(1, std::atoi(need("--scenes").c_str()));
        else if (a == "--seed") seed = std::strtoull(need("--seed").c_str(), nullptr, 10);
        else {
            std::fprintf(stderr,
                         "usage: rgvc_bench2d [--scenario fig1|large|accuracy|all] [--frames N] [--repeats R] "
                         "[--scenes N] [--seed S]\n");
            return a == "--help" || a == "-h" ? 0 : 2;
        }
    }
    std::printf("rgvc_bench2d on %s, one thread, seed %llu\n", machine().c_str(), (unsigned long long)seed);
    if (scenario == "fig1" || scenario == "all") runTiming("Figure 1 setting", 256, 300, frames, repeats, seed);
    if (scenario == "large" || scenario == "all") runTiming("large", 1024, 10000, frames, repeats, seed);
    if (scenario == "accuracy" || scenario == "all") runAccuracy(accuracyScenes, seed);
    return 0;
}
