// Culler<D>: object bookkeeping (I and O) and the per-frame cull over the dense storage. The same code
// serves 2D and 3D; only the view region and the traversal differ (ViewWedge + FrustumTraversal2D,
// ViewFrustum + FrustumTraversal3D), chosen by CullerTraits.
// This file: the public members and the per-frame driver (Impl::cull); the rest of Impl is declared in
// CullerImpl.hpp and defined by concept in ObjectTable.cpp, TbvPolicy.cpp, BrickPass.cpp, BufferPass.cpp
// and ViewPass.cpp (the view pass cull() shares with cullViews()).
#include "rgvc/dynamics/Culler.hpp"

#include "CullerImpl.hpp"
#include "rgvc/grid/SimdGuard.hpp"

#include <stdexcept>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <new>
#include <utility>

namespace rgvc {

namespace {
// Takes grid/src/SimdGuard.cpp (the AVX2 start-up check of an RGVC_SIMD build) into every program that
// links the culler: a static library's object file is linked only when one of its symbols is used.
[[gnu::used]] const int* const s_simdGuard = &detail::kSimdGuardAnchor;
} // namespace

const char* toString(Fallback f) {
    switch (f) {
    case Fallback::None: return "none";
    case Fallback::CameraOutsideGrid: return "camera_outside_grid";
    case Fallback::Orthographic: return "orthographic";
    case Fallback::OrthographicOcclusion: return "orthographic-occlusion";
    }
    return "unknown";
}

const char* toString(ObjectRole r) {
    switch (r) {
    case ObjectRole::Both: return "both";
    case ObjectRole::Occludee: return "occludee";
    case ObjectRole::Occluder: return "occluder";
    }
    return "unknown";
}

/// CullerOptions::adaptiveCaps: after a frame, how many of the next frames start without caps.
template <int D> void Culler<D>::Impl::scheduleCaps(const CullStats& st) {
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

template <int D> void Culler<D>::Impl::nextFrame() {
    ++frameIndex;
    if (++frame > DenseStorage<D>::kMaxStamp) { // past the stamps' range: one full clear, every 65,535 frames
        storage.resetStamps();
        std::fill(main.pvsStamp.begin(), main.pvsStamp.end(), 0);
        std::fill(main.classifiedStamp.begin(), main.classifiedStamp.end(), 0);
        std::fill(main.drawnStamp.begin(), main.drawnStamp.end(), 0);
        frame = 1;
    }
}

template <int D> const CullResult& Culler<D>::Impl::cull(const Camera<D>& camera, const PlacementQuery<D>* placementOf) {
    validateCamera<D>(camera);
    const bool ortho = camera.projection == Projection::Orthographic;
    const typename Traits::View view = ortho ? typename Traits::View() : typename Traits::View(camera, grid); // may throw (3D: up parallel to direction)
    const OrthoVolume<D> volume = ortho ? OrthoVolume<D>(camera, grid) : OrthoVolume<D>();
    const auto t0 = std::chrono::steady_clock::now();
    nextFrame();
    beginView(main);
    CullStats& st = main.result.stats;
    st.objectCount = std::uint32_t(slotOf.size());
    query = placementOf;
    queryException = nullptr;
    invalidField.clear();
    writes = 0;

    // An orthographic frame has no camera point: no new TBVs, and the next perspective frame checks
    // every TBV against its camera (havePrevCamera false), as after a camera outside the grid.
    const bool cameraIn = !ortho && grid.containsLocal(view.apex());
    const IVec<D> cameraVoxel = glm::clamp(GridGeometry<D>::voxelOfLocal(view.apex()), IVec<D>(0), grid.resolution() - 1);
    updateScene(cameraIn, std::span<const IVec<D>>(&cameraVoxel, cameraIn ? 1 : 0), st);
    st.updateMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (ortho) orthoPass(main, volume);
    else cullView(main, view, cameraIn);
    havePrevCamera = cameraIn;
    prevCameras.assign(1, cameraVoxel);
    query = nullptr;

    st.objectsOutsideGrid = std::uint32_t(outside.size());
    st.trackedObjects = std::uint32_t(tracked.size());
    st.hiddenObjects = std::uint32_t(hidden.size());
    st.parkedObjects = std::uint32_t(parked.size());
    st.gridWrites = writes;
    st.tbvMatrixAllocated = tbvs.allocated();
    st.cullMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (queryException) std::rethrow_exception(std::exchange(queryException, nullptr));
    if (!invalidField.empty()) throw InvalidInput(invalidField, invalidWhat);
    return main.result;
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
    if (options.traversalImageRows < 0 || options.traversalImageRows > OcclusionBuffer3D::kMaxExtent)
        throw InvalidInput("options.traversalImageRows", "must be in [0, " + std::to_string(OcclusionBuffer3D::kMaxExtent) +
                                                              "], got " + std::to_string(options.traversalImageRows));
    if (options.traversalImageBins < 0 || options.traversalImageBins > OcclusionBuffer2D::kMaxBins)
        throw InvalidInput("options.traversalImageBins", "must be in [0, " + std::to_string(OcclusionBuffer2D::kMaxBins) +
                                                              "], got " + std::to_string(options.traversalImageBins));
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
/// The Impl behind a public call, with the two ways to misuse the API made errors: a moved-from culler
/// (no Impl), and a call from inside the placement query, which runs in the middle of cull() (objects
/// being classified, the PVS half built; a removeObject there left a ghost id in the PVS for good).
template <int D> typename Culler<D>::Impl& Culler<D>::checked(const char* what, bool allowedInQuery) const {
    if (!m_impl) throw std::logic_error(std::string("rgvc::Culler::") + what + ": the culler was moved from");
    if (m_impl->inQuery && !allowedInQuery)
        throw std::logic_error(std::string("rgvc::Culler::") + what +
                               ": called from inside the placement query (it may call only hasObject, objectCount, "
                               "grid and options)");
    return *m_impl;
}

template <int D> Culler<D>::~Culler() = default;
template <int D> Culler<D>::Culler(Culler&&) noexcept = default;
template <int D> Culler<D>& Culler<D>::operator=(Culler&&) noexcept = default;

template <int D> const GridGeometry<D>& Culler<D>::grid() const { return checked("grid", true).grid; }
template <int D> const CullerOptions& Culler<D>::options() const { return checked("options", true).options; }
template <int D> bool Culler<D>::hasObject(ObjectId id) const { return checked("hasObject", true).slotOf.count(id) != 0; }
template <int D> std::size_t Culler<D>::objectCount() const { return checked("objectCount", true).slotOf.size(); }
template <int D> std::vector<ObjectDesc<D>> Culler<D>::objects() const {
    const Impl& m = checked("objects");
    std::vector<ObjectDesc<D>> out;
    out.reserve(m.slotOf.size());
    for (const typename Impl::Record& r : m.records)
        if (r.alive) out.push_back({r.id, r.at.world, r.isStatic, r.maxSpeed, r.inset, r.role});
    std::sort(out.begin(), out.end(), [](const ObjectDesc<D>& a, const ObjectDesc<D>& b) { return a.id < b.id; });
    return out;
}
template <int D> const CullResult& Culler<D>::lastResult() const { return checked("lastResult").main.result; }

/// Issue 13: "a mesh that is not closed can only be an occludee and says so". An open mesh is a surface: it
/// has no interior, so it gets no O and hides nothing. Given a role that promises occlusion (Both, Occluder)
/// it would quietly hide nothing, which a level designer's non-watertight building would not show until
/// something behind it was drawn: refused with the reason instead. (A placement query's open mesh for such
/// an object is not refused: that shape is the same object's, and hiding nothing stays sound.)
template <int D> static void checkMeshRole(const Shape<D>& shape, ObjectRole role, const std::string& field) {
    if constexpr (D == 3) {
        const auto* m = std::get_if<MeshSolid>(&shape);
        if (m == nullptr || m->closed() || role == ObjectRole::Occludee) return;
        const MeshTopology& t = m->model()->topology;
        throw InvalidInput(field + ".role", "an open mesh hides nothing (" + std::to_string(t.boundaryEdges) + " boundary, " +
                                                std::to_string(t.nonManifoldEdges) + " non-manifold, " +
                                                std::to_string(t.misorientedEdges) +
                                                " misoriented edges): give it role Occludee, or close the mesh");
    }
}

template <int D> void Culler<D>::addObject(const ObjectDesc<D>& object) {
    Impl& m = checked("addObject");
    const std::string field = "object " + std::to_string(object.id);
    if (m.slotOf.count(object.id)) throw InvalidInput(field + ".id", "duplicate id");
    if (!std::isfinite(object.maxSpeed) || object.maxSpeed < 0)
        throw InvalidInput(field + ".max_speed", "must be finite and >= 0");
    if (!std::isfinite(object.occluderInset) || object.occluderInset < 0)
        throw InvalidInput(field + ".occluder_inset", "must be finite and >= 0");
    if (object.role != ObjectRole::Both && object.role != ObjectRole::Occludee && object.role != ObjectRole::Occluder)
        throw InvalidInput(field + ".role", "must be Both, Occludee or Occluder");
    Shape<D> shape = object.shape;
    validateShape<D>(shape, field);
    checkMeshRole<D>(shape, object.role, field);
    typename Impl::Placement p = m.makePlacement(shape, object.occluderInset, object.role);

    ObjectSlot slot;
    if (!m.freeSlots.empty()) {
        slot = m.freeSlots.back();
        m.freeSlots.pop_back();
    } else {
        slot = ObjectSlot(m.records.size());
        m.records.emplace_back();
        m.main.pvsStamp.push_back(0);
        m.statePos.push_back(kNone);
        m.outsidePos.push_back(kNone);
        m.faceTbvs.addSlot();
        m.main.classifiedStamp.push_back(0);
        m.main.drawnStamp.push_back(0);
        m.footprints.emplace_back();
    }
    typename Impl::Record& r = m.records[slot];
    r = typename Impl::Record{};
    r.id = object.id;
    r.maxSpeed = object.maxSpeed;
    r.inset = object.occluderInset;
    r.role = object.role;
    r.isStatic = object.isStatic;
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
    Impl& m = checked("updateObject");
    auto it = m.slotOf.find(id);
    if (it == m.slotOf.end()) throw InvalidInput("object " + std::to_string(id) + ".id", "unknown id");
    Shape<D> validated = shape;
    validateShape<D>(validated, [&] { return "object " + std::to_string(id); });
    const ObjectSlot slot = it->second;
    typename Impl::Record& r = m.records[slot];
    checkMeshRole<D>(validated, r.role, "object " + std::to_string(id));
    typename Impl::Placement p = m.makePlacement(validated, r.inset, r.role);
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
    Impl& m = checked("removeObject");
    auto it = m.slotOf.find(id);
    if (it == m.slotOf.end()) throw InvalidInput("object " + std::to_string(id) + ".id", "unknown id");
    const ObjectSlot slot = it->second;
    m.detach(slot);
    m.records[slot].alive = false;
    m.freeSlots.push_back(slot);
    m.slotOf.erase(it);
}

template <int D> const CullResult& Culler<D>::cull(const Camera<D>& camera) { return checked("cull").cull(camera, nullptr); }

template <int D> const CullResult& Culler<D>::cull(const Camera<D>& camera, const PlacementQuery<D>& placementOf) {
    Impl& m = checked("cull");
    if (!placementOf) throw InvalidInput("placementOf", "must be callable");
    return m.cull(camera, &placementOf);
}

template <int D> VoxelState Culler<D>::voxelState(const IVec<D>& v) const {
    const Impl& m = checked("voxelState");
    VoxelState s;
    if (!m.grid.contains(v)) return s;
    const VoxelKey key = m.grid.linearIndex(v);
    s.inGrid = true;
    s.opaque = m.storage.opaque(key);
    s.occluded = m.frame != 0 && m.storage.occluded(key, m.frame);
    s.visited = m.frame != 0 && m.storage.visited(key, m.frame);
    // The brick walk keeps no H: a voxel it did not read that lies in view and is hidden in its final image
    // from the camera point (a voxel it read lay in a node the image did not hide when the walk reached it).
    if (m.main.imageKept && !s.visited) {
        const Vec<D> lo(v), hi = Vec<D>(v) + 1.0;
        s.occluded = m.main.imageView.touchesBox(lo, hi) && m.main.traversalImage.hidden(Box<D>{lo, hi}, m.main.imageView.slack());
    }
    s.occluder = m.frame != 0 && m.storage.used(key, m.frame);
    if (m.idsInI) {
        s.hasIds = m.storage.hasIds(key);
    } else if constexpr (D == 3) {
        // No per-voxel ids (CullerImpl.hpp, idsInI): the objects listed in the voxel's brick whose touched
        // voxels (the footprint I would hold) include it. For pictures and tests: one rasterization each.
        RowFootprint f;
        for (ObjectSlot slot : m.brickObjects.at(v >> BrickPyramid<D>::kBrickShift)) {
            const typename Impl::Record& r = m.records[slot];
            f.build<D>(r.at.local, nullptr, m.grid, m.grid.conversionSlack(r.at.worldMagnitude));
            if (f.touches(key, m.grid.resolution().x)) {
                s.hasIds = true;
                break;
            }
        }
    }
    s.hasTbv = m.tbvs.holdsAt(v);
    return s;
}

// Culler<D>'s explicit instantiation also instantiates the members of its member class Impl that this
// file defines (cull, scheduleCaps, nextFrame); naming them again is a duplicate for clang.
template class Culler<2>;
template class Culler<3>;

} // namespace rgvc
