// Exact 2D visibility by angular sweep; see ExactVisibility2D.hpp for the definition and tolerances.
#include "ExactVisibility2D.hpp"

#include "RayInterval.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <variant>

namespace rgvc::reference {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTwoPi = 2 * kPi;
constexpr double kInf = std::numeric_limits<double>::infinity();
// Intersection parameters slightly outside [0, 1] are accepted: an extra critical direction only
// costs a ray, a missing one could hide a visible object.
constexpr double kParamSlack = 1e-9;

Vec2 rotate(const Vec2& v, double a) {
    double c = std::cos(a), s = std::sin(a);
    return {c * v.x - s * v.y, s * v.x + c * v.y};
}

// An object in camera-relative coordinates (the camera is the origin, so rays are t*u): either a circle
// or a counter-clockwise convex polygon (boxes become polygons) with unit outward edge normals, so that
// offsets along the normals are distances.
struct Obj {
    bool isCircle = false;
    Vec2 center{0.0};
    double radius = 0;
    std::vector<Vec2> pts;
    std::vector<Vec2> normals; // normals[i]: edge pts[i] -> pts[i+1]
    Vec2 lo{0.0}, hi{0.0};     // bounding box
};

Obj prepare(const Shape<2>& shape, const Vec2& cam) {
    Obj o;
    std::visit(
        [&](const auto& s) {
            using T = std::decay_t<decltype(s)>;
            if constexpr (std::is_same_v<T, Ball<2>>) {
                o.isCircle = true;
                o.center = s.center - cam;
                o.radius = s.radius;
            } else if constexpr (std::is_same_v<T, Box<2>>) {
                o.pts = {s.min - cam, Vec2{s.max.x, s.min.y} - cam, s.max - cam, Vec2{s.min.x, s.max.y} - cam};
            } else {
                for (const Vec2& p : s.points) o.pts.push_back(p - cam);
                if (signedArea(o.pts) < 0) std::reverse(o.pts.begin(), o.pts.end());
            }
        },
        shape);
    if (o.isCircle) {
        o.lo = o.center - o.radius;
        o.hi = o.center + o.radius;
        return o;
    }
    // Drop repeated points (possible after the subtraction rounds): they would give NaN normals.
    std::vector<Vec2> pts;
    for (std::size_t i = 0; i < o.pts.size(); ++i)
        if (o.pts[i] != o.pts[(i + 1) % o.pts.size()]) pts.push_back(o.pts[i]);
    o.pts = pts;
    o.lo = o.hi = o.pts.front();
    for (std::size_t i = 0; i < o.pts.size(); ++i) {
        Vec2 e = o.pts[(i + 1) % o.pts.size()] - o.pts[i];
        o.normals.push_back(Vec2{e.y, -e.x} / std::sqrt(lengthSquared<2>(e)));
        o.lo = glm::min(o.lo, o.pts[i]);
        o.hi = glm::max(o.hi, o.pts[i]);
    }
    return o;
}


// Parameters t (whole line, t may be negative) where t*u lies within `off` of o: off > 0 grows the
// object, off < 0 keeps only points deeper than -off inside it.
Interval clip(const Obj& o, const Vec2& u, double off) {
    if (o.isCircle) return clipBall<2>(o.center, o.radius, u, off);
    double lo = -kInf, hi = kInf;
    for (std::size_t i = 0; i < o.pts.size(); ++i) {
        // Inside the grown edge half-plane: dot(n, t*u - p) <= off, i.e. f + t*d <= 0.
        double d = glm::dot(o.normals[i], u);
        double f = -glm::dot(o.normals[i], o.pts[i]) - off;
        if (d > 0) hi = std::min(hi, -f / d);
        else if (d < 0) lo = std::max(lo, -f / d);
        else if (f > 0) return {};
        if (lo > hi) return {};
    }
    // The bounding box too (grown or shrunk by off likewise, so no point of the object is lost): for a
    // sliver, two nearly parallel edges meet far from where their rounded normals say, and the half-planes
    // alone left a strip reaching hundreds of units past the polygon (fuzz_culler2d found a sliver
    // triangle reported visible from a camera looking away from it).
    for (int a = 0; a < 2; ++a) {
        const double bLo = o.lo[a] - off, bHi = o.hi[a] + off;
        if (u[a] > 0) {
            lo = std::max(lo, bLo / u[a]);
            hi = std::min(hi, bHi / u[a]);
        } else if (u[a] < 0) {
            lo = std::max(lo, bHi / u[a]);
            hi = std::min(hi, bLo / u[a]);
        } else if (bLo > 0 || bHi < 0) {
            return {};
        }
        if (lo > hi) return {};
    }
    return {lo, hi};
}

bool containsPoint(const Obj& o, const Vec2& q, double off) {
    if (o.isCircle) return lengthSquared<2>(q - o.center) <= (o.radius + off) * (o.radius + off);
    for (std::size_t i = 0; i < o.pts.size(); ++i)
        if (glm::dot(o.normals[i], q - o.pts[i]) > off) return false;
    return true;
}

// Casts rays from the camera (the origin) and marks the objects visible along them.
class RayCaster {
public:
    RayCaster(const std::vector<Obj>& objs, double far, double eps, bool fuse)
        : m_objs(objs), m_far(far), m_eps(eps), m_fuse(fuse), m_closed(objs.size()), m_inner(objs.size()) {}

    // Marks the objects visible along unit direction u; witness[x] = t * u for each one newly marked.
    void cast(const Vec2& u, std::vector<char>& visible, std::vector<Vec2>& witness) {
        const std::size_t n = m_objs.size();
        // Blockers: Y blocks X when Y's interior starts (clamped at the camera) before X's first point.
        // Only the two smallest starts are needed to answer "any Y other than X".
        double s1 = kInf, s2 = kInf;
        std::size_t i1 = n;
        for (std::size_t i = 0; i < n; ++i) {
            m_closed[i] = clip(m_objs[i], u, m_eps);
            m_inner[i] = clip(m_objs[i], u, -m_eps);
            const Interval& in = m_inner[i];
            if (in.lo < in.hi && in.hi > 0) {
                double s = std::max(in.lo, 0.0);
                if (s < s1) {
                    s2 = s1;
                    s1 = s;
                    i1 = i;
                } else if (s < s2) {
                    s2 = s;
                }
            }
        }
        for (std::size_t x = 0; x < n; ++x) {
            if (visible[x]) continue;
            const Interval& c = m_closed[x];
            if (c.empty() || c.hi < 0) continue;
            double t = std::max(c.lo, 0.0); // first point of X on the ray; 0 when X holds the camera
            if (t > m_far + m_eps) continue;
            if ((x == i1 ? s2 : s1) < t) continue; // the open segment (0, t) crosses an interior
            if (m_fuse && t > 0 && seamBlocked(x, t, u)) continue;
            visible[x] = 1;
            witness[x] = t * u;
        }
    }

private:
    // The seam rule (see the header): the open segment (0, t) is not blocked by any interior; is some
    // piece of it a seam, i.e. on an object boundary with objects other than x on both sides?
    bool seamBlocked(std::size_t x, double t, const Vec2& u) {
        const double minPiece = 1e3 * m_eps;
        bool anyGrazer = false;
        m_breaks.assign({0.0, t});
        for (std::size_t j = 0; j < m_objs.size(); ++j) {
            const Interval& c = m_closed[j];
            if (j == x || c.empty()) continue;
            if (std::min(c.hi, t) - std::max(c.lo, 0.0) > minPiece) anyGrazer = true;
            if (c.lo > 0 && c.lo < t) m_breaks.push_back(c.lo);
            if (c.hi > 0 && c.hi < t) m_breaks.push_back(c.hi);
        }
        if (!anyGrazer) return false;
        std::sort(m_breaks.begin(), m_breaks.end());
        const Vec2 normal{-u.y, u.x};
        for (std::size_t k = 0; k + 1 < m_breaks.size(); ++k) {
            double p = m_breaks[k], q = m_breaks[k + 1];
            if (q - p <= minPiece) continue;
            // Since nothing blocks, every object covering the piece only grazes it: the piece lies on
            // that object's boundary. Pieces covered by no object are open space, never a seam.
            bool onBoundary = false;
            for (std::size_t j = 0; j < m_objs.size() && !onBoundary; ++j)
                onBoundary = j != x && m_closed[j].lo <= p && m_closed[j].hi >= q;
            if (!onBoundary) continue;
            double delta = std::max(10 * m_eps, std::min(1e4 * m_eps, 1e-3 * (q - p)));
            Vec2 m = (0.5 * (p + q)) * u;
            Vec2 a = m + delta * normal, b = m - delta * normal;
            bool inA = false, inB = false;
            for (std::size_t j = 0; j < m_objs.size() && !(inA && inB); ++j) {
                if (j == x) continue;
                inA = inA || containsPoint(m_objs[j], a, m_eps);
                inB = inB || containsPoint(m_objs[j], b, m_eps);
            }
            if (inA && inB) return true;
        }
        return false;
    }

    const std::vector<Obj>& m_objs;
    double m_far, m_eps;
    bool m_fuse;
    std::vector<Interval> m_closed, m_inner;
    std::vector<double> m_breaks;
};

// The wedge as angles alpha in [0, fov] measured counter-clockwise from its clockwise edge e0.
struct Wedge {
    Vec2 e0{1.0, 0.0}, e1{1.0, 0.0};
    double fov = kTwoPi;
    bool full = true;

    explicit Wedge(const Camera2& camera) {
        Vec2 dir = camera.direction / std::sqrt(lengthSquared<2>(camera.direction));
        fov = camera.fovDeg * kPi / 180.0;
        // Same rule as ViewWedge: within 1e-12 of a full turn is a full turn.
        full = fov >= kTwoPi - 1e-12;
        if (full) {
            fov = kTwoPi;
            e0 = e1 = dir;
        } else {
            e0 = rotate(dir, -0.5 * fov);
            e1 = rotate(dir, 0.5 * fov);
        }
    }
    Vec2 at(double alpha) const { return rotate(e0, alpha); }
};

struct Direction {
    double alpha;
    Vec2 u;
};

class CriticalDirections {
public:
    explicit CriticalDirections(const Wedge& w) : m_w(w) {
        m_dirs.push_back({0.0, w.e0});
        if (!w.full) m_dirs.push_back({w.fov, w.e1});
    }

    // Direction towards point v (camera-relative); ignored when v is the camera or outside the wedge.
    // The ray is cast along v itself rather than along its rounded angle: it then passes through v to
    // within double rounding.
    void addPoint(const Vec2& v) {
        double len = std::sqrt(lengthSquared<2>(v));
        if (!(len > 0) || !std::isfinite(len)) return;
        Vec2 u = v / len;
        double a = std::atan2(cross2(m_w.e0, u), glm::dot(m_w.e0, u));
        if (a < 0) a += kTwoPi;
        if (m_w.full) {
            if (a >= kTwoPi) a = 0;
        } else if (a > m_w.fov) {
            return; // outside; a critical direction within rounding of an edge is replaced by the edge ray
        }
        m_dirs.push_back({a, u});
    }

    void addSegmentSegment(const Vec2& a, const Vec2& b, const Vec2& p, const Vec2& q) {
        Vec2 r = b - a, s = q - p;
        double den = cross2(r, s);
        if (den == 0) return; // parallel: a shared stretch ends at vertices, which are critical already
        double t = cross2(p - a, s) / den, w = cross2(p - a, r) / den;
        if (t >= -kParamSlack && t <= 1 + kParamSlack && w >= -kParamSlack && w <= 1 + kParamSlack)
            addPoint(a + t * r);
    }

    void addSegmentCircle(const Vec2& a, const Vec2& b, const Vec2& c, double r) {
        Vec2 d = b - a;
        double len2 = lengthSquared<2>(d);
        if (!(len2 > 0)) return;
        double t0 = glm::dot(c - a, d) / len2; // foot of the perpendicular from c
        double h2 = lengthSquared<2>(a + t0 * d - c);
        double disc = r * r - h2;
        if (disc < -1e-9 * r * r) return; // a near-tangent still counts: its touching point is critical
        double s = std::sqrt(std::max(disc, 0.0) / len2);
        for (double t : {t0 - s, t0 + s})
            if (t >= -kParamSlack && t <= 1 + kParamSlack) addPoint(a + t * d);
    }

    void addCircleCircle(const Vec2& c1, double r1, const Vec2& c2, double r2) {
        Vec2 v = c2 - c1;
        double d = std::sqrt(lengthSquared<2>(v));
        double tol = 1e-9 * (r1 + r2);
        if (!(d > 0) || d > r1 + r2 + tol || d < std::abs(r1 - r2) - tol) return;
        double a = (d * d + r1 * r1 - r2 * r2) / (2 * d);
        double h = std::sqrt(std::max(r1 * r1 - a * a, 0.0));
        Vec2 base = c1 + (a / d) * v, perp = Vec2{-v.y, v.x} / d;
        addPoint(base + h * perp);
        addPoint(base - h * perp);
    }

    // Every intersection of the boundaries of o1 and o2.
    void addBoundaryIntersections(const Obj& o1, const Obj& o2) {
        if (o1.isCircle && o2.isCircle) return addCircleCircle(o1.center, o1.radius, o2.center, o2.radius);
        if (o1.isCircle) return addBoundaryIntersections(o2, o1);
        const std::size_t n1 = o1.pts.size();
        for (std::size_t i = 0; i < n1; ++i) {
            const Vec2 &a = o1.pts[i], &b = o1.pts[(i + 1) % n1];
            if (o2.isCircle) {
                addSegmentCircle(a, b, o2.center, o2.radius);
                continue;
            }
            for (std::size_t j = 0, n2 = o2.pts.size(); j < n2; ++j) addSegmentSegment(a, b, o2.pts[j], o2.pts[(j + 1) % n2]);
        }
    }

    // Directions where the ray starts or stops meeting o: its vertices, or its tangents.
    void addSilhouette(const Obj& o, double eps) {
        if (!o.isCircle) {
            for (const Vec2& p : o.pts) addPoint(p);
            return;
        }
        double d = std::sqrt(lengthSquared<2>(o.center));
        if (!(d > 0) || d < o.radius - eps) return; // camera inside: every direction meets it
        double half = std::asin(std::min(1.0, o.radius / d));
        Vec2 w = o.center / d;
        addPoint(rotate(w, half));
        addPoint(rotate(w, -half));
    }

    // Sorted critical directions plus the middle of every gap between neighbours (wrapping for 360).
    std::vector<Vec2> rays(std::size_t& criticalCount) {
        std::sort(m_dirs.begin(), m_dirs.end(), [](const Direction& a, const Direction& b) { return a.alpha < b.alpha; });
        criticalCount = m_dirs.size();
        std::vector<Vec2> out;
        out.reserve(2 * m_dirs.size());
        for (std::size_t i = 0; i < m_dirs.size(); ++i) {
            out.push_back(m_dirs[i].u);
            double a = m_dirs[i].alpha;
            double b = i + 1 < m_dirs.size() ? m_dirs[i + 1].alpha : (m_w.full ? m_dirs[0].alpha + kTwoPi : a);
            if (b > a) out.push_back(m_w.at(0.5 * (a + b)));
        }
        return out;
    }

private:
    const Wedge& m_w;
    std::vector<Direction> m_dirs;
};

bool boxesNear(const Obj& a, const Obj& b, double tol) {
    return a.lo.x <= b.hi.x + tol && b.lo.x <= a.hi.x + tol && a.lo.y <= b.hi.y + tol && b.lo.y <= a.hi.y + tol;
}

std::vector<Obj> prepareAll(const std::vector<Shape<2>>& objects, const Camera2& camera) {
    std::vector<Obj> objs;
    objs.reserve(objects.size());
    for (const Shape<2>& s : objects) objs.push_back(prepare(s, camera.position));
    return objs;
}

double resolveEps(double eps, const std::vector<Shape<2>>& objects, const Camera2& camera) {
    return eps > 0 ? eps : sceneEpsilon(objects, camera);
}

std::vector<bool> toBools(const std::vector<char>& v) { return std::vector<bool>(v.begin(), v.end()); }

} // namespace

double sceneEpsilon(const std::vector<Shape<2>>& objects, const Camera2& camera) {
    double scale = std::max(std::abs(camera.position.x), std::abs(camera.position.y));
    auto grow = [&](const Vec2& p) { scale = std::max({scale, std::abs(p.x), std::abs(p.y)}); };
    for (const Shape<2>& s : objects) {
        Box<2> b = boundsOf<2>(s);
        grow(b.min);
        grow(b.max);
        if (const auto* ball = std::get_if<Ball<2>>(&s)) scale = std::max(scale, ball->radius);
    }
    return 1e-12 * (scale > 0 ? scale : 1.0);
}

std::vector<bool> exactVisible2D(const std::vector<Shape<2>>& objects, const Camera2& camera,
                                 const ExactOptions& options, ExactStats* stats) {
    const double eps = resolveEps(options.eps, objects, camera);
    const std::vector<Obj> objs = prepareAll(objects, camera);
    const Wedge wedge(camera);

    CriticalDirections crit(wedge);
    for (const Obj& o : objs) crit.addSilhouette(o, eps);
    for (std::size_t i = 0; i < objs.size(); ++i)
        for (std::size_t j = i + 1; j < objs.size(); ++j)
            if (boxesNear(objs[i], objs[j], 1e3 * eps)) crit.addBoundaryIntersections(objs[i], objs[j]);
    if (std::isfinite(camera.far)) {
        Obj farCircle;
        farCircle.isCircle = true;
        farCircle.radius = camera.far;
        farCircle.lo = Vec2(-camera.far);
        farCircle.hi = Vec2(camera.far);
        for (const Obj& o : objs)
            if (boxesNear(o, farCircle, 1e3 * eps)) crit.addBoundaryIntersections(o, farCircle);
    }

    std::size_t criticalCount = 0;
    const std::vector<Vec2> rays = crit.rays(criticalCount);
    RayCaster caster(objs, camera.far, eps, options.fuseSeams);
    std::vector<char> visible(objs.size(), 0);
    std::vector<Vec2> witness(objs.size(), Vec2(0.0));
    std::size_t cast = 0, remaining = objs.size();
    for (const Vec2& u : rays) {
        if (remaining == 0) break;
        caster.cast(u, visible, witness);
        ++cast;
        remaining = std::size_t(std::count(visible.begin(), visible.end(), char(0)));
    }
    if (stats) {
        stats->criticalDirections = criticalCount;
        stats->rays = cast;
        stats->witness.clear();
        for (const Vec2& w : witness) stats->witness.push_back(w + camera.position);
    }
    return toBools(visible);
}

std::vector<bool> denseRaycastVisible2D(const std::vector<Shape<2>>& objects, const Camera2& camera, int rays,
                                        const ExactOptions& options) {
    const double eps = resolveEps(options.eps, objects, camera);
    const std::vector<Obj> objs = prepareAll(objects, camera);
    const Wedge wedge(camera);
    RayCaster caster(objs, camera.far, eps, options.fuseSeams);
    std::vector<char> visible(objs.size(), 0);
    std::vector<Vec2> witness(objs.size(), Vec2(0.0));
    const int n = std::max(rays, 2);
    for (int k = 0; k < n; ++k) {
        // Full circle: n distinct directions; a wedge: both edges included.
        double alpha = wedge.full ? kTwoPi * k / n : wedge.fov * k / (n - 1);
        caster.cast(k == n - 1 && !wedge.full ? wedge.e1 : wedge.at(alpha), visible, witness);
    }
    return toBools(visible);
}

bool touchesViewRegion(const Shape<2>& shape, const Camera2& camera, double eps) {
    // A one-object sweep: with nothing to block, "visible" is "meets the view region".
    ExactOptions options;
    options.eps = eps > 0 ? eps : sceneEpsilon({shape}, camera);
    options.fuseSeams = false;
    return exactVisible2D({shape}, camera, options)[0];
}

std::vector<bool> inViewRegion2D(const std::vector<Shape<2>>& objects, const Camera2& camera) {
    const double eps = sceneEpsilon(objects, camera);
    std::vector<bool> out(objects.size());
    for (std::size_t i = 0; i < objects.size(); ++i) out[i] = touchesViewRegion(objects[i], camera, eps);
    return out;
}

} // namespace rgvc::reference
