// Validation, edge pairing and welding of triangle meshes (TriangleMesh.hpp).
#include "rgvc/grid/TriangleMesh.hpp"

#include "rgvc/grid/Error.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace rgvc {

void validateMesh(const TriangleMesh& mesh, const std::string& field) {
    if (mesh.triangles.empty()) throw InvalidInput(field + ".indices", "a mesh needs at least one triangle");
    if (mesh.positions.size() > kMaxMeshVertices)
        throw InvalidInput(field + ".positions", "more than " + std::to_string(kMaxMeshVertices) + " vertices");
    if (mesh.triangles.size() > kMaxMeshTriangles)
        throw InvalidInput(field + ".indices", "more than " + std::to_string(kMaxMeshTriangles) + " triangles");
    for (std::size_t i = 0; i < mesh.positions.size(); ++i)
        if (!allFinite<3>(mesh.positions[i]))
            throw InvalidInput(field + ".positions", "vertex " + std::to_string(i) + " is not finite");
    const std::size_t n = mesh.positions.size();
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const auto& tri = mesh.triangles[t];
        for (std::uint32_t v : tri)
            if (v >= n)
                throw InvalidInput(field + ".indices", "triangle " + std::to_string(t) + " uses vertex " + std::to_string(v) +
                                                           " of " + std::to_string(n));
        if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2])
            throw InvalidInput(field + ".indices", "triangle " + std::to_string(t) + " repeats a vertex");
    }
}

MeshTopology analyzeMeshTopology(const TriangleMesh& mesh) {
    // One key per directed edge: (lo, hi) in the high and low 32 bits... plus its direction in a side array.
    struct Edge {
        std::uint64_t key;
        bool forward; // lo -> hi in the triangle's winding
    };
    std::vector<Edge> e;
    e.reserve(mesh.triangles.size() * 3);
    for (const auto& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = t[k], b = t[(k + 1) % 3];
            const std::uint32_t lo = std::min(a, b), hi = std::max(a, b);
            e.push_back({(std::uint64_t(lo) << 32) | hi, a < b});
        }
    std::sort(e.begin(), e.end(), [](const Edge& x, const Edge& y) { return x.key < y.key; });
    MeshTopology r;
    for (std::size_t i = 0; i < e.size();) {
        std::size_t j = i;
        int fwd = 0;
        while (j < e.size() && e[j].key == e[i].key) fwd += e[j++].forward ? 1 : 0;
        const std::size_t uses = j - i;
        ++r.edges;
        if (uses == 1) ++r.boundaryEdges;
        else if (uses > 2) ++r.nonManifoldEdges;
        else if (fwd != 1) ++r.misorientedEdges;
        i = j;
    }
    return r;
}

void weldMeshVertices(TriangleMesh& mesh) {
    const std::size_t n = mesh.positions.size();
    std::vector<std::uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    auto less = [&](std::uint32_t a, std::uint32_t b) {
        const Vec3 &p = mesh.positions[a], &q = mesh.positions[b];
        if (p.x != q.x) return p.x < q.x;
        if (p.y != q.y) return p.y < q.y;
        if (p.z != q.z) return p.z < q.z;
        return a < b;
    };
    std::sort(order.begin(), order.end(), less);
    std::vector<std::uint32_t> remap(n);
    std::vector<Vec3> out;
    out.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3& p = mesh.positions[order[i]];
        if (out.empty() || out.back() != p) out.push_back(p);
        remap[order[i]] = std::uint32_t(out.size() - 1);
    }
    for (auto& t : mesh.triangles)
        for (auto& v : t) v = remap[v];
    mesh.positions = std::move(out);
}

void meshBounds(const TriangleMesh& mesh, Vec3& lo, Vec3& hi) {
    lo = Vec3(std::numeric_limits<double>::infinity());
    hi = -lo;
    for (const auto& t : mesh.triangles)
        for (std::uint32_t v : t) {
            lo = glm::min(lo, mesh.positions[v]);
            hi = glm::max(hi, mesh.positions[v]);
        }
}

} // namespace rgvc
