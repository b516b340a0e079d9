// Exact 2D visibility: the reference every culler test and benchmark compares against.
//
// Definition (the contract's, /work/shared/scene-format.md "Visibility"): object X is visible when some
// point p of X (a closed set) lies in the closed view region (the wedge of angular width fovDeg centred
// on the camera direction, apex at the camera, cut by the closed disc of radius `far`) and the open
// segment camera..p meets the interior of no other object.
//
// One refinement, because occluder fusion in any grid culler implies it: objects that touch along an
// edge are fused. A ray running exactly along a zero-width seam between two objects that touch along an
// edge (one object's closed set on each side of the ray) is blocked. It is implemented by a
// perpendicular probe: the part of the segment lying on object boundaries is cut into elementary pieces
// (at every object's entry/exit distance); at the midpoint m of a piece the segment is blocked when
// m + delta*n and m - delta*n (n the ray's normal) both lie in the closed union of the objects other
// than X. Two objects touching at a single point do not fuse: a ray through that point passes.
//
// Method: analytic angular sweep around the camera. Visibility along a ray changes only at "critical"
// directions: towards polygon/box vertices, tangent to circles, the two wedge edges, towards pairwise
// intersection points of object boundaries, and towards crossings of the far circle with object
// boundaries. Between two consecutive critical directions the status of every object is constant, so
// casting one ray at every critical direction and one in the middle of every gap between them is exact.
//
// Tolerances (all one length `eps`, world units; default 1e-12 times the largest coordinate magnitude
// in the scene, camera included): the reference decides a slightly *relaxed* problem, so that floating
// point can only make it report more, never fewer, visible objects than the exact answer:
//   - targets are grown by eps (a ray passing within eps of X hits X),
//   - blockers are shrunk by eps (a ray must pass deeper than eps into Y to be blocked by it),
//   - the far distance is grown by eps.
// The only rule that can hide more is the seam rule; it needs the ray to lie within eps of both
// touching objects over a piece longer than 1e3*eps, and probes at delta >= 10*eps, so a real gap wider
// than about delta (at most 1e4*eps) is never fused. Double rounding of the inputs (~1e-16 relative)
// is far below eps; the culler's own slack (1e-9 voxel) is far above it for the scenes the tests build.
//
// Cost: O(K * N) ray/object clips for N objects and K critical directions (K = O(N + pairwise
// boundary intersections)); a few milliseconds for 60 objects. Reference code: clarity over speed.
#pragma once

#include "rgvc/grid/Camera.hpp"
#include "rgvc/grid/Shapes.hpp"

#include <cstddef>
#include <vector>

namespace rgvc::reference {

struct ExactOptions {
    /// [World units] the tolerance described above; <= 0 picks 1e-12 * scene scale (see sceneEpsilon).
    double eps = 0;
    /// Apply the seam (edge fusion) rule. false = the contract's definition taken literally.
    bool fuseSeams = true;
};

/// What one sweep did, for tests and curiosity.
struct ExactStats {
    std::size_t criticalDirections = 0; ///< inside the view wedge, after sorting
    std::size_t rays = 0;               ///< rays cast (criticals + gap midpoints, or the dense count)
    /// Per object: the first point of it seen (world units; the camera + t * ray), where visible.
    /// Failure messages print it, so that a miss comes with the place it should have been seen.
    std::vector<Vec2> witness;
};

/// For each object index, whether it is visible from `camera` (analytic sweep, see above).
/// @param objects  valid shapes (see validateShape) in world units; polygons in either winding.
/// @param camera   valid camera (see validateCamera) in world units.
std::vector<bool> exactVisible2D(const std::vector<Shape<2>>& objects, const Camera2& camera,
                                 const ExactOptions& options = {}, ExactStats* stats = nullptr);

/// Brute-force cross-check: the same per-ray test on `rays` directions spread evenly over the wedge
/// (both edges included). Finds a subset of exactVisible2D: it misses objects seen only through gaps
/// narrower than the ray spacing, and objects seen only along one critical ray (a grazing ray, a
/// pinhole). Only for validating the analytic sweep; never use it as the reference.
std::vector<bool> denseRaycastVisible2D(const std::vector<Shape<2>>& objects, const Camera2& camera,
                                        int rays = 20000, const ExactOptions& options = {});

/// True when the closed shape meets the closed view region (wedge cut by far), within eps (grown, so
/// conservative in the same direction as exactVisible2D). Occlusion ignored: the VFC set.
bool touchesViewRegion(const Shape<2>& shape, const Camera2& camera, double eps = 0);

/// touchesViewRegion for every object, with one eps for the whole scene.
std::vector<bool> inViewRegion2D(const std::vector<Shape<2>>& objects, const Camera2& camera);

/// The default eps: 1e-12 * max(largest |coordinate| of camera and objects, largest radius), or 1e-12
/// when everything is zero.
double sceneEpsilon(const std::vector<Shape<2>>& objects, const Camera2& camera);

} // namespace rgvc::reference
