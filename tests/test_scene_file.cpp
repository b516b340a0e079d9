// Scene files (apps/scene): parsing, defaults, every bad-input rule of scene-format.md with the field it
// must name, and the simulated motion's reflection rule. Mesh objects (OBJ, glTF) are in test_mesh_file.cpp.
#include "SceneFile.hpp"
#include "SceneMotion.hpp"
#include "SceneWriter.hpp"

#include "RandomScenes2D.hpp"
#include "RandomScenes3D.hpp"
#include "SceneFileTestSupport.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

using json = nlohmann::json;
using namespace rgvc;
using namespace rgvc::scene_test;

namespace {

Scene parse(const json& j) { return parseScene(j.dump(), "t.json"); }

// text with its first `from` replaced by `to` (which must be there).
std::string replacedIn(std::string text, const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    REQUIRE(at != std::string::npos);
    return text.replace(at, from.size(), to);
}

std::string tempPath(const std::string& name) {
    return (std::filesystem::temp_directory_path() / ("rgvc_test_scene_" + name)).string();
}

} // namespace

TEST_CASE("the contract's example scene parses with its defaults", "[scene]") {
    Scene s = parse(example2D());
    REQUIRE(s.dimensions == 2);
    REQUIRE(s.name == "t.json");
    const SceneData2* d = s.as<2>();
    REQUIRE(d);
    REQUIRE(s.as<3>() == nullptr);
    CHECK(d->grid.resolution() == IVec2(256, 256));
    CHECK(d->grid.voxelSize() == 1.0);
    CHECK(d->camera.position == Vec2(10.5, 20.25));
    CHECK(d->camera.fovDeg == 90);
    CHECK(std::isinf(d->camera.far));
    CHECK_FALSE(d->cameraPath);
    CHECK(d->frameLimit() == SIZE_MAX);
    REQUIRE(d->objects.size() == 3);

    const auto& o1 = d->objects[0];
    CHECK(o1.id == 1);
    CHECK_FALSE(o1.isStatic);
    CHECK(o1.velocity == Vec2(0.4, -0.1));
    CHECK(o1.maxSpeed == Approx(std::sqrt(0.4 * 0.4 + 0.1 * 0.1)));
    REQUIRE(std::holds_alternative<Ball<2>>(o1.shape));
    CHECK(std::get<Ball<2>>(o1.shape).radius == 3.5);

    CHECK(d->objects[1].isStatic);
    CHECK(d->objects[1].maxSpeed == 0);
    REQUIRE(std::holds_alternative<Box<2>>(d->objects[1].shape));

    REQUIRE(std::holds_alternative<ConvexPolygon>(d->objects[2].shape));
    // The file's points are clockwise; validateShape stores them counter-clockwise.
    CHECK(signedArea(std::get<ConvexPolygon>(d->objects[2].shape).points) > 0);

    ObjectDesc<2> desc = o1.desc();
    CHECK(desc.id == 1);
    CHECK(desc.maxSpeed == o1.maxSpeed);
    CHECK_FALSE(desc.isStatic);
}

TEST_CASE("motion defaults: static, max_speed", "[scene]") {
    json j = example2D();
    j["objects"] = json::parse(R"([
      { "id": 0, "shape": "circle", "center": [5, 5], "radius": 1 },
      { "id": 1, "shape": "circle", "center": [9, 5], "radius": 1, "max_speed": 2 },
      { "id": 2, "shape": "circle", "center": [15, 5], "radius": 1, "static": false },
      { "id": 3, "shape": "circle", "center": [25, 5], "radius": 1, "velocity": [3, 4], "max_speed": 6 },
      { "id": 4, "shape": "circle", "center": [35, 5], "radius": 1, "velocity": [0, 0] },
      { "id": 5.0, "shape": "box", "min": [1, 1], "max": [2, 2], "extra_field": "ignored" }
    ])");
    const Scene scene = parse(j);
    const auto& o = scene.as<2>()->objects;
    CHECK(o[0].isStatic);
    CHECK(o[0].maxSpeed == 0);
    CHECK_FALSE(o[1].isStatic); // a max_speed means "may move"
    CHECK(o[1].maxSpeed == 2);
    CHECK_FALSE(o[2].isStatic);
    CHECK(o[2].maxSpeed == 0);
    CHECK(o[3].maxSpeed == 6);
    CHECK_FALSE(o[3].isStatic);
    CHECK(o[4].isStatic);
    CHECK(o[5].id == 5); // an integral float is an integer
}

TEST_CASE("roles: both (default), occludee, occluder reach the culler's ObjectDesc", "[scene][roles]") {
    json j = example2D();
    j["objects"] = json::parse(R"([
      { "id": 0, "shape": "circle", "center": [5, 5], "radius": 1 },
      { "id": 1, "shape": "circle", "center": [9, 5], "radius": 1, "role": "both" },
      { "id": 2, "shape": "box", "min": [1, 1], "max": [2, 2], "role": "occludee" },
      { "id": 3, "shape": "box", "min": [3, 1], "max": [4, 2], "role": "occluder" }
    ])");
    const Scene scene = parse(j);
    const auto& o = scene.as<2>()->objects;
    CHECK(o[0].role == ObjectRole::Both);
    CHECK(o[1].role == ObjectRole::Both);
    CHECK(o[2].role == ObjectRole::Occludee);
    CHECK(o[3].role == ObjectRole::Occluder);
    CHECK(o[2].desc().role == ObjectRole::Occludee);
    CHECK(o[3].desc().role == ObjectRole::Occluder);
}

TEST_CASE("camera options: 360 degrees, far, camera_path", "[scene]") {
    json j = example2D();
    j["camera"]["fov_deg"] = 360;
    j["camera"]["far"] = 50;
    j["camera"]["up"] = {0, 1, 0}; // 3D-only fields are ignored in 2D
    j["camera_path"] = json::parse(R"([
      { "position": [1, 2], "direction": [0, 1] },
      { "position": [3, 4], "direction": [-1, 0] }
    ])");
    Scene s = parse(j);
    const SceneData2& d = *s.as<2>();
    CHECK(d.camera.far == 50);
    REQUIRE(d.cameraPath);
    CHECK(d.frameLimit() == 2);
    Camera2 c1 = d.cameraAt(1);
    CHECK(c1.position == Vec2(3, 4));
    CHECK(c1.direction == Vec2(-1, 0));
    CHECK(c1.fovDeg == 360);
    CHECK(c1.far == 50);
    CHECK_NOTHROW(requireFrames(s, 2));
    try {
        requireFrames(s, 3);
        FAIL("3 frames accepted with a 2-entry camera_path");
    } catch (const SceneError& e) {
        CHECK(e.field() == "camera_path");
        CHECK(std::string(e.what()).rfind("t.json: camera_path: ", 0) == 0);
    }
    j["camera"]["far"] = nullptr; // null = no limit
    CHECK(std::isinf(parse(j).as<2>()->camera.far));
}

TEST_CASE("3D scenes parse: sphere, box, default and explicit up/aspect", "[scene]") {
    Scene s = parse(example3D());
    REQUIRE(s.dimensions == 3);
    const SceneData3* d = s.as<3>();
    REQUIRE(d);
    CHECK(d->grid.resolution() == IVec3(32, 16, 32));
    CHECK(d->camera.up == Vec3(0, 1, 0));
    CHECK(d->camera.aspect == 1);
    REQUIRE(d->objects.size() == 2);
    CHECK(std::holds_alternative<Ball<3>>(d->objects[0].shape));
    CHECK_FALSE(d->objects[0].isStatic);
    CHECK(d->objects[1].isStatic);

    json j = example3D();
    j["camera"]["up"] = {0, 0, 2};
    j["camera"]["direction"] = {1, 0, 0};
    j["camera"]["aspect"] = 1.5;
    j["camera_path"] = json::parse(R"([{ "position": [0, 1, 0], "direction": [0, 1, 1] }])");
    Scene s2 = parse(j);
    CHECK(s2.as<3>()->camera.up == Vec3(0, 0, 2));
    CHECK(s2.as<3>()->camera.aspect == 1.5);
    CHECK(s2.as<3>()->cameraAt(0).up == Vec3(0, 0, 2));
}

TEST_CASE("bad documents and top-level fields", "[scene]") {
    CHECK(rejectText("").find("line") != std::string::npos);
    CHECK(rejectText("{ \"dimensions\": 2,").find("line") != std::string::npos);
    CHECK(rejectText("{ \"dimensions\": 2 } trailing").rfind("line 1, column ", 0) == 0);
    CHECK(rejectText("{\n  \"dimensions\": 2,\n  \"grid\": [1, 2,, 3]\n}") == "line 3, column 17");
    CHECK(rejectText("[1, 2]") == "(root)");
    CHECK(reject(json::object()) == "dimensions");

    json j = example2D();
    j["dimensions"] = 4;
    CHECK(reject(j) == "dimensions");
    j["dimensions"] = "2";
    CHECK(reject(j) == "dimensions");
    j["dimensions"] = 2.5;
    CHECK(reject(j) == "dimensions");

    for (const char* key : {"grid", "camera", "objects"}) {
        json k = example2D();
        k.erase(key);
        CHECK(reject(k) == key);
        k[key] = 7;
        CHECK(reject(k) == key);
    }
}

TEST_CASE("numbers too large for double (1e999) name their field", "[scene]") {
    std::string text = example2D().dump();
    auto replaced = [&](const std::string& from, const std::string& to) { return replacedIn(text, from, to); };
    CHECK(rejectText(replaced("\"radius\":3.5", "\"radius\":1e999")) == "objects[0].radius");
    CHECK(rejectText(replaced("\"position\":[10.5,20.25]", "\"position\":[10.5,-1e999]")) == "camera.position[1]");
    CHECK(rejectText(replaced("\"voxel_size\":1.0", "\"voxel_size\":1e400")) == "grid.voxel_size");
    CHECK(rejectText(replaced("[90,82]", "[90,1e999]")) == "objects[2].points[1][1]");
}

TEST_CASE("bad grids", "[scene]") {
    auto grid = [](const char* key, json value) {
        json j = example2D();
        j["grid"][key] = std::move(value);
        return reject(j);
    };
    CHECK(grid("voxel_size", 0) == "grid.voxel_size");
    CHECK(grid("voxel_size", -1) == "grid.voxel_size");
    CHECK(grid("voxel_size", "1") == "grid.voxel_size");
    CHECK(grid("origin", {0, 0, 0}) == "grid.origin");
    CHECK(grid("origin", {0, "x"}) == "grid.origin[1]");
    CHECK(grid("resolution", {256}) == "grid.resolution");
    CHECK(grid("resolution", {0, 256}) == "grid.resolution[0]");
    CHECK(grid("resolution", {256, -3}) == "grid.resolution[1]");
    CHECK(grid("resolution", {2.5, 256}) == "grid.resolution[0]");
    CHECK(grid("resolution", {4294967296LL, 1}) == "grid.resolution[0]");
    CHECK(grid("resolution", {65536, 65536}) == "grid.resolution"); // more than 2^31-1 voxels
    json j = example2D();
    j["grid"].erase("voxel_size");
    CHECK(reject(j) == "grid.voxel_size");
}

TEST_CASE("bad cameras", "[scene]") {
    auto cam = [](const char* key, json value) {
        json j = example2D();
        j["camera"][key] = std::move(value);
        return reject(j);
    };
    CHECK(cam("direction", {0, 0}) == "camera.direction");
    CHECK(cam("direction", {1, 0, 0}) == "camera.direction");
    CHECK(cam("position", {1}) == "camera.position");
    CHECK(cam("position", "here") == "camera.position");
    CHECK(cam("fov_deg", 0) == "camera.fov_deg");
    CHECK(cam("fov_deg", -10) == "camera.fov_deg");
    CHECK(cam("fov_deg", 360.5) == "camera.fov_deg");
    CHECK(cam("fov_deg", "90") == "camera.fov_deg");
    CHECK(cam("far", 0) == "camera.far");
    CHECK(cam("far", -2) == "camera.far");
    json j = example2D();
    j["camera"].erase("fov_deg");
    CHECK(reject(j) == "camera.fov_deg");

    auto cam3 = [](const char* key, json value) {
        json k = example3D();
        k["camera"][key] = std::move(value);
        return reject(k);
    };
    CHECK(cam3("fov_deg", 180) == "camera.fov_deg");
    CHECK(cam3("aspect", 0) == "camera.aspect");
    CHECK(cam3("up", {0, 0, 0}) == "camera.up");
    CHECK(cam3("up", {0, 1}) == "camera.up");
    CHECK(cam3("up", {0, 0, -3}) == "camera.up");      // parallel to direction (0, 0, 1)
    CHECK(cam3("direction", {0, 2, 0}) == "camera.direction"); // parallel to the default up
}

TEST_CASE("bad camera paths", "[scene]") {
    auto path = [](json p) {
        json j = example2D();
        j["camera_path"] = std::move(p);
        return reject(j);
    };
    CHECK(path(7) == "camera_path");
    CHECK(path(json::parse(R"([{"position": [1, 1], "direction": [1, 0]}, 3])")) == "camera_path[1]");
    CHECK(path(json::parse(R"([{"position": [1, 1], "direction": [1, 0]}, {"position": [1, 1], "direction": [0, 0]}])")) ==
          "camera_path[1].direction");
    CHECK(path(json::parse(R"([{"direction": [1, 0]}])")) == "camera_path[0].position");
    CHECK(path(json::parse(R"([{"position": [1, 1, 1], "direction": [1, 0]}])")) == "camera_path[0].position");
    json j = example3D();
    j["camera_path"] = json::parse(R"([{"position": [0, 1, 0], "direction": [0, -1, 0]}])");
    CHECK(reject(j) == "camera_path[0].direction");
}

TEST_CASE("bad objects", "[scene]") {
    auto obj = [](std::size_t i, const char* key, json value) {
        json j = example2D();
        j["objects"][i][key] = std::move(value);
        return reject(j);
    };
    CHECK(obj(0, "shape", "triangle") == "objects[0].shape");
    CHECK(obj(0, "shape", 3) == "objects[0].shape");
    CHECK(obj(0, "shape", "sphere") == "objects[0].shape"); // 3D shape in a 2D scene
    CHECK(obj(0, "radius", 0) == "objects[0].radius");
    CHECK(obj(0, "radius", -1) == "objects[0].radius");
    CHECK(obj(0, "center", {1, 2, 3}) == "objects[0].center");
    CHECK(obj(0, "velocity", {1}) == "objects[0].velocity");
    CHECK(obj(0, "velocity", {1, "a"}) == "objects[0].velocity[1]");
    CHECK(obj(0, "max_speed", -1) == "objects[0].max_speed");
    CHECK(obj(0, "max_speed", 0.1) == "objects[0].max_speed"); // below |velocity| = 0.412
    CHECK(obj(0, "static", true) == "objects[0].static");       // moving but static
    CHECK(obj(0, "role", "glass") == "objects[0].role");
    CHECK(obj(0, "role", 1) == "objects[0].role");
    CHECK(obj(0, "role", "Occludee") == "objects[0].role"); // the names are lower case
    CHECK(obj(0, "static", "yes") == "objects[0].static");
    CHECK(obj(0, "id", -1) == "objects[0].id");
    CHECK(obj(0, "id", 1.5) == "objects[0].id");
    CHECK(obj(0, "id", "1") == "objects[0].id");
    CHECK(obj(0, "id", 1e300) == "objects[0].id");
    CHECK(obj(2, "id", 1) == "objects[2].id"); // duplicate of objects[0]
    CHECK(obj(1, "max", {60, 90}) == "objects[1].max");
    CHECK(obj(1, "max", {50, 95}) == "objects[1].max");
    CHECK(obj(1, "min", {60}) == "objects[1].min");
    CHECK(obj(2, "points", json::parse("[[0, 0], [1, 0]]")) == "objects[2].points");
    CHECK(obj(2, "points", json::parse("[[0, 0], [4, 0], [1, 1], [0, 4]]")) == "objects[2].points"); // not convex
    CHECK(obj(2, "points", json::parse("[[0, 0], [1, 1], [2, 2]]")) == "objects[2].points");         // zero area
    CHECK(obj(2, "points", json::parse("[[0, 0], [1, 0, 0], [0, 1]]")) == "objects[2].points[1]");
    CHECK(obj(2, "points", 5) == "objects[2].points");

    json j = example2D();
    j["objects"][0].erase("radius");
    CHECK(reject(j) == "objects[0].radius");
    j = example2D();
    j["objects"][1].erase("shape");
    CHECK(reject(j) == "objects[1].shape");
    j = example2D();
    j["objects"][1].erase("id");
    CHECK(reject(j) == "objects[1].id");
    j = example2D();
    j["objects"][1] = 4;
    CHECK(reject(j) == "objects[1]");

    json k = example3D();
    k["objects"][0]["shape"] = "circle";
    CHECK(reject(k) == "objects[0].shape");
    k = example3D();
    k["objects"][1] = json::parse(R"({"id": 3, "shape": "polygon", "points": [[0, 0], [1, 0], [0, 1]]})");
    CHECK(reject(k) == "objects[1].shape");
    k = example3D();
    k["objects"][1]["min"] = {-1, 0};
    CHECK(reject(k) == "objects[1].min");
}

TEST_CASE("error messages stay on one line", "[scene]") {
    json j = example2D();
    j["objects"][0]["shape"] = "tri\nangle";
    CHECK(reject(j) == "objects[0].shape");
}

TEST_CASE("field paths built from keys with line breaks stay on one line (fuzz_scene_loader finds)", "[scene]") {
    std::string text = example2D().dump();
    auto replaced = [&](const std::string& from, const std::string& to) { return replacedIn(text, from, to); };
    // An overflowing number under a key holding "\r": the field names the key, flattened like the message.
    CHECK(rejectText(replaced("\"radius\":3.5", "\"rad\\rius\":1e999")) == "objects[0].rad ius");
    // A NUL or another control character in a key is written as \u00XX (a NUL once cut what() short).
    CHECK(rejectText(replaced("\"radius\":3.5", "\"rad\\u0000ius\":1e999")) == "objects[0].rad\\u0000ius");
    CHECK(rejectText(replaced("\"radius\":3.5", "\"rad\\u001fius\":1e999")) == "objects[0].rad\\u001fius");
    // "number overflow" quoted from a key in a plain syntax error is a syntax error (a position), not a field.
    const std::string field = rejectText(replaced("\"radius\":3.5", "\"number overflow\\n\" 3.5"));
    CHECK(field.rfind("line 1, column ", 0) == 0);
}

TEST_CASE("loadScene: files", "[scene]") {
    const std::string missing = tempPath("does_not_exist.json");
    std::filesystem::remove(missing);
    try {
        loadScene(missing);
        FAIL("missing file accepted");
    } catch (const SceneError& e) {
        CHECK(e.file() == missing);
        CHECK(e.field() == "file");
    }
    try {
        loadScene(std::filesystem::temp_directory_path().string());
        FAIL("directory accepted");
    } catch (const SceneError& e) {
        CHECK(e.field() == "file");
    }
    const std::string good = tempPath("good.json");
    {
        std::ofstream(good) << example2D().dump(2);
    }
    Scene s = loadScene(good);
    CHECK(s.name == good);
    CHECK(s.as<2>()->objects.size() == 3);
    std::filesystem::remove(good);
}

// ---------------------------------------------------------------------------------------------------
// Motion.

namespace {

// A 10 x 10 grid at the origin with the given objects.
SceneData2 boxWorld(const std::string& objects) {
    json j = example2D();
    j["grid"] = json::parse(R"({ "origin": [0, 0], "voxel_size": 1, "resolution": [10, 10] })");
    j["objects"] = json::parse(objects);
    return *parse(j).as<2>();
}

} // namespace

TEST_CASE("reflectStep: flips only when the step leaves towards the bound it approaches", "[scene]") {
    double v = 1.5;
    CHECK(reflectStep(7, 9, 0, 10, v) == -1.5); // 9 + 1.5 > 10
    CHECK(v == -1.5);
    v = 1;
    CHECK(reflectStep(7, 9, 0, 10, v) == 1); // touching 10 is inside
    v = -2;
    CHECK(reflectStep(1, 3, 0, 10, v) == 2);
    v = -1;
    CHECK(reflectStep(12, 13, 0, 10, v) == -1); // outside, moving back in: untouched
    v = 1;
    CHECK(reflectStep(12, 13, 0, 10, v) == -1); // outside, moving away: turned round
    v = 0;
    CHECK(reflectStep(-5, 20, 0, 10, v) == 0);
}

TEST_CASE("motion: a circle bounces off the grid bounds", "[scene]") {
    SceneData2 d = boxWorld(R"([
      { "id": 7, "shape": "circle", "center": [8, 5], "radius": 1, "velocity": [1.5, 0.5] },
      { "id": 8, "shape": "box", "min": [1, 1], "max": [2, 2] }
    ])");
    SceneSimulator2 sim(d);
    CHECK(sim.frame() == 0);
    CHECK(sim.bounds().max == Vec2(10, 10));
    CHECK(sim.translation(7) == Vec2(0, 0));
    // x: bbox [7, 9]; 9 + 1.5 > 10 flips at once. y: bbox [4, 6] rises 0.5 a frame until 6 + t > 10.
    const double xs[] = {-1.5, -3, -4.5, -6, -4.5, -3, -1.5}; // flips again at lo = 1: 1 - 1.5 < 0
    const double ys[] = {0.5, 1, 1.5, 2, 2.5, 3, 3.5};
    for (int f = 0; f < 7; ++f) {
        sim.step();
        CHECK(sim.frame() == std::size_t(f + 1));
        CHECK(sim.translation(7) == Vec2(xs[f], ys[f]));
        CHECK(sim.movedAt(sim.indexOf(7)));
        CHECK(sim.translation(8) == Vec2(0, 0));
        CHECK_FALSE(sim.movedAt(sim.indexOf(8)));
    }
    // An object that starts inside never leaves.
    SceneSimulator2 again(d);
    for (int f = 0; f < 200; ++f) {
        again.step();
        Box<2> b = boundsOf<2>(again.shape(7));
        CHECK(b.min.x >= 0);
        CHECK(b.max.x <= 10);
        CHECK(b.min.y >= 0);
        CHECK(b.max.y <= 10);
    }
    Shape<2> s = again.shape(7);
    CHECK(std::get<Ball<2>>(s).center == Vec2(8, 5) + again.translation(7));
    CHECK_THROWS_AS(again.translation(99), std::out_of_range);
}

TEST_CASE("motionStaysInGrid: true exactly when reflected steps land inside (objectsStayInGrid)", "[scene]") {
    // Grid 10 x 10. A box of width w and speed v stays in when 2 v <= 10 - w.
    CHECK(motionStaysInGrid(boxWorld(R"([{ "id": 1, "shape": "circle", "center": [5, 5], "radius": 1, "velocity": [1.5, -2] }])")));
    CHECK(motionStaysInGrid(boxWorld(R"([{ "id": 1, "shape": "box", "min": [1, 1], "max": [7, 2], "velocity": [1.9, 0] }])")));
    CHECK_FALSE(motionStaysInGrid(boxWorld(R"([{ "id": 1, "shape": "box", "min": [1, 1], "max": [7, 2], "velocity": [2.1, 0] }])")));
    // As wide as the grid but not moving on that axis: fine.
    CHECK(motionStaysInGrid(boxWorld(R"([{ "id": 1, "shape": "box", "min": [0, 1], "max": [10, 2], "velocity": [0, 0.5] },
                                         { "id": 2, "shape": "box", "min": [1, 1], "max": [2, 2], "velocity": [0.1, 0] }])")));
    CHECK_FALSE(motionStaysInGrid(boxWorld(R"([{ "id": 1, "shape": "box", "min": [0, 1], "max": [10, 2], "velocity": [0.5, 0] }])")));
    // Static objects may be any size.
    CHECK(motionStaysInGrid(boxWorld(R"([{ "id": 1, "shape": "box", "min": [-5, -5], "max": [15, 15] }])")));
    CHECK(sceneCullerOptions(boxWorld(R"([{ "id": 1, "shape": "circle", "center": [5, 5], "radius": 1, "velocity": [1, 0] }])")).objectsStayInGrid);
    // What it promises, simulated: random boxes and speeds within the bound, every one that starts inside
    // the grid stays inside for 2,000 frames.
    std::mt19937_64 rng(17);
    for (int trial = 0; trial < 50; ++trial) {
        std::uniform_real_distribution<double> u(0, 1);
        const double w = 9.9 * u(rng), h = 9.9 * u(rng);
        const double x = (10 - w) * u(rng), y = (10 - h) * u(rng);
        const double vx = (10 - w) / 2 * u(rng) * (u(rng) < 0.5 ? -1 : 1), vy = (10 - h) / 2 * u(rng);
        json o = {{"id", 1}, {"shape", "box"}, {"min", {x, y}}, {"max", {x + w, y + h}}, {"velocity", {vx, vy}}};
        const SceneData2 d = boxWorld(json::array({o}).dump());
        INFO("trial " << trial << ": " << o.dump());
        REQUIRE(motionStaysInGrid(d) == (2 * std::abs(vx) <= 10 - w - 1e-8 && 2 * vy <= 10 - h - 1e-8));
        if (!motionStaysInGrid(d)) continue;
        SceneSimulator2 sim(d);
        bool inside = true;
        for (int f = 0; f < 2000 && inside; ++f) {
            sim.step();
            const Box<2> b = boundsOf<2>(sim.shape(1));
            inside = b.min.x >= 0 && b.min.y >= 0 && b.max.x <= 10 && b.max.y <= 10;
        }
        CHECK(inside);
    }
}

TEST_CASE("motion: objects starting outside the grid come back and are never stuck", "[scene]") {
    SceneData2 d = boxWorld(R"([
      { "id": 1, "shape": "box", "min": [12, 4], "max": [13, 5], "velocity": [1, 0] },
      { "id": 2, "shape": "box", "min": [12, 4], "max": [13, 5], "velocity": [-1, 0] },
      { "id": 3, "shape": "circle", "center": [5, -20], "radius": 2, "velocity": [0, -0.75] },
      { "id": 4, "shape": "box", "min": [-1, 4], "max": [11, 5], "velocity": [1, 0] }
    ])");
    SceneSimulator2 sim(d);
    sim.step();
    CHECK(sim.translation(1) == Vec2(-1, 0)); // moving away: turned round at once
    CHECK(sim.translation(2) == Vec2(-1, 0)); // moving back in: untouched
    CHECK(sim.translation(3) == Vec2(0, 0.75));
    CHECK(sim.translation(4) == Vec2(-1, 0)); // wider than the grid: oscillates in place
    sim.step();
    CHECK(sim.translation(4) == Vec2(0, 0));
    for (int f = 0; f < 100; ++f) sim.step();
    for (ObjectId id : {1, 2, 3}) {
        Box<2> b = boundsOf<2>(sim.shape(id));
        INFO("object " << id);
        CHECK(b.min.x >= 0);
        CHECK(b.max.x <= 10);
        CHECK(b.min.y >= 0);
        CHECK(b.max.y <= 10);
    }
    Vec2 t4 = sim.translation(4);
    CHECK((t4 == Vec2(0, 0) || t4 == Vec2(-1, 0)));
}

TEST_CASE("motion: static and zero-velocity objects never move, speed is |velocity| every frame", "[scene]") {
    std::mt19937 rng(12345);
    std::uniform_real_distribution<double> pos(-5, 15), vel(-3, 3), rad(0.2, 4);
    json objects = json::array();
    for (int i = 0; i < 60; ++i) {
        json o{{"id", i}, {"shape", "circle"}, {"center", {pos(rng), pos(rng)}}, {"radius", rad(rng)}};
        if (i % 3 == 1) o["velocity"] = {vel(rng), vel(rng)};
        if (i % 3 == 2) o["max_speed"] = 1.0; // may move but has no velocity
        objects.push_back(o);
    }
    SceneData2 d = boxWorld(objects.dump());
    SceneSimulator2 sim(d);
    for (int f = 0; f < 300; ++f) {
        std::vector<Vec2> before(sim.size());
        for (std::size_t i = 0; i < sim.size(); ++i) before[i] = sim.translationAt(i);
        sim.step();
        for (std::size_t i = 0; i < sim.size(); ++i) {
            Vec2 step = sim.translationAt(i) - before[i];
            const SceneObject<2>& o = d.objects[i];
            if (i % 3 != 1) {
                CHECK(step == Vec2(0, 0));
                CHECK_FALSE(sim.movedAt(i));
            } else {
                // Each component moves by exactly +-velocity (up to the rounding of the running sum).
                CHECK(std::abs(step.x) == Approx(std::abs(o.velocity.x)).margin(1e-12));
                CHECK(std::abs(step.y) == Approx(std::abs(o.velocity.y)).margin(1e-12));
                CHECK(std::sqrt(lengthSquared<2>(step)) <= o.maxSpeed + 1e-12);
            }
        }
    }
}

TEST_CASE("motion: 3D scenes step per axis too", "[scene]") {
    json j = example3D();
    // grid z: [-8, 8]; sphere z bbox [2.25, 3.75] at 0.1 a frame reaches 8 after 42.5 frames.
    Scene s = parse(j);
    SceneSimulator3 sim(*s.as<3>());
    for (int f = 0; f < 42; ++f) sim.step();
    CHECK(sim.translation(10).z == Approx(4.2));
    sim.step(); // 3.75 + 4.2 + 0.1 = 8.05 > 8: flips
    CHECK(sim.translation(10).z == Approx(4.1));
    CHECK(sim.velocity(10).z == -0.1);
    CHECK(sim.translation(11) == Vec3(0, 0, 0));
}

// ---------------------------------------------------------------------------------------------------
// obb and hull (scene-format.md: `obb` center, half_extents, rotation [x, y, z, w]; `hull` points).

namespace {
json obb() { return json::parse(R"({ "id": 12, "shape": "obb", "center": [0, 2, 6], "half_extents": [1, 0.5, 2], "rotation": [0, 0.38268343236508984, 0, 0.9238795325112867] })"); }
json hull() { return json::parse(R"({ "id": 13, "shape": "hull", "points": [[2, 0, 2], [4, 0, 2], [2, 0, 4], [2, 3, 2], [2.5, 0.5, 2.5]] })"); }
} // namespace

TEST_CASE("3D scenes parse obb and hull exactly", "[scene][polytope]") {
    json j = example3D();
    j["objects"].push_back(obb());
    j["objects"].push_back(hull());
    Scene s = parse(j);
    const auto& objs = s.as<3>()->objects;
    REQUIRE(objs.size() == 4);
    const auto* o = std::get_if<ConvexPolytope>(&objs[2].shape);
    REQUIRE(o);
    CHECK(o->vertices.size() == 8);
    CHECK(o->planes.size() == 6);
    // Turned by 45 degrees about y: the box's x/z bounds are (1 + 2) / sqrt 2 around the centre.
    CHECK(o->boundsMax.x == Approx(3 / std::sqrt(2.0)));
    CHECK(o->boundsMin.z == Approx(6 - 3 / std::sqrt(2.0)));
    CHECK(o->boundsMax.y == Approx(2.5));
    const auto* h = std::get_if<ConvexPolytope>(&objs[3].shape);
    REQUIRE(h);
    CHECK(h->vertices.size() == 4); // (2.5, 0.5, 2.5) is inside the tetrahedron
    CHECK(h->boundsMin == Vec3(2, 0, 2));
    CHECK(h->boundsMax == Vec3(4, 3, 4));
    // The rotation need only be unit to 1e-5 (JSON with 6 digits): normalised.
    json k = withObject(obb());
    k["objects"][2]["rotation"] = {0, 0.382683, 0, 0.92388};
    CHECK_NOTHROW(parse(k));
    // Motion: a moving hull reflects on its points' bounding box.
    json m = withObject(hull());
    m["objects"][2]["velocity"] = {0, 0, 1};
    Scene ms = parse(m);
    SceneSimulator3 sim(*ms.as<3>());
    for (int f = 0; f < 4; ++f) sim.step(); // z max 4 + 4 = 8 = the grid's bound: stays
    CHECK(sim.translation(13).z == 4);
    sim.step(); // would reach 9 > 8: flips
    CHECK(sim.translation(13).z == 3);
    const Box<3> b = boundsOf<3>(sim.shapeAt(2));
    CHECK(b.max.z == 7);
}

TEST_CASE("bad obb and hull objects name their field", "[scene][polytope]") {
    auto bad = [](const char* key, json value, bool isObb = true) {
        json o = isObb ? obb() : hull();
        if (value.is_null()) o.erase(key);
        else o[key] = std::move(value);
        return reject(withObject(o));
    };
    CHECK(bad("center", nullptr) == "objects[2].center");
    CHECK(bad("center", {0, 1}) == "objects[2].center");
    CHECK(bad("half_extents", nullptr) == "objects[2].half_extents");
    CHECK(bad("half_extents", {1, 0, 1}) == "objects[2].half_extents");
    CHECK(bad("half_extents", {1, -1, 1}) == "objects[2].half_extents");
    CHECK(bad("half_extents", {1, "x", 1}) == "objects[2].half_extents[1]");
    CHECK(bad("rotation", nullptr) == "objects[2].rotation");
    CHECK(bad("rotation", {0, 0, 1}) == "objects[2].rotation");
    CHECK(bad("rotation", {0, 0, 1, 1}) == "objects[2].rotation");  // length sqrt 2: not unit
    CHECK(bad("rotation", {0, 0, 0, 0}) == "objects[2].rotation");
    CHECK(bad("rotation", {0, 0, 0, 0.99}) == "objects[2].rotation"); // 1e-2 off: refused
    CHECK(bad("rotation", "identity") == "objects[2].rotation");
    CHECK(bad("points", nullptr, false) == "objects[2].points");
    CHECK(bad("points", 3, false) == "objects[2].points");
    CHECK(bad("points", json::parse("[[0,0,0],[1,0,0],[0,1,0]]"), false) == "objects[2].points"); // 3 points
    CHECK(bad("points", json::parse("[[0,0,0],[1,0,0],[0,1,0],[1,1,0],[5,5,0]]"), false) == "objects[2].points"); // one plane
    CHECK(bad("points", json::parse("[[0,0,0],[1,1,1],[2,2,2],[3,3,3]]"), false) == "objects[2].points");         // one line
    CHECK(bad("points", json::parse("[[1,1,1],[1,1,1],[1,1,1],[1,1,1]]"), false) == "objects[2].points");         // one point
    CHECK(bad("points", json::parse("[[0,0,0],[1,0,0],[0,1,0],[0,0]]"), false) == "objects[2].points[3]");
    CHECK(bad("points", json::parse("[[0,0,0],[1,0,0],[0,1,0],[0,0,\"z\"]]"), false) == "objects[2].points[3][2]");
    // NaN and infinity cannot be written in JSON; 1e999 overflows and names its field.
    std::string text = withObject(hull()).dump();
    CHECK(rejectText(replacedIn(text, "[4,0,2]", "[4,1e999,2]")) == "objects[2].points[1][1]");
    // 2D scenes have neither.
    json two = example2D();
    two["objects"].push_back(json::parse(R"({ "id": 99, "shape": "hull", "points": [[0,0],[1,0],[0,1]] })"));
    CHECK(reject(two) == "objects[3].shape");
    two["objects"][3]["shape"] = "obb";
    CHECK(reject(two) == "objects[3].shape");
}

// ---------------------------------------------------------------------------------------------------
// The scene writer (SceneWriter.hpp): a culler's scene dumped and loaded again culls to the same PVS.

namespace {

/// Dumps `culler` with `cam`, loads the text, builds a culler from it and culls the loaded camera.
template <int D> std::vector<ObjectId> replayed(const Culler<D>& culler, const Camera<D>& cam, const std::string& label) {
    const std::string text = sceneToJson<D>(culler, cam);
    const Scene scene = parseScene(text, label);
    const SceneData<D>* s = scene.as<D>();
    REQUIRE(s != nullptr);
    Culler<D> again(s->grid, culler.options());
    for (const SceneObject<D>& o : s->objects) again.addObject(o.desc());
    return again.cull(s->cameraAt(0)).pvs;
}

template <int D, class MakeScene> void roundTrips(int scenes, MakeScene&& makeScene) {
    int differ = 0, frames = 0;
    for (int i = 0; i < scenes; ++i) {
        auto scene = makeScene(std::uint64_t(500 + i));
        std::mt19937_64 rng(std::uint64_t(i) * 31 + 7);
        Culler<D> culler(scene.grid);
        // Roles, insets and motion vary, so that the dump carries every field.
        for (ObjectDesc<D> o : scene.objects) {
            o.role = ObjectRole(rng() % 3);
            if (rng() % 4 == 0) o.occluderInset = 0.1;
            if (rng() % 3 == 0) o.isStatic = false, o.maxSpeed = 0.25;
            culler.addObject(o);
        }
        const std::vector<ObjectId> pvs = culler.cull(scene.camera).pvs;
        INFO("seed " << scene.seed);
        differ += replayed<D>(culler, scene.camera, "round trip") != pvs;
        ++frames;
        // The dump's objects are the culler's: ids, roles, insets and flags.
        const Scene loaded = parseScene(sceneToJson<D>(culler, scene.camera), "round trip");
        const auto& objs = loaded.as<D>()->objects;
        const std::vector<ObjectDesc<D>> held = culler.objects();
        REQUIRE(objs.size() == held.size());
        for (std::size_t k = 0; k < held.size(); ++k) {
            CHECK(objs[k].id == held[k].id);
            CHECK(objs[k].role == held[k].role);
            CHECK(objs[k].occluderInset == held[k].occluderInset);
            CHECK(objs[k].isStatic == held[k].isStatic);
            CHECK(objs[k].maxSpeed == held[k].maxSpeed);
            CHECK(boundsOf<D>(objs[k].shape).min == boundsOf<D>(held[k].shape).min);
        }
    }
    std::printf("[scene] writer: %d %dD scenes written, loaded and culled: %d differ\n", frames, D, differ);
    REQUIRE(differ == 0);
}

} // namespace

TEST_CASE("scene writer: random 2D and 3D scenes round trip to the same PVS", "[scene]") {
    roundTrips<2>(120, [](std::uint64_t seed) { return reference::randomScene2D(seed); });
    roundTrips<3>(60, [](std::uint64_t seed) { return reference::randomScene3D(seed); });
}

TEST_CASE("scene writer: a moving scene dumped mid-run, with velocities, camera fields and the top view", "[scene]") {
    const GridGeometry3 grid({-8, 0, -8}, 0.5, {64, 32, 64});
    Culler3D culler(grid);
    culler.addObject({.id = 3, .shape = Box<3>{{-2, 0, 4}, {6, 8, 6}}, .isStatic = true});
    culler.addObject({.id = 4, .shape = Ball<3>{{2, 2, 12}, 1}, .maxSpeed = 0.5});
    culler.addObject({.id = 7, .shape = Ball<3>{{2, 2, -4}, 1}, .maxSpeed = 0.5, .role = ObjectRole::Occludee});
    Camera3 cam;
    cam.position = {2, 4, 0};
    cam.direction = {0, 0, 1};
    cam.fovDeg = 50;
    cam.aspect = 1.5;
    cam.far = 30;
    culler.cull(cam);
    culler.updateObject(4, Ball<3>{{2.25, 2, 12}, 1});
    const std::vector<ObjectId> pvs = culler.cull(cam).pvs;
    const SceneVelocities<3> v{{4, Vec3{0.25, 0, 0}}};
    const Scene s = parseScene(sceneToJson<3>(culler, cam, &v), "dump");
    const SceneData3& d = *s.as<3>();
    CHECK(d.camera.far == 30);
    CHECK(d.camera.aspect == 1.5);
    CHECK(d.objects[1].velocity == Vec3{0.25, 0, 0});
    CHECK(std::get<Ball<3>>(d.objects[1].shape).center.x == 2.25);
    CHECK(d.objects[2].role == ObjectRole::Occludee);
    CHECK(replayed<3>(culler, cam, "dump") == pvs);
    // A camera straight down with the default up: written with the up the culler used, so it loads.
    Camera3 top = cam;
    top.direction = {0, -1, 0};
    top.far = INFINITY;
    const SceneData3 t = *parseScene(sceneToJson<3>(culler, top), "top").as<3>();
    CHECK(t.camera.up == Vec3{0, 0, -1});
    CHECK(replayed<3>(culler, top, "top") == culler.cull(top).pvs);
    // What the format would refuse is refused here, naming the object.
    const SceneVelocities<3> fast{{4, Vec3{1, 0, 0}}}, onStatic{{3, Vec3{0.1, 0, 0}}};
    CHECK_THROWS_WITH(sceneToJson<3>(culler, cam, &fast), Catch::StartsWith("object 4.velocity"));
    CHECK_THROWS_WITH(sceneToJson<3>(culler, cam, &onStatic), Catch::StartsWith("object 3.velocity"));
    Camera3 bad = cam;
    bad.fovDeg = 0;
    CHECK_THROWS_AS(sceneToJson<3>(culler, bad), InvalidInput);
    CHECK_THROWS_WITH(writeSceneFile<3>("/nonexistent-dir/x.json", culler, cam), Catch::Contains("cannot be opened"));
    // occluder_inset is read back (and a negative one refused).
    json j = json::parse(sceneToJson<3>(culler, cam));
    j["objects"][0]["occluder_inset"] = -1;
    CHECK_THROWS_WITH(parseScene(j.dump(), "neg"), Catch::Contains("objects[0].occluder_inset"));
}
