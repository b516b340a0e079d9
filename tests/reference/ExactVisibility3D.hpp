// 3D visibility reference: the ground truth the 3D culler tests and benchmarks compare against.
//
// Definition (the contract's, /work/shared/scene-format.md "Visibility"): object X is visible when some
// point p of X (a closed set) lies in the closed view region and the open segment camera..p meets the
// interior of no other object. The 3D view region is the closed symmetric perspective frustum with apex
// at the camera (vertical fov fovDeg, horizontal half-angle tan = aspect * tan(fov/2), `up` default
// (0, 1, 0), no near plane), intersected with the closed ball of radius `far` around the camera.
//
// Seam fusion (occluder fusion in any grid culler implies it, as in ExactVisibility2D): a ray is also
// blocked where it runs, over a piece of positive length, inside the interior of the *union* of the
// other objects without entering any single interior, i.e. along a face shared by two boxes (or along
// the edge where four boxes of a wall meet). Among spheres and boxes only boxes can share a face: two
// spheres, or a sphere and a box, touch at a single point, and the union's interior never holds that
// point; a sphere's boundary holds no segment, so a piece of ray of positive length can run between
// interiors only on box faces. So the rule looks at boxes only (and a ray through the point where a
// sphere rests on a box, or where two spheres touch, passes), by a probe: the part of the segment
// lying on box boundaries is cut into elementary pieces (at every box's entry/exit distance); at the
// midpoint m of a piece longer than 1e3*eps the segment is blocked when all 16 points
// m + delta*(cos a * e1 + sin a * e2) (e1, e2 an
// orthonormal basis of the plane perpendicular to the ray, a = k*22.5 degrees, delta in [10, 1e4]*eps)
// lie in the closed union of the boxes other than X. A ray along a single box face, or along an edge
// where two boxes touch only along that edge, has uncovered probes and passes.
//
// Method: exact 3D visibility is hard, so this is a *sampled* reference. An object is reported visible
// when one of these rays from the camera shows it:
//   1. it contains the camera (the apex is in the view region and the segment is empty);
//   2. a dense grid of (gridDivisions+1)^2 rays spread uniformly in angle over the frustum, its four
//      boundary planes and four edge rays included;
//   3. rays aimed at target points on the object itself, each kept when the point lies in the view
//      region: the point nearest the camera; spheres: the centre, the silhouette circle as seen from the
//      camera (8*targetDivisions points) and targetDivisions-1 rings of 4*targetDivisions points on the
//      cap facing the camera; boxes: the 8 corners, targetDivisions-1 points inside each of the 12 edges
//      and a (targetDivisions-1)^2 grid inside each face that faces the camera (or holds it in its
//      plane); where a frustum side plane cuts the object: the cut circle (spheres, 4*targetDivisions
//      points) or the cut polygon's sides (boxes, targetDivisions+1 points each), and the exact points
//      where that cut curve meets the other side planes and the far sphere; where the far sphere cuts the
//      object: the cut circle (spheres) or the circles on each face plane (boxes, 4*targetDivisions
//      points each, kept inside the face) and the points where box edges pierce the far sphere;
//   4. critical rays, independent of the densities: on the sphere of directions every object's outline
//      is a curve (a sphere's silhouette circle; the great-circle arcs of a box's 12 edges; the
//      frustum's 4 sides). A visible part of X is a face of the arrangement of these curves; a face
//      bounded by two or more curves has a vertex (a crossing of two curves, a box corner, a frustum
//      corner), one bounded by a single curve is bounded by X's own outline (which the targets sample),
//      and the ray through a vertex of a visible face sees X too (interiors are open, so visibility is a
//      closed condition in the direction). So a ray through every crossing of two outlines (or of one
//      outline and a frustum side) and every box corner finds X through pinholes and slivers of any size.
// A ray to a target of X checks X only; grid and critical rays check every object. Along a ray, X's
// first point (clamped at the camera) must be within far and the open segment before it must meet no
// blocker.
//
// What it can still miss (documented limitation): faces of the arrangement bounded also by curves that
// are not outlines: where X cuts into another object, and where the far sphere cuts X. A part of X seen
// only in a tiny face bounded by such a curve and missed by the grid and targets is missed. So it may
// under-report, never over-report beyond eps: culler tests use it as "every object the reference sees
// must be in the PVS". Checked offline against an independent brute force of the literal rule (20000
// random surface points per object the reference calls hidden although it is in the view region) on
// 5000 random scenes, 9808 such objects: the brute force saw none of them (without the critical rays
// it saw 5 of 3163 in 1000 dense scenes, all in pinholes and slivers; the test "random surface points"
// repeats this on a small scale). Sample sets are nested when gridDivisions and targetDivisions
// double (the same directions bit for bit), so denser sampling never loses an object.
//
// Convex polytopes (oriented boxes, hulls) are handled like boxes with any number of faces: clipped by
// their planes, targets on their vertices, edges and camera-facing triangles (and the plane and far cuts),
// their edges' arcs in the outlines, their vertices as critical rays; flat faces take part in the seam rule
// like box faces.
//
// Triangle meshes (MeshSolid) are two things, as in the culler (MeshSolid.hpp's separate models): as the
// object seen, their hull (a polytope as above: what the culler reports is a superset of the mesh's own
// visibility, and the reference checks that superset); as a blocker, a closed mesh's solid: a ray is
// blocked where it runs inside the solid's interior for more than 2*eps of its length (MeshInterior3D.cpp:
// watertight crossing counts, so a ray through an edge or vertex counts its crossing once; a line whose
// crossings do not pair up is not blocked). An open mesh blocks nothing. Meshes take no part in the seam
// rule (it only hides more). Their edges join the outlines and their vertices the critical rays.
//
// Tolerances (one length eps, world units; default 1e-12 times the scene's largest coordinate or radius,
// camera included; see sceneEpsilon3D): floating point may only make the reference report MORE visible
// objects: targets are grown by eps (a ray passing within eps of X hits X), blockers are shrunk by eps (a
// ray must pass deeper than eps into Y to be blocked), far and the frustum planes are loosened by eps.
// The seam rule is the only one that hides more; it needs a piece longer than 1e3*eps within eps of
// boxes and probes at delta <= 1e4*eps, so a real gap wider than ~1e4*eps is never fused.
//
// Cost: O(((gridDivisions+1)^2 + targets + critical rays) * N) ray/object clips at worst, with O(N^2)
// outline pairs; grid rays skip the objects whose bounding sphere's angular range misses them
// (cullRays), so a ray costs about the number of objects it passes near, and the search stops once
// every object whose bounding sphere meets the view region is seen. Measured: see the test "cost per
// call" in test_reference3d.cpp (a few milliseconds for 50 objects at the defaults). Clarity over speed.
#pragma once

#include "rgvc/grid/Camera.hpp"
#include "rgvc/grid/Shapes.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace rgvc::reference {

struct Visibility3DOptions {
    /// [World units] the tolerance described above; <= 0 picks sceneEpsilon3D.
    double eps = 0;
    /// Apply the seam (shared box face) rule. false = the contract's definition taken literally.
    bool fuseSeams = true;
    /// The ray grid spans the frustum with (gridDivisions + 1)^2 rays, edges included; 0 = no grid.
    int gridDivisions = 256;
    /// Density of the target points on each object (see above); 0 = no targets (grid rays only).
    int targetDivisions = 16;
    /// Skip, per grid ray, the objects whose bounding sphere's angular range (plus a grid step) misses
    /// it. Same answers (a test checks it), much faster; false only to cross-check that.
    bool cullRays = true;
    /// Cast the critical rays (see above): through every crossing of two objects' outlines (or of one
    /// outline and the frustum's sides) and every box corner. false: sampling only.
    bool criticalRays = true;
};

/// How an object was first found visible (steps 1 to 4 above).
enum class Seen3D : std::uint8_t { No, ContainsCamera, GridRay, TargetRay, CriticalRay };

/// What one call did, for tests and curiosity.
struct Visibility3DStats {
    std::size_t gridRays = 0;     ///< grid rays cast (rays near no object are skipped when cullRays)
    std::size_t targets = 0;      ///< target points generated (objects not yet visible only)
    std::size_t targetRays = 0;   ///< of those, in the view region and cast
    std::size_t criticalRays = 0; ///< critical rays cast (in the frustum, near some object not yet seen)
    std::size_t seamBlocked = 0;  ///< rays (grid ray/object pairs or target rays) blocked by the seam rule only
    double eps = 0;               ///< the tolerance used
    /// Per object: the first point of it seen (world units), where visible; how it was found.
    std::vector<Vec3> witness;
    std::vector<Seen3D> seen;
};

/// For each object index, whether the reference sees it from `camera` (rays as described above).
/// @param objects  valid shapes (see validateShape) in world units.
/// @param camera   valid 3D camera (see validateCamera) in world units.
std::vector<bool> visible3D(const std::vector<Shape<3>>& objects, const Camera3& camera,
                            const Visibility3DOptions& options = {}, Visibility3DStats* stats = nullptr);

/// True when point p lies in the closed view region (frustum cut by far), each plane and far loosened
/// by eps (world units; 0 = exact up to rounding).
bool pointInView3D(const Camera3& camera, const Vec3& p, double eps = 0);

/// True when the closed shape meets the closed view region, loosened by eps (<= 0: sceneEpsilon3D of the
/// shape). Exact up to eps: spheres by projection onto the frustum cone (then onto the far ball), boxes
/// by clipping their faces against the side planes and the distance of the clipped faces to the camera.
/// Occlusion ignored: the VFC set.
bool touchesViewRegion3D(const Shape<3>& shape, const Camera3& camera, double eps = 0);

/// touchesViewRegion3D for every object, with one eps (sceneEpsilon3D) for the whole scene.
std::vector<bool> inViewRegion3D(const std::vector<Shape<3>>& objects, const Camera3& camera);

/// The default eps: 1e-12 * max(largest |coordinate| of camera and objects, largest radius), or 1e-12
/// when everything is zero.
double sceneEpsilon3D(const std::vector<Shape<3>>& objects, const Camera3& camera);

} // namespace rgvc::reference
