// Convex polytopes in 3D: convex hulls of points and oriented boxes (scene-format.md's `hull` and `obb`),
// and bounded intersections of half-spaces (a library-only constructor: the scene format gives hulls by
// points only).
//
// One representation for both, so that every stage that visits shapes (rasterization into O and I, the
// occlusion images, the GL stage) has one more alternative to handle, not two: an oriented box is the
// hull of its 8 corners, built directly (its topology is known) instead of through the hull algorithm.
//
// Both representations are kept, because each stage needs one of them:
//   - H: the facet planes n.x <= offset (unit outward n). Inside tests, chords of lines, ray entry and
//     exit (the occlusion images' slab test generalises to any number of planes), erosion;
//   - V: the vertices, the edges and a boundary triangulation. Extents of slices (the I rasterization),
//     bounds, the GL stage's triangles.
// The shape is the closed convex hull of the points it was built from. `tolerance` bounds how far the two
// representations may disagree with it (the hull algorithm drops points closer than its epsilon to a
// facet); every conservative test grows (I) or shrinks (O) by it.
#pragma once

#include "rgvc/grid/Math.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace rgvc {

template <int D> struct Box; // Shapes.hpp

/// The closed half-space normal . x <= offset. [Limit] |normal| = 1.
struct HalfSpace {
    Vec3 normal{0.0, 0.0, 1.0};
    double offset = 0;
};

/// A closed convex polytope with non-empty interior (3D only). Build it with makeConvexHull,
/// makePolytopeFromPlanes or makeOrientedBox; a polytope assembled by hand must pass validateShape (Shapes.hpp).
/// [Units] world or voxel, as the context says (like the other shapes).
struct ConvexPolytope {
    std::vector<Vec3> vertices;                         ///< the hull's vertices
    std::vector<HalfSpace> planes;                      ///< its facets (>= 4), unit outward normals
    std::vector<std::array<std::uint32_t, 2>> edges;    ///< every edge of `triangles` once (a superset of the hull's edges)
    std::vector<std::array<std::uint32_t, 3>> triangles; ///< the boundary, counter-clockwise seen from outside
    Vec3 boundsMin{0.0}, boundsMax{0.0};                ///< the exact bounding box of the input points
    /// Every point of the shape lies within `tolerance` of the vertices' hull and inside every plane moved
    /// out by it; every point of the vertices' hull lies in the shape grown by it. [Limit] >= 0, finite.
    double tolerance = 0;
};

/// [Limit] the most points makeConvexHull accepts (its cost is O(points x facets)).
inline constexpr std::size_t kMaxHullPoints = 20000;

/// The convex hull of `points` (scene-format.md's `hull`): an incremental hull in double precision with
/// an epsilon of 1e-13 of the points' extent (see ConvexPolytope.cpp for why it is hand-written).
/// @param field  the field path for errors, e.g. "objects[3].points".
/// @throws InvalidInput naming the field: fewer than 4 points, more than kMaxHullPoints, NaN/inf, all
///         points (within 1e-9 of their extent) on one plane or line, or coordinates whose products overflow.
ConvexPolytope makeConvexHull(std::span<const Vec3> points, const std::string& field);

/// [Limit] the most half-spaces makePolytopeFromPlanes accepts (its cost is O(planes^3) solves).
inline constexpr std::size_t kMaxPolytopePlanes = 256;

/// The convex polytope {x : planes[i].normal . x <= planes[i].offset for every i}: a bounded intersection
/// of closed half-spaces, in the same representation makeConvexHull produces (its planes are the facets;
/// input planes that touch the polytope in less than a facet, or not at all, are dropped). The vertices
/// are enumerated from plane triples (see PolytopeFromPlanes.cpp for the method and why it is
/// hand-written); `tolerance` covers their rounding. Normals need not be unit: (normal, offset) is scaled
/// by 1 / |normal|. [Limit] 4 to kMaxPolytopePlanes planes. [Units] world or voxel (any consistent unit).
/// @param field  the field path for errors, e.g. "brush.planes" (errors name field + "[3].normal", ...).
/// @throws InvalidInput naming the field: too few or too many planes; a NaN/inf or zero normal, a
///         NaN/inf offset; an unbounded intersection (the normals do not surround the origin within
///         1e-9); an empty one; one without volume (flat within 1e-9 of its extent); vertices that cannot
///         be computed robustly (nearly parallel planes meeting in one point).
ConvexPolytope makePolytopeFromPlanes(std::span<const HalfSpace> planes, const std::string& field);

/// The box centre + R (s0 h0, s1 h1, s2 h2), s_i in [-1, 1], R the rotation of the quaternion
/// (x, y, z, w) (glTF's order, scene-format.md's `obb`).
/// [Limit] half extents finite and > 0; | |q| - 1 | <= kQuaternionTolerance (the quaternion is then
/// normalised: JSON with 5 to 6 significant digits is not exactly unit).
/// @param field  the object's field path, e.g. "objects[3]" (errors name field + ".half_extents", ".rotation", ...).
/// @throws InvalidInput naming the field.
ConvexPolytope makeOrientedBox(const Vec3& center, const Vec3& halfExtents, const std::array<double, 4>& rotation,
                               const std::string& field);

/// [Limit] how far from 1 the length of an obb's quaternion may be.
inline constexpr double kQuaternionTolerance = 1e-5;

/// The rotation matrix of the unit quaternion (x, y, z, w), as columns: column i is the box's axis i.
std::array<Vec3, 3> rotationColumns(const std::array<double, 4>& q);

/// Throws InvalidInput (field + ".points", ".planes", ...) unless p is a consistent polytope: finite
/// numbers, unit normals (1e-9), >= 4 planes, >= 4 vertices, indices in range, a positive tolerance-free
/// thickness, every vertex inside every plane and inside the bounds within the tolerance (and rounding).
/// O(vertices x planes).
void validatePolytope(const ConvexPolytope& p, const std::string& field);

/// The polytope moved by t (vertices, plane offsets, bounds).
ConvexPolytope translatedPolytope(const ConvexPolytope& p, const Vec3& t);

/// The polytope under x -> (x - origin) * scale (the world-to-voxel map; scale > 0).
ConvexPolytope scaledPolytope(const ConvexPolytope& p, const Vec3& origin, double scale);

/// Erosion by d (>= 0): every plane moved inward by d, the vertices recomputed by clipping the polytope
/// with those planes. Exact up to rounding. @return false when less than a sliver is left.
bool erodePolytope(const ConvexPolytope& p, double d, ConvexPolytope& out);

} // namespace rgvc
