// The output-sensitive 3D traversal: the brick tree walked front to back, with occlusion from a
// conservative image of the occluders met so far (DESIGN.md, "Point or region" and "Work follows the
// visible, non-empty part of the view").
//
// Why not the shells. The per-voxel shell traversal (FrustumTraversal3D.hpp, §5.2-5.3) visits every
// voxel of the view that is not in H, one by one, empty or not, so its cost is the view's volume; and
// its caps hold only a thin strip of a wall that crosses the shells' faces at an angle, so a wall seen
// obliquely leaks. Here:
//   - the unit of work is a node of the implicit octree over 8x8x8 bricks (BrickPyramid.hpp). A node
//     whose subtree holds no id and no TBV is skipped in O(1); a node outside the frustum is skipped;
//     a node whose whole box is hidden in the occlusion image is skipped. Only the bricks left are read,
//     voxel by voxel, and only along the rows' spans inside the frustum;
//   - occlusion is an image over the camera's view (OcclusionBuffer3D.hpp), in which the caller draws
//     each object it finds visible. A pixel's depth bounds the distance at which every ray of the pixel
//     has entered some occluder's interior, so "a box is hidden" is a statement about the camera point
//     and the box's whole extent: it does not depend on how a wall is turned against the grid, the
//     shells or the view.
//
// Order and the soundness of skipping empty nodes: BrickWalk.hpp, shared with the 2D traversal.
//
// Soundness of a skipped node. (1) Empty: nothing in it can enter the PVS or reveal a TBV. (2) Outside
// the frustum (ViewFrustum::touchesBox is conservative): no point of it is in view. (3) Hidden: every
// point of the box in view is behind occluders (OcclusionBuffer3D::hidden, with the box grown by the
// camera's slack). An object whose every point lies in skipped nodes is not visible; an object with a
// visible point p is met in the brick holding p, whose every ancestor holds p too and so is neither
// empty nor outside nor hidden. A TBV is revealed the same way (see Culler.cpp): a ray from the camera
// to a visible point of a hidden object enters the TBV through a visible boundary voxel.
//
// Cost: O(nodes tested) + O(voxels of the visited bricks' in-frustum spans); nothing per voxel of empty
// or hidden space. An empty grid visits one node.
#pragma once

#include "rgvc/grid/BrickPyramid.hpp"
#include "rgvc/grid/BrickRows.hpp"
#include "rgvc/grid/BrickWalk.hpp"
#include "rgvc/grid/GridGeometry.hpp"
#include "rgvc/grid/OcclusionBuffer3D.hpp"
#include "rgvc/grid/ViewFrustum.hpp"
#include "rgvc/grid/VoxelStorage.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstddef>
#include <iterator>
#include <type_traits>
#include <vector>

namespace rgvc {

struct BrickTraversalStats3D {
    std::uint64_t nodesVisited = 0;  ///< nodes taken from the stack
    std::uint64_t nodesEmpty = 0;    ///< of those, skipped: nothing below them
    std::uint64_t nodesOutside = 0;  ///< of those, skipped: outside the frustum
    std::uint64_t nodesHidden = 0;   ///< of those, skipped: hidden in the occlusion image
    std::uint64_t bricksVisited = 0; ///< bricks whose voxels were read
    std::uint64_t bricksCleared = 0; ///< of those, found empty and cleared in the pyramid
    std::uint64_t voxelsVisited = 0; ///< voxels of those bricks inside the frustum
    std::uint64_t fusedBoxes = 0;    ///< boxes of opaque voxels drawn as occluders (drawFusedBox)
    /// Occupied bricks touching the frustum below the hidden nodes: what the image saved the walk from
    /// reading (counted up to bricksVisited / 4 + 16, more than CullerOptions::adaptiveImage asks).
    std::uint64_t bricksSkipped = 0;
};

template <VoxelStorage Storage> class BrickTraversal3D {
public:
    /// Walks the brick tree of `storage` for one frame.
    /// @param image      the occlusion image (begun for `frustum`), or null for none (view-frustum culling).
    ///                   The caller draws into it from onVoxel; nodes are tested against it as it grows.
    /// @param mayHoldTbv bool(IVec3 brick): whether a TBV may hold a voxel of that brick (false: a guarantee).
    /// @param onVoxel    void(VoxelKey, IVec3 voxel): called for every voxel of a visited brick that touches
    ///                   the frustum and holds ids. Its visited mark is set (stamp). It may add ids to the
    ///                   storage (a revealed object) and draw.
    /// @param onTbvs     void(IVec3 brick, const std::uint64_t visited[8], const std::uint64_t opaque[8]): for
    ///                   a visited brick that may hold a TBV, called once after its ids, with the brick's
    ///                   voxels that touch the frustum and those of them in O as its fused boxes read O
    ///                   (none without an image; O only grows during a walk, so they are in O at the call)
    ///                   (slice words: bit x + 8 y of slice z, brick-local); the caller tests those that
    ///                   hold a TBV against the image (and may leave out the opaque ones: BrickPass.cpp
    ///                   says when).
    /// @param insideObject bool(VoxelKey seed, IVec3 lo, IVec3 hi): whether the voxel box lo..hi (inclusive)
    ///                   grown from opaque voxel `seed` lies inside one object the caller will draw itself
    ///                   (a box object holding the seed): that fused box then adds nothing and is not drawn.
    /// @param onBrickIds bool(IVec3 brick, bool inCone), or null: when given, the caller keeps its own list of
    ///                   the objects in each brick (a superset of those with ids in it) and meets them there,
    ///                   once per visited brick after its fused boxes, returning whether the list holds any;
    ///                   the voxels' ids are then not read and onVoxel is not called. inCone: the brick's
    ///                   part in the grid lies inside the view's cone (strictly inside its four side planes),
    ///                   so whatever meets that part meets the cone.
    /// @param countSkippedBricks  fill st.bricksSkipped (CullerOptions::adaptiveImage's measure).
    template <class MayHoldTbv, class OnVoxel, class OnTbvs, class InsideObject, class OnBrickIds = std::nullptr_t>
    BrickTraversalStats3D run(const GridGeometry3& grid, Storage& storage, const ViewFrustum& frustum,
                              OcclusionBuffer3D* image, std::uint32_t stamp, MayHoldTbv&& mayHoldTbv,
                              OnVoxel&& onVoxel, OnTbvs&& onTbvs, InsideObject&& insideObject,
                              OnBrickIds&& onBrickIds = nullptr, bool countSkippedBricks = false) {
        BrickTraversalStats3D st;
        const IVec3 res = grid.resolution();
        const double grow = frustum.slack();
        const BrickWalkStats ws = walkBricks<3>(
            storage.bricks(), res, frustum.apex(), m_stack,
            [&](const IVec3& lo, const IVec3& hi, int level) {
                const Vec3 loF(lo), hiF(hi);
                if (!frustum.touchesBox(loF, hiF)) {
                    ++st.nodesOutside;
                    return true;
                }
                // A node above the bricks is tested with its one footprint: when that fails, the walk
                // tests its children, which are the parts hidden()'s refinement would have split it into
                // (the halves, each with its own nearest distance), so refining here would pay twice. A
                // brick's refinement has no such stand-in: its voxels are read when it is not hidden.
                const bool brick = hi.x - lo.x <= BrickPyramid<3>::kBrickSize && hi.y - lo.y <= BrickPyramid<3>::kBrickSize &&
                                   hi.z - lo.z <= BrickPyramid<3>::kBrickSize;
                if (image != nullptr && (brick ? image->hidden(Box<3>{loF, hiF}, grow) : image->hiddenCoarse(Box<3>{loF, hiF}, grow))) {
                    ++st.nodesHidden;
                    if (countSkippedBricks) countSkipped(storage.bricks(), res, frustum, level, lo, st);
                    return true;
                }
                return false;
            },
            [&](const IVec3& brick, const IVec3& lo, const IVec3& hi) {
                visitBrick(grid, storage, frustum, image, brick, lo, hi, stamp, mayHoldTbv(brick), onVoxel, onTbvs, insideObject,
                           onBrickIds, st);
            });
        st.nodesVisited = ws.nodesVisited;
        st.nodesEmpty = ws.nodesEmpty;
        return st;
    }

private:
    /// Adds to st.bricksSkipped the occupied bricks touching the frustum in the node of `level` whose first
    /// voxel is lo, walking its subtree with the same frustum test as the walk, until the count reaches
    /// bricksVisited / 4 + 16: twice what the adaptive schedule asks for (one skipped brick per eight
    /// read) unless the walk reads more than twice as much after the node, and it keeps the count's cost
    /// a small part of the walk's (a closed room hides thousands of bricks outside it).
    void countSkipped(const BrickPyramid<3>& tree, const IVec3& res, const ViewFrustum& frustum, int level, const IVec3& lo,
                      BrickTraversalStats3D& st) {
        const std::uint64_t cap = st.bricksVisited / 4 + 16;
        if (st.bricksSkipped >= cap) return;
        m_count.clear();
        m_count.push_back({level, lo / (BrickPyramid<3>::kBrickSize << level)});
        while (!m_count.empty() && st.bricksSkipped < cap) {
            const BrickNode<3> n = m_count.back();
            m_count.pop_back();
            if (!tree.occupied(n.level, n.c)) continue;
            const std::int32_t s = BrickPyramid<3>::kBrickSize << n.level;
            const IVec3 nlo = n.c * s, nhi = glm::min(nlo + s, res);
            if (!frustum.touchesBox(Vec3(nlo), Vec3(nhi))) continue;
            if (n.level == 0) {
                ++st.bricksSkipped;
                continue;
            }
            const IVec3 dims = tree.dims(n.level - 1);
            for (int i = 0; i < 8; ++i) {
                const IVec3 cc{2 * n.c.x + (i & 1), 2 * n.c.y + ((i >> 1) & 1), 2 * n.c.z + ((i >> 2) & 1)};
                if (cc.x < dims.x && cc.y < dims.y && cc.z < dims.z) m_count.push_back({n.level - 1, cc});
            }
        }
    }

    template <class OnVoxel, class OnTbvs, class InsideObject, class OnBrickIds>
    void visitBrick(const GridGeometry3& grid, Storage& storage, const ViewFrustum& frustum, OcclusionBuffer3D* image,
                    const IVec3& brick, const IVec3& lo, const IVec3& hi, std::uint32_t stamp, bool tbvHere,
                    OnVoxel& onVoxel, OnTbvs& onTbvs, InsideObject& insideObject, OnBrickIds& onBrickIds,
                    BrickTraversalStats3D& st) {
        constexpr bool kLists = !std::is_same_v<std::decay_t<OnBrickIds>, std::nullptr_t>;
        ++st.bricksVisited;
        // The far limit needs a test per voxel only in the bricks it cuts: a brick whose farthest corner is
        // within it keeps every voxel (withinFar tests a voxel's nearest point, which is no farther).
        bool hasFar = !std::isinf(frustum.far());
        if (hasFar) {
            double far2 = 0;
            for (int a = 0; a < 3; ++a) {
                const double d = std::max(std::abs(double(lo[a]) - frustum.apex()[a]), std::abs(double(hi[a]) - frustum.apex()[a]));
                far2 += d * d;
            }
            hasFar = !(far2 <= frustum.far() * frustum.far());
        }
        bool anyIds = false;
        // Pass 1: per row, which voxels hold ids, and the span inside the frustum; opaque voxels in view
        // start fused occluders (drawFusedBox) before any id of the brick is classified, so that a wall
        // hides what lies behind it in the same brick.
        // A brick wholly inside the cone (its nearest corner on the inner side of every side plane) needs
        // no row clipping: clipVoxelRow keeps every voxel of it (each voxel's farthest corner is on the
        // inner side too). Most bricks a traversal reads away from the view's edges are such bricks.
        // Per plane: a brick wholly on its inner side needs no clipping against it (the same argument,
        // plane by plane), so the rows of a brick at the view's edge are clipped against the one or two
        // planes it straddles (clipVoxelRow was a tenth of the walk on rgvc_bench_classes' game world).
        unsigned straddled = 0;
        for (int i = 0; i < 4; ++i) {
            const Vec3& n = frustum.sideNormal(i);
            double nearest = 0;
            for (int a = 0; a < 3; ++a) nearest += n[a] * (double(n[a] > 0 ? lo[a] : hi[a]) - frustum.apex()[a]);
            if (!(nearest > 0)) straddled |= 1u << i;
        }
        const bool inCone = straddled == 0;
        if constexpr (kLists)
            if (inCone && !hasFar) {
                visitWholeBrick(grid, storage, frustum, image, brick, lo, hi, stamp, tbvHere, onTbvs, insideObject, onBrickIds, st);
                return;
            }
        // The straddled planes' spans for all 64 rows at once (VoxelRowClipper::clipBrick, vectorized).
        std::int32_t clipU0[64], clipU1[64];
        if (!inCone) {
            std::fill(std::begin(clipU0), std::end(clipU0), lo.x);
            std::fill(std::begin(clipU1), std::end(clipU1), hi.x - 1);
            VoxelRowClipper(frustum, straddled).clipBrick(lo.y, lo.z, clipU0, clipU1);
        }
        const std::uint32_t resY = std::uint32_t(grid.resolution().y);
        // With the caller's lists and no far limit, no voxel callback needs ordering after the brick's
        // objects: the visited marks, counts and slice words are set in this one pass over the rows, and
        // pass 2 is skipped (its second loop over the rows was a fifth of the walk's per-brick work).
        const bool onePass = kLists && !hasFar;
        std::uint64_t visible[8] = {0, 0, 0, 0, 0, 0, 0, 0}; // the visited voxels, as slice words
        if constexpr (kLists)
            if (onePass) {
                visitClippedBrick(grid, storage, frustum, image, brick, lo, hi, stamp, tbvHere, clipU0, clipU1, onTbvs,
                                  insideObject, onBrickIds, st);
                return;
            }
        int rows = 0;
        std::uint64_t opaque[8] = {0, 0, 0, 0, 0, 0, 0, 0}; // onTbvs's: the opaque voxels the fused boxes read
        for (std::int32_t z = lo.z; z < hi.z; ++z)
            for (std::int32_t y = lo.y; y < hi.y; ++y) {
                RowInfo& r = m_rows[std::size_t(rows++)];
                r.word = storage.rowWord(std::uint32_t(y) + resY * std::uint32_t(z), lo.x);
                r.y = y;
                r.z = z;
                r.ids = 0; // bit x - lo.x: the voxels with ids (read only without the caller's lists)
                if constexpr (!kLists) {
                    r.key = grid.linearIndex(IVec3{0, y, z}); // (for onVoxel, which only the ids call)
                    for (std::int32_t x = lo.x; x < hi.x; ++x) r.ids |= std::uint32_t(storage.hasIds(VoxelKey(r.key + std::uint32_t(x)))) << (x - lo.x);
                    anyIds = anyIds || r.ids != 0;
                }
                r.u0 = lo.x;
                r.u1 = hi.x - 1;
                if (!inCone) {
                    const std::size_t c = std::size_t(8 * (z - lo.z) + (y - lo.y));
                    r.u0 = clipU0[c];
                    r.u1 = clipU1[c];
                    if (r.u0 > r.u1) r.u0 = 1, r.u1 = 0;
                }
                if (image == nullptr || r.u0 > r.u1) continue;
                // O's word (lo.x is a multiple of 8: bit x - lo.x), the span's opaque voxels only.
                const std::uint32_t span = ((2u << (r.u1 - r.u0)) - 1u) << (r.u0 - lo.x);
                std::uint32_t bits = storage.opaqueBits(r.word) & span;
                if (bits == 0) continue; // (most rows: U is read only where O is set, and again after each box,
                                         // which marks later voxels of the row used)
                opaque[z - lo.z] |= std::uint64_t(bits) << (8 * (y - lo.y));
                drawFusedBoxes(grid, storage, frustum, *image, bits, IVec3{lo.x, y, z}, stamp, insideObject, st);
            }
        // The caller's list of the brick's objects, after the fused boxes as the ids would be.
        if constexpr (kLists) anyIds = onBrickIds(brick, inCone);
        // Pass 2: visit the spans; then the brick's TBVs, all at once when the caller can.
        for (int i = 0; i < rows; ++i) {
            const RowInfo& r = m_rows[std::size_t(i)];
            std::uint32_t inView = 0; // bit x - lo.x: visited
            if (!hasFar) {
                // The whole span is visited: its mask at once, the ids' voxels by their bits.
                if (r.u0 > r.u1) continue;
                st.voxelsVisited += std::uint64_t(r.u1 - r.u0 + 1);
                inView = ((2u << (r.u1 - r.u0)) - 1u) << (r.u0 - lo.x);
                for (std::uint32_t bits = r.ids & inView; bits != 0; bits &= bits - 1) {
                    const std::int32_t x = lo.x + std::countr_zero(bits);
                    onVoxel(VoxelKey(r.key + std::uint32_t(x)), IVec3{x, r.y, r.z});
                }
            } else {
                for (std::int32_t x = r.u0; x <= r.u1; ++x) {
                    const IVec3 v{x, r.y, r.z};
                    if (!frustum.withinFar(Vec3(v), Vec3(v) + 1.0)) continue;
                    ++st.voxelsVisited;
                    inView |= 1u << (x - lo.x);
                    if (((r.ids >> (x - lo.x)) & 1) != 0) onVoxel(VoxelKey(r.key + std::uint32_t(x)), v);
                }
            }
            visible[r.z - lo.z] |= std::uint64_t(inView) << (8 * (r.y - lo.y));
        }
        storage.setBrickVisited(brick, visible, stamp);
        if (tbvHere) onTbvs(brick, visible, opaque);
        clearIfEmpty(storage, brick, anyIds, tbvHere, st);
    }

    /// visitBrick's one pass for a brick the cone's side planes cut, with the caller's object lists and no
    /// far limit to test (pass 2 is then empty): the same marks, counts, fused boxes and calls in the same
    /// order as the general row loop, which computed each row's word, span, mask and opaque bits in turn
    /// and kept a RowInfo per row for a pass 2 that never came. Here the rows' words come by their
    /// strides (as in visitWholeBrick) and their spans' masks, counts and visible slices in one loop.
    /// clipU0, clipU1: the rows' spans (8 (z - lo.z) + y - lo.y), from VoxelRowClipper::clipBrick.
    template <class OnTbvs, class InsideObject, class OnBrickIds>
    void visitClippedBrick(const GridGeometry3& grid, Storage& storage, const ViewFrustum& frustum, OcclusionBuffer3D* image,
                           const IVec3& brick, const IVec3& lo, const IVec3& hi, std::uint32_t stamp, bool tbvHere,
                           const std::int32_t* clipU0, const std::int32_t* clipU1, OnTbvs& onTbvs, InsideObject& insideObject,
                           OnBrickIds& onBrickIds, BrickTraversalStats3D& st) {
        std::size_t words[64];
        rowWords(grid, storage, lo, hi, words);
        std::uint32_t inView[64]; // per row (z major): bit x - lo.x, the span's voxels
        std::uint64_t visible[8] = {0, 0, 0, 0, 0, 0, 0, 0};
        std::uint64_t visited = 0, opaque[8] = {0, 0, 0, 0, 0, 0, 0, 0};
        for (std::int32_t z = lo.z, i = 0; z < hi.z; ++z)
            for (std::int32_t y = lo.y; y < hi.y; ++y, ++i) {
                const std::size_t c = std::size_t(8 * (z - lo.z) + (y - lo.y));
                const std::int32_t u0 = clipU0[c], u1 = std::min(clipU1[c], hi.x - 1);
                const std::uint32_t m = u0 <= u1 ? ((2u << (u1 - u0)) - 1u) << (u0 - lo.x) : 0u;
                inView[i] = m;
                visited += std::uint64_t(std::popcount(m));
                visible[z - lo.z] |= std::uint64_t(m) << (8 * (y - lo.y));
            }
        st.voxelsVisited += visited;
        storage.setBrickVisited(brick, visible, stamp);
        if (image != nullptr)
            drawOpaqueRows(grid, storage, frustum, *image, lo, hi, words, [&](int i) { return inView[i]; }, stamp, insideObject,
                           opaque, st);
        const bool anyIds = onBrickIds(brick, false);
        if (tbvHere) onTbvs(brick, visible, opaque);
        clearIfEmpty(storage, brick, anyIds, tbvHere, st);
    }

    /// visitBrick for a brick wholly inside the cone and the far limit, with the caller's object lists:
    /// every row's span is the whole row, so the per-row spans, clipping and id bits are not computed.
    /// The same work in the same order as the general path (fused boxes, the lists, the visited marks,
    /// the TBVs, the empty mark), and the same results; a third of the walk's per-brick cost, which the
    /// bricks away from the view's edges (most of them) paid row by row.
    template <class OnTbvs, class InsideObject, class OnBrickIds>
    void visitWholeBrick(const GridGeometry3& grid, Storage& storage, const ViewFrustum& frustum, OcclusionBuffer3D* image,
                         const IVec3& brick, const IVec3& lo, const IVec3& hi, std::uint32_t stamp, bool tbvHere,
                         OnTbvs& onTbvs, InsideObject& insideObject, OnBrickIds& onBrickIds, BrickTraversalStats3D& st) {
        const std::uint32_t full = (2u << (hi.x - 1 - lo.x)) - 1u; // bits x - lo.x of the row
        std::size_t words[64];
        const int rows = rowWords(grid, storage, lo, hi, words);
        std::uint64_t opaque[8] = {0, 0, 0, 0, 0, 0, 0, 0};
        if (image != nullptr)
            drawOpaqueRows(grid, storage, frustum, *image, lo, hi, words, [&](int) { return full; }, stamp, insideObject, opaque, st);
        const bool anyIds = onBrickIds(brick, true);
        st.voxelsVisited += std::uint64_t(rows) * std::uint64_t(hi.x - lo.x);
        std::uint64_t slice = 0; // `full` on each of the brick's rows along y
        for (std::int32_t y = lo.y; y < hi.y; ++y) slice |= std::uint64_t(full) << (8 * (y - lo.y));
        std::uint64_t visible[8] = {0, 0, 0, 0, 0, 0, 0, 0};
        for (std::int32_t z = lo.z; z < hi.z; ++z) visible[z - lo.z] = slice;
        storage.setBrickVisited(brick, visible, stamp);
        if (tbvHere) onTbvs(brick, visible, opaque);
        clearIfEmpty(storage, brick, anyIds, tbvHere, st);
    }

    /// The brick-row words of the brick's rows lo..hi (hi exclusive), z major, into `words`; returns their
    /// count. From the first by the y and z strides (taken from rowWord, so every storage lays them out its
    /// own way): a row's word per row, as rowWord computes it, was a tenth of scenes/open-3d.json's
    /// instructions through `rgvc cull`.
    int rowWords(const GridGeometry3& grid, const Storage& storage, const IVec3& lo, const IVec3& hi, std::size_t (&words)[64]) const {
        const std::uint32_t resY = std::uint32_t(grid.resolution().y);
        const std::uint32_t row0 = std::uint32_t(lo.y) + resY * std::uint32_t(lo.z);
        const std::size_t first = storage.rowWord(row0, lo.x);
        const std::size_t yStep = storage.rowWord(row0 + 1, lo.x) - first, zStep = yStep * resY;
        int rows = 0;
        for (std::int32_t z = lo.z; z < hi.z; ++z) {
            std::size_t word = first + std::size_t(z - lo.z) * zStep;
            for (std::int32_t y = lo.y; y < hi.y; ++y, word += yStep) words[rows++] = word;
        }
        return rows;
    }

    /// The fused boxes started from the brick's rows (words as rowWords gives them), row after row, from
    /// each row's opaque voxels among mask(i) (bit x - lo.x of row i); those voxels ORed into `opaque`
    /// (slice words, onTbvs's).
    template <class Mask, class InsideObject>
    void drawOpaqueRows(const GridGeometry3& grid, Storage& storage, const ViewFrustum& frustum, OcclusionBuffer3D& image,
                        const IVec3& lo, const IVec3& hi, const std::size_t* words, Mask&& mask, std::uint32_t stamp,
                        InsideObject& insideObject, std::uint64_t (&opaque)[8], BrickTraversalStats3D& st) {
        int i = 0;
        for (std::int32_t z = lo.z; z < hi.z; ++z)
            for (std::int32_t y = lo.y; y < hi.y; ++y, ++i) {
                const std::uint32_t bits = storage.opaqueBits(words[i]) & mask(i);
                if (bits == 0) continue;
                opaque[z - lo.z] |= std::uint64_t(bits) << (8 * (y - lo.y));
                drawFusedBoxes(grid, storage, frustum, image, bits, IVec3{lo.x, y, z}, stamp, insideObject, st);
            }
    }

    /// The fused boxes started from a brick row's opaque voxels `bits` (bit x - first.x; `first` is the
    /// row's first voxel) that no box drawn this frame has used yet. U is read again after each box, which
    /// marks later voxels of the row used.
    template <class InsideObject>
    void drawFusedBoxes(const GridGeometry3& grid, Storage& storage, const ViewFrustum& frustum, OcclusionBuffer3D& image,
                        std::uint32_t bits, const IVec3& first, std::uint32_t stamp,
                        InsideObject& insideObject, BrickTraversalStats3D& st) {
        for (bits &= ~storage.usedBits(first, stamp); bits != 0; bits &= ~storage.usedBits(first, stamp)) {
            const std::int32_t x = first.x + std::countr_zero(bits);
            bits &= bits - 1;
            drawFusedBox(grid, storage, frustum, image, IVec3{x, first.y, first.z}, stamp, insideObject, st);
        }
    }

    /// A visited brick with nothing in it (no listed object or id, no TBV) is cleared in the pyramid.
    /// (onVoxel, which may add ids, ran for no voxel of it then.) Not over a storage shared by concurrent
    /// views, kSharedScene: the pyramid is the scene's; it is left as a superset, which only costs a later
    /// walk the brick's voxels once more.
    void clearIfEmpty(Storage& storage, const IVec3& brick, bool anyIds, bool tbvHere, BrickTraversalStats3D& st) {
        if constexpr (!requires { Storage::kSharedScene; }) {
            if (!anyIds && !tbvHere) {
                storage.bricks().markEmpty(brick);
                ++st.bricksCleared;
            }
        }
    }

    /// Occluder fusion from O (the 3D counterpart of §4.3's extension). Objects are drawn into the image
    /// one by one, and a pixel counts for an occluder only if its whole cone passes through that one
    /// occluder, so a wall of boxes sharing faces would leave every seam open. O is their union (a voxel is
    /// opaque when it lies inside an object), so a box of opaque voxels is a single convex occluder however
    /// many objects make it. From an opaque voxel not yet used this frame: the longest opaque run along x
    /// through it (both ways), then grown along y while the whole run is opaque, then along z while the
    /// whole rectangle is, each side at most kMaxGrow voxels. The box may reach into voxels already used or
    /// outside the view: boxes that overlap are what fuses two walls meeting at a corner (a pixel on the
    /// corner's silhouette is inside one of them as long as the shared voxels span at least a pixel).
    /// Its voxels are marked used so that they start no other box. Drawn shrunk by the camera's slack
    /// (O already keeps the objects' conversion slack: its voxels are inside by that margin).
    template <class InsideObject>
    void drawFusedBox(const GridGeometry3& grid, Storage& storage, const ViewFrustum& frustum, OcclusionBuffer3D& image,
                      const IVec3& v, std::uint32_t stamp, InsideObject& insideObject, BrickTraversalStats3D& st) {
        const IVec3 res = grid.resolution();
        // Row index of (y, z): its key / res.x (VoxelStorage.hpp's brick-row words).
        auto rowOf = [&](std::int32_t y, std::int32_t z) { return std::uint32_t(y) + std::uint32_t(res.y) * std::uint32_t(z); };
        IVec3 lo = v, hi = v; // inclusive
        const std::uint32_t seedRow = rowOf(v.y, v.z);
        brick_rows::opaqueRun(storage, seedRow, res.x, v.x, kMaxGrow, lo.x, hi.x);
        auto rowOpaque = [&](std::int32_t y, std::int32_t z) { return brick_rows::allOpaque(storage, rowOf(y, z), lo.x, hi.x); };
        while (hi.y + 1 < res.y && hi.y - v.y < kMaxGrow && rowOpaque(hi.y + 1, v.z)) ++hi.y;
        while (lo.y > 0 && v.y - lo.y < kMaxGrow && rowOpaque(lo.y - 1, v.z)) --lo.y;
        auto sliceOpaque = [&](std::int32_t z) {
            for (std::int32_t y = lo.y; y <= hi.y; ++y)
                if (!rowOpaque(y, z)) return false;
            return true;
        };
        while (hi.z + 1 < res.z && hi.z - v.z < kMaxGrow && sliceOpaque(hi.z + 1)) ++hi.z;
        while (lo.z > 0 && v.z - lo.z < kMaxGrow && sliceOpaque(lo.z - 1)) --lo.z;
        storage.markUsedBox(lo, hi, stamp);
        // A box inside one box object (a wall, a building) repeats that object, which is drawn when the
        // brick's ids are classified (or is hidden, and then so is this box): the room's six walls and
        // the game world's buildings were drawn twice.
        // The size first: most boxes are too small to draw (the insides of small movers), and the
        // object check reads the objects of the seed (without I in the culler, its brick's whole list).
        const Box<3> box{Vec3(lo), Vec3(hi + 1)};
        const Vec3 half = 0.5 * Vec3(hi + 1 - lo);
        if (!image.spans(std::sqrt(lengthSquared<3>(half)), image.nearestDistance(box, 0), kMinOccluderPixels)) return;
        if (insideObject(grid.linearIndex(v), lo, hi)) return;
        image.draw(box, frustum.slack());
        ++st.fusedBoxes;
    }

    struct RowInfo {
        VoxelKey key = 0;
        std::size_t word = 0; // the row's brick-row word (VoxelStorage.hpp)
        std::int32_t y = 0, z = 0, u0 = 0, u1 = -1;
        std::uint32_t ids = 0;
    };
    static constexpr std::int32_t kMaxGrow = 64;
    static constexpr double kMinOccluderPixels = 4; // smaller fused boxes are not drawn (OcclusionBuffer3D::spans)
    std::array<RowInfo, 64> m_rows{}; // a brick's 8 x 8 rows
    std::vector<BrickNode<3>> m_count; // countSkipped's stack (kept: no allocation once warm)
    std::vector<BrickNode<3>> m_stack;
};

} // namespace rgvc
