// Parallel-ray visibility: the reference for orthographic cameras (Camera::projection = Orthographic).
//
// An object is visible from an orthographic camera when some point p of it lies in the closed view box
// (Camera.hpp: 0 <= (p - position) . f <= far, |(p - position) . right| <= width / 2, |... . trueUp| <=
// height / 2) and the open segment from p's foot on the near plane, p - ((p - position) . f) f, to p
// meets the interior of no other object (the contract's definition with the ray from the camera point
// replaced by the ray parallel to f; objects are convex, so a first hit lies on the boundary, and the
// samples are boundary points). Sampled: a Fibonacci sphere / circle of points for balls, a grid of
// points on each face or edge for boxes and polygons, and for polytopes (oriented boxes, hulls) their
// vertices, points along their edges and a grid on each boundary triangle, dense enough for the random scenes' objects
// (fractions of a voxel to tens of voxels). World units, like the other references.
#pragma once

#include "rgvc/grid/Camera.hpp"
#include "rgvc/grid/Shapes.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <variant>
#include <vector>

namespace rgvc::reference {

struct OrthoOptions {
    int ballSamples = 400;   ///< points on a sphere (3D) or circle (2D)
    int edgeSamples = 14;    ///< points per axis of a box face (3D) or per edge (2D: x 4)
    double tolerance = 1e-9; ///< relative to the scene's size: box membership grown, interiors shrunk by it
};

namespace ortho_detail {

/// The view box's frame (world units), built like OrthoVolume's.
template <int D> struct Frame {
    Vec<D> o{0.0};
    Vec<D> axis[D]{};
    double half[3] = {0, 0, 0};
    double depth = INFINITY;
    explicit Frame(const Camera<D>& c) {
        o = c.position;
        axis[0] = safeNormalize<D>(c.direction);
        if constexpr (D == 2) {
            axis[1] = Vec2{axis[0].y, -axis[0].x};
        } else {
            axis[1] = glm::normalize(glm::cross(axis[0], cameraUp(c)));
            axis[2] = glm::cross(axis[1], axis[0]);
            half[2] = 0.5 * c.height;
        }
        half[1] = 0.5 * c.width;
        depth = c.far;
    }
    bool contains(const Vec<D>& p, double tol) const {
        const Vec<D> q = p - o;
        const double t = glm::dot(q, axis[0]);
        if (t < -tol || t > depth + tol) return false;
        for (int i = 1; i < D; ++i)
            if (std::abs(glm::dot(q, axis[i])) > half[i] + tol) return false;
        return true;
    }
};

/// Whether the open segment a..b meets the interior of the shape shrunk by tol.
template <int D> bool segmentMeetsInterior(const Vec<D>& a, const Vec<D>& b, const Shape<D>& s, double tol) {
    return std::visit(
        [&](const auto& x) -> bool {
            using T = std::decay_t<decltype(x)>;
            const Vec<D> d = b - a;
            if constexpr (std::is_same_v<T, Ball<D>>) {
                const double len2 = lengthSquared<D>(d);
                double t = len2 > 0 ? glm::dot(x.center - a, d) / len2 : 0;
                t = std::clamp(t, 0.0, 1.0);
                const double r = x.radius - tol;
                return r > 0 && lengthSquared<D>(a + t * d - x.center) < r * r;
            } else if constexpr (std::is_same_v<T, Box<D>>) {
                double t0 = 0, t1 = 1;
                for (int k = 0; k < D; ++k) {
                    const double lo = x.min[k] + tol, hi = x.max[k] - tol;
                    if (d[k] == 0) {
                        if (!(a[k] > lo && a[k] < hi)) return false;
                        continue;
                    }
                    double u0 = (lo - a[k]) / d[k], u1 = (hi - a[k]) / d[k];
                    if (u0 > u1) std::swap(u0, u1);
                    t0 = std::max(t0, u0);
                    t1 = std::min(t1, u1);
                }
                return t0 < t1;
            } else if constexpr (std::is_same_v<T, ConvexPolygon>) {
                double t0 = 0, t1 = 1;
                const std::size_t m = x.points.size();
                double area = 0; // either winding: inside is left of each edge when counter-clockwise
                for (std::size_t i = 0; i < m; ++i) {
                    const Vec2 p = x.points[i], q = x.points[(i + 1) % m];
                    area += p.x * q.y - q.x * p.y;
                }
                const double sign = area >= 0 ? 1.0 : -1.0;
                for (std::size_t i = 0; i < m; ++i) {
                    // auto: the types stay dependent on T, so clang does not check this branch for D = 3
                    const auto p = x.points[i];
                    const auto e = x.points[(i + 1) % m] - p;
                    const double len = std::sqrt(e.x * e.x + e.y * e.y);
                    auto n = e;
                    n.x = -sign * e.y / len; // inward
                    n.y = sign * e.x / len;
                    const double fa = glm::dot(a - p, n) - tol, fd = glm::dot(d, n); // inside: > 0
                    if (fd == 0) {
                        if (!(fa > 0)) return false;
                        continue;
                    }
                    const double u = -fa / fd;
                    if (fd > 0) t0 = std::max(t0, u);
                    else t1 = std::min(t1, u);
                }
                return t0 < t1;
            } else if constexpr (std::is_same_v<T, ConvexPolytope>) {
                // The open segment against the open polytope (planes moved in by tol): the slab test over
                // every facet plane.
                double t0 = 0, t1 = 1;
                for (const auto& h : x.planes) { // auto: dependent on T (clang, D = 2)
                    const double fa = glm::dot(h.normal, a) - (h.offset - tol), fd = glm::dot(h.normal, d); // inside: < 0
                    if (fd == 0) {
                        if (!(fa < 0)) return false;
                        continue;
                    }
                    const double u = -fa / fd;
                    if (fd > 0) t1 = std::min(t1, u);
                    else t0 = std::max(t0, u);
                }
                return t0 < t1;
            } else {
                return false; // shapes this reference does not know occlude nothing
            }
        },
        s);
}

/// Boundary samples of a shape.
template <int D> void samplesOf(const Shape<D>& s, const OrthoOptions& opt, std::vector<Vec<D>>& out) {
    out.clear();
    std::visit(
        [&](const auto& x) {
            using T = std::decay_t<decltype(x)>;
            if constexpr (std::is_same_v<T, Ball<D>>) {
                const double golden = 2.399963229728653; // pi (3 - sqrt 5)
                for (int i = 0; i < opt.ballSamples; ++i) {
                    if constexpr (D == 2) {
                        const double a = 6.283185307179586 * (i + 0.5) / opt.ballSamples;
                        out.push_back(x.center + x.radius * Vec2{std::cos(a), std::sin(a)});
                    } else {
                        const double z = 1 - 2 * (i + 0.5) / opt.ballSamples, r = std::sqrt(std::max(0.0, 1 - z * z));
                        const double a = golden * i;
                        out.push_back(x.center + x.radius * Vec3{r * std::cos(a), r * std::sin(a), z});
                    }
                }
            } else if constexpr (std::is_same_v<T, Box<D>>) {
                const int n = D == 2 ? 4 * opt.edgeSamples : opt.edgeSamples;
                for (int axis = 0; axis < D; ++axis)
                    for (int side = 0; side < 2; ++side)
                        for (int i = 0; i <= n; ++i)
                            for (int j = 0; j <= (D == 3 ? n : 0); ++j) {
                                Vec<D> p;
                                p[axis] = side ? x.max[axis] : x.min[axis];
                                const int u = (axis + 1) % D;
                                p[u] = x.min[u] + (x.max[u] - x.min[u]) * i / n;
                                if constexpr (D == 3) {
                                    const int v = (axis + 2) % 3;
                                    p[v] = x.min[v] + (x.max[v] - x.min[v]) * j / n;
                                }
                                out.push_back(p);
                            }
            } else if constexpr (std::is_same_v<T, ConvexPolytope>) {
                // Vertices, points along every edge and a triangular grid on every boundary triangle.
                const int n = opt.edgeSamples;
                // (auto, not Vec3: the types stay dependent on T, which clang needs for D = 2)
                for (const auto& v : x.vertices) out.push_back(v);
                for (const auto& e : x.edges)
                    for (int k = 1; k < n; ++k) out.push_back(x.vertices[e[0]] + (x.vertices[e[1]] - x.vertices[e[0]]) * (double(k) / n));
                for (const auto& t : x.triangles) {
                    const auto &A = x.vertices[t[0]], &B = x.vertices[t[1]], &C = x.vertices[t[2]];
                    for (int i = 1; i < n; ++i)
                        for (int j = 1; i + j < n; ++j) out.push_back(A + (B - A) * (double(i) / n) + (C - A) * (double(j) / n));
                }
            } else if constexpr (std::is_same_v<T, ConvexPolygon>) {
                const int n = 4 * opt.edgeSamples;
                for (std::size_t i = 0; i < x.points.size(); ++i) {
                    const auto a = x.points[i], b = x.points[(i + 1) % x.points.size()]; // dependent (clang, D = 3)
                    for (int k = 0; k < n; ++k) out.push_back(a + (b - a) * (double(k) / n));
                }
            }
        },
        s);
}

} // namespace ortho_detail

/// Per shape, whether it is visible from the orthographic camera (sampled, see the top of this file).
/// occluders[i] false: shape i hides nothing (role occludee). Empty: every shape occludes.
template <int D>
std::vector<bool> orthoVisible(const std::vector<Shape<D>>& shapes, const Camera<D>& cam, const std::vector<bool>& occluders = {},
                               const OrthoOptions& opt = {}) {
    using namespace ortho_detail;
    const Frame<D> frame(cam);
    double scale = 1;
    for (const Shape<D>& s : shapes) {
        const Box<D> b = boundsOf<D>(s);
        for (int a = 0; a < D; ++a) scale = std::max({scale, std::abs(b.min[a]), std::abs(b.max[a])});
    }
    for (int a = 0; a < D; ++a) scale = std::max(scale, std::abs(cam.position[a]));
    const double tol = opt.tolerance * scale;
    std::vector<Box<D>> bounds;
    for (const Shape<D>& s : shapes) bounds.push_back(boundsOf<D>(s));
    std::vector<bool> visible(shapes.size(), false);
    std::vector<Vec<D>> pts;
    for (std::size_t i = 0; i < shapes.size(); ++i) {
        samplesOf<D>(shapes[i], opt, pts);
        for (const Vec<D>& p : pts) {
            if (!frame.contains(p, tol)) continue;
            const Vec<D> foot = p - glm::dot(p - frame.o, frame.axis[0]) * frame.axis[0];
            const Vec<D> lo = glm::min(foot, p), hi = glm::max(foot, p);
            bool blocked = false;
            for (std::size_t j = 0; j < shapes.size() && !blocked; ++j) {
                if (j == i || (!occluders.empty() && !occluders[j])) continue;
                bool overlap = true; // the segment's box against j's bounds first
                for (int a = 0; a < D; ++a) overlap = overlap && hi[a] >= bounds[j].min[a] && lo[a] <= bounds[j].max[a];
                blocked = overlap && segmentMeetsInterior<D>(foot, p, shapes[j], tol);
            }
            if (!blocked) {
                visible[i] = true;
                break;
            }
        }
    }
    return visible;
}

} // namespace rgvc::reference
