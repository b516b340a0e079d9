// `rgvc demo` on a 3D scene: a picture with two panels after the last cull, in the manner of the paper's
// Figure 6. Left, a top view (x right, z down) of the grid: per column of voxels the strongest state
// of any voxel in it (opaque dark gray, T teal, read by the traversal pale yellow, in view and hidden
// light gray), the objects' footprints (PVS translucent blue, culled red outline), the camera and its
// view's edges. Right, the view from the camera, ray cast on the CPU at pixel centres: each pixel shows
// the nearest object (PVS objects blue, shaded by depth; an object the culler left out shows red).
//
// The right panel is also a check: a pixel centre's ray sees an object not in the PVS only if the
// culler missed a visible object (the ray's first hit, and the occludees in front of it, are visible at
// that point by the scene format's definition), so `shown but culled` must be 0. Sampling pixel centres
// is weaker than the exact reference the tests use, but it is what a person looking at the picture sees.
//
// Why ray casting by hand rather than the GL stage: the demo runs without RGVC_WITH_GL, and a 480 x 270
// cast of a few thousand shapes is well under a second (the nearest hit is all it needs).
#include "Demo3D.hpp"

#include "SceneMotion.hpp"

#include "rgvc/render/GridPicture.hpp"
#include "rgvc/render/Image.hpp"
#include "rgvc/render/PngWriter.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <variant>

namespace rgvc::cli {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Entry and exit parameters of the ray o + t u (u unit) in a closed shape; entry > exit when it misses.
struct Hit {
    double entry = kInf, exit = -kInf;
};

Hit rayBall(const Ball<3>& b, const Vec3& o, const Vec3& u) {
    const Vec3 c = b.center - o;
    const double along = glm::dot(c, u);
    const double d2 = lengthSquared<3>(c - along * u);
    const double r2 = b.radius * b.radius;
    if (d2 > r2) return {};
    const double s = std::sqrt(r2 - d2);
    return {along - s, along + s};
}

/// Slab test against half-spaces n . x <= h (a box is six of them): `planes` holds elements that bind as
/// [n, h] (std::pair<Vec3, double>, HalfSpace).
template <class Planes> Hit rayPlanes(const Planes& planes, const Vec3& o, const Vec3& u) {
    double lo = -kInf, hi = kInf;
    for (const auto& [n, h] : planes) {
        const double nu = glm::dot(n, u), dist = h - glm::dot(n, o);
        if (nu == 0) {
            if (dist < 0) return {};
            continue;
        }
        const double t = dist / nu;
        if (nu < 0) lo = std::max(lo, t);
        else hi = std::min(hi, t);
        if (lo > hi) return {};
    }
    return {lo, hi};
}

/// The first and last triangle the ray meets (Moller-Trumbore): a picture's test, not a conservative one.
Hit rayMesh(const MeshSolid& m, const Vec3& o, const Vec3& u) {
    Hit h;
    const TriangleMesh& mesh = m.model()->mesh;
    for (const auto& t : mesh.triangles) {
        const Vec3 a = m.place(mesh.positions[t[0]]), e1 = m.place(mesh.positions[t[1]]) - a, e2 = m.place(mesh.positions[t[2]]) - a;
        const Vec3 p = glm::cross(u, e2);
        const double det = glm::dot(e1, p);
        if (!(std::abs(det) > 1e-300)) continue;
        const Vec3 s = o - a;
        const double b1 = glm::dot(s, p) / det;
        if (b1 < 0 || b1 > 1) continue;
        const Vec3 q = glm::cross(s, e1);
        const double b2 = glm::dot(u, q) / det;
        if (b2 < 0 || b1 + b2 > 1) continue;
        const double d = glm::dot(e2, q) / det;
        h.entry = std::min(h.entry, d);
        h.exit = std::max(h.exit, d);
    }
    return h;
}

Hit rayShape(const Shape<3>& shape, const Vec3& o, const Vec3& u) {
    return std::visit(
        [&](const auto& s) -> Hit {
            using T = std::decay_t<decltype(s)>;
            if constexpr (std::is_same_v<T, Ball<3>>) {
                return rayBall(s, o, u);
            } else if constexpr (std::is_same_v<T, Box<3>>) {
                const std::pair<Vec3, double> planes[6] = {
                    {{1, 0, 0}, s.max.x}, {{-1, 0, 0}, -s.min.x}, {{0, 1, 0}, s.max.y},
                    {{0, -1, 0}, -s.min.y}, {{0, 0, 1}, s.max.z}, {{0, 0, -1}, -s.min.z}};
                return rayPlanes(planes, o, u);
            } else if constexpr (std::is_same_v<T, ConvexPolytope>) {
                // The polytope's own planes (HalfSpace {normal, offset} binds as [n, h]): nothing is copied
                // or allocated per pixel and object.
                return rayPlanes(s.planes, o, u);
            } else if constexpr (std::is_same_v<T, MeshSolid>) {
                return rayMesh(s, o, u);
            } else {
                static_assert(sizeof(T) == 0, "rgvc demo: a 3D shape without a ray test");
            }
        },
        shape);
}

RGB8 shade(RGB8 base, double t, double far) {
    const double k = 1.0 - 0.6 * std::clamp(t / far, 0.0, 1.0);
    return {std::uint8_t(base.r * k), std::uint8_t(base.g * k), std::uint8_t(base.b * k)};
}

} // namespace

Demo3DResult drawDemo3D(const Culler3D& culler, const Camera3& camera, const std::vector<ObjectDesc<3>>& objects,
                        int size, const std::string& caption) {
    Demo3DResult out;
    const GridGeometry3& g = culler.grid();
    const IVec3 res = g.resolution();
    const std::vector<ObjectId>& pvs = culler.lastResult().pvs;
    auto inPvs = [&](ObjectId id) { return std::binary_search(pvs.begin(), pvs.end(), id); };

    // Left: the top view, one cell per column of voxels.
    const int half = std::max(64, size / 2);
    const double cell = std::max(1.0, std::floor(double(half) / double(std::max(res.x, res.z))));
    const int topW = int(cell * res.x), topH = int(cell * res.z);
    // Right: the camera's view.
    const int viewW = half, viewH = std::max(16, int(std::lround(half / camera.aspect)));
    const int margin = 8, captionH = 20;
    ImageRGB img(topW + viewW + 3 * margin, std::max(topH, viewH) + captionH + 2 * margin, colors::kWhite);
    const int topX0 = margin, topY0 = captionH + margin, viewX0 = topW + 2 * margin, viewY0 = topY0;

    for (int z = 0; z < res.z; ++z)
        for (int x = 0; x < res.x; ++x) {
            int rank = 0; // 0 empty, 1 hidden, 2 read, 3 T, 4 opaque
            for (int y = 0; y < res.y && rank < 4; ++y) {
                const VoxelState s = culler.voxelState({x, y, z});
                if (s.opaque) rank = 4;
                else if (s.hasTbv) rank = std::max(rank, 3);
                else if (s.visited && !s.occluded) rank = std::max(rank, 2);
                else if (s.occluded) rank = std::max(rank, 1);
            }
            const RGB8 colours[5] = {picture::kEmpty, picture::kOccluded, picture::kVisited, picture::kTbv, picture::kOpaque};
            fillRect(img, topX0 + std::int64_t(x * cell), topY0 + std::int64_t(z * cell), topX0 + std::int64_t((x + 1) * cell),
                     topY0 + std::int64_t((z + 1) * cell), colours[rank]);
        }
    auto toTop = [&](const Vec3& world) {
        const Vec3 l = g.toLocal(world);
        return Vec2{topX0 + l.x * cell, topY0 + l.z * cell};
    };
    for (const ObjectDesc<3>& o : objects) {
        const Box<3> b = boundsOf<3>(o.shape);
        const Vec2 a = toTop(b.min), c = toTop(b.max);
        const std::vector<Vec2> quad = {{a.x, a.y}, {c.x, a.y}, {c.x, c.y}, {a.x, c.y}};
        if (inPvs(o.id)) {
            fillConvexPolygon(img, quad, picture::kPvs, picture::kPvsFillAlpha);
            drawPolygonOutline(img, quad, picture::kPvs);
        } else if (o.role != ObjectRole::Occluder) {
            drawPolygonOutline(img, quad, picture::kHidden);
        }
    }
    // The camera's basis (cameraUp: the same up every part of rgvc reads).
    const Vec3 f = safeNormalize<3>(camera.direction);
    const Vec3 r = safeNormalize<3>(glm::cross(f, cameraUp(camera)));
    const Vec3 up = glm::cross(r, f);
    const double th = std::tan(camera.fovDeg * 3.14159265358979323846 / 360.0), tw = th * camera.aspect;
    const double reach = std::isinf(camera.far) ? 0.5 * g.voxelSize() * std::max(res.x, res.z) : camera.far;
    const Vec2 eye = toTop(camera.position);
    for (double sx : {-1.0, 1.0}) {
        const Vec3 edge = safeNormalize<3>(f + sx * tw * r);
        drawLine(img, eye, toTop(camera.position + edge * reach), picture::kView, 1.5);
    }
    drawDashedLine(img, eye, toTop(camera.position + f * reach), picture::kView);
    fillCircle(img, eye, 4, picture::kView);

    // Right: the view from the camera.
    const double far = std::isinf(camera.far) ? g.voxelSize() * std::sqrt(double(lengthSquared<3>(Vec3(res)))) : camera.far;
    std::vector<Hit> hits(objects.size());
    for (int py = 0; py < viewH; ++py)
        for (int px = 0; px < viewW; ++px) {
            const double sx = (2 * (px + 0.5) / viewW - 1) * tw, sy = (1 - 2 * (py + 0.5) / viewH) * th;
            const Vec3 u = safeNormalize<3>(f + sx * r + sy * up);
            // The nearest blocker (any role but occludee), then everything hit before it is visible here.
            double block = camera.far;
            std::size_t first = objects.size();
            double firstT = kInf;
            for (std::size_t i = 0; i < objects.size(); ++i) {
                hits[i] = rayShape(objects[i].shape, camera.position, u);
                const Hit& h = hits[i];
                if (h.entry > h.exit || h.exit < 0) continue;
                const double t = std::max(h.entry, 0.0);
                if (t > camera.far) continue;
                if (objects[i].role != ObjectRole::Occludee) block = std::min(block, t);
                if (t < firstT) firstT = t, first = i;
            }
            RGB8 colour{235, 235, 240};
            if (first < objects.size()) {
                const ObjectDesc<3>& o = objects[first];
                colour = shade(inPvs(o.id) || o.role == ObjectRole::Occluder ? picture::kPvs : picture::kHidden, firstT, far);
                ++out.pixelsCovered;
                for (std::size_t i = 0; i < objects.size(); ++i) {
                    const Hit& h = hits[i];
                    if (h.entry > h.exit || h.exit < 0 || std::max(h.entry, 0.0) > block) continue;
                    if (objects[i].role == ObjectRole::Occluder || inPvs(objects[i].id)) continue;
                    ++out.pixelsShownButCulled; // visible at this pixel's centre, not in the PVS: a miss
                    break;
                }
            }
            img.set(viewX0 + px, viewY0 + py, colour);
        }
    drawRectOutline(img, viewX0 - 1, viewY0 - 1, viewX0 + viewW + 1, viewY0 + viewH + 1, picture::kView);
    drawText(img, margin, 4, caption, picture::kText, 1);
    out.image = std::move(img);
    return out;
}

} // namespace rgvc::cli
