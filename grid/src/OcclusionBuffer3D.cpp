#include "rgvc/grid/OcclusionBuffer3D.hpp"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstring>
#include <limits>
#include <type_traits>

namespace rgvc {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// The silhouette of a box seen from a point outside it, as corner indices (bit 0: x at hi, bit 1: y,
/// bit 2: z) in cyclic order, for each of the 27 cases of where the point lies against the box's three
/// slabs (per axis: below lo, above hi, or strictly between; case 3^3 - 1, inside, has none).
/// Why a table: a face of the box faces the point exactly when the point lies beyond its plane, so the
/// faces facing it, and with them the loop of edges between facing and turned-away faces, depend only on
/// the case; the loop's corners are the vertices of the box's image, in the same cyclic order for every
/// image plane in front of them all (a central projection between two such planes is a projective map:
/// it keeps convexity and the order of a convex polygon's vertices, and at most reverses the
/// orientation, which footprintOf checks). This replaces sorting 8 points and building their hull
/// (Andrew's monotone chain) on every occludee test: a third of the buffer pass's instructions on
/// rgvc_bench_classes' clusters.
/// The table is built once from one box per case, by that same hull: a box with the point (the origin)
/// below it on an axis spans [1, 2] there, above it [-2, -1], between [-1, 2]; every corner then lies in
/// front of the plane through the box's centre perpendicular to the centre's direction.
struct Silhouettes {
    std::array<std::array<std::uint8_t, 6>, 27> corners{};
    std::array<std::uint8_t, 27> count{};
    Silhouettes() {
        for (int code = 0; code < 26; ++code) {
            Vec3 lo, hi;
            for (int a = 0, c = code; a < 3; ++a, c /= 3) {
                const int side = c % 3;
                lo[a] = side == 0 ? 1.0 : side == 1 ? -2.0 : -1.0;
                hi[a] = side == 0 ? 2.0 : side == 1 ? -1.0 : 2.0;
            }
            const Vec3 d = glm::normalize(0.5 * (lo + hi));
            const Vec3 u = glm::normalize(glm::cross(d, std::abs(d.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0}));
            const Vec3 v = glm::cross(d, u);
            double px[8], py[8];
            for (int k = 0; k < 8; ++k) {
                const Vec3 q{(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z};
                const double t = glm::dot(q, d); // > 0 for these boxes (see above)
                px[k] = glm::dot(q, u) / t;
                py[k] = glm::dot(q, v) / t;
            }
            int idx[8] = {0, 1, 2, 3, 4, 5, 6, 7};
            std::sort(idx, idx + 8, [&](int a, int b) { return px[a] < px[b] || (px[a] == px[b] && py[a] < py[b]); });
            auto cross = [&](int o, int a, int b) { return (px[a] - px[o]) * (py[b] - py[o]) - (py[a] - py[o]) * (px[b] - px[o]); };
            int hull[17], h = 0;
            for (int k = 0; k < 8; ++k) {
                while (h >= 2 && cross(hull[h - 2], hull[h - 1], idx[k]) <= 1e-12) --h;
                hull[h++] = idx[k];
            }
            for (int k = 6, lower = h + 1; k >= 0; --k) {
                while (h >= lower && cross(hull[h - 2], hull[h - 1], idx[k]) <= 1e-12) --h;
                hull[h++] = idx[k];
            }
            count[std::size_t(code)] = std::uint8_t(h - 1); // 4 (one face facing) or 6 (two or three)
            assert(h - 1 == 4 || h - 1 == 6);
            for (int k = 0; k + 1 < h && k < 6; ++k) corners[std::size_t(code)][std::size_t(k)] = std::uint8_t(hull[k]);
        }
    }
};

const Silhouettes& silhouettes() {
    static const Silhouettes table;
    return table;
}

} // namespace

bool OcclusionBuffer3D::begin(const ViewFrustum& view, int rows) {
    m_stats = {};
    m_active = false;
    const double th = view.tanHalfWidth(), tv = view.tanHalfHeight();
    if (rows < 1 || !(th >= 1e-4 && th <= 1e4 && tv >= 1e-4 && tv <= 1e4)) return false;
    m_rows = std::min(rows, kMaxExtent);
    m_cols = int(std::clamp(std::lround(double(m_rows) * th / tv), 1L, long(kMaxExtent)));
    m_apex = view.apex();
    m_forward = view.forward();
    m_right = view.right();
    m_up = view.trueUp();
    m_halfW = th * (1 + kImageMargin);
    m_halfH = tv * (1 + kImageMargin);
    m_depth.assign(std::size_t(m_rows) * std::size_t(m_cols), kInf);
    startImage();
    return true;
}

bool OcclusionBuffer3D::beginRefined(const OcclusionBuffer3D& coarse, int factor) {
    m_stats = {};
    m_active = false;
    if (!coarse.m_active || factor < 1 || coarse.m_rows > kMaxExtent / factor || coarse.m_cols > kMaxExtent / factor)
        return false;
    m_rows = coarse.m_rows * factor;
    m_cols = coarse.m_cols * factor;
    m_apex = coarse.m_apex;
    m_forward = coarse.m_forward;
    m_right = coarse.m_right;
    m_up = coarse.m_up;
    m_halfW = coarse.m_halfW;
    m_halfH = coarse.m_halfH;
    // Pixel (i, j) of this image is pixel (i / factor, j / factor) of the coarse one cut into factor^2:
    // its cone lies in the coarse pixel's cone, so every one of its rays has entered an occluder by the
    // coarse depth (OcclusionBuffer3D.hpp, "Occluders"), and that depth is a true bound here too. The two
    // lattices are computed separately, so a fine pixel's corner may lie an ulp outside its coarse pixel;
    // an occludee direction there is also within pixelsOf's index margin (1e-6 of a pixel) of the
    // neighbouring fine pixel, which its test then reads too, and which inherits the neighbouring coarse
    // pixel's bound: the sliver is covered by the pixel it belongs to.
    m_depth.resize(std::size_t(m_rows) * std::size_t(m_cols));
    for (int j = 0; j < m_rows; ++j) {
        const double* src = coarse.m_depth.data() + std::size_t(j / factor) * std::size_t(coarse.m_cols);
        double* dst = m_depth.data() + std::size_t(j) * std::size_t(m_cols);
        for (int i = 0; i < m_cols; ++i) dst[i] = src[i / factor];
    }
    startImage();
    return true;
}

void OcclusionBuffer3D::startImage() {
    m_pixelW = 2 * m_halfW / m_cols;
    m_pixelH = 2 * m_halfH / m_rows;
    m_partial.assign(std::size_t(m_rows) * std::size_t(m_cols), 0);
    // A pixel's corner bits are read only after its slot is set, which writes them: sized, not cleared.
    m_partialCorners.resize(std::size_t(m_rows) * std::size_t(m_cols));
    m_seamBoxes.clear();
    if (m_latticeW != m_halfW || m_latticeH != m_halfH || m_cornerX.size() != std::size_t(m_cols + 1) ||
        m_cornerY.size() != std::size_t(m_rows + 1)) {
        m_cornerX.resize(std::size_t(m_cols + 1));
        m_cornerY.resize(std::size_t(m_rows + 1));
        for (int i = 0; i <= m_cols; ++i) m_cornerX[std::size_t(i)] = -m_halfW + i * m_pixelW;
        for (int j = 0; j <= m_rows; ++j) m_cornerY[std::size_t(j)] = -m_halfH + j * m_pixelH;
        m_invLen.resize(std::size_t(m_rows + 1) * std::size_t(m_cols + 1));
        // forward, right and up are orthonormal: |forward + x right + y up|^2 = 1 + x^2 + y^2.
        for (int j = 0; j <= m_rows; ++j)
            for (int i = 0; i <= m_cols; ++i) {
                const double x = m_cornerX[std::size_t(i)], y = m_cornerY[std::size_t(j)];
                m_invLen[std::size_t(j) * std::size_t(m_cols + 1) + std::size_t(i)] = 1.0 / std::sqrt(1.0 + x * x + y * y);
            }
        m_latticeW = m_halfW;
        m_latticeH = m_halfH;
    }
    m_rowA.resize(std::size_t(m_cols + 1));
    m_rowB.resize(std::size_t(m_cols + 1));
    m_corners.resize(std::size_t(m_cols + 1));
    m_active = true;
}

OcclusionBuffer3D::PixelRect OcclusionBuffer3D::pixelsOf(double x0, double x1, double y0, double y1) const {
    // Pixel i covers [-halfW + i w, -halfW + (i + 1) w]; a small index margin keeps a direction on a
    // pixel boundary in both neighbours despite rounding.
    auto index = [](double v, double half, double size, double bias) {
        const double f = (v + half) / size + bias;
        return f < -1.0 ? -1.0 : (f > 1e7 ? 1e7 : double(floorToInt(f)));
    };
    // Bounds computed from overflowing coordinates (inf - inf) are NaN: nothing is known, so the whole
    // image (found by fuzz_culler3d).
    if (std::isnan(x0) || std::isnan(x1) || std::isnan(y0) || std::isnan(y1)) return wholeImage();
    PixelRect r;
    r.i0 = std::max(0, int(index(x0, m_halfW, m_pixelW, -1e-6)));
    r.i1 = std::min(m_cols - 1, int(index(x1, m_halfW, m_pixelW, 1e-6)));
    r.j0 = std::max(0, int(index(y0, m_halfH, m_pixelH, -1e-6)));
    r.j1 = std::min(m_rows - 1, int(index(y1, m_halfH, m_pixelH, 1e-6)));
    if (r.i0 > r.i1 || r.j0 > r.j1) r.i0 = 1, r.i1 = 0;
    return r;
}

OcclusionBuffer3D::PixelRect OcclusionBuffer3D::rectOf(const Vec3& c, double radius) const {
    // In camera coordinates (X, Y, Z) = (c.right, c.up, c.forward) the image coordinate x = X / Z over
    // the sphere takes the values over the disc of centre (cx, cz) and radius rho in the XZ plane; its
    // extremes are the tangents X = m Z from the origin: (cx - m cz)^2 = rho^2 (1 + m^2), so
    // m = (cx cz +- rho sqrt(cx^2 + cz^2 - rho^2)) / (cz^2 - rho^2), when the disc lies in Z > 0.
    const double cx = glm::dot(c, m_right), cy = glm::dot(c, m_up), cz = glm::dot(c, m_forward);
    if (!(cz > radius * 1.001)) return wholeImage();
    const double den = cz * cz - radius * radius;
    auto range = [&](double cw, double& lo, double& hi) {
        const double root = radius * std::sqrt(cw * cw + cz * cz - radius * radius);
        lo = (cw * cz - root) / den;
        hi = (cw * cz + root) / den;
        const double pad = 1e-8 * (std::abs(lo) + std::abs(hi) + 1.0);
        lo -= pad;
        hi += pad;
    };
    double x0, x1, y0, y1;
    range(cx, x0, x1);
    range(cy, y0, y1);
    return pixelsOf(x0, x1, y0, y1);
}

OcclusionBuffer3D::PixelRect OcclusionBuffer3D::rectOf(const Vec3& lo, const Vec3& hi) const {
    // A box entirely in front of the camera: its image is the convex hull of its corners' images.
    double x0 = kInf, x1 = -kInf, y0 = kInf, y1 = -kInf;
    for (int k = 0; k < 8; ++k) {
        const Vec3 q{(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z};
        const double z = glm::dot(q, m_forward);
        if (!(z > 1e-6 * std::sqrt(lengthSquared<3>(q)))) return wholeImage();
        const double x = glm::dot(q, m_right) / z, y = glm::dot(q, m_up) / z;
        x0 = std::min(x0, x);
        x1 = std::max(x1, x);
        y0 = std::min(y0, y);
        y1 = std::max(y1, y);
    }
    const double padX = 1e-8 * (std::abs(x0) + std::abs(x1) + 1.0), padY = 1e-8 * (std::abs(y0) + std::abs(y1) + 1.0);
    return pixelsOf(x0 - padX, x1 + padX, y0 - padY, y1 + padY);
}

bool OcclusionBuffer3D::footprintOf(const Vec3& lo, const Vec3& hi, double zMin, Footprint& f, bool forSeams) const {
    // The box's points in the view at distance >= nearest have z >= zMin (zMinOf), so the image of the box
    // clipped to the half-space z >= zMin holds every pixel that can show one of them. The clipped box is a
    // convex polytope whose vertices are the corners with z >= zMin and the points where the box's edges
    // cross the plane z = zMin; its image is the convex hull of their images (a central projection maps
    // segments in front of the apex to segments).
    double zc[8];
    Vec3 q[8];
    bool anyFront = false;
    for (int k = 0; k < 8; ++k) {
        q[k] = Vec3{(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z};
        zc[k] = glm::dot(q[k], m_forward);
        anyFront = anyFront || zc[k] >= zMin;
    }
    f.n = 0;
    if (!(zMin > 0)) {
        f.rect = wholeImage();
        return true;
    }
    if (!anyFront) return false; // no point of the box in view
    double px[20], py[20];
    int n = 0;
    auto add = [&](const Vec3& p, double z) {
        const double inv = 1.0 / z; // one division (the bounds are padded by 1e-7 relative below)
        px[n] = glm::dot(p, m_right) * inv;
        py[n] = glm::dot(p, m_up) * inv;
        ++n;
    };
    bool allFront = true;
    for (int k = 0; k < 8; ++k) allFront = allFront && zc[k] >= zMin;
    for (int k = 0; k < 8; ++k) {
        if (zc[k] >= zMin) add(q[k], zc[k]);
        if (allFront) continue; // no edge crosses the plane
        for (int a = 0; a < 3; ++a) { // the edge from corner k to the corner differing in bit a
            const int m = k ^ (1 << a);
            if (m < k || (zc[k] >= zMin) == (zc[m] >= zMin)) continue;
            const double t = (zMin - zc[k]) / (zc[m] - zc[k]);
            add(q[k] + (q[m] - q[k]) * t, zMin);
        }
    }
    double x0 = kInf, x1 = -kInf, y0 = kInf, y1 = -kInf;
    for (int k = 0; k < n; ++k) {
        x0 = std::min(x0, px[k]);
        x1 = std::max(x1, px[k]);
        y0 = std::min(y0, py[k]);
        y1 = std::max(y1, py[k]);
    }
    if (!(x0 <= x1) || !(y0 <= y1) || !std::isfinite(x0 + x1 + y0 + y1)) {
        f.rect = wholeImage();
        return true;
    }
    f.padX = 1e-7 * (std::abs(x0) + std::abs(x1) + 1.0);
    f.padY = 1e-7 * (std::abs(y0) + std::abs(y1) + 1.0);
    f.rect = pixelsOf(x0 - f.padX, x1 + f.padX, y0 - f.padY, y1 + f.padY);
    // A rectangle of 2 x 2 pixels or less gains nothing from the polygon.
    if (f.rect.i1 - f.rect.i0 < 2 && f.rect.j1 - f.rect.j0 < 2 && !forSeams) return true;
    // A box wholly in front of the plane, seen from outside every slab's boundary plane: its image's
    // vertices from the table (Silhouettes, above), oriented counter-clockwise.
    if (allFront) {
        int code = 0, weight = 1;
        bool general = true; // the apex strictly inside or outside each slab
        for (int a = 0; a < 3; ++a, weight *= 3) {
            general = general && lo[a] != 0 && hi[a] != 0;
            code += weight * (lo[a] > 0 ? 0 : hi[a] < 0 ? 1 : 2);
        }
        const Silhouettes& table = silhouettes();
        const int m = general ? table.count[std::size_t(code)] : 0;
        if (m >= 4) {
            const auto& c = table.corners[std::size_t(code)];
            double area = 0;
            for (int k = 0; k < m; ++k) {
                const int a = c[std::size_t(k)], b = c[std::size_t(k + 1 == m ? 0 : k + 1)];
                area += px[a] * py[b] - px[b] * py[a];
            }
            if (area != 0 && std::isfinite(area)) {
                f.n = m;
                for (int k = 0; k < m; ++k) {
                    const int v = c[std::size_t(area > 0 ? k : m - 1 - k)];
                    f.x[k] = px[v];
                    f.y[k] = py[v];
                }
#ifndef NDEBUG
                // Every corner's image inside the polygon, up to rounding (the padding covers that).
                for (int k = 0; k < 8; ++k)
                    for (int e = 0; e < m; ++e) {
                        const int g = e + 1 == m ? 0 : e + 1;
                        const double ex = f.x[g] - f.x[e], ey = f.y[g] - f.y[e];
                        const double side = ex * (py[k] - f.y[e]) - ey * (px[k] - f.x[e]);
                        assert(side >= -1e-9 * (std::abs(ex) + std::abs(ey)) * (1 + std::abs(px[k]) + std::abs(py[k])));
                    }
#endif
                return true;
            }
        }
    }
    // The hull (Andrew's monotone chain; at most 20 points, so sorting by hand is not worth a dependency).
    int idx[20];
    for (int k = 0; k < n; ++k) idx[k] = k;
    std::sort(idx, idx + n, [&](int a, int b) { return px[a] < px[b] || (px[a] == px[b] && py[a] < py[b]); });
    auto cross = [&](int o, int a, int b) { return (px[a] - px[o]) * (py[b] - py[o]) - (py[a] - py[o]) * (px[b] - px[o]); };
    int hull[40], h = 0;
    for (int k = 0; k < n; ++k) {
        while (h >= 2 && cross(hull[h - 2], hull[h - 1], idx[k]) <= 0) --h;
        hull[h++] = idx[k];
    }
    for (int k = n - 2, lower = h + 1; k >= 0; --k) {
        while (h >= lower && cross(hull[h - 2], hull[h - 1], idx[k]) <= 0) --h;
        hull[h++] = idx[k];
    }
    f.n = std::max(h - 1, 1); // the last point repeats the first
    for (int k = 0; k < f.n; ++k) {
        f.x[k] = px[hull[k]];
        f.y[k] = py[hull[k]];
    }
    return true;
}

bool OcclusionBuffer3D::rowSpan(const Footprint& f, int j, int& i0, int& i1) const {
    i0 = f.rect.i0;
    i1 = f.rect.i1;
    if (f.n == 0) return true;
    // The hull's x range over the pixel row's band of y (grown by the padding): every edge clipped to
    // the band contributes its clipped end points (a convex polygon meets a band in a convex set whose
    // x extremes lie on its boundary, i.e. on the clipped edges).
    const double ya = -m_halfH + j * m_pixelH - f.padY, yb = ya + m_pixelH + 2 * f.padY;
    double x0 = kInf, x1 = -kInf;
    for (int k = 0; k < f.n; ++k) {
        const int m = k + 1 == f.n ? 0 : k + 1;
        double ax = f.x[k], ay = f.y[k], bx = f.x[m], by = f.y[m];
        if (ay > by) {
            std::swap(ax, bx);
            std::swap(ay, by);
        }
        if (by < ya || ay > yb) continue;
        double t0 = 0, t1 = 1;
        if (by > ay) {
            t0 = std::max(0.0, (ya - ay) / (by - ay));
            t1 = std::min(1.0, (yb - ay) / (by - ay));
        }
        const double xa = ax + (bx - ax) * t0, xb = ax + (bx - ax) * t1;
        x0 = std::min({x0, xa, xb});
        x1 = std::max({x1, xa, xb});
    }
    if (!(x0 <= x1)) return false;
    // Columns as pixelsOf computes them (the same index margin), clamped to the rectangle before the
    // conversion to int: a huge occludee's coordinates overflow an int (found by test_stress3d's huge
    // spheres: an overflowing column emptied the row, and the sphere was reported hidden).
    const double f0 = (x0 - f.padX + m_halfW) / m_pixelW - 1e-6, f1 = (x1 + f.padX + m_halfW) / m_pixelW + 1e-6;
    if (!(f0 < double(i1) + 1) || !(f1 >= double(i0))) return false;
    i0 = std::max(i0, floorToInt(std::max(f0, double(i0)))); // in [i0, i1]: f0 < i1 + 1 above
    i1 = std::min(i1, floorToInt(std::min(f1, double(i1)))); // in [i0, i1]: f1 >= i0 above
    return i0 <= i1;
}

double OcclusionBuffer3D::nearestDistance(const Shape<3>& shape, double grow) const {
    if (const auto* b = std::get_if<Ball<3>>(&shape))
        return std::max(0.0, std::sqrt(lengthSquared<3>(b->center - m_apex)) - (b->radius + grow));
    // Boxes, and polytopes by their bounding box (which contains them: a nearer bound is conservative).
    const Box<3> box = boundsOf<3>(shape);
    const Vec3 nearest = glm::clamp(m_apex, box.min - grow, box.max + grow);
    return std::sqrt(lengthSquared<3>(nearest - m_apex));
}

bool OcclusionBuffer3D::hidden(const Shape<3>& shape, double grow, double distance, bool refine) {
    if (!m_active) return false;
    ++m_stats.tested;
    Vec3 lo, hi; // the shape's bounding box grown, relative to the apex
    const double nearest = distance * (1 - kRelMargin);
    if (!(nearest > 0)) return false;
    // The centre (of the ball, or of the box) is a point of the shape: when its own pixel is not covered
    // nearer than it, neither test below can succeed (both need that pixel below `nearest`, which is at
    // most the centre's distance). O(1) for the visible objects, which are most of what is tested.
    // The same for the shape's point nearest to the camera, where a shape in view is most often seen
    // (a ball's, or its bounding box's: the tests below are for that box).
    {
        const Box<3> b = boundsOf<3>(shape);
        if (!canHide(0.5 * (b.min + b.max) - m_apex)) return false;
        if (const auto* ball = std::get_if<Ball<3>>(&shape)) {
            const Vec3 c = ball->center - m_apex;
            const double r = (ball->radius + grow) * (1 - 1e-6), len = std::sqrt(lengthSquared<3>(c));
            if (len > r && !canHide(c * (1 - r / len))) return false;
        } else if (!canHide(glm::clamp(Vec3(0.0), b.min - grow - m_apex, b.max + grow - m_apex))) {
            return false;
        }
    }
    Footprint f;
    bool inView;
    if (const auto* b = std::get_if<Ball<3>>(&shape)) {
        const Vec3 c = b->center - m_apex;
        const double rad = b->radius + grow;
        lo = c - rad;
        hi = c + rad;
        // In front of the camera: its exact tangent rectangle (the refinement below handles what a
        // rectangle adds to the disc-like image). Otherwise its bounding box's clipped footprint.
        if (glm::dot(c, m_forward) > rad * 1.001) {
            f.n = 0;
            f.rect = rectOf(c, rad);
            inView = true;
        } else {
            inView = footprintOf(lo, hi, zMinOf(nearest), f);
        }
    } else {
        // A box, or a polytope's bounding box: its footprint holds the polytope's (the test is then for
        // the box, which contains the polytope: conservative).
        const Box<3> box = boundsOf<3>(shape);
        lo = box.min - grow - m_apex;
        hi = box.max + grow - m_apex;
        inView = footprintOf(lo, hi, zMinOf(nearest), f);
    }
    if (!inView || scanFootprint(f, nearest)) {
        ++m_stats.hidden;
        return true;
    }
    if (!refine) return false;
    // Refinement: the test compares every pixel with the shape's single nearest distance, and a
    // rectangle is larger than the image of a sphere or of a box seen at an angle, so an object just
    // behind a wall fails on pixels at the edge of its rectangle (where the wall is crossed farther out
    // than the object's nearest point is, or which show no part of it at all). The bounding box is then
    // split into 8 and each part tested with its own rectangle and nearest distance, two levels deep.
    // Sound: the parts cover the shape, and each part's test is the same conservative test. Cheap where
    // it cannot succeed: a point of the box in view whose pixel is not covered nearer than that point
    // belongs to some part at every level, and that part's test would fail on that pixel; the box's
    // centre was checked first (above).
    const Vec3 centre = 0.5 * (lo + hi);
    const auto* ball = std::get_if<Ball<3>>(&shape);
    // More such witnesses before the parts: the region's extreme points along the axes (a ball's six
    // poles, a box's eight corners), each inside the region the parts cover (a ball's, shrunk by 1e-6 relative, since
    // the parts skip what misses the ball). One pixel read each, against the refinement's up to 72
    // footprints; on rgvc_bench_classes' clusters 98% of the refinements failed, most on such a point.
    if (ball != nullptr) {
        const double r = (ball->radius + grow) * (1 - 1e-6);
        for (int a = 0; a < 3; ++a) {
            Vec3 d(0.0);
            d[a] = r;
            if (!canHide(centre + d) || !canHide(centre - d)) return false;
        }
    } else {
        for (int k = 0; k < 8; ++k)
            if (!canHide(Vec3{(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z})) return false;
    }
    if (!hiddenParts(lo, hi, 2, ball != nullptr ? &centre : nullptr, ball != nullptr ? ball->radius + grow : 0.0)) return false;
    ++m_stats.hidden;
    return true;
}

bool OcclusionBuffer3D::canHide(const Vec3& p) const {
    const double z = glm::dot(p, m_forward);
    if (!(z > 0)) return true;
    const double x = glm::dot(p, m_right) / z, y = glm::dot(p, m_up) / z;
    if (!(std::abs(x) < m_halfW) || !(std::abs(y) < m_halfH)) return true; // not in the image: no verdict
    const int i = std::min(m_cols - 1, int((x + m_halfW) / m_pixelW));
    const int j = std::min(m_rows - 1, int((y + m_halfH) / m_pixelH));
    return m_depth[std::size_t(j) * std::size_t(m_cols) + std::size_t(i)] < std::sqrt(lengthSquared<3>(p)) * (1 - kRelMargin);
}

ImageFootprint3D::Rect OcclusionBuffer3D::pixelRect(const Shape<3>& shape, double grow) const {
    if (!m_active) return {0, -1, 0, -1};
    if (const auto* b = std::get_if<Ball<3>>(&shape)) return rectOf(b->center - m_apex, b->radius + grow);
    const Box<3> box = boundsOf<3>(shape);
    return rectOf(box.min - grow - m_apex, box.max + grow - m_apex);
}

bool OcclusionBuffer3D::coveredNearer(const Vec3& point, double limit) const {
    if (!m_active) return false;
    const Vec3 p = point - m_apex;
    const double z = glm::dot(p, m_forward);
    if (!(z > 0)) return true; // no pixel: unknown
    const double x = glm::dot(p, m_right) / z, y = glm::dot(p, m_up) / z;
    if (!std::isfinite(x) || !std::isfinite(y)) return true;
    // Outside the image: the border pixel nearest to it (a shape poking into the view from beside it).
    const int i = int(std::clamp((x + m_halfW) / m_pixelW, 0.0, double(m_cols - 1)));
    const int j = int(std::clamp((y + m_halfH) / m_pixelH, 0.0, double(m_rows - 1)));
    return m_depth[std::size_t(j) * std::size_t(m_cols) + std::size_t(i)] < limit;
}

double OcclusionBuffer3D::zMinOf(double nearest) const {
    // A point of the view at distance r from the apex has z >= r / sqrt(1 + halfW^2 + halfH^2) (its image
    // coordinates are within the half extents), so a shape's points in view, all at distance >= nearest,
    // have z >= zMin: a shape reaching behind the camera is clipped there instead of taking the whole image
    // (an occludee behind the camera would otherwise need every pixel below its nearest distance).
    return nearest * (1 - kRelMargin) / std::sqrt(1 + m_halfW * m_halfW + m_halfH * m_halfH);
}

bool OcclusionBuffer3D::scanFootprint(const Footprint& f, double nearest) const {
    // An image that misses the view's rectangle: every point of the shape in view would project inside
    // the (padded) footprint, so no point of it is in view, and nothing of it can be seen.
    const PixelRect& r = f.rect;
    if (r.i0 > r.i1) return true;
    for (int j = r.j0; j <= r.j1; ++j) {
        int i0, i1;
        if (!rowSpan(f, j, i0, i1)) continue;
        const double* row = m_depth.data() + std::size_t(j) * std::size_t(m_cols);
        for (int i = i0; i <= i1; ++i)
            if (!(row[i] < nearest)) return false;
    }
    return true;
}

bool OcclusionBuffer3D::hiddenParts(const Vec3& lo, const Vec3& hi, int levels, const Vec3* centre, double radius) const {
    const Vec3 mid = 0.5 * (lo + hi);
    for (int k = 0; k < 8; ++k) {
        Vec3 l, h;
        for (int a = 0; a < 3; ++a) {
            const bool upper = ((k >> a) & 1) != 0;
            l[a] = upper ? mid[a] : lo[a];
            h[a] = upper ? hi[a] : mid[a];
        }
        // A part of a sphere's bounding cube that misses the (grown) sphere holds none of its points.
        if (centre != nullptr && lengthSquared<3>(glm::clamp(*centre, l, h) - *centre) > radius * radius * (1 + 1e-9))
            continue;
        const double nearest = std::sqrt(lengthSquared<3>(glm::clamp(Vec3(0.0), l, h))) * (1 - kRelMargin);
        if (!(nearest > 0)) return false;
        Footprint f;
        if (!footprintOf(l, h, zMinOf(nearest), f) || scanFootprint(f, nearest)) continue;
        if (levels <= 1 || !canHide(0.5 * (l + h)) || !hiddenParts(l, h, levels - 1, centre, radius)) return false;
    }
    return true;
}

template <class FillRow, class OnPartial>
void OcclusionBuffer3D::drawRect(const PixelRect& r, FillRow&& fillRow, OnPartial&& onPartial, bool partials) {
    if (r.i0 > r.i1) return;
    // Two lattice rows at a time; the pixel loop uses selects, not jumps.
    fillRow(r.j0, r.i0, r.i1 + 1, m_rowA.data());
    std::uint64_t covered = 0;
    for (int j = r.j0; j <= r.j1; ++j) {
        fillRow(j + 1, r.i0, r.i1 + 1, m_rowB.data());
        double* row = m_depth.data() + std::size_t(j) * std::size_t(m_cols);
        const double* a = m_rowA.data();
        const double* b = m_rowB.data();
        for (int i = r.i0; i <= r.i1; ++i) { // branch-free: vectorized
            const double e = std::max(std::max(a[i], a[i + 1]), std::max(b[i], b[i + 1]));
            const double lo = std::min(std::min(a[i], a[i + 1]), std::min(b[i], b[i + 1]));
            const bool in = lo >= 0; // every corner ray passes through the interior
            covered += in;
            const double m = std::min(row[i], e);
            row[i] = in ? m : row[i];
        }
        if constexpr (!std::is_same_v<std::decay_t<OnPartial>, std::nullptr_t>)
            if (partials) {
                // Which corner rays pass through the interior: bit 0, 1 on row j, 2, 3 on j + 1. Computed
                // branch-free into bytes (vectorized), then only the pixels with some but not all of them
                // (the footprint's rim) are handed on, eight bytes at a time.
                std::uint8_t* c = m_corners.data();
                for (int i = r.i0; i <= r.i1; ++i)
                    c[i] = std::uint8_t(std::uint8_t(a[i] >= 0) | std::uint8_t(a[i + 1] >= 0) << 1 |
                                        std::uint8_t(b[i] >= 0) << 2 | std::uint8_t(b[i + 1] >= 0) << 3);
                for (int i = r.i0; i <= r.i1; ++i) {
                    if (i + 8 <= r.i1 + 1) {
                        std::uint64_t w;
                        std::memcpy(&w, c + i, 8);
                        // All eight 0 or all eight 15: nothing partial among them.
                        if (w == 0 || w == 0x0F0F0F0F0F0F0F0FULL) {
                            i += 7;
                            continue;
                        }
                    }
                    if (c[i] != 0 && c[i] != 15) onPartial(i, j, unsigned(c[i]));
                }
            }
        std::swap(m_rowA, m_rowB);
    }
    m_stats.pixelsCovered += covered;
}

void OcclusionBuffer3D::draw(const Shape<3>& shape, double shrink) {
    if (!m_active) return;
    if (const auto* b = std::get_if<Ball<3>>(&shape)) {
        const double rho = b->radius - shrink;
        const Vec3 c = b->center - m_apex;
        const double l2 = lengthSquared<3>(c);
        // Inside or nearly touching the camera: skipped (the cone would be nearly a half-space).
        if (!(rho > 0) || !(l2 > rho * rho * (1 + 1e-6))) return;
        const double len = std::sqrt(l2);
        // A corner ray d passes through the interior when its angle to c is below asin(rho / |c|):
        // c.d > sqrt(|c|^2 - rho^2), with a margin; it then enters at c.d - sqrt(rho^2 - |c|^2 + (c.d)^2).
        const double cosLimit = std::sqrt(l2 - rho * rho) + kRelMargin * len;
        ++m_stats.occludersDrawn;
        // In camera coordinates c.d = (cz + x cx + y cy) / |forward + x right + y up| for the corner ray d.
        const double cx = glm::dot(c, m_right), cy = glm::dot(c, m_up), cz = glm::dot(c, m_forward);
        const double rho2l2 = rho * rho - l2, scale = 1 + kRelMargin, pad = kRelMargin * len;
        const double* xs = m_cornerX.data();
        drawRect(rectOf(c, rho), [&](int j, int i0, int i1, double* out) {
            const double yTerm = cz + m_cornerY[std::size_t(j)] * cy;
            const double* inv = m_invLen.data() + std::size_t(j) * std::size_t(m_cols + 1);
            for (int i = i0; i <= i1; ++i) {
                const double cd = (yTerm + xs[i] * cx) * inv[i];
                const double t = cd - std::sqrt(std::max(0.0, rho2l2 + cd * cd));
                out[i] = cd > cosLimit ? t * scale + pad : -1.0;
            }
        }, nullptr);
        return;
    }
    if (const auto* p = std::get_if<ConvexPolytope>(&shape)) {
        drawPolytope(*p, shrink);
        return;
    }
    // A mesh's occluder model is its solid voxelization (MeshSolid.hpp), which the grid's O already
    // holds: the traversal hides what is behind it. The image draws nothing for it (neither the hull,
    // which may exceed the solid, nor the voxels): less occlusion in the image, never a wrong one.
    if (std::holds_alternative<MeshSolid>(shape)) return;
    const Box<3>& box = std::get<Box<3>>(shape);
    const Vec3 lo = box.min + shrink - m_apex, hi = box.max - shrink - m_apex;
    for (int a = 0; a < 3; ++a)
        if (!(lo[a] < hi[a])) return;
    const double scale = std::max({std::abs(lo.x), std::abs(lo.y), std::abs(lo.z), std::abs(hi.x), std::abs(hi.y), std::abs(hi.z)});
    bool inside = true; // the camera in the (closed, slightly grown) box: skipped
    for (int a = 0; a < 3; ++a) inside = inside && lo[a] <= kRelMargin * scale && hi[a] >= -kRelMargin * scale;
    if (inside) return;
    ++m_stats.occludersDrawn;
    auto entry = [&](int i, int j) {
        const Vec3 d = (m_forward + m_cornerX[std::size_t(i)] * m_right + m_cornerY[std::size_t(j)] * m_up) * invLength(i, j);
        // Slab test along the unit ray t d; the ray passes through the interior when the open slab
        // intervals overlap with room to spare.
        double tEnter = -kInf, tExit = kInf;
        for (int a = 0; a < 3; ++a) {
            if (d[a] == 0) {
                if (!(lo[a] < 0 && hi[a] > 0)) return -1.0;
                continue;
            }
            double t1 = lo[a] / d[a], t2 = hi[a] / d[a];
            if (t1 > t2) std::swap(t1, t2);
            tEnter = std::max(tEnter, t1);
            tExit = std::min(tExit, t2);
        }
        if (!(tEnter > 0) || !(tExit - tEnter > kRelMargin * tExit + 1e-300)) return -1.0;
        return tEnter * (1 + kRelMargin) + kRelMargin * scale;
    };
    // The pixels this box covers only in part may be covered by its union with another box drawn this
    // frame (a wall meeting another at a corner, seen at an angle): OcclusionSeams3D.cpp.
    const PixelRect rect = rectOf(lo, hi);
    const std::uint32_t seam = addSeamBox(lo, hi);
    auto onPartial = [&](int i, int j, unsigned corners) { notePartial(i, j, seam, corners); };
    bool onPlane = false; // the camera on a face plane: 0 / 0 in the slab test below
    for (int a = 0; a < 3; ++a) onPlane = onPlane || lo[a] == 0 || hi[a] == 0;
    if (onPlane) {
        drawRect(rect, [&](int j, int i0, int i1, double* out) {
            for (int i = i0; i <= i1; ++i) out[i] = entry(i, j);
        }, onPartial, seam != 0);
        return;
    }
    // The same slab test as `entry`, branch-free so that the compiler vectorizes the row (the box draw
    // was the largest cost of the brick traversal: 44% of its instructions on the game world of
    // rgvc_bench_classes). Along the unnormalized corner ray D = forward + x right + y up, a point is
    // s D, and the distance is t = s |D| = s / invLength; the conditions scale by |D| > 0, so they read
    // the same in s, with the 1e-300 kept un-divided (stricter, |D| >= 1). No face plane holds the camera,
    // so every lo / D and hi / D is a number or an infinity of the right sign, never 0 / 0.
    const double m = kRelMargin, pad = kRelMargin * scale;
    const double* xs = m_cornerX.data();
    drawRect(rect, [&](int j, int i0, int i1, double* out) {
        const double y = m_cornerY[std::size_t(j)];
        const Vec3 b = m_forward + y * m_up, r = m_right;
        const double* inv = m_invLen.data() + std::size_t(j) * std::size_t(m_cols + 1);
        for (int i = i0; i <= i1; ++i) {
            const double x = xs[i];
            const double dx = b.x + x * r.x, dy = b.y + x * r.y, dz = b.z + x * r.z;
            const double x1 = lo.x / dx, x2 = hi.x / dx, y1 = lo.y / dy, y2 = hi.y / dy, z1 = lo.z / dz, z2 = hi.z / dz;
            const double e = std::max(std::max(std::min(x1, x2), std::min(y1, y2)), std::min(z1, z2));
            const double f = std::min(std::min(std::max(x1, x2), std::max(y1, y2)), std::max(z1, z2));
            const bool ok = (e > 0) & (f - e > m * f + 1e-300);
            const double t = (e / inv[i]) * (1 + m) + pad;
            out[i] = ok ? t : -1.0;
        }
    }, onPartial, seam != 0);
}

void OcclusionBuffer3D::drawPolytope(const ConvexPolytope& p, double shrink) {
    // The box's slab test generalised to any number of planes: along the corner ray s D (D = forward +
    // x right + y up, unnormalized), plane n.q <= c' (apex-relative, moved in by the shrink and by the
    // polytope's tolerance, so that only the true shape's interior counts) bounds s from below where
    // n.D < 0 (the ray enters there) and from above where n.D > 0. The ray passes through the interior
    // when the largest entry is positive and the smallest exit beyond it, with the relative margin; the
    // entry distance is s |D|. Sound for the same reasons as the box (OcclusionBuffer3D.hpp): the
    // polytope is convex, and its entry distance is a maximum over its near planes of quasi-convex
    // functions on the image plane, so the pixel's largest entry is at a corner ray. No seam fusion
    // (a polytope that only covers part of a pixel covers nothing there): conservative.
    const std::size_t np = p.planes.size();
    m_planeN.resize(np);
    m_planeC.resize(np);
    double scale = 0;
    for (std::size_t k = 0; k < np; ++k) {
        const HalfSpace& h = p.planes[k];
        m_planeN[k] = h.normal;
        m_planeC[k] = h.offset - shrink - p.tolerance - glm::dot(h.normal, m_apex);
        scale = std::max(scale, std::abs(m_planeC[k]));
    }
    // The camera inside the (shrunk) polytope, or on its boundary: skipped, like a box holding it.
    bool inside = true;
    for (std::size_t k = 0; k < np; ++k) inside = inside && m_planeC[k] >= -kRelMargin * scale;
    if (inside) return;
    const Vec3 lo = p.boundsMin - m_apex, hi = p.boundsMax - m_apex;
    ++m_stats.occludersDrawn;
    const double m = kRelMargin, pad = kRelMargin * scale;
    const Vec3* normals = m_planeN.data();
    const double* offsets = m_planeC.data();
    drawRect(rectOf(lo, hi), [&](int j, int i0, int i1, double* out) {
        const double y = m_cornerY[std::size_t(j)];
        const Vec3 b = m_forward + y * m_up;
        const double* inv = m_invLen.data() + std::size_t(j) * std::size_t(m_cols + 1);
        for (int i = i0; i <= i1; ++i) {
            const Vec3 d = b + m_cornerX[std::size_t(i)] * m_right;
            double e = -kInf, f = kInf;
            bool ok = true;
            for (std::size_t k = 0; k < np; ++k) {
                const double den = glm::dot(normals[k], d), c = offsets[k];
                if (den > 0) f = std::min(f, c / den);
                else if (den < 0) e = std::max(e, c / den);
                else ok = ok && c > 0;
            }
            ok = ok && e > 0 && f - e > m * f + 1e-300;
            out[i] = ok ? (e / inv[i]) * (1 + m) + pad : -1.0;
        }
    }, nullptr);
}

} // namespace rgvc
