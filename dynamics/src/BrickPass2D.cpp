// Culler<D>::Impl, CullerOptions::hierarchical in 2D: the quadtree walk with its angular occlusion image
// (traverseBricks over BrickTraversal2D.hpp). The verdict on the objects it meets (classify) and the end of
// the walk (finishWalk) are BrickPass.cpp's, shared with the 3D walk; the tests of its TBV voxels are
// TbvVoxelTests.hpp's, shared too.
#include "CullerImpl.hpp"
#include "TbvVoxelTests.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>

namespace rgvc {

/// CullerOptions::traversalImageBins = 0: bins of this width [radians] over the view, within the limits.
/// A closed room's corner, seen from up to ~60 voxels, spans ~1/60 rad: a bin straddling the corner is
/// covered when both its rays pass through the corner's voxels (shared by both walls' fused boxes), so
/// bins well under that width (0.002 rad: 786 bins at 90 degrees, 3,142 for the full circle) close it.
constexpr double kAutoBinWidth = 0.002;
constexpr int kAutoMinBins = 64;

/// CullerOptions::hierarchical, 2D: the quadtree walk (BrickTraversal2D.hpp) with the angular image.
/// Ids met in visited voxels are classified; a TBV met in a visited voxel that the image does not hide
/// is revealed, by the argument of the 3D walk's (BrickPass.cpp; a ray to a visible point of a hidden object
/// enters the TBV's disc through a visible point of its boundary ring, whose voxel T holds; T's voxels
/// that O fills are left out on the same conditions).
template <int D>
template <class S>
void Culler<D>::Impl::traverseBricks(ViewScratch<S>& vs, const ViewWedge& view, CullStats& st) requires(D == 2) {
    int bins = options.traversalImageBins;
    if (bins == 0) {
        const double want = std::ceil((view.isFullCircle() ? 2 * std::numbers::pi : view.fov()) / kAutoBinWidth);
        bins = int(std::clamp(want, double(kAutoMinBins), double(OcclusionBuffer2D::kMaxBins)));
    }
    OcclusionBuffer2D& image = vs.traversalImage;
    vs.imageActive = options.occlusion && image.begin(view, bins);
    st.tbvLookupsSkipped = tbvs.liveRegions() == 0;
    const bool leaveOpaque = options.occlusion && leaveOpaqueTbvVoxels<2>(view.apex(), view.slack(), grid, *vs.storage); // (the 3D walk's)
    const BrickTraversalStats2D ts = vs.brickTraversal.run(
        grid, *vs.storage, view, vs.imageActive ? &image : nullptr, vs.stamp,
        [&](const IVec2& brick) { return tbvs.mayHoldTile(brick); },
        [&](VoxelKey key, const IVec2&) {
            storage.forEachId(key, [&](ObjectSlot slot) { // (the stamp checked here, as in 3D)
                if (vs.classifiedStamp[slot] != vs.stamp) classify(vs, slot, view);
            });
        },
        [&](const IVec2& brick, const std::uint8_t inView[8], auto&& opaqueRow) {
            // The counts first (a row of the brick's tile in one read), then the image, then the tile's
            // list: next to a wall, the walk reads bricks whose outer voxels are crossed by many TBV
            // rings, all of them hidden. (Voxel by voxel, the counts' addresses were 5 % of the 2D random
            // scenes' instructions.)
            static_assert(BrickPyramid<2>::kBrickSize == 8 && BrickPyramid<2>::kBrickSize == 1 << TbvMatrix<2>::kTileShift,
                          "a brick is one of T's tiles, of 8 x 8 voxels");
            const IVec2 o = brick * BrickPyramid<2>::kBrickSize;
            // The visited voxels that may hold some TBV (less O's, leaveOpaque), bit x + 8 y.
            auto heldNow = [&] {
                std::uint64_t h = 0;
                for (int row = 0; row < BrickPyramid<2>::kBrickSize; ++row) {
                    std::uint32_t bits = inView[row] & tbvs.mayHoldRow(brick, row);
                    if (bits != 0 && leaveOpaque) bits &= ~opaqueRow(row); // (a row with voxels in view: in the grid)
                    h |= std::uint64_t(bits & 0xFFu) << (8 * row);
                }
                return h;
            };
            std::uint64_t held = heldNow();
            if (held == 0) return;
            // A voxel not hidden reveals its TBVs now (revealing erases them from T: collected first,
            // revealed after); voxels that only they held leave the later tests.
            auto revealAt = [&](const IVec2& local, std::uint64_t* h) {
                vs.revealScratch.clear();
                tbvs.collectAt(o + local, vs.revealScratch);
                bool any = false;
                for (ObjectSlot slot : vs.revealScratch)
                    if (records[slot].state == State::Hidden) {
                        tbvMet(vs, slot, st);
                        any = true;
                    }
                *h &= ~(std::uint64_t(1) << (local.x + 8 * local.y));
                if (any) *h &= heldNow();
            };
            if (vs.imageActive) {
                // The held voxels along the brick's quadtree (clearHiddenVoxels), as the 3D walk does.
                clearHiddenVoxels<2>(image, brick, view.slack(), &held, st.tbvImageTests, revealAt);
            } else {
                while (held != 0) {
                    const int b = std::countr_zero(held);
                    revealAt(IVec2{b & 7, b >> 3}, &held);
                }
            }
        },
        [&](VoxelKey seed, const IVec2& lo, const IVec2& hi) { return boxObjectHolds(seed, lo, hi); });
    finishWalk(vs, view, st, ts.voxelsVisited, ts.nodesVisited, ts.nodesEmpty, ts.nodesHidden, ts.bricksVisited, ts.fusedBoxes);
}

template void Culler<2>::Impl::traverseBricks(Culler<2>::Impl::MainScratch&, const ViewWedge&, CullStats&);
template void Culler<2>::Impl::traverseBricks(Culler<2>::Impl::SharedScratch&, const ViewWedge&, CullStats&);

} // namespace rgvc
