// The GL stage's traversal without GL: ChcRenderer (ZB, VFC, stop-and-wait, CHC, CHC++, Ideal) over an
// ObjectBvh (tested in test_object_bvh.cpp) and the deterministic CPU device of FakeQueryDevice.hpp.
// The central check: with n_vp = 0, the image of every frame equals the image of drawing everything
// (zero misses), on random scenes and coherent walks, with query latency.
#include "ChcTestSupport.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

using namespace rgvc;
using namespace rgvc::testing;

namespace {

constexpr CullMethod kQueryMethods[] = {CullMethod::StopAndWait, CullMethod::Chc, CullMethod::ChcPlusPlus};

std::vector<ObjectId> sorted(std::vector<ObjectId> v) {
    std::sort(v.begin(), v.end());
    return v;
}

/// Runs `frames` frames of a walk with every method in `methods` (each its own renderer, one device)
/// and checks each frame's image against drawing everything. Returns the total queries per method.
struct WalkResult {
    std::vector<std::uint64_t> queries;
    std::vector<std::uint64_t> drawn;
    int failures = 0;
};
WalkResult checkWalk(const ChcScene& s, const std::string& label, std::span<const CullMethod> methods, int frames,
                     int latency, const ChcOptions& options = {}, double degPerFrame = 1.5) {
    FakeQueryDevice device(64, 48, 0.01, latency);
    ObjectBvh bvh;
    load(s, device, bvh);
    std::vector<ChcRenderer> renderers;
    renderers.reserve(methods.size());
    for (std::size_t m = 0; m < methods.size(); ++m) renderers.emplace_back(device, bvh, options);
    WalkResult r;
    r.queries.assign(methods.size(), 0);
    r.drawn.assign(methods.size(), 0);
    for (int f = 0; f < frames && r.failures == 0; ++f) {
        const Camera3 cam = walkCamera(s.camera, s.step, f, degPerFrame);
        const IdDepthImage full = device.referenceImage(cam, s.ids);
        for (std::size_t m = 0; m < methods.size(); ++m) {
            const std::uint64_t fetchesBefore = device.blockingFetches();
            const ChcFrameStats& st = renderers[m].renderAll(cam, methods[m]);
            r.queries[m] += st.queries();
            r.drawn[m] += st.objectsDrawn;
            const bool same = device.image() == full;
            if (!same) {
                ++r.failures;
                FAIL_CHECK(label << ", frame " << f << ", " << cullMethodName(methods[m]) << ", latency " << latency
                                 << ": the image differs from drawing everything\n"
                                 << device.image().differences(full));
            }
            // The stats agree with what the device saw.
            CHECK(st.blockingFetches == device.blockingFetches() - fetchesBefore);
            CHECK(st.objectsDrawn == st.drawn.size());
            CHECK(!st.approximate);
        }
    }
    return r;
}

} // namespace

// --------------------------------------------------------------------------------------------------
// The traversal: conservativeness

TEST_CASE("CHC, CHC++, S&W and VFC miss nothing on random scenes and walks (n_vp = 0, with latency)", "[chc]") {
    const CullMethod methods[] = {CullMethod::Vfc, CullMethod::StopAndWait, CullMethod::Chc, CullMethod::ChcPlusPlus};
    int scenes = 0;
    for (std::uint64_t seed = 1; seed <= 100; ++seed) {
        const ChcScene s = randomChcScene(seed);
        for (int latency : {0, 3}) {
            const WalkResult r = checkWalk(s, "random scene seed " + std::to_string(seed), methods, 10, latency);
            CHECK(r.failures == 0);
        }
        ++scenes;
    }
    CHECK(scenes == 100);
}

TEST_CASE("CHC and CHC++ miss nothing with t_av, small batches and without tight bounds or multiqueries", "[chc]") {
    const CullMethod methods[] = {CullMethod::Chc, CullMethod::ChcPlusPlus};
    ChcOptions variants[4];
    variants[0].assumedVisibleFrames = 4;
    variants[1].batchSize = 1;
    variants[1].maxMultiquerySize = 3;
    variants[2].tightBounds = false;
    variants[2].multiqueries = false;
    variants[3].tightBoundsDepth = 4;
    variants[3].tightBoundsRatio = 2.0;
    variants[3].assumedVisibleFrames = 2;
    for (std::uint64_t seed = 100; seed < 112; ++seed)
        for (int v = 0; v < 4; ++v) {
            const ChcScene s = randomChcScene(seed);
            const WalkResult r =
                checkWalk(s, "seed " + std::to_string(seed) + ", options " + std::to_string(v), methods, 8, 2, variants[v]);
            CHECK(r.failures == 0);
        }
}

TEST_CASE("CHC: a camera inside a room of boxes sees the walls only, without querying the boxes it is in", "[chc]") {
    ChcScene s;
    // Six walls of a room [0, 10]^3 (thickness 0.5), and spheres outside it.
    const double t = 0.5;
    const Box<3> walls[6] = {{{-t, 0, 0}, {0, 10, 10}}, {{10, 0, 0}, {10 + t, 10, 10}}, {{0, -t, 0}, {10, 0, 10}},
                             {{0, 10, 0}, {10, 10 + t, 10}}, {{0, 0, -t}, {10, 10, 0}}, {{0, 0, 10}, {10, 10, 10 + t}}};
    for (int i = 0; i < 6; ++i) {
        s.ids.push_back(ObjectId(i + 1));
        s.shapes.push_back(walls[i]);
    }
    std::mt19937_64 rng(3);
    for (int i = 0; i < 200; ++i) {
        Vec3 c;
        do c = Vec3{reference::seeded::uniform(rng, -30, 40), reference::seeded::uniform(rng, -30, 40),
                    reference::seeded::uniform(rng, -30, 40)};
        while (c.x > -3 && c.x < 13 && c.y > -3 && c.y < 13 && c.z > -3 && c.z < 13);
        s.ids.push_back(ObjectId(100 + i));
        s.shapes.push_back(Ball<3>{c, 1.0});
    }
    s.camera.position = Vec3{5, 5, 5};
    s.camera.direction = Vec3{1, 0.2, 0.3};
    s.camera.fovDeg = 90;
    s.step = 0.05;
    const CullMethod methods[] = {CullMethod::StopAndWait, CullMethod::Chc, CullMethod::ChcPlusPlus};
    CHECK(checkWalk(s, "room", methods, 20, 2, {}, 10).failures == 0);

    FakeQueryDevice device(64, 48, 0.01, 2);
    ObjectBvh bvh;
    load(s, device, bvh);
    ChcRenderer chc(device, bvh);
    for (int f = 0; f < 6; ++f) {
        const ChcFrameStats& st = chc.renderAll(walkCamera(s.camera, s.step, f, 20), CullMethod::ChcPlusPlus);
        CHECK(st.nodesNearCamera >= 1); // the root (and every box holding the eye) without a query
        // Once coherence has settled: the walls, and what shares a leaf with a wall (a visible leaf
        // draws all its objects) or a leaf whose box holds the eye.
        if (f >= 2)
            for (ObjectId id : st.drawn) {
                const ObjectBvh::Node& leaf = bvh.node(bvh.leafOf(bvh.slotOf(id)));
                const Vec3 eye = walkCamera(s.camera, s.step, f, 20).position;
                const Box<3>& b = leaf.bounds;
                const bool holdsEye = b.min.x <= eye.x && eye.x <= b.max.x && b.min.y <= eye.y && eye.y <= b.max.y &&
                                      b.min.z <= eye.z && eye.z <= b.max.z;
                bool withWall = false;
                for (std::uint32_t slot : leaf.objects) withWall = withWall || bvh.objectId(slot) <= 6;
                CHECK((withWall || holdsEye));
            }
    }
}

TEST_CASE("CHC++: a batched query of a node whose box holds the eye would be wrong, the node is visible", "[chc]") {
    // The eye lies in leaf L = {Y, Q} (Y in front, Q behind the eye). A query of L's box counts its far
    // faces only (z = 4), which the wall Z (z = 3.5, drawn at once as previously visible) hides, although
    // Y's front (z = 3) is in front of Z. CHC++ batches L's query until after Z is drawn, so without the
    // camera-inside rule L is culled in frame 3 and Y's half of the image is missing.
    ChcScene s;
    s.ids = {1, 2, 3};
    s.shapes = {Box<3>{{-10, -10, 3}, {0, 10, 4}},       // Y: the left half of the view at z = 3
                Box<3>{{-10, -1, -3}, {-9, 1, -2}},      // Q: behind the eye
                Box<3>{{-0.4, -0.4, 3.5}, {200, 0.4, 3.6}}}; // Z: the whole (narrow) view at z = 3.5
    s.camera.position = Vec3(0.0);
    s.camera.direction = Vec3{0, 0, 1};
    s.camera.fovDeg = 10;
    BvhOptions two;
    two.maxLeafObjects = 2;
    FakeQueryDevice device(64, 48, 0.01, 0);
    ObjectBvh bvh(two);
    load(s, device, bvh);
    REQUIRE(bvh.leafOf(bvh.slotOf(1)) == bvh.leafOf(bvh.slotOf(2))); // the scene is built as intended
    REQUIRE(bvh.leafOf(bvh.slotOf(1)) != bvh.leafOf(bvh.slotOf(3)));
    ChcOptions loose; // tight bounds would query Y's own box, which does not hold the eye
    loose.tightBounds = false;
    ChcRenderer plus(device, bvh, loose);
    const IdDepthImage full = device.referenceImage(s.camera, s.ids);
    REQUIRE(full.visibleIds() == std::vector<ObjectId>{1, 3});
    for (int f = 0; f < 5; ++f) {
        const ChcFrameStats& st = plus.renderAll(s.camera, CullMethod::ChcPlusPlus);
        INFO("frame " << f);
        CHECK(st.nodesNearCamera >= 2); // the root and L
        CHECK(device.image() == full);
    }
}

// --------------------------------------------------------------------------------------------------
// The traversal: what coherence buys

TEST_CASE("CHC issues fewer queries than S&W on a coherent walk, CHC++ fewer than CHC, same images", "[chc]") {
    const CullMethod methods[] = {CullMethod::StopAndWait, CullMethod::Chc, CullMethod::ChcPlusPlus, CullMethod::Vfc};
    for (std::uint64_t seed : {1u, 2u}) {
        const ChcScene s = boxCity(seed);
        const WalkResult r = checkWalk(s, "box city seed " + std::to_string(seed), methods, 60, 4, {}, 0.1);
        REQUIRE(r.failures == 0);
        INFO("queries over the walk: S&W " << r.queries[0] << ", CHC " << r.queries[1] << ", CHC++ " << r.queries[2]
                                           << "; drawn: S&W " << r.drawn[0] << ", CHC " << r.drawn[1] << ", CHC++ "
                                           << r.drawn[2] << ", VFC " << r.drawn[3]);
        CHECK(r.queries[1] < r.queries[0]);
        CHECK(r.queries[2] < r.queries[1]);
        CHECK(r.drawn[1] < r.drawn[3]); // occlusion culling culls
        CHECK(r.drawn[2] < r.drawn[3]);
    }
}

TEST_CASE("CHC and CHC++ draw S&W's set in a static view after a few frames", "[chc]") {
    for (std::uint64_t seed : {1u, 2u, 3u}) {
        const ChcScene s = boxCity(seed, 8, 200);
        for (int latency : {0, 3}) {
            FakeQueryDevice device(64, 48, 0.01, latency);
            ObjectBvh bvh;
            load(s, device, bvh);
            ChcRenderer sw(device, bvh), chc(device, bvh), chcpp(device, bvh);
            const Camera3 cam = walkCamera(s.camera, s.step, 10, 0.1);
            const std::vector<ObjectId> swSet = sorted(sw.renderAll(cam, CullMethod::StopAndWait).drawn);
            std::vector<ObjectId> chcSet, chcppSet;
            std::uint32_t chcQueries = 0;
            for (int f = 0; f < 6; ++f) {
                chcSet = sorted(chc.renderAll(cam, CullMethod::Chc).drawn);
                chcQueries = chc.lastStats().queries();
                chcppSet = sorted(chcpp.renderAll(cam, CullMethod::ChcPlusPlus).drawn);
            }
            INFO("seed " << seed << ", latency " << latency);
            CHECK(chcSet == swSet);
            // Pull-up: the root is visible, and every drawn object's leaf was classified visible.
            CHECK(chc.nodeVisible(bvh.root()));
            for (ObjectId id : chcSet) CHECK(chc.nodeVisible(bvh.leafOf(bvh.slotOf(id))));
            CHECK(chcppSet == swSet);
            CHECK(chcQueries < sw.lastStats().queries());
        }
    }
}

TEST_CASE("CHC over moving objects: the refitted hierarchy keeps its ids and CHC misses nothing", "[chc]") {
    ChcScene s = boxCity(9, 8, 300);
    FakeQueryDevice device(64, 48, 0.01, 3);
    ObjectBvh bvh;
    load(s, device, bvh);
    ChcRenderer chc(device, bvh), chcpp(device, bvh);
    std::mt19937_64 rng(9);
    std::vector<Vec3> velocity(s.ids.size(), Vec3(0.0));
    for (std::size_t i = 64; i < s.ids.size(); ++i) // the small objects move; the buildings stay
        velocity[i] = Vec3{reference::seeded::uniform(rng, -0.3, 0.3), 0, reference::seeded::uniform(rng, -0.3, 0.3)};
    std::uint64_t sum = 0;
    for (int f = 0; f < 30; ++f) {
        const std::vector<NodeShape> pre = shapeOf(bvh);
        for (std::size_t i = 64; i < s.ids.size(); ++i) {
            s.shapes[i] = translated<3>(s.shapes[i], velocity[i]);
            device.setObject(s.ids[i], s.shapes[i]);
            bvh.update(s.ids[i], boundsOf<3>(s.shapes[i]));
        }
        REQUIRE(checkBvh(bvh).empty());
        CHECK(shapeOf(bvh) == pre);
        const Camera3 cam = walkCamera(s.camera, s.step, f, 0.1);
        const IdDepthImage full = device.referenceImage(cam, s.ids);
        for (ChcRenderer* r : {&chc, &chcpp}) {
            const ChcFrameStats& st = r->renderAll(cam, r == &chc ? CullMethod::Chc : CullMethod::ChcPlusPlus);
            sum += st.queries();
            INFO("frame " << f << ", " << cullMethodName(st.method));
            REQUIRE(device.image() == full);
        }
    }
    CHECK(sum > 0);
}

TEST_CASE("CHC over churn: objects added, removed and teleported, the tree rebuilt when degraded", "[chc]") {
    ChcScene s = boxCity(11, 8, 200);
    FakeQueryDevice device(64, 48, 0.01, 2);
    ObjectBvh bvh;
    load(s, device, bvh);
    ChcRenderer chc(device, bvh), chcpp(device, bvh);
    std::mt19937_64 rng(11);
    using reference::seeded::uniform;
    ObjectId next = 100000;
    int rebuilds = 0;
    for (int f = 0; f < 40; ++f) {
        for (int k = 0; k < 6; ++k) { // teleports anywhere in the city (not into the walk's street)
            const std::size_t i = 64 + rng() % (s.ids.size() - 64);
            Vec3 c{uniform(rng, -5, 80), uniform(rng, 0.3, 3), uniform(rng, -5, 80)};
            if (c.z > 26 && c.z < 31) c.z += 6;
            s.shapes[i] = Ball<3>{c, uniform(rng, 0.2, 0.8)};
            device.setObject(s.ids[i], s.shapes[i]);
            bvh.update(s.ids[i], boundsOf<3>(s.shapes[i]));
        }
        if (f % 3 == 0) { // one removed, two added
            const std::size_t i = 64 + rng() % (s.ids.size() - 64);
            bvh.remove(s.ids[i]);
            device.removeObject(s.ids[i]);
            s.ids.erase(s.ids.begin() + std::ptrdiff_t(i));
            s.shapes.erase(s.shapes.begin() + std::ptrdiff_t(i));
            for (int a = 0; a < 2; ++a) {
                const Vec3 c{uniform(rng, 0, 40), uniform(rng, 0.3, 3), uniform(rng, 31, 40)};
                s.ids.push_back(next++);
                s.shapes.push_back(Box<3>{c, c + 0.7});
                device.setObject(s.ids.back(), s.shapes.back());
                bvh.insert(s.ids.back(), boundsOf<3>(s.shapes.back()));
            }
        }
        rebuilds += bvh.rebuildIfDegraded() ? 1 : 0;
        REQUIRE(checkBvh(bvh).empty());
        const Camera3 cam = walkCamera(s.camera, s.step, f, 0.1);
        const IdDepthImage full = device.referenceImage(cam, s.ids);
        for (ChcRenderer* r : {&chc, &chcpp}) {
            const ChcFrameStats& st = r->renderAll(cam, r == &chc ? CullMethod::Chc : CullMethod::ChcPlusPlus);
            INFO("frame " << f << ", " << cullMethodName(st.method));
            REQUIRE(device.image() == full);
        }
    }
    CHECK(rebuilds >= 1);
    CHECK(bvh.buildCount() == std::uint64_t(1 + rebuilds));
}

// --------------------------------------------------------------------------------------------------
// Candidates, baselines, options and errors

TEST_CASE("Candidates: only they are drawn, and every one of them that shows is drawn", "[chc]") {
    for (std::uint64_t seed = 200; seed < 210; ++seed) {
        const ChcScene s = randomChcScene(seed);
        FakeQueryDevice device(64, 48, 0.01, 2);
        ObjectBvh bvh;
        load(s, device, bvh);
        std::mt19937_64 rng(seed);
        std::vector<ObjectId> candidates;
        for (ObjectId id : s.ids)
            if (rng() % 2) candidates.push_back(id);
        if (!candidates.empty()) candidates.push_back(candidates.front()); // a duplicate is harmless
        const std::vector<ObjectId> sortedCandidates = [&] {
            std::vector<ObjectId> v = sorted(candidates);
            v.erase(std::unique(v.begin(), v.end()), v.end());
            return v;
        }();
        ChcRenderer r[6] = {{device, bvh}, {device, bvh}, {device, bvh}, {device, bvh}, {device, bvh}, {device, bvh}};
        const CullMethod all[] = {CullMethod::Zb, CullMethod::Vfc, CullMethod::StopAndWait,
                                  CullMethod::Chc, CullMethod::ChcPlusPlus, CullMethod::Ideal};
        for (int f = 0; f < 6; ++f) {
            const Camera3 cam = walkCamera(s.camera, s.step, f);
            const IdDepthImage ref = device.referenceImage(cam, candidates);
            for (int m = 0; m < 6; ++m) {
                const ChcFrameStats& st = r[m].render(cam, all[m], candidates);
                INFO("seed " << seed << ", frame " << f << ", " << cullMethodName(all[m]));
                const std::vector<ObjectId> drawn = sorted(st.drawn);
                CHECK(std::adjacent_find(drawn.begin(), drawn.end()) == drawn.end()); // each once
                CHECK(std::includes(sortedCandidates.begin(), sortedCandidates.end(), drawn.begin(), drawn.end()));
                if (all[m] == CullMethod::Zb || all[m] == CullMethod::Ideal) CHECK(drawn == sortedCandidates);
                if (all[m] == CullMethod::Zb) CHECK(st.queries() == 0);
                CHECK(device.image() == ref);
            }
        }
    }
}

TEST_CASE("queryMinCandidates: a small candidate set is drawn with VFC, no queries, the same image", "[chc]") {
    const ChcScene s = randomChcScene(77);
    FakeQueryDevice device(64, 48, 0.01, 1);
    ObjectBvh bvh;
    load(s, device, bvh);
    const std::vector<ObjectId> few(s.ids.begin(), s.ids.begin() + std::min<std::size_t>(s.ids.size(), 5));
    REQUIRE(few.size() == 5);
    for (CullMethod m : kQueryMethods) {
        INFO(cullMethodName(m));
        ChcRenderer skipping(device, bvh, ChcOptions{.queryMinCandidates = 5});
        ChcRenderer querying(device, bvh, ChcOptions{.queryMinCandidates = 4});
        const Camera3 cam = walkCamera(s.camera, s.step, 0);
        const IdDepthImage ref = device.referenceImage(cam, few);
        const ChcFrameStats& a = skipping.render(cam, m, few);
        CHECK(a.queriesSkipped);
        CHECK(a.queries() == 0);
        CHECK(device.image() == ref);
        const ChcFrameStats& b = querying.render(cam, m, few);
        CHECK_FALSE(b.queriesSkipped);
        CHECK(device.image() == ref);
        // Every object is a candidate with renderAll: never skipped.
        CHECK_FALSE(skipping.renderAll(cam, m).queriesSkipped);
    }
}

TEST_CASE("n_vp > 0 is flagged approximate, ZB and VFC never are", "[chc]") {
    const ChcScene s = boxCity(4, 6, 100);
    FakeQueryDevice device;
    ObjectBvh bvh;
    load(s, device, bvh);
    ChcOptions approx;
    approx.visiblePixelThreshold = 5;
    ChcRenderer a(device, bvh, approx), exact(device, bvh);
    for (CullMethod m : kQueryMethods) {
        CHECK(a.renderAll(s.camera, m).approximate);
        CHECK_FALSE(exact.renderAll(s.camera, m).approximate);
    }
    // Approximate culls more: over a walk, n_vp = 5 draws no more than n_vp = 0.
    ChcRenderer a2(device, bvh, approx), exact2(device, bvh);
    std::uint64_t drawnApprox = 0, drawnExact = 0;
    for (int f = 0; f < 20; ++f) {
        const Camera3 cam = walkCamera(s.camera, s.step, f, 0.1);
        drawnApprox += a2.renderAll(cam, CullMethod::Chc).objectsDrawn;
        drawnExact += exact2.renderAll(cam, CullMethod::Chc).objectsDrawn;
    }
    CHECK(drawnApprox <= drawnExact);
    CHECK_FALSE(a.renderAll(s.camera, CullMethod::Zb).approximate);
    CHECK_FALSE(a.renderAll(s.camera, CullMethod::Vfc).approximate);
    CHECK(std::string(cullMethodName(CullMethod::ChcPlusPlus)) == "chcpp");
}

TEST_CASE("t_av: assumed-visible leaves are not queried, and CHC++'s first interval is randomized", "[chc]") {
    const ChcScene s = boxCity(5, 8, 200);
    FakeQueryDevice device(64, 48, 0.01, 0);
    ObjectBvh bvh;
    load(s, device, bvh);
    ChcOptions tav;
    tav.assumedVisibleFrames = 5;
    ChcRenderer plain(device, bvh), withTav(device, bvh, tav), plus(device, bvh, tav);
    const Camera3 cam = walkCamera(s.camera, s.step, 10, 0.1);
    std::uint64_t q0 = 0, q1 = 0;
    int chcAllQueried = 0, plusAllQueried = 0; // frames in which no visible leaf was assumed visible
    for (int f = 0; f < 25; ++f) {
        q0 += plain.renderAll(cam, CullMethod::Chc).queries();
        const ChcFrameStats& st = withTav.renderAll(cam, CullMethod::Chc);
        q1 += st.queries();
        const std::uint32_t plusAssumed = plus.renderAll(cam, CullMethod::ChcPlusPlus).nodesAssumedVisible;
        if (f >= 2 && st.nodesAssumedVisible == 0) ++chcAllQueried;
        if (f >= 2 && plusAssumed == 0) ++plusAllQueried;
        REQUIRE(device.image() == device.referenceImage(cam, s.ids)); // t_av only draws more
    }
    CHECK(q1 < q0);
    // CHC: the leaves found visible together are due together: every t_av-th frame queries them all.
    // CHC++: their first intervals are drawn from [1, t_av], so their queries spread over the frames.
    CHECK(chcAllQueried >= 4);
    CHECK(plusAllQueried == 0);
}

TEST_CASE("CHC++: multiqueries cut the queries, tight bounds send more, smaller boxes, runs are deterministic", "[chc]") {
    const ChcScene s = boxCity(1);
    struct Totals {
        std::uint64_t queries = 0, multi = 0, inMulti = 0, boxes = 0, drawn = 0;
        std::vector<ObjectId> lastDrawn;
    };
    auto run = [&](const ChcOptions& o) {
        FakeQueryDevice device(64, 48, 0.01, 4);
        ObjectBvh bvh;
        load(s, device, bvh);
        ChcRenderer r(device, bvh, o);
        Totals t;
        for (int f = 0; f < 40; ++f) {
            const ChcFrameStats& st = r.renderAll(walkCamera(s.camera, s.step, f, 0.1), CullMethod::ChcPlusPlus);
            t.queries += st.queries();
            t.multi += st.multiQueries;
            t.inMulti += st.nodesInMultiQueries;
            t.boxes += st.queryBoxes;
            t.drawn += st.objectsDrawn;
            t.lastDrawn = st.drawn;
        }
        return t;
    };
    ChcOptions all, noMulti, plain;
    noMulti.multiqueries = false;
    plain.multiqueries = false;
    plain.tightBounds = false;
    const Totals a = run(all), b = run(noMulti), c = run(plain), again = run(all);
    INFO("queries " << a.queries << " / " << b.queries << " / " << c.queries << ", boxes " << a.boxes << " / "
                    << b.boxes << " / " << c.boxes << ", drawn " << a.drawn << " / " << b.drawn << " / " << c.drawn);
    CHECK(a.multi > 0);
    CHECK(a.inMulti >= 2 * a.multi);
    CHECK(a.queries < b.queries);
    CHECK(b.multi == 0);
    CHECK(b.boxes > b.queries); // tight bounds: several boxes per query where cheaper
    CHECK(c.boxes == c.queries);
    CHECK(again.queries == a.queries); // the seeded randomization and everything else are deterministic
    CHECK(again.drawn == a.drawn);
    CHECK(again.lastDrawn == a.lastDrawn);
}

TEST_CASE("ChcRenderer: bad input is rejected with InvalidInput before the device sees the frame", "[chc]") {
    const ChcScene s = boxCity(6, 4, 20);
    FakeQueryDevice device;
    ObjectBvh bvh;
    load(s, device, bvh);
    ChcRenderer r(device, bvh);
    const std::vector<ObjectId> unknown = {1, 2, 999999};
    try {
        r.render(s.camera, CullMethod::Chc, unknown);
        FAIL("no throw");
    } catch (const InvalidInput& e) {
        CHECK(e.field() == "candidates[2]");
    }
    Camera3 bad = s.camera;
    bad.direction = Vec3(0.0);
    CHECK_THROWS_AS(r.renderAll(bad, CullMethod::Chc), InvalidInput);
    bad = s.camera;
    bad.position.x = std::numeric_limits<double>::quiet_NaN();
    CHECK_THROWS_AS(r.renderAll(bad, CullMethod::ChcPlusPlus), InvalidInput);
    bad = s.camera;
    bad.up = bad.direction;
    CHECK_THROWS_AS(r.renderAll(bad, CullMethod::StopAndWait), InvalidInput);
    CHECK(device.drawCalls() == 0);
    CHECK(device.queriesIssued() == 0);
    CHECK(r.lastStats().frame == 0);
    ChcOptions o;
    o.nearDistance = 0;
    CHECK_THROWS_AS(ChcRenderer(device, bvh, o), InvalidInput);
    o = {};
    o.batchSize = 0;
    CHECK_THROWS_AS(ChcRenderer(device, bvh, o), InvalidInput);
    o = {};
    o.tightBoundsRatio = std::numeric_limits<double>::infinity();
    CHECK_THROWS_AS(ChcRenderer(device, bvh, o), InvalidInput);
    // An empty hierarchy renders empty frames.
    ObjectBvh empty;
    ChcRenderer e(device, empty);
    CHECK(e.renderAll(s.camera, CullMethod::ChcPlusPlus).drawn.empty());
    CHECK(e.render(s.camera, CullMethod::Zb, {}).drawn.empty());
}
