// Convex polytopes given by half-spaces: the vertex enumeration behind makePolytopeFromPlanes
// (ConvexPolytope.hpp), issue 13's "convex hulls (given as points or planes)".
//
// Why hand-written, and why this method. The usual library answers are qhull's halfspace intersection
// (qhalf) and CGAL's halfspace_intersection_3; neither may enter the core (grid/ depends on glm alone, see
// ConvexPolytope.cpp), and both need a point strictly inside first, which is a linear program of its own.
// Scenes and games give convex volumes of tens of planes (a frustum is 6, a cascade box 6, a clipped
// brush 10-30), for which brute-force vertex enumeration is both the simplest method and fast:
//
//   1. Normalisation: (n, d) -> (n, d) / |n|, so that n . x - d is a Euclidean signed distance.
//   2. Boundedness: P = {x : n_i . x <= d_i} is bounded (when non-empty) iff no direction u != 0 has
//      n_i . u <= 0 for every i (such a u is a recession direction), i.e. iff the normals positively span
//      R^3, i.e. iff the origin lies strictly inside their convex hull. That hull is computed with
//      makeConvexHull; the origin must clear every facet by 1e-9 (normals are unit vectors), so a
//      polytope that is unbounded or only just bounded (a needle 1e9 times longer than wide) is refused.
//   3. Vertex enumeration: every vertex of a 3D polytope is the meeting point of (at least) three facet
//      planes with independent normals, and conversely a meeting point of three planes is a vertex iff
//      it satisfies every other half-space. So every triple i < j < k with |det[n_i n_j n_k]| > 1e-12 is
//      solved (Cramer's rule, n_j x n_k etc. as the inverse's columns, plus one step of iterative
//      refinement) and kept when n_m . v - d_m <= 1e-10 (|v| + |d_m|) for every m (the first failing m
//      ends the test: most triples fail at once). Points within 1e-11 of the scale of one another are
//      one vertex (several planes through a vertex: a pyramid's apex). This runs twice: once as given,
//      to find the polytope's centre c, then on the planes moved to c (d_i - n_i . c), so that rounding
//      and the merge distance are relative to the polytope's extent, not to its distance from the
//      origin. O(m^3) solves and O(m^4) dot products at worst; 256 planes at most (~0.3 s
//      for 256 tangent planes of a ball on one core).
//   4. Topology: the vertices go through makeConvexHull, so the result has exactly the representation a
//      hull of points has (vertices, edges, triangles, bounds).
//   5. Verification and the H-representation: hull(V) is contained in P (its vertices satisfy every
//      half-space, up to the rounding accounted for below). Each boundary triangle of hull(V) must have
//      its three vertices on one input plane (within the containment tolerance plus the vertex's error
//      bound). Then hull(V) is the intersection of those planes' half-spaces, a subset of P's, and so
//      contains P: hull(V) = P and no vertex was missed (an unbounded P, had step 2 let it through,
//      would fail here too). A triangle on no input plane means a vertex was lost (nearly parallel planes
//      meeting at a point: an ill-conditioned corner): a clear error rather than a polytope smaller
//      than asked for. The planes holding a triangle, each once, are the result's planes: the input's
//      own facet planes (normalised), so the H-representation is exact and redundant planes drop out.
//      (Matching triangles by their vertices rather than by their normals is what makes this robust:
//      the boundary triangulation of a facet can hold slivers whose normals are poor.)
//
// The tolerance (ConvexPolytope::tolerance) covers the rounding of this construction:
//   - each computed vertex v of the triple N x = d lies within |N^-1|_inf * |N v - d|_inf of the exact
//     triple point (x* - v = N^-1 (d - N v)); the residual is computed, so is |N^-1| (from the
//     adjugate), and the largest such bound over the vertices is added (P lies that close to hull(V));
//   - vertices kept with a small violation of some half-space make hull(V) stick out of P by at most
//     that violation along the plane's normal, and by a bounded multiple of it at sharp vertices: 8 times
//     the largest violation is added (the same safety factor as makeConvexHull's for dropped points);
//   - the rounding of the shift to c and back (a few ulps of |c| and of the offsets).
#include "rgvc/grid/ConvexPolytope.hpp"

#include "rgvc/grid/Error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace rgvc {

namespace {

constexpr double kEpsilon = std::numeric_limits<double>::epsilon();

std::string fmtNumber(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

double maxAbs(const Vec3& v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); }

/// A vertex found by enumeration (coordinates as the planes given to enumerateVertices).
struct Found {
    Vec3 v;
    double err;  ///< bound on |v - exact triple point|_inf
    double viol; ///< largest n_m . v - d_m over all m (>= 0)
};

/// Step 3 of the header comment over unit half-spaces h (scale = max |d_i|).
std::vector<Found> enumerateVertices(const std::vector<HalfSpace>& h, double scale) {
    const std::size_t m = h.size();
    std::vector<Found> found;
    for (std::size_t i = 0; i < m; ++i)
        for (std::size_t j = i + 1; j < m; ++j) {
            const Vec3 cij = glm::cross(h[i].normal, h[j].normal);
            if (lengthSquared<3>(cij) < 1e-24) continue; // parallel: no triple through both is a point
            for (std::size_t k = j + 1; k < m; ++k) {
                const Vec3& ni = h[i].normal;
                const Vec3& nj = h[j].normal;
                const Vec3& nk = h[k].normal;
                const double det = glm::dot(nk, cij);
                if (!(std::abs(det) > 1e-12)) continue;
                // N^-1 = [nj x nk, nk x ni, ni x nj] / det (columns).
                const Vec3 c0 = glm::cross(nj, nk) / det, c1 = glm::cross(nk, ni) / det, c2 = cij / det;
                const double di = h[i].offset, dj = h[j].offset, dk = h[k].offset;
                Vec3 v = di * c0 + dj * c1 + dk * c2;
                // One step of iterative refinement: v += N^-1 (d - N v).
                v += (di - glm::dot(ni, v)) * c0 + (dj - glm::dot(nj, v)) * c1 + (dk - glm::dot(nk, v)) * c2;
                if (!allFinite<3>(v)) continue;
                const double vm = maxAbs(v);
                double viol = 0;
                bool inside = true;
                for (std::size_t q = 0; q < m && inside; ++q) {
                    const double s = glm::dot(h[q].normal, v) - h[q].offset;
                    if (s > 1e-10 * (vm + std::abs(h[q].offset))) inside = false;
                    viol = std::max(viol, s);
                }
                if (!inside) continue;
                const double residual = std::max({std::abs(glm::dot(ni, v) - di), std::abs(glm::dot(nj, v) - dj),
                                                  std::abs(glm::dot(nk, v) - dk)}) +
                                        4 * kEpsilon * (vm + scale);
                double invNorm = 0; // row-sum norm of N^-1 (rows of the matrix whose columns are c0, c1, c2)
                for (int r = 0; r < 3; ++r) invNorm = std::max(invNorm, std::abs(c0[r]) + std::abs(c1[r]) + std::abs(c2[r]));
                const Found f{v, invNorm * residual, viol};
                bool merged = false;
                for (Found& g : found)
                    if (maxAbs(g.v - v) <= 1e-11 * (vm + scale)) {
                        g.err = std::max(g.err, f.err + maxAbs(g.v - v));
                        g.viol = std::max(g.viol, f.viol);
                        merged = true;
                        break;
                    }
                if (!merged) found.push_back(f);
            }
        }
    return found;
}

} // namespace

ConvexPolytope makePolytopeFromPlanes(std::span<const HalfSpace> input, const std::string& field) {
    const std::size_t m = input.size();
    if (m < 4) throw InvalidInput(field, "a bounded intersection of half-spaces needs at least 4 planes, got " + std::to_string(m));
    if (m > kMaxPolytopePlanes)
        throw InvalidInput(field, "at most " + std::to_string(kMaxPolytopePlanes) + " planes, got " + std::to_string(m));

    // 1. Unit normals.
    std::vector<HalfSpace> h(m);
    double scale = 0; // max |d_i|
    for (std::size_t i = 0; i < m; ++i) {
        const std::string fi = field + "[" + std::to_string(i) + "]";
        const Vec3& n = input[i].normal;
        if (!allFinite<3>(n)) throw InvalidInput(fi + ".normal", "must be finite");
        if (n.x == 0 && n.y == 0 && n.z == 0) throw InvalidInput(fi + ".normal", "must be non-zero");
        if (!std::isfinite(input[i].offset)) throw InvalidInput(fi + ".offset", "must be finite");
        const double big = maxAbs(n);
        const double len = big * std::sqrt(lengthSquared<3>(n / big));
        h[i].normal = safeNormalize<3>(n);
        h[i].offset = input[i].offset / len;
        if (!std::isfinite(h[i].offset) || !(std::abs(h[i].offset) < 1e150))
            throw InvalidInput(fi + ".offset", "offset / |normal| = " + fmtNumber(h[i].offset) + " is out of range");
        scale = std::max(scale, std::abs(h[i].offset));
    }

    // 2. Boundedness: the origin strictly inside the hull of the normals.
    {
        std::vector<Vec3> normals(m);
        for (std::size_t i = 0; i < m; ++i) normals[i] = h[i].normal;
        bool bounded = true;
        try {
            const ConvexPolytope cone = makeConvexHull(normals, field + " normals");
            for (const HalfSpace& f : cone.planes) bounded = bounded && f.offset > 1e-9;
        } catch (const InvalidInput&) {
            bounded = false; // the normals lie in one plane (or on a line): a prism or slab, unbounded
        }
        if (!bounded)
            throw InvalidInput(field, "the half-spaces' intersection is unbounded: some direction leaves every plane "
                                      "(the normals must surround the origin, within 1e-9)");
    }

    // 3. Vertex enumeration over triples, twice: once as given to find where the polytope is, then with
    //    the planes moved to its centre c (d_i - n_i . c), so that rounding and the merge distance are
    //    relative to the polytope's extent, not to its distance from the origin.
    std::vector<Found> found = enumerateVertices(h, scale);
    if (found.empty()) throw InvalidInput(field, "the half-spaces' intersection is empty");
    Vec3 lo = found.front().v, hi = lo;
    for (const Found& f : found) lo = glm::min(lo, f.v), hi = glm::max(hi, f.v);
    const Vec3 c = 0.5 * lo + 0.5 * hi;
    std::vector<HalfSpace> hc = h;
    double shiftedScale = 0, shiftRounding = 0;
    for (HalfSpace& g : hc) {
        const double along = glm::dot(g.normal, c);
        g.offset -= along;
        shiftedScale = std::max(shiftedScale, std::abs(g.offset));
        shiftRounding = std::max(shiftRounding, 4 * kEpsilon * (std::abs(g.offset) + std::abs(along)));
    }
    found = enumerateVertices(hc, shiftedScale);
    if (found.empty()) throw InvalidInput(field, "the half-spaces' intersection is empty");
    if (found.size() < 4)
        throw InvalidInput(field, "the half-spaces' intersection has no volume (" + std::to_string(found.size()) + " vertices)");

    // 4. Topology through the hull of the vertices (back in the caller's coordinates).
    std::vector<Vec3> vertices;
    vertices.reserve(found.size());
    double err = 0, viol = 0;
    for (const Found& f : found) {
        vertices.push_back(f.v + c);
        err = std::max(err, f.err);
        viol = std::max(viol, f.viol);
    }
    ConvexPolytope p;
    try {
        p = makeConvexHull(vertices, field);
    } catch (const InvalidInput& e) {
        throw InvalidInput(field, "the half-spaces' intersection has no volume, or is too thin to compute (" +
                                      std::string(e.what()).substr(field.size() + 2) + ")");
    }

    // 5. Every boundary triangle of hull(V) on an input plane (one its three vertices are all on); those
    //    planes, each once, become the H-representation, exactly as given (normalised).
    std::vector<std::size_t> indexOf(p.vertices.size());
    for (std::size_t a = 0; a < p.vertices.size(); ++a)
        indexOf[a] = std::size_t(std::find(vertices.begin(), vertices.end(), p.vertices[a]) - vertices.begin());
    auto onPlane = [&](std::size_t vi, std::size_t i) {
        const Found& f = found[vi];
        const double s = glm::dot(hc[i].normal, f.v) - hc[i].offset;
        return std::abs(s) <= 1e-10 * (maxAbs(f.v) + std::abs(hc[i].offset)) + f.err;
    };
    std::vector<char> facet(m, 0);
    for (const auto& t : p.triangles) {
        bool matched = false;
        for (std::size_t i = 0; i < m && !matched; ++i)
            if (onPlane(indexOf[t[0]], i) && onPlane(indexOf[t[1]], i) && onPlane(indexOf[t[2]], i)) {
                facet[i] = 1;
                matched = true;
            }
        if (!matched)
            throw InvalidInput(field, "the vertices of the half-spaces' intersection could not be computed robustly "
                                      "(nearly parallel planes meeting in a point); perturb or drop such planes");
    }
    p.planes.clear();
    for (std::size_t i = 0; i < m; ++i) {
        if (!facet[i]) continue;
        bool duplicate = false; // the same plane given twice
        for (const HalfSpace& g : p.planes)
            duplicate = duplicate || (lengthSquared<3>(g.normal - h[i].normal) < 1e-24 &&
                                      std::abs(g.offset - h[i].offset) <= 2 * shiftRounding + err);
        if (!duplicate) p.planes.push_back(h[i]);
    }
    double magnitude = maxAbs(c);
    for (const Vec3& v : p.vertices) magnitude = std::max(magnitude, maxAbs(v));
    p.tolerance += err + 8 * viol + shiftRounding + 4 * kEpsilon * magnitude;
    return p;
}

} // namespace rgvc
