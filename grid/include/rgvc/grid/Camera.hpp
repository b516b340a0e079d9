// The camera and its view region.
//
// 2D: the view region is the closed wedge of angular width fovDeg (0 < fov <= 360) centred on
// `direction`, apex at `position`. 3D: a symmetric perspective frustum, fovDeg vertical (0 < fov < 180),
// `aspect` = width/height, `up` not parallel to `direction`. Both: optional distance limit `far`
// (the view region is cut by the closed ball of that radius). No near plane.
#pragma once

#include "rgvc/grid/Error.hpp"
#include "rgvc/grid/Math.hpp"

#include <limits>
#include <string>

namespace rgvc {

template <int D> struct Camera {
    Vec<D> position{0.0};  ///< [World units]
    Vec<D> direction{0.0}; ///< Any non-zero length.
    double fovDeg = 90;    ///< [Degrees] 2D: (0, 360]. 3D: vertical, (0, 180).
    double far = std::numeric_limits<double>::infinity(); ///< [World units] > 0; infinity = no limit.
    Vec<D> up{0.0};        ///< 3D only; zero means the default (0, 1, 0).
    double aspect = 1;     ///< 3D only; width / height, > 0.
};

using Camera2 = Camera<2>;
using Camera3 = Camera<3>;

/// @throws InvalidInput ("camera.position", "camera.direction", "camera.fov_deg", "camera.far", ...).
template <int D> inline void validateCamera(const Camera<D>& c, const std::string& field = "camera") {
    if (!allFinite<D>(c.position)) throw InvalidInput(field + ".position", "must be finite");
    if (!allFinite<D>(c.direction)) throw InvalidInput(field + ".direction", "must be finite");
    bool nonZero = false;
    for (int i = 0; i < D; ++i) nonZero = nonZero || c.direction[i] != 0;
    if (!nonZero) throw InvalidInput(field + ".direction", "must be non-zero");
    double maxFov = D == 2 ? 360.0 : 180.0;
    bool fovOk = std::isfinite(c.fovDeg) && c.fovDeg > 0 && (D == 2 ? c.fovDeg <= maxFov : c.fovDeg < maxFov);
    if (!fovOk)
        throw InvalidInput(field + ".fov_deg", std::string("must be in (0, ") + (D == 2 ? "360]" : "180)") +
                                                   ", got " + std::to_string(c.fovDeg));
    if (std::isnan(c.far) || !(c.far > 0)) throw InvalidInput(field + ".far", "must be > 0");
    if constexpr (D == 3) {
        if (!allFinite<3>(c.up)) throw InvalidInput(field + ".up", "must be finite");
        if (!std::isfinite(c.aspect) || !(c.aspect > 0)) throw InvalidInput(field + ".aspect", "must be > 0");
    }
}

} // namespace rgvc
