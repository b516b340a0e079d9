// OcclusionBuffer3D's occludee tests (OcclusionBuffer3D.hpp, "Occludees"): the footprint of a box
// (silhouette table, clipped hull), the per-row spans, the witnesses, the shadow proof and the refinement
// of a box into parts. The exact per-pixel tests of a sphere and a box: OcclusionExact3D.cpp. Drawing and
// the image itself: OcclusionBuffer3D.cpp; seam fusion: OcclusionSeams3D.cpp.
#include "OcclusionRowSpans3D.hpp"
#include "rgvc/grid/OcclusionBuffer3D.hpp"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
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

// The witness test (OcclusionBuffer3D.hpp), inlined into the tests below: called about three times per
// object tested, it was the most frequent call of the buffer's pass.
[[gnu::always_inline]] inline bool OcclusionBuffer3D::canHide(const Vec3& p, std::size_t& pixel) const {
    const double z = glm::dot(p, m_forward);
    if (!(z > 0)) return true;
    // A filter, never a proof (false only says the object cannot be hidden; true is checked further), so
    // any pixel whose cone holds p will do: products by inverses, not quotients, where a rounding can only
    // pick a neighbour that p's direction borders within an ulp.
    const double invZ = 1 / z;
    return canHideAt(glm::dot(p, m_right) * invZ, glm::dot(p, m_up) * invZ, lengthSquared<3>(p), pixel);
}

[[gnu::always_inline]] inline bool OcclusionBuffer3D::canHideAt(double x, double y, double d2, std::size_t& pixel) const {
    if (!(std::abs(x) < m_halfW) || !(std::abs(y) < m_halfH)) return true; // not in the image: no verdict
    const int i = std::min(m_cols - 1, int((x + m_halfW) * m_invPixelW));
    const int j = std::min(m_rows - 1, int((y + m_halfH) * m_invPixelH));
    pixel = std::size_t(j) * std::size_t(m_cols) + std::size_t(i);
    // depth < |p| (1 - margin), squared (depths are positive or +inf): no square root.
    const double depth = m_depth[pixel];
    return depth * depth < d2 * ((1 - kRelMargin) * (1 - kRelMargin));
}

[[gnu::always_inline]] inline bool OcclusionBuffer3D::canHide(const Vec3& p) const {
    std::size_t pixel;
    return canHide(p, pixel);
}

/// The bounds of the n image points (px, py); false when they are empty or not finite (the caller
/// takes the whole image).
[[gnu::always_inline]] static inline bool vertexBounds(const double* px, const double* py, int n, double& x0, double& x1, double& y0, double& y1) {
    x0 = kInf, x1 = -kInf, y0 = kInf, y1 = -kInf;
    for (int k = 0; k < n; ++k) {
        x0 = std::min(x0, px[k]);
        x1 = std::max(x1, px[k]);
        y0 = std::min(y0, py[k]);
        y1 = std::max(y1, py[k]);
    }
    return x0 <= x1 && y0 <= y1 && std::isfinite(x0 + x1 + y0 + y1);
}

int OcclusionBuffer3D::clippedVertices(const double (&xc)[8], const double (&yc)[8], const double (&zc)[8], double zMin,
                                       double* px, double* py) {
    int n = 0;
    auto add = [&](double x, double y, double z) {
        const double inv = 1.0 / z; // one division (callers pad the bounds by 1e-7 relative)
        px[n] = x * inv;
        py[n] = y * inv;
        ++n;
    };
    for (int k = 0; k < 8; ++k) {
        if (zc[k] >= zMin) add(xc[k], yc[k], zc[k]);
        for (int a = 0; a < 3; ++a) { // the edge from corner k to the corner differing in bit a
            const int m = k ^ (1 << a);
            if (m < k || (zc[k] >= zMin) == (zc[m] >= zMin)) continue;
            // Camera coordinates are linear in the point, so the crossing's are the same blend of the
            // corners' (its z is zMin by construction).
            const double t = (zMin - zc[k]) / (zc[m] - zc[k]);
            add(xc[k] + (xc[m] - xc[k]) * t, yc[k] + (yc[m] - yc[k]) * t, zMin);
        }
    }
    return n;
}

OcclusionBuffer3D::PixelRect OcclusionBuffer3D::clippedRect(const Vec3& lo, const Vec3& hi, const double (&xc)[8],
                                                           const double (&yc)[8], const double (&zc)[8]) const {
    // Why this rectangle holds every pixel a draw can write. A draw writes a pixel (or hands it to the
    // seams) only where some corner ray of it passes through the box's interior, at a point q of the
    // box; the ray is a direction of the view (the lattice's corners lie in the closed image), so
    // z_q >= |q| / sqrt(1 + halfW^2 + halfH^2) >= nearest / sqrt(...) >= zMinOf(nearest): q lies in the
    // box clipped to z >= zMin, a convex polytope whose image is the hull of its vertices' images
    // (footprintOf's construction, which the occludee tests rely on the same way). A wall, floor or
    // building beside the camera, reaching behind it, took the whole image and filled every pixel's
    // corners (the closed rooms' three walls a frame, the street's buildings and ground): now only its
    // side of the image.
    const double nearest = std::sqrt(lengthSquared<3>(glm::clamp(Vec3(0.0), lo, hi)));
    if (!(nearest > 0)) return wholeImage(); // the camera in the closed box (or NaN)
    double px[20], py[20];
    const int n = clippedVertices(xc, yc, zc, zMinOf(nearest), px, py);
    if (n == 0) return {1, 0, 1, 0}; // no point of the box in view
    double x0, x1, y0, y1;
    if (!vertexBounds(px, py, n, x0, x1, y0, y1)) return wholeImage();
    const double padX = 1e-7 * (std::abs(x0) + std::abs(x1) + 1.0), padY = 1e-7 * (std::abs(y0) + std::abs(y1) + 1.0);
    return pixelsOf(x0 - padX, x1 + padX, y0 - padY, y1 + padY);
}

bool OcclusionBuffer3D::footprintOf(const Vec3& lo, const Vec3& hi, double zMin, Footprint& f, bool forSeams,
                                     double coveredBelow, bool cornerWitnesses) const {
    // The box's points in the view at distance >= nearest have z >= zMin (zMinOf), so the image of the box
    // clipped to the half-space z >= zMin holds every pixel that can show one of them. The clipped box is a
    // convex polytope whose vertices are the corners with z >= zMin and the points where the box's edges
    // cross the plane z = zMin; its image is the convex hull of their images (a central projection maps
    // segments in front of the apex to segments).
    double xc[8], yc[8], zc[8];
    boxCorners(lo, hi, xc, yc, zc); // (the projections were a fifth of this function's instructions)
    int front = 0; // bit k: corner k in front of the plane z = zMin
#pragma GCC unroll 8
    for (int k = 0; k < 8; ++k) front |= int(zc[k] >= zMin) << k;
    const bool anyFront = front != 0, allFront = front == 0xFF;
    f.n = 0;
    f.covered = f.cornersRead = f.cornerSeen = false;
    if (!(zMin > 0)) {
        f.rect = wholeImage();
        return true;
    }
    if (!anyFront) return false; // no point of the box in view
    // An occludee's corners are witnesses (hidden(), whose refinement reads them otherwise): a corner in
    // view whose pixel is not covered nearer than it fails every test of the box, the rectangle's, the
    // polygon's and the exact one (its pixel is in the footprint, and each test needs that pixel nearer
    // than the box's nearest point, or than the entry along the corner's ray, both at most the corner's
    // distance). One pixel each, before the footprint's pixels: a box seen at a corner (a brick, a voxel
    // box at the edge of a wall, a TBV's voxels in view) stops there. A box wholly in front of z = zMin
    // reads them from its projections below, once its rectangle is known to span more than 2 x 2 pixels
    // and not to be covered (a hidden box, or a smaller one, is decided at less cost by the rectangle's
    // scan; the refinement reads them then).
    const bool witnesses = cornerWitnesses && coveredBelow > 0;
    auto seen = [&](int k, double x, double y) { // corner k, projected to (x, y)
        std::size_t pixel;
        const Vec3 q{(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z};
        return !canHideAt(x, y, lengthSquared<3>(q), pixel);
    };
    if (witnesses && !allFront) {
        f.cornersRead = true;
        for (int k = 0; k < 8; ++k) {
            if (!(zc[k] > 0)) continue; // behind the camera: no pixel, no verdict
            const double inv = 1.0 / zc[k];
            if (seen(k, xc[k] * inv, yc[k] * inv)) {
                f.cornerSeen = true;
                return true;
            }
        }
    }
    double px[20], py[20];
    int n = 0;
    if (allFront) { // (most tests: straight-line code over the eight corners, no edge crosses the plane)
#pragma GCC unroll 8
        for (int k = 0; k < 8; ++k) {
            const double inv = 1.0 / zc[k];
            px[k] = xc[k] * inv;
            py[k] = yc[k] * inv;
        }
        n = 8;
    } else {
        n = clippedVertices(xc, yc, zc, zMin, px, py);
    }
    double x0, x1, y0, y1;
    if (!vertexBounds(px, py, n, x0, x1, y0, y1)) {
        f.rect = wholeImage();
        return true;
    }
    f.padX = 1e-7 * (std::abs(x0) + std::abs(x1) + 1.0);
    f.padY = 1e-7 * (std::abs(y0) + std::abs(y1) + 1.0);
    f.rect = pixelsOf(x0 - f.padX, x1 + f.padX, y0 - f.padY, y1 + f.padY);
    // A rectangle of 2 x 2 pixels or less gains nothing from the polygon.
    if (f.rect.i1 - f.rect.i0 < 2 && f.rect.j1 - f.rect.j0 < 2 && !forSeams) return true;
    // The rectangle holds the polygon: when every pixel of it is covered nearer than the occludee, so is
    // every pixel of the polygon, and the polygon and its per-row spans (which cost more than the pixels)
    // are not needed. Behind a wall that is the whole test (the closed rooms' TBV voxels and bricks).
    if (coveredBelow > 0 && scanFootprint(f, coveredBelow)) {
        f.covered = true;
        return true;
    }
    if (witnesses && allFront) {
        f.cornersRead = true;
        for (int k = 0; k < 8; ++k)
            if (seen(k, px[k], py[k])) {
                f.cornerSeen = true;
                return true;
            }
    }
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
                // Every corner's image within the padding of the polygon (rowSpan grows each row's span
                // by padX and its band by padY, which is what covers the projection's rounding). Not
                // "on the inner side of every edge's line": two vertices of the polygon can be images
                // within rounding of each other (a box seen almost along an edge, or far away), and the
                // line through them then has any direction; the polygon as a set is still right.
                for (int k = 0; k < 8; ++k) {
                    bool inside = true;
                    double d2 = kInf; // squared distance to the polygon's boundary
                    for (int e = 0; e < m; ++e) {
                        const int g = e + 1 == m ? 0 : e + 1;
                        const double ex = f.x[g] - f.x[e], ey = f.y[g] - f.y[e];
                        const double wx = px[k] - f.x[e], wy = py[k] - f.y[e];
                        inside = inside && ex * wy - ey * wx >= 0;
                        const double len2 = ex * ex + ey * ey;
                        const double t = len2 > 0 ? std::clamp((wx * ex + wy * ey) / len2, 0.0, 1.0) : 0.0;
                        d2 = std::min(d2, (wx - t * ex) * (wx - t * ex) + (wy - t * ey) * (wy - t * ey));
                    }
                    const double tol = 0.01 * std::min(f.padX, f.padY);
                    assert(inside || d2 <= tol * tol);
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
    const double f0 = (x0 - f.padX + m_halfW) * m_invPixelW - 1e-6, f1 = (x1 + f.padX + m_halfW) * m_invPixelW + 1e-6;
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
    const Box<3> bounds = boundsOf<3>(shape); // (the box tests below read it too)
    std::size_t centrePixel = std::size_t(-1);
    // Both witnesses behind some occluder: the box occluder at the centre may prove it at once, in object
    // space (a ball by its bounding box, which holds it). A ball in front of the camera asks after its
    // tangent rectangle's scan instead, which is cheaper where the image alone hides it (a ball in a
    // cloud of others): either proof hides it, so the verdict is the same.
    bool ballInFront = false;
    auto shadowProof = [&] {
        if (!shadowed(bounds.min - grow - m_apex, bounds.max + grow - m_apex, centrePixel)) return false;
        ++m_stats.hidden;
        ++m_stats.shadowed;
        return true;
    };
    {
        const Box<3>& b = bounds;
        if (!canHide(0.5 * (b.min + b.max) - m_apex, centrePixel)) return false;
        if (const auto* ball = std::get_if<Ball<3>>(&shape)) {
            const Vec3 c = ball->center - m_apex;
            const double r = (ball->radius + grow) * (1 - 1e-6), len = std::sqrt(lengthSquared<3>(c));
            if (len > r && !canHide(c * (1 - r / len))) return false;
            ballInFront = glm::dot(c, m_forward) > (ball->radius + grow) * 1.001;
        } else if (!canHide(glm::clamp(Vec3(0.0), b.min - grow - m_apex, b.max + grow - m_apex))) {
            return false;
        }
        if (!ballInFront && shadowProof()) return true;
    }
    Footprint f;
    bool inView;
    if (const auto* b = std::get_if<Ball<3>>(&shape)) {
        const Vec3 c = b->center - m_apex;
        const double rad = b->radius + grow;
        lo = c - rad;
        hi = c + rad;
        // In front of the camera: the exact per-pixel test (hiddenBall). Otherwise its bounding box's
        // clipped footprint, refined into parts below.
        if (ballInFront) {
            // First the tangent rectangle against the sphere's one nearest distance (the sphere behind a
            // closed wall: every pixel passes, with no arithmetic per pixel), then witnesses (the six
            // poles, each a point of the sphere: its pixel must be covered nearer than it), then the
            // exact test. A visible sphere fails at a witness or at the first uncovered pixel of a row.
            f.n = 0;
            f.rect = rectOf(c, rad);
            bool h = scanFootprint(f, nearest);
            if (!h && shadowProof()) return true;
            if (!h) {
                const double rw = rad * (1 - 1e-6);
                for (int a = 0; a < 3; ++a) {
                    Vec3 d(0.0);
                    d[a] = rw;
                    if (!canHide(c + d) || !canHide(c - d)) return false;
                }
                h = hiddenBall(c, rad, nearest);
            }
            m_stats.hidden += h;
            return h;
        }
        inView = footprintOf(lo, hi, zMinOf(nearest), f, false, nearest);
    } else {
        // A box, or a polytope's bounding box: its footprint holds the polytope's (the test is then for
        // the box, which contains the polytope: conservative).
        lo = bounds.min - grow - m_apex;
        hi = bounds.max + grow - m_apex;
        inView = footprintOf(lo, hi, zMinOf(nearest), f, false, nearest, true);
    }
    if (f.cornerSeen) return false;
    if (!inView || f.covered || scanFootprint(f, nearest)) {
        ++m_stats.hidden;
        return true;
    }
    if (!refine) return false;
    // Refinement: the test compares every pixel with the shape's single nearest distance, and a
    // rectangle is larger than the image of a sphere or of a box seen at an angle, so an object just
    // behind a wall fails on pixels at the edge of its rectangle (where the wall is crossed farther out
    // than the object's nearest point is, or which show no part of it at all). A box (or a polytope's
    // bounding box) is then tested pixel by pixel against the nearest entry each pixel's rays can have
    // (hiddenBoxExact); a ball reaching behind the camera has its bounding box split into 8 and each part
    // tested with its own rectangle and nearest distance, two levels deep.
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
    } else if (!f.cornersRead) { // (else footprintOf read them)
        for (int k = 0; k < 8; ++k)
            if (!canHide(Vec3{(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z})) return false;
    }
    // A box (or a polytope's bounding box): the exact per-pixel test over its footprint (the whole image
    // for a box reaching behind the camera: the bound holds for any ray). A ball reaching behind the
    // camera keeps the parts.
    if (ball == nullptr) {
        if (!hiddenBoxExact(lo, hi, nearest, f)) return false;
    } else if (!hiddenParts(lo, hi, 2, ball != nullptr ? &centre : nullptr, ball != nullptr ? ball->radius + grow : 0.0)) {
        return false;
    }
    ++m_stats.hidden;
    return true;
}

bool OcclusionBuffer3D::shadowed(const Vec3& lo, const Vec3& hi, std::size_t pixel) const {
    // Why. The image compares each pixel's depth (the largest entry over its corner rays) with an
    // occludee's nearest point; a wall seen at a grazing angle spans a long stretch of depths within one
    // pixel, so a box just behind it (a brick's voxels beyond a room's wall, an object behind a building)
    // fails there and goes down the refinement, and at last to single voxels. Here the box is tested
    // against one occluder box W in object space, exactly, whatever the pixels.
    // The shadow. With the apex at the origin, S = {p : the open segment (0, p) meets int W}. S is convex:
    // p1 = s1 w1 and p2 = s2 w2 (w1, w2 in int W, s1, s2 >= 1, as every point of S is) give
    // l p1 + (1 - l) p2 = s w with s = l s1 + (1 - l) s2 >= 1 and w = (l s1 w1 + (1 - l) s2 w2) / s, a convex
    // combination of w1 and w2, in int W. So the box lies in S when its eight corners do: for each, the
    // slab intervals of t q along the segment (t in (0, 1)) inside W's open slabs overlap, with the apex
    // outside W (the entry tEnter > 0). The margin (1e-9 of the segment) covers the quotients' rounding;
    // W is the box as drawn (shrunk by its slack) and lo..hi the occludee as tested (grown by its own):
    // the same conventions as the image's depths, so the proof means what hidden() promises.
    // An occluder never hides a box holding it: the box's point nearest to the apex would be s w with
    // s >= 1 and w in int W, inside the box: w is then nearer (s > 1) or the point is interior (s = 1).
    // The same holds for any convex W: a polytope's planes take the slabs' place.
    // The candidate W: the box or polytope that set the depth of the centre's pixel (when its image is
    // large: an occluder with a smaller image than the occludee's cannot shadow it). Any would do (the
    // proof does not depend on the pixel); that one is the likeliest.
    if (pixel >= m_depthNote.size()) return false;
    const std::uint32_t note = m_depthNote[pixel], id = note & 0xFFFFu;
    if (note >> 16 != m_noteStamp || id == 0 || !allFinite<3>(lo) || !allFinite<3>(hi)) return false;
    // Every corner's segment t q, t in (0, 1), enters W (tEnter > 0: the apex is outside it) and stays in
    // it for more than the margin before q; clip(q, tEnter, tExit) narrows [tEnter, tExit] to W's
    // interval along it, false when the segment never enters.
    constexpr double kMargin = 1e-9;
    auto allCorners = [&](auto&& clip) {
        for (int k = 0; k < 8; ++k) {
            const Vec3 q{(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z};
            double tEnter = -kInf, tExit = kInf;
            if (!clip(q, tEnter, tExit) || !(tEnter > 0) || !(std::min(tExit, 1.0) - tEnter > kMargin)) return false;
        }
        return true;
    };
    if (id & kPolytopeNote) {
        // A polytope: its planes n.x < c (as drawn: moved in by its tolerance and shrink). Along t q a
        // plane bounds t above where n.q > 0 and below where n.q < 0; where n.q = 0 the segment lies on
        // the inner side (c > 0) or never enters.
        const ShadowPolytope& w = m_shadowPolytopes[(id & ~kPolytopeNote) - 1];
        const Vec3* normals = m_shadowN.data() + w.first;
        const double* offsets = m_shadowC.data() + w.first;
        return allCorners([&](const Vec3& q, double& tEnter, double& tExit) {
            for (std::uint32_t e = 0; e < w.count; ++e) {
                const double d = glm::dot(normals[e], q), c = offsets[e];
                if (d > 0) tExit = std::min(tExit, c / d);
                else if (d < 0) tEnter = std::max(tEnter, c / d);
                else if (!(c > 0)) return false;
            }
            return true;
        });
    }
    // A box: its three open slabs.
    const SeamBox& w = m_seamBoxes[id - 1];
    return allCorners([&](const Vec3& q, double& tEnter, double& tExit) {
        for (int a = 0; a < 3; ++a) {
            if (q[a] == 0) { // the segment runs in the plane q[a] = 0: inside the slab or never
                if (!(w.lo[a] < 0 && w.hi[a] > 0)) return false;
                continue;
            }
            const double t1 = w.lo[a] / q[a], t2 = w.hi[a] / q[a];
            tEnter = std::max(tEnter, std::min(t1, t2));
            tExit = std::min(tExit, std::max(t1, t2));
        }
        return true;
    });
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
    const int i = int(std::clamp((x + m_halfW) * m_invPixelW, 0.0, double(m_cols - 1)));
    const int j = int(std::clamp((y + m_halfH) * m_invPixelH, 0.0, double(m_rows - 1)));
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
    if (f.n == 0) { // the rectangle alone (every sphere's first test): no spans to compute
        for (int j = r.j0; j <= r.j1; ++j) {
            const double* row = m_depth.data() + std::size_t(j) * std::size_t(m_cols);
            for (int i = r.i0; i <= r.i1; ++i)
                if (!(row[i] < nearest)) return false;
        }
        return true;
    }
    // A row fails exactly when some pixel of its span is not covered nearer, i.e. when its open span is
    // not empty (whose ends are such pixels).
    for (int j = r.j0; j <= r.j1; ++j) {
        int i0, i1;
        if (openRowSpan(f, j, nearest, i0, i1)) return false;
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
        if (!footprintOf(l, h, zMinOf(nearest), f, false, nearest) || f.covered || scanFootprint(f, nearest)) continue;
        if (levels <= 1 || !canHide(0.5 * (l + h)) || !hiddenParts(l, h, levels - 1, centre, radius)) return false;
    }
    return true;
}

} // namespace rgvc
