// TbvMatrix<2>: T in 2D, counts per voxel and lists per tile (TbvRegion.hpp says what is stored and why
// the boundary suffices).
#pragma once

#include "rgvc/grid/TbvRegion.hpp"
#include "rgvc/grid/ZeroedArray.hpp"

#include <cstring>

namespace rgvc {

/// 2D T: a count of TBVs per voxel, and per 8 x 8 tile of voxels a list of the TBVs whose ring crosses it
/// (and, where rounding within kConservativeSlack of a voxel corner widens a band's runs, perhaps a tile
/// beside those: tbvBandRuns2D; lookups test the voxel, so a list may be longer, never shorter).
/// Allocated on the first insert (a scene without moving objects never allocates or reads it).
///
/// Why counts and tiles, not a list per voxel: with 100,000 hidden objects rings overlap by the dozen
/// (100,000 rings of ~135 voxels on the dynamic benchmark), and a renewal rewrote ~135 list nodes scattered
/// over memory (~11 us, cache misses). A renewal now adds and subtracts along the ring's rows (contiguous runs) and
/// touches a dozen tile lists. A lookup reads one count; only where it is non-zero, which the traversal
/// meets only at TBVs it reveals, does it test the tile's TBVs against the voxel with the very
/// computation that drew them (tbvCovers2D), so the count and the lists always agree.
///
/// Counts written lazily, tile by tile (as TbvMatrix<3>'s bricks are block by block). The counts of a tile
/// are read only when a lookup asks about a voxel of it, and the brick walk asks only about tiles in view
/// that hold some TBV's ring: around a closed room, or in a large world, most rings lie where no lookup
/// goes. T's inserts and erases were 22-49 % of the 2D classes' instructions (rgvc_bench_classes' random
/// scenes, city, room and large world), and writing counts only where lookups go took 6-15 % off the
/// classes' totals. An insert finds the tiles that list the TBV a tile row at a time (tbvBandRuns2D),
/// and it and an erase compute a ring's rows only in tile rows with a hot tile (computing every row on
/// insert was a third of the 2D room's instructions after the counts went lazy). So a tile no lookup
/// has needed yet ("cold") keeps only its list, and its counts stay zero; the first lookup that needs them (mayHoldAt,
/// mayHoldRow, collectAt) writes them from the list's TBVs (each TBV's runs clipped to the tile), and the
/// tile stays "hot": inserts and erases update its counts from then on. holdsAt answers a cold tile from
/// its list without writing, and freshen() heats every cold tile that has a list, after which no lookup
/// writes (cullViews' concurrent passes). Every lookup returns what it did when every count was written
/// eagerly, except that a count may be below the sticky 255 where eager writing had saturated it; both
/// say "maybe" there and the lists settle it.
template <> class TbvMatrix<2> {
public:
    static constexpr int kTileShift = 3; // 8 x 8 voxels

    explicit TbvMatrix(const IVec2& res)
        : m_res(res), m_tiles{((res.x - 1) >> kTileShift) + 1, ((res.y - 1) >> kTileShift) + 1} {}

    /// Adds the slot's region. Returns the T incidences written: the tile list nodes, one per tile its
    /// discretization crosses (as TbvMatrix<3> counts its brick lists' nodes; the counts of hot tiles are
    /// a cache of those lists, not counted).
    std::size_t insert(ObjectSlot slot, const TbvRegion<2>& r, TbvDiscretization mode) {
        if (m_counts.size() == 0) {
            m_counts = ZeroedArray<std::uint8_t>(std::size_t(m_tiles.x) * std::size_t(m_tiles.y) * kTileArea);
            m_tileHeads.assign(std::size_t(m_tiles.x) * std::size_t(m_tiles.y), kNone);
            m_tileMark.assign(m_tileHeads.size(), 0);
            m_tileHot.assign(m_tileHeads.size(), 0);
        }
        if (slot >= m_regions.size()) m_regions.resize(std::size_t(slot) + 1);
        Stored& st = m_regions[slot];
        st.region = r;
        st.mode = mode;
        ++m_live;
        // The tiles of its voxel box (erase looks for hot ones there): they hold every tile its ring crosses.
        IVec2 lo, hi;
        if (!tbvVoxelBox<2>(r, m_res, lo, hi)) {
            st.tileLo = IVec2(0);
            st.tileHi = IVec2(-1);
            return 0;
        }
        st.tileLo = lo >> kTileShift;
        st.tileHi = hi >> kTileShift;
        if (++m_mark == 0) { // wrapped: forget every old mark
            std::fill(m_tileMark.begin(), m_tileMark.end(), 0);
            m_mark = 1;
        }
        std::size_t n = 0;
        // A tile row at a time: the band's runs (tbvBandRuns2D: two square roots for its 8 rows) say which
        // tiles list the slot, each once (a band's two runs may share a tile). Only a band that meets a
        // hot tile computes its rows, to add to that tile's counts.
        for (std::int32_t ty = st.tileLo.y; ty <= st.tileHi.y; ++ty) {
            const std::int32_t yA = ty << kTileShift, yB = std::min(m_res.y - 1, yA + kTileMask);
            const std::size_t tileRow = std::size_t(ty) * std::size_t(m_tiles.x);
            bool anyHot = false;
            tbvBandRuns2D(r, m_res, mode, yA, yB, [&](std::int32_t x0, std::int32_t x1) {
                for (std::int32_t t = x0 >> kTileShift; t <= (x1 >> kTileShift); ++t) {
                    const std::size_t tile = tileRow + std::size_t(t);
                    if (m_tileMark[tile] != m_mark) {
                        m_tileMark[tile] = m_mark;
                        m_tileLists.add(m_tileHeads[tile], slot, st.nodes);
                        ++n;
                    }
                    anyHot = anyHot || m_tileHot[tile] != 0;
                }
            });
            if (anyHot) updateHotCounts(st, ty, addOne);
        }
        return n;
    }
    /// Removes the slot's region (added with these arguments). Returns the incidences removed. Cost: its
    /// tiles' lists, and its rows only where a tile of it is hot.
    std::size_t erase(ObjectSlot slot, const TbvRegion<2>& /*r*/, TbvDiscretization /*mode*/) {
        Stored& st = m_regions[slot];
        // Only the tile rows of its box with a hot tile are computed again (a ring around a room, whose
        // tiles along the walls the walk has read, is hot there and nowhere else).
        for (std::int32_t ty = st.tileLo.y; ty <= st.tileHi.y; ++ty) {
            const std::size_t tileRow = std::size_t(ty) * std::size_t(m_tiles.x);
            bool anyHot = false;
            for (std::int32_t tx = st.tileLo.x; tx <= st.tileHi.x && !anyHot; ++tx) anyHot = m_tileHot[tileRow + std::size_t(tx)] != 0;
            if (anyHot) updateHotCounts(st, ty, removeOne);
        }
        --m_live;
        return m_tileLists.eraseAll(st.nodes);
    }
    /// Asks the processor for the slot's stored region and node indices (a hint, as TbvMatrix<3>'s).
    void prefetch(ObjectSlot slot) const {
        if (slot < m_regions.size()) __builtin_prefetch(&m_regions[slot], 1);
    }
    /// Appends the slots whose TBV covers voxel v (in the grid) to out. Writes v's tile's counts first if
    /// they are not yet.
    void collectAt(const IVec2& v, std::vector<ObjectSlot>& out) {
        if (m_live == 0) return;
        const std::size_t tile = tileOf(v);
        warm(tile);
        if (m_counts[key(v.x, v.y)] == 0) return;
        m_tileLists.forEach(m_tileHeads[tile], [&](ObjectSlot s) {
            if (tbvCovers2D(m_regions[s].region, m_res, m_regions[s].mode, v)) out.push_back(s);
        });
    }
    /// Whether some TBV holds voxel v (exact: a saturated count, or a cold tile, is settled by the tile's
    /// lists). Writes nothing.
    bool holdsAt(const IVec2& v) const {
        if (m_live == 0) return false;
        const std::size_t tile = tileOf(v);
        if (m_tileHot[tile] != 0) {
            const std::uint8_t c = m_counts[key(v.x, v.y)];
            if (c != kSticky) return c != 0;
        }
        bool any = false;
        m_tileLists.forEach(m_tileHeads[tile], [&](ObjectSlot s) {
            any = any || tbvCovers2D(m_regions[s].region, m_res, m_regions[s].mode, v);
        });
        return any;
    }

    /// Writes the counts of every tile that holds a TBV and has none yet: every later lookup is then
    /// read-only (cullViews' passes read T at once; see TbvMatrix<3>::freshen).
    void freshen() {
        for (std::size_t tile = 0; tile < m_tileHot.size(); ++tile) warm(tile);
    }
    /// Whether some TBV may hold voxel v: one count read (false is a guarantee; true may be a saturated
    /// count, which collectAt settles). Writes v's tile's counts first if they are not yet.
    bool mayHoldAt(const IVec2& v) {
        if (m_live == 0) return false;
        warm(tileOf(v));
        return m_counts[key(v.x, v.y)] != 0;
    }
    /// mayHoldAt for the 8 voxels of row `row` (0..7) of tile t (tile coordinates): bit i for voxel
    /// (8 t.x + i, 8 t.y + row). One 8-byte read (a tile's row of counts is contiguous: key()); voxels past
    /// the grid's edge have count 0. Writes the tile's counts first if they are not yet.
    std::uint8_t mayHoldRow(const IVec2& t, int row) {
        if (m_live == 0) return 0;
        const std::size_t tile = std::size_t(t.y) * std::size_t(m_tiles.x) + std::size_t(t.x);
        warm(tile);
        std::uint64_t w;
        std::memcpy(&w, m_counts.data() + tile * kTileArea + (std::size_t(row) << kTileShift), sizeof w);
        // Bit 7 of each byte: set when the byte is non-zero (its low 7 bits plus 0x7f carry into bit 7, or
        // bit 7 was set), without carries between bytes. Then bit 8 i -> bit 56 + i by one product.
        constexpr std::uint64_t kLow7 = 0x7f7f7f7f7f7f7f7fULL;
        const std::uint64_t nonZero = ((((w & kLow7) + kLow7) | w) & ~kLow7) >> 7;
        return std::uint8_t((nonZero * 0x0102040810204080ULL) >> 56);
    }
    /// Whether some TBV may hold a voxel of tile t (tile coordinates, 8 x 8 voxels: the brick traversal's
    /// bricks): false is a guarantee (every insert lists the slot in each tile its ring crosses).
    bool mayHoldTile(const IVec2& t) const {
        return m_live != 0 && !m_tileHeads.empty() &&
               m_tileHeads[std::size_t(t.y) * std::size_t(m_tiles.x) + std::size_t(t.x)] != kNone;
    }
    std::size_t liveRegions() const { return m_live; }
    bool allocated() const { return m_counts.size() != 0; }
    /// Tile list nodes in use (what inserts returned less what erases did).
    std::size_t incidences() const { return m_tileLists.size(); }
    /// Tiles whose counts are written (at most one per tile that some lookup needed or freshen() heated).
    std::size_t hotTiles() const { return std::size_t(std::count(m_tileHot.begin(), m_tileHot.end(), 1)); }

private:
    struct Stored {
        TbvRegion<2> region;
        TbvDiscretization mode = TbvDiscretization::Boundary;
        IVec2 tileLo{0}, tileHi{-1}; // the tiles of its voxel box (tbvVoxelBox): every tile its ring crosses
        TbvSlotNodes nodes;          // its tile lists' nodes
    };
    static constexpr std::size_t kTileArea = std::size_t(1) << (2 * kTileShift);
    static constexpr std::int32_t kTileMask = (1 << kTileShift) - 1;
    /// Counts are stored tile by tile (8 x 8 voxels in 64 contiguous bytes, one cache line): a ring's rows
    /// then share cache lines within a tile, where row-major rows are a grid width apart (measured:
    /// renewals were bound by one cache miss per ring row).
    std::size_t key(std::int32_t x, std::int32_t y) const {
        const std::size_t tile = std::size_t(y >> kTileShift) * std::size_t(m_tiles.x) + std::size_t(x >> kTileShift);
        const std::size_t mask = (std::size_t(1) << kTileShift) - 1;
        return tile * kTileArea + ((std::size_t(y) & mask) << kTileShift) + (std::size_t(x) & mask);
    }
    std::size_t tileOf(const IVec2& v) const {
        return std::size_t(v.y >> kTileShift) * std::size_t(m_tiles.x) + std::size_t(v.x >> kTileShift);
    }
    /// A count's step up or down; kSticky stays (see m_counts).
    static void addOne(std::uint8_t& c) { c = std::uint8_t(c + (c != kSticky)); }
    static void removeOne(std::uint8_t& c) { c = std::uint8_t(c - (c != kSticky)); }
    /// fn(count) for voxels x0..x1 of row y, all in one tile.
    template <class Fn> void forEachCount(std::int32_t y, std::int32_t x0, std::int32_t x1, Fn&& fn) {
        for (std::int32_t x = x0; x <= x1; ++x) fn(m_counts[key(x, y)]);
    }
    /// fn(count) for the voxels of the region's runs in tile row ty that lie in hot tiles (an insert's or
    /// an erase's count updates).
    template <class Fn> void updateHotCounts(const Stored& st, std::int32_t ty, Fn&& fn) {
        const std::size_t tileRow = std::size_t(ty) * std::size_t(m_tiles.x);
        const std::int32_t y1 = std::min(m_res.y - 1, (ty << kTileShift) + kTileMask);
        for (std::int32_t y = ty << kTileShift; y <= y1; ++y)
            tbvRowRuns2D(st.region, m_res, st.mode, y, [&](std::int32_t, std::int32_t x0, std::int32_t x1) {
                for (std::int32_t t = x0 >> kTileShift; t <= (x1 >> kTileShift); ++t)
                    if (m_tileHot[tileRow + std::size_t(t)] != 0)
                        forEachCount(y, std::max(x0, t << kTileShift), std::min(x1, (t << kTileShift) + kTileMask), fn);
            });
    }
    /// Writes a cold tile's counts from the TBVs of its list (each one's runs clipped to the tile), and
    /// keeps it hot. A cold tile's counts are all zero: no insert or erase wrote them.
    void warm(std::size_t tile) {
        if (m_tileHot[tile] == 0 && m_tileHeads[tile] != kNone) heat(tile);
    }
    // Out of line: it runs once per tile, and inlined into every lookup it grew the walk's translation
    // unit enough that GCC stopped inlining a vector's push_back into the 3D classify (+0.7 % instructions
    // on the 3D clusters).
    [[gnu::noinline]] void heat(std::size_t tile) {
        m_tileHot[tile] = 1;
        const std::int32_t tx = std::int32_t(tile % std::size_t(m_tiles.x)), ty = std::int32_t(tile / std::size_t(m_tiles.x));
        const std::int32_t xa = tx << kTileShift, xb = std::min(m_res.x - 1, xa + kTileMask);
        const std::int32_t ya = ty << kTileShift, yb = std::min(m_res.y - 1, ya + kTileMask);
        m_tileLists.forEach(m_tileHeads[tile], [&](ObjectSlot s) {
            const Stored& st = m_regions[s];
            for (std::int32_t y = ya; y <= yb; ++y)
                tbvRowRuns2D(st.region, m_res, st.mode, y, [&](std::int32_t, std::int32_t x0, std::int32_t x1) {
                    x0 = std::max(x0, xa);
                    x1 = std::min(x1, xb);
                    if (x0 <= x1) forEachCount(y, x0, x1, addOne);
                });
        });
    }
    IVec2 m_res;
    IVec2 m_tiles;
    /// Per voxel, tile by tile: how many TBVs hold it, saturating at kSticky, where it stays for good.
    /// Below kSticky the count is exact; at kSticky it only says "maybe", and a lookup scans the tile's
    /// lists, which are exact. One byte instead of four: the renewals' ring writes were bound by the
    /// cache misses on this array (measured below), and a quarter of the bytes is a quarter of the lines.
    /// Zero pages until written (ZeroedArray.hpp): a 2048^2 grid's 4 MiB were cleared by the first insert.
    /// Written only in hot tiles (above).
    ZeroedArray<std::uint8_t> m_counts;
    static constexpr std::uint8_t kSticky = 255;
    std::vector<std::uint32_t> m_tileHeads; // per tile: list of TBVs crossing it
    TbvListPool m_tileLists;
    std::vector<Stored> m_regions;          // per slot: its region, to test and to erase
    std::vector<std::uint32_t> m_tileMark; // per tile: the insert that last added to its list
    std::vector<std::uint8_t> m_tileHot;   // per tile: its counts are written (a lookup needed them)
    std::uint32_t m_mark = 0;
    std::size_t m_live = 0;
};

} // namespace rgvc
