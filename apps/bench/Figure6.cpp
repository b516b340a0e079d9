// Figure 6 of seed 004 (§6): "visualization of a 3D regular grid ... showing hidden and opaque voxels"
// above "scene snapshot as seen from the viewpoint", drawn with the GL stage (Figures3D.hpp).
//
// The voxels are drawn by a SceneRenderer of their own as thin boxes, one per exposed face (a face whose
// neighbour across it has another state, or lies outside the grid), so that the item buffer tells, per
// pixel, the voxel's state and the face's axis: the picture is then shaded on the CPU with one flat
// colour per state and a light per face direction. SceneRenderer's own colour output cannot do that (it
// colours by object id), and a face per box is what a voxel viewer draws anyway (interior faces are
// never drawn). The scene itself is the walk's renderer's colour output from the camera.
#include "Figures3D.hpp"

#include "GlWalk.hpp"

#include "rgvc/grid/ViewFrustum.hpp"
#include "rgvc/render/PngWriter.hpp"
#include "rgvc/render/gl/GlFramebuffer.hpp"
#include "rgvc/render/gl/ItemBuffer.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>

namespace rgvc::bench {

namespace {

// Beyond: in the view frustum but never reached, because the traversal ended at a shell that was hidden
// entirely (early termination, seed 004 §4.2): hidden too, though H does not record it voxel by voxel.
enum Category : std::uint8_t { Empty = 0, Opaque = 1, Hidden = 2, CameraMark = 3, Edge = 4, Beyond = 5 };

constexpr RGB8 kCategoryColour[6] = {{255, 255, 255}, {95, 95, 105}, {225, 60, 50}, {250, 200, 0}, {20, 20, 20}, {245, 175, 165}};
// Light per face: -x, +x, -y, +y, -z, +z (the overview looks down from above -x, -z).
constexpr double kFaceLight[6] = {0.82, 0.62, 0.5, 1.0, 0.7, 0.55};

RGB8 shaded(Category c, int face) {
    const RGB8 base = kCategoryColour[c];
    const double l = c == Edge ? 1.0 : kFaceLight[face];
    return {std::uint8_t(base.r * l), std::uint8_t(base.g * l), std::uint8_t(base.b * l)};
}

void copyInto(ImageRGB& dst, const ImageRGB& src, int x0, int y0) {
    for (int y = 0; y < src.height(); ++y)
        for (int x = 0; x < src.width(); ++x)
            if (dst.contains(x0 + x, y0 + y)) dst.set(x0 + x, y0 + y, src.at(x, y));
}

} // namespace

void writeFigure6(GlWalk& walk, const std::string& cullerName, const Camera3& camera, const std::string& caption,
                  const std::string& path) {
    const Culler3D* culler = walk.culler(cullerName);
    if (!culler) throw std::runtime_error("figure 6: no grid method '" + cullerName + "'");
    const GridGeometry3& g = culler->grid();
    const IVec3 r = g.resolution();
    const double vs = g.voxelSize();
    auto index = [&](int x, int y, int z) { return (std::size_t(z) * std::size_t(r.y) + std::size_t(y)) * std::size_t(r.x) + std::size_t(x); };
    std::vector<std::uint8_t> state(std::size_t(r.x) * std::size_t(r.y) * std::size_t(r.z), Empty);
    std::size_t opaque = 0, hidden = 0, beyond = 0;
    const ViewFrustum frustum(camera, g);
    for (int z = 0; z < r.z; ++z)
        for (int y = 0; y < r.y; ++y)
            for (int x = 0; x < r.x; ++x) {
                const VoxelState s = culler->voxelState(IVec3{x, y, z});
                const Category c = s.opaque     ? Opaque
                                   : s.occluded ? Hidden
                                   : !s.visited && frustum.touchesVoxel(IVec3{x, y, z}) ? Beyond
                                                : Empty;
                state[index(x, y, z)] = c;
                opaque += c == Opaque;
                hidden += c == Hidden;
                beyond += c == Beyond;
            }

    // The boxes: exposed voxel faces, the grid's 12 edges, the camera and its line of sight.
    SceneRenderer boxes(walk.context());
    std::vector<std::pair<Category, std::uint8_t>> kind(1); // by object id: category, face
    auto add = [&](const Shape<3>& shape, Category c, int face) {
        const ObjectId id = ObjectId(kind.size());
        boxes.setObject(id, shape);
        kind.emplace_back(c, std::uint8_t(face));
    };
    const double t = 0.05 * vs; // face thickness
    const std::array<IVec3, 6> dirs = {IVec3{-1, 0, 0}, IVec3{1, 0, 0}, IVec3{0, -1, 0}, IVec3{0, 1, 0}, IVec3{0, 0, -1}, IVec3{0, 0, 1}};
    for (int z = 0; z < r.z; ++z)
        for (int y = 0; y < r.y; ++y)
            for (int x = 0; x < r.x; ++x) {
                const Category c = Category(state[index(x, y, z)]);
                if (c == Empty) continue;
                const Vec3 lo = g.toWorld(Vec3{double(x), double(y), double(z)});
                const Vec3 hi = lo + Vec3(vs);
                for (int f = 0; f < 6; ++f) {
                    const IVec3 n{x + dirs[f].x, y + dirs[f].y, z + dirs[f].z};
                    const bool inside = n.x >= 0 && n.y >= 0 && n.z >= 0 && n.x < r.x && n.y < r.y && n.z < r.z;
                    if (inside && state[index(n.x, n.y, n.z)] == c) continue;
                    Box<3> b{lo, hi};
                    const int axis = f / 2;
                    if (f % 2 == 0) b.max[axis] = lo[axis] + t;
                    else b.min[axis] = hi[axis] - t;
                    add(b, c, f);
                }
            }
    const Vec3 glo = g.origin(), ghi = g.toWorld(Vec3(r));
    const double e = 0.25 * vs;
    for (int axis = 0; axis < 3; ++axis)
        for (int k = 0; k < 4; ++k) {
            Box<3> b;
            for (int a = 0, bit = 0; a < 3; ++a) {
                if (a == axis) {
                    b.min[a] = glo[a];
                    b.max[a] = ghi[a];
                } else {
                    const double v = (k >> bit++) & 1 ? ghi[a] : glo[a];
                    b.min[a] = v - e;
                    b.max[a] = v + e;
                }
            }
            add(b, Edge, 0);
        }
    const Vec3 dir = safeNormalize<3>(camera.direction);
    add(Ball<3>{camera.position, 1.5 * vs}, CameraMark, 3);
    for (int k = 1; k <= 6; ++k) add(Ball<3>{camera.position + dir * (2.0 * vs * k), 0.5 * vs}, CameraMark, 3);

    // Top: the voxels from above, beside the grid's -x, -z corner, looking at its centre.
    const int width = 800, topHeight = 500;
    const Vec3 centre = 0.5 * (glo + ghi), size = ghi - glo;
    Camera3 overview;
    overview.position = centre + Vec3{-0.95 * size.x, 1.6 * size.y, -0.75 * size.z};
    overview.direction = centre - Vec3{0, 0.15 * size.y, 0} - overview.position;
    overview.fovDeg = 45;
    overview.aspect = double(width) / topHeight;
    const ItemBufferImage ids = itemBuffer(boxes, overview, width, topHeight);
    ImageRGB top(width, topHeight);
    for (int y = 0; y < topHeight; ++y)
        for (int x = 0; x < width; ++x)
            if (const auto id = ids.idAt(x, y)) {
                const auto& [c, face] = kind[std::size_t(*id)];
                top.set(x, y, shaded(c, face));
            }

    // Bottom: the scene from the viewpoint, at the camera's aspect.
    const int bottomHeight = std::clamp(int(width / camera.aspect + 0.5), 16, 2000);
    GlFramebuffer target(walk.context(), width, bottomHeight, ColourFormat::Rgba8);
    target.bind();
    target.clear();
    walk.renderer().setCamera(camera);
    walk.renderer().drawAll(DrawOutput::Colour);
    const std::vector<std::uint8_t> rgba = target.readRgba();
    ImageRGB bottom(width, bottomHeight);
    for (int y = 0; y < bottomHeight; ++y)
        for (int x = 0; x < width; ++x) {
            const std::uint8_t* p = &rgba[(std::size_t(y) * std::size_t(width) + std::size_t(x)) * 4];
            // Sky where nothing is drawn (cleared to black; a drawn face is at least 0.3 * 0.35 bright).
            const bool empty = p[0] == 0 && p[1] == 0 && p[2] == 0;
            bottom.set(x, y, empty ? RGB8{200, 220, 240} : RGB8{p[0], p[1], p[2]});
        }

    // Layout: caption, top, legend, bottom.
    const int strip = 28;
    ImageRGB out(width, strip + topHeight + strip + bottomHeight);
    drawText(out, 8, 7, caption, colors::kBlack, 2);
    copyInto(out, top, 0, strip);
    const int ly = strip + topHeight;
    int lx = 8;
    auto legend = [&](Category c, const std::string& text) {
        fillRect(out, lx, ly + 7, lx + 14, ly + 21, kCategoryColour[c]);
        drawText(out, lx + 20, ly + 7, text, colors::kBlack, 2);
        lx += 20 + int(textWidth(text, 2)) + 24;
    };
    legend(Opaque, "O " + std::to_string(opaque));
    legend(Hidden, "H " + std::to_string(hidden));
    legend(Beyond, "in view, past the end " + std::to_string(beyond));
    legend(CameraMark, "camera");
    copyInto(out, bottom, 0, ly + strip);
    drawText(out, 8, ly + strip + 6, "seen from the camera", colors::kBlack, 2);
    writePng(path, out);
}

} // namespace rgvc::bench
