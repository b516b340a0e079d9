// The storage interface of the grid matrices, and its dense implementation.
//
// The algorithms (traversal, occlusion, the culler) are templates over a type that models
// `VoxelStorage`, so the per-voxel calls inline; a sparse OpenVDB backend implements the same concept
// behind RGVC_WITH_OPENVDB without any OpenVDB type reaching a public header.
//
// Matrices (seed 004 §3):
//   O  opaque      a count of objects whose inner voxels include this voxel (O = count > 0). Counting,
//                  not a flag, makes removing one of two overlapping objects exact; static objects (Os)
//                  are counted in the same way, once.
//   H  occluded    a frame stamp: H(v) holds iff stamp(v) == current frame. Starting a frame clears H
//                  in O(1); stamps run up to S::kMaxStamp, and the user of the storage then calls
//                  resetStamps() (one full clear) and starts again at 1.
//   I  ids         per voxel, its only object slot stored in the cell, or a chain of 3-slot buckets drawn
//                  from one pool with a free list. After warm-up no insertion allocates. (The 3D brick
//                  core keeps I at brick resolution instead, BrickObjects.hpp, and writes none here.)
//   U  used        the voxels already part of an extended occluder this frame, so a wall of n opaque
//                  voxels is extended once, not n times; per brick, as V (a fused box marks its bricks).
//   T  TBVs        not here: T is read only at visited voxels and written only when TBVs change; it is
//                  counts and tile lists in 2D and a brick index in 3D, not a voxel matrix (TbvMatrix.hpp).
//   Os             O is maintained incrementally (objects add and remove their own inner voxels) and never
//                  rebuilt, so the paper's static occluder matrix is O's static part: a static object is
//                  counted in once and stays; there is nothing to copy from Os into O each frame.
//   V  visited     the voxels the traversal visited this frame (for pictures and voxelState), as one
//                  stamped bit set per brick (StampedBrickBits.hpp): a brick walk writes a brick's at once.
//
// Brick rows. The brick walks (BrickTraversal2D/3D.hpp) read and write whole rows of a brick, the 8 voxels
// x = 8 bx .. 8 bx + 7 of one grid row, as bit words: O's flags (opaqueBits, stored so), and U's bits of a
// brick row (usedBits, read from U's brick). O's word w = rowIndex * ceil(res.x / 8) + bx, where rowIndex is the row's key / res.x (y in 2D, y + res.y z in
// 3D), and bit i is voxel x = 8 bx + i. Why words: reading a brick voxel by voxel for O and writing V voxel
// by voxel was a third of the walk (rgvc_bench_classes' game world: 512 reads and writes per brick, for a
// brick that holds a few spheres); as words a brick costs 64 (3D) or 8 (2D). A sparse backend answers the
// same from its leaves' value masks.
#pragma once

#include "rgvc/grid/BrickPyramid.hpp"
#include "rgvc/grid/GridGeometry.hpp"
#include "rgvc/grid/StampedBrickBits.hpp"
#include "rgvc/grid/ZeroedArray.hpp"

#include <algorithm>
#include <concepts>
#include <cstdint>
#include <vector>

namespace rgvc {

using VoxelKey = std::uint32_t;
/// Dense object slot inside a culler (not the user's id).
using ObjectSlot = std::uint32_t;
inline constexpr std::uint32_t kNone = 0xFFFFFFFFu;

template <class S>
concept VoxelStorage = requires(S s, const S cs, VoxelKey k, ObjectSlot o, std::uint32_t stamp) {
    { cs.opaque(k) } -> std::convertible_to<bool>;
    s.addOpaque(k, 1);
    { S::kMaxStamp } -> std::convertible_to<std::uint32_t>;
    { cs.occluded(k, stamp) } -> std::convertible_to<bool>;
    s.setOccluded(k, stamp);
    { cs.used(k, stamp) } -> std::convertible_to<bool>;
    s.setUsed(k, stamp);
    { cs.visited(k, stamp) } -> std::convertible_to<bool>;
    s.setVisited(k, stamp);
    { cs.rowWord(std::uint32_t{}, std::int32_t{}) } -> std::convertible_to<std::size_t>;
    { cs.opaqueBits(std::size_t{}) } -> std::convertible_to<std::uint32_t>;
    s.setBrickVisited(typename S::Coord{}, static_cast<const std::uint64_t*>(nullptr), stamp);
    { cs.usedBits(typename S::Coord{}, stamp) } -> std::convertible_to<std::uint32_t>;
    s.markUsedBox(typename S::Coord{}, typename S::Coord{}, stamp);
    { cs.hasIds(k) } -> std::convertible_to<bool>;
    cs.forEachId(k, [](ObjectSlot) {});
    s.addId(k, o);
    s.removeId(k, o);
    s.resetStamps();
};

/// Lists of object slots, one list per head, as chains of 16-byte buckets of up to three slots, all drawn
/// from one pool with a free list: after warm-up, adding to a list allocates nothing. Buckets, not one node
/// per slot: walking a voxel's ids was the 3D traversal's largest cost, one dependent cache miss per node
/// (the pool is in allocation order, not voxel order), and a voxel of two or three ids now costs one.
/// Invariant: every bucket but the head is full, and the head's slots are packed from index 0.
class SlotBucketPool {
public:
    template <class Fn> void forEach(std::uint32_t head, Fn&& fn) const {
        for (std::uint32_t b = head; b != kNone; b = m_buckets[b].next)
            for (ObjectSlot s : m_buckets[b].slots) {
                if (s == kNone) break; // only the head bucket (the first) has free entries, and they come last
                fn(s);
            }
    }
    void add(std::uint32_t& head, ObjectSlot o) {
        if (head != kNone) {
            Bucket& h = m_buckets[head];
            for (ObjectSlot& s : h.slots)
                if (s == kNone) {
                    s = o;
                    ++m_count;
                    return;
                }
        }
        std::uint32_t b;
        if (m_free != kNone) {
            b = m_free;
            m_free = m_buckets[b].next;
        } else {
            b = std::uint32_t(m_buckets.size());
            m_buckets.emplace_back(); // amortised growth of one pool, not a per-voxel allocation
        }
        m_buckets[b] = Bucket{{o, kNone, kNone}, head};
        head = b;
        ++m_count;
    }
    /// Removes one occurrence of o; returns false if the list does not hold it. The head's last slot
    /// fills the hole, so the invariant holds.
    bool remove(std::uint32_t& head, ObjectSlot o) {
        for (std::uint32_t b = head; b != kNone; b = m_buckets[b].next)
            for (ObjectSlot& s : m_buckets[b].slots) {
                if (s == kNone) break;
                if (s != o) continue;
                Bucket& h = m_buckets[head];
                int last = kPerBucket - 1;
                while (h.slots[std::size_t(last)] == kNone) --last;
                s = h.slots[std::size_t(last)];
                h.slots[std::size_t(last)] = kNone;
                if (last == 0) { // the head bucket is empty: back to the free list
                    const std::uint32_t next = h.next;
                    h.next = m_free;
                    m_free = head;
                    head = next;
                }
                --m_count;
                return true;
            }
        return false;
    }
    void prefetch(std::uint32_t head) const { __builtin_prefetch(&m_buckets[head]); }
    /// Whether the list starting at head (not kNone) holds exactly one slot, and its first slot.
    bool isSingle(std::uint32_t head) const {
        return m_buckets[head].next == kNone && m_buckets[head].slots[1] == kNone;
    }
    ObjectSlot front(std::uint32_t head) const { return m_buckets[head].slots[0]; }
    /// Slots in use.
    std::size_t size() const { return m_count; }

private:
    static constexpr int kPerBucket = 3;
    struct Bucket {
        ObjectSlot slots[kPerBucket] = {kNone, kNone, kNone};
        std::uint32_t next = kNone;
    };
    static_assert(sizeof(Bucket) == 16);
    std::vector<Bucket> m_buckets;
    std::uint32_t m_free = kNone;
    std::size_t m_count = 0;
};

/// The brick-row word layout (see the file's header): words per grid row, and a voxel's word and bit.
/// [Limit] res.x >= 1.
class BrickRowLayout {
public:
    BrickRowLayout() = default;
    BrickRowLayout(std::int32_t resX, std::size_t rows) : m_resX(std::uint32_t(resX)), m_perRow(std::uint32_t((resX + 7) >> 3)), m_rows(rows) {}
    /// Words in all (rows x words per row).
    std::size_t size() const { return m_rows * m_perRow; }
    /// The word of voxels x & ~7 .. (x & ~7) + 7 of row rowIndex (the row's key / res.x).
    std::size_t word(std::uint32_t rowIndex, std::int32_t x) const { return std::size_t(rowIndex) * m_perRow + std::size_t(x >> 3); }
    /// Voxel k's word, and its bit in it (one division: per-voxel callers only, never the brick walks).
    std::size_t wordOf(VoxelKey k, std::uint32_t& bit) const {
        const std::uint32_t row = k / m_resX, x = k - row * m_resX;
        bit = 1u << (x & 7);
        return std::size_t(row) * m_perRow + (x >> 3);
    }

private:
    std::uint32_t m_resX = 1, m_perRow = 1;
    std::size_t m_rows = 0;
};

/// Dense arrays over the whole grid. What a traversal step reads and writes sits in one 8-byte cell per
/// voxel: the I list head with O's flag in its top bit, and a 16-bit H stamp. One cell, so that a step
/// touches one cache line whatever the axis it walks along (profiling the 3D traversal, which walks x faces
/// with a stride of a whole row, showed one miss per matrix per voxel with separate arrays); 8 bytes, not
/// the 16 of 32-bit stamps and an inline O count, so that twice as many voxels share the caches (the 3D
/// traversal is bound by these reads). O's count (4 bytes, touched only when objects are rasterized), the
/// brick-row words of O's flags (file header) and V and U's bricks (FrameMarks) live apart. A voxel's only id sits in the cell; two or more take
/// a 16-byte bucket per three.
/// Stamps are 16 bits: a full clear every 65,535 frames.
template <int D> class DenseStorage : public FrameMarks<D> {
public:
    static constexpr std::uint32_t kMaxStamp = 0xFFFF;

    explicit DenseStorage(const GridGeometry<D>& grid)
        : FrameMarks<D>(grid.resolution()), m_cells(grid.voxelCount()), m_opaque(grid.voxelCount()),
          m_layout(grid.resolution().x, grid.voxelCount() / std::size_t(grid.resolution().x)),
          m_opaqueBits(m_layout.size()), m_bricks(grid.resolution()), m_res(grid.resolution()) {}

    /// For users that read every voxel of a view, written or not (the paper's per-voxel traversals): the
    /// per-voxel arrays on huge pages (ZeroedArray::adviseHugePages says why). A hint; results never change.
    void adviseWholeGridReads() {
        m_cells.adviseHugePages();
        m_opaque.adviseHugePages();
        m_opaqueBits.adviseHugePages();
        this->adviseMarksHugePages();
    }

    /// For users that read and write per-voxel state of any brick they walk (the brick walks): the arrays
    /// a walk reaches in every brick it reads, written now, so that a camera moving into space not seen
    /// before pays no page's first touch during a frame (the walk reads and writes them in every brick it
    /// visits, occupied or not by anything written before). O's flags, V and U are about 3 bits a voxel; `cells` adds the cells
    /// (8 bytes a voxel), which the 2D walk reads for ids. What only objects write (O's counts, and the
    /// cells in 3D) stays untouched where no object ever was.
    void touchWalkedArrays(bool cells) {
        m_opaqueBits.touch();
        this->touchMarks();
        if (cells) m_cells.touch();
    }
    /// Every per-voxel array written now: no page's first touch ever falls in a frame (what a
    /// std::vector did at construction).
    void touchAll() {
        touchWalkedArrays(true);
        m_opaque.touch();
    }

    /// The block hierarchy over the grid (BrickPyramid.hpp): which bricks may hold ids. Writers of ids
    /// call noteIdsAdded for every run they add; readers that find a brick empty clear it.
    BrickPyramid<D>& bricks() { return m_bricks; }
    const BrickPyramid<D>& bricks() const { return m_bricks; }
    /// Ids were added to voxels row + x0 .. row + x1 (row: the key of the row's voxel x = 0): marks their
    /// bricks occupied. One division per run, not per voxel (RowFootprint calls it per span).
    void noteIdsAdded(VoxelKey row, std::int32_t x0, std::int32_t x1) {
        if (x1 < x0) return;
        IVec<D> b;
        std::uint32_t rest = std::uint32_t(row) / std::uint32_t(m_res.x);
        for (int a = 1; a < D; ++a) {
            if (a + 1 < D) {
                b[a] = std::int32_t(rest % std::uint32_t(m_res[a])) >> BrickPyramid<D>::kBrickShift;
                rest /= std::uint32_t(m_res[a]);
            } else {
                b[a] = std::int32_t(rest) >> BrickPyramid<D>::kBrickShift;
            }
        }
        for (std::int32_t bx = x0 >> BrickPyramid<D>::kBrickShift; bx <= x1 >> BrickPyramid<D>::kBrickShift; ++bx) {
            b.x = bx;
            m_bricks.markOccupied(b);
        }
    }

    bool opaque(VoxelKey k) const { return (head(k) & kOpaqueBit) != 0; }
    /// delta is +1 or -1; the count never goes below zero when calls are paired.
    void addOpaque(VoxelKey k, std::int32_t delta) {
        const std::uint32_t n = std::uint32_t(std::int64_t(m_opaque[k]) + delta);
        m_opaque[k] = n;
        setHead(k, (head(k) & ~kOpaqueBit) | (n != 0 ? kOpaqueBit : 0u));
        std::uint32_t bit;
        const std::size_t w = m_layout.wordOf(k, bit);
        m_opaqueBits[w] = std::uint8_t(n != 0 ? m_opaqueBits[w] | bit : m_opaqueBits[w] & ~bit);
    }
    /// The brick-row word of row rowIndex (its key / res.x) holding voxel x (see the file's header).
    std::size_t rowWord(std::uint32_t rowIndex, std::int32_t x) const { return m_layout.word(rowIndex, x); }
    const BrickRowLayout& rowLayout() const { return m_layout; }
    /// O's flags of word w's 8 voxels (bit i: voxel x = 8 bx + i).
    std::uint32_t opaqueBits(std::size_t w) const { return m_opaqueBits[w]; }

    bool occluded(VoxelKey k, std::uint32_t stamp) const { return m_cells[k].occluded == stamp; }
    void setOccluded(VoxelKey k, std::uint32_t stamp) { m_cells[k].occluded = std::uint16_t(stamp); }
    // V and U: FrameMarks (visited, setVisited, setBrickVisited, used, setUsed, usedBits, markUsedBox).
    /// [Voxels] the grid's resolution.
    const IVec<D>& resolution() const { return m_res; }

    bool hasIds(VoxelKey k) const { return (head(k) & ~kOpaqueBit) != kNoList; }
    template <class Fn> void forEachId(VoxelKey k, Fn&& fn) const {
        const std::uint32_t h = head(k) & ~kOpaqueBit;
        if (h == kNoList) return;
        if (h & kInlineBit) {
            fn(ObjectSlot(h & kValueMask));
            return;
        }
        m_ids.forEach(h, fn);
    }
    /// Starts loading voxel k's cell (a traversal reading rows across the grid's memory order).
    void prefetchCell(VoxelKey k) const { __builtin_prefetch(&m_cells[k]); }
    /// Starts loading the first bucket of voxel k (nothing when it has none or one id), so that a
    /// caller about to walk the lists of many voxels overlaps their cache misses.
    void prefetchIds(VoxelKey k) const {
        const std::uint32_t h = head(k) & ~kOpaqueBit;
        if ((h & kInlineBit) == 0 && h != kNoList) m_ids.prefetch(h);
    }
    /// [Limit] o < 2^30 (the slot is stored in the cell's 30 value bits when it is the voxel's only id).
    void addId(VoxelKey k, ObjectSlot o) {
        const std::uint32_t h = head(k) & ~kOpaqueBit;
        if (h == kNoList) {
            setField(k, kInlineBit | o);
            ++m_inlineIds;
            return;
        }
        std::uint32_t head = kNone;
        if (h & kInlineBit) { // a second id: the inline one moves into a list
            m_ids.add(head, ObjectSlot(h & kValueMask));
            --m_inlineIds;
        } else {
            head = h;
        }
        m_ids.add(head, o);
        setField(k, head);
    }
    void removeId(VoxelKey k, ObjectSlot o) {
        const std::uint32_t h = head(k) & ~kOpaqueBit;
        if (h == kNoList) return;
        if (h & kInlineBit) {
            if ((h & kValueMask) == o) {
                setField(k, kNoList);
                --m_inlineIds;
            }
            return;
        }
        std::uint32_t head = h;
        m_ids.remove(head, o);
        if (head != kNone && m_ids.isSingle(head)) { // one id left: back into the cell, its bucket freed
            const ObjectSlot last = m_ids.front(head);
            m_ids.remove(head, last);
            setField(k, kInlineBit | last);
            ++m_inlineIds;
            return;
        }
        setField(k, head == kNone ? kNoList : head);
    }

    /// Called when the frame stamp passes kMaxStamp: every stamp back to "never".
    void resetStamps() {
        // (The cells also hold I and O's flag: written, not replaced; only stamps set, so that the pages a
        // lazy storage never wrote stay untouched.)
        for (Cell& c : m_cells)
            if (c.occluded != 0) c.occluded = 0;
        this->resetMarks();
    }

    /// Incidences currently stored in I (for stats and consistency tests).
    std::size_t idCount() const { return m_ids.size() + m_inlineIds; }

private:
    // The head field: the top bit is O's flag; below it, kNoList (no id), or the voxel's only id with
    // kInlineBit set (most voxels of scenes of small objects hold one id: reading it from the cell saves
    // the list node, a cache miss per voxel that was half of the 3D traversal's time), or the index of
    // the first node of its list (two ids or more). Node indices and slots stay below 2^30 (a pool of 2^30
    // nodes holds 8 GiB).
    static constexpr std::uint32_t kOpaqueBit = 0x80000000u;
    static constexpr std::uint32_t kInlineBit = 0x40000000u;
    static constexpr std::uint32_t kValueMask = 0x3FFFFFFFu;
    static constexpr std::uint32_t kNoList = 0x3FFFFFFFu;

    void setField(VoxelKey k, std::uint32_t field) { setHead(k, (head(k) & kOpaqueBit) | field); }
    // The cell stores the head XOR kNoList, so that the all-zero cell of a fresh ZeroedArray reads as no
    // id, not opaque, never occluded: construction writes nothing (ZeroedArray.hpp).
    std::uint32_t head(VoxelKey k) const { return m_cells[k].headX ^ kNoList; }
    void setHead(VoxelKey k, std::uint32_t h) { m_cells[k].headX = h ^ kNoList; }

    struct Cell {
        std::uint32_t headX;  // head() ^ kNoList. I: kNoList, an inline id or a list head; O flag in the top bit
        std::uint16_t occluded; // H's stamp, 0: never
    };
    static_assert(sizeof(Cell) == 8);
    // The per-voxel arrays start as zero pages that cost memory only where written (ZeroedArray.hpp): a
    // large, mostly empty world costs what its content touches.
    ZeroedArray<Cell> m_cells;
    ZeroedArray<std::uint32_t> m_opaque; // O counts
    BrickRowLayout m_layout;
    ZeroedArray<std::uint8_t> m_opaqueBits; // O's flags as brick-row words
    BrickPyramid<D> m_bricks;
    IVec<D> m_res;
    SlotBucketPool m_ids;
    std::size_t m_inlineIds = 0; // ids stored in cells, not in m_ids
};

static_assert(VoxelStorage<DenseStorage<2>>);
static_assert(VoxelStorage<DenseStorage<3>>);

} // namespace rgvc
