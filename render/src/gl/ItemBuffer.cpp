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
    // outside shows. "On" within a few float steps of the scene's extent, the precision of what is drawn.
    const std::vector<ObjectId> all = subset ? std::vector<ObjectId>() : renderer.ids();
    const std::span<const ObjectId> drawn = subset ? *subset : std::span<const ObjectId>(all);
    const double scale = renderer.drawnExtent() + glm::length(camera.position);
    const double onSurface = 1e-6 * scale;
    std::vector<ObjectId> containers;
    double nearest = std::numeric_limits<double>::infinity();
    for (ObjectId id : drawn) {
        if (renderer.drawnShapeContains(id, camera.position, onSurface)) containers.push_back(id);
        else nearest = std::min(nearest, renderer.distanceToDrawn(id, camera.position));
    }
    // Otherwise the near plane stays nearer than every drawn surface (half the distance to the nearest),
    // so that nothing in front of the camera is clipped open.
    renderer.setCamera(camera, std::max(onSurface * 0.5, std::min(renderer.nearPlane(), 0.5 * nearest)));
    if (!containers.empty()) renderer.draw(containers, DrawOutput::ItemId);
    else if (subset) renderer.draw(*subset, DrawOutput::ItemId);
    else renderer.drawAll(DrawOutput::ItemId);
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
