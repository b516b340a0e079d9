#include "SimWorld.hpp"

#include "SceneMotion.hpp"

#include "rgvc/grid/Error.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace rgvc::sim {

const char* toString(SpawnKind k) {
    switch (k) {
    case SpawnKind::Circle: return "circle";
    case SpawnKind::Box: return "box";
    case SpawnKind::Polygon: return "polygon";
    }
    return "?";
}

SimWorld::SimWorld(std::string name, const GridGeometry2& grid, const Camera2& camera, std::vector<SimObject> objects)
    : m_name(std::move(name)), m_grid(grid), m_camera(camera), m_objects(std::move(objects)) {
    validateCamera(m_camera, "camera");
    const Vec2 extent = Vec2(grid.resolution()) * grid.voxelSize();
    m_bounds = {grid.origin(), grid.origin() + extent};
    for (std::size_t i = 0; i < m_objects.size(); ++i) {
        SimObject& o = m_objects[i];
        const std::string field = "objects[" + std::to_string(i) + "]";
        validateShape<2>(o.shape0, field);
        if (!m_index.emplace(o.id, i).second) throw InvalidInput(field + ".id", "repeats id " + std::to_string(o.id));
    }
}

SimWorld SimWorld::fromScene(const std::string& name, const SceneData2& scene) {
    std::vector<SimObject> objects;
    objects.reserve(scene.objects.size());
    for (const SceneObject<2>& o : scene.objects)
        objects.push_back({o.id, o.shape, Vec2(0.0), o.velocity, o.maxSpeed, o.isStatic, o.role});
    return SimWorld(name, scene.grid, scene.camera, std::move(objects));
}

void SimWorld::step() {
    for (SimObject& o : m_objects) {
        if (o.isStatic || (o.velocity.x == 0 && o.velocity.y == 0)) continue;
        const Box<2> b = boundsOf<2>(o.shape());
        for (int a = 0; a < 2; ++a)
            o.translation[a] += reflectStep(b.min[a], b.max[a], m_bounds.min[a], m_bounds.max[a], o.velocity[a]);
    }
    ++m_frame;
}

std::size_t SimWorld::spawn(SpawnKind kind, const Vec2& at) {
    ObjectId id = 0;
    for (const SimObject& o : m_objects) id = std::max(id, o.id + 1);
    const double v = m_grid.voxelSize();
    SimObject o;
    o.id = id;
    o.isStatic = false;
    o.maxSpeed = 0;
    switch (kind) {
    case SpawnKind::Circle: o.shape0 = Ball<2>{at, 3 * v}; break;
    case SpawnKind::Box: o.shape0 = Box<2>{at - Vec2(3 * v, 2 * v), at + Vec2(3 * v, 2 * v)}; break;
    case SpawnKind::Polygon: {
        ConvexPolygon p;
        for (int k = 0; k < 5; ++k) {
            const double a = std::numbers::pi / 2 + 2 * std::numbers::pi * k / 5;
            p.points.push_back(at + 3 * v * Vec2(std::cos(a), std::sin(a)));
        }
        o.shape0 = p;
        break;
    }
    }
    validateShape<2>(o.shape0, "spawn");
    m_index.emplace(id, m_objects.size());
    m_objects.push_back(std::move(o));
    return m_objects.size() - 1;
}

void SimWorld::moveTo(std::size_t index, const Vec2& translation) { m_objects.at(index).translation = translation; }

std::optional<std::size_t> SimWorld::pick(const Vec2& p) const {
    for (std::size_t i = m_objects.size(); i-- > 0;)
        if (shapeContains(m_objects[i].shape(), p)) return i;
    return std::nullopt;
}

bool SimWorld::staysInGrid() const {
    // motionStaysInGrid's rule, on the objects as they are now (SceneObject is the rule's input type).
    SceneData2 scene{m_grid, m_camera, std::nullopt, {}};
    for (const SimObject& o : m_objects) {
        SceneObject<2> s;
        s.id = o.id;
        s.shape = o.shape();
        s.velocity = o.velocity;
        s.maxSpeed = o.maxSpeed;
        s.isStatic = o.isStatic;
        scene.objects.push_back(std::move(s));
    }
    return motionStaysInGrid(scene);
}

bool shapeContains(const Shape<2>& s, const Vec2& p) {
    return std::visit(
        [&](const auto& x) -> bool {
            using T = std::decay_t<decltype(x)>;
            if constexpr (std::is_same_v<T, Ball<2>>) {
                const Vec2 d = p - x.center;
                return glm::dot(d, d) <= x.radius * x.radius;
            } else if constexpr (std::is_same_v<T, Box<2>>) {
                return p.x >= x.min.x && p.x <= x.max.x && p.y >= x.min.y && p.y <= x.max.y;
            } else {
                // Counter-clockwise after validation: inside is left of (or on) every edge.
                const std::size_t n = x.points.size();
                for (std::size_t i = 0; i < n; ++i) {
                    const Vec2 a = x.points[i], b = x.points[(i + 1) % n];
                    if ((b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x) < 0) return false;
                }
                return true;
            }
        },
        s);
}

} // namespace rgvc::sim
