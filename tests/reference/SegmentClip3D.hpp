// Internal to the 3D reference (not part of its interface): the camera-relative objects it casts rays
// against, the ray clipping against each shape (balls, boxes, convex polytopes), the point-in-shape test,
// the camera's frustum, and the exact (up to eps) view-region tests, which clip each shape's faces against
// the frustum. Split out of ExactVisibility3D.cpp (the sampling and ray-casting algorithm stays there) so
// that each file holds one concept; the definitions and tolerances are those of ExactVisibility3D.hpp.
#pragma once

#include "RayInterval.hpp"

#include "rgvc/grid/Camera.hpp"
#include "rgvc/grid/Shapes.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace rgvc::reference::detail {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTwoPi = 2 * kPi;
constexpr double kInf = std::numeric_limits<double>::infinity();
// Parameters slightly outside [0, 1] are accepted when intersecting segments: an extra target only
// costs a ray.
constexpr double kParamSlack = 1e-9;

inline Vec3 normalized(const Vec3& v) { return v / std::sqrt(lengthSquared<3>(v)); }

// An object in camera-relative coordinates (the camera is the origin, so rays are t*u, u a unit vector).
struct Obj {
    bool isBall = false;
    bool isPoly = false; // a convex polytope (obb, hull): planes, vertices, edges, triangles
    Vec3 center{0.0}; // ball
    double radius = 0;
    Vec3 lo{0.0}, hi{0.0}; // box; for a ball or a polytope its bounds
    std::vector<HalfSpace> planes; // camera-relative
    std::vector<Vec3> verts;
    std::vector<std::array<std::uint32_t, 2>> edges;
    std::vector<std::array<std::uint32_t, 3>> tris;
    // A triangle mesh (MeshSolid): the fields above hold its hull (isPoly), which is what it is as the
    // object seen (its outer model, as the culler takes it: a superset of the mesh's own visibility); as a
    // blocker it is its solid (clip with off < 0 goes to meshInterior). It takes no part in the seam rule
    // (fusesSeams): that rule only hides more, so leaving meshes out only reports more.
    bool isMesh = false;
    bool meshClosed = false;
    std::vector<Vec3> meshVerts;
    std::vector<std::array<std::uint32_t, 3>> meshTris;
    std::vector<std::array<std::uint32_t, 2>> meshEdges; // every edge once
};

/// Whether o takes part in the seam rule (flat faces that can be shared: boxes and polytopes).
inline bool fusesSeams(const Obj& o) { return !o.isBall && !o.isMesh; }

/// The shape, camera-relative (cam: the camera position, world units).
Obj prepare(const Shape<3>& shape, const Vec3& cam);

/// Parameters t (whole line) where t*u (u a unit vector) lies within `off` of o: off > 0 grows the object,
/// off < 0 keeps only points deeper than -off inside it.
Interval clip(const Obj& o, const Vec3& u, double off);

/// The first interval of parameters t (the one with the smallest start among those ending after 0) where
/// the line t*u runs inside the interior of mesh o's solid, shrunk by eta at both ends; empty when there is
/// none, for an open mesh, or when the line's crossings do not pair up. See MeshInterior3D.cpp.
Interval meshInterior(const Obj& o, const Vec3& u, double eta);

/// Whether camera-relative point q lies within `off` of o (off < 0: deeper than -off inside it). A mesh
/// is taken as its hull here (the test is only asked of the object seen, and of seam-rule objects).
bool containsPoint(const Obj& o, const Vec3& q, double off);

// The camera's frame and its view region, camera-relative.
struct Frustum {
    Vec3 f{0.0, 0.0, 1.0}, r{1.0, 0.0, 0.0}, v{0.0, 1.0, 0.0}; // forward, right, up: orthonormal
    double tanH = 1, tanV = 1, far = kInf;
    std::array<Vec3, 4> n;    // unit outward normals: right, left, top, bottom (planes through the apex)
    std::array<Vec3, 4> edge; // unit edge rays

    explicit Frustum(const Camera3& c) {
        f = normalized(c.direction);
        // As the library reads it (ViewFrustum): any non-zero up counts, however tiny; scaled before use, so
        // that a denormal up is not squared to zero (fuzz_culler3d found up = (-5e-324, 0, 0) read as "no up").
        Vec3 up = cameraUp(c); // the default up falls back for cameras looking straight up or down
        Vec3 side = glm::cross(f, up);
        if (!(lengthSquared<3>(side) > 0)) // up parallel to direction: invalid camera; any frame will do
            side = glm::cross(f, std::abs(f.x) < 0.9 ? Vec3{1.0, 0.0, 0.0} : Vec3{0.0, 0.0, 1.0});
        r = normalized(side);
        v = glm::cross(r, f);
        tanV = std::tan(0.5 * c.fovDeg * kPi / 180.0);
        tanH = c.aspect * tanV;
        far = c.far;
        const double sh = std::sqrt(1 + tanH * tanH), sv = std::sqrt(1 + tanV * tanV);
        n = {(r - tanH * f) / sh, (-r - tanH * f) / sh, (v - tanV * f) / sv, (-v - tanV * f) / sv};
        edge = {normalized(f + tanH * r + tanV * v), normalized(f - tanH * r + tanV * v),
                normalized(f + tanH * r - tanV * v), normalized(f - tanH * r - tanV * v)};
    }

    bool contains(const Vec3& q, double eps) const {
        for (const Vec3& nn : n)
            if (glm::dot(nn, q) > eps) return false;
        return !(lengthSquared<3>(q) > (far + eps) * (far + eps));
    }
    // An in-plane unit vector of side plane i (v lies in the left/right planes, r in the top/bottom ones).
    Vec3 inPlane(int i) const { return i < 2 ? v : r; }
};

/// Sutherland-Hodgman: keeps the part of the convex polygon with dot(n, p) <= e.
std::vector<Vec3> clipPolygon(const std::vector<Vec3>& poly, const Vec3& n, double e);

/// Whether the closed object, grown by eps, meets the closed view region (see touchesViewRegion3D).
bool sphereTouchesView(const Obj& o, const Frustum& fr, double eps);
bool polyTouchesView(const Obj& o, const Frustum& fr, double eps);
bool boxTouchesView(const Obj& o, const Frustum& fr, double eps);

} // namespace rgvc::reference::detail
