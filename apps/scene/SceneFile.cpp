// Scene file reader: JSON text -> validated rgvc::Scene, or one SceneError naming file, field, problem.
//
// Validation is done in two layers. This file checks what JSON can get wrong (presence, types, vector
// lengths, integer-ness, unknown shapes, dimension mismatches, duplicate ids); the library's own
// validators (validateShape, validateCamera, GridGeometry's constructor) then check the geometry, and
// their InvalidInput, which already names the field, is re-thrown with the file name in front. That
// keeps one definition of "a valid radius" for the library and its file format.
#include "SceneFile.hpp"

#include "MeshFile.hpp"
#include "SceneMesh.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <unordered_map>

namespace rgvc {

namespace {

using json = nlohmann::json;

// Messages must stay on one line whatever the file contains (names, echoed tokens): line breaks become
// spaces, other control characters \u00XX (a NUL in a key once cut what() short, found by
// fuzz_scene_loader).
std::string oneLine(const std::string& s) {
    std::string out;
    out.reserve(s.size());
    for (char c : s) {
        const auto u = static_cast<unsigned char>(c);
        if (c == '\n' || c == '\r') {
            out += ' ';
        } else if (u < 0x20 || u == 0x7F) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", unsigned(u));
            out += buf;
        } else {
            out += c;
        }
    }
    return out;
}

} // namespace

SceneError::SceneError(std::string file, std::string field, std::string problem)
    : std::runtime_error(oneLine(file + ": " + field + ": " + problem)), m_file(oneLine(file)),
      m_field(oneLine(field)), m_problem(oneLine(problem)) {}
// (The parts are flattened too, so that what() is always exactly "<file>: <field>: <problem>" of them:
// a field path can hold a key with a line break in it, found by fuzz_scene_loader.)

template <int D> std::size_t SceneData<D>::frameLimit() const {
    return cameraPath ? cameraPath->size() : std::numeric_limits<std::size_t>::max();
}

template <int D> Camera<D> SceneData<D>::cameraAt(std::size_t frame) const {
    Camera<D> c = camera;
    if (cameraPath) {
        const SceneCameraPose<D>& pose = cameraPath->at(frame);
        c.position = pose.position;
        c.direction = pose.direction;
    }
    return c;
}

template struct SceneData<2>;
template struct SceneData<3>;

namespace {

// ---------------------------------------------------------------------------------------------------
// Locating JSON syntax errors. nlohmann reports a byte offset; a user wants the line, the column and,
// when the error is a value (1e999 overflows double and is refused by the parser), the field it was
// meant for. A second, SAX-only pass over the failing text tracks the path of the value being read.

class PathTracker : public nlohmann::json_sax<json> {
public:
    std::string path() const {
        std::string p;
        for (const Level& l : m_levels) {
            if (l.array) {
                p += "[" + std::to_string(l.index < 0 ? 0 : l.index) + "]";
            } else if (!l.key.empty()) {
                if (!p.empty()) p += ".";
                p += l.key;
            }
        }
        return p;
    }
    std::size_t position = 0;
    std::string message;
    bool overflow = false;

    bool null() override { return value(); }
    bool boolean(bool) override { return value(); }
    bool number_integer(number_integer_t) override { return value(); }
    bool number_unsigned(number_unsigned_t) override { return value(); }
    bool number_float(number_float_t, const string_t&) override { return value(); }
    bool string(string_t&) override { return value(); }
    bool binary(binary_t&) override { return value(); }
    bool start_object(std::size_t) override {
        value();
        m_levels.push_back({false, -1, {}});
        return true;
    }
    bool key(string_t& k) override {
        m_levels.back().key = k;
        return true;
    }
    bool end_object() override {
        m_levels.pop_back();
        return true;
    }
    bool start_array(std::size_t) override {
        value();
        m_levels.push_back({true, -1, {}});
        return true;
    }
    bool end_array() override {
        m_levels.pop_back();
        return true;
    }
    bool parse_error(std::size_t pos, const std::string& lastToken, const nlohmann::detail::exception& ex) override {
        position = pos;
        message = ex.what();
        // Only the lexer's own overflow (a number token) belongs to a field; "number overflow" may also
        // be text quoted from a key in a syntax error (found by fuzz_scene_loader).
        overflow = message.find("number overflow") != std::string::npos && !lastToken.empty() &&
                   lastToken.find_first_not_of("0123456789+-.eE") == std::string::npos;
        // The failing value has not been counted yet: point at the element it would have been.
        if (!m_levels.empty() && m_levels.back().array) ++m_levels.back().index;
        return false;
    }

private:
    struct Level {
        bool array;
        long long index;
        std::string key;
    };
    bool value() {
        if (!m_levels.empty() && m_levels.back().array) ++m_levels.back().index;
        return true;
    }
    std::vector<Level> m_levels;
};

[[noreturn]] void throwJsonError(const std::string& text, const std::string& file, const std::string& firstError) {
    PathTracker tracker;
    json::sax_parse(text, &tracker, json::input_format_t::json, /*strict=*/true, /*ignore_comments=*/false);
    // Strip nlohmann's "[json.exception.parse_error.101] " tag: the user needs what, not which class.
    std::string what = tracker.message.empty() ? firstError : tracker.message;
    if (auto close = what.find("] "); what.rfind("[json.exception.", 0) == 0 && close != std::string::npos)
        what = what.substr(close + 2);
    // nlohmann's syntax errors read "parse error at line L, column C: <what>"; the position becomes the
    // field, since a syntax error belongs to no field. Overflowing numbers do belong to one: the path.
    std::string where;
    const std::string tag = "parse error at ";
    if (auto at = what.find(tag); at != std::string::npos) {
        auto colon = what.find(": ", at);
        if (colon != std::string::npos) {
            where = what.substr(at + tag.size(), colon - at - tag.size());
            what = what.substr(colon + 2);
        }
    }
    if (where.empty()) {
        std::size_t line = 1, column = 1;
        for (std::size_t i = 0; i + 1 < tracker.position && i < text.size(); ++i) {
            if (text[i] == '\n') {
                ++line;
                column = 1;
            } else {
                ++column;
            }
        }
        where = "line " + std::to_string(line) + ", column " + std::to_string(column);
    }
    const std::string path = tracker.path();
    if (tracker.overflow && !path.empty()) {
        throw SceneError(file, path, "number is not finite in double precision (" + what + ") at " + where);
    }
    throw SceneError(file, where, "invalid JSON: " + what);
}

// ---------------------------------------------------------------------------------------------------
// Typed access with field paths.

class Reader {
public:
    explicit Reader(std::string file) : m_file(std::move(file)) {}

    /// A path the file gives (a mesh's `file`), resolved against the scene file's directory.
    std::string resolve(const std::string& relative) const {
        return (std::filesystem::path(m_file).parent_path() / relative).string();
    }

    [[noreturn]] void fail(const std::string& field, const std::string& problem) const {
        throw SceneError(m_file, field, problem);
    }

    static std::string describe(const json& v) { return v.type_name(); }

    const json& require(const json& obj, const char* key, const std::string& path) const {
        auto it = obj.find(key);
        if (it == obj.end()) fail(join(path, key), "missing");
        return *it;
    }
    const json* optional(const json& obj, const char* key) const {
        auto it = obj.find(key);
        return it == obj.end() ? nullptr : &*it;
    }
    void requireObject(const json& v, const std::string& path) const {
        if (!v.is_object()) fail(path.empty() ? "(root)" : path, "must be an object, got " + describe(v));
    }
    void requireArray(const json& v, const std::string& path) const {
        if (!v.is_array()) fail(path, "must be an array, got " + describe(v));
    }

    double number(const json& v, const std::string& path) const {
        if (!v.is_number()) fail(path, "must be a number, got " + describe(v));
        double x = v.get<double>();
        if (!std::isfinite(x)) fail(path, "must be finite");
        return x;
    }

    /// A JSON integer, or a float with an integral value, in [lo, hi].
    long long integer(const json& v, const std::string& path, long long lo, long long hi) const {
        if (!v.is_number()) fail(path, "must be an integer, got " + describe(v));
        const std::string range = "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got ";
        if (v.is_number_unsigned()) {
            auto u = v.get<std::uint64_t>();
            if (u > std::uint64_t(hi) || static_cast<long long>(u) < lo) fail(path, range + std::to_string(u));
            return static_cast<long long>(u);
        }
        if (v.is_number_integer()) {
            auto i = v.get<std::int64_t>();
            if (i < 0 && lo == 0) fail(path, "must be a non-negative integer, got " + std::to_string(i));
            if (i < lo || i > hi) fail(path, range + std::to_string(i));
            return i;
        }
        double x = v.get<double>();
        if (!std::isfinite(x) || x != std::floor(x)) fail(path, "must be an integer, got " + v.dump());
        // Doubles above 2^53 no longer name one integer: refuse rather than guess.
        if (x < double(lo) || x > double(hi) || std::abs(x) > 9007199254740992.0) fail(path, range + v.dump());
        return static_cast<long long>(x);
    }

    template <int D> Vec<D> vec(const json& v, const std::string& path) const {
        if (!v.is_array()) fail(path, "must be an array of " + std::to_string(D) + " numbers, got " + describe(v));
        if (v.size() != std::size_t(D))
            fail(path, "must have " + std::to_string(D) + " components (dimensions is " + std::to_string(D) +
                           "), got " + std::to_string(v.size()));
        Vec<D> r(0.0);
        for (int i = 0; i < D; ++i) r[i] = number(v[std::size_t(i)], path + "[" + std::to_string(i) + "]");
        return r;
    }

    bool boolean(const json& v, const std::string& path) const {
        if (!v.is_boolean()) fail(path, "must be true or false, got " + describe(v));
        return v.get<bool>();
    }

    static std::string join(const std::string& path, const char* key) {
        return path.empty() ? std::string(key) : path + "." + key;
    }

    /// Runs a library validator and puts the file name in front of its InvalidInput.
    template <class F> void library(F&& f) const {
        try {
            f();
        } catch (const InvalidInput& e) {
            std::string what = e.what();
            std::string prefix = e.field() + ": ";
            fail(e.field(), what.rfind(prefix, 0) == 0 ? what.substr(prefix.size()) : what);
        }
    }

private:
    std::string m_file;
};

// ---------------------------------------------------------------------------------------------------

template <int D> GridGeometry<D> readGrid(const Reader& r, const json& root) {
    const json& g = r.require(root, "grid", "");
    r.requireObject(g, "grid");
    Vec<D> origin = r.vec<D>(r.require(g, "origin", "grid"), "grid.origin");
    double voxel = r.number(r.require(g, "voxel_size", "grid"), "grid.voxel_size");
    const json& res = r.require(g, "resolution", "grid");
    if (!res.is_array() || res.size() != std::size_t(D))
        r.fail("grid.resolution", "must be an array of " + std::to_string(D) + " integers");
    IVec<D> resolution(0);
    for (int i = 0; i < D; ++i)
        resolution[i] = std::int32_t(r.integer(res[std::size_t(i)], "grid.resolution[" + std::to_string(i) + "]", 1,
                                               std::numeric_limits<std::int32_t>::max()));
    GridGeometry<D> grid;
    r.library([&] { grid = GridGeometry<D>(origin, voxel, resolution); });
    return grid;
}

// 3D only: `up` must not be parallel to the direction (the frustum would have no "right" axis).
// Relative test, so that it does not depend on the lengths the file happens to use.
void checkUpNotParallel(const Reader& r, const Vec3& up, const Vec3& dir, const std::string& field,
                        const char* other) {
    Vec3 c(up.y * dir.z - up.z * dir.y, up.z * dir.x - up.x * dir.z, up.x * dir.y - up.y * dir.x);
    if (!(lengthSquared<3>(c) > 1e-18 * lengthSquared<3>(up) * lengthSquared<3>(dir)))
        r.fail(field, std::string("must not be parallel to ") + other);
}

template <int D> Camera<D> readCamera(const Reader& r, const json& root) {
    const json& c = r.require(root, "camera", "");
    r.requireObject(c, "camera");
    Camera<D> cam;
    cam.position = r.vec<D>(r.require(c, "position", "camera"), "camera.position");
    cam.direction = r.vec<D>(r.require(c, "direction", "camera"), "camera.direction");
    cam.fovDeg = r.number(r.require(c, "fov_deg", "camera"), "camera.fov_deg");
    if (const json* far = r.optional(c, "far"); far && !far->is_null()) cam.far = r.number(*far, "camera.far");
    if constexpr (D == 3) {
        cam.up = Vec3(0.0, 1.0, 0.0);
        if (const json* up = r.optional(c, "up")) {
            cam.up = r.vec<3>(*up, "camera.up");
            if (!(lengthSquared<3>(cam.up) > 0)) r.fail("camera.up", "must be non-zero");
        }
        if (const json* aspect = r.optional(c, "aspect")) cam.aspect = r.number(*aspect, "camera.aspect");
    }
    r.library([&] { validateCamera<D>(cam, "camera"); });
    // Blame the field the file wrote: an explicit `up`, else the direction against the default up.
    if constexpr (D == 3) {
        if (r.optional(c, "up"))
            checkUpNotParallel(r, cam.up, cam.direction, "camera.up", "camera.direction");
        else
            checkUpNotParallel(r, cam.up, cam.direction, "camera.direction", "camera.up (default [0, 1, 0])");
    }
    return cam;
}

template <int D>
std::optional<std::vector<SceneCameraPose<D>>> readPath(const Reader& r, const json& root, const Camera<D>& camera) {
    const json* p = r.optional(root, "camera_path");
    if (!p) return std::nullopt;
    r.requireArray(*p, "camera_path");
    std::vector<SceneCameraPose<D>> path;
    path.reserve(p->size());
    for (std::size_t t = 0; t < p->size(); ++t) {
        std::string f = "camera_path[" + std::to_string(t) + "]";
        const json& e = (*p)[t];
        r.requireObject(e, f);
        SceneCameraPose<D> pose;
        pose.position = r.vec<D>(r.require(e, "position", f), f + ".position");
        pose.direction = r.vec<D>(r.require(e, "direction", f), f + ".direction");
        // The frame's camera is `camera` with this pose: validate exactly that.
        Camera<D> c = camera;
        c.position = pose.position;
        c.direction = pose.direction;
        r.library([&] { validateCamera<D>(c, f); });
        if constexpr (D == 3) checkUpNotParallel(r, c.up, c.direction, f + ".direction", "camera.up");
        path.push_back(pose);
    }
    return path;
}

// `rotation`: a unit quaternion [x, y, z, w] within kQuaternionTolerance, normalised.
std::array<double, 4> readQuaternion(const Reader& r, const json& q, const std::string& field) {
    if (!q.is_array() || q.size() != 4)
        r.fail(field, "must be a unit quaternion [x, y, z, w] (4 numbers), got " +
                          (q.is_array() ? std::to_string(q.size()) + " numbers" : Reader::describe(q)));
    std::array<double, 4> rot{};
    for (std::size_t i = 0; i < 4; ++i) rot[i] = r.number(q[i], field + "[" + std::to_string(i) + "]");
    const double len = std::sqrt(rot[0] * rot[0] + rot[1] * rot[1] + rot[2] * rot[2] + rot[3] * rot[3]);
    if (!(std::abs(len - 1) <= kQuaternionTolerance))
        r.fail(field, "must be a unit quaternion (length " + std::to_string(len) + ")");
    for (double& c : rot) c /= len;
    return rot;
}

// `"shape": "mesh"`: the file read, placed and made a MeshSolid (SceneMesh.cpp).
Shape<3> readMesh(const Reader& r, const json& o, const std::string& f, std::optional<SceneMeshInfo>& info) {
    const json& file = r.require(o, "file", f);
    if (!file.is_string() || file.get<std::string>().empty())
        r.fail(f + ".file", "must be a non-empty string (a .gltf, .glb or .obj file relative to the scene file)");
    MeshPlacement placement;
    if (const json* t = r.optional(o, "translation")) placement.translation = r.vec<3>(*t, f + ".translation");
    if (const json* q = r.optional(o, "rotation")) placement.rotation = readQuaternion(r, *q, f + ".rotation");
    if (const json* sc = r.optional(o, "scale")) {
        if (sc->is_number()) {
            const double s = r.number(*sc, f + ".scale");
            placement.scale = Vec3(s, s, s);
        } else if (sc->is_array()) {
            placement.scale = r.vec<3>(*sc, f + ".scale");
        } else {
            r.fail(f + ".scale", "must be a number or an array of 3 numbers, got " + Reader::describe(*sc));
        }
        for (int a = 0; a < 3; ++a)
            if (placement.scale[a] == 0) r.fail(f + ".scale", "must be non-zero on every axis");
    }
    SceneMeshInfo mesh;
    Shape<3> shape;
    try {
        r.library([&] { shape = sceneMeshShape(r.resolve(file.get<std::string>()), placement, f, mesh); });
    } catch (const MeshFileError& e) {
        r.fail(f + ".file", e.what());
    }
    info = mesh;
    return shape;
}

template <int D>
Shape<D> readShape(const Reader& r, const json& o, const std::string& f, std::optional<SceneMeshInfo>& mesh) {
    const json& kind = r.require(o, "shape", f);
    if (!kind.is_string()) r.fail(f + ".shape", "must be a string, got " + Reader::describe(kind));
    const std::string name = kind.get<std::string>();
    const char* expected = D == 2 ? "circle, box or polygon" : "sphere, box, obb, hull or mesh";
    Shape<D> shape;
    if (name == "circle" || name == "sphere") {
        if ((name == "circle") != (D == 2))
            r.fail(f + ".shape", "\"" + name + "\" is a " + (D == 2 ? "3D" : "2D") + " shape; a " +
                                     std::to_string(D) + "D scene uses \"" + (D == 2 ? "circle" : "sphere") + "\"");
        Ball<D> b;
        b.center = r.vec<D>(r.require(o, "center", f), f + ".center");
        b.radius = r.number(r.require(o, "radius", f), f + ".radius");
        shape = b;
    } else if (name == "box") {
        Box<D> b;
        b.min = r.vec<D>(r.require(o, "min", f), f + ".min");
        b.max = r.vec<D>(r.require(o, "max", f), f + ".max");
        shape = b;
    } else if (name == "polygon") {
        if constexpr (D == 2) {
            const json& pts = r.require(o, "points", f);
            r.requireArray(pts, f + ".points");
            ConvexPolygon poly;
            poly.points.reserve(pts.size());
            for (std::size_t i = 0; i < pts.size(); ++i)
                poly.points.push_back(r.vec<2>(pts[i], f + ".points[" + std::to_string(i) + "]"));
            shape = std::move(poly);
        } else {
            r.fail(f + ".shape", "\"polygon\" is a 2D shape; a 3D scene has " + std::string(expected));
        }
    } else if (name == "mesh") {
        if constexpr (D == 3) {
            shape = readMesh(r, o, f, mesh);
        } else {
            r.fail(f + ".shape", "\"mesh\" is a 3D shape; a 2D scene has " + std::string(expected));
        }
    } else if (name == "obb" || name == "hull") {
        if constexpr (D == 3) {
            if (name == "obb") {
                const Vec3 center = r.vec<3>(r.require(o, "center", f), f + ".center");
                const Vec3 half = r.vec<3>(r.require(o, "half_extents", f), f + ".half_extents");
                const json& q = r.require(o, "rotation", f);
                if (!q.is_array() || q.size() != 4)
                    r.fail(f + ".rotation", "must be a unit quaternion [x, y, z, w] (4 numbers), got " +
                                                (q.is_array() ? std::to_string(q.size()) + " numbers" : Reader::describe(q)));
                std::array<double, 4> rot{};
                for (std::size_t i = 0; i < 4; ++i) rot[i] = r.number(q[i], f + ".rotation[" + std::to_string(i) + "]");
                r.library([&] { shape = makeOrientedBox(center, half, rot, f); });
            } else {
                const json& pts = r.require(o, "points", f);
                r.requireArray(pts, f + ".points");
                if (pts.size() > kMaxHullPoints)
                    r.fail(f + ".points", "at most " + std::to_string(kMaxHullPoints) + " points, got " + std::to_string(pts.size()));
                std::vector<Vec3> points;
                points.reserve(pts.size());
                for (std::size_t i = 0; i < pts.size(); ++i)
                    points.push_back(r.vec<3>(pts[i], f + ".points[" + std::to_string(i) + "]"));
                r.library([&] { shape = makeConvexHull(points, f + ".points"); });
            }
        } else {
            r.fail(f + ".shape", "\"" + name + "\" is a 3D shape; a 2D scene has " + std::string(expected));
        }
    } else {
        r.fail(f + ".shape", "unknown shape \"" + name + "\" (expected " + expected + ")");
    }
    r.library([&] { validateShape<D>(shape, f); });
    return shape;
}

template <int D> std::vector<SceneObject<D>> readObjects(const Reader& r, const json& root) {
    const json& arr = r.require(root, "objects", "");
    r.requireArray(arr, "objects");
    std::vector<SceneObject<D>> objects;
    objects.reserve(arr.size());
    std::unordered_map<ObjectId, std::size_t> seen;
    seen.reserve(arr.size());
    for (std::size_t i = 0; i < arr.size(); ++i) {
        const std::string f = "objects[" + std::to_string(i) + "]";
        const json& o = arr[i];
        r.requireObject(o, f);
        SceneObject<D> obj;
        obj.id = ObjectId(r.integer(r.require(o, "id", f), f + ".id", 0, std::numeric_limits<long long>::max()));
        auto [it, fresh] = seen.emplace(obj.id, i);
        if (!fresh)
            r.fail(f + ".id", "duplicate id " + std::to_string(obj.id) + " (also objects[" + std::to_string(it->second) + "])");
        obj.shape = readShape<D>(r, o, f, obj.mesh);

        if (const json* v = r.optional(o, "velocity")) obj.velocity = r.vec<D>(*v, f + ".velocity");
        const double speed = std::sqrt(lengthSquared<D>(obj.velocity));
        if (!std::isfinite(speed)) r.fail(f + ".velocity", "length overflows double precision");
        const json* ms = r.optional(o, "max_speed");
        obj.maxSpeed = speed;
        if (ms) {
            obj.maxSpeed = r.number(*ms, f + ".max_speed");
            if (obj.maxSpeed < 0) r.fail(f + ".max_speed", "must be >= 0, got " + ms->dump());
            // Reflection keeps |velocity| per frame; a smaller bound would make TBVs too small.
            if (obj.maxSpeed < speed)
                r.fail(f + ".max_speed", "must be >= the length of velocity (" + std::to_string(speed) + "), got " + ms->dump());
        }
        obj.isStatic = speed == 0 && !ms;
        if (const json* st = r.optional(o, "static")) {
            obj.isStatic = r.boolean(*st, f + ".static");
            if (obj.isStatic && speed != 0) r.fail(f + ".static", "a static object must have zero velocity");
        }
        if (const json* inset = r.optional(o, "occluder_inset")) {
            obj.occluderInset = r.number(*inset, f + ".occluder_inset");
            if (obj.occluderInset < 0) r.fail(f + ".occluder_inset", "must be >= 0, got " + inset->dump());
        }
        if (const json* role = r.optional(o, "role")) {
            const std::string name = role->is_string() ? role->get<std::string>() : std::string();
            if (name == "both") obj.role = ObjectRole::Both;
            else if (name == "occludee") obj.role = ObjectRole::Occludee;
            else if (name == "occluder") obj.role = ObjectRole::Occluder;
            else
                r.fail(f + ".role", "must be \"both\", \"occludee\" or \"occluder\", got " +
                                        (role->is_string() ? role->dump() : Reader::describe(*role)));
        }
        // A closed mesh is a solid and keeps its role; an open one is a surface, which hides nothing
        // (scene-format.md): it becomes an occludee, the file's role kept in the mesh info (SceneMesh.cpp).
        if (obj.mesh) {
            obj.mesh->requestedRole = obj.role;
            if (!obj.mesh->closed) obj.role = ObjectRole::Occludee;
        }
        objects.push_back(std::move(obj));
    }
    return objects;
}

template <int D> SceneData<D> readScene(const Reader& r, const json& root) {
    SceneData<D> s;
    s.grid = readGrid<D>(r, root);
    s.camera = readCamera<D>(r, root);
    s.cameraPath = readPath<D>(r, root, s.camera);
    s.objects = readObjects<D>(r, root);
    return s;
}

} // namespace

Scene parseScene(const std::string& jsonText, const std::string& nameForErrors) {
    // nlohmann's parser stops at a NUL byte as at the end of input; JSON text never contains one.
    if (const std::size_t nul = jsonText.find('\0'); nul != std::string::npos)
        throw SceneError(nameForErrors, "byte " + std::to_string(nul), "invalid JSON: a NUL byte");
    json root;
    try {
        root = json::parse(jsonText, nullptr, /*allow_exceptions=*/true, /*ignore_comments=*/false);
    } catch (const json::exception& e) {
        throwJsonError(jsonText, nameForErrors, e.what());
    }
    Reader r(nameForErrors);
    r.requireObject(root, "");
    Scene scene;
    scene.name = nameForErrors;
    scene.dimensions = int(r.integer(r.require(root, "dimensions", ""), "dimensions", 2, 3));
    if (scene.dimensions == 2)
        scene.data = readScene<2>(r, root);
    else
        scene.data = readScene<3>(r, root);
    return scene;
}

Scene loadScene(const std::string& path) {
    // A directory opens as a stream on Linux and then reads as empty: say what it is instead.
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw SceneError(path, "file", "is a directory, not a scene file");
    errno = 0;
    std::ifstream in(path, std::ios::binary);
    if (!in)
        throw SceneError(path, "file", std::string("cannot open for reading: ") + std::strerror(errno ? errno : ENOENT));
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) throw SceneError(path, "file", "read error");
    return parseScene(text, path);
}

void requireFrames(const Scene& scene, std::size_t frames) {
    std::size_t limit = std::visit([](const auto& s) { return s.frameLimit(); }, scene.data);
    if (frames > limit)
        throw SceneError(scene.name, "camera_path",
                         "has " + std::to_string(limit) + " entries, fewer than the " + std::to_string(frames) +
                             " frames asked for");
}

} // namespace rgvc
