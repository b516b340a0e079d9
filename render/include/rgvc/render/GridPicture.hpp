// A picture of a 2D grid after a cull, in the spirit of the paper's Figure 1 (CPU only, no GL).
//
//   rgvc::Culler2D culler(grid);  ... addObject ...;  culler.cull(camera);
//   rgvc::ImageRGB img = rgvc::drawGridPicture(culler, camera, objects, {});
//   rgvc::writePng("grid.png", img);
//
// Layout: the y axis points up (world y grows towards the top row), the grid fills a square-ish area
// whose longer side is about opt.maxPixels, surrounded by a white margin, with a legend strip below.
// Every voxel is a cell coloured by culler.voxelState(v) (see voxelCellColor); objects are outlined on
// top (PVS objects filled translucent blue, the others outlined red); the view wedge's edges are solid
// black, the line of sight dashed black, the camera a black dot. Everything is clipped to the picture,
// so cameras and objects outside the grid are fine.
#pragma once

#include "rgvc/dynamics/Culler.hpp"
#include "rgvc/render/Image.hpp"

#include <string>
#include <vector>

namespace rgvc {

struct GridPictureOptions {
    int maxPixels = 1024;      ///< [Pixels] about the longer side of the grid area; clamped to [16, 16384].
    int margin = 12;           ///< [Pixels] white border around the grid area, >= 0.
    bool gridLines = true;     ///< thin lines between cells (only drawn when cells are >= 6 px)
    bool markIdVoxels = true;  ///< a small gray dot in voxels with a non-empty id list (cells >= 6 px)
    bool drawObjects = true;
    bool drawView = true;      ///< wedge edges, far arc, line of sight, camera dot
    bool legend = true;        ///< legend strip at the bottom
    bool legendText = true;    ///< labels and the stats line in the legend (5x7 bitmap font)
    std::string caption;       ///< optional first line of the legend, e.g. the scene name
};

/// The colours of the picture.
namespace picture {
inline constexpr RGB8 kEmpty{255, 255, 255};      ///< not reached by the traversal
inline constexpr RGB8 kVisited{255, 246, 196};    ///< reached, not occluded
inline constexpr RGB8 kOpaque{85, 85, 85};        ///< O
inline constexpr RGB8 kOccluded{200, 200, 200};   ///< H
inline constexpr RGB8 kOccluder{92, 38, 118};     ///< part of an extended occluder
inline constexpr RGB8 kTbv{0, 128, 128};          ///< T: a TBV's boundary (the paper draws these black)
inline constexpr RGB8 kIdDot{120, 120, 140};      ///< I-voxel marker
inline constexpr RGB8 kPvs{30, 80, 220};          ///< PVS object fill (translucent) and outline
inline constexpr double kPvsFillAlpha = 0.35;
inline constexpr RGB8 kHidden{220, 30, 30};       ///< object not in the PVS: outline
inline constexpr RGB8 kView{0, 0, 0};             ///< wedge edges, line of sight, camera
inline constexpr RGB8 kText{20, 20, 20};
} // namespace picture

/// The fill colour of a voxel cell. Priority: occluder > opaque > T > occluded > visited > empty.
RGB8 voxelCellColor(const VoxelState& s);

/// Where things land in a picture of a given grid.
struct GridPictureLayout {
    int width = 0, height = 0;          ///< [Pixels] the whole image
    int gridX0 = 0, gridY0 = 0;         ///< [Pixels] top-left corner of the grid area
    int gridWidth = 0, gridHeight = 0;  ///< [Pixels] size of the grid area
    double scaleX = 1, scaleY = 1;      ///< [Pixels per voxel] (equal for integer cell sizes)
    int legendY0 = 0;                   ///< [Pixels] first row of the legend strip (== height without it)
    int textScale = 1;
    Vec2 origin{0.0};                   ///< grid origin, world units
    double voxelSize = 1;               ///< world units

    /// Continuous picture coordinates of a world point (y flipped).
    Vec2 toPicture(const Vec2& world) const;
    /// Continuous picture coordinates of a point in voxel units.
    Vec2 localToPicture(const Vec2& local) const;
    /// The pixel that holds the centre of voxel v (which may lie outside the picture).
    IVec2 voxelCentrePixel(const IVec2& v) const;
    /// The voxel shown by pixel (x, y) of the grid area; the result may lie outside the grid.
    IVec2 voxelAtPixel(int x, int y) const;
};

/// The layout drawGridPicture uses for this grid and these options.
GridPictureLayout gridPictureLayout(const GridGeometry2& grid, const GridPictureOptions& opt = {});

/// Draws the state of the last cull of `culler` (its voxelState and lastResult) for `camera` (the camera
/// of that cull) and `objects` (the objects the culler holds, world units; ids absent from the culler
/// are drawn as hidden). Call after culler.cull(camera).
/// @throws InvalidInput on an invalid camera (see validateCamera).
ImageRGB drawGridPicture(const Culler2D& culler, const Camera2& camera, const std::vector<ObjectDesc<2>>& objects,
                         const GridPictureOptions& opt = {});

} // namespace rgvc
