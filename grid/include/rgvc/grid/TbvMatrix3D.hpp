// TbvMatrix<3>: T in 3D, a list and a bitmap per brick, written block by block where lookups go
// (TbvRegion.hpp says what is stored and why the boundary suffices).
#pragma once

#include "rgvc/grid/TbvRegion.hpp"
#include "rgvc/grid/ZeroedArray.hpp"

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
/// "some live TBV's discretization holds the voxel": the list walk tests each TBV with its box. The
/// brick walk may read a stale brick with a long list as it stands (brickBits' rebuildUpTo): it tests
/// the voxels against its image and confirms a visible one against the brick's parts (brickParts), so
/// a stale bit costs it a test, never a reveal; reading the parts settles the bitmap (settleBrick).
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
/// voxel, so every lookup returns what it did when every brick was written eagerly. A cold block's
/// entries stay in the pool, unread, until their TBVs are erased.
template <> class TbvMatrix<3> {
public:
    static constexpr int kBrickShift = 3; // 8 x 8 x 8 voxels: a slice of a brick is one 64-bit word

    static constexpr int kBlockShift = 1; // 2 x 2 x 2 bricks per block (lazily written, see above)

    explicit TbvMatrix(const IVec3& res)
        : m_res(res),
          m_bricks{((res.x - 1) >> kBrickShift) + 1, ((res.y - 1) >> kBrickShift) + 1, ((res.z - 1) >> kBrickShift) + 1},
          m_blocks{((m_bricks.x - 1) >> kBlockShift) + 1, ((m_bricks.y - 1) >> kBlockShift) + 1, ((m_bricks.z - 1) >> kBlockShift) + 1} {}

    /// Adds the slot's region. Returns the T incidences written: brick list nodes and cold blocks' list
    /// nodes (Boundary, Filled) or voxel list nodes (Shell).
    std::size_t insert(ObjectSlot slot, const TbvRegion<3>& r, TbvDiscretization mode) {
        if (slot >= m_boxes.size()) m_boxes.resize(std::size_t(slot) + 1);
        Stored& st = m_boxes[slot];
        st.mode = mode;
        st.inGrid = tbvVoxelBox3D(r, m_res, st.lo, st.hi);
        ++m_live;
        if (mode == TbvDiscretization::Shell) {
            if (m_voxels.empty()) m_voxels.assign(cellCount<3>(m_res), kNone);
            return forEachShellVoxel(st, [&](std::uint32_t& head) { m_lists.add(head, slot, st.nodes); });
        }
        if (m_heads.empty()) {
            const std::size_t n = cellCount<3>(m_bricks);
            m_heads.assign(n, kNone);
            m_bits = ZeroedArray<std::uint64_t>(n * kSlices);
            m_brickState.assign(n, 0);
            const std::size_t blocks = cellCount<3>(m_blocks);
            m_blockHeads.assign(blocks, kNone);
            m_blockHot.assign(blocks, 0);
        }
        if (!st.inGrid) return 0;
        // One node per cold block the box meets; brick nodes only in hot blocks.
        std::size_t n = 0;
        bool anyHot = false, anyCold = false;
        const IVec3 klo = (st.lo >> kBrickShift) >> kBlockShift, khi = (st.hi >> kBrickShift) >> kBlockShift;
        for (std::int32_t z = klo.z; z <= khi.z; ++z)
            for (std::int32_t y = klo.y; y <= khi.y; ++y) {
                const std::size_t row = blockIndex({0, y, z});
                for (std::int32_t x = klo.x; x <= khi.x; ++x) {
                    const std::size_t k = row + std::size_t(x);
                    if (m_blockHot[k] != 0) {
                        anyHot = true;
                        continue;
                    }
                    anyCold = true;
                    m_lists.add(m_blockHeads[k], slot, st.nodes);
                    ++n;
                }
            }
        if (!anyHot) return n;
        auto write = [&](std::size_t brick, const BrickPart& p) {
            m_lists.add(m_heads[brick], slot, st.nodes);
            m_brickState[brick] += 2u;
            orPart(brick, p);
        };
        if (!anyCold) // all hot (where the camera has been): every brick, no test
            return forEachBrick(st, IVec3(0), m_bricks - 1, [&](std::size_t brick, const IVec3&, const BrickPart& p) { write(brick, p); });
        forEachBrick(st, IVec3(0), m_bricks - 1, [&](std::size_t brick, const IVec3& bc, const BrickPart& p) {
            if (m_blockHot[blockOfBrick(bc)] == 0) return;
            write(brick, p);
            ++n;
        });
        return n;
    }
    /// Asks the processor for the slot's stored box and node indices (a hint, no effect on results): the
    /// culler's renewals, in no order of slots, call it a few renewals ahead of the erase that reads them.
    void prefetch(ObjectSlot slot) const {
        if (slot < m_boxes.size()) __builtin_prefetch(&m_boxes[slot], 1);
    }
    /// The voxel box (tbvVoxelBox) of the slot's region as its last insert computed it; false when the
    /// region lies outside the grid. The per-frame update marks the brick tree with it, so a renewal
    /// converts its region once (tbvVoxelBox was 3 % of the 100k room's frame, computed twice).
    bool voxelBox(ObjectSlot slot, IVec3& lo, IVec3& hi) const {
        const Stored& st = m_boxes[slot];
        lo = st.lo;
        hi = st.hi;
        return st.inGrid;
    }
    /// Removes the slot's region. Returns the incidences removed. Its bricks' bitmaps go stale (see above).
    std::size_t erase(ObjectSlot slot, const TbvRegion<3>& /*r*/, TbvDiscretization /*mode*/) {
        --m_live;
        Stored& st = m_boxes[slot];
        if (st.mode == TbvDiscretization::Shell) return m_lists.eraseAll(st.nodes);
        // Each node of the slot sits in one brick's or one block's list: its head word says which (no
        // brick parts). Its brick nodes make their bricks stale; its blocks' nodes need nothing.
        const std::uint32_t* heads = m_heads.data();
        const std::size_t bricks = m_heads.size();
        return m_lists.eraseAll(st.nodes, [&](const std::uint32_t* head) {
            if (head >= heads && head < heads + bricks) {
                std::uint32_t& state = m_brickState[std::size_t(head - heads)];
                state = (state - 2u) | 1u; // one node fewer, stale
            }
        });
    }
    /// Appends the slots whose discretization holds voxel v (in the grid), each once.
    ///
    /// Cost: one bit where no TBV holds v (a stale brick's superset bit may cost one rebuild of the
    /// brick, after which its bits are exact again); where one does, the brick's list, each entry tested
    /// against its box (a brick's list holds a slot at most once, so nothing is reported twice).
    void collectAt(const IVec3& v, std::vector<ObjectSlot>& out) {
        if (m_live == 0) return;
        if (!m_voxels.empty()) m_lists.forEach(m_voxels[voxel(v)], [&](ObjectSlot s) { out.push_back(s); });
        if (m_heads.empty()) return;
        if (!warm(v >> kBrickShift)) return;
        const std::size_t brick = brickOf(v);
        // Most voxels the traversal asks about lie in bricks no TBV reaches: the heads (4 bytes per brick)
        // stay in L1, the bitmaps (a cache line per brick) do not.
        if (m_heads[brick] == kNone || !bitAt(brick, v)) return;
        if (stale(brick)) {
            rebuild(brick);
            if (!bitAt(brick, v)) return;
        }
        m_lists.forEach(m_heads[brick], [&](ObjectSlot s) {
            if (boxHolds(m_boxes[s], v)) out.push_back(s);
        });
    }
    /// Whether some TBV holds voxel v (exact: a set bit is confirmed by the brick's list).
    bool holdsAt(const IVec3& v) const {
        if (m_live == 0) return false;
        if (!m_voxels.empty() && m_voxels[voxel(v)] != kNone) return true;
        if (m_heads.empty()) return false;
        bool any = false;
        const std::size_t block = blockOfBrick(v >> kBrickShift);
        if (m_blockHot[block] == 0) { // a cold block: its list, each box tested
            m_lists.forEach(m_blockHeads[block], [&](ObjectSlot s) { any = any || boxHolds(m_boxes[s], v); });
            return any;
        }
        const std::size_t brick = brickOf(v);
        if (m_heads[brick] == kNone || !bitAt(brick, v)) return false;
        m_lists.forEach(m_heads[brick], [&](ObjectSlot s) { any = any || boxHolds(m_boxes[s], v); });
        return any;
    }

    /// Rebuilds every stale brick now, so that collectAt and brickBits write nothing until the next
    /// erase: after it, lookups from several threads at once are safe (Culler::cullViews' view passes).
    /// Cost: one byte per brick, and each stale brick's list.
    /// Cold blocks that hold TBVs are written into their bricks first (a view pass would otherwise write
    /// them on its first lookup), so after it every block that holds a TBV is hot.
    void freshen() {
        for (std::size_t block = 0; block < m_blockHot.size(); ++block)
            if (m_blockHot[block] == 0 && m_blockHeads[block] != kNone) heat(block);
        for (std::size_t brick = 0; brick < m_brickState.size(); ++brick)
            if (stale(brick)) rebuild(brick);
    }
    std::size_t liveRegions() const { return m_live; }
    bool allocated() const { return !m_heads.empty() || !m_voxels.empty(); }
    std::size_t incidences() const { return m_lists.size(); }

    /// Brick-at-a-time lookups (the brick traversal): the voxels of brick b (brick coordinates) that some
    /// TBV holds, as 8 slice words (bit x + 8 y of slice z, brick-local), exact: a stale brick is rebuilt
    /// first, when its list holds at most rebuildUpTo TBVs. A longer one's bitmap is returned as it
    /// stands, a superset of its TBVs' voxels (the erases since its last rebuild), for a caller that
    /// confirms every voxel it acts on against the brick's parts (brickParts, collectInBrick): the brick
    /// walk, which tests the voxels against its image first and reads the parts only where one is
    /// visible. Next to a room's walls the renewals of thousands of hidden movers stale the bricks every
    /// frame, with nothing visible behind them, and rebuilding their lists of hundreds of TBVs node by
    /// node was two thirds of the 100k room's walk; short lists are rebuilt (a superset there cost the
    /// 1k room and the game world up to 10 % more image tests and part reads than the rebuilds it saved).
    /// False when no TBV reaches the brick. Boundary and Filled only (hasBrickLists()).
    bool brickBits(const IVec3& b, std::uint64_t out[8], std::uint32_t rebuildUpTo = ~std::uint32_t(0)) {
        if (m_heads.empty()) return false;
        if (!warm(b)) return false;
        const std::size_t brick = brickIndex(b);
        if (m_heads[brick] == kNone) return false;
        if (stale(brick) && listLength(brick) <= rebuildUpTo) rebuild(brick);
        const std::uint64_t* w = &m_bits[brick * kSlices];
        bool any = false;
        for (std::size_t z = 0; z < kSlices; ++z) any = (out[z] = w[z]) != 0 || any;
        return any;
    }
    /// Makes a stale brick's bitmap exact again from its parts just read (brickParts(b, ...), with no
    /// insert or erase since): their union. Nothing for a brick that is not stale (so nothing is written
    /// while cullViews' views read T at once: freshen left no brick stale). Bounds what brickBits' superset
    /// carries to the erases since the brick's last visible voxel.
    void settleBrick(const IVec3& b, const std::vector<std::array<std::uint64_t, 8>>& parts) {
        const std::size_t brick = brickIndex(b);
        if (m_brickState.empty() || !stale(brick)) return;
        std::uint64_t* w = &m_bits[brick * kSlices];
        std::fill(w, w + kSlices, 0);
        for (const std::array<std::uint64_t, 8>& part : parts)
            for (std::size_t z = 0; z < kSlices; ++z) w[z] |= part[z];
        m_brickState[brick] &= ~1u;
    }
    /// Appends, each once, the slots whose voxels in brick b meet `voxels` (8 slice words as above).
    /// Cost: the brick's list, one part (8 words at most) per entry.
    void collectInBrick(const IVec3& b, const std::uint64_t voxels[8], std::vector<ObjectSlot>& out) const {
        if (m_heads.empty()) return;
        BrickPart p;
        m_lists.forEach(listOf(b), [&](ObjectSlot s) {
            if (!brickPart(m_boxes[s], b, p)) return;
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
        if (m_heads.empty()) return;
        BrickPart p;
        m_lists.forEach(listOf(b), [&](ObjectSlot s) {
            if (!brickPart(m_boxes[s], b, p)) return;
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
        if (m_heads.empty()) return false;
        const std::size_t block = blockOfBrick(b);
        return m_blockHot[block] != 0 ? m_heads[brickIndex(b)] != kNone : m_blockHeads[block] != kNone;
    }
    /// Blocks written into their bricks so far (see the class comment); for tests and statistics.
    std::size_t hotBlocks() const { return std::size_t(std::count(m_blockHot.begin(), m_blockHot.end(), std::uint8_t(1))); }

private:
    static constexpr std::size_t kSlices = std::size_t(1) << kBrickShift; // words per brick
    static constexpr std::int32_t kBrickMask = (1 << kBrickShift) - 1;

    std::size_t voxel(const IVec3& v) const { return cellIndex<3>(m_res, v); }

    /// A slot's voxel box, clipped to the grid (inGrid false: none), how it was written, and where its
    /// nodes are: one cache line, which an erase reads once (and the renewals fetch ahead: prefetch).
    struct alignas(64) Stored {
        IVec3 lo{0}, hi{-1};
        TbvDiscretization mode = TbvDiscretization::Boundary;
        bool inGrid = false;
        TbvSlotNodes nodes;
    };
    static_assert(sizeof(Stored) == 64);

    /// Calls fn(head) for every voxel of the outer shell of a stored voxel box; returns the count.
    template <class Fn> std::size_t forEachShellVoxel(const Stored& b, Fn&& fn) {
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

    /// Whether the slot's discretization holds v: Filled, the box; Boundary, its outer shell.
    static bool boxHolds(const Stored& b, const IVec3& v) {
        bool bound = b.mode == TbvDiscretization::Filled;
        for (int a = 0; a < 3; ++a) {
            if (v[a] < b.lo[a] || v[a] > b.hi[a]) return false;
            bound = bound || v[a] == b.lo[a] || v[a] == b.hi[a];
        }
        return bound;
    }

    /// The part of a box's discretization inside one brick, as slice words (bit x + 8 y, brick-local):
    /// slices z0..z1 hold it; slice zFace0 and zFace1 (-1: none), those on the box's z bounds, and every
    /// slice of a Filled box get `face` (the box's cross-section), the others `ring` (the voxels on an x
    /// or y bound: the only shell voxels of a slice strictly between the z bounds).
    struct BrickPart {
        std::uint64_t face = 0, ring = 0;
        std::int32_t z0 = 0, z1 = -1, zFace0 = -1, zFace1 = -1;
        std::uint64_t slice(std::int32_t z) const { return z == zFace0 || z == zFace1 ? face : ring; }
    };

    /// Bits 8 y, y in [y0, y1] (0 <= y0 <= y1 <= 7): the first bit of those rows of a slice word.
    static std::uint64_t rowStarts(std::int32_t y0, std::int32_t y1) {
        const std::uint64_t below = y1 == kBrickMask ? ~std::uint64_t(0) : (std::uint64_t(1) << (8 * (y1 + 1))) - 1;
        return 0x0101010101010101ull & below & ~((std::uint64_t(1) << (8 * y0)) - 1);
    }

    /// The part of box b in the brick at brick coordinates bc; false when b's discretization misses it.
    static bool brickPart(const Stored& b, const IVec3& bc, BrickPart& p) {
        const IVec3 o = bc * (1 << kBrickShift);
        IVec3 l, h;
        for (int a = 0; a < 3; ++a) {
            l[a] = std::max(b.lo[a], o[a]);
            h[a] = std::min(b.hi[a], o[a] + kBrickMask);
            if (l[a] > h[a]) return false;
        }
        // xs * rows copies the row's byte into each row (xs < 256 and rows' bits are 8 apart: no carries).
        const std::uint64_t xs = ((std::uint64_t(2) << (h.x - o.x)) - 1) & ~((std::uint64_t(1) << (l.x - o.x)) - 1);
        const std::uint64_t rows = rowStarts(l.y - o.y, h.y - o.y);
        p.face = xs * rows;
        p.z0 = l.z - o.z;
        p.z1 = h.z - o.z;
        if (b.mode == TbvDiscretization::Filled) {
            p.ring = p.face;
            p.zFace0 = p.zFace1 = -1;
            return true;
        }
        // A bound of the box lies in the brick iff the clipped range starts (ends) at it.
        p.ring = 0;
        if (l.y == b.lo.y) p.ring |= xs << (8 * (b.lo.y - o.y));
        if (h.y == b.hi.y) p.ring |= xs << (8 * (b.hi.y - o.y));
        if (l.x == b.lo.x) p.ring |= rows << (b.lo.x - o.x);
        if (h.x == b.hi.x) p.ring |= rows << (b.hi.x - o.x);
        p.zFace0 = l.z == b.lo.z ? p.z0 : -1;
        p.zFace1 = h.z == b.hi.z ? p.z1 : -1;
        return p.ring != 0 || p.zFace0 >= 0 || p.zFace1 >= 0;
    }

    /// Calls fn(brick, part) for every brick the box's discretization reaches; returns their count. The
    /// same parts as brickPart gives, with what depends on one axis only computed once per brick along
    /// that axis (brickPart per brick was a third of an insert on rgvc_bench_classes' paper scene), and
    /// for Boundary the shell's hollow inside skipped: between the box's faces on y and z only the first
    /// and the last brick along x hold shell voxels (those of its x faces). Only the bricks in
    /// [clipLo, clipHi] (brick coordinates) are visited; fn gets the brick's index and coordinates.
    template <class Fn> std::size_t forEachBrick(const Stored& b, const IVec3& clipLo, const IVec3& clipHi, Fn&& fn) const {
        if (!b.inGrid) return 0;
        std::size_t n = 0;
        BrickPart p;
        const bool filled = b.mode == TbvDiscretization::Filled;
        const IVec3 lo = b.lo >> kBrickShift, hi = b.hi >> kBrickShift;
        const IVec3 from = glm::max(lo, clipLo), to = glm::min(hi, clipHi);
        for (std::int32_t bz = from.z; bz <= to.z; ++bz) {
            const std::int32_t oz = bz << kBrickShift;
            const std::int32_t lz = std::max(b.lo.z, oz), hz = std::min(b.hi.z, oz + kBrickMask);
            p.z0 = lz - oz;
            p.z1 = hz - oz;
            p.zFace0 = !filled && lz == b.lo.z ? p.z0 : -1;
            p.zFace1 = !filled && hz == b.hi.z ? p.z1 : -1;
            const bool zFace = p.zFace0 >= 0 || p.zFace1 >= 0;
            for (std::int32_t by = from.y; by <= to.y; ++by) {
                const std::int32_t oy = by << kBrickShift;
                const std::int32_t ly = std::max(b.lo.y, oy), hy = std::min(b.hi.y, oy + kBrickMask);
                const std::uint64_t rows = rowStarts(ly - oy, hy - oy);
                const bool yLo = ly == b.lo.y, yHi = hy == b.hi.y;
                // Boundary, strictly between the faces on y and z: only the x faces' bricks.
                const bool hollow = !filled && !zFace && !yLo && !yHi;
                const std::int32_t step = hollow ? std::max(1, hi.x - lo.x) : 1;
                for (std::int32_t bx = hollow ? lo.x : from.x; bx <= to.x; bx += step) {
                    if (bx < from.x) continue; // hollow: lo.x left of the clip, hi.x may be in it
                    const std::int32_t ox = bx << kBrickShift;
                    const std::int32_t lx = std::max(b.lo.x, ox), hx = std::min(b.hi.x, ox + kBrickMask);
                    // xs * rows copies the row's byte into each row (no carries: see brickPart).
                    const std::uint64_t xs = ((std::uint64_t(2) << (hx - ox)) - 1) & ~((std::uint64_t(1) << (lx - ox)) - 1);
                    p.face = xs * rows;
                    if (filled) {
                        p.ring = p.face;
                    } else {
                        p.ring = 0;
                        if (yLo) p.ring |= xs << (8 * (b.lo.y - oy));
                        if (yHi) p.ring |= xs << (8 * (b.hi.y - oy));
                        if (lx == b.lo.x) p.ring |= rows << (b.lo.x - ox);
                        if (hx == b.hi.x) p.ring |= rows << (b.hi.x - ox);
                        if (p.ring == 0 && !zFace) continue;
                    }
                    fn(brickIndex({bx, by, bz}), IVec3{bx, by, bz}, p);
                    ++n;
                }
            }
        }
        return n;
    }

    std::size_t blockIndex(const IVec3& k) const { return cellIndex<3>(m_blocks, k); }
    std::size_t blockOfBrick(const IVec3& bc) const { return blockIndex(bc >> kBlockShift); }
    /// The list to read for brick bc: its own in a hot block, its block's in a cold one (a superset:
    /// every TBV whose box meets the block; callers test each against the brick).
    std::uint32_t listOf(const IVec3& bc) const {
        const std::size_t block = blockOfBrick(bc);
        return m_blockHot[block] != 0 ? m_heads[brickIndex(bc)] : m_blockHeads[block];
    }
    /// Makes brick bc's block hot if it is not; false when it is cold and holds no TBV (nothing written).
    bool warm(const IVec3& bc) {
        const std::size_t block = blockOfBrick(bc);
        if (m_blockHot[block] != 0) return true;
        if (m_blockHeads[block] == kNone) return false;
        heat(block);
        return true;
    }
    /// Writes a cold block's TBVs into its bricks (clipped to it) and marks it hot. Its list's nodes stay
    /// in their slots' chains until erased; nothing reads them again.
    void heat(std::size_t block) {
        m_blockHot[block] = 1;
        const IVec3 lo = cellOf<3>(m_blocks, block) << kBlockShift;
        const IVec3 hi = glm::min(lo + ((1 << kBlockShift) - 1), m_bricks - 1);
        // (add() may grow the pool under forEach: forEach reads each next link by index, after fn.)
        m_lists.forEach(m_blockHeads[block], [&](ObjectSlot s) {
            forEachBrick(m_boxes[s], lo, hi, [&](std::size_t brick, const IVec3&, const BrickPart& p) {
                m_lists.add(m_heads[brick], s, m_boxes[s].nodes);
                m_brickState[brick] += 2u;
                orPart(brick, p);
            });
        });
    }

    void orPart(std::size_t brick, const BrickPart& p) {
        std::uint64_t* w = &m_bits[brick * kSlices];
        // The ring on every slice, then the face on the face slices (ring is part of face): the same words
        // as slice(z) per slice, without its selects in the loop.
        for (std::int32_t z = p.z0; z <= p.z1; ++z) w[z] |= p.ring;
        if (p.zFace0 >= 0) w[p.zFace0] |= p.face;
        if (p.zFace1 >= 0) w[p.zFace1] |= p.face;
    }

    /// The brick's bitmap, recomputed from its list: exactly the union of its live TBVs' parts.
    void rebuild(std::size_t brick) {
        std::uint64_t* w = &m_bits[brick * kSlices];
        std::fill(w, w + kSlices, 0);
        const IVec3 bc = cellOf<3>(m_bricks, brick);
        BrickPart p;
        m_lists.forEach(m_heads[brick], [&](ObjectSlot s) {
            if (brickPart(m_boxes[s], bc, p)) orPart(brick, p);
        });
        m_brickState[brick] &= ~1u;
    }

    std::size_t brickIndex(const IVec3& bc) const { return cellIndex<3>(m_bricks, bc); }
    std::size_t brickOf(const IVec3& v) const { return brickIndex(v >> kBrickShift); }
    bool bitAt(std::size_t brick, const IVec3& v) const {
        const std::uint64_t w = m_bits[brick * kSlices + std::size_t(v.z & kBrickMask)];
        return ((w >> ((v.x & kBrickMask) + 8 * (v.y & kBrickMask))) & 1) != 0;
    }

    IVec3 m_res;
    IVec3 m_bricks;                      // bricks per axis (the last ones may reach past the grid)
    std::vector<std::uint32_t> m_heads;  // per brick: the head of its list of slots
    // per brick, kSlices words: a superset of its TBVs' voxels (exact unless stale). Zero pages until a
    // brick of a hot block is written (ZeroedArray.hpp): 64 bytes a brick, 4 MiB over a 512 x 128 x 512
    // grid, were cleared by the first insert (a tenth of the large world's 16 frames in callgrind).
    ZeroedArray<std::uint64_t> m_bits;
    // Per brick: bit 0, an erase since its last rebuild (stale); above it, the length of its list (the
    // rebuild's cost: brickBits' rebuildUpTo).
    std::vector<std::uint32_t> m_brickState;
    bool stale(std::size_t brick) const { return (m_brickState[brick] & 1u) != 0; }
    std::uint32_t listLength(std::size_t brick) const { return m_brickState[brick] >> 1; }
    IVec3 m_blocks;                           // blocks of 2^3 bricks per axis
    std::vector<std::uint32_t> m_blockHeads;  // per block: while cold, the TBVs whose box meets it
    std::vector<std::uint8_t> m_blockHot;     // per block: its bricks' lists and bitmaps are written
    std::vector<std::uint32_t> m_voxels; // Shell: one list head per voxel
    TbvListPool m_lists;
    std::vector<Stored> m_boxes;         // per slot: its box, to test and to find its bricks
    std::size_t m_live = 0;
};


} // namespace rgvc
