// The output-sensitive 2D traversal: the quadtree over 8x8 bricks walked front to back (BrickWalk.hpp),
// with occlusion from a conservative 1D angular image of the occluders met so far (OcclusionBuffer2D.hpp).
// The 2D counterpart of BrickTraversal3D.hpp; CullerOptions::hierarchical picks it.
//
// Why not the chess rings alone. The ring traversal (FrustumTraversal2D.hpp, §4.2-4.4) visits every
// voxel of the view that is not in H, one by one, empty or not, so its cost is the view's area: an
// empty 2048^2 world seen through 360 degrees is 4 million voxel visits. Here the unit of work is a node
// of the implicit quadtree over 8x8 bricks: a node with no id and no TBV below it is skipped in O(1), a
// node outside the wedge is skipped, a node hidden in the image is skipped, and only the bricks left
// read their voxels.
//
// Occlusion. The image holds, per angular bin, a distance by which every ray of the bin has entered the
// interior of some occluder (OcclusionBuffer2D.hpp derives it). Two kinds of occluders are drawn:
//   - the objects the caller finds visible (it draws their occluder model from onVoxel);
//   - boxes of opaque voxels (drawFusedBox): O is the union of the objects' inner voxels, so a box of
//     opaque voxels is one convex occluder however many objects make it (walls of unit boxes packed face
//     to face). Boxes are grown from an unused opaque voxel along x, then along y while the whole run is
//     opaque, and may reach into voxels already used: two walls meeting at a corner share the corner's
//     voxels, so a bin whose rays hit both walls near the corner passes through the corner voxels of
//     either box, and is covered (the role of §4.4's L-shaped polygon, here at bin resolution).
// A box drawn is inside the union of other objects' closed shapes; every bin depth is a true bound when
// written, so a node or voxel the image hides is hidden from the camera point for its whole extent
// (the contract's requirement), whatever the order of drawing.
//
// Soundness of a skipped node: BrickWalk.hpp (empty), ViewWedge::touchesBox (outside, conservative),
// OcclusionBuffer2D::hidden (hidden, the box grown by the camera's slack). TBVs: see Culler's
// traverseBricks.
//
// Cost: O(nodes tested) + O(64 per visited brick) + the drawing; nothing per voxel of empty or hidden
// space. An empty grid visits one node.
#pragma once

#include "rgvc/grid/BrickPyramid.hpp"
#include "rgvc/grid/BrickRows.hpp"
#include "rgvc/grid/BrickWalk.hpp"
#include "rgvc/grid/GridGeometry.hpp"
#include "rgvc/grid/OcclusionBuffer2D.hpp"
#include "rgvc/grid/ViewWedge.hpp"
#include "rgvc/grid/VoxelStorage.hpp"

#include <bit>
#include <cstdint>
#include <vector>

namespace rgvc {

struct BrickTraversalStats2D {
    std::uint64_t nodesVisited = 0;  ///< nodes taken from the stack
    std::uint64_t nodesEmpty = 0;    ///< of those, skipped: nothing below them
    std::uint64_t nodesOutside = 0;  ///< of those, skipped: outside the wedge (or past `far`)
    std::uint64_t nodesHidden = 0;   ///< of those, skipped: hidden in the occlusion image
    std::uint64_t bricksVisited = 0; ///< bricks whose voxels were read
    std::uint64_t bricksCleared = 0; ///< of those, found empty and cleared in the pyramid
    std::uint64_t voxelsVisited = 0; ///< voxels of those bricks in view
    std::uint64_t fusedBoxes = 0;    ///< boxes of opaque voxels drawn as occluders
};

template <VoxelStorage Storage> class BrickTraversal2D {
public:
    /// Walks the brick tree of `storage` for one frame.
    /// @param image      the occlusion image (begun for `wedge`), or null for none (view-region culling).
    ///                   The caller draws into it from onVoxel; nodes are tested against it as it grows.
    /// @param mayHoldTbv bool(IVec2 brick): whether a TBV may hold a voxel of that brick (false: a guarantee).
    /// @param onVoxel    void(VoxelKey, IVec2 voxel): called for every voxel of a visited brick that is in
    ///                   view and holds ids. Its visited mark is set (stamp). It may add ids and draw.
    /// @param onTbvs     void(IVec2 brick, const std::uint8_t inView[8], opaqueRow): for a visited brick that
    ///                   may hold a TBV, called after the brick's ids with its voxels in view (bit x - lo.x
    ///                   of row y - lo.y, lo = 8 brick); the caller looks them up in T and tests them
    ///                   against the image. opaqueRow(int row) gives the voxels in O of a row in the grid
    ///                   (lo.y + row < the grid's rows), for a caller that leaves those out (BrickPass.cpp
    ///                   says when).
    /// @param insideObject bool(VoxelKey seed, IVec2 lo, IVec2 hi): whether the voxel box lo..hi (inclusive)
    ///                   grown from opaque voxel `seed` lies inside one box object the caller draws itself.
    template <class MayHoldTbv, class OnVoxel, class OnTbvs, class InsideObject>
    BrickTraversalStats2D run(const GridGeometry2& grid, Storage& storage, const ViewWedge& wedge,
                              OcclusionBuffer2D* image, std::uint32_t stamp, MayHoldTbv&& mayHoldTbv,
                              OnVoxel&& onVoxel, OnTbvs&& onTbvs, InsideObject&& insideObject) {
        BrickTraversalStats2D st;
        const double grow = wedge.slack();
        const BrickWalkStats ws = walkBricks<2>(
            storage.bricks(), grid.resolution(), wedge.apex(), m_stack,
            [&](const IVec2& lo, const IVec2& hi) {
                const Vec2 loF(lo), hiF(hi);
                if (!wedge.touchesBox(loF, hiF)) {
                    ++st.nodesOutside;
                    return true;
                }
                // As in 3D (BrickTraversal3D.hpp): a node above the bricks takes the one-extent test, since
                // its children, tested next when it fails, are the quarters the refinement would split it
                // into; a brick keeps the refinement (its voxels are read when it fails).
                const bool brick = hi.x - lo.x <= BrickPyramid<2>::kBrickSize && hi.y - lo.y <= BrickPyramid<2>::kBrickSize;
                if (image != nullptr && (brick ? image->hidden(Box<2>{loF, hiF}, grow) : image->hiddenCoarse(Box<2>{loF, hiF}, grow))) {
                    ++st.nodesHidden;
                    return true;
                }
                return false;
            },
            [&](const IVec2& brick, const IVec2& lo, const IVec2& hi) {
                visitBrick(grid, storage, wedge, image, brick, lo, hi, stamp, mayHoldTbv(brick), onVoxel, onTbvs,
                           insideObject, st);
            });
        st.nodesVisited = ws.nodesVisited;
        st.nodesEmpty = ws.nodesEmpty;
        return st;
    }

private:
    template <class OnVoxel, class OnTbvs, class InsideObject>
    void visitBrick(const GridGeometry2& grid, Storage& storage, const ViewWedge& wedge, OcclusionBuffer2D* image,
                    const IVec2& brick, const IVec2& lo, const IVec2& hi, std::uint32_t stamp, bool tbvHere,
                    OnVoxel& onVoxel, OnTbvs& onTbvs, InsideObject& insideObject, BrickTraversalStats2D& st) {
        ++st.bricksVisited;
        // A brick wholly in view needs no per-voxel test. The wedge (<= 180 degrees or the full circle) and
        // the far disc are convex, so four corners in view put the whole box in view.
        const Vec2 loF(lo), hiF(hi);
        const bool convex = wedge.isFullCircle() || wedge.isConvex();
        const bool whole = convex && wedge.containsPoint(loF) && wedge.containsPoint(hiF) &&
                           wedge.containsPoint(Vec2{loF.x, hiF.y}) && wedge.containsPoint(Vec2{hiF.x, loF.y});
        // Pass 1: the voxels in view (bit x - lo.x of row y - lo.y), which hold ids, and the fused boxes
        // of the opaque ones, drawn before any id of the brick is classified so that a wall hides what
        // lies behind it in the same brick.
        bool anyIds = false;
        std::uint8_t inView[8] = {0, 0, 0, 0, 0, 0, 0, 0}, ids[8] = {0, 0, 0, 0, 0, 0, 0, 0};
        const std::uint32_t all = (1u << (hi.x - lo.x)) - 1u;
        for (std::int32_t y = lo.y; y < hi.y; ++y) {
            const VoxelKey row = grid.linearIndex(IVec2{0, y});
            const std::size_t word = storage.rowWord(std::uint32_t(y), lo.x);
            std::uint32_t view = whole ? all : 0, hold = 0;
            if (!whole && convex) {
                // A convex view (the wedge and the far disc are convex; touchesVoxel is their two box
                // tests) meets a row of voxels in one run: the voxels meeting a convex set are those whose
                // x range meets the set's part in the row's band, an interval. So only the voxels before
                // the run's first and after its last are tested from the row's ends inward (a straddling
                // brick's voxels in view are not: most of the per-voxel tests, 7 % of the 2D random
                // scenes' time). Were rounding to open a gap inside the run, its voxels would be visited
                // as in view: more work, never a voxel left out.
                std::int32_t a = lo.x, b = hi.x - 1;
                while (a <= b && !wedge.touchesVoxel(IVec2{a, y})) ++a;
                while (b > a && !wedge.touchesVoxel(IVec2{b, y})) --b;
                if (a <= b) view = ((2u << (b - lo.x)) - 1u) & ~((1u << (a - lo.x)) - 1u);
            }
            for (std::int32_t x = lo.x; x < hi.x; ++x) {
                if (!whole && !convex) view |= std::uint32_t(wedge.touchesVoxel(IVec2{x, y})) << (x - lo.x);
                hold |= std::uint32_t(storage.hasIds(VoxelKey(row + std::uint32_t(x)))) << (x - lo.x);
            }
            // O's word (lo.x is a multiple of 8: bit x - lo.x), its voxels in view only.
            // (U read only where O is set, and again after each box: a box marks later voxels of the row used.)
            if (std::uint32_t bits = image != nullptr ? storage.opaqueBits(word) & view : 0u; bits != 0)
                for (bits &= ~storage.usedBits(IVec2{lo.x, y}, stamp); bits != 0; bits &= ~storage.usedBits(IVec2{lo.x, y}, stamp)) {
                    const std::int32_t x = lo.x + std::countr_zero(bits);
                    bits &= bits - 1;
                    drawFusedBox(grid, storage, wedge, *image, IVec2{x, y}, stamp, insideObject, st);
                }
            inView[y - lo.y] = std::uint8_t(view);
            ids[y - lo.y] = std::uint8_t(hold);
            anyIds = anyIds || hold != 0;
        }
        // Pass 2: visit (V's bits for the brick at once, then the ids' voxels).
        std::uint64_t visible = 0;
        for (std::int32_t y = lo.y; y < hi.y; ++y) visible |= std::uint64_t(inView[y - lo.y]) << (8 * (y - lo.y));
        storage.setBrickVisited(brick, &visible, stamp);
        for (std::int32_t y = lo.y; y < hi.y; ++y) {
            const VoxelKey row = grid.linearIndex(IVec2{0, y});
            const std::uint32_t view = inView[y - lo.y];
            st.voxelsVisited += std::uint64_t(std::popcount(view));
            for (std::uint32_t bits = view & ids[y - lo.y]; bits != 0; bits &= bits - 1) {
                const std::int32_t x = lo.x + std::countr_zero(bits);
                onVoxel(VoxelKey(row + std::uint32_t(x)), IVec2{x, y});
            }
        }
        if (tbvHere)
            onTbvs(brick, inView, [&](int row) { return std::uint32_t(storage.opaqueBits(storage.rowWord(std::uint32_t(lo.y + row), lo.x))); });
        // (Not over a storage shared by concurrent views, kSharedScene: the pyramid is the scene's; it is
        // left as a superset, which only costs a later walk the brick's voxels once more.)
        if constexpr (!requires { Storage::kSharedScene; }) {
            if (!anyIds && !tbvHere) {
                storage.bricks().markEmpty(brick);
                ++st.bricksCleared;
            }
        }
    }

    /// A box of opaque voxels from v (not yet used this frame): the longest opaque run along x through it
    /// (both ways, at most kMaxGrow each side), grown along y while the whole run is opaque. Its voxels are
    /// marked used so that they start no other box. Drawn shrunk by the camera's slack (O keeps the
    /// objects' conversion slack already: its voxels lie inside by that margin).
    template <class InsideObject>
    void drawFusedBox(const GridGeometry2& grid, Storage& storage, const ViewWedge& wedge, OcclusionBuffer2D& image,
                      const IVec2& v, std::uint32_t stamp, InsideObject& insideObject, BrickTraversalStats2D& st) {
        const IVec2 res = grid.resolution();
        IVec2 lo = v, hi = v; // inclusive
        brick_rows::opaqueRun(storage, std::uint32_t(v.y), res.x, v.x, kMaxGrow, lo.x, hi.x);
        auto rowOpaque = [&](std::int32_t y) { return brick_rows::allOpaque(storage, std::uint32_t(y), lo.x, hi.x); };
        while (hi.y + 1 < res.y && hi.y - v.y < kMaxGrow && rowOpaque(hi.y + 1)) ++hi.y;
        while (lo.y > 0 && v.y - lo.y < kMaxGrow && rowOpaque(lo.y - 1)) --lo.y;
        storage.markUsedBox(lo, hi, stamp);
        // A box inside one box object repeats that object, which the caller draws when it classifies it.
        if (insideObject(grid.linearIndex(v), lo, hi)) return;
        image.draw(Box<2>{Vec2(lo), Vec2(hi + 1)}, wedge.slack());
        ++st.fusedBoxes;
    }

    static constexpr std::int32_t kMaxGrow = 64;
    std::vector<BrickNode<2>> m_stack;
};

} // namespace rgvc
