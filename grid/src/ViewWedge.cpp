#include "rgvc/grid/ViewWedge.hpp"

#include <algorithm>
#include <cmath>

namespace rgvc {

namespace {
constexpr double kPi = 3.14159265358979323846;
Vec2 rotate(const Vec2& v, double a) {
    double c = std::cos(a), s = std::sin(a);
    return {c * v.x - s * v.y, s * v.x + c * v.y};
}
} // namespace

ViewWedge::ViewWedge(const Camera2& camera, const GridGeometry2& grid)
    : ViewWedge(grid.toLocal(camera.position), camera.direction, camera.fovDeg * kPi / 180.0,
                std::isinf(camera.far) ? camera.far : grid.toLocalLength(camera.far),
                grid.conversionSlack(std::max(std::abs(camera.position.x), std::abs(camera.position.y)))) {}

ViewWedge::ViewWedge(const Vec2& apex, const Vec2& direction, double fovRad, double far, double slack)
    : m_apex(apex), m_fov(fovRad), m_far(far), m_slack(slack) {
    m_dir = safeNormalize<2>(direction);
    // fov within 1e-12 of a full turn is a full turn: the two edges coincide and the complement is empty.
    m_full = fovRad >= 2 * kPi - 1e-12;
    m_convex = fovRad < kPi;
    double h = 0.5 * fovRad;
    m_edgeCw = rotate(m_dir, -h);
    m_edgeCcw = rotate(m_dir, h);
    m_n1 = {-m_edgeCw.y, m_edgeCw.x};  // the wedge lies counter-clockwise of its clockwise edge
    m_n2 = {m_edgeCcw.y, -m_edgeCcw.x}; // and clockwise of its counter-clockwise edge
}

bool ViewWedge::containsPoint(const Vec2& p) const {
    Vec2 r = p - m_apex;
    if (!std::isinf(m_far) && lengthSquared<2>(r) > (m_far + m_slack) * (m_far + m_slack))
        return false;
    if (m_full) return true;
    double s1 = glm::dot(m_n1, r), s2 = glm::dot(m_n2, r);
    if (m_convex) return s1 >= -m_slack && s2 >= -m_slack;
    return !(s1 < -m_slack && s2 < -m_slack);
}

bool ViewWedge::withinFar(const Vec2& lo, const Vec2& hi) const {
    if (std::isinf(m_far)) return true;
    // The wedge and the disc are tested separately by touchesBox, which can only over-report.
    const Vec2 nearest = glm::clamp(m_apex, lo, hi);
    const double r = m_far + m_slack;
    return lengthSquared<2>(nearest - m_apex) <= r * r;
}

bool ViewWedge::touchesWedge(const Vec2& lo, const Vec2& hi) const {
    const double eps = m_slack;
    if (m_full) return true;
    // Fast path (most voxels of a traversed ring): the box's centre lies in the wedge.
    {
        const Vec2 r = 0.5 * (lo + hi) - m_apex;
        const double s1 = glm::dot(m_n1, r), s2 = glm::dot(m_n2, r);
        if (m_convex ? (s1 >= 0 && s2 >= 0) : (s1 >= 0 || s2 >= 0)) return true;
    }
    if (m_apex.x >= lo.x - eps && m_apex.x <= hi.x + eps && m_apex.y >= lo.y - eps && m_apex.y <= hi.y + eps)
        return true;

    const Vec2 corners[4] = {{lo.x, lo.y}, {hi.x, lo.y}, {lo.x, hi.y}, {hi.x, hi.y}};
    if (!m_convex) {
        // The complement of the wedge is an open convex cone; the box misses the wedge iff all its corners
        // lie strictly inside that cone.
        for (const Vec2& c : corners) {
            Vec2 r = c - m_apex;
            if (!(glm::dot(m_n1, r) < -eps && glm::dot(m_n2, r) < -eps)) return true;
        }
        return false;
    }

    // Convex wedge vs box: separating-axis test over the wedge's two edge normals and the box's two axes.
    bool allOut1 = true, allOut2 = true;
    for (const Vec2& c : corners) {
        Vec2 r = c - m_apex;
        allOut1 = allOut1 && glm::dot(m_n1, r) < -eps;
        allOut2 = allOut2 && glm::dot(m_n2, r) < -eps;
    }
    if (allOut1 || allOut2) return false;
    // Projection of the wedge onto an axis: unbounded on a side iff some direction of the arc points
    // there; the arc's extreme x is at an edge or at the axis direction itself when the arc contains it.
    auto arcContains = [&](const Vec2& u) { return glm::dot(m_n1, u) >= 0 && glm::dot(m_n2, u) >= 0; };
    for (int axis = 0; axis < 2; ++axis) {
        Vec2 u{0.0};
        u[axis] = 1;
        bool reachesPos = m_edgeCw[axis] > 0 || m_edgeCcw[axis] > 0 || arcContains(u);
        bool reachesNeg = m_edgeCw[axis] < 0 || m_edgeCcw[axis] < 0 || arcContains(-u);
        if (!reachesPos && lo[axis] > m_apex[axis] + eps) return false;
        if (!reachesNeg && hi[axis] < m_apex[axis] - eps) return false;
    }
    return true;
}

} // namespace rgvc
