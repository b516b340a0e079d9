// Object roles (ObjectDesc::role, scene-format.md's `role`) in 2D and 3D, against the references.
//
// The contract's visibility leaves occludees out of the blockers: "the open segment ... does not meet the
// interior of the union of the other objects (... leaving out those whose role is `occludee`)". The
// references take plain shape lists, so a frame's truth is built from them: the objects that are not
// occludees see each other as usual (occludees block nothing, so leaving them out changes nothing for
// the others), and each occludee X is visible when it is visible among the non-occludees plus X alone.
// Checked: every visible object that is not an occluder-only one is in the PVS, and no occluder-only
// object ever is; a glass wall hides nothing and a hidden wall still hides.
#include "CullerTestSupport.hpp"

#include "RandomScenes2D.hpp"
#include "RandomScenes3D.hpp"
#include "rgvc/dynamics/Culler.hpp"

#include <catch2/catch.hpp>

#include <random>
#include <vector>

using namespace rgvc;
using namespace rgvc::culler_test;

namespace {

/// Per object, whether it is visible under the roles (see the top of the file).
template <int D>
std::vector<bool> visibleWithRoles(const std::vector<ObjectDesc<D>>& objects, const Camera<D>& cam) {
    std::vector<Shape<D>> blockers;
    std::vector<std::size_t> blockerIndex;
    for (std::size_t i = 0; i < objects.size(); ++i)
        if (objects[i].role != ObjectRole::Occludee) {
            blockers.push_back(objects[i].shape);
            blockerIndex.push_back(i);
        }
    std::vector<bool> visible(objects.size(), false);
    const std::vector<bool> base = referenceVisible<D>(blockers, cam);
    for (std::size_t k = 0; k < blockerIndex.size(); ++k) visible[blockerIndex[k]] = base[k];
    for (std::size_t i = 0; i < objects.size(); ++i) {
        if (objects[i].role != ObjectRole::Occludee) continue;
        std::vector<Shape<D>> withX = blockers;
        withX.push_back(objects[i].shape);
        visible[i] = referenceVisible<D>(withX, cam).back();
    }
    return visible;
}

template <int D> struct RandomScene;
template <> struct RandomScene<2> {
    static reference::Scene2D make(std::uint64_t seed) { return reference::randomScene2D(seed); }
};
template <> struct RandomScene<3> {
    static reference::Scene3D make(std::uint64_t seed) { return reference::randomScene3D(seed, {.maxObjects = 40}); }
};

/// Random scenes with random roles: zero misses, no occluder-only object reported. Returns how many
/// visible objects were checked (for the caller to assert the test did something).
template <int D> std::size_t checkRandomRoles(std::uint64_t firstSeed, int scenes) {
    std::size_t checked = 0, occluderOnly = 0, occludees = 0;
    for (std::uint64_t seed = firstSeed; seed < firstSeed + std::uint64_t(scenes); ++seed) {
        auto scene = RandomScene<D>::make(seed);
        std::mt19937_64 rng(seed * 7919 + 3);
        for (ObjectDesc<D>& o : scene.objects) {
            const auto r = rng() % 10;
            o.role = r < 3 ? ObjectRole::Occludee : r < 4 ? ObjectRole::Occluder : ObjectRole::Both;
            occludees += o.role == ObjectRole::Occludee;
            occluderOnly += o.role == ObjectRole::Occluder;
        }
        Culler<D> culler = makeCuller<D>(scene.grid, scene.objects);
        const CullResult& r = culler.cull(scene.camera);
        const std::vector<bool> visible = visibleWithRoles<D>(scene.objects, scene.camera);
        for (std::size_t i = 0; i < scene.objects.size(); ++i) {
            const ObjectDesc<D>& o = scene.objects[i];
            INFO(D << "D, seed " << seed << ", object " << o.id << ", role " << toString(o.role));
            if (o.role == ObjectRole::Occluder) {
                CHECK_FALSE(contains(r.pvs, o.id));
            } else if (visible[i]) {
                ++checked;
                CHECK(contains(r.pvs, o.id));
            }
        }
    }
    CHECK(occludees > 0);
    CHECK(occluderOnly > 0);
    return checked;
}

} // namespace

TEST_CASE("roles: a glass wall hides nothing, a hidden wall hides and is not reported", "[culler][roles]") {
    for (ObjectRole role : {ObjectRole::Both, ObjectRole::Occludee, ObjectRole::Occluder}) {
        INFO("wall role " << toString(role));
        {
            Culler3D culler(GridGeometry3({0, 0, 0}, 1.0, {32, 32, 32}));
            culler.addObject({1, Box<3>{{12, 2, 2}, {14, 30, 30}}, true, 0, 0, role});
            culler.addObject({2, Ball<3>{{24, 16, 16}, 1.5}, true});
            const CullResult& r = culler.cull(makeCamera({5.5, 16.5, 16.5}, {1, 0, 0}, 60));
            CHECK(contains(r.pvs, ObjectId(1)) == (role != ObjectRole::Occluder));
            CHECK(contains(r.pvs, ObjectId(2)) == (role == ObjectRole::Occludee));
            CHECK(r.stats.pvsSize == r.pvs.size());
            CHECK(culler.voxelState({13, 16, 16}).opaque == (role != ObjectRole::Occludee));
        }
        {
            Culler2D culler(GridGeometry2({0, 0}, 1.0, {64, 64}));
            culler.addObject({1, Box<2>{{12, 2}, {14, 62}}, true, 0, 0, role});
            culler.addObject({2, Ball<2>{{24, 32}, 1.5}, true});
            const CullResult& r = culler.cull(makeCamera({5.5, 32.5}, {1, 0}, 60));
            CHECK(contains(r.pvs, ObjectId(1)) == (role != ObjectRole::Occluder));
            CHECK(contains(r.pvs, ObjectId(2)) == (role == ObjectRole::Occludee));
        }
    }
}

TEST_CASE("roles: a moving occluder-only object keeps hiding while in view, never reported", "[culler][roles]") {
    // The occluder-only wall moves slowly across the view; the sphere behind it stays hidden in every frame
    // (the wall is tracked like a PVS object: it never drops out of O for a TBV while it is in view).
    Culler3D culler(GridGeometry3({0, 0, 0}, 1.0, {48, 32, 48}));
    culler.addObject({1, Box<3>{{14, 0, 0}, {16, 32, 48}}, false, 0.05, 0, ObjectRole::Occluder});
    culler.addObject({2, Ball<3>{{30, 16, 24}, 1.5}, true});
    for (int f = 0; f < 40; ++f) {
        INFO("frame " << f);
        const double dx = 0.05 * f;
        const CullResult& r = culler.cull(makeCamera({5.5, 16.5, 24.5}, {1, 0, 0}, 60), [&](ObjectId id) -> Shape<3> {
            REQUIRE(id == 1);
            return Box<3>{{14 + dx, 0, 0}, {16 + dx, 32, 48}};
        });
        CHECK(r.pvs.empty());
    }
}

TEST_CASE("roles: random 2D scenes with random roles, zero misses, occluders never reported", "[culler][roles]") {
    CHECK(checkRandomRoles<2>(0x401E5ULL, 300) > 300);
}

TEST_CASE("roles: random 3D scenes with random roles, zero misses, occluders never reported", "[culler][roles]") {
    CHECK(checkRandomRoles<3>(0x401E53ULL, 120) > 100);
}

TEST_CASE("roles: bad roles are refused with their field", "[culler][roles][errors]") {
    Culler3D culler(GridGeometry3({0, 0, 0}, 1.0, {8, 8, 8}));
    try {
        culler.addObject({5, Ball<3>{{4, 4, 4}, 1}, true, 0, 0, ObjectRole(9)});
        FAIL("accepted a bad role");
    } catch (const InvalidInput& e) {
        CHECK(e.field() == "object 5.role");
    }
    CHECK_FALSE(culler.hasObject(5));
}
