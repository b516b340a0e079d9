// The caps of the 3D traversal (FrustumTraversal3D.hpp): which voxels of a shell are hidden by the
// blocked voxels of earlier shells (seed 004 §5.3, in the raster formulation DESIGN.md allows).
//
// Caps. After shell k is visited, the opaque and occluded voxels of each of its faces form a bitmap: the
// paper vectorizes it into cap polygons (with holes), extrudes them from the viewpoint and rasterizes
// the cross-sections with §4.4's sampling correction. We keep the bitmap as a summed-area table instead.
// A voxel q of a later shell is occluded if, for some earlier shell k', every segment from any point of
// the camera voxel to any point of q crosses shell k' only through blocked voxels: the set of such
// crossing points (q's *footprint* on shell k') is bounded per face by an axis-aligned rectangle
// (below), and a summed-area lookup tells in O(1) whether every voxel of that rectangle is blocked. This
// is the cap test with the from-region correction built in: the footprint is the cross-section of the
// beam between the camera voxel and q, so H holds only voxels hidden from every point of the camera
// voxel; occluder fusion is automatic (any blocked voxels, from any objects, side by side in a cap), and
// blocked includes occluded voxels, as occluder extension does.
//
// Which earlier shells: k-1, k-2, k-4, k-8, ... Every segment from the camera voxel to shell k crosses
// every shell in between, so each is a valid cap. Testing only k-1 (propagating occlusion layer by layer)
// erodes the hidden region by about one voxel per shell, because a footprint on the adjacent shell is
// about two voxels wide; the exponentially spaced caps bound that loss by a logarithmic number of
// footprint margins.
//
// Footprint of q on face (a, s) of shell k' (centre-relative coordinates, camera voxel [-1/2, 1/2]^3,
// q's voxel Q = [o - 1/2, o + 1/2]^3, slab s*x_a in [k' - 1/2, k' + 1/2]): a segment c -> q' crosses the
// plane s*x_a = X at parameter t = (X - s*c_a) / (s*q'_a - s*c_a), monotone in each endpoint coordinate,
// so t over the slab lies in [tMin, tMax] from the endpoint extremes; there, every other coordinate
// (1 - t) c_b + t q'_b lies between the extremes of -1/2 + t*o_b and 1/2 + t*o_b at tMin and tMax.
// Treating t and the other coordinates independently only enlarges the rectangle (conservative).
//
// Tables. A cap is built from the blocked voxels the traversal visited (addBlocked), over their bounding
// rectangle per face: the test needs a footprint inside it, so nothing outside is ever read. Voxels the
// traversal did not record count as not blocked, which can only leave voxels out of H; it records the
// opaque voxels of a margin around the visited rows and those there that the caps hide (recordMargins),
// as footprints near the frustum's sides reach past the visited rows. A voxel on a cube edge lies on the squares of two or three faces and is entered in each.
//
// Where to test: most voxels cannot be hidden by any cap, and the test is skipped for them.
// (1) A footprint is at least two voxels wide on each axis: the range of an axis is [t o_b - 1, t o_b + 1]
//     or more around the crossing of the centre segment (t o_b), which holds floor(t o_b) and
//     floor(t o_b) + 1. So a hidden verdict on a face needs the 2x2 voxels around that crossing point
//     blocked or, at the square's border where the range is clipped, outside the square: a *core cell*
//     (i, j), covering [i, i + 1] x [j, j + 1] in centre coordinates, is one whose four voxels
//     (i..i+1, j..j+1) are each blocked or outside the face's square.
// (2) If cap k' hides q, the segment between the centres of the camera voxel and q crosses a core cell
//     of shell k'. That segment starts at chess norm 0 and ends at k > k', so it has a point p with
//     |p|_inf in [k' - 1/2, k' + 1/2]; with a the axis of p's largest coordinate and s its sign, p is in
//     the slab of face (a, s), within its square. p = t o with t in [x0 / o_a', x1 / o_a'] (o_a' = s o_a
//     >= k' - 1/2, so the test does not skip the face), and that t lies inside crossingRange's [tMin,
//     tMax] (its extremes are over a box of endpoints that contains the centres, and it is monotone in
//     each). So the face's footprint ranges contain [p_b - 1, p_b + 1] clipped to the square, and a hidden
//     verdict makes p's cell (floor p_b) a core.
// (3) So q's centre o = p / t lies in the central projection, from the camera voxel's centre, of the 3D
//     box of some core cells (the cells' extent on the face, the face's slab across). On q's face (axis
//     a', sign s', plane s' x_a' = k), every p that projects there has s' p_a' = t k >= |p_b| for all b
//     (as |o|_inf = k), so s' p_a' >= |p_a| >= k' - 1/2 > 0: clipping the box to s' x_a' >= k' - 1/2 keeps
//     every such p and leaves it in front of the camera, where the projection of a box is the convex
//     hull of its eight projected corners. Their bounding rectangle, rounded outwards, is a *candidate
//     rectangle* of the cap on q's face. The cores are grouped by tiles of kCoreTile x kCoreTile cells,
//     one rectangle per tile. A voxel outside all of a cap's candidate rectangles is never hidden by it.
// Each voxel is tested against the caps whose candidate rectangles hold it, nearest first (the caps
// outside could not hide it anyway). Every hidden verdict is the full footprint test, so H stays exactly
// as sound as before; it may hold a few more voxels than testing every cap in order did, since the
// "open just in front" shortcut below now stops the search only when shell k-1 is among those caps.
#pragma once

#include "rgvc/grid/GridGeometry.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace rgvc {

namespace traversal3d_detail {

/// Axes of face a: the two others, in increasing order.
inline void otherAxes(int a, int& b1, int& b2) {
    b1 = a == 0 ? 1 : 0;
    b2 = a == 2 ? 1 : 2;
}

/// A rectangle of voxel offsets (u on axis b1, v on axis b2) of one shell face.
struct FaceRect {
    std::int32_t u0, u1, v0, v1;
};

/// Summed-area table of one shell face, over the bounding rectangle of its blocked voxels (offsets from
/// the camera voxel on the face's axes b1, b2), and that face's core rectangles.
struct FaceSat {
    std::int32_t u0 = 0, u1 = -1, v0 = 0, v1 = -1;
    std::size_t offset = 0; // into the frame's pool; (w+1)*(h+1) entries
    std::uint32_t coreBegin = 0, coreEnd = 0; // [begin, end) in the frame's core rectangles
    bool anyBlocked() const { return u0 <= u1 && v0 <= v1; }
};

} // namespace traversal3d_detail

class ShellCaps3D {
public:
    /// Bit i of a cap mask stands for the i-th cap of the current shell (nearest first).
    using CapMask = std::uint16_t;
    static constexpr std::size_t kMaxCaps = 16;

    /// Forgets the previous frame's caps; shells 0..kMax of this frame start with none.
    void beginFrame(std::int32_t kMax) {
        m_shells.assign(std::size_t(kMax) + 1, {});
        m_pool.clear();
        m_cores.clear();
        for (auto& b : m_blocked) b.clear();
    }

    /// Chooses the caps tested for the voxels of shell k and their candidate rectangles on its faces.
    void prepare(std::int32_t k, bool exponentialCaps) {
        m_caps.clear();
        for (std::int32_t step = 1; k - step >= 1 && m_caps.size() < kMaxCaps; step *= 2) {
            const std::int32_t kk = k - step;
            if (m_shells[std::size_t(kk)].anyBlocked) {
                CapRef cap{k, kk, 0, 0};
                crossingRange(double(k), kk, cap.tMin, cap.tMax);
                m_caps.push_back(cap);
            }
            if (!exponentialCaps) break;
        }
        for (auto& r : m_rects) r.clear();
        for (std::size_t i = 0; i < m_caps.size(); ++i)
            for (int f = 0; f < 6; ++f) {
                const traversal3d_detail::FaceSat& sat = m_shells[std::size_t(m_caps[i].kk)].faces[f];
                for (std::uint32_t j = sat.coreBegin; j < sat.coreEnd; ++j)
                    addCandidates(k, m_caps[i].kk, f, m_cores[j], CapMask(1u << i));
            }
    }

    /// Rasterizes the cap masks of face `face` of the current shell over the rectangle [lo, hi] of
    /// offsets it visits, for the rows that some candidate rectangle reaches; false when no voxel there can
    /// be hidden.
    bool prepareFace(int face, const IVec2& lo, const IVec2& hi) {
        const auto& rects = m_rects[std::size_t(face)];
        if (rects.empty()) return false;
        m_maskLo = lo;
        m_maskWidth = std::size_t(hi.x - lo.x + 1);
        m_maskRows.assign(std::size_t(hi.y - lo.y + 1), kNoRow);
        m_masks.clear();
        for (const Rect& r : rects) {
            const std::int32_t u0 = std::max(r.r.u0, lo.x), u1 = std::min(r.r.u1, hi.x);
            const std::int32_t v0 = std::max(r.r.v0, lo.y), v1 = std::min(r.r.v1, hi.y);
            if (u0 > u1) continue;
            for (std::int32_t v = v0; v <= v1; ++v) {
                std::size_t& row = m_maskRows[std::size_t(v - lo.y)];
                if (row == kNoRow) {
                    row = m_masks.size();
                    m_masks.resize(m_masks.size() + m_maskWidth, 0);
                }
                CapMask* m = m_masks.data() + row; // indexed by u - lo.x (no pointer before the array)
                for (std::int32_t u = u0; u <= u1; ++u) m[std::size_t(u - lo.x)] |= r.caps;
            }
        }
        return !m_masks.empty();
    }
    /// The cap masks of row v of the face prepared last, indexed by u - maskU0(); null when no voxel of
    /// the row can be hidden.
    const CapMask* maskRow(std::int32_t v) const {
        const std::size_t row = m_maskRows[std::size_t(v - m_maskLo.y)];
        return row == kNoRow ? nullptr : m_masks.data() + row;
    }
    std::int32_t maskU0() const { return m_maskLo.x; }

    /// Occluded by one of the caps in `caps` (offsets o from the camera voxel, on face ownFace).
    ///
    /// Shortcut: when q's footprint on shell k-1 holds no blocked voxel at all, the beam passes through
    /// open space just in front of q, and the farther caps are not tried (skipping a cap can only leave a
    /// voxel out of H, never put one in).
    /// Always inlined: with a second caller (FrustumTraversal3D::recordMargins) GCC stops inlining it into
    /// the visit loop, the hot caller.
    [[gnu::always_inline]] bool hiddenByCaps(const IVec3& offset, int ownFace, CapMask caps) const {
        const Offset o{offset.x, offset.y, offset.z};
        for (unsigned m = caps; m != 0; m &= m - 1) {
            const int i = std::countr_zero(m);
            const CapTest t = hiddenByShell(o, m_caps[std::size_t(i)], ownFace);
            if (t == CapTest::Hidden) return true;
            if (t == CapTest::Open && i == 0 && m_caps[0].kk == m_caps[0].k - 1) return false;
        }
        return false;
    }

    /// Records a blocked (opaque or occluded) visited voxel of shell k, at offset o from the camera voxel,
    /// on every face whose square holds it.
    void addBlocked(const IVec3& o, std::int32_t k) {
        for (int a = 0; a < 3; ++a) {
            if (o[a] != k && o[a] != -k) continue;
            int b1, b2;
            traversal3d_detail::otherAxes(a, b1, b2);
            m_blocked[std::size_t(2 * a + (o[a] < 0))].push_back({o[b1], o[b2]});
        }
    }

    /// Forgets the blocked voxels recorded since the last build (the shell gets no cap).
    void discardRecorded() {
        for (auto& b : m_blocked) b.clear();
    }

    /// Whether blocked voxels were recorded since the last build.
    bool anyRecorded() const {
        for (const auto& b : m_blocked)
            if (!b.empty()) return true;
        return false;
    }

    /// Builds shell k's caps from the blocked voxels recorded since the last call (see the file comment),
    /// and clears the records. Adds the tables built and their voxels to the two counters.
    void build(std::int32_t k, std::uint64_t& faces, std::uint64_t& voxels) {
        using namespace traversal3d_detail;
        Shell& shell = m_shells[std::size_t(k)];
        for (int face = 0; face < 6; ++face) {
            auto& list = m_blocked[std::size_t(face)];
            if (list.empty()) continue;
            FaceSat& s = shell.faces[face];
            s.u0 = s.v0 = std::numeric_limits<std::int32_t>::max();
            s.u1 = s.v1 = std::numeric_limits<std::int32_t>::min();
            for (const IVec2& b : list) {
                s.u0 = std::min(s.u0, b.x);
                s.u1 = std::max(s.u1, b.x);
                s.v0 = std::min(s.v0, b.y);
                s.v1 = std::max(s.v1, b.y);
            }
            const std::size_t w = std::size_t(s.u1 - s.u0 + 2), h = std::size_t(s.v1 - s.v0 + 2);
            s.offset = m_pool.size();
            m_pool.resize(m_pool.size() + w * h, 0); // row 0 and column 0 stay zero
            std::uint32_t* base = m_pool.data() + s.offset;
            for (const IVec2& b : list) base[std::size_t(b.y - s.v0 + 1) * w + std::size_t(b.x - s.u0 + 1)] = 1;
            for (std::size_t r = 1; r < h; ++r) {
                std::uint32_t rowSum = 0;
                std::uint32_t* row = base + r * w;
                const std::uint32_t* above = row - w;
                for (std::size_t col = 1; col < w; ++col) {
                    rowSum += row[col];
                    row[col] = above[col] + rowSum;
                }
            }
            shell.anyBlocked = true;
            findCores(s, list, k);
            list.clear();
            ++faces;
            voxels += (w - 1) * (h - 1);
        }
    }

private:
    struct Shell {
        std::array<traversal3d_detail::FaceSat, 6> faces;
        bool anyBlocked = false;
    };

    enum class CapTest { Hidden, Partial, Open };
    /// A voxel's offsets from the camera voxel, indexed by axis (glm's operator[] with a runtime index is a
    /// switch).
    using Offset = std::array<std::int32_t, 3>;

    struct CapRef {
        std::int32_t k, kk;
        double tMin, tMax; // crossing parameters for a voxel on the same face as the cap face (oa = k)
    };

    struct Rect {
        traversal3d_detail::FaceRect r;
        CapMask caps;
    };

    static constexpr std::int32_t kCoreTile = 4;

    /// Appends the core cells of face table s (blocked voxels `list`, shell k) to m_cores, as the bounding
    /// rectangle of the cores in each tile. A core has an in-square voxel, which is blocked; each cell is
    /// examined once, from its lowest in-square voxel.
    void findCores(traversal3d_detail::FaceSat& s, const std::vector<IVec2>& list, std::int32_t k) {
        using traversal3d_detail::FaceRect;
        s.coreBegin = std::uint32_t(m_cores.size());
        const std::int32_t i0 = s.u0 - 1, j0 = s.v0 - 1;
        const std::int32_t tw = (s.u1 - i0) / kCoreTile + 1, th = (s.v1 - j0) / kCoreTile + 1;
        constexpr std::int32_t kMax = std::numeric_limits<std::int32_t>::max(), kMin = std::numeric_limits<std::int32_t>::min();
        m_tiles.assign(std::size_t(tw) * std::size_t(th), FaceRect{kMax, kMin, kMax, kMin});
        auto cell = [&](std::int32_t i, std::int32_t j) {
            // In-square part of the cell's 2x2 voxels: all blocked, hence all inside the table.
            const std::int32_t wu0 = std::max(i, -k), wu1 = std::min(i + 1, k);
            const std::int32_t wv0 = std::max(j, -k), wv1 = std::min(j + 1, k);
            if (wu0 < s.u0 || wu1 > s.u1 || wv0 < s.v0 || wv1 > s.v1) return;
            if (blockedCount(s, wu0, wu1, wv0, wv1) != std::uint32_t((wu1 - wu0 + 1) * (wv1 - wv0 + 1))) return;
            FaceRect& t = m_tiles[std::size_t((j - j0) / kCoreTile) * std::size_t(tw) + std::size_t((i - i0) / kCoreTile)];
            t.u0 = std::min(t.u0, i);
            t.u1 = std::max(t.u1, i);
            t.v0 = std::min(t.v0, j);
            t.v1 = std::max(t.v1, j);
        };
        for (const IVec2& b : list) {
            cell(b.x, b.y);
            if (b.x == -k) cell(b.x - 1, b.y);
            if (b.y == -k) cell(b.x, b.y - 1);
            if (b.x == -k && b.y == -k) cell(b.x - 1, b.y - 1);
        }
        for (const FaceRect& t : m_tiles)
            if (t.u0 <= t.u1) m_cores.push_back(t);
        s.coreEnd = std::uint32_t(m_cores.size());
    }

    /// Adds to each face of shell k the candidate rectangle of core rectangle `core` of face capFace of
    /// shell kk (see the file comment, (3)).
    void addCandidates(std::int32_t k, std::int32_t kk, int capFace, const traversal3d_detail::FaceRect& core,
                       CapMask caps) {
        using namespace traversal3d_detail;
        const int aF = capFace / 2;
        int f1, f2;
        otherAxes(aF, f1, f2);
        // The cores' box, centre-relative. Its three axes are set below (zeroed first: GCC 12 at -O2 cannot
        // follow the permutation and warned).
        Vec3 lo(0.0), hi(0.0);
        lo[aF] = capFace % 2 == 0 ? kk - 0.5 : -kk - 0.5;
        hi[aF] = lo[aF] + 1.0;
        lo[f1] = core.u0;
        hi[f1] = core.u1 + 1.0;
        lo[f2] = core.v0;
        hi[f2] = core.v1 + 1.0;
        for (int face = 0; face < 6; ++face) {
            const int a = face / 2;
            const bool positive = face % 2 == 0;
            int b1, b2;
            otherAxes(a, b1, b2);
            // Distances along the face's outward axis, clipped to d >= kk - 1/2.
            const double dLo = std::max(positive ? lo[a] : -hi[a], kk - 0.5), dHi = positive ? hi[a] : -lo[a];
            if (dHi < dLo) continue;
            double min1 = INFINITY, max1 = -INFINITY, min2 = INFINITY, max2 = -INFINITY;
            for (double d : {dLo, dHi}) {
                const double scale = double(k) / d;
                min1 = std::min(min1, std::min(lo[b1] * scale, hi[b1] * scale));
                max1 = std::max(max1, std::max(lo[b1] * scale, hi[b1] * scale));
                min2 = std::min(min2, std::min(lo[b2] * scale, hi[b2] * scale));
                max2 = std::max(max2, std::max(lo[b2] * scale, hi[b2] * scale));
            }
            // Centres o_b (integers) inside [min, max], widened by far more than the rounding of a few
            // products of numbers below 2^20.
            const double eps = 1e-6;
            FaceRect r;
            r.u0 = std::int32_t(std::max(double(-k), std::ceil(min1 - eps)));
            r.u1 = std::int32_t(std::min(double(k), std::floor(max1 + eps)));
            r.v0 = std::int32_t(std::max(double(-k), std::ceil(min2 - eps)));
            r.v1 = std::int32_t(std::min(double(k), std::floor(max2 + eps)));
            if (r.u0 <= r.u1 && r.v0 <= r.v1) m_rects[std::size_t(face)].push_back({r, caps});
        }
    }

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

    /// ceil and floor of x for |x| < 2^31 (std::ceil and std::floor are function-length sequences on
    /// x86-64 without SSE4.1, and they were the largest cost of the cap test).
    static std::int32_t ceilInt(double x) {
        const auto i = std::int32_t(x); // truncates towards zero
        return i + std::int32_t(double(i) < x);
    }
    static std::int32_t floorInt(double x) {
        const auto i = std::int32_t(x);
        return i - std::int32_t(double(i) > x);
    }

    /// The voxels of face `face` of shell kk that segments from the camera voxel to voxel offset o cross,
    /// for crossing parameters in [tMin, tMax]: [u0, u1] x [v0, v1], empty when they cross the slab
    /// outside the face's square. Touched voxel offsets i: [i - 1/2, i + 1/2] meets [lo, hi].
    static bool footprint(const Offset& o, int face, std::int32_t kk, double tMin, double tMax, std::int32_t& u0,
                          std::int32_t& u1, std::int32_t& v0, std::int32_t& v1) {
        int b1, b2;
        traversal3d_detail::otherAxes(face / 2, b1, b2);
        auto range = [&](int b, std::int32_t& first, std::int32_t& last) {
            const double lo = std::min(tMin * o[b], tMax * o[b]) - 0.5 - 1e-9;
            const double hi = std::max(tMin * o[b], tMax * o[b]) + 0.5 + 1e-9;
            first = std::max<std::int32_t>(-kk, ceilInt(lo - 0.5));
            last = std::min<std::int32_t>(kk, floorInt(hi + 0.5));
        };
        range(b1, u0, u1);
        range(b2, v0, v1);
        return u0 <= u1 && v0 <= v1;
    }

    /// Every segment from the camera voxel to voxel offset o crosses shell kk only through blocked voxels.
    /// q's own face first: most tests end there, without the crossing ranges of the other faces (which
    /// the beam reaches only near the shell's edges). The face order changes no Hidden verdict, only
    /// which of Open and Partial a failing test reports.
    CapTest hiddenByShell(const Offset& o, const CapRef& cap, int ownFace) const {
        using namespace traversal3d_detail;
        const std::int32_t kk = cap.kk;
        const Shell& shell = m_shells[std::size_t(kk)];
        bool crossed = false;
        bool anyBlocked = false;
        // Verdict of one face's footprint: blocked entirely (true), or the test's answer in `verdict`.
        CapTest verdict = CapTest::Partial;
        auto faceBlocked = [&](int face, std::int32_t u0, std::int32_t u1, std::int32_t v0, std::int32_t v1) {
            crossed = true;
            const FaceSat& sat = shell.faces[face];
            verdict = anyBlocked ? CapTest::Partial : CapTest::Open;
            if (u1 < sat.u0 || u0 > sat.u1 || v1 < sat.v0 || v0 > sat.v1) return false; // none blocked
            verdict = CapTest::Partial;
            if (u0 < sat.u0 || u1 > sat.u1 || v0 < sat.v0 || v1 > sat.v1) return false;
            const std::uint32_t blocked = blockedCount(sat, u0, u1, v0, v1);
            if (blocked == 0 && !anyBlocked) verdict = CapTest::Open;
            if (blocked != std::uint32_t((u1 - u0 + 1) * (v1 - v0 + 1))) return false;
            anyBlocked = true;
            return true;
        };
        std::int32_t u0, u1, v0, v1;
        if (footprint(o, ownFace, kk, cap.tMin, cap.tMax, u0, u1, v0, v1) && !faceBlocked(ownFace, u0, u1, v0, v1))
            return verdict;
        for (int face = 0; face < 6; ++face) {
            if (face == ownFace) continue;
            const int a = face / 2;
            const double oa = (face % 2 == 0) ? o[a] : -o[a];
            if (oa < kk - 1) continue; // the beam never reaches this face's slab
            double tMin, tMax;
            crossingRange(oa, kk, tMin, tMax);
            if (footprint(o, face, kk, tMin, tMax, u0, u1, v0, v1) && !faceBlocked(face, u0, u1, v0, v1)) return verdict;
        }
        return crossed ? CapTest::Hidden : CapTest::Partial;
    }

    /// Blocked voxels in [u0, u1] x [v0, v1], which lies inside s's rectangle.
    std::uint32_t blockedCount(const traversal3d_detail::FaceSat& s, std::int32_t u0, std::int32_t u1, std::int32_t v0,
                               std::int32_t v1) const {
        const std::size_t w = std::size_t(s.u1 - s.u0 + 2);
        auto at = [&](std::int32_t u, std::int32_t v) { // sum over [s.u0, u) x [s.v0, v)
            return m_pool[s.offset + std::size_t(v - s.v0) * w + std::size_t(u - s.u0)];
        };
        return at(u1 + 1, v1 + 1) - at(u0, v1 + 1) - at(u1 + 1, v0) + at(u0, v0);
    }

    std::vector<Shell> m_shells;                                   // per shell of this frame
    std::vector<CapRef> m_caps;                                    // the caps tested in the current shell
    std::vector<std::uint32_t> m_pool;                             // all summed-area tables of this frame
    std::vector<traversal3d_detail::FaceRect> m_cores;             // core rectangles of this frame
    std::vector<traversal3d_detail::FaceRect> m_tiles;             // findCores' scratch
    std::array<std::vector<IVec2>, 6> m_blocked;                   // blocked voxels of the current shell
    std::array<std::vector<Rect>, 6> m_rects;                      // candidate rectangles per face
    static constexpr std::size_t kNoRow = std::numeric_limits<std::size_t>::max();
    std::vector<CapMask> m_masks;                                  // cap masks of the face prepared last
    std::vector<std::size_t> m_maskRows;                           // per row: offset in m_masks or kNoRow
    IVec2 m_maskLo{0};
    std::size_t m_maskWidth = 0;
};

} // namespace rgvc
