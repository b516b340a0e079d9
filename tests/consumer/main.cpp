// The consumer check (tests/consumer/CMakeLists.txt): a game's smallest use of rgvc, built against the
// installed package or through add_subdirectory. A wall, a sphere hidden behind it and one in front;
// the PVS must be the wall and the front sphere. Exit 0 when it is.
#include <rgvc/config.hpp>
#include <rgvc/rgvc.hpp>
#include <rgvc/version.hpp>
#if RGVC_CONSUMER_GL
#include <rgvc/render/gl/GlContext.hpp>
#endif

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <vector>

// This project asks for C++17; rgvc's headers compile only because its cxx_std_20 reached this target.
static_assert(__cplusplus >= 202002L, "rgvc's C++20 requirement did not propagate (target_compile_features)");
static_assert(RGVC_VERSION_MAJOR == 0 && RGVC_VERSION_MINOR >= 2, "rgvc/version.hpp");

int main() {
    rgvc::Culler3D culler(rgvc::GridGeometry3({0, 0, 0}, 1.0, {32, 32, 32}));
    culler.addObject({.id = 1, .shape = rgvc::Box<3>{{12, 0, 0}, {14, 32, 32}}, .isStatic = true}); // a wall
    culler.addObject({.id = 2, .shape = rgvc::Ball<3>{{24, 16, 16}, 2}, .maxSpeed = 0.5});          // behind it
    culler.addObject({.id = 3, .shape = rgvc::Ball<3>{{6, 16, 16}, 1}, .maxSpeed = 0.5});           // in front

    const rgvc::Camera3 camera{.position = {2.5, 16.25, 16.25}, .direction = {1, 0, 0}, .fovDeg = 60};
    std::vector<rgvc::ObjectId> pvs = culler.cull(camera).pvs;
    std::sort(pvs.begin(), pvs.end());

    std::printf("rgvc %s (RGVC_WITH_GL %d, RGVC_WITH_OPENVDB %d), pvs:", RGVC_VERSION_STRING, RGVC_WITH_GL,
                RGVC_WITH_OPENVDB);
    for (rgvc::ObjectId id : pvs) std::printf(" %llu", (unsigned long long)id);
    std::printf("\n");
    if (std::strcmp(RGVC_VERSION_STRING, RGVC_CONSUMER_EXPECTED_VERSION) != 0) {
        std::printf("FAIL: version.hpp says %s, the package %s\n", RGVC_VERSION_STRING,
                    RGVC_CONSUMER_EXPECTED_VERSION);
        return 1;
    }
#if RGVC_CONSUMER_GL
    // Links rgvc::render_gl and its OSMesa: a context is made only when asked (it needs llvmpipe).
    std::printf("gl component linked (%p)\n", reinterpret_cast<void*>(&rgvc::createOsMesaContext));
#endif
    const std::vector<rgvc::ObjectId> expected{1, 3};
    if (pvs != expected) {
        std::printf("FAIL: expected the pvs 1 3\n");
        return 1;
    }
    return 0;
}
