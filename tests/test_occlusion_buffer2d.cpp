// OcclusionBuffer2D: fixed cases, occludees grazing occluders' silhouettes, the +-pi seam and the full
// circle, and random scenes against the exact 2D reference (an object the buffer hides must be one the
// reference does not see). Tag: [buffer2d].
#include "CullerTestSupport.hpp"

#include "rgvc/grid/FastAtan2.hpp"
#include "rgvc/grid/OcclusionBuffer2D.hpp"
#include "rgvc/grid/ViewWedge.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <utility>
#include <vector>

using namespace rgvc;
namespace ref = rgvc::reference;
namespace sd = rgvc::reference::seeded;
using rgvc::culler_test::bufferPass;
using rgvc::culler_test::kPi;
using rgvc::culler_test::makeCamera;

namespace {

const GridGeometry2 kUnitGrid(Vec2(0.0), 1.0, IVec2(100));

Vec2 unitAt(double angle) { return {std::cos(angle), std::sin(angle)}; }

/// Angular extent [lo, hi] of a shape's vertices (or a disc) seen from `eye`, as angles around `mid`'s
/// direction (the shape must not hold the eye).
std::pair<double, double> extentOf(const Shape<2>& s, const Vec2& eye) {
    const Vec2 mid = boundingBall<2>(s).center - eye;
    const double base = std::atan2(mid.y, mid.x);
    auto rel = [&](const Vec2& p) {
        const Vec2 v = p - eye;
        return base + std::atan2(cross2(mid, v), glm::dot(mid, v));
    };
    if (const auto* b = std::get_if<Ball<2>>(&s)) {
        const double a = std::asin(b->radius / std::sqrt(lengthSquared<2>(mid)));
        return {base - a, base + a};
    }
    std::vector<Vec2> pts;
    if (const auto* x = std::get_if<Box<2>>(&s))
        pts = {x->min, {x->max.x, x->min.y}, x->max, {x->min.x, x->max.y}};
    else
        pts = std::get<ConvexPolygon>(s).points;
    double lo = 1e9, hi = -1e9;
    for (const Vec2& p : pts) {
        lo = std::min(lo, rel(p));
        hi = std::max(hi, rel(p));
    }
    return {lo, hi};
}

} // namespace

TEST_CASE("buffer2d: fastAtan2 stays within its bound of std::atan2", "[buffer2d]") {
    // The bound's derivation (FastAtan2.hpp) samples the octant's t every 1e-8; here every 1e-7, the
    // octant edges (t near 0 and 1) finer, and directions around the whole circle at many scales.
    double worst = 0;
    for (int i = 0; i <= 10'000'000; ++i) {
        const double t = i * 1e-7;
        worst = std::max(worst, std::abs(fastAtan2(t, 1.0) - std::atan2(t, 1.0)));
    }
    for (int i = 0; i <= 100'000; ++i) {
        const double t = i * 1e-11;
        worst = std::max(worst, std::abs(fastAtan2(t, 1.0) - std::atan2(t, 1.0)));
        worst = std::max(worst, std::abs(fastAtan2(1.0 - t, 1.0) - std::atan2(1.0 - t, 1.0)));
    }
    INFO("octant: largest error " << worst);
    CHECK(worst < 2e-9); // the measured 1.51e-9, well inside kFastAtan2MaxError = 1e-7
    std::mt19937_64 rng(0xa7a2);
    std::uniform_real_distribution<double> angle(-kPi, kPi), scale(-300.0, 300.0);
    worst = 0;
    for (int i = 0; i < 1'000'000; ++i) {
        const double a = angle(rng), r = std::exp2(scale(rng) * 0.1);
        const double x = r * std::cos(a), y = r * std::sin(a);
        worst = std::max(worst, std::abs(fastAtan2(y, x) - std::atan2(y, x)));
    }
    INFO("circle (seed 0xa7a2): largest error " << worst);
    CHECK(worst < kFastAtan2MaxError);
    // Signs of zero and the octant edges as std::atan2; NaN where nothing is known.
    for (const double x : {1.0, -1.0, 0.0, -0.0, 2.5, -1e-300})
        for (const double y : {1.0, -1.0, 0.0, -0.0, 1e-300, -7.0}) {
            INFO("atan2(" << y << ", " << x << ")");
            CHECK(std::abs(fastAtan2(y, x) - std::atan2(y, x)) < kFastAtan2MaxError);
            CHECK(std::signbit(fastAtan2(y, x)) == std::signbit(std::atan2(y, x)));
        }
    const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
    CHECK(fastAtan2(inf, 1.0) == Approx(kPi / 2));
    CHECK(fastAtan2(1.0, -inf) == Approx(kPi));
    CHECK(std::isnan(fastAtan2(nan, 1.0)));
    CHECK(std::isnan(fastAtan2(1.0, nan)));
    CHECK(std::isnan(fastAtan2(inf, inf)));
}

TEST_CASE("buffer2d: fixed occluders and occludees", "[buffer2d]") {
    const Camera2 cam = makeCamera({50, 50}, {1, 0}, 90);
    const ViewWedge view(cam, kUnitGrid);
    OcclusionBuffer2D buffer;
    REQUIRE(buffer.begin(view, 64));
    CHECK(buffer.bins() == 64);
    CHECK_FALSE(buffer.fullCircle());
    // A wall across the view: its interior is crossed by the rays within 45 degrees of the axis.
    const Shape<2> wall = Box<2>{{60, 40}, {61, 60}};
    buffer.draw(wall, 0);
    CHECK(buffer.stats().occludersDrawn == 1);
    CHECK(buffer.stats().binsCovered > 50);
    CHECK(buffer.depthAt(32) == Approx(10.0).epsilon(1e-3));
    // Behind the wall, within its silhouette: hidden.
    CHECK(buffer.hidden(Ball<2>{{80, 50}, 2}, 0));
    CHECK(buffer.hidden(Ball<2>{{80, 70}, 1}, 0)); // 33.7 degrees off the axis
    CHECK(buffer.hidden(Box<2>{{70, 45}, {72, 55}}, 0));
    CHECK(buffer.hidden(ConvexPolygon{{{70, 45}, {75, 50}, {70, 55}}}, 0));
    CHECK(buffer.hidden(ConvexPolygon{{{70, 55}, {75, 50}, {70, 45}}}, 0)); // clockwise
    // Wider than the silhouette, beside it, in front of it, or holding the camera: not hidden.
    CHECK_FALSE(buffer.hidden(Ball<2>{{80, 50}, 25}, 0));  // asin(25/30) = 56 degrees
    // At 45 degrees, the wedge's edge is also the ray through the wall's corner, which only touches the wall:
    // the circle is seen along that one ray.
    CHECK_FALSE(buffer.hidden(Ball<2>{{80, 80}, 1}, 0));
    CHECK_FALSE(buffer.hidden(Ball<2>{{55, 50}, 1}, 0));   // in front of the wall
    CHECK_FALSE(buffer.hidden(Ball<2>{{50, 50}, 0.5}, 0)); // holds the camera
    CHECK_FALSE(buffer.hidden(Box<2>{{49, 49}, {70, 51}}, 0));
    // Overlapping the wall but starting behind its near face on every ray towards it.
    CHECK(buffer.hidden(Box<2>{{60.5, 48}, {62, 52}}, 0));
    // Growing the occludee by its slack can only make it visible.
    CHECK_FALSE(buffer.hidden(Ball<2>{{80, 50}, 2}, 40));
    // Behind the camera (outside the 90 degree wedge): no point in view, hidden with or without occluders.
    CHECK(buffer.hidden(Ball<2>{{30, 50}, 1}, 0));
    CHECK(buffer.hidden(Box<2>{{20, 20}, {25, 80}}, 0));
    CHECK(buffer.hidden(Ball<2>{{80, 82}, 1}, 0)); // 45.5..48.1 degrees off the axis: outside the wedge
    CHECK(buffer.stats().tested == 15);
    CHECK(buffer.stats().hidden == 9);

    SECTION("the refinement: a shape just behind the wall's near face") {
        // The box's nearest point is 10.6 from the camera, but the wall is entered at up to
        // 10 / cos(atan(4 / 10.6)) = 10.69 at the edge of its extent: only the split into parts, each with its
        // own nearest distance, hides it.
        REQUIRE(buffer.begin(view, 256));
        buffer.draw(Box<2>{{60, 30}, {61, 70}}, 0);
        CHECK(buffer.hidden(Box<2>{{60.6, 46}, {60.9, 54}}, 0));
        CHECK(buffer.hidden(Ball<2>{{61, 50}, 0.3}, 0));
        CHECK_FALSE(buffer.hidden(Box<2>{{60.2, 42}, {60.8, 58}}, 0)); // too close to the near face for 2 levels
        CHECK(buffer.stats().hidden == 2);
    }
    SECTION("a draw behind a nearer occluder skips the bins covered at its end") {
        // The near wall covers the rays from 0 to 45 degrees, the far wall those from -45 to 26.6: the bins
        // at the far wall's upper end are covered nearer than its nearest point (20 away), and its draw skips
        // them (drawRuns' trimmed ends), so every covered bin is counted once.
        REQUIRE(buffer.begin(view, 128));
        buffer.draw(Box<2>{{60, 50}, {61, 60}}, 0); // near
        const std::uint64_t nearBins = buffer.stats().binsCovered;
        std::vector<double> nearDepth;
        for (int b = 0; b < buffer.bins(); ++b) nearDepth.push_back(buffer.depthAt(b));
        buffer.draw(Box<2>{{70, 30}, {71, 60}}, 0); // far
        std::uint64_t finite = 0;
        for (int b = 0; b < buffer.bins(); ++b) {
            finite += std::isfinite(buffer.depthAt(b));
            if (std::isfinite(nearDepth[std::size_t(b)])) CHECK(buffer.depthAt(b) == nearDepth[std::size_t(b)]);
        }
        CHECK(nearBins > 40);
        CHECK(finite > nearBins + 40);
        CHECK(buffer.stats().binsCovered == finite);
        CHECK(buffer.stats().occludersDrawn == 2);
        CHECK(buffer.hidden(Ball<2>{{80, 55}, 1}, 0));       // behind both
        CHECK(buffer.hidden(Ball<2>{{80, 40}, 1}, 0));       // behind the far wall only
        CHECK_FALSE(buffer.hidden(Ball<2>{{65, 40}, 1}, 0)); // in front of the far wall, beside the near one
    }
    SECTION("a polygon occluder, and one seen from inside") {
        REQUIRE(buffer.begin(view, 128));
        buffer.draw(ConvexPolygon{{{60, 40}, {62, 50}, {60, 60}}}, 0);
        CHECK(buffer.stats().occludersDrawn == 1);
        CHECK(buffer.hidden(Ball<2>{{80, 50}, 2}, 0));
        CHECK(buffer.hidden(Ball<2>{{80, 50}, 15}, 0));       // 30 degrees, entered at 11.5 < 15
        CHECK_FALSE(buffer.hidden(Ball<2>{{80, 50}, 25}, 0)); // 56 degrees
        REQUIRE(buffer.begin(view, 128));
        buffer.draw(ConvexPolygon{{{45, 40}, {60, 50}, {45, 60}}}, 0); // holds the camera
        buffer.draw(Ball<2>{{51, 50}, 2}, 0);                           // holds the camera
        buffer.draw(Ball<2>{{52, 50}, 2}, 0);                           // touches the camera
        buffer.draw(Box<2>{{49, 49}, {51, 51}}, 0);                     // holds the camera
        CHECK(buffer.stats().occludersDrawn == 0);
        CHECK_FALSE(buffer.hidden(Ball<2>{{80, 50}, 1}, 0));
        // A box with the camera at its corner: the rays into the quadrant are blocked at once, the ray along
        // its face y = 50 is not.
        buffer.draw(Box<2>{{50, 50}, {52, 52}}, 0);
        CHECK(buffer.stats().occludersDrawn == 1);
        CHECK(buffer.hidden(Ball<2>{{80, 70}, 1}, 0));
        CHECK_FALSE(buffer.hidden(Ball<2>{{80, 50}, 1}, 0));
        // The camera on a box's face: everything behind the face is hidden, nothing beside it.
        buffer.draw(Box<2>{{50, 40}, {52, 60}}, 0);
        CHECK(buffer.hidden(Ball<2>{{80, 50}, 1}, 0));
        CHECK(buffer.hidden(Ball<2>{{80, 30}, 1}, 0)); // 33.7 degrees
        CHECK(buffer.stats().occludersDrawn == 2);
    }
    SECTION("shrinking an occluder to nothing draws nothing") {
        REQUIRE(buffer.begin(view, 64));
        buffer.draw(Ball<2>{{70, 50}, 1}, 1);
        buffer.draw(Box<2>{{70, 45}, {72, 55}}, 1);
        buffer.draw(ConvexPolygon{{{70, 45}, {72, 45}, {72, 55}, {70, 55}}}, 1.01);
        CHECK(buffer.stats().occludersDrawn == 0);
        CHECK(buffer.stats().binsCovered == 0);
        CHECK_FALSE(buffer.hidden(Ball<2>{{80, 50}, 0.1}, 0));
    }
    SECTION("limits") {
        CHECK_FALSE(buffer.begin(view, 0));
        buffer.draw(wall, 0);
        CHECK_FALSE(buffer.hidden(Ball<2>{{80, 50}, 1}, 0));
        CHECK_FALSE(buffer.hidden(Ball<2>{{30, 50}, 1}, 0)); // inactive: hides nothing at all
        const ViewWedge thin({50, 50}, {1, 0}, 1e-7, std::numeric_limits<double>::infinity());
        CHECK_FALSE(buffer.begin(thin, 64));
        REQUIRE(buffer.begin(view, 1 << 20));
        CHECK(buffer.bins() == OcclusionBuffer2D::kMaxBins);
        const ViewWedge full(makeCamera({50, 50}, {0, 1}, 360), kUnitGrid);
        REQUIRE(buffer.begin(full, 1));
        CHECK(buffer.fullCircle());
        CHECK(buffer.bins() == 3); // a bin is narrower than pi
        CHECK(buffer.boundaryRay(3) == buffer.boundaryRay(0));
        const ViewWedge half(makeCamera({50, 50}, {0, 1}, 180), kUnitGrid);
        REQUIRE(buffer.begin(half, 1));
        CHECK(buffer.bins() == 2);
    }
    SECTION("boundary rays") {
        for (double fov : {1.0, 45.0, 179.5, 300.0, 359.0, 360.0}) {
            const ViewWedge w(makeCamera({50, 50}, {-1, 2}, fov), kUnitGrid);
            REQUIRE(buffer.begin(w, 100));
            const double step = buffer.fullCircle() ? 2 * kPi / 100 : fov * kPi / 180 / 100;
            CHECK(buffer.binWidth() == Approx(step).epsilon(1e-6));
            for (int b = 0; b < buffer.bins(); ++b) {
                const Vec2 u = buffer.boundaryRay(b), v = buffer.boundaryRay(b + 1);
                CHECK(std::abs(lengthSquared<2>(u) - 1) < 1e-15);
                CHECK(std::atan2(cross2(u, v), glm::dot(u, v)) == Approx(buffer.binWidth()).epsilon(1e-9));
            }
            // The first and last rays bound the wedge (a hair outside it).
            if (!buffer.fullCircle()) {
                CHECK(cross2(buffer.boundaryRay(0), w.edgeCw()) > 0);
                CHECK(cross2(w.edgeCcw(), buffer.boundaryRay(buffer.bins())) > 0);
            }
        }
    }
}

TEST_CASE("buffer2d: a frozen image answers every test as before, wide ones a block at a time", "[buffer2d]") {
    // freeze() keeps each block's largest depth; a test over many bins reads whole blocks by it. Random
    // walls and circles drawn, then random boxes and balls from tiny to wider than the view tested before
    // and after the freeze: the same answers (seeds 1..200; 40 shapes each).
    int hiddenWide = 0, tested = 0;
    for (std::uint64_t seed = 1; seed <= 200; ++seed) {
        std::mt19937_64 rng(seed);
        const double fov = sd::pick(rng, std::vector<double>{45, 90, 170, 270, 360});
        const Vec2 dir{std::cos(sd::uniform(rng, 0, 6.283)), std::sin(sd::uniform(rng, 0, 6.283))};
        const ViewWedge view(makeCamera({64, 64}, dir, fov), kUnitGrid);
        OcclusionBuffer2D buffer;
        REQUIRE(buffer.begin(view, sd::pick(rng, std::vector<int>{100, 786, 3142, 4096})));
        for (int k = sd::uniformInt(rng, 2, 12); k > 0; --k) { // walls around the camera, some circles
            const Vec2 c{sd::uniform(rng, 30, 98), sd::uniform(rng, 30, 98)};
            if (lengthSquared<2>(c - Vec2{64, 64}) < 16) continue;
            if (sd::chance(rng, 0.7)) buffer.draw(Box<2>{c - Vec2{sd::uniform(rng, 0.5, 20), 0.5}, c + Vec2{sd::uniform(rng, 0.5, 20), 0.5}}, 0);
            else buffer.draw(Ball<2>{c, sd::uniform(rng, 0.5, 6)}, 0);
        }
        std::vector<Shape<2>> shapes;
        for (int k = 0; k < 40; ++k) {
            const Vec2 c{sd::uniform(rng, -40, 168), sd::uniform(rng, -40, 168)};
            const double h = sd::logUniform(rng, 0.1, 120);
            if (sd::chance(rng, 0.5)) shapes.push_back(Box<2>{c - h, c + Vec2{h, sd::uniform(rng, 0.1, 1) * h}});
            else shapes.push_back(Ball<2>{c, h});
        }
        std::vector<char> before;
        for (const Shape<2>& s : shapes) before.push_back(buffer.hidden(s, 0.01));
        buffer.freeze();
        for (std::size_t k = 0; k < shapes.size(); ++k) {
            INFO("seed " << seed << ", shape " << k);
            const bool after = buffer.hidden(shapes[k], 0.01);
            CHECK(after == bool(before[k]));
            hiddenWide += after && boundsOf<2>(shapes[k]).max.x - boundsOf<2>(shapes[k]).min.x > 40;
            ++tested;
        }
    }
    std::printf("[buffer2d] freeze: %d tests the same before and after, %d of them wide boxes or balls hidden\n", tested, hiddenWide);
    CHECK(hiddenWide > 20); // wide shapes hidden, whose tests read whole blocks
    // A draw ends the freeze: a wall with a gap, frozen, then the gap closed; a wide box behind is hidden
    // only if the blocks over the gap are not read as they were frozen.
    const ViewWedge view(makeCamera({50, 10}, {0, 1}, 90), kUnitGrid);
    OcclusionBuffer2D buffer;
    REQUIRE(buffer.begin(view, 786));
    buffer.draw(Box<2>{{0, 30}, {48, 31}}, 0);
    buffer.draw(Box<2>{{52, 30}, {100, 31}}, 0);
    const Box<2> behind{{10, 60}, {90, 70}};
    CHECK_FALSE(buffer.hidden(behind, 0));
    buffer.freeze();
    CHECK_FALSE(buffer.hidden(behind, 0));
    buffer.draw(Box<2>{{47, 29}, {53, 30.5}}, 0);
    CHECK(buffer.hidden(behind, 0));
}

TEST_CASE("buffer2d: the full circle and the +-pi seam", "[buffer2d]") {
    // The full circle's bins start behind the camera (at -direction); with direction (1, 0) that is also
    // where atan2 jumps from pi to -pi. A wall behind the camera straddles both.
    for (const Vec2 dir : {Vec2{1, 0}, Vec2{0, 1}, Vec2{-1, 0}, Vec2{0.6, -0.8}, Vec2{1, 1e-9}, Vec2{1, -1e-9}}) {
        INFO("direction " << dir.x << ", " << dir.y);
        const ViewWedge view(makeCamera({50, 50}, dir, 360), kUnitGrid);
        for (int bins : {1, 3, 4, 17, 256, 4096}) {
            INFO("bins " << bins);
            OcclusionBuffer2D buffer;
            REQUIRE(buffer.begin(view, bins));
            REQUIRE(buffer.fullCircle());
            buffer.draw(Box<2>{{39, 44}, {40, 56}}, 0); // at -x: within atan(6 / 10) = 31 degrees of it
            if (bins >= 64) { // bins narrower than the gap between the occludees' extents and the wall's
                CHECK(buffer.hidden(Ball<2>{{30, 50}, 1}, 0));
                CHECK(buffer.hidden(Ball<2>{{30, 50}, 5}, 0)); // 14.5 degrees
                CHECK(buffer.hidden(Box<2>{{20, 48}, {22, 52}}, 0));
                CHECK(buffer.hidden(ConvexPolygon{{{20, 48}, {22, 50}, {20, 52}}}, 0));
                CHECK(buffer.hidden(Ball<2>{{30, 50.5}, 1}, 0));
                CHECK(buffer.hidden(Ball<2>{{30, 49.5}, 1}, 0));
            }
            if (dir == Vec2{1, 0} && bins >= 17) { // the first and the last bin meet at -x, both covered
                CHECK(std::isfinite(buffer.depthAt(0)));
                CHECK(std::isfinite(buffer.depthAt(buffer.bins() - 1)));
            }
            CHECK_FALSE(buffer.hidden(Ball<2>{{30, 50}, 15}, 0)); // 48.6 degrees: seen around the wall
            CHECK_FALSE(buffer.hidden(Ball<2>{{30, 70}, 1}, 0));  // beside it
            CHECK_FALSE(buffer.hidden(Ball<2>{{70, 50}, 1}, 0));  // in front of the camera: nothing there
            CHECK_FALSE(buffer.hidden(Ball<2>{{45, 50}, 1}, 0));  // between the camera and the wall
        }
    }
    SECTION("fov 359: the 1 degree gap behind the camera is not in view") {
        const ViewWedge view(makeCamera({50, 50}, {1, 0}, 359), kUnitGrid);
        OcclusionBuffer2D buffer;
        REQUIRE(buffer.begin(view, 359));
        CHECK_FALSE(buffer.fullCircle());
        CHECK(buffer.hidden(Ball<2>{{20, 50}, 0.1}, 0));      // 0.19 degrees wide, in the gap: never in view
        CHECK_FALSE(buffer.hidden(Ball<2>{{20, 50}, 0.5}, 0)); // 0.95 degrees: reaches into the view
        buffer.draw(Box<2>{{39, 44}, {40, 56}}, 0);
        CHECK(buffer.hidden(Ball<2>{{20, 50}, 3}, 0));
        CHECK(std::isfinite(buffer.depthAt(0)));
        CHECK(std::isfinite(buffer.depthAt(buffer.bins() - 1)));
    }
}

TEST_CASE("buffer2d: a box beside a boundary ray that runs along an axis does not cover that ray's bins", "[buffer2d]") {
    // Found through the culler (test_culler2d, mixed seed 109): with a 360-degree view along +y and 256
    // bins, boundary ray 64 runs along +x, 6e-17 off the axis. For a box just below the axis, that ray's
    // slab test gave an exit distance of -1.6e16 from the edge line it lies outside of, and the margin,
    // scaled by that negative distance, let it "enter" the box: bin 63 was covered, and a box behind,
    // whose top face is visible over the first one, was hidden.
    const GridGeometry2 grid({-88, 25}, 1.0, {79, 79});
    const ViewWedge view(makeCamera({-60, 39}, {0, 0.3344053551304632}, 360), grid);
    OcclusionBuffer2D buffer;
    REQUIRE(buffer.begin(view, 256));
    const Vec2 o = -grid.origin();
    const Shape<2> front = Box<2>{Vec2{-13.625193486426099, 37.17517257814355} + o, Vec2{-11.425382500777062, 38.03351010864146} + o};
    const Shape<2> beside = Box<2>{Vec2{-13.625193486426099, 38.03351010864146} + o, Vec2{-11.425382500777062, 38.89184763913937} + o};
    const Shape<2> behind = Box<2>{Vec2{-11.425382500777062, 38.03351010864146} + o, Vec2{-9.225571515128038, 38.89184763913937} + o};
    for (int k = 0; k < buffer.bins(); ++k) REQUIRE(!(buffer.depthAt(k) < 1e300));
    buffer.draw(front, 1e-9);
    buffer.draw(beside, 1e-9);
    const Vec2 ray = buffer.boundaryRay(64);
    CHECK(std::abs(ray.y) < 1e-15); // the ray along +x, as in the finding
    CHECK_FALSE(buffer.depthAt(63) < 1e300);
    CHECK_FALSE(buffer.hidden(behind, 1e-9));
    const Camera2 cam = makeCamera({-60, 39}, {0, 0.3344053551304632}, 360);
    REQUIRE(ref::exactVisible2D({front, beside, behind}, cam)[2]);
}

TEST_CASE("buffer2d: an occludee poking out of an occluder's silhouette is never hidden", "[buffer2d]") {
    // Occluder S (circle, box or polygon) in front; a circle far behind it whose angular extent pokes out of
    // S's by `poke` radians (0, 1e-13 .. 1e-2) on one side, in random directions, at many bin counts. The
    // poking part is visible (a ray through it misses S), so a hidden verdict would be a miss. The same
    // circle tucked in by the same angle is counted as hidden, to show the cases are not trivially lost.
    const std::uint64_t seed = 20261201;
    std::mt19937_64 rng(seed);
    int cases = 0, hiddenCount = 0, refSeen = 0, tucked = 0, tuckedHidden = 0;
    for (int n = 0; n < 4000; ++n) {
        const Vec2 eye{sd::uniform(rng, 20, 80), sd::uniform(rng, 20, 80)};
        const double toS = sd::uniform(rng, -kPi, kPi), dist = sd::uniform(rng, 3, 30);
        const Vec2 cs = eye + dist * unitAt(toS);
        Shape<2> s;
        const int kind = n % 3;
        if (kind == 0) {
            s = Ball<2>{cs, dist * std::sin(sd::uniform(rng, 1, 30) * kPi / 180)};
        } else if (kind == 1) {
            const Vec2 h{sd::uniform(rng, 0.2, 0.4) * dist, sd::uniform(rng, 0.2, 0.4) * dist};
            s = Box<2>{cs - h, cs + h};
        } else {
            ConvexPolygon p;
            const int k = int(sd::uniformInt(rng, 3, 7));
            const double r = sd::uniform(rng, 0.1, 0.5) * dist, a0 = sd::uniform(rng, 0, 2 * kPi);
            for (int i = 0; i < k; ++i) p.points.push_back(cs + r * unitAt(a0 + 2 * kPi * i / k));
            s = p;
        }
        const auto [lo, hi] = extentOf(s, eye);
        // Mostly 1e-7 .. 1e-2; some down to 1e-13 and some exactly 0 (tangent to the silhouette ray: seen along
        // that ray, which only touches S).
        const double pr = sd::uniform01(rng);
        const double poke = pr < 0.05 ? 0.0 : std::pow(10.0, pr < 0.25 ? sd::uniform(rng, -13, -7) : sd::uniform(rng, -7, -2));
        const double side = sd::chance(rng, 0.5) ? 1.0 : -1.0; // poke past hi (ccw) or past lo (cw)
        const double edge = side > 0 ? hi : lo;
        const double distO = dist * sd::uniform(rng, 2, 6);
        const double beta = std::min(0.4 * (hi - lo), sd::uniform(rng, 0.2, 10) * kPi / 180);
        auto occludee = [&](double out) { // the circle whose extent ends `out` radians past the edge
            return Shape<2>{Ball<2>{eye + distO * unitAt(edge + side * (out - beta)), distO * std::sin(beta)}};
        };
        const Shape<2> o = occludee(poke);
        // The wedge: centred near S, wide enough (mostly) to hold the poking direction.
        const double fov = sd::chance(rng, 0.2) ? 360 : sd::uniform(rng, 5, 359);
        const Camera2 cam = makeCamera(eye, unitAt(toS + sd::uniform(rng, -0.3, 0.3) * fov * kPi / 180), fov);
        const ViewWedge view(cam, kUnitGrid);
        OcclusionBuffer2D buffer;
        const int bins = std::array<int, 7>{1, 3, 16, 64, 255, 1024, 4096}[std::size_t(n % 7)];
        REQUIRE(buffer.begin(view, bins));
        buffer.draw(s, 0);
        const bool hidden = buffer.hidden(o, 0);
        const Vec2 pokePoint = eye + distO * std::cos(beta) * unitAt(edge + side * poke * 0.5);
        if (!view.containsPoint(pokePoint)) continue; // either verdict is right
        ++cases;
        hiddenCount += hidden;
        const bool seen = ref::exactVisible2D({s, o}, cam)[1];
        refSeen += seen;
        if (hidden) {
            UNSCOPED_INFO("seed " << seed << " case " << n << " bins " << bins << " poke " << poke << " kind " << kind
                                  << " reference sees it: " << seen);
            CHECK_FALSE(hidden);
        }
        if (bins >= 1024 && poke > 1e-3) { // tucked in by the same angle: the buffer should mostly hide it
            OcclusionBuffer2D b2;
            REQUIRE(b2.begin(view, bins));
            b2.draw(s, 0);
            ++tucked;
            tuckedHidden += b2.hidden(occludee(-poke), 0);
        }
    }
    std::printf("[buffer2d] poking silhouettes: %d cases in view, %d seen by the reference, %d hidden (must be 0); "
                "tucked in by > 1e-3 rad at >= 1024 bins: %d of %d hidden\n",
                cases, refSeen, hiddenCount, tuckedHidden, tucked);
    CHECK(cases > 2500);
    CHECK(refSeen * 100 > cases * 99);
    CHECK(tuckedHidden * 2 > tucked);
}

namespace {

struct PassTally {
    int frames = 0, objects = 0, inView = 0, seen = 0, hiddenInView = 0, misses = 0;
    void add(const std::vector<bool>& hidden, const std::vector<bool>& seenV, const std::vector<bool>& inViewV) {
        ++frames;
        for (std::size_t i = 0; i < hidden.size(); ++i) {
            ++objects;
            inView += inViewV[i];
            seen += seenV[i];
            hiddenInView += hidden[i] && inViewV[i];
            misses += hidden[i] && seenV[i];
        }
    }
    /// The share of the objects in view that the reference does not see which the buffer removes.
    double removed() const { return double(hiddenInView) / std::max(1, inView - seen); }
};

} // namespace

TEST_CASE("buffer2d: random scenes against the exact reference", "[buffer2d]") {
    // Random scenes of the culler's test mixture (circles, boxes, polygons from 1/20 voxel to a third of the
    // grid, walls, rows of abutting boxes, snapped coordinates), cameras on voxel corners, edges and centres,
    // inside objects and outside the grid, fov 0.5..360, the whole pass as the culler runs it, bins 1..1024.
    // Every object the buffer hides must be one the reference does not see.
    const std::uint64_t seed0 = 880000;
    PassTally tally;
    constexpr std::array<int, 8> kBins{1, 2, 5, 16, 64, 97, 256, 1024};
    std::array<PassTally, 8> byBins;
    const int scenes = 2000, camerasPerScene = 3;
    for (std::uint64_t k = 0; k < std::uint64_t(scenes); ++k) {
        const ref::Scene2D scene = ref::randomScene2D(seed0 + k);
        const std::vector<Shape<2>> world = ref::shapesOf(scene.objects);
        std::vector<Shape<2>> local;
        double magnitude = 0; // the largest world coordinate: the culler's slack per object is at most this one's
        for (const Shape<2>& s : world) {
            local.push_back(toLocal<2>(s, scene.grid));
            const Box<2> b = boundsOf<2>(s);
            for (int a = 0; a < 2; ++a) magnitude = std::max({magnitude, std::abs(b.min[a]), std::abs(b.max[a])});
        }
        std::mt19937_64 rng((seed0 + k) ^ 0x9e3779b97f4a7c15ull);
        for (int c = 0; c < camerasPerScene; ++c) {
            const Camera2 cam = c == 0 ? scene.camera : ref::randomCamera2D(rng, scene.grid, scene.objects, scene.snapped);
            const ViewWedge view(cam, scene.grid);
            OcclusionBuffer2D buffer;
            const std::size_t binsIndex = (k * camerasPerScene + std::uint64_t(c)) % kBins.size();
            const int bins = kBins[binsIndex];
            REQUIRE(buffer.begin(view, bins));
            const double slack = view.slack() + scene.grid.conversionSlack(magnitude);
            const std::vector<bool> hidden = bufferPass(buffer, local, slack);
            const std::vector<bool> seen = ref::exactVisible2D(world, cam);
            const std::vector<bool> inView = ref::inViewRegion2D(world, cam);
            tally.add(hidden, seen, inView);
            byBins[binsIndex].add(hidden, seen, inView);
            for (std::size_t i = 0; i < world.size(); ++i)
                if (hidden[i] && seen[i]) {
                    UNSCOPED_INFO("seed " << scene.seed << " camera " << c << " object " << scene.objects[i].id << " bins "
                                          << bins << "\n" << ref::toJson(scene.grid, scene.objects, cam));
                    CHECK_FALSE((hidden[i] && seen[i]));
                }
        }
    }
    std::printf("[buffer2d] random scenes: %d scene/camera pairs, %d objects, %d in view, %d seen by the reference, "
                "%d hidden in view by the buffer (%.1f%% of the %d in view not seen), %d misses (must be 0)\n",
                tally.frames, tally.objects, tally.inView, tally.seen, tally.hiddenInView, 100 * tally.removed(),
                tally.inView - tally.seen, tally.misses);
    std::printf("[buffer2d] random scenes, share removed by bin count:");
    for (std::size_t b = 0; b < kBins.size(); ++b) std::printf(" %d: %.1f%%", kBins[b], 100 * byBins[b].removed());
    std::printf("\n");
    CHECK(tally.misses == 0);
    CHECK(tally.removed() > 0.3);
}

TEST_CASE("buffer2d: slivers and cameras on edge lines against the exact reference", "[buffer2d]") {
    // Needle triangles (width 1e-6 .. 1e-1 of their length) and thin boxes as occluders, often with the camera
    // exactly on the line through one of their edges (rays grazing an edge, nearly parallel edges meeting far
    // from where their rounded normals say), and small circles, boxes and triangles behind them.
    const std::uint64_t seed = 626262;
    std::mt19937_64 rng(seed);
    PassTally tally;
    for (int n = 0; n < 600; ++n) {
        const Vec2 eye{sd::uniform(rng, 30, 70), sd::uniform(rng, 30, 70)};
        std::vector<Shape<2>> objects;
        for (int i = 0; i < 6; ++i) {
            const double len = sd::uniform(rng, 2, 30), ang = sd::uniform(rng, 0, 2 * kPi);
            const Vec2 d = unitAt(ang), perp{-d.y, d.x};
            Vec2 a = eye + sd::uniform(rng, 1, 20) * unitAt(sd::uniform(rng, 0, 2 * kPi));
            if (sd::chance(rng, 0.5)) a = eye + sd::uniform(rng, 0.5, 10) * d; // the edge a..b lies on a ray from the eye
            const double w = len * std::pow(10.0, sd::uniform(rng, -6, -1)) * (sd::chance(rng, 0.5) ? 1 : -1);
            if (sd::chance(rng, 0.25)) { // a thin axis-aligned box, often with the camera on the line of a face
                Vec2 lo = a;
                if (sd::chance(rng, 0.5)) lo.y = eye.y;
                const double t = std::abs(w);
                objects.push_back(sd::chance(rng, 0.5) ? Box<2>{lo, lo + Vec2{len, t}} : Box<2>{lo, lo + Vec2{t, len}});
            } else {
                objects.push_back(ConvexPolygon{{a, a + len * d, a + len * d + w * perp}});
            }
        }
        for (int i = 0; i < 20; ++i) {
            const Vec2 c = eye + sd::uniform(rng, 5, 45) * unitAt(sd::uniform(rng, 0, 2 * kPi));
            const double r = sd::logUniform(rng, 0.01, 1.5);
            const int kind = int(sd::uniformInt(rng, 0, 2));
            if (kind == 0) objects.push_back(Ball<2>{c, r});
            else if (kind == 1) objects.push_back(Box<2>{c - r, c + r});
            else objects.push_back(ConvexPolygon{{c, c + Vec2{r, 0}, c + Vec2{0, r}}});
        }
        std::vector<Shape<2>> valid;
        for (Shape<2> s : objects) {
            try {
                validateShape<2>(s, "generated");
            } catch (const InvalidInput&) {
                continue;
            }
            valid.push_back(s);
        }
        const double fov = std::array<double, 4>{20, 90, 240, 360}[std::size_t(n % 4)];
        const Camera2 cam = makeCamera(eye, unitAt(sd::uniform(rng, 0, 2 * kPi)), fov);
        const ViewWedge view(cam, kUnitGrid);
        OcclusionBuffer2D buffer;
        REQUIRE(buffer.begin(view, std::array<int, 3>{64, 512, 4096}[std::size_t(n % 3)]));
        const std::vector<bool> hidden = bufferPass(buffer, valid, view.slack() + kUnitGrid.conversionSlack(100));
        const std::vector<bool> seen = ref::exactVisible2D(valid, cam);
        tally.add(hidden, seen, ref::inViewRegion2D(valid, cam));
        for (std::size_t i = 0; i < valid.size(); ++i)
            if (hidden[i] && seen[i]) {
                UNSCOPED_INFO("seed " << seed << " scene " << n << " object " << i);
                CHECK_FALSE((hidden[i] && seen[i]));
            }
    }
    std::printf("[buffer2d] slivers: %d scenes, %d objects, %d in view, %d seen, %d hidden by the buffer (%.1f%% of those not seen), "
                "%d misses\n",
                tally.frames, tally.objects, tally.inView, tally.seen, tally.hiddenInView, 100 * tally.removed(), tally.misses);
    CHECK(tally.misses == 0);
    CHECK(tally.hiddenInView > 0);
}

TEST_CASE("buffer2d: circle clouds against the exact reference", "[buffer2d]") {
    // The case the buffer is for: many small circles (below two voxels), where the grid's occluders are
    // empty. No misses, and a good part of what the reference does not see is removed.
    const std::uint64_t seed = 515151;
    std::mt19937_64 rng(seed);
    PassTally tally;
    for (int n = 0; n < 60; ++n) {
        std::vector<Shape<2>> objects;
        for (int i = 0; i < 300; ++i) {
            const Vec2 c{sd::uniform(rng, 0, 100), sd::uniform(rng, 0, 100)};
            objects.push_back(Ball<2>{c, sd::logUniform(rng, 0.3, 2.5)});
        }
        const double fov = std::array<double, 5>{30, 60, 90, 200, 360}[std::size_t(n % 5)];
        Vec2 eye{sd::uniform(rng, 30, 70), sd::uniform(rng, 30, 70)};
        if (n % 3 == 0) eye = glm::floor(eye); // a voxel corner
        const Camera2 cam = makeCamera(eye, unitAt(sd::uniform(rng, 0, 2 * kPi)), fov);
        const ViewWedge view(cam, kUnitGrid);
        OcclusionBuffer2D buffer;
        REQUIRE(buffer.begin(view, 1024));
        const std::vector<bool> hidden = bufferPass(buffer, objects, view.slack() + kUnitGrid.conversionSlack(100));
        const std::vector<bool> seen = ref::exactVisible2D(objects, cam);
        const std::vector<bool> inView = ref::inViewRegion2D(objects, cam);
        tally.add(hidden, seen, inView);
        for (std::size_t i = 0; i < objects.size(); ++i)
            if (hidden[i] && seen[i]) {
                UNSCOPED_INFO("seed " << seed << " scene " << n << " object " << i);
                CHECK_FALSE((hidden[i] && seen[i]));
            }
    }
    std::printf("[buffer2d] circle clouds: %d in view, %d seen, %d hidden by the buffer of %d not seen (%.1f%%), %d misses\n",
                tally.inView, tally.seen, tally.hiddenInView, tally.inView - tally.seen, 100 * tally.removed(), tally.misses);
    CHECK(tally.misses == 0);
    CHECK(tally.removed() >= 0.3);
}

TEST_CASE("buffer2d: a box draws the depths of the same box as a polygon", "[buffer2d]") {
    // Boxes take a branch-free slab test of their own (OcclusionBuffer2D::draw); polygons the general
    // half-plane test, which for a box's four corners adds the four edge lines again after the bounding
    // box's. Both must give the same bins the same depths, bit for bit: the fast path is the same
    // arithmetic. Cameras anywhere, some on a box's edge line (the general path then) or on a bin ray
    // along an axis; boxes from 1e-3 to 40 voxels, near and far.
    const std::uint64_t seed = 881000;
    std::mt19937_64 rng(seed);
    int compared = 0, covered = 0;
    for (int k = 0; k < 3000; ++k) {
        const Vec2 eye{sd::uniform(rng, 0, 100), sd::uniform(rng, 0, 100)};
        const double angle = k % 4 == 0 ? 0.5 * kPi * double(k % 16 / 4) : sd::uniform(rng, -kPi, kPi);
        const double fov = k % 3 == 0 ? 360 : sd::uniform(rng, 1, 359);
        const ViewWedge view(makeCamera(eye, unitAt(angle), fov), kUnitGrid);
        const int bins = std::array<int, 4>{7, 64, 786, 4096}[std::size_t(k % 4)];
        OcclusionBuffer2D asBox, asPolygon;
        REQUIRE(asBox.begin(view, bins));
        REQUIRE(asPolygon.begin(view, bins));
        const Vec2 size{sd::logUniform(rng, 1e-3, 40), sd::logUniform(rng, 1e-3, 40)};
        Vec2 lo{sd::uniform(rng, -20, 120), sd::uniform(rng, -20, 120)};
        if (k % 5 == 0) lo.x = eye.x; // the camera on an edge line
        if (k % 7 == 0) lo.y = eye.y - size.y;
        const Box<2> box{lo, lo + size};
        const ConvexPolygon polygon{{box.min, {box.max.x, box.min.y}, box.max, {box.min.x, box.max.y}}};
        const double shrink = k % 2 == 0 ? 0.0 : 1e-9;
        asBox.draw(box, shrink);
        asPolygon.draw(polygon, shrink);
        for (int b = 0; b < asBox.bins(); ++b) {
            const double d = asBox.depthAt(b), e = asPolygon.depthAt(b);
            if (!(d == e)) {
                UNSCOPED_INFO("seed " << seed << " case " << k << " bin " << b << " box " << d << " polygon " << e);
                REQUIRE(d == e);
            }
            covered += d < 1e300;
        }
        ++compared;
    }
    std::printf("[buffer2d] box against polygon: %d draws compared, %d bins covered, all equal\n", compared, covered);
    CHECK(covered > 10000);
}
