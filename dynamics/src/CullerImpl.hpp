// Culler<D>::Impl: the state behind the public Culler (dynamics/include/rgvc/dynamics/Culler.hpp) and the
// declarations of its parts. Internal to rgvc::dynamics. The members are defined by concept, one file each:
//   Culler.cpp       the public members and the per-frame driver (cull, nextFrame, scheduleCaps)
//   ObjectTable.cpp  placements, rasterization into I and O, the objects' states (attach, detach, fetch)
//   TbvPolicy.cpp    temporal bounding volumes: buildTbv, updateScene, reveal, revealDuringTraversal
//   BrickPass.cpp    CullerOptions::hierarchical (3D): traverseBricks and classify
//   BufferPass.cpp   the occlusion buffer's pass over the grid's PVS (refineWithBuffer)
// Each file explicitly instantiates, for D = 2 and 3, the members it defines; the few defined here are
// inline (addToPvs runs once per id the traversal meets, ballInside is also used by updateObject).
#pragma once

#include "rgvc/dynamics/Culler.hpp"

#include "rgvc/grid/BrickTraversal3D.hpp"
#include "rgvc/grid/OcclusionBuffer3D.hpp"
#include "rgvc/grid/RowFootprint.hpp"
#include "rgvc/grid/VoxelStorage.hpp"

#include "CullerTraits.hpp"
#include "SlotSet.hpp"

#include <cmath>
#include <cstdint>
#include <exception>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace rgvc {

template <int D> struct Culler<D>::Impl {
    using Traits = culler_detail::CullerTraits<D>;

    /// Where an object is held. Static: O and I for good (§4.5). Tracked: O and I at its current placement
    /// (last PVS, revealed, new, or refused a TBV). Hidden: only its TBV in T. Parked: its placement query
    /// failed; reported in every PVS until one succeeds. Detached: between two of these.
    enum class State : std::uint8_t { Static, Tracked, Hidden, Parked, Detached };

    /// A placement converted once: what rasterization, TBVs and the outside-grid test read.
    struct Placement {
        Shape<D> world;
        Shape<D> local;            // voxel units, as rasterized into I and O
        Box<D> localBounds;
        // The occluder model (ObjectDesc::occluderInset), voxel units: what O holds and the occlusion
        // images draw. Held apart only for a positive inset (a polygon copy per placement query otherwise).
        Shape<D> inner;
        bool inset = false;    // the occluder is `inner`, not `local`
        bool occludes = true;  // false when the inset leaves nothing
        /// The occluder model, or null when the object occludes nothing.
        const Shape<D>* occluder() const { return !occludes ? nullptr : inset ? &inner : &local; }
        double worldMagnitude = 0; // largest |coordinate| of the world-unit bounds
        bool outsideGrid = false;  // partly or wholly outside: also tested against the view region
    };

    struct Record {
        ObjectId id = 0;
        Placement at;
        double maxSpeed = 0;
        double inset = 0; // [World units] ObjectDesc::occluderInset
        ObjectRole role = ObjectRole::Both;
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
    bool inQuery = false; // the placement query is running (Culler's members refuse to be called)
    std::exception_ptr queryException;
    std::string invalidField, invalidWhat;
    std::uint64_t writes = 0;
    std::vector<ObjectSlot> revealScratch;
    Placement fetched; // the last placement a query returned
    const typename Traits::View* currentView = nullptr; // the frame's view, while cull() runs
    // CullerOptions::adaptiveCaps (3D): frames still to start without caps, and the next skip's length.
    std::uint32_t capsSkip = 0, capsBackoff = 1;
    // CullerOptions::adaptiveBuffer: frames still to skip the occlusion buffer's pass, and the next skip.
    std::uint32_t bufferSkip = 0, bufferBackoff = 1;
    // The grid PVS's slots in the order added, and the occlusion buffer that refines it (3D).
    std::vector<ObjectSlot> pvsSlots;
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

    // ---- placements, rasterization and object states (ObjectTable.cpp) ------------------------------

    Placement makePlacement(const Shape<D>& world, double inset, ObjectRole role) const;
    void rasterize(ObjectSlot slot, int sign);
    void buildFootprint(const Placement& p, RowFootprint& f) const;
    void moveRasterized(ObjectSlot slot, const Placement& p);
    void syncOutside(ObjectSlot slot);
    SlotSet* setOf(State s);
    void enter(ObjectSlot slot, State s);
    void detach(ObjectSlot slot);
    void adopt(ObjectSlot slot, const Placement& p);
    void attachTracked(ObjectSlot slot, const Placement& p);
    void attachHidden(ObjectSlot slot, const Placement& p, const TbvRegion<D>& region, std::uint64_t expiry);
    const Placement* fetch(ObjectSlot slot, CullStats& st);

    // ---- temporal bounding volumes (§4.1; TbvPolicy.cpp) -------------------------------------------

    bool buildTbv(const Record& r, const Placement& p, bool cameraKnown, const IVec<D>& camera, TbvRegion<D>& region,
                  std::uint64_t& expiry) const;
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
    void updateScene(bool cameraIn, const IVec<D>& camera, CullStats& st);
    void revealDuringTraversal(ObjectSlot slot, CullStats& st);

    // ---- 3D hierarchical traversal (BrickPass.cpp) -------------------------------------------------

    template <class View> void classify(ObjectSlot slot, const View& view);
    void classify(ObjectSlot slot);
    void traverseBricks(const ViewFrustum& view, CullStats& st) requires(D == 3);

    // ---- the occlusion buffer's pass (BufferPass.cpp) ----------------------------------------------

    template <class View> void refineWithBuffer(const View& view, CullStats& st);

    // ---- the frame (Culler.cpp) --------------------------------------------------------------------

    /// Adds an object to this frame's PVS (once per frame; called per id met, so kept inline here).
    void addToPvs(ObjectSlot slot) {
        if (pvsStamp[slot] == frame) return;
        pvsStamp[slot] = frame;
        records[slot].lastPvsFrame = frameIndex;
        // An occluder-only object counts as in the PVS for the culler's own bookkeeping (it stays in O and
        // I while in view) but is not reported.
        if (records[slot].role != ObjectRole::Occluder) result.pvs.push_back(records[slot].id);
        pvsSlots.push_back(slot);
    }
    void scheduleCaps(const CullStats& st);
    void nextFrame();
    const CullResult& cull(const Camera<D>& camera, const PlacementQuery<D>* placementOf);
};

} // namespace rgvc
