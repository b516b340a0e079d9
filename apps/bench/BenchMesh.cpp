// rgvc_bench_mesh: what a closed mesh costs as an occluder (MeshSolid.hpp): building the model (weld,
// topology, hull), voxelizing its solid (O) at several voxel sizes, and a moving mesh's per-frame update
// (re-voxelized on every move) in a culler. Medians over repeated runs (thread CPU time).
//
//   rgvc_bench_mesh [MESH_FILE] [--scale S] [--runs N]
//
// Default mesh: scenes/meshes/house.gltf (the project's glTF building), placed at scale S (default 4).
#include "MeshFile.hpp"

#include "BenchSupport.hpp"
#include "rgvc/dynamics/Culler.hpp"
#include "rgvc/grid/MeshSolid.hpp"

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

using namespace rgvc;

int main(int argc, char** argv) {
    std::string file = RGVC_SCENES_DIR "/meshes/house.gltf";
    double scale = 4;
    int runs = 21;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--scale" && i + 1 < argc) scale = std::atof(argv[++i]);
        else if (a == "--runs" && i + 1 < argc) runs = std::max(1, std::atoi(argv[++i]));
        else if (!a.empty() && a[0] != '-') file = a;
        else {
            std::fprintf(stderr, "usage: rgvc_bench_mesh [MESH_FILE] [--scale S] [--runs N]\n");
            return 2;
        }
    }
    std::printf("%s\n", bench::machine().c_str());
    try {
        TriangleMesh mesh = readMeshFile(file);
        for (Vec3& p : mesh.positions) p *= scale;
        std::vector<double> build;
        std::shared_ptr<const MeshModel> model;
        for (int r = 0; r < runs; ++r) {
            const double t0 = bench::threadCpuMs();
            model = makeMeshModel(mesh, "mesh");
            build.push_back(bench::threadCpuMs() - t0);
        }
        Vec3 lo, hi;
        meshBounds(model->mesh, lo, hi);
        std::printf("%s at scale %g: %zu triangles, %zu welded vertices, %s, extent %.3g x %.3g x %.3g\n", file.c_str(), scale,
                    model->mesh.triangles.size(), model->mesh.positions.size(), model->closed() ? "closed" : "open", hi.x - lo.x,
                    hi.y - lo.y, hi.z - lo.z);
        std::printf("model (weld, topology, hull): median %.4f ms over %d runs\n", bench::percentile(build, 0.5), runs);
        const MeshSolid solid(model);
        MeshVoxelization scratch;
        for (double voxel : {1.0, 0.5, 0.25, 0.125}) {
            const Vec3 origin = lo - 2 * voxel;
            IVec3 res;
            for (int a = 0; a < 3; ++a) res[a] = int((hi[a] - lo[a]) / voxel) + 5;
            const MeshSolid local = solid.mapped(origin, 1 / voxel);
            std::vector<double> t;
            std::size_t voxels = 0, spans = 0;
            for (int r = 0; r < runs; ++r) {
                const double t0 = bench::threadCpuMs();
                voxelizeMeshSolid(local, res, true, kConservativeSlack, scratch);
                t.push_back(bench::threadCpuMs() - t0);
            }
            for (const VoxelRowSpan& s : scratch.spans) voxels += std::size_t(s.x1 - s.x0 + 1);
            spans = scratch.spans.size();
            std::printf("O at voxel %.3g (grid %d x %d x %d): %zu voxels in %zu spans, median %.4f ms\n", voxel, res.x, res.y, res.z,
                        voxels, spans, bench::percentile(t, 0.5));
        }
        // A moving mesh in a culler: updateObject every frame, then cull (the update re-voxelizes it).
        const double voxel = 0.5;
        const GridGeometry3 grid(lo - Vec3(8.0), voxel, {int((hi.x - lo.x) / voxel) + 48, int((hi.y - lo.y) / voxel) + 48,
                                                        int((hi.z - lo.z) / voxel) + 48});
        Culler3D culler(grid);
        ObjectDesc<3> d;
        d.id = 1;
        d.shape = solid;
        d.maxSpeed = 0.3;
        culler.addObject(d);
        Camera3 cam;
        cam.position = 0.5 * (lo + hi) - Vec3(0, 0, 0.5 * (hi.z - lo.z) + 6); // in the grid, in front of the mesh
        cam.direction = {0, 0, 1};
        cam.fovDeg = 60;
        std::vector<double> upd, cull;
        MeshSolid at = solid;
        for (int f = 0; f < 4 * runs; ++f) {
            at = at.translated(Vec3(0.1 * ((f / 20) % 2 ? -1 : 1), 0, 0.05));
            double t0 = bench::threadCpuMs();
            culler.updateObject(1, at);
            upd.push_back(bench::threadCpuMs() - t0);
            t0 = bench::threadCpuMs();
            (void)culler.cull(cam);
            cull.push_back(bench::threadCpuMs() - t0);
        }
        std::printf("moving in a culler at voxel %.3g: updateObject median %.4f ms, cull median %.4f ms over %d frames\n", voxel,
                    bench::percentile(upd, 0.5), bench::percentile(cull, 0.5), 4 * runs);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "rgvc_bench_mesh: %s\n", e.what());
        return 2;
    }
    return 0;
}
