// TbvMatrix (T) against brute force: thousands of random TBV regions, 2D discs and 3D cubes, both
// discretizations, clipped by the grid, several at once.
//
// The discretization is where a TBV either works or silently loses its object, so each voxel is
// classified independently of TbvMatrix.hpp (distances from the centre to the closed square/cube,
// computed here) as "must hold the slot", "may hold it" (within a few kConservativeSlack of the
// decision, where rounding may go either way) or "must not". Then the property that makes the ring
// enough (TbvMatrix.hpp, "Why the boundary suffices") is checked directly: a segment from a camera
// outside the region to any point inside it crosses a voxel holding the slot before it gets there.
// Every failure prints the seed and the region.
#include "SeededRandom.hpp"

#include "rgvc/grid/TbvMatrix.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

using namespace rgvc;
namespace sr = rgvc::reference::seeded;

namespace {

enum class Expect { Must, May, MustNot };

// Width of the "may" band around a decision: the header's slack on each side plus rounding.
constexpr double kBand = 4 * kConservativeSlack;

std::string describe(const TbvRegion<2>& r) {
    std::ostringstream os;
    os.precision(17);
    os << "disc centre (" << r.centre.x << ", " << r.centre.y << ") radius " << r.radius;
    return os.str();
}
std::string describe(const TbvRegion<3>& r) {
    std::ostringstream os;
    os.precision(17);
    os << "cube centre (" << r.centre.x << ", " << r.centre.y << ", " << r.centre.z << ") half-side " << r.radius;
    return os.str();
}

// Nearest and farthest distance from c to the closed unit square of voxel v (Euclidean), computed
// without TbvMatrix.hpp's helpers.
void squareDistances(const Vec2& c, const IVec2& v, double& nearest, double& farthest) {
    const double nx = std::clamp(c.x, double(v.x), double(v.x) + 1), ny = std::clamp(c.y, double(v.y), double(v.y) + 1);
    nearest = std::hypot(c.x - nx, c.y - ny);
    const double fx = std::max(std::abs(c.x - v.x), std::abs(c.x - (v.x + 1.0)));
    const double fy = std::max(std::abs(c.y - v.y), std::abs(c.y - (v.y + 1.0)));
    farthest = std::hypot(fx, fy);
}

// The circle touches the closed square iff nearest <= r <= farthest; the disc iff nearest <= r.
Expect expect2D(const TbvRegion<2>& r, const IVec2& v, TbvDiscretization mode) {
    double nearest, farthest;
    squareDistances(r.centre, v, nearest, farthest);
    const double tol = kBand + 1e-13 * (std::abs(r.centre.x) + std::abs(r.centre.y) + r.radius);
    if (nearest > r.radius + tol) return Expect::MustNot;
    if (mode == TbvDiscretization::Boundary && farthest < r.radius - tol) return Expect::MustNot;
    const bool sure = nearest <= r.radius && (mode == TbvDiscretization::Filled || farthest >= r.radius);
    return sure ? Expect::Must : Expect::May;
}

// Per axis, the voxel indices whose closed interval lies within Chebyshev distance r of c: [lo, hi],
// the tight range (distance <= r) and the loose one (<= r + band), clipped to [0, res).
void axisRange(double c, double r, std::int32_t res, double tol, std::int32_t& lo, std::int32_t& hi) {
    lo = res;
    hi = -1;
    for (std::int32_t i = 0; i < res; ++i) {
        const double gap = std::max({double(i) - c, c - double(i + 1), 0.0});
        if (gap <= r + tol) {
            lo = std::min(lo, i);
            hi = std::max(hi, i);
        }
    }
}

TbvRegion<2> randomDisc(std::mt19937_64& rng, const IVec2& res) {
    TbvRegion<2> r;
    // Centres up to 20% beyond the grid: clipped regions. A third snapped to voxel corners or centres
    // with integer or half-integer radii: circles through voxel corners and along voxel edges.
    r.centre = {sr::uniform(rng, -0.2 * res.x, 1.2 * res.x), sr::uniform(rng, -0.2 * res.y, 1.2 * res.y)};
    r.radius = sr::logUniform(rng, 0.01, 0.6 * std::max(res.x, res.y));
    if (sr::chance(rng, 0.35)) {
        r.centre = glm::round(r.centre) + (sr::chance(rng, 0.5) ? 0.5 : 0.0);
        r.radius = 0.5 * std::round(2 * r.radius);
    }
    return r;
}

TbvRegion<3> randomCube(std::mt19937_64& rng, const IVec3& res) {
    TbvRegion<3> r;
    for (int a = 0; a < 3; ++a) r.centre[a] = sr::uniform(rng, -0.2 * res[a], 1.2 * res[a]);
    r.radius = sr::logUniform(rng, 0.01, 0.6 * std::max({res.x, res.y, res.z}));
    if (sr::chance(rng, 0.35)) {
        r.centre = glm::round(r.centre) + (sr::chance(rng, 0.5) ? 0.5 : 0.0);
        r.radius = 0.5 * std::round(2 * r.radius);
    }
    return r;
}

std::size_t countOf(const std::vector<ObjectSlot>& v, ObjectSlot s) { return std::size_t(std::count(v.begin(), v.end(), s)); }

// Checks every in-grid voxel of a 2D T holding `regions` (slot i+offset of each) against expect2D.
// Returns false on the first bad voxel (after a CHECK that prints it).
// First holdsAt alone on every voxel (read-only: a tile no lookup has needed yet answers from its list),
// then collectAt (which writes the counts of the tiles it reads), holdsAt again and the filters.
bool check2D(TbvMatrix<2>& t, const IVec2& res, const std::vector<TbvRegion<2>>& regions,
             const std::vector<ObjectSlot>& slots, const std::vector<bool>& live, TbvDiscretization mode) {
    std::vector<char> heldBefore(std::size_t(res.x) * std::size_t(res.y));
    for (std::int32_t y = 0; y < res.y; ++y)
        for (std::int32_t x = 0; x < res.x; ++x) {
            const bool held = heldBefore[std::size_t(y) * std::size_t(res.x) + std::size_t(x)] = t.holdsAt({x, y});
            for (std::size_t i = 0; i < regions.size(); ++i) {
                const Expect e = live[i] ? expect2D(regions[i], {x, y}, mode) : Expect::MustNot;
                if (e == Expect::Must && !held) {
                    INFO("voxel (" << x << ", " << y << ") read-only holdsAt misses slot " << slots[i] << "; " << describe(regions[i]));
                    CHECK(held);
                    return false;
                }
            }
        }
    std::vector<ObjectSlot> got;
    for (std::int32_t y = 0; y < res.y; ++y)
        for (std::int32_t x = 0; x < res.x; ++x) {
            got.clear();
            t.collectAt({x, y}, got);
            bool anyMust = false;
            for (std::size_t i = 0; i < regions.size(); ++i) {
                const std::size_t n = countOf(got, slots[i]);
                const Expect e = live[i] ? expect2D(regions[i], {x, y}, mode) : Expect::MustNot;
                anyMust = anyMust || (e == Expect::Must);
                const bool ok = n <= 1 && (e != Expect::Must || n == 1) && (e != Expect::MustNot || n == 0);
                if (!ok) {
                    INFO("voxel (" << x << ", " << y << ") slot " << slots[i] << " held " << n << " times; expected "
                                   << (e == Expect::Must ? "must" : e == Expect::May ? "may" : "must not") << "; "
                                   << describe(regions[i]) << (live[i] ? "" : " (erased)"));
                    CHECK(ok);
                    return false;
                }
            }
            // Nothing but the live slots: no stray or stale ids.
            for (ObjectSlot s : got) {
                const bool known = std::find(slots.begin(), slots.end(), s) != slots.end();
                if (!known) {
                    INFO("voxel (" << x << ", " << y << ") holds unknown slot " << s);
                    CHECK(known);
                    return false;
                }
            }
            if (t.holdsAt({x, y}) != !got.empty() || (anyMust && got.empty()) ||
                (heldBefore[std::size_t(y) * std::size_t(res.x) + std::size_t(x)] != 0) != !got.empty()) {
                INFO("voxel (" << x << ", " << y << ") holdsAt disagrees with collectAt");
                CHECK(false);
                return false;
            }
            // The filters: mayHoldAt false only where nothing is held, and mayHoldRow (a tile row's
            // counts in one read) the same answer bit by bit.
            const bool may = t.mayHoldAt({x, y});
            const bool rowBit = ((t.mayHoldRow({x >> 3, y >> 3}, y & 7) >> (x & 7)) & 1) != 0;
            if (may != rowBit || (!got.empty() && !may)) {
                INFO("voxel (" << x << ", " << y << ") mayHoldAt " << may << ", mayHoldRow's bit " << rowBit << ", held by "
                               << got.size());
                CHECK(false);
                return false;
            }
        }
    // Past the grid's edge, in its last tiles: nothing.
    for (std::int32_t y = 0; y < ((res.y + 7) & ~7); ++y)
        for (std::int32_t x = (y < res.y ? res.x : 0); x < ((res.x + 7) & ~7); ++x)
            if (((t.mayHoldRow({x >> 3, y >> 3}, y & 7) >> (x & 7)) & 1) != 0) {
                INFO("voxel (" << x << ", " << y << ") outside the " << res.x << "x" << res.y << " grid may hold a TBV");
                CHECK(false);
                return false;
            }
    return true;
}

} // namespace

TEST_CASE("tbv: the list pool keeps every list exact through random adds and erases, inline and chained", "[tbv]") {
    // TbvSlotNodes: a slot's first kInline nodes by index, the rest chained. Slots get 0 to 20 lists (so
    // both), are erased and re-added at random; every list must hold exactly the slots added to it since.
    const std::uint64_t seed = 909;
    std::mt19937_64 rng(seed);
    constexpr int kLists = 40, kSlots = 30;
    std::vector<std::uint32_t> heads(kLists, kNone);
    std::vector<TbvSlotNodes> nodes(kSlots);
    std::vector<std::set<int>> model(kLists); // per list: its slots
    TbvListPool pool;
    std::size_t chained = 0;
    for (int op = 0; op < 4000; ++op) {
        INFO("seed " << seed << " op " << op);
        const int slot = sr::uniformInt(rng, 0, kSlots - 1);
        if (nodes[slot].count == 0) {
            const int n = sr::uniformInt(rng, 0, 20);
            for (int i = 0; i < n; ++i) {
                const int list = sr::uniformInt(rng, 0, kLists - 1);
                if (model[list].insert(slot).second) pool.add(heads[std::size_t(list)], ObjectSlot(slot), nodes[slot]);
            }
            chained += nodes[slot].count > TbvSlotNodes::kInline;
        } else {
            std::size_t expected = 0, heard = 0;
            for (std::set<int>& m : model) expected += m.erase(slot);
            CHECK(pool.eraseAll(nodes[slot], [&](const std::uint32_t*) { ++heard; }) == expected);
            CHECK(heard == expected);
            CHECK(nodes[slot].count == 0);
        }
        std::size_t total = 0;
        for (int list = 0; list < kLists; ++list) {
            std::multiset<int> got;
            pool.forEach(heads[std::size_t(list)], [&](ObjectSlot s) { got.insert(int(s)); });
            CHECK(got == std::multiset<int>(model[list].begin(), model[list].end()));
            total += model[list].size();
        }
        REQUIRE(pool.size() == total);
    }
    CHECK(chained > 100); // slots past kInline nodes were added and erased
}

TEST_CASE("tbv: T is not allocated, and holds nothing, until the first insert", "[tbv]") {
    TbvMatrix<2> t2({16, 12});
    TbvMatrix<3> t3({8, 6, 10});
    CHECK_FALSE(t2.allocated());
    CHECK_FALSE(t3.allocated());
    std::vector<ObjectSlot> got;
    t2.collectAt({3, 4}, got);
    t3.collectAt({3, 4, 5}, got);
    CHECK(got.empty());
    CHECK_FALSE(t2.holdsAt({0, 0}));
    CHECK_FALSE(t3.holdsAt({7, 5, 9}));
    CHECK(t2.incidences() == 0);
    CHECK(t3.liveRegions() == 0);

    // A region wholly outside the grid still allocates (it is the first insert) but writes nothing.
    const TbvRegion<2> away{{-50.0, 6.0}, 3.0};
    CHECK(t2.insert(4, away, TbvDiscretization::Boundary) == 0);
    CHECK(t2.allocated());
    CHECK(t2.liveRegions() == 1);
    CHECK(t2.erase(4, away, TbvDiscretization::Boundary) == 0);
    CHECK(t2.liveRegions() == 0);

    const TbvRegion<3> inside{{4.0, 3.0, 5.0}, 1.5};
    CHECK(t3.insert(9, inside, TbvDiscretization::Boundary) > 0);
    CHECK(t3.allocated());
    CHECK(t3.holdsAt({2, 1, 3}));       // a corner of the voxel box [2, 5] x [1, 4] x [3, 6]
    CHECK_FALSE(t3.holdsAt({3, 2, 4})); // strictly inside the box: not on the shell
    t3.erase(9, inside, TbvDiscretization::Boundary);
    CHECK(t3.incidences() == 0);
    CHECK_FALSE(t3.holdsAt({2, 1, 3}));
}

TEST_CASE("tbv: 2D ring and filled disc match brute force on thousands of random regions", "[tbv]") {
    for (const TbvDiscretization mode : {TbvDiscretization::Boundary, TbvDiscretization::Filled}) {
        const std::uint64_t seed = mode == TbvDiscretization::Boundary ? 101 : 202;
        std::mt19937_64 rng(seed);
        std::size_t regionsChecked = 0, mayVoxels = 0;
        for (int iter = 0; iter < 3000; ++iter) {
            const IVec2 res{sr::uniformInt(rng, 1, 40), sr::uniformInt(rng, 1, 40)};
            const TbvRegion<2> r = randomDisc(rng, res);
            INFO("seed " << seed << " iteration " << iter << " grid " << res.x << "x" << res.y << " " << describe(r)
                         << " mode " << (mode == TbvDiscretization::Boundary ? "boundary" : "filled"));
            TbvMatrix<2> t(res);
            const ObjectSlot slot = ObjectSlot(iter % 50);
            const std::size_t written = t.insert(slot, r, mode);
            CHECK(t.incidences() == written);
            std::size_t held = 0;
            std::set<std::pair<int, int>> heldTiles; // the 8 x 8 tiles with a voxel that holds the slot
            bool ok = true;
            for (std::int32_t y = 0; y < res.y && ok; ++y)
                for (std::int32_t x = 0; x < res.x && ok; ++x) {
                    std::vector<ObjectSlot> got;
                    t.collectAt({x, y}, got);
                    const Expect e = expect2D(r, {x, y}, mode);
                    mayVoxels += e == Expect::May;
                    const bool in = got.size() == 1 && got[0] == slot;
                    held += in;
                    if (in) heldTiles.insert({x >> 3, y >> 3});
                    ok = (got.empty() || in) && (e != Expect::Must || in) && (e != Expect::MustNot || !in);
                    // tbvTouches is the same predicate as the filled discretization (up to the band).
                    double nearest, farthest;
                    squareDistances(r.centre, {x, y}, nearest, farthest);
                    ok = ok && std::abs(tbvGap(r.centre, IVec2{x, y}) - nearest) <= 1e-12 * (1 + nearest);
                    if (e != Expect::May && mode == TbvDiscretization::Filled) ok = ok && tbvTouches(r, IVec2{x, y}) == in;
                    if (!ok) {
                        INFO("voxel (" << x << ", " << y << ") held " << got.size() << " slots, expected "
                                       << (e == Expect::Must ? "must" : e == Expect::May ? "may" : "must not")
                                       << "; nearest " << nearest << " farthest " << farthest);
                        CHECK(ok);
                    }
                }
            REQUIRE(ok);
            // One incidence per tile the discretization crosses, and no other: the lists are no looser than
            // the voxels (tbvBandRuns2D finds them a tile row at a time), and the counts hold each voxel once.
            CHECK(written == heldTiles.size());
            std::size_t runVoxels = 0;
            forEachTbvRun2D(r, res, mode, [&](std::int32_t, std::int32_t x0, std::int32_t x1) { runVoxels += std::size_t(x1 - x0 + 1); });
            CHECK(held == runVoxels);
            CHECK(t.erase(slot, r, mode) == written);
            CHECK(t.incidences() == 0);
            ++regionsChecked;
        }
        CHECK(regionsChecked == 3000);
        CHECK(mayVoxels < 3000); // the band is a rounding allowance, not a loophole
    }
}

TEST_CASE("tbv: a band of rows' two runs hold every run of its rows, and no more voxels", "[tbv]") {
    // tbvBandRuns2D (which tiles an insert lists the TBV in) against tbvRowRuns2D row by row: the same
    // columns, as sets, over bands of 1 to 20 rows anywhere on and off the disc, both discretizations.
    const std::uint64_t seed = 606;
    std::mt19937_64 rng(seed);
    std::size_t nonEmpty = 0;
    for (int iter = 0; iter < 4000; ++iter) {
        const TbvDiscretization mode = iter % 4 == 3 ? TbvDiscretization::Filled : TbvDiscretization::Boundary;
        const IVec2 res{sr::uniformInt(rng, 1, 60), sr::uniformInt(rng, 1, 60)};
        const TbvRegion<2> r = randomDisc(rng, res);
        const std::int32_t yA = sr::uniformInt(rng, 0, res.y - 1);
        const std::int32_t yB = std::min(res.y - 1, yA + sr::uniformInt(rng, 0, 19));
        INFO("seed " << seed << " iteration " << iter << " grid " << res.x << "x" << res.y << " rows " << yA << ".." << yB
                     << " " << describe(r));
        std::vector<char> rows(std::size_t(res.x), 0), band(std::size_t(res.x), 0);
        for (std::int32_t y = yA; y <= yB; ++y)
            tbvRowRuns2D(r, res, mode, y, [&](std::int32_t, std::int32_t x0, std::int32_t x1) {
                for (std::int32_t x = x0; x <= x1; ++x) rows[std::size_t(x)] = 1;
            });
        int runs = 0;
        tbvBandRuns2D(r, res, mode, yA, yB, [&](std::int32_t x0, std::int32_t x1) {
            ++runs;
            REQUIRE(0 <= x0);
            REQUIRE(x0 <= x1);
            REQUIRE(x1 < res.x);
            for (std::int32_t x = x0; x <= x1; ++x) band[std::size_t(x)] = 1;
        });
        CHECK(runs <= 2);
        for (std::int32_t x = 0; x < res.x; ++x) {
            INFO("column " << x << ": rows " << int(rows[std::size_t(x)]) << ", band " << int(band[std::size_t(x)]));
            REQUIRE(rows[std::size_t(x)] <= band[std::size_t(x)]); // conservative: every row's voxel
            REQUIRE(rows[std::size_t(x)] == band[std::size_t(x)]); // tight: the ring is 4-connected
        }
        nonEmpty += std::count(rows.begin(), rows.end(), 1) > 0;
    }
    CHECK(nonEmpty > 1000); // most bands meet their disc
}

TEST_CASE("tbv: 2D overlapping regions keep their own slots once each, and erasing all leaves T empty", "[tbv]") {
    const std::uint64_t seed = 303;
    std::mt19937_64 rng(seed);
    for (int iter = 0; iter < 300; ++iter) {
        const TbvDiscretization mode = iter % 2 ? TbvDiscretization::Filled : TbvDiscretization::Boundary;
        const IVec2 res{sr::uniformInt(rng, 4, 32), sr::uniformInt(rng, 4, 32)};
        INFO("seed " << seed << " iteration " << iter << " grid " << res.x << "x" << res.y);
        TbvMatrix<2> t(res);
        const int k = sr::uniformInt(rng, 2, 8);
        std::vector<TbvRegion<2>> regions;
        std::vector<ObjectSlot> slots;
        std::vector<bool> live(static_cast<std::size_t>(k), true);
        std::size_t written = 0;
        for (int i = 0; i < k; ++i) {
            // Many regions near the same place, some identical: the lists must keep one entry per slot.
            regions.push_back(i > 0 && sr::chance(rng, 0.2) ? regions.back() : randomDisc(rng, res));
            slots.push_back(ObjectSlot(i * 37 + 5));
            written += t.insert(slots.back(), regions.back(), mode);
        }
        CHECK(t.liveRegions() == std::size_t(k));
        CHECK(t.incidences() == written);
        REQUIRE(check2D(t, res, regions, slots, live, mode));
        // Erase in random order, checking after each: the others are untouched.
        std::vector<int> order(static_cast<std::size_t>(k));
        for (int i = 0; i < k; ++i) order[std::size_t(i)] = i;
        std::shuffle(order.begin(), order.end(), rng);
        for (int i : order) {
            written -= t.erase(slots[std::size_t(i)], regions[std::size_t(i)], mode);
            live[std::size_t(i)] = false;
            CHECK(t.incidences() == written);
            REQUIRE(check2D(t, res, regions, slots, live, mode));
        }
        CHECK(t.incidences() == 0);
        CHECK(t.liveRegions() == 0);
    }
}

TEST_CASE("tbv: 2D counts saturate at 255 without losing a region (more than 255 rings on one voxel)", "[tbv]") {
    // 399 rings through the same voxels (the same centre, radii a hair apart), so their counts reach the
    // sticky 255; lookups (holdsAt included) must stay exact while they are live, as they are erased, and
    // once all are gone. Region 0, elsewhere, is erased last.
    const IVec2 res{48, 48};
    TbvMatrix<2> t(res);
    std::vector<TbvRegion<2>> regions;
    std::vector<ObjectSlot> slots;
    const int k = 400;
    std::vector<bool> live(std::size_t(k), false);
    for (int i = 0; i < k; ++i) {
        regions.push_back(i == 0 ? TbvRegion<2>{{8.5, 8.5}, 3.0} : TbvRegion<2>{{30.3, 29.7}, 10.0 + 1e-4 * i});
        slots.push_back(ObjectSlot(i));
        t.insert(slots.back(), regions.back(), TbvDiscretization::Boundary);
        live[std::size_t(i)] = true;
        // Counts of 127, 128 and 129 on the shared voxels (mayHoldRow's bytes with and without bit 7).
        if (i >= 127 && i <= 129) REQUIRE(check2D(t, res, regions, slots, live, TbvDiscretization::Boundary));
    }
    REQUIRE(check2D(t, res, regions, slots, live, TbvDiscretization::Boundary));
    std::vector<ObjectSlot> onVoxel;
    t.collectAt({20, 25}, onVoxel);
    CHECK(onVoxel.size() > 255); // its count did saturate
    std::mt19937_64 rng(404);
    std::vector<int> order(static_cast<std::size_t>(k));
    for (int i = 0; i < k; ++i) order[std::size_t(i)] = (i + 1) % k;
    std::shuffle(order.begin(), order.end() - 1, rng);
    for (int n = 0; n < k; ++n) {
        const int i = order[std::size_t(n)];
        t.erase(slots[std::size_t(i)], regions[std::size_t(i)], TbvDiscretization::Boundary);
        live[std::size_t(i)] = false;
        if (n % 50 == 49 || n > k - 5) REQUIRE(check2D(t, res, regions, slots, live, TbvDiscretization::Boundary));
    }
    CHECK(t.liveRegions() == 0);
    std::vector<ObjectSlot> got;
    for (std::int32_t y = 0; y < res.y; ++y)
        for (std::int32_t x = 0; x < res.x; ++x) t.collectAt({x, y}, got);
    CHECK(got.empty());
}

TEST_CASE("tbv: 2D counts are written only for tiles a lookup needs, and lookups answer as if all were", "[tbv]") {
    // Inserts, erases and lookups interleaved at random, so regions enter and leave tiles whose counts
    // are written (hot) and tiles whose are not (cold), and tiles turn hot between an insert and its erase.
    const std::uint64_t seed = 505;
    std::mt19937_64 rng(seed);
    for (int iter = 0; iter < 60; ++iter) {
        const TbvDiscretization mode = iter % 3 == 2 ? TbvDiscretization::Filled : TbvDiscretization::Boundary;
        const IVec2 res{sr::uniformInt(rng, 5, 40), sr::uniformInt(rng, 5, 40)};
        INFO("seed " << seed << " iteration " << iter << " grid " << res.x << "x" << res.y);
        TbvMatrix<2> t(res);
        std::vector<TbvRegion<2>> regions;
        std::vector<ObjectSlot> slots;
        std::vector<bool> live;
        // Inserts alone write no counts: every tile stays cold (the laziness this test is about).
        for (int i = 0; i < 6; ++i) {
            regions.push_back(randomDisc(rng, res));
            slots.push_back(ObjectSlot(regions.size() * 3));
            live.push_back(true);
            t.insert(slots.back(), regions.back(), mode);
        }
        CHECK(t.hotTiles() == 0);
        std::vector<ObjectSlot> got;
        for (int step = 0; step < 80; ++step) {
            const double u = sr::uniform(rng, 0, 1);
            if (u < 0.25) {
                regions.push_back(randomDisc(rng, res));
                slots.push_back(ObjectSlot(regions.size() * 3));
                live.push_back(true);
                t.insert(slots.back(), regions.back(), mode);
            } else if (u < 0.45) {
                std::vector<std::size_t> alive;
                for (std::size_t i = 0; i < live.size(); ++i)
                    if (live[i]) alive.push_back(i);
                if (alive.empty()) continue;
                const std::size_t i = alive[std::size_t(sr::uniformInt(rng, 0, int(alive.size()) - 1))];
                t.erase(slots[i], regions[i], mode);
                live[i] = false;
            } else {
                // A lookup at one voxel: collectAt or mayHoldRow heat its tile.
                const IVec2 v{sr::uniformInt(rng, 0, res.x - 1), sr::uniformInt(rng, 0, res.y - 1)};
                got.clear();
                const bool collect = u < 0.75;
                bool mayBit = false;
                if (collect) t.collectAt(v, got);
                else mayBit = ((t.mayHoldRow({v.x >> 3, v.y >> 3}, v.y & 7) >> (v.x & 7)) & 1) != 0;
                for (std::size_t i = 0; i < regions.size(); ++i) {
                    const Expect e = live[i] ? expect2D(regions[i], v, mode) : Expect::MustNot;
                    const std::size_t n = countOf(got, slots[i]);
                    const bool ok = collect ? n <= 1 && (e != Expect::Must || n == 1) && (e != Expect::MustNot || n == 0)
                                            : e != Expect::Must || mayBit; // (false is a guarantee)
                    INFO("step " << step << " voxel (" << v.x << ", " << v.y << ") slot " << slots[i] << " held " << n
                                 << " times; " << describe(regions[i]));
                    REQUIRE(ok);
                }
            }
        }
        REQUIRE(check2D(t, res, regions, slots, live, mode));
        // freshen(): every tile a live ring crosses is hot, and no lookup writes after it.
        t.freshen();
        const std::size_t hot = t.hotTiles();
        REQUIRE(check2D(t, res, regions, slots, live, mode));
        CHECK(t.hotTiles() == hot);
    }
}

TEST_CASE("tbv: 3D shell (2 of 3 projections) and filled box match brute force, several regions at once", "[tbv]") {
    const std::uint64_t seed = 404;
    std::mt19937_64 rng(seed);
    std::size_t shellVoxels = 0;
    for (int iter = 0; iter < 1500; ++iter) {
        // Shell stores the same voxels as Boundary, one list per voxel instead of three projections.
        const TbvDiscretization mode = iter % 3 == 2   ? TbvDiscretization::Filled
                                       : iter % 3 == 1 ? TbvDiscretization::Shell
                                                       : TbvDiscretization::Boundary;
        const IVec3 res{sr::uniformInt(rng, 1, 20), sr::uniformInt(rng, 1, 20), sr::uniformInt(rng, 1, 20)};
        const int k = sr::uniformInt(rng, 1, 4);
        INFO("seed " << seed << " iteration " << iter << " grid " << res.x << "x" << res.y << "x" << res.z << " regions " << k
                     << " mode " << int(mode) << " (0 boundary, 1 filled, 2 shell)");
        TbvMatrix<3> t(res);
        std::vector<TbvRegion<3>> regions;
        const std::size_t nk = static_cast<std::size_t>(k);
        std::vector<IVec3> lo(nk), hi(nk);
        std::vector<bool> hit(nk);
        std::size_t written = 0;
        for (int i = 0; i < k; ++i) {
            const TbvRegion<3> r = randomCube(rng, res);
            regions.push_back(r);
            CAPTURE(i, describe(r));
            written += t.insert(ObjectSlot(i * 11 + 2), r, mode);
            // The box the header computes must lie between the tight brute-force box (voxels within
            // Chebyshev distance r) and the loose one (within r + band).
            hit[std::size_t(i)] = tbvVoxelBox3D(r, res, lo[std::size_t(i)], hi[std::size_t(i)]);
            bool tightEmpty = false, looseEmpty = false;
            for (int a = 0; a < 3; ++a) {
                std::int32_t tlo, thi, llo, lhi;
                axisRange(r.centre[a], r.radius, res[a], 0.0, tlo, thi);
                axisRange(r.centre[a], r.radius, res[a], kBand, llo, lhi);
                tightEmpty = tightEmpty || tlo > thi;
                looseEmpty = looseEmpty || llo > lhi;
                if (hit[std::size_t(i)] && tlo <= thi) {
                    CHECK(llo <= lo[std::size_t(i)][a]);
                    CHECK(lo[std::size_t(i)][a] <= tlo);
                    CHECK(thi <= hi[std::size_t(i)][a]);
                    CHECK(hi[std::size_t(i)][a] <= lhi);
                }
            }
            if (!tightEmpty) CHECK(hit[std::size_t(i)]);
            if (looseEmpty) CHECK_FALSE(hit[std::size_t(i)]);
        }
        CHECK(t.incidences() == written);
        bool ok = true;
        std::vector<ObjectSlot> got;
        for (std::int32_t z = 0; z < res.z && ok; ++z)
            for (std::int32_t y = 0; y < res.y && ok; ++y)
                for (std::int32_t x = 0; x < res.x && ok; ++x) {
                    const IVec3 v{x, y, z};
                    got.clear();
                    t.collectAt(v, got);
                    std::size_t expectedTotal = 0;
                    for (int i = 0; i < k; ++i) {
                        const IVec3 l = lo[std::size_t(i)], h = hi[std::size_t(i)];
                        bool inBox = hit[std::size_t(i)], onBound = false;
                        for (int a = 0; a < 3; ++a) {
                            inBox = inBox && v[a] >= l[a] && v[a] <= h[a];
                            onBound = onBound || v[a] == l[a] || v[a] == h[a];
                        }
                        const bool expected = inBox && (mode == TbvDiscretization::Filled || onBound);
                        const std::size_t n = countOf(got, ObjectSlot(i * 11 + 2));
                        expectedTotal += expected;
                        shellVoxels += expected;
                        // tbvTouches agrees: true in the box, and outside it the region does not truly touch.
                        if (inBox && !tbvTouches(regions[std::size_t(i)], v)) ok = false;
                        if (!inBox && tbvGap(regions[std::size_t(i)].centre, v) <= regions[std::size_t(i)].radius) ok = false;
                        if (n != std::size_t(expected)) {
                            INFO("voxel (" << x << ", " << y << ", " << z << ") region " << i << " " << describe(regions[std::size_t(i)])
                                           << " box [" << l.x << "," << h.x << "]x[" << l.y << "," << h.y << "]x[" << l.z << "," << h.z
                                           << "] held " << n << " times, expected " << expected);
                            CHECK(n == std::size_t(expected));
                            ok = false;
                        }
                    }
                    if (got.size() != expectedTotal) {
                        INFO("voxel (" << x << ", " << y << ", " << z << ") collected " << got.size() << " slots, expected " << expectedTotal);
                        CHECK(got.size() == expectedTotal);
                        ok = false;
                    }
                    // holdsAt is exact: some slot holds the voxel iff collectAt found one.
                    if (t.holdsAt(v) != !got.empty()) {
                        INFO("voxel (" << x << ", " << y << ", " << z << ") holdsAt disagrees with collectAt");
                        CHECK(false);
                        ok = false;
                    }
                }
        REQUIRE(ok);
        // The lookups heated the blocks they read (their bricks' nodes came on top of the blocks' own).
        std::size_t erased = 0;
        for (int i = 0; i < k; ++i) erased += t.erase(ObjectSlot(i * 11 + 2), regions[std::size_t(i)], mode);
        CHECK(erased >= written);
        CHECK(t.incidences() == 0);
        CHECK(t.liveRegions() == 0);
        CHECK_FALSE(t.holdsAt({0, 0, 0}));
    }
    CHECK(shellVoxels > 10000); // the regions did reach the grids
}

TEST_CASE("tbv: 3D T writes one node per cold block, and per brick its discretization reaches in hot ones", "[tbv]") {
    // Boundary and Filled cost one list node per 8^3 brick the shell (box) reaches, not per voxel or per
    // plane cell: the box [22, 42]^3 spans bricks 2..5 on each axis (64), and its shell misses the 8
    // bricks 3..4 on every axis, which lie strictly inside it. Where no lookup has gone yet (cold blocks
    // of 2^3 bricks), one node per block the box meets: blocks 1..2 on each axis, 8.
    TbvMatrix<3> t({64, 64, 64});
    const TbvRegion<3> r{{32.5, 32.5, 32.5}, 9.9}; // voxel box [22, 42]^3: n = 21
    const std::size_t n = 21;
    CHECK(t.insert(1, r, TbvDiscretization::Boundary) == 8);
    CHECK(t.hotBlocks() == 0);
    // A brick walk's lookup heats the brick's block only: block (1, 1, 1) holds bricks 2..3 on each axis,
    // 7 of which the shell reaches (brick (3, 3, 3) is inside it).
    std::uint64_t bits[8];
    CHECK(t.brickBits({2, 2, 2}, bits));
    CHECK(t.hotBlocks() == 1);
    CHECK(t.incidences() == 8 + 7);
    CHECK_FALSE(t.brickBits({3, 3, 3}, bits)); // hot now, and the shell misses it
    CHECK(t.hotBlocks() == 1);
    t.freshen(); // every block that holds a TBV
    CHECK(t.hotBlocks() == 8);
    CHECK(t.incidences() == 8 + 64 - 8);
    CHECK(t.erase(1, r, TbvDiscretization::Boundary) == 8 + 64 - 8);
    // Hot blocks: brick nodes only.
    CHECK(t.insert(1, r, TbvDiscretization::Boundary) == 64 - 8);
    CHECK(t.incidences() == 64 - 8);
    CHECK(t.erase(1, r, TbvDiscretization::Boundary) == 64 - 8);
    CHECK(t.incidences() == 0);
    TbvMatrix<3> f({64, 64, 64});
    CHECK(f.insert(1, r, TbvDiscretization::Filled) == 8);
    f.freshen();
    CHECK(f.erase(1, r, TbvDiscretization::Filled) == 8 + 64);
    CHECK(f.insert(1, r, TbvDiscretization::Filled) == 64);
    // Shell: the shell's voxels themselves, n^3 - (n - 2)^3.
    TbvMatrix<3> sh({64, 64, 64});
    CHECK(sh.insert(1, r, TbvDiscretization::Shell) == n * n * n - (n - 2) * (n - 2) * (n - 2));
    CHECK(sh.erase(1, r, TbvDiscretization::Shell) == n * n * n - (n - 2) * (n - 2) * (n - 2));
    CHECK(sh.incidences() == 0);
}

namespace {

// The model of a 3D T: per live slot its voxel box (computed by tbvVoxelBox3D, checked against brute
// force above) and mode; a voxel holds the slot iff it is in the box and, unless Filled, on its shell.
struct Model3D {
    struct Entry {
        ObjectSlot slot;
        IVec3 lo, hi;
        TbvDiscretization mode;
        bool inGrid;
        TbvRegion<3> region;
    };
    std::vector<Entry> live;
    std::vector<ObjectSlot> holding(const IVec3& v) const {
        std::vector<ObjectSlot> out;
        for (const Entry& e : live) {
            bool in = e.inGrid, bound = e.mode == TbvDiscretization::Filled;
            for (int a = 0; a < 3; ++a) {
                in = in && v[a] >= e.lo[a] && v[a] <= e.hi[a];
                bound = bound || v[a] == e.lo[a] || v[a] == e.hi[a];
            }
            if (in && bound) out.push_back(e.slot);
        }
        std::sort(out.begin(), out.end());
        return out;
    }
};

} // namespace

TEST_CASE("tbv: 3D bricks match a model through random inserts, erases and lookups (stale bitmaps)", "[tbv]") {
    // The bitmaps of a brick go stale on every erase and are rebuilt by the first lookup that meets a
    // stale bit, so lookups are interleaved with the updates at random voxels (sometimes every voxel),
    // many overlapping boxes share bricks, grids are not multiples of 8, and slots are reused.
    const std::uint64_t seed = 606;
    std::mt19937_64 rng(seed);
    std::size_t positives = 0, lookups = 0;
    for (int iter = 0; iter < 200; ++iter) {
        const IVec3 res{sr::uniformInt(rng, 1, 40), sr::uniformInt(rng, 1, 30), sr::uniformInt(rng, 1, 40)};
        INFO("seed " << seed << " iteration " << iter << " grid " << res.x << "x" << res.y << "x" << res.z);
        TbvMatrix<3> t(res);
        // The same updates, asked only what the read-only lookups answer: its blocks stay cold, so they
        // answer from the blocks' lists (TbvMatrix<3>, "Blocks written lazily") all through.
        TbvMatrix<3> cold(res);
        Model3D model;
        std::vector<ObjectSlot> got;
        const int ops = sr::uniformInt(rng, 10, 120);
        for (int op = 0; op < ops; ++op) {
            CAPTURE(op);
            const bool doInsert = model.live.empty() || (model.live.size() < 40 && sr::chance(rng, 0.6));
            if (doInsert) {
                Model3D::Entry e;
                e.slot = ObjectSlot(sr::uniformInt(rng, 0, 63));
                bool used = false;
                for (const auto& l : model.live) used = used || l.slot == e.slot;
                if (used) continue;
                e.region = randomCube(rng, res);
                // Mostly small boxes, as the culler makes them, so that many share bricks.
                if (sr::chance(rng, 0.7)) e.region.radius = std::min(e.region.radius, 5.0);
                e.mode = sr::chance(rng, 0.25) ? TbvDiscretization::Filled : TbvDiscretization::Boundary;
                e.inGrid = tbvVoxelBox3D(e.region, res, e.lo, e.hi);
                CAPTURE(e.slot, describe(e.region), int(e.mode));
                t.insert(e.slot, e.region, e.mode);
                cold.insert(e.slot, e.region, e.mode);
                model.live.push_back(e);
            } else {
                const std::size_t i = std::size_t(sr::uniformInt(rng, 0, int(model.live.size()) - 1));
                const Model3D::Entry e = model.live[i];
                t.erase(e.slot, e.region, e.mode);
                cold.erase(e.slot, e.region, e.mode);
                model.live.erase(model.live.begin() + std::ptrdiff_t(i));
            }
            CHECK(t.liveRegions() == model.live.size());
            auto check = [&](const IVec3& v) {
                // holdsAt first: it must be exact on a stale brick too, before collectAt rebuilds it.
                const std::vector<ObjectSlot> expected = model.holding(v);
                const bool holds = t.holdsAt(v);
                CHECK(cold.holdsAt(v) == !expected.empty());
                got.clear();
                t.collectAt(v, got);
                std::sort(got.begin(), got.end());
                ++lookups;
                positives += !expected.empty();
                if (got != expected || holds != !expected.empty()) {
                    INFO("voxel (" << v.x << ", " << v.y << ", " << v.z << ") collected " << got.size() << " slots, expected "
                                   << expected.size() << "; holdsAt " << holds);
                    CHECK(false);
                    return false;
                }
                return true;
            };
            bool ok = true;
            if (op % 7 == 6) {
                for (std::int32_t z = 0; z < res.z && ok; ++z)
                    for (std::int32_t y = 0; y < res.y && ok; ++y)
                        for (std::int32_t x = 0; x < res.x && ok; ++x) ok = check({x, y, z});
                // brickParts: per brick, each listed slot's voxels there, exactly the model's; every slot
                // holding a voxel of the brick listed once.
                std::vector<ObjectSlot> slots;
                std::vector<std::array<std::uint64_t, 8>> parts;
                for (std::int32_t bz = 0; bz * 8 < res.z && ok; ++bz)
                    for (std::int32_t by = 0; by * 8 < res.y && ok; ++by)
                        for (std::int32_t bx = 0; bx * 8 < res.x && ok; ++bx) {
                            // Read-only lookups first: a block no lookup has heated answers from its list.
                            t.brickParts({bx, by, bz}, slots, parts);
                            REQUIRE(slots.size() == parts.size());
                            std::set<ObjectSlot> seen(slots.begin(), slots.end());
                            CHECK(seen.size() == slots.size());
                            const std::uint64_t all[8] = {~0ull, ~0ull, ~0ull, ~0ull, ~0ull, ~0ull, ~0ull, ~0ull};
                            got.clear();
                            t.collectInBrick({bx, by, bz}, all, got);
                            CHECK(std::set<ObjectSlot>(got.begin(), got.end()) == seen); // each once, as brickParts
                            CHECK(got.size() == seen.size());
                            std::vector<ObjectSlot> coldSlots;
                            std::vector<std::array<std::uint64_t, 8>> coldParts;
                            cold.brickParts({bx, by, bz}, coldSlots, coldParts);
                            std::vector<std::pair<ObjectSlot, std::array<std::uint64_t, 8>>> a, b;
                            for (std::size_t i = 0; i < slots.size(); ++i) a.push_back({slots[i], parts[i]});
                            for (std::size_t i = 0; i < coldSlots.size(); ++i) b.push_back({coldSlots[i], coldParts[i]});
                            std::sort(a.begin(), a.end());
                            std::sort(b.begin(), b.end());
                            CHECK(a == b);
                            got.clear();
                            cold.collectInBrick({bx, by, bz}, all, got);
                            CHECK(std::set<ObjectSlot>(got.begin(), got.end()) == seen);
                            CHECK(got.size() == seen.size());
                            if (!seen.empty()) CHECK(cold.mayHoldBrick({bx, by, bz}));
                            // brickBits (what the brick walk reads): exactly the voxels some live region
                            // holds, a brick an erase left stale rebuilt first.
                            std::uint64_t bits[8] = {0, 0, 0, 0, 0, 0, 0, 0};
                            const bool anyBits = t.brickBits({bx, by, bz}, bits);
                            bool anyExpected = false;
                            for (std::int32_t z = 0; z < 8; ++z)
                                for (std::int32_t y = 0; y < 8; ++y)
                                    for (std::int32_t x = 0; x < 8; ++x) {
                                        const IVec3 v{bx * 8 + x, by * 8 + y, bz * 8 + z};
                                        const std::uint64_t bit = std::uint64_t(1) << (x + 8 * y);
                                        const bool inGrid = v.x < res.x && v.y < res.y && v.z < res.z;
                                        const std::vector<ObjectSlot> expected = inGrid ? model.holding(v) : std::vector<ObjectSlot>{};
                                        anyExpected = anyExpected || !expected.empty();
                                        ok = ok && (((bits[z] & bit) != 0) == !expected.empty());
                                        for (ObjectSlot e : expected) ok = ok && seen.count(e) == 1;
                                        for (std::size_t i = 0; i < slots.size(); ++i) {
                                            const bool want = std::find(expected.begin(), expected.end(), slots[i]) != expected.end();
                                            ok = ok && (((parts[i][std::size_t(z)] & bit) != 0) == want);
                                        }
                                    }
                            ok = ok && anyBits == anyExpected;
                            if (!ok) INFO("brick (" << bx << ", " << by << ", " << bz << ")");
                            CHECK(ok);
                        }
            } else {
                for (int q = 0; q < 200 && ok; ++q)
                    ok = check({sr::uniformInt(rng, 0, res.x - 1), sr::uniformInt(rng, 0, res.y - 1), sr::uniformInt(rng, 0, res.z - 1)});
            }
            REQUIRE(ok);
        }
        CHECK(cold.hotBlocks() == 0);
        for (const auto& e : model.live) t.erase(e.slot, e.region, e.mode);
        CHECK(t.incidences() == 0);
        for (int q = 0; q < 100; ++q) {
            const IVec3 v{sr::uniformInt(rng, 0, res.x - 1), sr::uniformInt(rng, 0, res.y - 1), sr::uniformInt(rng, 0, res.z - 1)};
            got.clear();
            t.collectAt(v, got);
            CHECK(got.empty());
            CHECK_FALSE(t.holdsAt(v));
        }
    }
    CHECK(positives > 20000); // the lookups did meet held voxels, not only empty space
    CHECK(lookups > 200000);
}

TEST_CASE("tbv: 3D brickBits with a rebuild limit: a long stale list is read as a superset, settleBrick makes it exact", "[tbv]") {
    // What the brick walk reads (BrickPass.cpp, kRebuildUpTo): a stale brick whose list holds more TBVs
    // than the limit is returned as it stands, a superset of the live TBVs' voxels that still holds every
    // one of them (the walk confirms each voxel against brickParts); a shorter one is rebuilt, exact.
    // settleBrick with the parts just read makes a stale brick exact without its list walk. Boxes around
    // one brick, so that its list grows long; random erases stale it.
    const std::uint64_t seed = 707;
    std::mt19937_64 rng(seed);
    const IVec3 res{24, 24, 24}, brick{1, 1, 1};
    std::size_t supersets = 0, strict = 0, rebuilt = 0, settled = 0;
    for (int iter = 0; iter < 60; ++iter) {
        INFO("seed " << seed << " iteration " << iter);
        TbvMatrix<3> t(res);
        Model3D model;
        ObjectSlot nextSlot = 0;
        std::vector<ObjectSlot> slots;
        std::vector<std::array<std::uint64_t, 8>> parts;
        std::uint64_t bits[8];
        for (int op = 0; op < 150; ++op) {
            CAPTURE(op);
            if (model.live.size() < 60 && (model.live.empty() || sr::chance(rng, 0.6))) {
                Model3D::Entry e;
                e.slot = nextSlot++;
                e.region.centre = Vec3(12.0) + Vec3(sr::uniform(rng, -5, 5), sr::uniform(rng, -5, 5), sr::uniform(rng, -5, 5));
                e.region.radius = sr::uniform(rng, 0.5, 7.0);
                e.mode = sr::chance(rng, 0.2) ? TbvDiscretization::Filled : TbvDiscretization::Boundary;
                e.inGrid = tbvVoxelBox3D(e.region, res, e.lo, e.hi);
                t.insert(e.slot, e.region, e.mode);
                model.live.push_back(e);
            } else {
                const std::size_t i = std::size_t(sr::uniformInt(rng, 0, int(model.live.size()) - 1));
                t.erase(model.live[i].slot, model.live[i].region, model.live[i].mode);
                model.live.erase(model.live.begin() + std::ptrdiff_t(i));
            }
            if (op % 3 != 2) continue;
            // The brick's exact voxels, and its list's length (brickParts lists every slot of it once).
            std::uint64_t exact[8] = {0, 0, 0, 0, 0, 0, 0, 0};
            for (std::int32_t z = 0; z < 8; ++z)
                for (std::int32_t y = 0; y < 8; ++y)
                    for (std::int32_t x = 0; x < 8; ++x)
                        if (!model.holding(brick * 8 + IVec3{x, y, z}).empty()) exact[z] |= std::uint64_t(1) << (x + 8 * y);
            t.brickParts(brick, slots, parts);
            const std::uint32_t limit = std::uint32_t(sr::pick(rng, std::vector<int>{0, 4, 16, 1000}));
            CAPTURE(limit, slots.size());
            std::fill(std::begin(bits), std::end(bits), 0);
            t.brickBits(brick, bits, limit);
            bool same = true, holds = true;
            for (int z = 0; z < 8; ++z) {
                same = same && bits[z] == exact[z];
                holds = holds && (bits[z] & exact[z]) == exact[z];
            }
            CHECK(holds); // never a voxel of a live TBV left out
            if (slots.size() <= limit) {
                CHECK(same); // rebuilt when stale
                ++rebuilt;
            } else {
                ++supersets;
                strict += !same;
            }
            if (sr::chance(rng, 0.3)) {
                t.settleBrick(brick, parts);
                std::fill(std::begin(bits), std::end(bits), 0);
                t.brickBits(brick, bits, 0); // no rebuild allowed: exact only if settled
                for (int z = 0; z < 8; ++z) CHECK(bits[z] == exact[z]);
                ++settled;
            }
        }
    }
    std::printf("[tbv] brick reads: %zu rebuilt or exact, %zu supersets (%zu strictly larger), %zu settled\n", rebuilt, supersets,
                strict, settled);
    CHECK(strict > 50); // the long lists' erases did leave stale bits, which the limit kept
    CHECK(rebuilt > 50);
    CHECK(settled > 50);
}

TEST_CASE("tbv: the 2D ring and 3D shell stop every segment from an outside camera to a point inside", "[tbv]") {
    // The property that makes the boundary enough: the traversal reaches, in a layer no farther than p,
    // a voxel the segment camera->p crosses before p, and that voxel holds the slot. Brute force: sample
    // the segment densely up to p, and also check the voxel at the analytic first crossing of the circle.
    const std::uint64_t seed = 505;
    std::mt19937_64 rng(seed);
    int segments2D = 0, segments3D = 0;
    for (int iter = 0; iter < 2000; ++iter) {
        const IVec2 res{sr::uniformInt(rng, 8, 48), sr::uniformInt(rng, 8, 48)};
        TbvRegion<2> r = randomDisc(rng, res);
        r.radius = std::min(r.radius, 0.4 * std::min(res.x, res.y));
        INFO("seed " << seed << " iteration " << iter << " grid " << res.x << "x" << res.y << " " << describe(r));
        TbvMatrix<2> t(res);
        t.insert(7, r, TbvDiscretization::Boundary);
        for (int trial = 0; trial < 10; ++trial) {
            const Vec2 cam{sr::uniform(rng, 0, res.x), sr::uniform(rng, 0, res.y)};
            const IVec2 cv = IVec2(glm::floor(cam));
            double nearest, farthest;
            squareDistances(r.centre, cv, nearest, farthest);
            if (nearest <= r.radius + kBand) continue; // the condition: the camera's voxel misses the disc
            const double a = sr::uniform(rng, 0, 6.283185307179586), d = r.radius * std::sqrt(sr::uniform01(rng));
            const Vec2 p = r.centre + d * Vec2{std::cos(a), std::sin(a)};
            if (!(p.x >= 0 && p.x < res.x && p.y >= 0 && p.y < res.y)) continue;
            CAPTURE(cam.x, cam.y, p.x, p.y);
            bool held = false;
            const int steps = 4000;
            for (int k = 0; k <= steps && !held; ++k) {
                const Vec2 s = cam + (p - cam) * (double(k) / steps);
                held = t.holdsAt(glm::clamp(IVec2(glm::floor(s)), IVec2(0), res - 1));
            }
            CHECK(held);
            // First crossing of the circle: |cam + u (p - cam) - c| = r, smallest u in (0, 1].
            const Vec2 dd = p - cam, f = cam - r.centre;
            const double A = glm::dot(dd, dd), B = 2 * glm::dot(f, dd), C = glm::dot(f, f) - r.radius * r.radius;
            const double u = (-B - std::sqrt(std::max(0.0, B * B - 4 * A * C))) / (2 * A);
            const Vec2 q = cam + u * dd;
            CHECK(t.holdsAt(glm::clamp(IVec2(glm::floor(q)), IVec2(0), res - 1)));
            ++segments2D;
        }
        // The frame-to-frame half: a voxel next to (8-connected) one that misses the disc either misses
        // the disc too or holds the ring, so a camera moving by one voxel cannot step inside unseen.
        for (std::int32_t y = 0; y < res.y; ++y)
            for (std::int32_t x = 0; x < res.x; ++x) {
                double nearest, farthest;
                squareDistances(r.centre, {x, y}, nearest, farthest);
                if (nearest > r.radius || t.holdsAt({x, y})) continue;
                // {x, y} touches the disc but not the circle: every neighbour touches the disc.
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        double n2, f2;
                        squareDistances(r.centre, {x + dx, y + dy}, n2, f2);
                        if (n2 > r.radius + kBand) {
                            INFO("voxel (" << x << ", " << y << ") is inside the ring but its neighbour (" << x + dx << ", "
                                           << y + dy << ") misses the disc");
                            CHECK(false);
                        }
                    }
            }
    }
    for (int iter = 0; iter < 600; ++iter) {
        const IVec3 res{sr::uniformInt(rng, 6, 24), sr::uniformInt(rng, 6, 24), sr::uniformInt(rng, 6, 24)};
        TbvRegion<3> r = randomCube(rng, res);
        r.radius = std::min(r.radius, 0.4 * std::min({res.x, res.y, res.z}));
        INFO("seed " << seed << " 3D iteration " << iter << " grid " << res.x << "x" << res.y << "x" << res.z << " " << describe(r));
        TbvMatrix<3> t(res);
        t.insert(3, r, TbvDiscretization::Boundary);
        IVec3 lo, hi;
        if (!tbvVoxelBox3D(r, res, lo, hi)) continue;
        for (int trial = 0; trial < 10; ++trial) {
            Vec3 cam(0.0), p(0.0);
            for (int a = 0; a < 3; ++a) {
                cam[a] = sr::uniform(rng, 0, res[a]);
                p[a] = std::clamp(r.centre[a] + sr::uniform(rng, -r.radius, r.radius), 0.0, std::nextafter(double(res[a]), 0.0));
            }
            const IVec3 cv = IVec3(glm::floor(cam));
            bool outside = false;
            for (int a = 0; a < 3; ++a) outside = outside || cv[a] < lo[a] || cv[a] > hi[a];
            if (!outside) continue; // the condition: the camera's voxel index is outside the box
            CAPTURE(cam.x, cam.y, cam.z, p.x, p.y, p.z);
            std::vector<ObjectSlot> got;
            bool held = false;
            const int steps = 3000;
            for (int k = 0; k <= steps && !held; ++k) {
                const Vec3 s = cam + (p - cam) * (double(k) / steps);
                got.clear();
                t.collectAt(glm::clamp(IVec3(glm::floor(s)), IVec3(0), res - 1), got);
                held = countOf(got, 3) == 1;
            }
            CHECK(held);
            ++segments3D;
        }
    }
    CHECK(segments2D > 5000);
    CHECK(segments3D > 1500);
}
