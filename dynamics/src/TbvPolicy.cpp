// Culler<D>::Impl, the temporal bounding volumes (seed 004 §4.1; Sudarsky and Gotsman): how long a
// hidden object's TBV may live (buildTbv), the scene update of each frame before the traversal
// (updateScene: PVS members re-placed, the others given a TBV, expired TBVs renewed, the camera-jump
// check, the hysteresis against reveal/re-hide cycles), and taking an object back out of T when the
// traversal meets its TBV (reveal, revealDuringTraversal).
#include "CullerImpl.hpp"

#include "TbvVoxelTests.hpp"
#include "rgvc/grid/BrickRows.hpp"
#include "rgvc/grid/ConservativeRaster.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace rgvc {

/// Builds the TBV of an object placed at p now: a disc (2D) or cube (3D) around its bounding ball,
/// grown by maxSpeed per frame of validity. The validity is the longest that keeps the region, for
/// boundary TBVs, clear of every camera's voxel (§4.1; several with cullViews), capped by tbvMaxFrames
/// and tbvMaxGrowth. False if not even one frame fits, or if the object already reaches outside the grid.
/// The region may reach past the grid's bounds: T clips it there, and without the promise that objects
/// stay in the grid (CullerOptions::objectsStayInGrid) its parts beyond are tested by every view
/// (revealFaceTbvs). (Before, such a region had to fit inside the grid: objects near the bounds were
/// renewed every few frames or placed every frame; README, "Scene classes", has what that cost.)
template <int D>
bool Culler<D>::Impl::buildTbv(const Record& r, const Placement& p, bool cameraKnown, std::span<const IVec<D>> cameras,
                               TbvRegion<D>& region, std::uint64_t& expiry) const {
    if (p.outsideGrid) return false;
    const Ball<D> b = boundingBall<D>(p.local);
    double room = INFINITY;
    // Past a face whose beyond was in view when last tested, a TBV would be tested there every frame (and,
    // in view, revealed): it stays inside that face, as every TBV did before (faceOpen). A choice of cost
    // only: a TBV past any face is sound (revealFaceTbvs).
    if (!options.objectsStayInGrid)
        for (int a = 0; a < D; ++a) {
            if (faceOpen[std::size_t(2 * a)]) room = std::min(room, b.center[a]);
            if (faceOpen[std::size_t(2 * a + 1)]) room = std::min(room, double(grid.resolution()[a]) - b.center[a]);
        }
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
            // Its TBV out of T, but the object still in `hidden`: a renewal keeps it there (no set's
            // swap-remove and insert, each a write to another object's slot).
            dropTbv(slot);
            const Placement* p = fetch(slot, st);
            if (p == nullptr) {
                leaveState(slot);
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
                placeTbv(slot, *p, region, expiry);
                r.fruitless = 0; // it stayed hidden for a whole validity
                ++st.tbvsRenewed;
            } else {
                leaveState(slot);
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

namespace {

/// revealFaceTbvs: tiles per lateral axis of a face's slab that is not hidden as a whole, when the face
/// has more than kFaceTilesFrom TBVs.
constexpr int kFaceTiles = 4;
constexpr std::size_t kFaceTilesFrom = 16;
/// revealFaceTbvs: frames between the tests of a face without TBVs past it that was open at its last
/// test (faceOpen, CullerImpl.hpp): whether it has closed since.
constexpr std::uint64_t kFaceReprobeFrames = 16;

/// Clips a box [voxel units] to the part beyond face f (axis f / 2) and within the grid's sides that come
/// before f (within[c]: bit 0 the low side of axis c, bit 1 the high). False when nothing is left.
template <int D> bool clipBeyondFace(Box<D>& b, int f, const int (&within)[D], const IVec<D>& res) {
    const int a = f >> 1;
    if (f & 1) b.min[a] = std::max(b.min[a], double(res[a]));
    else b.max[a] = std::min(b.max[a], 0.0);
    for (int c = 0; c < D; ++c) {
        if (within[c] & 1) b.min[c] = std::max(b.min[c], 0.0);
        if (within[c] & 2) b.max[c] = std::min(b.max[c], double(res[c]));
    }
    for (int c = 0; c < D; ++c)
        if (!(b.min[c] <= b.max[c])) return false;
    return true;
}

/// Whether a box [voxel units] lies within the grid's bounds on every axis but a.
template <int D> bool laterallyWithin(const Box<D>& box, int a, const IVec<D>& res) {
    for (int c = 0; c < D; ++c)
        if (c != a && !(box.min[c] >= 0 && box.max[c] <= double(res[c]))) return false;
    return true;
}

/// Whether face f's layer of voxels is all opaque. Reads the layer's rows along x (axis 0) a word of 8
/// voxels at a time (BrickRows.hpp): all of each row when f's axis is not x, one voxel of each when it is;
/// stops at the first open voxel.
template <int D> bool faceLayerOpaque(int f, const GridGeometry<D>& grid, const DenseStorage<D>& storage) {
    const int a = f >> 1;
    const IVec<D> res = grid.resolution();
    IVec<D> v(0);
    v[a] = (f & 1) ? res[a] - 1 : 0;
    while (true) {
        const std::uint32_t row = std::uint32_t(grid.linearIndex(v) / VoxelKey(res[0]));
        if (a == 0 ? !storage.opaque(grid.linearIndex(v)) : !brick_rows::allOpaque(storage, row, 0, res[0] - 1)) return false;
        int b = 1;
        while (b < D && (b == a || v[b] == res[b] - 1)) {
            if (b != a) v[b] = 0;
            ++b;
        }
        if (b == D) return true;
        ++v[b];
    }
}

/// A visible slab of face f cut into kFaceTiles tiles per lateral axis, each tested once; a part is then
/// tested only where it meets a visible tile. The 3D city's floor is hidden by its ground but for the
/// streets' ends, where a pixel shows both (the image's edge is not exact), and its 200 TBVs' parts cost a
/// fifth of the frame when each was tested. A face with few TBVs (kFaceTilesFrom) is not cut: one tile,
/// all of it visible.
template <int D> class FaceTiles {
public:
    template <class Visible>
    FaceTiles(const Box<D>& slab, int a, bool tiled, Visible&& visible, CullStats& st)
        : m_slab(slab), m_count(!tiled ? 0 : D == 2 ? kFaceTiles : kFaceTiles * kFaceTiles) {
        for (int c = 0; c < D; ++c)
            if (c != a) m_lateral[m_nl++] = c;
        double step[D];
        for (int c = 0; c < D; ++c) {
            step[c] = (slab.max[c] - slab.min[c]) / kFaceTiles;
            m_invStep[c] = step[c] > 0 ? 1 / step[c] : 0.0;
        }
        for (int t = 0; t < m_count; ++t) {
            Box<D> tile = slab;
            for (int l = 0, u = t; l < m_nl; ++l, u /= kFaceTiles) {
                const int c = m_lateral[l], i = u % kFaceTiles;
                tile.min[c] = slab.min[c] + step[c] * i;
                tile.max[c] = i == kFaceTiles - 1 ? slab.max[c] : slab.min[c] + step[c] * (i + 1);
            }
            ++st.faceTbvTests;
            m_seen[t] = visible(tile);
        }
    }
    /// Open when some tile is in view: a slab whose tiles all hide is as good as hidden.
    bool anySeen() const { return m_count == 0 || std::any_of(m_seen, m_seen + m_count, [](bool b) { return b; }); }
    /// Whether a part (in the slab) meets a visible tile: its closed box against the closed tiles, so a
    /// part on a tile's edge meets both, and an index off by a rounding takes in a neighbour too.
    bool meetsSeen(const Box<D>& part) const {
        if (m_count == 0) return true;
        int t0[kNl], t1[kNl];
        for (int l = 0; l < m_nl; ++l) {
            const int c = m_lateral[l];
            // (Clamped in double, then truncated: the part lies in the slab, so the values are about
            // 0..kFaceTiles.)
            const double u0 = (part.min[c] - m_slab.min[c]) * m_invStep[c] - 1e-9;
            const double u1 = (part.max[c] - m_slab.min[c]) * m_invStep[c] + 1e-9;
            t0[l] = int(std::clamp(u0, 0.0, double(kFaceTiles - 1)));
            t1[l] = int(std::clamp(u1, 0.0, double(kFaceTiles - 1)));
        }
        if constexpr (D == 2) {
            for (int u = t0[0]; u <= t1[0]; ++u)
                if (m_seen[u]) return true;
        } else {
            for (int v = t0[1]; v <= t1[1]; ++v)
                for (int u = t0[0]; u <= t1[0]; ++u)
                    if (m_seen[v * kFaceTiles + u]) return true;
        }
        return false;
    }

private:
    static constexpr int kNl = D > 1 ? D - 1 : 1;
    Box<D> m_slab;
    int m_lateral[kNl] = {}, m_nl = 0, m_count;
    double m_invStep[D] = {};
    bool m_seen[kFaceTiles * kFaceTiles] = {};
};

} // namespace

/// Why the parts beyond the faces suffice (FaceTbvs.hpp). Let x be a visible point of a hidden object and c
/// the camera, in the grid and outside the TBV's region R (a disc or cube, in its bounding box B; T stores
/// the in-grid voxels of its boundary). The open segment from c to x meets no occluder's interior, and it
/// enters R at a point y before x (c is not in R). If y lies in the closed grid, so does the segment up to y
/// (the grid is convex), and the traversal reveals the TBV where that segment crosses the boundary T stores,
/// as for an object in the grid (TbvRegion.hpp). Otherwise y lies strictly beyond some faces of the grid (so
/// B reaches past them, and faceTbvs holds it there); let f be the first of them in the order below. Then y
/// lies in f's part of B, the points of B beyond f and within the grid's bounds on the sides that come before
/// f (a box), and in f's slab (the same for the grid's side, grown laterally by the reach of the faces that
/// come after). y is in the view (a point of a view ray, as x is), and no ray through y's pixel can have
/// entered an occluder before y (the segment to y is part of the segment to x): the view's touch test holds
/// for both boxes, and the image cannot hide either (an image hides a box only if every pixel of it is
/// covered nearer than the box's nearest point, and y's pixel is not covered nearer than y). So the slab's
/// test fails, the part's test fails, and the TBV is met. A slab with many TBVs is tested in tiles first, and
/// a part only where it meets a visible tile: y's tile is one of them, visible for the same reason. Both
/// boxes are grown by the camera's slack, as objects are (classify). Without an image (the per-voxel
/// traversals, a frame of CullerOptions::adaptiveImage without it, no occlusion) the view's test alone
/// decides, which reveals more, never less. A face whose layer of voxels is all opaque needs no test for what
/// lies within its bounds (below, where it is checked).
/// The order: any order is sound. In 3D the faces of the axis nearest the camera's up come last, so that
/// the floor's part holds only what lies under the grid's floor (the 3D city's movers on their ground slab:
/// every TBV reaches past the floor, whose slab, with the sides' margins, was visible past the streets'
/// ends).
template <int D>
template <class S>
void Culler<D>::Impl::revealFaceTbvs(ViewScratch<S>& vs, const typename Traits::View& view, CullStats& st) {
    if (options.objectsStayInGrid) return;
    std::vector<ObjectSlot>& met = vs.faceMet;
    met.clear();
    const IVec<D> res = grid.resolution();
    const double slack = view.slack();
    auto* image = vs.imageActive ? &vs.traversalImage : nullptr;
    // 2D: the walk's angular image is final (its objects revealed here are classified after): the tests
    // read it a block of bins at a time (a face's slab spans most of the view), once one is needed.
    bool frozen = false;
    auto visible = [&](const Box<D>& box) {
        const Vec<D> lo = box.min - slack, hi = box.max + slack;
        if (!view.touchesBox(lo, hi)) return false;
        if (image == nullptr) return true;
        if constexpr (D == 2)
            if (!std::exchange(frozen, true)) image->freeze();
        return !image->hidden(Shape<D>(Box<D>{lo, hi}), 0.0);
    };
    int order[D];
    for (int a = 0; a < D; ++a) order[a] = a;
    if constexpr (D == 3) {
        const Vec3 up = glm::abs(view.trueUp());
        const int last = up.x >= up.y && up.x >= up.z ? 0 : up.y >= up.z ? 1 : 2;
        std::rotate(order + last, order + last + 1, order + D);
    }
    // A face whose layer of voxels is all opaque hides what lies beyond it within its bounds: the segment
    // from the camera (a voxel or more inside the grid, in no opaque voxel: leaveOpaqueTbvVoxels) to such a
    // point crosses the face's plane within its bounds, in the closed box of an opaque voxel, which lies in
    // an object's interior (O holds the voxels inside an object by its conversion slack); a point on the plane
    // itself lies in that interior. A ground under the whole grid is such a layer (the 3D city, the game
    // world): its TBVs' parts, all within the floor's bounds, need no test.
    const bool cameraClear = leaveOpaqueTbvVoxels<D>(view.apex(), slack, grid, storage);
    // within[b]: the sides of axis b that come before the face at hand (bit 0 low, bit 1 high).
    int within[D] = {};
    for (int k = 0; k < 2 * D; ++k) {
        const int a = order[k >> 1], f = 2 * a + (k & 1);
        const typename FaceTbvs<D>::Face& face = faceTbvs.face(f);
        // A face without TBVs past it is tested only to learn whether an open one has closed (cull() only).
        bool probe = !face.slots.empty();
        if constexpr (!ViewScratch<S>::kShared)
            probe = probe || (faceOpen[std::size_t(f)] && frameIndex % kFaceReprobeFrames == 0);
        if (probe) {
            // The slab (at least a voxel deep: a face without TBVs has no reach, and its slab tells what
            // lies beyond).
            Box<D> slab;
            for (int c = 0; c < D; ++c) {
                slab.min[c] = -std::max(faceTbvs.face(2 * c).reach, 1.0);
                slab.max[c] = double(res[c]) + std::max(faceTbvs.face(2 * c + 1).reach, 1.0);
            }
            const bool opaqueLayer = cameraClear && faceLayerOpaque<D>(f, grid, storage);
            ++st.faceTbvTests;
            bool open = clipBeyondFace<D>(slab, f, within, res) && !(opaqueLayer && laterallyWithin<D>(slab, a, res)) &&
                        visible(slab);
            if (open) {
                const FaceTiles<D> tiles(slab, a, face.slots.size() > kFaceTilesFrom, visible, st);
                open = tiles.anySeen();
                for (std::size_t i = 0; i < face.slots.size(); ++i) {
                    Box<D> part = face.boxes[i];
                    if (!clipBeyondFace<D>(part, f, within, res)) continue; // all of it beyond an earlier face
                    if (opaqueLayer && laterallyWithin<D>(part, a, res)) continue;
                    if (!tiles.meetsSeen(part)) continue;
                    ++st.faceTbvTests;
                    if (visible(part)) met.push_back(face.slots[i]);
                }
            }
            if constexpr (!ViewScratch<S>::kShared) faceOpen[std::size_t(f)] = open;
        }
        within[a] |= 1 << (k & 1);
    }
    if (met.empty()) return;
    // (A TBV reaching past two faces may be met twice; met, it is no longer hidden.)
    std::sort(met.begin(), met.end());
    met.erase(std::unique(met.begin(), met.end()), met.end());
    for (const ObjectSlot slot : met)
        if (records[slot].state == State::Hidden) tbvMet(vs, slot, st);
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
template void Culler<2>::Impl::revealFaceTbvs(Culler<2>::Impl::MainScratch&, const ViewWedge&, CullStats&);
template void Culler<2>::Impl::revealFaceTbvs(Culler<2>::Impl::SharedScratch&, const ViewWedge&, CullStats&);
template void Culler<3>::Impl::revealFaceTbvs(Culler<3>::Impl::MainScratch&, const ViewFrustum&, CullStats&);
template void Culler<3>::Impl::revealFaceTbvs(Culler<3>::Impl::SharedScratch&, const ViewFrustum&, CullStats&);

} // namespace rgvc
