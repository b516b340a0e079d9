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

// ---------------------------------------------------------------------------------------------------
// Polytopes given by half-spaces (makePolytopeFromPlanes): the planes of a box, an obb or a random hull,
// shuffled, scaled and mixed with redundant planes, give the same polytope back (the vertices within the
// tolerances, the same O and I voxels), and bad input is refused naming the field.

namespace {

std::vector<IVec3> voxelSet(bool innerSet, const Shape<3>& s, IVec3 res) {
    std::vector<IVec3> out;
    auto fn = [&](const IVec3& v) { out.push_back(v); };
    if (innerSet) forEachInnerVoxel<3>(s, res, fn);
    else forEachTouchedVoxel<3>(s, res, fn);
    return out;
}

double maxCoord(const ConvexPolytope& p) {
    double m = 0;
    for (const Vec3& v : p.vertices) m = std::max({m, std::abs(v.x), std::abs(v.y), std::abs(v.z)});
    return m;
}

/// Every vertex of a inside every plane of b moved out by tol.
bool insideAll(const ConvexPolytope& a, const ConvexPolytope& b, double tol) {
    for (const Vec3& v : a.vertices)
        for (const HalfSpace& h : b.planes)
            if (glm::dot(h.normal, v) > h.offset + tol) return false;
    return true;
}

/// The largest distance from a vertex of a to the nearest vertex of b.
double vertexGap(const ConvexPolytope& a, const ConvexPolytope& b) {
    double worst = 0;
    for (const Vec3& v : a.vertices) {
        double best = std::numeric_limits<double>::infinity();
        for (const Vec3& w : b.vertices) best = std::min(best, std::sqrt(lengthSquared<3>(v - w)));
        worst = std::max(worst, best);
    }
    return worst;
}

std::string planesOf(const std::vector<HalfSpace>& hs) {
    std::ostringstream o;
    o << std::setprecision(17);
    for (const HalfSpace& h : hs) o << "\n    (" << h.normal.x << ", " << h.normal.y << ", " << h.normal.z << ") . x <= " << h.offset;
    return o.str();
}

} // namespace

TEST_CASE("Polytope: the planes of boxes, obbs and hulls round-trip to the same polytope", "[raster][polytope]") {
    const std::uint64_t seed = 0x91A4E5ULL;
    int failures = 0, shapes = 0, redundant = 0, sameCount = 0;
    std::size_t innerVoxels = 0, touchedVoxels = 0;
    for (int i = 0; i < 600; ++i) {
        Gen g(seed * 1000003ULL + std::uint64_t(i));
        const IVec3 res(g.irange(1, 10), g.irange(1, 10), g.irange(1, 10));
        ConvexPolytope p;
        const int kind = i % 3;
        if (kind == 0) { // an axis-aligned box as an obb with the identity rotation
            Vec3 lo(0.0), hi(0.0);
            for (int a = 0; a < 3; ++a) {
                double u = g.coord(res[a]), w = g.coord(res[a]);
                if (u == w) w += 0.5;
                lo[a] = std::min(u, w), hi[a] = std::max(u, w);
            }
            p = makeOrientedBox(0.5 * (lo + hi), 0.5 * (hi - lo), {0, 0, 0, 1}, "box");
        } else {
            std::vector<Vec3> points;
            Shape<3> s = randomPolytope(g, res, points);
            p = std::get<ConvexPolytope>(s);
        }
        std::vector<HalfSpace> hs = p.planes;
        // Redundant planes (moved out, or touching only a vertex), non-unit normals, a shuffled order.
        const int extra = g.irange(0, 3);
        for (int k = 0; k < extra; ++k) {
            HalfSpace r = hs[std::size_t(g.irange(0, int(hs.size()) - 1))];
            r.offset += g.uni(0.01, 2);
            hs.push_back(r);
            ++redundant;
        }
        if (g.chance(0.3)) {
            const Vec3 dir = safeNormalize<3>(Vec3(g.uni(-1, 1), g.uni(-1, 1), g.uni(-1, 1)) + Vec3(1e-3));
            double support = -std::numeric_limits<double>::infinity();
            for (const Vec3& v : p.vertices) support = std::max(support, glm::dot(dir, v));
            hs.push_back({dir, support + 1e-3});
            ++redundant;
        }
        for (HalfSpace& h : hs)
            if (g.chance(0.3)) {
                const double s = g.logUni(1e-3, 1e3);
                h.normal *= s;
                h.offset *= s;
            }
        for (std::size_t k = hs.size(); k > 1; --k) std::swap(hs[k - 1], hs[std::size_t(g.irange(0, int(k) - 1))]);

        std::string err;
        try {
            const ConvexPolytope q = makePolytopeFromPlanes(hs, "planes");
            Shape<3> sq = q;
            validateShape<3>(sq, "planes");
            const double tol = p.tolerance + q.tolerance + 1e-12 * (1 + std::max(maxCoord(p), 1.0));
            // The same point set: q's vertices are p's (p may also keep points on an edge or a facet, which
            // a hull of lattice points can: q has only the true corners), and each lies in the other.
            if (q.vertices.size() > p.vertices.size()) err = "more vertices than the hull: " + std::to_string(q.vertices.size());
            else if (vertexGap(q, p) > tol) err = "a vertex from the planes is no vertex of the hull";
            else if (!insideAll(p, q, tol) || !insideAll(q, p, tol)) err = "a vertex of one lies outside the other";
            else if (q.planes.size() > p.planes.size()) err = "more planes than the hull";
            else if (voxelSet(true, p, res) != voxelSet(true, q, res)) err = "O (inner voxels) differ";
            else if (voxelSet(false, p, res) != voxelSet(false, q, res)) err = "I (touched voxels) differ";
            if (!(q.tolerance <= 1e-9 * (1 + maxCoord(p)))) err = "tolerance " + std::to_string(q.tolerance) + " is not a rounding error";
            if (q.vertices.size() == p.vertices.size() && q.planes.size() == p.planes.size()) ++sameCount;
            innerVoxels += voxelSet(true, q, res).size();
            touchedVoxels += voxelSet(false, q, res).size();
        } catch (const InvalidInput& e) {
            err = std::string("refused: ") + e.what();
        }
        ++shapes;
        if (!err.empty() && failures++ < 5)
            FAIL_CHECK("planes seed=" << seed << " shape #" << i << ": " << err << "\n  " << describe(Shape<3>(p)) << "\n  planes:" << planesOf(hs));
    }
    CHECK(failures == 0);
    CHECK(shapes == 600);
    CHECK(redundant > 300);
    CHECK(sameCount > 500); // the same vertex and facet counts but for hulls that keep points on edges
    CHECK(innerVoxels > 1000);
    CHECK(touchedVoxels > innerVoxels);
}

TEST_CASE("Polytope: a tetrahedron, a pyramid apex of many planes and a frustum from planes", "[raster][polytope]") {
    // The unit-corner tetrahedron x, y, z >= 0, x + y + z <= 1 (the last normal not unit).
    const std::vector<HalfSpace> tet = {{{-1, 0, 0}, 0}, {{0, -1, 0}, 0}, {{0, 0, -1}, 0}, {{1, 1, 1}, 1}};
    const ConvexPolytope t = makePolytopeFromPlanes(tet, "tet");
    CHECK(t.vertices.size() == 4);
    CHECK(t.planes.size() == 4);
    for (const HalfSpace& h : t.planes) CHECK(std::abs(lengthSquared<3>(h.normal) - 1) < 1e-12);
    // A pyramid over a regular 12-gon: 12 planes through the apex (0, 0, 2) and the base z >= 0.
    std::vector<HalfSpace> pyr = {{{0, 0, -1}, 0}};
    for (int k = 0; k < 12; ++k) {
        const double a = 2 * 3.14159265358979323846 * k / 12;
        const Vec3 n = safeNormalize<3>(Vec3(2 * std::cos(a), 2 * std::sin(a), 1));
        pyr.push_back({n, glm::dot(n, Vec3(0, 0, 2))});
    }
    const ConvexPolytope py = makePolytopeFromPlanes(pyr, "pyramid");
    CHECK(py.vertices.size() == 13); // the apex once, however many triples meet there
    CHECK(py.planes.size() == 13);
    double top = 0;
    for (const Vec3& v : py.vertices) top = std::max(top, v.z);
    CHECK(std::abs(top - 2) < 1e-12);
    // A view frustum's 6 planes (near 1, far 10, 90 degrees): 8 corners; O holds voxels near the far end.
    std::vector<HalfSpace> fr = {{{0, 0, -1}, -1}, {{0, 0, 1}, 10}};
    for (int s : {-1, 1}) {
        fr.push_back({{double(s), 0, -1}, 0});
        fr.push_back({{0, double(s), -1}, 0});
    }
    const ConvexPolytope f = makePolytopeFromPlanes(fr, "frustum");
    CHECK(f.vertices.size() == 8);
    CHECK(f.planes.size() == 6);
    const ConvexPolytope moved = translatedPolytope(f, Vec3(10, 10, 0));
    CHECK(voxelSet(true, moved, IVec3(20, 20, 12)).size() > 300);
    // kMaxPolytopePlanes tangent planes of a ball of radius 3 at (1e6, 1e6, 1e6) (far from the origin, so
    // rounding is relative to 1e6): a polytope around the ball, inside the ball grown by 3%.
    Gen g(0x7A46E7ULL);
    std::vector<HalfSpace> ball;
    const Vec3 c(1e6);
    while (ball.size() < kMaxPolytopePlanes) {
        const Vec3 n = safeNormalize<3>(Vec3(g.uni(-1, 1), g.uni(-1, 1), g.uni(-1, 1)) + Vec3(1e-9));
        ball.push_back({n, glm::dot(n, c) + 3});
    }
    const ConvexPolytope b = makePolytopeFromPlanes(ball, "ball");
    Shape<3> sb = b;
    validateShape<3>(sb, "ball");
    CHECK(b.planes.size() == kMaxPolytopePlanes); // every tangent plane is a facet
    CHECK(b.tolerance < 1e-6);
    for (const Vec3& v : b.vertices) {
        const double r = std::sqrt(lengthSquared<3>(v - c));
        CHECK(r >= 3 - 1e-6);
        CHECK(r < 3.5);
    }
}

TEST_CASE("Polytope: bad half-spaces are refused naming the field", "[raster][polytope][errors]") {
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    std::vector<HalfSpace> cube;
    for (int a = 0; a < 3; ++a)
        for (int s : {-1, 1}) {
            Vec3 n(0.0);
            n[a] = s;
            cube.push_back({n, 1});
        }
    REQUIRE(makePolytopeFromPlanes(cube, "cube").vertices.size() == 8);
    auto refused = [](std::vector<HalfSpace> hs, const std::string& field, const std::string& words) {
        try {
            makePolytopeFromPlanes(hs, "brush");
        } catch (const InvalidInput& e) {
            CHECK(e.field() == field);
            CHECK_THAT(e.what(), Catch::Contains(words));
            return;
        }
        FAIL("accepted: " << field << " / " << words);
    };
    auto with = [&](std::size_t i, HalfSpace h) {
        auto c = cube;
        c[i] = h;
        return c;
    };
    refused({cube.begin(), cube.begin() + 3}, "brush", "at least 4");
    refused(std::vector<HalfSpace>(kMaxPolytopePlanes + 1, cube[0]), "brush", "at most");
    refused(with(2, {{nan, 0, 1}, 1}), "brush[2].normal", "finite");
    refused(with(3, {{0, inf, 0}, 1}), "brush[3].normal", "finite");
    refused(with(4, {{0, 0, 0}, 1}), "brush[4].normal", "non-zero");
    refused(with(5, {{0, 0, 1}, nan}), "brush[5].offset", "finite");
    refused(with(0, {{1e-300, 0, 0}, 1e300}), "brush[0].offset", "out of range");
    // Unbounded: a half-open slab (one side missing), a prism (no z planes), a cone opening upwards.
    refused({cube.begin(), cube.begin() + 5}, "brush", "unbounded");
    refused({cube[0], cube[1], cube[2], cube[3]}, "brush", "unbounded");
    refused({{{1, 0, -1}, 0}, {{-1, 0, -1}, 0}, {{0, 1, -1}, 0}, {{0, -1, -1}, 0}}, "brush", "unbounded");
    // Empty: x <= -2 next to x >= -1.
    refused(with(1, {{1, 0, 0}, -2}), "brush", "empty");
    // No volume: x >= 1 next to x <= 1, and a sliver 1e-12 thick.
    refused(with(0, {{-1, 0, 0}, -1}), "brush", "no volume");
    refused(with(0, {{-1, 0, 0}, -1 + 1e-12}), "brush", "no volume");
    // Every refusal leaves nothing behind: the cube still builds.
    CHECK(makePolytopeFromPlanes(cube, "cube").planes.size() == 6);
}
