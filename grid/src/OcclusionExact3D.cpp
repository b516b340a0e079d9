// OcclusionBuffer3D's exact per-pixel occludee tests (OcclusionBuffer3D.hpp, "Occludees"): a sphere
// wholly in front of the camera (hiddenBall) and a box over its footprint (hiddenBoxExact), each pixel
// against the nearest distance of the part of the shape it shows, from the largest dot product over the
// pixel's rays (PixelMaxDot). The cheaper tests that run first (rectangles, witnesses, shadows):
// OcclusionTests3D.cpp.
#include "OcclusionRowSpans3D.hpp"
#include "rgvc/grid/OcclusionBuffer3D.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>

namespace rgvc {

/// The largest c.d over the rays d of each pixel of a rectangle, row after row (OcclusionBuffer3D::
/// hiddenBall, hiddenBoxExact), for a vector c in camera coordinates (right, up, forward).
/// Why it is exact. In image coordinates d ∝ (x, y, 1), and c.d / |c| = cos θ, θ the angle between d and
/// c. On the sphere of directions cos θ has two critical points, ±ĉ; on the image plane (the open front
/// hemisphere) only ĉ's image (cx / cz, cy / cz) when cz > 0, a maximum (-ĉ, when in front, is the
/// minimum). So over a closed pixel rectangle the maximum is there when the pixel holds it, or else on
/// the boundary: at a corner, or at an edge's interior critical point. Along a row edge y = y_j,
/// c.d ∝ (A + x cx) / sqrt(B + x²) with A = cz + y_j cy, B = 1 + y_j², whose derivative has the sign of
/// cx B - A x: one critical point, x* = cx B / A, a maximum when A > 0 (when A <= 0 the edge's maximum is
/// at a corner). Column edges x = x_i likewise, y* = cy (1 + x_i²) / (cz + x_i cx). Each lattice line
/// holds one x* (y*), so one pixel on each side of it takes that value into account.
/// Rounding: the values to ~1e-15 |c|; a critical point that rounding assigns to the neighbouring pixel
/// leaves its true pixel with a corner within an ulp of it, where c.d is flat (its derivative vanishes
/// there). Callers pad the values (1e-9 |c|).
/// Only the pixels a caller asks for are computed (next's column range; rows may be skipped): the tests
/// need the maxima only where the image is not already covered nearer than the shape's nearest point.
class PixelMaxDot {
public:
    struct Lattice {
        const double *x, *y, *inv; // corner coordinates and 1 / |(x, y, 1)| (OcclusionBuffer3D's lattice)
        std::size_t stride;        // cols + 1
        double halfW, halfH, pixelW, pixelH;
    };
    using Scratch = ImageMaxDotScratch;
    PixelMaxDot(const Lattice& l, Scratch& s, const Vec3& c, double len, const ImageFootprint3D::Rect& r)
        : m_l(l), m_s(s), m_c(c), m_len(len), m_r(r), m_n(std::size_t(r.i1 - r.i0 + 2)) {
        if (m_s.colRow.size() < m_n) {
            m_s.colRow.resize(m_n);
            m_s.colVal.resize(m_n);
            m_s.rowA.resize(m_n);
            m_s.rowB.resize(m_n);
            m_s.out.resize(m_n);
        }
        // The pixel holding ĉ's image, when ĉ is in front.
        if (c.z > 0) {
            const double fi = (c.x / c.z + l.halfW) / l.pixelW, fj = (c.y / c.z + l.halfH) / l.pixelH;
            if (fi >= double(r.i0) && fi < double(r.i1 + 1) && fj >= double(r.j0) && fj < double(r.j1 + 1))
                m_ic = int(fi), m_jc = int(fj);
        }
    }
    /// The maxima of pixels i0..i1 of pixel row j (r.j0 <= j <= r.j1, r.i0 <= i0 <= i1 <= r.i1; rows in
    /// increasing order, any of them skipped): out[q] for pixel r.i0 + q, i0 - r.i0 <= q <= i1 - r.i0 (the
    /// other entries are stale).
    const double* next(int j, int i0, int i1) {
        const int q0 = i0 - m_r.i0, q1 = i1 - m_r.i0 + 1; // the lattice columns the pixels need
        if (m_cLo > m_cHi) {
            columns(q0, q1);
            m_cLo = q0, m_cHi = q1;
        }
        if (q0 < m_cLo) columns(q0, m_cLo - 1), m_cLo = q0;
        if (q1 > m_cHi) columns(m_cHi + 1, q1), m_cHi = q1;
        // Lattice row j is the last call's row j + 1 when the rows follow each other (kept in rowA).
        if (m_inA != j || m_aLo > q0 || m_aHi < q1) fill(j, q0, q1, m_s.rowA.data(), m_kA, m_vA);
        int kB;
        double vB;
        fill(j + 1, q0, q1, m_s.rowB.data(), kB, vB);
        const double* a = m_s.rowA.data();
        const double* b = m_s.rowB.data();
        const int* colRow = m_s.colRow.data();
        const double* colVal = m_s.colVal.data();
        double* out = m_s.out.data();
        const int cA = m_kA - m_r.i0, cB = kB - m_r.i0, cC = j == m_jc ? m_ic - m_r.i0 : -1;
        for (int q = q0; q < q1; ++q) { // branch-free
            double m = std::max(std::max(a[q], a[q + 1]), std::max(b[q], b[q + 1]));
            m = colRow[q] == j ? std::max(m, colVal[q]) : m;
            m = colRow[q + 1] == j ? std::max(m, colVal[q + 1]) : m;
            m = q == cA ? std::max(m, m_vA) : m;
            m = q == cB ? std::max(m, vB) : m;
            out[q] = q == cC ? m_len : m;
        }
        std::swap(m_s.rowA, m_s.rowB);
        m_inA = j + 1;
        m_aLo = q0;
        m_aHi = q1;
        m_kA = kB;
        m_vA = vB;
        return out;
    }

private:
    // Column edges q0..q1 (lattice columns r.i0 + q): the pixel row of each edge's critical point (-1: none
    // in the rectangle), its c.d. Computed once per column, for the columns some row asks for.
    void columns(int q0, int q1) {
        for (int q = q0; q <= q1; ++q) {
            const double x = m_l.x[std::size_t(m_r.i0 + q)], a = m_c.z + x * m_c.x, b = 1 + x * x;
            const double y = m_c.y * b / a, fj = (y + m_l.halfH) / m_l.pixelH;
            const bool in = a > 0 && fj >= double(m_r.j0) && fj < double(m_r.j1 + 1);
            m_s.colRow[std::size_t(q)] = in ? int(fj) : -1;
            m_s.colVal[std::size_t(q)] = in ? (a + y * m_c.y) / std::sqrt(b + y * y) : 0.0;
        }
    }
    // Lattice row j: c.d at its corners q0..q1 (out, indexed from r.i0) and its row edge's critical point.
    void fill(int j, int q0, int q1, double* out, int& k, double& v) const {
        const double y = m_l.y[std::size_t(j)], a = m_c.z + y * m_c.y, b = 1 + y * y;
        const double* inv = m_l.inv + std::size_t(j) * m_l.stride + std::size_t(m_r.i0);
        const double* xs = m_l.x + std::size_t(m_r.i0);
        for (int q = q0; q <= q1; ++q) out[q] = (a + xs[q] * m_c.x) * inv[q];
        const double x = m_c.x * b / a, fi = (x + m_l.halfW) / m_l.pixelW;
        const bool in = a > 0 && fi >= double(m_r.i0) && fi < double(m_r.i1 + 1);
        k = in ? int(fi) : -1;
        v = in ? (a + x * m_c.x) / std::sqrt(b + x * x) : 0.0;
    }
    const Lattice& m_l;
    Scratch& m_s;
    Vec3 m_c;
    double m_len;
    ImageFootprint3D::Rect m_r;
    std::size_t m_n;
    int m_ic = -1, m_jc = -1, m_kA = -1;
    double m_vA = 0;
    int m_inA = std::numeric_limits<int>::min(), m_aLo = 0, m_aHi = -1; // the lattice row in rowA, its columns
    int m_cLo = 0, m_cHi = -1;                                           // the column edges computed
};

bool OcclusionBuffer3D::hiddenBall(const Vec3& c, double rho, double nearest) {
    // A sphere (centre c, apex-relative, radius rho) wholly in front of the camera, tested pixel by pixel
    // against the nearest distance of the part of it that the pixel shows.
    // Along a unit ray d at angle θ to c, the sphere is entered at t(cd) = cd - sqrt(rho² - |c|² + cd²),
    // cd = c.d = |c| cos θ, when cd >= sqrt(|c|² - rho²) (else the ray misses it); t decreases as cd grows
    // (dt/dcd = 1 - cd / sqrt(...) < 0). So over the rays of pixel P the nearest entry is t(max cd over P)
    // (PixelMaxDot), and P hides every point of the sphere it shows when depth(P) < t(max cd): each ray of
    // P has entered an occluder's interior before depth(P), nearer than any point of the sphere along it.
    // A pixel whose largest cd is below the tangent limit shows none of the sphere. The sphere's points in
    // view lie in its tangent rectangle's pixels (rectOf).
    // Rounding: cd padded by 1e-9 |c| upward (t is then lower); t's square root cancels near grazing (its
    // argument to ~1e-16 |c|², the root to ~1.5e-8 |c|), so t is lowered by 1e-7 |c|, and never below the
    // sphere's nearest distance (a true bound of every entry).
    const PixelRect r = rectOf(c, rho);
    if (r.i0 > r.i1) return true; // its image misses the view: no point of it is in view
    const Vec3 cc{glm::dot(c, m_right), glm::dot(c, m_up), glm::dot(c, m_forward)};
    const double l2 = lengthSquared<3>(c), len = std::sqrt(l2);
    const double cdPad = 1e-9 * len, tPad = 1e-7 * len;
    const double tangentLo = std::sqrt(l2 - rho * rho) * (1 - 1e-9); // cz > 1.001 rho: no cancellation
    const double rho2l2 = rho * rho - l2;
    const PixelMaxDot::Lattice lattice{m_cornerX.data(), m_cornerY.data(), m_invLen.data(), std::size_t(m_cols + 1),
                                       m_halfW, m_halfH, m_pixelW, m_pixelH};
    PixelMaxDot maxCd(lattice, m_maxDot[0], cc, len, r);
    for (int j = r.j0; j <= r.j1; ++j) {
        // The row's maxima only between its first and last pixel not covered nearer (tLo >= nearest).
        const double* depth = m_depth.data() + std::size_t(j) * std::size_t(m_cols);
        int i0 = r.i0, i1 = r.i1;
        if (!uncoveredSpan(depth, nearest, i0, i1)) continue;
        const double* m = maxCd.next(j, i0, i1); // indexed from r.i0
        bool ok = true;
        for (int i = i0; i <= i1; ++i) { // branch-free
            const double cd = m[i - r.i0] + cdPad;
            const double t = cd - std::sqrt(std::max(0.0, rho2l2 + cd * cd)) - tPad;
            const double tLo = t > nearest ? t : nearest; // (a NaN t: nearest)
            const bool shows = !(cd < tangentLo);
            ok = ok & (!shows | (depth[i] < tLo));
        }
        if (!ok) return false;
    }
    return true;
}

bool OcclusionBuffer3D::hiddenBoxExact(const Vec3& lo, const Vec3& hi, double nearest, const Footprint& f) {
    // A box (apex-relative, grown) tested pixel by pixel, within its footprint's rows and spans (which hold
    // every pixel that can show a point of it in view). The box's faces that face the camera are those
    // whose plane it lies beyond: along axis a, x_a = lo_a when lo_a > 0 (normal s = +1), x_a = hi_a when
    // hi_a < 0 (s = -1); c_a = |that plane's coordinate|. A unit ray d that enters the box crosses every
    // facing plane before it does, at t = c_a / (s d_a) with s d_a > 0, so its entry is at least the
    // largest of those; over the rays of pixel P, every entry is at least max_a c_a / max_P(s d_a), and
    // max_P(s d_a) = max over P of (s e_a).d is PixelMaxDot's. A pixel where some max_P(s d_a) <= 0 has no
    // ray moving towards that face: it shows none of the box. The pixel passes when its depth is below the
    // bound (or it shows nothing), which then holds for every point of the box it shows. The bound is
    // exact for a face seen alone and within a pixel's angle otherwise: the 8-part refinement's parts,
    // each with one nearest distance, are not needed.
    // Rounding: max_P(s d_a) padded by 1e-9 upward (|e_a| = 1), the quotient lowered by a relative 1e-9,
    // and never below the box's nearest distance (a true bound of every entry).
    const PixelRect& r = f.rect;
    if (r.i0 > r.i1) return true;
    const PixelMaxDot::Lattice lattice{m_cornerX.data(), m_cornerY.data(), m_invLen.data(), std::size_t(m_cols + 1),
                                       m_halfW, m_halfH, m_pixelW, m_pixelH};
    // Up to three facing planes, each with its PixelMaxDot.
    std::optional<PixelMaxDot> axes[3];
    double planes[3];
    int n = 0;
    for (int a = 0; a < 3; ++a) {
        double s = 0;
        if (lo[a] > 0) s = 1, planes[n] = lo[a];
        else if (hi[a] < 0) s = -1, planes[n] = -hi[a];
        else continue;
        Vec3 e(0.0);
        e[a] = s;
        const Vec3 cam{glm::dot(e, m_right), glm::dot(e, m_up), glm::dot(e, m_forward)};
        axes[n].emplace(lattice, m_maxDot[n], cam, 1.0, r);
        ++n;
    }
    bool hiddenAll = n > 0; // n = 0: the apex inside the box (callers never get here then)
    for (int j = r.j0; j <= r.j1 && hiddenAll; ++j) {
        // The maxima only where the span is not covered nearer (t >= nearest). On the 3D cities' node
        // tests the rest was a fifth of the spans' pixels, and half of the rows had none.
        int i0, i1;
        if (!openRowSpan(f, j, nearest, i0, i1)) continue;
        const double* depth = m_depth.data() + std::size_t(j) * std::size_t(m_cols);
        const double* m[3] = {nullptr, nullptr, nullptr};
        for (int k = 0; k < n; ++k) m[k] = axes[k]->next(j, i0, i1);
        for (int i = i0; i <= i1; ++i) {
            const int q = i - r.i0;
            double t = nearest;
            bool shows = true;
            for (int k = 0; k < n; ++k) {
                const double dot = m[k][q] + 1e-9;
                shows = shows && dot > 0;
                t = std::max(t, planes[k] / dot * (1 - 1e-9));
            }
            if (shows && !(depth[i] < t)) {
                hiddenAll = false;
                break;
            }
        }
    }
    return hiddenAll;
}

} // namespace rgvc
