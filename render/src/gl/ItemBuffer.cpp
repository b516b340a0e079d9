#include "rgvc/render/gl/ItemBuffer.hpp"

#include "rgvc/render/gl/GlFramebuffer.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace rgvc {

namespace {

ItemBufferImage render(SceneRenderer& renderer, const Camera3& camera, int width, int height,
                       const std::span<const ObjectId>* subset) {
    validateCamera<3>(camera);
    if (subset)
        for (ObjectId id : *subset) (void)renderer.itemOf(id); // throws for an unknown id before any GL work
    const Camera3 previous = renderer.camera();
    const double previousNear = renderer.cameraNearPlane();
    GlFramebuffer target(renderer.context(), width, height, ColourFormat::R32ui);
    target.clear();
    // The camera in or on drawn objects sees only those objects: every ray starts in their interior or
    // on their surface, and the near plane would cut a hole next to the camera through which the
    // outside shows. "On" within 1e-6 of the scene's extent, the precision of what is drawn.
    const std::vector<ObjectId> all = renderer.ids();
    const double scale = renderer.drawnExtent() + glm::length(camera.position - renderer.anchor());
    const double onSurface = 1e-6 * scale;
    std::vector<bool> contains(all.size());
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < all.size(); ++i) {
        contains[i] = renderer.drawnShapeContains(all[i], camera.position, onSurface);
        if (!contains[i]) nearest = std::min(nearest, renderer.distanceToDrawn(all[i], camera.position));
    }
    // Otherwise the near plane stays nearer than every surface (half the distance to the nearest, at most
    // the renderer's near plane). Taken over all objects, not the subset, and objects drawn in item
    // order either way: an image of a subset then has the depths and tie-breaks of the image of all,
    // pixel for pixel, wherever it holds the object that the image of all shows.
    renderer.setCamera(camera, std::max(onSurface * 0.5, std::min(renderer.nearPlane(), 0.5 * nearest)));
    std::vector<std::pair<std::uint32_t, ObjectId>> order; // (item, id) of what is drawn
    if (subset) {
        for (ObjectId id : *subset) {
            const auto it = std::lower_bound(all.begin(), all.end(), id);
            if (contains[std::size_t(it - all.begin())]) order.emplace_back(renderer.itemOf(id), id);
        }
        if (order.empty())
            for (ObjectId id : *subset) order.emplace_back(renderer.itemOf(id), id);
    } else {
        for (std::size_t i = 0; i < all.size(); ++i)
            if (contains[i]) order.emplace_back(renderer.itemOf(all[i]), all[i]);
        if (order.empty())
            for (ObjectId id : all) order.emplace_back(renderer.itemOf(id), id);
    }
    std::sort(order.begin(), order.end());
    std::vector<ObjectId> drawn;
    drawn.reserve(order.size());
    for (const auto& [item, id] : order) drawn.push_back(id);
    renderer.draw(drawn, DrawOutput::ItemId);
    renderer.setCamera(previous, previousNear);

    ItemBufferImage img;
    img.width = width;
    img.height = height;
    img.items = target.readIds();
    renderer.context().gl().BindFramebuffer(GL_FRAMEBUFFER, 0);

    // Items are slot + 1: the table runs up to the largest item seen.
    std::uint32_t maxItem = 0;
    for (std::uint32_t item : img.items) maxItem = std::max(maxItem, item);
    img.itemIds.assign(std::size_t(maxItem) + 1, 0);
    std::vector<std::uint32_t> counts(std::size_t(maxItem) + 1, 0);
    for (std::uint32_t item : img.items) ++counts[item];
    std::vector<std::pair<ObjectId, std::uint32_t>> seen;
    for (std::uint32_t item = 1; item <= maxItem; ++item) {
        ObjectId id = 0;
        if (renderer.objectOfItem(item, id)) {
            img.itemIds[item] = id;
            if (counts[item]) seen.emplace_back(id, counts[item]);
        } else if (counts[item]) {
            throw GlError("GL: the item buffer holds item " + std::to_string(item) + ", which no object has");
        }
    }
    std::sort(seen.begin(), seen.end());
    for (const auto& [id, count] : seen) {
        img.visible.push_back(id);
        img.pixelCounts.push_back(count);
    }
    return img;
}

} // namespace

ItemBufferImage itemBuffer(SceneRenderer& renderer, const Camera3& camera, int width, int height) {
    return render(renderer, camera, width, height, nullptr);
}

ItemBufferImage itemBuffer(SceneRenderer& renderer, const Camera3& camera, int width, int height,
                           std::span<const ObjectId> subset) {
    return render(renderer, camera, width, height, &subset);
}

} // namespace rgvc
