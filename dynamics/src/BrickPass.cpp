// Culler<D>::Impl, CullerOptions::hierarchical (3D): the brick-tree walk with its occlusion image
// (traverseBricks, over BrickTraversal3D.hpp) and the per-object verdict it gives (classify). classify is
// instantiated for 2D too (revealDuringTraversal names it), where it only adds the object to the PVS.
#include "CullerImpl.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <variant>

namespace rgvc {

/// CullerOptions::hierarchical: spheres smaller than this many pixels across are not drawn into the
/// traversal's image (OcclusionBuffer3D::spans; see classify).
constexpr double kMinTraversalOccluderPixels = 16;

/// The hierarchical traversal's verdict on an object held in O and I (or parked), once per frame:
/// in the PVS unless its bounds miss the view or the occlusion image hides it; a visible object is
/// drawn into the image (shrunk by its conversion slack and the camera's), so it hides what follows.
/// Sound whatever the order: every pixel depth in the image is a true bound when it is written.
template <int D>
template <class S, class View>
void Culler<D>::Impl::classify(ViewScratch<S>& vs, ObjectSlot slot, const View& view) {
    if (vs.classifiedStamp[slot] == vs.stamp) return;
    vs.classifiedStamp[slot] = vs.stamp;
    const Record& r = records[slot];
    if (r.state != State::Tracked && r.state != State::Static) {
        addToPvs(vs, slot); // parked: no placement to test
        return;
    }
    const double slack = grid.conversionSlack(r.at.worldMagnitude) + view.slack();
    const Box<D> b = r.at.localBounds;
    if (!view.touchesBox(b.min - slack, b.max + slack)) return;
    if constexpr (D == 3) {
        const double nearest = vs.imageActive ? vs.traversalImage.nearestDistance(r.at.local, slack) : 0.0;
        if (vs.imageActive && vs.traversalImage.hidden(r.at.local, slack, nearest)) {
            ++vs.result.stats.imageHidden;
            return;
        }

        addToPvs(vs, slot);
        // Drawn when it spans enough pixels: a smaller occluder hides little of a brick (the refinement
        // pass draws it). Spheres from 16 pixels across: spheres-3d.json took 8.7 ms per frame with a
        // threshold of 4 pixels, 7.5 ms with 16, 4.3 with 32 (|PVS| 192, 199, 210), the clusters scene of
        // rgvc_bench_classes 17.0, 10.4 and 8.5 ms. Boxes from 4: boxes tile (walls of unit boxes,
        // floors, buildings side by side), and the seams between them fuse only if both are drawn
        // (test_brick_traversal's rooms of unit boxes seen at 138 degrees let an object through at 16).
        // Polytopes (oriented boxes, hulls) are level geometry like boxes, and drawn from 4 pixels too.
        const bool tiles = std::holds_alternative<Box<D>>(r.at.local);
        bool polytope = false;
        if constexpr (D == 3) polytope = std::holds_alternative<ConvexPolytope>(r.at.local);
        const double minPixels = tiles || polytope ? 4.0 : kMinTraversalOccluderPixels;
        if (vs.imageActive && r.at.occludes && vs.traversalImage.spans(boundingBall<D>(r.at.local).radius, nearest, minPixels))
            vs.traversalImage.draw(*r.at.occluder(), slack);
    } else {
        addToPvs(vs, slot);
    }
}

template <int D> void Culler<D>::Impl::classify(ObjectSlot slot) { classify(main, slot, *main.view); }

/// CullerOptions::hierarchical: the brick-tree walk (BrickTraversal3D.hpp) with the occlusion image.
/// Ids met in visited voxels are classified (classify); a TBV met in a visited voxel that the image
/// does not hide is revealed. Why that reveals every TBV it must: a ray from the camera (outside every
/// boundary TBV, see updateScene) to a visible point x of a hidden object enters the TBV's region
/// through a point y of its boundary before x; y is visible (its open segment is part of x's), so the
/// voxel of y (a boundary voxel: T holds it) touches the view, lies in a brick the tree visits (every
/// node holding y is occupied, touches the view and is not hidden), and is not hidden in the image.
/// Objects reaching outside the grid are classified too: the image's facts hold for any point.
template <int D>
template <class S>
void Culler<D>::Impl::traverseBricks(ViewScratch<S>& vs, const ViewFrustum& view, CullStats& st) requires(D == 3) {
    int rows = options.traversalImageRows;
    if (rows == 0) {
        const double want = std::ceil(2 * view.tanHalfHeight() / kAutoImagePixelTan);
        rows = int(std::clamp(want, double(kAutoImageMinRows), double(kAutoImageMaxRows)));
    }
    OcclusionBuffer3D& image = vs.traversalImage;
    std::vector<ObjectSlot>& revealScratch = vs.revealScratch;
    vs.imageActive = options.occlusion && image.begin(view, rows);
    st.tbvLookupsSkipped = tbvs.liveRegions() == 0;
    const BrickTraversalStats3D ts = vs.brickTraversal.run(
        grid, *vs.storage, view, vs.imageActive ? &image : nullptr, vs.stamp,
        [&](const IVec3& brick) { return tbvs.mayHoldBrick(brick); },
        [&](VoxelKey key, const IVec3&) { storage.forEachId(key, [&](ObjectSlot slot) { classify(vs, slot, view); }); },
        [&](const IVec3& brick, const std::uint64_t visited[8]) {
            revealScratch.clear();
            // The visited voxels that hold some TBV, then those of them the image does not hide (a row's
            // run of them tested as one box first: hidden as a whole, none of them can reveal anything).
            std::uint64_t held[8];
            const bool lists = tbvs.hasBrickLists();
            if (lists && !tbvs.brickBits(brick, held)) return;
            bool any = false;
            for (int z = 0; z < 8; ++z) any = (held[z] = lists ? held[z] & visited[z] : visited[z]) != 0 || any;
            if (!any) return;
            if (vs.imageActive) {
                const IVec3 o = brick * 8;
                for (int z = 0; z < 8; ++z)
                    for (int y = 0; y < 8; ++y) {
                        const std::uint32_t row = std::uint32_t(held[z] >> (8 * y)) & 0xFFu;
                        if (row == 0) continue;
                        const int first = std::countr_zero(row), last = 31 - std::countl_zero(row);
                        const Vec3 at(o + IVec3{0, y, z});
                        const double s = view.slack();
                        bool hide = image.hidden(Box<3>{at + Vec3(first, 0, 0), at + Vec3(last + 1, 1, 1)}, s);
                        std::uint32_t keep = hide ? 0u : row;
                        if (!hide && first != last)
                            for (std::uint32_t bits = row; bits != 0; bits &= bits - 1) {
                                const int x = std::countr_zero(bits);
                                if (image.hidden(Box<3>{at + Vec3(x, 0, 0), at + Vec3(x + 1, 1, 1)}, s))
                                    keep &= ~(1u << x);
                            }
                        held[z] = (held[z] & ~(std::uint64_t(0xFF) << (8 * y))) | (std::uint64_t(keep) << (8 * y));
                    }
            }
            if (lists) {
                tbvs.collectInBrick(brick, held, revealScratch);
            } else { // a Shell TBV exists: its voxel lists answer voxel by voxel
                for (int z = 0; z < 8; ++z)
                    for (std::uint64_t bits = held[z]; bits != 0; bits &= bits - 1) {
                        const int b = std::countr_zero(bits);
                        tbvs.collectAt(brick * 8 + IVec3{b & 7, b >> 3, z}, revealScratch);
                    }
                std::sort(revealScratch.begin(), revealScratch.end());
                revealScratch.erase(std::unique(revealScratch.begin(), revealScratch.end()), revealScratch.end());
            }
            // Revealing erases from the lists: collected first, revealed after.
            for (ObjectSlot slot : revealScratch)
                if (records[slot].state == State::Hidden) tbvMet(vs, slot, st);
        },
        [&](VoxelKey seed, const IVec3& lo, const IVec3& hi) {
            // A box object holding the seed that contains the whole fused box (its voxel range lo..hi).
            bool inside = false;
            storage.forEachId(seed, [&](ObjectSlot slot) {
                const Record& r = records[slot];
                const auto* b = std::get_if<Box<3>>(&r.at.local);
                if (inside || b == nullptr || (r.state != State::Tracked && r.state != State::Static)) return;
                inside = glm::all(glm::lessThanEqual(b->min, Vec3(lo))) && glm::all(glm::greaterThanEqual(b->max, Vec3(hi + 1)));
            });
            return inside;
        });
    for (std::size_t i = 0; i < outside.size(); ++i) classify(vs, outside[i], view);
    st.layers = 0;
    st.voxelsVisited = ts.voxelsVisited;
    st.nodesVisited = ts.nodesVisited;
    st.nodesEmpty = ts.nodesEmpty;
    st.nodesHidden = ts.nodesHidden;
    st.bricksVisited = ts.bricksVisited;
    st.occludersExtended = ts.fusedBoxes;
    st.occlusionSkipped = !vs.imageActive || image.stats().occludersDrawn == 0;
    vs.imageActive = false;
}

template void Culler<2>::Impl::classify(ObjectSlot);
template void Culler<3>::Impl::classify(ObjectSlot);
template void Culler<3>::Impl::traverseBricks(Culler<3>::Impl::MainScratch&, const ViewFrustum&, CullStats&);
template void Culler<3>::Impl::traverseBricks(Culler<3>::Impl::SharedScratch&, const ViewFrustum&, CullStats&);

} // namespace rgvc
