// What the scene-file test files share (header-only; tests/test_scene_file.cpp, tests/test_mesh_file.cpp):
// the contract's example scenes, a 3D example with one object appended, and the check that a document is
// rejected with the one-line "<file>: <field>: <problem>" form scene-format.md fixes.
#pragma once

#include "SceneFile.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <exception>
#include <string>
#include <utility>

namespace rgvc::scene_test {

// The contract's example scene.
inline nlohmann::json example2D() {
    return nlohmann::json::parse(R"({
      "dimensions": 2,
      "grid":   { "origin": [0, 0], "voxel_size": 1.0, "resolution": [256, 256] },
      "camera": { "position": [10.5, 20.25], "direction": [1, 0.2], "fov_deg": 90 },
      "objects": [
        { "id": 1, "shape": "circle",  "center": [40, 30], "radius": 3.5, "velocity": [0.4, -0.1] },
        { "id": 2, "shape": "box",     "min": [60, 10], "max": [70, 90], "static": true },
        { "id": 3, "shape": "polygon", "points": [[80, 80], [90, 82], [85, 95]], "static": true }
      ]
    })");
}

inline nlohmann::json example3D() {
    return nlohmann::json::parse(R"({
      "dimensions": 3,
      "grid":   { "origin": [-8, 0, -8], "voxel_size": 0.5, "resolution": [32, 16, 32] },
      "camera": { "position": [0, 2, 0], "direction": [0, 0, 1], "fov_deg": 60 },
      "objects": [
        { "id": 10, "shape": "sphere", "center": [1, 2, 3], "radius": 0.75, "velocity": [0, 0, 0.1] },
        { "id": 11, "shape": "box", "min": [-1, 0, 4], "max": [1, 3, 5] }
      ]
    })");
}

// example3D() with `object` appended (objects[2]).
inline nlohmann::json withObject(nlohmann::json object) {
    nlohmann::json j = example3D();
    j["objects"].push_back(std::move(object));
    return j;
}

// Parses text that must be rejected; checks the one-line "t.json: <field>: <problem>" form and returns the field.
inline std::string rejectText(const std::string& text) {
    try {
        parseScene(text, "t.json");
    } catch (const SceneError& e) {
        const std::string what = e.what();
        CHECK(what.find('\n') == std::string::npos);
        CHECK(e.file() == "t.json");
        CHECK(what.rfind("t.json: " + e.field() + ": ", 0) == 0);
        CHECK_FALSE(e.problem().empty());
        return e.field();
    } catch (const std::exception& e) {
        FAIL("not a SceneError: " << e.what());
    }
    FAIL("accepted: " << text);
    return {};
}
inline std::string reject(const nlohmann::json& j) { return rejectText(j.dump()); }

} // namespace rgvc::scene_test
