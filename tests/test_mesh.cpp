// Triangle meshes (grid/TriangleMesh.hpp): validation, closedness, and the conservative voxelization
// against brute force (sample points of every O voxel inside the analytic solid, no triangle meeting an
// O voxel, every voxel a triangle touches in I by Akenine-Moller's separating-axis test); the mesh as a
// shape (grid/MeshSolid.hpp): model, hull, placements, its O and I rows, moving footprints.
#include "rgvc/grid/ConservativeRaster.hpp"
#include "rgvc/grid/Error.hpp"
#include "rgvc/grid/MeshSolid.hpp"
#include "rgvc/grid/RowFootprint.hpp"
#include "rgvc/grid/TriangleMesh.hpp"
#include "reference/SeededRandom.hpp"
#include "reference/TestMeshes.hpp"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <tuple>

using namespace rgvc;
namespace sr = rgvc::reference::seeded;

namespace {

using Key = std::tuple<int, int, int>;

/// A box given by its centre, three orthonormal axes and half extents, as 12 outward triangles.
void appendBox(TriangleMesh& m, const Vec3& c, const std::array<Vec3, 3>& ax, const Vec3& h, bool inward = false) {
    const std::uint32_t base = std::uint32_t(m.positions.size());
    for (int i = 0; i < 8; ++i)
        m.positions.push_back(c + ax[0] * (i & 1 ? h.x : -h.x) + ax[1] * (i & 2 ? h.y : -h.y) + ax[2] * (i & 4 ? h.z : -h.z));
    // Faces as quads (corner bits), counter-clockwise seen from outside for a right-handed frame.
    const int q[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (const auto& f : q) {
        std::array<std::uint32_t, 3> t0{base + f[0], base + f[1], base + f[2]}, t1{base + f[0], base + f[2], base + f[3]};
        if (inward) {
            std::swap(t0[1], t0[2]);
            std::swap(t1[1], t1[2]);
        }
        m.triangles.push_back(t0);
        m.triangles.push_back(t1);
    }
}

std::array<Vec3, 3> randomFrame(std::mt19937_64& rng) {
    // A random rotation from a random unit quaternion.
    double q[4], n = 0;
    for (double& v : q) {
        v = sr::uniform(rng, -1, 1);
        n += v * v;
    }
    n = std::sqrt(n);
    const double x = q[0] / n, y = q[1] / n, z = q[2] / n, w = q[3] / n;
    return {Vec3{1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y)},
            Vec3{2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x)},
            Vec3{2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)}};
}

struct Solid {
    TriangleMesh mesh;
    std::function<bool(const Vec3&, double)> inside; ///< p inside the closed solid grown by eps
};

struct BoxDesc {
    Vec3 c, h;
    std::array<Vec3, 3> ax;
};
bool inBox(const BoxDesc& b, const Vec3& p, double eps) {
    const Vec3 d = p - b.c;
    for (int i = 0; i < 3; ++i)
        if (std::abs(glm::dot(d, b.ax[i])) > b.h[i] + eps) return false;
    return true;
}

/// Random solids: one turned box, two disjoint turned boxes, or a hollow box (an inward box inside).
Solid randomSolid(std::mt19937_64& rng, int kind) {
    Solid s;
    auto box = [&](double lo, double hi) {
        BoxDesc b{Vec3{sr::uniform(rng, 8, 24), sr::uniform(rng, 8, 24), sr::uniform(rng, 8, 24)},
                  Vec3{sr::uniform(rng, lo, hi), sr::uniform(rng, lo, hi), sr::uniform(rng, lo, hi)}, randomFrame(rng)};
        return b;
    };
    if (kind == 0) {
        BoxDesc b = box(1, 7);
        appendBox(s.mesh, b.c, b.ax, b.h);
        s.inside = [b](const Vec3& p, double e) { return inBox(b, p, e); };
    } else if (kind == 1) {
        BoxDesc a = box(1, 4);
        BoxDesc b = a;
        b.c = a.c + Vec3{11, 0, 0};
        b.ax = randomFrame(rng);
        appendBox(s.mesh, a.c, a.ax, a.h);
        appendBox(s.mesh, b.c, b.ax, b.h);
        s.inside = [a, b](const Vec3& p, double e) { return inBox(a, p, e) || inBox(b, p, e); };
    } else {
        BoxDesc outer = box(5, 8);
        BoxDesc inner = outer;
        inner.h = outer.h * 0.5;
        appendBox(s.mesh, outer.c, outer.ax, outer.h);
        appendBox(s.mesh, inner.c, inner.ax, inner.h, true);
        s.inside = [outer, inner](const Vec3& p, double e) { return inBox(outer, p, e) && !inBox(inner, p, -e); };
    }
    return s;
}

/// Akenine-Moller's triangle/box overlap (13 separating axes), box centre c and half size h.
bool triBoxOverlap(const Vec3& c, double h, const Vec3& a, const Vec3& b, const Vec3& d) {
    const Vec3 v[3] = {a - c, b - c, d - c};
    const Vec3 e[3] = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
    auto separated = [&](const Vec3& axis) {
        const double p0 = glm::dot(v[0], axis), p1 = glm::dot(v[1], axis), p2 = glm::dot(v[2], axis);
        const double r = h * (std::abs(axis.x) + std::abs(axis.y) + std::abs(axis.z));
        return std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r;
    };
    for (int i = 0; i < 3; ++i) {
        Vec3 u{0.0};
        u[i] = 1;
        if (separated(u)) return false;
        for (const Vec3& ed : e)
            if (separated(glm::cross(u, ed))) return false;
    }
    return !separated(glm::cross(e[0], e[1]));
}

std::set<Key> spansToSet(const std::vector<VoxelRowSpan>& spans) {
    std::set<Key> r;
    for (const auto& s : spans)
        for (int x = s.x0; x <= s.x1; ++x) r.insert({x, s.y, s.z});
    return r;
}

void checkSpansWellFormed(const std::vector<VoxelRowSpan>& spans, const IVec3& res) {
    for (std::size_t i = 0; i < spans.size(); ++i) {
        const auto& s = spans[i];
        REQUIRE(s.x0 <= s.x1);
        REQUIRE(s.x0 >= 0);
        REQUIRE(s.x1 < res.x);
        REQUIRE((s.y >= 0 && s.y < res.y && s.z >= 0 && s.z < res.z));
        if (i > 0) {
            const auto& p = spans[i - 1];
            const bool sameRow = p.y == s.y && p.z == s.z;
            REQUIRE((p.z < s.z || (p.z == s.z && p.y < s.y) || (sameRow && p.x1 + 1 < s.x0)));
        }
    }
}

} // namespace

TEST_CASE("Mesh validation names the field and the problem", "[grid][mesh]") {
    TriangleMesh m;
    appendBox(m, Vec3{0.0}, {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}}, Vec3{1.0});
    REQUIRE_NOTHROW(validateMesh(m, "objects[0]"));
    auto message = [](const TriangleMesh& bad) {
        try {
            validateMesh(bad, "objects[0]");
        } catch (const InvalidInput& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    TriangleMesh nan = m;
    nan.positions[3].y = std::nan("");
    CHECK(message(nan) == "objects[0].positions: vertex 3 is not finite");
    TriangleMesh inf = m;
    inf.positions[0].x = HUGE_VAL;
    CHECK(message(inf).find("not finite") != std::string::npos);
    TriangleMesh range = m;
    range.triangles[5][1] = 8;
    CHECK(message(range) == "objects[0].indices: triangle 5 uses vertex 8 of 8");
    TriangleMesh repeat = m;
    repeat.triangles[2][2] = repeat.triangles[2][0];
    CHECK(message(repeat) == "objects[0].indices: triangle 2 repeats a vertex");
    TriangleMesh empty;
    CHECK(message(empty) == "objects[0].indices: a mesh needs at least one triangle");
}

TEST_CASE("Mesh closedness: boundary, non-manifold and misoriented edges", "[grid][mesh]") {
    TriangleMesh cube;
    appendBox(cube, Vec3{0.0}, {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}}, Vec3{1.0});
    MeshTopology t = analyzeMeshTopology(cube);
    CHECK(t.closed());
    CHECK(t.edges == 18);

    TriangleMesh open = cube;
    open.triangles.pop_back();
    t = analyzeMeshTopology(open);
    CHECK_FALSE(t.closed());
    CHECK(t.boundaryEdges == 3);

    TriangleMesh flipped = cube;
    std::swap(flipped.triangles[0][1], flipped.triangles[0][2]);
    t = analyzeMeshTopology(flipped);
    CHECK_FALSE(t.closed());
    CHECK(t.misorientedEdges == 3);

    TriangleMesh doubled = cube;
    doubled.triangles.push_back(cube.triangles[0]);
    t = analyzeMeshTopology(doubled);
    CHECK_FALSE(t.closed());
    CHECK(t.nonManifoldEdges == 3);

    // Split seams (one vertex per face corner, as OBJ/glTF exporters write them) are open until welded.
    TriangleMesh split;
    for (const auto& tri : cube.triangles) {
        const std::uint32_t b = std::uint32_t(split.positions.size());
        for (std::uint32_t v : tri) split.positions.push_back(cube.positions[v]);
        split.triangles.push_back({b, b + 1, b + 2});
    }
    CHECK_FALSE(analyzeMeshTopology(split).closed());
    weldMeshVertices(split);
    CHECK(split.positions.size() == 8);
    CHECK(analyzeMeshTopology(split).closed());

    // Both consistent orientations are closed (the solid is where the winding number is non-zero).
    TriangleMesh inward;
    appendBox(inward, Vec3{0.0}, {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}}, Vec3{1.0}, true);
    CHECK(analyzeMeshTopology(inward).closed());
}

TEST_CASE("Mesh voxelization of an axis-aligned box equals the box's raster", "[grid][mesh]") {
    const IVec3 res{32, 32, 32};
    for (int orient = 0; orient < 2; ++orient)
        for (const auto& [lo, hi] : std::vector<std::pair<Vec3, Vec3>>{{Vec3{4, 5, 6}, Vec3{20, 12, 17}},
                                                                       {Vec3{3.3, 4.7, 5.5}, Vec3{19.2, 12.5, 16.9}},
                                                                       {Vec3{-5, 2, 3}, Vec3{40, 9.5, 10}}}) {
            TriangleMesh m;
            appendBox(m, (lo + hi) * 0.5, {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}}, (hi - lo) * 0.5, orient == 1);
            MeshVoxelization vox;
            std::set<Key> want;
            for (bool inner : {true, false}) {
                voxelizeMesh(m, res, true, inner, kConservativeSlack, vox);
                checkSpansWellFormed(vox.spans, res);
                want.clear();
                const Shape<3> box = Box<3>{lo, hi};
                auto add = [&](const IVec3& v) { want.insert({v.x, v.y, v.z}); };
                if (inner) forEachInnerVoxel<3>(box, res, add);
                else forEachTouchedVoxel<3>(box, res, add);
                INFO("box " << lo.x << " " << lo.y << " " << lo.z << " .. " << hi.x << " " << hi.y << " " << hi.z
                            << (inner ? " inner" : " touched") << " orientation " << orient);
                CHECK(spansToSet(vox.spans) == want);
            }
        }
}

TEST_CASE("Mesh voxelization against brute force on random closed solids", "[grid][mesh]") {
    const IVec3 res{32, 30, 34};
    MeshVoxelization vox;
    std::size_t innerTotal = 0, bruteTotal = 0;
    for (std::uint64_t seed = 1; seed <= 60; ++seed) {
        INFO("seed " << seed);
        std::mt19937_64 rng(seed);
        const int kind = int(seed % 3);
        Solid s = randomSolid(rng, kind);
        REQUIRE(analyzeMeshTopology(s.mesh).closed());
        voxelizeMesh(s.mesh, res, true, true, kConservativeSlack, vox);
        checkSpansWellFormed(vox.spans, res);
        const std::set<Key> inner = spansToSet(vox.spans);
        voxelizeMesh(s.mesh, res, true, false, kConservativeSlack, vox);
        checkSpansWellFormed(vox.spans, res);
        const std::set<Key> touched = spansToSet(vox.spans);

        // O: 27 points of every voxel (corners, edge and face midpoints, centre) inside the solid, and no
        // triangle meets the voxel shrunk by 1e-6.
        for (const auto& [x, y, z] : inner) {
            for (int k = 0; k < 27; ++k) {
                const Vec3 p{x + 0.5 * (k % 3), y + 0.5 * (k / 3 % 3), z + 0.5 * (k / 9)};
                REQUIRE(s.inside(p, 1e-9));
            }
            for (const auto& t : s.mesh.triangles)
                REQUIRE_FALSE(triBoxOverlap(Vec3{x + 0.5, y + 0.5, z + 0.5}, 0.5 - 1e-6, s.mesh.positions[t[0]],
                                            s.mesh.positions[t[1]], s.mesh.positions[t[2]]));
            REQUIRE(touched.count({x, y, z}) == 1);
        }
        // I: every voxel a triangle touches (SAT), and every voxel whose centre is inside. And O is tight:
        // a voxel whose 27 points are inside by a margin of 1e-6 and that no triangle meets is in O.
        std::size_t brute = 0;
        for (int z = 0; z < res.z; ++z)
            for (int y = 0; y < res.y; ++y)
                for (int x = 0; x < res.x; ++x) {
                    const Vec3 c{x + 0.5, y + 0.5, z + 0.5};
                    bool hit = false;
                    for (const auto& t : s.mesh.triangles)
                        if (triBoxOverlap(c, 0.5, s.mesh.positions[t[0]], s.mesh.positions[t[1]], s.mesh.positions[t[2]])) {
                            hit = true;
                            break;
                        }
                    if (hit || s.inside(c, 0)) REQUIRE(touched.count({x, y, z}) == 1);
                    if (!hit && s.inside(c, -1e-6)) {
                        ++brute;
                        REQUIRE(inner.count({x, y, z}) == 1);
                    }
                }
        innerTotal += inner.size();
        bruteTotal += brute;
    }
    INFO("O voxels " << innerTotal << ", brute-force interior voxels " << bruteTotal);
    CHECK(innerTotal >= bruteTotal);
    CHECK(bruteTotal > 5000);
}

TEST_CASE("Mesh voxelization: lines through vertices and along edges count each crossing once", "[grid][mesh]") {
    // An octahedron with its vertices on voxel-centre lines and a cube turned 45 degrees about x: the
    // centre lines pass exactly through vertices and along edges (the symbolic perturbation's cases).
    const IVec3 res{16, 16, 16};
    MeshVoxelization vox;
    TriangleMesh oct;
    const Vec3 c{8.5, 8.5, 8.5};
    const double r = 6;
    oct.positions = {c + Vec3{r, 0, 0}, c - Vec3{r, 0, 0}, c + Vec3{0, r, 0}, c - Vec3{0, r, 0}, c + Vec3{0, 0, r}, c - Vec3{0, 0, r}};
    oct.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    REQUIRE(analyzeMeshTopology(oct).closed());
    auto inOct = [&](const Vec3& p, double e) {
        return std::abs(p.x - c.x) + std::abs(p.y - c.y) + std::abs(p.z - c.z) <= r + e;
    };
    voxelizeMesh(oct, res, true, true, kConservativeSlack, vox);
    const std::set<Key> inner = spansToSet(vox.spans);
    voxelizeMesh(oct, res, true, false, kConservativeSlack, vox);
    const std::set<Key> touched = spansToSet(vox.spans);
    std::size_t brute = 0;
    for (int z = 0; z < res.z; ++z)
        for (int y = 0; y < res.y; ++y)
            for (int x = 0; x < res.x; ++x) {
                bool all = true, any = false;
                for (int k = 0; k < 8; ++k) {
                    const bool in = inOct(Vec3{x + double(k & 1), y + double(k >> 1 & 1), z + double(k >> 2)}, 1e-12);
                    all = all && in;
                    any = any || in;
                }
                INFO("voxel " << x << " " << y << " " << z);
                if (inner.count({x, y, z})) REQUIRE(all);
                if (any) REQUIRE(touched.count({x, y, z}) == 1);
                // Convex solid: the 8 corners inside means the voxel is inside; a voxel inside only
                // touching faces at its border is in O.
                if (all) {
                    ++brute;
                    CHECK(inner.count({x, y, z}) == 1);
                }
            }
    CHECK(brute > 100);
}

TEST_CASE("Open meshes are surfaces: no O, I the touched voxels only", "[grid][mesh]") {
    TriangleMesh m;
    appendBox(m, Vec3{10.0}, {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}}, Vec3{5.0});
    m.triangles.resize(10); // one face missing
    REQUIRE_FALSE(analyzeMeshTopology(m).closed());
    MeshVoxelization vox;
    voxelizeMesh(m, IVec3{24}, false, true, kConservativeSlack, vox);
    CHECK(vox.spans.empty());
    voxelizeMesh(m, IVec3{24}, false, false, kConservativeSlack, vox);
    const std::set<Key> touched = spansToSet(vox.spans);
    CHECK(touched.count({10, 10, 10}) == 0); // the inside is not part of a surface
    CHECK(touched.count({5, 10, 10}) == 1);  // a face is
    for (const auto& [x, y, z] : touched) {
        bool hit = false;
        for (const auto& t : m.triangles)
            hit = hit || triBoxOverlap(Vec3{x + 0.5, y + 0.5, z + 0.5}, 0.5 + 1e-6, m.positions[t[0]], m.positions[t[1]], m.positions[t[2]]);
        REQUIRE(hit); // tight: I holds only voxels a triangle touches
    }
}

TEST_CASE("Mesh voxelization of a large mesh reuses its scratch", "[grid][mesh]") {
    // 20^3 boxes = 96,000 triangles in a 128^3 grid: the answer is checked on a sample, and a second run
    // into the same MeshVoxelization does not grow its buffers.
    TriangleMesh m;
    for (int i = 0; i < 20; ++i)
        for (int j = 0; j < 20; ++j)
            for (int k = 0; k < 20; ++k)
                appendBox(m, Vec3{6.0 * i + 4, 6.0 * j + 4, 6.0 * k + 4}, {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}}, Vec3{2.0});
    REQUIRE(analyzeMeshTopology(m).closed());
    MeshVoxelization vox;
    voxelizeMesh(m, IVec3{128}, true, true, kConservativeSlack, vox);
    // Each box [6i+2, 6i+6]^3 holds 4^3 inner voxels.
    std::size_t n = 0;
    for (const auto& s : vox.spans) n += std::size_t(s.x1 - s.x0 + 1);
    CHECK(n == 8000u * 64u);
    const std::size_t cap = vox.crossings.capacity() + vox.touchedScratch.capacity() + vox.spans.capacity();
    voxelizeMesh(m, IVec3{128}, true, true, kConservativeSlack, vox);
    CHECK(vox.crossings.capacity() + vox.touchedScratch.capacity() + vox.spans.capacity() == cap);
}

// ---------------------------------------------------------------------------------------------------
// MeshSolid (grid/MeshSolid.hpp): a mesh as a Shape<3>, its hull the outer model, its solid voxelization O.

namespace {

/// Whether world point p lies in the union of the cells (cell size `size`, lower corner `at`, unturned)
/// grown by eps: the brute force for reference::cellMesh solids.
bool inCells(const std::vector<reference::Cell>& cells, const Vec3& size, const Vec3& at, const Vec3& p, double eps) {
    for (const reference::Cell& c : cells) {
        bool in = true;
        for (int a = 0; a < 3; ++a) {
            const double lo = at[a] + c[std::size_t(a)] * size[a];
            in = in && p[a] >= lo - eps && p[a] <= lo + size[a] + eps;
        }
        if (in) return true;
    }
    return false;
}

/// A storage that records what RowFootprint writes: ids per voxel, opaque counts per voxel.
struct RecordingStorage {
    std::map<VoxelKey, std::set<ObjectSlot>> ids;
    std::map<VoxelKey, int> opaque;
    void addId(VoxelKey k, ObjectSlot s) { CHECK(ids[k].insert(s).second); }
    void removeId(VoxelKey k, ObjectSlot s) { CHECK(ids[k].erase(s) == 1); }
    void addOpaque(VoxelKey k, int sign) {
        opaque[k] += sign;
        CHECK(opaque[k] >= 0);
    }
    void tidy() {
        std::erase_if(ids, [](const auto& e) { return e.second.empty(); });
        std::erase_if(opaque, [](const auto& e) { return e.second == 0; });
    }
};

} // namespace

TEST_CASE("MeshSolid: the model, its hull, placements, validation and the inset", "[grid][mesh]") {
    TriangleMesh cube;
    appendBox(cube, {1, 2, 3}, {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}}, {1, 2, 3});
    const auto model = makeMeshModel(cube, "objects[4]");
    CHECK(model->closed());
    CHECK(model->hull.vertices.size() == 8);
    const MeshSolid m(model);
    CHECK(boundsOf(m).min == Vec3(0, 0, 0));
    CHECK(boundsOf(m).max == Vec3(2, 4, 6));
    // Moved: the hull with it, the model shared (copies of a placement cost the hull, not the mesh).
    const Shape<3> moved = translated<3>(Shape<3>(m), Vec3{10, 0, -1});
    const MeshSolid& mm = std::get<MeshSolid>(moved);
    CHECK(mm.offset() == Vec3(10, 0, -1));
    CHECK(mm.sharedModel() == model);
    CHECK(boundsOf<3>(moved).min == Vec3(10, 0, -1));
    CHECK(mm.place(Vec3(2, 4, 6)) == Vec3(12, 4, 5));
    // toLocal: the same map for the mesh and the hull.
    const GridGeometry3 grid({-4, 0, 2}, 0.5, {40, 40, 40});
    const Shape<3> local = toLocal<3>(moved, grid);
    const MeshSolid& ml = std::get<MeshSolid>(local);
    CHECK(ml.place(Vec3(0, 0, 0)) == grid.toLocal(Vec3(10, 0, -1)));
    CHECK(boundsOf<3>(local).max.x == Approx(grid.toLocal(Vec3(12, 4, 5)).x));
    // Validation at the API boundary.
    Shape<3> none = MeshSolid{};
    CHECK_THROWS_AS(validateShape<3>(none, "objects[4]"), InvalidInput);
    CHECK_THROWS_AS(MeshSolid(nullptr, "objects[4]"), InvalidInput);
    Shape<3> ok = m;
    CHECK_NOTHROW(validateShape<3>(ok, "objects[4]"));
    TriangleMesh bad = cube;
    bad.triangles[0][0] = 99;
    CHECK_THROWS_WITH(makeMeshModel(bad, "objects[4]"), Catch::Contains("objects[4].mesh"));
    // An open mesh: a model without a solid.
    TriangleMesh open = cube;
    open.triangles.pop_back();
    CHECK_FALSE(makeMeshModel(open, "o")->closed());
    // No erosion of a mesh: a positive inset leaves nothing to occlude, zero keeps the mesh.
    Shape<3> out;
    CHECK_FALSE(insetShape<3>(Shape<3>(m), 0.1, out));
    CHECK(insetShape<3>(Shape<3>(m), 0.0, out));
    // A triangle that welding makes degenerate (two indices at one position) still counts for the hull: its
    // third vertex, used by no other triangle, lies in it (fuzz_mesh_file found a mesh that lost it); the
    // segment takes no part in the topology, so the cube stays closed.
    TriangleMesh seg = cube;
    const std::uint32_t copy = std::uint32_t(seg.positions.size());
    seg.positions.push_back(seg.positions[0]);
    seg.positions.push_back({9, 9, 9});
    seg.triangles.push_back({0, copy, copy + 1});
    const auto segModel = makeMeshModel(seg, "s");
    CHECK(segModel->closed());
    CHECK(segModel->hull.boundsMax == Vec3(9, 9, 9));
    // A flat mesh (one triangle) still gets a hull with an interior: its grown bounding box.
    TriangleMesh tri;
    tri.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    tri.triangles = {{0, 1, 2}};
    const auto flat = makeMeshModel(tri, "t");
    CHECK_FALSE(flat->closed());
    CHECK(flat->hull.boundsMin.z < 0);
    CHECK(flat->hull.boundsMax.z > 0);
}

TEST_CASE("MeshSolid rasterization: O inside the solid with several spans per row, I the mesh's within the hull's", "[grid][mesh]") {
    // A U (open towards +y) and a ring, at non-integer places on a grid with an odd origin and voxel size:
    // every O voxel (its corners and centre) lies in the union of the cells, some row holds two spans, I
    // holds every voxel whose box overlaps a cell and lies within the hull's touched rows, it is smaller
    // than the hull's (the U's notch, the ring's hole), and O lies in I.
    const GridGeometry3 grid({-3.3, 0.7, 1.1}, 0.37, {64, 48, 64});
    struct Case {
        const std::vector<reference::Cell>* cells;
        Vec3 size, at;
    };
    const Case cases[] = {{&reference::kUCells, {2.1, 1.7, 5.3}, {0.2, 2.9, 4.4}}, {&reference::kRingCells, {1.9, 3.1, 2.3}, {-1.0, 3.3, 3.7}},
                          {&reference::kLCells, {2.3, 1.9, 2.9}, {0.4, 3.1, 2.2}}};
    std::size_t hullVoxels = 0, touchedVoxels = 0; // over the cases: the L's hull cuts across its corner
    for (const Case& c : cases) {
        const MeshSolid world = reference::cellMesh(*c.cells, c.size, c.at);
        REQUIRE(world.closed());
        const Shape<3> local = toLocal<3>(Shape<3>(world), grid);
        const double slack = grid.conversionSlack(20.0);
        std::vector<std::array<std::int32_t, 4>> inner, touched, hull;
        forEachInnerRow<3>(local, grid.resolution(), [&](const IVec3& r, std::int32_t a, std::int32_t b) { inner.push_back({r.z, r.y, a, b}); }, slack);
        forEachTouchedRow<3>(local, grid.resolution(), [&](const IVec3& r, std::int32_t a, std::int32_t b) { touched.push_back({r.z, r.y, a, b}); }, slack);
        const Shape<3> localHull = std::get<MeshSolid>(local).hull();
        forEachTouchedRow<3>(localHull, grid.resolution(), [&](const IVec3& r, std::int32_t a, std::int32_t b) { hull.push_back({r.z, r.y, a, b}); }, slack);
        // I within the hull's rows, one span per row.
        std::map<std::pair<int, int>, std::pair<int, int>> hullRow;
        for (const auto& h : hull) {
            hullRow[{h[0], h[1]}] = {h[2], h[3]};
            hullVoxels += std::size_t(h[3] - h[2] + 1);
        }
        std::size_t outsideHull = 0;
        for (std::size_t i = 0; i < touched.size(); ++i) {
            const auto& t = touched[i];
            touchedVoxels += std::size_t(t[3] - t[2] + 1);
            const auto it = hullRow.find({t[0], t[1]});
            outsideHull += it == hullRow.end() || t[2] < it->second.first || t[3] > it->second.second;
            if (i > 0) CHECK(std::array<int, 2>{touched[i - 1][0], touched[i - 1][1]} < std::array<int, 2>{t[0], t[1]});
        }
        CHECK(outsideHull == 0);
        // Every voxel of the hull's rows whose box overlaps a cell by more than 1e-6 is in I (a brute-force
        // test of the conservative rule: a voxel that holds a point of the solid is touched).
        std::set<Key> inI;
        for (const auto& t : touched)
            for (int x = t[2]; x <= t[3]; ++x) inI.insert({x, t[1], t[0]});
        std::size_t missed = 0;
        for (const auto& h : hull)
            for (int x = h[2]; x <= h[3]; ++x) {
                const Vec3 lo = grid.toWorld(Vec3(x, h[1], h[0])), hi = grid.toWorld(Vec3(x + 1, h[1] + 1, h[0] + 1));
                bool overlaps = false;
                for (const reference::Cell& cell : *c.cells) {
                    bool o = true;
                    for (int a = 0; a < 3; ++a) {
                        const double c0 = c.at[a] + cell[a] * c.size[a], c1 = c0 + c.size[a];
                        o = o && std::min(hi[a], c1) - std::max(lo[a], c0) > 1e-6;
                    }
                    overlaps = overlaps || o;
                }
                missed += overlaps && !inI.count({x, h[1], h[0]});
            }
        CHECK(missed == 0);
        REQUIRE(inner.size() > 20);
        CHECK(std::is_sorted(inner.begin(), inner.end()));
        bool twoSpans = false;
        for (std::size_t i = 0; i + 1 < inner.size(); ++i)
            twoSpans = twoSpans || (inner[i][0] == inner[i + 1][0] && inner[i][1] == inner[i + 1][1]);
        CHECK((twoSpans || c.cells == &reference::kLCells)); // an L's rows through x are single runs
        std::set<Key> in;
        for (const auto& s : touched)
            for (int x = s[2]; x <= s[3]; ++x) in.insert({x, s[1], s[0]});
        std::size_t outside = 0, notTouched = 0;
        for (const auto& s : inner)
            for (int x = s[2]; x <= s[3]; ++x) {
                notTouched += !in.count({x, s[1], s[0]});
                for (int k = 0; k < 9; ++k) {
                    const Vec3 v = k < 8 ? Vec3(x + (k & 1), s[1] + (k >> 1 & 1), s[0] + (k >> 2 & 1)) : Vec3(x + 0.5, s[1] + 0.5, s[0] + 0.5);
                    outside += !inCells(*c.cells, c.size, c.at, grid.toWorld(v), 1e-9);
                }
            }
        CHECK(outside == 0);
        CHECK(notTouched == 0);
    }
    CHECK(touchedVoxels < hullVoxels);
}

TEST_CASE("RowFootprint moves a mesh's footprint (several O spans per row) exactly", "[grid][mesh]") {
    // A U moved by random steps: moveTo leaves the storage exactly as removing the old footprint and adding
    // the new one would (same ids, same opaque counts), and no count goes below zero on the way.
    const GridGeometry3 grid({0, 0, 0}, 1.0, {48, 32, 48});
    std::mt19937_64 rng(77);
    MeshSolid u = reference::cellMesh(reference::kUCells, {3.3, 2.7, 6.1}, {10.2, 5.1, 9.7});
    RowFootprint at, next;
    at.build<3>(toLocal<3>(Shape<3>(u), grid), grid, kConservativeSlack);
    RecordingStorage moving;
    at.write(moving, 5, +1);
    for (int step = 0; step < 40; ++step) {
        u = u.translated(Vec3{sr::uniform(rng, -1.5, 1.5), sr::uniform(rng, -1.5, 1.5), sr::uniform(rng, -1.5, 1.5)});
        next.build<3>(toLocal<3>(Shape<3>(u), grid), grid, kConservativeSlack);
        at.moveTo(moving, 5, next);
        RecordingStorage fresh;
        next.write(fresh, 5, +1);
        moving.tidy();
        INFO("step " << step);
        REQUIRE(next.innerRows() > next.touchedRows() / 4);
        CHECK(moving.ids == fresh.ids);
        CHECK(moving.opaque == fresh.opaque);
    }
}
