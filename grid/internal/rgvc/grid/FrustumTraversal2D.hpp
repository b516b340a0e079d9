// Front-to-back traversal of the 2D view region in chess-metric layers (seed 004 §4.2), with occluder
// extension (§4.3), occlusion rasterization into H (§4.4) and early termination.
//
// Per layer k (the ring of voxels at chess distance k from the camera's voxel c):
//   1. H for ring k: every occlusion polygon found in earlier layers is rasterized onto the ring's four
//      sides (an exact integer span per side, see OcclusionShadow2D). Rasterizing the polygons one ring
//      at a time, as the traversal reaches it, costs what the traversal visits, not the polygons' full
//      extent up to the grid border, and gives the same H on every visited voxel.
//   2. The ring's voxels that touch the closed view wedge form one contiguous arc (the wedge is a union
//      of rays from a point inside c, each ray crosses the ring's annulus in one segment, and the union
//      of these segments is connected). The arc is walked from the line-of-sight seed in both directions
//      (the paper's direction rules, see ChessRing2D.hpp) until a voxel that misses the wedge, or until
//      the walks have covered all 8k voxels (wide views). The far cut is applied per voxel, not to the
//      walk: a disc can cut a ring into up to four pieces (its corners lie farther than its sides),
//      so the wedge-and-disc voxels of a ring need not be contiguous, while the wedge's are.
//   3. A visited voxel not in H reports its ids (callback) and, if opaque and not yet part of an
//      extended occluder, starts an occluder extension whose runs become occlusion polygons, with the
//      corner ray of each L that joins them into one region (OcclusionShadow2D::cornerRay).
//   4. Early termination: if every in-grid voxel of the arc is opaque or occluded, every ray to anything
//      farther crosses the ring's blocked voxels (DESIGN.md invariant), so the traversal ends. It also ends
//      when the arc has no in-grid voxel: the grid is convex, so nothing farther is inside it either.
//
// Requires the camera inside the closed grid box (the culler takes a fallback otherwise).
#pragma once

#include "rgvc/grid/ChessRing2D.hpp"
#include "rgvc/grid/GridGeometry.hpp"
#include "rgvc/grid/OccluderExtension2D.hpp"
#include "rgvc/grid/OcclusionShadow2D.hpp"
#include "rgvc/grid/ViewWedge.hpp"
#include "rgvc/grid/VoxelStorage.hpp"

#include <cmath>
#include <vector>

namespace rgvc {

struct TraversalOptions2D {
    bool occlusion = true;       ///< false: view-frustum culling only
    bool extension = true;       ///< §4.3 extension through opaque *and occluded* voxels, with L arms
    std::int32_t maxRun = 1 << 14; ///< [Voxels] cap on one extension walk
};

struct TraversalStats2D {
    std::uint32_t layers = 0;
    std::uint64_t voxelsVisited = 0;
    std::uint64_t voxelsOccluded = 0;
    std::uint64_t occludersExtended = 0;
    std::uint64_t occluderVoxels = 0;
    std::uint64_t shadows = 0;
    std::uint64_t voxelsMarkedOccluded = 0;
    bool earlyTermination = false;
    bool opaqueMet = false;
};

template <VoxelStorage Storage> class FrustumTraversal2D {
public:
    /// Runs one frame. `stamp` identifies this frame in the storage's stamped matrices (H, U, V) and must
    /// differ from every earlier frame's stamp since the last resetStamps().
    /// @param onVoxel  void(VoxelKey, IVec2): called once for every visited in-grid voxel not in H.
    template <class OnVoxel>
    TraversalStats2D run(const GridGeometry2& grid, Storage& storage, const ViewWedge& wedge, std::uint32_t stamp,
                         const TraversalOptions2D& options, OnVoxel&& onVoxel) {
        TraversalStats2D stats;
        m_active.clear();
        m_pending.clear();
        m_cones.clear();
        const IVec2 res = grid.resolution();
        const IVec2 c = glm::clamp(GridGeometry2::voxelOfLocal(wedge.apex()), IVec2(0), res - 1);
        const std::int32_t kMax = std::max(std::max(c.x, res.x - 1 - c.x), std::max(c.y, res.y - 1 - c.y));

        // A camera on the grid's boundary sees along the boundary itself: such a ray grazes the outer faces
        // of the edge voxels, so opaque voxels there do not block it, and what lies outside the grid is
        // unknown. Early termination's argument needs every ray to cross the interior of the ring's blocked
        // voxels, so it is off for such cameras (found by the numerical stress tests).
        const bool cameraOnBoundary = onGridBoundary(wedge.apex(), res);
        auto isBlocker = [&](const IVec2& v) {
            if (!grid.contains(v)) return false;
            const VoxelKey key = grid.linearIndex(v);
            return storage.opaque(key) || (options.extension && storage.occluded(key, stamp));
        };

        // Layer 0: the camera's own voxel. It is never an occluder (the camera may sit anywhere in it) and
        // never terminates the traversal.
        {
            const VoxelKey key = grid.linearIndex(c);
            storage.setVisited(key, stamp);
            ++stats.voxelsVisited;
            onVoxel(key, c);
            stats.layers = 1;
        }

        for (std::int32_t k = 1; k <= kMax; ++k) {
            // Every point of ring k is at least k - 1 voxels (chess) from any point of the camera voxel.
            if (!std::isinf(wedge.far()) && double(k - 1) > wedge.far()) break;
            if (options.occlusion) {
                matureShadows(c, k);
                stampRing(grid, storage, c, k, stamp, stats);
            }

            std::int64_t p0;
            if (!findSeed(wedge, c, k, p0)) break;
            const std::int64_t perimeter = 8 * std::int64_t(k);
            std::int64_t walked = 0;
            std::uint64_t inGrid = 0, open = 0;
            auto process = [&](std::int64_t p) {
                const IVec2 v = c + ringOffset(k, p);
                if (!grid.contains(v) || !wedge.voxelWithinFar(v)) return;
                ++inGrid;
                const VoxelKey key = grid.linearIndex(v);
                storage.setVisited(key, stamp);
                ++stats.voxelsVisited;
                if (options.occlusion && storage.occluded(key, stamp)) {
                    ++stats.voxelsOccluded;
                    return;
                }
                onVoxel(key, v);
                if (!storage.opaque(key)) {
                    ++open;
                    return;
                }
                stats.opaqueMet = true;
                if (options.occlusion && !storage.used(key, stamp)) extend(grid, storage, c, v, stamp, options, isBlocker, stats);
            };
            // Counter-clockwise from the seed, then clockwise from just before it. Stretches of the ring
            // outside the grid are jumped over: the arc is contiguous, so if the position after a jump
            // still touches the wedge, so did every position jumped over.
            const RingSpans spans = ringSpansInGrid(c, k, res);
            for (int dir : {1, -1}) {
                for (std::int64_t p = dir > 0 ? p0 : p0 - 1; walked < perimeter;) {
                    const IVec2 v = c + ringOffset(k, p);
                    if (!wedge.voxelTouchesWedge(v)) break;
                    if (!grid.contains(v)) {
                        const std::int64_t jump = spans.distanceToNext(p, dir, perimeter);
                        p += dir * jump;
                        walked += jump;
                        continue;
                    }
                    process(p);
                    p += dir;
                    ++walked;
                }
            }

            stats.layers = std::uint32_t(k + 1);
            m_active.insert(m_active.end(), m_pending.begin(), m_pending.end());
            m_pending.clear();
            if (inGrid == 0) break;
            if (options.occlusion && open == 0 && !cameraOnBoundary) {
                stats.earlyTermination = true;
                break;
            }
        }
        return stats;
    }

private:
    /// Perimeter-index intervals of ring k that lie in the grid: at most one per side.
    struct RingSpans {
        std::int64_t lo[4], hi[4]; // empty when lo > hi
        /// Steps from p (outside the grid) to the nearest in-grid position in direction dir (+1 or -1);
        /// `perimeter` when there is none.
        std::int64_t distanceToNext(std::int64_t p, int dir, std::int64_t perimeter) const {
            p %= perimeter;
            if (p < 0) p += perimeter;
            std::int64_t best = perimeter;
            for (int s = 0; s < 4; ++s) {
                if (lo[s] > hi[s]) continue;
                std::int64_t d = dir > 0 ? lo[s] - p : p - hi[s];
                d %= perimeter;
                if (d <= 0) d += perimeter;
                best = std::min(best, d);
            }
            return best;
        }
    };

    static RingSpans ringSpansInGrid(const IVec2& c, std::int32_t k, const IVec2& res) {
        // Side s holds perimeter indices [2ks, 2k(s+1)); t is the index within the side (ChessRing2D).
        const std::int64_t K = k, twoK = 2 * K;
        auto clip = [&](bool fixedInside, std::int64_t tLo, std::int64_t tHi, std::int64_t base, std::int64_t& lo,
                        std::int64_t& hi) {
            tLo = std::max<std::int64_t>(tLo, 0);
            tHi = std::min<std::int64_t>(tHi, twoK - 1);
            lo = fixedInside && tLo <= tHi ? base + tLo : 1;
            hi = fixedInside && tLo <= tHi ? base + tHi : 0;
        };
        RingSpans r;
        clip(c.x + K < res.x, K - c.y, res.y - 1 - c.y + K, 0, r.lo[0], r.hi[0]);               // (k, -k + t)
        clip(c.y + K < res.y, c.x + K - (res.x - 1), c.x + K, twoK, r.lo[1], r.hi[1]);         // (k - t, k)
        clip(c.x - K >= 0, c.y + K - (res.y - 1), c.y + K, 2 * twoK, r.lo[2], r.hi[2]);        // (-k, k - t)
        clip(c.y - K >= 0, K - c.x, res.x - 1 - c.x + K, 3 * twoK, r.lo[3], r.hi[3]);          // (-k + t, -k)
        return r;
    }

    static bool onGridBoundary(const Vec2& p, const IVec2& res) {
        for (int a = 0; a < 2; ++a)
            if (p[a] <= kConservativeSlack || p[a] >= res[a] - kConservativeSlack) return true;
        return false;
    }

    /// Seed of ring k on the line of sight; if rounding put it just outside the wedge, any voxel of the
    /// ring that touches the wedge will do. False: no voxel of ring k touches the wedge, and then none
    /// farther does either.
    bool findSeed(const ViewWedge& wedge, const IVec2& c, std::int32_t k, std::int64_t& p) const {
        const IVec2 o = lineOfSightSeed(wedge.apex(), wedge.direction(), c, k);
        p = ringIndex(o, k);
        if (wedge.voxelTouchesWedge(c + o)) return true;
        for (std::int64_t q = 0, n = 8 * std::int64_t(k); q < n; ++q) {
            if (wedge.voxelTouchesWedge(c + ringOffset(k, q))) {
                p = q;
                return true;
            }
        }
        return false;
    }

    /// Shadows whose trace on ring k is their bare cone move into the merged cone set. Without this,
    /// every occluder ever met costs three span computations per side of every later ring; profiling
    /// the Figure 1 scene showed that as the traversal's largest cost. Merged cones stay few.
    void matureShadows(const IVec2& c, std::int32_t k) {
        for (std::size_t i = 0; i < m_active.size();) {
            if (m_active[i].coneFrom() <= k) {
                const OcclusionShadow2D& a = m_active[i];
                mergeCone(m_cones, c, AngularInterval{a.coneLo(), a.coneHi(), a.loClosed(), a.hiClosed()});
                m_active[i] = m_active.back();
                m_active.pop_back();
            } else {
                ++i;
            }
        }
    }

    /// Rasterizes every occlusion polygon found so far onto ring k's four sides.
    void stampRing(const GridGeometry2& grid, Storage& storage, const IVec2& c, std::int32_t k, std::uint32_t stamp,
                   TraversalStats2D& stats) const {
        if (m_active.empty() && m_cones.empty()) return;
        const IVec2 res = grid.resolution();
        // Side s starts at its first corner and steps along `dir` for 2k voxels (ChessRing2D numbering).
        const IVec2 starts[4] = {c + IVec2{k, -k}, c + IVec2{k, k}, c + IVec2{-k, k}, c + IVec2{-k, -k}};
        const IVec2 dirs[4] = {{0, 1}, {-1, 0}, {0, -1}, {1, 0}};
        for (int s = 0; s < 4; ++s) {
            const IVec2 o = starts[s], step = dirs[s];
            // Clip t in [0, 2k) to the grid.
            std::int64_t tLo = 0, tHi = 2 * std::int64_t(k) - 1;
            bool inside = true;
            for (int a = 0; a < 2 && inside; ++a) {
                if (step[a] == 0) {
                    inside = o[a] >= 0 && o[a] < res[a];
                } else if (step[a] > 0) {
                    tLo = std::max<std::int64_t>(tLo, -std::int64_t(o[a]));
                    tHi = std::min<std::int64_t>(tHi, std::int64_t(res[a]) - 1 - o[a]);
                } else {
                    tLo = std::max<std::int64_t>(tLo, std::int64_t(o[a]) - (res[a] - 1));
                    tHi = std::min<std::int64_t>(tHi, std::int64_t(o[a]));
                }
            }
            if (!inside || tLo > tHi) continue;
            auto stampSpans = [&](const std::vector<OcclusionShadow2D>& shadows) {
                for (const OcclusionShadow2D& shadow : shadows) {
                    std::int64_t lo, hi;
                    shadow.spanOnLine(o, step, tLo, tHi, lo, hi);
                    for (std::int64_t t = lo; t <= hi; ++t) {
                        const VoxelKey key = grid.linearIndex(o + step * std::int32_t(t));
                        if (!storage.occluded(key, stamp)) {
                            storage.setOccluded(key, stamp);
                            ++stats.voxelsMarkedOccluded;
                        }
                    }
                }
            };
            stampSpans(m_active);
            stampSpans(m_cones);
        }
    }

    template <class IsBlocker>
    void extend(const GridGeometry2& grid, Storage& storage, const IVec2& c, const IVec2& v, std::uint32_t stamp,
                const TraversalOptions2D& options, IsBlocker& isBlocker, TraversalStats2D& stats) {
        ++stats.occludersExtended;
        storage.setUsed(grid.linearIndex(v), stamp);
        auto opaqueOnly = [&](const IVec2& u) { return grid.contains(u) && storage.opaque(grid.linearIndex(u)); };
        VoxelRun2D runs[3];
        const int n = options.extension ? extendOccluder2D(c, v, isBlocker, true, options.maxRun, runs)
                                        : extendOccluder2D(c, v, opaqueOnly, false, options.maxRun, runs);
        bool castsShadow[3] = {false, false, false};
        for (int i = 0; i < n; ++i) {
            const VoxelRun2D& run = runs[i];
            const IVec2 step = glm::sign(run.b - run.a);
            for (IVec2 u = run.a;; u += step) {
                storage.setUsed(grid.linearIndex(u), stamp);
                ++stats.occluderVoxels;
                if (u == run.b) break;
            }
            OcclusionShadow2D shadow(c, run.a, run.b);
            castsShadow[i] = shadow.valid();
            if (shadow.valid()) {
                m_pending.push_back(shadow);
                ++stats.shadows;
            }
        }
        // The corner ray of each L (OcclusionShadow2D.hpp): an arm starts at an end K of the primary run
        // and is perpendicular to it, and both runs cast shadows, so both have two voxels or more:
        // condition (1). Condition (2), the runs on opposite sides of ray C->K, is what the extension's
        // choice of arm direction ("away from the run") amounts to; it is checked here all the same, since
        // soundness rests on it. The two open cones then meet exactly on that ray, and with it the
        // occluder's shadow is one region.
        for (int i = 1; i < n; ++i) {
            if (!castsShadow[0] || !castsShadow[i]) continue;
            const IVec2 k = runs[i].a;
            const IVec2 primaryOther = k == runs[0].a ? runs[0].b : runs[0].a;
            const IVec2 d = k - c;
            const std::int64_t sidePrimary = cross2(d, glm::sign(primaryOther - k));
            const std::int64_t sideArm = cross2(d, glm::sign(runs[i].b - k));
            if ((sidePrimary > 0 && sideArm < 0) || (sidePrimary < 0 && sideArm > 0)) {
                m_pending.push_back(OcclusionShadow2D::cornerRay(c, k));
                ++stats.shadows;
            }
        }
    }

    // Reused across frames: shadows not yet equal to their cone, shadows found in the current ring,
    // and the merged cones of mature shadows.
    std::vector<OcclusionShadow2D> m_active, m_pending, m_cones;
};

} // namespace rgvc
