// BrickPyramid<D>: the block hierarchy over a grid. Bricks of 8^D voxels are the leaves of an implicit
// 2^D-tree (an octree in 3D, a quadtree in 2D), and every node knows whether anything may lie below it.
//
// Why. The traversal's cost should follow the non-empty, visible part of the view, not its volume
// (DESIGN.md, "Work follows the visible, non-empty part of the view"): a region with no ids and no TBV
// adds nothing to the PVS and nothing to occlusion, so it is skipped as a block, and a node whose
// subtree is empty is skipped in O(1). The shape is that of OpenVDB's tree (8^3 leaves under internal
// nodes), so a sparse backend can answer the same questions from its child masks.
//
// What "occupied" means. A brick is marked occupied when ids (I, and with them O: an object's inner
// voxels are among its touched voxels) or a TBV are written into it. Marking is exact and eager; clearing
// is lazy: removals do not look at the brick (that would cost a scan per removal), so an occupied brick
// may in fact be empty. A traversal that reads such a brick finds it empty and calls markEmpty. So
// occupied(node) == false is a guarantee (nothing below), true is a hint. Conservative in the only
// direction that matters: an empty brick is never believed to hold something it does not, the other
// way round it costs one visit.
//
// Layout. Level 0 holds one flag per brick; level l > 0 holds, per node, the number of occupied children
// (at most 2^D). Node (l, c) covers bricks [c 2^l, (c + 1) 2^l) on each axis, clipped to the grid. The top
// level has a single node.
//
// Cost: a mark or clear walks up at most log2(bricks per axis) levels and stops at the first node whose
// count does not change between zero and non-zero. Memory: one byte per brick, and 4 bytes per node
// above the bricks (each level has 1/2^D of the nodes of the one below).
#pragma once

#include "rgvc/grid/Math.hpp"

#include <cstdint>
#include <vector>

namespace rgvc {

template <int D> class BrickPyramid {
public:
    static constexpr int kBrickShift = 3;             ///< bricks of 8^D voxels
    static constexpr std::int32_t kBrickSize = 1 << kBrickShift;

    BrickPyramid() = default;
    /// @param res  [Voxels] the grid's resolution (each axis >= 1).
    explicit BrickPyramid(const IVec<D>& res) {
        IVec<D> dims;
        for (int a = 0; a < D; ++a) dims[a] = ((res[a] - 1) >> kBrickShift) + 1;
        m_dims.push_back(dims);
        m_flags.assign(count(dims), 0);
        while (true) {
            bool single = true;
            for (int a = 0; a < D; ++a) single = single && dims[a] == 1;
            if (single && m_dims.size() > 1) break;
            if (single) { // a grid of one brick still gets a root above it (the traversal starts at a root)
                m_dims.push_back(dims);
                m_counts.emplace_back(1, 0);
                break;
            }
            for (int a = 0; a < D; ++a) dims[a] = (dims[a] + 1) >> 1;
            m_dims.push_back(dims);
            m_counts.emplace_back(count(dims), 0);
        }
    }

    /// Levels including the leaves (level 0) and the root (levels() - 1).
    int levels() const { return int(m_dims.size()); }
    /// Nodes per axis at a level.
    const IVec<D>& dims(int level) const { return m_dims[std::size_t(level)]; }
    /// Bricks per axis.
    const IVec<D>& bricks() const { return m_dims[0]; }

    /// Index of brick b (brick coordinates) in [0, brick count).
    std::size_t brickIndex(const IVec<D>& b) const { return index(m_dims[0], b); }

    /// False: no id and no TBV lies in the node's bricks (a guarantee). True: something may.
    bool occupied(int level, const IVec<D>& node) const {
        if (level == 0) return m_flags[index(m_dims[0], node)] != 0;
        return m_counts[std::size_t(level - 1)][index(m_dims[std::size_t(level)], node)] != 0;
    }

    /// Something was written into brick b.
    void markOccupied(const IVec<D>& b) {
        std::uint8_t& f = m_flags[index(m_dims[0], b)];
        if (f != 0) return;
        f = 1;
        IVec<D> node = b;
        for (std::size_t l = 0; l < m_counts.size(); ++l) {
            node = parentOf(node, l + 1);
            if (m_counts[l][index(m_dims[l + 1], node)]++ != 0) return; // the parent was occupied already
        }
    }
    /// Every brick meeting the voxel box [lo, hi] (inclusive, clipped by the caller to the grid).
    /// The bricks' flags are read along each row from one index, and only an unmarked brick takes the
    /// climb: every TBV made or renewed marks its box (the 100k room's 7,800 renewals a frame), and
    /// nearly all of its bricks are marked already (an index per brick cost the 100k room 2 % of its
    /// instructions; reading a row's flags as one word saved nothing more).
    void markOccupied(const IVec<D>& lo, const IVec<D>& hi) {
        const IVec<D> b0 = lo >> kBrickShift, b1 = hi >> kBrickShift;
        const IVec<D>& dims = m_dims[0];
        auto row = [&](IVec<D> b) { // bricks b0.x..b1.x of b's row
            const std::size_t first = index(dims, b);
            for (std::int32_t x = b0.x; x <= b1.x; ++x)
                if (m_flags[first + std::size_t(x - b0.x)] == 0) {
                    b.x = x;
                    markOccupied(b);
                }
        };
        if constexpr (D == 2) {
            for (std::int32_t y = b0.y; y <= b1.y; ++y) row(IVec<D>{b0.x, y});
        } else {
            for (std::int32_t z = b0.z; z <= b1.z; ++z)
                for (std::int32_t y = b0.y; y <= b1.y; ++y) row(IVec<D>{b0.x, y, z});
        }
    }
    /// A traversal read brick b and found nothing in it.
    void markEmpty(const IVec<D>& b) {
        std::uint8_t& f = m_flags[index(m_dims[0], b)];
        if (f == 0) return;
        f = 0;
        IVec<D> node = b;
        for (std::size_t l = 0; l < m_counts.size(); ++l) {
            node = parentOf(node, l + 1);
            if (--m_counts[l][index(m_dims[l + 1], node)] != 0) return;
        }
    }

    /// Occupied bricks (for tests and stats; O(bricks)).
    std::size_t occupiedBricks() const {
        std::size_t n = 0;
        for (std::uint8_t f : m_flags) n += f;
        return n;
    }

private:
    static std::size_t count(const IVec<D>& d) { return cellCount<D>(d); }
    static std::size_t index(const IVec<D>& d, const IVec<D>& c) { return cellIndex<D>(d, c); }
    /// The parent at `level` of a node one level below (the top level of a one-brick grid is its copy).
    IVec<D> parentOf(const IVec<D>& node, std::size_t level) const {
        IVec<D> p = node >> 1;
        for (int a = 0; a < D; ++a)
            if (p[a] >= m_dims[level][a]) p[a] = m_dims[level][a] - 1;
        return p;
    }

    std::vector<IVec<D>> m_dims;                      // per level, nodes per axis
    std::vector<std::uint8_t> m_flags;                // level 0: brick occupied
    std::vector<std::vector<std::uint32_t>> m_counts; // levels 1..: occupied children per node
};

} // namespace rgvc
