// GridGeometry (world <-> voxel mapping, bounds convention, linear indices, input validation) and the
// dense VoxelStorage, checked against brute force; and the build's RGVC_SIMD setting. Tag: [grid].
#include "rgvc/config.hpp"
#include "rgvc/grid/GridGeometry.hpp"
#include "rgvc/grid/Shapes.hpp"
#include "rgvc/grid/VoxelStorage.hpp"
#include "rgvc/grid/VoxelSize.hpp"
#include "rgvc/grid/DistanceSort.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <limits>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

using namespace rgvc;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

/// Runs `make` and checks that it throws InvalidInput naming `field`, with what() = "<field>: ...".
template <class F> void requireInvalid(F&& make, const std::string& field) {
    bool threw = false;
    try {
        make();
    } catch (const InvalidInput& e) {
        threw = true;
        CHECK(e.field() == field);
        CHECK(std::string(e.what()).rfind(field + ": ", 0) == 0);
    }
    CHECK(threw);
}

/// Local coordinate of a world coordinate computed in extended precision (the reference mapping).
long double refLocal(double world, double origin, double d) {
    return ((long double)world - (long double)origin) / (long double)d;
}

} // namespace

// RGVC_SIMD (top-level CMakeLists.txt): config.hpp must say what the code was compiled for (the tests get
// the libraries' flags through rgvc_warnings), and an AVX2 build only ever runs where AVX2 is: AUTO
// chose it by running a probe on this machine, and SimdGuard.cpp would have aborted otherwise.
TEST_CASE("RGVC_SIMD: config.hpp matches the compiler's target, and the CPU runs it", "[grid]") {
    INFO("RGVC_SIMD_LEVEL = " RGVC_SIMD_LEVEL);
    // One way only: flags of the user's own (CMAKE_CXX_FLAGS=-march=native with RGVC_SIMD=NONE) may
    // target AVX2 without RGVC_SIMD knowing, but RGVC_SIMD=AVX2 must reach the code.
#if RGVC_SIMD_AVX2
    CHECK(std::string(RGVC_SIMD_LEVEL) == "avx2");
#if !defined(__AVX2__)
    FAIL("RGVC_SIMD_AVX2 is 1 but this code was not compiled for AVX2 (rgvc_warnings lost -mavx2)");
#endif
#else
    CHECK(std::string(RGVC_SIMD_LEVEL) == "default");
#endif
#if RGVC_SIMD_AVX2 && (defined(__x86_64__) || defined(__i386__))
    __builtin_cpu_init();
    CHECK(__builtin_cpu_supports("avx2"));
#endif
}

TEST_CASE("GridGeometry accessors and voxel count", "[grid]") {
    GridGeometry2 g2(Vec2(-1.5, 2.0), 0.5, IVec2(7, 3));
    CHECK(g2.origin() == Vec2(-1.5, 2.0));
    CHECK(g2.voxelSize() == 0.5);
    CHECK(g2.resolution() == IVec2(7, 3));
    CHECK(g2.voxelCount() == 21);

    GridGeometry3 g3(Vec3(0.0), 2.0, IVec3(4, 5, 6));
    CHECK(g3.voxelCount() == 120);

    GridGeometry2 def;
    CHECK(def.voxelCount() == 1);
    CHECK(def.voxelSize() == 1.0);
    CHECK(def.toLocal(Vec2(0.25, 0.75)) == Vec2(0.25, 0.75));

    // Products near the 2^31 - 1 limit are accepted and counted in size_t.
    GridGeometry2 big(Vec2(0.0), 1.0, IVec2(46340, 46340));
    CHECK(big.voxelCount() == std::size_t(46340) * 46340);
    GridGeometry2 line(Vec2(0.0), 1.0, IVec2(std::numeric_limits<std::int32_t>::max(), 1));
    CHECK(line.voxelCount() == std::size_t(std::numeric_limits<std::int32_t>::max()));
}

TEST_CASE("GridGeometry rejects invalid input with InvalidInput naming the field", "[grid]") {
    const IVec2 r2(4, 4);
    const IVec3 r3(4, 4, 4);
    SECTION("origin must be finite on every axis") {
        for (double bad : {kNaN, kInf, -kInf}) {
            CAPTURE(bad);
            requireInvalid([&] { GridGeometry2(Vec2(bad, 0.0), 1.0, r2); }, "grid.origin");
            requireInvalid([&] { GridGeometry2(Vec2(0.0, bad), 1.0, r2); }, "grid.origin");
            requireInvalid([&] { GridGeometry3(Vec3(0.0, 0.0, bad), 1.0, r3); }, "grid.origin");
            requireInvalid([&] { GridGeometry3(Vec3(bad, 1.0, 2.0), 1.0, r3); }, "grid.origin");
        }
    }
    SECTION("voxel size must be finite and > 0") {
        for (double bad : {0.0, -0.0, -1.0, -1e-300, kNaN, kInf, -kInf}) {
            CAPTURE(bad);
            requireInvalid([&] { GridGeometry2(Vec2(0.0), bad, r2); }, "grid.voxel_size");
            requireInvalid([&] { GridGeometry3(Vec3(0.0), bad, r3); }, "grid.voxel_size");
        }
        // The far corner must be finite and distinct from the origin.
        requireInvalid([&] { GridGeometry2(Vec2(1e20, 0.0), 1e-10, IVec2(1, 1)); }, "grid.voxel_size");
        requireInvalid([&] { GridGeometry2(Vec2(0.0, 1e308), 1e308, IVec2(2, 2)); }, "grid.voxel_size");
        requireInvalid([&] { GridGeometry3(Vec3(0.0), 1e308, IVec3(1, 1, 3)); }, "grid.voxel_size");
        // Tiny but representable voxels are fine.
        CHECK_NOTHROW(GridGeometry2(Vec2(0.0), 1e-300, IVec2(3, 3)));
        CHECK_NOTHROW(GridGeometry2(Vec2(1e6), 1e-3, IVec2(1000, 1000)));
    }
    SECTION("resolution must be >= 1 on every axis") {
        for (std::int32_t bad : {0, -1, std::numeric_limits<std::int32_t>::min()}) {
            CAPTURE(bad);
            requireInvalid([&] { GridGeometry2(Vec2(0.0), 1.0, IVec2(bad, 4)); }, "grid.resolution");
            requireInvalid([&] { GridGeometry2(Vec2(0.0), 1.0, IVec2(4, bad)); }, "grid.resolution");
            requireInvalid([&] { GridGeometry3(Vec3(0.0), 1.0, IVec3(4, 4, bad)); }, "grid.resolution");
            requireInvalid([&] { GridGeometry3(Vec3(0.0), 1.0, IVec3(bad, 4, 4)); }, "grid.resolution");
        }
        CHECK_NOTHROW(GridGeometry2(Vec2(0.0), 1.0, IVec2(1, 1)));
        CHECK_NOTHROW(GridGeometry3(Vec3(0.0), 1.0, IVec3(1, 1, 1)));
    }
    SECTION("at most 2^31 - 1 voxels in all") {
        const std::int32_t maxI = std::numeric_limits<std::int32_t>::max();
        requireInvalid([&] { GridGeometry2(Vec2(0.0), 1.0, IVec2(65536, 32768)); }, "grid.resolution");
        requireInvalid([&] { GridGeometry2(Vec2(0.0), 1.0, IVec2(46341, 46341)); }, "grid.resolution");
        requireInvalid([&] { GridGeometry2(Vec2(0.0), 1.0, IVec2(maxI, 2)); }, "grid.resolution");
        requireInvalid([&] { GridGeometry2(Vec2(0.0), 1.0, IVec2(maxI, maxI)); }, "grid.resolution");
        requireInvalid([&] { GridGeometry3(Vec3(0.0), 1.0, IVec3(2048, 1024, 1024)); }, "grid.resolution");
        requireInvalid([&] { GridGeometry3(Vec3(0.0), 1.0, IVec3(1291, 1291, 1291)); }, "grid.resolution");
        requireInvalid([&] { GridGeometry3(Vec3(0.0), 1.0, IVec3(maxI, maxI, maxI)); }, "grid.resolution");
        CHECK_NOTHROW(GridGeometry2(Vec2(0.0), 1.0, IVec2(maxI, 1)));
        CHECK_NOTHROW(GridGeometry3(Vec3(0.0), 1.0, IVec3(1290, 1290, 1290)));
        CHECK_NOTHROW(GridGeometry3(Vec3(0.0), 1.0, IVec3(1, 1, maxI)));
    }
}

TEST_CASE("GridGeometry bounds convention on an exactly representable grid (2D)", "[grid]") {
    // Power-of-two voxel size and origin: every voxel face is an exact double, so the closed-box
    // convention can be checked exactly. Voxel v covers [origin + v*d, origin + (v+1)*d].
    const Vec2 o(-3.0, 2.5);
    const double d = 0.25;
    const IVec2 res(9, 6);
    GridGeometry2 g(o, d, res);
    int checked = 0;
    for (int y = 0; y < res.y; ++y)
        for (int x = 0; x < res.x; ++x) {
            const IVec2 v(x, y);
            CAPTURE(x, y);
            // Interior points (including the centre) map to v.
            for (int i = 1; i < 8; ++i)
                for (int j = 1; j < 8; ++j) {
                    Vec2 p = o + (Vec2(v) + Vec2(i / 8.0, j / 8.0)) * d;
                    if (g.voxelOf(p) != v) FAIL_CHECK("interior point " << i << "," << j << " not in its voxel");
                    ++checked;
                }
            // Lower corner: lies in the closed boxes of v and its lower neighbours; voxelOf picks v (floor).
            Vec2 lower = o + Vec2(v) * d;
            CHECK(g.voxelOf(lower) == v);
            CHECK(g.toLocal(lower) == Vec2(v));
            // Upper corner: shared with v + (1,1); floor picks the larger index.
            Vec2 upper = o + (Vec2(v) + 1.0) * d;
            CHECK(g.voxelOf(upper) == v + 1);
            // A point on the shared vertical face x = v.x + 1 (mid-height): floor picks x + 1.
            Vec2 face = o + Vec2(x + 1.0, y + 0.5) * d;
            CHECK(g.voxelOf(face) == IVec2(x + 1, y));
            // Closed boxes: the face point lies in both neighbours' boxes (checked in local units).
            Vec2 l = g.toLocal(face);
            CHECK((l.x >= x && l.x <= x + 1 && l.y >= y && l.y <= y + 1));
            CHECK((l.x >= x + 1 && l.x <= x + 2 && l.y >= y && l.y <= y + 1));
            // Centre in local units is v + 0.5.
            CHECK(g.toLocal(o + (Vec2(v) + 0.5) * d) == Vec2(v) + 0.5);
            CHECK(g.toWorld(Vec2(v) + 0.5) == o + (Vec2(v) + 0.5) * d);
        }
    CHECK(checked == 49 * res.x * res.y);

    // Points on the outer faces of the grid: the closed grid box contains them; voxelOf may leave the grid.
    CHECK(g.containsLocal(Vec2(0.0, 0.0)));
    CHECK(g.containsLocal(Vec2(res)));
    CHECK(g.containsLocal(Vec2(res.x, 0.0)));
    CHECK(g.voxelOf(o + Vec2(res) * d) == res);
    CHECK_FALSE(g.contains(g.voxelOf(o + Vec2(res) * d)));
    CHECK(g.voxelOf(o) == IVec2(0, 0));
    CHECK(g.voxelOf(o - Vec2(1e-9)) == IVec2(-1, -1));
}

TEST_CASE("GridGeometry bounds convention on an exactly representable grid (3D)", "[grid]") {
    const Vec3 o(1.0, -2.0, 0.5);
    const double d = 2.0;
    const IVec3 res(3, 4, 5);
    GridGeometry3 g(o, d, res);
    for (int z = 0; z < res.z; ++z)
        for (int y = 0; y < res.y; ++y)
            for (int x = 0; x < res.x; ++x) {
                const IVec3 v(x, y, z);
                CAPTURE(x, y, z);
                CHECK(g.voxelOf(o + (Vec3(v) + 0.5) * d) == v);
                CHECK(g.voxelOf(o + (Vec3(v) + Vec3(0.001, 0.999, 0.5)) * d) == v);
                CHECK(g.voxelOf(o + Vec3(v) * d) == v);
                CHECK(g.voxelOf(o + (Vec3(v) + 1.0) * d) == v + 1);
                CHECK(g.contains(v));
                CHECK(g.containsLocal(Vec3(v)));
                CHECK(g.containsLocal(Vec3(v) + 1.0));
            }
}

TEST_CASE("GridGeometry contains / containsLocal are the closed grid", "[grid]") {
    GridGeometry2 g(Vec2(0.0), 1.0, IVec2(5, 3));
    CHECK(g.contains(IVec2(0, 0)));
    CHECK(g.contains(IVec2(4, 2)));
    CHECK_FALSE(g.contains(IVec2(5, 2)));
    CHECK_FALSE(g.contains(IVec2(4, 3)));
    CHECK_FALSE(g.contains(IVec2(-1, 0)));
    CHECK_FALSE(g.contains(IVec2(0, -1)));
    CHECK(g.containsLocal(Vec2(5.0, 3.0)));
    CHECK(g.containsLocal(Vec2(0.0, 1.5)));
    CHECK_FALSE(g.containsLocal(Vec2(5.0 + 1e-12, 1.0)));
    CHECK_FALSE(g.containsLocal(Vec2(-1e-300, 1.0)));
    CHECK_FALSE(g.containsLocal(Vec2(kNaN, 1.0)));
    CHECK_FALSE(g.containsLocal(Vec2(1.0, kInf)));

    GridGeometry3 g3(Vec3(0.0), 1.0, IVec3(2, 3, 4));
    CHECK(g3.contains(IVec3(1, 2, 3)));
    CHECK_FALSE(g3.contains(IVec3(1, 2, 4)));
    CHECK(g3.containsLocal(Vec3(2.0, 3.0, 4.0)));
    CHECK_FALSE(g3.containsLocal(Vec3(2.0, 3.0, 4.0000001)));
}

TEST_CASE("GridGeometry voxelOfLocal floors and clamps to +-2^30", "[grid]") {
    CHECK(GridGeometry2::voxelOfLocal(Vec2(0.0, 0.999)) == IVec2(0, 0));
    CHECK(GridGeometry2::voxelOfLocal(Vec2(-0.5, -1.0)) == IVec2(-1, -1));
    CHECK(GridGeometry2::voxelOfLocal(Vec2(-1e-300, 1.0)) == IVec2(-1, 1));
    CHECK(GridGeometry2::voxelOfLocal(Vec2(1e12, -1e12)) == IVec2(1073741824, -1073741824));
    CHECK(GridGeometry2::voxelOfLocal(Vec2(kInf, -kInf)) == IVec2(1073741824, -1073741824));
    CHECK(GridGeometry3::voxelOfLocal(Vec3(3.5, -7.25, 1e300)) == IVec3(3, -8, 1073741824));
}

TEST_CASE("GridGeometry linearIndex is row-major, x fastest, and a bijection", "[grid]") {
    SECTION("2D") {
        GridGeometry2 g(Vec2(0.0), 1.0, IVec2(7, 5));
        std::vector<int> hits(g.voxelCount(), 0);
        for (int y = 0; y < 5; ++y)
            for (int x = 0; x < 7; ++x) {
                std::uint32_t i = g.linearIndex(IVec2(x, y));
                CHECK(i == std::uint32_t(x + 7 * y));
                REQUIRE(i < hits.size());
                ++hits[i];
            }
        for (int h : hits) CHECK(h == 1);
    }
    SECTION("3D") {
        GridGeometry3 g(Vec3(0.0), 1.0, IVec3(3, 4, 5));
        std::vector<int> hits(g.voxelCount(), 0);
        for (int z = 0; z < 5; ++z)
            for (int y = 0; y < 4; ++y)
                for (int x = 0; x < 3; ++x) {
                    std::uint32_t i = g.linearIndex(IVec3(x, y, z));
                    CHECK(i == std::uint32_t(x + 3 * (y + 4 * z)));
                    REQUIRE(i < hits.size());
                    ++hits[i];
                }
        for (int h : hits) CHECK(h == 1);
    }
    SECTION("largest grids: the last voxel has index count - 1") {
        GridGeometry2 g2(Vec2(0.0), 1.0, IVec2(46340, 46340));
        CHECK(g2.linearIndex(IVec2(46339, 46339)) == std::uint32_t(g2.voxelCount() - 1));
        CHECK(g2.linearIndex(IVec2(46339, 0)) == 46339u);
        CHECK(g2.linearIndex(IVec2(0, 1)) == 46340u);
        GridGeometry3 g3(Vec3(0.0), 1.0, IVec3(1290, 1290, 1290));
        CHECK(g3.linearIndex(IVec3(1289, 1289, 1289)) == std::uint32_t(g3.voxelCount() - 1));
        CHECK(g3.linearIndex(IVec3(0, 0, 1)) == 1290u * 1290u);
        const std::int32_t maxI = std::numeric_limits<std::int32_t>::max();
        GridGeometry2 line(Vec2(0.0), 1.0, IVec2(1, maxI));
        CHECK(line.linearIndex(IVec2(0, maxI - 1)) == std::uint32_t(maxI - 1));
    }
}

TEST_CASE("GridGeometry world <-> local mapping on random grids", "[grid]") {
    const std::uint64_t seed = 0x9a1d5eedULL;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    int failures = 0;
    for (int iter = 0; iter < 2000; ++iter) {
        const Vec2 o((uni(rng) - 0.5) * std::pow(10.0, 6 * uni(rng)), (uni(rng) - 0.5) * std::pow(10.0, 6 * uni(rng)));
        const double d = std::pow(10.0, -3 + 5 * uni(rng));
        const IVec2 res(1 + int(uni(rng) * 300), 1 + int(uni(rng) * 300));
        GridGeometry2 g(o, d, res);
        for (int k = 0; k < 20; ++k) {
            // A random point in (or slightly around) the grid.
            Vec2 l(uni(rng) * (res.x + 2) - 1, uni(rng) * (res.y + 2) - 1);
            Vec2 w = o + l * d;
            IVec2 v = g.voxelOf(w);
            // Reference: the world point's local coordinate in extended precision lies in v's closed box
            // (up to the rounding of the mapping, far below a voxel).
            for (int a = 0; a < 2; ++a) {
                long double ref = refLocal(w[a], o[a], d);
                long double tol = 1e-9L * (1 + std::fabs((long double)o[a] / d));
                if (!(ref >= v[a] - tol && ref <= v[a] + 1 + tol)) {
                    if (failures++ < 5)
                        FAIL_CHECK("seed " << seed << " iter " << iter << " axis " << a << ": world " << w[a]
                                           << " local " << (double)ref << " mapped to voxel " << v[a]);
                }
            }
            // Round trips.
            Vec2 back = g.toLocal(g.toWorld(l));
            for (int a = 0; a < 2; ++a) {
                double tol = 1e-12 * (1 + std::abs(l[a]) + std::abs(o[a]) / d);
                if (!(std::abs(back[a] - l[a]) <= tol)) {
                    if (failures++ < 5)
                        FAIL_CHECK("seed " << seed << " iter " << iter << " round trip " << l[a] << " -> " << back[a]);
                }
            }
            double len = uni(rng) * 100;
            if (!(std::abs(g.toLocalLength(len) - len / d) <= 1e-14 * len / d)) ++failures;
        }
    }
    CHECK(failures == 0);
}

TEST_CASE("GridGeometry with large offsets: origin 1e6, voxel 1e-3", "[grid]") {
    const std::uint64_t seed = 0x0ff5e7ULL;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    SECTION("2D") {
        const Vec2 o(1e6, -1e6);
        const double d = 1e-3;
        const IVec2 res(1000, 1000);
        GridGeometry2 g(o, d, res);
        int failures = 0;
        for (int k = 0; k < 20000; ++k) {
            IVec2 v(int(uni(rng) * res.x), int(uni(rng) * res.y));
            // Fractions at least 1e-3 voxel from any face: the world point is representable to ~1e-7 voxel.
            Vec2 f(0.001 + 0.998 * uni(rng), 0.001 + 0.998 * uni(rng));
            Vec2 w = o + (Vec2(v) + f) * d;
            if (g.voxelOf(w) != v) {
                if (failures++ < 5) FAIL_CHECK("voxel " << v.x << "," << v.y << " frac " << f.x << "," << f.y);
            }
            Vec2 l = g.toLocal(w);
            for (int a = 0; a < 2; ++a) {
                long double ref = refLocal(w[a], o[a], d);
                if (!(std::fabs((long double)l[a] - ref) <= 1e-9L)) ++failures;  // ~1e-13 expected
                if (!(std::abs(l[a] - (v[a] + f[a])) <= 1e-6)) ++failures;       // world rounding ~1e-7
            }
            Vec2 back = g.toLocal(g.toWorld(Vec2(v) + f));
            if (!(std::abs(back.x - (v.x + f.x)) <= 1e-6 && std::abs(back.y - (v.y + f.y)) <= 1e-6)) ++failures;
            // The centre of every voxel maps back to it, and is 0.5 voxel from both faces.
            Vec2 c = g.toWorld(Vec2(v) + 0.5);
            if (g.voxelOf(c) != v) ++failures;
        }
        CHECK(failures == 0);
        CHECK(g.voxelOf(o) == IVec2(0, 0));
        CHECK(g.voxelOf(Vec2(o.x - 1e-6, o.y)) == IVec2(-1, 0)); // one thousandth of a voxel below the grid
        CHECK(g.toLocalLength(1.0) == Approx(1000.0).epsilon(1e-14));
    }
    SECTION("3D") {
        const Vec3 o(1e6, 1e6, -1e6);
        const double d = 1e-3;
        const IVec3 res(100, 200, 50);
        GridGeometry3 g(o, d, res);
        int failures = 0;
        for (int k = 0; k < 20000; ++k) {
            IVec3 v(int(uni(rng) * res.x), int(uni(rng) * res.y), int(uni(rng) * res.z));
            Vec3 f(0.001 + 0.998 * uni(rng), 0.001 + 0.998 * uni(rng), 0.001 + 0.998 * uni(rng));
            Vec3 w = o + (Vec3(v) + f) * d;
            if (g.voxelOf(w) != v) ++failures;
            if (!g.contains(g.voxelOf(w))) ++failures;
            Vec3 l = g.toLocal(w);
            for (int a = 0; a < 3; ++a)
                if (!(std::abs(l[a] - (v[a] + f[a])) <= 1e-6)) ++failures;
        }
        CHECK(failures == 0);
    }
}

// ---------------------------------------------------------------------------------------------------
// DenseStorage: the grid matrices' dense backend.

TEST_CASE("DenseStorage opaque counts, frame stamps and id lists", "[grid]") {
    GridGeometry2 g(Vec2(0.0), 1.0, IVec2(8, 8));
    DenseStorage<2> s(g);
    const VoxelKey k = g.linearIndex(IVec2(3, 4));
    const VoxelKey k2 = g.linearIndex(IVec2(7, 7));

    SECTION("opaque is a count") {
        CHECK_FALSE(s.opaque(k));
        s.addOpaque(k, 1);
        s.addOpaque(k, 1);
        CHECK(s.opaque(k));
        s.addOpaque(k, -1);
        CHECK(s.opaque(k));
        s.addOpaque(k, -1);
        CHECK_FALSE(s.opaque(k));
        CHECK_FALSE(s.opaque(k2));
    }
    SECTION("stamps: set for one frame only, reset clears") {
        CHECK_FALSE(s.occluded(k, 1));
        s.setOccluded(k, 1);
        s.setUsed(k, 1);
        s.setVisited(k2, 1);
        CHECK(s.occluded(k, 1));
        CHECK(s.used(k, 1));
        CHECK(s.visited(k2, 1));
        CHECK_FALSE(s.occluded(k, 2));
        CHECK_FALSE(s.used(k, 2));
        CHECK_FALSE(s.visited(k2, 2));
        CHECK_FALSE(s.occluded(k2, 1));
        s.setOccluded(k, DenseStorage<2>::kMaxStamp);
        CHECK(s.occluded(k, DenseStorage<2>::kMaxStamp));
        s.resetStamps();
        CHECK_FALSE(s.occluded(k, DenseStorage<2>::kMaxStamp));
        CHECK_FALSE(s.occluded(k, 1));
        CHECK_FALSE(s.used(k, 1));
        CHECK_FALSE(s.visited(k2, 1));
    }
    SECTION("id lists against a brute-force multiset") {
        std::mt19937_64 rng(42);
        std::vector<std::multiset<ObjectSlot>> ref(g.voxelCount());
        std::size_t total = 0;
        for (int step = 0; step < 20000; ++step) {
            VoxelKey key = VoxelKey(rng() % g.voxelCount());
            ObjectSlot o = ObjectSlot(rng() % 6);
            if (rng() % 3 != 0) {
                s.addId(key, o);
                ref[key].insert(o);
                ++total;
            } else {
                s.removeId(key, o);
                auto it = ref[key].find(o);
                if (it != ref[key].end()) {
                    ref[key].erase(it);
                    --total;
                }
            }
        }
        CHECK(s.idCount() == total);
        int mismatches = 0;
        for (VoxelKey key = 0; key < g.voxelCount(); ++key) {
            std::multiset<ObjectSlot> got;
            s.forEachId(key, [&](ObjectSlot o) { got.insert(o); });
            if (got != ref[key]) ++mismatches;
            if (s.hasIds(key) != !ref[key].empty()) ++mismatches;
        }
        CHECK(mismatches == 0);
        // Removing everything leaves no ids; removing an absent id is a no-op.
        for (VoxelKey key = 0; key < g.voxelCount(); ++key)
            for (ObjectSlot o : std::multiset<ObjectSlot>(ref[key])) s.removeId(key, o);
        s.removeId(k, 99);
        CHECK(s.idCount() == 0);
        for (VoxelKey key = 0; key < g.voxelCount(); ++key) CHECK_FALSE(s.hasIds(key));
    }
}

TEST_CASE("recommendVoxelSize: the surface-weighted median of the objects' opaque sizes, within the limits", "[grid]") {
    const Box<3> world{{0, 0, 0}, {128, 64, 128}};
    // Boxes only: a box of smallest extent e is opaque down to e / 2.
    const std::vector<Shape<3>> walls = {Box<3>{{0, 0, 0}, {40, 20, 2}}, Box<3>{{50, 0, 0}, {90, 20, 2}}};
    CHECK(recommendVoxelSize<3>(walls, world) == Approx(1.0));
    // Big buildings and many small spheres: the buildings' surface outweighs the spheres'.
    std::vector<Shape<3>> city;
    for (int b = 0; b < 20; ++b) city.push_back(Box<3>{{6.0 * b, 0, 0}, {6.0 * b + 4, 30, 8}});
    for (int s = 0; s < 2000; ++s) city.push_back(Ball<3>{{1.0 + s % 120, 40, 1.0 + s / 20}, 0.3});
    CHECK(recommendVoxelSize<3>(city, world) == Approx(2.0)); // the buildings' 4-unit side / 2
    // Spheres alone: radius / sqrt(3).
    const std::vector<Shape<3>> balls(10, Ball<3>{{10, 10, 10}, std::sqrt(3.0)});
    CHECK(recommendVoxelSize<3>(balls, world) == Approx(1.0));
    // The limits: a voxel budget (tiny objects in a big world) and a minimum of voxels per axis (one huge wall).
    const std::vector<Shape<3>> dust(5, Ball<3>{{10, 10, 10}, 1e-3});
    const double budget = std::cbrt(128.0 * 64 * 128 / (16.0 * 1024 * 1024));
    CHECK(recommendVoxelSize<3>(dust, world) == Approx(budget));
    const std::vector<Shape<3>> slab = {Box<3>{{0, 0, 0}, {128, 60, 128}}};
    CHECK(recommendVoxelSize<3>(slab, world) == Approx(64.0 / 8));
    CHECK(recommendVoxelSize<3>(std::vector<Shape<3>>{}, world) == Approx(8.0));
    // 2D: perimeter weights, the same rule.
    const std::vector<Shape<2>> flat = {Box<2>{{0, 0}, {30, 3}}, ConvexPolygon{{{40, 40}, {50, 40}, {45, 50}}}};
    const double v2 = recommendVoxelSize<2>(flat, Box<2>{{0, 0}, {256, 256}});
    CHECK(v2 > 1.4);
    CHECK(v2 <= 5.0);
    // Bad input names its field.
    auto field = [](auto f) {
        try {
            f();
        } catch (const InvalidInput& e) {
            return e.field();
        }
        return std::string("<accepted>");
    };
    CHECK(field([&] { recommendVoxelSize<3>(walls, Box<3>{{0, 0, 0}, {0, 1, 1}}); }) == "world");
    CHECK(field([&] { recommendVoxelSize<3>(walls, Box<3>{{0, 0, 0}, {INFINITY, 1, 1}}); }) == "world");
    CHECK(field([&] { recommendVoxelSize<3>(std::vector<Shape<3>>{Ball<3>{{0, 0, 0}, -1}}, world); }) == "shapes[0].radius");
    CHECK(field([&] { recommendVoxelSize<3>(walls, world, {.maxVoxels = 0}); }) == "options.maxVoxels");
    CHECK(field([&] { recommendVoxelSize<3>(walls, world, {.minVoxelsPerAxis = NAN}); }) == "options.minVoxelsPerAxis");
}

// ---------------------------------------------------------------------------------------------------
// Convex polytopes (ConvexPolytope.hpp): the hull, oriented boxes, erosion, validation.

TEST_CASE("makeConvexHull: every point inside, every vertex a point, a closed 2-manifold", "[grid][polytope]") {
    std::mt19937_64 rng(1234);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int trial = 0; trial < 200; ++trial) {
        const int n = trial < 100 ? 4 + trial % 40 : 50 + 20 * (trial % 10);
        const bool sphere = trial % 3 == 0, lattice = trial % 7 == 0;
        const Vec3 offset = trial % 5 == 0 ? Vec3(1e6, -3e5, 2e4) : Vec3(0.0);
        std::vector<Vec3> pts;
        for (int k = 0; k < n; ++k) {
            Vec3 q(u(rng), u(rng), u(rng));
            if (sphere) q = safeNormalize<3>(q);
            if (lattice) q = glm::round(q * 3.0);
            pts.push_back(offset + q * 10.0);
        }
        ConvexPolytope p;
        try {
            p = makeConvexHull(pts, "pts");
        } catch (const InvalidInput& e) {
            INFO(e.what());
            CHECK(lattice); // only a lattice draw can be flat
            continue;
        }
        INFO("trial " << trial);
        CHECK_NOTHROW(validatePolytope(p, "p"));
        const double tol = 1e-12 * (1e6 + 10);
        for (const Vec3& q : pts)
            for (const HalfSpace& h : p.planes) CHECK(glm::dot(h.normal, q) <= h.offset + tol);
        for (const Vec3& v : p.vertices) CHECK(std::find(pts.begin(), pts.end(), v) != pts.end());
        // Closed: every edge in two triangles; Euler V - E + F = 2.
        CHECK(p.edges.size() * 2 == p.triangles.size() * 3);
        CHECK(p.vertices.size() + p.triangles.size() - p.edges.size() == 2);
        // Points on a sphere are all vertices (none is inside the others' hull).
        if (sphere && !lattice && offset == Vec3(0.0)) CHECK(p.vertices.size() == pts.size());
    }
    // A cube's corners and its centre: 8 vertices, 6 planes (coplanar triangles merged).
    std::vector<Vec3> cube;
    for (int k = 0; k < 8; ++k) cube.push_back(Vec3(k & 1, (k >> 1) & 1, (k >> 2) & 1));
    cube.push_back(Vec3(0.5));
    cube.push_back(Vec3(0.5, 0.5, 1)); // on a face
    const ConvexPolytope c = makeConvexHull(cube, "cube");
    CHECK(c.vertices.size() == 8);
    CHECK(c.planes.size() == 6);
    CHECK(c.boundsMin == Vec3(0.0));
    CHECK(c.boundsMax == Vec3(1.0));
    // 2,000 points on a sphere (the cost is O(points x facets)).
    std::vector<Vec3> many;
    for (int k = 0; k < 2000; ++k) many.push_back(safeNormalize<3>(Vec3(u(rng), u(rng), u(rng))));
    const auto t0 = std::chrono::steady_clock::now();
    const ConvexPolytope big = makeConvexHull(many, "many");
    std::printf("hull of 2,000 points on a sphere: %zu vertices, %zu planes, %.0f ms\n", big.vertices.size(), big.planes.size(),
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    CHECK(big.vertices.size() == 2000);
}

TEST_CASE("makeConvexHull and makeOrientedBox: bad input is a clear InvalidInput", "[grid][polytope]") {
    auto fails = [](auto&& f, const std::string& field, const std::string& part) {
        try {
            f();
        } catch (const InvalidInput& e) {
            INFO(e.what());
            CHECK(e.field() == field);
            CHECK(std::string(e.what()).find(part) != std::string::npos);
            return;
        }
        FAIL("accepted");
    };
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    auto hull = [](std::vector<Vec3> p) { return [p] { makeConvexHull(p, "h"); }; };
    fails(hull({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}), "h", "at least 4");
    fails(hull({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {3, 2, 0}}), "h", "one plane");
    fails(hull({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 1e-12}}), "h", "one plane"); // flat within 1e-9 of its extent
    fails(hull({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {-1, -1, -1}}), "h", "one line");
    fails(hull({{1, 1, 1}, {1, 1, 1}, {1, 1, 1}, {1, 1, 1}}), "h", "coincide");
    fails(hull({{0, 0, 0}, {1, 0, 0}, {0, nan, 0}, {0, 0, 1}}), "h[2]", "finite");
    fails(hull({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, inf}}), "h[3]", "finite");
    fails(hull({{0, 0, 0}, {1e300, 0, 0}, {0, 1e300, 0}, {0, 0, 1e300}}), "h", "overflows");
    auto obb = [](Vec3 c, Vec3 h, std::array<double, 4> q) { return [=] { makeOrientedBox(c, h, q, "o"); }; };
    fails(obb({0, 0, 0}, {1, 1, 1}, {0, 0, 0, 1.01}), "o.rotation", "unit quaternion");
    fails(obb({0, 0, 0}, {1, 1, 1}, {0, 0, 0, 0}), "o.rotation", "unit quaternion");
    fails(obb({0, 0, 0}, {1, 1, 1}, {0, nan, 0, 1}), "o.rotation", "finite");
    fails(obb({0, 0, 0}, {1, 0, 1}, {0, 0, 0, 1}), "o.half_extents", "> 0");
    fails(obb({0, 0, 0}, {1, -2, 1}, {0, 0, 0, 1}), "o.half_extents", "> 0");
    fails(obb({0, inf, 0}, {1, 1, 1}, {0, 0, 0, 1}), "o.center", "finite");
    fails(obb({0, 0, 0}, {1.5e308, 1.5e308, 1}, {0, 0, 0.3826834323650898, 0.9238795325112867}), "o.half_extents", "overflow");
    // Within 1e-5 of unit: normalised.
    const ConvexPolytope ok = makeOrientedBox({0, 0, 0}, {1, 2, 3}, {0, 0, 0, 1.000009}, "o");
    CHECK(ok.boundsMax.z == Approx(3));
    // A polytope assembled by hand must be consistent (validateShape).
    ConvexPolytope bad = ok;
    bad.planes[0].offset -= 1; // a vertex now outside a plane
    Shape<3> s = bad;
    fails([&] { validateShape<3>(s, "obj"); }, "obj.planes", "inside every plane");
    bad = ok;
    bad.planes[1].normal *= 2;
    s = bad;
    fails([&] { validateShape<3>(s, "obj"); }, "obj.planes", "unit");
    bad = ok;
    bad.triangles[0][1] = 99;
    s = bad;
    fails([&] { validateShape<3>(s, "obj"); }, "obj.triangles", "out of range");
    bad = ok;
    bad.vertices[2].x = nan;
    s = bad;
    fails([&] { validateShape<3>(s, "obj"); }, "obj.points", "finite");
}

TEST_CASE("oriented boxes: corners, planes, bounds, erosion moves every plane in exactly", "[grid][polytope]") {
    const double s2 = std::sqrt(0.5);
    // 90 degrees about z: x -> y, y -> -x.
    const ConvexPolytope p = makeOrientedBox({1, 2, 3}, {1, 2, 3}, {0, 0, s2, s2}, "o");
    CHECK(p.vertices.size() == 8);
    CHECK(p.planes.size() == 6);
    CHECK(p.boundsMin.x == Approx(-1));
    CHECK(p.boundsMax.x == Approx(3));
    CHECK(p.boundsMin.y == Approx(1));
    CHECK(p.boundsMax.y == Approx(3));
    CHECK(p.boundsMax.z == Approx(6));
    const auto cols = rotationColumns({0, 0, s2, s2});
    CHECK(cols[0].y == Approx(1));
    CHECK(cols[1].x == Approx(-1));
    // Erosion by 0.5: the box of half extents (0.5, 1.5, 2.5), same centre and rotation.
    Shape<3> in;
    REQUIRE(insetShape<3>(p, 0.5, in));
    const ConvexPolytope& e = std::get<ConvexPolytope>(in);
    const ConvexPolytope expect = makeOrientedBox({1, 2, 3}, {0.5, 1.5, 2.5}, {0, 0, s2, s2}, "o");
    CHECK(e.vertices.size() == 8);
    for (int a = 0; a < 3; ++a) {
        CHECK(e.boundsMin[a] == Approx(expect.boundsMin[a]).margin(1e-12));
        CHECK(e.boundsMax[a] == Approx(expect.boundsMax[a]).margin(1e-12));
    }
    // A tetrahedron eroded: every plane moved by d, the vertices where three of them meet.
    const ConvexPolytope t = makeConvexHull(std::vector<Vec3>{{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {0, 0, 4}}, "t");
    Shape<3> ti;
    REQUIRE(insetShape<3>(t, 0.25, ti));
    const ConvexPolytope& te = std::get<ConvexPolytope>(ti);
    for (const Vec3& v : te.vertices)
        for (const HalfSpace& h : t.planes) CHECK(glm::dot(h.normal, v) <= h.offset - 0.25 + 1e-12);
    CHECK(te.boundsMin.x == Approx(0.25));
    // Nothing left: false.
    CHECK_FALSE(insetShape<3>(t, 2.0, ti));
    // Translation moves vertices, planes and bounds.
    const ConvexPolytope moved = translated(t, Vec3(1, 2, 3));
    CHECK(moved.boundsMin == Vec3(1, 2, 3));
    for (const HalfSpace& h : moved.planes) CHECK(glm::dot(h.normal, Vec3(1, 2, 3) + Vec3(0.5)) <= h.offset);
}

// The occlusion buffer's pass orders the PVS with sortByDistance and relies on it giving exactly
// std::sort's order of the pairs (ties by index), so that draws, tests and the PVS match the comparison
// sort's: checked on sizes across the small-input cut-off, with ties, negative zero, negative and huge
// distances, keys that share their high bits (the skipped passes) and distances that agree in the
// 32 bits the radix passes read (the insertion pass).
TEST_CASE("sortByDistance gives std::sort's order of (distance, index) pairs", "[grid]") {
    std::mt19937_64 rng(20261206);
    std::vector<std::pair<double, std::uint32_t>> pairs, scratch, expect;
    for (int trial = 0; trial < 400; ++trial) {
        const std::size_t n = std::size_t(rng() % 3000);
        const int kind = trial % 4;
        pairs.clear();
        std::uniform_real_distribution<double> uni(0.0, 150.0);
        for (std::size_t i = 0; i < n; ++i) {
            double d = uni(rng);
            if (kind == 1) d = std::floor(d / 10.0);                         // many ties
            if (kind == 2) d = (rng() % 5 == 0) ? -0.0 : d - 75.0;           // negative, -0.0 against 0.0
            if (kind == 2 && rng() % 7 == 0) d = 0.0;
            if (kind == 3) d = 64.0 + std::ldexp(double(rng() % 1024), -40 + int(rng() % 30)); // low bits
            if (trial == 5 && i == 3) d = kInf;
            if (trial == 9 && i == 7) d = 1e300;
            pairs.push_back({d, std::uint32_t(i * 3 + 1)});                  // increasing, not contiguous
        }
        expect = pairs;
        std::sort(expect.begin(), expect.end());
        sortByDistance(pairs, scratch);
        INFO("trial " << trial << ", n " << n << ", seed 20261206");
        REQUIRE(pairs.size() == expect.size());
        std::size_t wrong = 0;
        for (std::size_t i = 0; i < n; ++i) wrong += pairs[i].second != expect[i].second;
        REQUIRE(wrong == 0);
    }
    CHECK(distanceSortKey(-0.0) == distanceSortKey(0.0));
    CHECK(distanceSortKey(-1.0) < distanceSortKey(-0.5));
    CHECK(distanceSortKey(-kInf) < distanceSortKey(-1e300));
    CHECK(distanceSortKey(1e300) < distanceSortKey(kInf));
}
