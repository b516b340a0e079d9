// Culler<D>::Impl, occlusion for orthographic 3D views (orthoOcclusionView): the brick tree walked front
// to back along the parallel rays, with the parallel-ray occlusion image (OrthoOcclusionImage.hpp).
//
// Why a pass of its own. The perspective walk's facts are about rays through the camera point (seed 004
// §4.4's shadows are cones from the apex; the depth image of OcclusionBuffer3D is indexed by direction),
// and none of them holds for parallel rays. The construction below is the same one with the apex moved
// to infinity behind the near plane: every ray is origin + u right + v up + t f, t >= 0.
//
//   1. Order (the analogue of §4.2's front-to-back layers and of BrickWalk's nearest-child order). The
//      brick tree is walked by walkBricks (BrickWalk.hpp) with the apex at infinity against f: on each
//      axis with f_a > 0 the child on the low side is near, with f_a < 0 the high side, with f_a = 0 either
//      (no ray crosses that split plane). A parallel ray crosses each split plane at most once, from the
//      near side to the far one, so BrickWalk's argument holds unchanged: no child is visited before one
//      that can lie in front of it along a ray.
//   2. Skipping (§4.2's occluded voxels, for nodes): a node is skipped when its box misses the view box
//      (OrthoVolume::touchesBox, exact) or when the image hides it (every pixel its outer footprint
//      touches holds a depth nearer than the node's nearest depth). A visible point p of an object lies
//      in a node that touches the view box and that the image cannot hide (the image only holds true
//      facts, and p's backward segment is unblocked), so the brick holding p is visited, and the object
//      (its I voxels include p's voxel; without I, the brick's list holds it) is met.
//   3. Occluders (§4.3-4.4 for parallel rays): each visited brick's opaque voxels (O: inside some
//      object's occluder model) are drawn as runs along x, boxes of up to 8 voxels; the occluder models of
//      the objects met are drawn too (sub-voxel exact, and the parts outside the grid), from 2 pixels of
//      bounding radius on (smaller ones cover no pixel entirely); a run inside a box object drawn so is
//      not drawn again.
//   4. Verdicts after the walk, when the image holds every occluder drawn (the order of 1. makes most of
//      them present when a node is tested; the verdicts wait for all): every object met, every object
//      reaching outside the grid (the image's facts hold for any point, in the grid or not) and every
//      revealed one is reported unless its exact shape misses the view box or the image hides it (a
//      ball as a ball, other shapes by their bounding box).
//   5. Hidden objects (TBVs). The perspective walk reveals a TBV when a visited voxel of its boundary is
//      visible, because a ray from the camera (outside the TBV) to a visible point of the object enters the
//      TBV through a visible boundary point. A parallel ray starts on the near plane, which may cut a TBV
//      (the ray then starts inside it), and with objectsStayInGrid a TBV is clipped at the grid, so the
//      ray may enter it through the grid's bound, where T stores nothing. So T is not read here: every
//      hidden object's TBV cube is tested as a box (against the view box and the finished image), and a
//      visible one is revealed (cull(): put back into O and I and classified like the others;
//      cullViews(): reported and revealed after all views). Sound without any condition on where the
//      near plane lies, at O(hidden objects) per orthographic view (stats.orthoTbvBoxTests).
// Parked objects are reported as everywhere.
#include "CullerImpl.hpp"

#include "rgvc/grid/BrickWalk.hpp"

#include <algorithm>
#include <cmath>
#include <variant>

namespace rgvc {

template <int D>
template <class S>
void Culler<D>::Impl::orthoOcclusionView(ViewScratch<S>& vs, const OrthoVolume<D>& volume) requires(D == 3) {
    CullStats& st = vs.result.stats;
    st.fallback = Fallback::OrthographicOcclusion;
    st.tbvLookupsSkipped = true; // T is not read (5. above)
    OrthoOcclusionImage& image = vs.orthoImage;
    const bool active = image.begin(volume, 1.0);
    const double viewSlack = volume.slack();
    const double pixel = image.pixelSize();
    std::vector<ObjectSlot>& met = vs.orthoMet;
    met.clear();
    auto meet = [&](ObjectSlot slot) {
        if (vs.classifiedStamp[slot] == vs.stamp) return;
        vs.classifiedStamp[slot] = vs.stamp;
        met.push_back(slot);
        const Record& r = records[slot];
        // 3. The object's occluder model, when it may cover pixels entirely.
        if (active && r.at.occludes && (r.state == State::Tracked || r.state == State::Static) &&
            boundingBall<D>(*r.at.occluder()).radius >= 2 * pixel)
            image.draw(*r.at.occluder(), grid.conversionSlack(r.at.worldMagnitude) + viewSlack);
    };

    // A run of opaque voxels inside a box object whose model was drawn (met in the run's first voxel,
    // large enough) repeats that box: not drawn again (inside buildings and walls, most runs are such).
    auto drawnBoxHolds = [&](VoxelKey seed, const IVec3& lo, const IVec3& hi) {
        bool inside = false;
        forEachObjectAt(seed, lo, [&](ObjectSlot slot) { // (seed is lo here: the run's first voxel)
            const Record& r = records[slot];
            const auto* b = std::get_if<Box<3>>(&r.at.local);
            if (inside || b == nullptr || !r.at.occludes || r.at.inset || (r.state != State::Tracked && r.state != State::Static)) return;
            if (boundingBall<3>(r.at.local).radius < 2 * pixel) return;
            inside = glm::all(glm::lessThanEqual(b->min, Vec3(lo))) && glm::all(glm::greaterThanEqual(b->max, Vec3(hi + 1)));
        });
        return inside;
    };

    // 1.-3. The walk.
    const Vec3 f = volume.axis(0);
    Vec3 apex = volume.origin();
    for (int a = 0; a < 3; ++a)
        if (f[a] != 0) apex[a] = f[a] > 0 ? -1e300 : 1e300;
    std::uint64_t hiddenNodes = 0, bricks = 0, voxels = 0;
    const IVec3 res = grid.resolution();
    const BrickWalkStats ws = walkBricks<3>(
        storage.bricks(), res, apex, vs.orthoStack,
        [&](const IVec3& lo, const IVec3& hi) {
            const Vec3 l(lo), h(hi);
            if (!volume.touchesBox(l, h)) return true;
            if (active && image.hiddenBox(l, h, viewSlack)) {
                ++hiddenNodes;
                return true;
            }
            return false;
        },
        [&](const IVec3& brick, const IVec3& lo, const IVec3& hi) {
            ++bricks;
            // Without ids in I, the brick's list (a superset of the objects with voxels in it) is met at
            // once; 4. judges each by its shape.
            if (!idsInI)
                for (ObjectSlot slot : brickObjects.at(brick)) meet(slot);
            for (std::int32_t z = lo.z; z < hi.z; ++z)
                for (std::int32_t y = lo.y; y < hi.y; ++y) {
                    const VoxelKey row = grid.linearIndex(IVec3{0, y, z});
                    std::int32_t runStart = -1;
                    for (std::int32_t x = lo.x; x <= hi.x; ++x) {
                        const bool opaque = x < hi.x && storage.opaque(row + VoxelKey(x));
                        if (x < hi.x) {
                            ++voxels;
                            if (idsInI) storage.forEachId(row + VoxelKey(x), [&](ObjectSlot slot) { meet(slot); });
                        }
                        if (opaque && runStart < 0) runStart = x;
                        if (!opaque && runStart >= 0) {
                            if (active && !drawnBoxHolds(row + VoxelKey(runStart), IVec3{runStart, y, z}, IVec3{x - 1, y, z}))
                                image.drawBox(Vec3(runStart, y, z), Vec3(x, y + 1, z + 1), viewSlack);
                            runStart = -1;
                        }
                    }
                }
        });

    // 4. Objects reaching outside the grid join the ones met (their occluders drawn too).
    for (std::size_t i = 0; i < outside.size(); ++i) meet(outside[i]);

    // 5. Hidden objects by their TBV cubes, against the finished image.
    vs.revealScratch.clear();
    for (std::size_t i = 0; i < hidden.size(); ++i) {
        const Record& r = records[hidden[i]];
        ++st.orthoTbvBoxTests;
        const Vec3 lo = r.tbv.centre - r.tbv.radius, hi = r.tbv.centre + r.tbv.radius;
        if (!volume.touchesBox(lo, hi)) continue;
        if (active && image.hiddenBox(lo, hi, viewSlack)) continue;
        vs.revealScratch.push_back(hidden[i]);
    }
    for (ObjectSlot slot : vs.revealScratch) { // revealing edits `hidden`: collected first
        if (records[slot].state != State::Hidden) continue;
        if constexpr (ViewScratch<S>::kShared) {
            tbvMet(vs, slot, st);
        } else {
            ++st.tbvsRevealed;
            records[slot].revealedFrame = frameIndex;
            if (reveal(slot, st)) meet(slot);
            else addToPvs(vs, slot); // parked
        }
    }

    // 4. The verdicts.
    for (ObjectSlot slot : met) {
        const Record& r = records[slot];
        if (r.state != State::Tracked && r.state != State::Static) {
            if (r.state == State::Parked) addToPvs(vs, slot);
            continue;
        }
        const double objectSlack = grid.conversionSlack(r.at.worldMagnitude);
        if (!volume.touchesShape(r.at.local, objectSlack)) continue;
        const Ball<3>* ball = std::get_if<Ball<3>>(&r.at.local);
        const bool hiddenInImage = ball ? image.hiddenBall(ball->center, ball->radius, objectSlack + viewSlack)
                                        : image.hiddenBox(r.at.localBounds.min, r.at.localBounds.max, objectSlack + viewSlack);
        if (active && hiddenInImage) {
            ++st.imageHidden;
            continue;
        }
        addToPvs(vs, slot);
    }
    for (std::size_t i = 0; i < parked.size(); ++i) addToPvs(vs, parked[i]);

    st.voxelsVisited = voxels;
    st.nodesVisited = ws.nodesVisited;
    st.nodesEmpty = ws.nodesEmpty;
    st.nodesHidden = hiddenNodes;
    st.bricksVisited = bricks;
    st.occlusionSkipped = !active || image.stats().occludersDrawn == 0;
    std::sort(vs.result.pvs.begin(), vs.result.pvs.end());
    st.pvsSize = std::uint32_t(vs.result.pvs.size());
}

template void Culler<3>::Impl::orthoOcclusionView(Culler<3>::Impl::MainScratch&, const OrthoVolume<3>&);
template void Culler<3>::Impl::orthoOcclusionView(Culler<3>::Impl::SharedScratch&, const OrthoVolume<3>&);

} // namespace rgvc
