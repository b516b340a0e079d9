// Closed triangle meshes for the tests (header-only): unions of lattice cells (a box, an L, a U, a ring
// with a hole: concave solids whose voxel rows hold several spans) and an octahedron (faces at angles to
// every axis), optionally turned, as MeshSolid shapes; and a seeded random pick of them.
//
//   Shape<3> s = rgvc::reference::cellMesh(rgvc::reference::kUCells, {2, 3, 1}, {10, 0, 5});
//   Shape<3> r = rgvc::reference::randomMeshShape(rng, centre, size, snapped);
#pragma once

#include "SeededRandom.hpp"
#include "rgvc/grid/ConvexPolytope.hpp"
#include "rgvc/grid/Shapes.hpp"

#include <array>
#include <cmath>
#include <map>
#include <random>
#include <vector>

namespace rgvc::reference {

using Cell = std::array<int, 3>;
/// One cell: a box.
inline const std::vector<Cell> kBoxCells = {{0, 0, 0}};
/// An L in the xy plane (three cells).
inline const std::vector<Cell> kLCells = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
/// A U in the xy plane, open towards +y: rows along x at y = 1 cross it twice.
inline const std::vector<Cell> kUCells = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {2, 1, 0}};
/// A square ring in the xz plane (3 x 3 cells without the centre): a solid with a through hole.
inline const std::vector<Cell> kRingCells = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 0, 1}, {2, 0, 1}, {0, 0, 2}, {1, 0, 2}, {2, 0, 2}};

/// The boundary of the union of `cells` (cell (i, j, k) is [i, i+1] x [j, j+1] x [k, k+1] scaled by `size`
/// per axis), turned by the rotation with columns `axes` (identity by default) and moved by `at`.
/// Triangles counter-clockwise seen from outside; closed as long as no two cells meet only along an edge.
inline TriangleMesh cellMeshTriangles(const std::vector<Cell>& cells, const Vec3& size, const Vec3& at,
                                      const std::array<Vec3, 3>& axes = {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}}) {
    TriangleMesh m;
    std::map<Cell, std::uint32_t> index;
    auto vertex = [&](const Cell& c) {
        auto [it, added] = index.emplace(c, std::uint32_t(m.positions.size()));
        if (added) {
            const Vec3 p{c[0] * size.x, c[1] * size.y, c[2] * size.z};
            m.positions.push_back(at + p.x * axes[0] + p.y * axes[1] + p.z * axes[2]);
        }
        return it->second;
    };
    auto filled = [&](const Cell& c) {
        for (const Cell& d : cells)
            if (d == c) return true;
        return false;
    };
    for (const Cell& c : cells)
        for (int a = 0; a < 3; ++a)
            for (int side = 0; side < 2; ++side) {
                Cell n = c;
                n[std::size_t(a)] += side ? 1 : -1;
                if (filled(n)) continue;
                // The face's corners in the (b, c) plane, b = a+1, c = a+2: (0,0), (1,0), (1,1), (0,1) runs
                // counter-clockwise about +a (e_b x e_c = e_a); the -a face takes them the other way.
                const int b = (a + 1) % 3, cc = (a + 2) % 3;
                std::array<Cell, 4> q;
                const int uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
                for (int k = 0; k < 4; ++k) {
                    Cell p = c;
                    p[std::size_t(a)] += side;
                    p[std::size_t(b)] += uv[side ? k : 3 - k][0];
                    p[std::size_t(cc)] += uv[side ? k : 3 - k][1];
                    q[std::size_t(k)] = p;
                }
                const std::uint32_t i0 = vertex(q[0]), i1 = vertex(q[1]), i2 = vertex(q[2]), i3 = vertex(q[3]);
                m.triangles.push_back({i0, i1, i2});
                m.triangles.push_back({i0, i2, i3});
            }
    return m;
}

inline MeshSolid meshShape(TriangleMesh m) { return MeshSolid(makeMeshModel(std::move(m), "test mesh")); }

inline MeshSolid cellMesh(const std::vector<Cell>& cells, const Vec3& size, const Vec3& at,
                          const std::array<Vec3, 3>& axes = {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}}) {
    return meshShape(cellMeshTriangles(cells, size, at, axes));
}

/// The octahedron |x - c|_1 <= r (per axis radii), counter-clockwise seen from outside.
inline TriangleMesh octahedronTriangles(const Vec3& c, const Vec3& r) {
    TriangleMesh m;
    m.positions = {c + Vec3{r.x, 0, 0}, c - Vec3{r.x, 0, 0}, c + Vec3{0, r.y, 0}, c - Vec3{0, r.y, 0}, c + Vec3{0, 0, r.z}, c - Vec3{0, 0, r.z}};
    // Octant (sx, sy, sz): the face (x, y, z) in that order is counter-clockwise from outside when
    // sx * sy * sz > 0, else reversed.
    for (int sx = 0; sx < 2; ++sx)
        for (int sy = 0; sy < 2; ++sy)
            for (int sz = 0; sz < 2; ++sz) {
                const std::uint32_t x = std::uint32_t(sx), y = std::uint32_t(2 + sy), z = std::uint32_t(4 + sz);
                if ((sx + sy + sz) % 2 == 0) m.triangles.push_back({x, y, z});
                else m.triangles.push_back({x, z, y});
            }
    return m;
}

/// Columns of a rotation: identity, or turned about a random axis.
inline std::array<Vec3, 3> randomAxes(std::mt19937_64& rng, bool turned) {
    if (!turned) return {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}};
    std::array<double, 4> q{seeded::uniform(rng, -1, 1), seeded::uniform(rng, -1, 1), seeded::uniform(rng, -1, 1),
                            seeded::uniform(rng, 0.2, 1)};
    const double l = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (double& v : q) v /= l;
    return rotationColumns(q);
}

/// A random closed mesh of extent about `size` near `centre`: a box, an L, a U, a ring or an octahedron,
/// turned unless `snapped` (then its faces lie on voxel faces when centre and size are integers).
inline TriangleMesh randomMeshTriangles(std::mt19937_64& rng, const Vec3& centre, double size, bool snapped) {
    const int kind = seeded::uniformInt(rng, 0, 4);
    const bool turned = !snapped && seeded::chance(rng, 0.6);
    const std::array<Vec3, 3> axes = randomAxes(rng, turned);
    if (kind == 4) {
        Vec3 r{size * seeded::uniform(rng, 0.3, 0.6), size * seeded::uniform(rng, 0.3, 0.6), size * seeded::uniform(rng, 0.3, 0.6)};
        if (snapped) r = glm::max(glm::round(r), Vec3(1.0));
        TriangleMesh m = octahedronTriangles(Vec3(0.0), r);
        const Vec3 c = snapped ? glm::round(centre) : centre;
        for (Vec3& p : m.positions) p = c + p.x * axes[0] + p.y * axes[1] + p.z * axes[2];
        return m;
    }
    const std::vector<Cell>& cells = kind == 0 ? kBoxCells : kind == 1 ? kLCells : kind == 2 ? kUCells : kRingCells;
    Vec3 cell;
    for (int a = 0; a < 3; ++a) cell[a] = snapped ? std::max(1.0, std::round(size / 3)) : size * seeded::uniform(rng, 0.15, 0.4);
    const Vec3 at = snapped ? glm::round(centre) : centre - 1.5 * (cell.x * axes[0] + cell.y * axes[1] + cell.z * axes[2]);
    return cellMeshTriangles(cells, cell, at, axes);
}

inline MeshSolid randomMeshShape(std::mt19937_64& rng, const Vec3& centre, double size, bool snapped) {
    return meshShape(randomMeshTriangles(rng, centre, size, snapped));
}

} // namespace rgvc::reference
