// Front-to-back traversal of the 3D view frustum in chess-metric shells, with occlusion computed by a
// raster formulation of the paper's cap polygons (seed 004 §5.2, §5.3; DESIGN.md "Where the paper leaves
// room").
//
// Shells. Shell k is the surface of the cube of voxels at chess distance k from the camera voxel c: six
// faces, each a (2k+1)^2 square of voxels on an axis-aligned plane. For visiting, the faces partition the
// shell (the +-x faces own their edges, then +-y, then +-z). On each face the traversal scans only the
// bounding rectangle of the frustum's cross-section with the face's slab (the frustum clipped to the
// face, computed from its truncated pyramid), testing each voxel against the frustum; the paper seeds
// this plane sweep with 3D Bresenham voxels of the line of sight, and the clipped rectangle is the
// region such a sweep covers, found without walking.
//
// Occlusion: the voxels of shell k are tested against caps built from the opaque and occluded voxels
// of earlier shells; ShellCaps3D.hpp derives the test and where it can be skipped.
//
// Cost. A frame visits every voxel of the frustum that is not behind a terminating layer, so the visit
// itself is the floor: per voxel one cell read and one stamp write, plus the callback's id list. Rows are
// walked by key steps, in chunks whose cell reads are independent of each other (no branch between them,
// so the loads overlap); the callback then runs only for the voxels that hold ids. The cap test runs only
// where a cap's candidate rectangle says it can succeed.
#pragma once

#include "rgvc/grid/GridGeometry.hpp"
#include "rgvc/grid/ShellCaps3D.hpp"
#include "rgvc/grid/ViewFrustum.hpp"
#include "rgvc/grid/VoxelStorage.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <vector>

namespace rgvc {

struct TraversalOptions3D {
    bool occlusion = true; ///< false: view-frustum culling only
    /// Test caps at k-1, k-2, k-4, ... (true) or only at k-1 (false: layer-by-layer propagation).
    bool exponentialCaps = true;
    /// Call onVoxel for every visited voxel not in H, not only for those holding ids (the culler needs
    /// this while TBVs exist: a TBV is revealed by any visited, non-occluded voxel of T, ids or not).
    bool reportEveryVoxel = false;
    /// Start the frame without caps (view-frustum traversal, opaque voxels still recorded) and switch them
    /// on for the rest of the frame after the first shell that is at least half opaque (a wall), building
    /// that shell's cap from its opaque voxels. For scenes whose caps hide little (the culler decides, see
    /// CullerOptions::adaptiveCaps): the caps' bookkeeping is then most of the traversal's cost.
    bool deferCaps = false;
};

struct TraversalStats3D {
    std::uint32_t layers = 0;
    std::uint64_t voxelsVisited = 0;
    std::uint64_t voxelsOccluded = 0;
    std::uint64_t opaqueVisited = 0;
    std::uint64_t capFaces = 0;       ///< face bitmaps turned into summed-area tables
    std::uint64_t capVoxels = 0;      ///< voxels in those tables
    bool earlyTermination = false;
    /// With deferCaps: the first shell tested against caps (0: caps never switched on this frame).
    std::uint32_t capsFromShell = 0;
};

template <VoxelStorage Storage> class FrustumTraversal3D {
public:
    /// Runs one frame; see FrustumTraversal2D::run for the stamp contract.
    /// @param onVoxel  void(VoxelKey, IVec3): called once for every visited in-grid voxel not in H that
    ///                 holds ids (storage.hasIds), or for every such voxel with options.reportEveryVoxel.
    ///                 When it is called for a voxel, the voxel's visited mark is set and its O was read;
    ///                 its H mark (if the voxel turns out hidden) may come later in the same row.
    template <class OnVoxel>
    TraversalStats3D run(const GridGeometry3& grid, Storage& storage, const ViewFrustum& frustum, std::uint32_t stamp,
                         const TraversalOptions3D& options, OnVoxel&& onVoxel) {
        using namespace traversal3d_detail;
        TraversalStats3D stats;
        const IVec3 res = grid.resolution();
        const IVec3 c = glm::clamp(GridGeometry3::voxelOfLocal(frustum.apex()), IVec3(0), res - 1);
        std::int32_t kMax = 0;
        for (int a = 0; a < 3; ++a) kMax = std::max(kMax, std::max(c[a], res[a] - 1 - c[a]));
        m_caps.beginFrame(kMax);
        // Caps for this shell on (the normal case) or deferred until a wall shows up (options.deferCaps).
        bool caps = options.occlusion && !options.deferCaps;
        m_capsOn = caps;
        // Key steps along each axis: a row of a face is walked by adding one of them to the key.
        const std::array<std::int64_t, 3> stride{1, res.x, std::int64_t(res.x) * res.y};
        const bool hasFar = !std::isinf(frustum.far());

        // Truncated pyramid covering the frustum up to beyond the grid (centre-relative).
        const Vec3 apex = frustum.apex() - (Vec3(c) + 0.5);
        const double cosEdge = glm::dot(frustum.edge(0), frustum.forward());
        const bool nearlyFlat = cosEdge < 1e-3;
        const double reach = (std::sqrt(3.0) * (kMax + 1.5) + 1.0) / std::max(cosEdge, 1e-3);
        std::array<Vec3, 5> pyramid{apex, apex + frustum.edge(0) * reach, apex + frustum.edge(1) * reach,
                                    apex + frustum.edge(2) * reach, apex + frustum.edge(3) * reach};

        // A camera on the grid's boundary sees along it (see FrustumTraversal2D): no early termination.
        bool cameraOnBoundary = false;
        for (int a = 0; a < 3; ++a)
            cameraOnBoundary = cameraOnBoundary || frustum.apex()[a] <= kConservativeSlack ||
                               frustum.apex()[a] >= res[a] - kConservativeSlack;
        {
            const VoxelKey key = grid.linearIndex(c);
            storage.setVisited(key, stamp);
            ++stats.voxelsVisited;
            if (options.reportEveryVoxel || storage.hasIds(key)) onVoxel(key, c);
            stats.layers = 1;
        }

        for (std::int32_t k = 1; k <= kMax; ++k) {
            if (hasFar && double(k - 1) > frustum.far()) break;
            std::uint64_t inGrid = 0, open = 0, occluded = 0, opaque = 0;
            if (caps) m_caps.prepare(k, options.exponentialCaps);
            for (int face = 0; face < 6; ++face) {
                const int a = face / 2;
                const int sgn = face % 2 == 0 ? 1 : -1;
                int b1, b2;
                otherAxes(a, b1, b2);
                // Partition of the shell among faces (which face owns the edges).
                const std::int32_t r1 = (a == 0) ? k : k - 1;
                const std::int32_t r2 = (a == 2) ? k - 1 : k;
                IVec2 lo{-r1, -r2}, hi{r1, r2};
                // A frustum within ~0.06 degrees of a half-space has edges nearly orthogonal to its axis: its
                // truncated pyramid would be far too long to build accurately, so such a view scans whole
                // faces (clipVoxelRow still clips every row to the side planes). Found by fuzz_culler3d.
                if (!nearlyFlat && !crossSection(pyramid, a, sgn, k, b1, b2, lo, hi)) continue;
                // Clip to the grid.
                lo.x = std::max(lo.x, -c[b1]);
                hi.x = std::min(hi.x, res[b1] - 1 - c[b1]);
                lo.y = std::max(lo.y, -c[b2]);
                hi.y = std::min(hi.y, res[b2] - 1 - c[b2]);
                const std::int32_t ca = c[a] + sgn * k;
                if (ca < 0 || ca >= res[a] || lo.x > hi.x || lo.y > hi.y) continue;
                // The face's voxels are c + oRow + u e1 for rows oRow = k sgn ea + v e2: vector arithmetic and a
                // key step per voxel (writing one component of a vector in memory and reading the whole
                // vector back stalled every voxel on store forwarding).
                IVec3 ea(0), e1(0), e2(0);
                ea[a] = 1;
                e1[b1] = 1;
                e2[b2] = 1;
                const IVec3 oFace = ea * (sgn * k);
                const std::int64_t step = stride[b1];
                // The masks cover the margins too: recordMargins tests the voxels there for H (see there).
                const IVec2 mLo{std::max({lo.x - kMargin, -k, -c[b1]}), std::max({lo.y - kMargin, -k, -c[b2]})};
                const IVec2 mHi{std::min({hi.x + kMargin, k, res[b1] - 1 - c[b1]}),
                                std::min({hi.y + kMargin, k, res[b2] - 1 - c[b2]})};
                const bool testCaps = caps && m_caps.prepareFace(face, mLo, mHi);
                if (caps) m_spans.assign(std::size_t(hi.y - lo.y + 1), IVec2(1, 0));
                for (std::int32_t v = lo.y; v <= hi.y; ++v) {
                    const IVec3 oRow = oFace + e2 * v;
                    std::int32_t u0 = lo.x, u1 = hi.x;
                    if (!clipVoxelRow(frustum, c, oRow, b1, u0, u1)) continue;
                    const std::int64_t rowKey = std::int64_t(grid.linearIndex(c + oRow)); // u = 0 is in the grid
                    auto keyOf = [&](std::int32_t u) { return VoxelKey(rowKey + u * step); };
                    if (caps) m_spans[std::size_t(v - lo.y)] = {u0, u1};
                    // Some cap may hide voxel u where masks[u] != 0 (null: nowhere on this row).
                    // Indexed by u - maskU0 (a pointer shifted before the array would be undefined behaviour).
                    const ShellCaps3D::CapMask* masks = testCaps ? m_caps.maskRow(v) : nullptr;
                    const std::int32_t maskU0 = m_caps.maskU0();
                    // Start loading the next row's cells (over this row's span, which the next one nearly
                    // shares): a face whose rows run along y or z reads one cache line per voxel, and those
                    // misses then overlap with this row's work instead of following it.
                    if constexpr (requires(const Storage& st) { st.prefetchCell(VoxelKey(0)); }) {
                        const std::int32_t vNext = v + 1;
                        if (vNext <= hi.y && c[b2] + vNext < res[b2]) {
                            const std::int64_t nextKey = rowKey + stride[b2];
                            const std::int32_t every = step == 1 ? 8 : 1; // 8 cells share a 64-byte line
                            for (std::int32_t u = u0; u <= u1; u += every)
                                storage.prefetchCell(VoxelKey(nextKey + u * step));
                        }
                    }
                    if (hasFar) { // rare: the far ball's test for every voxel
                        for (std::int32_t u = u0; u <= u1; ++u) {
                            const IVec3 o = oRow + e1 * u;
                            if (!frustum.withinFar(Vec3(c + o), Vec3(c + o) + 1.0)) continue;
                            visitChunk(storage, keyOf(u), step, 1, o, e1, c, k, face, masks ? masks + (u - maskU0) : nullptr,
                                       options, stamp, onVoxel, inGrid, open, occluded, opaque);
                        }
                        continue;
                    }
                    for (std::int32_t u = u0; u <= u1; u += 32)
                        visitChunk(storage, keyOf(u), step, std::min<std::int32_t>(32, u1 - u + 1), oRow + e1 * u, e1, c, k,
                                   face, masks ? masks + (u - maskU0) : nullptr, options, stamp, onVoxel, inGrid, open, occluded,
                                   opaque);
                }
                if (caps) recordMargins(grid, storage, c, k, face, oFace, e1, e2, b1, b2, lo, hi, step, stamp, testCaps);
            }
            stats.voxelsVisited += inGrid;
            stats.voxelsOccluded += occluded;
            stats.opaqueVisited += opaque;
            stats.layers = std::uint32_t(k + 1);
            if (inGrid == 0) break;
            if (options.occlusion && open == 0 && !cameraOnBoundary) {
                stats.earlyTermination = true;
                break;
            }
            // Deferred caps: a shell at least half opaque switches them on; its cap is built from the opaque
            // voxels visitChunk recorded (no margins: fewer records can only leave voxels out of H).
            if (options.occlusion && !caps && 2 * opaque >= inGrid) {
                caps = m_capsOn = true;
                stats.capsFromShell = std::uint32_t(k + 1);
            } else if (options.occlusion && !caps) {
                m_caps.discardRecorded();
                continue;
            }
            // A shell with no blocked voxel recorded gets no caps (and the records never outlive their shell).
            if (options.occlusion && m_caps.anyRecorded()) m_caps.build(k, stats.capFaces, stats.capVoxels);
        }
        return stats;
    }

private:
    /// Visits the n <= 32 voxels c + o0 + i e1 (keys key + i step) of one row of face `face` of shell k.
    /// First the cap tests (where masks[i] != 0), then every cell read with no branch in between, so that
    /// the reads overlap, then the callbacks for the voxels with ids and the records of blocked voxels.
    template <class OnVoxel>
    void visitChunk(Storage& storage, VoxelKey key, std::int64_t step, int n, const IVec3& o0, const IVec3& e1,
                    const IVec3& c, std::int32_t k, int face, const ShellCaps3D::CapMask* masks,
                    const TraversalOptions3D& options, std::uint32_t stamp, OnVoxel& onVoxel, std::uint64_t& inGrid,
                    std::uint64_t& open, std::uint64_t& occluded, std::uint64_t& opaque) {
        std::uint32_t hidden = 0, withIds = 0, opaqueBits = 0;
        if (masks != nullptr)
            for (int i = 0; i < n; ++i)
                if (masks[i] != 0 && m_caps.hiddenByCaps(o0 + e1 * i, face, masks[i])) hidden |= 1u << i;
        for (int i = 0; i < n; ++i) {
            const VoxelKey ki = key + VoxelKey(i * step);
            storage.setVisited(ki, stamp);
            withIds |= std::uint32_t(storage.hasIds(ki)) << i;
            opaqueBits |= std::uint32_t(storage.opaque(ki)) << i;
        }
        if (options.reportEveryVoxel) withIds = n == 32 ? ~0u : (1u << n) - 1;
        withIds &= ~hidden;
        opaqueBits &= ~hidden;
        // The callback walks each voxel's id list: start every list's first load now, so that the misses
        // overlap instead of following one another (the list nodes were the traversal's largest cost).
        if constexpr (requires(const Storage& st) { st.prefetchIds(key); })
            for (std::uint32_t bits = withIds; bits != 0; bits &= bits - 1)
                storage.prefetchIds(key + VoxelKey(std::countr_zero(bits) * step));
        for (; withIds != 0; withIds &= withIds - 1) {
            const int i = std::countr_zero(withIds);
            onVoxel(key + VoxelKey(i * step), c + o0 + e1 * i);
        }
        int nHidden = 0, nOpaque = 0;
        for (std::uint32_t bits = hidden; bits != 0; bits &= bits - 1, ++nHidden)
            storage.setOccluded(key + VoxelKey(std::countr_zero(bits) * step), stamp);
        for (std::uint32_t bits = opaqueBits; bits != 0; bits &= bits - 1) ++nOpaque;
        // Without caps (deferred) only opaque voxels are recorded, in case a wall switches the caps on.
        if (options.occlusion)
            for (std::uint32_t bits = m_capsOn ? hidden | opaqueBits : opaqueBits; bits != 0; bits &= bits - 1)
                m_caps.addBlocked(o0 + e1 * std::countr_zero(bits), k);
        inGrid += std::uint64_t(n);
        occluded += std::uint64_t(nHidden);
        opaque += std::uint64_t(nOpaque);
        open += std::uint64_t(n - nHidden - nOpaque);
    }

    /// Blocked voxels next to the visited part of a face are blockers too: the footprint of a later voxel near
    /// the frustum's side reaches a few voxels past it. They are read, not visited: for every row v (the
    /// visited rows and kMargin beyond), the span of rows v-kMargin..v+kMargin grown by kMargin, minus v's
    /// own visited span. Without the rows around a slanted edge (a view turned by a fraction of a degree), a
    /// cap has holes all along the frustum's edges, the voxels there stay out of H shell after shell, and
    /// behind a wall spanning the whole view the traversal never terminates (found by rgvc_bench_dynamic: a
    /// 256 x 128 wall leaked 50,000 voxels with the view turned by 0.6 degrees).
    ///
    /// Opaque voxels alone are not enough: behind a wall the caps are made of occluded voxels, and the margin
    /// of a shell behind it holds no opaque voxel, so a footprint that reaches past the visited rows found
    /// an unrecorded (open) voxel there, and H eroded from the frustum's sides shell after shell until a cap
    /// at k - 2^i happened to fall on the wall's shells (a 2 degree turn left ~25,000 voxels behind a wall
    /// out of H, and the traversal ran on through 1.6 M voxels). So margin voxels are also tested against
    /// the caps, exactly as visited ones (the test is sound for any voxel of the shell), and recorded when
    /// hidden; they are not marked in H (not visited).
    ///
    /// What is read and tested is limited to where a footprint could come out all blocked: a footprint that
    /// reaches into the margin beside a row also holds the visited voxel at the end of some row it spans, so
    /// a side of a row is read only if the end of some row within kMargin on that side is blocked; and the
    /// cap test walks outwards from the span and stops at the first voxel that is not blocked. Both only
    /// leave voxels unrecorded, which can only leave voxels out of H.
    void recordMargins(const GridGeometry3& grid, const Storage& storage, const IVec3& c, std::int32_t k, int face,
                       const IVec3& oFace, const IVec3& e1, const IVec3& e2, int b1, int b2, const IVec2& lo,
                       const IVec2& hi, std::int64_t step, std::uint32_t stamp, bool testCaps) {
        const IVec3 res = grid.resolution();
        // Per visited row: bit 0 when its first voxel is blocked, bit 1 when its last one is. The first and
        // last rows with a span also get bit 2 when any of their voxels is blocked (for the rows beyond them).
        m_ends.assign(m_spans.size(), 0);
        std::int32_t vFirst = hi.y + 1, vLast = lo.y - 1;
        for (std::int32_t v = lo.y; v <= hi.y; ++v) {
            const IVec2 sp = m_spans[std::size_t(v - lo.y)];
            if (sp.x > sp.y) continue;
            vFirst = std::min(vFirst, v);
            vLast = v;
            const std::int64_t rowKey = std::int64_t(grid.linearIndex(c + oFace + e2 * v));
            auto blocked = [&](std::int32_t u) {
                const VoxelKey key(rowKey + u * step);
                return storage.opaque(key) || storage.occluded(key, stamp);
            };
            m_ends[std::size_t(v - lo.y)] = std::uint8_t(int(blocked(sp.x)) | int(blocked(sp.y)) << 1);
        }
        for (std::int32_t v : {vFirst, vLast}) {
            if (v > vLast) break; // no visited row
            const IVec2 sp = m_spans[std::size_t(v - lo.y)];
            const std::int64_t rowKey = std::int64_t(grid.linearIndex(c + oFace + e2 * v));
            for (std::int32_t u = sp.x; u <= sp.y; ++u) {
                const VoxelKey key(rowKey + u * step);
                if (storage.opaque(key) || storage.occluded(key, stamp)) {
                    m_ends[std::size_t(v - lo.y)] |= 4;
                    break;
                }
            }
        }
        const std::int32_t vMin = std::max({lo.y - kMargin, -k, -c[b2]});
        const std::int32_t vMax = std::min({hi.y + kMargin, k, res[b2] - 1 - c[b2]});
        const std::int32_t uMinFace = std::max(-k, -c[b1]), uMaxFace = std::min(k, res[b1] - 1 - c[b1]);
        auto spanOf = [&](std::int32_t v) {
            return v < lo.y || v > hi.y ? IVec2(1, 0) : m_spans[std::size_t(v - lo.y)];
        };
        for (std::int32_t v = vMin; v <= vMax; ++v) {
            std::int32_t from = std::numeric_limits<std::int32_t>::max(), to = std::numeric_limits<std::int32_t>::min();
            int ends = 0;
            for (std::int32_t w = v - kMargin; w <= v + kMargin; ++w) {
                const IVec2 sp = spanOf(w);
                if (sp.x > sp.y) continue;
                from = std::min(from, sp.x - kMargin);
                to = std::max(to, sp.y + kMargin);
                ends |= m_ends[std::size_t(w - lo.y)];
            }
            from = std::max(from, uMinFace);
            to = std::min(to, uMaxFace);
            if (from > to) continue;
            const IVec2 own = spanOf(v);
            const IVec3 oRow = oFace + e2 * v;
            const ShellCaps3D::CapMask* masks = testCaps && ends != 0 ? m_caps.maskRow(v) : nullptr;
            const std::int32_t maskU0 = m_caps.maskU0();
            const std::int64_t rowKey = std::int64_t(grid.linearIndex(c + oRow));
            // Records margin voxel u if it is blocked, testing it against the caps while `chain` holds; the
            // chain ends at the first voxel that is not blocked.
            auto record = [&](std::int32_t u, bool& chain) {
                const IVec3 o = oRow + e1 * u;
                bool blocked = storage.opaque(VoxelKey(rowKey + u * step));
                if (!blocked && chain && masks != nullptr && masks[u - maskU0] != 0)
                    blocked = m_caps.hiddenByCaps(o, face, masks[u - maskU0]);
                if (blocked) m_caps.addBlocked(o, k);
                chain = chain && blocked;
            };
            if (own.x > own.y) { // beyond the first or last visited row
                if (ends != 0)
                    for (std::int32_t u = from; u <= to; ++u) {
                        bool chain = (ends & 4) != 0;
                        record(u, chain);
                    }
            } else {
                bool chain = (ends & 1) != 0;
                if (chain)
                    for (std::int32_t u = own.x - 1; u >= from; --u) record(u, chain);
                chain = (ends & 2) != 0;
                if (chain)
                    for (std::int32_t u = own.y + 1; u <= to; ++u) record(u, chain);
            }
            // Where the margin reaches the square's edge it continues on the neighbouring face (same shell,
            // one and two voxels nearer along this face's axis), which the frustum may not reach at all.
            for (std::int32_t u : {from, to})
                if (u == -k || u == k) recordEdgeStrip(grid, storage, c, k, oRow + e1 * u, oFace);
            if (v == -k || v == k)
                for (std::int32_t u = from; u <= to; ++u) recordEdgeStrip(grid, storage, c, k, oRow + e1 * u, oFace);
        }
    }

    /// The voxels at o - d * (face axis), d = 1, 2 (o on the face's edge): on the neighbouring face of shell k.
    void recordEdgeStrip(const GridGeometry3& grid, const Storage& storage, const IVec3& c, std::int32_t k, const IVec3& o,
                         const IVec3& oFace) {
        const IVec3 inward = -oFace / k; // unit vector from the face towards the camera along its axis
        for (std::int32_t d = 1; d <= 2; ++d) {
            const IVec3 q = o + inward * d;
            if (grid.contains(c + q) && storage.opaque(grid.linearIndex(c + q))) m_caps.addBlocked(q, k);
        }
    }

    /// Bounding rectangle (offsets on b1, b2) of the frustum's cross-section with face (a, sgn) of shell k,
    /// intersected with [lo, hi]. False when the frustum misses the face's slab.
    static bool crossSection(const std::array<Vec3, 5>& pyr, int a, int sgn, std::int32_t k, int b1, int b2,
                             IVec2& lo, IVec2& hi) {
        const double x0 = sgn > 0 ? k - 0.5 : -k - 0.5, x1 = x0 + 1.0;
        double min1 = INFINITY, max1 = -INFINITY, min2 = INFINITY, max2 = -INFINITY;
        auto add = [&](const Vec3& p) {
            min1 = std::min(min1, p[b1]);
            max1 = std::max(max1, p[b1]);
            min2 = std::min(min2, p[b2]);
            max2 = std::max(max2, p[b2]);
        };
        for (int i = 0; i < 5; ++i)
            if (pyr[i][a] >= x0 && pyr[i][a] <= x1) add(pyr[i]);
        for (int i = 0; i < 5; ++i)
            for (int j = i + 1; j < 5; ++j)
                for (double x : {x0, x1}) {
                    const double di = pyr[i][a] - x, dj = pyr[j][a] - x;
                    if ((di < 0 && dj > 0) || (di > 0 && dj < 0)) add(pyr[i] + (pyr[j] - pyr[i]) * (di / (di - dj)));
                }
        if (!(min1 <= max1)) return false;
        const double eps = 1e-7; // pyramid vertices are far away: keep the rounding on the safe side
        lo.x = std::max<std::int32_t>(lo.x, std::int32_t(std::max(-1e9, std::ceil(min1 - 0.5 - eps))));
        hi.x = std::min<std::int32_t>(hi.x, std::int32_t(std::min(1e9, std::floor(max1 + 0.5 + eps))));
        lo.y = std::max<std::int32_t>(lo.y, std::int32_t(std::max(-1e9, std::ceil(min2 - 0.5 - eps))));
        hi.y = std::min<std::int32_t>(hi.y, std::int32_t(std::min(1e9, std::floor(max2 + 0.5 + eps))));
        return lo.x <= hi.x && lo.y <= hi.y;
    }

    // Voxels around the visited rows that recordMargins reads (and tests against the caps). Measured on a
    // 256 x 128 wall across the whole view (test_culler3d "a full wall hides everything behind it"): with
    // occluded margin voxels recorded, 4 still left up to 87 voxels behind the wall out of H at a 10 degree
    // turn, 5 left 4, 6 none up to 10 degrees of yaw and pitch.
    static constexpr std::int32_t kMargin = 6;

    ShellCaps3D m_caps;          // this frame's caps (reused across frames)
    bool m_capsOn = false;       // caps tested and built in the current shell (see deferCaps)
    std::vector<IVec2> m_spans;  // visited span of each row of the current face ((1, 0): none)
    std::vector<std::uint8_t> m_ends; // recordMargins' scratch: which ends of each visited row are blocked
};

} // namespace rgvc
