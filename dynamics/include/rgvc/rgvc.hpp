// rgvc: conservative visibility culling for dynamic 2D (top-view) and 3D worlds on a regular voxel grid.
// The one header a game includes. After Batagelo & Wu, "Dynamic scene occlusion culling using a regular
// grid" (SIBGRAPI 2002), cited below as "seed 004 §n".
//
// ------------------------------------------------------------------------------------------------
// Conventions
// ------------------------------------------------------------------------------------------------
// Axes      2D: x, y (top view). 3D: x, y, z with y up (a camera's default `up` is +y). Right-handed.
// Units     World units at the API (positions, sizes, speeds per frame); angles in degrees
//           (Camera::fovDeg). Internally: voxel units, local(p) = (p - origin) / voxelSize.
// Voxels    Cubic, edge voxelSize. Voxel v covers the CLOSED box [origin + v*d, origin + (v+1)*d];
//           neighbours share faces; the grid covers [origin, origin + d*resolution] (closed).
//           Indices are x-fastest (GridGeometry::linearIndex). 2D grids: at most 2^20 voxels per
//           axis; all grids: at most 2^31 - 1 voxels.
// Shapes    Closed sets: circle/sphere (Ball), axis-aligned box (Box), convex polygon (2D).
// View      2D: closed wedge of width fovDeg in (0, 360] around `direction`, apex at `position`.
//           3D: symmetric perspective frustum, vertical fovDeg in (0, 180), `aspect` = w/h, no near
//           plane. Optional `far`: the region is cut by the closed disc/ball of that radius.
// Visible   An object is visible if some point of it lies in the view region and the open segment
//           from the camera to that point meets no other object's interior. Objects touching along
//           an edge or face are fused (a zero-width seam lets no sight through): this is what occluder
//           fusion means, and the exact references in tests/reference use the same rule.
// Conservative
//           Culler::cull returns a SUPERSET of the visible objects: never a miss. Every stage errs
//           one way: O (opaque voxels) only under-estimates the objects' interiors, I (object ids per
//           voxel) only over-estimates their extent, H (occluded voxels) holds only voxels hidden from
//           EVERY point of the camera's voxel, the traversal visits every voxel the closed view region
//           touches until a layer that blocks every ray. Objects or cameras outside the grid take a
//           view-region-only fallback, reported in CullStats. Floating point errs the same way (see
//           kConservativeSlack and GridGeometry::conversionSlack).
// Frames    One frame = one cull() call. maxSpeed is in world units per frame. A hidden moving object
//           is held by a temporal bounding volume (TBV) that contains it until it expires (seed 004
//           §4.1); with boundary TBVs the camera voxel should move at most one voxel per axis per
//           frame, and larger moves cost a check of every TBV (CullStats::cameraJump), never a miss.
// Errors    Public functions validate first and throw rgvc::InvalidInput ("field: what"), leaving the
//           object unchanged. Per-frame work never throws and never allocates per voxel; a failing
//           placement query is reported after the frame has completed conservatively.
// Threads   A Culler is not thread-safe; use one per thread.
//
// Modules: rgvc::grid (geometry, rasterization, traversal, occlusion; no GL/IO) and rgvc::dynamics
// (objects and the per-frame Culler). Scene files, pictures and the CLI live in apps/ and render/.
#pragma once

#include "rgvc/dynamics/Culler.hpp"
#include "rgvc/dynamics/TbbExecutor.hpp"
#include "rgvc/grid/Camera.hpp"
#include "rgvc/grid/Error.hpp"
#include "rgvc/grid/GridGeometry.hpp"
#include "rgvc/grid/Shapes.hpp"
#include "rgvc/grid/VoxelSize.hpp"
