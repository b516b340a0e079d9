// `rgvc demo` on 3D scenes (Demo3D.cpp): the picture of a culled 3D frame, a top view of the grid beside
// the view from the camera.
#pragma once

#include "rgvc/dynamics/Culler.hpp"
#include "rgvc/render/Image.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace rgvc::cli {

struct Demo3DResult {
    ImageRGB image;
    std::uint64_t pixelsCovered = 0;        ///< view pixels whose centre ray hits an object
    std::uint64_t pixelsShownButCulled = 0; ///< of those, pixels that see an object not in the PVS (a miss; must be 0)
};

/// Draws the culler's last frame. `objects` [World units] are the objects at that frame (shape, role).
/// @param size  [Pixels] about the width of each of the two panels times 2 (>= 128).
Demo3DResult drawDemo3D(const Culler3D& culler, const Camera3& camera, const std::vector<ObjectDesc<3>>& objects,
                        int size, const std::string& caption);

} // namespace rgvc::cli
