// rgvc_bench_views --ortho: a shadow-cascade-like orthographic view over a small city, culled with the
// parallel-ray occlusion (CullerOptions::orthographicOcclusion = true) and with view-volume culling
// only (orthographicOcclusion = false, the default), interleaved frame by frame on the same scene.
//
// The scene (fixed seed): a 128 x 48 x 128 grid of unit voxels; 60 buildings (boxes 6-18 wide, 8-40
// tall; every other one hollow: four walls and a roof 1 voxel thick, with spheres inside) and a deck (a slab at height 22 over a quarter of the city); `spheres` moving spheres
// (radius 0.3-1.5, max_speed 0.5, pushed with updateObject every frame, reflected at the grid and never
// entering a building). The camera: an orthographic box 64 x 64 wide looking along the sun direction
// (0.3, -1, 0.2), sweeping across the city. Per frame: cull_ms of both cullers (stats.cullMs, wall
// time) and the thread's CPU time for the call (on a shared machine wall time includes waiting for a
// core), their |PVS|; every refEvery-th frame the sampled parallel-ray reference (reference/OrthoVisibility.hpp, 100
// samples per sphere, over the objects the view box touches) gives |visible|, and a miss exits 1.
#include "BenchOrtho.hpp"

#include "rgvc/dynamics/Culler.hpp"

#include "BenchSupport.hpp"

#include "OrthoVisibility.hpp"
#include "SeededRandom.hpp"

#include <algorithm>
#include <cstdio>
#include <random>
#include <vector>

namespace rgvc::bench {

namespace {

bool overlaps(const Box<3>& a, const Box<3>& b) {
    for (int k = 0; k < 3; ++k)
        if (a.max[k] <= b.min[k] || b.max[k] <= a.min[k]) return false;
    return true;
}

} // namespace

int runOrthoBench(int frames, int spheres, int seed, int refEvery) {
    const GridGeometry3 grid({0, 0, 0}, 1.0, {128, 48, 128});
    std::mt19937_64 rng(std::uint64_t(seed) * 7919 + 3);
    std::uniform_real_distribution<double> u01(0, 1);
    std::vector<Box<3>> solids;
    std::vector<ObjectDesc<3>> objects;
    for (int k = 0; k < 60; ++k) {
        const double w = 6 + 12 * u01(rng), d = 6 + 12 * u01(rng), h = 8 + 32 * u01(rng);
        const double x = 2 + (124 - w) * u01(rng), z = 2 + (124 - d) * u01(rng);
        if (k % 2 == 0) { // solid
            const Box<3> b{{x, 0, z}, {x + w, h, z + d}};
            solids.push_back(b);
            objects.push_back({.id = ObjectId(100000 + 10 * k), .shape = b, .isStatic = true});
            continue;
        }
        // Hollow: four walls and a roof, 1 thick; spheres may live inside.
        const Box<3> parts[5] = {{{x, 0, z}, {x + 1, h, z + d}},         {{x + w - 1, 0, z}, {x + w, h, z + d}},
                                 {{x, 0, z}, {x + w, h, z + 1}},         {{x, 0, z + d - 1}, {x + w, h, z + d}},
                                 {{x, h - 1, z}, {x + w, h, z + d}}};
        for (int p = 0; p < 5; ++p) {
            solids.push_back(parts[p]);
            objects.push_back({.id = ObjectId(100000 + 10 * k + p), .shape = parts[p], .isStatic = true});
        }
    }
    const Box<3> deck{{0, 22, 64}, {64, 23, 128}};
    solids.push_back(deck);
    objects.push_back({.id = 200000, .shape = deck, .isStatic = true});
    std::vector<Vec3> velocity;
    const std::size_t firstSphere = objects.size();
    while (int(objects.size() - firstSphere) < spheres) {
        const double r = 0.3 + 1.2 * u01(rng);
        const Vec3 c(r + (128 - 2 * r) * u01(rng), r + (46 - 2 * r) * u01(rng), r + (128 - 2 * r) * u01(rng));
        const Box<3> bb{c - r, c + r};
        bool free = true;
        for (const Box<3>& s : solids) free = free && !overlaps(bb, s);
        if (!free) continue;
        Vec3 v(u01(rng) - 0.5, u01(rng) - 0.5, u01(rng) - 0.5);
        velocity.push_back(0.5 * v / std::max(1e-9, std::sqrt(lengthSquared<3>(v))));
        objects.push_back({.id = ObjectId(objects.size() - firstSphere), .shape = Ball<3>{c, r}, .maxSpeed = 0.5});
    }
    CullerOptions vfcOptions;
    vfcOptions.orthographicOcclusion = false;
    CullerOptions occlOptions;
    occlOptions.orthographicOcclusion = true;
    Culler3D occl(grid, occlOptions), vfc(grid, vfcOptions);
    for (const ObjectDesc<3>& o : objects) {
        occl.addObject(o);
        vfc.addObject(o);
    }
    std::vector<double> msO, msV, cpuO, cpuV; // wall (stats.cullMs) and this thread's CPU time per cull
    double pvsO = 0, pvsV = 0, visSum = 0, ratioO = 0, ratioV = 0;
    int checked = 0, misses = 0;
    std::uint64_t bricks = 0;
    for (int f = 0; f < frames; ++f) {
        // Motion: per axis, a step that would leave the grid or enter a solid flips that component.
        for (std::size_t i = firstSphere; i < objects.size(); ++i) {
            Ball<3> b = std::get<Ball<3>>(objects[i].shape);
            Vec3& v = velocity[i - firstSphere];
            for (int a = 0; a < 3; ++a) {
                Ball<3> n = b;
                n.center[a] += v[a];
                bool ok = n.center[a] - n.radius > 0 && n.center[a] + n.radius < double(grid.resolution()[a]);
                for (const Box<3>& s : solids) ok = ok && !overlaps(Box<3>{n.center - n.radius, n.center + n.radius}, s);
                if (ok) b = n;
                else v[a] = -v[a];
            }
            objects[i].shape = b;
            occl.updateObject(objects[i].id, b);
            vfc.updateObject(objects[i].id, b);
        }
        Camera3 cam;
        cam.projection = Projection::Orthographic;
        const double s = double(f) / std::max(1, frames - 1);
        cam.position = {32 + 64 * s, 80, 20 + 88 * s};
        cam.direction = {0.3, -1, 0.2};
        cam.width = 64;
        cam.height = 64;
        const bool first = f % 2 == 0; // alternate which culler runs first
        const double c0 = threadCpuMs();
        const CullResult& a = first ? occl.cull(cam) : vfc.cull(cam);
        const double c1 = threadCpuMs();
        const CullResult& b = first ? vfc.cull(cam) : occl.cull(cam);
        const double c2 = threadCpuMs();
        const CullResult& ro = first ? a : b;
        const CullResult& rv = first ? b : a;
        cpuO.push_back(first ? c1 - c0 : c2 - c1);
        cpuV.push_back(first ? c2 - c1 : c1 - c0);
        msO.push_back(ro.stats.cullMs);
        msV.push_back(rv.stats.cullMs);
        pvsO += double(ro.pvs.size());
        pvsV += double(rv.pvs.size());
        bricks += ro.stats.bricksVisited;
        if (refEvery > 0 && f % refEvery == 0) {
            // The reference over the objects the view box touches (VFC's PVS: exactly those).
            std::vector<Shape<3>> shapes;
            std::vector<ObjectId> ids;
            for (const ObjectDesc<3>& o : objects)
                if (std::binary_search(rv.pvs.begin(), rv.pvs.end(), o.id)) shapes.push_back(o.shape), ids.push_back(o.id);
            reference::OrthoOptions opt;
            opt.ballSamples = 100;
            opt.edgeSamples = 8;
            const std::vector<bool> vis = reference::orthoVisible<3>(shapes, cam, {}, opt);
            int visible = 0;
            for (std::size_t i = 0; i < vis.size(); ++i) {
                if (!vis[i]) continue;
                ++visible;
                if (!std::binary_search(ro.pvs.begin(), ro.pvs.end(), ids[i])) {
                    ++misses;
                    std::fprintf(stderr, "rgvc_bench_views --ortho: frame %d: object %llu visible but culled\n", f,
                                 (unsigned long long)ids[i]);
                }
            }
            if (visible > 0) {
                ++checked;
                visSum += visible;
                ratioO += double(ro.pvs.size()) / visible;
                ratioV += double(rv.pvs.size()) / visible;
            }
        }
    }
    std::printf("rgvc_bench_views --ortho: %zu objects (%d moving spheres, %zu static occluders), %d frames, %s\n",
                objects.size(), spheres, objects.size() - std::size_t(spheres), frames, machine().c_str());
    std::printf("| ortho variant | median cull_ms | p90 | median CPU ms | mean PVS | PVS/visible |\n|---|---|---|---|---|---|\n");
    std::printf("| occlusion | %.3f | %.3f | %.3f | %.1f | %.2f |\n", percentile(msO, 0.5), percentile(msO, 0.9),
                percentile(cpuO, 0.5), pvsO / frames, checked ? ratioO / checked : 0.0);
    std::printf("| view volume (VFC) | %.3f | %.3f | %.3f | %.1f | %.2f |\n", percentile(msV, 0.5), percentile(msV, 0.9),
                percentile(cpuV, 0.5), pvsV / frames, checked ? ratioV / checked : 0.0);
    std::printf("  reference checks: %d frames, mean |visible| %.1f, %d misses; occlusion read %.1f bricks per frame\n", checked,
                checked ? visSum / checked : 0.0, misses, double(bricks) / frames);
    return misses == 0 ? 0 : 1;
}

} // namespace rgvc::bench
