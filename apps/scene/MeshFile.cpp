// OBJ and glTF readers behind readMeshFile (MeshFile.hpp). Both libraries are Debian's shared builds
// (tinyobjloader_double, tinygltf): well-kept parsers, so nothing here parses text or JSON itself. What
// is hand-written is the part the libraries leave to the caller: bounds checks of glTF accessors
// against their buffers, and the node hierarchy's transforms.
#include "MeshFile.hpp"

#include "rgvc/grid/Error.hpp"

#include <tiny_gltf.h>
#include <tiny_obj_loader.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstring>
#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>

namespace rgvc {

namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const std::string& problem) {
    std::string s = problem;
    for (char& c : s)
        if (c == '\n' || c == '\r') c = ' ';
    while (!s.empty() && s.back() == ' ') s.pop_back();
    throw MeshFileError(s);
}

// Adds triangle (a, b, c) unless it repeats an index (zero area: it adds no point to the mesh that its
// other triangles' vertices do not hold... and validateMesh refuses it).
void addTriangle(TriangleMesh& m, std::uint64_t a, std::uint64_t b, std::uint64_t c) {
    const std::uint64_t n = m.positions.size();
    if (a >= n || b >= n || c >= n)
        fail("triangle " + std::to_string(m.triangles.size()) + " has a vertex index out of range (" + std::to_string(std::max({a, b, c})) +
             " with " + std::to_string(n) + " vertices)");
    if (a == b || b == c || a == c) return;
    if (m.triangles.size() >= kMaxMeshTriangles) fail("more than " + std::to_string(kMaxMeshTriangles) + " triangles");
    m.triangles.push_back({std::uint32_t(a), std::uint32_t(b), std::uint32_t(c)});
}

// ---------------------------------------------------------------------------------------------------
// OBJ

// tinyobjloader reads a coordinate it cannot parse ("nan", "x") as 0 without a word, which would put a
// vertex somewhere the file never said. So the `v` lines are checked first, with strtod: three finite
// numbers (an optional fourth, w, is ignored as tinyobjloader ignores it).
void checkObjVertices(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail("cannot open for reading");
    std::string line;
    for (std::size_t lineNo = 1; std::getline(in, line); ++lineNo) {
        std::size_t i = line.find_first_not_of(" \t");
        if (i == std::string::npos || line[i] != 'v' || i + 1 >= line.size() || (line[i + 1] != ' ' && line[i + 1] != '\t'))
            continue;
        const char* p = line.c_str() + i + 1;
        for (int k = 0; k < 3; ++k) {
            while (*p == ' ' || *p == '\t') ++p;
            char* end = nullptr;
            errno = 0;
            const double x = std::strtod(p, &end);
            std::string token(p, std::size_t(end > p ? end - p : 0));
            if (end == p) {
                const char* e = p;
                while (*e && *e != ' ' && *e != '\t' && *e != '\r') ++e;
                token.assign(p, std::size_t(e - p));
            }
            if (end == p || !std::isfinite(x) || (*end && *end != ' ' && *end != '\t' && *end != '\r'))
                fail("OBJ line " + std::to_string(lineNo) + ": vertex coordinate " + std::to_string(k) + " (\"" + token +
                     "\") is not a finite number");
            p = end;
        }
    }
}

TriangleMesh readObj(const std::string& path) {
    checkObjVertices(path);
    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
    config.vertex_color = false;
    config.mtl_search_path = fs::path(path).parent_path().string();
    tinyobj::ObjReader reader;
    if (!reader.ParseFromFile(path, config)) fail("OBJ: " + (reader.Error().empty() ? std::string("cannot parse") : reader.Error()));
    const tinyobj::attrib_t& attrib = reader.GetAttrib();
    TriangleMesh m;
    if (attrib.vertices.size() / 3 > kMaxMeshVertices) fail("more than " + std::to_string(kMaxMeshVertices) + " vertices");
    m.positions.reserve(attrib.vertices.size() / 3);
    for (std::size_t i = 0; i + 2 < attrib.vertices.size(); i += 3)
        m.positions.emplace_back(attrib.vertices[i], attrib.vertices[i + 1], attrib.vertices[i + 2]);
    for (const tinyobj::shape_t& s : reader.GetShapes()) {
        std::size_t at = 0;
        for (std::size_t f = 0; f < s.mesh.num_face_vertices.size(); ++f) {
            const std::size_t n = s.mesh.num_face_vertices[f];
            if (at + n > s.mesh.indices.size()) fail("OBJ: face list shorter than its vertex counts");
            if (n == 3) {
                std::array<std::uint64_t, 3> v{};
                for (std::size_t k = 0; k < 3; ++k) {
                    const int idx = s.mesh.indices[at + k].vertex_index;
                    // tinyobjloader resolves negative (relative) indices; what is still negative is bad.
                    v[k] = idx < 0 ? std::numeric_limits<std::uint64_t>::max() : std::uint64_t(idx);
                }
                addTriangle(m, v[0], v[1], v[2]);
            }
            at += n; // faces of fewer than 3 vertices (lines, points) are no triangles
        }
    }
    return m;
}

// ---------------------------------------------------------------------------------------------------
// glTF

using Mat4 = std::array<double, 16>; // column-major, as glTF writes `matrix`

Mat4 identity() { return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}; }

Mat4 multiply(const Mat4& a, const Mat4& b) {
    Mat4 r{};
    for (int c = 0; c < 4; ++c)
        for (int row = 0; row < 4; ++row) {
            double s = 0;
            for (int k = 0; k < 4; ++k) s += a[std::size_t(k * 4 + row)] * b[std::size_t(c * 4 + k)];
            r[std::size_t(c * 4 + row)] = s;
        }
    return r;
}

Mat4 localMatrix(const tinygltf::Node& n, std::size_t index) {
    const std::string where = "node " + std::to_string(index);
    if (n.matrix.size() == 16) {
        Mat4 m{};
        for (std::size_t i = 0; i < 16; ++i) m[i] = n.matrix[i];
        return m;
    }
    Mat4 t = identity(), r = identity(), s = identity();
    if (n.translation.size() == 3)
        for (int i = 0; i < 3; ++i) t[std::size_t(12 + i)] = n.translation[std::size_t(i)];
    if (n.scale.size() == 3)
        for (int i = 0; i < 3; ++i) s[std::size_t(i * 5)] = n.scale[std::size_t(i)];
    if (n.rotation.size() == 4) {
        double x = n.rotation[0], y = n.rotation[1], z = n.rotation[2], w = n.rotation[3];
        const double len = std::sqrt(x * x + y * y + z * z + w * w);
        if (!(len > 0) || !std::isfinite(len)) fail(where + ": rotation is not a quaternion");
        x /= len, y /= len, z /= len, w /= len;
        r = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w), 0,
             2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w), 0,
             2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y), 0,
             0, 0, 0, 1};
    }
    return multiply(t, multiply(r, s));
}

// The bytes of accessor `a` (element size `elem`), checked against its view and buffer.
struct AccessorBytes {
    const unsigned char* data = nullptr;
    std::size_t stride = 0, count = 0;
};

AccessorBytes accessorBytes(const tinygltf::Model& model, int index, std::size_t elem, const std::string& what) {
    if (index < 0 || std::size_t(index) >= model.accessors.size()) fail(what + ": accessor " + std::to_string(index) + " does not exist");
    const tinygltf::Accessor& a = model.accessors[std::size_t(index)];
    if (a.sparse.isSparse) fail(what + ": sparse accessors are not supported");
    if (a.bufferView < 0 || std::size_t(a.bufferView) >= model.bufferViews.size()) fail(what + ": accessor without a buffer view");
    const tinygltf::BufferView& v = model.bufferViews[std::size_t(a.bufferView)];
    if (v.buffer < 0 || std::size_t(v.buffer) >= model.buffers.size()) fail(what + ": buffer view without a buffer");
    const std::vector<unsigned char>& buf = model.buffers[std::size_t(v.buffer)].data;
    const std::size_t stride = v.byteStride ? v.byteStride : elem;
    if (stride < elem) fail(what + ": byteStride smaller than an element");
    AccessorBytes r{nullptr, stride, a.count};
    if (a.count == 0) return r;
    // Everything in size_t with overflow guards: offsets come from the file.
    const std::size_t limit = std::numeric_limits<std::size_t>::max() / 4;
    if (a.count > limit / stride || a.byteOffset > limit || v.byteOffset > limit || v.byteLength > limit)
        fail(what + ": accessor too large");
    const std::size_t span = a.byteOffset + stride * (a.count - 1) + elem;
    if (span > v.byteLength || v.byteOffset + v.byteLength > buf.size())
        fail(what + ": accessor runs past the end of its buffer (truncated file?)");
    r.data = buf.data() + v.byteOffset + a.byteOffset;
    return r;
}

void addPrimitive(const tinygltf::Model& model, const tinygltf::Primitive& p, const Mat4& m, TriangleMesh& out,
                  const std::string& where) {
    const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES)
        fail(where + ": mode " + std::to_string(mode) + " is not supported (only TRIANGLES, mode 4)");
    auto pos = p.attributes.find("POSITION");
    if (pos == p.attributes.end()) fail(where + ": no POSITION attribute");
    const tinygltf::Accessor* pa =
        pos->second >= 0 && std::size_t(pos->second) < model.accessors.size() ? &model.accessors[std::size_t(pos->second)] : nullptr;
    if (pa && (pa->type != TINYGLTF_TYPE_VEC3 || pa->componentType != TINYGLTF_COMPONENT_TYPE_FLOAT))
        fail(where + ": POSITION must be a float VEC3 accessor");
    const AccessorBytes vb = accessorBytes(model, pos->second, 12, where + " POSITION");
    const std::size_t base = out.positions.size();
    if (vb.count > kMaxMeshVertices - base) fail("more than " + std::to_string(kMaxMeshVertices) + " vertices");
    for (std::size_t i = 0; i < vb.count; ++i) {
        float f[3];
        std::memcpy(f, vb.data + i * vb.stride, sizeof f);
        const double x = f[0], y = f[1], z = f[2];
        if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
            fail(where + ": vertex " + std::to_string(i) + " is not finite");
        out.positions.emplace_back(m[0] * x + m[4] * y + m[8] * z + m[12], m[1] * x + m[5] * y + m[9] * z + m[13],
                                   m[2] * x + m[6] * y + m[10] * z + m[14]);
    }
    if (p.indices < 0) {
        if (vb.count % 3 != 0) fail(where + ": vertex count is not a multiple of 3");
        for (std::size_t i = 0; i + 2 < vb.count; i += 3) addTriangle(out, base + i, base + i + 1, base + i + 2);
        return;
    }
    if (std::size_t(p.indices) >= model.accessors.size()) fail(where + ": index accessor does not exist");
    const tinygltf::Accessor& ia = model.accessors[std::size_t(p.indices)];
    std::size_t size = 0;
    switch (ia.componentType) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: size = 1; break;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: size = 2; break;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: size = 4; break;
    default: fail(where + ": indices must be unsigned byte, short or int");
    }
    if (ia.type != TINYGLTF_TYPE_SCALAR) fail(where + ": indices must be SCALAR");
    const AccessorBytes ib = accessorBytes(model, p.indices, size, where + " indices");
    if (ib.count % 3 != 0) fail(where + ": index count is not a multiple of 3");
    auto index = [&](std::size_t i) -> std::uint64_t {
        const unsigned char* q = ib.data + i * ib.stride;
        if (size == 1) return q[0];
        if (size == 2) {
            std::uint16_t v;
            std::memcpy(&v, q, 2);
            return v;
        }
        std::uint32_t v;
        std::memcpy(&v, q, 4);
        return v;
    };
    for (std::size_t i = 0; i + 2 < ib.count; i += 3) {
        const std::uint64_t a = index(i), b = index(i + 1), c = index(i + 2);
        if (a >= vb.count || b >= vb.count || c >= vb.count)
            fail(where + ": index " + std::to_string(std::max({a, b, c})) + " out of range (" + std::to_string(vb.count) + " vertices)");
        addTriangle(out, base + a, base + b, base + c);
    }
}

void addMesh(const tinygltf::Model& model, int mesh, const Mat4& m, TriangleMesh& out) {
    if (mesh < 0 || std::size_t(mesh) >= model.meshes.size()) fail("mesh " + std::to_string(mesh) + " does not exist");
    const tinygltf::Mesh& me = model.meshes[std::size_t(mesh)];
    for (std::size_t k = 0; k < me.primitives.size(); ++k)
        addPrimitive(model, me.primitives[k], m, out, "mesh " + std::to_string(mesh) + " primitive " + std::to_string(k));
}

// No decoding of images: the culler needs geometry only (and images are the largest attack surface).
bool skipImage(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
    return true;
}

// External buffers and images (`"uri": "x.bin"`) are read only from regular files inside the glTF file's
// own directory, and only up to kMaxMeshFileBytes: tinygltf's default callbacks read whatever path a
// hostile file names ("../../dev/zero", a FIFO that blocks for ever, a file of gigabytes). The directory
// is canonical, and so is each candidate, so ".." and symbolic links cannot lead out of it.
struct GltfFiles {
    std::filesystem::path dir; // canonical
};

bool insideDir(const std::string& file, const GltfFiles& g, std::filesystem::path& canonical) {
    std::error_code ec;
    canonical = std::filesystem::weakly_canonical(std::filesystem::path(file), ec);
    if (ec || !std::filesystem::is_regular_file(canonical, ec) || ec) return false;
    const std::string d = g.dir.string(), c = canonical.string();
    return c.size() > d.size() && c.compare(0, d.size(), d) == 0 && (d.back() == '/' || c[d.size()] == '/');
}

bool gltfFileExists(const std::string& file, void* user) {
    std::filesystem::path c;
    return insideDir(file, *static_cast<const GltfFiles*>(user), c);
}

std::string gltfExpandPath(const std::string& file, void*) { return file; } // no ~ or $VAR expansion

bool gltfReadFile(std::vector<unsigned char>* out, std::string* err, const std::string& file, void* user) {
    std::filesystem::path c;
    if (!insideDir(file, *static_cast<const GltfFiles*>(user), c)) {
        if (err) *err += "file '" + file + "' is not a regular file beside the glTF file";
        return false;
    }
    std::error_code ec;
    const std::uintmax_t size = std::filesystem::file_size(c, ec);
    if (ec || size == 0 || size > kMaxMeshFileBytes) {
        if (err) *err += "file '" + file + "' is empty, larger than the limit or unreadable";
        return false;
    }
    std::ifstream in(c, std::ios::binary);
    out->resize(std::size_t(size));
    if (size > 0 && !in.read(reinterpret_cast<char*>(out->data()), std::streamsize(size))) {
        if (err) *err += "cannot read external file '" + file + "'";
        return false;
    }
    return true;
}

bool gltfWriteFile(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err += "writing is not allowed";
    return false;
}

TriangleMesh readGltf(const std::string& path, bool binary) {
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(&skipImage, nullptr);
    GltfFiles files;
    {
        std::error_code ec;
        files.dir = std::filesystem::weakly_canonical(std::filesystem::absolute(path, ec).parent_path(), ec);
    }
    loader.SetFsCallbacks({&gltfFileExists, &gltfExpandPath, &gltfReadFile, &gltfWriteFile, &files});
    tinygltf::Model model;
    std::string err, warn;
    const bool ok = binary ? loader.LoadBinaryFromFile(&model, &err, &warn, path) : loader.LoadASCIIFromFile(&model, &err, &warn, path);
    if (!ok) fail("glTF: " + (err.empty() ? std::string("cannot parse") : err));
    TriangleMesh out;
    if (model.scenes.empty()) {
        for (std::size_t i = 0; i < model.meshes.size(); ++i) addMesh(model, int(i), identity(), out);
        return out;
    }
    const std::size_t sceneIndex = model.defaultScene >= 0 ? std::size_t(model.defaultScene) : 0;
    if (sceneIndex >= model.scenes.size()) fail("glTF: default scene " + std::to_string(sceneIndex) + " does not exist");
    // Depth-first with an explicit stack; a node graph with a cycle (invalid glTF) would loop forever,
    // so each node is visited at most once.
    std::vector<char> visited(model.nodes.size(), 0);
    std::vector<std::pair<int, Mat4>> stack;
    for (int n : model.scenes[sceneIndex].nodes) stack.emplace_back(n, identity());
    while (!stack.empty()) {
        auto [n, parent] = stack.back();
        stack.pop_back();
        if (n < 0 || std::size_t(n) >= model.nodes.size()) fail("glTF: node " + std::to_string(n) + " does not exist");
        if (visited[std::size_t(n)]++) fail("glTF: node " + std::to_string(n) + " is reached twice (the node graph is not a forest)");
        const tinygltf::Node& node = model.nodes[std::size_t(n)];
        const Mat4 m = multiply(parent, localMatrix(node, std::size_t(n)));
        for (double x : m)
            if (!std::isfinite(x)) fail("glTF: node " + std::to_string(n) + " has a non-finite transform");
        if (node.mesh >= 0) addMesh(model, node.mesh, m, out);
        for (int c : node.children) stack.emplace_back(c, m);
    }
    return out;
}

} // namespace

TriangleMesh readMeshFile(const std::string& path) {
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (ec || !fs::exists(st)) fail("cannot open \"" + path + "\": no such file");
    if (!fs::is_regular_file(st)) fail("\"" + path + "\" is not a regular file");
    const std::uintmax_t bytes = fs::file_size(path, ec);
    if (ec) fail("cannot read \"" + path + "\": " + ec.message());
    if (bytes > kMaxMeshFileBytes) fail("\"" + path + "\" is larger than " + std::to_string(kMaxMeshFileBytes) + " bytes");
    std::string ext = fs::path(path).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    TriangleMesh m;
    try {
        if (ext == ".obj") m = readObj(path);
        else if (ext == ".gltf") m = readGltf(path, false);
        else if (ext == ".glb") m = readGltf(path, true);
        else fail("\"" + path + "\": unknown extension \"" + ext + "\" (expected .obj, .gltf or .glb)");
    } catch (const MeshFileError& e) {
        if (ext == ".obj" || ext == ".gltf" || ext == ".glb") fail("\"" + path + "\": " + e.what());
        throw;
    } catch (const std::bad_alloc&) {
        throw;
    } catch (const std::exception& e) {
        // tinygltf's JSON (nlohmann) may throw on malformed numbers; nothing else may escape.
        fail("\"" + path + "\": " + e.what());
    }
    try {
        validateMesh(m, "mesh");
    } catch (const InvalidInput& e) {
        fail("\"" + path + "\": " + e.what());
    }
    return m;
}

} // namespace rgvc
