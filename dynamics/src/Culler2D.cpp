// Culler<2>: object bookkeeping (I and O) and the per-frame cull over the dense storage.
#include "rgvc/dynamics/Culler.hpp"

#include "rgvc/grid/ConservativeRaster.hpp"
#include "rgvc/grid/FrustumTraversal2D.hpp"
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

template <> struct Culler<2>::Impl {
    struct Record {
        ObjectId id = 0;
        Shape<2> local;       // voxel units, as rasterized into I and O
        Box<2> localBounds;
        bool isStatic = false;
        bool outsideGrid = false; // partly or wholly outside: also tested against the view region
        bool alive = false;
        double maxSpeed = 0;
    };

    GridGeometry2 grid;
    CullerOptions options;
    DenseStorage<2> storage;
    FrustumTraversal2D<DenseStorage<2>> traversal;
    std::vector<Record> records;
    std::vector<ObjectSlot> freeSlots;
    std::unordered_map<ObjectId, ObjectSlot> slotOf;
    std::vector<std::uint32_t> pvsStamp; // per slot: frame in which it was added to the PVS
    std::uint32_t outsideCount = 0;
    std::uint32_t frame = 0;
    CullResult result;

    Impl(const GridGeometry2& g, const CullerOptions& o) : grid(g), options(o), storage(g) {}

    void rasterize(ObjectSlot slot, int sign) {
        const Record& r = records[slot];
        const IVec2 res = grid.resolution();
        forEachTouchedVoxel<2>(r.local, res, [&](const IVec2& v) {
            const VoxelKey key = grid.linearIndex(v);
            if (sign > 0) storage.addId(key, slot);
            else storage.removeId(key, slot);
        });
        forEachInnerVoxel<2>(r.local, res, [&](const IVec2& v) { storage.addOpaque(grid.linearIndex(v), sign); });
    }

    void place(ObjectSlot slot, const Shape<2>& world) {
        Record& r = records[slot];
        r.local = toLocal<2>(world, grid);
        r.localBounds = boundsOf<2>(r.local);
        const bool outside = extendsOutsideGrid<2>(r.local, grid.resolution());
        outsideCount += std::uint32_t(outside) - std::uint32_t(r.outsideGrid && r.alive);
        r.outsideGrid = outside;
        rasterize(slot, +1);
    }

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

template <> Culler<2>::Culler(const GridGeometry2& grid, const CullerOptions& options) {
    for (int a = 0; a < 2; ++a)
        if (grid.resolution()[a] > kMaxShadowExtent)
            throw InvalidInput("grid.resolution", "at most " + std::to_string(kMaxShadowExtent) +
                                                      " voxels per axis in 2D, got " + std::to_string(grid.resolution()[a]));
    try {
        m_impl = std::make_unique<Impl>(grid, options);
    } catch (const std::bad_alloc&) {
        throw InvalidInput("grid.resolution", "the grid's " + std::to_string(grid.voxelCount()) +
                                                  " voxels need more memory than is available");
    }
}
template <> Culler<2>::~Culler() = default;
template <> Culler<2>::Culler(Culler&&) noexcept = default;
template <> Culler<2>& Culler<2>::operator=(Culler&&) noexcept = default;

template <> const GridGeometry2& Culler<2>::grid() const { return m_impl->grid; }
template <> const CullerOptions& Culler<2>::options() const { return m_impl->options; }
template <> bool Culler<2>::hasObject(ObjectId id) const { return m_impl->slotOf.count(id) != 0; }
template <> std::size_t Culler<2>::objectCount() const { return m_impl->slotOf.size(); }
template <> const CullResult& Culler<2>::lastResult() const { return m_impl->result; }

template <> void Culler<2>::addObject(const ObjectDesc<2>& object) {
    Impl& m = *m_impl;
    const std::string field = "object " + std::to_string(object.id);
    if (m.slotOf.count(object.id)) throw InvalidInput(field + ".id", "duplicate id");
    if (!std::isfinite(object.maxSpeed) || object.maxSpeed < 0)
        throw InvalidInput(field + ".max_speed", "must be finite and >= 0");
    Shape<2> shape = object.shape;
    validateShape<2>(shape, field);

    ObjectSlot slot;
    if (!m.freeSlots.empty()) {
        slot = m.freeSlots.back();
        m.freeSlots.pop_back();
    } else {
        slot = ObjectSlot(m.records.size());
        m.records.emplace_back();
        m.pvsStamp.push_back(0);
    }
    Impl::Record& r = m.records[slot];
    r = Impl::Record{};
    r.id = object.id;
    r.isStatic = object.isStatic;
    r.maxSpeed = object.maxSpeed;
    m.place(slot, shape);
    r.alive = true;
    m.slotOf.emplace(object.id, slot);
}

template <> void Culler<2>::updateObject(ObjectId id, const Shape<2>& shape) {
    Impl& m = *m_impl;
    auto it = m.slotOf.find(id);
    const std::string field = "object " + std::to_string(id);
    if (it == m.slotOf.end()) throw InvalidInput(field + ".id", "unknown id");
    Shape<2> validated = shape;
    validateShape<2>(validated, field);
    m.rasterize(it->second, -1);
    m.place(it->second, validated);
}

template <> void Culler<2>::removeObject(ObjectId id) {
    Impl& m = *m_impl;
    auto it = m.slotOf.find(id);
    if (it == m.slotOf.end()) throw InvalidInput("object " + std::to_string(id) + ".id", "unknown id");
    const ObjectSlot slot = it->second;
    m.rasterize(slot, -1);
    Impl::Record& r = m.records[slot];
    if (r.outsideGrid) --m.outsideCount;
    r.alive = false;
    r.outsideGrid = false;
    m.freeSlots.push_back(slot);
    m.slotOf.erase(it);
}

template <> const CullResult& Culler<2>::cull(const Camera2& camera) {
    validateCamera<2>(camera);
    Impl& m = *m_impl;
    const auto t0 = std::chrono::steady_clock::now();
    m.nextFrame();
    m.result.pvs.clear();
    CullStats& st = m.result.stats;
    st = CullStats{};
    st.objectCount = std::uint32_t(m.slotOf.size());

    const ViewWedge wedge(camera, m.grid);
    if (m.grid.containsLocal(wedge.apex())) {
        TraversalOptions2D topt;
        topt.occlusion = m.options.occlusion;
        topt.extension = m.options.occluderExtension;
        const TraversalStats2D ts = m.traversal.run(m.grid, m.storage, wedge, m.frame, topt, [&](VoxelKey key, const IVec2&) {
            m.storage.forEachId(key, [&](ObjectSlot slot) { m.addToPvs(slot); });
        });
        st.layers = ts.layers;
        st.voxelsVisited = ts.voxelsVisited;
        st.voxelsOccluded = ts.voxelsOccluded;
        st.occludersExtended = ts.occludersExtended;
        st.occluderVoxels = ts.occluderVoxels;
        st.shadows = ts.shadows;
        st.voxelsMarkedOccluded = ts.voxelsMarkedOccluded;
        st.earlyTermination = ts.earlyTermination;
        st.occlusionSkipped = !ts.opaqueMet;
        // Objects reaching outside the grid may be seen through the part the grid does not hold: they are
        // tested against the view region only.
        if (m.outsideCount > 0) {
            for (ObjectSlot s = 0; s < m.records.size(); ++s) {
                const Impl::Record& r = m.records[s];
                if (r.alive && r.outsideGrid && wedge.touchesBox(r.localBounds.min, r.localBounds.max)) m.addToPvs(s);
            }
        }
        st.objectsOutsideGrid = m.outsideCount;
    } else {
        // The grid's occlusion is only valid for cameras inside it: view-region test for every object.
        st.fallback = Fallback::CameraOutsideGrid;
        st.occlusionSkipped = true;
        for (ObjectSlot s = 0; s < m.records.size(); ++s) {
            const Impl::Record& r = m.records[s];
            if (r.alive && wedge.touchesBox(r.localBounds.min, r.localBounds.max)) m.addToPvs(s);
        }
        st.objectsOutsideGrid = m.outsideCount;
    }
    std::sort(m.result.pvs.begin(), m.result.pvs.end());
    st.pvsSize = std::uint32_t(m.result.pvs.size());
    st.cullMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return m.result;
}

template <> VoxelState Culler<2>::voxelState(const IVec2& v) const {
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

} // namespace rgvc
