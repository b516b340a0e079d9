// Culler<D>::Impl, CullerOptions::hierarchical: the 3D brick-tree walk with its occlusion image
// (traverseBricks, over BrickTraversal3D.hpp; the 2D walk is BrickPass2D.cpp) and the per-object verdict
// both walks give (classify, finishWalk).
#include "CullerImpl.hpp"
#include "TbvVoxelTests.hpp"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <numbers>
#include <variant>

namespace rgvc {

/// CullerOptions::hierarchical: spheres smaller than this many pixels across are not drawn into the
/// traversal's image (OcclusionBuffer3D::spans; see classify).
constexpr double kMinTraversalOccluderPixels = 16;
/// The brick walk reads a stale brick of T as it stands (a superset of its TBVs' voxels) when its list
/// holds more TBVs than this, and rebuilds it otherwise (TbvMatrix<3>::brickBits). callgrind, classes over
/// 16 frames: 8 and 16 measured the same (the 100k room −4.1 %, room 10k −2.2 %, paper −1.2 %, the
/// others unchanged); 32 gave back a third of room 10k's gain, 64 all of it; 0 (never a rebuild) cost
/// the 1k room 10 % and the game world 5 % (short lists' stale bits then cost more tests than rebuilds).
constexpr std::uint32_t kRebuildUpTo = 16;

/// The hierarchical traversal's verdict on an object held in O and I (or parked), once per frame:
/// in the PVS unless its bounds miss the view or the occlusion image hides it; a visible object is
/// drawn into the image (shrunk by its conversion slack and the camera's), so it hides what follows.
/// Sound whatever the order: every pixel depth in the image is a true bound when it is written.
template <int D>
template <class S, class View>
void Culler<D>::Impl::classify(ViewScratch<S>& vs, ObjectSlot slot, const View& view, bool inCone) {
    if (vs.classifiedStamp[slot] == vs.stamp) return;
    vs.classifiedStamp[slot] = vs.stamp;
    const Record& r = records[slot];
    if (r.state != State::Tracked && r.state != State::Static) {
        addToPvs(vs, slot); // parked: no placement to test
        return;
    }
    const double slack = grid.conversionSlack(r.at.worldMagnitude) + view.slack();
    const Box<D> b = r.at.localBounds;
    if constexpr (D == 3) {
        // Met in a brick inside the cone (onBrickIds' inCone): the object is listed there because its
        // bounds, grown by the conversion slack and 1e-6 voxel, touch a voxel of the brick's part in the
        // grid (BrickObjects::boxOf: every brick of its box holds such a voxel), a point of the cone. So
        // only the far limit is tested (touchesBox is withinFar and touchesCone); an object that misses
        // the cone by less than 1e-6 voxel may be kept, which is sound. The cone test was 3 % of the
        // clusters' instructions, for objects met in bricks away from the view's edges.
        if (inCone ? !view.withinFar(b.min - slack, b.max + slack) : !view.touchesBox(b.min - slack, b.max + slack)) return;
    } else {
        if (!view.touchesBox(b.min - slack, b.max + slack)) return;
    }
    if constexpr (D == 3) {
        const double nearest = vs.imageActive ? vs.traversalImage.nearestDistance(r.at.local, slack) : 0.0;
        if (vs.imageActive && vs.traversalImage.hidden(r.at.local, slack, nearest)) {
            ++vs.result.stats.imageHidden;
            return;
        }

        addToPvs(vs, slot);
        // (CullerOptions::adaptiveImage: a mesh in view keeps the image on next frame.)
        if (r.at.occludes && r.at.template localIs<MeshSolid>()) vs.meshInView = true;
        // Drawn when it spans enough pixels: a smaller occluder hides little of a brick (the refinement
        // pass draws it). Spheres from 16 pixels across: spheres-3d.json took 8.7 ms per frame with a
        // threshold of 4 pixels, 7.5 ms with 16, 4.3 with 32 (|PVS| 192, 199, 210), the clusters scene of
        // rgvc_bench_classes 17.0, 10.4 and 8.5 ms. Boxes from 4: boxes tile (walls of unit boxes,
        // floors, buildings side by side), and the seams between them fuse only if both are drawn
        // (test_brick_traversal's rooms of unit boxes seen at 138 degrees let an object through at 16).
        // Polytopes (oriented boxes, hulls) are level geometry like boxes, and drawn from 4 pixels too.
        const bool tiles = r.at.template localIs<Box<D>>();
        bool polytope = false;
        if constexpr (D == 3) polytope = r.at.template localIs<ConvexPolytope>();
        const double minPixels = tiles || polytope ? 4.0 : kMinTraversalOccluderPixels;
        if (vs.imageActive && r.at.occludes && vs.traversalImage.spans(boundingBall<D>(r.at.local).radius, nearest, minPixels))
        {
            vs.traversalImage.draw(*r.at.occluder(), slack);
            vs.drawnStamp[slot] = vs.stamp; // the refinement pass's image inherits it (refineWithBuffer)
        }
    } else {
        // 2D: the angular image (OcclusionBuffer2D). Drawing is cheap in 1D: every visible occluder is
        // drawn, whatever its size.
        if (vs.imageActive && vs.traversalImage.hidden(r.at.local, slack)) {
            ++vs.result.stats.imageHidden;
            return;
        }
        addToPvs(vs, slot);
        if (vs.imageActive && r.at.occludes) vs.traversalImage.draw(*r.at.occluder(), slack);
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
/// Objects reaching outside the grid are classified too: the image's facts hold for any point. With
/// `occlusion`, T's voxels that O fills are left out while the camera is a voxel or more inside the grid
/// (leaveOpaqueTbvVoxels, TbvVoxelTests.hpp, which shows that the TBV is revealed all the same).

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
    // CullerOptions::adaptiveImage (cull() only): a frame in the schedule's skip walks without the image.
    constexpr bool shared = ViewScratch<S>::kShared;
    const bool adaptive = !shared && options.adaptiveImage && options.occlusion;
    const bool skipImage = adaptive && imageSkip > 0;
    vs.meshInView = false;
    if (skipImage) --imageSkip;
    st.imageSkipped = skipImage;
    vs.imageActive = !skipImage && options.occlusion && image.begin(view, rows);
    st.tbvLookupsSkipped = tbvs.liveRegions() == 0;
    const bool leaveOpaque = options.occlusion && leaveOpaqueTbvVoxels<3>(view.apex(), view.slack(), grid, *vs.storage);
    const BrickTraversalStats3D ts = vs.brickTraversal.run(
        grid, *vs.storage, view, vs.imageActive ? &image : nullptr, vs.stamp,
        [&](const IVec3& brick) { return tbvs.mayHoldBrick(brick); },
        [&](VoxelKey key, const IVec3&) {
            // An object is met in every voxel of it that the walk reads (a hundred for a sphere 5 voxels
            // across) and classified at the first: the stamp is checked here, without the call.
            storage.forEachId(key, [&](ObjectSlot slot) {
                if (vs.classifiedStamp[slot] != vs.stamp) classify(vs, slot, view);
            });
        },
        [&](const IVec3& brick, const std::uint64_t visited[8], const std::uint64_t opaque[8]) {
            revealScratch.clear();
            // The visited voxels that hold some TBV (less O's, leaveOpaque), then those of them the image
            // does not hide (a row's run of them tested as one box first: hidden as a whole, none of them
            // can reveal anything).
            std::uint64_t held[8];
            const bool lists = tbvs.hasBrickLists();
            if (lists && !tbvs.brickBits(brick, held, kRebuildUpTo)) return;
            bool any = false;
            for (int z = 0; z < 8; ++z) {
                const std::uint64_t open = leaveOpaque ? visited[z] & ~opaque[z] : visited[z];
                any = (held[z] = lists ? held[z] & open : open) != 0 || any;
            }
            if (!any) return;
            if (lists) {
                // A voxel found visible takes its TBVs for revealing at once, and the voxels only they
                // hold leave the tests (where movers crowd, most of a brick's held voxels are visible,
                // and each cost a footprint test: clusters and the game world of rgvc_bench_classes).
                // Its slots and parts are read once, at the brick's first visible voxel.
                bool partsRead = false;
                auto onVisible = [&](const IVec3& local, std::uint64_t h[8]) {
                    auto& slots = vs.brickTbvSlots;
                    auto& parts = vs.brickTbvParts;
                    auto& taken = vs.brickTbvTaken;
                    if (!partsRead) {
                        tbvs.brickParts(brick, slots, parts);
                        tbvs.settleBrick(brick, parts);
                        taken.assign(slots.size(), 0);
                        partsRead = true;
                    }
                    const std::uint64_t bit = std::uint64_t(1) << (local.x + 8 * local.y);
                    std::uint64_t rest[8] = {0, 0, 0, 0, 0, 0, 0, 0}; // what the slots not taken hold
                    for (std::size_t i = 0; i < slots.size(); ++i) {
                        if (taken[i] == 0 && (parts[i][std::size_t(local.z)] & bit) != 0) {
                            taken[i] = 1;
                            revealScratch.push_back(slots[i]);
                        }
                        if (taken[i] != 0) continue;
                        for (std::size_t z = 0; z < 8; ++z) rest[z] |= parts[i][z];
                    }
                    for (std::size_t z = 0; z < 8; ++z) h[z] &= rest[z];
                };
                if (vs.imageActive && !clearHiddenVoxels<3>(image, brick, view.slack(), held, st.tbvImageTests, onVisible) && revealScratch.empty())
                    return;
                // Without the image every visited voxel that holds a TBV reveals it; with it, what the
                // callback left (nothing, unless a voxel's slots were all taken already).
                bool left = false;
                for (int z = 0; z < 8; ++z) left = left || held[z] != 0;
                if (left) {
                    tbvs.collectInBrick(brick, held, revealScratch);
                    std::sort(revealScratch.begin(), revealScratch.end());
                    revealScratch.erase(std::unique(revealScratch.begin(), revealScratch.end()), revealScratch.end());
                }
            } else {
                // A Shell TBV exists: its voxel lists answer voxel by voxel.
                if (vs.imageActive && !clearHiddenVoxels<3>(image, brick, view.slack(), held, st.tbvImageTests, [](const IVec3&, std::uint64_t*) {})) return;
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
            if (boxObjectHolds(seed, lo, hi)) return true;
            // The pair is classified (tested, and drawn when visible) now, where the fused box would
            // have been drawn: before the brick's other objects, which it may hide.
            ObjectSlot pair[2];
            if (!boxPairHolds(seed, lo, hi, image, view.slack(), pair)) return false;
            classify(vs, pair[0], view);
            classify(vs, pair[1], view);
            return true;
        },
        [&](const IVec3& brick, bool inCone) {
            // The brick's objects (BrickObjects.hpp: a superset of those with ids in it), met once per
            // brick instead of once per voxel in view; the stamp checked here, as for the ids.
            const std::vector<ObjectSlot>& list = brickObjects.at(brick);
#ifndef NDEBUG
            // The lists' invariant: every id in a voxel of the brick is listed in it (where I is kept).
            if (idsInI) {
            const IVec3 o = brick * BrickPyramid<3>::kBrickSize, hi = glm::min(o + BrickPyramid<3>::kBrickSize, grid.resolution());
            for (std::int32_t z = o.z; z < hi.z; ++z)
                for (std::int32_t y = o.y; y < hi.y; ++y)
                    for (std::int32_t x = o.x; x < hi.x; ++x)
                        vs.storage->forEachId(grid.linearIndex(IVec3{x, y, z}), [&](ObjectSlot s) {
                            assert(std::find(list.begin(), list.end(), s) != list.end());
                            (void)s;
                        });
            }
#endif
            for (std::size_t i = 0; i < list.size(); ++i)
                if (vs.classifiedStamp[list[i]] != vs.stamp) classify(vs, list[i], view, inCone);
            return !list.empty();
        },
        adaptive && vs.imageActive);
    if (adaptive && vs.imageActive) {
        // Paid when a mesh occluder was in view (a mesh occludes only through O's fused boxes, which the
        // refinement pass's fresh image does not draw: OcclusionBuffer3D::draw), or the image covered all
        // of its pixels (a closed room, a street between buildings: a turn of the camera stays behind
        // the same walls, whatever the count says in a room with few objects outside), or it hid at least
        // one occupied brick in view for every eight the walk read or covered nine tenths of its pixels,
        // with at most kFusedPerHiddenBrick fused boxes of O drawn per brick it hid. That bound is what a
        // cloud of spheres large enough to fill voxels of O fails: it covers most of the image and hides
        // a brick in four, but each sphere's interior is a fused box of its own (400 a frame in
        // scenes/spheres-3d.json), and the buffer's pass hides the same objects from a fresh image of the
        // spheres. Walls of boxes fuse into few large boxes, or none (a box object is drawn as itself).
        // Measured per frame with the image on every frame, fused boxes / (hidden bricks + 1) in frames
        // that left a pixel open: where the image pays at most 0.68 (the 3D cities, the game world; 0 in
        // the large world; rooms, the maze and streets cover every pixel); scenes/spheres-3d.json 14-139
        // (median 26), the paper's spheres 1.5-49 (median 10), scenes/paper-walk-3d.json 1.1-66
        // (median 12.5). Walking spheres-3d without the image cost 46 % fewer instructions at the same
        // |PVS|; with the bound, 33 % fewer (the image is still tried every 1-8 frames); the paper's
        // scene and paper-walk-3d 2-4 % fewer (a bound of 3: 0.7 % and 0). Cost only: a skipped image
        // is never a miss.
        constexpr double kFusedPerHiddenBrick = 1.5;
        const bool cheap = double(ts.fusedBoxes) <= kFusedPerHiddenBrick * double(ts.bricksSkipped + 1);
        bool pays = vs.meshInView || (cheap && 8 * ts.bricksSkipped >= ts.bricksVisited);
        if (!pays) { // (the count of covered pixels is a pass over the image: only when it decides)
            const std::size_t pixels = std::size_t(image.rows()) * std::size_t(image.cols()), covered = image.coveredPixels();
            pays = covered == pixels || (cheap && 10 * covered >= 9 * pixels);
        }
        if (pays) {
            imageBackoff = 1;
        } else {
            imageSkip = imageBackoff;
            imageBackoff = std::min<std::uint32_t>(2 * imageBackoff, 8);
        }
    }
    finishWalk(vs, view, st, ts.voxelsVisited, ts.nodesVisited, ts.nodesEmpty, ts.nodesHidden, ts.bricksVisited, ts.fusedBoxes);
}

/// After either walk: objects reaching outside the grid (the image's facts hold for any point), the
/// objects revealed during the walk (cull(): classified now that the image is complete; see
/// revealDuringTraversal), and the walk's statistics.
template <int D>
template <class S>
void Culler<D>::Impl::finishWalk(ViewScratch<S>& vs, const typename Traits::View& view, CullStats& st, std::uint64_t voxels,
                                 std::uint64_t nodes, std::uint64_t empty, std::uint64_t hiddenNodes, std::uint64_t bricks,
                                 std::uint64_t fused) {
    for (std::size_t i = 0; i < outside.size(); ++i) classify(vs, outside[i], view);
    revealFaceTbvs(vs, view, st); // (their objects join revealedPending in cull())
    for (std::size_t i = 0; i < vs.revealedPending.size(); ++i) classify(vs, vs.revealedPending[i], view);
    vs.revealedPending.clear();
    st.layers = 0;
    st.voxelsVisited = voxels;
    st.nodesVisited = nodes;
    st.nodesEmpty = empty;
    st.nodesHidden = hiddenNodes;
    st.bricksVisited = bricks;
    st.occludersExtended = fused;
    st.occlusionSkipped = !vs.imageActive || vs.traversalImage.stats().occludersDrawn == 0;
    vs.imageKept = vs.imageActive;
    if (vs.imageKept) vs.imageView = view;
    vs.imageActive = false;
}

template <int D> bool Culler<D>::Impl::boxObjectHolds(VoxelKey seed, const IVec<D>& lo, const IVec<D>& hi) const {
    // A box object holding the voxels lo..hi holds the seed (one of them) and lo: its id is in the seed's
    // set, and it is listed in lo's brick (without I, forEachObjectAt reads that list).
    bool inside = false;
    forEachObjectAt(seed, lo, [&](ObjectSlot slot) {
        const Record& r = records[slot];
        const auto* b = std::get_if<Box<D>>(&r.at.local);
        if (inside || b == nullptr || (r.state != State::Tracked && r.state != State::Static)) return;
        inside = glm::all(glm::lessThanEqual(b->min, Vec<D>(lo))) && glm::all(glm::greaterThanEqual(b->max, Vec<D>(hi + 1)));
    });
    return inside;
}

/// Whether the voxel box lo..hi (inclusive), a fused box of opaque voxels, lies in the union of two box
/// objects that the walk draws itself, each large in the image: their own images, and the seam fusion
/// of the pixels they share (OcclusionSeams3D.cpp), already cover what the fused box would. The common
/// case is a building on a ground slab: the box grown from the building's voxels takes in the ground's
/// row beneath it, is inside neither object, and was drawn on top of both every frame (a quarter of the
/// 3D city's instructions, 6 % of the game world's). Boxes spanning three or more objects (walls of unit
/// boxes) are drawn as before. Leaving a box undrawn is sound whatever the answer: the image only holds
/// less; the answer only decides where the image may lose a little depth at a seam (the 3D city's
/// |PVS| / |visible| rose from 1.04 to 1.08: the fused box's depth at a building's base was a little
/// better). The pair's slots go to `slots`: the caller classifies them at once, where the fused box was
/// drawn, before the brick's other objects are classified.
template <int D>
bool Culler<D>::Impl::boxPairHolds(VoxelKey seed, const IVec<D>& lo, const IVec<D>& hi, const OcclusionBuffer3D& image,
                                   double slack, ObjectSlot (&slots)[2]) const
    requires(D == 3) {
    const Box<3> f{Vec3(lo), Vec3(hi + 1)};
    const Box<3>* pair[2] = {nullptr, nullptr};
    int n = 0;
    bool other = false; // a third object meets the box, or one that is not a plain drawn box
    forEachObjectAt(seed, lo, [&](ObjectSlot slot) {
        if (other) return;
        const Record& r = records[slot];
        const auto* b = std::get_if<Box<3>>(&r.at.local);
        const Box<3> bounds = r.at.localBounds;
        bool meets = true;
        for (int a = 0; a < 3; ++a) meets = meets && bounds.min[a] < f.max[a] && f.min[a] < bounds.max[a];
        if (!meets) return;
        // Drawn by classify when visible: a box occluder (no inset: its drawn model is the box itself),
        // tracked or static, and large: twice classify's 4 pixels, so that it is a seam box too.
        const bool drawn = b != nullptr && r.at.occludes && !r.at.inset && (r.state == State::Tracked || r.state == State::Static) &&
                           image.spans(boundingBall<3>(r.at.local).radius, image.nearestDistance(r.at.local, slack), 8.0);
        if (!drawn || n == 2) {
            other = true;
            return;
        }
        slots[n] = slot;
        pair[n++] = b;
    });
    if (other || n != 2) return false;
    // f in A u B: every part of f outside A (cut off axis by axis) lies in B.
    const Box<3>& a = *pair[0];
    const Box<3>& b = *pair[1];
    auto inB = [&](const Box<3>& p) { return glm::all(glm::lessThanEqual(b.min, p.min)) && glm::all(glm::lessThanEqual(p.max, b.max)); };
    Box<3> rest = f;
    for (int k = 0; k < 3; ++k) {
        if (rest.min[k] < a.min[k]) {
            Box<3> part = rest;
            part.max[k] = std::min(rest.max[k], a.min[k]);
            if (!inB(part)) return false;
            rest.min[k] = std::min(rest.max[k], a.min[k]);
        }
        if (rest.max[k] > a.max[k]) {
            Box<3> part = rest;
            part.min[k] = std::max(rest.min[k], a.max[k]);
            if (!inB(part)) return false;
            rest.max[k] = std::max(rest.min[k], a.max[k]);
        }
        if (!(rest.min[k] < rest.max[k])) return true; // nothing of f left inside A's slab: all in B
    }
    return true; // what is left lies in A
}

template void Culler<2>::Impl::classify(ObjectSlot);
template void Culler<3>::Impl::classify(ObjectSlot);
template bool Culler<2>::Impl::boxObjectHolds(VoxelKey, const IVec<2>&, const IVec<2>&) const;
template bool Culler<3>::Impl::boxObjectHolds(VoxelKey, const IVec<3>&, const IVec<3>&) const;
// (the 2D walk, BrickPass2D.cpp, classifies and finishes with these)
template void Culler<2>::Impl::classify(Culler<2>::Impl::MainScratch&, ObjectSlot, const ViewWedge&, bool);
template void Culler<2>::Impl::classify(Culler<2>::Impl::SharedScratch&, ObjectSlot, const ViewWedge&, bool);
template void Culler<2>::Impl::finishWalk(Culler<2>::Impl::MainScratch&, const ViewWedge&, CullStats&, std::uint64_t,
                                          std::uint64_t, std::uint64_t, std::uint64_t, std::uint64_t, std::uint64_t);
template void Culler<2>::Impl::finishWalk(Culler<2>::Impl::SharedScratch&, const ViewWedge&, CullStats&, std::uint64_t,
                                          std::uint64_t, std::uint64_t, std::uint64_t, std::uint64_t, std::uint64_t);
template void Culler<3>::Impl::traverseBricks(Culler<3>::Impl::MainScratch&, const ViewFrustum&, CullStats&);
template void Culler<3>::Impl::traverseBricks(Culler<3>::Impl::SharedScratch&, const ViewFrustum&, CullStats&);

} // namespace rgvc
