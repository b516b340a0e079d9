// An object's footprint in I and O as one x span per voxel row, and the incremental update from one
// footprint to the next.
//
// Why spans: a moving object rewrites only the difference of its old and new footprints, and a sphere that
// moves a fraction of a voxel keeps nearly all its voxels. The rasterizer already works per row
// (ConservativeRaster.hpp: every shape is convex, so a row holds one span), so a footprint is a short
// list of (row, x0, x1), and two footprints differ row by row by at most two runs on each side: the diff
// costs O(rows) plus the voxels that really change, with no per-voxel list to build, sort or compare
// (the per-voxel key vectors were two thirds of the update time on the moving-spheres benchmark).
//
// Why cached: the culler keeps each object's footprint while the object is in I and O, so a move
// rasterizes only the new placement, and a removal takes out exactly the voxels that were put in.
//
// Several spans per row (a concave mesh's O, MeshSolid.hpp). The I part always has one span per row (a
// mesh's I is its convex hull's); the O part may hold several, ascending and disjoint. diff() then pairs
// the spans of a row in order and treats the unpaired ones as wholly gone or come. That is still exact
// for O, which holds counts (addOpaque +-1): per voxel v, a paired (A, B) contributes [v in B] - [v in A]
// (gone(A \ B), came(B \ A)), an unpaired A -[v in A], an unpaired B +[v in B]; summed over the row that
// is (new count of v) - (old count of v), because each side's spans are disjoint. No count goes below
// zero on the way: v is taken out at most once per old span holding it, while that span's +1 is still
// in. (For I, which holds id sets, pairing would not be exact; one span per row keeps it exact there.)
#pragma once

#include "rgvc/grid/ConservativeRaster.hpp"
#include "rgvc/grid/GridGeometry.hpp"
#include "rgvc/grid/Shapes.hpp"
#include "rgvc/grid/VoxelStorage.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace rgvc {

/// Voxels row + x0 .. row + x1 (linear keys), x0 <= x1; row is the linear key of the row's voxel x = 0.
struct RowSpan {
    VoxelKey row = 0;
    std::int32_t x0 = 0, x1 = -1;
    friend bool operator==(const RowSpan&, const RowSpan&) = default;
};

/// The touched (I) and inner (O) voxels of one placement, as spans in increasing row order.
class RowFootprint {
public:
    /// Rasterizes a shape given in voxel units (see forEachTouchedRow / forEachInnerRow): I from `local`,
    /// O from `inner` (the occluder model, contained in `local`; null: no O). Reuses the capacity it
    /// has: no allocation once it has held a footprint as large.
    /// @param touched  false: no I part (O only), for a culler that keeps its ids per brick instead
    ///                 (BrickObjects.hpp: the 3D brick walk); write and moveTo then touch O alone.
    template <int D>
    void build(const Shape<D>& local, const Shape<D>* inner, const GridGeometry<D>& grid, double slack, bool touched = true) {
        m_spans.clear();
        auto push = [&](const IVec<D>& row, std::int32_t x0, std::int32_t x1) {
            m_spans.push_back({grid.linearIndex(row), x0, x1});
        };
        if (touched) forEachTouchedRow<D>(local, grid.resolution(), push, slack);
        m_touched = std::uint32_t(m_spans.size());
        if (inner != nullptr) forEachInnerRow<D>(*inner, grid.resolution(), push, slack);
    }
    /// The shape is its own occluder model.
    template <int D> void build(const Shape<D>& local, const GridGeometry<D>& grid, double slack) {
        build<D>(local, &local, grid, slack);
    }

    /// Adds (sign > 0) or removes (sign < 0) the whole footprint of `slot`. Returns the voxels written.
    template <class S> std::uint64_t write(S& storage, ObjectSlot slot, int sign) const {
        std::uint64_t n = 0;
        for (std::size_t i = 0; i < m_spans.size(); ++i) {
            const RowSpan& s = m_spans[i];
            if (i < m_touched) {
                if (sign > 0) {
                    n += run(s.row, s.x0, s.x1, [&](VoxelKey k) { storage.addId(k, slot); });
                    noteAdded(storage, s.row, s.x0, s.x1);
                } else n += run(s.row, s.x0, s.x1, [&](VoxelKey k) { storage.removeId(k, slot); });
            } else {
                n += run(s.row, s.x0, s.x1, [&](VoxelKey k) { storage.addOpaque(k, sign); });
            }
        }
        return n;
    }

    /// Turns the storage's record of `slot` at this footprint into one at `next` by writing only the
    /// voxels that differ, then becomes a copy of `next`. The storage ends exactly as write(-1) then
    /// next.write(+1) would leave it (same I sets, same O counts). Returns the voxels written.
    template <class S> std::uint64_t moveTo(S& storage, ObjectSlot slot, const RowFootprint& next) {
        if (*this == next) return 0; // moved within the same voxels: the common case of a slow object
        const RowSpan* a = m_spans.data();
        const RowSpan* b = next.m_spans.data();
        std::uint64_t n = diff(a, a + m_touched, b, b + next.m_touched,
                               [&](VoxelKey k) { storage.removeId(k, slot); },
                               [&](VoxelKey k) { storage.addId(k, slot); },
                               [&](VoxelKey row, std::int32_t x0, std::int32_t x1) { noteAdded(storage, row, x0, x1); });
        n += diff(a + m_touched, a + m_spans.size(), b + next.m_touched, b + next.m_spans.size(),
                  [&](VoxelKey k) { storage.addOpaque(k, -1); }, [&](VoxelKey k) { storage.addOpaque(k, +1); },
                  [](VoxelKey, std::int32_t, std::int32_t) {});
        m_spans.assign(next.m_spans.begin(), next.m_spans.end()); // a copy, not a swap: no capacity drifts between objects
        m_touched = next.m_touched;
        return n;
    }

    /// Frees the spans (an object leaving I and O, e.g. hidden by a TBV, holds no memory here).
    void release() {
        std::vector<RowSpan>().swap(m_spans);
        m_touched = 0;
    }

    bool empty() const { return m_spans.empty(); }
    /// Whether the I part holds voxel `key` (one span per row, in row order: a binary search by row).
    bool touches(VoxelKey key, std::int32_t resX) const {
        const VoxelKey row = key - key % VoxelKey(resX);
        const auto end = m_spans.begin() + m_touched;
        const auto it = std::lower_bound(m_spans.begin(), end, row, [](const RowSpan& s, VoxelKey r) { return s.row < r; });
        const std::int32_t x = std::int32_t(key - row);
        return it != end && it->row == row && it->x0 <= x && x <= it->x1;
    }
    std::size_t touchedRows() const { return m_touched; }
    std::size_t innerRows() const { return m_spans.size() - m_touched; }

    friend bool operator==(const RowFootprint& a, const RowFootprint& b) {
        return a.m_touched == b.m_touched && a.m_spans == b.m_spans;
    }

private:
    /// Tells a storage with a block hierarchy (DenseStorage::noteIdsAdded) that ids came into a run.
    template <class S> static void noteAdded(S& storage, VoxelKey row, std::int32_t x0, std::int32_t x1) {
        if constexpr (requires { storage.noteIdsAdded(row, x0, x1); }) storage.noteIdsAdded(row, x0, x1);
    }

    template <class Fn> static std::uint64_t run(VoxelKey row, std::int32_t x0, std::int32_t x1, Fn&& fn) {
        for (std::int32_t x = x0; x <= x1; ++x) fn(VoxelKey(row + std::uint32_t(x)));
        return x1 >= x0 ? std::uint64_t(x1 - x0) + 1 : 0;
    }

    /// Calls gone(k) for the voxels of [a, aEnd) not in [b, bEnd) and came(k) for the converse; both are
    /// sorted by row with one span per row (for O, several are allowed: see the file comment). On a row held by both, with old span [a0, a1] and new [b0, b1],
    /// old \ new = [a0, min(a1, b0 - 1)] u [max(a0, b1 + 1), a1] (either part may be empty; disjoint spans
    /// leave all of [a0, a1] in exactly one part), and symmetrically for new \ old.
    /// cameRun(row, x0, x1) is called once for every non-empty run of came() calls.
    template <class Gone, class Came, class CameRun>
    static std::uint64_t diff(const RowSpan* a, const RowSpan* aEnd, const RowSpan* b, const RowSpan* bEnd, Gone&& gone,
                              Came&& came, CameRun&& cameRun) {
        auto comeRun = [&](VoxelKey row, std::int32_t x0, std::int32_t x1) {
            if (x0 <= x1) cameRun(row, x0, x1);
            return run(row, x0, x1, came);
        };
        std::uint64_t n = 0;
        while (a != aEnd || b != bEnd) {
            if (b == bEnd || (a != aEnd && a->row < b->row)) {
                n += run(a->row, a->x0, a->x1, gone);
                ++a;
            } else if (a == aEnd || b->row < a->row) {
                n += comeRun(b->row, b->x0, b->x1);
                ++b;
            } else {
                if (a->x0 != b->x0 || a->x1 != b->x1) {
                    n += run(a->row, a->x0, std::min(a->x1, b->x0 - 1), gone);
                    n += run(a->row, std::max(a->x0, b->x1 + 1), a->x1, gone);
                    n += comeRun(b->row, b->x0, std::min(b->x1, a->x0 - 1));
                    n += comeRun(b->row, std::max(b->x0, a->x1 + 1), b->x1);
                }
                ++a;
                ++b;
            }
        }
        return n;
    }

    std::vector<RowSpan> m_spans; // touched rows [0, m_touched), then inner rows; each part in row order
    std::uint32_t m_touched = 0;
};

} // namespace rgvc
