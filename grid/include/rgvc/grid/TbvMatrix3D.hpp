// TbvMatrix<3>: T in 3D, a list and a bitmap per brick, written block by block where lookups go
// (TbvRegion.hpp says what is stored and why the boundary suffices).
#pragma once

#include "rgvc/grid/TbvBrickPart.hpp"

namespace rgvc {

/// 3D T: per brick of 8 x 8 x 8 voxels, the list of the TBVs whose discretization reaches into it and a
/// bitmap of the voxels some TBV holds there; or (Shell) one list per voxel. Allocated on the first
/// insert of either kind.
///
/// Why bricks and not the paper's projection planes (§5.2). The traversal asks T about every visited
/// voxel that is not in H while TBVs exist, and with thousands of TBVs mixed with visible space (5,000
/// moving spheres in clusters, the camera among them) the planes answer badly: a plane cell collects
/// every TBV whose outline projects onto it, whatever its depth, so both lists of a lookup held hundreds
/// of TBVs, nearly none holding the voxel, at ~64,000 lookups a frame (45 % of the frame). A voxel the
/// traversal reaches outside H is one no live TBV holds, except where it reveals one, so what a lookup
/// must be fast at is "none": one bit, read from the brick's bitmap. Only a set bit walks the brick's
/// list, and then (the bitmap being exact once its brick is rebuilt, below) at least one TBV is revealed
/// and leaves T. Measured on that scene: 45 % of the frame in T's lookups before, under 3 % after.
///
/// The bitmap of a brick is the union of its TBVs' voxels. An insert ORs its part in (per slice of the
/// brick, one 64-bit word, bit x + 8 y; a box's part is the same word on every slice but its z faces,
/// so a brick costs at most 8 word writes in one cache line). An erase cannot clear bits another TBV
/// may share, so it only marks the brick stale: the bitmap is then a superset of the union, and a lookup
/// that meets a set bit in a stale brick rebuilds it from its list first (the union of its TBVs' parts).
/// A bit can therefore be stale only where a lookup never looked, and the reveal rule stays exactly
/// "some live TBV's discretization holds the voxel": the list walk tests each TBV with its box.
///
/// Cost of an insert or erase: one list node per brick the shell reaches. A box of side n spans at most
/// n / 8 + 2 bricks per axis, so a 20-voxel box writes at most 64 nodes (56: its shell misses the 8 inner
/// bricks), against 12 n = 240 plane cells; T's writes on rgvc_bench_dynamic hidden3d at 100,000 TBVs
/// fell from 319,000 to 41,000 a frame. The stored *set* of voxels is the one the header argues about
/// (the shell of the voxel box, or the box for Filled), whatever the storage.
///
/// Blocks written lazily. A brick's list and bitmap are read only when a lookup asks about the brick,
/// and the brick walk asks only about bricks in view that its image does not hide: around a closed room
/// with 100,000 movers outside (rgvc_bench_classes' room-100k), nearly every TBV lies where no lookup
/// ever goes, and writing their bricks (a list node and a bitmap OR for each of the ~21 bricks a renewed
/// TBV's shell reaches, 9,500 renewals a frame) was a third of the frame's instructions. So the bricks
/// are grouped in blocks of 2 x 2 x 2 (16^3 voxels), and a block no lookup has asked about yet ("cold")
/// keeps one list of the TBVs whose voxel box meets it instead: an insert writes one node per cold
/// block its box meets (8 on average there) and brick nodes only in the blocks already asked about
/// ("hot"). Blocks of 4^3 bricks measured the same. The first lookup that needs a cold
/// block's bricks (brickBits, collectAt) writes its TBVs into its bricks, clipped to the block, and the
/// block stays hot from then on; the read-only lookups (holdsAt, brickParts, collectInBrick,
/// mayHoldBrick) answer a cold block from its list directly, testing each TBV against the brick or
/// voxel, so every lookup returns what it did when every brick was written eagerly. Heating a block
/// moves its TBVs into its bricks and empties its list.
///
/// Lists as arrays, erased lazily. A list is an array of entries, each stamped with its slot's
/// generation at insert; an erase only bumps the slot's generation (every entry of the slot dies at
/// once), counts its lists' live entries down and marks its bricks stale. Every reader skips dead
/// entries (the generation differs), and a list drops them when it is rebuilt or when it has grown to
/// twice its live entries (so it holds at most 2 live + 4 entries, and the drops cost O(1) per insert
/// amortised). Why not linked nodes: around the 100k room a frame renews 9,500 TBVs and rebuilds ~70
/// stale bricks of ~170 TBVs each; the nodes (and each node's box, for the brick's part) sat at random
/// places in a pool of millions, so every rebuild step and every erase's unlink was a cache miss on a
/// miss (perf put half of the rebuild on the node's load and a third on its box). A brick entry holds
/// its part (TbvBrickPart, the 24 bytes the bitmap needs), so a rebuild reads one array in order and
/// one generation word per entry, and an erase writes nothing but counters, stale bytes and the
/// generation (no list is read).
template <> class TbvMatrix<3> {
public:
    static constexpr int kBrickShift = kTbvBrickShift; // 8 x 8 x 8 voxels: a slice of a brick is one 64-bit word

    static constexpr int kBlockShift = 1; // 2 x 2 x 2 bricks per block (lazily written, see above)

    explicit TbvMatrix(const IVec3& res)
        : m_res(res),
          m_bricks{((res.x - 1) >> kBrickShift) + 1, ((res.y - 1) >> kBrickShift) + 1, ((res.z - 1) >> kBrickShift) + 1},
          m_blocks{((m_bricks.x - 1) >> kBlockShift) + 1, ((m_bricks.y - 1) >> kBlockShift) + 1, ((m_bricks.z - 1) >> kBlockShift) + 1} {}
    TbvMatrix(const TbvMatrix&) = delete; // large; the culler owns one
    TbvMatrix& operator=(const TbvMatrix&) = delete;

    /// Adds the slot's region; the slot must not hold one. Returns the T incidences written: brick list
    /// entries and cold blocks' list entries (Boundary, Filled) or voxel list nodes (Shell).
    std::size_t insert(ObjectSlot slot, const TbvRegion<3>& r, TbvDiscretization mode) {
        if (slot >= m_boxes.size()) {
            m_boxes.resize(std::size_t(slot) + 1);
            m_gen.resize(std::size_t(slot) + 1, 0);
        }
        TbvVoxelBox& st = m_boxes[slot];
        st.mode = mode;
        st.inGrid = tbvVoxelBox3D(r, m_res, st.lo, st.hi);
        ++m_live;
        if (mode == TbvDiscretization::Shell) {
            if (m_voxels.empty()) m_voxels.assign(cellCount<3>(m_res), kNone);
            return forEachShellVoxel(st, [&](std::uint32_t& head) { m_lists.add(head, slot); });
        }
        if (m_count.empty()) {
            const std::size_t n = cellCount<3>(m_bricks);
            m_brickLists.resize(n);
            m_count.assign(n, 0);
            m_bits.assign(n * kSlices, 0);
            m_stale.assign(n, 0);
            const std::size_t blocks = cellCount<3>(m_blocks);
            m_blockLists.resize(blocks);
            m_blockCount.assign(blocks, 0);
            m_blockHot.assign(blocks, 0);
        }
        if (!st.inGrid) return 0;
        const std::uint32_t gen = m_gen[slot];
        // One entry per cold block the box meets; brick entries only in hot blocks.
        std::size_t n = 0;
        bool anyHot = false, anyCold = false;
        forEachBlock(st, [&](std::size_t k) {
            if (m_blockHot[k] != 0) {
                anyHot = true;
                return;
            }
            anyCold = true;
            append(m_blockLists[k], m_blockCount[k], BlockEntry{slot, gen});
            ++n;
        });
        if (anyHot) {
            auto write = [&](const IVec3& bc, const TbvBrickPart& p) { writeBrick(brickIndex(bc), p, slot, gen); };
            if (!anyCold) // all hot (where the camera has been): every brick, no test
                n += forEachTbvBrick(st, IVec3(0), m_bricks - 1, write);
            else
                forEachTbvBrick(st, IVec3(0), m_bricks - 1, [&](const IVec3& bc, const TbvBrickPart& p) {
                    if (m_blockHot[blockOfBrick(bc)] == 0) return;
                    write(bc, p);
                    ++n;
                });
        }
        m_incidences += n;
        return n;
    }
    /// The voxel box (tbvVoxelBox) of the slot's region as its last insert computed it; false when the
    /// region lies outside the grid. The per-frame update marks the brick tree with it, so a renewal
    /// converts its region once (tbvVoxelBox was 3 % of the 100k room's frame, computed twice).
    bool voxelBox(ObjectSlot slot, IVec3& lo, IVec3& hi) const {
        const TbvVoxelBox& st = m_boxes[slot];
        lo = st.lo;
        hi = st.hi;
        return st.inGrid;
    }
    /// Removes the slot's region (it must hold one). Returns the incidences removed: its live entries
    /// (the cold blocks its box meets, the bricks of hot blocks its discretization reaches), found from
    /// its stored box, not from the lists. Its bricks' bitmaps go stale and its entries die (see above).
    std::size_t erase(ObjectSlot slot, const TbvRegion<3>& /*r*/, TbvDiscretization /*mode*/) {
        --m_live;
        const TbvVoxelBox& st = m_boxes[slot];
        if (st.mode == TbvDiscretization::Shell) return m_lists.eraseAll(slot);
        ++m_gen[slot]; // its entries die; wrapping takes 2^32 erases of one slot while one entry waits
        if (!st.inGrid) return 0;
        // Blocks never cool: a block cold now was cold at the insert (one block entry), a hot one holds
        // a brick entry in each brick the discretization reaches (written at the insert or by heat).
        std::size_t n = 0;
        bool anyHot = false;
        forEachBlock(st, [&](std::size_t k) {
            if (m_blockHot[k] != 0) {
                anyHot = true;
                return;
            }
            --m_blockCount[k];
            ++n;
        });
        if (anyHot)
            forEachTbvBrick(st, IVec3(0), m_bricks - 1, [&](const IVec3& bc, const TbvBrickPart&) {
                if (m_blockHot[blockOfBrick(bc)] == 0) return;
                const std::size_t brick = brickIndex(bc);
                --m_count[brick];
                m_stale[brick] = 1;
                ++n;
            });
        m_incidences -= n;
        return n;
    }
    /// Appends the slots whose discretization holds voxel v (in the grid), each once.
    ///
    /// Cost: one bit where no TBV holds v (a stale brick's superset bit may cost one rebuild of the
    /// brick, after which its bits are exact again); where one does, the brick's list, each live entry
    /// tested with its part (a brick's list holds a slot's live entry at most once).
    void collectAt(const IVec3& v, std::vector<ObjectSlot>& out) {
        if (m_live == 0) return;
        if (!m_voxels.empty()) m_lists.forEach(m_voxels[voxel(v)], [&](ObjectSlot s) { out.push_back(s); });
        if (m_count.empty()) return;
        if (!warm(v >> kBrickShift)) return;
        const std::size_t brick = brickOf(v);
        // Most voxels the traversal asks about lie in bricks no TBV reaches: the counts (4 bytes per
        // brick) stay in L1, the bitmaps (a cache line per brick) do not.
        if (m_count[brick] == 0 || !bitAt(brick, v)) return;
        if (m_stale[brick] != 0) {
            rebuild(brick);
            if (!bitAt(brick, v)) return;
        }
        const IVec3 l = v & kTbvBrickMask;
        for (const BrickEntry& e : m_brickLists[brick])
            if (live(e) && e.part.holds(l)) out.push_back(e.slot);
    }
    /// Whether some TBV holds voxel v (exact: a set bit is confirmed by the brick's list).
    bool holdsAt(const IVec3& v) const {
        if (m_live == 0) return false;
        if (!m_voxels.empty() && m_voxels[voxel(v)] != kNone) return true;
        if (m_count.empty()) return false;
        const std::size_t block = blockOfBrick(v >> kBrickShift);
        if (m_blockHot[block] == 0) { // a cold block: its list, each box tested
            for (const BlockEntry& e : m_blockLists[block])
                if (live(e) && tbvBoxHolds(m_boxes[e.slot], v)) return true;
            return false;
        }
        const std::size_t brick = brickOf(v);
        if (m_count[brick] == 0 || !bitAt(brick, v)) return false;
        const IVec3 l = v & kTbvBrickMask;
        for (const BrickEntry& e : m_brickLists[brick])
            if (live(e) && e.part.holds(l)) return true;
        return false;
    }

    /// Rebuilds every stale brick now, so that collectAt and brickBits write nothing until the next
    /// erase: after it, lookups from several threads at once are safe (Culler::cullViews' view passes).
    /// Cost: one byte per brick, and each stale brick's list.
    /// Cold blocks that hold TBVs are written into their bricks first (a view pass would otherwise write
    /// them on its first lookup), so after it every block that holds a TBV is hot; cold blocks' lists of
    /// dead entries only are emptied, so the arrays then hold live entries only.
    void freshen() {
        for (std::size_t block = 0; block < m_blockHot.size(); ++block) {
            if (m_blockHot[block] != 0) continue;
            if (m_blockCount[block] != 0) heat(block);
            else m_blockLists[block].clear();
        }
        for (std::size_t brick = 0; brick < m_stale.size(); ++brick)
            if (m_stale[brick] != 0) rebuild(brick);
    }
    std::size_t liveRegions() const { return m_live; }
    bool allocated() const { return !m_count.empty() || !m_voxels.empty(); }
    /// Live incidences: brick and cold-block entries (dead ones waiting in their arrays not counted),
    /// and Shell voxel nodes.
    std::size_t incidences() const { return m_incidences + m_lists.size(); }

    /// Brick-at-a-time lookups (the brick traversal): the voxels of brick b (brick coordinates) that some
    /// TBV holds, as 8 slice words (bit x + 8 y of slice z, brick-local), exact (a stale brick is rebuilt
    /// first). False when no TBV reaches the brick. Boundary and Filled only (hasBrickLists()).
    bool brickBits(const IVec3& b, std::uint64_t out[8]) {
        if (m_count.empty()) return false;
        if (!warm(b)) return false;
        const std::size_t brick = brickIndex(b);
        if (m_count[brick] == 0) return false;
        if (m_stale[brick] != 0) rebuild(brick);
        const std::uint64_t* w = &m_bits[brick * kSlices];
        bool any = false;
        for (std::size_t z = 0; z < kSlices; ++z) any = (out[z] = w[z]) != 0 || any;
        return any;
    }
    /// Appends, each once, the slots whose voxels in brick b meet `voxels` (8 slice words as above).
    /// Cost: the brick's list, one part (8 words at most) per entry.
    void collectInBrick(const IVec3& b, const std::uint64_t voxels[8], std::vector<ObjectSlot>& out) const {
        forEachPart(b, [&](ObjectSlot s, const TbvBrickPart& p) {
            for (std::int32_t z = p.z0; z <= p.z1; ++z)
                if ((p.slice(z) & voxels[z]) != 0) {
                    out.push_back(s);
                    return;
                }
        });
    }
    /// The slots listed in brick b and, per slot, the voxels of the brick it holds (8 slice words, as
    /// brickBits gives), appended to `slots` and `parts` (cleared first); slots whose discretization
    /// misses the brick are left out. Boundary and Filled only (hasBrickLists()). Cost: the brick's list,
    /// one part per entry. (The brick traversal reveals the TBVs of a visible voxel at once with these:
    /// clearHiddenVoxels in BrickPass.cpp.)
    void brickParts(const IVec3& b, std::vector<ObjectSlot>& slots, std::vector<std::array<std::uint64_t, 8>>& parts) const {
        static_assert(kSlices == 8);
        slots.clear();
        parts.clear();
        forEachPart(b, [&](ObjectSlot s, const TbvBrickPart& p) {
            slots.push_back(s);
            std::array<std::uint64_t, 8>& w = parts.emplace_back();
            w.fill(0);
            for (std::int32_t z = p.z0; z <= p.z1; ++z) w[std::size_t(z)] = p.slice(z);
        });
    }

    /// Whether TBVs are kept per brick (Boundary, Filled); false while a Shell TBV exists (its voxel lists
    /// answer only collectAt).
    bool hasBrickLists() const { return m_voxels.empty(); }

    /// Whether some TBV may hold a voxel of brick b (brick coordinates, 8^3 voxels): false is a guarantee.
    /// The Shell discretization keeps no brick lists, so while it is in use every brick may.
    bool mayHoldBrick(const IVec3& b) const {
        if (m_live == 0) return false;
        if (!m_voxels.empty()) return true;
        if (m_count.empty()) return false;
        const std::size_t block = blockOfBrick(b);
        return m_blockHot[block] != 0 ? m_count[brickIndex(b)] != 0 : m_blockCount[block] != 0;
    }
    /// Blocks written into their bricks so far (see the class comment); for tests and statistics.
    std::size_t hotBlocks() const { return std::size_t(std::count(m_blockHot.begin(), m_blockHot.end(), std::uint8_t(1))); }
    /// Entries held in the brick and block arrays, dead ones included; for tests of the drop rule.
    std::size_t storedEntries() const {
        std::size_t n = 0;
        for (const auto& l : m_brickLists) n += l.size();
        for (const auto& l : m_blockLists) n += l.size();
        return n;
    }

private:
    static constexpr std::size_t kSlices = std::size_t(1) << kBrickShift; // words per brick

    /// A brick list's entry: the slot, its generation at the insert and its part of the brick.
    struct BrickEntry {
        TbvBrickPart part;
        ObjectSlot slot;
        std::uint32_t gen;
    };
    /// A cold block's entry (the box is the slot's stored one).
    struct BlockEntry {
        ObjectSlot slot;
        std::uint32_t gen;
    };
    static_assert(sizeof(BrickEntry) == 32, "half a cache line per entry");

    std::size_t voxel(const IVec3& v) const { return cellIndex<3>(m_res, v); }

    template <class E> bool live(const E& e) const { return m_gen[e.slot] == e.gen; }

    /// Appends e to a list holding `liveCount` live entries, first dropping its dead ones once it has
    /// grown to twice its live entries (+ 4: a short list is not scanned on every append). After a drop
    /// the list holds liveCount entries, so at least liveCount + 4 appends come before the next one,
    /// which reads at most 2 liveCount + 4: O(1) amortised per append.
    template <class E> void append(std::vector<E>& list, std::uint32_t& liveCount, const E& e) {
        if (list.size() >= 2 * std::size_t(liveCount) + 4) std::erase_if(list, [&](const E& x) { return !live(x); });
        list.push_back(e); // amortised growth of one array, not a per-voxel allocation
        ++liveCount;
    }
    void writeBrick(std::size_t brick, const TbvBrickPart& p, ObjectSlot slot, std::uint32_t gen) {
        append(m_brickLists[brick], m_count[brick], BrickEntry{p, slot, gen});
        p.orInto(&m_bits[brick * kSlices]);
    }

    /// Calls fn(block index) for every block the box meets.
    template <class Fn> void forEachBlock(const TbvVoxelBox& st, Fn&& fn) const {
        const IVec3 klo = (st.lo >> kBrickShift) >> kBlockShift, khi = (st.hi >> kBrickShift) >> kBlockShift;
        for (std::int32_t z = klo.z; z <= khi.z; ++z)
            for (std::int32_t y = klo.y; y <= khi.y; ++y) {
                const std::size_t row = blockIndex({0, y, z});
                for (std::int32_t x = klo.x; x <= khi.x; ++x) fn(row + std::size_t(x));
            }
    }

    /// Calls fn(slot, part) for each live TBV whose discretization reaches brick b: from the brick's list
    /// in a hot block, from the block's (each box clipped to the brick) in a cold one.
    template <class Fn> void forEachPart(const IVec3& b, Fn&& fn) const {
        if (m_count.empty()) return;
        const std::size_t block = blockOfBrick(b);
        if (m_blockHot[block] != 0) {
            for (const BrickEntry& e : m_brickLists[brickIndex(b)])
                if (live(e)) fn(e.slot, e.part);
            return;
        }
        TbvBrickPart p;
        for (const BlockEntry& e : m_blockLists[block])
            if (live(e) && tbvBrickPart(m_boxes[e.slot], b, p)) fn(e.slot, p);
    }

    /// Calls fn(head) for every voxel of the outer shell of a stored voxel box; returns the count.
    template <class Fn> std::size_t forEachShellVoxel(const TbvVoxelBox& b, Fn&& fn) {
        if (!b.inGrid) return 0;
        const IVec3 lo = b.lo, hi = b.hi;
        std::size_t n = 0;
        for (std::int32_t z = lo.z; z <= hi.z; ++z)
            for (std::int32_t y = lo.y; y <= hi.y; ++y) {
                const std::size_t row = voxel({0, y, z});
                if (z == lo.z || z == hi.z || y == lo.y || y == hi.y) {
                    for (std::int32_t x = lo.x; x <= hi.x; ++x) fn(m_voxels[row + std::size_t(x)]);
                    n += std::size_t(hi.x - lo.x + 1);
                } else {
                    fn(m_voxels[row + std::size_t(lo.x)]);
                    if (hi.x != lo.x) fn(m_voxels[row + std::size_t(hi.x)]);
                    n += hi.x != lo.x ? 2 : 1;
                }
            }
        return n;
    }

    std::size_t blockIndex(const IVec3& k) const { return cellIndex<3>(m_blocks, k); }
    std::size_t blockOfBrick(const IVec3& bc) const { return blockIndex(bc >> kBlockShift); }
    /// Makes brick bc's block hot if it is not; false when it is cold and holds no TBV (nothing written).
    bool warm(const IVec3& bc) {
        const std::size_t block = blockOfBrick(bc);
        if (m_blockHot[block] != 0) return true;
        if (m_blockCount[block] == 0) return false;
        heat(block);
        return true;
    }
    /// Writes a cold block's live TBVs into its bricks (clipped to it), empties its list and marks it hot.
    /// Its bricks hold nothing before (erases mark only hot blocks' bricks stale).
    void heat(std::size_t block) {
        m_blockHot[block] = 1;
        const IVec3 lo = cellOf<3>(m_blocks, block) << kBlockShift;
        const IVec3 hi = glm::min(lo + ((1 << kBlockShift) - 1), m_bricks - 1);
        std::size_t written = 0;
        for (const BlockEntry& e : m_blockLists[block])
            if (live(e))
                written += forEachTbvBrick(m_boxes[e.slot], lo, hi, [&](const IVec3& bc, const TbvBrickPart& p) {
                    writeBrick(brickIndex(bc), p, e.slot, e.gen);
                });
        m_incidences += written;
        m_incidences -= m_blockCount[block];
        m_blockCount[block] = 0;
        std::vector<BlockEntry>().swap(m_blockLists[block]); // never read again: its memory goes
    }

    /// The brick's bitmap, recomputed from its list: exactly the union of its live TBVs' parts. Drops
    /// the dead entries on the way (the list is read whole anyway).
    void rebuild(std::size_t brick) {
        std::uint64_t* w = &m_bits[brick * kSlices];
        std::fill(w, w + kSlices, 0);
        std::vector<BrickEntry>& list = m_brickLists[brick];
        std::size_t kept = 0;
        for (std::size_t i = 0; i < list.size(); ++i) {
            const BrickEntry& e = list[i];
            if (!live(e)) continue;
            e.part.orInto(w);
            list[kept++] = e;
        }
        list.resize(kept); // shrinks: no allocation
        m_stale[brick] = 0;
    }

    std::size_t brickIndex(const IVec3& bc) const { return cellIndex<3>(m_bricks, bc); }
    std::size_t brickOf(const IVec3& v) const { return brickIndex(v >> kBrickShift); }
    bool bitAt(std::size_t brick, const IVec3& v) const {
        const std::uint64_t w = m_bits[brick * kSlices + std::size_t(v.z & kTbvBrickMask)];
        return ((w >> ((v.x & kTbvBrickMask) + 8 * (v.y & kTbvBrickMask))) & 1) != 0;
    }

    IVec3 m_res;
    IVec3 m_bricks;                                   // bricks per axis (the last ones may reach past the grid)
    std::vector<std::vector<BrickEntry>> m_brickLists; // per brick: its entries, live and dead
    std::vector<std::uint32_t> m_count;               // per brick: its live entries
    std::vector<std::uint64_t> m_bits;                // per brick, kSlices words: a superset of its TBVs' voxels (exact unless stale)
    std::vector<std::uint8_t> m_stale;                // per brick: an erase since its last rebuild
    IVec3 m_blocks;                                   // blocks of 2^3 bricks per axis
    std::vector<std::vector<BlockEntry>> m_blockLists; // per block: while cold, the TBVs whose box meets it
    std::vector<std::uint32_t> m_blockCount;          // per block: while cold, its live entries
    std::vector<std::uint8_t> m_blockHot;             // per block: its bricks' lists and bitmaps are written
    std::vector<std::uint32_t> m_voxels;              // Shell: one list head per voxel
    TbvListPool m_lists;                              // Shell: the voxel lists
    std::vector<TbvVoxelBox> m_boxes;                 // per slot: its box, to test and to find its bricks
    std::vector<std::uint32_t> m_gen;                 // per slot: its generation (entries stamped with another are dead)
    std::size_t m_incidences = 0;                     // live brick and block entries
    std::size_t m_live = 0;
};

} // namespace rgvc
