// The view region of an orthographic camera (Camera.hpp: projection = Orthographic) in voxel units: the
// closed box origin + t f + x right (+ y trueUp) with 0 <= t <= depth, |x| <= halfWidth (|y| <=
// halfHeight), and its exact touch tests.
//
// What an orthographic view culls (Culler): with CullerOptions::orthographicOcclusion (3D, opt-in;
// stats.fallback = OrthographicOcclusion) the objects touching this box that the parallel-ray occlusion
// image hides (OrthoPass.cpp, OrthoOcclusionImage.hpp: the perspective traversal's caps, image and buffer
// all derive occlusion from rays through the camera point, §4.4, and none of their facts holds for
// parallel rays, so that pass has its own image of depths along f over the box's cross-section); without
// it, and always in 2D (stats.fallback = Orthographic), exactly the objects whose shape misses this box
// (grown by the conversion slack): view-volume culling, exact and conservative.
//
// Exactness. Boxes (axis-aligned) and convex polygons are tested with the separating axis theorem over
// every candidate axis (3D: the 3 grid axes, the 3 box axes and their 9 cross products; 2D: the 2 grid
// axes, the 2 box axes and the polygon's edge normals), which is exact for two convex sets; balls by
// their distance to the box (clamping in the box's orthonormal frame). An infinite depth is replaced by
// the shape's own largest depth (no point of the shape lies deeper, so the intersection is the same).
// Other shapes (polytopes: oriented boxes, hulls) are tested by their bounding box (conservative).
#pragma once

#include "rgvc/grid/Camera.hpp"
#include "rgvc/grid/GridGeometry.hpp"
#include "rgvc/grid/Math.hpp"
#include "rgvc/grid/Shapes.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <variant>

namespace rgvc {

template <int D> class OrthoVolume {
public:
    OrthoVolume() = default;
    /// @param camera validated (validateCamera), orthographic, world units.
    /// @throws InvalidInput ("camera.up") in 3D when up is parallel to the direction.
    OrthoVolume(const Camera<D>& camera, const GridGeometry<D>& grid) {
        m_origin = grid.toLocal(camera.position);
        m_axis[0] = safeNormalize<D>(camera.direction);
        if constexpr (D == 2) {
            m_axis[1] = Vec2{m_axis[0].y, -m_axis[0].x}; // f turned clockwise
        } else {
            Vec3 right = glm::cross(m_axis[0], cameraUp(camera));
            const double len = std::sqrt(lengthSquared<3>(right));
            if (!(len > 1e-12)) throw InvalidInput("camera.up", "must not be parallel to camera.direction");
            m_axis[1] = right / len;
            m_axis[2] = glm::cross(m_axis[1], m_axis[0]);
        }
        m_depth = std::isinf(camera.far) ? camera.far : grid.toLocalLength(camera.far);
        m_half[1] = 0.5 * grid.toLocalLength(camera.width);
        if constexpr (D == 3) m_half[2] = 0.5 * grid.toLocalLength(camera.height);
        double magnitude = 0;
        for (int a = 0; a < D; ++a) magnitude = std::max(magnitude, std::abs(camera.position[a]));
        m_slack = grid.conversionSlack(magnitude);
    }

    const Vec<D>& origin() const { return m_origin; }
    /// Axis 0: the view direction f; 1: right; 2 (3D): trueUp. Orthonormal.
    const Vec<D>& axis(int i) const { return m_axis[i]; }
    double depth() const { return m_depth; }
    /// Half extent along axis i (1, 2); axis 0 runs from 0 to depth().
    double halfExtent(int i) const { return m_half[i]; }
    /// [Voxel units] the camera's conversion slack, added to every test.
    double slack() const { return m_slack; }

    bool containsPoint(const Vec<D>& p, double extra = 0) const {
        const Vec<D> q = p - m_origin;
        const double s = m_slack + extra, t = glm::dot(q, m_axis[0]);
        if (t < -s || t > m_depth + s) return false;
        for (int i = 1; i < D; ++i)
            if (std::abs(glm::dot(q, m_axis[i])) > m_half[i] + s) return false;
        return true;
    }

    /// Whether the closed ball meets the closed box grown by slack() + extra. Exact.
    bool touchesBall(const Vec<D>& c, double r, double extra = 0) const {
        const Vec<D> q = c - m_origin;
        const double t = glm::dot(q, m_axis[0]);
        double d0 = t < 0 ? -t : (t > m_depth ? t - m_depth : 0);
        double d2 = d0 * d0;
        for (int i = 1; i < D; ++i) {
            const double x = std::abs(glm::dot(q, m_axis[i]));
            if (x > m_half[i]) d2 += (x - m_half[i]) * (x - m_half[i]);
        }
        const double reach = r + m_slack + extra;
        return d2 <= reach * reach;
    }

    /// Whether the closed axis-aligned box lo..hi meets the closed view box grown by slack() + extra. Exact (SAT).
    bool touchesBox(const Vec<D>& lo, const Vec<D>& hi, double extra = 0) const {
        Vec<D> corners[1 << D];
        for (int k = 0; k < (1 << D); ++k)
            for (int a = 0; a < D; ++a) corners[k][a] = (k >> a) & 1 ? hi[a] : lo[a];
        Vec<D> axes[15];
        int n = 0;
        for (int a = 0; a < D; ++a) {
            axes[n] = Vec<D>(0.0);
            axes[n++][a] = 1;
        }
        for (int i = 0; i < D; ++i) axes[n++] = m_axis[i];
        if constexpr (D == 3)
            for (int a = 0; a < 3; ++a)
                for (int i = 0; i < 3; ++i) {
                    Vec3 e(0.0);
                    e[a] = 1;
                    axes[n++] = glm::cross(e, m_axis[i]);
                }
        return separatedByNone(corners, 1 << D, axes, n, extra);
    }

    /// Whether a convex polygon (2D) meets the view box grown by slack() + extra. Exact (SAT).
    /// (A template over the polygon type so that OrthoVolume<3>'s shape visit never instantiates it.)
    template <class Polygon = ConvexPolygon> bool touchesPolygon(const Polygon& p, double extra = 0) const {
        static_assert(D == 2, "OrthoVolume::touchesPolygon: 2D only");
        Vec2 axes[64 + 4];
        int n = 0;
        axes[n++] = {1, 0};
        axes[n++] = {0, 1};
        axes[n++] = m_axis[0];
        axes[n++] = m_axis[1];
        const std::size_t m = p.points.size();
        bool ok = true;
        for (std::size_t i = 0; i < m && ok; ++i) {
            if (n == int(std::size(axes))) { // more edges than room: the bounding box decides (conservative)
                ok = false;
                break;
            }
            const Vec2 e = p.points[(i + 1) % m] - p.points[i];
            axes[n++] = Vec2{-e.y, e.x};
        }
        if (!ok) {
            const Box<2> b = boundsOf(p);
            return touchesBox(b.min, b.max, extra);
        }
        return separatedByNone(p.points.data(), int(m), axes, n, extra);
    }

    /// Any shape (voxel units): exact for balls, boxes and polygons, the bounding box for others.
    bool touchesShape(const Shape<D>& s, double extra = 0) const {
        return std::visit(
            [&](const auto& x) {
                using T = std::decay_t<decltype(x)>;
                if constexpr (std::is_same_v<T, Ball<D>>) return touchesBall(x.center, x.radius, extra);
                else if constexpr (std::is_same_v<T, Box<D>>) return touchesBox(x.min, x.max, extra);
                else if constexpr (std::is_same_v<T, ConvexPolygon>) return touchesPolygon(x, extra);
                else {
                    const Box<D> b = boundsOf<D>(Shape<D>(x));
                    return touchesBox(b.min, b.max, extra);
                }
            },
            s);
    }

private:
    /// SAT: the point set pts (a convex set's vertices) and the view box overlap on every axis.
    bool separatedByNone(const Vec<D>* pts, int count, const Vec<D>* axes, int n, double extra) const {
        // The shape's largest depth bounds the box's useful depth (an infinite depth included).
        double deepest = -INFINITY;
        for (int k = 0; k < count; ++k) deepest = std::max(deepest, glm::dot(pts[k] - m_origin, m_axis[0]));
        const double s = m_slack + extra;
        if (deepest < -s) return false;
        const double depth = std::max(0.0, std::min(m_depth, deepest));
        Vec<D> centre = m_origin + 0.5 * depth * m_axis[0];
        double half[3] = {0.5 * depth, m_half[1], D == 3 ? m_half[2] : 0};
        for (int j = 0; j < n; ++j) {
            const Vec<D>& L = axes[j];
            const double len = std::sqrt(lengthSquared<D>(L));
            if (!(len > 1e-12)) continue; // a cross product of parallel axes: no axis
            double lo = INFINITY, hi = -INFINITY;
            for (int k = 0; k < count; ++k) {
                const double v = glm::dot(pts[k], L);
                lo = std::min(lo, v);
                hi = std::max(hi, v);
            }
            const double c = glm::dot(centre, L);
            double r = 0;
            for (int i = 0; i < D; ++i) r += half[i] * std::abs(glm::dot(m_axis[i], L));
            const double grow = s * len;
            if (lo > c + r + grow || hi < c - r - grow) return false;
        }
        return true;
    }

    Vec<D> m_origin{0.0};
    Vec<D> m_axis[D]{};
    double m_half[3] = {0, 0, 0};
    double m_depth = INFINITY;
    double m_slack = kConservativeSlack;
};

} // namespace rgvc
