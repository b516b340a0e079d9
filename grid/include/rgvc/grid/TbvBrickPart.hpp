// TbvBrickPart: the part of one TBV's discretization that lies in one 8 x 8 x 8 brick, as slice words;
// what TbvMatrix<3> stores per brick (TbvMatrix3D.hpp) and ORs into the brick's bitmap.
#pragma once

#include "rgvc/grid/TbvRegion.hpp"

#include <algorithm>
#include <cstdint>

namespace rgvc {

/// Bricks of 8 x 8 x 8 voxels: a slice of a brick is one 64-bit word, bit x + 8 y (brick-local).
inline constexpr int kTbvBrickShift = 3;
inline constexpr std::int32_t kTbvBrickMask = (1 << kTbvBrickShift) - 1;

/// A TBV's voxel box, clipped to the grid (inGrid false: none), and how it is discretized.
struct TbvVoxelBox {
    IVec3 lo{0}, hi{-1};
    TbvDiscretization mode = TbvDiscretization::Boundary;
    bool inGrid = false;
};

/// Whether the box's discretization holds voxel v: Filled, the box; Boundary (and Shell), its outer shell.
inline bool tbvBoxHolds(const TbvVoxelBox& b, const IVec3& v) {
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
/// or y bound: the only shell voxels of a slice strictly between the z bounds). 24 bytes: the brick
/// lists store it as it is (TbvMatrix<3>), so that a rebuild ORs parts without their boxes.
struct TbvBrickPart {
    std::uint64_t face = 0, ring = 0;
    std::int8_t z0 = 0, z1 = -1, zFace0 = -1, zFace1 = -1;

    std::uint64_t slice(std::int32_t z) const { return z == zFace0 || z == zFace1 ? face : ring; }
    /// Whether the part holds the brick-local voxel l (each coordinate in 0..7).
    bool holds(const IVec3& l) const {
        return l.z >= z0 && l.z <= z1 && ((slice(l.z) >> (l.x + 8 * l.y)) & 1) != 0;
    }
    /// ORs the part into a brick's 8 slice words: the ring on every slice, then the face on the face
    /// slices (ring is part of face): the same words as slice(z) per slice, without its selects.
    void orInto(std::uint64_t* w) const {
        for (std::int32_t z = z0; z <= z1; ++z) w[z] |= ring;
        if (zFace0 >= 0) w[zFace0] |= face;
        if (zFace1 >= 0) w[zFace1] |= face;
    }
};

/// Bits 8 y, y in [y0, y1] (0 <= y0 <= y1 <= 7): the first bit of those rows of a slice word.
inline std::uint64_t tbvRowStarts(std::int32_t y0, std::int32_t y1) {
    const std::uint64_t below = y1 == kTbvBrickMask ? ~std::uint64_t(0) : (std::uint64_t(1) << (8 * (y1 + 1))) - 1;
    return 0x0101010101010101ull & below & ~((std::uint64_t(1) << (8 * y0)) - 1);
}

/// The part of box b in the brick at brick coordinates bc; false when b's discretization misses it.
inline bool tbvBrickPart(const TbvVoxelBox& b, const IVec3& bc, TbvBrickPart& p) {
    const IVec3 o = bc * (1 << kTbvBrickShift);
    IVec3 l, h;
    for (int a = 0; a < 3; ++a) {
        l[a] = std::max(b.lo[a], o[a]);
        h[a] = std::min(b.hi[a], o[a] + kTbvBrickMask);
        if (l[a] > h[a]) return false;
    }
    // xs * rows copies the row's byte into each row (xs < 256 and rows' bits are 8 apart: no carries).
    const std::uint64_t xs = ((std::uint64_t(2) << (h.x - o.x)) - 1) & ~((std::uint64_t(1) << (l.x - o.x)) - 1);
    const std::uint64_t rows = tbvRowStarts(l.y - o.y, h.y - o.y);
    p.face = xs * rows;
    p.z0 = std::int8_t(l.z - o.z);
    p.z1 = std::int8_t(h.z - o.z);
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
    p.zFace0 = l.z == b.lo.z ? p.z0 : std::int8_t(-1);
    p.zFace1 = h.z == b.hi.z ? p.z1 : std::int8_t(-1);
    return p.ring != 0 || p.zFace0 >= 0 || p.zFace1 >= 0;
}

/// Calls fn(bc, part) for every brick (brick coordinates bc) in [clipLo, clipHi] that the box's
/// discretization reaches; returns their count. The same parts as tbvBrickPart gives, with what depends
/// on one axis only computed once per brick along that axis (tbvBrickPart per brick was a third of an
/// insert on rgvc_bench_classes' paper scene), and for Boundary the shell's hollow inside skipped:
/// between the box's faces on y and z only the first and the last brick along x hold shell voxels (those
/// of its x faces).
template <class Fn> std::size_t forEachTbvBrick(const TbvVoxelBox& b, const IVec3& clipLo, const IVec3& clipHi, Fn&& fn) {
    if (!b.inGrid) return 0;
    std::size_t n = 0;
    TbvBrickPart p;
    const bool filled = b.mode == TbvDiscretization::Filled;
    const IVec3 lo = b.lo >> kTbvBrickShift, hi = b.hi >> kTbvBrickShift;
    const IVec3 from = glm::max(lo, clipLo), to = glm::min(hi, clipHi);
    for (std::int32_t bz = from.z; bz <= to.z; ++bz) {
        const std::int32_t oz = bz << kTbvBrickShift;
        const std::int32_t lz = std::max(b.lo.z, oz), hz = std::min(b.hi.z, oz + kTbvBrickMask);
        p.z0 = std::int8_t(lz - oz);
        p.z1 = std::int8_t(hz - oz);
        p.zFace0 = !filled && lz == b.lo.z ? p.z0 : std::int8_t(-1);
        p.zFace1 = !filled && hz == b.hi.z ? p.z1 : std::int8_t(-1);
        const bool zFace = p.zFace0 >= 0 || p.zFace1 >= 0;
        for (std::int32_t by = from.y; by <= to.y; ++by) {
            const std::int32_t oy = by << kTbvBrickShift;
            const std::int32_t ly = std::max(b.lo.y, oy), hy = std::min(b.hi.y, oy + kTbvBrickMask);
            const std::uint64_t rows = tbvRowStarts(ly - oy, hy - oy);
            const bool yLo = ly == b.lo.y, yHi = hy == b.hi.y;
            // Boundary, strictly between the faces on y and z: only the x faces' bricks.
            const bool hollow = !filled && !zFace && !yLo && !yHi;
            const std::int32_t step = hollow ? std::max(1, hi.x - lo.x) : 1;
            for (std::int32_t bx = hollow ? lo.x : from.x; bx <= to.x; bx += step) {
                if (bx < from.x) continue; // hollow: lo.x left of the clip, hi.x may be in it
                const std::int32_t ox = bx << kTbvBrickShift;
                const std::int32_t lx = std::max(b.lo.x, ox), hx = std::min(b.hi.x, ox + kTbvBrickMask);
                // xs * rows copies the row's byte into each row (no carries: see tbvBrickPart).
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
                fn(IVec3{bx, by, bz}, static_cast<const TbvBrickPart&>(p));
                ++n;
            }
        }
    }
    return n;
}

} // namespace rgvc
