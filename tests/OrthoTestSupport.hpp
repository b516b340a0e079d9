// Shared by the view tests (test_views, test_ortho): the misses of a perspective view's PVS against the
// reference, random orthographic cameras over a grid and the check of one orthographic view's PVS
// against the sampled parallel-ray reference (reference/OrthoVisibility.hpp).
#pragma once

#include "CullerTestSupport.hpp"
#include "OrthoVisibility.hpp"

#include <random>
#include <vector>

namespace rgvc::culler_test {

/// Visible objects (by the reference) that `pvs` misses; objects' ids are their indices' ids.
template <int D> int missesOf(const std::vector<ObjectDesc<D>>& objects, const Camera<D>& cam, const std::vector<ObjectId>& pvs) {
    std::vector<Shape<D>> shapes;
    for (const ObjectDesc<D>& o : objects) shapes.push_back(o.shape);
    const std::vector<bool> vis = referenceVisible<D>(shapes, cam);
    int misses = 0;
    for (std::size_t i = 0; i < objects.size(); ++i)
        if (vis[i] && !contains(pvs, objects[i].id)) ++misses;
    return misses;
}

template <int D> Camera<D> randomOrtho(std::mt19937_64& rng, const GridGeometry<D>& grid) {
    std::uniform_real_distribution<double> u(0, 1);
    const Vec<D> size = Vec<D>(grid.resolution()) * grid.voxelSize();
    Camera<D> c;
    c.projection = Projection::Orthographic;
    for (int a = 0; a < D; ++a) c.position[a] = grid.origin()[a] + size[a] * (1.4 * u(rng) - 0.2);
    const double kind = u(rng);
    if (kind < 0.3) { // along an axis (3D: often straight down, the shadow-cascade / top view)
        c.direction = Vec<D>(0.0);
        c.direction[int(rng() % D)] = u(rng) < 0.5 ? -1 : 1;
        if (D == 3 && u(rng) < 0.5) c.direction = Vec<D>(0.0), c.direction[1] = -1;
    } else {
        for (int a = 0; a < D; ++a) c.direction[a] = 2 * u(rng) - 1;
        if (lengthSquared<D>(c.direction) < 1e-6) c.direction[0] = 1;
    }
    c.width = size[0] * (0.03 + 0.8 * u(rng));
    c.height = size[D - 1] * (0.03 + 0.8 * u(rng));
    if (u(rng) < 0.3) c.far = size[0] * (0.1 + u(rng));
    return c;
}

/// Objects whose bounding box lies strictly outside one face plane of the view box (an independent,
/// sufficient test of missing it) must not be reported; the reference's visible ones must be.
template <int D> void checkOrtho(const std::vector<ObjectDesc<D>>& objects, const Camera<D>& cam, const std::vector<ObjectId>& pvs,
                                 int& misses, int& mustCull, int& wrongKeeps) {
    std::vector<Shape<D>> shapes;
    for (const ObjectDesc<D>& o : objects) shapes.push_back(o.shape);
    const std::vector<bool> vis = reference::orthoVisible<D>(shapes, cam);
    const reference::ortho_detail::Frame<D> frame(cam);
    for (std::size_t i = 0; i < objects.size(); ++i) {
        if (vis[i] && !contains(pvs, objects[i].id)) ++misses;
        const Box<D> b = boundsOf<D>(objects[i].shape);
        bool outside = false;
        for (int k = 0; k < D && !outside; ++k) {
            double lo = INFINITY, hi = -INFINITY;
            for (int c = 0; c < (1 << D); ++c) {
                Vec<D> p;
                for (int a = 0; a < D; ++a) p[a] = (c >> a) & 1 ? b.max[a] : b.min[a];
                const double v = glm::dot(p - frame.o, frame.axis[k]);
                lo = std::min(lo, v);
                hi = std::max(hi, v);
            }
            const double margin = 1e-6 * (1 + std::abs(lo) + std::abs(hi));
            if (k == 0) outside = hi < -margin || lo > frame.depth + margin;
            else outside = hi < -frame.half[k] - margin || lo > frame.half[k] + margin;
        }
        if (outside) {
            ++mustCull;
            wrongKeeps += contains(pvs, objects[i].id);
        }
    }
}

} // namespace rgvc::culler_test
