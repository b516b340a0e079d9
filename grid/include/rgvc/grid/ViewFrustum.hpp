// The 3D view region in voxel units: a symmetric perspective frustum with apex at the camera and no
// near plane, optionally cut by the closed ball of radius `far`; and the conservative box tests.
#pragma once

#include "rgvc/grid/Camera.hpp"
#include "rgvc/grid/GridGeometry.hpp"
#include "rgvc/grid/Math.hpp"

namespace rgvc {

class ViewFrustum {
public:
    ViewFrustum() = default;
    /// @param camera  validated camera (see validateCamera), world units. `up` zero means (0, 1, 0).
    /// @throws InvalidInput ("camera.up") when up is parallel to the direction.
    ViewFrustum(const Camera3& camera, const GridGeometry3& grid);

    const Vec3& apex() const { return m_apex; }
    const Vec3& forward() const { return m_forward; }
    /// Unit vectors of the image: right = forward x up, trueUp = right x forward (orthonormal with forward).
    const Vec3& right() const { return m_right; }
    const Vec3& trueUp() const { return m_trueUp; }
    /// Half extents of the image on the plane at distance 1 along forward: the view's directions are
    /// forward + x right + y trueUp with |x| <= tanHalfWidth(), |y| <= tanHalfHeight().
    double tanHalfWidth() const { return m_tanHalfWidth; }
    double tanHalfHeight() const { return m_tanHalfHeight; }
    double far() const { return m_far; }
    /// [Voxel units] tolerance of the touch tests: the grid's conversionSlack().
    double slack() const { return m_slack; }
    /// Unit directions of the four edge rays (the frustum is the cone they span).
    const Vec3& edge(int i) const { return m_edges[i]; }
    /// Inward unit normals of the four side planes through the apex.
    const Vec3& sideNormal(int i) const { return m_normals[i]; }

    /// Conservative: true whenever the closed box meets the closed view region. Tests the four side
    /// planes and the far ball separately, so it may also answer true for boxes near the frustum's edges
    /// (never false for a box that touches it).
    bool touchesBox(const Vec3& lo, const Vec3& hi) const { return withinFar(lo, hi) && touchesCone(lo, hi); }
    bool touchesVoxel(const IVec3& v) const { return touchesBox(Vec3(v), Vec3(v) + 1.0); }
    bool touchesCone(const Vec3& lo, const Vec3& hi) const;
    bool withinFar(const Vec3& lo, const Vec3& hi) const;
    bool containsPoint(const Vec3& p) const;

private:
    Vec3 m_apex{0.0}, m_forward{0.0, 0.0, -1.0}, m_right{1.0, 0.0, 0.0}, m_trueUp{0.0, 1.0, 0.0};
    double m_tanHalfWidth = 1, m_tanHalfHeight = 1;
    Vec3 m_edges[4]{};
    Vec3 m_normals[4]{};
    double m_far = 0, m_slack = kConservativeSlack;
};

} // namespace rgvc
