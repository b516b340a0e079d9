// Choosing the voxel size: recommendVoxelSize.
//
//   std::vector<rgvc::Shape<3>> shapes = ...;                       // the scene's objects, world units
//   const double v = rgvc::recommendVoxelSize<3>(shapes, worldBox);
//   rgvc::GridGeometry3 grid(worldBox.min, v, rgvc::IVec3(glm::ceil((worldBox.max - worldBox.min) / v)));
//
// Why it matters. Occlusion comes from O, the voxels lying *entirely* inside an object (seed 004 §5.1),
// so an object occludes through the grid only when it is at least about two voxels thick; the
// occlusion image (3D) covers smaller ones, but costs per object. Smaller voxels make more objects
// opaque and the PVS tighter, but every object's footprint, the traversal's bricks and the memory grow
// with (size / voxel)^D. The game world of rgvc_bench_classes ran 76 ms per frame at 0.5-unit voxels,
// 9.8 at 1, 1.5 at 2 and 0.5 at 4 before the brick tree (README, "Choosing the voxel size", has today's
// figures).
//
// The rule. Each object's "opaque size" is the largest voxel for which it holds a whole voxel wherever
// it lies: a box's smallest extent / 2 (a segment of length 2v holds a whole cell of side v on its axis);
// a ball's radius / sqrt(3) (the voxel nearest the centre has its centre within sqrt(3) v / 2 of it and its
// corners sqrt(3) v / 2 further); a convex polygon's bounding box's smallest extent / 2 (an upper
// bound; polygons are 2D only). The recommendation is the median of these sizes weighted by each object's
// bounding-box surface (area in 2D: perimeter): what hides things is surface, so a few large buildings
// outweigh thousands of small movers, which the image handles anyway. It is then clamped so that the
// grid holds at most `maxVoxels` voxels and at least `minVoxelsPerAxis` along the world's shortest axis.
#pragma once

#include "rgvc/grid/Error.hpp"
#include "rgvc/grid/Shapes.hpp"

#include <algorithm>
#include <cmath>
#include <span>
#include <utility>
#include <vector>

namespace rgvc {

struct VoxelSizeOptions {
    /// [Voxels] [Limit] >= 1. The grid may hold at most this many voxels (memory, traversal cost).
    double maxVoxels = 16.0 * 1024 * 1024;
    /// [Voxels] [Limit] >= 1. At least this many voxels along the world's shortest axis.
    double minVoxelsPerAxis = 8;
};

/// The recommended voxel size for `shapes` in `world` (see the top of the file). [Units] world units.
/// With no shapes, the size that fills maxVoxels (or the minVoxelsPerAxis bound, whichever is larger).
/// @throws InvalidInput ("shapes[i]..." from validateShape, "world" when min < max fails or is not
///         finite, "options" for out-of-range limits).
template <int D>
double recommendVoxelSize(std::span<const Shape<D>> shapes, const Box<D>& world, const VoxelSizeOptions& options = {}) {
    if (!allFinite<D>(world.min) || !allFinite<D>(world.max)) throw InvalidInput("world", "must be finite");
    for (int a = 0; a < D; ++a)
        if (!(world.min[a] < world.max[a])) throw InvalidInput("world", "max must exceed min on every axis");
    if (!(options.maxVoxels >= 1) || !std::isfinite(options.maxVoxels))
        throw InvalidInput("options.maxVoxels", "must be finite and >= 1");
    if (!(options.minVoxelsPerAxis >= 1) || !std::isfinite(options.minVoxelsPerAxis))
        throw InvalidInput("options.minVoxelsPerAxis", "must be finite and >= 1");

    double volume = 1, shortest = world.max[0] - world.min[0];
    for (int a = 0; a < D; ++a) {
        volume *= world.max[a] - world.min[a];
        shortest = std::min(shortest, world.max[a] - world.min[a]);
    }
    const double smallest = std::pow(volume / options.maxVoxels, 1.0 / D); // the grid's voxel budget
    const double largest = shortest / options.minVoxelsPerAxis;

    std::vector<std::pair<double, double>> sized; // (opaque size, weight)
    sized.reserve(shapes.size());
    double total = 0;
    for (std::size_t i = 0; i < shapes.size(); ++i) {
        Shape<D> s = shapes[i];
        validateShape<D>(s, [&] { return "shapes[" + std::to_string(i) + "]"; });
        const Box<D> b = boundsOf<D>(s);
        double minExtent = b.max[0] - b.min[0], weight = 0;
        for (int a = 0; a < D; ++a) minExtent = std::min(minExtent, b.max[a] - b.min[a]);
        if constexpr (D == 3) {
            const Vec3 e = b.max - b.min;
            weight = 2 * (e.x * e.y + e.y * e.z + e.z * e.x);
        } else {
            const Vec2 e = b.max - b.min;
            weight = 2 * (e.x + e.y);
        }
        const auto* ball = std::get_if<Ball<D>>(&s);
        const double opaque = ball != nullptr ? ball->radius / std::sqrt(double(D)) : 0.5 * minExtent;
        if (!(weight > 0) || !std::isfinite(weight) || !std::isfinite(opaque)) continue;
        sized.emplace_back(opaque, weight);
        total += weight;
    }
    double v = std::max(smallest, largest); // no objects: as coarse as the axis bound allows
    if (!sized.empty()) {
        std::sort(sized.begin(), sized.end());
        double acc = 0;
        for (const auto& [size, weight] : sized) {
            acc += weight;
            if (acc >= 0.5 * total) {
                v = size;
                break;
            }
        }
    }
    // The budget wins over the axis bound when they conflict (a very flat world with a small budget).
    return std::max(smallest, std::min(v, std::max(largest, smallest)));
}

} // namespace rgvc
