// The brick walks' tests of the visited voxels that hold TBVs (BrickPass.cpp, BrickPass2D.cpp): which of
// them may be left out because O fills them (leaveOpaqueTbvVoxels), and which the walk's occlusion image
// hides, tested as boxes along the brick's octree or quadtree (clearHiddenVoxels). Internal to
// rgvc::dynamics.
#pragma once

#include "rgvc/grid/GridGeometry.hpp"
#include "rgvc/grid/Math.hpp"
#include "rgvc/grid/Shapes.hpp"
#include "rgvc/grid/ConservativeRaster.hpp"

#include <bit>
#include <cstdint>

namespace rgvc {

/// Whether a walk may leave T's voxels that O fills out of its reveals: with `occlusion` (without it the
/// PVS holds every object in view), while the camera (apex) is a voxel or more inside the grid on every
/// axis. A walk reveals a hidden object's TBV when a visible point x of the object exists (BrickPass.cpp,
/// traverseBricks: the ray to x enters the TBV's region through a visible point y of its boundary). With
/// the camera so far inside, every point of the open segment from it to x lies inside the grid. (The 3D
/// walk knows O's voxels from the rows its fused boxes read: on a frame that walks without the image, none
/// are left out.) Take a point p of that open segment every closed voxel holding which holds the TBV in T:
///   - a boundary TBV (3D): just past y, where the segment enters the shell's box (a voxel holding p then
///     holds y, a point of the box's surface: a shell voxel). The box holds the region, x included, with a
///     margin except at the grid's faces, so the segment cannot run on the box's surface up to x without
///     lying in a face of the grid, where the camera is not;
///   - a filled TBV: just before x;
///   - 2D: where the segment crosses the ring's circle, or just before x when that is x (every voxel
///     touching the circle, for a filled TBV the disc, is in T).
/// Were all of p's voxels opaque, they would cover a neighbourhood of p (p lies inside the grid), and each
/// lies in an object other than the hidden one (O holds the inner voxels of the objects at their current
/// placements; a hidden object has none): p would be interior to the union of the other objects, and x
/// hidden. So one of them is not opaque, and as p is visible it is visited and not hidden, as y's voxel
/// above: the TBV is revealed. (A TBV that ends in a wall, a building or the ground was revealed by its
/// voxels there in every frame it lasted, with nothing to see behind them: the 100k room revealed 148 TBVs
/// a frame, 106 now.)
///
/// The camera inside an object. The argument needs a visible point x seen along an open segment that
/// misses the other objects' interiors. An object that holds the camera is visible (the contract) even
/// where the camera lies inside another object, whose interior every segment from it meets: its TBV, which
/// the camera entered a voxel a frame at most (updateScene checks larger steps), is revealed in the frame
/// the camera's voxel is one of the TBV's boundary voxels, which must then be kept even when O fills it.
/// So no voxel is left out in a frame whose camera point lies in an opaque voxel (any voxel whose closed
/// box holds it, or holds it within `slack`, the camera's rounding: ViewFrustum / ViewWedge::slack).
/// fuzz_culler2d found the miss: a tiny circle at the camera, hidden by its TBV, the camera inside a large
/// circle whose voxels are opaque.
template <int D, class Storage>
bool leaveOpaqueTbvVoxels(const Vec<D>& apex, double slack, const GridGeometry<D>& grid, const Storage& storage) {
    const IVec<D> res = grid.resolution();
    for (int a = 0; a < D; ++a)
        if (!(apex[a] >= 1.0 && apex[a] <= double(res[a]) - 1.0)) return false;
    // The voxels whose closed box meets the apex grown by the slack (the rasterizer's touched range of a
    // point: ConservativeRaster.hpp), at most two per axis.
    IVec<D> lo, hi;
    for (int a = 0; a < D; ++a) raster_detail::touchedRange(apex[a], apex[a], res[a], lo[a], hi[a], slack);
    IVec<D> v = lo;
    while (true) {
        if (storage.opaque(grid.linearIndex(v))) return false;
        int a = 0;
        while (a < D && v[a] == hi[a]) v[a] = lo[a], ++a;
        if (a == D) return true;
        ++v[a];
    }
}

/// Clears from `held` (a brick's voxels as slice words: bit x + 8 y of slice z; in 2D one word, bit
/// x + 8 y) the voxels the image hides, coarse to fine along the brick's octree (quadtree in 2D): the
/// bounding box of the held voxels of the brick, then of each held octant of 4^D, of 2^D, and last each
/// voxel. A box hidden as a whole hides every voxel in it; a failed test sends its voxels to the next level
/// (`tests` counts them: CullStats::tbvImageTests). In 3D every level is tested with hidden()'s refinement,
/// which for a box is the exact per-pixel test (hiddenBoxExact: each pixel against the nearest entry its
/// own rays can have). Without it a box's pixels are compared with the box's single nearest distance, and a
/// box just behind a wall seen at an angle fails on the pixels where the wall is crossed farther out than
/// the box's nearest corner: on the closed rooms 37 % of the 2^3 tests and 43 % of the 4^3 ones failed so,
/// each sending up to 8 tests down, while their voxels were hidden. With the refinement at every level the
/// rooms' frames fell by 17 % (1k movers) and 26 % (10k) in callgrind, with the same reveals; elsewhere
/// within 0.5 %. (The octant tests were coarse when the refinement split boxes into 8 parts, which the next
/// level already does.)
/// A voxel whose own test fails goes to onVisible(brick-local voxel, held), which may clear voxels from
/// `held` (those whose TBVs it has already taken for revealing: they would reveal nothing more); later
/// tests read `held` afresh. Sound whatever the outcome: only a hidden test clears a voxel by itself, and a
/// hidden box has no point in view that is visible. Returns whether any voxel is left.
/// Why: behind a closed wall the held voxels of a brick are hidden together (the room's movers: half of the
/// bricks' sets by the first test), and where a wall crosses a brick the octants on its far side are, so
/// the tests follow the wall's area in the brick, not its volume. Each test costs a footprint (about a
/// thousand instructions in 3D). The 2D walk tested the TBV rings crossing the bricks outside a room's
/// walls voxel by voxel: two thirds of the 2D room's walk (rgvc_bench_classes' room2d), whose frames now
/// take 10 % fewer instructions (README, "Scene classes").
template <int D, class Image, class OnVisible>
static bool clearHiddenVoxels(Image& image, const IVec<D>& brick, double slack, std::uint64_t* held, std::uint64_t& tests,
                              OnVisible&& onVisible) {
    constexpr int kSlices = D == 3 ? 8 : 1; // held's words
    const IVec<D> o = brick * 8;
    // held restricted to the cube (square) c .. c + size - 1 (brick-local), as slice words.
    auto cubeMask = [](const IVec<D>& c, int size, int z) -> std::uint64_t {
        if constexpr (D == 3)
            if (z < c.z || z >= c.z + size) return 0;
        const std::uint64_t row = ((std::uint64_t(1) << size) - 1) << c.x;
        std::uint64_t m = 0;
        for (int y = c.y; y < c.y + size; ++y) m |= row << (8 * y);
        return m;
    };
    // Bit b of slice z as a brick-local voxel.
    auto voxelOf = [](int b, int z) {
        if constexpr (D == 3) return IVec3{b & 7, b >> 3, z};
        else return IVec2{b & 7, b >> 3};
    };
    // The test of a box: with hidden()'s refinement, which in 3D is the exact per-pixel test (above). In 2D
    // the refinement splits the box into quarters, two levels deep, as the levels below do: it is used for
    // the brick's whole set and for single voxels, not in between. A wall seen at an angle is entered
    // farther out along its length than the box's nearest point, so the coarse test of the whole set
    // behind it fails where the refined one hides it at once (test_brick_traversal's wall: 1 test per
    // brick, 7.7 with coarse tests above the voxels); a failed refinement in between repeats the next
    // level's tests (refined at every level, random 2D scenes took 1 % more instructions).
    auto hiddenAt = [&](const Box<D>& box, bool voxel, bool top) {
        ++tests;
        if constexpr (D == 3) return image.hidden(box, slack);
        else return voxel || top ? image.hidden(box, slack) : image.hiddenCoarse(box, slack);
    };
    auto visit = [&](auto& self, const IVec<D>& c, int size) -> void {
        std::uint64_t m[kSlices];
        IVec<D> lo{8}, hi{-1};
        int z0 = 0, z1 = 1;
        if constexpr (D == 3) z0 = c.z, z1 = c.z + size;
        for (int z = z0; z < z1; ++z) {
            m[z] = held[z] & cubeMask(c, size, z);
            for (std::uint64_t bits = m[z]; bits != 0; bits &= bits - 1) {
                const IVec<D> p = voxelOf(std::countr_zero(bits), z);
                lo = glm::min(lo, p);
                hi = glm::max(hi, p);
            }
        }
        if (hi.x < 0) return; // none held here
        const Box<D> box{Vec<D>(o + lo), Vec<D>(o + hi + 1)};
        const bool one = lo == hi;
        if (hiddenAt(box, one || size == 1, size == 8)) {
            for (int z = z0; z < z1; ++z) held[z] &= ~m[z];
            return;
        }
        if (one || size == 1) {
            onVisible(lo, held);
            return;
        }
        const int h = size / 2;
        for (int k = 0; k < (1 << D); ++k) {
            if constexpr (D == 3) self(self, c + IVec3{(k & 1) * h, ((k >> 1) & 1) * h, ((k >> 2) & 1) * h}, h);
            else self(self, c + IVec2{(k & 1) * h, ((k >> 1) & 1) * h}, h);
        }
    };
    visit(visit, IVec<D>{0}, 8);
    for (int z = 0; z < kSlices; ++z)
        if (held[z] != 0) return true;
    return false;
}

} // namespace rgvc
