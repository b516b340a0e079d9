// Object shapes: balls (circle in 2D, sphere in 3D), axis-aligned boxes, in 2D convex polygons and in
// 3D convex polytopes (hulls of points and oriented boxes, ConvexPolytope.hpp) and triangle meshes
// (MeshSolid.hpp: the convex hull as the outer model, a closed mesh's solid voxelization as the inner one).
//
// Shapes are closed sets. They are given in world units at the API boundary and converted once to
// voxel units (`toLocal`) before rasterization. §5.1 of the paper reduces any other 3D shape to an
// inner and an outer simplified model; a new shape joins by adding a variant alternative with its
// `innerVoxels`/`touchedVoxels` rasterizers (see ConservativeRaster.hpp).
//
// Adding an alternative: every visit below ends in `static_assert(kUnhandledShape<T>)`, so the compiler
// lists each dispatch point that does not know the new shape yet (also in ConservativeRaster.hpp,
// OcclusionBuffer3D.cpp and the GL stage). Points that test a shape with std::get_if fall through to
// their last branch for a new shape: MeshSolid was added by giving each of those an explicit branch (the
// hull, MeshSolid::hull(), everywhere but O).
#pragma once

#include "rgvc/grid/ConvexPolytope.hpp"
#include "rgvc/grid/Error.hpp"
#include "rgvc/grid/GridGeometry.hpp"
#include "rgvc/grid/Math.hpp"
#include "rgvc/grid/MeshSolid.hpp"

#include <algorithm>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

namespace rgvc {

/// Circle (D = 2) or sphere (D = 3). [Units] world or voxel, as the context says. [Limit] radius > 0.
template <int D> struct Ball {
    Vec<D> center{0.0};
    double radius = 0;
};

/// Axis-aligned box, closed. [Limit] min < max on every axis.
template <int D> struct Box {
    Vec<D> min{0.0};
    Vec<D> max{0.0};
};

/// Convex polygon (2D only), closed. Points in either winding; stored counter-clockwise after
/// validation. [Limit] >= 3 points, convex, non-zero area.
struct ConvexPolygon {
    std::vector<Vec2> points;
};

template <int D> struct ShapeTypes;
template <> struct ShapeTypes<2> { using type = std::variant<Ball<2>, Box<2>, ConvexPolygon>; };
template <> struct ShapeTypes<3> { using type = std::variant<Ball<3>, Box<3>, ConvexPolytope, MeshSolid>; };
/// Any shape of a D-dimensional scene.
template <int D> using Shape = typename ShapeTypes<D>::type;

/// False for every type: ends an `if constexpr` chain over the alternatives, so that a shape added to
/// the variant without a branch is a compile error at that dispatch point, not a silent fall-through.
template <class T> inline constexpr bool kUnhandledShape = false;

// ---------------------------------------------------------------------------------------------------
// Free functions on shapes.

template <int D> inline Box<D> boundsOf(const Ball<D>& b) { return {b.center - b.radius, b.center + b.radius}; }
template <int D> inline Box<D> boundsOf(const Box<D>& b) { return b; }
inline Box<2> boundsOf(const ConvexPolygon& p) {
    Box<2> r{p.points.front(), p.points.front()};
    for (const Vec2& q : p.points) {
        r.min = glm::min(r.min, q);
        r.max = glm::max(r.max, q);
    }
    return r;
}
/// The exact bounding box of the points the polytope was built from.
inline Box<3> boundsOf(const ConvexPolytope& p) { return {p.boundsMin, p.boundsMax}; }
/// Its hull's (which contains the mesh: MeshSolid.hpp).
inline Box<3> boundsOf(const MeshSolid& m) { return boundsOf(m.hull()); }
template <int D> inline Box<D> boundsOf(const Shape<D>& s) {
    return std::visit([](const auto& x) { return boundsOf(x); }, s);
}

/// A ball containing the shape (not always the smallest): centred on its bounding box, reaching its
/// farthest point. Used to size temporal bounding volumes.
template <int D> inline Ball<D> boundingBall(const Ball<D>& b) { return b; }
template <int D> inline Ball<D> boundingBall(const Box<D>& b) {
    return {(b.min + b.max) * 0.5, 0.5 * std::sqrt(lengthSquared<D>(b.max - b.min))};
}
inline Ball<2> boundingBall(const ConvexPolygon& p) {
    const Box<2> box = boundsOf(p);
    Ball<2> r{(box.min + box.max) * 0.5, 0.0};
    for (const Vec2& q : p.points) r.radius = std::max(r.radius, std::sqrt(lengthSquared<2>(q - r.center)));
    return r;
}
inline Ball<3> boundingBall(const ConvexPolytope& p) {
    Ball<3> r{0.5 * (p.boundsMin + p.boundsMax), 0.0};
    for (const Vec3& q : p.vertices) r.radius = std::max(r.radius, std::sqrt(lengthSquared<3>(q - r.center)));
    r.radius += p.tolerance;
    return r;
}
inline Ball<3> boundingBall(const MeshSolid& m) { return boundingBall(m.hull()); }
template <int D> inline Ball<D> boundingBall(const Shape<D>& s) {
    return std::visit([](const auto& x) { return boundingBall(x); }, s);
}

template <int D> inline Ball<D> translated(const Ball<D>& b, const Vec<D>& t) { return {b.center + t, b.radius}; }
template <int D> inline Box<D> translated(const Box<D>& b, const Vec<D>& t) { return {b.min + t, b.max + t}; }
inline ConvexPolygon translated(const ConvexPolygon& p, const Vec2& t) {
    ConvexPolygon r = p;
    for (Vec2& q : r.points) q += t;
    return r;
}
inline ConvexPolytope translated(const ConvexPolytope& p, const Vec3& t) { return translatedPolytope(p, t); }
inline MeshSolid translated(const MeshSolid& m, const Vec3& t) { return m.translated(t); }
template <int D> inline Shape<D> translated(const Shape<D>& s, const Vec<D>& t) {
    return std::visit([&](const auto& x) -> Shape<D> { return translated(x, t); }, s);
}

/// Converts a world-unit ball or box to voxel units of `grid`.
template <int D> inline Ball<D> toLocal(const Ball<D>& b, const GridGeometry<D>& grid) {
    return {grid.toLocal(b.center), grid.toLocalLength(b.radius)};
}
template <int D> inline Box<D> toLocal(const Box<D>& b, const GridGeometry<D>& grid) {
    return {grid.toLocal(b.min), grid.toLocal(b.max)};
}

/// Converts a world-unit shape to voxel units of `grid`.
template <int D> inline Shape<D> toLocal(const Shape<D>& s, const GridGeometry<D>& grid) {
    return std::visit(
        [&](const auto& x) -> Shape<D> {
            using T = std::decay_t<decltype(x)>;
            if constexpr (std::is_same_v<T, Ball<D>> || std::is_same_v<T, Box<D>>) {
                return toLocal<D>(x, grid);
            } else if constexpr (std::is_same_v<T, ConvexPolygon>) {
                T r;
                r.points.reserve(x.points.size());
                for (const auto& q : x.points) r.points.push_back(grid.toLocal(q));
                return r;
            } else if constexpr (std::is_same_v<T, ConvexPolytope>) {
                // The same map as GridGeometry::toLocal: (x - origin) / voxel size.
                return scaledPolytope(x, grid.origin(), grid.toLocalLength(1.0));
            } else if constexpr (std::is_same_v<T, MeshSolid>) {
                return x.mapped(grid.origin(), grid.toLocalLength(1.0)); // the same map, mesh and hull
            } else {
                static_assert(kUnhandledShape<T>);
            }
        },
        s);
}

/// Signed area of a polygon (positive when counter-clockwise).
inline double signedArea(const std::vector<Vec2>& pts) {
    double a = 0;
    for (std::size_t i = 0, n = pts.size(); i < n; ++i) a += cross2(pts[i], pts[(i + 1) % n]);
    return 0.5 * a;
}

/// Validates a shape given in world units and normalises it (polygons become counter-clockwise).
/// @param field  prefix for the error message, e.g. "objects[3]", or a callable returning it (called on error only).
/// @throws InvalidInput naming the field: NaN/inf, radius <= 0, min >= max, < 3 points, non-convex, zero area.
namespace shape_detail {
inline std::string fieldText(const std::string& field) { return field; }
inline std::string fieldText(const char* field) { return field; }
/// A callable naming the field: called only when there is an error to report, so that validating a
/// shape on the hot path (a placement query per tracked object per frame) builds no string.
template <class F>
    requires std::is_invocable_r_v<std::string, const F&>
inline std::string fieldText(const F& field) {
    return field();
}
} // namespace shape_detail

template <int D, class Field> inline void validateShape(Shape<D>& s, const Field& field) {
    std::visit(
        [&](auto& x) {
            using T = std::decay_t<decltype(x)>;
            if constexpr (std::is_same_v<T, Ball<D>>) {
                if (!allFinite<D>(x.center)) throw InvalidInput(shape_detail::fieldText(field) + ".center", "must be finite");
                if (!std::isfinite(x.radius) || !(x.radius > 0))
                    throw InvalidInput(shape_detail::fieldText(field) + ".radius", "must be finite and > 0, got " + std::to_string(x.radius));
            } else if constexpr (std::is_same_v<T, Box<D>>) {
                if (!allFinite<D>(x.min)) throw InvalidInput(shape_detail::fieldText(field) + ".min", "must be finite");
                if (!allFinite<D>(x.max)) throw InvalidInput(shape_detail::fieldText(field) + ".max", "must be finite");
                for (int i = 0; i < D; ++i)
                    if (!(x.min[i] < x.max[i]))
                        throw InvalidInput(shape_detail::fieldText(field) + ".max", "must exceed min on every axis");
            } else if constexpr (std::is_same_v<T, ConvexPolytope>) {
                validatePolytope(x, shape_detail::fieldText(field));
            } else if constexpr (std::is_same_v<T, MeshSolid>) {
                validateMeshSolid(x, shape_detail::fieldText(field));
            } else if constexpr (std::is_same_v<T, ConvexPolygon>) {
                const std::size_t n = x.points.size();
                if (n < 3) throw InvalidInput(shape_detail::fieldText(field) + ".points", "a polygon needs at least 3 points");
                for (const Vec2& q : x.points)
                    if (!allFinite<2>(q)) throw InvalidInput(shape_detail::fieldText(field) + ".points", "must be finite");
                double area = signedArea(x.points);
                if (!(std::abs(area) > 0) || !std::isfinite(area))
                    throw InvalidInput(shape_detail::fieldText(field) + ".points", "polygon has zero area");
                // Checked on a counter-clockwise copy: a rejected polygon goes back to the caller untouched.
                // Repeated consecutive points carry no edge and are dropped; without that, a polygon that
                // runs along a line and back ((a, b, a, c, ...), found by fuzz_culler2d) hides its
                // reversal behind a zero-length edge and passes the turning test below.
                std::vector<Vec2> ccw;
                ccw.reserve(n);
                for (std::size_t i = 0; i < n; ++i) {
                    const Vec2& q = x.points[area < 0 ? n - 1 - i : i];
                    if (ccw.empty() || q != ccw.back()) ccw.push_back(q);
                }
                while (ccw.size() > 1 && ccw.back() == ccw.front()) ccw.pop_back();
                const std::size_t m = ccw.size();
                if (m < 3) throw InvalidInput(shape_detail::fieldText(field) + ".points", "a polygon needs at least 3 distinct points");
                for (std::size_t i = 0; i < m; ++i) {
                    const Vec2& a = ccw[i];
                    const Vec2& b = ccw[(i + 1) % m];
                    const Vec2& c = ccw[(i + 2) % m];
                    const double turn = cross2(b - a, c - b);
                    if (turn < 0) throw InvalidInput(shape_detail::fieldText(field) + ".points", "polygon is not convex");
                    if (turn == 0 && glm::dot(b - a, c - b) < 0)
                        throw InvalidInput(shape_detail::fieldText(field) + ".points", "polygon doubles back on itself");
                }
                // A convex polygon winds around once: the turning angles sum to 2*pi. A star-shaped
                // self-intersecting "polygon" has all left turns too but winds more than once.
                double turning = 0;
                for (std::size_t i = 0; i < m; ++i) {
                    Vec2 e0 = ccw[(i + 1) % m] - ccw[i];
                    Vec2 e1 = ccw[(i + 2) % m] - ccw[(i + 1) % m];
                    turning += std::atan2(cross2(e0, e1), glm::dot(e0, e1));
                }
                if (turning > 2 * 3.141592653589793 + 1e-6)
                    throw InvalidInput(shape_detail::fieldText(field) + ".points", "polygon is self-intersecting");
                x.points = std::move(ccw);
            } else {
                static_assert(kUnhandledShape<T>);
            }
        },
        s);
}

/// The shape shrunk by `d` (an erosion: every point at distance > d from the outside; closed sets are
/// kept closed by taking the offset faces as the new faces). This is the occluder model of seed 004
/// §5.1's occlusion-preserving principle when what is drawn differs from the analytic shape: a sphere
/// drawn as an inscribed mesh of inradius r_in contains the ball shrunk by r - r_in, so voxels entirely
/// inside that ball are covered by the mesh and O never hides what the mesh lets through.
/// Ball: radius - d. Box: every face moved in by d. Convex polygon (counter-clockwise, as validateShape
/// leaves it): the original clipped by every edge's half-plane moved in by d (Sutherland-Hodgman), so
/// edges that vanish are dropped exactly. Convex polytope: every plane moved in by d, its vertices
/// recomputed (erodePolytope). Mesh: no erosion of a mesh is computed, so a positive inset leaves nothing
/// (the mesh then occludes nothing: sound, and its hull stays the outer model).
/// [Units] d in the shape's units. [Limit] d finite, >= 0.
/// @return false when nothing is left (the shape then occludes nothing); `out` is only written on true.
template <int D> inline bool insetShape(const Shape<D>& s, double d, Shape<D>& out) {
    if (d <= 0) {
        out = s;
        return true;
    }
    return std::visit(
        [&](const auto& x) -> bool {
            using T = std::decay_t<decltype(x)>;
            if constexpr (std::is_same_v<T, Ball<D>>) {
                if (!(x.radius > d)) return false;
                out = Ball<D>{x.center, x.radius - d};
                return true;
            } else if constexpr (std::is_same_v<T, Box<D>>) {
                Box<D> b{x.min + d, x.max - d};
                for (int a = 0; a < D; ++a)
                    if (!(b.min[a] < b.max[a])) return false;
                out = b;
                return true;
            } else if constexpr (std::is_same_v<T, ConvexPolytope>) {
                T r; // T, not ConvexPolytope: keeps the branch dependent, so that D = 2 never instantiates it (clang)
                if (!erodePolytope(x, d, r)) return false;
                out = std::move(r);
                return true;
            } else if constexpr (std::is_same_v<T, MeshSolid>) {
                return false;
            } else if constexpr (std::is_same_v<T, ConvexPolygon>) {
                const std::size_t n = x.points.size();
                std::vector<Vec2> poly = x.points, next;
                for (std::size_t i = 0; i < n && poly.size() >= 3; ++i) {
                    const Vec2 a = x.points[i], e = x.points[(i + 1) % n] - a;
                    const double len = std::sqrt(lengthSquared<2>(e));
                    if (!(len > 0)) continue;
                    // Inside (left of the ccw edge, by more than d): cross(e, p - a) / |e| - d >= 0.
                    auto side = [&](const Vec2& p) { return cross2(e, p - a) / len - d; };
                    next.clear();
                    for (std::size_t k = 0, m = poly.size(); k < m; ++k) {
                        const Vec2 p = poly[k], q = poly[(k + 1) % m];
                        const double sp = side(p), sq = side(q);
                        if (sp >= 0) next.push_back(p);
                        if ((sp >= 0) != (sq >= 0)) next.push_back(p + (q - p) * (sp / (sp - sq)));
                    }
                    poly.swap(next);
                }
                if (poly.size() < 3 || !(signedArea(poly) > 1e-12)) return false;
                T r;
                r.points = std::move(poly);
                out = r;
                return true;
            } else {
                static_assert(kUnhandledShape<T>);
            }
        },
        s);
}

} // namespace rgvc
