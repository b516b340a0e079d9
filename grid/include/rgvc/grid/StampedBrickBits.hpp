// StampedBrickBits: a set of voxels that holds for one frame, kept as one stamped bit set per brick; and
// FrameMarks, V (the voxels a frame's traversal visited) and U (those a fused occluder box covers) as two
// such sets, the part of the storage concept both storages implement alike.
#pragma once

#include "rgvc/grid/Math.hpp"
#include "rgvc/grid/ZeroedArray.hpp"

#include <algorithm>
#include <cstdint>

namespace rgvc {

namespace brick_bits_detail {
__extension__ using U128 = unsigned __int128; // (a GCC and Clang extension; -Wpedantic accepts it so marked)
} // namespace brick_bits_detail

/// A set of voxels that holds for one frame, kept per brick of 8^D voxels (the brick walks' bricks): the
/// brick's stamp and its voxels' bits, relative to the brick's first voxel (3D: eight slice words, bit
/// x + 8 y of word z; 2D: one word, bit x + 8 y). A brick's bits hold only for the frame of its stamp, so
/// a frame starts with the set empty in O(1). Stamps are 1..0xFFFF (0: never); the owner calls reset()
/// before a stamp repeats.
///
/// Why per brick. V was one stamped word per brick row, and a brick walk wrote 64 of them per brick, each
/// in a cache line of its own (a brick's rows are a grid row apart): 1.6-4 % of the 3D scene classes'
/// instructions and 10-15 % of their cache misses, for a matrix that in the brick walks' frames only
/// Culler::voxelState reads. A walk now writes a brick's visited voxels in one call (nine stores in 3D).
/// Per-voxel writers and readers (the per-voxel traversals, voxelState) find the brick from a voxel key
/// with two multiplications (fastDivide below) instead of divisions.
template <int D> class StampedBrickBits {
public:
    static constexpr int kWords = D == 3 ? 8 : 1;

    StampedBrickBits() = default;
    /// [Limit] res: the grid's resolution, each axis in [1, 2^31 - 1], at most 2^32 - 1 voxels in all.
    explicit StampedBrickBits(const IVec<D>& res) : m_res(res) {
        for (int a = 0; a < D; ++a) m_bricks[a] = ((res[a] - 1) >> 3) + 1;
        const std::size_t bricks = cellCount<D>(m_bricks);
        m_divX = divider(std::uint32_t(res.x));
        m_divY = divider(std::uint32_t(res.y));
        m_stamps = ZeroedArray<std::uint16_t>(bricks);
        m_bits = ZeroedArray<std::uint64_t>(bricks * kWords);
    }

    /// ORs `words` (kWords of them, in the layout above) into brick `brick`'s bits for frame `stamp`.
    void orBrick(const IVec<D>& brick, const std::uint64_t* words, std::uint32_t stamp) {
        const std::size_t b = brickIndex(brick);
        const bool fresh = m_stamps[b] == stamp;
        std::uint64_t* bits = &m_bits[b * kWords];
        for (int i = 0; i < kWords; ++i) bits[i] = (fresh ? bits[i] : 0) | words[i];
        m_stamps[b] = std::uint16_t(stamp);
    }
    /// Whether voxel k (the grid's linear index) is in the set of frame `stamp`.
    bool voxel(std::uint32_t k, std::uint32_t stamp) const {
        std::size_t b;
        int word, bit;
        locate(k, b, word, bit);
        return m_stamps[b] == stamp && ((m_bits[b * kWords + std::size_t(word)] >> bit) & 1) != 0;
    }
    /// Adds voxel k to the set of frame `stamp`.
    void setVoxel(std::uint32_t k, std::uint32_t stamp) {
        std::size_t b;
        int word, bit;
        locate(k, b, word, bit);
        std::uint64_t* bits = &m_bits[b * kWords];
        if (m_stamps[b] != stamp)
            for (int i = 0; i < kWords; ++i) bits[i] = 0;
        bits[word] |= std::uint64_t(1) << bit;
        m_stamps[b] = std::uint16_t(stamp);
    }
    /// The 8 bits of the brick row through voxel v in frame `stamp` (bit i: voxel (v.x & ~7) + i of the row).
    /// Out of line: inlined into the 3D walk's row loops, it tipped GCC into calling the culler's PVS
    /// push_back out of line (+0.7 % instructions on the clusters); a call per opaque brick row is less.
    [[gnu::noinline]] std::uint32_t rowBits(const IVec<D>& v, std::uint32_t stamp) const {
        const std::size_t b = brickIndex(v >> 3);
        if (m_stamps[b] != stamp) return 0;
        const std::size_t word = b * kWords + std::size_t(D == 3 ? (v[D - 1] & 7) : 0);
        return std::uint32_t(m_bits[word] >> (8 * (v.y & 7))) & 0xFFu;
    }
    /// Adds the voxels of the box [lo, hi] (inclusive; in the grid) to the set of frame `stamp`: per brick
    /// it meets, the box's part of a slice is one word (a byte per row it covers, the row's x mask in each),
    /// ORed into the slices it covers (most boxes, the insides of small movers, meet one brick). Out of
    /// line: once per fused box, whose growth costs far more than the call.
    [[gnu::noinline]] void orBox(const IVec<D>& lo, const IVec<D>& hi, std::uint32_t stamp) {
        const IVec<D> b0 = lo >> 3, b1 = hi >> 3;
        IVec<D> b = b0;
        while (true) {
            // The box's part along each axis in brick b: a..e (0..7).
            IVec<D> a, e;
            for (int k = 0; k < D; ++k) {
                a[k] = std::max(lo[k] - 8 * b[k], 0);
                e[k] = std::min(hi[k] - 8 * b[k], 7);
            }
            const std::uint64_t mx = ((2u << e.x) - 1u) & ~((1u << a.x) - 1u);
            const std::uint64_t rows = (0x0101010101010101ULL >> (8 * (7 - (e.y - a.y)))) << (8 * a.y); // bit 8 y, y in a.y..e.y
            const std::uint64_t slice = rows * mx; // mx in each of those bytes: no carries (mx < 256)
            const std::size_t first = brickIndex(b);
            std::uint64_t* bits = &m_bits[first * kWords];
            if (m_stamps[first] != stamp) {
                for (int i = 0; i < kWords; ++i) bits[i] = 0;
                m_stamps[first] = std::uint16_t(stamp);
            }
            if constexpr (D == 3) {
                for (std::int32_t z = a.z; z <= e.z; ++z) bits[z] |= slice;
            } else {
                bits[0] |= slice;
            }
            // The next brick, x fastest.
            int k = 0;
            while (k < D && b[k] == b1[k]) b[k] = b0[k], ++k;
            if (k == D) break;
            ++b[k];
        }
    }
    /// Every stamp back to "never".
    void reset() { m_stamps.clear(); }
    void adviseHugePages() {
        m_stamps.adviseHugePages();
        m_bits.adviseHugePages();
    }
    void touch() {
        m_stamps.touch();
        m_bits.touch();
    }

private:
    /// n / d for every 32-bit n as ((M n) >> 64) with M = floor((2^64 - 1) / d) + 1 (Lemire, Kaser and
    /// Kurz, "Faster remainder by direct computation", 2019, for divisors 2 to 2^32 - 1; d = 1, whose M
    /// would be 2^64, is M = 0 here and divides by returning n). Hand-written: three lines, where a
    /// library (libdivide) would be a dependency for them.
    static std::uint64_t divider(std::uint32_t d) { return d == 1 ? 0 : ~std::uint64_t(0) / d + 1; }
    static std::uint32_t fastDivide(std::uint32_t n, std::uint64_t m) {
        return m == 0 ? n : std::uint32_t((static_cast<brick_bits_detail::U128>(m) * n) >> 64);
    }
    std::size_t brickIndex(const IVec<D>& brick) const { return cellIndex<D>(m_bricks, brick); }
    /// Voxel k's brick, its word in the brick and its bit in the word.
    void locate(std::uint32_t k, std::size_t& b, int& word, int& bit) const {
        const std::uint32_t row = fastDivide(k, m_divX), x = k - row * std::uint32_t(m_res.x);
        IVec<D> v;
        v.x = std::int32_t(x);
        if constexpr (D == 3) {
            const std::uint32_t z = fastDivide(row, m_divY);
            v.y = std::int32_t(row - z * std::uint32_t(m_res.y));
            v.z = std::int32_t(z);
        } else {
            v.y = std::int32_t(row);
        }
        b = brickIndex(v >> 3);
        word = D == 3 ? (v[D - 1] & 7) : 0;
        bit = (v.x & 7) + 8 * (v.y & 7);
    }

    IVec<D> m_res{1};
    IVec<D> m_bricks{1};
    std::uint64_t m_divX = 0, m_divY = 0;
    ZeroedArray<std::uint16_t> m_stamps; // per brick; 0: never
    ZeroedArray<std::uint64_t> m_bits;   // kWords per brick
};

/// V and U (VoxelStorage.hpp's matrices) as the storage concept reads and writes them: the part that
/// DenseStorage and the culler's per-view ViewStorage implement alike, so both derive from it.
template <int D> class FrameMarks {
public:
    using Coord = IVec<D>; // integer coordinates: of a voxel, or of a brick of 8^D voxels (setBrickVisited)

    explicit FrameMarks(const IVec<D>& res) : m_visited(res), m_used(res) {}

    /// Whether voxel k (the grid's linear index) was visited in frame stamp; marks it.
    bool visited(std::uint32_t k, std::uint32_t stamp) const { return m_visited.voxel(k, stamp); }
    void setVisited(std::uint32_t k, std::uint32_t stamp) { m_visited.setVoxel(k, stamp); }
    /// Marks the voxels of brick `brick` (its first voxel is 8 brick) given by `words` visited in frame
    /// stamp, the others keeping their marks. words: 8 slice words in 3D (bit x + 8 y of word z, relative
    /// to the brick), one in 2D (bit x + 8 y).
    void setBrickVisited(const Coord& brick, const std::uint64_t* words, std::uint32_t stamp) { m_visited.orBrick(brick, words, stamp); }
    /// Whether voxel k is part of an occluder box drawn in frame stamp; marks it.
    bool used(std::uint32_t k, std::uint32_t stamp) const { return m_used.voxel(k, stamp); }
    void setUsed(std::uint32_t k, std::uint32_t stamp) { m_used.setVoxel(k, stamp); }
    /// U's bits of the brick row through voxel v (bit i: voxel (v.x & ~7) + i) in frame stamp.
    std::uint32_t usedBits(const Coord& v, std::uint32_t stamp) const { return m_used.rowBits(v, stamp); }
    /// Marks the voxels of the box [lo, hi] (inclusive, in the grid) used in frame stamp.
    void markUsedBox(const Coord& lo, const Coord& hi, std::uint32_t stamp) { m_used.orBox(lo, hi, stamp); }

protected:
    void resetMarks() {
        m_visited.reset();
        m_used.reset();
    }
    void adviseMarksHugePages() {
        m_visited.adviseHugePages();
        m_used.adviseHugePages();
    }
    void touchMarks() {
        m_visited.touch();
        m_used.touch();
    }

private:
    StampedBrickBits<D> m_visited; // V
    StampedBrickBits<D> m_used;    // U
};

} // namespace rgvc
