// Mesh objects in scene files (apps/scene/MeshFile.cpp): OBJ, glTF and GLB files placed by scale, rotation
// and translation and given to the culler as the placed mesh (MeshSolid: its hull outside, a closed mesh's
// solid as the occluder; an open mesh an occludee); the scene writer's mesh dumps; every bad file and field refused
// with one line (MeshFileError reported as a SceneError naming objects[i].file), external glTF buffers only
// from regular files beside the glTF file. The rest of the scene format is in test_scene_file.cpp.
#include "SceneFile.hpp"
#include "SceneMotion.hpp"
#include "SceneWriter.hpp"

#include "rgvc/dynamics/Culler.hpp"

#include "SceneFileTestSupport.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <variant>
#include <vector>

using json = nlohmann::json;
using namespace rgvc;
using namespace rgvc::scene_test;

// ---------------------------------------------------------------------------------------------------
// mesh (scene-format.md: `file` relative to the scene file, `translation`, `rotation`, `scale`): read by
// apps/scene/MeshFile.cpp, given to the culler as the placed mesh (a MeshSolid), role occludee when open.
// tests/data/cube.* come from scripts/make_mesh_files.py.

namespace {

const std::string kDataDir = RGVC_TEST_DATA_DIR;

json meshObject(const std::string& file) {
    json o = json::object();
    o["id"] = 20;
    o["shape"] = "mesh";
    o["file"] = file;
    return o;
}

// The scene of example3D() with `object` appended, parsed as if the scene file were sceneDir/s.json.
Scene parseIn(const std::string& sceneDir, const json& object) {
    return parseScene(withObject(object).dump(), sceneDir + "/s.json");
}

// A mesh scene that must be rejected: one line "<scene>: <field>: <problem>"; returns field and problem.
std::pair<std::string, std::string> rejectMesh(const std::string& sceneDir, const json& object) {
    const std::string name = sceneDir + "/s.json";
    try {
        parseScene(withObject(object).dump(), name);
    } catch (const SceneError& e) {
        const std::string what = e.what();
        CHECK(what.find('\n') == std::string::npos);
        CHECK(what.rfind(name + ": " + e.field() + ": ", 0) == 0);
        return {e.field(), e.problem()};
    } catch (const std::exception& e) {
        FAIL("not a SceneError: " << e.what());
    }
    FAIL("accepted: " << object.dump());
    return {};
}

void checkBounds(const Shape<3>& s, Vec3 lo, Vec3 hi) {
    const Box<3> b = boundsOf<3>(s);
    INFO("bounds " << b.min.x << " " << b.min.y << " " << b.min.z << " .. " << b.max.x << " " << b.max.y << " " << b.max.z);
    for (int a = 0; a < 3; ++a) {
        CHECK(b.min[a] == Approx(lo[a]).margin(1e-9));
        CHECK(b.max[a] == Approx(hi[a]).margin(1e-9));
    }
}

std::string writeFile(const std::string& name, const std::string& bytes) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "rgvc_test_scene_meshes";
    std::filesystem::create_directories(dir);
    std::ofstream(dir / name, std::ios::binary) << bytes;
    return dir.string();
}

std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

} // namespace

TEST_CASE("mesh objects: OBJ, glTF and GLB cubes placed by scale, rotation, translation, closed ones as solids", "[scene][mesh]") {
    SECTION("OBJ: scale 2, 90 degrees about z, translation (5, 5, 5); a closed mesh keeps its role occluder") {
        json o = meshObject("cube.obj");
        o["scale"] = 2;
        o["rotation"] = {0, 0, 0.7071067811865476, 0.7071067811865476};
        o["translation"] = {5, 5, 5};
        o["role"] = "occluder";
        Scene s = parseIn(kDataDir, o);
        const SceneObject<3>& m = s.as<3>()->objects.at(2);
        const auto* ms = std::get_if<MeshSolid>(&m.shape);
        REQUIRE(ms);
        CHECK(ms->closed());
        const ConvexPolytope* p = &ms->hull();
        CHECK(p->vertices.size() == 8);
        CHECK(p->planes.size() >= 6);
        // [0,1]^3 scaled to [0,2]^3, turned (x, y) -> (-y, x): x in [-2, 0], y in [0, 2]; then moved.
        checkBounds(m.shape, Vec3(3, 5, 5), Vec3(5, 7, 7));
        CHECK(m.role == ObjectRole::Occluder);
        CHECK(m.desc().role == ObjectRole::Occluder);
        REQUIRE(m.mesh);
        CHECK(m.mesh->requestedRole == ObjectRole::Occluder);
        CHECK(m.mesh->closed);
        CHECK(m.mesh->triangles == 12);
        CHECK(m.mesh->file == kDataDir + "/cube.obj");
    }
    SECTION("glTF: the node's translation (10, 0, 0) and scale 2, split faces welded; then the object's translation") {
        json o = meshObject("cube.gltf");
        o["translation"] = {0, 1, 0};
        Scene s = parseIn(kDataDir, o);
        const SceneObject<3>& m = s.as<3>()->objects.at(2);
        REQUIRE(std::get_if<MeshSolid>(&m.shape));
        checkBounds(m.shape, Vec3(10, 1, 0), Vec3(12, 3, 2));
        CHECK(m.role == ObjectRole::Both);
        REQUIRE(m.mesh);
        CHECK(m.mesh->closed); // 24 vertices in the file, 8 after welding
        CHECK(m.mesh->vertices == 8);
        CHECK(m.mesh->triangles == 12);
    }
    SECTION("GLB: per-axis scale [1, 2, 3], uint8 indices, moving (the mesh with its hull)") {
        json o = meshObject("cube.glb");
        o["scale"] = {1, 2, 3};
        o["velocity"] = {0, 0, 1};
        Scene s = parseIn(kDataDir, o);
        const SceneObject<3>& m = s.as<3>()->objects.at(2);
        checkBounds(m.shape, Vec3(0, 0, 0), Vec3(1, 2, 3));
        CHECK(m.role == ObjectRole::Both);
        CHECK_FALSE(m.isStatic);
        SceneSimulator3 sim(*s.as<3>());
        sim.step();
        checkBounds(sim.shapeAt(2), Vec3(0, 0, 1), Vec3(1, 2, 4));
        const Shape<3> at1 = sim.shapeAt(2);
        const auto* moved = std::get_if<MeshSolid>(&at1);
        REQUIRE(moved);
        CHECK(moved->offset() == Vec3(0, 0, 1));
        CHECK(moved->sharedModel() == std::get<MeshSolid>(m.shape).sharedModel()); // one mesh, shared
    }
    SECTION("glTF variants: no indices (every three vertices a triangle), no scenes (meshes untransformed)") {
        json g = json::parse(readFile(kDataDir + "/cube.gltf"));
        g["meshes"][0]["primitives"][0].erase("indices");
        const std::string dir = writeFile("noindex.gltf", g.dump());
        Scene s = parseIn(dir, meshObject("noindex.gltf"));
        const SceneObject<3>& m = s.as<3>()->objects.at(2);
        checkBounds(m.shape, Vec3(10, 0, 0), Vec3(12, 2, 2)); // the node transform still applies
        REQUIRE(m.mesh);
        CHECK(m.mesh->triangles == 8);
        CHECK_FALSE(m.mesh->closed);
        CHECK(m.role == ObjectRole::Occludee); // open: a surface hides nothing
        json n = json::parse(readFile(kDataDir + "/cube.gltf"));
        n.erase("scene");
        n.erase("scenes");
        writeFile("noscene.gltf", n.dump());
        checkBounds(parseIn(dir, meshObject("noscene.gltf")).as<3>()->objects.at(2).shape, Vec3(0, 0, 0), Vec3(1, 1, 1));
        // An absolute `file` is taken as it is.
        checkBounds(parseIn("/nonexistent", meshObject(kDataDir + "/cube.obj")).as<3>()->objects.at(2).shape, Vec3(0, 0, 0),
                    Vec3(1, 1, 1));
    }
    SECTION("an open, flat mesh (one quad) is a surface: a thin box around it, an occludee") {
        const std::string dir = writeFile("quad.obj", "v 0 0 0\nv 2 0 0\nv 2 0 3\nv 0 0 3\nf 1 2 3 4\n");
        json o = meshObject("quad.obj");
        o["role"] = "both";
        Scene s = parseIn(dir, o);
        const SceneObject<3>& m = s.as<3>()->objects.at(2);
        REQUIRE(m.mesh);
        CHECK_FALSE(m.mesh->closed);
        CHECK(m.mesh->requestedRole == ObjectRole::Both);
        REQUIRE(std::get_if<MeshSolid>(&m.shape));
        const Box<3> b = boundsOf<3>(m.shape);
        CHECK(b.min.x <= 0);
        CHECK(b.max.x >= 2);
        CHECK(b.min.y < 0);
        CHECK(b.max.y > 0);
        CHECK(b.max.y < 1e-5);
        CHECK(b.max.z >= 3);
        CHECK(m.role == ObjectRole::Occludee);
    }
}

TEST_CASE("mesh objects in the culler: a closed mesh hides what is behind it, an open one nothing; dumps replay", "[scene][mesh]") {
    // The test cube as a wall (scale [8, 8, 1] at z 4..5) between the camera and a sphere, in a scene file;
    // the culler built from the loaded objects as `rgvc cull` builds it.
    json j = json::parse(R"({
      "dimensions": 3,
      "grid":   { "origin": [-8, -8, -8], "voxel_size": 0.5, "resolution": [32, 32, 40] },
      "camera": { "position": [0, 0, 0], "direction": [0, 0, 1], "fov_deg": 40 },
      "objects": [ { "id": 1, "shape": "sphere", "center": [0, 0, 9], "radius": 0.5 } ]
    })");
    json wall = meshObject(kDataDir + "/cube.obj");
    wall["scale"] = {8, 8, 1};
    wall["translation"] = {-4, -4, 4};
    j["objects"].push_back(wall);
    auto cull = [](const Scene& s, Culler3D& culler) {
        const SceneData<3>& d = *s.as<3>();
        for (const SceneObject<3>& o : d.objects) culler.addObject(o.desc());
        return culler.cull(d.camera).pvs;
    };
    const Scene closed = parseScene(j.dump(), "wall.json");
    Culler3D c1(closed.as<3>()->grid);
    CHECK(cull(closed, c1) == std::vector<ObjectId>{20}); // the sphere is hidden by the solid wall
    // Open (the glTF cube without indices: 8 of its 12 triangles), the same wall hides nothing.
    json g = json::parse(readFile(kDataDir + "/cube.gltf"));
    g["meshes"][0]["primitives"][0].erase("indices");
    g.erase("scene");
    g.erase("scenes"); // untransformed: the unit cube's 8 triangles
    const std::string dir = writeFile("open-cube.gltf", g.dump());
    j["objects"][1]["file"] = dir + "/open-cube.gltf";
    const Scene open = parseScene(j.dump(), "open-wall.json");
    REQUIRE(open.as<3>()->objects.at(1).role == ObjectRole::Occludee);
    Culler3D c2(open.as<3>()->grid);
    CHECK(cull(open, c2) == std::vector<ObjectId>{1, 20});

    // writeSceneFile dumps the mesh object as an OBJ file beside the scene; the replay culls the same.
    const std::string dumpDir = writeFile("dump.json", "");
    const std::string path = dumpDir + "/dump.json";
    writeSceneFile<3>(path, c1, closed.as<3>()->camera);
    const std::string obj = readFile(dumpDir + "/dump.mesh-20.obj");
    CHECK(obj.find("\nf ") != std::string::npos);
    const Scene replay = loadScene(path);
    const SceneObject<3>& m = replay.as<3>()->objects.at(1);
    REQUIRE(std::get_if<MeshSolid>(&m.shape));
    CHECK(m.mesh->closed);
    CHECK(boundsOf<3>(m.shape).min == boundsOf<3>(closed.as<3>()->objects.at(1).shape).min);
    CHECK(boundsOf<3>(m.shape).max == boundsOf<3>(closed.as<3>()->objects.at(1).shape).max);
    Culler3D c3(replay.as<3>()->grid);
    CHECK(cull(replay, c3) == std::vector<ObjectId>{20});
    // sceneToJson alone has nowhere to put the mesh: a clear error naming the object.
    CHECK_THROWS_WITH(sceneToJson<3>(c1, closed.as<3>()->camera), Catch::Contains("object 20") && Catch::Contains("writeSceneFile"));
}

TEST_CASE("bad mesh objects and files: one line naming the scene, objects[i].file and the problem", "[scene][mesh]") {
    // Files whose problem is in the file: field objects[2].file.
    const std::string cubeGltf = readFile(kDataDir + "/cube.gltf");
    const std::string cubeGlb = readFile(kDataDir + "/cube.glb");
    REQUIRE(cubeGltf.size() > 200);
    REQUIRE(cubeGlb.size() > 200);
    json strip = json::parse(cubeGltf);
    strip["meshes"][0]["primitives"][0]["mode"] = 5;
    json badIndex = json::parse(cubeGltf);
    badIndex["accessors"][1]["componentType"] = 5126; // float indices
    json pastEnd = json::parse(cubeGltf);
    pastEnd["accessors"][0]["count"] = 400; // more vertices than the buffer holds
    // External buffers only from regular files beside the glTF file: not a device reached through "..",
    // not a file outside the directory (one is written there below).
    json devZero = json::parse(cubeGltf);
    devZero["buffers"][0]["uri"] = "../../../../../../../../dev/zero";
    json outside = json::parse(cubeGltf);
    outside["buffers"][0]["uri"] = "../rgvc_test_scene_outside.bin";
    {
        std::ofstream f(std::filesystem::temp_directory_path() / "rgvc_test_scene_outside.bin", std::ios::binary);
        f << std::string(4096, '\0');
    }
    struct Bad {
        const char* name;
        std::string bytes;
        const char* problem; // a word the problem must contain
    };
    const std::vector<Bad> files = {
        {"nan.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "finite"},
        {"range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", ""},
        {"points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n", "triangle"},
        {"lines.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\n", "triangle"},
        {"degenerate.obj", "v 0 0 0\nv 1 0 0\nf 1 2 2\n", "triangle"},
        {"cut.gltf", cubeGltf.substr(0, cubeGltf.size() / 2), "glTF"},
        {"cut.glb", cubeGlb.substr(0, 100), "glTF"},
        {"empty.glb", "", "glTF"},
        {"strip.gltf", strip.dump(), "mode 5"},
        {"floatindex.gltf", badIndex.dump(), "indices"},
        {"pastend.gltf", pastEnd.dump(), "end of its buffer"},
        {"devzero.gltf", devZero.dump(), "glTF"},
        {"outside.gltf", outside.dump(), "glTF"},
        {"cube.stl", "solid x\nendsolid x\n", "extension"},
    };
    std::string dir;
    for (const Bad& b : files) dir = writeFile(b.name, b.bytes);
    for (const Bad& b : files) {
        INFO(b.name);
        const auto [field, problem] = rejectMesh(dir, meshObject(b.name));
        INFO(problem);
        CHECK(field == "objects[2].file");
        CHECK(problem.find(b.name) != std::string::npos);
        CHECK(problem.find(b.problem) != std::string::npos);
    }
    {
        const auto [field, problem] = rejectMesh(dir, meshObject("does_not_exist.obj"));
        CHECK(field == "objects[2].file");
        CHECK(problem.find("no such file") != std::string::npos);
    }
    {
        std::filesystem::create_directories(dir + "/folder.obj");
        CHECK(rejectMesh(dir, meshObject("folder.obj")).first == "objects[2].file");
    }
    // Fields of the object.
    auto field = [&](const char* key, json value) {
        json o = meshObject("cube.obj");
        if (value.is_null()) o.erase(key);
        else o[key] = std::move(value);
        return rejectMesh(kDataDir, o).first;
    };
    CHECK(field("file", nullptr) == "objects[2].file");
    CHECK(field("file", 3) == "objects[2].file");
    CHECK(field("file", "") == "objects[2].file");
    CHECK(field("scale", 0) == "objects[2].scale");
    CHECK(field("scale", {1, 0, 1}) == "objects[2].scale");
    CHECK(field("scale", {1, 1}) == "objects[2].scale");
    CHECK(field("scale", "big") == "objects[2].scale");
    CHECK(field("rotation", {0, 0, 0, 2}) == "objects[2].rotation");
    CHECK(field("rotation", {0, 0, 1}) == "objects[2].rotation");
    CHECK(field("rotation", {0, 0, "x", 1}) == "objects[2].rotation[2]");
    CHECK(field("translation", {0, 1}) == "objects[2].translation");
    // A 2D scene has no meshes.
    json j = example2D();
    j["objects"].push_back(json::parse(R"({ "id": 9, "shape": "mesh", "file": "cube.obj" })"));
    CHECK(reject(j) == "objects[3].shape");
}
