// Culler<D>::Impl: the state behind the public Culler (dynamics/include/rgvc/dynamics/Culler.hpp) and the
// declarations of its parts. Internal to rgvc::dynamics. The members are defined by concept, one file each:
//   Culler.cpp       the public members and the per-frame driver (cull, nextFrame, scheduleCaps)
//   ObjectTable.cpp  placements, rasterization into I and O, the objects' states (attach, detach, fetch)
//   TbvPolicy.cpp    temporal bounding volumes: buildTbv, updateScene, reveal, revealDuringTraversal
//   BrickPass.cpp    CullerOptions::hierarchical: traverseBricks (3D) and classify
//   BrickPass2D.cpp  CullerOptions::hierarchical: traverseBricks (2D)
//   BufferPass.cpp   the occlusion buffer's pass over the grid's PVS (refineWithBuffer)
//   ViewPass.cpp     one view's pass of a frame (cullView) and several views per frame (cullViews)
//
// Scene state and view state. Everything a frame's view pass writes per view (traversal stamps, the
// traversal's image, the occlusion buffer, the PVS under construction) lives in a ViewScratch; the rest of
// Impl is the scene (objects, O, I, T, the TBV schedule), written only by the scene update before the view
// passes and by the reveals after them. cull() runs one pass over `main`, whose stamps are the scene
// storage's own and which reveals TBVs the moment it meets them (classifying the object in the same
// frame); cullViews() runs one pass per camera over `views`, concurrently, with the scene read-only.
// Each file explicitly instantiates, for D = 2 and 3, the members it defines; the few defined here are
// inline (addToPvs runs once per id the traversal meets, ballInside is also used by updateObject).
#pragma once

#include "rgvc/dynamics/Culler.hpp"
#include "rgvc/grid/BrickObjects.hpp"

#include "rgvc/grid/BrickTraversal2D.hpp"
#include "rgvc/grid/BrickTraversal3D.hpp"
#include "rgvc/grid/OcclusionBuffer3D.hpp"
#include "rgvc/grid/OrthoOcclusionImage.hpp"
#include "rgvc/grid/OrthoVolume.hpp"
#include "rgvc/grid/BrickWalk.hpp"
#include "rgvc/grid/RowFootprint.hpp"
#include "rgvc/grid/VoxelStorage.hpp"

#include "CullerTraits.hpp"
#include "FaceTbvs.hpp"
#include "SlotSet.hpp"
#include "ViewStorage.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <exception>
#include <memory>
#include <span>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace rgvc {

/// The index of T among the alternatives of the variant V (T one of them, once).
template <class T, class V> constexpr std::size_t variantIndexOf() {
    return []<std::size_t... I>(std::index_sequence<I...>) {
        std::size_t index = std::variant_size_v<V>;
        (void)((std::is_same_v<T, std::variant_alternative_t<I, V>> ? (index = I, true) : false) || ...); // (clang: -Wunused-value)
        return index;
    }(std::make_index_sequence<std::variant_size_v<V>>{});
}
static_assert(variantIndexOf<Box<3>, Shape<3>>() == 1 && variantIndexOf<Box<2>, Shape<2>>() == 1);

/// dst = src. std::variant's assignment dispatches on both alternatives through a visit (copy-assign,
/// or destroy and construct) even for two balls: over a tenth of a placement query's instructions, and
/// each mover is placed again once per TBV renewal (the 100k room). Balls and boxes, nearly every
/// moving object, are copied as plain structs when dst already holds the same alternative.
template <int D> inline void assignShape(Shape<D>& dst, const Shape<D>& src) {
    if (const auto* b = std::get_if<Ball<D>>(&src)) {
        if (auto* d = std::get_if<Ball<D>>(&dst)) {
            *d = *b;
            return;
        }
    } else if (const auto* x = std::get_if<Box<D>>(&src)) {
        if (auto* d = std::get_if<Box<D>>(&dst)) {
            *d = *x;
            return;
        }
    }
    dst = src;
}

template <int D> struct Culler<D>::Impl {
    using Traits = culler_detail::CullerTraits<D>;

    /// Where an object is held. Static: O and I for good (§4.5). Tracked: O and I at its current placement
    /// (last PVS, revealed, new, or refused a TBV). Hidden: only its TBV in T. Parked: its placement query
    /// failed; reported in every PVS until one succeeds. Detached: between two of these.
    enum class State : std::uint8_t { Static, Tracked, Hidden, Parked, Detached };

    /// A placement converted once: what rasterization, TBVs and the outside-grid test read.
    struct Placement {
        // The bounds and the flags first: Record puts them in its first cache lines (see there).
        Box<D> localBounds;
        double worldMagnitude = 0; // largest |coordinate| of the world-unit bounds
        bool inset = false;        // the occluder is `inner`, not `local`
        bool occludes = true;      // false when the inset leaves nothing
        bool outsideGrid = false;  // partly or wholly outside: also tested against the view region
        // local.index(), next to the bounds: the variant's own index sits after its ~240 bytes, in a
        // cache line that classify's kind tests (a mesh in view, a box) would otherwise miss.
        std::uint8_t kind = 0;
        Shape<D> local;            // voxel units, as rasterized into I and O
        Shape<D> world;
        // The occluder model (ObjectDesc::occluderInset), voxel units: what O holds and the occlusion
        // images draw. Held apart only for a positive inset (a polygon copy per placement query otherwise).
        Shape<D> inner;
        /// The occluder model, or null when the object occludes nothing.
        const Shape<D>* occluder() const { return !occludes ? nullptr : inset ? &inner : &local; }
        /// *this = o, with balls and boxes copied as such (assignShape). `inner` is copied only where o
        /// reads it (o.inset).
        void assign(const Placement& o) {
            assignShape<D>(world, o.world);
            assignShape<D>(local, o.local);
            if (o.inset) assignShape<D>(inner, o.inner);
            localBounds = o.localBounds;
            inset = o.inset;
            occludes = o.occludes;
            worldMagnitude = o.worldMagnitude;
            outsideGrid = o.outsideGrid;
            kind = o.kind;
        }
        /// Whether local holds a T (read from `kind`).
        template <class T> bool localIs() const { return kind == variantIndexOf<T, Shape<D>>(); }
    };

    /// Cache-line aligned, with what a view reads of every object it meets first: its state, role, id and
    /// last PVS frame, then the placement's bounds, scale and flags (classify, addToPvs), in the first two
    /// lines. A record is ~850 bytes (three shapes), and these fields sat in three lines far apart: perf
    /// put 11 % of the clusters' time on classify's loads of them.
    struct alignas(64) Record {
        State state = State::Detached;
        ObjectRole role = ObjectRole::Both;
        bool isStatic = false; // ObjectDesc::isStatic, as added
        bool alive = false;
        ObjectId id = 0;
        std::uint64_t lastPvsFrame = 0; // frameIndex of the last PVS holding it
        Placement at;
        double maxSpeed = 0;
        double inset = 0; // [World units] ObjectDesc::occluderInset
        std::uint64_t placedFrame = 0;  // frameIndex of its last successful placement query
        std::uint64_t failedFrame = 0;  // frameIndex of its last failed placement query
        // Hysteresis against reveal/re-hide cycles (see updateScene): the frame its TBV was last revealed
        // by the traversal, how many such reveals in a row found it hidden, and until when it stays in O and I.
        std::uint64_t revealedFrame = 0;
        std::uint64_t holdUntil = 0;
        std::uint8_t fruitless = 0;
        std::uint8_t growthLevel = 0;   // its TBVs grow by tbvMaxGrowth / 2^growthLevel (see updateScene)
        std::uint8_t cleanRenewals = 0; // validities lived out unrevealed since growthLevel last changed
        std::uint8_t tbvFaces = 0;      // the grid faces its TBV reaches past (faceTbvs; bit f: face f)
        TbvRegion<D> tbv;
        std::uint64_t tbvExpiry = 0;    // first frame the TBV no longer covers
        std::uint32_t tbvGeneration = 0;
        BrickBox<D> listedIn;           // 3D: the bricks whose lists hold it while it is in I (BrickObjects.hpp)
    };

    GridGeometry<D> grid;
    CullerOptions options;
    DenseStorage<D> storage;
    TbvMatrix<D> tbvs;
    std::vector<Record> records;
    std::vector<ObjectSlot> freeSlots;
    std::unordered_map<ObjectId, ObjectSlot> slotOf;
    std::vector<std::uint32_t> pvsStamp;    // per slot: frame stamp in which it was added to the PVS
    std::vector<std::uint32_t> statePos;    // per slot: position in tracked, hidden or parked
    std::vector<std::uint32_t> outsidePos;  // per slot: position in outside
    SlotSet tracked, hidden, parked, outside;
    // Hidden objects whose TBV reaches past a face of the grid, unless the application promised that
    // objects stay in it (CullerOptions::objectsStayInGrid): each view tests those parts (revealFaceTbvs).
    FaceTbvs<D> faceTbvs;
    // Per face: cull()'s last test found the part of the world beyond it in view (revealFaceTbvs). New TBVs
    // then stay inside it as before (buildTbv): each one reaching past it would cost a test every frame. An
    // open face without TBVs past it is tested again every kFaceReprobeFrames frames (TbvPolicy.cpp).
    std::array<bool, 2 * D> faceOpen{};
    // Expiry buckets: TBVs expiring at frame f wait in expiring[f % size] (a validity is at most
    // tbvMaxFrames, so a bucket never holds two different frames). Entries of TBVs revealed or
    // renewed meanwhile are recognised by their generation and dropped.
    std::vector<std::vector<std::pair<ObjectSlot, std::uint32_t>>> expiring;
    std::uint32_t frame = 0;         // stamp of the stamped matrices, 1..DenseStorage::kMaxStamp, then again
    std::uint64_t frameIndex = 0;    // cull() calls so far, never wraps
    bool havePrevCamera = false;     // every camera of the last frame was in the grid
    std::vector<IVec<D>> prevCameras; // their voxels (one per view)

    // The current frame's placement source (null: the stored placements) and its first failure.
    const PlacementQuery<D>* query = nullptr;
    bool inQuery = false; // the placement query is running (Culler's members refuse to be called)
    std::exception_ptr queryException;
    std::string invalidField, invalidWhat;
    std::uint64_t writes = 0;
    std::vector<ObjectSlot> revealScratch;
    Placement fetched; // the last placement a query returned
    // CullerOptions::adaptiveCaps (3D): frames still to start without caps, and the next skip's length.
    std::uint32_t capsSkip = 0, capsBackoff = 1;
    // CullerOptions::adaptiveBuffer: frames still to skip the occlusion buffer's pass, and the next skip.
    std::uint32_t bufferSkip = 0, bufferBackoff = 1;
    // CullerOptions::adaptiveImage (3D hierarchical): frames still to walk without the image, and the next skip's length.
    std::uint32_t imageSkip = 0, imageBackoff = 1;
    struct BufferShape {
        // Voxel units. Balls and boxes are copied (the sort's pass then reads no record); a shape that
        // owns memory (a polytope) is not, to allocate nothing per object and frame: `large` points at it
        // in its record, which no step of the pass changes.
        Shape<D> small;
        const Shape<D>* large;
        const Shape<D>* occluder;  // its occluder model (in records; null: occludes nothing)
        const Shape<D>& shape() const { return large != nullptr ? *large : small; }
        double slack;              // conversion slack of the object and the camera
        ObjectSlot slot;
    };

    /// CullerOptions::bufferFromTraversalImage: an occluder the walk drew, inherited by the pass's image
    /// and drawn into it again at its resolution only once a farther object it may cover stays visible.
    struct LazyOccluder {
        ImageFootprint3D::Rect rect; // the pixels its image can touch (OcclusionBuffer3D::pixelRect)
        double nearest;              // [voxel units] the sort key
        std::uint32_t index;         // in bufferShapes
        bool redrawn;
    };

    /// One view's state in a frame. S is the storage its traversal stamps: the scene's DenseStorage
    /// (cull()) or a ViewStorage over it (cullViews(), kShared: the pass writes nothing of the scene).
    template <class S> struct ViewScratch {
        static constexpr bool kShared = requires { S::kSharedScene; };
        S* storage = nullptr;
        std::unique_ptr<S> ownStorage;   // kShared: this view's stamps
        std::uint32_t stamp = 0;         // this view's frame stamp (main: Impl::frame)
        typename Traits::template Traversal<S> traversal;
        // CullerOptions::hierarchical: the brick-tree walk and its occlusion image (3D depth, 2D angular).
        typename Traits::template BrickTraversal<S> brickTraversal;
        // Mutable: voxelState (const) asks it about voxels after the frame, which only counts in its stats.
        mutable typename Traits::Buffer traversalImage;
        bool imageActive = false;
        bool meshInView = false;                 // 3D: the walk met a mesh occluder in view (adaptiveImage)
        bool imageKept = false;                  // the last walk drew into traversalImage (voxelState reads it)
        typename Traits::View imageView;         // that walk's view
        std::vector<ObjectSlot> revealedPending; // main: revealed during the walk, classified after it
        // The grid PVS's slots in the order added, and the occlusion buffer that refines it.
        std::vector<ObjectSlot> pvsSlots;
        std::vector<std::pair<double, std::uint32_t>> bufferOrder; // (nearest distance, index in bufferShapes)
        std::vector<std::pair<double, std::uint32_t>> bufferOrderScratch; // sortByDistance's working memory
        std::vector<BufferShape> bufferShapes;
        std::vector<LazyOccluder> lazyOccluders;
        typename Traits::Buffer occlusionBuffer;
        // Per slot: the stamp in which the object joined this view's PVS, in which the hierarchical
        // traversal classified it (tested against the view and the image), and in which it drew it into
        // its image (3D).
        std::vector<std::uint32_t> pvsStamp, classifiedStamp, drawnStamp;
        std::vector<ObjectSlot> revealScratch;
        // The brick walk's TBVs of the brick at hand and the voxels each holds there (TbvMatrix::brickParts),
        // and which of them a visible voxel has taken for revealing (traverseBricks).
        std::vector<ObjectSlot> brickTbvSlots;
        std::vector<std::array<std::uint64_t, 8>> brickTbvParts;
        std::vector<std::uint8_t> brickTbvTaken;
        std::vector<ObjectSlot> met; // kShared: hidden objects whose TBV this view met, in the order met
        std::vector<ObjectSlot> faceMet; // revealFaceTbvs: the TBVs whose part beyond the grid it found visible
        const typename Traits::View* view = nullptr; // while the pass runs
        std::exception_ptr failure;  // kShared: what the pass threw (bad_alloc), rethrown after all views
        // Orthographic 3D views with occlusion (OrthoPass.cpp): the parallel-ray image, the objects met,
        // the walk's stack.
        OrthoOcclusionImage orthoImage;
        std::vector<ObjectSlot> orthoMet;
        std::vector<BrickNode<D>> orthoStack;
        CullResult result;
    };
    using MainScratch = ViewScratch<DenseStorage<D>>;
    using SharedScratch = ViewScratch<ViewStorage<D>>;
    MainScratch main;
    std::vector<std::unique_ptr<SharedScratch>> views; // cullViews: one per camera slot, kept for reuse
    MultiCullResult multiResult;
    std::unique_ptr<TaskExecutor> defaultExecutor; // cullViews without an executor: a TBB arena, made once
    // Per slot: the footprint written into I and O while the object is there (Static, Tracked), empty
    // otherwise. A move rasterizes only its new placement; a removal takes out exactly what was put in.
    std::vector<RowFootprint> footprints;
    RowFootprint nextFootprint; // reused by every move (no allocation per update after warm-up)
    // 3D: the objects in I and O per brick, which the brick walk meets instead of the voxels' ids.
    BrickObjects<D> brickObjects;
    // Whether objects are written into I voxel by voxel. 3D with CullerOptions::hierarchical: no. Every
    // reader of ids there meets objects through brickObjects (the walk, the fused boxes' check, the
    // orthographic pass, voxelState), which is I at brick resolution: a superset of the objects whose
    // voxels lie in a brick, each then judged by its own shape. Keeping the per-voxel sets as well cost a
    // moving object its touched rows' rasterization and their difference every frame, for no reader
    // (README, "Scene classes"). The paper's traversals (hierarchical = false) and 2D read I per voxel.
    const bool idsInI;

    Impl(const GridGeometry<D>& g, const CullerOptions& o)
        : grid(g), options(o), storage(g), tbvs(g.resolution()), expiring(std::size_t(o.tbvMaxFrames) + 2),
          brickObjects(g.resolution()), idsInI(D == 2 || !o.hierarchical) {
        if (options.tbvMaxGrowth == 0) options.tbvMaxGrowth = D == 2 ? 32.0 : o.hierarchical ? 4.0 : 8.0;
        // The storage's per-voxel arrays start as untouched zero pages (ZeroedArray.hpp). By default every
        // page is written now, so that none is first touched during a frame; CullerOptions::lazyStorage
        // leaves untouched what the walks do not reach in every brick (memory follows the content).
        if (!options.hierarchical) storage.adviseWholeGridReads();
        if (!options.lazyStorage) storage.touchAll();
        else if (options.hierarchical) storage.touchWalkedArrays(D == 2);
        main.storage = &storage;
    }

    // ---- placements, rasterization and object states (ObjectTable.cpp) ------------------------------

    Placement makePlacement(const Shape<D>& world, double inset, ObjectRole role) const;
    /// The same, written over p (fetch's scratch: a ball or box replaces a ball or box without a variant
    /// visit).
    void makePlacementInto(Placement& p, const Shape<D>& world, double inset, ObjectRole role) const;
    void rasterize(ObjectSlot slot, int sign);
    void buildFootprint(const Placement& p, RowFootprint& f) const;
    void markListed(const BrickBox<D>& box);
    /// The objects that may hold voxel `v` (key `key`) in I: its id set where ids are kept per voxel
    /// (idsInI), else its brick's list (a superset: callers judge each object by its shape).
    template <class Fn> void forEachObjectAt(VoxelKey key, const IVec<D>& v, Fn&& fn) const {
        if (idsInI) {
            storage.forEachId(key, fn);
        } else {
            if constexpr (D == 3)
                for (ObjectSlot slot : brickObjects.at(v >> BrickPyramid<D>::kBrickShift)) fn(slot);
        }
    }
    void moveRasterized(ObjectSlot slot, const Placement& p);
    void syncOutside(ObjectSlot slot);
    SlotSet* setOf(State s);
    void enter(ObjectSlot slot, State s);
    void detach(ObjectSlot slot);
    void adopt(ObjectSlot slot, const Placement& p);
    void attachTracked(ObjectSlot slot, const Placement& p);
    void attachHidden(ObjectSlot slot, const Placement& p, const TbvRegion<D>& region, std::uint64_t expiry);
    void placeTbv(ObjectSlot slot, const Placement& p, const TbvRegion<D>& region, std::uint64_t expiry);
    void dropTbv(ObjectSlot slot);
    void leaveState(ObjectSlot slot);
    const Placement* fetch(ObjectSlot slot, CullStats& st);
    /// Asks the processor to bring a record into the cache (a hint: no effect on results). Loops over
    /// slots in no order (the renewals, the tracked objects, the buffer pass) call it kRecordsAhead ahead:
    /// a record is 850 bytes in 3D (three shapes of 208), and with thousands of objects the wait for
    /// each one's first line was most of such a loop's time. Two ahead: the 100k room measured 4 % faster
    /// than with four (whose 56 lines in flight left prefetches waiting for a free fill buffer in perf)
    /// and within 3 % of one; prefetching only the lines of the renewal's first reads was 6-15 % slower
    /// (the record's placement is rewritten).
    static constexpr std::size_t kRecordsAhead = 2;
    /// The whole record, to be written (a renewal rewrites its placement and TBV).
    void prefetchRecord(ObjectSlot slot) const {
        const char* p = reinterpret_cast<const char*>(records.data() + slot);
        for (std::size_t off = 0; off < sizeof(Record); off += 64) __builtin_prefetch(p + off, 1);
    }
    /// The lines an occludee test reads: its state, its local shape (a ball's or box's fields at the
    /// start, the variant's index at the end), its bounds and the occluder's flags; and its id, which an
    /// object kept in the PVS is listed by (addToPvs, the buffer pass's end).
    void prefetchRecordTests(ObjectSlot slot) const {
        const Record& r = records[slot];
        __builtin_prefetch(&r.id);
        const char* local = reinterpret_cast<const char*>(&r.at.local);
        __builtin_prefetch(local);
        __builtin_prefetch(local + sizeof(Shape<D>) - 1);
        __builtin_prefetch(reinterpret_cast<const char*>(&r.at.localBounds) + sizeof(Box<D>) - 1);
        __builtin_prefetch(&r.at.worldMagnitude);
        __builtin_prefetch(&r.state);
    }

    // ---- temporal bounding volumes (§4.1; TbvPolicy.cpp) -------------------------------------------

    /// cameras: the voxels of this frame's cameras (every view's), which a boundary TBV must stay clear of.
    bool buildTbv(const Record& r, const Placement& p, bool cameraKnown, std::span<const IVec<D>> cameras,
                  TbvRegion<D>& region, std::uint64_t& expiry) const;
    bool brokePromise(const Placement& p) const;
    double stepOf(const Record& r) const;
    /// Whether ball b lies inside the TBV region r (a disc in 2D, a cube in 3D).
    static bool ballInside(const Ball<D>& b, const TbvRegion<D>& r) {
        if constexpr (D == 2) {
            return std::sqrt(lengthSquared<2>(b.center - r.centre)) + b.radius <= r.radius;
        } else {
            for (int a = 0; a < 3; ++a)
                if (std::abs(b.center[a] - r.centre[a]) + b.radius > r.radius) return false;
            return true;
        }
    }
    bool reveal(ObjectSlot slot, CullStats& st);
    /// cameraIn: every camera of the frame is a perspective one in the grid (new TBVs may be made);
    /// cameras: the voxels of the frame's perspective cameras that are in the grid.
    void updateScene(bool cameraIn, std::span<const IVec<D>> cameras, CullStats& st);
    void revealDuringTraversal(ObjectSlot slot, CullStats& st);
    /// After a perspective view's traversal, with its image complete (or none): every TBV part beyond a
    /// face of the grid (faceTbvs) that touches the view and that the image does not hide is met (tbvMet).
    template <class S> void revealFaceTbvs(ViewScratch<S>& vs, const typename Traits::View& view, CullStats& st);

    // ---- the hierarchical traversal (BrickPass.cpp) -------------------------------------------------

    /// inCone (3D): the object was met in a brick inside the view's cone, so only the far limit is tested.
    template <class S, class View> void classify(ViewScratch<S>& vs, ObjectSlot slot, const View& view, bool inCone = false);
    void classify(ObjectSlot slot); // cull()'s view (main)
    template <class S> void traverseBricks(ViewScratch<S>& vs, const ViewFrustum& view, CullStats& st) requires(D == 3);
    template <class S> void traverseBricks(ViewScratch<S>& vs, const ViewWedge& view, CullStats& st) requires(D == 2);
    /// Whether one box object (Tracked or Static) holding voxel `seed` contains the voxel box lo..hi
    /// (inclusive): a fused box of opaque voxels inside it repeats it and is not drawn.
    bool boxObjectHolds(VoxelKey seed, const IVec<D>& lo, const IVec<D>& hi) const;
    bool boxPairHolds(VoxelKey seed, const IVec<D>& lo, const IVec<D>& hi, const OcclusionBuffer3D& image, double slack,
                      ObjectSlot (&pair)[2]) const
        requires(D == 3);
    template <class S>
    void finishWalk(ViewScratch<S>& vs, const typename Traits::View& view, CullStats& st, std::uint64_t voxels,
                    std::uint64_t nodes, std::uint64_t empty, std::uint64_t hiddenNodes, std::uint64_t bricks,
                    std::uint64_t fused);

    // ---- the occlusion buffer's pass (BufferPass.cpp) ----------------------------------------------

    template <class S, class View> void refineWithBuffer(ViewScratch<S>& vs, const View& view, CullStats& st);

    // ---- the frame (Culler.cpp) --------------------------------------------------------------------

    /// Adds an object to a view's PVS (once per frame; called per id met, so kept inline here). The
    /// scene's record of it (lastPvsFrame, the grid's verdict, which the next scene update reads) is
    /// written here for cull()'s view, while the caller has the record in cache (a pass over the PVS's
    /// records after the walk took a cache miss per object), and after all views by cullViews.
    /// (flatten: GCC inlines the two push_backs here whatever its budget for the caller; where it did not,
    /// as after unrelated changes to BrickPass.cpp, the clusters paid 0.7 % more instructions for the calls.)
    template <class S> [[gnu::flatten]] void addToPvs(ViewScratch<S>& vs, ObjectSlot slot) {
        if (vs.pvsStamp[slot] == vs.stamp) return;
        vs.pvsStamp[slot] = vs.stamp;
        Record& r = records[slot];
        // An occluder-only object counts as in the PVS for the culler's own bookkeeping (it stays in O and
        // I while in view) but is not reported.
        if (r.role != ObjectRole::Occluder) vs.result.pvs.push_back(r.id);
        if constexpr (!ViewScratch<S>::kShared) r.lastPvsFrame = frameIndex;
        vs.pvsSlots.push_back(slot);
    }
    /// A hidden object's TBV met in a visible voxel: cull() reveals it now; a cullViews() pass reports it
    /// (its placement inside the TBV is unknown to the pass) and records it for the reveals after all views.
    template <class S> void tbvMet(ViewScratch<S>& vs, ObjectSlot slot, CullStats& st) {
        if constexpr (ViewScratch<S>::kShared) {
            vs.met.push_back(slot);
            addToPvs(vs, slot);
        } else {
            revealDuringTraversal(slot, st);
        }
    }
    void scheduleCaps(const CullStats& st);
    void nextFrame();
    /// Starts a view's frame: stamps (the shared scratch's own, wrapping like the scene's), the PVS.
    template <class S> void beginView(ViewScratch<S>& vs);
    /// One view's pass of a frame after the scene update (ViewPass.cpp): traversal, objects outside the
    /// grid, parked objects, the occlusion buffer, the sorted PVS. Writes the scene only through tbvMet
    /// when S is the scene's own storage.
    template <class S> void cullView(ViewScratch<S>& vs, const typename Traits::View& view, bool cameraIn);
    /// Every object tested against a view region on its own (camera outside the grid, orthographic):
    /// held ones by touchesObject(record), hidden ones by touchesTbv(lo, hi) on their TBV's box.
    template <class S, class TouchesTbv, class TouchesObject>
    void testEveryObject(ViewScratch<S>& vs, TouchesTbv&& touchesTbv, TouchesObject&& touchesObject, CullStats& st);
    /// An orthographic view's pass (OrthoVolume.hpp): view-volume culling, exact, no occlusion.
    template <class S> void orthoView(ViewScratch<S>& vs, const OrthoVolume<D>& volume);
    /// An orthographic 3D view's pass with occlusion (OrthoPass.cpp; CullerOptions::orthographicOcclusion).
    template <class S> void orthoOcclusionView(ViewScratch<S>& vs, const OrthoVolume<D>& volume) requires(D == 3);
    /// Either of the two above, as the options say.
    template <class S> void orthoPass(ViewScratch<S>& vs, const OrthoVolume<D>& volume) {
        if constexpr (D == 3)
            if (options.occlusion && options.orthographicOcclusion) return orthoOcclusionView(vs, volume);
        orthoView(vs, volume);
    }
    const CullResult& cull(const Camera<D>& camera, const PlacementQuery<D>* placementOf);
    const MultiCullResult& cullViews(std::span<const Camera<D>> cameras, const PlacementQuery<D>* placementOf,
                                     TaskExecutor* executor);
};

} // namespace rgvc
