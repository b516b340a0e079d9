// Culler<D>::Impl, the temporal bounding volumes (seed 004 §4.1; Sudarsky and Gotsman): how long a
// hidden object's TBV may live (buildTbv), the scene update of each frame before the traversal
// (updateScene: PVS members re-placed, the others given a TBV, expired TBVs renewed, the camera-jump
// check, the hysteresis against reveal/re-hide cycles), and taking an object back out of T when the
// traversal meets its TBV (reveal, revealDuringTraversal).
#include "CullerImpl.hpp"

#include "rgvc/grid/ConservativeRaster.hpp"

#include <algorithm>
#include <cmath>

namespace rgvc {

/// Builds the TBV of an object placed at p now: a disc (2D) or cube (3D) around its bounding ball,
/// grown by maxSpeed per frame of validity. The validity is the longest that keeps the region inside
/// the grid (so the object stays in it; not needed under objectsStayInGrid) and, for boundary TBVs,
/// clear of every camera's voxel (§4.1; several with cullViews),
/// capped by tbvMaxFrames and tbvMaxGrowth. False if not even one frame fits.
template <int D>
bool Culler<D>::Impl::buildTbv(const Record& r, const Placement& p, bool cameraKnown, std::span<const IVec<D>> cameras,
                               TbvRegion<D>& region, std::uint64_t& expiry) const {
    if (p.outsideGrid) return false;
    const Ball<D> b = boundingBall<D>(p.local);
    double room = INFINITY;
    // Without the application's promise the object could leave the grid, where T cannot see it: the
    // region must fit inside. With it, T clips the region at the bounds (CullerOptions::objectsStayInGrid).
    if (!options.objectsStayInGrid)
        for (int a = 0; a < D; ++a)
            room = std::min(room, std::min(b.center[a], double(grid.resolution()[a]) - b.center[a]));
    // Strictly clear of the camera voxel: tbvTouches() must say no, with its slack and some rounding.
    if (cameraKnown && tbvBoundaryOnly(options.tbvDiscretization))
        for (const IVec<D>& camera : cameras) room = std::min(room, tbvGap(b.center, camera) - 4 * kConservativeSlack);
    // Rounding of world-to-voxel conversions, now and at every later placement.
    const double slack = 2 * grid.conversionSlack(p.worldMagnitude) + kConservativeSlack;
    const double base = b.radius + slack;
    if (!(base < room)) return false;
    const double speed = stepOf(r); // > 0: objects without a speed are static
    region.centre = b.center;
    // (The 1e-9 keeps an exact quotient, 4 voxels / 1 voxel per frame, from rounding down to 3 frames.)
    const double growth = options.tbvMaxGrowth / double(1u << r.growthLevel);
    double frames = std::min<double>(options.tbvMaxFrames, std::max(1.0, std::floor(growth / speed + 1e-9)));
    // Up to a quarter shorter, by a hash of the slot: objects hidden in the same frame (all of them, in
    // the first frames) would otherwise all expire in the same frame, again and again, and every
    // renewal would land in a few frames (a p90 several times the median, measured).
    const std::uint32_t hash = (std::uint32_t(&r - records.data()) * 2654435761u) >> 16;
    frames -= std::floor(frames * 0.25 * double(hash) / 65536.0);
    frames = std::min(frames, std::floor((room - base) / speed));
    if (!(frames >= 1)) return false;
    region.radius = base + speed * frames;
    expiry = frameIndex + std::uint64_t(frames) + 1; // covers this frame and the next `frames`
    return true;
}

/// A hidden object found (partly) outside the grid although the application promised it stays in.
template <int D> bool Culler<D>::Impl::brokePromise(const Placement& p) const {
    return options.objectsStayInGrid && p.outsideGrid;
}

/// [Voxels per frame] how far the object may move in one frame, rounded up a little.
template <int D> double Culler<D>::Impl::stepOf(const Record& r) const {
    return r.maxSpeed / grid.voxelSize() * (1 + 1e-12);
}

/// Moves a hidden object back into O and I (revealed, expired without a new TBV, camera jump).
/// Returns false if it had to be parked.
template <int D> bool Culler<D>::Impl::reveal(ObjectSlot slot, CullStats& st) {
    TbvRegion<D> old = records[slot].tbv;
    // A TBV expiring this frame covered up to the frame before (renewal has not run yet): one more step.
    if (records[slot].tbvExpiry == frameIndex) old.radius += stepOf(records[slot]);
    detach(slot);
    const Placement* p = fetch(slot, st);
    if (p == nullptr) {
        enter(slot, State::Parked);
        return false;
    }
    if (!ballInside(boundingBall<D>(p->local), old) || brokePromise(*p)) ++st.speedViolations;
    attachTracked(slot, *p);
    return true;
}

/// Validities lived out unrevealed, in a row, after which a TBV's growth doubles back (Record::growthLevel).
/// Why not one: an object that stays near an occluder (a mover outside a room's wall) alternated between
/// two growths, the larger revealed through the wall each time it came back and the smaller living out its
/// validity: a reveal, a rasterization and a new TBV every other validity. After two, the 2D room revealed
/// 16 % and created 11 % fewer TBVs a frame over 200 frames (and renewed 6 % more), and its frames took
/// 6.5–7.7 % less time (the paper's spheres 3–5 %, the 100k room 4 %, the others within their noise,
/// |PVS| the same); four measured the same as two.
constexpr int kCleanRenewalsToGrow = 2;

/// Scene discretization of one frame (§4.1), before the traversal. cameraIn: new TBVs may be made (every
/// camera of the frame is a perspective one inside the grid); cameras: the voxels of the frame's
/// perspective cameras inside the grid, whose traversals rely on §4.1's camera condition.
template <int D> void Culler<D>::Impl::updateScene(bool cameraIn, std::span<const IVec<D>> cameras, CullStats& st) {
    if (!options.temporalBoundingVolumes) { // the baseline: every moving object re-placed every frame
        for (std::size_t i = 0; i < tracked.size();) {
            const ObjectSlot slot = tracked[i];
            const Placement* p = fetch(slot, st);
            if (p == nullptr) {
                detach(slot);
                enter(slot, State::Parked);
                continue;
            }
            moveRasterized(slot, *p);
            ++i;
        }
    } else {
        const bool boundary = tbvBoundaryOnly(options.tbvDiscretization);
        // §4.1's camera condition: a camera voxel that moved by more than one voxel on some axis may
        // have landed inside a TBV without crossing its boundary. Check them all (the only O(hidden)
        // step, and only on such frames). With several views, each camera against the same view's last
        // one; a change in the number of views counts as a jump.
        if (boundary && !cameras.empty() && !hidden.empty()) {
            bool jump = !havePrevCamera || prevCameras.size() != cameras.size();
            for (std::size_t c = 0; c < cameras.size() && !jump; ++c)
                for (int a = 0; a < D; ++a) jump = jump || std::abs(cameras[c][a] - prevCameras[c][a]) > 1;
            if (jump) {
                st.cameraJump = true;
                for (std::size_t i = 0; i < hidden.size();) {
                    const ObjectSlot slot = hidden[i];
                    bool touches = false;
                    for (const IVec<D>& camera : cameras) touches = touches || tbvTouches<D>(records[slot].tbv, camera);
                    if (!touches) {
                        ++i;
                        continue;
                    }
                    reveal(slot, st); // leaves `hidden`: index i now holds another slot
                    ++st.tbvsRevealedByJump;
                }
            }
        }
        // Last frame's tracked objects: PVS members are re-placed, the others get a TBV. (Their records
        // fetched a few ahead, as the renewals' below.)
        for (std::size_t i = 0; i < tracked.size();) {
            if (i + kRecordsAhead < tracked.size()) prefetchRecord(tracked[i + kRecordsAhead]);
            const ObjectSlot slot = tracked[i];
            Record& r = records[slot];
            const Placement* p = fetch(slot, st);
            if (p == nullptr) {
                detach(slot);
                enter(slot, State::Parked);
                continue;
            }
            TbvRegion<D> region;
            std::uint64_t expiry = 0;
            const bool inPvs = r.lastPvsFrame + 1 == frameIndex;
            if (inPvs) r.fruitless = 0;
            // An object whose TBV the traversal revealed last frame, but which was not in the PVS, sits
            // where its TBV reaches visible space while it stays hidden (just behind an occluder's edge,
            // or in view behind other objects): a new TBV would be revealed again at once, costing T
            // writes, a rasterization and a query every frame. It stays in O and I for 2, 4, ..., 32
            // frames instead (costing what the no-TBV baseline costs for it), doubling while it repeats.
            // Its next TBVs are also smaller (half the growth per such reveal, down to 1/16): a large TBV
            // pays off far from the view (fewer renewals) and is revealed at once near it. Two TBVs in a
            // row that live out their validity unrevealed double the growth back (kCleanRenewalsToGrow).
            if (!inPvs && cameraIn && r.revealedFrame + 1 == frameIndex) {
                r.fruitless = std::uint8_t(std::min(r.fruitless + 1, 5));
                r.holdUntil = frameIndex + (std::uint64_t(1) << r.fruitless);
                r.growthLevel = std::uint8_t(std::min(r.growthLevel + 1, 4));
                r.cleanRenewals = 0;
            }
            if (!inPvs && cameraIn && frameIndex < r.holdUntil) {
                ++st.tbvsHeld;
            } else if (!inPvs && cameraIn) {
                if (buildTbv(r, *p, true, cameras, region, expiry)) {
                    detach(slot);
                    attachHidden(slot, *p, region, expiry);
                    ++st.tbvsCreated;
                    continue;
                }
                ++st.tbvsRefused;
            }
            moveRasterized(slot, *p);
            ++i;
        }
        // Expired TBVs: a new validity around the current placement (or back into O and I).
        auto& bucket = expiring[frameIndex % expiring.size()];
        // Each renewal reads and rewrites its object's record (its placement, its TBV), at a slot of no
        // order: with many hidden movers (the 100k room: 85 MB of records, 9,600 renewals a frame) the
        // wait for its first line was nine tenths of this loop's own time in perf. The record a few
        // renewals ahead is fetched meanwhile (a hint only: nothing is read from it here).
        for (std::size_t e = 0; e < bucket.size(); ++e) {
            if (e + kRecordsAhead < bucket.size()) {
                prefetchRecord(bucket[e + kRecordsAhead].first);
                tbvs.prefetch(bucket[e + kRecordsAhead].first); // its box and node indices in T
            }
            const auto [slot, generation] = bucket[e];
            Record& r = records[slot];
            if (!r.alive || r.state != State::Hidden || r.tbvGeneration != generation || r.tbvExpiry != frameIndex)
                continue;
            const TbvRegion<D> old = r.tbv;
            detach(slot);
            const Placement* p = fetch(slot, st);
            if (p == nullptr) {
                enter(slot, State::Parked);
                continue;
            }
            // The TBV covered up to the frame before this one: one more step is allowed.
            TbvRegion<D> grown = old;
            grown.radius += stepOf(r);
            if (!ballInside(boundingBall<D>(p->local), grown) || brokePromise(*p)) ++st.speedViolations;
            TbvRegion<D> region;
            std::uint64_t expiry = 0;
            // Unrevealed for kCleanRenewalsToGrow validities in a row: grow larger again.
            if (r.growthLevel > 0 && ++r.cleanRenewals >= kCleanRenewalsToGrow) {
                --r.growthLevel;
                r.cleanRenewals = 0;
            }
            if (buildTbv(r, *p, !cameras.empty(), cameras, region, expiry)) {
                attachHidden(slot, *p, region, expiry);
                r.fruitless = 0; // it stayed hidden for a whole validity
                ++st.tbvsRenewed;
            } else {
                attachTracked(slot, *p);
                ++st.tbvsRefused;
            }
        }
        bucket.clear();
    }
    // Objects whose placement query failed before: ask again.
    for (std::size_t i = 0; i < parked.size();) {
        const ObjectSlot slot = parked[i];
        const Placement* p = fetch(slot, st);
        if (p == nullptr) {
            ++i;
            continue;
        }
        detach(slot);
        attachTracked(slot, *p);
    }
}

/// A TBV met in a visited, non-occluded voxel: the object goes back into O and I now, and is
/// classified in this same frame. The traversal reaches its voxels from here on; those it already
/// visited (this layer and earlier ones) are checked now, with the same rule (visited, not in H).
template <int D> void Culler<D>::Impl::revealDuringTraversal(ObjectSlot slot, CullStats& st) {
    ++st.tbvsRevealed;
    records[slot].revealedFrame = frameIndex;
    if (!reveal(slot, st)) {
        addToPvs(main, slot);
        return;
    }
    if (options.hierarchical) {
        // Classified against the view and the image once the walk is done (traverseBricks), when the image
        // holds every occluder in view: a TBV reaching into a room through its wall is met before the
        // wall's far part is drawn, and the object behind the wall would be let in. (The walk meets the
        // object's voxels in bricks it has yet to visit, and classifies it then: once per frame either way.)
        main.revealedPending.push_back(slot);
        return;
    }
    const Placement& p = records[slot].at;
    bool seen = false;
    forEachTouchedVoxel<D>(
        p.local, grid.resolution(),
        [&](const IVec<D>& v) {
            const VoxelKey key = grid.linearIndex(v);
            seen = seen || (storage.visited(key, frame) && !storage.occluded(key, frame));
        },
        grid.conversionSlack(p.worldMagnitude));
    if (seen) addToPvs(main, slot);
}

template bool Culler<2>::Impl::buildTbv(const Record&, const Placement&, bool, std::span<const IVec<2>>,
                                        TbvRegion<2>&, std::uint64_t&) const;
template bool Culler<2>::Impl::brokePromise(const Placement&) const;
template double Culler<2>::Impl::stepOf(const Record&) const;
template bool Culler<2>::Impl::reveal(ObjectSlot, CullStats&);
template void Culler<2>::Impl::updateScene(bool, std::span<const IVec<2>>, CullStats&);
template void Culler<2>::Impl::revealDuringTraversal(ObjectSlot, CullStats&);
template bool Culler<3>::Impl::buildTbv(const Record&, const Placement&, bool, std::span<const IVec<3>>,
                                        TbvRegion<3>&, std::uint64_t&) const;
template bool Culler<3>::Impl::brokePromise(const Placement&) const;
template double Culler<3>::Impl::stepOf(const Record&) const;
template bool Culler<3>::Impl::reveal(ObjectSlot, CullStats&);
template void Culler<3>::Impl::updateScene(bool, std::span<const IVec<3>>, CullStats&);
template void Culler<3>::Impl::revealDuringTraversal(ObjectSlot, CullStats&);

} // namespace rgvc
