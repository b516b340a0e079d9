// OcclusionBuffer2D: see the header for the geometry, the soundness argument and the margins.
#include "rgvc/grid/OcclusionBuffer2D.hpp"
#include "rgvc/grid/FastAtan2.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rgvc {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTwoPi = 2 * kPi;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kEps = 2.220446049250313e-16; // DBL_EPSILON
/// Relative margin of every distance and "passes through the interior" test, far above the rounding of
/// a few dozen double operations (~1e-15) and far below anything that changes a verdict in practice.
constexpr double kRelMargin = 1e-9;
/// [Radians] widening of the buffer's range over the wedge (both sides): the rounding of its boundary
/// rays, which are computed with std::cos and std::sin.
constexpr double kRangePad = 1e-10;
/// [Radians] widening of every angular extent (both sides): the rounding, and the error of the angles
/// (fastAtan2, kFastAtan2MaxError each). An extent's end adds or subtracts at most three computed angles
/// (a grown polygon's: its centre's bin coordinate, a vertex's angle from it, a disc's half-width), so
/// four errors cover it.
constexpr double kAnglePad = 1e-10 + 4 * kFastAtan2MaxError;
/// [Bins] widening of every bin index range (both sides).
constexpr double kIndexBias = 1e-6;
/// Internal shrink / growth: this many ulps of the largest coordinate magnitude (apex or shape).
constexpr double kPadUlps = 32;
/// Occludees nearer than this fraction of their apex-relative extent are not hidden (ill-conditioned).
constexpr double kMinNearestRel = 1e-9;
/// Widest bin (radians): well below pi, where the header's argument (2) needs it.
constexpr double kMaxBinWidth = 0.75 * kPi;

double absMax(const Vec2& v) { return std::max(std::abs(v.x), std::abs(v.y)); }

/// The shape's bounding box and the largest coordinate magnitude of it and of the apex.
double magnitudeOf(const Shape<2>& shape, const Vec2& apex, Box<2>& bounds) {
    bounds = boundsOf<2>(shape);
    return std::max({absMax(apex), absMax(bounds.min), absMax(bounds.max)});
}

/// Angular half-width [radians] of a disc of radius rho seen from distance l > rho:
/// asin(rho / l) = atan2(rho, sqrt(l^2 - rho^2)), with l^2 - rho^2 as (l - rho)(l + rho); within
/// kFastAtan2MaxError (covered by kAnglePad).
double halfAngle(double rho, double l) { return rho > 0 ? fastAtan2(rho, std::sqrt((l - rho) * (l + rho))) : 0.0; }

/// Signed angle [radians, [-pi, pi]] from r to v (counter-clockwise positive), within kFastAtan2MaxError.
double angleFrom(const Vec2& r, const Vec2& v) { return fastAtan2(cross2(r, v), glm::dot(r, v)); }

} // namespace

bool OcclusionBuffer2D::begin(const ViewWedge& view, int bins) {
    m_stats = {};
    m_active = false;
    m_frozen = false;
    const double fov = view.fov();
    if (bins < 1 || !(fov >= kMinFov) || !allFinite<2>(view.apex()) || !allFinite<2>(view.direction())) return false;
    m_apex = view.apex();
    m_dir = view.direction(); // unit (safeNormalize)
    const double half = 0.5 * fov * (1 + 1e-9) + kRangePad;
    m_full = view.isFullCircle() || half >= kPi;
    m_half = m_full ? kPi : half;
    m_span = 2 * m_half;
    int n = std::min(bins, kMaxBins);
    n = std::max(n, int(std::ceil(m_span / kMaxBinWidth)));
    m_bins = n;
    m_binW = m_span / n;
    m_invBinW = 1 / m_binW;
    m_binsPerTurn = kTwoPi / m_binW;
    if (m_cacheHalf != m_half || m_cacheBins != n) {
        m_relCos.resize(std::size_t(n) + 1);
        m_relSin.resize(std::size_t(n) + 1);
        for (int b = 0; b <= n; ++b) {
            const double a = -m_half + b * m_binW;
            m_relCos[std::size_t(b)] = std::cos(a);
            m_relSin[std::size_t(b)] = std::sin(a);
        }
        if (m_full) { // ray n is ray 0: the bins wrap around exactly
            m_relCos[std::size_t(n)] = m_relCos[0];
            m_relSin[std::size_t(n)] = m_relSin[0];
        }
        m_cacheHalf = m_half;
        m_cacheBins = n;
    }
    m_rayX.resize(std::size_t(n) + 1);
    m_rayY.resize(std::size_t(n) + 1);
    for (std::size_t b = 0; b <= std::size_t(n); ++b) { // the direction rotated by the ray's angle
        const double c = m_relCos[b], s = m_relSin[b];
        m_rayX[b] = c * m_dir.x - s * m_dir.y;
        m_rayY[b] = s * m_dir.x + c * m_dir.y;
    }
    m_depth.assign(std::size_t(n), kInf);
    m_entries.resize(std::size_t(n) + 1);
    if (m_planes.capacity() < 64) m_planes.reserve(64);
    m_active = true;
    return true;
}

double OcclusionBuffer2D::binCoord(const Vec2& v) const { return angleFrom(m_dir, v) + m_half; }

template <class F> bool OcclusionBuffer2D::forEachRun(double x0, double x1, F&& f) const {
    if (!(x0 <= x1)) return f(0, m_bins - 1); // NaN: nothing is known
    // A direction's bin coordinate is defined modulo 2 pi. The extents built here have x0 > -2 pi - pad and
    // x1 < 3 pi + pad (binCoord in [-pi, 2 pi], offsets within (-pi, pi)), so shifts by -1..1 turns reach
    // every representative in [0, span]; -2..2 costs nothing and leaves room.
    // In bins, by products (the quotients (x + k 2 pi) / binW were ten divisions per extent, in every
    // test and draw of the 2D image): each of x * (1 / binW) and k * (2 pi / binW) is within a few ulps of
    // a value of at most 3 turns, ~1e-12 bins at kMaxBins, far inside kIndexBias.
    const double a0 = x0 * m_invBinW - kIndexBias, b0 = x1 * m_invBinW + kIndexBias;
    for (int k = -2; k <= 2; ++k) {
        const double fa = a0 + k * m_binsPerTurn, fb = b0 + k * m_binsPerTurn;
        if (!(fb >= 0) || !(fa < double(m_bins))) continue;
        const int i0 = fa <= 0 ? 0 : int(fa);
        const int i1 = fb >= double(m_bins) ? m_bins - 1 : int(fb);
        if (!f(i0, i1)) return false;
    }
    return true;
}

void OcclusionBuffer2D::freeze() {
    if (!m_active) return;
    const std::size_t blocks = (std::size_t(m_bins) + kBlockBins - 1) / kBlockBins;
    m_blockMax.resize(blocks);
    for (std::size_t b = 0; b < blocks; ++b) {
        const std::size_t i0 = b * kBlockBins, i1 = std::min(i0 + kBlockBins, std::size_t(m_bins));
        double m = m_depth[i0];
        for (std::size_t i = i0 + 1; i < i1; ++i) m = std::max(m, m_depth[i]);
        m_blockMax[b] = m;
    }
    m_frozen = true;
}

bool OcclusionBuffer2D::coveredNearer(double x0, double x1, double nearest) const {
    return forEachRun(x0, x1, [&](int i0, int i1) {
        // Four bins a step, one branch per four: an extent spans tens of bins (0.002 rad each at the
        // walk's resolution), and perf put most of this loop's samples on a bin-by-bin exit branch.
        const double* d = m_depth.data();
        int i = i0;
        // Frozen (freeze()): the whole blocks inside the run by their maxima (every bin of a block is
        // below `nearest` exactly when its maximum is), the bins before and after them one by one.
        if (m_frozen && i1 - i0 >= 2 * kBlockBins) {
            const int b0 = (i0 + kBlockBins - 1) / kBlockBins, b1 = (i1 + 1) / kBlockBins; // whole blocks [b0, b1)
            for (; i < b0 * kBlockBins; ++i)
                if (!(d[i] < nearest)) return false;
            for (int b = b0; b < b1; ++b)
                if (!(m_blockMax[std::size_t(b)] < nearest)) return false;
            i = b1 * kBlockBins;
        }
        for (; i + 3 <= i1; i += 4)
            if (!((d[i] < nearest) & (d[i + 1] < nearest) & (d[i + 2] < nearest) & (d[i + 3] < nearest))) return false;
        for (; i <= i1; ++i)
            if (!(d[i] < nearest)) return false;
        return true;
    });
}

void OcclusionBuffer2D::boxExtent(const Vec2& lo, const Vec2& hi, double& x0, double& x1) const {
    // O is outside the box, so the box lies in an open half-plane through O and its directions form an
    // arc narrower than pi, from its most clockwise corner to its most counter-clockwise one (the box is
    // the convex hull of its corners). In that half-plane the corners are ordered by angle, and the order
    // is the sign of their cross products: the extreme two are found so. A sign that rounding gets wrong
    // belongs to two corners within ~1e-16 rad of each other, far inside kAnglePad.
    // The two extreme corners' bin coordinates are then the extent's ends, up to a turn: both lie in one
    // window of 2 pi, so x(qMax) - x(qMin) is the arc's width or the width less 2 pi (a box behind the
    // camera, across the window's cut), which adds the turn back. A difference that rounding made
    // negative but small (a box narrower than the angles' error) is a zero width. Two angles per box:
    // four, one per corner, were 17 % of the instructions of rgvc_bench_classes' random 2D scenes, and
    // three (the corners measured from the centre) 12 % (with std::atan2; fastAtan2 since).
    Vec2 qMin = lo, qMax = lo;
    for (int k = 1; k < 4; ++k) {
        const Vec2 q{(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y};
        if (cross2(qMin, q) < 0) qMin = q;
        if (cross2(qMax, q) > 0) qMax = q;
    }
    const double a = binCoord(qMin);
    double b = binCoord(qMax);
    if (b < a) b = a - b > kPi ? b + kTwoPi : a;
    x0 = a - kAnglePad;
    x1 = b + kAnglePad;
}

bool OcclusionBuffer2D::canHide(const Vec2& p) const {
    const double x = binCoord(p);
    if (!m_full && (!(x >= 0) || !(x <= m_span))) return true; // not in the buffer's range: no verdict
    // Clamped in double (a NaN to bin 0), then truncated: floor for q >= 0, without std::floor's library
    // call on the baseline ISA.
    double q = x * m_invBinW;
    q = q >= 0 ? q : 0.0;
    q = q < double(m_bins - 1) ? q : double(m_bins - 1);
    const int b = int(q);
    return m_depth[std::size_t(b)] < std::sqrt(lengthSquared<2>(p)) * (1 - kRelMargin);
}

bool OcclusionBuffer2D::hiddenParts(const Vec2& lo, const Vec2& hi, int levels, double pad, double minNearest) const {
    const Vec2 mid = 0.5 * (lo + hi);
    for (int k = 0; k < 4; ++k) {
        const Vec2 l{(k & 1) ? mid.x : lo.x, (k & 2) ? mid.y : lo.y};
        const Vec2 h{(k & 1) ? hi.x : mid.x, (k & 2) ? hi.y : mid.y};
        const double nearest = std::sqrt(lengthSquared<2>(glm::clamp(Vec2(0.0), l, h))) * (1 - kRelMargin) - pad;
        if (!(nearest > minNearest)) return false;
        double x0, x1;
        boxExtent(l, h, x0, x1);
        if (coveredNearer(x0, x1, nearest)) continue;
        if (levels <= 1 || !canHide(0.5 * (l + h)) || !hiddenParts(l, h, levels - 1, pad, minNearest)) return false;
    }
    return true;
}

double OcclusionBuffer2D::nearestDistance(const Shape<2>& shape, double grow) const {
    if (const auto* b = std::get_if<Ball<2>>(&shape))
        return std::max(0.0, std::sqrt(lengthSquared<2>(b->center - m_apex)) - (b->radius + grow));
    if (const auto* x = std::get_if<Box<2>>(&shape)) {
        const Vec2 nearest = glm::clamp(m_apex, x->min - grow, x->max + grow);
        return std::sqrt(lengthSquared<2>(nearest - m_apex));
    }
    // A convex polygon: 0 when the apex is inside (on the inner side of every edge), else the smallest
    // distance to an edge segment, less the growth.
    const std::vector<Vec2>& pts = std::get<ConvexPolygon>(shape).points;
    const std::size_t n = pts.size();
    if (n == 0) return kInf;
    double area2 = 0;
    for (std::size_t k = 0; k < n; ++k) area2 += cross2(pts[k] - m_apex, pts[(k + 1) % n] - m_apex);
    const double orient = area2 >= 0 ? 1.0 : -1.0;
    bool inside = n >= 3;
    double best = kInf;
    for (std::size_t k = 0; k < n; ++k) {
        const Vec2 a = pts[k] - m_apex, e = pts[(k + 1) % n] - pts[k];
        inside = inside && orient * cross2(a, e) >= 0;
        const double e2 = lengthSquared<2>(e);
        const double t = e2 > 0 ? std::clamp(-glm::dot(a, e) / e2, 0.0, 1.0) : 0.0;
        best = std::min(best, lengthSquared<2>(a + t * e));
    }
    if (inside) return 0.0;
    return std::max(0.0, std::sqrt(best) - grow);
}

bool OcclusionBuffer2D::hidden(const Shape<2>& shape, double grow, double distance, bool refine) {
    if (!m_active) return false;
    ++m_stats.tested;
    Box<2> bounds;
    const double pad = kPadUlps * kEps * magnitudeOf(shape, m_apex, bounds);
    const double g = std::max(0.0, grow) + pad;
    const double nearest = distance * (1 - kRelMargin) - pad;
    // The grown bounding box, apex-relative: the parts of the refinement.
    Vec2 lo, hi;
    if (const auto* b = std::get_if<Ball<2>>(&shape)) {
        lo = b->center - m_apex - (b->radius + g);
        hi = b->center - m_apex + (b->radius + g);
    } else {
        lo = bounds.min - m_apex - g;
        hi = bounds.max - m_apex + g;
    }
    const double minNearest = kMinNearestRel * std::max(absMax(lo), absMax(hi));
    if (!(nearest > minNearest)) return false; // holds or (nearly) touches the camera
    // A witness first, for a box or a ball: its point nearest to the camera (grown). Every bin of the
    // shape's extent must be covered nearer than `nearest`, which is at most that point's distance, and the
    // point's own bin is one of them: when it is not covered nearer than the point, the test cannot
    // succeed. One angle, where the extent costs two and the scan of its bins more, and most shapes tested
    // are visible (the walk's nodes, objects in open space): the 2D city −12 %, random scenes −3 %
    // instructions. (A polygon goes straight to its extent.)
    double x0, x1;
    if (const auto* b = std::get_if<Ball<2>>(&shape)) {
        const Vec2 c = b->center - m_apex;
        const double rho = b->radius + g, l = std::sqrt(lengthSquared<2>(c));
        if (!(l > rho)) return false;
        if (!canHide(c * ((l - rho) / l))) return false;
        const double x = binCoord(c), beta = halfAngle(rho, l);
        x0 = x - beta - kAnglePad;
        x1 = x + beta + kAnglePad;
    } else if (std::holds_alternative<Box<2>>(shape)) {
        if (!canHide(glm::clamp(Vec2(0.0), lo, hi))) return false;
        boxExtent(lo, hi, x0, x1);
    } else {
        // The polygon grown by g is the convex hull of the discs of radius g at its vertices: its extent
        // is the smallest arc holding theirs, measured from the vertices' average (a point inside it).
        const std::vector<Vec2>& pts = std::get<ConvexPolygon>(shape).points;
        if (pts.size() < 3) return false;
        Vec2 r{0.0};
        for (const Vec2& p : pts) r += p - m_apex;
        r /= double(pts.size());
        double dMin = 0, dMax = 0;
        for (const Vec2& p : pts) {
            const Vec2 v = p - m_apex;
            const double l = std::sqrt(lengthSquared<2>(v));
            if (!(l > g)) return false; // the camera is in the grown polygon
            const double d = angleFrom(r, v), beta = halfAngle(g, l);
            dMin = std::min(dMin, d - beta);
            dMax = std::max(dMax, d + beta);
        }
        const double x = binCoord(r);
        x0 = x + dMin - kAnglePad;
        x1 = x + dMax + kAnglePad;
    }
    if (coveredNearer(x0, x1, nearest)) {
        ++m_stats.hidden;
        return true;
    }
    // Refinement (see the header): the bounding box in quarters, two levels deep, after the early-out on
    // its centre.
    if (!refine || !canHide(0.5 * (lo + hi))) return false;
    if (!hiddenParts(lo, hi, 2, pad, minNearest)) return false;
    ++m_stats.hidden;
    return true;
}

double OcclusionBuffer2D::planeEntry(double ux, double uy, double scale) const {
    double tEnter = -kInf, tExit = kInf, aEnter = 1, aExit = 1;
    for (const HalfPlane& p : m_planes) {
        const double a = p.nx * ux + p.ny * uy;
        if (a > 0) {
            const double t = p.h / a;
            if (t < tExit) tExit = t, aExit = a;
        } else if (a < 0) {
            const double t = p.h / a;
            if (t > tEnter) tEnter = t, aEnter = -a;
        } else if (!(p.h > 0)) {
            return -1.0; // parallel to the edge line, on or outside it
        }
    }
    // h / a carries a relative error of a few ulps / |a| (a is rounded absolutely): near-parallel binding
    // edges get a margin of that size on top of kRelMargin.
    const double mEnter = kRelMargin + 8 * kEps / aEnter, mExit = 8 * kEps / aExit;
    // tExit > tEnter first: the margin scales with tExit, and a negative tExit (a ray nearly parallel to an
    // edge it lies outside of: h / a with a ~ 1e-17) would turn the margin's sign and pass the test
    // (found by test_culler2d through the culler: the ray of a 360-degree buffer along +x, 6e-17 off the
    // axis, "entered" a box lying just below that axis, and a visible box behind it was hidden).
    if (!(tEnter > 0) || !(tExit > tEnter) || !(tExit - tEnter > (mEnter + mExit) * tExit + kRelMargin * scale * 1e-3))
        return -1.0;
    return tEnter * (1 + mEnter) + kRelMargin * scale;
}

template <class Fill> void OcclusionBuffer2D::drawRuns(double x0, double x1, double nearest, Fill&& fill) {
    std::uint64_t covered = 0;
    double* e = m_entries.data();
    forEachRun(x0, x1, [&](int i0, int i1) {
        double* depth = m_depth.data();
        // The bins already covered at `nearest` or nearer are left out at both ends of the run: no entry of
        // the occluder is nearer, so it cannot lower them (an object partly behind nearer ones draws only
        // where it can still hide something, as the 3D image's rows do).
        while (i0 <= i1 && !(depth[i0] > nearest)) ++i0;
        if (i0 > i1) return true;
        while (!(depth[i1] > nearest)) --i1; // stops at i0
        // The boundary rays' entries first (one vectorizable loop per shape kind), then the bins.
        fill(i0, i1 + 1, e);
        for (int i = i0; i <= i1; ++i) { // branch-free: vectorized
            const bool in = (e[i] >= 0) & (e[i + 1] >= 0); // both boundary rays pass through the interior
            covered += in;
            const double m = std::min(depth[i], std::max(e[i], e[i + 1]));
            depth[i] = in ? m : depth[i];
        }
        return true;
    });
    m_stats.binsCovered += covered;
    if (covered != 0) ++m_stats.occludersDrawn;
}

void OcclusionBuffer2D::draw(const Shape<2>& shape, double shrink) {
    if (!m_active) return;
    m_frozen = false;
    Box<2> bounds;
    const double pad = kPadUlps * kEps * magnitudeOf(shape, m_apex, bounds);
    const double s = std::max(0.0, shrink) + pad;
    if (const auto* b = std::get_if<Ball<2>>(&shape)) {
        const Vec2 c = b->center - m_apex;
        const double rho = b->radius - s, l2 = lengthSquared<2>(c);
        // Inside or nearly touching the camera: skipped (the extent would be nearly a half-circle, and the
        // entry distances ill-conditioned).
        if (!(rho > 0) || !(l2 > rho * rho * (1 + 1e-6))) return;
        const double l = std::sqrt(l2), beta = halfAngle(rho, l), x = binCoord(c);
        // A unit ray u passes through the interior when c.u > 0 and |c x u| < rho, with room for the
        // rounding of c x u (a few ulps of l); it enters at (l^2 - rho^2) / (c.u + sqrt(rho^2 - (c x u)^2)).
        const double crLimit = rho * (1 - kRelMargin) - 8 * kEps * l;
        const double num = (l - rho) * (l + rho), scale = 1 + kRelMargin, absPad = kRelMargin * l;
        const double* rx = m_rayX.data();
        const double* ry = m_rayY.data();
        // (The extent only selects the bins to try: each boundary ray is tested exactly. Padded as the
        // occludees' extents, so that fastAtan2's error drops no bin.)
        // Every entry written is at least the disc's nearest distance l - rho (drawRuns' trimmed ends).
        drawRuns(x - beta - kAnglePad, x + beta + kAnglePad, (l - rho) * (1 - 1e-6), [&](int i0, int i1, double* out) {
            for (int i = i0; i <= i1; ++i) { // branch-free (the square root of a ray that misses is unused)
                const double cd = c.x * rx[i] + c.y * ry[i], cr = std::abs(c.x * ry[i] - c.y * rx[i]);
                const bool in = (cd > 0) & (cr < crLimit);
                const double t = num / (cd + std::sqrt(std::max(0.0, (rho - cr) * (rho + cr))));
                out[i] = in ? t * scale + absPad : -1.0;
            }
        });
        return;
    }
    m_planes.clear();
    const Vec2 lo = bounds.min - m_apex, hi = bounds.max - m_apex; // the (polygon's bounding) box, unshrunk
    if (!(lo.x + s < hi.x - s) || !(lo.y + s < hi.y - s)) return;  // shrunk to nothing
    const double scale = std::max(absMax(lo), absMax(hi));
    // The bounding box shrunk by s: the whole shape for a box, a bound that keeps a polygon's rounded edge
    // lines from reaching past it (two nearly parallel edges of a sliver meet far from where their rounded
    // normals say).
    m_planes.push_back({1, 0, hi.x - s});
    m_planes.push_back({-1, 0, -lo.x - s});
    m_planes.push_back({0, 1, hi.y - s});
    m_planes.push_back({0, -1, -lo.y - s});
    double x0, x1;
    if (const auto* poly = std::get_if<ConvexPolygon>(&shape)) {
        const std::vector<Vec2>& pts = poly->points;
        const std::size_t n = pts.size();
        if (n < 3) return;
        double area2 = 0;
        for (std::size_t k = 0; k < n; ++k) area2 += cross2(pts[k] - m_apex, pts[(k + 1) % n] - m_apex);
        if (!(area2 != 0)) return;
        const double orient = area2 > 0 ? 1.0 : -1.0;
        bool rawHoldsApex = true;
        for (std::size_t k = 0; k < n; ++k) {
            const Vec2 a = pts[k] - m_apex, e = pts[(k + 1) % n] - pts[k];
            const double len = std::sqrt(lengthSquared<2>(e));
            if (!(len > 0)) continue;
            // Counter-clockwise, the interior is left of each edge: the outward normal is (e.y, -e.x) / |e|.
            const double nx = orient * e.y / len, ny = -orient * e.x / len, h = nx * a.x + ny * a.y;
            rawHoldsApex = rawHoldsApex && h >= 0;
            m_planes.push_back({nx, ny, h - s});
        }
        if (rawHoldsApex) { // the shrunk polygon may still miss the apex; its extent is then unknown here
            x0 = 0;
            x1 = m_span;
        } else {
            Vec2 r{0.0};
            for (const Vec2& p : pts) r += p - m_apex;
            r /= double(n);
            double dMin = 0, dMax = 0;
            for (const Vec2& p : pts) {
                const double d = angleFrom(r, p - m_apex);
                dMin = std::min(dMin, d);
                dMax = std::max(dMax, d);
            }
            const double x = binCoord(r);
            x0 = x + dMin - kAnglePad;
            x1 = x + dMax + kAnglePad;
        }
    } else {
        boxExtent(lo + s, hi - s, x0, x1);
    }
    // Holding or touching the camera (the apex in the closed half-plane intersection): skipped; no ray would
    // pass the tEnter > 0 test anyway. An apex outside it by any margin is fine: the computed region lies in
    // the true shrunk shape (pad), and the entries are computed with their own margins, so a shape whose
    // unshrunk boundary passes through the camera (a camera on a wall's face) still blocks the rays into it.
    bool holdsApex = true;
    for (const HalfPlane& p : m_planes) holdsApex = holdsApex && p.h >= 0;
    if (holdsApex) return;
    const double* rx = m_rayX.data();
    const double* ry = m_rayY.data();
    // Every entry written is at least the nearest distance of the shrunk bounding box (drawRuns' trimmed
    // ends): the entries are computed with their margins on the large side.
    const double nearest = std::sqrt(lengthSquared<2>(glm::clamp(Vec2(0.0), lo + s, hi - s))) * (1 - 1e-6);
    // A box whose four edge lines all miss the camera: planeEntry over its four half-planes, branch-free
    // (it was a quarter of the instructions of rgvc_bench_classes' 2D box city). The same arithmetic in
    // the same order, so the same entries: along x, the planes x < X1 and -x < -X0 give the bounds X1 / ux
    // and (-X0) / (-ux) = X0 / ux, the smaller the entry when ux > 0 and the larger when ux < 0, each with
    // |n.u| = |ux|; a tie between the axes keeps x's (planeEntry replaces only on a strict improvement).
    // A ray parallel to x (ux = +-0) gets the bounds +-inf, which leave it passing exactly when X0 < 0 <
    // X1, planeEntry's condition; no bound is 0 / 0 since no edge line holds the camera (X0, X1, Y0, Y1
    // != 0; otherwise planeEntry itself).
    const double X0 = -m_planes[1].h, X1 = m_planes[0].h, Y0 = -m_planes[3].h, Y1 = m_planes[2].h;
    if (std::holds_alternative<Box<2>>(shape) && X0 != 0 && X1 != 0 && Y0 != 0 && Y1 != 0) {
        const double absMargin = kRelMargin * scale * 1e-3, absPad = kRelMargin * scale;
        drawRuns(x0, x1, nearest, [&](int i0, int i1, double* out) {
            for (int i = i0; i <= i1; ++i) {
                const double ux = rx[i], uy = ry[i];
                const double xa = X0 / ux, xb = X1 / ux, ya = Y0 / uy, yb = Y1 / uy;
                const double ex = std::min(xa, xb), fx = std::max(xa, xb), ey = std::min(ya, yb), fy = std::max(ya, yb);
                const bool yEnters = ey > ex, yExits = fy < fx;
                const double tEnter = yEnters ? ey : ex, tExit = yExits ? fy : fx;
                const double aEnter = yEnters ? std::abs(uy) : std::abs(ux), aExit = yExits ? std::abs(uy) : std::abs(ux);
                const double mEnter = kRelMargin + 8 * kEps / aEnter, mExit = 8 * kEps / aExit;
                const bool ok = (tEnter > 0) & (tExit > tEnter) & (tExit - tEnter > (mEnter + mExit) * tExit + absMargin);
                out[i] = ok ? tEnter * (1 + mEnter) + absPad : -1.0;
            }
        });
        return;
    }
    drawRuns(x0, x1, nearest, [&](int i0, int i1, double* out) {
        for (int i = i0; i <= i1; ++i) out[i] = planeEntry(rx[i], ry[i], scale);
    });
}

} // namespace rgvc
