// Culler<D>::Impl, the object table: each object's placement (converted once to voxel units), its
// footprint in I and O (RowFootprint: a move writes only the difference), and which of the states it is in
// (Static, Tracked, Hidden, Parked; CullerImpl.hpp), with the sets and the list of objects reaching outside
// the grid kept in step. Also the per-frame placement query (fetch).
#include "CullerImpl.hpp"

#include "rgvc/grid/ConservativeRaster.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace rgvc {

template <int D> auto Culler<D>::Impl::makePlacement(const Shape<D>& world, double inset, ObjectRole role) const -> Placement {
    Placement p;
    makePlacementInto(p, world, inset, role);
    return p;
}

template <int D>
void Culler<D>::Impl::makePlacementInto(Placement& p, const Shape<D>& world, double inset, ObjectRole role) const {
    assignShape<D>(p.world, world);
    const Box<D> wb = boundsOf<D>(world);
    p.worldMagnitude = 0;
    for (int a = 0; a < D; ++a)
        p.worldMagnitude = std::max(p.worldMagnitude, std::max(std::abs(wb.min[a]), std::abs(wb.max[a])));
    // toLocal's result written over a ball or box of its kind as a plain struct, as assignShape does.
    if (const auto* b = std::get_if<Ball<D>>(&world); b != nullptr && std::holds_alternative<Ball<D>>(p.local))
        std::get<Ball<D>>(p.local) = toLocal<D>(*b, grid);
    else if (const auto* x = std::get_if<Box<D>>(&world); x != nullptr && std::holds_alternative<Box<D>>(p.local))
        std::get<Box<D>>(p.local) = toLocal<D>(*x, grid);
    else
        p.local = toLocal<D>(world, grid);
    p.localBounds = boundsOf<D>(p.local);
    p.kind = std::uint8_t(p.local.index());
    p.inset = false;
    p.occludes = true;
    if (role == ObjectRole::Occludee) {
        p.inset = true; // no occluder model at all
        p.occludes = false;
    } else if (inset > 0) {
        p.inset = true;
        p.occludes = insetShape<D>(p.local, grid.toLocalLength(inset), p.inner);
    }
    p.outsideGrid = extendsOutsideGrid<D>(p.local, grid.resolution());
}

/// Puts the object at its stored placement into I and O (sign > 0), or takes it out (sign < 0).
template <int D> void Culler<D>::Impl::rasterize(ObjectSlot slot, int sign) {
    RowFootprint& f = footprints[slot];
    Record& r = records[slot];
    if (sign > 0) {
        buildFootprint(r.at, f);
        writes += f.write(storage, slot, +1);
        if constexpr (D == 3) {
            r.listedIn = brickObjects.boxOf(r.at.localBounds, grid.conversionSlack(r.at.worldMagnitude));
            brickObjects.add(slot, r.listedIn);
            if (!idsInI) markListed(r.listedIn);
        }
    } else {
        writes += f.write(storage, slot, -1);
        f.release();
        if constexpr (D == 3) {
            brickObjects.remove(slot, r.listedIn);
            r.listedIn = {};
        }
    }
}

template <int D> void Culler<D>::Impl::buildFootprint(const Placement& p, RowFootprint& f) const {
    // The slack covers the world-to-voxel rounding of the object's coordinates (and the grid's).
    f.build<D>(p.local, p.occluder(), grid, grid.conversionSlack(p.worldMagnitude), idsInI);
}

/// Without ids in I (idsInI), the brick tree learns of an object from its list's box: every brick of it
/// is marked occupied (marking is eager, BrickPyramid.hpp), as writing its ids marked their bricks. The
/// walk clears a brick only when its list is empty, so a listed brick stays occupied.
template <int D> void Culler<D>::Impl::markListed(const BrickBox<D>& box) {
    if (box.empty()) return;
    constexpr int s = BrickPyramid<D>::kBrickShift;
    storage.bricks().markOccupied(box.lo << s, box.hi << s);
}

/// Moves a rasterized object by writing only the difference between its old (cached) and new
/// footprints: a sphere that moves a fraction of a voxel changes a thin shell of its footprint, or
/// nothing at all (profiling the moving-spheres benchmark showed remove-all/add-all updates, and then
/// per-voxel footprint lists, as its largest costs).
template <int D> void Culler<D>::Impl::moveRasterized(ObjectSlot slot, const Placement& p) {
    if (&p == &records[slot].at) return; // the stored placement: already rasterized
    buildFootprint(p, nextFootprint);
    writes += footprints[slot].moveTo(storage, slot, nextFootprint);
    if constexpr (D == 3) { // the brick lists change only when its box of bricks does (rarely, for a mover)
        Record& r = records[slot];
        const BrickBox<D> box = brickObjects.boxOf(p.localBounds, grid.conversionSlack(p.worldMagnitude));
        if (!(box == r.listedIn)) {
            brickObjects.remove(slot, r.listedIn);
            brickObjects.add(slot, box);
            if (!idsInI) markListed(box);
            r.listedIn = box;
        }
    }
    if (&p != &records[slot].at) records[slot].at.assign(p);
    syncOutside(slot);
}

/// Objects held in O and I that reach outside the grid are also tested against the view region.
template <int D> void Culler<D>::Impl::syncOutside(ObjectSlot slot) {
    const Record& r = records[slot];
    const bool want = r.alive && r.at.outsideGrid && (r.state == State::Tracked || r.state == State::Static);
    if (want != SlotSet::contains(slot, outsidePos)) {
        if (want) outside.insert(slot, outsidePos);
        else outside.erase(slot, outsidePos);
    }
}

template <int D> SlotSet* Culler<D>::Impl::setOf(State s) {
    switch (s) {
    case State::Tracked: return &tracked;
    case State::Hidden: return &hidden;
    case State::Parked: return &parked;
    default: return nullptr;
    }
}

template <int D> void Culler<D>::Impl::enter(ObjectSlot slot, State s) {
    records[slot].state = s;
    if (SlotSet* set = setOf(s)) set->insert(slot, statePos);
    syncOutside(slot);
}

/// Takes an object out of whatever holds it (O and I, T, or the parked list).
template <int D> void Culler<D>::Impl::detach(ObjectSlot slot) {
    Record& r = records[slot];
    if (r.state == State::Tracked || r.state == State::Static) rasterize(slot, -1);
    if (r.state == State::Hidden) dropTbv(slot);
    leaveState(slot);
}

/// Takes an object out of its state's set (its T, O and I parts already taken out): Detached.
template <int D> void Culler<D>::Impl::leaveState(ObjectSlot slot) {
    Record& r = records[slot];
    if (SlotSet* set = setOf(r.state)) set->erase(slot, statePos);
    r.state = State::Detached;
    syncOutside(slot);
}

template <int D> void Culler<D>::Impl::adopt(ObjectSlot slot, const Placement& p) {
    if (&p != &records[slot].at) records[slot].at.assign(p);
}

template <int D> void Culler<D>::Impl::attachTracked(ObjectSlot slot, const Placement& p) {
    adopt(slot, p);
    rasterize(slot, +1);
    enter(slot, State::Tracked);
}

/// Takes a hidden object's TBV out of T (and the faces' lists); its state and sets stay as they are.
template <int D> void Culler<D>::Impl::dropTbv(ObjectSlot slot) {
    Record& r = records[slot];
    writes += tbvs.erase(slot, r.tbv, options.tbvDiscretization);
    ++r.tbvGeneration; // its expiry entry, if any, is now stale
    if (r.tbvFaces != 0) faceTbvs.erase(slot, std::exchange(r.tbvFaces, std::uint8_t(0)));
}

template <int D>
void Culler<D>::Impl::attachHidden(ObjectSlot slot, const Placement& p, const TbvRegion<D>& region, std::uint64_t expiry) {
    placeTbv(slot, p, region, expiry);
    enter(slot, State::Hidden);
}

/// Adopts the placement and writes the new TBV into T, the brick tree's marks, the expiry buckets and the
/// faces' lists; the caller sets the state (attachHidden), or keeps it (a renewal: updateScene).
template <int D>
void Culler<D>::Impl::placeTbv(ObjectSlot slot, const Placement& p, const TbvRegion<D>& region, std::uint64_t expiry) {
    Record& r = records[slot];
    adopt(slot, p);
    r.tbv = region;
    r.tbvExpiry = expiry;
    writes += tbvs.insert(slot, region, options.tbvDiscretization);
    { // the brick tree must see the TBV (BrickPyramid: marking is eager)
        IVec<D> lo, hi;
        bool inGrid;
        if constexpr (D == 3) inGrid = tbvs.voxelBox(slot, lo, hi); // the box the insert just computed
        else inGrid = tbvVoxelBox<D>(region, grid.resolution(), lo, hi);
        if (inGrid) storage.bricks().markOccupied(lo, hi);
    }
    expiring[expiry % expiring.size()].emplace_back(slot, r.tbvGeneration);
    // Without the promise that objects stay in the grid, a TBV reaching past its bounds is also tested by
    // every view beyond them (FaceTbvs.hpp).
    if (!options.objectsStayInGrid) r.tbvFaces = faceTbvs.insert(slot, Box<D>{region.centre - region.radius, region.centre + region.radius}, grid.resolution());
}

/// The object's placement now, asking the application at most once per frame: the stored placement
/// (no query, or asked already) or a fresh one, valid until the next fetch. Null when the query threw
/// or returned an invalid shape: the failure is kept to be reported once the frame is done.
template <int D> auto Culler<D>::Impl::fetch(ObjectSlot slot, CullStats& st) -> const Placement* {
    Record& r = records[slot];
    if (query == nullptr || r.placedFrame == frameIndex) return &r.at;
    if (r.failedFrame == frameIndex) return nullptr; // asked once this frame already
    ++st.placementQueries;
    try {
        // While the application's code runs, Culler's members refuse to be called (checkedImpl).
        struct QueryScope {
            bool& flag;
            explicit QueryScope(bool& f) : flag(f) { flag = true; }
            ~QueryScope() { flag = false; }
        } scope(inQuery);
        Shape<D> s = (*query)(r.id);
        validateShape<D>(s, [&] { return "object " + std::to_string(r.id) + ".shape"; });
        makePlacementInto(fetched, s, r.inset, r.role);
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

template auto Culler<2>::Impl::makePlacement(const Shape<2>&, double, ObjectRole) const -> Placement;
template void Culler<2>::Impl::makePlacementInto(Placement&, const Shape<2>&, double, ObjectRole) const;
template void Culler<2>::Impl::rasterize(ObjectSlot, int);
template void Culler<2>::Impl::buildFootprint(const Placement&, RowFootprint&) const;
template void Culler<2>::Impl::moveRasterized(ObjectSlot, const Placement&);
template void Culler<2>::Impl::syncOutside(ObjectSlot);
template SlotSet* Culler<2>::Impl::setOf(State);
template void Culler<2>::Impl::enter(ObjectSlot, State);
template void Culler<2>::Impl::detach(ObjectSlot);
template void Culler<2>::Impl::adopt(ObjectSlot, const Placement&);
template void Culler<2>::Impl::attachTracked(ObjectSlot, const Placement&);
template void Culler<2>::Impl::attachHidden(ObjectSlot, const Placement&, const TbvRegion<2>&, std::uint64_t);
template void Culler<2>::Impl::placeTbv(ObjectSlot, const Placement&, const TbvRegion<2>&, std::uint64_t);
template void Culler<2>::Impl::dropTbv(ObjectSlot);
template void Culler<2>::Impl::leaveState(ObjectSlot);
template auto Culler<2>::Impl::fetch(ObjectSlot, CullStats&) -> const Placement*;
template auto Culler<3>::Impl::makePlacement(const Shape<3>&, double, ObjectRole) const -> Placement;
template void Culler<3>::Impl::makePlacementInto(Placement&, const Shape<3>&, double, ObjectRole) const;
template void Culler<3>::Impl::rasterize(ObjectSlot, int);
template void Culler<3>::Impl::buildFootprint(const Placement&, RowFootprint&) const;
template void Culler<3>::Impl::markListed(const BrickBox<3>&);
template void Culler<3>::Impl::moveRasterized(ObjectSlot, const Placement&);
template void Culler<3>::Impl::syncOutside(ObjectSlot);
template SlotSet* Culler<3>::Impl::setOf(State);
template void Culler<3>::Impl::enter(ObjectSlot, State);
template void Culler<3>::Impl::detach(ObjectSlot);
template void Culler<3>::Impl::adopt(ObjectSlot, const Placement&);
template void Culler<3>::Impl::attachTracked(ObjectSlot, const Placement&);
template void Culler<3>::Impl::attachHidden(ObjectSlot, const Placement&, const TbvRegion<3>&, std::uint64_t);
template void Culler<3>::Impl::placeTbv(ObjectSlot, const Placement&, const TbvRegion<3>&, std::uint64_t);
template void Culler<3>::Impl::dropTbv(ObjectSlot);
template void Culler<3>::Impl::leaveState(ObjectSlot);
template auto Culler<3>::Impl::fetch(ObjectSlot, CullStats&) -> const Placement*;

} // namespace rgvc
