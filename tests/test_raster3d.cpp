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

// ---------------------------------------------------------------------------------------------------
// Convex polytopes: oriented boxes and hulls (ConvexPolytope.hpp, PolytopeRaster.hpp) against the
// brute-force polytope oracle (RasterOracle.hpp: facets from every triple of points, SAT distances).

namespace {

std::array<double, 4> randomQuaternion(Gen& g) {
    const double q = g.uni();
    if (q < 0.2) return {0, 0, 0, 1}; // axis-aligned: faces on voxel boundaries when the numbers are integral
    if (q < 0.35) { // a quarter turn about an axis: axis-aligned again, through rounding of sqrt(1/2)
        std::array<double, 4> r{0, 0, 0, std::sqrt(0.5)};
        r[std::size_t(g.irange(0, 2))] = std::sqrt(0.5);
        return r;
    }
    std::array<double, 4> r;
    double n2 = 0;
    do {
        n2 = 0;
        for (double& c : r) {
            c = g.uni(-1, 1);
            n2 += c * c;
        }
    } while (n2 < 0.01 || n2 > 1);
    for (double& c : r) c /= std::sqrt(n2);
    return r;
}

/// A random polytope and the points it is the hull of (the oracle's input).
Shape<3> randomPolytope(Gen& g, IVec3 res, std::vector<Vec3>& points) {
    const int n = std::max({res.x, res.y, res.z});
    Vec3 c;
    for (int a = 0; a < 3; ++a) c[a] = g.coord(res[a]);
    for (;;) {
        try {
            if (g.chance(0.5)) {
                Vec3 h;
                const bool integral = g.chance(0.4);
                for (int a = 0; a < 3; ++a) {
                    const double q = g.uni();
                    h[a] = q < 0.15 ? g.logUni(1e-6, 1e-2) : (q < 0.25 ? n + g.uni(0, 5) : g.uni(0.05, 0.4 * n + 1));
                    if (integral) h[a] = std::max(0.5, std::round(2 * h[a]) / 2);
                }
                if (integral) c = glm::round(c);
                ConvexPolytope p = makeOrientedBox(c, h, randomQuaternion(g), "test");
                points = p.vertices;
                return p;
            }
            points.clear();
            const int m = g.irange(4, 12);
            const double r = g.chance(0.2) ? g.logUni(1e-3, 0.3) : g.uni(0.3, 0.6 * n + 1);
            const bool lattice = g.chance(0.3);
            for (int k = 0; k < m; ++k) {
                Vec3 q(g.uni(-1, 1), g.uni(-1, 1), g.uni(-1, 1));
                if (g.chance(0.5)) q = safeNormalize<3>(q); // on a sphere: every point a vertex
                Vec3 pt = c + r * q;
                if (lattice) pt = glm::round(pt);
                points.push_back(pt);
            }
            return makeConvexHull(points, "test");
        } catch (const InvalidInput&) {
            // a flat or coincident draw (lattice points): draw again
        }
    }
}

} // namespace

TEST_CASE("Raster: random 3D oriented boxes and hulls against brute force", "[raster]") {
    const std::uint64_t seed = 0x0BB0ULL;
    auto t0 = std::chrono::steady_clock::now();
    Stats st;
    int failures = 0;
    const int count = 700;
    for (int i = 0; i < count; ++i) {
        Gen g(seed * 1000003ULL + std::uint64_t(i));
        IVec3 res(g.irange(1, 10), g.irange(1, 10), g.irange(1, 10));
        std::vector<Vec3> points;
        Shape<3> s = randomPolytope(g, res, points);
        if (g.chance(0.3)) {
            const Vec3 t(g.jitter(), g.jitter(), g.jitter());
            s = translated<3>(s, t);
            for (Vec3& q : points) q += t;
        }
        validateShape<3>(s, "test");
        std::string err = checkPolytope3(s, points, res, st);
        if (!err.empty() && failures++ < 5)
            FAIL_CHECK("polytope seed=" << seed << " shape #" << i << " grid " << res.x << "x" << res.y << "x" << res.z
                                        << "\n  " << describe(s) << "\n  " << err);
    }
    CHECK(failures == 0);
    printStats("polytope", st, secondsSince(t0));
    CHECK(st.shapes == count);
    CHECK(st.inner > 1000);
    CHECK(st.contact > 50);
    CHECK(st.sampleChecks > 10000);
    CHECK(st.outside > 0);
    CHECK(st.outside < st.shapes);
}

TEST_CASE("Raster: polytope fixed cases and row spans", "[raster]") {
    const IVec3 res(6, 6, 6);
    auto count = [&](bool innerSet, const Shape<3>& s) {
        std::size_t k = 0;
        auto fn = [&](const IVec3&) { ++k; };
        if (innerSet) forEachInnerVoxel<3>(s, res, fn);
        else forEachTouchedVoxel<3>(s, res, fn);
        return k;
    };
    // An axis-aligned obb on voxel boundaries is the box: the same voxels.
    const ConvexPolytope obb = makeOrientedBox(Vec3(3, 3, 3), Vec3(1, 1.5, 2), {0, 0, 0, 1}, "obb");
    const Box<3> box{Vec3(2, 1.5, 1), Vec3(4, 4.5, 5)};
    CHECK(count(true, obb) == count(true, box));
    CHECK(count(false, obb) == count(false, box));
    CHECK(count(true, obb) == 2 * 2 * 4);
    // Turned by 90 degrees about z (through sqrt(1/2), rounded): x and y swap, and rounding loses nothing.
    const ConvexPolytope turned = makeOrientedBox(Vec3(3, 3, 3), Vec3(1.5, 1, 2), {0, 0, std::sqrt(0.5), std::sqrt(0.5)}, "obb");
    CHECK(count(true, turned) == count(true, box));
    CHECK(count(false, turned) == count(false, box));
    // A hull of a unit cube's corners and a point above it (a house): O holds the cube's voxel.
    std::vector<Vec3> house;
    for (int k = 0; k < 8; ++k) house.push_back(Vec3(2 + (k & 1), 2 + ((k >> 1) & 1), 2 + ((k >> 2) & 1)));
    house.push_back(Vec3(2.5, 3.5, 2.5));
    const ConvexPolytope h = makeConvexHull(house, "house");
    CHECK(h.vertices.size() == 9);
    CHECK(h.planes.size() == 9); // 5 sides of the cube (the top one is gone) and the 4 roof faces
    CHECK(count(true, h) == 1);
    // Rows: ordered, one span per row, equal to the voxel sets.
    for (std::uint64_t i = 0; i < 200; ++i) {
        Gen g(0x9011ULL + i);
        IVec3 r(g.irange(1, 12), g.irange(1, 12), g.irange(1, 12));
        std::vector<Vec3> pts;
        checkRows<3>(randomPolytope(g, r, pts), r, 0x9011ULL + i);
    }
}
