// ConservativeRaster in 3D (balls and boxes) against the brute-force oracle of RasterOracle.hpp, on
// thousands of random and adversarial shapes. Tag: [raster].
#include "RasterOracle.hpp"

using namespace raster_oracle;

TEST_CASE("Raster: random 3D balls and boxes against brute force", "[raster]") {
    const std::uint64_t seed = 0x3D3D3DULL;
    auto t0 = std::chrono::steady_clock::now();
    Stats st;
    int failures = 0;
    const int count = 3000;
    for (int i = 0; i < count; ++i) {
        Gen g(seed * 1000003ULL + std::uint64_t(i));
        IVec3 res(g.irange(1, 12), g.irange(1, 12), g.irange(1, 12));
        const int n = std::max({res.x, res.y, res.z});
        Shape<3> s;
        if (g.chance(0.5)) {
            Ball<3> b;
            for (int a = 0; a < 3; ++a) b.center[a] = g.coord(res[a]);
            double q = g.uni();
            if (q < 0.15) b.radius = std::array<double, 6>{0.5, 1, 2, 3, 7, 9}[g.irange(0, 5)]; // 1-2-2-3, 2-3-6-7...
            else if (q < 0.3) b.radius = g.logUni(1e-4, 0.3);
            else if (q < 0.35) b.radius = 2.0 * n + g.uni(0, 20);
            else b.radius = g.uni(0.05, 0.8 * n + 1);
            s = b;
        } else {
            Box<3> b;
            bool integral = g.chance(0.4);
            for (int a = 0; a < 3; ++a) {
                double lo = g.coord(res[a]);
                double q = g.uni();
                double w = q < 0.2 ? g.logUni(1e-7, 1e-2) : (q < 0.3 ? 2.0 * n + g.uni(0, 10) : g.uni(0.01, 0.7 * n + 1));
                if (integral) {
                    lo = std::round(lo);
                    if (w >= 1) w = std::round(w);
                }
                b.min[a] = lo;
                b.max[a] = lo + w;
            }
            s = b;
        }
        if (g.chance(0.3)) s = translated<3>(s, Vec3(g.jitter(), g.jitter(), g.jitter()));
        validateShape<3>(s, "test");
        std::string err = checkShape3(s, res, st);
        if (!err.empty() && failures++ < 5)
            FAIL_CHECK("3D seed=" << seed << " shape #" << i << " grid " << res.x << "x" << res.y << "x" << res.z
                                  << "\n  " << describe(s) << "\n  " << err);
    }
    CHECK(failures == 0);
    printStats("3D", st, secondsSince(t0));
    CHECK(st.shapes == count);
    CHECK(st.inner > 10000);
    CHECK(st.contact > 1000);
}

TEST_CASE("Raster: 3D fixed cases", "[raster]") {
    const IVec3 res(6, 6, 6);
    auto collect = [&](bool innerSet, const Shape<3>& s) {
        std::set<std::array<int, 3>> out;
        auto fn = [&](const IVec3& v) { out.insert({v.x, v.y, v.z}); };
        if (innerSet) forEachInnerVoxel<3>(s, res, fn);
        else forEachTouchedVoxel<3>(s, res, fn);
        return out;
    };
    // Tiny sphere on a voxel corner touches the 8 voxels around it.
    auto t = collect(false, Ball<3>{Vec3(3, 3, 3), 1e-4});
    CHECK(t.size() == 8);
    CHECK(t.count({2, 2, 2}));
    CHECK(t.count({3, 3, 3}));
    CHECK(collect(true, Ball<3>{Vec3(3, 3, 3), 1e-4}).empty());
    // Sphere of radius 3 centred on (3,3,3): the corner (1,1,1)+... (dx,dy,dz) = (1,2,2) lies on it, so the
    // voxel [4,5]x[5,6]x[5,6] has its nearest corner (4,5,5) on the sphere: touched.
    auto t3 = collect(false, Ball<3>{Vec3(3, 3, 3), 3});
    CHECK(t3.count({4, 5, 5}));
    CHECK_FALSE(t3.count({5, 5, 5})); // nearest corner (5,5,5): sqrt(12) > 3
    // Unit box on a voxel: touched is the 3x3x3 block around it.
    auto tb = collect(false, Box<3>{Vec3(2, 2, 2), Vec3(3, 3, 3)});
    CHECK(tb.size() == 27);
    // A box covering the grid.
    CHECK(collect(true, Box<3>{Vec3(-1), Vec3(7)}).size() == 216);
    CHECK(extendsOutsideGrid<3>(Box<3>{Vec3(-1), Vec3(7)}, res));
    CHECK_FALSE(extendsOutsideGrid<3>(Box<3>{Vec3(0), Vec3(6)}, res));
    CHECK(extendsOutsideGrid<3>(Ball<3>{Vec3(3), 3.0000001}, res));
    CHECK_FALSE(extendsOutsideGrid<3>(Ball<3>{Vec3(3), 3}, res));
}

// ---------------------------------------------------------------------------------------------------

// What RowFootprint relies on: one span per row, rows in strictly increasing linear order, spans inside
// the grid, and exactly the voxels of forEachTouchedVoxel / forEachInnerVoxel (2D polygons included).
template <int D> static void checkRows(const Shape<D>& s, const IVec<D>& res, std::uint64_t seed) {
    const GridGeometry<D> grid(Vec<D>(0.0), 1.0, res);
    for (bool inner : {false, true}) {
        std::vector<std::uint32_t> fromRows, fromVoxels;
        std::int64_t lastRow = -1;
        std::size_t bad = 0;
        auto onRow = [&](const IVec<D>& row, std::int32_t x0, std::int32_t x1) {
            const std::int64_t key = grid.linearIndex(row);
            bad += row.x != 0 || key <= lastRow || x0 < 0 || x1 >= res.x || x0 > x1;
            lastRow = key;
            for (std::int32_t x = x0; x <= x1; ++x) fromRows.push_back(std::uint32_t(key + x));
        };
        auto onVoxel = [&](const IVec<D>& v) { fromVoxels.push_back(grid.linearIndex(v)); };
        if (inner) {
            forEachInnerRow<D>(s, res, onRow);
            forEachInnerVoxel<D>(s, res, onVoxel);
        } else {
            forEachTouchedRow<D>(s, res, onRow);
            forEachTouchedVoxel<D>(s, res, onVoxel);
        }
        INFO("seed " << seed << (inner ? " inner" : " touched"));
        CHECK(bad == 0);
        CHECK(fromRows == fromVoxels);
    }
}

TEST_CASE("Raster: row spans (2D and 3D) are ordered, one per row, and equal the voxel sets", "[raster]") {
    for (std::uint64_t i = 0; i < 400; ++i) {
        const std::uint64_t seed = 0x5EA5ULL + i;
        Gen g(seed);
        IVec3 res(g.irange(1, 12), g.irange(1, 12), g.irange(1, 12));
        Vec3 c(g.uni(-2, res.x + 2), g.uni(-2, res.y + 2), g.uni(-2, res.z + 2));
        const double r = g.uni(0.05, 6);
        checkRows<3>(Ball<3>{c, r}, res, seed);
        checkRows<3>(Box<3>{c - r * 0.7, c + Vec3(r, 0.5 * r, 0.3 * r)}, res, seed);
        const IVec2 res2(res.x, res.y);
        const Vec2 c2(c.x, c.y);
        checkRows<2>(Ball<2>{c2, r}, res2, seed);
        checkRows<2>(Box<2>{c2 - r, c2 + 0.5 * r}, res2, seed);
        checkRows<2>(ConvexPolygon{{c2, c2 + Vec2{r, 0.3}, c2 + Vec2{0.2, r}}}, res2, seed);
    }
}
