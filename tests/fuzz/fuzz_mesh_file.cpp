// libFuzzer target: arbitrary bytes -> a mesh file (.obj, .gltf or .glb, chosen by the first byte) ->
// rgvc::sceneMeshShape (readMeshFile, placement, validation, the MeshSolid the culler gets) -> one cull.
//
// A MeshFileError (the file) or an InvalidInput (the placed mesh) is the one acceptable way to refuse
// (the scene loader turns both into exit status 2 and one line); anything else that escapes (another
// exception, a crash, a sanitizer report, a hang, a huge allocation) is a bug. A mesh that loads must be
// usable: it passes the core's validateMesh, and the shape the culler gets passes validateShape and its
// hull contains every placed vertex (it must: the hull is what makes the mesh conservative). Then it goes
// through a culler once (a 24^3 grid around it, the mesh and a sphere behind it, a camera in front): the
// mesh, alone in front of the camera, must be in the PVS; InvalidInput (a grid that the mesh's extent
// makes unrepresentable) is the only refusal there.
//
// The readers take a path, so each input is written to a file in a directory of this process (the scene
// loader's mesh files are files too; libtinygltf and tinyobjloader read from disk).
//
// Build: -DRGVC_BUILD_FUZZERS=ON -DCMAKE_CXX_COMPILER=clang++; run: scripts/fuzz.sh mesh_file.
#include "MeshFile.hpp"
#include "SceneMesh.hpp"

#include "rgvc/dynamics/Culler.hpp"
#include "rgvc/grid/TriangleMesh.hpp"

#include <algorithm>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include <unistd.h>

namespace {

[[noreturn]] void bug(const std::string& what) {
    std::fprintf(stderr, "fuzz_mesh_file: BUG: %s\n", what.c_str());
    std::fflush(stderr);
    std::abort();
}

bool inside(const rgvc::Shape<3>& shape, const rgvc::Vec3& p) {
    const rgvc::Box<3> b = rgvc::boundsOf<3>(shape);
    const double slack = 1e-6 * (1 + std::abs(p.x) + std::abs(p.y) + std::abs(p.z));
    for (int a = 0; a < 3; ++a)
        if (p[a] < b.min[a] - slack || p[a] > b.max[a] + slack) return false;
    const auto* mesh = std::get_if<rgvc::MeshSolid>(&shape);
    if (mesh == nullptr) return false;
    if (const rgvc::ConvexPolytope* poly = &mesh->hull())
        for (const rgvc::HalfSpace& h : poly->planes)
            if (glm::dot(h.normal, p) > h.offset + poly->tolerance + slack) return false;
    return true;
}

/// The mesh in a culler once: a 24^3 grid spanning 1.5 times its bounds, the mesh (role both: a closed one
/// occludes through its voxelization) and a sphere behind it, the camera in front looking at it.
void cullOnce(const rgvc::Shape<3>& shape) {
    const rgvc::Box<3> b = rgvc::boundsOf<3>(shape);
    const rgvc::Vec3 c = 0.5 * (b.min + b.max), e = b.max - b.min;
    const double extent = std::max({e.x, e.y, e.z});
    if (!(extent > 0) || !std::isfinite(extent) || !std::isfinite(4 * extent + std::abs(c.x) + std::abs(c.y) + std::abs(c.z))) return;
    try {
        const double voxel = 4 * extent / 24;
        rgvc::Culler3D culler(rgvc::GridGeometry3(c - 2 * extent, voxel, {24, 24, 24}));
        rgvc::ObjectDesc<3> m;
        m.id = 1;
        m.shape = shape;
        m.isStatic = true;
        culler.addObject(m);
        rgvc::ObjectDesc<3> ball;
        ball.id = 2;
        ball.shape = rgvc::Ball<3>{c + rgvc::Vec3{0, 0, 1.2 * extent}, 0.2 * extent};
        ball.isStatic = true;
        culler.addObject(ball);
        rgvc::Camera3 cam;
        cam.position = c - rgvc::Vec3{0, 0, 1.5 * extent};
        cam.direction = {0, 0, 1};
        cam.fovDeg = 60;
        const rgvc::CullResult& r = culler.cull(cam);
        if (std::find(r.pvs.begin(), r.pvs.end(), rgvc::ObjectId(1)) == r.pvs.end())
            bug("the mesh, alone in front of the camera, is missing from the PVS");
    } catch (const rgvc::InvalidInput&) {
        // a grid the mesh's extent or position cannot give (too small or too far out for double voxels)
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    static const char* const kExt[] = {".obj", ".gltf", ".glb"};
    // A directory of this process's own, empty but for the input: a glTF's relative `uri` then names
    // nothing (the loader reads external files only beside the glTF file), whatever else is in /tmp.
    static const std::string dir = [] {
        char name[] = "/tmp/rgvc-fuzz-mesh-XXXXXX";
        if (::mkdtemp(name) == nullptr) bug("mkdtemp failed");
        return std::string(name);
    }();
    const std::string path = dir + "/input" + kExt[data[0] % 3];
    {
        std::ofstream f(path, std::ios::binary | std::ios::trunc);
        f.write(reinterpret_cast<const char*>(data + 1), std::streamsize(size - 1));
    }
    rgvc::TriangleMesh mesh;
    try {
        mesh = rgvc::readMeshFile(path);
    } catch (const rgvc::MeshFileError&) {
        return 0;
    } catch (const std::exception& e) {
        bug(std::string("readMeshFile threw something other than MeshFileError: ") + e.what());
    }
    try {
        rgvc::validateMesh(mesh, "mesh");
    } catch (const rgvc::InvalidInput& e) {
        bug(std::string("readMeshFile returned a mesh validateMesh refuses: ") + e.what());
    }
    (void)rgvc::analyzeMeshTopology(mesh);
    rgvc::MeshPlacement placement;
    placement.translation = {3.5, -2.0, 7.25};
    placement.rotation = {0, 0.6, 0, 0.8};
    placement.scale = {2.0, 0.5, 1.0};
    rgvc::SceneMeshInfo info;
    rgvc::Shape<3> shape;
    try {
        shape = rgvc::sceneMeshShape(path, placement, "objects[0]", info);
    } catch (const rgvc::InvalidInput&) {
        return 0; // e.g. coordinates whose placement overflows
    } catch (const rgvc::MeshFileError& e) {
        bug(std::string("the file read once and refused the second time: ") + e.what());
    } catch (const std::exception& e) {
        bug(std::string("sceneMeshShape threw something unexpected: ") + e.what());
    }
    try {
        rgvc::Shape<3> copy = shape;
        rgvc::validateShape<3>(copy, "mesh shape");
    } catch (const rgvc::InvalidInput& e) {
        bug(std::string("the culler would refuse the mesh's shape: ") + e.what());
    }
    // The shape contains the placed mesh (its triangles' vertices span it). R(q) for q = (0, 0.6, 0, 0.8):
    // the rotation about y by 2 atan2(0.6, 0.8).
    const double a = 2 * std::atan2(0.6, 0.8), ca = std::cos(a), sa = std::sin(a);
    for (const auto& t : mesh.triangles)
        for (std::uint32_t k : t) {
            const rgvc::Vec3 scaled = mesh.positions[k] * placement.scale;
            const rgvc::Vec3 placed = rgvc::Vec3{ca * scaled.x + sa * scaled.z, scaled.y, -sa * scaled.x + ca * scaled.z} +
                                      placement.translation;
            if (std::isfinite(placed.x) && std::isfinite(placed.y) && std::isfinite(placed.z) && !inside(shape, placed))
                bug("a placed vertex lies outside the shape the culler gets for the mesh");
        }
    cullOnce(shape);
    return 0;
}
