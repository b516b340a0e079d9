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
// Occlusion. After shell k is processed, the opaque and occluded voxels of each of its faces form a
// bitmap: the paper vectorizes it into cap polygons (with holes), extrudes them from the viewpoint and
// rasterizes the cross-sections with §4.4's sampling correction. We keep the bitmap and store its
// summed-area table instead. A voxel q of a later shell is occluded if, for some earlier shell k', every
// segment from any point of the camera voxel to any point of q crosses shell k' only through blocked
// voxels: the set of such crossing points (q's *footprint* on shell k') is bounded per face by an
// axis-aligned rectangle (below), and a summed-area lookup tells in O(1) whether every voxel of that
// rectangle is blocked. This is the cap test with the from-region correction built in: the footprint
// is the cross-section of the beam between the camera voxel and q, so H holds only voxels hidden from
// every point of the camera voxel; occluder fusion is automatic (any blocked voxels, from any objects,
// side by side in a cap), and blocked includes occluded voxels, as occluder extension does.
//
// Which earlier shells: k-1, k-2, k-4, k-8, ... Every segment from the camera voxel to shell k crosses
// every shell in between, so each is a valid cap. Testing only k-1 (propagating occlusion layer by layer)
// erodes the hidden region by about one voxel per shell, because a footprint on the adjacent shell is
// about two voxels wide; the exponentially spaced caps bound that loss by a logarithmic number of
// footprint margins, at log(k) lookups per voxel.
//
// Footprint of q on face (a, s) of shell k' (centre-relative coordinates, camera voxel [-1/2, 1/2]^3,
// q's voxel Q = [o - 1/2, o + 1/2]^3, slab s*x_a in [k' - 1/2, k' + 1/2]): a segment c -> q' crosses the
// plane s*x_a = X at parameter t = (X - s*c_a) / (s*q'_a - s*c_a), monotone in each endpoint coordinate,
// so t over the slab lies in [tMin, tMax] from the endpoint extremes; there, every other coordinate
// (1 - t) c_b + t q'_b lies between the extremes of -1/2 + t*o_b and 1/2 + t*o_b at tMin and tMax.
// Treating t and the other coordinates independently only enlarges the rectangle (conservative).
#pragma once

#include "rgvc/grid/GridGeometry.hpp"
#include "rgvc/grid/ViewFrustum.hpp"
#include "rgvc/grid/VoxelStorage.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace rgvc {

struct TraversalOptions3D {
    bool occlusion = true; ///< false: view-frustum culling only
    /// Test caps at k-1, k-2, k-4, ... (true) or only at k-1 (false: layer-by-layer propagation).
    bool exponentialCaps = true;
};

struct TraversalStats3D {
    std::uint32_t layers = 0;
    std::uint64_t voxelsVisited = 0;
    std::uint64_t voxelsOccluded = 0;
    std::uint64_t opaqueVisited = 0;
    std::uint64_t capFaces = 0;       ///< face bitmaps turned into summed-area tables
    std::uint64_t capVoxels = 0;      ///< voxels in those tables
    bool earlyTermination = false;
};

namespace traversal3d_detail {

/// Axes of face a: the two others, in increasing order.
inline void otherAxes(int a, int& b1, int& b2) {
    b1 = a == 0 ? 1 : 0;
    b2 = a == 2 ? 1 : 2;
}

/// Summed-area table of blocked voxels over a rectangle of one shell face (offsets from c).
struct FaceSat {
    std::int32_t u0 = 0, u1 = -1, v0 = 0, v1 = -1; // rectangle of offsets on axes b1, b2
    std::size_t offset = 0;                         // into the frame's pool; (w+1)*(h+1) entries
    // Bounding rectangle of the blocked voxels: a footprint not inside it cannot be all blocked, which
    // rejects most lookups in O(1) without touching the table.
    std::int32_t bu0 = 0, bu1 = -1, bv0 = 0, bv1 = -1;
    bool empty() const { return u0 > u1 || v0 > v1; }
};

} // namespace traversal3d_detail

template <VoxelStorage Storage> class FrustumTraversal3D {
public:
    /// Runs one frame; see FrustumTraversal2D::run for the stamp and callback contract.
    template <class OnVoxel>
    TraversalStats3D run(const GridGeometry3& grid, Storage& storage, const ViewFrustum& frustum, std::uint32_t stamp,
                         const TraversalOptions3D& options, OnVoxel&& onVoxel) {
        using namespace traversal3d_detail;
        TraversalStats3D stats;
        const IVec3 res = grid.resolution();
        const IVec3 c = glm::clamp(GridGeometry3::voxelOfLocal(frustum.apex()), IVec3(0), res - 1);
        std::int32_t kMax = 0;
        for (int a = 0; a < 3; ++a) kMax = std::max(kMax, std::max(c[a], res[a] - 1 - c[a]));
        m_shells.assign(std::size_t(kMax) + 1, {});
        m_pool.clear();

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
            onVoxel(key, c);
            stats.layers = 1;
        }

        for (std::int32_t k = 1; k <= kMax; ++k) {
            if (!std::isinf(frustum.far()) && double(k - 1) > frustum.far()) break;
            std::uint64_t inGrid = 0, open = 0, shellBlocked = 0;
            std::array<IVec2, 6> rectLo, rectHi; // visited rectangles per face (b1, b2 offsets)
            if (options.occlusion) prepareCaps(k, options);
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
                // faces (rowSpan still clips every row to the side planes). Found by fuzz_culler3d.
                if (!nearlyFlat && !crossSection(pyramid, a, sgn, k, b1, b2, lo, hi)) {
                    rectLo[face] = IVec2(1);
                    rectHi[face] = IVec2(0);
                    continue;
                }
                // Clip to the grid.
                lo.x = std::max(lo.x, -c[b1]);
                hi.x = std::min(hi.x, res[b1] - 1 - c[b1]);
                lo.y = std::max(lo.y, -c[b2]);
                hi.y = std::min(hi.y, res[b2] - 1 - c[b2]);
                const std::int32_t ca = c[a] + sgn * k;
                const bool empty = ca < 0 || ca >= res[a] || lo.x > hi.x || lo.y > hi.y;
                rectLo[face] = empty ? IVec2(1) : lo;
                rectHi[face] = empty ? IVec2(0) : hi;
                if (empty) continue;
                IVec3 o{0};
                o[a] = sgn * k;
                const bool hasFar = !std::isinf(frustum.far());
                for (std::int32_t v = lo.y; v <= hi.y; ++v) {
                    o[b2] = v;
                    std::int32_t u0 = lo.x, u1 = hi.x;
                    if (!rowSpan(frustum, c, o, b1, u0, u1)) continue;
                    for (std::int32_t u = u0; u <= u1; ++u) {
                        o[b1] = u;
                        const IVec3 voxel = c + o;
                        if (hasFar && !frustum.withinFar(Vec3(voxel), Vec3(voxel) + 1.0)) continue;
                        ++inGrid;
                        const VoxelKey key = grid.linearIndex(voxel);
                        storage.setVisited(key, stamp);
                        ++stats.voxelsVisited;
                        if (options.occlusion && hiddenByCaps(o, face)) {
                            storage.setOccluded(key, stamp);
                            ++stats.voxelsOccluded;
                            ++shellBlocked;
                            continue;
                        }
                        onVoxel(key, voxel);
                        if (storage.opaque(key)) {
                            ++stats.opaqueVisited;
                            ++shellBlocked;
                        } else {
                            ++open;
                        }
                    }
                }
            }
            stats.layers = std::uint32_t(k + 1);
            if (inGrid == 0) break;
            if (options.occlusion && open == 0 && !cameraOnBoundary) {
                stats.earlyTermination = true;
                break;
            }
            // A shell whose visited voxels hold nothing opaque or occluded gets no caps: skipping a cap only
            // leaves voxels out of H (its margin outside the frustum might have held a few blockers).
            if (options.occlusion && (shellBlocked > 0)) buildCaps(grid, storage, c, k, stamp, rectLo, rectHi, stats);
        }
        return stats;
    }

private:
    struct Shell {
        std::array<traversal3d_detail::FaceSat, 6> faces;
        bool anyBlocked = false;
    };

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

    /// Clips the row of voxels c + o with o[b1] in [u0, u1] to those that touch the frustum's cone, with
    /// the same test as ViewFrustum::touchesCone (the box corner farthest along each inward side normal),
    /// solved for the row coordinate: each side plane bounds u from one side. Cost O(1) per row instead
    /// of four dot products per voxel.
    static bool rowSpan(const ViewFrustum& f, const IVec3& c, const IVec3& o, int b1, std::int32_t& u0,
                        std::int32_t& u1) {
        const Vec3& apex = f.apex();
        for (int i = 0; i < 4; ++i) {
            const Vec3& n = f.sideNormal(i);
            double rest = 0;
            for (int ax = 0; ax < 3; ++ax) {
                if (ax == b1) continue;
                const double lo = double(c[ax] + o[ax]);
                rest += n[ax] * ((n[ax] > 0 ? lo + 1.0 : lo) - apex[ax]);
            }
            // n_b1 * (x + delta - apex_b1) + rest >= -slack, x = c[b1] + u, delta = 1 if n_b1 > 0.
            const double slack = f.slack() + 1e-12 * (std::abs(rest) + 1.0);
            const double nb = n[b1];
            if (nb == 0) {
                if (rest < -slack) return false;
                continue;
            }
            const double bound = (-slack - rest) / nb; // x + delta - apex_b1 >= bound (nb > 0) or <= (nb < 0)
            if (nb > 0) {
                const double u = std::ceil(bound + apex[b1] - 1.0 - c[b1] - 1e-9);
                if (u > u0) u0 = u > 1e9 ? std::int32_t(1e9) : std::int32_t(u);
            } else {
                const double u = std::floor(bound + apex[b1] - c[b1] + 1e-9);
                if (u < u1) u1 = u < -1e9 ? std::int32_t(-1e9) : std::int32_t(u);
            }
            if (u0 > u1) return false;
        }
        return true;
    }

    /// Occluded by the caps of some earlier shell. The shells tested for shell k are prepared once per
    /// shell (prepareCaps), with the crossing parameters of q's own face precomputed.
    ///
    /// Shortcut: when q's footprint on the nearest cap holds no blocked voxel at all, the beam passes
    /// through open space just in front of q, and the farther caps are not tried (skipping a cap can only
    /// leave a voxel out of H, never put one in). Visible voxels, the bulk of a traversal, then cost one
    /// footprint test instead of log(k).
    bool hiddenByCaps(const IVec3& o, int ownFace) const {
        for (std::size_t i = 0; i < m_caps.size(); ++i) {
            const CapTest t = hiddenByShell(o, m_caps[i], ownFace);
            if (t == CapTest::Hidden) return true;
            if (t == CapTest::Open && i == 0 && m_caps[0].kk == m_caps[0].k - 1) return false;
        }
        return false;
    }

    enum class CapTest { Hidden, Partial, Open };

    struct CapRef {
        std::int32_t k, kk;
        double tMin, tMax; // crossing parameters for a voxel on the same face as the cap face (oa = k)
    };

    /// Range of t at which segments from the camera voxel to a voxel at signed axis offset oa cross the
    /// slab [kk - 1/2, kk + 1/2] (see the file comment). Monotone in each endpoint: the extremes are at
    /// the corners of the two boxes' extents on that axis.
    static void crossingRange(double oa, std::int32_t kk, double& tMin, double& tMax) {
        const double x0 = kk - 0.5, x1 = kk + 0.5;
        const double q0 = std::max(oa - 0.5, x0), q1 = oa + 0.5;
        tMin = 1;
        tMax = 0;
        for (double cA : {-0.5, 0.5})
            for (double qA : {q0, q1}) {
                const double den = qA - cA;
                if (!(den > 0)) {
                    tMin = 0;
                    tMax = 1;
                    continue;
                }
                tMin = std::min(tMin, (x0 - cA) / den);
                tMax = std::max(tMax, (x1 - cA) / den);
            }
        tMin = std::max(tMin, 0.0);
        tMax = std::min(tMax, 1.0);
    }

    void prepareCaps(std::int32_t k, const TraversalOptions3D& options) {
        m_caps.clear();
        for (std::int32_t step = 1; k - step >= 1; step *= 2) {
            const std::int32_t kk = k - step;
            if (m_shells[std::size_t(kk)].anyBlocked) {
                CapRef cap{k, kk, 0, 0};
                crossingRange(double(k), kk, cap.tMin, cap.tMax);
                m_caps.push_back(cap);
            }
            if (!options.exponentialCaps) break;
        }
    }

    /// Every segment from the camera voxel to voxel offset o crosses shell kk only through blocked voxels.
    CapTest hiddenByShell(const IVec3& o, const CapRef& cap, int ownFace) const {
        using namespace traversal3d_detail;
        const std::int32_t kk = cap.kk;
        const Shell& shell = m_shells[std::size_t(kk)];
        bool crossed = false;
        bool anyBlocked = false;
        for (int face = 0; face < 6; ++face) {
            const int a = face / 2;
            const double oa = (face % 2 == 0) ? o[a] : -o[a];
            if (oa < kk - 1) continue; // the beam never reaches this face's slab
            double tMin = cap.tMin, tMax = cap.tMax;
            if (face != ownFace) crossingRange(oa, kk, tMin, tMax);
            int b1, b2;
            otherAxes(a, b1, b2);
            // Touched voxel offsets i: [i - 1/2, i + 1/2] meets [lo, hi].
            auto range = [&](int b, std::int32_t& first, std::int32_t& last) {
                const double lo = std::min(tMin * o[b], tMax * o[b]) - 0.5 - 1e-9;
                const double hi = std::max(tMin * o[b], tMax * o[b]) + 0.5 + 1e-9;
                first = std::max<std::int32_t>(-kk, std::int32_t(std::ceil(lo - 0.5)));
                last = std::min<std::int32_t>(kk, std::int32_t(std::floor(hi + 0.5)));
            };
            std::int32_t u0, u1, v0, v1;
            range(b1, u0, u1);
            range(b2, v0, v1);
            if (u0 > u1 || v0 > v1) continue; // crosses the slab outside this face's square
            crossed = true;
            const FaceSat& sat = shell.faces[face];
            if (u1 < sat.bu0 || u0 > sat.bu1 || v1 < sat.bv0 || v0 > sat.bv1) return CapTest::Open; // none blocked
            if (u0 < sat.bu0 || u1 > sat.bu1 || v0 < sat.bv0 || v1 > sat.bv1) return CapTest::Partial;
            if (u0 < sat.u0 || u1 > sat.u1 || v0 < sat.v0 || v1 > sat.v1) return CapTest::Partial;
            const std::uint32_t blocked = blockedCount(sat, u0, u1, v0, v1);
            if (blocked == 0) return anyBlocked ? CapTest::Partial : CapTest::Open;
            if (blocked != std::uint32_t((u1 - u0 + 1) * (v1 - v0 + 1))) return CapTest::Partial;
            anyBlocked = true;
        }
        return crossed ? CapTest::Hidden : CapTest::Partial;
    }

    std::uint32_t blockedCount(const traversal3d_detail::FaceSat& s, std::int32_t u0, std::int32_t u1, std::int32_t v0,
                               std::int32_t v1) const {
        const std::size_t w = std::size_t(s.u1 - s.u0 + 2);
        auto at = [&](std::int32_t u, std::int32_t v) { // sum over [s.u0, u) x [s.v0, v)
            return m_pool[s.offset + std::size_t(v - s.v0) * w + std::size_t(u - s.u0)];
        };
        return at(u1 + 1, v1 + 1) - at(u0, v1 + 1) - at(u1 + 1, v0) + at(u0, v0);
    }

    /// Summed-area tables of the blocked (opaque or occluded) voxels of shell k's faces, over each
    /// face's visited rectangle grown by two voxels (footprints of the next shells reach a little
    /// outside the frustum). Voxels outside the grid count as not blocked.
    void buildCaps(const GridGeometry3& grid, const Storage& storage, const IVec3& c, std::int32_t k, std::uint32_t stamp,
                   const std::array<IVec2, 6>& rectLo, const std::array<IVec2, 6>& rectHi, TraversalStats3D& stats) {
        using namespace traversal3d_detail;
        Shell& shell = m_shells[std::size_t(k)];
        for (int face = 0; face < 6; ++face) {
            if (rectLo[face].x > rectHi[face].x || rectLo[face].y > rectHi[face].y) continue;
            const int a = face / 2;
            const int sgn = face % 2 == 0 ? 1 : -1;
            int b1, b2;
            otherAxes(a, b1, b2);
            FaceSat& s = shell.faces[face];
            s.bu0 = s.bv0 = std::numeric_limits<std::int32_t>::max();
            s.bu1 = s.bv1 = std::numeric_limits<std::int32_t>::min();
            s.u0 = std::max(-k, rectLo[face].x - 2);
            s.u1 = std::min(k, rectHi[face].x + 2);
            s.v0 = std::max(-k, rectLo[face].y - 2);
            s.v1 = std::min(k, rectHi[face].y + 2);
            const std::size_t w = std::size_t(s.u1 - s.u0 + 2), h = std::size_t(s.v1 - s.v0 + 2);
            s.offset = m_pool.size();
            m_pool.resize(m_pool.size() + w * h, 0); // row 0 and column 0 stay zero
            IVec3 o{0};
            o[a] = sgn * k;
            std::uint32_t* base = m_pool.data() + s.offset;
            for (std::int32_t v = s.v0; v <= s.v1; ++v) {
                o[b2] = v;
                std::uint32_t rowSum = 0;
                std::uint32_t* row = base + std::size_t(v - s.v0 + 1) * w;
                const std::uint32_t* above = row - w;
                for (std::int32_t u = s.u0; u <= s.u1; ++u) {
                    o[b1] = u;
                    const IVec3 voxel = c + o;
                    bool blocked = false;
                    if (grid.contains(voxel)) {
                        const VoxelKey key = grid.linearIndex(voxel);
                        blocked = storage.opaque(key) || storage.occluded(key, stamp);
                    }
                    if (blocked) {
                        s.bu0 = std::min(s.bu0, u);
                        s.bu1 = std::max(s.bu1, u);
                        s.bv0 = std::min(s.bv0, v);
                        s.bv1 = std::max(s.bv1, v);
                        shell.anyBlocked = true;
                    }
                    rowSum += blocked;
                    const std::size_t col = std::size_t(u - s.u0 + 1);
                    row[col] = above[col] + rowSum;
                }
            }
            ++stats.capFaces;
            stats.capVoxels += (w - 1) * (h - 1);
        }
    }

    std::vector<Shell> m_shells;       // per shell of this frame
    std::vector<CapRef> m_caps;        // the caps tested in the current shell
    std::vector<std::uint32_t> m_pool; // all summed-area tables of this frame (reused across frames)
};

} // namespace rgvc
