// Culler<D>: object bookkeeping (I and O) and the per-frame cull over the dense storage. The same code
// serves 2D and 3D; only the view region and the traversal differ (ViewWedge + FrustumTraversal2D,
// ViewFrustum + FrustumTraversal3D), chosen by CullerTraits.
#include "rgvc/dynamics/Culler.hpp"

#include "rgvc/grid/BrickTraversal3D.hpp"
#include "rgvc/grid/ConservativeRaster.hpp"
#include "rgvc/grid/FrustumTraversal2D.hpp"
#include "rgvc/grid/FrustumTraversal3D.hpp"
#include "rgvc/grid/OcclusionBuffer2D.hpp"
#include "rgvc/grid/OcclusionBuffer3D.hpp"
#include "rgvc/grid/RowFootprint.hpp"
#include "rgvc/grid/ViewFrustum.hpp"
#include "rgvc/grid/ViewWedge.hpp"
#include "rgvc/grid/VoxelStorage.hpp"

#include "SlotSet.hpp"

#include <algorithm>
#include <bit>
#include <chrono>
#include <exception>
#include <utility>
#include <new>
#include <unordered_map>

namespace rgvc {

const char* toString(Fallback f) {
    switch (f) {
    case Fallback::None: return "none";
    case Fallback::CameraOutsideGrid: return "camera_outside_grid";
    }
    return "unknown";
}

namespace {

template <int D> struct CullerTraits;

template <> struct CullerTraits<2> {
    using View = ViewWedge;
    using Buffer = OcclusionBuffer2D;
    static int bufferSize(const CullerOptions& o) { return o.occlusionBufferBins; }
    using Traversal = FrustumTraversal2D<DenseStorage<2>>;
    static void checkGrid(const GridGeometry2& grid) {
        for (int a = 0; a < 2; ++a)
            if (grid.resolution()[a] > kMaxShadowExtent)
                throw InvalidInput("grid.resolution", "at most " + std::to_string(kMaxShadowExtent) +
                                                          " voxels per axis in 2D, got " +
                                                          std::to_string(grid.resolution()[a]));
    }
    /// reportEveryVoxel: the 2D traversal reports every visited voxel not in H anyway.
    template <class OnVoxel>
    static void traverse(Traversal& t, const GridGeometry2& grid, DenseStorage<2>& storage, const View& view,
                         std::uint32_t stamp, const CullerOptions& options, bool /*reportEveryVoxel*/,
                         bool /*deferCaps*/, CullStats& st, OnVoxel&& onVoxel) {
        TraversalOptions2D topt;
        topt.occlusion = options.occlusion;
        topt.extension = options.occluderExtension;
        const TraversalStats2D ts = t.run(grid, storage, view, stamp, topt, onVoxel);
        st.layers = ts.layers;
        st.voxelsVisited = ts.voxelsVisited;
        st.voxelsOccluded = ts.voxelsOccluded;
        st.occludersExtended = ts.occludersExtended;
        st.occluderVoxels = ts.occluderVoxels;
        st.shadows = ts.shadows;
        st.voxelsMarkedOccluded = ts.voxelsMarkedOccluded;
        st.earlyTermination = ts.earlyTermination;
        st.occlusionSkipped = !ts.opaqueMet;
    }
};

template <> struct CullerTraits<3> {
    using View = ViewFrustum;
    using Buffer = OcclusionBuffer3D;
    static int bufferSize(const CullerOptions& o) { return o.occlusionBufferRows; }
    using Traversal = FrustumTraversal3D<DenseStorage<3>>;
    static void checkGrid(const GridGeometry3&) {}
    template <class OnVoxel>
    static void traverse(Traversal& t, const GridGeometry3& grid, DenseStorage<3>& storage, const View& view,
                         std::uint32_t stamp, const CullerOptions& options, bool reportEveryVoxel, bool deferCaps,
                         CullStats& st, OnVoxel&& onVoxel) {
        TraversalOptions3D topt;
        topt.deferCaps = deferCaps;
        topt.occlusion = options.occlusion;
        topt.exponentialCaps = options.occluderExtension;
        topt.reportEveryVoxel = reportEveryVoxel;
        const TraversalStats3D ts = t.run(grid, storage, view, stamp, topt, onVoxel);
        st.layers = ts.layers;
        st.voxelsVisited = ts.voxelsVisited;
        st.voxelsOccluded = ts.voxelsOccluded;
        st.occludersExtended = ts.opaqueVisited;
        st.occluderVoxels = ts.capVoxels;
        st.shadows = ts.capFaces;
        st.voxelsMarkedOccluded = ts.voxelsOccluded;
        st.earlyTermination = ts.earlyTermination;
        st.occlusionSkipped = ts.opaqueVisited == 0;
        st.capsDeferred = deferCaps;
        st.capsFromShell = ts.capsFromShell;
    }
};

} // namespace

/// CullerOptions::hierarchical: spheres smaller than this many pixels across are not drawn into the
/// traversal's image (OcclusionBuffer3D::spans; see classify).
constexpr double kMinTraversalOccluderPixels = 16;

template <int D> struct Culler<D>::Impl {
    using Traits = CullerTraits<D>;

    /// Where an object is held. Static: O and I for good (§4.5). Tracked: O and I at its current placement
    /// (last PVS, revealed, new, or refused a TBV). Hidden: only its TBV in T. Parked: its placement query
    /// failed; reported in every PVS until one succeeds. Detached: between two of these.
    enum class State : std::uint8_t { Static, Tracked, Hidden, Parked, Detached };

    /// A placement converted once: what rasterization, TBVs and the outside-grid test read.
    struct Placement {
        Shape<D> world;
        Shape<D> local;            // voxel units, as rasterized into I and O
        Box<D> localBounds;
        double worldMagnitude = 0; // largest |coordinate| of the world-unit bounds
        bool outsideGrid = false;  // partly or wholly outside: also tested against the view region
    };

    struct Record {
        ObjectId id = 0;
        Placement at;
        double maxSpeed = 0;
        State state = State::Detached;
        bool alive = false;
        std::uint64_t lastPvsFrame = 0; // frameIndex of the last PVS holding it
        std::uint64_t placedFrame = 0;  // frameIndex of its last successful placement query
        std::uint64_t failedFrame = 0;  // frameIndex of its last failed placement query
        // Hysteresis against reveal/re-hide cycles (see updateScene): the frame its TBV was last revealed
        // by the traversal, how many such reveals in a row found it hidden, and until when it stays in O and I.
        std::uint64_t revealedFrame = 0;
        std::uint64_t holdUntil = 0;
        std::uint8_t fruitless = 0;
        std::uint8_t growthLevel = 0;   // its TBVs grow by tbvMaxGrowth / 2^growthLevel (see updateScene)
        TbvRegion<D> tbv;
        std::uint64_t tbvExpiry = 0;    // first frame the TBV no longer covers
        std::uint32_t tbvGeneration = 0;
    };

    GridGeometry<D> grid;
    CullerOptions options;
    DenseStorage<D> storage;
    TbvMatrix<D> tbvs;
    typename Traits::Traversal traversal;
    std::vector<Record> records;
    std::vector<ObjectSlot> freeSlots;
    std::unordered_map<ObjectId, ObjectSlot> slotOf;
    std::vector<std::uint32_t> pvsStamp;    // per slot: frame stamp in which it was added to the PVS
    std::vector<std::uint32_t> statePos;    // per slot: position in tracked, hidden or parked
    std::vector<std::uint32_t> outsidePos;  // per slot: position in outside
    SlotSet tracked, hidden, parked, outside;
    // Expiry buckets: TBVs expiring at frame f wait in expiring[f % size] (a validity is at most
    // tbvMaxFrames, so a bucket never holds two different frames). Entries of TBVs revealed or
    // renewed meanwhile are recognised by their generation and dropped.
    std::vector<std::vector<std::pair<ObjectSlot, std::uint32_t>>> expiring;
    std::uint32_t frame = 0;         // stamp of the stamped matrices, 1..DenseStorage::kMaxStamp, then again
    std::uint64_t frameIndex = 0;    // cull() calls so far, never wraps
    bool havePrevCamera = false;
    IVec<D> prevCamera{0};
    CullResult result;

    // The current frame's placement source (null: the stored placements) and its first failure.
    const PlacementQuery<D>* query = nullptr;
    std::exception_ptr queryException;
    std::string invalidField, invalidWhat;
    std::uint64_t writes = 0;
    std::vector<ObjectSlot> revealScratch;
    Placement fetched; // the last placement a query returned
    const typename Traits::View* currentView = nullptr; // the frame's view, while cull() runs
    // CullerOptions::adaptiveCaps (3D): frames still to start without caps, and the next skip's length.
    std::uint32_t capsSkip = 0, capsBackoff = 1;
    // The grid PVS's slots in the order added, and the occlusion buffer that refines it (3D).
    std::vector<ObjectSlot> pvsSlots;
    struct BufferShape {
        Shape<D> shape; // voxel units
        double slack;   // conversion slack of the object and the camera
        ObjectSlot slot;
    };
    std::vector<std::pair<double, std::uint32_t>> bufferOrder; // (nearest distance, index in bufferShapes)
    std::vector<BufferShape> bufferShapes;
    typename Traits::Buffer occlusionBuffer;
    // CullerOptions::hierarchical (3D): the brick-tree walk, its occlusion image, and per slot the frame
    // stamp in which the object was classified (tested against the view and the image) by it.
    BrickTraversal3D<DenseStorage<3>> brickTraversal;
    OcclusionBuffer3D traversalImage;
    bool imageActive = false;
    std::vector<std::uint32_t> classifiedStamp;
    // Per slot: the footprint written into I and O while the object is there (Static, Tracked), empty
    // otherwise. A move rasterizes only its new placement; a removal takes out exactly what was put in.
    std::vector<RowFootprint> footprints;
    RowFootprint nextFootprint; // reused by every move (no allocation per update after warm-up)

    Impl(const GridGeometry<D>& g, const CullerOptions& o)
        : grid(g), options(o), storage(g), tbvs(g.resolution()), expiring(std::size_t(o.tbvMaxFrames) + 2) {
        if (options.tbvMaxGrowth == 0) options.tbvMaxGrowth = D == 2 ? 32.0 : 8.0;
    }

    // ---- placements and rasterization ------------------------------------------------------------

    Placement makePlacement(const Shape<D>& world) const {
        Placement p;
        p.world = world;
        const Box<D> wb = boundsOf<D>(world);
        for (int a = 0; a < D; ++a)
            p.worldMagnitude = std::max(p.worldMagnitude, std::max(std::abs(wb.min[a]), std::abs(wb.max[a])));
        p.local = toLocal<D>(world, grid);
        p.localBounds = boundsOf<D>(p.local);
        p.outsideGrid = extendsOutsideGrid<D>(p.local, grid.resolution());
        return p;
    }

    /// Puts the object at its stored placement into I and O (sign > 0), or takes it out (sign < 0).
    void rasterize(ObjectSlot slot, int sign) {
        RowFootprint& f = footprints[slot];
        if (sign > 0) {
            buildFootprint(records[slot].at, f);
            writes += f.write(storage, slot, +1);
        } else {
            writes += f.write(storage, slot, -1);
            f.release();
        }
    }

    void buildFootprint(const Placement& p, RowFootprint& f) const {
        // The slack covers the world-to-voxel rounding of the object's coordinates (and the grid's).
        f.build<D>(p.local, grid, grid.conversionSlack(p.worldMagnitude));
    }

    /// Moves a rasterized object by writing only the difference between its old (cached) and new
    /// footprints: a sphere that moves a fraction of a voxel changes a thin shell of its footprint, or
    /// nothing at all (profiling the moving-spheres benchmark showed remove-all/add-all updates, and then
    /// per-voxel footprint lists, as its largest costs).
    void moveRasterized(ObjectSlot slot, const Placement& p) {
        if (&p == &records[slot].at) return; // the stored placement: already rasterized
        buildFootprint(p, nextFootprint);
        writes += footprints[slot].moveTo(storage, slot, nextFootprint);
        records[slot].at = p;
        syncOutside(slot);
    }

    /// Objects held in O and I that reach outside the grid are also tested against the view region.
    void syncOutside(ObjectSlot slot) {
        const Record& r = records[slot];
        const bool want = r.alive && r.at.outsideGrid && (r.state == State::Tracked || r.state == State::Static);
        if (want != SlotSet::contains(slot, outsidePos)) {
            if (want) outside.insert(slot, outsidePos);
            else outside.erase(slot, outsidePos);
        }
    }

    // ---- object states ---------------------------------------------------------------------------

    SlotSet* setOf(State s) {
        switch (s) {
        case State::Tracked: return &tracked;
        case State::Hidden: return &hidden;
        case State::Parked: return &parked;
        default: return nullptr;
        }
    }

    void enter(ObjectSlot slot, State s) {
        records[slot].state = s;
        if (SlotSet* set = setOf(s)) set->insert(slot, statePos);
        syncOutside(slot);
    }

    /// Takes an object out of whatever holds it (O and I, T, or the parked list).
    void detach(ObjectSlot slot) {
        Record& r = records[slot];
        if (r.state == State::Tracked || r.state == State::Static) rasterize(slot, -1);
        if (r.state == State::Hidden) {
            writes += tbvs.erase(slot, r.tbv, options.tbvDiscretization);
            ++r.tbvGeneration; // its expiry entry, if any, is now stale
        }
        if (SlotSet* set = setOf(r.state)) set->erase(slot, statePos);
        r.state = State::Detached;
        syncOutside(slot);
    }

    void adopt(ObjectSlot slot, const Placement& p) {
        if (&p != &records[slot].at) records[slot].at = p;
    }

    void attachTracked(ObjectSlot slot, const Placement& p) {
        adopt(slot, p);
        rasterize(slot, +1);
        enter(slot, State::Tracked);
    }

    void attachHidden(ObjectSlot slot, const Placement& p, const TbvRegion<D>& region, std::uint64_t expiry) {
        Record& r = records[slot];
        adopt(slot, p);
        r.tbv = region;
        r.tbvExpiry = expiry;
        writes += tbvs.insert(slot, region, options.tbvDiscretization);
        if constexpr (D == 3) { // the brick tree must see the TBV (BrickPyramid: marking is eager)
            IVec3 lo, hi;
            if (tbvVoxelBox3D(region, grid.resolution(), lo, hi)) storage.bricks().markOccupied(lo, hi);
        }
        expiring[expiry % expiring.size()].emplace_back(slot, r.tbvGeneration);
        enter(slot, State::Hidden);
    }

    // ---- temporal bounding volumes (§4.1) --------------------------------------------------------

    /// Builds the TBV of an object placed at p now: a disc (2D) or cube (3D) around its bounding ball,
    /// grown by maxSpeed per frame of validity. The validity is the longest that keeps the region inside
    /// the grid (so the object stays in it; not needed under objectsStayInGrid) and, for boundary TBVs,
    /// clear of the camera's voxel (§4.1),
    /// capped by tbvMaxFrames and tbvMaxGrowth. False if not even one frame fits.
    bool buildTbv(const Record& r, const Placement& p, bool cameraKnown, const IVec<D>& camera, TbvRegion<D>& region,
                  std::uint64_t& expiry) const {
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
            room = std::min(room, tbvGap(b.center, camera) - 4 * kConservativeSlack);
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
    bool brokePromise(const Placement& p) const { return options.objectsStayInGrid && p.outsideGrid; }

    /// [Voxels per frame] how far the object may move in one frame, rounded up a little.
    double stepOf(const Record& r) const { return r.maxSpeed / grid.voxelSize() * (1 + 1e-12); }

    static bool ballInside(const Ball<D>& b, const TbvRegion<D>& r) {
        if constexpr (D == 2) {
            return std::sqrt(lengthSquared<2>(b.center - r.centre)) + b.radius <= r.radius;
        } else {
            for (int a = 0; a < 3; ++a)
                if (std::abs(b.center[a] - r.centre[a]) + b.radius > r.radius) return false;
            return true;
        }
    }

    /// The object's placement now, asking the application at most once per frame: the stored placement
    /// (no query, or asked already) or a fresh one, valid until the next fetch. Null when the query threw
    /// or returned an invalid shape: the failure is kept to be reported once the frame is done.
    const Placement* fetch(ObjectSlot slot, CullStats& st) {
        Record& r = records[slot];
        if (query == nullptr || r.placedFrame == frameIndex) return &r.at;
        if (r.failedFrame == frameIndex) return nullptr; // asked once this frame already
        ++st.placementQueries;
        try {
            Shape<D> s = (*query)(r.id);
            validateShape<D>(s, [&] { return "object " + std::to_string(r.id) + ".shape"; });
            fetched = makePlacement(s);
        } catch (const InvalidInput& e) {
            if (invalidField.empty() && !queryException) {
                invalidField = e.field();
                invalidWhat = std::string(e.what()).substr(e.field().size() + 2);
            }
            r.failedFrame = frameIndex;
            return nullptr;
        } catch (...) {
            if (invalidField.empty() && !queryException) queryException = std::current_exception();
            r.failedFrame = frameIndex;
            return nullptr;
        }
        r.placedFrame = frameIndex;
        return &fetched;
    }

    /// Moves a hidden object back into O and I (revealed, expired without a new TBV, camera jump).
    /// Returns false if it had to be parked.
    bool reveal(ObjectSlot slot, CullStats& st) {
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

    /// Scene discretization of one frame (§4.1), before the traversal.
    void updateScene(bool cameraIn, const IVec<D>& camera, CullStats& st) {
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
            // step, and only on such frames).
            if (boundary && cameraIn && !hidden.empty()) {
                bool jump = !havePrevCamera;
                for (int a = 0; a < D; ++a) jump = jump || std::abs(camera[a] - prevCamera[a]) > 1;
                if (jump) {
                    st.cameraJump = true;
                    for (std::size_t i = 0; i < hidden.size();) {
                        const ObjectSlot slot = hidden[i];
                        if (!tbvTouches<D>(records[slot].tbv, camera)) {
                            ++i;
                            continue;
                        }
                        reveal(slot, st); // leaves `hidden`: index i now holds another slot
                        ++st.tbvsRevealedByJump;
                    }
                }
            }
            // Last frame's tracked objects: PVS members are re-placed, the others get a TBV.
            for (std::size_t i = 0; i < tracked.size();) {
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
                // pays off far from the view (fewer renewals) and is revealed at once near it. A TBV that
                // lives out its validity unrevealed doubles the growth back.
                if (!inPvs && cameraIn && r.revealedFrame + 1 == frameIndex) {
                    r.fruitless = std::uint8_t(std::min(r.fruitless + 1, 5));
                    r.holdUntil = frameIndex + (std::uint64_t(1) << r.fruitless);
                    r.growthLevel = std::uint8_t(std::min(r.growthLevel + 1, 4));
                }
                if (!inPvs && cameraIn && frameIndex < r.holdUntil) {
                    ++st.tbvsHeld;
                } else if (!inPvs && cameraIn) {
                    if (buildTbv(r, *p, true, camera, region, expiry)) {
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
            for (const auto& [slot, generation] : bucket) {
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
                if (r.growthLevel > 0) --r.growthLevel; // unrevealed for a whole validity: grow larger again
                if (buildTbv(r, *p, cameraIn, camera, region, expiry)) {
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
    void revealDuringTraversal(ObjectSlot slot, CullStats& st) {
        ++st.tbvsRevealed;
        records[slot].revealedFrame = frameIndex;
        if (!reveal(slot, st)) {
            addToPvs(slot);
            return;
        }
        if (D == 3 && options.hierarchical) { // classified against the view and the image, now
            classify(slot);
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
        if (seen) addToPvs(slot);
    }

    /// The hierarchical traversal's verdict on an object held in O and I (or parked), once per frame:
    /// in the PVS unless its bounds miss the view or the occlusion image hides it; a visible object is
    /// drawn into the image (shrunk by its conversion slack and the camera's), so it hides what follows.
    /// Sound whatever the order: every pixel depth in the image is a true bound when it is written.
    template <class View> void classify(ObjectSlot slot, const View& view) {
        if (classifiedStamp[slot] == frame) return;
        classifiedStamp[slot] = frame;
        const Record& r = records[slot];
        if (r.state != State::Tracked && r.state != State::Static) {
            addToPvs(slot); // parked: no placement to test
            return;
        }
        const double slack = grid.conversionSlack(r.at.worldMagnitude) + view.slack();
        const Box<D> b = r.at.localBounds;
        if (!view.touchesBox(b.min - slack, b.max + slack)) return;
        if constexpr (D == 3) {
            if (imageActive && traversalImage.hidden(r.at.local, slack)) {
                ++result.stats.imageHidden;
                return;
            }

            addToPvs(slot);
            // Drawn when it spans enough pixels: a smaller occluder hides little of a brick (the refinement
            // pass draws it). Spheres from 16 pixels across: spheres-3d.json took 8.7 ms per frame with a
            // threshold of 4 pixels, 7.5 ms with 16, 4.3 with 32 (|PVS| 192, 199, 210), the clusters scene of
            // rgvc_bench_classes 17.0, 10.4 and 8.5 ms. Boxes from 4: boxes tile (walls of unit boxes,
            // floors, buildings side by side), and the seams between them fuse only if both are drawn
            // (test_brick_traversal's rooms of unit boxes seen at 138 degrees let an object through at 16).
            const double minPixels = std::holds_alternative<Box<D>>(r.at.local) ? 4.0 : kMinTraversalOccluderPixels;
            if (imageActive && traversalImage.spans(boundingBall<D>(r.at.local).radius,
                                                    traversalImage.nearestDistance(r.at.local, 0), minPixels))
                traversalImage.draw(r.at.local, slack);
        } else {
            addToPvs(slot);
        }
    }
    void classify(ObjectSlot slot) { classify(slot, *currentView); }

    void addToPvs(ObjectSlot slot) {
        if (pvsStamp[slot] == frame) return;
        pvsStamp[slot] = frame;
        records[slot].lastPvsFrame = frameIndex;
        result.pvs.push_back(records[slot].id);
        pvsSlots.push_back(slot);
    }

    /// CullerOptions::hierarchical: the brick-tree walk (BrickTraversal3D.hpp) with the occlusion image.
    /// Ids met in visited voxels are classified (classify); a TBV met in a visited voxel that the image
    /// does not hide is revealed. Why that reveals every TBV it must: a ray from the camera (outside every
    /// boundary TBV, see updateScene) to a visible point x of a hidden object enters the TBV's region
    /// through a point y of its boundary before x; y is visible (its open segment is part of x's), so the
    /// voxel of y (a boundary voxel: T holds it) touches the view, lies in a brick the tree visits (every
    /// node holding y is occupied, touches the view and is not hidden), and is not hidden in the image.
    /// Objects reaching outside the grid are classified too: the image's facts hold for any point.
    void traverseBricks(const ViewFrustum& view, CullStats& st) requires(D == 3) {
        imageActive = options.occlusion && traversalImage.begin(view, options.traversalImageRows);
        st.tbvLookupsSkipped = tbvs.liveRegions() == 0;
        const BrickTraversalStats3D ts = brickTraversal.run(
            grid, storage, view, imageActive ? &traversalImage : nullptr, frame,
            [&](const IVec3& brick) { return tbvs.mayHoldBrick(brick); },
            [&](VoxelKey key, const IVec3&) { storage.forEachId(key, [&](ObjectSlot slot) { classify(slot, view); }); },
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
                if (imageActive) {
                    const IVec3 o = brick * 8;
                    for (int z = 0; z < 8; ++z)
                        for (int y = 0; y < 8; ++y) {
                            const std::uint32_t row = std::uint32_t(held[z] >> (8 * y)) & 0xFFu;
                            if (row == 0) continue;
                            const int first = std::countr_zero(row), last = 31 - std::countl_zero(row);
                            const Vec3 at(o + IVec3{0, y, z});
                            const double s = view.slack();
                            bool hide = traversalImage.hidden(Box<3>{at + Vec3(first, 0, 0), at + Vec3(last + 1, 1, 1)}, s);
                            std::uint32_t keep = hide ? 0u : row;
                            if (!hide && first != last)
                                for (std::uint32_t bits = row; bits != 0; bits &= bits - 1) {
                                    const int x = std::countr_zero(bits);
                                    if (traversalImage.hidden(Box<3>{at + Vec3(x, 0, 0), at + Vec3(x + 1, 1, 1)}, s))
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
                    if (records[slot].state == State::Hidden) revealDuringTraversal(slot, st);
            });
        for (std::size_t i = 0; i < outside.size(); ++i) classify(outside[i], view);
        st.layers = 0;
        st.voxelsVisited = ts.voxelsVisited;
        st.nodesVisited = ts.nodesVisited;
        st.nodesEmpty = ts.nodesEmpty;
        st.nodesHidden = ts.nodesHidden;
        st.bricksVisited = ts.bricksVisited;
        st.occludersExtended = ts.fusedBoxes;
        st.occlusionSkipped = !imageActive || traversalImage.stats().occludersDrawn == 0;
        imageActive = false;
    }

    /// CullerOptions::adaptiveCaps: after a frame, how many of the next frames start without caps.
    void scheduleCaps(const CullStats& st) {
        if (st.capsDeferred) {
            --capsSkip;
            if (st.capsFromShell != 0) capsSkip = 0, capsBackoff = 1; // a wall: caps every frame again
            return;
        }
        const bool paid = st.earlyTermination || st.voxelsOccluded * 10 >= st.voxelsVisited;
        if (paid) {
            capsBackoff = 1;
        } else {
            capsSkip = capsBackoff;
            capsBackoff = std::min<std::uint32_t>(2 * capsBackoff, 8);
        }
    }

    /// The occlusion buffer's pass over the grid's PVS (OcclusionBuffer3D.hpp): nearest first, each object
    /// with a current placement is tested against the image of the nearer ones kept, and drawn into it when
    /// it stays. Shapes are grown (tests) or shrunk (drawing) by their conversion slack and the camera's.
    /// Parked objects have no current placement: they stay and occlude nothing. Only result.pvs changes.
    template <class View> void refineWithBuffer(const View& view, CullStats& st) {
        {
            const auto t0 = std::chrono::steady_clock::now();
            if (!occlusionBuffer.begin(view, Traits::bufferSize(options))) return;
            // One pass over the records (large, scattered: each read is a cache miss) copies what the buffer
            // needs; the sort then moves 16-byte keys, and the test-and-draw pass reads the copies in order.
            bufferOrder.clear();
            bufferShapes.clear();
            for (ObjectSlot slot : pvsSlots) {
                const Record& r = records[slot];
                if (r.state != State::Tracked && r.state != State::Static) continue;
                const double slack = grid.conversionSlack(r.at.worldMagnitude) + view.slack();
                bufferOrder.push_back({occlusionBuffer.nearestDistance(r.at.local, slack), std::uint32_t(bufferShapes.size())});
                bufferShapes.push_back({r.at.local, slack, slot});
            }
            std::sort(bufferOrder.begin(), bufferOrder.end());
            std::uint32_t removed = 0;
            for (const auto& [distance, index] : bufferOrder) {
                const BufferShape& b = bufferShapes[index];
                if (occlusionBuffer.hidden(b.shape, b.slack, distance)) {
                    pvsStamp[b.slot] = 0; // marks it for removal below; the grid's verdict (lastPvsFrame) stays
                    ++removed;
                } else {
                    occlusionBuffer.draw(b.shape, b.slack);
                }
            }
            if (removed != 0) {
                result.pvs.clear();
                for (ObjectSlot slot : pvsSlots)
                    if (pvsStamp[slot] == frame) result.pvs.push_back(records[slot].id);
                    else pvsStamp[slot] = frame; // back to "in this frame's grid PVS"
            }
            st.bufferTested = occlusionBuffer.stats().tested;
            st.bufferHidden = removed;
            st.bufferMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        }
    }

    void nextFrame() {
        ++frameIndex;
        if (++frame > DenseStorage<D>::kMaxStamp) { // past the stamps' range: one full clear, every 65,535 frames
            storage.resetStamps();
            std::fill(pvsStamp.begin(), pvsStamp.end(), 0);
            std::fill(classifiedStamp.begin(), classifiedStamp.end(), 0);
            frame = 1;
        }
    }

    const CullResult& cull(const Camera<D>& camera, const PlacementQuery<D>* placementOf);
};

template <int D> const CullResult& Culler<D>::Impl::cull(const Camera<D>& camera, const PlacementQuery<D>* placementOf) {
    validateCamera<D>(camera);
    const typename Traits::View view(camera, grid); // may throw (3D: up parallel to direction)
    const auto t0 = std::chrono::steady_clock::now();
    nextFrame();
    result.pvs.clear();
    pvsSlots.clear();
    CullStats& st = result.stats;
    st = CullStats{};
    st.objectCount = std::uint32_t(slotOf.size());
    query = placementOf;
    queryException = nullptr;
    invalidField.clear();
    writes = 0;

    const bool cameraIn = grid.containsLocal(view.apex());
    const IVec<D> cameraVoxel = glm::clamp(GridGeometry<D>::voxelOfLocal(view.apex()), IVec<D>(0), grid.resolution() - 1);
    updateScene(cameraIn, cameraVoxel, st);
    st.updateMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

    currentView = &view;
    if (D == 3 && cameraIn && options.hierarchical) {
        if constexpr (D == 3) traverseBricks(view, st);
    } else if (cameraIn) {
        st.tbvLookupsSkipped = hidden.empty();
        const bool deferCaps = D == 3 && options.adaptiveCaps && options.occlusion && capsSkip > 0;
        Traits::traverse(traversal, grid, storage, view, frame, options, !hidden.empty(), deferCaps, st,
                         [&](VoxelKey key, const IVec<D>& v) {
            if (tbvs.liveRegions() != 0) {
                revealScratch.clear();
                tbvs.collectAt(v, revealScratch);
                for (ObjectSlot slot : revealScratch) revealDuringTraversal(slot, st);
            }
            storage.forEachId(key, [&](ObjectSlot slot) { addToPvs(slot); });
        });
        if (D == 3 && options.adaptiveCaps && options.occlusion) scheduleCaps(st);
        // Objects reaching outside the grid may be seen through the part the grid does not hold: they are
        // tested against the view region only.
        for (std::size_t i = 0; i < outside.size(); ++i) {
            const Record& r = records[outside[i]];
            if (view.touchesBox(r.at.localBounds.min, r.at.localBounds.max)) addToPvs(outside[i]);
        }
    } else {
        // The grid's occlusion is only valid for cameras inside it: view-region test for every object, a
        // hidden one by its TBV (revealed if the TBV touches the view).
        st.fallback = Fallback::CameraOutsideGrid;
        st.occlusionSkipped = true;
        st.tbvLookupsSkipped = true;
        for (ObjectSlot s = 0; s < records.size(); ++s) {
            Record& r = records[s];
            if (!r.alive) continue;
            if (r.state == State::Hidden) {
                const Vec<D> lo = r.tbv.centre - r.tbv.radius, hi = r.tbv.centre + r.tbv.radius;
                if (!view.touchesBox(lo, hi)) continue;
                ++st.tbvsRevealed;
                if (!reveal(s, st)) continue; // parked: reported below
            }
            if ((r.state == State::Tracked || r.state == State::Static) &&
                view.touchesBox(r.at.localBounds.min, r.at.localBounds.max))
                addToPvs(s);
        }
    }
    for (std::size_t i = 0; i < parked.size(); ++i) addToPvs(parked[i]);
    currentView = nullptr;
    havePrevCamera = cameraIn;
    prevCamera = cameraVoxel;
    query = nullptr;

    st.objectsOutsideGrid = std::uint32_t(outside.size());
    st.trackedObjects = std::uint32_t(tracked.size());
    st.hiddenObjects = std::uint32_t(hidden.size());
    st.parkedObjects = std::uint32_t(parked.size());
    st.gridWrites = writes;
    st.tbvMatrixAllocated = tbvs.allocated();
    if (options.occlusion && Traits::bufferSize(options) > 0 && pvsSlots.size() > 1) refineWithBuffer(view, st);
    std::sort(result.pvs.begin(), result.pvs.end());
    st.pvsSize = std::uint32_t(result.pvs.size());
    st.cullMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (queryException) std::rethrow_exception(std::exchange(queryException, nullptr));
    if (!invalidField.empty()) throw InvalidInput(invalidField, invalidWhat);
    return result;
}

template <int D> Culler<D>::Culler(const GridGeometry<D>& grid, const CullerOptions& options) {
    Impl::Traits::checkGrid(grid);
    if (options.tbvMaxFrames < 1 || options.tbvMaxFrames > 65536)
        throw InvalidInput("options.tbvMaxFrames", "must be in [1, 65536], got " + std::to_string(options.tbvMaxFrames));
    if (!std::isfinite(options.tbvMaxGrowth) || !(options.tbvMaxGrowth >= 0))
        throw InvalidInput("options.tbvMaxGrowth", "must be finite and >= 0");
    if (options.occlusionBufferRows < 0 || options.occlusionBufferRows > OcclusionBuffer3D::kMaxExtent)
        throw InvalidInput("options.occlusionBufferRows", "must be in [0, " + std::to_string(OcclusionBuffer3D::kMaxExtent) +
                                                               "], got " + std::to_string(options.occlusionBufferRows));
    if (options.occlusionBufferBins < 0 || options.occlusionBufferBins > OcclusionBuffer2D::kMaxBins)
        throw InvalidInput("options.occlusionBufferBins", "must be in [0, " + std::to_string(OcclusionBuffer2D::kMaxBins) +
                                                               "], got " + std::to_string(options.occlusionBufferBins));
    if (options.traversalImageRows < 1 || options.traversalImageRows > OcclusionBuffer3D::kMaxExtent)
        throw InvalidInput("options.traversalImageRows", "must be in [1, " + std::to_string(OcclusionBuffer3D::kMaxExtent) +
                                                              "], got " + std::to_string(options.traversalImageRows));
    if (options.tbvDiscretization != TbvDiscretization::Boundary && options.tbvDiscretization != TbvDiscretization::Filled &&
        options.tbvDiscretization != TbvDiscretization::Shell)
        throw InvalidInput("options.tbvDiscretization", "unknown value");
    try {
        m_impl = std::make_unique<Impl>(grid, options);
    } catch (const std::bad_alloc&) {
        throw InvalidInput("grid.resolution", "the grid's " + std::to_string(grid.voxelCount()) +
                                                  " voxels need more memory than is available");
    }
}
template <int D> Culler<D>::~Culler() = default;
template <int D> Culler<D>::Culler(Culler&&) noexcept = default;
template <int D> Culler<D>& Culler<D>::operator=(Culler&&) noexcept = default;

template <int D> const GridGeometry<D>& Culler<D>::grid() const { return m_impl->grid; }
template <int D> const CullerOptions& Culler<D>::options() const { return m_impl->options; }
template <int D> bool Culler<D>::hasObject(ObjectId id) const { return m_impl->slotOf.count(id) != 0; }
template <int D> std::size_t Culler<D>::objectCount() const { return m_impl->slotOf.size(); }
template <int D> const CullResult& Culler<D>::lastResult() const { return m_impl->result; }

template <int D> void Culler<D>::addObject(const ObjectDesc<D>& object) {
    Impl& m = *m_impl;
    const std::string field = "object " + std::to_string(object.id);
    if (m.slotOf.count(object.id)) throw InvalidInput(field + ".id", "duplicate id");
    if (!std::isfinite(object.maxSpeed) || object.maxSpeed < 0)
        throw InvalidInput(field + ".max_speed", "must be finite and >= 0");
    Shape<D> shape = object.shape;
    validateShape<D>(shape, field);
    typename Impl::Placement p = m.makePlacement(shape);

    ObjectSlot slot;
    if (!m.freeSlots.empty()) {
        slot = m.freeSlots.back();
        m.freeSlots.pop_back();
    } else {
        slot = ObjectSlot(m.records.size());
        m.records.emplace_back();
        m.pvsStamp.push_back(0);
        m.statePos.push_back(kNone);
        m.outsidePos.push_back(kNone);
        m.classifiedStamp.push_back(0);
        m.footprints.emplace_back();
    }
    typename Impl::Record& r = m.records[slot];
    r = typename Impl::Record{};
    r.id = object.id;
    r.maxSpeed = object.maxSpeed;
    r.alive = true;
    // A new object counts as a member of the last PVS: the next frame classifies it before it can be
    // hidden (the paper's first frame treats every object so).
    r.lastPvsFrame = m.frameIndex;
    r.at = std::move(p);
    m.rasterize(slot, +1);
    // Without a speed an object cannot move by itself: it is asked for nothing and needs no TBV (§4.5).
    const bool fixed = object.isStatic || object.maxSpeed == 0;
    m.enter(slot, fixed ? Impl::State::Static : Impl::State::Tracked);
    m.slotOf.emplace(object.id, slot);
}

template <int D> void Culler<D>::updateObject(ObjectId id, const Shape<D>& shape) {
    Impl& m = *m_impl;
    auto it = m.slotOf.find(id);
    if (it == m.slotOf.end()) throw InvalidInput("object " + std::to_string(id) + ".id", "unknown id");
    Shape<D> validated = shape;
    validateShape<D>(validated, [&] { return "object " + std::to_string(id); });
    typename Impl::Placement p = m.makePlacement(validated);
    const ObjectSlot slot = it->second;
    typename Impl::Record& r = m.records[slot];
    switch (r.state) {
    case Impl::State::Tracked:
    case Impl::State::Static: m.moveRasterized(slot, p); break;
    case Impl::State::Hidden:
        if (!p.outsideGrid && Impl::ballInside(boundingBall<D>(p.local), r.tbv)) {
            r.at = std::move(p); // still inside its TBV: nothing in the grid changes
            break;
        }
        [[fallthrough]];
    default:
        m.detach(slot);
        m.attachTracked(slot, p);
        r.lastPvsFrame = m.frameIndex; // classified by the next frame before it may be hidden again
    }
}

template <int D> void Culler<D>::removeObject(ObjectId id) {
    Impl& m = *m_impl;
    auto it = m.slotOf.find(id);
    if (it == m.slotOf.end()) throw InvalidInput("object " + std::to_string(id) + ".id", "unknown id");
    const ObjectSlot slot = it->second;
    m.detach(slot);
    m.records[slot].alive = false;
    m.freeSlots.push_back(slot);
    m.slotOf.erase(it);
}

template <int D> const CullResult& Culler<D>::cull(const Camera<D>& camera) { return m_impl->cull(camera, nullptr); }

template <int D> const CullResult& Culler<D>::cull(const Camera<D>& camera, const PlacementQuery<D>& placementOf) {
    if (!placementOf) throw InvalidInput("placementOf", "must be callable");
    return m_impl->cull(camera, &placementOf);
}

template <int D> VoxelState Culler<D>::voxelState(const IVec<D>& v) const {
    const Impl& m = *m_impl;
    VoxelState s;
    if (!m.grid.contains(v)) return s;
    const VoxelKey key = m.grid.linearIndex(v);
    s.inGrid = true;
    s.opaque = m.storage.opaque(key);
    s.occluded = m.frame != 0 && m.storage.occluded(key, m.frame);
    s.visited = m.frame != 0 && m.storage.visited(key, m.frame);
    s.occluder = m.frame != 0 && m.storage.used(key, m.frame);
    s.hasIds = m.storage.hasIds(key);
    s.hasTbv = m.tbvs.holdsAt(v);
    return s;
}

template class Culler<2>;
template class Culler<3>;

} // namespace rgvc
