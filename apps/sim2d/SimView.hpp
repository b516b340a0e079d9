// What the simulator draws and where: the layers (seed 004 Figure 1), their colours, and the map's
// placement of the world in the window.
//
// Colours are render/GridPicture.hpp's (rgvc demo's pictures), so both pictures read the same, plus
// the two the picture does not separate: Os (the static part of O) and I (voxels with ids).
#pragma once

#include "SimWorld.hpp"

#include "rgvc/render/GridPicture.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace rgvc::sim {

/// The toggled layers, in the order of their keys 1, 2, ..., 9, 0.
enum class Layer : int {
    Opaque = 0,   ///< O, the moving objects' part (key 1)
    Static,       ///< Os, the static objects' part of O (key 2)
    Occluded,     ///< H (key 3)
    Ids,          ///< I: voxels with a non-empty id list (key 4)
    Tbv,          ///< T: TBV boundaries (key 5)
    View,         ///< the view wedge, line of sight and camera (key 6)
    Visited,      ///< voxels the traversal reached (key 7)
    Occluders,    ///< extended occluders (key 8)
    Pvs,          ///< PVS objects (key 9)
    Hidden,       ///< objects not in the PVS (key 0)
    Count
};
inline constexpr int kLayerCount = int(Layer::Count);
const char* layerName(Layer l);
/// The digit key that toggles layer l (1..9, then 0).
int layerDigit(Layer l);

struct Layers {
    std::array<bool, kLayerCount> on{true, true, true, true, true, true, true, true, true, true};
    bool operator[](Layer l) const { return on[std::size_t(l)]; }
    void toggle(Layer l) { on[std::size_t(l)] = !on[std::size_t(l)]; }
    /// Parses "all", "none" or a comma list of layer names ("pvs,hidden,view"). @throws InvalidInput.
    static Layers parse(const std::string& list);
};

namespace palette {
inline constexpr RGB8 kStaticOpaque{50, 50, 50};   ///< Os (O of the moving objects: picture::kOpaque)
inline constexpr double kIdTintAlpha = 0.45;        ///< I: picture::kIdDot blended over the cell
inline constexpr RGB8 kOutside{228, 228, 232};     ///< the window around the grid
inline constexpr double kObjectAlpha = 0.55;        ///< object fills (PVS picture::kPvs, hidden kHidden)
} // namespace palette

/// The colour of one voxel cell under the enabled layers. Priority as voxelCellColor's: extended
/// occluder > Os > O > T > H > visited > empty, then I tinted over it.
RGB8 layeredVoxelColor(const VoxelState& s, bool staticOpaque, const Layers& layers);

/// World to window pixels: the grid fitted into the window, centred, y up. [Pixels] top-left origin.
struct MapTransform {
    Vec2 worldMin{0.0}, worldMax{1.0}; ///< [World units] the grid box
    double scale = 1;                  ///< [Pixels per world unit]
    Vec2 offset{0.0};                  ///< [Pixels] window position of worldMin.x, worldMax.y

    static MapTransform fit(const Box<2>& bounds, int width, int height);
    Vec2 toWindow(const Vec2& world) const { return {offset.x + (world.x - worldMin.x) * scale, offset.y + (worldMax.y - world.y) * scale}; }
    Vec2 toWorld(const Vec2& pixel) const { return {worldMin.x + (pixel.x - offset.x) / scale, worldMax.y - (pixel.y - offset.y) / scale}; }
};

} // namespace rgvc::sim
