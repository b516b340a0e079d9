// MeshModel / MeshSolid (MeshSolid.hpp): a mesh's hull, its placements and its placed voxelization.
#include "rgvc/grid/MeshSolid.hpp"

#include "rgvc/grid/Error.hpp"

#include <algorithm>
#include <cmath>

namespace rgvc {

namespace mesh_detail {
void voxelizePositions(const std::vector<Vec3>& positions, const std::vector<std::array<std::uint32_t, 3>>& triangles,
                       const IVec3& res, bool solid, bool inner, double slack, MeshVoxelization& out);
}

namespace {

/// The hull of the referenced vertices, or their box grown so that it has an interior (see MeshModel::hull).
ConvexPolytope hullOf(const TriangleMesh& mesh, const std::string& field) {
    std::vector<char> used(mesh.positions.size(), 0);
    for (const auto& t : mesh.triangles)
        for (std::uint32_t v : t) used[v] = 1;
    std::vector<Vec3> pts;
    pts.reserve(mesh.positions.size());
    for (std::size_t i = 0; i < mesh.positions.size(); ++i)
        if (used[i]) pts.push_back(mesh.positions[i]); // welded: distinct already
    if (pts.size() >= 4 && pts.size() <= kMaxHullPoints) {
        try {
            return makeConvexHull(pts, field + ".mesh");
        } catch (const InvalidInput&) {
            // Flat (or nearly flat) point set: no interior for a polytope; the grown box below holds it.
        }
    }
    Vec3 lo, hi;
    meshBounds(mesh, lo, hi);
    double scale = 1.0;
    for (int a = 0; a < 3; ++a) scale = std::max({scale, std::abs(lo[a]), std::abs(hi[a])});
    // 1e-7 of the coordinates' magnitude: far above double rounding at that magnitude (the box has
    // positive thickness on every axis), far below a voxel in any sensible scene; only overestimation.
    const double g = 1e-7 * scale;
    const Vec3 half = 0.5 * (hi - lo) + g;
    if (!allFinite<3>(half) || !allFinite<3>(0.5 * (lo + hi)))
        throw InvalidInput(field + ".mesh", "the mesh's extent overflows double precision");
    return makeOrientedBox(0.5 * (lo + hi), half, {0, 0, 0, 1}, field + ".mesh");
}

} // namespace

std::shared_ptr<const MeshModel> makeMeshModel(TriangleMesh mesh, const std::string& field) {
    validateMesh(mesh, field + ".mesh");
    weldMeshVertices(mesh); // file formats split vertices at seams: closedness needs them merged
    auto m = std::make_shared<MeshModel>();
    // The hull holds every triangle, degenerate ones included (a segment is part of the object too).
    m->hull = hullOf(mesh, field);
    // Welding can give a triangle two equal indices (distinct indices at one position): a segment, with no
    // area and no part in the winding number; dropped so that the topology and the voxelizer see only real
    // triangles (kept when nothing else is left: such a mesh is open either way).
    const auto degenerate = [](const auto& t) { return t[0] == t[1] || t[1] == t[2] || t[2] == t[0]; };
    if (!std::all_of(mesh.triangles.begin(), mesh.triangles.end(), degenerate)) std::erase_if(mesh.triangles, degenerate);
    m->topology = analyzeMeshTopology(mesh);
    m->mesh = std::move(mesh);
    return m;
}

MeshSolid::MeshSolid(std::shared_ptr<const MeshModel> model, const std::string& field) : m_model(std::move(model)) {
    if (m_model == nullptr) throw InvalidInput(field + ".mesh", "no mesh model");
    m_hull = m_model->hull;
}

MeshSolid MeshSolid::translated(const Vec3& t) const {
    MeshSolid r;
    r.m_model = m_model;
    r.m_scale = m_scale;
    r.m_offset = m_offset + t;
    r.m_hull = translatedPolytope(m_hull, t);
    return r;
}

MeshSolid MeshSolid::mapped(const Vec3& origin, double k) const {
    // (scale x + offset - origin) k = (scale k) x + (offset - origin) k, the hull under the same map.
    MeshSolid r;
    r.m_model = m_model;
    r.m_scale = m_scale * k;
    r.m_offset = (m_offset - origin) * k;
    r.m_hull = scaledPolytope(m_hull, origin, k);
    return r;
}

void validateMeshSolid(const MeshSolid& s, const std::string& field) {
    if (s.model() == nullptr) throw InvalidInput(field + ".mesh", "no mesh model");
    if (!std::isfinite(s.scale()) || !(s.scale() > 0)) throw InvalidInput(field + ".mesh", "the mesh's scale must be finite and > 0");
    if (!allFinite<3>(s.offset())) throw InvalidInput(field + ".mesh", "the mesh's placement must be finite");
    // The hull was validated when built and moves with the placement; its numbers are checked here so
    // that a placement that overflowed is refused (O(hull), not O(mesh): this runs per placement query).
    const ConvexPolytope& h = s.hull();
    if (!allFinite<3>(h.boundsMin) || !allFinite<3>(h.boundsMax))
        throw InvalidInput(field + ".mesh", "the placed mesh overflows double precision");
    for (const HalfSpace& p : h.planes)
        if (!std::isfinite(p.offset)) throw InvalidInput(field + ".mesh", "the placed mesh overflows double precision");
}

void voxelizeMeshSolid(const MeshSolid& local, const IVec3& resolution, bool inner, double slack, MeshVoxelization& out) {
    const MeshModel* m = local.model();
    if (m == nullptr) {
        out.spans.clear();
        return;
    }
    // Each vertex is mapped once, so the two triangles of an edge see bit-identical coordinates and the
    // voxelizer's watertight crossing test (MeshVoxelize.cpp) stays watertight.
    out.placed.resize(m->mesh.positions.size());
    for (std::size_t i = 0; i < out.placed.size(); ++i) out.placed[i] = local.place(m->mesh.positions[i]);
    mesh_detail::voxelizePositions(out.placed, m->mesh.triangles, resolution, m->closed(), inner, slack, out);
}

const std::vector<VoxelRowSpan>& meshInnerSpans(const MeshSolid& local, const IVec3& resolution, double slack) {
    thread_local MeshVoxelization scratch;
    voxelizeMeshSolid(local, resolution, true, slack, scratch);
    return scratch.spans;
}

const std::vector<VoxelRowSpan>& meshTouchedSpans(const MeshSolid& local, const IVec3& resolution, double slack) {
    thread_local MeshVoxelization scratch; // its own, so that O's spans stay valid while I's are made
    voxelizeMeshSolid(local, resolution, false, slack, scratch);
    return scratch.spans;
}

} // namespace rgvc
