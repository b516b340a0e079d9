// The 2D view region in voxel units, and the conservative "does this box touch it" test.
#pragma once

#include "rgvc/grid/Camera.hpp"
#include "rgvc/grid/GridGeometry.hpp"
#include "rgvc/grid/Math.hpp"

namespace rgvc {

/// Closed wedge with apex `apex`, angular width `fov` (radians, (0, 2*pi]) centred on unit `dir`,
/// optionally cut by the closed disc of radius `far` around the apex. All in voxel units.
class ViewWedge {
public:
    ViewWedge() = default;
    /// @param camera  validated camera (see validateCamera), world units.
    ViewWedge(const Camera2& camera, const GridGeometry2& grid);
    /// Same, already in voxel units. @param slack  [Voxel units] tolerance of the touch tests.
    ViewWedge(const Vec2& apex, const Vec2& direction, double fovRad, double far, double slack = kConservativeSlack);

    const Vec2& apex() const { return m_apex; }
    const Vec2& direction() const { return m_dir; }
    double fov() const { return m_fov; }
    double far() const { return m_far; }
    bool isFullCircle() const { return m_full; }
    /// Narrower than 180 degrees (a convex wedge).
    bool isConvex() const { return m_convex; }
    /// [Voxel units] kConservativeSlack, or the grid's conversionSlack() when built from world units.
    double slack() const { return m_slack; }
    /// Unit directions of the two bounding rays (clockwise edge first).
    const Vec2& edgeCw() const { return m_edgeCw; }
    const Vec2& edgeCcw() const { return m_edgeCcw; }

    /// Conservative: true whenever the closed box [lo, hi] intersects the closed view region, and
    /// possibly when it misses it by less than slack(). Exact otherwise (separating-axis test).
    bool touchesBox(const Vec2& lo, const Vec2& hi) const { return withinFar(lo, hi) && touchesWedge(lo, hi); }
    bool touchesVoxel(const IVec2& v) const { return touchesBox(Vec2(v), Vec2(v) + 1.0); }

    /// The wedge alone, ignoring `far` (same conservative semantics).
    bool touchesWedge(const Vec2& lo, const Vec2& hi) const;
    bool voxelTouchesWedge(const IVec2& v) const { return touchesWedge(Vec2(v), Vec2(v) + 1.0); }
    /// The far disc alone: the box has a point within far (+ slack) of the apex. Always true without far.
    bool withinFar(const Vec2& lo, const Vec2& hi) const;
    bool voxelWithinFar(const IVec2& v) const { return withinFar(Vec2(v), Vec2(v) + 1.0); }

    /// True when p lies in the closed region (with the same slack).
    bool containsPoint(const Vec2& p) const;

private:
    Vec2 m_apex{0.0}, m_dir{1.0, 0.0};
    double m_fov = 0, m_far = 0, m_slack = kConservativeSlack;
    bool m_full = false;
    bool m_convex = true; // fov < pi: the wedge is the intersection of two closed half-planes
    Vec2 m_edgeCw{0.0}, m_edgeCcw{0.0};
    // Inward normals of the two bounding lines. For fov < pi the wedge is {n1.(p-a) >= 0} and {n2.(p-a) >= 0};
    // for fov >= pi its complement is the open convex cone {n1.(p-a) < 0} and {n2.(p-a) < 0}.
    Vec2 m_n1{0.0}, m_n2{0.0};
};

} // namespace rgvc
