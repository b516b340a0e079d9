// libFuzzer target: arbitrary bytes -> rgvc::parseScene.
//
// A SceneError is the one acceptable way to refuse a file (scene-format.md: exit status 2 and one line);
// it must be one line of the form "<file>: <field>: <problem>". Anything else that escapes (another
// exception, a crash, a sanitizer report, a hang) is a bug. A scene that parses must also be usable: its
// camera and shapes pass the library's validators, its ids are unique, and a small 2D scene loads into a
// Culler2D and culls every frame of its camera path (up to 8) with a sorted, duplicate-free PVS of known ids.
//
// Build: -DRGVC_BUILD_FUZZERS=ON -DCMAKE_CXX_COMPILER=clang++; run: scripts/fuzz.sh scene_loader.
#include "SceneFile.hpp"

#include "rgvc/dynamics/Culler.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <functional>
#include <string>
#include <unordered_set>

namespace {

[[noreturn]] void bug(const std::string& what) {
    std::fprintf(stderr, "fuzz_scene_loader: BUG: %s\n", what.c_str());
    std::fflush(stderr);
    std::abort();
}

template <int D> void checkScene(const rgvc::SceneData<D>& s) {
    try {
        rgvc::validateCamera<D>(s.camera);
        for (std::size_t t = 0; s.cameraPath && t < s.cameraPath->size(); ++t) rgvc::validateCamera<D>(s.cameraAt(t));
        for (const rgvc::SceneObject<D>& o : s.objects) {
            rgvc::Shape<D> copy = o.shape;
            rgvc::validateShape<D>(copy, "object");
            if (!(o.maxSpeed >= 0) || !std::isfinite(o.maxSpeed)) bug("accepted a bad max_speed");
        }
    } catch (const rgvc::InvalidInput& e) {
        bug(std::string("parseScene accepted what the library rejects: ") + e.what());
    }
    std::unordered_set<rgvc::ObjectId> ids;
    for (const rgvc::SceneObject<D>& o : s.objects)
        if (!ids.insert(o.id).second) bug("parseScene accepted a duplicate id " + std::to_string(o.id));
}

void cullScene(const rgvc::SceneData2& s) {
    // Small grids only: the fuzzer should spend its time on parsing, not on allocating voxels.
    if (s.grid.voxelCount() > (1u << 14)) return;
    std::unordered_set<rgvc::ObjectId> ids;
    try {
        rgvc::Culler2D culler(s.grid);
        for (const rgvc::SceneObject<2>& o : s.objects) {
            culler.addObject(o.desc());
            ids.insert(o.id);
        }
        const std::size_t frames = std::min<std::size_t>(s.frameLimit(), 8);
        for (std::size_t t = 0; t < frames; ++t) {
            const rgvc::CullResult& r = culler.cull(s.cameraAt(t));
            if (std::adjacent_find(r.pvs.begin(), r.pvs.end(), std::greater_equal<rgvc::ObjectId>()) != r.pvs.end())
                bug("PVS not sorted ascending without duplicates");
            for (rgvc::ObjectId id : r.pvs)
                if (!ids.count(id)) bug("PVS holds unknown id " + std::to_string(id));
            if (r.stats.pvsSize != r.pvs.size()) bug("stats.pvs_size differs from the PVS");
        }
    } catch (const rgvc::InvalidInput& e) {
        bug(std::string("Culler2D rejected a scene that parseScene accepted: ") + e.what());
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    rgvc::Scene scene;
    try {
        scene = rgvc::parseScene(text, "fuzz.json");
    } catch (const rgvc::SceneError& e) {
        const std::string what = e.what();
        if (what.find('\n') != std::string::npos || what.find('\r') != std::string::npos)
            bug("SceneError message spans lines: " + what);
        if (e.file() != "fuzz.json" || what.rfind("fuzz.json: " + e.field() + ": ", 0) != 0)
            bug("SceneError not of the form '<file>: <field>: <problem>': " + what);
        if (e.field().empty() || e.problem().empty()) bug("SceneError with an empty field or problem: " + what);
        return 0;
    } catch (const std::bad_alloc&) {
        return 0; // documented: loadScene/parseScene may throw bad_alloc
    } catch (const std::exception& e) {
        bug(std::string("parseScene threw something other than SceneError: ") + e.what());
    }
    if (scene.dimensions != 2 && scene.dimensions != 3) bug("dimensions " + std::to_string(scene.dimensions));
    if (const rgvc::SceneData2* s2 = scene.as<2>()) {
        if (scene.dimensions != 2) bug("2D data in a 3D scene");
        checkScene<2>(*s2);
        cullScene(*s2);
    } else if (const rgvc::SceneData3* s3 = scene.as<3>()) {
        if (scene.dimensions != 3) bug("3D data in a 2D scene");
        checkScene<3>(*s3);
    }
    return 0;
}
