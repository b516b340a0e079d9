// The exact references the benchmarks check a PVS against (rgvc_bench_classes, rgvc_sweep): the visible
// set of a frame from tests/reference, computed on the objects that touch the view region only.
//
// Why only those: the view region is convex (a wedge of at most 180 degrees in 2D, a frustum in 3D) and
// holds the camera, so a segment from the camera to a point in it meets only objects that touch it; the
// eps is the whole scene's. 3D: reference::visible3D at 128 grid and 8 target divisions with critical rays
// (about 3x cheaper than its 256/16 defaults on the paper's scene, and the same visible sets on the frames
// compared, rgvc_bench3d's accuracy scenario); 2D: reference::exactVisible2D (exact). Wider 2D views than
// 180 degrees give every object to the reference.
#pragma once

#include "rgvc/dynamics/Culler.hpp"

#include "ExactVisibility2D.hpp"
#include "ExactVisibility3D.hpp"
#include "RandomScenes2D.hpp"
#include "RandomScenes3D.hpp"

#include <cstddef>
#include <type_traits>
#include <variant>
#include <vector>

namespace rgvc::bench {

/// [Limit] 3D reference resolution used by referenceOf (and stated by the benchmarks' output).
inline constexpr int kReferenceGridDivisions = 128, kReferenceTargetDivisions = 8;

/// Whether the point lies in the open interior of a 2D shape.
inline bool cameraInside(const Shape<2>& s, const Vec2& p) {
    return std::visit(
        [&](const auto& x) {
            using T = std::decay_t<decltype(x)>;
            if constexpr (std::is_same_v<T, Ball<2>>) return lengthSquared<2>(p - x.center) < x.radius * x.radius;
            else if constexpr (std::is_same_v<T, Box<2>>)
                return p.x > x.min.x && p.x < x.max.x && p.y > x.min.y && p.y < x.max.y;
            else {
                bool pos = true, neg = true;
                for (std::size_t i = 0; i < x.points.size(); ++i) {
                    const Vec2 a = x.points[i], b = x.points[(i + 1) % x.points.size()];
                    const double c = (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
                    pos = pos && c > 0;
                    neg = neg && c < 0;
                }
                return pos || neg;
            }
        },
        s);
}

/// The reference's answer for all objects (index = position in `objects`), computed on those touching the
/// view region (see the top). cameraInsideObject: from inside an object the reference sees that object only,
/// so ratios |PVS|/|visible| leave such frames out.
struct Reference {
    std::vector<bool> visible;
    std::size_t count = 0;
    bool cameraInsideObject = false;
};

/// The shapes touching the view region (inView[i]) and their positions in the scene's `shapes`: what the
/// reference is run on (see the top), and where its answers go back to.
template <int D> struct InView {
    std::vector<Shape<D>> shapes;
    std::vector<std::size_t> index;
};
template <int D> InView<D> inViewOnly(const std::vector<Shape<D>>& shapes, const std::vector<bool>& inView) {
    InView<D> in;
    for (std::size_t i = 0; i < shapes.size(); ++i)
        if (inView[i]) {
            in.shapes.push_back(shapes[i]);
            in.index.push_back(i);
        }
    return in;
}

inline Reference referenceOf(const std::vector<ObjectDesc<3>>& objects, const Camera3& cam) {
    const std::vector<Shape<3>> shapes = reference::shapesOf(objects);
    const std::vector<bool> inView = reference::inViewRegion3D(shapes, cam);
    const auto [sub, index] = inViewOnly<3>(shapes, inView);
    reference::Visibility3DOptions opt;
    opt.gridDivisions = kReferenceGridDivisions;
    opt.targetDivisions = kReferenceTargetDivisions;
    opt.eps = reference::sceneEpsilon3D(shapes, cam);
    reference::Visibility3DStats st;
    const std::vector<bool> vis = reference::visible3D(sub, cam, opt, &st);
    Reference r;
    r.visible.assign(shapes.size(), false);
    for (std::size_t k = 0; k < sub.size(); ++k) {
        r.visible[index[k]] = vis[k];
        r.count += vis[k];
        r.cameraInsideObject = r.cameraInsideObject || st.seen[k] == reference::Seen3D::ContainsCamera;
    }
    return r;
}

inline Reference referenceOf(const std::vector<ObjectDesc<2>>& objects, const Camera2& cam) {
    const std::vector<Shape<2>> shapes = reference::shapesOf(objects);
    Reference r;
    r.visible.assign(shapes.size(), false);
    reference::ExactOptions opt;
    opt.eps = reference::sceneEpsilon(shapes, cam);
    // The wedge is convex for fov <= 180 only; wider views get every object.
    const std::vector<bool> inView =
        cam.fovDeg <= 180 ? reference::inViewRegion2D(shapes, cam) : std::vector<bool>(shapes.size(), true);
    const auto [sub, index] = inViewOnly<2>(shapes, inView);
    const std::vector<bool> vis = reference::exactVisible2D(sub, cam, opt);
    for (std::size_t k = 0; k < sub.size(); ++k) {
        r.visible[index[k]] = vis[k];
        r.count += vis[k];
    }
    for (const Shape<2>& s : shapes)
        r.cameraInsideObject = r.cameraInsideObject || cameraInside(s, cam.position);
    return r;
}

} // namespace rgvc::bench
