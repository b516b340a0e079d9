// Scene motion: the reflection rule documented in SceneMotion.hpp.
#include "SceneMotion.hpp"

#include <cmath>

#include <stdexcept>
#include <string>

namespace rgvc {

double reflectStep(double lo, double hi, double gridLo, double gridHi, double& v) {
    // Only a step towards a bound that would end past it reflects; see the header for why this never
    // traps an object that starts outside the grid.
    if ((v > 0 && hi + v > gridHi) || (v < 0 && lo + v < gridLo)) v = -v;
    return v;
}

template <int D> SceneSimulator<D>::SceneSimulator(const SceneData<D>& scene) : m_objects(scene.objects) {
    const GridGeometry<D>& g = scene.grid;
    for (int a = 0; a < D; ++a) {
        m_bounds.min[a] = g.origin()[a];
        // The same expression GridGeometry validates as finite, so the bound is what the grid means.
        m_bounds.max[a] = g.origin()[a] + g.voxelSize() * g.resolution()[a];
    }
    m_frame0Bounds.reserve(m_objects.size());
    m_state.resize(m_objects.size());
    m_index.reserve(m_objects.size());
    for (std::size_t i = 0; i < m_objects.size(); ++i) {
        m_frame0Bounds.push_back(boundsOf<D>(m_objects[i].shape));
        if (!m_objects[i].isStatic) m_state[i].velocity = m_objects[i].velocity;
        m_index.emplace(m_objects[i].id, i);
    }
}

template <int D> void SceneSimulator<D>::step() {
    for (std::size_t i = 0; i < m_objects.size(); ++i) {
        State& s = m_state[i];
        s.moved = false;
        if (m_objects[i].isStatic) continue;
        const Box<D>& b0 = m_frame0Bounds[i];
        for (int a = 0; a < D; ++a) {
            // The rule is defined on frame-0 box + translation (SceneMotion.hpp), not on the bounds of the
            // translated shape, which can differ in the last bit (a ball's (c + t) - r vs (c - r) + t):
            // one definition keeps `--dump-objects` reproducible by a checker.
            double lo = b0.min[a] + s.translation[a];
            double hi = b0.max[a] + s.translation[a];
            double d = reflectStep(lo, hi, m_bounds.min[a], m_bounds.max[a], s.velocity[a]);
            if (d != 0) {
                s.translation[a] += d;
                s.moved = true;
            }
        }
    }
    ++m_frame;
}

template <int D> Shape<D> SceneSimulator<D>::shapeAt(std::size_t index) const {
    return translated<D>(m_objects[index].shape, m_state[index].translation);
}

template <int D> std::size_t SceneSimulator<D>::indexOf(ObjectId id) const {
    auto it = m_index.find(id);
    if (it == m_index.end()) throw std::out_of_range("SceneSimulator: unknown object id " + std::to_string(id));
    return it->second;
}

template <int D> bool motionStaysInGrid(const SceneData<D>& scene) {
    const GridGeometry<D>& g = scene.grid;
    for (const SceneObject<D>& o : scene.objects) {
        if (o.isStatic) continue;
        const Box<D> b = boundsOf<D>(o.shape);
        for (int a = 0; a < D; ++a) {
            if (o.velocity[a] == 0) continue; // never moves on this axis
            const double extent = g.voxelSize() * g.resolution()[a];
            const double freeRoom = extent - (b.max[a] - b.min[a]);
            if (!(2 * std::abs(o.velocity[a]) <= freeRoom - 1e-9 * extent)) return false;
        }
    }
    return true;
}
template bool motionStaysInGrid<2>(const SceneData<2>&);
template bool motionStaysInGrid<3>(const SceneData<3>&);

template class SceneSimulator<2>;
template class SceneSimulator<3>;

} // namespace rgvc
