// OrthoOcclusionImage (grid/internal/rgvc/grid/OrthoOcclusionImage.hpp): the parallel-ray occlusion image.
#include "rgvc/grid/OrthoOcclusionImage.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <variant>

namespace rgvc {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}

bool OrthoOcclusionImage::begin(const OrthoVolume<3>& view, double pixelSize) {
    m_view = view;
    m_origin = view.origin();
    m_f = view.axis(0);
    m_right = view.axis(1);
    m_up = view.axis(2);
    const double s = view.slack();
    const double w = view.halfExtent(1) + s, h = view.halfExtent(2) + s;
    m_stats = Stats{};
    if (!(w > 0) || !(h > 0) || !std::isfinite(w) || !std::isfinite(h) || !(pixelSize > 0)) {
        m_cols = m_rows = 0;
        return false;
    }
    m_cols = int(std::clamp(std::ceil(2 * w / pixelSize), 8.0, double(kMaxPixels)));
    m_rows = int(std::clamp(std::ceil(2 * h / pixelSize), 8.0, double(kMaxPixels)));
    m_u0 = -w;
    m_v0 = -h;
    m_du = 2 * w / m_cols;
    m_dv = 2 * h / m_rows;
    m_depth.assign(std::size_t(m_cols) * std::size_t(m_rows), kInf);
    m_partial.assign(m_depth.size(), -1);
    m_drawn.clear();
    m_margin = 1e-7 * std::max(m_du, m_dv);
    m_lattice.reserve(std::size_t(m_cols + 1) * std::size_t(m_rows + 1));
    return true;
}

void OrthoOcclusionImage::depthRange(const Vec3& lo, const Vec3& hi, double& nearest, double& farthest) const {
    const Vec3 c = 0.5 * (lo + hi), h = 0.5 * (hi - lo);
    const double t = glm::dot(c - m_origin, m_f);
    const double r = std::abs(m_f.x) * h.x + std::abs(m_f.y) * h.y + std::abs(m_f.z) * h.z;
    nearest = t - r;
    farthest = t + r;
}

bool OrthoOcclusionImage::footprint(const Vec3& lo, const Vec3& hi, double grow, int& c0, int& c1, int& r0, int& r1) const {
    if (m_cols == 0) return false;
    const Vec3 c = 0.5 * (lo + hi), h = 0.5 * (hi - lo) + grow;
    const Vec3 q = c - m_origin;
    const double uc = glm::dot(q, m_right), vc = glm::dot(q, m_up);
    const double ru = std::abs(m_right.x) * h.x + std::abs(m_right.y) * h.y + std::abs(m_right.z) * h.z;
    const double rv = std::abs(m_up.x) * h.x + std::abs(m_up.y) * h.y + std::abs(m_up.z) * h.z;
    const double a0 = (uc - ru - m_u0) / m_du, a1 = (uc + ru - m_u0) / m_du;
    const double b0 = (vc - rv - m_v0) / m_dv, b1 = (vc + rv - m_v0) / m_dv;
    if (!(a1 >= 0) || !(a0 <= m_cols) || !(b1 >= 0) || !(b0 <= m_rows)) return false;
    c0 = int(std::max(0.0, std::floor(a0)));
    c1 = int(std::min(double(m_cols - 1), std::floor(a1)));
    r0 = int(std::max(0.0, std::floor(b0)));
    r1 = int(std::min(double(m_rows - 1), std::floor(b1)));
    return c0 <= c1 && r0 <= r1;
}

double OrthoOcclusionImage::entryAt(const Shape<3>& s, double slack, double u, double v) const {
    const Vec3 o = m_origin + u * m_right + v * m_up;
    const Vec3& f = m_f;
    return std::visit(
        [&](const auto& x) -> double {
            using T = std::decay_t<decltype(x)>;
            double t0 = 0, t1 = kInf;
            if constexpr (std::is_same_v<T, Ball<3>>) {
                const double r = x.radius - slack;
                if (!(r > 0)) return kInf;
                const Vec3 oc = o - x.center;
                const double b = glm::dot(oc, f), c = lengthSquared<3>(oc) - r * r, disc = b * b - c;
                if (!(disc > 0)) return kInf;
                const double root = std::sqrt(disc);
                t0 = std::max(0.0, -b - root);
                t1 = -b + root;
            } else if constexpr (std::is_same_v<T, Box<3>>) {
                for (int a = 0; a < 3; ++a) {
                    const double lo = x.min[a] + slack, hi = x.max[a] - slack;
                    if (!(lo < hi)) return kInf;
                    if (f[a] == 0) {
                        if (!(o[a] > lo && o[a] < hi)) return kInf;
                        continue;
                    }
                    double u0 = (lo - o[a]) / f[a], u1 = (hi - o[a]) / f[a];
                    if (u0 > u1) std::swap(u0, u1);
                    t0 = std::max(t0, u0);
                    t1 = std::min(t1, u1);
                }
            } else if constexpr (std::is_same_v<T, MeshSolid>) {
                return kInf; // never drawn (see draw)
            } else {
                for (const HalfSpace& hs : x.planes) {
                    const double nd = glm::dot(hs.normal, f);
                    const double na = glm::dot(hs.normal, o) - (hs.offset - x.tolerance - slack); // inside: < 0
                    if (nd == 0) {
                        if (!(na < 0)) return kInf;
                        continue;
                    }
                    const double u = -na / nd;
                    if (nd > 0) t1 = std::min(t1, u);
                    else t0 = std::max(t0, u);
                }
            }
            return t0 < t1 ? t0 : kInf;
        },
        s);
}

namespace {

/// A small convex polygon on the image plane.
struct Poly {
    double u[24], v[24]; // a square clipped by at most 8 + 8 half-planes
    int n = 0;
};

/// Keeps the part of p with (b - a) x (q - a) >= shift (the left of a -> b moved in by shift);
/// keepLeft false keeps the other side (<= shift).
void clipBy(const Poly& p, double au, double av, double bu, double bv, double shift, bool keepLeft, Poly& out) {
    out.n = 0;
    const double eu = bu - au, ev = bv - av, len = std::sqrt(eu * eu + ev * ev);
    if (!(len > 0)) {
        if (keepLeft) out = p;
        return;
    }
    auto side = [&](double u, double v) {
        const double s = (eu * (v - av) - ev * (u - au)) / len - shift;
        return keepLeft ? s : -s;
    };
    for (int k = 0; k < p.n; ++k) {
        const int l = (k + 1) % p.n;
        const double sk = side(p.u[k], p.v[k]), sl = side(p.u[l], p.v[l]);
        if (sk >= 0 && out.n < 24) out.u[out.n] = p.u[k], out.v[out.n++] = p.v[k];
        if (((sk > 0 && sl < 0) || (sk < 0 && sl > 0)) && out.n < 24) {
            const double t = sk / (sk - sl);
            out.u[out.n] = p.u[k] + t * (p.u[l] - p.u[k]);
            out.v[out.n++] = p.v[k] + t * (p.v[l] - p.v[k]);
        }
    }
}

} // namespace

double OrthoOcclusionImage::largestEntry(const Drawn& d, int col, int row) const {
    Poly q, t;
    const double u0 = m_u0 + col * m_du, v0 = m_v0 + row * m_dv;
    q.n = 4;
    q.u[0] = u0, q.v[0] = v0, q.u[1] = u0 + m_du, q.v[1] = v0, q.u[2] = u0 + m_du, q.v[2] = v0 + m_dv, q.u[3] = u0, q.v[3] = v0 + m_dv;
    for (int k = 0; k < d.n; ++k) {
        const int l = (k + 1) % d.n;
        clipBy(q, d.pu[k], d.pv[k], d.pu[l], d.pv[l], 0, true, t);
        q = t;
    }
    const Shape<3> box = d.box;
    double z = 0;
    for (int k = 0; k < q.n; ++k) {
        const double e = entryAt(box, 0, q.u[k], q.v[k]);
        if (!std::isfinite(e)) return d.farthest; // a grazing ray missed by rounding: the far side bounds it
        z = std::max(z, e);
    }
    return z;
}

bool OrthoOcclusionImage::unionCovers(const Drawn& a, const Drawn& b, int col, int row, double& depth) const {
    Poly rest, piece, tmp;
    const double u0 = m_u0 + col * m_du, v0 = m_v0 + row * m_dv;
    rest.n = 4;
    rest.u[0] = u0, rest.v[0] = v0, rest.u[1] = u0 + m_du, rest.v[1] = v0, rest.u[2] = u0 + m_du, rest.v[2] = v0 + m_dv,
    rest.u[3] = u0, rest.v[3] = v0 + m_dv;
    // Pieces of Q \ a (a shrunk by the margin): rest n not H_k, then rest := rest n H_k.
    for (int k = 0; k < a.n && rest.n > 0; ++k) {
        const int l = (k + 1) % a.n;
        clipBy(rest, a.pu[k], a.pv[k], a.pu[l], a.pv[l], m_margin, false, piece);
        for (int p = 0; p < piece.n; ++p)
            for (int e = 0; e < b.n; ++e) {
                const int f = (e + 1) % b.n;
                const double eu = b.pu[f] - b.pu[e], ev = b.pv[f] - b.pv[e], len = std::sqrt(eu * eu + ev * ev);
                if (!(len > 0)) continue;
                if (!((eu * (piece.v[p] - b.pv[e]) - ev * (piece.u[p] - b.pu[e])) / len >= m_margin)) return false;
            }
        clipBy(rest, a.pu[k], a.pv[k], a.pu[l], a.pv[l], m_margin, true, tmp);
        rest = tmp;
    }
    depth = std::max(largestEntry(a, col, row), largestEntry(b, col, row));
    return true;
}

void OrthoOcclusionImage::draw(const Shape<3>& occluder, double slack) {
    if (m_cols == 0) return;
    // A mesh's occluder is its solid voxelization, already in O (MeshSolid.hpp): the image draws nothing
    // for it, as the perspective image does (less occlusion here, never a wrong one).
    if (std::holds_alternative<MeshSolid>(occluder)) return;
    const Box<3> b = boundsOf<3>(occluder);
    int c0, c1, r0, r1;
    if (!footprint(b.min, b.max, 0.0, c0, c1, r0, r1)) return;
    const int lw = c1 - c0 + 2;
    m_lattice.resize(std::size_t(lw) * std::size_t(r1 - r0 + 2));
    for (int j = r0; j <= r1 + 1; ++j)
        for (int i = c0; i <= c1 + 1; ++i) m_lattice[std::size_t(j - r0) * std::size_t(lw) + std::size_t(i - c0)] = entry(occluder, slack, i, j);
    // Boxes are kept for the seam test: the shrunk box and its image polygon (the hull of its corners).
    std::int32_t self = -1;
    if (const Box<3>* bx = std::get_if<Box<3>>(&occluder)) {
        Drawn d;
        d.box = Box<3>{bx->min + slack, bx->max - slack};
        if (glm::all(glm::lessThan(d.box.min, d.box.max))) {
            double pu[8], pv[8];
            for (int k = 0; k < 8; ++k) {
                const Vec3 c((k & 1) ? d.box.max.x : d.box.min.x, (k & 2) ? d.box.max.y : d.box.min.y, (k & 4) ? d.box.max.z : d.box.min.z);
                pu[k] = glm::dot(c - m_origin, m_right);
                pv[k] = glm::dot(c - m_origin, m_up);
            }
            // Monotone chain over the 8 points, counter-clockwise.
            int idx[8] = {0, 1, 2, 3, 4, 5, 6, 7};
            std::sort(idx, idx + 8, [&](int x, int y) { return pu[x] < pu[y] || (pu[x] == pu[y] && pv[x] < pv[y]); });
            int hull[17], h = 0;
            auto turn = [&](int o, int x, int y) { return (pu[x] - pu[o]) * (pv[y] - pv[o]) - (pv[x] - pv[o]) * (pu[y] - pu[o]); };
            for (int k = 0; k < 8; ++k) {
                while (h >= 2 && turn(hull[h - 2], hull[h - 1], idx[k]) <= 0) --h;
                hull[h++] = idx[k];
            }
            for (int k = 6, lower = h + 1; k >= 0; --k) {
                while (h >= lower && turn(hull[h - 2], hull[h - 1], idx[k]) <= 0) --h;
                hull[h++] = idx[k];
            }
            d.n = std::min(h - 1, 8);
            for (int k = 0; k < d.n; ++k) d.pu[k] = pu[hull[k]], d.pv[k] = pv[hull[k]];
            double nearest;
            depthRange(d.box.min, d.box.max, nearest, d.farthest);
            if (d.n >= 3) {
                self = std::int32_t(m_drawn.size());
                m_drawn.push_back(d);
            }
        }
    }
    bool any = false;
    for (int j = r0; j <= r1; ++j) {
        const double* a = &m_lattice[std::size_t(j - r0) * std::size_t(lw)];
        const double* n = a + lw;
        double* row = &m_depth[std::size_t(j) * std::size_t(m_cols)];
        std::int32_t* partial = &m_partial[std::size_t(j) * std::size_t(m_cols)];
        for (int i = c0; i <= c1; ++i) {
            const int k = i - c0;
            double z = std::max({a[k], a[k + 1], n[k], n[k + 1]}); // +inf when a corner misses
            if (!std::isfinite(z) && self >= 0) {
                const int hits = std::isfinite(a[k]) + std::isfinite(a[k + 1]) + std::isfinite(n[k]) + std::isfinite(n[k + 1]);
                // Covered already (by a nearer or farther occluder): the union test is skipped, which
                // only ever leaves a pixel's depth as it is (it costs most of a draw along seams).
                if (hits == 0 || std::isfinite(row[i])) continue;
                // Covered in part: the union with the last box that covered this pixel in part.
                const std::int32_t other = partial[i];
                partial[i] = self;
                double zu;
                if (other < 0 || !unionCovers(m_drawn[std::size_t(self)], m_drawn[std::size_t(other)], i, j, zu)) continue;
                z = zu;
                ++m_stats.seamPixels;
            }
            if (z < row[i]) {
                row[i] = z;
                ++m_stats.pixelsWritten;
                any = true;
            }
        }
    }
    if (any) ++m_stats.occludersDrawn;
}

bool OrthoOcclusionImage::hiddenBox(const Vec3& lo, const Vec3& hi, double slack) {
    ++m_stats.tests;
    if (m_cols == 0) return false;
    int c0, c1, r0, r1;
    if (!footprint(lo, hi, slack, c0, c1, r0, r1)) return true; // no point in the cross-section
    const Vec3 l = lo - slack, h = hi + slack;
    double nearest, farthest;
    depthRange(l, h, nearest, farthest);
    // The near face planes' depths, t_a(u, v) = A_a + B_a u + C_a v (see the top of the header).
    double A[3], B[3], C[3];
    int axes = 0;
    for (int a = 0; a < 3; ++a) {
        if (m_f[a] == 0) continue;
        const double plane = m_f[a] > 0 ? l[a] : h[a];
        A[axes] = (plane - m_origin[a]) / m_f[a];
        B[axes] = -m_right[a] / m_f[a];
        C[axes] = -m_up[a] / m_f[a];
        ++axes;
    }
    for (int j = r0; j <= r1; ++j) {
        const double* row = &m_depth[std::size_t(j) * std::size_t(m_cols)];
        const double v0 = m_v0 + j * m_dv, v1 = v0 + m_dv;
        for (int i = c0; i <= c1; ++i) {
            if (!(row[i] < nearest - slack)) {
                if (!std::isfinite(row[i])) return false;
                const double u0 = m_u0 + i * m_du, u1 = u0 + m_du;
                double bound = nearest;
                for (int k = 0; k < axes; ++k)
                    bound = std::max(bound, A[k] + std::min(B[k] * u0, B[k] * u1) + std::min(C[k] * v0, C[k] * v1));
                if (!(row[i] < bound - slack)) return false;
            }
        }
    }
    return true;
}

bool OrthoOcclusionImage::hiddenBall(const Vec3& centre, double radius, double slack) {
    ++m_stats.tests;
    if (m_cols == 0) return false;
    const double r = radius + slack;
    int c0, c1, r0, r1;
    if (!footprint(centre - r, centre + r, 0.0, c0, c1, r0, r1)) return true;
    const Vec3 q = centre - m_origin;
    const double t = glm::dot(q, m_f), uc = glm::dot(q, m_right), vc = glm::dot(q, m_up);
    for (int j = r0; j <= r1; ++j) {
        const double* row = &m_depth[std::size_t(j) * std::size_t(m_cols)];
        const double v0 = m_v0 + j * m_dv, v1 = v0 + m_dv;
        const double dv = vc < v0 ? v0 - vc : (vc > v1 ? vc - v1 : 0);
        for (int i = c0; i <= c1; ++i) {
            const double u0 = m_u0 + i * m_du, u1 = u0 + m_du;
            const double du = uc < u0 ? u0 - uc : (uc > u1 ? uc - u1 : 0);
            const double d2 = du * du + dv * dv;
            if (d2 > r * r) continue; // the disc misses this pixel
            const double bound = t - std::sqrt(r * r - d2);
            if (!(row[i] < bound - slack)) return false;
        }
    }
    return true;
}

} // namespace rgvc
