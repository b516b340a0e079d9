// DenseStorage: the I lists against a multiset model, O counts and stamps, and the brick-row words (O's
// flags, V, U) against per-voxel models. (T lives in TbvMatrix.hpp;
// test_tbv.cpp covers it.)
#include <catch2/catch.hpp>

#include "rgvc/grid/BrickRows.hpp"
#include "rgvc/grid/StampedBrickBits.hpp"
#include "rgvc/grid/VoxelStorage.hpp"

#include <map>
#include <random>
#include <set>
#include <utility>

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

TEST_CASE("storage: brick-row words of O, and U's and V's bricks, agree with the voxels, and the row helpers with a voxel-by-voxel scan",
          "[storage]") {
    // Widths a multiple of 8 and not (the last word of a row is partial, or the next word is the next row's).
    for (const std::int32_t resX : {8, 13, 24, 37}) {
        const std::uint64_t seed = 79 + std::uint64_t(resX);
        INFO("seed " << seed << ", res.x " << resX);
        std::mt19937_64 rng(seed);
        const GridGeometry3 grid({0, 0, 0}, 1.0, {resX, 5, 3});
        DenseStorage<3> s(grid);
        const std::uint32_t rows = 5 * 3;
        std::vector<int> opaque(grid.voxelCount(), 0);
        std::vector<std::uint32_t> usedAt(grid.voxelCount(), 0), visitedAt(grid.voxelCount(), 0);
        std::uint32_t stamp = 1;
        for (int step = 0; step < 4000; ++step) {
            const std::uint32_t row = std::uint32_t(rng() % rows);
            const std::int32_t x0 = std::int32_t(rng() % std::uint64_t(resX));
            const std::int32_t x1 = x0 + std::int32_t(rng() % std::uint64_t(resX - x0));
            const VoxelKey k0 = row * std::uint32_t(resX);
            switch (rng() % 6) {
            case 0: // a run made opaque (the walls the fusion grows along)
                for (std::int32_t x = x0; x <= x1; ++x) s.addOpaque(k0 + std::uint32_t(x), +1), ++opaque[k0 + std::uint32_t(x)];
                break;
            case 1:
                for (std::int32_t x = x0; x <= x1; ++x)
                    if (opaque[k0 + std::uint32_t(x)] > 0) s.addOpaque(k0 + std::uint32_t(x), -1), --opaque[k0 + std::uint32_t(x)];
                break;
            case 2: { // a fused box marked used: x0..x1 of rows y..y1 and slices z..z1 (its bricks at once)
                const std::int32_t y = std::int32_t(row % 5), z = std::int32_t(row / 5);
                const std::int32_t y1 = y + std::int32_t(rng() % std::uint64_t(5 - y)), z1 = z + std::int32_t(rng() % std::uint64_t(3 - z));
                s.markUsedBox(IVec3{x0, y, z}, IVec3{x1, y1, z1}, stamp);
                for (std::int32_t bz = z; bz <= z1; ++bz)
                    for (std::int32_t by = y; by <= y1; ++by)
                        for (std::int32_t x = x0; x <= x1; ++x) usedAt[grid.linearIndex(IVec3{x, by, bz})] = stamp;
                break;
            }
            case 3: { // V by bricks (the walks) and by voxels (the per-voxel traversals)
                const std::int32_t y = std::int32_t(row % 5), z = std::int32_t(row / 5);
                const IVec3 brick{x0 >> 3, y >> 3, z >> 3};
                std::uint64_t words[8];
                for (std::uint64_t& w : words) w = rng() & rng(); // about a quarter of the bits
                s.setBrickVisited(brick, words, stamp);
                for (int bz = 0; bz < 8; ++bz)
                    for (int by = 0; by < 8; ++by)
                        for (int bx = 0; bx < 8; ++bx) {
                            const IVec3 v = brick * 8 + IVec3{bx, by, bz};
                            if (v.x < resX && v.y < 5 && v.z < 3 && ((words[bz] >> (bx + 8 * by)) & 1) != 0)
                                visitedAt[grid.linearIndex(v)] = stamp;
                        }
                s.setVisited(k0 + std::uint32_t(x1), stamp), visitedAt[k0 + std::uint32_t(x1)] = stamp;
                break;
            }
            case 4: s.setUsed(k0 + std::uint32_t(x1), stamp), usedAt[k0 + std::uint32_t(x1)] = stamp; break;
            default: stamp = stamp % DenseStorage<3>::kMaxStamp + 1;
            }
            // The words and the voxels.
            for (std::int32_t x = 0; x < resX; ++x) {
                const VoxelKey k = k0 + std::uint32_t(x);
                const std::uint32_t bit = 1u << (x & 7);
                CHECK(((s.opaqueBits(s.rowWord(row, x)) & bit) != 0) == (opaque[k] > 0));
                CHECK(s.used(k, stamp) == (usedAt[k] == stamp));
                CHECK(((s.usedBits(IVec3{x & ~7, std::int32_t(row % 5), std::int32_t(row / 5)}, stamp) & bit) != 0) == (usedAt[k] == stamp));
            }
            // V and U over the whole grid (a brick's or a box's write reaches other rows).
            for (VoxelKey k = 0; k < VoxelKey(grid.voxelCount()); ++k)
                if (s.visited(k, stamp) != (visitedAt[k] == stamp) || s.used(k, stamp) != (usedAt[k] == stamp)) {
                    INFO("step " << step << " voxel " << k << " visited " << s.visited(k, stamp) << " used " << s.used(k, stamp));
                    REQUIRE(false);
                }
            // The helpers against a scan.
            bool all = true;
            for (std::int32_t x = x0; x <= x1; ++x) all = all && opaque[k0 + std::uint32_t(x)] > 0;
            CHECK(brick_rows::allOpaque(s, row, x0, x1) == all);
            if (opaque[k0 + std::uint32_t(x0)] > 0) {
                for (const std::int32_t grow : {0, 3, 9, 64}) {
                    std::int32_t lo = x0, hi = x0;
                    while (hi + 1 < resX && hi - x0 < grow && opaque[k0 + std::uint32_t(hi + 1)] > 0) ++hi;
                    while (lo > 0 && x0 - lo < grow && opaque[k0 + std::uint32_t(lo - 1)] > 0) --lo;
                    std::int32_t rlo = -1, rhi = -1;
                    brick_rows::opaqueRun(s, row, resX, x0, grow, rlo, rhi);
                    INFO("row " << row << ", x " << x0 << ", grow " << grow);
                    CHECK(rlo == lo);
                    CHECK(rhi == hi);
                }
            }
        }
    }
}

TEST_CASE("storage: V's and U's bricks in 2D agree with the voxels, across stamps and a reset", "[storage]") {
    // Grids whose edges cut bricks (bits past the edge are ignored) and one brick wide or tall.
    for (const IVec2 res : {IVec2{8, 8}, IVec2{13, 21}, IVec2{1, 30}, IVec2{40, 3}}) {
        const std::uint64_t seed = 131 + std::uint64_t(res.x * 100 + res.y);
        INFO("seed " << seed << ", grid " << res.x << "x" << res.y);
        std::mt19937_64 rng(seed);
        const GridGeometry2 grid({0, 0}, 1.0, res);
        DenseStorage<2> s(grid);
        std::vector<std::uint32_t> visitedAt(grid.voxelCount(), 0), usedAt(grid.voxelCount(), 0);
        std::uint32_t stamp = 1;
        for (int step = 0; step < 3000; ++step) {
            const IVec2 brick{std::int32_t(rng() % std::uint64_t((res.x + 7) / 8)), std::int32_t(rng() % std::uint64_t((res.y + 7) / 8))};
            switch (rng() % 5) {
            case 4: { // U: a fused box marked used (any size, across bricks)
                IVec2 lo, hi;
                for (int a = 0; a < 2; ++a) {
                    lo[a] = std::int32_t(rng() % std::uint64_t(res[a]));
                    hi[a] = lo[a] + std::int32_t(rng() % std::uint64_t(res[a] - lo[a]));
                }
                s.markUsedBox(lo, hi, stamp);
                for (std::int32_t y = lo.y; y <= hi.y; ++y)
                    for (std::int32_t x = lo.x; x <= hi.x; ++x) usedAt[grid.linearIndex(IVec2{x, y})] = stamp;
                break;
            }
            case 0: {
                const std::uint64_t word = rng() & rng();
                s.setBrickVisited(brick, &word, stamp);
                for (int b = 0; b < 64; ++b) {
                    const IVec2 v = brick * 8 + IVec2{b & 7, b >> 3};
                    if (v.x < res.x && v.y < res.y && ((word >> b) & 1) != 0) visitedAt[grid.linearIndex(v)] = stamp;
                }
                break;
            }
            case 1: {
                const IVec2 v{std::int32_t(rng() % std::uint64_t(res.x)), std::int32_t(rng() % std::uint64_t(res.y))};
                s.setVisited(grid.linearIndex(v), stamp);
                visitedAt[grid.linearIndex(v)] = stamp;
                break;
            }
            case 2: stamp = stamp % DenseStorage<2>::kMaxStamp + 1; break;
            default:
                if (rng() % 50 == 0) { // the wrap: every stamp back to never
                    s.resetStamps();
                    std::fill(visitedAt.begin(), visitedAt.end(), 0);
                    std::fill(usedAt.begin(), usedAt.end(), 0);
                }
            }
            for (VoxelKey k = 0; k < VoxelKey(grid.voxelCount()); ++k) {
                INFO("step " << step << " voxel " << k);
                REQUIRE(s.visited(k, stamp) == (visitedAt[k] == stamp));
                REQUIRE(s.used(k, stamp) == (usedAt[k] == stamp));
                const std::int32_t x = std::int32_t(k % VoxelKey(res.x)), y = std::int32_t(k / VoxelKey(res.x));
                REQUIRE(((s.usedBits(IVec2{x & ~7, y}, stamp) >> (x & 7)) & 1u) == (usedAt[k] == stamp ? 1u : 0u));
            }
        }
    }
}

TEST_CASE("storage: V's bricks find the voxel of any key, up to grids of nearly 2^32 voxels", "[storage]") {
    // The key's coordinates come from multiplications (StampedBrickBits' fastDivide), exact for every
    // 32-bit key: checked at random keys, half of them a row's or a slice's first voxel (where a quotient
    // one too small shows), in grids whose keys reach past 2^31, against coordinates from divisions.
    // (Zero pages: only the bricks written cost memory.)
    std::mt19937_64 rng(151);
    for (const IVec3 res : {IVec3{1021, 1019, 4127 - 127}, IVec3{1, 65535, 65535}, IVec3{65535, 1, 3}, IVec3{3, 7, 11}}) {
        INFO("seed 151, grid " << res.x << "x" << res.y << "x" << res.z);
        StampedBrickBits<3> v(res);
        const std::uint64_t count = std::uint64_t(res.x) * std::uint64_t(res.y) * std::uint64_t(res.z);
        REQUIRE(count <= 0xFFFFFFFFull);
        for (int i = 0; i < 2000; ++i) {
            std::uint32_t k = i < 4 ? std::uint32_t(count - 1 - std::uint64_t(i) % count) : std::uint32_t(rng() % count);
            if (i % 4 == 1) k -= k % std::uint32_t(res.x);                               // a row's first voxel
            if (i % 4 == 3) k -= k % (std::uint32_t(res.x) * std::uint32_t(res.y)); // a slice's
            const std::uint32_t stamp = std::uint32_t(i % 7 + 1);
            v.setVoxel(k, stamp);
            CHECK(v.voxel(k, stamp));
            CHECK_FALSE(v.voxel(k, stamp % 7 + 1));
            // Its brick holds it at the bit the walks use: bit x + 8 y of slice z, relative to the brick.
            const std::uint32_t x = k % std::uint32_t(res.x), y = (k / std::uint32_t(res.x)) % std::uint32_t(res.y),
                                z = k / std::uint32_t(res.x) / std::uint32_t(res.y);
            std::uint64_t words[8] = {0, 0, 0, 0, 0, 0, 0, 0};
            words[z & 7] = std::uint64_t(1) << ((x & 7) + 8 * (y & 7));
            const std::uint32_t next = stamp % 7 + 1;
            v.orBrick(IVec3{std::int32_t(x >> 3), std::int32_t(y >> 3), std::int32_t(z >> 3)}, words, next);
            CHECK(v.voxel(k, next));
        }
    }
}

TEST_CASE("storage: ZeroedArray starts zero, copies, moves, clears and touches", "[storage]") {
    ZeroedArray<std::uint32_t> a(1000);
    REQUIRE(a.size() == 1000);
    for (std::uint32_t v : a) CHECK(v == 0);
    for (std::size_t i = 0; i < a.size(); ++i) a[i] = std::uint32_t(i * 7 + 1);
    ZeroedArray<std::uint32_t> b = a; // copy
    REQUIRE(b.size() == 1000);
    CHECK(b[999] == 999 * 7 + 1);
    b[0] = 42;
    CHECK(a[0] == 1); // a deep copy
    ZeroedArray<std::uint32_t> c = std::move(b);
    CHECK(c[0] == 42);
    CHECK(b.size() == 0); // NOLINT(bugprone-use-after-move): moved-from is empty by contract
    a.clear();
    REQUIRE(a.size() == 1000);
    for (std::uint32_t v : a) CHECK(v == 0);
    c.touch(); // zeros again, written
    for (std::uint32_t v : c) CHECK(v == 0);
    c.adviseHugePages(); // a hint: contents unchanged
    c[3] = 9;
    c.clear();
    CHECK(c[3] == 0);
    ZeroedArray<std::uint8_t> empty(0);
    CHECK(empty.size() == 0);
    CHECK(empty.begin() == empty.end());
}

TEST_CASE("storage: a fresh dense storage reads empty everywhere, whatever it was told about its pages", "[storage]") {
    // The cells hold the I head XOR'ed so that all-zero memory reads as no id, not opaque, never
    // occluded, not visited, not used: the encoding the untouched pages rely on.
    const GridGeometry3 grid({0, 0, 0}, 1.0, {24, 16, 40});
    for (int mode = 0; mode < 3; ++mode) {
        INFO("mode " << mode);
        DenseStorage<3> s(grid);
        if (mode == 1) s.adviseWholeGridReads();
        if (mode == 2) s.touchWalkedArrays(true);
        std::size_t bad = 0;
        for (VoxelKey k = 0; k < VoxelKey(grid.voxelCount()); ++k)
            bad += s.hasIds(k) || s.opaque(k) || s.occluded(k, 1) || s.visited(k, 1) || s.used(k, 1);
        CHECK(bad == 0);
        s.addId(5, 3);
        s.addOpaque(5, +1);
        CHECK(s.hasIds(5));
        CHECK(s.opaque(5));
        s.addOpaque(5, -1);
        s.removeId(5, 3);
        CHECK_FALSE(s.hasIds(5));
        CHECK_FALSE(s.opaque(5));
    }
}

#if defined(__linux__) && !defined(__SANITIZE_ADDRESS__)
#include <fstream>
namespace {
/// Resident memory of this process [bytes] (Linux: /proc/self/statm's second field, in pages).
std::size_t residentBytes() {
    std::ifstream f("/proc/self/statm");
    std::size_t size = 0, resident = 0;
    f >> size >> resident;
    return resident * 4096;
}
} // namespace

TEST_CASE("storage: a large grid costs memory where it is written, not its volume", "[storage]") {
    // 512 x 256 x 512 voxels: 870 MB as dense arrays written at construction. The brick walks' storage
    // writes O's flags, V and U (7 bits a voxel, 59 MB) and leaves the cells and O's counts to the pages
    // objects write. (Not under AddressSanitizer, whose shadow memory is resident memory too.)
    const GridGeometry3 grid({0, 0, 0}, 1.0, {512, 256, 512});
    const std::size_t before = residentBytes();
    DenseStorage<3> s(grid);
    s.touchWalkedArrays(false);
    for (VoxelKey k = 0; k < 4096; ++k) s.addOpaque(k * 997, +1); // a few scattered objects' voxels
    const std::size_t grown = residentBytes() - std::min(before, residentBytes());
    INFO("resident growth " << grown / 1000000 << " MB");
    CHECK(grown < 200u * 1000 * 1000);
    CHECK(grown > 50u * 1000 * 1000); // the walked arrays are written
}
#endif
