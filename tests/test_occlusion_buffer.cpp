// OcclusionBuffer3D: fixed cases, and random scenes against the sampled 3D reference (an object the
// buffer hides must be one the reference does not see). The culler's own tests (test_culler3d,
// test_stress3d) run the buffer inside the whole pipeline; these check it alone, with occludees placed
// to graze the occluders' silhouettes and to sit just behind their near surfaces.
#include "CullerTestSupport.hpp"

#include "rgvc/grid/ConvexPolytope.hpp"
#include "rgvc/grid/OcclusionBuffer3D.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <utility>
#include <vector>

using namespace rgvc;
namespace ref = rgvc::reference;
namespace sd = rgvc::reference::scene3d_detail;
using rgvc::culler_test::bufferPass;
using rgvc::culler_test::kPi;
using rgvc::culler_test::sanitizedShare;

namespace {

const GridGeometry3 kUnitGrid(Vec3(0.0), 1.0, IVec3(100));

Camera3 lookingAlongZ(Vec3 position = {50, 30, 0}, double fov = 60, double aspect = 1) {
    Camera3 c;
    c.position = position;
    c.direction = {0, 0, 1};
    c.fovDeg = fov;
    c.aspect = aspect;
    return c;
}

/// A random reference scene in the grid's local coordinates, with the slack the culler would give its
/// objects (the view's and the conversion slack of the largest world coordinate, which bounds every
/// object's own).
struct LocalScene {
    std::vector<Shape<3>> world, local;
    double slack = 0;
};

LocalScene localScene(const ref::Scene3D& scene, const ViewFrustum& view) {
    LocalScene l;
    l.world = ref::shapesOf(scene.objects);
    double magnitude = 0;
    for (const Shape<3>& s : l.world) {
        l.local.push_back(toLocal<3>(s, scene.grid));
        const Box<3> b = boundsOf<3>(s);
        for (int a = 0; a < 3; ++a) magnitude = std::max({magnitude, std::abs(b.min[a]), std::abs(b.max[a])});
    }
    l.slack = view.slack() + scene.grid.conversionSlack(magnitude);
    return l;
}

} // namespace

TEST_CASE("buffer: fixed occluders and occludees", "[buffer]") {
    const Camera3 cam = lookingAlongZ();
    const ViewFrustum view(cam, kUnitGrid);
    OcclusionBuffer3D buffer;
    REQUIRE(buffer.begin(view, 64));
    CHECK(buffer.rows() == 64);
    CHECK(buffer.cols() == 64);
    const Shape<3> wallSphere = Ball<3>{{50, 30, 20}, 5};
    buffer.draw(wallSphere, 0);
    CHECK(buffer.stats().occludersDrawn == 1);
    CHECK(buffer.stats().pixelsCovered > 0);
    // Behind the sphere, within its silhouette (asin(5/20) = 14.5 degrees): hidden.
    CHECK(buffer.hidden(Ball<3>{{50, 30, 40}, 1}, 0));
    CHECK(buffer.hidden(Box<3>{{49, 29, 35}, {51, 31, 36}}, 0));
    // Larger than the silhouette (asin(12/40) = 17.5 degrees): seen around it.
    CHECK_FALSE(buffer.hidden(Ball<3>{{50, 30, 40}, 12}, 0));
    // Beside it, and in front of it.
    CHECK_FALSE(buffer.hidden(Ball<3>{{65, 30, 40}, 1}, 0)); // 20.5 degrees off the axis
    CHECK_FALSE(buffer.hidden(Ball<3>{{50, 30, 10}, 1}, 0));
    // Overlapping the occluder but starting behind its near surface at the centre ray: the open segment to
    // any of its points crosses the occluder's interior first.
    CHECK(buffer.hidden(Ball<3>{{50, 30, 16}, 0.5}, 0));
    // Growing the occludee by its slack can only make it visible.
    CHECK_FALSE(buffer.hidden(Ball<3>{{50, 30, 40}, 1}, 11));
    // An occludee holding the camera is never hidden.
    CHECK_FALSE(buffer.hidden(Ball<3>{{50, 30, 0}, 0.5}, 0));
    CHECK(buffer.stats().hidden == 3);

    SECTION("a box wall, and an occluder holding the camera") {
        REQUIRE(buffer.begin(view, 32));
        buffer.draw(Box<3>{{40, 20, 20}, {60, 40, 21}}, 0); // covers +-26.6 degrees around the axis
        CHECK(buffer.hidden(Ball<3>{{50, 30, 40}, 5}, 0));
        CHECK(buffer.hidden(Box<3>{{45, 25, 30}, {55, 35, 31}}, 0));
        CHECK_FALSE(buffer.hidden(Box<3>{{40, 20, 10}, {60, 40, 11}}, 0)); // in front of the wall
        CHECK_FALSE(buffer.hidden(Ball<3>{{50, 30, 60}, 30}, 0));          // 30 degrees: wider than the wall's image
        REQUIRE(buffer.begin(view, 32));
        buffer.draw(Ball<3>{{50, 30, 1}, 2}, 0); // holds the camera: draws nothing
        buffer.draw(Box<3>{{49, 29, -1}, {51, 31, 1}}, 0);
        CHECK(buffer.stats().occludersDrawn == 0);
        CHECK_FALSE(buffer.hidden(Ball<3>{{50, 30, 40}, 1}, 0));
    }
    SECTION("shrinking an occluder to nothing draws nothing") {
        REQUIRE(buffer.begin(view, 32));
        buffer.draw(Ball<3>{{50, 30, 20}, 1}, 1);
        buffer.draw(Box<3>{{49, 29, 20}, {51, 31, 22}}, 1);
        CHECK(buffer.stats().occludersDrawn == 0);
        CHECK_FALSE(buffer.hidden(Ball<3>{{50, 30, 40}, 0.1}, 0));
    }
    SECTION("views too extreme for an image hide nothing") {
        const ViewFrustum wide(lookingAlongZ({50, 30, 0}, 179.99999), kUnitGrid);
        CHECK_FALSE(buffer.begin(wide, 64));
        buffer.draw(wallSphere, 0);
        CHECK_FALSE(buffer.hidden(Ball<3>{{50, 30, 40}, 1}, 0));
        const ViewFrustum thin(lookingAlongZ({50, 30, 0}, 60, 1e-6), kUnitGrid);
        CHECK_FALSE(buffer.begin(thin, 64));
        CHECK_FALSE(buffer.begin(view, 0));
    }
    SECTION("columns follow the aspect") {
        const ViewFrustum wide(lookingAlongZ({50, 30, 0}, 60, 16.0 / 9.0), kUnitGrid);
        REQUIRE(buffer.begin(wide, 90));
        CHECK(buffer.cols() == 160);
        REQUIRE(buffer.begin(wide, 1));
        CHECK(buffer.cols() == 2);
    }
}

TEST_CASE("buffer: a box is tested pixel by pixel against the nearest point each pixel shows", "[buffer]") {
    // OcclusionBuffer3D::hiddenBoxExact. A wall across the view at z = 20..21, a flat box behind it at
    // z = 23..24 reaching from the axis to the image's edge (30 degrees): the wall's depth there, 23.09,
    // exceeds the box's one nearest distance, 23, so the footprint against that distance fails at the
    // edge; the box's own entry through those pixels is 23 / cos 30 = 26.6, and every pixel hides it.
    const ViewFrustum view(lookingAlongZ(), kUnitGrid);
    OcclusionBuffer3D buffer;
    for (int rows : {32, 64, 128}) {
        INFO("rows " << rows);
        REQUIRE(buffer.begin(view, rows));
        buffer.draw(Box<3>{{0, 0, 20}, {100, 60, 21}}, 0);
        CHECK(buffer.hidden(Box<3>{{50, 25, 23}, {80, 35, 24}}, 0));
        CHECK(buffer.hidden(Box<3>{{20, 0, 23}, {80, 60, 24}}, 0)); // the whole view
        // Reaching in front of the wall's near face: seen.
        CHECK_FALSE(buffer.hidden(Box<3>{{50, 25, 19.5}, {80, 35, 24}}, 0));
        // Beside the wall's image: a wall that ends at x = 60 leaves the box's far part open.
        REQUIRE(buffer.begin(view, rows));
        buffer.draw(Box<3>{{0, 0, 20}, {60, 60, 21}}, 0);
        CHECK_FALSE(buffer.hidden(Box<3>{{50, 25, 23}, {80, 35, 24}}, 0));
    }
}

/// What test "boxes in a wall's shadow" counts for one wall.
struct WallShadowCounts {
    int hidden = 0, comfortable = 0, comfortableHidden = 0, grazing = 0, grazingHidden = 0, misses = 0;
    std::uint64_t shadowed = 0;
};

/// 4,000 random boxes behind a wall 1 voxel thick (centre (40.5, 30, 50), half extents (0.5, 30, 40)),
/// axis-aligned or turned by 20 degrees about y (then drawn as an obb, a ConvexPolytope), seen from
/// (60, 30, 50) at yaws of 0..85 degrees off its normal; see the test case below.
WallShadowCounts wallShadowCase(bool turned, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::mt19937_64 points(seed + 1); // the sample points (their count follows the verdicts)
    const Vec3 centre{40.5, 30, 50}, half{0.5, 30, 40};
    const double turn = turned ? 20 * kPi / 180 : 0.0;
    const std::array<double, 4> q{0, std::sin(turn / 2), 0, std::cos(turn / 2)}; // (x, y, z, w) about y
    const std::array<Vec3, 3> axes = rotationColumns(q);
    const Shape<3> wall = turned ? Shape<3>(makeOrientedBox(centre, half, q, "wall")) : Shape<3>(Box<3>{centre - half, centre + half});
    auto local = [&](const Vec3& p) {
        const Vec3 d = p - centre;
        return Vec3{glm::dot(d, axes[0]), glm::dot(d, axes[1]), glm::dot(d, axes[2])};
    };
    auto throughWall = [&](const Vec3& from, const Vec3& p, double shrink) {
        // The open segment from..p meets the open wall shrunk by `shrink`: an independent slab test in
        // the wall's own frame.
        const Vec3 a = local(from), b = local(p);
        double t0 = 0, t1 = 1;
        for (int k = 0; k < 3; ++k) {
            const double d = b[k] - a[k], lo = -half[k] + shrink - a[k], hi = half[k] - shrink - a[k];
            if (d == 0) {
                if (!(lo < 0 && hi > 0)) return false;
                continue;
            }
            t0 = std::max(t0, std::min(lo / d, hi / d));
            t1 = std::min(t1, std::max(lo / d, hi / d));
        }
        return t0 < t1;
    };
    WallShadowCounts n;
    for (int i = 0; i < 4000; ++i) {
        const double yaw = sd::uniform(rng, 0, 85) * kPi / 180;
        Camera3 cam = lookingAlongZ({60, 30, 50}, sd::uniform(rng, 40, 100), sd::uniform(rng, 1, 2));
        cam.direction = {-std::cos(yaw), sd::uniform(rng, -0.2, 0.2), (rng() & 1 ? 1 : -1) * std::sin(yaw)};
        const ViewFrustum view(cam, kUnitGrid);
        OcclusionBuffer3D buffer;
        REQUIRE(buffer.begin(view, std::array<int, 3>{16, 32, 64}[std::size_t(i % 3)]));
        buffer.draw(wall, 0);
        // A box behind the wall (local x < -0.5) or straddling its plane or its edges.
        const Vec3 c = centre + axes[0] * sd::uniform(rng, -10.5, 1) + axes[1] * sd::uniform(rng, -35, 35) +
                       axes[2] * sd::uniform(rng, -50, 50);
        const Vec3 h{sd::uniform(rng, 0.05, 2), sd::uniform(rng, 0.05, 4), sd::uniform(rng, 0.05, 4)};
        const Box<3> b{c - h, c + h};
        const auto before = buffer.stats().shadowed;
        const bool hidden = buffer.hidden(b, 0);
        n.shadowed += buffer.stats().shadowed - before;
        n.hidden += hidden;
        bool comfy = true;
        double nearSide = -1e300; // the box's largest local x: its side towards the wall
        for (int k = 0; k < 8; ++k) {
            const Vec3 corner{(k & 1) ? b.max.x + 0.05 : b.min.x - 0.05, (k & 2) ? b.max.y + 0.05 : b.min.y - 0.05,
                              (k & 4) ? b.max.z + 0.05 : b.min.z - 0.05};
            comfy = comfy && throughWall(cam.position, corner, 0.05);
            nearSide = std::max(nearSide, local(corner).x);
        }
        const bool behind = nearSide >= -1.5; // within a voxel behind the wall's back face (local x = -0.5)
        n.comfortable += comfy;
        n.comfortableHidden += comfy && hidden;
        // Within a voxel behind the wall, seen at 60 degrees or more: where its pixels are longest.
        const bool graze = comfy && behind && yaw >= kPi / 3;
        n.grazing += graze;
        n.grazingHidden += graze && hidden;
        if (!hidden) continue;
        for (int k = 0; k < 64; ++k) {
            const Vec3 p = k < 8 ? Vec3{(k & 1) ? b.max.x : b.min.x, (k & 2) ? b.max.y : b.min.y, (k & 4) ? b.max.z : b.min.z}
                                 : Vec3{sd::uniform(points, b.min.x, b.max.x), sd::uniform(points, b.min.y, b.max.y),
                                        sd::uniform(points, b.min.z, b.max.z)};
            if (!ref::pointInView3D(cam, p) || throughWall(cam.position, p, 0)) continue;
            ++n.misses;
            UNSCOPED_INFO("seed " << seed << (turned ? " turned" : "") << " case " << i << " yaw " << yaw * 180 / kPi
                                  << " box " << b.min.x << " " << b.min.y << " " << b.min.z << " .. " << b.max.x << " "
                                  << b.max.y << " " << b.max.z);
            CHECK(false);
            break;
        }
    }
    return n;
}

TEST_CASE("buffer: boxes in a wall's shadow at grazing angles, proved in object space, against sampled segments", "[buffer]") {
    // OcclusionBuffer3D::shadowed. A wall seen at grazing angles spans long stretches of depth in one
    // pixel, and boxes just behind it fail the pixel tests near its far end; the wall's shadow proves them
    // hidden at once (a box, and an obb: a polytope's planes). Boxes poking out around its edges or
    // through its plane must never be hidden: for every box called hidden, the open segments from the
    // camera to 64 points of it (corners and random points) must meet the wall's interior. Comfortably
    // shadowed boxes (grown by 0.05, all corners' segments through the wall shrunk by 0.05) must be hidden.
    for (const bool turned : {false, true}) {
        const WallShadowCounts n = wallShadowCase(turned, 20261205);
        std::printf("[buffer] wall shadows (%s): %d boxes hidden (%llu by the shadow proof), %d of %d comfortably "
                    "shadowed hidden, of those within a voxel behind the wall at >= 60 degrees %d of %d; %d seen points "
                    "hidden (must be 0)\n",
                    turned ? "obb turned 20 degrees" : "axis-aligned box", n.hidden, (unsigned long long)n.shadowed,
                    n.comfortableHidden, n.comfortable, n.grazingHidden, n.grazing, n.misses);
        CHECK(n.misses == 0);
        CHECK(n.comfortable > 500);
        CHECK(n.grazing > 100);
        CHECK(n.shadowed > 0);
        // Measured with the proof: box 2,973 of 3,036 (97.9 %) and 114 of 134 within a voxel behind at
        // >= 60 degrees (85 %), obb 2,848 of 2,890 (98.5 %) and 124 of 132 (94 %); without it
        // (shadowed() answering false) 95.2 % and 77 %, 95.4 % and 85 %. What stays is where the wall
        // covers the centre's pixel only in part (no candidate) and the pixels fail too.
        CHECK(n.comfortableHidden >= n.comfortable * 97 / 100);
        CHECK(n.grazingHidden >= n.grazing * (turned ? 90 : 82) / 100);
    }
}

TEST_CASE("buffer: far boxes seen almost along an edge, drawn and tested against exact rays", "[buffer]") {
    // Boxes 1e2..1e9 away, thin across the view (1e-9..1e-2 of their distance) and of any depth, their
    // long edge's line within 1e-12..1e-3 of the camera (relative): two of their silhouette's vertices project within rounding of
    // each other (fuzz_culler3d found one whose footprint tripped a Debug check that asked every corner
    // to be on the inner side of such an edge's line; corpus: regression-far-box-degenerate-silhouette).
    // Each box is drawn (its seam footprint goes through the silhouette table), then a tiny ball farther
    // along a ray through a perturbed point of the box: when that ray misses the box, the ball is seen
    // and must not be hidden. Some balls straight behind large images must be hidden.
    const std::uint64_t seed = 20261203;
    std::mt19937_64 rng(seed);
    int missing = 0, hiddenBehind = 0, behind = 0, seen = 0;
    for (int n = 0; n < 3000; ++n) {
        // A signed 10^[lo, hi].
        auto tiny = [&](double lo, double hi) { return (rng() & 1 ? 1 : -1) * std::pow(10.0, sd::uniform(rng, lo, hi)); };
        // The camera tilted off the box's axis (image coordinates of 1e-4..1e-1, whose rounding then
        // dwarfs the image of the box's long edge) and rolled (any up).
        Camera3 cam = lookingAlongZ({50, 30, 0}, sd::uniform(rng, 20, 120), sd::uniform(rng, 0.5, 2.5));
        cam.direction = glm::normalize(Vec3{tiny(-4, -1), tiny(-4, -1), 1.0});
        cam.up = sd::unitVector(rng);
        const ViewFrustum view(cam, kUnitGrid);
        OcclusionBuffer3D buffer;
        REQUIRE(buffer.begin(view, std::array<int, 3>{16, 64, 200}[std::size_t(n % 3)]));
        const double dist = std::pow(10.0, sd::uniform(rng, 2, 9));
        const double across = dist * std::pow(10.0, sd::uniform(rng, -9, -2));
        const double along = dist * std::pow(10.0, sd::uniform(rng, -12, 0));
        // The box's z axis passes within 1e-12..1e-3 of its distance from the camera: its z edges' images
        // are about along * offset / dist long (down to rounding).
        const Vec3 c = cam.position + Vec3{tiny(-12, -3), tiny(-12, -3), 1.0} * dist;
        const Vec3 half{across * sd::uniform(rng, 0.1, 1), across * sd::uniform(rng, 0.1, 1), along};
        const Box<3> a{c - half, c + half};
        buffer.draw(a, 0);
        // A point of the box (a corner, or its centre), pushed out or in by a relative 1e-9..1e-1 across.
        Vec3 p = c;
        if (n % 4 != 0)
            for (int k = 0; k < 3; ++k) p[k] += (rng() & 1 ? 1 : -1) * half[k] * (1 + (rng() & 1 ? 1 : -1) * std::pow(10.0, sd::uniform(rng, -9, -1)));
        const Vec3 d = glm::normalize(p - cam.position);
        const double far = glm::length(p - cam.position) * sd::uniform(rng, 1.5, 4);
        const Ball<3> o{cam.position + d * far, far * 1e-12};
        if (!ref::pointInView3D(cam, o.center)) continue;
        // The ray from the camera to the ball's centre against the box grown by a relative 1e-9 (so that
        // the test's own rounding never calls a grazing ray a miss): a miss means the centre is seen.
        double t0 = 0, t1 = far;
        for (int k = 0; k < 3; ++k) {
            const double g = 1e-9 * (std::abs(c[k]) + half[k]);
            const double lo = a.min[k] - g - cam.position[k], hi = a.max[k] + g - cam.position[k];
            if (d[k] == 0) {
                if (!(lo <= 0 && hi >= 0)) t1 = -1;
                continue;
            }
            const double u = lo / d[k], v = hi / d[k];
            t0 = std::max(t0, std::min(u, v));
            t1 = std::min(t1, std::max(u, v));
        }
        const bool rayMisses = !(t0 <= t1);
        const bool hidden = buffer.hidden(o, 0);
        seen += rayMisses;
        if (rayMisses && hidden) {
            ++missing;
            UNSCOPED_INFO("seed " << seed << " case " << n << " dist " << dist << " across " << across << " along " << along);
            CHECK_FALSE(hidden);
        }
        if (n % 4 == 0) {
            ++behind;
            hiddenBehind += hidden;
        }
    }
    std::printf("[buffer] far boxes along an edge: %d balls behind centres, %d hidden; %d balls seen past the box, "
                "%d of them hidden (must be 0)\n",
                behind, hiddenBehind, seen, missing);
    CHECK(seen > 1000);
    CHECK(hiddenBehind > 0);
}

TEST_CASE("buffer: a polytope's pixel depths bound every ray of the pixel, and an unturned obb covers what its box covers", "[buffer]") {
    // OcclusionBuffer3D::drawPolytope, written plane by plane over a row's lattice points. Random oriented
    // boxes and hulls in front of random cameras: for every pixel the draw covers, rays through its four
    // corners and through random points of it must pass through the polytope's interior (its planes
    // moved in by its tolerance) and enter it no farther than the pixel's depth (the image's one fact,
    // OcclusionBuffer3D.hpp). And an oriented box without rotation is a box: its image must cover the
    // same pixels at the same depths as the box's own slab test, up to the polytope's tolerance.
    const std::uint64_t seed = 20261207;
    std::mt19937_64 rng(seed);
    std::uint64_t raysChecked = 0, pixelsCovered = 0, boxPixels = 0, obbPixels = 0, bad = 0, depthMismatch = 0;
    for (int n = 0; n < 240; ++n) {
        INFO("seed " << seed << " case " << n);
        Camera3 cam = lookingAlongZ({50, 30, 0}, sd::uniform(rng, 30, 150), sd::uniform(rng, 0.5, 2.5));
        cam.direction = glm::normalize(Vec3{sd::uniform(rng, -0.5, 0.5), sd::uniform(rng, -0.5, 0.5), 1.0});
        cam.up = sd::unitVector(rng);
        const ViewFrustum view(cam, kUnitGrid);
        const int rows = std::array<int, 3>{16, 32, 64}[std::size_t(n % 3)];
        const Vec3 centre = cam.position + cam.direction * sd::uniform(rng, 6, 60) + sd::unitVector(rng) * sd::uniform(rng, 0, 4);
        ConvexPolytope poly;
        if (n % 2 == 0) {
            const Vec3 axis = sd::unitVector(rng);
            const double angle = sd::uniform(rng, 0, kPi);
            const std::array<double, 4> q{axis.x * std::sin(angle / 2), axis.y * std::sin(angle / 2), axis.z * std::sin(angle / 2),
                                          std::cos(angle / 2)};
            const Vec3 half{sd::uniform(rng, 0.2, 5), sd::uniform(rng, 0.2, 5), sd::uniform(rng, 0.2, 5)};
            poly = makeOrientedBox(centre, half, q, "obb");
        } else {
            std::vector<Vec3> points;
            const double r = sd::uniform(rng, 0.5, 5);
            for (int k = sd::uniformInt(rng, 6, 24); k > 0; --k) points.push_back(centre + sd::unitVector(rng) * r * sd::uniform(rng, 0.3, 1));
            poly = makeConvexHull(points, "hull");
        }
        OcclusionBuffer3D buffer;
        REQUIRE(buffer.begin(view, rows));
        buffer.draw(Shape<3>(poly), 0);
        // The pixel lattice as begin() makes it: the view's rectangle enlarged by a relative 1e-6.
        const double halfW = view.tanHalfWidth() * (1 + 1e-6), halfH = view.tanHalfHeight() * (1 + 1e-6);
        const double pw = 2 * halfW / buffer.cols(), ph = 2 * halfH / buffer.rows();
        // The ray apex + t d (|d| = 1) against the planes moved in by the tolerance: whether it passes
        // through the interior, and where it enters.
        auto enters = [&](const Vec3& d, double& entry) {
            double e = 0, f = 1e300;
            for (const HalfSpace& h : poly.planes) {
                const double den = glm::dot(h.normal, d), c = h.offset - poly.tolerance - glm::dot(h.normal, cam.position);
                if (den == 0) {
                    if (!(c > 0)) return false;
                } else if (den < 0) {
                    e = std::max(e, c / den);
                } else {
                    f = std::min(f, c / den);
                }
            }
            entry = e;
            return e < f;
        };
        for (int j = 0; j < buffer.rows(); ++j)
            for (int i = 0; i < buffer.cols(); ++i) {
                const double depth = buffer.depthAt(i, j);
                if (!std::isfinite(depth)) continue;
                ++pixelsCovered;
                for (int k = 0; k < 8; ++k) {
                    // The corners (a hair inside, away from the neighbours' rounding), then random points.
                    const double u = k < 4 ? ((k & 1) ? 1 - 1e-9 : 1e-9) : sd::uniform(rng, 0, 1);
                    const double v = k < 4 ? ((k & 2) ? 1 - 1e-9 : 1e-9) : sd::uniform(rng, 0, 1);
                    const double x = -halfW + (i + u) * pw, y = -halfH + (j + v) * ph;
                    const Vec3 d = glm::normalize(view.forward() + x * view.right() + y * view.trueUp());
                    double entry = 0;
                    ++raysChecked;
                    if (!enters(d, entry) || entry > depth * (1 + 1e-7)) {
                        ++bad;
                        UNSCOPED_INFO("pixel (" << i << ", " << j << ") depth " << depth << " ray " << k << " entry " << entry);
                        CHECK(false);
                    }
                }
            }
        // The unturned obb against its box (both in front of the camera here; the box is drawn alone, so
        // no seam fuses).
        if (n % 2 == 0) {
            const Vec3 half{sd::uniform(rng, 0.2, 5), sd::uniform(rng, 0.2, 5), sd::uniform(rng, 0.2, 5)};
            const Box<3> box{centre - half, centre + half};
            const double near = glm::length(glm::clamp(cam.position, box.min, box.max) - cam.position);
            if (!(near > 0.5)) continue;
            OcclusionBuffer3D a, b;
            REQUIRE(a.begin(view, rows));
            REQUIRE(b.begin(view, rows));
            a.draw(Shape<3>(box), 0);
            b.draw(Shape<3>(makeOrientedBox(centre, half, {0, 0, 0, 1}, "obb")), 0);
            for (int j = 0; j < a.rows(); ++j)
                for (int i = 0; i < a.cols(); ++i) {
                    const double da = a.depthAt(i, j), db = b.depthAt(i, j);
                    boxPixels += std::isfinite(da);
                    obbPixels += std::isfinite(db);
                    if (std::isfinite(da) && std::isfinite(db) && std::abs(da - db) > 1e-6 * da) ++depthMismatch;
                }
        }
    }
    std::printf("[buffer] polytope draws: %llu covered pixels, %llu rays checked, %llu entering past the depth "
                "(must be 0); unturned obbs cover %llu pixels, their boxes %llu, %llu depths apart (must be 0)\n",
                (unsigned long long)pixelsCovered, (unsigned long long)raysChecked, (unsigned long long)bad,
                (unsigned long long)obbPixels, (unsigned long long)boxPixels, (unsigned long long)depthMismatch);
    CHECK(bad == 0);
    CHECK(pixelsCovered > 10000); // the draws did cover pixels
    CHECK(depthMismatch == 0);
    // The same pixels, but for a rim the tolerance may take away (a corner ray grazing a face).
    CHECK(obbPixels <= boxPixels);
    CHECK(obbPixels * 1000 >= boxPixels * 995);
}

TEST_CASE("buffer: boxes and balls around the camera cover exactly the pixels whose corner rays pass through them", "[buffer]") {
    // OcclusionBuffer3D::draw for shapes reaching behind the camera: their pixels come from the part of
    // the shape in view (rectOf's clippedRect), no longer from the whole image; and for small shapes, whose
    // draw stops when their image holds no whole pixel (pixelsOf's noPixel). Random boxes and balls around random
    // cameras (most reaching behind the camera or beside it, some wholly behind), and small ones farther
    // out, each drawn alone: a pixel all four of whose corner rays clearly pass through the shape's interior must be
    // covered, at the largest of their entry distances; a pixel with a corner ray that clearly misses must
    // stay open. Rays within a relative 1e-6 of grazing decide nothing.
    const std::uint64_t seed = 20261208;
    std::mt19937_64 rng(seed);
    std::uint64_t mustCover = 0, mustOpen = 0, wrong = 0, clipped = 0, smallCovering = 0;
    for (int n = 0; n < 400; ++n) {
        INFO("seed " << seed << " case " << n);
        Camera3 cam = lookingAlongZ({50, 30, 50}, sd::uniform(rng, 30, 150), sd::uniform(rng, 0.5, 2.5));
        cam.direction = sd::unitVector(rng);
        cam.up = sd::unitVector(rng);
        const ViewFrustum view(cam, kUnitGrid);
        const int rows = std::array<int, 3>{16, 32, 64}[std::size_t(n % 3)];
        const Vec3 o = cam.position; // shapes relative to the apex below
        // One case in three: a small shape farther out, one to three pixels across, where the draw's
        // early exit for an image holding no whole pixel (OcclusionBuffer3D::pixelsOf's noPixel) decides.
        const bool small = n % 3 == 2;
        const Vec3 centre = small ? o + glm::normalize(view.forward() + sd::unitVector(rng) * 0.4) * sd::uniform(rng, 20, 80)
                                  : o + sd::unitVector(rng) * sd::uniform(rng, 0, 12);
        const bool ball = n % 4 == 3;
        const double size = small ? 0.25 : 1.0, least = small ? 0.05 : 0.3;
        const Vec3 half{sd::uniform(rng, least, 10 * size), sd::uniform(rng, least, 10 * size), sd::uniform(rng, least, 10 * size)};
        const double radius = sd::uniform(rng, least, 10 * size);
        const Shape<3> shape = ball ? Shape<3>(Ball<3>{centre, radius}) : Shape<3>(Box<3>{centre - half, centre + half});
        // The camera inside, or within a hair of, the shape is not drawn at all: not this test's case.
        const Box<3> bounds = boundsOf<3>(shape);
        const double gap = ball ? glm::length(centre - o) - radius : glm::length(glm::clamp(o, bounds.min, bounds.max) - o);
        if (!(gap > 0.05)) continue;
        clipped += glm::dot(bounds.min - o, view.forward()) < 0 || glm::dot(bounds.max - o, view.forward()) < 0 ||
                   ball && glm::dot(centre - o, view.forward()) < radius * 1.001;
        OcclusionBuffer3D buffer;
        REQUIRE(buffer.begin(view, rows));
        buffer.draw(shape, 0);
        const double halfW = view.tanHalfWidth() * (1 + 1e-6), halfH = view.tanHalfHeight() * (1 + 1e-6);
        const double pw = 2 * halfW / buffer.cols(), ph = 2 * halfH / buffer.rows();
        // Along the unit ray t d: +1 with its entry when it clearly passes through the interior, -1 when it
        // clearly misses, 0 near grazing.
        auto through = [&](const Vec3& d, double& entry) {
            if (ball) {
                const Vec3 c = centre - o;
                const double cd = glm::dot(c, d), q = radius * radius - (glm::dot(c, c) - cd * cd);
                const double tol = 1e-6 * (glm::length(c) + radius);
                if (cd <= 0 || q <= 0) return cd < -tol || q < -tol * radius ? -1 : 0;
                entry = cd - std::sqrt(q);
                return std::sqrt(q) > tol ? 1 : 0;
            }
            double e = -1e300, f = 1e300;
            for (int a = 0; a < 3; ++a) {
                const double lo = bounds.min[a] - o[a], hi = bounds.max[a] - o[a];
                if (d[a] == 0) {
                    if (!(lo < 0 && hi > 0)) return -1;
                    continue;
                }
                const double t1 = lo / d[a], t2 = hi / d[a];
                e = std::max(e, std::min(t1, t2));
                f = std::min(f, std::max(t1, t2));
            }
            const double tol = 1e-6 * (std::abs(f) + 1);
            entry = e;
            if (e > tol && f - e > tol) return 1;
            return f < -tol || f - e < -tol ? -1 : 0;
        };
        for (int j = 0; j < buffer.rows(); ++j)
            for (int i = 0; i < buffer.cols(); ++i) {
                int in = 0, out = 0;
                double farthest = 0;
                for (int k = 0; k < 4; ++k) {
                    const double x = -halfW + (i + (k & 1)) * pw, y = -halfH + (j + (k >> 1)) * ph;
                    const Vec3 d = glm::normalize(view.forward() + x * view.right() + y * view.trueUp());
                    double entry = 0;
                    const int r = through(d, entry);
                    in += r > 0;
                    out += r < 0;
                    if (r > 0) farthest = std::max(farthest, entry);
                }
                const double depth = buffer.depthAt(i, j);
                if (in == 4) {
                    ++mustCover;
                    smallCovering += small;
                    if (!(std::abs(depth - farthest) <= 1e-6 * farthest)) {
                        ++wrong;
                        UNSCOPED_INFO("pixel (" << i << ", " << j << ") depth " << depth << ", its corner rays enter by " << farthest);
                        CHECK(false);
                    }
                } else if (out > 0) {
                    ++mustOpen;
                    if (!std::isinf(depth)) {
                        ++wrong;
                        UNSCOPED_INFO("pixel (" << i << ", " << j << ") depth " << depth << " with a corner ray missing the shape");
                        CHECK(false);
                    }
                }
            }
    }
    std::printf("[buffer] shapes around the camera: %llu pixels to cover (%llu of small far shapes), %llu to leave open, "
                "%llu wrong (must be 0); %llu shapes reached behind the camera\n",
                (unsigned long long)mustCover, (unsigned long long)smallCovering, (unsigned long long)mustOpen,
                (unsigned long long)wrong, (unsigned long long)clipped);
    CHECK(wrong == 0);
    CHECK(mustCover > 20000);
    CHECK(mustOpen > 20000);
    CHECK(clipped > 100);
    CHECK(smallCovering > 50); // small shapes that do cover a pixel or two were drawn
}

TEST_CASE("buffer: a clipped draw writes only the pixels of its clip", "[buffer]") {
    // OcclusionBuffer3D::draw with a clip (refineWithBuffer draws the walk's occluders again over the
    // pixels of the one occludee that needs them): the same depths inside the clip, none outside.
    const ViewFrustum view(lookingAlongZ(), kUnitGrid);
    OcclusionBuffer3D full, clipped;
    REQUIRE(full.begin(view, 64));
    REQUIRE(clipped.begin(view, 64));
    const Shape<3> wall = Box<3>{{20, 0, 20}, {80, 60, 21}};
    const Shape<3> ball = Ball<3>{{50, 30, 15}, 4};
    const ImageFootprint3D::Rect clip{10, 40, 20, 43}; // holds the image centre column, rows 27 and 36
    for (const Shape<3>* s : {&wall, &ball}) {
        full.draw(*s, 0);
        clipped.draw(*s, 0, clip);
    }
    int inside = 0;
    for (int j = 0; j < full.rows(); ++j)
        for (int i = 0; i < full.cols(); ++i) {
            const bool in = i >= clip.i0 && i <= clip.i1 && j >= clip.j0 && j <= clip.j1;
            if (in) {
                CHECK(clipped.depthAt(i, j) == full.depthAt(i, j));
                inside += std::isfinite(full.depthAt(i, j));
            } else {
                CHECK(std::isinf(clipped.depthAt(i, j)));
            }
        }
    CHECK(inside == (clip.i1 - clip.i0 + 1) * (clip.j1 - clip.j0 + 1)); // the wall covers the whole clip
    // Behind the wall, inside the clip: hidden in both; outside it only in the full image.
    CHECK(clipped.hidden(Ball<3>{{50, 27, 40}, 0.5}, 0));
    CHECK(full.hidden(Ball<3>{{50, 27, 40}, 0.5}, 0));
    CHECK(full.hidden(Ball<3>{{70, 50, 40}, 0.5}, 0));
    CHECK_FALSE(clipped.hidden(Ball<3>{{70, 50, 40}, 0.5}, 0));
}

TEST_CASE("buffer: a sphere in front of the camera is tested pixel by pixel", "[buffer]") {
    // OcclusionBuffer3D::hiddenBall: each pixel against the nearest point of the sphere it shows. Behind
    // the sphere S (14.5 degrees across its half-angle) lies a sphere 12 degrees across whose tangent
    // rectangle's corners (16.8 degrees off the axis) S does not cover: the rectangle alone fails there,
    // the pixels that show the sphere are all covered by S nearer than it.
    const ViewFrustum view(lookingAlongZ(), kUnitGrid);
    OcclusionBuffer3D buffer;
    for (int rows : {64, 128, 256}) { // pixels under 1 degree: the margins below are 1.5 degrees and more
        INFO("rows " << rows);
        REQUIRE(buffer.begin(view, rows));
        buffer.draw(Ball<3>{{50, 30, 20}, 5}, 0);
        const double d = 45.2, deg = kPi / 180;
        CHECK(buffer.hidden(Ball<3>{{50, 30, d}, d * std::sin(12 * deg)}, 0));
        // Off the axis by 2 degrees: still inside S's silhouette.
        CHECK(buffer.hidden(Ball<3>{{50 + d * std::tan(2 * deg), 30, d}, d * std::sin(11 * deg)}, 0));
        // Wider than the silhouette by 1.5 degrees, centred or shifted: its rim is seen.
        CHECK_FALSE(buffer.hidden(Ball<3>{{50, 30, d}, d * std::sin(16 * deg)}, 0));
        CHECK_FALSE(buffer.hidden(Ball<3>{{50 + d * std::tan(4 * deg), 30, d}, d * std::sin(12 * deg)}, 0));
        // In front of S's far side but behind its near side along every ray it is seen through: hidden
        // only where S's entry is nearer; a sphere reaching in front of S's near surface is seen.
        CHECK_FALSE(buffer.hidden(Ball<3>{{50, 30, 16}, 2}, 0));
    }
}

TEST_CASE("buffer: what the exact pixel tests hide behind patchy rows is covered nearer along every ray", "[buffer]") {
    // hiddenBoxExact and hiddenBall compute a pixel's bound (the nearest entry its rays can have) only
    // where the image is not already covered nearer than the occludee's nearest point: row by row, over
    // column ranges that change from row to row, skipping rows. Walls in front, some seen at an angle
    // (their depths spread across a pixel), make such rows. Checked independently of that bookkeeping: a
    // box or ball they hide (not by the object-space shadow proof) has no ray through it, 5 x 5 sampled
    // per pixel, that enters it no farther than its pixel's depth; every bound the tests compare with is
    // at most each such entry. Failing this means a stale or missing bound let a seen part through.
    const std::uint64_t seed = 20261207;
    std::mt19937_64 rng(seed);
    int tested = 0, hidden = 0, exact = 0, bad = 0;
    for (int n = 0; n < 150; ++n) {
        const double yaw = sd::uniform(rng, -50, 50) * kPi / 180, pitch = sd::uniform(rng, -15, 15) * kPi / 180;
        Camera3 cam = lookingAlongZ({50, 30, 0}, sd::uniform(rng, 40, 90), sd::uniform(rng, 1, 1.8));
        cam.direction = {std::sin(yaw) * std::cos(pitch), std::sin(pitch), std::cos(yaw) * std::cos(pitch)};
        const ViewFrustum view(cam, kUnitGrid);
        OcclusionBuffer3D buffer;
        REQUIRE(buffer.begin(view, std::array<int, 3>{24, 48, 64}[std::size_t(n % 3)]));
        // Walls 1 voxel thick, across the axis or along it (seen at an angle), with gaps between them.
        for (int w = 0; w < 6; ++w) {
            const Vec3 c{sd::uniform(rng, 20, 80), sd::uniform(rng, 15, 45), sd::uniform(rng, 12, 30)};
            const bool along = rng() % 2 == 0;
            const Vec3 h = along ? Vec3{0.5, sd::uniform(rng, 8, 25), sd::uniform(rng, 8, 25)}
                                 : Vec3{sd::uniform(rng, 8, 25), sd::uniform(rng, 8, 25), 0.5};
            buffer.draw(Box<3>{c - h, c + h}, 0);
        }
        const Vec3 apex = view.apex(), fw = view.forward(), rt = view.right(), up = view.trueUp();
        const double th = view.tanHalfWidth(), tv = view.tanHalfHeight();
        const double pw = 2 * th / buffer.cols(), ph = 2 * tv / buffer.rows();
        for (int k = 0; k < 30; ++k) {
            const Vec3 c{sd::uniform(rng, 20, 80), sd::uniform(rng, 15, 45), sd::uniform(rng, 14, 40)};
            const bool ball = rng() % 2 == 0;
            const Vec3 h{sd::uniform(rng, 0.3, 10), sd::uniform(rng, 0.3, 10), sd::uniform(rng, 0.3, 10)};
            const Shape<3> shape = ball ? Shape<3>(Ball<3>{c, h.x}) : Shape<3>(Box<3>{c - h, c + h});
            // Wholly in front of the camera (a ball reaching behind it takes the 8-part refinement).
            if (!(glm::dot(c - apex, fw) > glm::length(h) + 1)) continue;
            ++tested;
            const auto shadowedBefore = buffer.stats().shadowed;
            if (!buffer.hidden(shape, 0) || buffer.stats().shadowed != shadowedBefore) continue;
            ++hidden;
            const double nearest = buffer.nearestDistance(shape, 0);
            bool pastNearest = false; // a hit ray's pixel not covered nearer than the nearest point: the
                                      // per-pixel bounds decided the verdict, not the rectangle's scan
            for (int j = 0; j < buffer.rows(); ++j)
                for (int i = 0; i < buffer.cols(); ++i)
                    for (int s = 0; s < 25; ++s) {
                        const double x = -th + (i + 0.1 + 0.2 * (s % 5)) * pw, y = -tv + (j + 0.1 + 0.2 * (s / 5)) * ph;
                        const Vec3 d = glm::normalize(fw + x * rt + y * up);
                        double entry = -1;
                        if (ball) {
                            const Vec3 q = c - apex;
                            const double b = glm::dot(q, d), disc = b * b - (glm::dot(q, q) - h.x * h.x);
                            if (disc > 0) entry = b - std::sqrt(disc);
                        } else {
                            double t0 = 0, t1 = 1e300;
                            for (int a = 0; a < 3; ++a) {
                                const double lo = (c[a] - h[a] - apex[a]) / d[a], hi = (c[a] + h[a] - apex[a]) / d[a];
                                t0 = std::max(t0, std::min(lo, hi));
                                t1 = std::min(t1, std::max(lo, hi));
                            }
                            if (t0 < t1) entry = t0;
                        }
                        if (!(entry > 0)) continue;
                        const double depth = buffer.depthAt(i, j);
                        pastNearest = pastNearest || !(depth < nearest);
                        if (depth < entry) continue;
                        ++bad;
                        UNSCOPED_INFO("seed " << seed << " case " << n << " occludee " << k << (ball ? " ball" : " box")
                                              << " pixel " << i << "," << j << " depth " << depth << " entry " << entry);
                    }
            exact += pastNearest;
        }
    }
    std::printf("[buffer] patchy rows: %d occludees tested, %d hidden, %d of them by per-pixel bounds past the "
                "nearest distance, %d rays seen nearer than their pixel's depth (must be 0)\n", tested, hidden, exact, bad);
    CHECK(bad == 0);
    CHECK(exact >= 30); // the per-pixel path is what this test is about
}

TEST_CASE("buffer: an occludee grazing an occluder's silhouette is never hidden", "[buffer]") {
    // Sphere S in front; a sphere far behind whose cone pokes out of S's cone by a tiny angle on one side,
    // in random directions and sizes, at several buffer resolutions. The poking part is visible (a ray
    // through it misses S), so a hidden verdict would be a miss.
    const std::uint64_t seed = 20261130;
    std::mt19937_64 rng(seed);
    int cases = 0, hiddenCount = 0;
    for (int n = 0; n < 3000; ++n) {
        const Camera3 cam = lookingAlongZ({50, 30, 0}, sd::uniform(rng, 20, 120), sd::uniform(rng, 0.5, 2.5));
        const ViewFrustum view(cam, kUnitGrid);
        OcclusionBuffer3D buffer;
        const int rows = std::array<int, 4>{8, 33, 64, 150}[std::size_t(n % 4)];
        REQUIRE(buffer.begin(view, rows));
        // S: centre within 15 degrees of the axis, distance 5..40, angular radius 1..20 degrees.
        const double dist = sd::uniform(rng, 5, 40), alpha = sd::uniform(rng, 1, 20) * kPi / 180;
        Vec3 dirS = glm::normalize(Vec3{sd::uniform(rng, -0.25, 0.25), sd::uniform(rng, -0.25, 0.25), 1.0});
        const Ball<3> s{cam.position + dirS * dist, dist * std::sin(alpha)};
        // The occludee: cone of half-angle beta around dirO, touching S's cone from inside except for a poke of
        // `poke` radians: the angle between dirS and dirO plus beta = alpha + poke.
        const double poke = std::pow(10.0, sd::uniform(rng, -7, -2));
        const double beta = sd::uniform(rng, 0.1, 0.95) * alpha;
        const Vec3 side = glm::normalize(glm::cross(dirS, sd::unitVector(rng)));
        const double tilt = alpha + poke - beta;
        const Vec3 dirO = dirS * std::cos(tilt) + side * std::sin(tilt);
        const double distO = dist * sd::uniform(rng, 2, 6);
        const Ball<3> o{cam.position + dirO * distO, distO * std::sin(beta)};
        buffer.draw(s, 0);
        const bool hidden = buffer.hidden(o, 0);
        // The poking direction must be inside the view for the case to count; otherwise either verdict is right.
        const Vec3 pokeDir = dirS * std::cos(alpha + poke * 0.5) + side * std::sin(alpha + poke * 0.5);
        if (!ref::pointInView3D(cam, cam.position + pokeDir * distO)) continue;
        ++cases;
        hiddenCount += hidden;
        if (hidden) {
            UNSCOPED_INFO("seed " << seed << " case " << n << " rows " << rows << " poke " << poke << " alpha " << alpha);
            CHECK_FALSE(hidden);
        }
    }
    std::printf("[buffer] grazing silhouettes: %d cases in view, %d hidden (must be 0)\n", cases, hiddenCount);
    CHECK(cases > 1000);
}

TEST_CASE("buffer: random scenes against the exact reference", "[buffer]") {
    // Random scenes of the culler's test mixture (spheres and boxes from tiny to a third of the grid, walls
    // of boxes and of touching spheres, cameras on corners and inside objects), the whole pass as the culler
    // runs it, at several resolutions and slacks. Every object the buffer hides must be one the reference
    // does not see.
    const std::uint64_t seed0 = 7100;
    ref::SceneOptions3D opt;
    opt.maxObjects = 120;
    int scenes = 0, tested = 0, hiddenCount = 0, visibleCount = 0;
    for (std::uint64_t k = 0; k < 500; ++k) {
        const ref::Scene3D scene = ref::randomScene3D(seed0 + k, opt);
        const ViewFrustum view(scene.camera, scene.grid);
        const auto [world, local, slack] = localScene(scene, view);
        OcclusionBuffer3D buffer;
        const int rows = std::array<int, 5>{1, 16, 64, 97, 256}[k % 5];
        if (!buffer.begin(view, rows)) continue;
        const std::vector<bool> hidden = bufferPass(buffer, local, slack);
        const std::vector<bool> seen = ref::visible3D(world, scene.camera);
        ++scenes;
        for (std::size_t i = 0; i < world.size(); ++i) {
            ++tested;
            hiddenCount += hidden[i];
            visibleCount += seen[i];
            if (hidden[i] && seen[i]) {
                UNSCOPED_INFO("seed " << scene.seed << " object " << scene.objects[i].id << " rows " << rows
                                      << "\n" << ref::toJson(scene));
                CHECK_FALSE((hidden[i] && seen[i]));
            }
        }
    }
    std::printf("[buffer] random scenes: %d scenes, %d objects, %d seen by the reference, %d hidden by the buffer, "
                "0 of them seen allowed\n",
                scenes, tested, visibleCount, hiddenCount);
    CHECK(scenes > 400);
    CHECK(hiddenCount > 0);
}

TEST_CASE("buffer: room corners of touching boxes seen at wide views against the exact reference", "[buffer]") {
    // Seam fusion (OcclusionSeams3D.cpp) covers pixels that only the union of two or three boxes covers.
    // Here: the three walls of a room's corner (slabs meeting at a point, overlapping there or just
    // meeting, some cut into tiles that share faces), occludees behind them (some poking past a wall's
    // end) and in front, cameras inside the corner's octant looking towards it with 40-170 degree views.
    // Every object the buffer hides must be one the reference does not see, and the fusion must run.
    const std::uint64_t seed = 90210;
    std::mt19937_64 rng(seed);
    int tested = 0, hiddenCount = 0, misses = 0;
    std::uint64_t fused = 0;
    for (int n = 0; n < 600; ++n) {
        const Vec3 p{sd::uniform(rng, 30, 70), sd::uniform(rng, 30, 70), sd::uniform(rng, 30, 70)};
        const double t = sd::uniform(rng, 0.3, 2.0), len = sd::uniform(rng, 8, 25);
        const double past = n % 2 == 0 ? t : 0.0; // walls overlapping at the corner, or meeting face to face
        std::vector<Shape<3>> objects;
        for (int a = 0; a < 3; ++a) {
            Vec3 lo = p - past, hi = p + len;
            lo[a] = p[a] - t;
            hi[a] = p[a];
            const int tiles = 1 + n % 3; // cut along the next axis into tiles sharing their faces
            const int b = (a + 1) % 3;
            for (int k = 0; k < tiles; ++k) {
                Vec3 l = lo, h = hi;
                l[b] = lo[b] + (hi[b] - lo[b]) * k / tiles;
                h[b] = lo[b] + (hi[b] - lo[b]) * (k + 1) / tiles;
                objects.push_back(Box<3>{l, h});
            }
        }
        const std::size_t walls = objects.size();
        for (int i = 0; i < 24; ++i) { // behind the walls near the corner, a few in front
            const bool front = i % 6 == 0;
            Vec3 c;
            for (int a = 0; a < 3; ++a) c[a] = p[a] + (front ? sd::uniform(rng, 1, len - 1) : sd::uniform(rng, -6, len));
            if (!front) c[i % 3] = p[i % 3] - t - sd::uniform(rng, 0.2, 5);
            const double r = sd::logUniform(rng, 0.1, 1.5);
            objects.push_back(i % 2 == 0 ? Shape<3>(Ball<3>{c, r}) : Shape<3>(Box<3>{c - r, c + r}));
        }
        const Vec3 eye = p + Vec3{sd::uniform(rng, 1, len - 1), sd::uniform(rng, 1, len - 1), sd::uniform(rng, 1, len - 1)};
        Vec3 dir = p - eye;
        for (int a = 0; a < 3; ++a) dir[a] += sd::uniform(rng, -0.3, 0.3) * std::sqrt(lengthSquared<3>(p - eye));
        Camera3 cam = lookingAlongZ(eye, sd::uniform(rng, 40, 170), sd::uniform(rng, 0.5, 2));
        cam.direction = dir;
        const ViewFrustum view(cam, kUnitGrid);
        OcclusionBuffer3D buffer;
        const int rows = std::array<int, 3>{16, 64, 128}[n % 3];
        REQUIRE(buffer.begin(view, rows));
        const std::vector<bool> hidden = bufferPass(buffer, objects, view.slack());
        fused += buffer.stats().pixelsFused;
        const std::vector<bool> seen = ref::visible3D(objects, cam);
        for (std::size_t i = walls; i < objects.size(); ++i) {
            ++tested;
            hiddenCount += hidden[i];
            if (hidden[i] && seen[i]) {
                ++misses;
                UNSCOPED_INFO("seed " << seed << " scene " << n << " object " << i << " rows " << rows);
                CHECK_FALSE((hidden[i] && seen[i]));
            }
        }
    }
    std::printf("[buffer] room corners: %d occludees, %d hidden by the buffer, %llu pixels covered by fusion, %d misses\n",
                tested, hiddenCount, (unsigned long long)fused, misses);
    CHECK(misses == 0);
    CHECK(fused > 0);
    CHECK(hiddenCount > tested / 2);
}

TEST_CASE("buffer: sphere clouds against the exact reference", "[buffer]") {
    // The case the buffer is for: many small spheres (below two voxels) in front of the camera, where the
    // grid's O is empty. Checks misses and that a good part of what the reference does not see is hidden.
    const std::uint64_t seed = 424242;
    std::mt19937_64 rng(seed);
    int inView = 0, seenCount = 0, hiddenCount = 0, misses = 0;
    for (int n = 0; n < sanitizedShare(40); ++n) { // 20 clouds under ASan (kSanitized)
        const Camera3 cam = lookingAlongZ({50, 30, 0}, sd::uniform(rng, 40, 90), sd::uniform(rng, 0.8, 2));
        std::vector<Shape<3>> objects;
        for (int i = 0; i < 400; ++i) {
            const Vec3 c{sd::uniform(rng, 35, 65), sd::uniform(rng, 15, 45), sd::uniform(rng, 3, 60)};
            objects.push_back(Ball<3>{c, sd::logUniform(rng, 0.3, 2.5)});
        }
        const ViewFrustum view(cam, kUnitGrid);
        OcclusionBuffer3D buffer;
        REQUIRE(buffer.begin(view, 64));
        const std::vector<bool> hidden = bufferPass(buffer, objects, view.slack());
        const std::vector<bool> seen = ref::visible3D(objects, cam);
        const std::vector<bool> view3 = ref::inViewRegion3D(objects, cam);
        for (std::size_t i = 0; i < objects.size(); ++i) {
            inView += view3[i];
            seenCount += seen[i];
            hiddenCount += hidden[i] && view3[i];
            if (hidden[i] && seen[i]) {
                ++misses;
                UNSCOPED_INFO("seed " << seed << " scene " << n << " object " << i);
                CHECK_FALSE((hidden[i] && seen[i]));
            }
        }
    }
    const int hiddenInView = inView - seenCount;
    std::printf("[buffer] sphere clouds: %d in view, %d seen, %d hidden by the buffer of %d not seen (%.0f%%), %d misses\n",
                inView, seenCount, hiddenCount, hiddenInView, 100.0 * hiddenCount / std::max(1, hiddenInView), misses);
    CHECK(misses == 0);
    CHECK(hiddenCount * 2 > hiddenInView); // most of the hidden objects in view are left out
}

TEST_CASE("buffer: a refined image inherits the coarse image's depths and what it hides", "[buffer]") {
    // beginRefined: every fine pixel starts at the depth of the coarse pixel that contains it, so what the
    // coarse image hides the refined one hides without drawing anything again.
    const Camera3 cam = lookingAlongZ({50, 30, 0}, 60, 1.6);
    const ViewFrustum view(cam, kUnitGrid);
    OcclusionBuffer3D coarse, fine;
    REQUIRE(coarse.begin(view, 32));
    coarse.draw(Box<3>{{40, 20, 20}, {60, 40, 21}}, 0);
    coarse.draw(Ball<3>{{35, 30, 30}, 4}, 0);
    for (const int factor : {1, 2, 3, 4, 5}) { // (1-4 spread with the factor a constant, 5 the general path)
        REQUIRE(fine.beginRefined(coarse, factor));
        CHECK(fine.rows() == coarse.rows() * factor);
        CHECK(fine.cols() == coarse.cols() * factor);
        int mismatched = 0;
        for (int j = 0; j < fine.rows(); ++j)
            for (int i = 0; i < fine.cols(); ++i) mismatched += fine.depthAt(i, j) != coarse.depthAt(i / factor, j / factor);
        CHECK(mismatched == 0);
        CHECK(fine.stats().occludersDrawn == 0);
        CHECK(fine.hidden(Ball<3>{{50, 30, 40}, 5}, 0));
        CHECK(fine.hidden(Box<3>{{45, 25, 30}, {55, 35, 31}}, 0));
        CHECK_FALSE(fine.hidden(Box<3>{{40, 20, 10}, {60, 40, 11}}, 0)); // in front of the wall
        CHECK_FALSE(fine.hidden(Ball<3>{{50, 30, 60}, 30}, 0));          // wider than the wall's image
    }
    // Limits: an inactive coarse image, a factor below 1, or more than kMaxExtent pixels a side.
    OcclusionBuffer3D idle;
    CHECK_FALSE(fine.beginRefined(idle, 2));
    CHECK_FALSE(fine.beginRefined(coarse, 0));
    CHECK_FALSE(fine.beginRefined(coarse, OcclusionBuffer3D::kMaxExtent));
    CHECK_FALSE(fine.hidden(Ball<3>{{50, 30, 40}, 1}, 0)); // a failed begin hides nothing
}

TEST_CASE("buffer: random scenes through a coarse image refined, against the exact reference", "[buffer]") {
    // The culler's order (CullerOptions::bufferFromTraversalImage): a coarse image gets the large objects
    // (the walk draws those), a refined image of it then tests every object nearest first and draws only
    // those the coarse one did not get. Every object hidden must be one the reference does not see, and
    // the refined pass must hide some.
    const std::uint64_t seed0 = 7700;
    ref::SceneOptions3D opt;
    opt.maxObjects = 120;
    int scenes = 0, tested = 0, hiddenCount = 0, misses = 0;
    for (std::uint64_t k = 0; k < 300; ++k) {
        const ref::Scene3D scene = ref::randomScene3D(seed0 + k, opt);
        const ViewFrustum view(scene.camera, scene.grid);
        const auto [world, local, slack] = localScene(scene, view);
        OcclusionBuffer3D coarse, fine;
        const int rows = std::array<int, 4>{8, 17, 32, 50}[k % 4], factor = 1 + int(k % 3);
        if (!coarse.begin(view, rows)) continue;
        std::vector<bool> drawn(local.size(), false);
        for (std::size_t i = 0; i < local.size(); ++i)
            if (boundingBall<3>(local[i]).radius >= 2) { // "large"; the coarse image tests nothing here
                coarse.draw(local[i], slack);
                drawn[i] = true;
            }
        REQUIRE(fine.beginRefined(coarse, factor));
        std::vector<std::pair<double, std::size_t>> order;
        for (std::size_t i = 0; i < local.size(); ++i) order.push_back({fine.nearestDistance(local[i], slack), i});
        std::sort(order.begin(), order.end());
        std::vector<bool> hidden(local.size(), false);
        for (const auto& [d, i] : order) {
            if (fine.hidden(local[i], slack, d)) hidden[i] = true;
            else if (!drawn[i]) fine.draw(local[i], slack);
        }
        const std::vector<bool> seen = ref::visible3D(world, scene.camera);
        ++scenes;
        for (std::size_t i = 0; i < world.size(); ++i) {
            ++tested;
            hiddenCount += hidden[i];
            if (hidden[i] && seen[i]) {
                ++misses;
                UNSCOPED_INFO("seed " << scene.seed << " object " << scene.objects[i].id << " rows " << rows << " factor "
                                      << factor << "\n" << ref::toJson(scene));
                CHECK_FALSE((hidden[i] && seen[i]));
            }
        }
    }
    std::printf("[buffer] refined images: %d scenes, %d objects, %d hidden, %d misses\n", scenes, tested, hiddenCount, misses);
    CHECK(misses == 0);
    CHECK(scenes > 250);
    CHECK(hiddenCount > 0);
}
