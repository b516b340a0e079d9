// Culler<D>: object bookkeeping (I and O) and the per-frame cull over the dense storage. The same code
// serves 2D and 3D; only the view region and the traversal differ (ViewWedge + FrustumTraversal2D,
// ViewFrustum + FrustumTraversal3D), chosen by CullerTraits.
#include "rgvc/dynamics/Culler.hpp"

#include "rgvc/grid/ConservativeRaster.hpp"
#include "rgvc/grid/FrustumTraversal2D.hpp"
#include "rgvc/grid/FrustumTraversal3D.hpp"
#include "rgvc/grid/ViewFrustum.hpp"
#include "rgvc/grid/ViewWedge.hpp"
#include "rgvc/grid/VoxelStorage.hpp"

#include <algorithm>
#include <chrono>
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
    using Traversal = FrustumTraversal2D<DenseStorage<2>>;
    static void checkGrid(const GridGeometry2& grid) {
        for (int a = 0; a < 2; ++a)
            if (grid.resolution()[a] > kMaxShadowExtent)
                throw InvalidInput("grid.resolution", "at most " + std::to_string(kMaxShadowExtent) +
                                                          " voxels per axis in 2D, got " +
                                                          std::to_string(grid.resolution()[a]));
    }
    template <class OnVoxel>
    static void traverse(Traversal& t, const GridGeometry2& grid, DenseStorage<2>& storage, const View& view,
                         std::uint32_t stamp, const CullerOptions& options, CullStats& st, OnVoxel&& onVoxel) {
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
    using Traversal = FrustumTraversal3D<DenseStorage<3>>;
    static void checkGrid(const GridGeometry3&) {}
    template <class OnVoxel>
    static void traverse(Traversal& t, const GridGeometry3& grid, DenseStorage<3>& storage, const View& view,
                         std::uint32_t stamp, const CullerOptions& options, CullStats& st, OnVoxel&& onVoxel) {
        TraversalOptions3D topt;
        topt.occlusion = options.occlusion;
        topt.exponentialCaps = options.occluderExtension;
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
    }
};

} // namespace

template <int D> struct Culler<D>::Impl {
    using Traits = CullerTraits<D>;

    struct Record {
        ObjectId id = 0;
        Shape<D> local;           // voxel units, as rasterized into I and O
        Box<D> localBounds;
        double worldMagnitude = 0; // largest |coordinate| of the world-unit bounds
        bool isStatic = false;
        bool outsideGrid = false; // partly or wholly outside: also tested against the view region
        bool alive = false;
        double maxSpeed = 0;
    };

    GridGeometry<D> grid;
    CullerOptions options;
    DenseStorage<D> storage;
    typename Traits::Traversal traversal;
    std::vector<Record> records;
    std::vector<ObjectSlot> freeSlots;
    std::unordered_map<ObjectId, ObjectSlot> slotOf;
    std::vector<std::uint32_t> pvsStamp; // per slot: frame in which it was added to the PVS
    std::uint32_t outsideCount = 0;
    std::uint32_t frame = 0;
    CullResult result;

    Impl(const GridGeometry<D>& g, const CullerOptions& o) : grid(g), options(o), storage(g) {}

    void rasterize(ObjectSlot slot, int sign) {
        const Record& r = records[slot];
        const IVec<D> res = grid.resolution();
        // The slack covers the world-to-voxel rounding of the object's coordinates (and the grid's).
        const double slack = grid.conversionSlack(r.worldMagnitude);
        forEachTouchedVoxel<D>(
            r.local, res,
            [&](const IVec<D>& v) {
                const VoxelKey key = grid.linearIndex(v);
                if (sign > 0) storage.addId(key, slot);
                else storage.removeId(key, slot);
            },
            slack);
        forEachInnerVoxel<D>(
            r.local, res, [&](const IVec<D>& v) { storage.addOpaque(grid.linearIndex(v), sign); }, slack);
    }

    /// The footprint of a placed object: its touched (I) and inner (O) voxels, in increasing key order
    /// (the rasterizers emit rows in increasing order, x fastest, as linearIndex counts).
    void footprint(const Record& r, std::vector<VoxelKey>& touched, std::vector<VoxelKey>& inner) const {
        touched.clear();
        inner.clear();
        const IVec<D> res = grid.resolution();
        const double slack = grid.conversionSlack(r.worldMagnitude);
        forEachTouchedVoxel<D>(r.local, res, [&](const IVec<D>& v) { touched.push_back(grid.linearIndex(v)); }, slack);
        forEachInnerVoxel<D>(r.local, res, [&](const IVec<D>& v) { inner.push_back(grid.linearIndex(v)); }, slack);
    }

    /// Moves an object by writing only the difference between its old and new footprints: a sphere that
    /// moves a fraction of a voxel changes a thin shell of its footprint, not all of it (profiling the
    /// moving-spheres benchmark showed remove-all/add-all updates as its largest cost).
    void move(ObjectSlot slot, const Shape<D>& world) {
        footprint(records[slot], oldTouched, oldInner);
        setPlacement(slot, world);
        footprint(records[slot], newTouched, newInner);
        diff(oldTouched, newTouched, [&](VoxelKey k) { storage.removeId(k, slot); },
             [&](VoxelKey k) { storage.addId(k, slot); });
        diff(oldInner, newInner, [&](VoxelKey k) { storage.addOpaque(k, -1); },
             [&](VoxelKey k) { storage.addOpaque(k, +1); });
    }

    /// Calls gone(k) for keys only in `before` and came(k) for keys only in `after` (both sorted).
    template <class Gone, class Came>
    static void diff(const std::vector<VoxelKey>& before, const std::vector<VoxelKey>& after, Gone&& gone, Came&& came) {
        std::size_t i = 0, j = 0;
        while (i < before.size() || j < after.size()) {
            if (j == after.size() || (i < before.size() && before[i] < after[j])) gone(before[i++]);
            else if (i == before.size() || after[j] < before[i]) came(after[j++]);
            else ++i, ++j;
        }
    }

    void place(ObjectSlot slot, const Shape<D>& world) {
        setPlacement(slot, world);
        rasterize(slot, +1);
    }

    void setPlacement(ObjectSlot slot, const Shape<D>& world) {
        Record& r = records[slot];
        const Box<D> wb = boundsOf<D>(world);
        r.worldMagnitude = 0;
        for (int a = 0; a < D; ++a)
            r.worldMagnitude = std::max(r.worldMagnitude, std::max(std::abs(wb.min[a]), std::abs(wb.max[a])));
        r.local = toLocal<D>(world, grid);
        r.localBounds = boundsOf<D>(r.local);
        const bool outside = extendsOutsideGrid<D>(r.local, grid.resolution());
        outsideCount += std::uint32_t(outside) - std::uint32_t(r.outsideGrid && r.alive);
        r.outsideGrid = outside;
    }

    // Footprint buffers reused by every move (no allocation per update after warm-up).
    std::vector<VoxelKey> oldTouched, oldInner, newTouched, newInner;

    void addToPvs(ObjectSlot slot) {
        if (pvsStamp[slot] == frame) return;
        pvsStamp[slot] = frame;
        result.pvs.push_back(records[slot].id);
    }

    void nextFrame() {
        if (++frame == 0) { // the stamps wrapped: pay one full clear every 2^32 - 1 frames
            storage.resetStamps();
            std::fill(pvsStamp.begin(), pvsStamp.end(), 0);
            frame = 1;
        }
    }
};

template <int D> Culler<D>::Culler(const GridGeometry<D>& grid, const CullerOptions& options) {
    Impl::Traits::checkGrid(grid);
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

    ObjectSlot slot;
    if (!m.freeSlots.empty()) {
        slot = m.freeSlots.back();
        m.freeSlots.pop_back();
    } else {
        slot = ObjectSlot(m.records.size());
        m.records.emplace_back();
        m.pvsStamp.push_back(0);
    }
    typename Impl::Record& r = m.records[slot];
    r = typename Impl::Record{};
    r.id = object.id;
    r.isStatic = object.isStatic;
    r.maxSpeed = object.maxSpeed;
    m.place(slot, shape);
    r.alive = true;
    m.slotOf.emplace(object.id, slot);
}

template <int D> void Culler<D>::updateObject(ObjectId id, const Shape<D>& shape) {
    Impl& m = *m_impl;
    auto it = m.slotOf.find(id);
    if (it == m.slotOf.end()) throw InvalidInput("object " + std::to_string(id) + ".id", "unknown id");
    Shape<D> validated = shape;
    try {
        validateShape<D>(validated, "object"); // the id is spelled out only if there is an error to report
    } catch (const InvalidInput& e) {
        const std::string what = e.what();
        throw InvalidInput("object " + std::to_string(id) + e.field().substr(6), what.substr(e.field().size() + 2));
    }
    m.move(it->second, validated);
}

template <int D> void Culler<D>::removeObject(ObjectId id) {
    Impl& m = *m_impl;
    auto it = m.slotOf.find(id);
    if (it == m.slotOf.end()) throw InvalidInput("object " + std::to_string(id) + ".id", "unknown id");
    const ObjectSlot slot = it->second;
    m.rasterize(slot, -1);
    typename Impl::Record& r = m.records[slot];
    if (r.outsideGrid) --m.outsideCount;
    r.alive = false;
    r.outsideGrid = false;
    m.freeSlots.push_back(slot);
    m.slotOf.erase(it);
}

template <int D> const CullResult& Culler<D>::cull(const Camera<D>& camera) {
    validateCamera<D>(camera);
    Impl& m = *m_impl;
    const typename Impl::Traits::View view(camera, m.grid); // may throw (3D: up parallel to direction)
    const auto t0 = std::chrono::steady_clock::now();
    m.nextFrame();
    m.result.pvs.clear();
    CullStats& st = m.result.stats;
    st = CullStats{};
    st.objectCount = std::uint32_t(m.slotOf.size());

    if (m.grid.containsLocal(view.apex())) {
        Impl::Traits::traverse(m.traversal, m.grid, m.storage, view, m.frame, m.options, st,
                               [&](VoxelKey key, const IVec<D>&) {
                                   m.storage.forEachId(key, [&](ObjectSlot slot) { m.addToPvs(slot); });
                               });
        // Objects reaching outside the grid may be seen through the part the grid does not hold: they are
        // tested against the view region only.
        if (m.outsideCount > 0) {
            for (ObjectSlot s = 0; s < m.records.size(); ++s) {
                const typename Impl::Record& r = m.records[s];
                if (r.alive && r.outsideGrid && view.touchesBox(r.localBounds.min, r.localBounds.max)) m.addToPvs(s);
            }
        }
    } else {
        // The grid's occlusion is only valid for cameras inside it: view-region test for every object.
        st.fallback = Fallback::CameraOutsideGrid;
        st.occlusionSkipped = true;
        for (ObjectSlot s = 0; s < m.records.size(); ++s) {
            const typename Impl::Record& r = m.records[s];
            if (r.alive && view.touchesBox(r.localBounds.min, r.localBounds.max)) m.addToPvs(s);
        }
    }
    st.objectsOutsideGrid = m.outsideCount;
    std::sort(m.result.pvs.begin(), m.result.pvs.end());
    st.pvsSize = std::uint32_t(m.result.pvs.size());
    st.cullMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return m.result;
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
    return s;
}

template class Culler<2>;
template class Culler<3>;

} // namespace rgvc
