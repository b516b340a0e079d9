// Per-brick lists of the objects held in O and I: the brick walk (BrickTraversal3D.hpp, onBrickIds) meets
// an object once per brick it reads instead of once per voxel of it. In the culler's brick core they are
// I itself, at brick resolution: objects are not written into I voxel by voxel there (CullerImpl.hpp,
// idsInI), and every reader of ids reads these lists.
//
// Why. The walk read every visited brick's 512 cells for their ids, and then the ids of every voxel in
// view (an object 5 voxels across holds a hundred voxels): the same reads view-frustum culling makes,
// about a seventh of a frame on rgvc_bench_classes' game world. A list per brick holds each object whose
// footprint may reach into the brick; it changes only when an object's box of bricks does, which for a
// mover of a few voxels at a fraction of a voxel per frame is every few dozen frames, while its voxels
// in I change every frame or two. (Per-brick masks of the id voxels, rebuilt where a write touched the
// brick, were tried first: movers touch most bricks in view every frame, so they were rebuilt as often
// as they were read.)
//
// What a list holds: the objects whose box of bricks contains the brick, the box being the bricks of the
// voxels that the object's bounds, grown by its conversion slack, can touch. It is a
// superset of the bricks its I footprint reaches (every voxel forEachTouchedVoxel gives lies in it), so
// an object with a voxel in a visited brick is in that brick's list; the walk classifies it by its own
// shape, so an object listed where none of its voxels is in view costs a classify() and no verdict.
// Exactly the rasterized objects are listed (the culler adds and removes them with their footprints in O
// and, where it keeps one, I), so a listed object is Tracked or Static, as an id in I is.
#pragma once

#include "rgvc/grid/BrickPyramid.hpp"
#include "rgvc/grid/GridGeometry.hpp"
#include "rgvc/grid/Shapes.hpp"
#include "rgvc/grid/VoxelStorage.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace rgvc {

/// A box of bricks, inclusive; empty when lo.x > hi.x.
template <int D> struct BrickBox {
    IVec<D> lo{0}, hi{-1};
    bool empty() const { return lo.x > hi.x; }
    friend bool operator==(const BrickBox&, const BrickBox&) = default;
};

template <int D> class BrickObjects {
public:
    explicit BrickObjects(const IVec<D>& res) : m_res(res) {
        std::size_t n = 1;
        for (int a = 0; a < D; ++a) {
            m_dims[a] = ((res[a] - 1) >> BrickPyramid<D>::kBrickShift) + 1;
            n *= std::size_t(m_dims[a]);
        }
        m_lists.resize(n);
    }

    /// The bricks an object with bounds `b` [voxel units] and conversion slack `slack` can reach in I.
    BrickBox<D> boxOf(const Box<D>& b, double slack) const {
        BrickBox<D> r;
        for (int a = 0; a < D; ++a) {
            // Voxel v (the closed [v, v + 1]) touches [lo, hi] when v <= hi and v + 1 >= lo: v from
            // ceil(lo) - 1 to floor(hi), and floor(lo - e) = ceil(lo) - 1 for any lo and a small e > 0;
            // e = 1e-6 voxel on both ends covers the rounding of the bounds and of the rasterizer (the
            // test against forEachTouchedVoxel puts shapes on voxel and brick faces). Clamped in double
            // first (huge or infinite bounds), empty when the bounds miss the grid.
            // (Truncation after the clamps is that floor: both are then >= 0. std::floor is a library call
            // on the baseline ISA, and this runs for every move.)
            const double lo = b.min[a] - slack - 1e-6, hi = b.max[a] + slack + 1e-6;
            if (!(hi >= 0) || !(lo < double(m_res[a]))) return {};
            const auto v0 = lo > 0 ? std::int32_t(lo) : 0, v1 = hi < double(m_res[a] - 1) ? std::int32_t(hi) : m_res[a] - 1;
            r.lo[a] = v0 >> BrickPyramid<D>::kBrickShift;
            r.hi[a] = v1 >> BrickPyramid<D>::kBrickShift;
        }
        return r;
    }

    void add(ObjectSlot slot, const BrickBox<D>& box) {
        forEach(box, [&](std::vector<ObjectSlot>& list) { list.push_back(slot); });
    }
    void remove(ObjectSlot slot, const BrickBox<D>& box) {
        forEach(box, [&](std::vector<ObjectSlot>& list) {
            const auto it = std::find(list.begin(), list.end(), slot);
            if (it == list.end()) return;
            *it = list.back();
            list.pop_back();
        });
    }
    /// The objects listed in brick b (brick coordinates inside the grid's bricks).
    const std::vector<ObjectSlot>& at(const IVec<D>& b) const { return m_lists[index(b)]; }

private:
    std::size_t index(const IVec<D>& b) const {
        std::size_t i = 0;
        for (int a = D - 1; a >= 0; --a) i = i * std::size_t(m_dims[a]) + std::size_t(b[a]);
        return i;
    }
    template <class Fn> void forEach(const BrickBox<D>& box, Fn&& fn) {
        if (box.empty()) return;
        IVec<D> b = box.lo;
        for (;;) {
            fn(m_lists[index(b)]);
            int a = 0;
            for (; a < D; ++a) {
                if (b[a] < box.hi[a]) {
                    ++b[a];
                    break;
                }
                b[a] = box.lo[a];
            }
            if (a == D) return;
        }
    }

    IVec<D> m_res, m_dims{0};
    std::vector<std::vector<ObjectSlot>> m_lists;
};

} // namespace rgvc
