// ConservativeRaster (forEachInnerVoxel / forEachTouchedVoxel / extendsOutsideGrid) against brute-force
// geometry, on thousands of random and adversarial shapes. Tag: [raster].
// (2D cases and world coordinates; 3D cases in test_raster3d.cpp; the oracle in RasterOracle.hpp.)
#include "RasterOracle.hpp"

using namespace raster_oracle;


// ---------------------------------------------------------------------------------------------------
// Fixed adversarial cases with exactly known answers.

namespace {
std::set<std::pair<int, int>> collect2(bool innerSet, const Shape<2>& s, IVec2 res) {
    std::set<std::pair<int, int>> out;
    auto fn = [&](const IVec2& v) { out.insert({v.x, v.y}); };
    if (innerSet) forEachInnerVoxel<2>(s, res, fn);
    else forEachTouchedVoxel<2>(s, res, fn);
    return out;
}
std::set<std::pair<int, int>> rect(int x0, int y0, int x1, int y1) {
    std::set<std::pair<int, int>> out;
    for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) out.insert({x, y});
    return out;
}
bool subset(const std::set<std::pair<int, int>>& a, const std::set<std::pair<int, int>>& b) {
    return std::includes(b.begin(), b.end(), a.begin(), a.end());
}
} // namespace

TEST_CASE("Raster: integer-aligned box touches its face and corner neighbours", "[raster]") {
    const IVec2 res(10, 10);
    Shape<2> box = Box<2>{Vec2(2, 3), Vec2(5, 7)};
    // Closed voxels sharing a face or a corner with the closed box are touched.
    CHECK(collect2(false, box, res) == rect(1, 2, 5, 7));
    // The inner voxels are the box's own voxels, possibly minus a boundary ring (the slack may drop voxels
    // flush with the boundary), and at least the voxels at margin >= 1.
    auto in = collect2(true, box, res);
    CHECK(subset(in, rect(2, 3, 4, 6)));
    CHECK(subset(rect(3, 4, 3, 5), in));
    CHECK_FALSE(extendsOutsideGrid<2>(box, res));
    // The same box as a polygon, in both windings.
    for (bool cw : {false, true}) {
        ConvexPolygon p{{Vec2(2, 3), Vec2(5, 3), Vec2(5, 7), Vec2(2, 7)}};
        if (cw) std::reverse(p.points.begin(), p.points.end());
        Shape<2> s = p;
        validateShape<2>(s, "poly");
        CHECK(collect2(false, s, res) == rect(1, 2, 5, 7));
        auto pin = collect2(true, s, res);
        CHECK(subset(pin, rect(2, 3, 4, 6)));
        CHECK(subset(rect(3, 4, 3, 5), pin));
    }
}

TEST_CASE("Raster: inner faces snap to voxel boundaries within 1e-9 voxel, and no further", "[raster]") {
    const IVec2 res(30, 30);
    // A grid-aligned box that world-to-voxel rounding moved by 4e-13 still covers its boundary voxels.
    Shape<2> nearly = Box<2>{Vec2(20.0000000000004, 3 - 4e-13), Vec2(22 - 4e-13, 5.0000000000004)};
    CHECK(collect2(true, nearly, res) == rect(20, 3, 21, 4));
    Shape<2> nearlyPoly = ConvexPolygon{{Vec2(20.0000000000004, 3), Vec2(22 - 4e-13, 3), Vec2(22 - 4e-13, 5), Vec2(20.0000000000004, 5)}};
    validateShape<2>(nearlyPoly, "p");
    CHECK(collect2(true, nearlyPoly, res) == rect(20, 3, 21, 4));
    // Faces 1e-8 inside a voxel boundary are not snapped: the boundary voxels are not inner.
    Shape<2> inside = Box<2>{Vec2(20 + 1e-8, 3), Vec2(22, 5 - 1e-8)};
    CHECK(collect2(true, inside, res) == rect(21, 3, 21, 3));
    Shape<2> insidePoly = ConvexPolygon{{Vec2(20 + 1e-8, 3), Vec2(22, 3), Vec2(22, 5), Vec2(20 + 1e-8, 5)}};
    validateShape<2>(insidePoly, "p");
    CHECK(collect2(true, insidePoly, res) == rect(21, 3, 21, 4));
    // The touched set of the nearly aligned box is its ring of neighbours, as for the aligned one.
    CHECK(collect2(false, nearly, res) == rect(19, 2, 22, 5));
}

TEST_CASE("Raster: shapes much smaller than a voxel", "[raster]") {
    const IVec2 res(8, 8);
    SECTION("tiny circle centred on a voxel corner touches the four voxels around it") {
        Shape<2> c = Ball<2>{Vec2(4, 4), 1e-3};
        CHECK(collect2(false, c, res) == rect(3, 3, 4, 4));
        CHECK(collect2(true, c, res).empty());
    }
    SECTION("tiny circle centred in a voxel touches it alone") {
        Shape<2> c = Ball<2>{Vec2(2.5, 6.5), 1e-3};
        CHECK(collect2(false, c, res) == rect(2, 6, 2, 6));
        CHECK(collect2(true, c, res).empty());
    }
    SECTION("tiny circle centred on a voxel edge touches both voxels") {
        Shape<2> c = Ball<2>{Vec2(3, 0.5), 1e-6};
        CHECK(collect2(false, c, res) == rect(2, 0, 3, 0));
    }
    SECTION("tiny box on a corner, tiny polygon inside a voxel") {
        Shape<2> b = Box<2>{Vec2(5 - 1e-6, 5 - 1e-6), Vec2(5 + 1e-6, 5 + 1e-6)};
        CHECK(collect2(false, b, res) == rect(4, 4, 5, 5));
        CHECK(collect2(true, b, res).empty());
        Shape<2> p = ConvexPolygon{{Vec2(1.4, 1.4), Vec2(1.4001, 1.4), Vec2(1.4, 1.4001)}};
        validateShape<2>(p, "p");
        CHECK(collect2(false, p, res) == rect(1, 1, 1, 1));
        CHECK(collect2(true, p, res).empty());
    }
}

TEST_CASE("Raster: circle through voxel corners (3-4-5)", "[raster]") {
    // Centre on a voxel corner, radius 5: corners (c.x+3, c.y+4) etc. lie exactly on the circle.
    const IVec2 res(20, 20);
    Shape<2> c = Ball<2>{Vec2(10, 10), 5};
    auto t = collect2(false, c, res);
    // Voxel [13,14]x[14,15] has its nearest corner (13,14) exactly on the circle: touched.
    CHECK(t.count({13, 14}));
    CHECK(t.count({14, 13}));
    CHECK(t.count({6, 5}));   // nearest corner (7,6): (-3,-4)
    CHECK(t.count({15, 9}));  // nearest point (15,10) exactly on the circle
    CHECK_FALSE(t.count({14, 14})); // nearest corner (14,14): distance sqrt(32) > 5
    auto in = collect2(true, c, res);
    // Voxel [12,13]x[13,14] has its farthest corner (13,14) on the circle: inside, margin 0 (may be dropped).
    // Voxel [12,13]x[12,13] (farthest corner (13,13), distance sqrt(18)) must be inner.
    CHECK(in.count({12, 12}));
    CHECK_FALSE(in.count({13, 13}));
    CHECK(subset(in, t));
}

TEST_CASE("Raster: shapes larger than the grid and shapes outside it", "[raster]") {
    const IVec2 res(10, 6);
    SECTION("covering circle") {
        Shape<2> c = Ball<2>{Vec2(5, 3), 1000};
        CHECK(collect2(false, c, res) == rect(0, 0, 9, 5));
        CHECK(collect2(true, c, res) == rect(0, 0, 9, 5));
        CHECK(extendsOutsideGrid<2>(c, res));
    }
    SECTION("covering polygon and box") {
        Shape<2> p = ConvexPolygon{{Vec2(-1e6, -1e6), Vec2(1e6, -1e6), Vec2(0, 1e6)}};
        validateShape<2>(p, "p");
        CHECK(collect2(false, p, res) == rect(0, 0, 9, 5));
        CHECK(collect2(true, p, res) == rect(0, 0, 9, 5));
        Shape<2> b = Box<2>{Vec2(-1e9, -1e9), Vec2(1e9, 1e9)};
        CHECK(collect2(true, b, res) == rect(0, 0, 9, 5));
        CHECK(extendsOutsideGrid<2>(b, res));
    }
    SECTION("box exactly the grid") {
        Shape<2> b = Box<2>{Vec2(0, 0), Vec2(10, 6)};
        CHECK(collect2(false, b, res) == rect(0, 0, 9, 5));
        CHECK_FALSE(extendsOutsideGrid<2>(b, res));
        auto in = collect2(true, b, res);
        CHECK(subset(rect(1, 1, 8, 4), in));
    }
    SECTION("wholly outside, at a distance") {
        for (Shape<2> s : {Shape<2>(Box<2>{Vec2(-5, 2), Vec2(-1, 3)}), Shape<2>(Ball<2>{Vec2(5, -2), 1.5}),
                           Shape<2>(Ball<2>{Vec2(-100, -100), 50}), Shape<2>(Box<2>{Vec2(11, 7), Vec2(12, 8)})}) {
            CAPTURE(describe(s));
            CHECK(collect2(false, s, res).empty());
            CHECK(collect2(true, s, res).empty());
            CHECK(extendsOutsideGrid<2>(s, res));
        }
    }
    SECTION("outside, touching the grid boundary") {
        Shape<2> b = Box<2>{Vec2(-5, 2), Vec2(0, 3)};
        CHECK(collect2(false, b, res) == rect(0, 1, 0, 3));
        CHECK(collect2(true, b, res).empty());
        Shape<2> c = Ball<2>{Vec2(5, -2), 2}; // touches the grid at the single point (5, 0)
        CHECK(collect2(false, c, res) == rect(4, 0, 5, 0));
        Shape<2> corner = Ball<2>{Vec2(12, 9), 5}; // contains the grid corner (10, 6): 2^2 + 3^2 < 25
        CHECK(collect2(false, corner, res).count({9, 5}));
    }
}

TEST_CASE("Raster: thin polygons", "[raster]") {
    const IVec2 res(16, 16);
    SECTION("a sliver along a voxel row boundary touches both rows") {
        Shape<2> p = ConvexPolygon{{Vec2(1.5, 8), Vec2(14.5, 8), Vec2(14.5, 8 + 1e-9), Vec2(1.5, 8 + 1e-9)}};
        validateShape<2>(p, "p");
        auto t = collect2(false, p, res);
        CHECK(subset(rect(1, 7, 14, 8), t));
        CHECK(collect2(true, p, res).empty());
    }
    SECTION("a diagonal sliver") {
        Shape<2> p = ConvexPolygon{{Vec2(0.5, 0.5), Vec2(15.5, 15.5), Vec2(15.5, 15.5 + 1e-7)}};
        validateShape<2>(p, "p");
        auto t = collect2(false, p, res);
        for (int k = 0; k < 16; ++k) CHECK(t.count({k, k}));
        CHECK(collect2(true, p, res).empty());
    }
}

TEST_CASE("Raster: huge finite balls (squared distances beyond double range)", "[raster]") {
    // A ball of radius ~2e154 voxels whose squared radius overflows to inf. Either validation rejects such a
    // shape, or the rasterization still covers the grid: the ball contains every voxel of the 8x8 grid
    // (its lowest point is 2e139 below y = 0 and its chord there is ~1e147 wide).
    const IVec2 res(8, 8);
    for (double c : {1e150, 2e154, 1e160, 1e300}) {
        INFO("ball centre offset and radius ~ " << c);
        Shape<2> s = Ball<2>{Vec2(4.5, c), c * (1 + 1e-15)};
        bool rejected = false;
        try {
            validateShape<2>(s, "ball");
        } catch (const InvalidInput&) {
            rejected = true;
        }
        if (rejected) continue;
        CHECK(collect2(false, s, res) == rect(0, 0, 7, 7));
        CHECK(collect2(true, s, res) == rect(0, 0, 7, 7));
    }
    for (double c : {1e150, 2e154}) {
        INFO("ball centre offset and radius ~ " << c);
        Shape<3> s = Ball<3>{Vec3(1.5, 1.5, c), c * (1 + 1e-15)};
        bool rejected = false;
        try {
            validateShape<3>(s, "ball");
        } catch (const InvalidInput&) {
            rejected = true;
        }
        if (rejected) continue;
        int n = 0;
        forEachTouchedVoxel<3>(s, IVec3(3, 3, 3), [&](const IVec3&) { ++n; });
        CHECK(n == 27);
    }
}

// ---------------------------------------------------------------------------------------------------
// Thousands of random shapes against the oracle.

TEST_CASE("Raster: random circles against brute force", "[raster]") {
    runRandom2("circles", 0xC1C1E5ULL, 3000, randomCircle, 10000, 100);
}

TEST_CASE("Raster: random boxes against brute force", "[raster]") {
    runRandom2("boxes", 0xB0B0B0ULL, 3000, randomBox, 10000, 1000);
}

TEST_CASE("Raster: random convex polygons against brute force", "[raster]") {
    runRandom2("polygons", 0x9017601ULL, 4000, randomPolygon, 10000, 1000);
}

// World units at large offsets: the conversion keeps the rasterization conservative.

TEST_CASE("Raster: world shapes at origin 1e6 with 1e-3 voxels", "[raster]") {
    const std::uint64_t seed = 0x1E6ULL;
    const Vec2 origin(1e6, -1e6);
    const double d = 1e-3;
    int failures = 0;
    Stats st;
    for (int i = 0; i < 1500; ++i) {
        Gen g(seed * 1000003ULL + std::uint64_t(i));
        IVec2 res = g.resolution();
        GridGeometry2 grid(origin, d, res);
        // A local shape, mapped to world units (rounded there), then back through the API.
        Shape<2> local = i % 3 == 0 ? randomCircle(g, res) : (i % 3 == 1 ? randomBox(g, res) : randomPolygon(g, res));
        Shape<2> world = std::visit(
            [&](const auto& x) -> Shape<2> {
                using T = std::decay_t<decltype(x)>;
                if constexpr (std::is_same_v<T, Ball<2>>) return Ball<2>{grid.toWorld(x.center), x.radius * d};
                else if constexpr (std::is_same_v<T, Box<2>>) return Box<2>{grid.toWorld(x.min), grid.toWorld(x.max)};
                else {
                    ConvexPolygon p;
                    for (const Vec2& q : x.points) p.points.push_back(grid.toWorld(q));
                    return p;
                }
            },
            local);
        try {
            validateShape<2>(world, "world");
        } catch (const InvalidInput&) {
            continue; // rounding in world units collapsed a tiny shape
        }
        Shape<2> conv = toLocal<2>(world, grid);
        // Reference: the world shape's exact local coordinates, in long double.
        auto loc = [&](double w, int a) { return ((L)w - (L)origin[a]) / (L)d; };
        Ref2 ref;
        if (auto* b = std::get_if<Ball<2>>(&world)) ref = Ref2::circle(loc(b->center.x, 0), loc(b->center.y, 1), (L)b->radius / d);
        else if (auto* x = std::get_if<Box<2>>(&world))
            ref = Ref2::box(loc(x->min.x, 0), loc(x->min.y, 1), loc(x->max.x, 0), loc(x->max.y, 1));
        else {
            std::vector<L> xs, ys;
            for (const Vec2& q : std::get<ConvexPolygon>(world).points) {
                xs.push_back(loc(q.x, 0));
                ys.push_back(loc(q.y, 1));
            }
            ref = Ref2::poly(xs, ys);
        }
        std::string err = checkShape2(conv, ref, res, false, st, false);
        // extendsOutsideGrid against the exact shape: it may only differ where the bounds are within rounding
        // (1e-9 voxel) of the grid's faces.
        if (err.empty() && extendsOutsideGrid<2>(conv, res) != ref.outsideGrid(res)) {
            bool nearFace = false;
            for (L v : {ref.minx, ref.miny, ref.maxx - res.x, ref.maxy - res.y}) nearFace = nearFace || std::fabs(v) < 1e-9L;
            if (!nearFace) err = "extendsOutsideGrid disagrees with the exact shape";
        }
        if (!err.empty() && failures++ < 5)
            FAIL_CHECK("world seed=" << seed << " shape #" << i << " grid " << res.x << "x" << res.y << "\n  world "
                                     << describe(world) << "\n  " << err);
    }
    CHECK(failures == 0);
    CHECK(st.shapes > 1000);
    CHECK(st.inner > 1000);
}

// ---------------------------------------------------------------------------------------------------
// insetShape: the occluder model of ObjectDesc::occluderInset (an erosion of the shape).

namespace {
/// Signed distance from p to the boundary of a counter-clockwise convex polygon, positive inside.
double insideDistance(const std::vector<Vec2>& pts, const Vec2& p) {
    double d = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0, n = pts.size(); i < n; ++i) {
        const Vec2 e = pts[(i + 1) % n] - pts[i];
        const double len = std::sqrt(lengthSquared<2>(e));
        if (len > 0) d = std::min(d, cross2(e, p - pts[i]) / len);
    }
    return d;
}
} // namespace

TEST_CASE("Raster: insetShape shrinks balls, boxes and convex polygons exactly", "[raster]") {
    Shape<2> out;
    REQUIRE(insetShape<2>(Ball<2>{{1, 2}, 3}, 0.5, out));
    CHECK(std::get<Ball<2>>(out).radius == 2.5);
    CHECK_FALSE(insetShape<2>(Ball<2>{{1, 2}, 3}, 3, out)); // nothing left
    Shape<3> out3;
    REQUIRE(insetShape<3>(Box<3>{{0, 0, 0}, {4, 2, 6}}, 0.5, out3));
    CHECK(std::get<Box<3>>(out3).min == Vec3(0.5, 0.5, 0.5));
    CHECK(std::get<Box<3>>(out3).max == Vec3(3.5, 1.5, 5.5));
    CHECK_FALSE(insetShape<3>(Box<3>{{0, 0, 0}, {4, 1, 6}}, 0.5, out3)); // the thin axis closes
    REQUIRE(insetShape<2>(Box<2>{{0, 0}, {4, 2}}, 0, out)); // 0: the shape itself
    CHECK(std::get<Box<2>>(out).max == Vec2(4, 2));
    // A square inset by 1 is the square of side 2.
    Shape<2> sq = ConvexPolygon{{{0, 0}, {4, 0}, {4, 4}, {0, 4}}};
    REQUIRE(insetShape<2>(sq, 1, out));
    const auto& q = std::get<ConvexPolygon>(out).points;
    CHECK(std::abs(signedArea(q) - 4) < 1e-12);

    // Random convex polygons: every vertex of the inset lies at distance >= d inside the original (so the
    // inset is contained: it is convex), and sampled points deeper than d lie in the inset.
    Gen g(0x1A5E7ULL);
    int checked = 0, vanished = 0;
    for (int k = 0; k < 2000; ++k) {
        INFO("seed 0x1A5E7, polygon " << k);
        Shape<2> s = randomPolygon(g, {64, 64});
        validateShape<2>(s, "p");
        const auto& pts = std::get<ConvexPolygon>(s).points;
        const Box<2> b = boundsOf<2>(s);
        const double d = g.uni(0, 0.3) * std::max(b.max.x - b.min.x, b.max.y - b.min.y);
        Shape<2> in;
        if (!insetShape<2>(s, d, in)) {
            ++vanished;
            // Nothing deeper than d may exist: sample and check.
            for (int t = 0; t < 200; ++t) {
                const Vec2 p(g.uni(b.min.x, b.max.x), g.uni(b.min.y, b.max.y));
                REQUIRE(insideDistance(pts, p) <= d + 1e-9 * (1 + d));
            }
            continue;
        }
        ++checked;
        const auto& ip = std::get<ConvexPolygon>(in).points;
        for (const Vec2& v : ip) REQUIRE(insideDistance(pts, v) >= d - 1e-9 * (1 + d));
        for (int t = 0; t < 200; ++t) {
            const Vec2 p(g.uni(b.min.x, b.max.x), g.uni(b.min.y, b.max.y));
            if (insideDistance(pts, p) > d + 1e-7 * (1 + d)) REQUIRE(insideDistance(ip, p) >= -1e-9 * (1 + d));
        }
    }
    CHECK(checked > 1000);
    CHECK(vanished > 0);
}
