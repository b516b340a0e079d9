#include "SimView.hpp"

#include "rgvc/grid/Error.hpp"

#include <algorithm>
#include <sstream>

namespace rgvc::sim {

const char* layerName(Layer l) {
    static const char* const names[] = {"o",    "os",      "h",         "i",   "t",
                                        "view", "visited", "occluders", "pvs", "hidden"};
    return int(l) < kLayerCount ? names[int(l)] : "?";
}

int layerDigit(Layer l) { return (int(l) + 1) % 10; }

Layers Layers::parse(const std::string& list) {
    Layers s;
    if (list == "all") return s;
    s.on.fill(false);
    if (list == "none") return s;
    std::istringstream in(list);
    for (std::string name; std::getline(in, name, ',');) {
        bool found = false;
        for (int i = 0; i < kLayerCount; ++i)
            if (name == layerName(Layer(i))) {
                s.on[std::size_t(i)] = true;
                found = true;
            }
        if (!found)
            throw InvalidInput("--layers", "unknown layer '" + name +
                                               "' (all, none, or a list of o, os, h, i, t, view, visited, occluders, pvs, hidden)");
    }
    return s;
}

RGB8 layeredVoxelColor(const VoxelState& s, bool staticOpaque, const Layers& layers) {
    RGB8 c = picture::kEmpty;
    if (s.occluder && layers[Layer::Occluders]) c = picture::kOccluder;
    else if (s.opaque && staticOpaque && layers[Layer::Static]) c = palette::kStaticOpaque;
    else if (s.opaque && !staticOpaque && layers[Layer::Opaque]) c = picture::kOpaque;
    else if (s.hasTbv && layers[Layer::Tbv]) c = picture::kTbv;
    else if (s.occluded && layers[Layer::Occluded]) c = picture::kOccluded;
    else if (s.visited && layers[Layer::Visited]) c = picture::kVisited;
    if (s.hasIds && layers[Layer::Ids]) c = blendColor(c, picture::kIdDot, palette::kIdTintAlpha);
    return c;
}

MapTransform MapTransform::fit(const Box<2>& bounds, int width, int height) {
    MapTransform m;
    m.worldMin = bounds.min;
    m.worldMax = bounds.max;
    const Vec2 extent = bounds.max - bounds.min;
    m.scale = std::min(double(width) / extent.x, double(height) / extent.y);
    // Whole pixels per voxel when the window allows, so cells are drawn pixel-exact.
    m.offset = {std::floor(0.5 * (width - extent.x * m.scale)), std::floor(0.5 * (height - extent.y * m.scale))};
    return m;
}

} // namespace rgvc::sim
