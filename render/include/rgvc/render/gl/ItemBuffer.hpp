// The item buffer: the exact visible set of a scene at pixel level, for a camera and a resolution.
//
//   rgvc::ItemBufferImage img = rgvc::itemBuffer(renderer, camera, 128, 96);
//   for (rgvc::ObjectId id : img.visible) ...      // every object that shows at least one pixel
//   if (auto id = img.idAt(64, 48)) ...             // the object seen through pixel (64, 48)
//
// Every object (or a given subset) is drawn with its item id (SceneRenderer::itemOf) into a 32-bit
// integer colour attachment with the depth test on, and the image is read back. It is the reference the
// GL tests check every culler against ("culled" must mean "no pixel changes"), and it is here for users
// validating their own scenes: a culler's PVS must contain itemBuffer(...).visible of all objects, at any
// resolution, when the culler's shapes contain what is drawn (SceneRenderer.hpp, outer models).
//
// Visibility as scene-format.md defines it, at pixel level: a point shows when the segment from the
// camera to it crosses no other object's interior. So
//   - faces seen from inside an object hide what lies on them (DrawOutput::ItemId draws back faces first);
//   - a camera in or on drawn objects (within 1e-6 of the scene's extent, the precision of float
//     positions) sees only those objects: only they are drawn;
//   - otherwise the near plane is moved to half the distance to the nearest drawn surface (at most the
//     renderer's near plane), so that no surface in front of the camera is clipped open.
// Pixel-level, not exact geometry: an object that covers no pixel centre is not in `visible` (raise the
// resolution to see smaller things).
#pragma once

#include "rgvc/render/gl/SceneRenderer.hpp"

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace rgvc {

struct ItemBufferImage {
    int width = 0, height = 0; ///< [Pixels]
    /// width * height item ids, row-major, top row first; 0 where no object is drawn.
    std::vector<std::uint32_t> items;
    /// itemIds[k] is the object of item k (k >= 1; itemIds[0] is unused), as the renderer held them
    /// when the image was made.
    std::vector<ObjectId> itemIds;
    /// The objects with at least one pixel, ascending, without duplicates.
    std::vector<ObjectId> visible;
    /// How many pixels each object of `visible` covers (same order).
    std::vector<std::uint32_t> pixelCounts;

    /// The item at pixel (x, y), x to the right, y down from the top row. [Limit] inside the image.
    std::uint32_t itemAt(int x, int y) const { return items[std::size_t(y) * std::size_t(width) + std::size_t(x)]; }
    /// The object seen through pixel (x, y), if any.
    std::optional<ObjectId> idAt(int x, int y) const {
        const std::uint32_t item = itemAt(x, y);
        return item ? std::optional<ObjectId>(itemIds[item]) : std::nullopt;
    }
};

/// Renders every object of `renderer` as seen from `camera` at width x height pixels and reads the ids
/// back. The camera's aspect is used as given (pixels are square when aspect = width / height). The
/// renderer's camera is restored afterwards; framebuffer 0 is left bound. Synchronous (it waits for the
/// GPU): for tests and validation, not for every frame.
/// [Pixels] [Limit] 1 <= width, height <= 16384. @throws GlError (framebuffer), InvalidInput (camera).
ItemBufferImage itemBuffer(SceneRenderer& renderer, const Camera3& camera, int width, int height);

/// The same for the objects `subset` only (the others are not drawn and hide nothing). Duplicates are
/// drawn twice, harmlessly. Objects are drawn in item order, and the near plane is that
/// of the image of all objects, so wherever this image and the image of all objects hold the same
/// object's nearest surface they agree pixel for pixel (the CHC tests compare such images).
/// @throws InvalidInput for an id the renderer does not hold.
ItemBufferImage itemBuffer(SceneRenderer& renderer, const Camera3& camera, int width, int height,
                           std::span<const ObjectId> subset);

} // namespace rgvc
