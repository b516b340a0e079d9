// DenseStorage: the I lists against a multiset model, O counts and stamps. (T lives in TbvMatrix.hpp;
// test_tbv.cpp covers it.)
#include <catch2/catch.hpp>

#include "rgvc/grid/VoxelStorage.hpp"

#include <map>
#include <random>
#include <set>

using namespace rgvc;

namespace {
using Model = std::map<VoxelKey, std::multiset<ObjectSlot>>;

template <class ForEach> std::multiset<ObjectSlot> collect(ForEach&& forEach) {
    std::multiset<ObjectSlot> out;
    forEach([&](ObjectSlot o) { out.insert(o); });
    return out;
}
} // namespace

TEST_CASE("storage: I lists match a multiset model over random adds and removes", "[storage]") {
    const std::uint64_t seed = 77;
    INFO("seed " << seed);
    std::mt19937_64 rng(seed);
    const GridGeometry2 grid({0, 0}, 1.0, {16, 16});
    DenseStorage<2> s(grid);
    Model ids;
    std::uniform_int_distribution<VoxelKey> key(0, 255);
    std::uniform_int_distribution<ObjectSlot> slot(0, 20);
    std::uniform_int_distribution<int> op(0, 1);
    for (int step = 0; step < 20000; ++step) {
        const VoxelKey k = key(rng);
        const ObjectSlot o = slot(rng);
        if (op(rng) == 0) {
            s.addId(k, o);
            ids[k].insert(o);
        } else if (auto it = ids[k].find(o); it != ids[k].end()) {
            s.removeId(k, o);
            ids[k].erase(it);
        }
    }
    std::size_t idTotal = 0;
    for (VoxelKey k = 0; k < 256; ++k) {
        CHECK(collect([&](auto fn) { s.forEachId(k, fn); }) == ids[k]);
        CHECK(s.hasIds(k) == !ids[k].empty());
        idTotal += ids[k].size();
    }
    CHECK(s.idCount() == idTotal);
}

TEST_CASE("storage: O counts overlapping objects, stamps clear in O(1) and reset on wrap", "[storage]") {
    DenseStorage<2> s(GridGeometry2({0, 0}, 1.0, {4, 4}));
    s.addOpaque(3, +1);
    s.addOpaque(3, +1);
    s.addOpaque(3, -1);
    CHECK(s.opaque(3)); // one of two overlapping objects left
    s.addOpaque(3, -1);
    CHECK_FALSE(s.opaque(3));
    s.setOccluded(2, 7);
    CHECK(s.occluded(2, 7));
    CHECK_FALSE(s.occluded(2, 8)); // the next frame's H is empty without touching memory
    s.setVisited(2, 7);
    s.setUsed(2, 7);
    s.resetStamps();
    CHECK_FALSE(s.occluded(2, 7));
    CHECK_FALSE(s.visited(2, 7));
    CHECK_FALSE(s.used(2, 7));
}

TEST_CASE("storage: O flags, I lists and stamps share a cell without disturbing each other", "[storage]") {
    // The cell packs O's flag into the I list head's top bit: interleave every kind of write on the same
    // voxels and compare each matrix with its own model after every step.
    const std::uint64_t seed = 78;
    INFO("seed " << seed);
    std::mt19937_64 rng(seed);
    const GridGeometry3 grid({0, 0, 0}, 1.0, {4, 4, 4});
    DenseStorage<3> s(grid);
    Model ids;
    std::map<VoxelKey, int> opaque;
    std::map<VoxelKey, std::uint32_t> occludedAt, visitedAt;
    std::uniform_int_distribution<VoxelKey> key(0, 63);
    std::uniform_int_distribution<ObjectSlot> slot(0, 9);
    std::uniform_int_distribution<int> op(0, 5);
    std::uint32_t stamp = 1;
    for (int step = 0; step < 20000; ++step) {
        const VoxelKey k = key(rng);
        const ObjectSlot o = slot(rng);
        switch (op(rng)) {
        case 0: s.addId(k, o), ids[k].insert(o); break;
        case 1:
            if (auto it = ids[k].find(o); it != ids[k].end()) s.removeId(k, o), ids[k].erase(it);
            break;
        case 2: s.addOpaque(k, +1), ++opaque[k]; break;
        case 3:
            if (opaque[k] > 0) s.addOpaque(k, -1), --opaque[k];
            break;
        case 4: s.setOccluded(k, stamp), occludedAt[k] = stamp, s.setVisited(k, stamp), visitedAt[k] = stamp; break;
        default: // the next frame (1..kMaxStamp), now and then straight to the last stamp before the wrap
            stamp = rng() % 40 == 0 ? DenseStorage<3>::kMaxStamp : stamp % DenseStorage<3>::kMaxStamp + 1;
        }
        if (stamp == 1) { // passed kMaxStamp: the culler clears every stamp
            s.resetStamps();
            occludedAt.clear();
            visitedAt.clear();
        }
        CHECK(s.opaque(k) == (opaque[k] > 0));
        CHECK(s.hasIds(k) == !ids[k].empty());
        CHECK(collect([&](auto fn) { s.forEachId(k, fn); }) == ids[k]);
        CHECK(s.occluded(k, stamp) == (occludedAt.count(k) && occludedAt[k] == stamp));
        CHECK(s.visited(k, stamp) == (visitedAt.count(k) && visitedAt[k] == stamp));
    }
}
