// Culler<D>::Impl, the occlusion buffer's pass (OcclusionBuffer2D.hpp, OcclusionBuffer3D.hpp): after the
// grid traversal, the grid's PVS is tested nearest first against an image of the objects kept so far, so
// clouds of objects smaller than a voxel, which leave O empty, still hide what is behind them. Only the
// reported PVS shrinks (CullerOptions::occlusionBufferRows, occlusionBufferBins).
#include "CullerImpl.hpp"

#include "rgvc/grid/DistanceSort.hpp"

#include <algorithm>
#include <cassert>
#include <chrono>
#include <variant>

namespace rgvc {

/// The occlusion buffer's pass over the grid's PVS (OcclusionBuffer3D.hpp): nearest first, each object
/// with a current placement is tested against the image of the nearer ones kept, and drawn into it when
/// it stays. Shapes are grown (tests) or shrunk (drawing) by their conversion slack and the camera's.
/// Parked objects have no current placement: they stay and occlude nothing. Only result.pvs changes.
template <int D>
template <class S, class View>
void Culler<D>::Impl::refineWithBuffer(ViewScratch<S>& vs, const View& view, CullStats& st) {
    auto& occlusionBuffer = vs.occlusionBuffer;
    bool inherited = false; // CullerOptions::bufferFromTraversalImage: begun from the walk's image
    auto& bufferOrder = vs.bufferOrder;
    auto& bufferShapes = vs.bufferShapes;
    auto& pvsStamp = vs.pvsStamp;
    // Either form of the pass ends here: the objects whose pvsStamp it cleared leave result.pvs (the
    // others' stamps stay), and its counts and time go to the statistics. result.pvs holds the ids of
    // pvsSlots' entries that are reported (not occluders only), in their order (addToPvs). When that is
    // all of them (no occluder-only object in view), it is compacted in place without reading a record:
    // each read was a cache miss (2 % of the clusters' time in perf).
    auto finish = [&](std::uint32_t tested, std::uint32_t removed, std::chrono::steady_clock::time_point t0) {
        if (removed != 0) {
            auto& pvs = vs.result.pvs;
            const bool everyReported = pvs.size() == vs.pvsSlots.size();
            std::size_t in = 0, out = 0;
            for (const ObjectSlot slot : vs.pvsSlots) {
                const bool kept = pvsStamp[slot] == vs.stamp;
                if (everyReported || records[slot].role != ObjectRole::Occluder) {
                    if (kept) pvs[out++] = pvs[in];
                    ++in;
                }
                if (!kept) pvsStamp[slot] = vs.stamp; // back to "in this frame's grid PVS"
            }
            assert(in == pvs.size());
            pvs.resize(out);
        }
        st.bufferTested = tested;
        st.bufferHidden = removed;
        st.bufferMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    };
    if constexpr (D == 2) {
        // CullerOptions::bufferFromTraversalImage in 2D. The walk drew every object it kept into its
        // angular image, whatever its size, besides O's fused boxes (classify, BrickTraversal2D.hpp), so
        // the finished image already holds everything a fresh buffer would draw, at bins at least as fine
        // (when they are). What the walk let through that the image now hides is what it classified before
        // a nearer occluder was drawn (its order is the bricks', not the distances'): each kept object is
        // tested once more against the finished image; nothing is drawn and nothing sorted. Sound as the
        // walk's own tests are: every bin depth is a true bound, and an object's own draw never hides it
        // (its entries are no nearer than its grown shape's nearest point, and a bin hides only when
        // strictly nearer). The test is the walk's own, refinement included: without it an object the walk
        // met after its occluders (a refined verdict) and one met before them (an unrefined one) could end
        // differently, and the PVS would depend on the order the objects were added (18 of 3,000 random
        // scenes replayed from a dump, test_scene_file's round trip, differed; none with it). Against the
        // fresh buffer below (rgvc_bench_classes, README "Scene classes"): 3-5 % fewer instructions on the
        // 2D city and random scenes, 1-2 % on the room and the large world; |PVS| within 0.5 %.
        if (options.bufferFromTraversalImage && vs.imageKept && vs.traversalImage.bins() >= Traits::bufferSize(options)) {
            const auto t0 = std::chrono::steady_clock::now();
            std::uint32_t removed = 0, tested = 0;
            for (ObjectSlot slot : vs.pvsSlots) {
                const Record& r = records[slot];
                if (r.state != State::Tracked && r.state != State::Static) continue;
                ++tested;
                const double slack = grid.conversionSlack(r.at.worldMagnitude) + view.slack();
                if (vs.traversalImage.hidden(r.at.local, slack)) {
                    pvsStamp[slot] = 0; // marks it for removal; the grid's verdict (lastPvsFrame) stays
                    ++removed;
                }
            }
            finish(tested, removed, t0);
            return;
        }
    }
    {
        const auto t0 = std::chrono::steady_clock::now();
        if constexpr (D == 3) {
            // The walk drew the large occluders (walls, buildings) into its image; the pass inherits them
            // at a finer resolution instead of drawing them again (each of its pixels starts at the depth
            // of the walk's pixel that contains it: a true bound, OcclusionBuffer3D::beginRefined).
            if (options.bufferFromTraversalImage && vs.imageKept) {
                const int rows = vs.traversalImage.rows(), want = Traits::bufferSize(options);
                inherited = occlusionBuffer.beginRefined(vs.traversalImage, std::max(1, (want + rows - 1) / rows));
            }
        }
        if (!inherited && !occlusionBuffer.begin(view, Traits::bufferSize(options))) return;
        // One pass over the records (large, scattered: each read is a cache miss) copies what the buffer
        // needs; the sort then moves 16-byte keys, and the test-and-draw pass reads the copies in order.
        bufferOrder.clear();
        // The entries of earlier frames are overwritten, not destroyed and made again: a ball or box
        // over one of its kind is a plain copy (assignShape), where clear() and emplace_back() cost two
        // variant visits per object (2 % of the clusters' instructions).
        std::uint32_t shapes = 0;
        const auto& pvsSlots = vs.pvsSlots;
        for (std::size_t k = 0; k < pvsSlots.size(); ++k) {
            if (k + kRecordsAhead < pvsSlots.size()) prefetchRecordTests(pvsSlots[k + kRecordsAhead]);
            const ObjectSlot slot = pvsSlots[k];
            const Record& r = records[slot];
            if (r.state != State::Tracked && r.state != State::Static) continue;
            const double slack = grid.conversionSlack(r.at.worldMagnitude) + view.slack();
            bufferOrder.push_back({occlusionBuffer.nearestDistance(r.at.local, slack), shapes});
            const bool small = std::holds_alternative<Ball<D>>(r.at.local) || std::holds_alternative<Box<D>>(r.at.local);
            // Filled in place: a braced temporary of the variant made GCC 12 warn (maybe-uninitialized,
            // a false positive in std::variant's move) on every Release build.
            if (shapes == bufferShapes.size()) bufferShapes.emplace_back();
            BufferShape& shape = bufferShapes[shapes++];
            if (small) assignShape<D>(shape.small, r.at.local);
            shape.large = small ? nullptr : &r.at.local;
            shape.occluder = r.at.occluder();
            shape.slack = slack;
            shape.slot = slot;
        }
        // std::sort's order without its comparisons, half of whose branches mispredicted (DistanceSort.hpp).
        sortByDistance(bufferOrder, vs.bufferOrderScratch);
        // The occluders the walk drew are in the inherited image at its coarser resolution, whose depths
        // are a coarse pixel's largest entry: behind a wall seen at a grazing angle, or at a room's corner,
        // that can leave an object visible which the finer pixels would hide. Such an occluder is drawn
        // again over the object's pixels when an object behind it (farther by the sort key) whose image
        // may overlap its image (their outer pixel rectangles meet) fails its test, and the object is
        // tested again. The object's verdict is then what a fresh image with every kept object drawn
        // would give it: every occluder that fresh image would hold nearer than it and overlapping it is
        // drawn at full resolution over the pixels its test reads. Drawing more is always sound; the rectangle test only saves work. Beyond kMaxLazy such
        // occluders (a cloud of large spheres) the rectangle checks would cost more than they save: all
        // are drawn in sorted order, as in a fresh image.
        constexpr std::size_t kMaxLazy = 32;
        auto& lazy = vs.lazyOccluders;
        lazy.clear();
        if constexpr (D == 3) {
            if (inherited) {
                for (const auto& [distance, index] : bufferOrder) {
                    const BufferShape& b = bufferShapes[index];
                    if (b.occluder == nullptr || vs.drawnStamp[b.slot] != vs.stamp) continue;
                    lazy.push_back({occlusionBuffer.pixelRect(*b.occluder, 0.0), distance, index, false});
                }
                if (lazy.size() > kMaxLazy) lazy.clear();
            }
        }
        const bool lazyRedraw = inherited && !lazy.empty();
        auto redrawNearer = [&](const BufferShape& x, double distance) {
            bool any = false;
            if constexpr (D == 3) {
                // Drawn over the pixels the occludee's test can read only: its rectangle, grown by a pixel
                // (a footprint's padding can reach one further). A building redrawn for a small mover
                // behind it cost its whole image at the finer resolution (the game world: 24k
                // instructions per draw of the pass). An occluder whose rectangle lies inside is done.
                ImageFootprint3D::Rect r = occlusionBuffer.pixelRect(x.shape(), x.slack);
                r = {r.i0 - 1, r.i1 + 1, r.j0 - 1, r.j1 + 1};
                for (LazyOccluder& e : lazy) {
                    if (e.redrawn || !(e.nearest < distance)) continue;
                    if (e.rect.i0 > r.i1 || r.i0 > e.rect.i1 || e.rect.j0 > r.j1 || r.j0 > e.rect.j1) continue;
                    const BufferShape& o = bufferShapes[e.index];
                    occlusionBuffer.draw(*o.occluder, o.slack, r);
                    e.redrawn = r.i0 <= e.rect.i0 && e.rect.i1 <= r.i1 && r.j0 <= e.rect.j0 && e.rect.j1 <= r.j1;
                    any = true;
                }
            }
            return any;
        };
        // Only an object whose centre is already behind some occluder drawn (its centre's pixel, or the
        // border pixel nearest to a centre outside the image, covered nearer than the object's nearest
        // point) is one that sharper occluders may hide: an object seen through open space at its centre
        // stays visible whatever is drawn. (Centres outside the image matter: in the 100k room objects
        // poking into the view from beside it got through when they were not asked.) Occluders the walk
        // drew do not ask (their own coarse image covers their centre; they are in the PVS either way).
        auto coveredBehind = [&](const BufferShape& x, double distance) {
            if constexpr (D == 3) {
                if (vs.drawnStamp[x.slot] == vs.stamp) return false;
                return occlusionBuffer.coveredNearer(boundingBall<D>(x.shape()).center, distance);
            } else {
                return true;
            }
        };
        std::uint32_t removed = 0;
        for (std::size_t k = 0; k < bufferOrder.size(); ++k) {
            const auto [distance, index] = bufferOrder[k];
            // The entries are read in distance order, which is not the order they were written in: with
            // thousands of objects (240 bytes each) each read was a cache miss (the clusters' load of
            // an entry's slack took 40 % of this loop's own samples in perf). Its shape's first line
            // and the line of the variant's index, the pointers, the slack and the slot, asked for early.
            if (k + kRecordsAhead < bufferOrder.size()) {
                const char* next = reinterpret_cast<const char*>(&bufferShapes[bufferOrder[k + kRecordsAhead].second]);
                __builtin_prefetch(next);
                __builtin_prefetch(next + sizeof(BufferShape) - 1);
            }
            const BufferShape& b = bufferShapes[index];
            bool hides = occlusionBuffer.hidden(b.shape(), b.slack, distance);
            if (!hides && lazyRedraw && coveredBehind(b, distance) && redrawNearer(b, distance)) hides = occlusionBuffer.hidden(b.shape(), b.slack, distance);
            if (hides) {
                pvsStamp[b.slot] = 0; // marks it for removal below; the grid's verdict (lastPvsFrame) stays
                ++removed;
            } else if (b.occluder != nullptr && !(lazyRedraw && vs.drawnStamp[b.slot] == vs.stamp)) {
                occlusionBuffer.draw(*b.occluder, b.slack); // (an occluder the walk drew is drawn when needed)
            }
        }
        finish(occlusionBuffer.stats().tested, removed, t0);
    }
}

template void Culler<2>::Impl::refineWithBuffer(Culler<2>::Impl::MainScratch&, const ViewWedge&, CullStats&);
template void Culler<2>::Impl::refineWithBuffer(Culler<2>::Impl::SharedScratch&, const ViewWedge&, CullStats&);
template void Culler<3>::Impl::refineWithBuffer(Culler<3>::Impl::MainScratch&, const ViewFrustum&, CullStats&);
template void Culler<3>::Impl::refineWithBuffer(Culler<3>::Impl::SharedScratch&, const ViewFrustum&, CullStats&);

} // namespace rgvc
