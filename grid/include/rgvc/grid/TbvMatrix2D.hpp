// TbvMatrix<2>: T in 2D, counts per voxel and lists per tile (TbvRegion.hpp says what is stored and why
// the boundary suffices).
#pragma once

#include "rgvc/grid/TbvRegion.hpp"
#include "rgvc/grid/ZeroedArray.hpp"

#include <cstring>

namespace rgvc {

/// 2D T: a count of TBVs per voxel, and per 8 x 8 tile of voxels a list of the TBVs whose ring crosses it.
/// Allocated on the first insert (a scene without moving objects never allocates or reads it).
///
/// Why counts and tiles, not a list per voxel: with 100,000 hidden objects rings overlap by the dozen
/// (100,000 rings of ~135 voxels on the dynamic benchmark), and a renewal rewrote ~135 list nodes scattered
/// over memory (~11 us, cache misses). A renewal now adds and subtracts along the ring's rows (contiguous runs) and
/// touches a dozen tile lists. A lookup reads one count; only where it is non-zero, which the traversal
/// meets only at TBVs it reveals, does it test the tile's TBVs against the voxel with the very
/// computation that drew them (tbvCovers2D), so the count and the lists always agree.
template <> class TbvMatrix<2> {
public:
    static constexpr int kTileShift = 3; // 8 x 8 voxels

    explicit TbvMatrix(const IVec2& res)
        : m_res(res), m_tiles{((res.x - 1) >> kTileShift) + 1, ((res.y - 1) >> kTileShift) + 1} {}

    /// Adds the slot's region. Returns the number of voxel incidences written.
    std::size_t insert(ObjectSlot slot, const TbvRegion<2>& r, TbvDiscretization mode) {
        if (m_counts.size() == 0) {
            m_counts = ZeroedArray<std::uint8_t>(std::size_t(m_tiles.x) * std::size_t(m_tiles.y) * kTileArea);
            m_tileHeads.assign(std::size_t(m_tiles.x) * std::size_t(m_tiles.y), kNone);
            m_tileMark.assign(m_tileHeads.size(), 0);
        }
        if (slot >= m_regions.size()) m_regions.resize(std::size_t(slot) + 1);
        m_regions[slot] = {r, mode};
        if (++m_mark == 0) { // wrapped: forget every old mark
            std::fill(m_tileMark.begin(), m_tileMark.end(), 0);
            m_mark = 1;
        }
        std::size_t n = 0;
        forEachTbvRun2D(r, m_res, mode, [&](std::int32_t y, std::int32_t x0, std::int32_t x1) {
            for (std::int32_t x = x0; x <= x1; ++x) {
                std::uint8_t& c = m_counts[key(x, y)];
                c = std::uint8_t(c + (c != kSticky));
            }
            n += std::size_t(x1 - x0 + 1);
            // Each tile the ring crosses gets the slot once (rows of one tile row meet the same tiles).
            const std::size_t tileRow = std::size_t(y >> kTileShift) * std::size_t(m_tiles.x);
            for (std::int32_t t = x0 >> kTileShift; t <= (x1 >> kTileShift); ++t) {
                const std::size_t tile = tileRow + std::size_t(t);
                if (m_tileMark[tile] == m_mark) continue;
                m_tileMark[tile] = m_mark;
                m_tileLists.add(m_tileHeads[tile], slot);
            }
        });
        m_incidences += n;
        ++m_live;
        return n;
    }
    /// Removes the slot's region (added with these arguments). Returns the incidences removed. Cost: the
    /// region's own rows and tiles.
    std::size_t erase(ObjectSlot slot, const TbvRegion<2>& /*r*/, TbvDiscretization /*mode*/) {
        const Stored& st = m_regions[slot];
        std::size_t n = 0;
        forEachTbvRun2D(st.region, m_res, st.mode, [&](std::int32_t y, std::int32_t x0, std::int32_t x1) {
            for (std::int32_t x = x0; x <= x1; ++x) {
                std::uint8_t& c = m_counts[key(x, y)];
                c = std::uint8_t(c - (c != kSticky));
            }
            n += std::size_t(x1 - x0 + 1);
        });
        m_tileLists.eraseAll(slot);
        m_incidences -= n;
        --m_live;
        return n;
    }
    /// Appends the slots whose TBV covers voxel v (in the grid) to out.
    void collectAt(const IVec2& v, std::vector<ObjectSlot>& out) const {
        if (m_live == 0 || m_counts[key(v.x, v.y)] == 0) return;
        const std::size_t tile = std::size_t(v.y >> kTileShift) * std::size_t(m_tiles.x) + std::size_t(v.x >> kTileShift);
        m_tileLists.forEach(m_tileHeads[tile], [&](ObjectSlot s) {
            if (tbvCovers2D(m_regions[s].region, m_res, m_regions[s].mode, v)) out.push_back(s);
        });
    }
    /// Whether some TBV holds voxel v (exact: a saturated count is settled by the tile's lists).
    bool holdsAt(const IVec2& v) const {
        if (m_live == 0) return false;
        const std::uint8_t c = m_counts[key(v.x, v.y)];
        if (c != kSticky) return c != 0;
        bool any = false;
        const std::size_t tile = std::size_t(v.y >> kTileShift) * std::size_t(m_tiles.x) + std::size_t(v.x >> kTileShift);
        m_tileLists.forEach(m_tileHeads[tile], [&](ObjectSlot s) {
            any = any || tbvCovers2D(m_regions[s].region, m_res, m_regions[s].mode, v);
        });
        return any;
    }

    /// Makes every later lookup read-only (see TbvMatrix<3>::freshen); 2D lookups always are.
    void freshen() {}
    /// Whether some TBV may hold voxel v: one count read (false is a guarantee; true may be a saturated
    /// count, which collectAt settles).
    bool mayHoldAt(const IVec2& v) const { return m_live != 0 && m_counts[key(v.x, v.y)] != 0; }
    /// mayHoldAt for the 8 voxels of row `row` (0..7) of tile t (tile coordinates): bit i for voxel
    /// (8 t.x + i, 8 t.y + row). One 8-byte read (a tile's row of counts is contiguous: key()); voxels past
    /// the grid's edge have count 0.
    std::uint8_t mayHoldRow(const IVec2& t, int row) const {
        if (m_live == 0) return 0;
        std::uint64_t w;
        std::memcpy(&w, m_counts.data() + (std::size_t(t.y) * std::size_t(m_tiles.x) + std::size_t(t.x)) * kTileArea +
                            (std::size_t(row) << kTileShift), sizeof w);
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
    std::size_t incidences() const { return m_incidences; }

private:
    struct Stored {
        TbvRegion<2> region;
        TbvDiscretization mode = TbvDiscretization::Boundary;
    };
    static constexpr std::size_t kTileArea = std::size_t(1) << (2 * kTileShift);
    /// Counts are stored tile by tile (8 x 8 voxels in 64 contiguous bytes, one cache line): a ring's rows
    /// then share cache lines within a tile, where row-major rows are a grid width apart (measured:
    /// renewals were bound by one cache miss per ring row).
    std::size_t key(std::int32_t x, std::int32_t y) const {
        const std::size_t tile = std::size_t(y >> kTileShift) * std::size_t(m_tiles.x) + std::size_t(x >> kTileShift);
        const std::size_t mask = (std::size_t(1) << kTileShift) - 1;
        return tile * kTileArea + ((std::size_t(y) & mask) << kTileShift) + (std::size_t(x) & mask);
    }
    IVec2 m_res;
    IVec2 m_tiles;
    /// Per voxel, tile by tile: how many TBVs hold it, saturating at kSticky, where it stays for good.
    /// Below kSticky the count is exact; at kSticky it only says "maybe", and a lookup scans the tile's
    /// lists, which are exact. One byte instead of four: the renewals' ring writes were bound by the
    /// cache misses on this array (measured below), and a quarter of the bytes is a quarter of the lines.
    /// Zero pages until written (ZeroedArray.hpp): a 2048^2 grid's 4 MiB were cleared by the first insert.
    ZeroedArray<std::uint8_t> m_counts;
    static constexpr std::uint8_t kSticky = 255;
    std::vector<std::uint32_t> m_tileHeads; // per tile: list of TBVs crossing it
    TbvListPool m_tileLists;
    std::vector<Stored> m_regions;          // per slot: its region, to test and to erase
    std::vector<std::uint32_t> m_tileMark; // per tile: the insert that last added to its list
    std::uint32_t m_mark = 0;
    std::size_t m_incidences = 0;
    std::size_t m_live = 0;
};

} // namespace rgvc
