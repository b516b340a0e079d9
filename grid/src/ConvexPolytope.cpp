// Convex polytopes: the 3D hull algorithm, oriented boxes, erosion and validation (ConvexPolytope.hpp).
//
// Why a hand-written hull. The core (grid/, dynamics/) depends on glm alone (it is what a game embeds
// through add_subdirectory), Debian's hull library (qhull) would add a C library with global state and
// its own error channel to it, and scenes give hulls of tens to hundreds of points, for which an
// incremental hull in O(points x facets) is fast enough (2,000 points on a sphere: ~0.1 s; 10,000: ~3 s).
//
// The algorithm (the incremental hull of Clarkson and Shor, without conflict lists):
//   1. an initial tetrahedron of far-apart points (the degeneracy checks: all points on a line or a plane
//      within 1e-9 of their extent is an error, as scene-format.md asks for 4 points not in one plane);
//   2. every other point, in a fixed pseudo-random order (expected O(n log n) facets touched), removes the
//      facets it sees by more than eps = 1e-13 of the extent and closes the hole with a fan of triangles
//      from its horizon; points seeing no facet are inside (or within eps of the boundary) and are dropped;
//   3. the result is checked: a closed 2-manifold (every directed edge has its twin) with Euler
//      characteristic 2; if it is not (near-duplicate points, points within rounding of a facet: the
//      cut points of an erosion), 2-3 run again with eps 1e-11 and 1e-9 of the extent, and input that
//      still fails gets a clear error.
// Coordinates are shifted to the bounding box's centre first, so that rounding is relative to the
// hull's extent, not to its distance from the origin.
//
// The planes' offsets are the support values max_p n.p over *every* input point, so every input point lies
// inside every plane (up to the rounding of one dot product): the H-representation contains the exact
// hull. `tolerance` records the largest amount a dropped point stuck out of the vertices' facets (0 in
// exact arithmetic), times a safety factor for sharp vertices, plus rounding.
#include "rgvc/grid/ConvexPolytope.hpp"

#include "rgvc/grid/Error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <unordered_map>

namespace rgvc {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct Face {
    std::uint32_t v[3];
    Vec3 n; // unit
    double off;
    bool alive = true;
};

std::uint64_t edgeKey(std::uint32_t a, std::uint32_t b) { return (std::uint64_t(a) << 32) | b; }

/// Union-find over facets (coplanar neighbours share one plane).
std::uint32_t findRoot(std::vector<std::uint32_t>& parent, std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}

std::string fmt(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

/// Fills edges, planes (coplanar neighbours merged), bounds from vertices + triangles; offsets are the
/// support values over `support` points (world coordinates).
void finish(ConvexPolytope& p, std::span<const Vec3> support, const std::vector<Vec3>& normals) {
    std::unordered_map<std::uint64_t, std::uint32_t> owner; // directed edge -> triangle
    owner.reserve(p.triangles.size() * 3);
    for (std::uint32_t t = 0; t < p.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) owner[edgeKey(p.triangles[t][k], p.triangles[t][(k + 1) % 3])] = t;
    std::vector<std::uint32_t> parent(p.triangles.size());
    std::iota(parent.begin(), parent.end(), 0u);
    p.edges.clear();
    for (std::uint32_t t = 0; t < p.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = p.triangles[t][k], b = p.triangles[t][(k + 1) % 3];
            if (a < b) p.edges.push_back({a, b});
            auto it = owner.find(edgeKey(b, a));
            if (it != owner.end() && glm::dot(normals[t], normals[it->second]) > 1 - 1e-12) {
                const std::uint32_t ra = findRoot(parent, t), rb = findRoot(parent, it->second);
                if (ra != rb) parent[ra] = rb;
            }
        }
    p.planes.clear();
    std::vector<std::int64_t> planeOf(p.triangles.size(), -1);
    for (std::uint32_t t = 0; t < p.triangles.size(); ++t) {
        const std::uint32_t r = findRoot(parent, t);
        if (planeOf[r] < 0) {
            planeOf[r] = std::int64_t(p.planes.size());
            p.planes.push_back({normals[r], -kInf});
        }
    }
    for (HalfSpace& h : p.planes)
        for (const Vec3& q : support) h.offset = std::max(h.offset, glm::dot(h.normal, q));
    p.boundsMin = p.boundsMax = support.front();
    for (const Vec3& q : support) {
        p.boundsMin = glm::min(p.boundsMin, q);
        p.boundsMax = glm::max(p.boundsMax, q);
    }
}

} // namespace

ConvexPolytope makeConvexHull(std::span<const Vec3> points, const std::string& field) {
    const std::size_t n = points.size();
    if (n < 4) throw InvalidInput(field, "a hull needs at least 4 points, got " + std::to_string(n));
    if (n > kMaxHullPoints)
        throw InvalidInput(field, "at most " + std::to_string(kMaxHullPoints) + " points, got " + std::to_string(n));
    Vec3 lo(kInf), hi(-kInf);
    for (std::size_t i = 0; i < n; ++i) {
        if (!allFinite<3>(points[i])) throw InvalidInput(field + "[" + std::to_string(i) + "]", "must be finite");
        lo = glm::min(lo, points[i]);
        hi = glm::max(hi, points[i]);
    }
    const Vec3 centre = 0.5 * lo + 0.5 * hi;
    const double extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
    if (!(extent > 0)) throw InvalidInput(field, "all points coincide");
    // Cross products of shifted coordinates are O(extent^2): keep them finite.
    if (!(extent < 1e150)) throw InvalidInput(field, "the points' extent " + fmt(extent) + " overflows the hull's arithmetic");
    std::vector<Vec3> q(n);
    for (std::size_t i = 0; i < n; ++i) q[i] = points[i] - centre;
    const double flat = 1e-9 * extent;

    // 1. The initial tetrahedron: the farthest pair among the axis extremes, the point farthest from their
    //    line, the point farthest from their plane.
    std::uint32_t ext[6] = {0, 0, 0, 0, 0, 0};
    for (std::uint32_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) {
            if (q[i][a] < q[ext[2 * a]][a]) ext[2 * a] = i;
            if (q[i][a] > q[ext[2 * a + 1]][a]) ext[2 * a + 1] = i;
        }
    std::uint32_t i0 = 0, i1 = 0;
    double best = -1;
    for (int a = 0; a < 6; ++a)
        for (int b = a + 1; b < 6; ++b) {
            const double d2 = lengthSquared<3>(q[ext[a]] - q[ext[b]]);
            if (d2 > best) best = d2, i0 = ext[a], i1 = ext[b];
        }
    const Vec3 axis = safeNormalize<3>(q[i1] - q[i0]);
    std::uint32_t i2 = i0;
    best = -1;
    for (std::uint32_t i = 0; i < n; ++i) {
        const double d = std::sqrt(lengthSquared<3>(glm::cross(q[i] - q[i0], axis)));
        if (d > best) best = d, i2 = i;
    }
    if (!(best > flat)) throw InvalidInput(field, "all points lie on one line (within 1e-9 of their extent)");
    const Vec3 normal = safeNormalize<3>(glm::cross(q[i1] - q[i0], q[i2] - q[i0]));
    std::uint32_t i3 = i0;
    best = -1;
    for (std::uint32_t i = 0; i < n; ++i) {
        const double d = std::abs(glm::dot(q[i] - q[i0], normal));
        if (d > best) best = d, i3 = i;
    }
    if (!(best > flat)) throw InvalidInput(field, "all points lie in one plane (within 1e-9 of their extent): the hull has no volume");

    // 2.-3. as one attempt with a given epsilon; nearly degenerate input (near-duplicate points, points
    // almost on a facet) that breaks the manifold check is retried with a 100x and a 10,000x larger one
    // (the support offsets and the tolerance below stay exact whatever epsilon dropped).
    ConvexPolytope out;
    std::vector<Vec3> normals;
    auto attempt = [&](double eps) -> bool {
        std::vector<Face> faces;
        std::unordered_map<std::uint64_t, std::uint32_t> edgeFace; // directed edge -> alive face holding it
        bool broken = false;
        const Vec3 inner = 0.25 * (q[i0] + q[i1] + q[i2] + q[i3]); // stays inside every later hull
        auto addFace = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
            Face f;
            Vec3 nn = glm::cross(q[b] - q[a], q[c] - q[a]);
            if (glm::dot(nn, inner - q[a]) > 0) {
                std::swap(b, c);
                nn = -nn;
            }
            f.v[0] = a, f.v[1] = b, f.v[2] = c;
            const double len = std::sqrt(lengthSquared<3>(nn));
            f.n = len > 0 ? nn / len : Vec3(0.0);
            if (!(len > 0)) broken = true;
            f.off = glm::dot(f.n, q[a]);
            const std::uint32_t id = std::uint32_t(faces.size());
            for (int k = 0; k < 3; ++k)
                if (!edgeFace.emplace(edgeKey(f.v[k], f.v[(k + 1) % 3]), id).second) broken = true;
            faces.push_back(f);
        };
        addFace(i0, i1, i2);
        addFace(i0, i1, i3);
        addFace(i0, i2, i3);
        addFace(i1, i2, i3);

        // 2. The other points in a fixed pseudo-random order.
        std::vector<std::uint32_t> order;
        order.reserve(n);
        for (std::uint32_t i = 0; i < n; ++i)
            if (i != i0 && i != i1 && i != i2 && i != i3) order.push_back(i);
        std::uint64_t state = 0x9E3779B97F4A7C15ULL;
        for (std::size_t k = order.size(); k > 1; --k) {
            state = state * 6364136223846793005ULL + 1442695040888963407ULL;
            std::swap(order[k - 1], order[std::size_t((state >> 33) % k)]);
        }
        std::vector<std::uint32_t> alive = {0, 1, 2, 3}, visible, next;
        std::vector<std::array<std::uint32_t, 2>> horizon;
        std::vector<std::uint64_t> seenStamp(4, 0);
        std::uint64_t stamp = 0;
        for (std::uint32_t pi : order) {
            const Vec3& p = q[pi];
            visible.clear();
            ++stamp;
            for (std::uint32_t f : alive)
                if (glm::dot(faces[f].n, p) - faces[f].off > eps) {
                    visible.push_back(f);
                    seenStamp[f] = stamp;
                }
            if (visible.empty()) continue;
            horizon.clear();
            for (std::uint32_t f : visible)
                for (int k = 0; k < 3; ++k) {
                    const std::uint32_t a = faces[f].v[k], b = faces[f].v[(k + 1) % 3];
                    auto it = edgeFace.find(edgeKey(b, a));
                    if (it == edgeFace.end()) {
                        broken = true;
                        continue;
                    }
                    if (seenStamp[it->second] != stamp) horizon.push_back({a, b});
                }
            for (std::uint32_t f : visible) {
                faces[f].alive = false;
                for (int k = 0; k < 3; ++k) edgeFace.erase(edgeKey(faces[f].v[k], faces[f].v[(k + 1) % 3]));
            }
            for (const auto& e : horizon) addFace(e[0], e[1], pi);
            seenStamp.resize(faces.size(), 0);
            next.clear();
            for (std::uint32_t f : alive)
                if (faces[f].alive) next.push_back(f);
            for (std::uint32_t f = std::uint32_t(faces.size() - horizon.size()); f < faces.size(); ++f) next.push_back(f);
            alive.swap(next);
            if (broken) break;
        }

        // 3. Closed 2-manifold with V - E + F = 2.
        std::vector<std::int64_t> remap(n, -1);
        for (std::uint32_t f : alive) {
            std::array<std::uint32_t, 3> t{};
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t v = faces[f].v[k];
                if (remap[v] < 0) {
                    remap[v] = std::int64_t(out.vertices.size());
                    out.vertices.push_back(points[v]);
                }
                t[std::size_t(k)] = std::uint32_t(remap[v]);
                if (edgeFace.find(edgeKey(faces[f].v[(k + 1) % 3], v)) == edgeFace.end()) broken = true;
            }
            out.triangles.push_back(t);
            normals.push_back(faces[f].n);
        }
        const std::size_t V = out.vertices.size(), F = out.triangles.size();
        return !(broken || F < 4 || F % 2 != 0 || V + F - 3 * F / 2 != 2);
    };
    bool ok = false;
    for (double scale : {1e-13, 1e-11, 1e-9}) {
        out = ConvexPolytope{};
        normals.clear();
        if ((ok = attempt(scale * extent))) break;
    }
    if (!ok)
        throw InvalidInput(field, "the hull of these points could not be computed robustly (nearly degenerate points); "
                                  "perturb or thin them");
    const std::size_t F = out.triangles.size();

    // Support offsets over every input point; the tolerance from how far any point stuck out of the
    // vertices' own facets (a dropped point within eps of the boundary).
    double excess = 0;
    {
        std::vector<double> vOff(F, -kInf);
        for (std::size_t t = 0; t < F; ++t)
            for (std::uint32_t v : out.triangles[t]) vOff[t] = std::max(vOff[t], glm::dot(normals[t], out.vertices[v] - centre));
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t t = 0; t < F; ++t) excess = std::max(excess, glm::dot(normals[t], q[i]) - vOff[t]);
    }
    finish(out, points, normals);
    const double magnitude = std::max({std::abs(lo.x), std::abs(lo.y), std::abs(lo.z), std::abs(hi.x), std::abs(hi.y), std::abs(hi.z)});
    out.tolerance = 8 * excess + 1e-15 * (magnitude + extent);
    return out;
}

std::array<Vec3, 3> rotationColumns(const std::array<double, 4>& r) {
    const double x = r[0], y = r[1], z = r[2], w = r[3];
    return {Vec3{1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w)},
            Vec3{2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w)},
            Vec3{2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y)}};
}

ConvexPolytope makeOrientedBox(const Vec3& center, const Vec3& half, const std::array<double, 4>& rotation,
                               const std::string& field) {
    if (!allFinite<3>(center)) throw InvalidInput(field + ".center", "must be finite");
    for (int a = 0; a < 3; ++a)
        if (!std::isfinite(half[a]) || !(half[a] > 0))
            throw InvalidInput(field + ".half_extents", "must be finite and > 0 on every axis, got " + fmt(half[a]));
    double q2 = 0;
    for (double c : rotation) {
        if (!std::isfinite(c)) throw InvalidInput(field + ".rotation", "must be finite");
        q2 += c * c;
    }
    const double len = std::sqrt(q2);
    if (!(std::abs(len - 1) <= kQuaternionTolerance))
        throw InvalidInput(field + ".rotation", "must be a unit quaternion [x, y, z, w] (length within " + fmt(kQuaternionTolerance) +
                                                    " of 1), got length " + fmt(len));
    const std::array<double, 4> unit{rotation[0] / len, rotation[1] / len, rotation[2] / len, rotation[3] / len};
    std::array<Vec3, 3> axes = rotationColumns(unit);
    for (Vec3& a : axes) a = safeNormalize<3>(a); // unit to the last bit, for the planes
    ConvexPolytope p;
    for (int k = 0; k < 8; ++k) {
        Vec3 c = center;
        for (int a = 0; a < 3; ++a) c += ((k >> a) & 1 ? half[a] : -half[a]) * axes[std::size_t(a)];
        if (!allFinite<3>(c)) throw InvalidInput(field + ".half_extents", "the corners overflow double precision");
        p.vertices.push_back(c);
    }
    // Faces: corners with bit a = side; two triangles each, wound outward.
    std::vector<Vec3> normals;
    for (int a = 0; a < 3; ++a)
        for (int side = 0; side < 2; ++side) {
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            auto corner = [&](int sb, int sc) { return std::uint32_t((side << a) | (sb << b) | (sc << c)); };
            std::uint32_t quad[4] = {corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)};
            const Vec3 n = side ? axes[std::size_t(a)] : -axes[std::size_t(a)];
            // axes are right-handed (b x c = a): quad order is counter-clockwise about +a.
            if (!side) std::swap(quad[1], quad[3]);
            p.triangles.push_back({quad[0], quad[1], quad[2]});
            p.triangles.push_back({quad[0], quad[2], quad[3]});
            normals.push_back(n);
            normals.push_back(n);
        }
    finish(p, p.vertices, normals);
    const double magnitude = std::max({std::abs(p.boundsMin.x), std::abs(p.boundsMin.y), std::abs(p.boundsMin.z),
                                       std::abs(p.boundsMax.x), std::abs(p.boundsMax.y), std::abs(p.boundsMax.z)});
    p.tolerance = 1e-15 * magnitude;
    return p;
}

void validatePolytope(const ConvexPolytope& p, const std::string& field) {
    if (p.vertices.size() < 4) throw InvalidInput(field + ".points", "a polytope needs at least 4 vertices");
    if (p.planes.size() < 4) throw InvalidInput(field + ".planes", "a polytope needs at least 4 planes");
    if (p.triangles.size() < 4) throw InvalidInput(field + ".triangles", "a polytope needs at least 4 triangles");
    if (!std::isfinite(p.tolerance) || !(p.tolerance >= 0)) throw InvalidInput(field + ".tolerance", "must be finite and >= 0");
    double magnitude = 0;
    for (const Vec3& v : p.vertices) {
        if (!allFinite<3>(v)) throw InvalidInput(field + ".points", "must be finite");
        magnitude = std::max({magnitude, std::abs(v.x), std::abs(v.y), std::abs(v.z)});
    }
    if (!allFinite<3>(p.boundsMin) || !allFinite<3>(p.boundsMax)) throw InvalidInput(field + ".bounds", "must be finite");
    const double extent = std::max({p.boundsMax.x - p.boundsMin.x, p.boundsMax.y - p.boundsMin.y, p.boundsMax.z - p.boundsMin.z});
    if (!(extent > 0) || !(extent < 1e150)) throw InvalidInput(field + ".bounds", "must have a finite positive extent");
    const double tol = p.tolerance + 1e-12 * (magnitude + extent);
    for (const Vec3& v : p.vertices)
        for (int a = 0; a < 3; ++a)
            if (v[a] < p.boundsMin[a] - tol || v[a] > p.boundsMax[a] + tol)
                throw InvalidInput(field + ".bounds", "must contain every vertex");
    for (const HalfSpace& h : p.planes) {
        if (!allFinite<3>(h.normal) || !std::isfinite(h.offset)) throw InvalidInput(field + ".planes", "must be finite");
        if (!(std::abs(lengthSquared<3>(h.normal) - 1) <= 1e-9)) throw InvalidInput(field + ".planes", "normals must be unit vectors");
        double support = -kInf;
        for (const Vec3& v : p.vertices) {
            const double s = glm::dot(h.normal, v);
            if (s > h.offset + tol) throw InvalidInput(field + ".planes", "every vertex must lie inside every plane");
            support = std::max(support, s);
        }
        // Each plane must touch the vertices (a facet), not float away from them.
        if (support < h.offset - tol) throw InvalidInput(field + ".planes", "every plane must touch the vertices");
    }
    const std::uint32_t nv = std::uint32_t(p.vertices.size());
    for (const auto& e : p.edges)
        if (e[0] >= nv || e[1] >= nv) throw InvalidInput(field + ".edges", "vertex index out of range");
    for (const auto& t : p.triangles)
        if (t[0] >= nv || t[1] >= nv || t[2] >= nv) throw InvalidInput(field + ".triangles", "vertex index out of range");
    // Thickness: the width along some plane normal must be positive well beyond the tolerance.
    double thinnest = kInf;
    for (const HalfSpace& h : p.planes) {
        double lo = kInf;
        for (const Vec3& v : p.vertices) lo = std::min(lo, glm::dot(h.normal, v));
        thinnest = std::min(thinnest, h.offset - lo);
    }
    if (!(thinnest > 1e-9 * extent) || !(thinnest > 2 * tol)) throw InvalidInput(field + ".points", "the polytope is flat (no volume)");
}

ConvexPolytope translatedPolytope(const ConvexPolytope& p, const Vec3& t) {
    ConvexPolytope r = p;
    for (Vec3& v : r.vertices) v += t;
    for (HalfSpace& h : r.planes) h.offset += glm::dot(h.normal, t);
    r.boundsMin += t;
    r.boundsMax += t;
    return r;
}

ConvexPolytope scaledPolytope(const ConvexPolytope& p, const Vec3& origin, double scale) {
    ConvexPolytope r = p;
    for (Vec3& v : r.vertices) v = (v - origin) * scale;
    for (HalfSpace& h : r.planes) h.offset = (h.offset - glm::dot(h.normal, origin)) * scale;
    r.boundsMin = (p.boundsMin - origin) * scale;
    r.boundsMax = (p.boundsMax - origin) * scale;
    r.tolerance = p.tolerance * scale;
    return r;
}

bool erodePolytope(const ConvexPolytope& p, double d, ConvexPolytope& out) {
    if (!(d > 0)) {
        out = p;
        return true;
    }
    // The polytope as face polygons (its triangles), clipped by every plane moved in by d; each clip adds
    // the cut as a new face, ordered by angle around its centroid (a cut of a convex polytope is convex).
    std::vector<std::vector<Vec3>> faces, next;
    faces.reserve(p.triangles.size());
    for (const auto& t : p.triangles) faces.push_back({p.vertices[t[0]], p.vertices[t[1]], p.vertices[t[2]]});
    std::vector<Vec3> cut, poly;
    for (const HalfSpace& h : p.planes) {
        const double c = h.offset - d;
        next.clear();
        cut.clear();
        for (const auto& f : faces) {
            poly.clear();
            for (std::size_t k = 0, m = f.size(); k < m; ++k) {
                const Vec3& a = f[k];
                const Vec3& b = f[(k + 1) % m];
                const double sa = glm::dot(h.normal, a) - c, sb = glm::dot(h.normal, b) - c;
                if (sa <= 0) poly.push_back(a);
                if ((sa < 0 && sb > 0) || (sa > 0 && sb < 0)) {
                    const Vec3 x = a + (b - a) * (sa / (sa - sb));
                    poly.push_back(x);
                    cut.push_back(x);
                } else if (sa == 0) {
                    cut.push_back(a);
                }
            }
            if (poly.size() >= 3) next.push_back(poly);
        }
        if (cut.size() >= 3) {
            Vec3 mid(0.0);
            for (const Vec3& x : cut) mid += x;
            mid /= double(cut.size());
            const Vec3 e1 = safeNormalize<3>(glm::cross(h.normal, std::abs(h.normal.x) < 0.6 ? Vec3(1, 0, 0) : Vec3(0, 1, 0)));
            const Vec3 e2 = glm::cross(h.normal, e1);
            std::sort(cut.begin(), cut.end(), [&](const Vec3& a, const Vec3& b) {
                return std::atan2(glm::dot(a - mid, e2), glm::dot(a - mid, e1)) < std::atan2(glm::dot(b - mid, e2), glm::dot(b - mid, e1));
            });
            next.push_back(cut);
        }
        faces.swap(next);
        if (faces.size() < 4) return false;
    }
    std::vector<Vec3> pts;
    for (const auto& f : faces) pts.insert(pts.end(), f.begin(), f.end());
    std::sort(pts.begin(), pts.end(), [](const Vec3& a, const Vec3& b) {
        return a.x < b.x || (a.x == b.x && (a.y < b.y || (a.y == b.y && a.z < b.z)));
    });
    pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
    if (pts.size() < 4 || pts.size() > kMaxHullPoints) return false;
    try {
        ConvexPolytope r = makeConvexHull(pts, "eroded");
        // The eroded planes are the true ones; the hull of the clipped vertices equals their intersection
        // up to rounding, which its own tolerance and the original's cover.
        r.tolerance += p.tolerance;
        out = std::move(r);
        return true;
    } catch (const InvalidInput&) {
        return false; // a sliver: flat within 1e-9 of its extent
    }
}

} // namespace rgvc
