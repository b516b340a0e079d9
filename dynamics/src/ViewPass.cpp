// Culler<D>::Impl, one view's pass of a frame (cullView: the traversal, objects outside the grid, parked
// objects, the occlusion buffer), shared by cull() (one view over the scene's own stamps, TBVs revealed
// when met) and cullViews() (several views at once over their own stamps, the scene read-only, TBVs met
// revealed after all views in a fixed order; see the top of Culler.hpp for how the views combine).
#include "CullerImpl.hpp"

#include "rgvc/dynamics/TbbExecutor.hpp"

#include <algorithm>
#include <chrono>
#include <exception>
#include <new>
#include <string>
#include <utility>

namespace rgvc {

template <int D> template <class S> void Culler<D>::Impl::beginView(ViewScratch<S>& vs) {
    if constexpr (ViewScratch<S>::kShared) {
        if (++vs.stamp > S::kMaxStamp) { // the view's own stamps wrap like the scene's (nextFrame)
            vs.storage->resetStamps();
            std::fill(vs.pvsStamp.begin(), vs.pvsStamp.end(), 0);
            std::fill(vs.classifiedStamp.begin(), vs.classifiedStamp.end(), 0);
            std::fill(vs.drawnStamp.begin(), vs.drawnStamp.end(), 0);
            vs.stamp = 1;
        }
        vs.pvsStamp.resize(records.size(), 0);
        vs.classifiedStamp.resize(records.size(), 0);
        vs.drawnStamp.resize(records.size(), 0);
        vs.met.clear();
        vs.failure = nullptr;
    } else {
        vs.stamp = frame;
    }
    vs.result.pvs.clear();
    vs.pvsSlots.clear();
    vs.result.stats = CullStats{};
}

template <int D>
template <class S>
void Culler<D>::Impl::cullView(ViewScratch<S>& vs, const typename Traits::View& view, bool cameraIn) {
    constexpr bool shared = ViewScratch<S>::kShared;
    CullStats& st = vs.result.stats;
    vs.view = &view;
    vs.imageKept = false;
    if (cameraIn && options.hierarchical) {
        traverseBricks(vs, view, st);
    } else if (cameraIn) {
        st.tbvLookupsSkipped = hidden.empty();
        const bool deferCaps = !shared && D == 3 && options.adaptiveCaps && options.occlusion && capsSkip > 0;
        Traits::traverse(vs.traversal, grid, *vs.storage, view, vs.stamp, options, !hidden.empty(), deferCaps, st,
                         [&](VoxelKey key, const IVec<D>& v) {
            if (tbvs.liveRegions() != 0) {
                vs.revealScratch.clear();
                tbvs.collectAt(v, vs.revealScratch);
                for (ObjectSlot slot : vs.revealScratch) tbvMet(vs, slot, st);
            }
            storage.forEachId(key, [&](ObjectSlot slot) { addToPvs(vs, slot); });
        });
        if constexpr (!shared)
            if (D == 3 && options.adaptiveCaps && options.occlusion) scheduleCaps(st);
        // TBVs reaching past the grid, by the view region only (no image here); a revealed object reaching
        // outside the grid joins `outside`, which is tested next.
        revealFaceTbvs(vs, view, st);
        // Objects reaching outside the grid may be seen through the part the grid does not hold: they are
        // tested against the view region only.
        for (std::size_t i = 0; i < outside.size(); ++i) {
            const Record& r = records[outside[i]];
            if (view.touchesBox(r.at.localBounds.min, r.at.localBounds.max)) addToPvs(vs, outside[i]);
        }
    } else {
        // The grid's occlusion is only valid for cameras inside it: view-region test for every object, a
        // hidden one by its TBV (revealed if the TBV touches the view).
        st.fallback = Fallback::CameraOutsideGrid;
        testEveryObject(vs, [&](const Vec<D>& lo, const Vec<D>& hi) { return view.touchesBox(lo, hi); },
                        [&](const Record& r) { return view.touchesBox(r.at.localBounds.min, r.at.localBounds.max); }, st);
    }
    for (std::size_t i = 0; i < parked.size(); ++i) addToPvs(vs, parked[i]);
    vs.view = nullptr;
    // (The grid's verdict, lastPvsFrame, is written by addToPvs; cullViews writes it after all views.)

    if (options.occlusion && Traits::bufferSize(options) > 0 && vs.pvsSlots.size() > 1) {
        // CullerOptions::adaptiveBuffer (cull() only): a pass that hid under a tenth of what it tested
        // skips the next 1, 2, 4, then at most 8 frames; a pass that pays resets the schedule. Skipping
        // only leaves the grid's PVS as it is (a superset).
        const bool adaptive = !shared && options.adaptiveBuffer;
        if (adaptive && bufferSkip > 0) {
            --bufferSkip;
            st.bufferSkipped = true;
        } else {
            refineWithBuffer(vs, view, st);
            if (adaptive && st.bufferTested > 0 && st.bufferHidden * 10 < st.bufferTested) {
                bufferSkip = bufferBackoff;
                bufferBackoff = std::min<std::uint32_t>(2 * bufferBackoff, 8);
            } else if (adaptive) {
                bufferBackoff = 1;
            }
        }
    }
    std::sort(vs.result.pvs.begin(), vs.result.pvs.end());
    st.pvsSize = std::uint32_t(vs.result.pvs.size());
}

template <int D>
template <class S, class TouchesTbv, class TouchesObject>
void Culler<D>::Impl::testEveryObject(ViewScratch<S>& vs, TouchesTbv&& touchesTbv, TouchesObject&& touchesObject, CullStats& st) {
    st.occlusionSkipped = true;
    st.tbvLookupsSkipped = true;
    for (ObjectSlot s = 0; s < records.size(); ++s) {
        const Record& r = records[s];
        if (!r.alive) continue;
        if (r.state == State::Hidden) {
            if (!touchesTbv(r.tbv.centre - r.tbv.radius, r.tbv.centre + r.tbv.radius)) continue;
            if constexpr (ViewScratch<S>::kShared) {
                tbvMet(vs, s, st);
                continue;
            } else {
                ++st.tbvsRevealed;
                if (!reveal(s, st)) continue; // parked: reported with the parked ones
            }
        }
        if ((r.state == State::Tracked || r.state == State::Static) && touchesObject(r)) addToPvs(vs, s);
    }
}

template <int D> template <class S> void Culler<D>::Impl::orthoView(ViewScratch<S>& vs, const OrthoVolume<D>& volume) {
    CullStats& st = vs.result.stats;
    st.fallback = Fallback::Orthographic;
    // Objects by their exact shape, grown by their own conversion slack (the volume adds the camera's).
    testEveryObject(vs, [&](const Vec<D>& lo, const Vec<D>& hi) { return volume.touchesBox(lo, hi); },
                    [&](const Record& r) { return volume.touchesShape(r.at.local, grid.conversionSlack(r.at.worldMagnitude)); },
                    st);
    for (std::size_t i = 0; i < parked.size(); ++i) addToPvs(vs, parked[i]); // (lastPvsFrame: addToPvs)
    std::sort(vs.result.pvs.begin(), vs.result.pvs.end());
    st.pvsSize = std::uint32_t(vs.result.pvs.size());
}

template <int D>
const MultiCullResult& Culler<D>::Impl::cullViews(std::span<const Camera<D>> cameras, const PlacementQuery<D>* placementOf,
                                                  TaskExecutor* executor) {
    const std::size_t n = cameras.size();
    if (n == 0 || n > kMaxViews)
        throw InvalidInput("cameras", "must hold 1 to " + std::to_string(kMaxViews) + " cameras, got " + std::to_string(n));
    std::vector<typename Traits::View> regions(n);
    std::vector<OrthoVolume<D>> volumes(n);
    std::vector<char> ortho(n);
    for (std::size_t i = 0; i < n; ++i) {
        const std::string field = "cameras[" + std::to_string(i) + "]";
        validateCamera<D>(cameras[i], field);
        ortho[i] = cameras[i].projection == Projection::Orthographic;
        try {
            if (ortho[i]) volumes[i] = OrthoVolume<D>(cameras[i], grid);
            else regions[i] = typename Traits::View(cameras[i], grid);
        } catch (const InvalidInput& e) { // 3D: up parallel to direction
            throw InvalidInput(field + e.field().substr(e.field().find('.')), std::string(e.what()).substr(e.field().size() + 2));
        }
    }
    // View slots and their stamps before anything changes: running out of memory here leaves the scene as it was.
    try {
        while (views.size() < n) {
            auto v = std::make_unique<SharedScratch>();
            v->ownStorage = std::make_unique<ViewStorage<D>>(storage, grid.voxelCount());
            v->storage = v->ownStorage.get();
            views.push_back(std::move(v));
        }
        if (!executor && !defaultExecutor) defaultExecutor = std::make_unique<TbbExecutor>();
    } catch (const std::bad_alloc&) {
        throw InvalidInput("cameras", std::to_string(n) + " views need 6 bytes per voxel each (" +
                                          std::to_string(grid.voxelCount()) + " voxels): more memory than is available");
    }
    TaskExecutor& run = executor ? *executor : *defaultExecutor;

    const auto t0 = std::chrono::steady_clock::now();
    nextFrame();
    CullStats& sc = multiResult.scene;
    sc = CullStats{};
    sc.objectCount = std::uint32_t(slotOf.size());
    query = placementOf;
    queryException = nullptr;
    invalidField.clear();
    writes = 0;

    // 1. The scene update, once, under every camera's conditions: new TBVs only when every camera is a
    // perspective one in the grid; the camera condition for each perspective camera in the grid.
    std::vector<IVec<D>> voxels;
    std::vector<char> inside(n);
    bool allIn = true;
    for (std::size_t i = 0; i < n; ++i) {
        inside[i] = !ortho[i] && grid.containsLocal(regions[i].apex());
        allIn = allIn && inside[i];
        if (inside[i]) voxels.push_back(glm::clamp(GridGeometry<D>::voxelOfLocal(regions[i].apex()), IVec<D>(0), grid.resolution() - 1));
    }
    updateScene(allIn, voxels, sc);
    tbvs.freshen(); // lookups write nothing from here on: the passes may read T at once
    sc.updateMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

    // 2. The view passes, concurrently; each writes only its own scratch.
    for (std::size_t i = 0; i < n; ++i) beginView(*views[i]);
    run.parallelFor(n, [&](std::size_t i) {
        SharedScratch& vs = *views[i];
        const auto p0 = std::chrono::steady_clock::now();
        try {
            if (ortho[i]) orthoPass(vs, volumes[i]);
            else cullView(vs, regions[i], inside[i] != 0);
        } catch (...) { // bad_alloc growing a buffer: reported after all views
            vs.failure = std::current_exception();
        }
        vs.result.stats.cullMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - p0).count();
    });

    // 3. In view order: the grid's verdicts, then the reveals of every TBV some view met.
    for (std::size_t i = 0; i < n; ++i)
        for (ObjectSlot slot : views[i]->pvsSlots)
            if (records[slot].state != State::Hidden) records[slot].lastPvsFrame = frameIndex;
    for (std::size_t i = 0; i < n; ++i)
        for (ObjectSlot slot : views[i]->met) {
            Record& r = records[slot];
            if (!r.alive || r.state != State::Hidden) continue; // met by an earlier view too
            ++sc.tbvsRevealed;
            r.revealedFrame = frameIndex;
            reveal(slot, sc);
        }
    havePrevCamera = allIn;
    prevCameras = voxels;
    query = nullptr;

    sc.objectsOutsideGrid = std::uint32_t(outside.size());
    sc.trackedObjects = std::uint32_t(tracked.size());
    sc.hiddenObjects = std::uint32_t(hidden.size());
    sc.parkedObjects = std::uint32_t(parked.size());
    sc.gridWrites = writes;
    sc.tbvMatrixAllocated = tbvs.allocated();
    multiResult.views.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        CullResult& out = multiResult.views[i];
        std::swap(out, views[i]->result); // the scratch's vectors are reused by the next call
        out.stats.objectCount = sc.objectCount;
        out.stats.objectsOutsideGrid = sc.objectsOutsideGrid;
        out.stats.trackedObjects = sc.trackedObjects;
        out.stats.hiddenObjects = sc.hiddenObjects;
        out.stats.parkedObjects = sc.parkedObjects;
        out.stats.tbvMatrixAllocated = sc.tbvMatrixAllocated;
    }
    for (std::size_t i = 0; i < n; ++i)
        if (views[i]->failure) std::rethrow_exception(std::exchange(views[i]->failure, nullptr));
    sc.pvsSize = 0;
    for (const CullResult& v : multiResult.views) sc.pvsSize += v.stats.pvsSize;
    sc.cullMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (queryException) std::rethrow_exception(std::exchange(queryException, nullptr));
    if (!invalidField.empty()) throw InvalidInput(invalidField, invalidWhat);
    return multiResult;
}

template <int D>
const MultiCullResult& Culler<D>::cullViews(std::span<const Camera<D>> cameras, TaskExecutor* executor) {
    return checked("cullViews").cullViews(cameras, nullptr, executor);
}

template <int D>
const MultiCullResult& Culler<D>::cullViews(std::span<const Camera<D>> cameras, const PlacementQuery<D>& placementOf,
                                            TaskExecutor* executor) {
    Impl& m = checked("cullViews");
    if (!placementOf) throw InvalidInput("placementOf", "must be callable");
    return m.cullViews(cameras, &placementOf, executor);
}

template void Culler<2>::Impl::beginView(Culler<2>::Impl::MainScratch&);
template void Culler<3>::Impl::beginView(Culler<3>::Impl::MainScratch&);
template void Culler<2>::Impl::cullView(Culler<2>::Impl::MainScratch&, const ViewWedge&, bool);
template void Culler<3>::Impl::cullView(Culler<3>::Impl::MainScratch&, const ViewFrustum&, bool);
template void Culler<2>::Impl::orthoView(Culler<2>::Impl::MainScratch&, const OrthoVolume<2>&);
template void Culler<3>::Impl::orthoView(Culler<3>::Impl::MainScratch&, const OrthoVolume<3>&);
template const MultiCullResult& Culler<2>::cullViews(std::span<const Camera<2>>, TaskExecutor*);
template const MultiCullResult& Culler<3>::cullViews(std::span<const Camera<3>>, TaskExecutor*);
template const MultiCullResult& Culler<2>::cullViews(std::span<const Camera<2>>, const PlacementQuery<2>&, TaskExecutor*);
template const MultiCullResult& Culler<3>::cullViews(std::span<const Camera<3>>, const PlacementQuery<3>&, TaskExecutor*);

} // namespace rgvc
