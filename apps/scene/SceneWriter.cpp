// The scene writer (SceneWriter.hpp) over nlohmann::ordered_json: fields in the order the format's
// example gives them, numbers as nlohmann writes doubles (the shortest form that reads back exactly).
#include "SceneWriter.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <string>
#include <type_traits>
#include <variant>

namespace rgvc {

namespace {

using json = nlohmann::ordered_json;

template <int D> json vec(const Vec<D>& v) {
    json a = json::array();
    for (int i = 0; i < D; ++i) a.push_back(v[i]);
    return a;
}

/// Where a mesh object's triangles go: writeSceneFile writes them to a file of their own and returns its
/// name as the scene file is to give it (relative to the scene); sceneToJson has nowhere to put them (null).
using MeshSink = std::function<std::string(ObjectId, const MeshSolid&)>;

/// The shape's fields. One case per alternative of Shape<D> and no generic one: a shape added to the
/// variant fails to compile here until the writer handles it.
template <int D> void writeShape(json& o, const Shape<D>& shape, ObjectId id, const std::string& field, const MeshSink& meshes) {
    std::visit(
        [&](const auto& s) {
            using T = std::decay_t<decltype(s)>;
            if constexpr (std::is_same_v<T, Ball<D>>) {
                o["shape"] = D == 2 ? "circle" : "sphere";
                o["center"] = vec<D>(s.center);
                o["radius"] = s.radius;
            } else if constexpr (std::is_same_v<T, Box<D>>) {
                o["shape"] = "box";
                o["min"] = vec<D>(s.min);
                o["max"] = vec<D>(s.max);
            } else if constexpr (std::is_same_v<T, ConvexPolygon>) {
                o["shape"] = "polygon";
                json pts = json::array();
                for (const Vec2& p : s.points) pts.push_back(vec<2>(p));
                o["points"] = std::move(pts);
            } else if constexpr (std::is_same_v<T, ConvexPolytope>) {
                // Oriented boxes and hulls are both polytopes once loaded: written as the hull of the
                // vertices (an obb's 8 corners), which the loader rebuilds into the same solid.
                o["shape"] = "hull";
                json pts = json::array();
                for (const Vec3& p : s.vertices) pts.push_back(vec<3>(p));
                o["points"] = std::move(pts);
            } else if constexpr (std::is_same_v<T, MeshSolid>) {
                // A mesh lives in a file (scene-format.md: `file`, relative to the scene): its placed
                // vertices are written there, so the object needs no translation, rotation or scale.
                if (!meshes)
                    throw InvalidInput(field, "a mesh object needs a file of its own: writeSceneFile writes it next to the "
                                              "scene, sceneToJson alone cannot");
                o["shape"] = "mesh";
                o["file"] = meshes(id, s);
            } else {
                static_assert(sizeof(T) == 0, "sceneToJson: a Shape<D> alternative the scene writer does not handle");
            }
        },
        shape);
}

template <int D> json cameraJson(const Camera<D>& c) {
    json cam;
    cam["position"] = vec<D>(c.position);
    cam["direction"] = vec<D>(c.direction);
    cam["fov_deg"] = c.fovDeg;
    if (std::isfinite(c.far)) cam["far"] = c.far;
    if constexpr (D == 3) {
        cam["aspect"] = c.aspect;
        cam["up"] = vec<3>(cameraUp(c)); // the loader's default up is (0, 1, 0), not cameraUp's
    }
    return cam;
}

/// The mesh as an OBJ file: its placed vertices to 17 significant digits (they read back bit for bit, so the
/// loader rebuilds the same solid and hull), its triangles 1-based.
void writeObj(const std::string& path, const MeshSolid& m) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) throw SceneError(path, "file", "cannot be opened for writing");
    out << "# rgvc scene dump: a mesh object's placed triangles\n";
    char buf[96];
    for (const Vec3& p : m.model()->mesh.positions) {
        const Vec3 q = m.place(p);
        std::snprintf(buf, sizeof buf, "v %.17g %.17g %.17g\n", q.x, q.y, q.z);
        out << buf;
    }
    for (const auto& t : m.model()->mesh.triangles) out << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
    out.flush();
    if (!out) throw SceneError(path, "file", "could not be written");
}

template <int D>
std::string sceneJson(const GridGeometry<D>& grid, const std::vector<ObjectDesc<D>>& objects, const Camera<D>& camera,
                      const SceneVelocities<D>* velocities, const MeshSink& meshes) {
    validateCamera<D>(camera);
    json root;
    root["dimensions"] = D;
    root["grid"] = {{"origin", vec<D>(grid.origin())}, {"voxel_size", grid.voxelSize()}, {"resolution", json::array()}};
    for (int a = 0; a < D; ++a) root["grid"]["resolution"].push_back(grid.resolution()[a]);
    root["camera"] = cameraJson<D>(camera);
    json list = json::array();
    for (const ObjectDesc<D>& d : objects) {
        const std::string field = "object " + std::to_string(d.id);
        Shape<D> shape = d.shape;
        validateShape<D>(shape, field);
        json o;
        o["id"] = d.id;
        writeShape<D>(o, shape, d.id, field, meshes);
        if (d.isStatic) {
            o["static"] = true;
        } else {
            if (!std::isfinite(d.maxSpeed) || d.maxSpeed < 0) throw InvalidInput(field + ".max_speed", "must be finite and >= 0");
            o["max_speed"] = d.maxSpeed;
        }
        if (velocities) {
            if (auto it = velocities->find(d.id); it != velocities->end()) {
                const Vec<D>& v = it->second;
                if (!allFinite<D>(v)) throw InvalidInput(field + ".velocity", "must be finite");
                const double speed = std::sqrt(lengthSquared<D>(v));
                if (d.isStatic && speed != 0) throw InvalidInput(field + ".velocity", "a static object cannot move");
                if (speed > d.maxSpeed && !d.isStatic)
                    throw InvalidInput(field + ".velocity", "longer than the object's max_speed " + std::to_string(d.maxSpeed));
                o["velocity"] = vec<D>(v);
            }
        }
        if (d.role != ObjectRole::Both) o["role"] = toString(d.role);
        if (d.occluderInset != 0) o["occluder_inset"] = d.occluderInset;
        list.push_back(std::move(o));
    }
    root["objects"] = std::move(list);
    return root.dump(1) + "\n";
}

} // namespace

template <int D>
std::string sceneToJson(const GridGeometry<D>& grid, const std::vector<ObjectDesc<D>>& objects, const Camera<D>& camera,
                        const SceneVelocities<D>* velocities) {
    return sceneJson<D>(grid, objects, camera, velocities, nullptr);
}

template <int D> std::string sceneToJson(const Culler<D>& culler, const Camera<D>& camera, const SceneVelocities<D>* velocities) {
    return sceneToJson<D>(culler.grid(), culler.objects(), camera, velocities);
}

template <int D>
void writeSceneFile(const std::string& path, const Culler<D>& culler, const Camera<D>& camera, const SceneVelocities<D>* velocities) {
    // Mesh objects: "<scene name without .json>.mesh-<id>.obj" in the scene's directory.
    const std::size_t slash = path.find_last_of('/');
    const std::string dir = slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
    std::string stem = slash == std::string::npos ? path : path.substr(slash + 1);
    if (stem.size() > 5 && stem.compare(stem.size() - 5, 5, ".json") == 0) stem.resize(stem.size() - 5);
    const MeshSink meshes = [&](ObjectId id, const MeshSolid& m) {
        const std::string name = stem + ".mesh-" + std::to_string(id) + ".obj";
        writeObj(dir + name, m);
        return name;
    };
    const std::string text = sceneJson<D>(culler.grid(), culler.objects(), camera, velocities, meshes);
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) throw SceneError(path, "file", "cannot be opened for writing");
    out << text;
    out.flush();
    if (!out) throw SceneError(path, "file", "could not be written");
}

template std::string sceneToJson<2>(const GridGeometry<2>&, const std::vector<ObjectDesc<2>>&, const Camera<2>&, const SceneVelocities<2>*);
template std::string sceneToJson<3>(const GridGeometry<3>&, const std::vector<ObjectDesc<3>>&, const Camera<3>&, const SceneVelocities<3>*);
template std::string sceneToJson<2>(const Culler<2>&, const Camera<2>&, const SceneVelocities<2>*);
template std::string sceneToJson<3>(const Culler<3>&, const Camera<3>&, const SceneVelocities<3>*);
template void writeSceneFile<2>(const std::string&, const Culler<2>&, const Camera<2>&, const SceneVelocities<2>*);
template void writeSceneFile<3>(const std::string&, const Culler<3>&, const Camera<3>&, const SceneVelocities<3>*);

} // namespace rgvc
