// ObjectBvh, the GL stage's persistent hierarchy: a build bounds every object exactly; refits keep every
// node's id, stamp, links and leaves; inserts and removes keep the other nodes'; a degraded tree is rebuilt;
// bad input throws InvalidInput and changes nothing. The structure is checked against recomputation
// (checkBvh in ChcTestSupport.hpp).
#include "ChcTestSupport.hpp"

#include <catch2/catch.hpp>

#include <limits>
#include <random>
#include <vector>

using namespace rgvc;
using namespace rgvc::testing;

TEST_CASE("ObjectBvh: a build bounds every object exactly, leaves hold at most maxLeafObjects", "[chc][bvh]") {
    for (std::uint64_t seed : {1u, 2u, 3u}) {
        std::mt19937_64 rng(seed);
        std::vector<BvhItem> items;
        const int n = seed == 1 ? 1 : (seed == 2 ? 37 : 500);
        for (int i = 0; i < n; ++i) items.push_back({ObjectId(i) * 3 + 11, randomBox(rng, 100)});
        if (seed == 3) // coincident centroids: the median split must still terminate
            for (int i = 0; i < 50; ++i) items.push_back({ObjectId(10000 + i), Box<3>{Vec3(5.0), Vec3(6.0)}});
        ObjectBvh bvh;
        bvh.build(items);
        INFO("seed " << seed);
        CHECK(checkBvh(bvh).empty());
        CHECK(bvh.objectCount() == items.size());
        CHECK(bvh.degradation() == Approx(1.0));
        for (BvhNodeId id = 0; id < bvh.nodeCapacity(); ++id)
            if (bvh.node(id).isLeaf()) CHECK(bvh.node(id).objects.size() <= 4u);
        for (const BvhItem& it : items) CHECK(bvh.contains(it.id));
    }
    // From a scene's objects: boundsOf their shapes.
    std::vector<ObjectDesc<3>> objects(2);
    objects[0].id = 5;
    objects[0].shape = Ball<3>{Vec3{1, 2, 3}, 0.5};
    objects[1].id = 6;
    objects[1].shape = Box<3>{Vec3{0, 0, 0}, Vec3{1, 1, 1}};
    ObjectBvh fromObjects;
    fromObjects.build(bvhItems(std::span<const ObjectDesc<3>>(objects)));
    CHECK(fromObjects.objectBounds(fromObjects.slotOf(5)).min == Vec3{0.5, 1.5, 2.5});
    CHECK(checkBvh(fromObjects).empty());
    ObjectBvh empty;
    empty.build({});
    CHECK(empty.root() == kNoBvhNode);
    CHECK(checkBvh(empty).empty());
}

TEST_CASE("ObjectBvh: refit keeps node ids and contains moved objects, insert and remove keep other ids", "[chc][bvh]") {
    std::mt19937_64 rng(77);
    std::vector<BvhItem> items;
    for (int i = 0; i < 300; ++i) items.push_back({ObjectId(i + 1), randomBox(rng, 50)});
    ObjectBvh bvh;
    bvh.build(items);
    const std::vector<NodeShape> before = shapeOf(bvh);
    // Moves, small and large: refit only.
    for (int round = 0; round < 20; ++round) {
        for (int k = 0; k < 40; ++k) {
            const ObjectId id = ObjectId(rng() % 300 + 1);
            const Vec3 t{reference::seeded::uniform(rng, -3, 3), reference::seeded::uniform(rng, -3, 3),
                         reference::seeded::uniform(rng, -3, 3)};
            Box<3> b = bvh.objectBounds(bvh.slotOf(id));
            bvh.update(id, Box<3>{b.min + t, b.max + t});
        }
        REQUIRE(checkBvh(bvh).empty());
    }
    CHECK(shapeOf(bvh) == before); // same ids, stamps, links and leaves: only boxes changed
    // Removes: two nodes go (the leaf and its parent) when a leaf empties; every other node stays.
    for (int k = 0; k < 120; ++k) {
        const std::vector<NodeShape> pre = shapeOf(bvh);
        const ObjectId id = ObjectId(k * 2 + 1);
        bvh.remove(id);
        REQUIRE(checkBvh(bvh).empty());
        CHECK_FALSE(bvh.contains(id));
        const std::vector<NodeShape> post = shapeOf(bvh);
        for (std::size_t i = 0; i < pre.size(); ++i)
            if (post[i].stamp != 0 && pre[i].stamp != 0) CHECK(post[i].stamp == pre[i].stamp);
    }
    // Inserts: only a split leaf changes its stamp; new nodes get new stamps.
    for (int k = 0; k < 200; ++k) {
        const std::vector<NodeShape> pre = shapeOf(bvh);
        bvh.insert(ObjectId(1000 + k), randomBox(rng, 50));
        REQUIRE(checkBvh(bvh).empty());
        const std::vector<NodeShape> post = shapeOf(bvh);
        int changed = 0;
        for (std::size_t i = 0; i < pre.size(); ++i)
            if (pre[i].stamp != 0 && post[i].stamp != pre[i].stamp) ++changed;
        CHECK(changed <= 1);
    }
    CHECK(bvh.objectCount() == 300 - 120 + 200);
}

TEST_CASE("ObjectBvh: refitted far apart, the tree degrades past the ratio and is rebuilt", "[chc][bvh]") {
    std::mt19937_64 rng(5);
    std::vector<BvhItem> items;
    for (int i = 0; i < 400; ++i) items.push_back({ObjectId(i), randomBox(rng, 40)});
    ObjectBvh bvh;
    bvh.build(items);
    CHECK_FALSE(bvh.rebuildIfDegraded());
    for (int i = 0; i < 400; ++i) bvh.update(ObjectId(i), randomBox(rng, 40)); // a shuffle: boxes far from their leaves
    CHECK(checkBvh(bvh).empty());
    CHECK(bvh.degradation() > 2.0);
    CHECK(bvh.rebuildIfDegraded());
    CHECK(bvh.buildCount() == 2);
    CHECK(bvh.degradation() == Approx(1.0));
    CHECK(checkBvh(bvh).empty());
}

TEST_CASE("ObjectBvh: bad input is rejected with InvalidInput and changes nothing", "[chc][bvh]") {
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    ObjectBvh bvh;
    bvh.build(std::vector<BvhItem>{{1, Box<3>{Vec3(0.0), Vec3(1.0)}}, {2, Box<3>{Vec3(2.0), Vec3(3.0)}}});
    const std::vector<NodeShape> before = shapeOf(bvh);
    CHECK_THROWS_AS(bvh.build(std::vector<BvhItem>{{1, Box<3>{Vec3(nan), Vec3(1.0)}}}), InvalidInput);
    CHECK_THROWS_AS(bvh.build(std::vector<BvhItem>{{1, Box<3>{Vec3(0.0), Vec3(inf)}}}), InvalidInput);
    CHECK_THROWS_AS(bvh.build(std::vector<BvhItem>{{1, Box<3>{Vec3(1.0), Vec3(0.0)}}}), InvalidInput);
    CHECK_THROWS_AS(bvh.build(std::vector<BvhItem>{{7, Box<3>{Vec3(0.0), Vec3(1.0)}}, {7, Box<3>{Vec3(0.0), Vec3(1.0)}}}),
                    InvalidInput);
    CHECK_THROWS_AS(bvh.insert(1, Box<3>{Vec3(0.0), Vec3(1.0)}), InvalidInput);
    CHECK_THROWS_AS(bvh.insert(3, Box<3>{Vec3(0.0), Vec3(nan)}), InvalidInput);
    CHECK_THROWS_AS(bvh.update(9, Box<3>{Vec3(0.0), Vec3(1.0)}), InvalidInput);
    CHECK_THROWS_AS(bvh.update(1, Box<3>{Vec3(-inf), Vec3(1.0)}), InvalidInput);
    CHECK_THROWS_AS(bvh.remove(9), InvalidInput);
    CHECK(shapeOf(bvh) == before);
    CHECK(bvh.objectCount() == 2);
    CHECK_THROWS_AS(ObjectBvh(BvhOptions{0, 2.0}), InvalidInput);
    CHECK_THROWS_AS(ObjectBvh(BvhOptions{4, 1.0}), InvalidInput);
    try {
        bvh.update(1, Box<3>{Vec3(0.0), Vec3(nan)});
        FAIL("no throw");
    } catch (const InvalidInput& e) {
        CHECK(e.field() == "bounds");
    }
}
