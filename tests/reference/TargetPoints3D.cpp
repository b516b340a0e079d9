// Target points of the 3D reference's shapes; see TargetPoints3D.hpp and ExactVisibility3D.hpp (step 3).
#include "TargetPoints3D.hpp"

#include <algorithm>

namespace rgvc::reference::detail {

namespace {

// Target points are camera-relative. Every parameter is computed as (integer / integer) first (frac), so
// that the sample sets for divisions d and 2d are nested bit for bit.

// Points on the circle centre + rho * (cos a * e1 + sin a * e2), count of them.
void addCircle(std::vector<Vec3>& out, const Vec3& centre, double rho, const Vec3& e1, const Vec3& e2, int count) {
    for (int j = 0; j < count; ++j) {
        double a = kTwoPi * frac(j, count);
        out.push_back(centre + rho * (std::cos(a) * e1 + std::sin(a) * e2));
    }
}

// Points on segment [a, b] with parameter in [0, 1] where |p| = far.
void addSegmentFarPoints(std::vector<Vec3>& out, const Vec3& a, const Vec3& b, double far) {
    if (!std::isfinite(far)) return;
    Vec3 d = b - a;
    double qa = lengthSquared<3>(d), qb = glm::dot(a, d), qc = lengthSquared<3>(a) - far * far;
    if (!(qa > 0)) return;
    double disc = qb * qb - qa * qc;
    if (disc < 0) return;
    double s = std::sqrt(disc);
    for (double t : {(-qb - s) / qa, (-qb + s) / qa})
        if (t >= -kParamSlack && t <= 1 + kParamSlack) out.push_back(a + std::clamp(t, 0.0, 1.0) * d);
}

// The point of segment [a, b] on the plane n.p = 0, if it crosses it.
void addSegmentPlanePoint(std::vector<Vec3>& out, const Vec3& a, const Vec3& b, const Vec3& n) {
    double sa = glm::dot(n, a), sb = glm::dot(n, b);
    if ((sa <= 0 && sb >= 0) || (sa >= 0 && sb <= 0)) {
        if (sa == sb) return; // in the plane: its endpoints are targets already
        out.push_back(a + (sa / (sa - sb)) * (b - a));
    }
}

// Where side plane i cuts the convex face q[0..m-1]: the points where its sides cross the plane, then per
// pair of them d+1 points along the chord between them, the chord's crossings with the other side planes
// and with the far sphere. Shared by boxes (faces of 4) and polytopes (triangles).
void addPlaneCutTargets(std::vector<Vec3>& out, const Vec3* q, int m, int i, const Frustum& fr, int d) {
    std::vector<Vec3> cut;
    for (int k = 0; k < m; ++k) addSegmentPlanePoint(cut, q[k], q[(k + 1) % m], fr.n[i]);
    for (std::size_t p = 0; p < cut.size(); ++p)
        for (std::size_t r = p + 1; r < cut.size(); ++r) {
            for (int k = 0; k <= d; ++k) out.push_back(cut[p] + frac(k, d) * (cut[r] - cut[p]));
            for (int j = 0; j < 4; ++j)
                if (j != i) addSegmentPlanePoint(out, cut[p], cut[r], fr.n[j]);
            addSegmentFarPoints(out, cut[p], cut[r], fr.far);
        }
}

// Basis of the plane perpendicular to unit w, derived from the camera frame so that mirrored or
// permuted scenes get mirrored or permuted samples.
void basisAround(const Vec3& w, const Frustum& fr, Vec3& e1, Vec3& e2) {
    Vec3 ref = std::abs(glm::dot(w, fr.v)) < 0.9 ? fr.v : fr.r;
    e1 = normalized(glm::cross(w, ref));
    e2 = glm::cross(w, e1);
}

} // namespace

void sphereTargets(const Obj& o, const Frustum& fr, int d, std::vector<Vec3>& out) {
    const Vec3& s = o.center;
    const double R = o.radius, L = std::sqrt(lengthSquared<3>(s));
    if (!(L > R)) return; // holds the camera: handled before
    const Vec3 w = -s / L; // centre -> camera
    Vec3 e1, e2;
    basisAround(w, fr, e1, e2);
    out.push_back(s + R * w); // the nearest point
    out.push_back(s);
    // Silhouette circle, then rings on the cap facing the camera.
    const double cosMax = R / L, sinMax = std::sqrt(std::max(0.0, 1 - cosMax * cosMax));
    addCircle(out, s + R * cosMax * w, R * sinMax, e1, e2, 8 * d);
    const double thetaMax = std::atan2(sinMax, cosMax);
    for (int k = 1; k < d; ++k) {
        double th = thetaMax * frac(k, d);
        addCircle(out, s + R * std::cos(th) * w, R * std::sin(th), e1, e2, 4 * d);
    }
    // Cuts by the side planes.
    for (int i = 0; i < 4; ++i) {
        const Vec3& n = fr.n[i];
        double dist = glm::dot(s, n);
        if (std::abs(dist) > R) continue;
        Vec3 cc = s - dist * n;
        double rho = std::sqrt(std::max(0.0, R * R - dist * dist));
        Vec3 a = fr.inPlane(i);
        a = normalized(a - glm::dot(a, n) * n);
        Vec3 b = glm::cross(n, a);
        addCircle(out, cc, rho, a, b, 4 * d);
        // Exact points where the cut circle meets the other side planes.
        for (int j = 0; j < 4; ++j) {
            if (j == i) continue;
            double A = rho * glm::dot(fr.n[j], a), B = rho * glm::dot(fr.n[j], b), C = glm::dot(fr.n[j], cc);
            double M = std::sqrt(A * A + B * B);
            if (!(M > 0) || std::abs(C) > M) continue;
            double base = std::atan2(B, A), delta = std::acos(std::clamp(-C / M, -1.0, 1.0));
            for (double ang : {base - delta, base + delta}) out.push_back(cc + rho * (std::cos(ang) * a + std::sin(ang) * b));
        }
        // ... and the far circle (centre: the camera, in this plane).
        if (std::isfinite(fr.far)) {
            double D = std::sqrt(lengthSquared<3>(cc));
            if (D > 0) {
                double h = (fr.far * fr.far - rho * rho + D * D) / (2 * D), k2 = fr.far * fr.far - h * h;
                if (k2 >= -1e-9 * fr.far * fr.far) {
                    Vec3 dir = cc / D, side = glm::cross(n, dir);
                    double k = std::sqrt(std::max(0.0, k2));
                    out.push_back(h * dir + k * side);
                    out.push_back(h * dir - k * side);
                }
            }
        }
    }
    // Cut by the far sphere.
    if (std::isfinite(fr.far)) {
        const double F = fr.far;
        double h = (F * F - R * R + L * L) / (2 * L), k2 = F * F - h * h;
        if (k2 >= 0) addCircle(out, (-h) * w, std::sqrt(k2), e1, e2, 4 * d);
    }
}

void boxTargets(const Obj& o, const Frustum& fr, int d, std::vector<Vec3>& out) {
    const Vec3 lo = o.lo, hi = o.hi;
    auto corner = [&](int bits) { return Vec3{bits & 1 ? hi.x : lo.x, bits & 2 ? hi.y : lo.y, bits & 4 ? hi.z : lo.z}; };
    out.push_back(glm::clamp(Vec3(0.0), lo, hi)); // the nearest point
    out.push_back(0.5 * (lo + hi));
    for (int c = 0; c < 8; ++c) out.push_back(corner(c));
    // Edges: along axis a, the other two axes at either bound.
    struct Seg {
        Vec3 a, b;
    };
    std::vector<Seg> edges;
    for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 8; ++c)
            if (!(c & (1 << a))) edges.push_back({corner(c), corner(c | (1 << a))});
    for (const Seg& e : edges)
        for (int k = 1; k < d; ++k) out.push_back(e.a + frac(k, d) * (e.b - e.a));
    // Faces facing the camera (or holding it in their plane): a grid inside.
    for (int a = 0; a < 3; ++a) {
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        for (int side = 0; side < 2; ++side) {
            double wv = side ? hi[a] : lo[a];
            if (side ? wv > 0 : wv < 0) continue; // the camera is inside the slab's far side: back face
            for (int i = 1; i < d; ++i)
                for (int j = 1; j < d; ++j) {
                    Vec3 p{0.0};
                    p[a] = wv;
                    p[b] = lo[b] + frac(i, d) * (hi[b] - lo[b]);
                    p[c] = lo[c] + frac(j, d) * (hi[c] - lo[c]);
                    out.push_back(p);
                }
        }
    }
    // Faces as quadrilaterals (4 edges each), for the plane cuts.
    for (int i = 0; i < 4; ++i) {
        for (int a = 0; a < 3; ++a) {
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            for (int side = 0; side < 2; ++side) {
                Vec3 q[4];
                for (int k = 0; k < 4; ++k) {
                    q[k][a] = side ? hi[a] : lo[a];
                    q[k][b] = (k == 1 || k == 2) ? hi[b] : lo[b];
                    q[k][c] = (k >= 2) ? hi[c] : lo[c];
                }
                addPlaneCutTargets(out, q, 4, i, fr, d);
            }
        }
    }
    // Cut by the far sphere: a circle on each face plane, kept inside the face; edges piercing it.
    if (std::isfinite(fr.far)) {
        const double F = fr.far;
        for (int a = 0; a < 3; ++a) {
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            Vec3 eb{0.0}, ec{0.0};
            eb[b] = 1;
            ec[c] = 1;
            for (int side = 0; side < 2; ++side) {
                double wv = side ? hi[a] : lo[a];
                if (std::abs(wv) > F) continue;
                Vec3 centre{0.0};
                centre[a] = wv;
                std::vector<Vec3> circle;
                addCircle(circle, centre, std::sqrt(F * F - wv * wv), eb, ec, 4 * d);
                for (const Vec3& p : circle)
                    if (p[b] >= lo[b] && p[b] <= hi[b] && p[c] >= lo[c] && p[c] <= hi[c]) out.push_back(p);
            }
        }
        for (const Seg& e : edges) addSegmentFarPoints(out, e.a, e.b, F);
    }
}

// A polytope: the centroid, the vertices, points inside every edge, a barycentric grid inside every
// triangle that faces the camera (or holds it in its plane), the cuts of every triangle by the side planes
// (points along them, and where they meet the other side planes and the far sphere), and where the far
// sphere cuts it: circles on each triangle's plane kept inside the triangle, and the edges piercing it.
void polyTargets(const Obj& o, const Frustum& fr, int d, std::vector<Vec3>& out) {
    Vec3 mid(0.0);
    for (const Vec3& v : o.verts) mid += v;
    out.push_back(mid / double(o.verts.size()));
    for (const Vec3& v : o.verts) out.push_back(v);
    for (const auto& e : o.edges)
        for (int k = 1; k < d; ++k) out.push_back(o.verts[e[0]] + frac(k, d) * (o.verts[e[1]] - o.verts[e[0]]));
    for (const auto& t : o.tris) {
        const Vec3 &a = o.verts[t[0]], &b = o.verts[t[1]], &c = o.verts[t[2]];
        const Vec3 n = glm::cross(b - a, c - a);
        if (glm::dot(n, a) > 0) continue; // the camera is behind this triangle's plane: a back face
        for (int i = 1; i < d; ++i)
            for (int j = 1; i + j < d; ++j) out.push_back(a + frac(i, d) * (b - a) + frac(j, d) * (c - a));
    }
    for (int i = 0; i < 4; ++i) {
        for (const auto& t : o.tris) {
            const Vec3 q[3] = {o.verts[t[0]], o.verts[t[1]], o.verts[t[2]]};
            addPlaneCutTargets(out, q, 3, i, fr, d);
        }
    }
    if (std::isfinite(fr.far)) {
        const double F = fr.far;
        for (const auto& t : o.tris) {
            const Vec3 &a = o.verts[t[0]], &b = o.verts[t[1]], &c = o.verts[t[2]];
            const Vec3 n = normalized(glm::cross(b - a, c - a));
            const double h = glm::dot(n, a);
            if (std::abs(h) > F) continue;
            Vec3 e1 = normalized(b - a);
            const Vec3 e2 = glm::cross(n, e1);
            std::vector<Vec3> circle;
            addCircle(circle, h * n, std::sqrt(F * F - h * h), e1, e2, 4 * d);
            for (const Vec3& p : circle) {
                // Inside the triangle (barycentric signs, with a little slack).
                const double s0 = glm::dot(glm::cross(b - a, p - a), n), s1 = glm::dot(glm::cross(c - b, p - b), n),
                             s2 = glm::dot(glm::cross(a - c, p - c), n);
                const double tol = -1e-12 * lengthSquared<3>(b - a);
                if (s0 >= tol && s1 >= tol && s2 >= tol) out.push_back(p);
            }
        }
        for (const auto& e : o.edges) addSegmentFarPoints(out, o.verts[e[0]], o.verts[e[1]], F);
    }
}

} // namespace rgvc::reference::detail
