#include "rgvc/grid/ViewFrustum.hpp"

#include <algorithm>
#include <cmath>

namespace rgvc {

ViewFrustum::ViewFrustum(const Camera3& camera, const GridGeometry3& grid) {
    constexpr double kPi = 3.14159265358979323846;
    m_apex = grid.toLocal(camera.position);
    m_far = std::isinf(camera.far) ? camera.far : grid.toLocalLength(camera.far);
    double magnitude = 0;
    for (int a = 0; a < 3; ++a) magnitude = std::max(magnitude, std::abs(camera.position[a]));
    m_slack = grid.conversionSlack(magnitude);
    m_forward = safeNormalize<3>(camera.direction);
    const Vec3 up = cameraUp(camera);
    Vec3 right = glm::cross(m_forward, up);
    const double rightLen = std::sqrt(lengthSquared<3>(right));
    if (!(rightLen > 1e-12)) throw InvalidInput("camera.up", "must not be parallel to camera.direction");
    right /= rightLen;
    const Vec3 trueUp = glm::cross(right, m_forward);
    const double tv = std::tan(0.5 * camera.fovDeg * kPi / 180.0);
    const double th = camera.aspect * tv;
    m_right = right;
    m_trueUp = trueUp;
    m_tanHalfWidth = th;
    m_tanHalfHeight = tv;
    // Edges counter-clockwise seen from behind: bottom-left, bottom-right, top-right, top-left.
    const double sx[4] = {-1, 1, 1, -1}, sy[4] = {-1, -1, 1, 1};
    for (int i = 0; i < 4; ++i) m_edges[i] = glm::normalize(m_forward + sx[i] * th * right + sy[i] * tv * trueUp);
    for (int i = 0; i < 4; ++i) {
        Vec3 n = glm::normalize(glm::cross(m_edges[i], m_edges[(i + 1) % 4]));
        if (glm::dot(n, m_forward) < 0) n = -n;
        m_normals[i] = n;
    }
}

bool ViewFrustum::withinFar(const Vec3& lo, const Vec3& hi) const {
    if (std::isinf(m_far)) return true;
    const Vec3 nearest = glm::clamp(m_apex, lo, hi);
    const double r = m_far + m_slack;
    return lengthSquared<3>(nearest - m_apex) <= r * r;
}

bool ViewFrustum::touchesCone(const Vec3& lo, const Vec3& hi) const {
    // The box misses the cone if it lies strictly outside one side plane: test the corner farthest
    // along the inward normal (the "p-vertex").
    for (const Vec3& n : m_normals) {
        const Vec3 p{n.x > 0 ? hi.x : lo.x, n.y > 0 ? hi.y : lo.y, n.z > 0 ? hi.z : lo.z};
        if (glm::dot(n, p - m_apex) < -m_slack) return false;
    }
    return true;
}

bool ViewFrustum::containsPoint(const Vec3& p) const {
    const Vec3 r = p - m_apex;
    if (!std::isinf(m_far) && lengthSquared<3>(r) > (m_far + m_slack) * (m_far + m_slack))
        return false;
    for (const Vec3& n : m_normals)
        if (glm::dot(n, r) < -m_slack) return false;
    return true;
}

} // namespace rgvc
