// Ray parameter intervals shared by the exact references (header-only): where the line t * u (t any
// real, u a unit direction from the camera at the origin) lies within `off` of a ball.
#pragma once

#include "rgvc/grid/Math.hpp"

#include <cmath>
#include <limits>

namespace rgvc::reference {

struct Interval {
    double lo = std::numeric_limits<double>::infinity(), hi = -std::numeric_limits<double>::infinity();
    bool empty() const { return !(lo <= hi); }
};

/// Parameters t where t * u lies within `off` of the ball (centre relative to the camera): off > 0 grows
/// the ball, off < 0 keeps only points deeper than -off inside it. Empty when the line misses.
template <int D> Interval clipBall(const Vec<D>& center, double radius, const Vec<D>& u, double off) {
    const double r = radius + off;
    if (!(r > 0)) return {};
    const double b = glm::dot(center, u);
    // r^2 - |perpendicular offset|^2 instead of b^2 - |c|^2 + r^2: no cancellation for far balls.
    const Vec<D> perp = center - b * u;
    const double disc = r * r - lengthSquared<D>(perp);
    if (disc < 0) return {};
    const double s = std::sqrt(disc);
    return {b - s, b + s};
}

} // namespace rgvc::reference
