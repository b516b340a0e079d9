// Ray clipping and view-region tests of the 3D reference's shapes; see SegmentClip3D.hpp.
#include "SegmentClip3D.hpp"

#include <algorithm>
#include <variant>

namespace rgvc::reference::detail {

Obj prepare(const Shape<3>& shape, const Vec3& cam) {
    Obj o;
    if (const auto* b = std::get_if<Ball<3>>(&shape)) {
        o.isBall = true;
        o.center = b->center - cam;
        o.radius = b->radius;
        o.lo = o.center - o.radius;
        o.hi = o.center + o.radius;
    } else if (const auto* x = std::get_if<Box<3>>(&shape)) {
        o.lo = x->min - cam;
        o.hi = x->max - cam;
    } else {
        // A polytope: taken as its vertices' hull with its planes (the library's two representations agree
        // to within its tolerance, ~1e-15 of the extent, far below eps). A mesh: its hull, and its triangles.
        const MeshSolid* mesh = std::get_if<MeshSolid>(&shape);
        const ConvexPolytope& p = mesh != nullptr ? mesh->hull() : std::get<ConvexPolytope>(shape);
        if (mesh != nullptr) {
            o.isMesh = true;
            o.meshClosed = mesh->closed();
            const TriangleMesh& m = mesh->model()->mesh;
            for (const Vec3& v : m.positions) o.meshVerts.push_back(mesh->place(v) - cam);
            o.meshTris = m.triangles;
            for (const auto& t : m.triangles)
                for (int k = 0; k < 3; ++k) {
                    const std::uint32_t a = t[std::size_t(k)], b = t[std::size_t((k + 1) % 3)];
                    o.meshEdges.push_back({std::min(a, b), std::max(a, b)});
                }
            std::sort(o.meshEdges.begin(), o.meshEdges.end());
            o.meshEdges.erase(std::unique(o.meshEdges.begin(), o.meshEdges.end()), o.meshEdges.end());
        }
        o.isPoly = true;
        o.lo = p.boundsMin - cam;
        o.hi = p.boundsMax - cam;
        for (const HalfSpace& h : p.planes) o.planes.push_back({h.normal, h.offset - glm::dot(h.normal, cam)});
        for (const Vec3& v : p.vertices) o.verts.push_back(v - cam);
        o.edges = p.edges;
        o.tris = p.triangles;
    }
    return o;
}


// Parameters t (whole line) where t*u lies within `off` of o: off > 0 grows the object, off < 0 keeps only
// points deeper than -off inside it.
Interval clip(const Obj& o, const Vec3& u, double off) {
    if (o.isBall) return clipBall<3>(o.center, o.radius, u, off);
    if (o.isMesh && off < 0) return meshInterior(o, u, -off);
    double lo = -kInf, hi = kInf;
    if (o.isPoly) {
        for (const HalfSpace& h : o.planes) {
            const double den = glm::dot(h.normal, u), c = h.offset + off;
            if (std::abs(den) < 1e-300) {
                if (c < 0) return {};
                continue;
            }
            if (den > 0) hi = std::min(hi, c / den);
            else lo = std::max(lo, c / den);
            if (lo > hi) return {};
        }
        return {lo, hi};
    }
    for (int a = 0; a < 3; ++a) {
        double l = o.lo[a] - off, h = o.hi[a] + off;
        if (!(l <= h)) return {};
        if (std::abs(u[a]) < 1e-300) {
            if (0 < l || 0 > h) return {};
            continue;
        }
        double inv = 1.0 / u[a];
        double t1 = l * inv, t2 = h * inv;
        if (t1 > t2) std::swap(t1, t2);
        lo = std::max(lo, t1);
        hi = std::min(hi, t2);
        if (lo > hi) return {};
    }
    return {lo, hi};
}

bool containsPoint(const Obj& o, const Vec3& q, double off) {
    if (o.isBall) return lengthSquared<3>(q - o.center) <= (o.radius + off) * (o.radius + off);
    if (o.isPoly) {
        for (const HalfSpace& h : o.planes)
            if (glm::dot(h.normal, q) > h.offset + off) return false;
        return true;
    }
    for (int a = 0; a < 3; ++a)
        if (q[a] < o.lo[a] - off || q[a] > o.hi[a] + off) return false;
    return true;
}


// ---------------------------------------------------------------------------------------------------
// Exact (up to eps) view-region tests.

// Sutherland-Hodgman: keeps the part of the polygon with dot(n, p) <= e.
std::vector<Vec3> clipPolygon(const std::vector<Vec3>& poly, const Vec3& n, double e) {
    std::vector<Vec3> out;
    const std::size_t m = poly.size();
    for (std::size_t k = 0; k < m; ++k) {
        const Vec3& a = poly[k];
        const Vec3& b = poly[(k + 1) % m];
        double sa = glm::dot(n, a) - e, sb = glm::dot(n, b) - e;
        if (sa <= 0) out.push_back(a);
        if ((sa < 0 && sb > 0) || (sa > 0 && sb < 0)) out.push_back(a + (sa / (sa - sb)) * (b - a));
    }
    return out;
}

double pointSegmentDistance(const Vec3& p, const Vec3& a, const Vec3& b) {
    Vec3 d = b - a;
    double len2 = lengthSquared<3>(d);
    double t = len2 > 0 ? std::clamp(glm::dot(p - a, d) / len2, 0.0, 1.0) : 0.0;
    return std::sqrt(lengthSquared<3>(p - (a + t * d)));
}

// Distance from the origin to a convex polygon lying in the plane x[axis] = const.
double originPolygonDistance(const std::vector<Vec3>& poly, int axis) {
    const int b = (axis + 1) % 3, c = (axis + 2) % 3;
    const std::size_t m = poly.size();
    if (m >= 3) {
        // The origin's projection (0, 0) in (b, c): inside when on one side of every edge.
        bool pos = true, neg = true;
        for (std::size_t k = 0; k < m; ++k) {
            const Vec3& p = poly[k];
            const Vec3& q = poly[(k + 1) % m];
            double cr = (q[b] - p[b]) * (0 - p[c]) - (q[c] - p[c]) * (0 - p[b]);
            pos = pos && cr >= 0;
            neg = neg && cr <= 0;
        }
        if (pos || neg) return std::abs(poly[0][axis]);
    }
    double best = kInf;
    for (std::size_t k = 0; k < m; ++k) best = std::min(best, pointSegmentDistance(Vec3(0.0), poly[k], poly[(k + 1) % m]));
    return best;
}

bool sphereTouchesView(const Obj& o, const Frustum& fr, double eps) {
    const Vec3& q = o.center;
    // Projection onto the frustum cone K: q itself when inside, else the nearest of the candidates that
    // lie in K (the apex, the projections onto the edge rays and onto the faces).
    Vec3 best{0.0};
    double bestD2 = kInf;
    auto consider = [&](const Vec3& p) {
        double d2 = lengthSquared<3>(q - p);
        if (d2 < bestD2) {
            bestD2 = d2;
            best = p;
        }
    };
    bool inside = true;
    for (const Vec3& n : fr.n) inside = inside && glm::dot(n, q) <= 0;
    if (inside) {
        consider(q);
    } else {
        consider(Vec3(0.0));
        for (const Vec3& e : fr.edge) {
            double t = glm::dot(q, e);
            if (t > 0) consider(t * e);
        }
        for (int i = 0; i < 4; ++i) {
            Vec3 p = q - glm::dot(q, fr.n[i]) * fr.n[i];
            bool ok = true;
            for (int j = 0; j < 4; ++j) ok = ok && (j == i || glm::dot(fr.n[j], p) <= eps);
            if (ok) consider(p);
        }
    }
    // The projection onto K cut by the far ball is the projection onto K scaled back to the far sphere.
    double len = std::sqrt(lengthSquared<3>(best));
    if (len > fr.far) best *= fr.far / len;
    double r = o.radius + eps;
    return lengthSquared<3>(q - best) <= r * r;
}

// Distance from the origin to a convex polygon in any plane.
double originPolygonDistanceAny(const std::vector<Vec3>& poly) {
    const std::size_t m = poly.size();
    if (m >= 3) {
        Vec3 n(0.0);
        for (std::size_t k = 1; k + 1 < m; ++k) n += glm::cross(poly[k] - poly[0], poly[k + 1] - poly[0]);
        const double n2 = lengthSquared<3>(n);
        if (n2 > 0) {
            const Vec3 nn = n / std::sqrt(n2);
            const Vec3 p = glm::dot(poly[0], nn) * nn; // the origin's projection onto the plane
            bool inside = true;
            for (std::size_t k = 0; k < m && inside; ++k) inside = glm::dot(glm::cross(poly[(k + 1) % m] - poly[k], p - poly[k]), nn) >= 0;
            if (inside) return std::abs(glm::dot(poly[0], nn));
        }
    }
    double best = kInf;
    for (std::size_t k = 0; k < m; ++k) best = std::min(best, pointSegmentDistance(Vec3(0.0), poly[k], poly[(k + 1) % m]));
    return best;
}

bool polyTouchesView(const Obj& o, const Frustum& fr, double eps) {
    if (containsPoint(o, Vec3(0.0), eps)) return true; // holds the apex
    double best = kInf;
    for (const auto& t : o.tris) {
        // The triangle pushed out by eps along its plane's normal, clipped by the side planes.
        const Vec3 &a = o.verts[t[0]], &b = o.verts[t[1]], &c = o.verts[t[2]];
        const Vec3 n = normalized(glm::cross(b - a, c - a));
        const Vec3 mid = (a + b + c) / 3.0;
        std::vector<Vec3> poly;
        for (const Vec3* v : {&a, &b, &c}) poly.push_back(*v + eps * n + eps * normalized(*v - mid));
        for (const Vec3& nn : fr.n) {
            poly = clipPolygon(poly, nn, eps);
            if (poly.empty()) break;
        }
        if (poly.empty()) continue;
        if (!std::isfinite(fr.far)) return true;
        best = std::min(best, originPolygonDistanceAny(poly));
    }
    return best < kInf && best <= fr.far + eps;
}

bool boxTouchesView(const Obj& o, const Frustum& fr, double eps) {
    const Vec3 lo = o.lo - eps, hi = o.hi + eps;
    if (lo.x <= 0 && hi.x >= 0 && lo.y <= 0 && hi.y >= 0 && lo.z <= 0 && hi.z >= 0) return true; // holds the apex
    double best = kInf;
    for (int a = 0; a < 3; ++a) {
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        for (int side = 0; side < 2; ++side) {
            std::vector<Vec3> poly(4);
            for (int k = 0; k < 4; ++k) {
                poly[std::size_t(k)][a] = side ? hi[a] : lo[a];
                poly[std::size_t(k)][b] = (k == 1 || k == 2) ? hi[b] : lo[b];
                poly[std::size_t(k)][c] = (k >= 2) ? hi[c] : lo[c];
            }
            for (const Vec3& n : fr.n) {
                poly = clipPolygon(poly, n, eps);
                if (poly.empty()) break;
            }
            if (poly.empty()) continue;
            if (!std::isfinite(fr.far)) return true;
            best = std::min(best, originPolygonDistance(poly, a));
        }
    }
    return best < kInf && best <= fr.far + eps; // (with no face left best stays infinite)
}

} // namespace rgvc::reference::detail
