// The camera and its view region.
//
// 2D: the view region is the closed wedge of angular width fovDeg (0 < fov <= 360) centred on
// `direction`, apex at `position`. 3D: a symmetric perspective frustum, fovDeg vertical (0 < fov < 180),
// `aspect` = width/height, `up` not parallel to `direction`. Both: optional distance limit `far`
// (the view region is cut by the closed ball of that radius). No near plane.
//
// Orthographic cameras (projection = Orthographic; shadow-map cascades, top-down and editor views): the
// view region is the closed box of the points p with 0 <= (p - position) . f <= far, |(p - position) .
// right| <= width / 2 and, in 3D, |(p - position) . trueUp| <= height / 2 (f the unit direction, right and
// trueUp as for the perspective frustum: right = f x up, trueUp = right x f; in 2D right is f turned
// clockwise). `far` is a depth along f here, not a distance; fovDeg and aspect are not read.
#pragma once

#include "rgvc/grid/Error.hpp"
#include "rgvc/grid/Math.hpp"

#include <cstdint>
#include <limits>
#include <string>

namespace rgvc {

/// How a camera projects: rays from its position (Perspective), or parallel to its direction from the
/// plane through its position (Orthographic).
enum class Projection : std::uint8_t { Perspective, Orthographic };

template <int D> struct Camera {
    Vec<D> position{0.0};  ///< [World units]
    Vec<D> direction{0.0}; ///< Any non-zero length.
    double fovDeg = 90;    ///< [Degrees] 2D: (0, 360]. 3D: vertical, (0, 180).
    double far = std::numeric_limits<double>::infinity(); ///< [World units] > 0; infinity = no limit.
    Vec<D> up{0.0};        ///< 3D only; zero means the default (0, 1, 0), or (0, 0, -+1) looking straight down or up (cameraUp).
    double aspect = 1;     ///< 3D only; width / height, > 0.
    Projection projection = Projection::Perspective;
    /// Orthographic only: [World units] [Limit] finite, > 0. The view box's extent across (along right).
    double width = 0;
    /// Orthographic 3D only: [World units] [Limit] finite, > 0. The view box's extent along trueUp.
    double height = 0;
};

using Camera2 = Camera<2>;
using Camera3 = Camera<3>;

/// The up vector every part of rgvc reads from a 3D camera (the grid's frustum, the references, the GL
/// renderer): `up` normalized when it is given (non-zero); else (0, 1, 0), except for a camera looking
/// straight up or down, where (0, 1, 0) spans no image plane with the direction: then (0, 0, -1) looking
/// down and (0, 0, 1) looking up, so a top view has +x to the right and -z at the top of the image.
/// "Straight" is within 1e-9 of the y axis, far above the 1e-12 at which a frame is refused, so that a
/// direction just off the axis keeps the default and still has a well-defined frame.
inline Vec3 cameraUp(const Camera3& c) {
    if (c.up.x != 0 || c.up.y != 0 || c.up.z != 0) return safeNormalize<3>(c.up);
    const Vec3 f = safeNormalize<3>(c.direction);
    if (std::sqrt(f.x * f.x + f.z * f.z) > 1e-9) return {0.0, 1.0, 0.0}; // |f x (0, 1, 0)|
    return {0.0, 0.0, f.y < 0 ? -1.0 : 1.0};
}

/// @throws InvalidInput ("camera.position", "camera.direction", "camera.fov_deg", "camera.far", ...).
template <int D> inline void validateCamera(const Camera<D>& c, const std::string& field = "camera") {
    if (!allFinite<D>(c.position)) throw InvalidInput(field + ".position", "must be finite");
    if (!allFinite<D>(c.direction)) throw InvalidInput(field + ".direction", "must be finite");
    bool nonZero = false;
    for (int i = 0; i < D; ++i) nonZero = nonZero || c.direction[i] != 0;
    if (!nonZero) throw InvalidInput(field + ".direction", "must be non-zero");
    if (c.projection != Projection::Perspective && c.projection != Projection::Orthographic)
        throw InvalidInput(field + ".projection", "must be Perspective or Orthographic");
    const bool ortho = c.projection == Projection::Orthographic;
    if (ortho) {
        if (!std::isfinite(c.width) || !(c.width > 0))
            throw InvalidInput(field + ".width", "must be finite and > 0 for an orthographic camera, got " + std::to_string(c.width));
        if (D == 3 && (!std::isfinite(c.height) || !(c.height > 0)))
            throw InvalidInput(field + ".height", "must be finite and > 0 for an orthographic camera, got " + std::to_string(c.height));
    }
    double maxFov = D == 2 ? 360.0 : 180.0;
    bool fovOk = std::isfinite(c.fovDeg) && c.fovDeg > 0 && (D == 2 ? c.fovDeg <= maxFov : c.fovDeg < maxFov);
    if (!fovOk && !ortho)
        throw InvalidInput(field + ".fov_deg", std::string("must be in (0, ") + (D == 2 ? "360]" : "180)") +
                                                   ", got " + std::to_string(c.fovDeg));
    if (std::isnan(c.far) || !(c.far > 0)) throw InvalidInput(field + ".far", "must be > 0");
    if constexpr (D == 3) {
        if (!allFinite<3>(c.up)) throw InvalidInput(field + ".up", "must be finite");
        if (!ortho && (!std::isfinite(c.aspect) || !(c.aspect > 0))) throw InvalidInput(field + ".aspect", "must be > 0");
    }
}

} // namespace rgvc
