// Sampled 3D visibility reference; see ExactVisibility3D.hpp for the definition, method and tolerances.
#include "ExactVisibility3D.hpp"

#include "SegmentClip3D.hpp"
#include "TargetPoints3D.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <type_traits>
#include <variant>

namespace rgvc::reference {

namespace {

using namespace detail;

// Number of seam probes around the ray (every 22.5 degrees).
constexpr int kProbes = 16;

// Casts rays from the camera (the origin).
class RayCaster {
public:
    RayCaster(const std::vector<Obj>& objs, double far, double eps, bool fuse)
        : m_objs(objs), m_far(far), m_eps(eps), m_fuse(fuse), m_closed(objs.size()), m_inner(objs.size()) {
        for (std::size_t i = 0; i < objs.size(); ++i) m_all.push_back(i);
    }

    std::size_t seamBlockedCount = 0;

    // A grid ray: marks every object visible along unit direction u. `cand` lists (ascending) every
    // object the ray may come within 1e4*eps of; the others are known to miss it.
    void castAll(const Vec3& u, const std::vector<std::size_t>& cand, std::vector<Seen3D>& seen, std::vector<Vec3>& witness) {
        const std::size_t n = m_objs.size();
        // Y blocks X when Y's interior starts (clamped at the camera) before X's first point; only the two
        // smallest starts are needed to answer "any Y other than X".
        double s1 = kInf, s2 = kInf;
        std::size_t i1 = n;
        for (std::size_t i : cand) {
            m_closed[i] = clip(m_objs[i], u, m_eps);
            if (m_closed[i].empty() || m_closed[i].hi < 0) { // misses the grown object: misses its interior
                m_inner[i] = {};
                continue;
            }
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
        for (std::size_t x : cand) {
            if (seen[x] != Seen3D::No) continue;
            const Interval& c = m_closed[x];
            if (c.empty() || c.hi < 0) continue;
            double t = std::max(c.lo, 0.0); // first point of X on the ray; 0 when X holds the camera
            if (t > m_far + m_eps) continue;
            if ((x == i1 ? s2 : s1) < t) continue; // the open segment (0, t) crosses an interior
            if (m_fuse && t > 0 && seamBlocked(x, t, u, cand)) {
                ++seamBlockedCount;
                continue;
            }
            seen[x] = Seen3D::GridRay;
            witness[x] = t * u;
        }
    }

    // A target ray of object x: whether it shows x; t = x's first point along u.
    bool castAt(std::size_t x, const Vec3& u, double& t) {
        Interval c = clip(m_objs[x], u, m_eps);
        if (c.empty() || c.hi < 0) return false;
        t = std::max(c.lo, 0.0);
        if (t > m_far + m_eps) return false;
        for (std::size_t j = 0; j < m_objs.size(); ++j) {
            if (j == x) continue;
            Interval in = clip(m_objs[j], u, -m_eps);
            if (in.lo < in.hi && in.hi > 0 && std::max(in.lo, 0.0) < t) return false;
        }
        if (m_fuse && t > 0) {
            for (std::size_t j = 0; j < m_objs.size(); ++j)
                if (fusesSeams(m_objs[j])) m_closed[j] = clip(m_objs[j], u, m_eps);
            if (seamBlocked(x, t, u, m_all)) {
                ++seamBlockedCount;
                return false;
            }
        }
        return true;
    }

private:
    // The seam rule (see the header): the open segment (0, t) is not blocked by any interior; does some
    // piece of it run inside the interior of the union of the boxes other than x? Needs m_closed of the
    // boxes in `cand` (every object within 1e4*eps of the ray, so every one a probe can reach).
    bool seamBlocked(std::size_t x, double t, const Vec3& u, const std::vector<std::size_t>& cand) {
        const double minPiece = 1e3 * m_eps;
        bool anyGrazer = false;
        m_breaks.assign({0.0, t});
        for (std::size_t j : cand) {
            const Interval& c = m_closed[j];
            if (j == x || !fusesSeams(m_objs[j]) || c.empty()) continue;
            if (std::min(c.hi, t) - std::max(c.lo, 0.0) > minPiece) anyGrazer = true;
            if (c.lo > 0 && c.lo < t) m_breaks.push_back(c.lo);
            if (c.hi > 0 && c.hi < t) m_breaks.push_back(c.hi);
        }
        if (!anyGrazer) return false;
        std::sort(m_breaks.begin(), m_breaks.end());
        // An orthonormal basis of the plane perpendicular to u.
        const Vec3 e1 = normalized(glm::cross(u, std::abs(u.x) < 0.6 ? Vec3{1.0, 0.0, 0.0} : Vec3{0.0, 1.0, 0.0}));
        const Vec3 e2 = glm::cross(u, e1);
        for (std::size_t k = 0; k + 1 < m_breaks.size(); ++k) {
            double p = m_breaks[k], q = m_breaks[k + 1];
            if (q - p <= minPiece) continue;
            // Since nothing blocks, every box covering the piece only grazes it: the piece lies on that
            // box's boundary. Pieces covered by no box are never inside the boxes' union.
            bool onBoundary = false;
            for (std::size_t k2 = 0; k2 < cand.size() && !onBoundary; ++k2) {
                const std::size_t j = cand[k2];
                onBoundary = j != x && fusesSeams(m_objs[j]) && m_closed[j].lo <= p && m_closed[j].hi >= q;
            }
            if (!onBoundary) continue;
            double delta = std::max(10 * m_eps, std::min(1e4 * m_eps, 1e-3 * (q - p)));
            Vec3 m = (0.5 * (p + q)) * u;
            bool all = true;
            for (int a = 0; a < kProbes && all; ++a) {
                double ang = kTwoPi * a / kProbes;
                Vec3 probe = m + delta * (std::cos(ang) * e1 + std::sin(ang) * e2);
                bool in = false;
                for (std::size_t k2 = 0; k2 < cand.size() && !in; ++k2) {
                    const std::size_t j = cand[k2];
                    in = j != x && fusesSeams(m_objs[j]) && containsPoint(m_objs[j], probe, m_eps);
                }
                all = in;
            }
            if (all) return true;
        }
        return false;
    }

    const std::vector<Obj>& m_objs;
    double m_far, m_eps;
    bool m_fuse;
    std::vector<Interval> m_closed, m_inner;
    std::vector<double> m_breaks;
    std::vector<std::size_t> m_all; // 0 .. n-1
};


// ---------------------------------------------------------------------------------------------------
// Ray culling for the grid. Grid ray (i, j) has direction f + tan(th_i) r + tan(tv_j) v; projected onto
// the (r, f) plane it is the 2D ray at angle th_i, so it can only pass within rho of a point at 2D
// distance D and angle c from the apex when |th_i - c| <= asin(rho / D); the same in the (v, f) plane
// for tv_j. With rho the object's bounding sphere grown by 2e4*eps (every probe of the seam rule is
// within 1e4*eps of the ray) and one grid step of margin each way, an object outside its range is
// certainly missed by the ray, so skipping it changes nothing.

struct GridRange {
    int i0, i1, j0, j1; // inclusive; i0 > i1 (or j0 > j1) when empty
};

GridRange gridRange(const Obj& o, const Frustum& fr, int g, double eps) {
    Vec3 c;
    double rho;
    if (o.isBall) {
        c = o.center;
        rho = o.radius;
    } else {
        c = 0.5 * (o.lo + o.hi);
        rho = 0.5 * std::sqrt(lengthSquared<3>(o.hi - o.lo));
    }
    rho = rho * (1 + 1e-9) + 2e4 * eps;
    const double z = glm::dot(c, fr.f);
    auto range = [&](double lateral, double tanHalf, int& k0, int& k1) {
        const double D = std::sqrt(lateral * lateral + z * z);
        k0 = 0;
        k1 = g;
        if (!(D > rho * (1 + 1e-9))) return; // the apex is (nearly) inside: every ray
        const double centre = std::atan2(lateral, z), half = std::asin(rho / D), alpha = std::atan(tanHalf);
        // Index of angle th: (th / alpha + 1) * g / 2.
        const double lo = ((centre - half) / alpha + 1) * 0.5 * g, hi = ((centre + half) / alpha + 1) * 0.5 * g;
        if (!(hi >= -1) || !(lo <= g + 1)) { // outside the fan (or NaN): empty
            k0 = 1;
            k1 = 0;
            return;
        }
        k0 = lo <= 1 ? 0 : int(std::floor(lo)) - 1;
        k1 = hi >= g - 1 ? g : int(std::ceil(hi)) + 1;
    };
    GridRange r{0, 0, 0, 0};
    range(glm::dot(c, fr.r), fr.tanH, r.i0, r.i1);
    range(glm::dot(c, fr.v), fr.tanV, r.j0, r.j1);
    return r;
}

// ---------------------------------------------------------------------------------------------------
// Critical rays. On the sphere of directions around the camera every object's outline is a curve: a
// sphere's silhouette is a circle (the cone u.c = k), a box's outline is made of arcs of great circles
// (the fans of its edges; all 12 are taken, a superset), and the frustum's boundary is four such arcs.
// The part of X that is visible is a union of faces of the arrangement of these curves (up to the
// curves where X cuts into another object, and where the far sphere cuts it, which only the targets
// sample). A face bounded by two or more curves has a vertex: a crossing of two curves, a box corner or
// a frustum corner; a face bounded by one curve only is bounded by X's own outline, which the targets
// sample. Visibility is a closed condition in the ray direction (interiors are open), so the ray
// through a vertex of a visible face of X sees X too: it grazes the curves that meet there. So a ray
// through every crossing of every two curves finds the objects seen through pinholes and thin slivers
// that no sampling density would be sure to hit.

struct BoundCone {
    Vec3 axis{0.0, 0.0, 1.0};
    double cosR = -2; // u is inside when dot(u, axis) >= cosR; -2: every direction
};

// The directions of every ray that comes within 1e4*eps of the object (its bounding sphere, grown).
BoundCone boundCone(const Obj& o, double eps) {
    Vec3 c = o.isBall ? o.center : 0.5 * (o.lo + o.hi);
    double rho = o.isBall ? o.radius : 0.5 * std::sqrt(lengthSquared<3>(o.hi - o.lo));
    rho = rho * (1 + 1e-9) + 2e4 * eps;
    const double D = std::sqrt(lengthSquared<3>(c));
    BoundCone b;
    if (!(D > rho * (1 + 1e-9))) return b;
    b.axis = c / D;
    const double sinR = rho / D;
    b.cosR = std::sqrt(std::max(0.0, 1 - sinR * sinR)) - 1e-12;
    return b;
}

bool coneHas(const BoundCone& b, const Vec3& u) { return b.cosR < -1 || glm::dot(u, b.axis) >= b.cosR; }

bool conesOverlap(const BoundCone& a, const BoundCone& b) {
    if (a.cosR < -1 || b.cosR < -1) return true;
    const double between = std::acos(std::clamp(glm::dot(a.axis, b.axis), -1.0, 1.0));
    return between <= std::acos(std::clamp(a.cosR, -1.0, 1.0)) + std::acos(std::clamp(b.cosR, -1.0, 1.0)) + 1e-9;
}

struct Arc { // the great-circle arc from direction a to direction b (less than half a turn); n = a x b, unit
    Vec3 a, b, n;
};
struct Outline {
    bool hasCircle = false;
    Vec3 axis{0.0}; // circle: dot(u, axis) = k
    double k = 0;
    std::vector<Arc> arcs;
    BoundCone bound;
};

void addArc(std::vector<Arc>& arcs, const Vec3& p, const Vec3& q) {
    const Vec3 c = glm::cross(p, q);
    const double c2 = lengthSquared<3>(c);
    if (!(c2 > 1e-24 * lengthSquared<3>(p) * lengthSquared<3>(q))) return; // the camera is on the edge's line
    arcs.push_back({normalized(p), normalized(q), c / std::sqrt(c2)});
}

Outline outlineOf(const Obj& o, double eps) {
    Outline out;
    out.bound = boundCone(o, eps);
    if (o.isBall) {
        const double L = std::sqrt(lengthSquared<3>(o.center));
        if (L > o.radius) {
            out.hasCircle = true;
            out.axis = o.center / L;
            const double sr = o.radius / L;
            out.k = std::sqrt(std::max(0.0, 1 - sr * sr));
        }
        return out;
    }
    if (o.isPoly) { // its outline is made of arcs of its edges' fans (all taken: a superset)
        for (const auto& e : o.edges) addArc(out.arcs, o.verts[e[0]], o.verts[e[1]]);
        // A mesh as a blocker: its silhouette is made of its own edges (a concave mesh's are not all on
        // the hull), so all of them join too.
        for (const auto& e : o.meshEdges) addArc(out.arcs, o.meshVerts[e[0]], o.meshVerts[e[1]]);
        return out;
    }
    auto corner = [&](int bits) { return Vec3{bits & 1 ? o.hi.x : o.lo.x, bits & 2 ? o.hi.y : o.lo.y, bits & 4 ? o.hi.z : o.lo.z}; };
    for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 8; ++c)
            if (!(c & (1 << a))) addArc(out.arcs, corner(c), corner(c | (1 << a)));
    return out;
}

bool onArc(const Arc& arc, const Vec3& u) {
    const double tol = 1e-12;
    return glm::dot(glm::cross(arc.a, u), arc.n) >= -tol && glm::dot(glm::cross(u, arc.b), arc.n) >= -tol &&
           glm::dot(u, arc.a + arc.b) > 0;
}

// Directions on both circles dot(u, c1) = k1 and dot(u, c2) = k2.
void circleCircle(const Vec3& c1, double k1, const Vec3& c2, double k2, std::vector<Vec3>& out) {
    const double g = glm::dot(c1, c2), det = 1 - g * g;
    if (!(det > 1e-15)) return; // (nearly) the same axis: no isolated crossing
    const double al = (k1 - g * k2) / det, be = (k2 - g * k1) / det;
    const Vec3 w = glm::cross(c1, c2); // |w|^2 = det
    double ga2 = (1 - (al * al + be * be + 2 * al * be * g)) / det;
    if (ga2 < -1e-12) return;
    const double ga = std::sqrt(std::max(0.0, ga2));
    out.push_back(normalized(al * c1 + be * c2 + ga * w));
    if (ga > 0) out.push_back(normalized(al * c1 + be * c2 - ga * w));
}

// Directions on the circle dot(u, c) = k and on the arc.
void circleArc(const Vec3& c, double k, const Arc& arc, std::vector<Vec3>& out) {
    const double s = glm::dot(c, arc.n);
    Vec3 e1 = c - s * arc.n;
    const double m = std::sqrt(lengthSquared<3>(e1));
    if (!(m > 1e-12)) return;
    e1 /= m;
    const Vec3 e2 = glm::cross(arc.n, e1);
    const double cph = k / m;
    if (cph > 1 + 1e-12 || cph < -1 - 1e-12) return;
    const double ph = std::acos(std::clamp(cph, -1.0, 1.0));
    for (double a : {ph, -ph}) {
        Vec3 u = std::cos(a) * e1 + std::sin(a) * e2;
        if (onArc(arc, u)) out.push_back(u);
    }
}

void arcArc(const Arc& p, const Arc& q, std::vector<Vec3>& out) {
    const Vec3 w = glm::cross(p.n, q.n);
    const double w2 = lengthSquared<3>(w);
    if (!(w2 > 1e-30)) return; // the same great circle: the endpoints are vertices already
    const Vec3 u = w / std::sqrt(w2);
    for (const Vec3& v : {u, -u})
        if (onArc(p, v) && onArc(q, v)) out.push_back(v);
}

void crossings(const Outline& A, const Outline& B, std::vector<Vec3>& out) {
    if (A.hasCircle && B.hasCircle) circleCircle(A.axis, A.k, B.axis, B.k, out);
    if (A.hasCircle)
        for (const Arc& b : B.arcs) circleArc(A.axis, A.k, b, out);
    if (B.hasCircle)
        for (const Arc& a : A.arcs) circleArc(B.axis, B.k, a, out);
    for (const Arc& a : A.arcs)
        for (const Arc& b : B.arcs) arcArc(a, b, out);
}

double resolveEps(double eps, const std::vector<Shape<3>>& objects, const Camera3& camera) {
    return eps > 0 ? eps : sceneEpsilon3D(objects, camera);
}

} // namespace

double sceneEpsilon3D(const std::vector<Shape<3>>& objects, const Camera3& camera) {
    double scale = 0;
    auto grow = [&](const Vec3& p) { scale = std::max({scale, std::abs(p.x), std::abs(p.y), std::abs(p.z)}); };
    grow(camera.position);
    for (const Shape<3>& s : objects) {
        Box<3> b = boundsOf<3>(s);
        grow(b.min);
        grow(b.max);
        if (const auto* ball = std::get_if<Ball<3>>(&s)) scale = std::max(scale, ball->radius);
    }
    return 1e-12 * (scale > 0 ? scale : 1.0);
}

bool pointInView3D(const Camera3& camera, const Vec3& p, double eps) {
    return Frustum(camera).contains(p - camera.position, std::max(eps, 0.0));
}

bool touchesViewRegion3D(const Shape<3>& shape, const Camera3& camera, double eps) {
    if (!(eps > 0)) eps = sceneEpsilon3D({shape}, camera);
    const Frustum fr(camera);
    const Obj o = prepare(shape, camera.position);
    return o.isBall ? sphereTouchesView(o, fr, eps) : o.isPoly ? polyTouchesView(o, fr, eps) : boxTouchesView(o, fr, eps);
}

std::vector<bool> inViewRegion3D(const std::vector<Shape<3>>& objects, const Camera3& camera) {
    const double eps = sceneEpsilon3D(objects, camera);
    std::vector<bool> out(objects.size());
    for (std::size_t i = 0; i < objects.size(); ++i) out[i] = touchesViewRegion3D(objects[i], camera, eps);
    return out;
}

std::vector<bool> visible3D(const std::vector<Shape<3>>& objects, const Camera3& camera,
                            const Visibility3DOptions& options, Visibility3DStats* stats) {
    const double eps = resolveEps(options.eps, objects, camera);
    const Frustum fr(camera);
    std::vector<Obj> objs;
    objs.reserve(objects.size());
    for (const Shape<3>& s : objects) objs.push_back(prepare(s, camera.position));
    const std::size_t n = objs.size();

    std::vector<Seen3D> seen(n, Seen3D::No);
    std::vector<Vec3> witness(n, Vec3(0.0));
    // Objects whose bounding sphere misses the view region can never be seen (they still block, as far as
    // the ray tests go): they do not keep the search going.
    std::vector<char> possible(n);
    for (std::size_t x = 0; x < n; ++x) {
        Obj bs;
        bs.isBall = true;
        bs.center = objs[x].isBall ? objs[x].center : 0.5 * (objs[x].lo + objs[x].hi);
        bs.radius = objs[x].isBall ? objs[x].radius : 0.5 * std::sqrt(lengthSquared<3>(objs[x].hi - objs[x].lo));
        bs.radius *= 1 + 1e-9;
        possible[x] = sphereTouchesView(bs, fr, eps);
    }
    auto countRemaining = [&] {
        std::size_t r = 0;
        for (std::size_t x = 0; x < n; ++x) r += seen[x] == Seen3D::No && possible[x];
        return r;
    };
    std::size_t remaining = countRemaining();
    // 1. Objects holding the camera: the apex is in the view region and the segment to it is empty.
    for (std::size_t x = 0; x < n; ++x)
        if (containsPoint(objs[x], Vec3(0.0), eps)) {
            seen[x] = Seen3D::ContainsCamera;
            remaining -= possible[x] ? 1 : 0;
        }

    RayCaster caster(objs, fr.far, eps, options.fuseSeams);
    std::size_t gridRays = 0, targets = 0, targetRays = 0;

    // 2. The ray grid, uniform in angle over the frustum; the boundary rays use the exact tangents.
    const int g = options.gridDivisions;
    if (g > 0 && remaining > 0) {
        std::vector<double> ta(std::size_t(g) + 1), tb(std::size_t(g) + 1);
        const double ah = std::atan(fr.tanH), av = std::atan(fr.tanV);
        for (int i = 0; i <= g; ++i) {
            double s = 2 * frac(i, g) - 1;
            ta[std::size_t(i)] = i == 0 ? -fr.tanH : i == g ? fr.tanH : std::tan(ah * s);
            tb[std::size_t(i)] = i == 0 ? -fr.tanV : i == g ? fr.tanV : std::tan(av * s);
        }
        // Candidate objects per ray (see GridRange): per column i, those whose i-range covers it; per ray,
        // those of them whose j-range covers j.
        std::vector<GridRange> ranges;
        for (const Obj& o : objs) ranges.push_back(options.cullRays ? gridRange(o, fr, g, eps) : GridRange{0, g, 0, g});
        std::vector<std::size_t> column, cand;
        for (int i = 0; i <= g && remaining > 0; ++i) {
            column.clear();
            for (std::size_t x = 0; x < n; ++x)
                if (ranges[x].i0 <= i && i <= ranges[x].i1) column.push_back(x);
            if (column.empty()) continue; // no object near these rays
            for (int j = 0; j <= g && remaining > 0; ++j) {
                cand.clear();
                for (std::size_t x : column)
                    if (ranges[x].j0 <= j && j <= ranges[x].j1) cand.push_back(x);
                if (cand.empty()) continue;
                Vec3 u = normalized(fr.f + ta[std::size_t(i)] * fr.r + tb[std::size_t(j)] * fr.v);
                caster.castAll(u, cand, seen, witness);
                ++gridRays;
            }
            remaining = countRemaining();
        }
    }

    // 3. Rays aimed at target points on each object not yet seen.
    const int d = options.targetDivisions;
    if (d > 0) {
        std::vector<Vec3> pts;
        for (std::size_t x = 0; x < n; ++x) {
            if (seen[x] != Seen3D::No || !possible[x]) continue;
            pts.clear();
            if (objs[x].isBall) sphereTargets(objs[x], fr, d, pts);
            else if (objs[x].isPoly) polyTargets(objs[x], fr, d, pts);
            else boxTargets(objs[x], fr, d, pts);
            targets += pts.size();
            for (const Vec3& p : pts) {
                double len2 = lengthSquared<3>(p);
                if (!(len2 > 0) || !fr.contains(p, eps)) continue;
                Vec3 u = p / std::sqrt(len2);
                double t = 0;
                ++targetRays;
                if (caster.castAt(x, u, t)) {
                    seen[x] = Seen3D::TargetRay;
                    witness[x] = t * u;
                    break;
                }
            }
        }
    }

    // 4. Critical rays: through every crossing of two outlines (and the frustum's), and every box corner.
    remaining = countRemaining();
    std::size_t criticalRays = 0;
    if (options.criticalRays && remaining > 0) {
        std::vector<Outline> outlines;
        for (const Obj& o : objs) outlines.push_back(outlineOf(o, eps));
        Outline frustum; // every direction; its four side arcs between the edge rays
        addArc(frustum.arcs, fr.edge[0], fr.edge[2]);
        addArc(frustum.arcs, fr.edge[1], fr.edge[3]);
        addArc(frustum.arcs, fr.edge[0], fr.edge[1]);
        addArc(frustum.arcs, fr.edge[2], fr.edge[3]);
        std::vector<Vec3> dirs(fr.edge.begin(), fr.edge.end()); // the frustum's corners
        for (std::size_t x = 0; x < n; ++x) {
            // The outline of an object outside the view region lies outside the frustum.
            if (!possible[x]) continue;
            crossings(outlines[x], frustum, dirs);
            for (std::size_t y = x + 1; y < n; ++y)
                if (possible[y] && conesOverlap(outlines[x].bound, outlines[y].bound)) crossings(outlines[x], outlines[y], dirs);
            if (objs[x].isPoly) {
                for (const Vec3& v : objs[x].verts)
                    if (lengthSquared<3>(v) > 0) dirs.push_back(normalized(v));
                for (const Vec3& v : objs[x].meshVerts)
                    if (lengthSquared<3>(v) > 0) dirs.push_back(normalized(v));
            } else if (!objs[x].isBall)
                for (int c = 0; c < 8; ++c) {
                    Vec3 p{c & 1 ? objs[x].hi.x : objs[x].lo.x, c & 2 ? objs[x].hi.y : objs[x].lo.y, c & 4 ? objs[x].hi.z : objs[x].lo.z};
                    if (lengthSquared<3>(p) > 0) dirs.push_back(normalized(p));
                }
        }
        std::vector<std::size_t> cand;
        for (const Vec3& u : dirs) {
            if (remaining == 0) break;
            bool inView = true; // the direction in the frustum (loosened by 1e-13 radians)
            for (const Vec3& nn : fr.n) inView = inView && glm::dot(nn, u) <= 1e-13;
            if (!inView) continue;
            cand.clear();
            bool useful = false;
            for (std::size_t x = 0; x < n; ++x)
                if (coneHas(outlines[x].bound, u)) {
                    cand.push_back(x);
                    useful = useful || (seen[x] == Seen3D::No && possible[x]);
                }
            if (!useful) continue;
            std::vector<Seen3D> before = seen;
            caster.castAll(u, cand, seen, witness);
            ++criticalRays;
            for (std::size_t x : cand)
                if (before[x] == Seen3D::No && seen[x] != Seen3D::No) {
                    seen[x] = Seen3D::CriticalRay;
                    remaining -= possible[x] ? 1 : 0;
                }
        }
    }

    if (stats) {
        stats->criticalRays = criticalRays;
        stats->gridRays = gridRays;
        stats->targets = targets;
        stats->targetRays = targetRays;
        stats->seamBlocked = caster.seamBlockedCount;
        stats->eps = eps;
        stats->seen = seen;
        stats->witness.clear();
        for (const Vec3& w : witness) stats->witness.push_back(w + camera.position);
    }
    std::vector<bool> out(n);
    for (std::size_t x = 0; x < n; ++x) out[x] = seen[x] != Seen3D::No;
    return out;
}

} // namespace rgvc::reference
