// The settings rgvc_sweep runs on every scene: a base setting and one-factor-at-a-time variations of it,
// plus a few combinations (not the full cross product: 30 settings in 3D, 15 in 2D, instead of thousands).
//
// Factors (CullerOptions in dynamics/include/rgvc/dynamics/Culler.hpp; the GL stage in render/):
//   resolution  voxel size x0.5, x1 (base), x2, x4 of the scene file's (same world box, so x0.5 has 8x
//               the voxels of x1 in 3D)
//   extension   occluderExtension off (2D: no L-shaped extension; 3D shells: caps of shell k-1 only)
//   core        3D: the brick tree with its occlusion image (base) against the paper's shell caps, with
//               adaptive caps and with caps every frame
//   image       3D: the brick tree's occlusion image rows 32, 64, 128 (base: 0 = chosen from the fov)
//   buffer      the object-space occlusion buffer: 3D rows off, 16, 64 (base), 256; 2D angular bins off, 16,
//               64, 256 (base); and adaptiveBuffer (skips unpaying passes)
//   tbv         temporal bounding volumes: boundary (base), shell (3D), filled, off (re-insert every frame)
//   baseline    occlusion off: grid view-frustum culling only
//   gl          3D: the GL stage after the CPU pipeline: zb (base: draw the CPU PVS), vfc, sw, chc, chcpp
//   nvp         3D: CHC++ with n_vp = 1, 8, 32 (approximate: visible objects may be culled)
// Frame time with drawing is cull + the GL method + glFinish; in 2D the PVS is drawn as prisms (zb only:
// the GL query stage answers for a 3D image, not for the 2D scene's visibility).
#pragma once

#include "rgvc/dynamics/Culler.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace rgvc::bench {

struct SweepSetting {
    std::string name;           ///< unique within a dimension ("base", "voxel x2", "chcpp n_vp 8", ...)
    std::string factor;         ///< the factor varied (see the top), "base" or "combo"
    double voxelScale = 1;      ///< the scene's voxel size times this
    CullerOptions options;      ///< objectsStayInGrid is set per scene (sceneCullerOptions)
    std::string glMethod = "zb"; ///< zb, vfc, sw, chc, chcpp (3D); zb draws the CPU PVS as it is
    std::uint64_t visiblePixels = 0; ///< CHC's n_vp [Samples]; > 0 with a query method is approximate

    /// A GL method that issues occlusion queries (its answer is then the objects it drew).
    bool queries() const { return glMethod == "sw" || glMethod == "chc" || glMethod == "chcpp"; }
    /// n_vp > 0 with a query method: its misses are counted, not a failure.
    bool approximate() const { return queries() && visiblePixels > 0; }
};

/// The settings for scenes of dimension `dims` (2 or 3), base first. quick: a handful (ctest).
std::vector<SweepSetting> sweepSettings(int dims, bool quick);

/// Short descriptions of a setting's options, for the CSV columns.
std::string coreName(const SweepSetting& s, int dims);   ///< "bricks", "shells", "shells-caps-every-frame", "vfc"
std::string bufferName(const SweepSetting& s, int dims); ///< "off", "64 rows", "256 bins", "+adaptive"
std::string tbvName(const CullerOptions& o);             ///< "boundary", "shell", "filled", "off"

} // namespace rgvc::bench
