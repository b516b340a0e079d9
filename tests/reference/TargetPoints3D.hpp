// Target points of the 3D reference (step 3 of ExactVisibility3D.hpp's method): per shape, the points on
// it that rays are aimed at. Internal to the reference.
#pragma once

#include "SegmentClip3D.hpp"

#include <vector>

namespace rgvc::reference::detail {

/// k / n as a double (computed as integer / integer, so that the sample sets for divisions d and 2d are
/// nested bit for bit).
inline double frac(int k, int n) { return double(k) / double(n); }

/// Target points (camera-relative) of a ball, a box and a convex polytope at density d, appended to out.
void sphereTargets(const Obj& o, const Frustum& fr, int d, std::vector<Vec3>& out);
void boxTargets(const Obj& o, const Frustum& fr, int d, std::vector<Vec3>& out);
void polyTargets(const Obj& o, const Frustum& fr, int d, std::vector<Vec3>& out);

} // namespace rgvc::reference::detail
