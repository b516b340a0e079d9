// A small RGB8 raster image and the CPU drawing primitives the pictures need (no GL).
//
// Pixel convention: pixel (x, y) has x to the right and y *down* (row 0 is the top row, as in PNG).
// The continuous-coordinate primitives (the ones taking Vec2 / double) treat pixel (x, y) as the unit
// square [x, x+1) x [y, y+1) with its centre at (x + 0.5, y + 0.5): a filled shape covers exactly the
// pixels whose centre lies inside it. Every primitive clips to the image: nothing is ever written out of
// bounds, whatever the coordinates (huge, negative, or non-finite ones, which are ignored), and the work
// is bounded by the visible part, not by the size of the shape.
#pragma once

#include "rgvc/grid/Math.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <ostream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace rgvc {

/// One 8-bit sRGB colour.
struct RGB8 {
    std::uint8_t r = 0, g = 0, b = 0;
    friend constexpr bool operator==(const RGB8&, const RGB8&) = default;
};

inline std::ostream& operator<<(std::ostream& os, const RGB8& c) {
    return os << "RGB(" << int(c.r) << ", " << int(c.g) << ", " << int(c.b) << ")";
}

namespace colors {
inline constexpr RGB8 kWhite{255, 255, 255};
inline constexpr RGB8 kBlack{0, 0, 0};
inline constexpr RGB8 kRed{220, 30, 30};
inline constexpr RGB8 kBlue{30, 80, 220};
} // namespace colors

/// `over` blended onto `under` with opacity alpha in [0, 1] (clamped), rounded to nearest.
inline RGB8 blendColor(RGB8 under, RGB8 over, double alpha) {
    if (!(alpha > 0)) return under; // also NaN
    if (alpha >= 1) return over;
    auto mix = [alpha](std::uint8_t u, std::uint8_t o) {
        return std::uint8_t(std::lround(double(u) + (double(o) - double(u)) * alpha));
    };
    return {mix(under.r, over.r), mix(under.g, over.g), mix(under.b, over.b)};
}

/// A width x height RGB8 image, row-major, top row first, 3 bytes per pixel, no padding.
class ImageRGB {
public:
    /// Largest accepted pixel count (3 bytes each: 768 MiB).
    static constexpr std::int64_t kMaxPixels = std::int64_t(1) << 28;

    ImageRGB() = default;
    /// @throws std::invalid_argument when a side is negative or the image exceeds kMaxPixels.
    ImageRGB(int width, int height, RGB8 fill = colors::kWhite) {
        if (width < 0 || height < 0 || std::int64_t(width) * height > kMaxPixels)
            throw std::invalid_argument("ImageRGB: bad size " + std::to_string(width) + "x" +
                                        std::to_string(height));
        m_width = width;
        m_height = height;
        m_pixels.resize(std::size_t(width) * std::size_t(height) * 3);
        this->fill(fill);
    }

    int width() const { return m_width; }
    int height() const { return m_height; }
    bool empty() const { return m_width == 0 || m_height == 0; }
    bool contains(int x, int y) const { return x >= 0 && y >= 0 && x < m_width && y < m_height; }

    /// @throws std::out_of_range outside the image.
    RGB8 at(int x, int y) const {
        if (!contains(x, y))
            throw std::out_of_range("ImageRGB::at(" + std::to_string(x) + ", " + std::to_string(y) +
                                    ") outside " + std::to_string(m_width) + "x" + std::to_string(m_height));
        const std::uint8_t* p = &m_pixels[index(x, y)];
        return {p[0], p[1], p[2]};
    }
    /// Writes one pixel; silently ignored outside the image (this is the clipping of every primitive).
    void set(int x, int y, RGB8 c) noexcept {
        if (!contains(x, y)) return;
        std::uint8_t* p = &m_pixels[index(x, y)];
        p[0] = c.r;
        p[1] = c.g;
        p[2] = c.b;
    }
    /// Blends c over one pixel with opacity alpha; ignored outside the image.
    void blend(int x, int y, RGB8 c, double alpha) noexcept {
        if (!contains(x, y)) return;
        std::uint8_t* p = &m_pixels[index(x, y)];
        RGB8 out = blendColor({p[0], p[1], p[2]}, c, alpha);
        p[0] = out.r;
        p[1] = out.g;
        p[2] = out.b;
    }
    void fill(RGB8 c) noexcept {
        for (std::size_t i = 0; i < m_pixels.size(); i += 3) {
            m_pixels[i] = c.r;
            m_pixels[i + 1] = c.g;
            m_pixels[i + 2] = c.b;
        }
    }

    /// Raw bytes, row-major, top row first; row stride = 3 * width.
    const std::uint8_t* data() const { return m_pixels.data(); }
    std::uint8_t* data() { return m_pixels.data(); }
    std::size_t stride() const { return std::size_t(m_width) * 3; }

    friend bool operator==(const ImageRGB&, const ImageRGB&) = default;

private:
    std::size_t index(int x, int y) const { return (std::size_t(y) * std::size_t(m_width) + std::size_t(x)) * 3; }

    int m_width = 0;
    int m_height = 0;
    std::vector<std::uint8_t> m_pixels;
};

namespace detail {

/// Clamps a double to an int range safely (NaN -> lo).
inline int clampToInt(double v, int lo, int hi) {
    if (!(v >= double(lo))) return lo;
    if (v >= double(hi)) return hi;
    return int(v);
}

/// Fills (or blends) pixels [x0, x1] of row y, clipped.
inline void span(ImageRGB& img, int y, int x0, int x1, RGB8 c, double alpha) {
    if (y < 0 || y >= img.height()) return;
    x0 = std::max(x0, 0);
    x1 = std::min(x1, img.width() - 1);
    if (alpha >= 1) {
        for (int x = x0; x <= x1; ++x) img.set(x, y, c);
    } else {
        for (int x = x0; x <= x1; ++x) img.blend(x, y, c, alpha);
    }
}

/// Pixel indices whose centres lie in the closed continuous interval [lo, hi], clamped to [-1, n].
inline void centreRange(double lo, double hi, int n, int& first, int& last) {
    first = clampToInt(std::ceil(lo - 0.5), -1, n);
    last = clampToInt(std::floor(hi - 0.5), -1, n);
}

/// Liang-Barsky: clips segment a-b to the box [lo, hi]^2 (x and y ranges); returns false when it misses.
/// t0, t1 are the parameters of the kept part along a + t (b - a), t in [0, 1].
inline bool clipSegment(const Vec2& a, const Vec2& b, double xlo, double ylo, double xhi, double yhi,
                        double& t0, double& t1) {
    if (!allFinite<2>(a) || !allFinite<2>(b)) return false;
    t0 = 0;
    t1 = 1;
    const Vec2 d = b - a;
    const double p[4] = {-d.x, d.x, -d.y, d.y};
    const double q[4] = {a.x - xlo, xhi - a.x, a.y - ylo, yhi - a.y};
    for (int i = 0; i < 4; ++i) {
        if (p[i] == 0) {
            if (q[i] < 0) return false; // parallel and outside
            continue;
        }
        double r = q[i] / p[i];
        if (p[i] < 0) {
            if (r > t1) return false;
            t0 = std::max(t0, r);
        } else {
            if (r < t0) return false;
            t1 = std::min(t1, r);
        }
    }
    return t0 <= t1;
}

} // namespace detail

/// Fills the pixels [x0, x1) x [y0, y1) (half-open, integer pixel indices), clipped.
inline void fillRect(ImageRGB& img, std::int64_t x0, std::int64_t y0, std::int64_t x1, std::int64_t y1, RGB8 c,
                     double alpha = 1.0) {
    x0 = std::max<std::int64_t>(x0, 0);
    y0 = std::max<std::int64_t>(y0, 0);
    x1 = std::min<std::int64_t>(x1, img.width());
    y1 = std::min<std::int64_t>(y1, img.height());
    if (x1 <= x0 || y1 <= y0) return;
    for (std::int64_t y = y0; y < y1; ++y) detail::span(img, int(y), int(x0), int(x1 - 1), c, alpha);
}

/// One-pixel outline of the pixels [x0, x1) x [y0, y1), clipped.
inline void drawRectOutline(ImageRGB& img, std::int64_t x0, std::int64_t y0, std::int64_t x1, std::int64_t y1,
                            RGB8 c) {
    if (x1 <= x0 || y1 <= y0) return;
    fillRect(img, x0, y0, x1, y0 + 1, c);
    fillRect(img, x0, y1 - 1, x1, y1, c);
    fillRect(img, x0, y0, x0 + 1, y1, c);
    fillRect(img, x1 - 1, y0, x1, y1, c);
}

/// Fills the convex polygon (either winding) in continuous coordinates: every pixel whose centre lies in
/// it. Non-convex input fills, per row, the span between the leftmost and rightmost crossing.
inline void fillConvexPolygon(ImageRGB& img, const std::vector<Vec2>& pts, RGB8 c, double alpha = 1.0) {
    const std::size_t n = pts.size();
    if (n < 3 || img.empty()) return;
    double ylo = std::numeric_limits<double>::infinity(), yhi = -ylo;
    for (const Vec2& p : pts) {
        if (!allFinite<2>(p)) return;
        ylo = std::min(ylo, p.y);
        yhi = std::max(yhi, p.y);
    }
    int rowFirst, rowLast;
    detail::centreRange(ylo, yhi, img.height(), rowFirst, rowLast);
    rowFirst = std::max(rowFirst, 0);
    rowLast = std::min(rowLast, img.height() - 1);
    for (int y = rowFirst; y <= rowLast; ++y) {
        const double yc = y + 0.5;
        double xl = std::numeric_limits<double>::infinity(), xr = -xl;
        for (std::size_t i = 0; i < n; ++i) {
            const Vec2& a = pts[i];
            const Vec2& b = pts[(i + 1) % n];
            if ((a.y < yc && b.y < yc) || (a.y > yc && b.y > yc)) continue;
            if (a.y == b.y) { // horizontal edge on this row's centre line
                xl = std::min({xl, a.x, b.x});
                xr = std::max({xr, a.x, b.x});
                continue;
            }
            double x = a.x + (yc - a.y) * (b.x - a.x) / (b.y - a.y);
            xl = std::min(xl, x);
            xr = std::max(xr, x);
        }
        if (!(xl <= xr)) continue;
        int x0, x1;
        detail::centreRange(xl, xr, img.width(), x0, x1);
        detail::span(img, y, x0, x1, c, alpha);
    }
}

/// Line between two points in continuous coordinates. thickness <= 1: a Bresenham line (8-connected,
/// one pixel wide) between the pixels containing the end points; thicker: a filled quad of that width.
inline void drawLine(ImageRGB& img, const Vec2& a, const Vec2& b, RGB8 c, double thickness = 1.0) {
    if (img.empty()) return;
    // Clip to a margin around the image first: the loop below then costs O(visible length).
    const double m = 2 + std::max(thickness, 1.0);
    double t0, t1;
    if (!detail::clipSegment(a, b, -m, -m, img.width() + m, img.height() + m, t0, t1)) return;
    const Vec2 d = b - a;
    const Vec2 p = a + d * t0;
    const Vec2 q = a + d * t1;
    if (thickness > 1.0) {
        const double len = std::sqrt(lengthSquared<2>(q - p));
        if (len == 0) {
            // Degenerate: a square dot.
            Vec2 h(thickness / 2);
            fillConvexPolygon(img, {p - h, Vec2(p.x + h.x, p.y - h.y), p + h, Vec2(p.x - h.x, p.y + h.y)}, c);
            return;
        }
        const Vec2 nrm = Vec2(-(q - p).y, (q - p).x) * (thickness / 2 / len);
        fillConvexPolygon(img, {p + nrm, q + nrm, q - nrm, p - nrm}, c);
        return;
    }
    int x0 = int(std::floor(p.x)), y0 = int(std::floor(p.y));
    const int x1 = int(std::floor(q.x)), y1 = int(std::floor(q.y));
    const int dx = std::abs(x1 - x0), dy = -std::abs(y1 - y0);
    const int sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1;
    int err = dx + dy;
    for (;;) {
        img.set(x0, y0, c);
        if (x0 == x1 && y0 == y1) break;
        const int e2 = 2 * err;
        if (e2 >= dy) {
            err += dy;
            x0 += sx;
        }
        if (e2 <= dx) {
            err += dx;
            y0 += sy;
        }
    }
}

/// Bresenham line between the centres of pixels (x0, y0) and (x1, y1), both included.
inline void drawLine(ImageRGB& img, int x0, int y0, int x1, int y1, RGB8 c) {
    drawLine(img, Vec2(x0 + 0.5, y0 + 0.5), Vec2(x1 + 0.5, y1 + 0.5), c, 1.0);
}

/// Dashed line: dashes of `dash` pixels separated by gaps of `gap` pixels, starting with a dash at `a`.
/// The pattern is anchored at `a`, so clipping does not shift it.
inline void drawDashedLine(ImageRGB& img, const Vec2& a, const Vec2& b, RGB8 c, double dash = 8.0,
                           double gap = 5.0, double thickness = 1.0) {
    if (img.empty() || !(dash > 0) || !(gap >= 0)) return;
    const double m = 2 + std::max(thickness, 1.0);
    double t0, t1;
    if (!detail::clipSegment(a, b, -m, -m, img.width() + m, img.height() + m, t0, t1)) return;
    const double len = std::sqrt(lengthSquared<2>(b - a));
    if (!(len > 0) || !std::isfinite(len)) {
        drawLine(img, a, b, c, thickness);
        return;
    }
    const Vec2 u = (b - a) / len;
    const double s0 = t0 * len, s1 = t1 * len, period = dash + gap;
    for (double s = std::floor(s0 / period) * period; s < s1; s += period) {
        const double d0 = std::max(s, s0), d1 = std::min(s + dash, s1);
        // A dash covers [d0, d1): pulled back a hair so that a dash of n pixels sets n pixels, not n + 1.
        if (d0 < d1) drawLine(img, a + u * d0, a + u * std::max(d0, d1 - 1e-6), c, thickness);
    }
}

/// Filled disc of radius r centred at (cx, cy) in continuous coordinates.
inline void fillCircle(ImageRGB& img, const Vec2& centre, double r, RGB8 c, double alpha = 1.0) {
    if (img.empty() || !allFinite<2>(centre) || !(r > 0) || !std::isfinite(r)) return;
    int y0, y1;
    detail::centreRange(centre.y - r, centre.y + r, img.height(), y0, y1);
    y0 = std::max(y0, 0);
    y1 = std::min(y1, img.height() - 1);
    for (int y = y0; y <= y1; ++y) {
        const double dy = y + 0.5 - centre.y;
        const double w2 = r * r - dy * dy;
        if (w2 < 0) continue;
        const double w = std::sqrt(w2);
        int x0, x1;
        detail::centreRange(centre.x - w, centre.x + w, img.width(), x0, x1);
        detail::span(img, y, x0, x1, c, alpha);
    }
}

/// Circle outline: every pixel whose centre lies at distance [r - t/2, r + t/2] from the centre
/// (t = thickness, at least 1, which keeps the ring 8-connected).
inline void drawCircle(ImageRGB& img, const Vec2& centre, double r, RGB8 c, double thickness = 1.0) {
    if (img.empty() || !allFinite<2>(centre) || !(r > 0) || !std::isfinite(r)) return;
    const double t = std::max(thickness, 1.0);
    const double ro = r + t / 2, ri = r - t / 2;
    int y0, y1;
    detail::centreRange(centre.y - ro, centre.y + ro, img.height(), y0, y1);
    y0 = std::max(y0, 0);
    y1 = std::min(y1, img.height() - 1);
    for (int y = y0; y <= y1; ++y) {
        const double dy = y + 0.5 - centre.y;
        const double wo2 = ro * ro - dy * dy;
        if (wo2 < 0) continue;
        const double wo = std::sqrt(wo2);
        int ox0, ox1;
        detail::centreRange(centre.x - wo, centre.x + wo, img.width(), ox0, ox1);
        const double wi2 = ri > 0 ? ri * ri - dy * dy : -1;
        if (wi2 <= 0) {
            detail::span(img, y, ox0, ox1, c, 1.0);
            continue;
        }
        // Inner open interval (centre.x - wi, centre.x + wi) is excluded.
        const double wi = std::sqrt(wi2);
        int ix0, ix1;
        detail::centreRange(centre.x - wi, centre.x + wi, img.width(), ix0, ix1);
        // Pixels exactly on the inner boundary stay in the ring.
        if (ix0 <= ix1 && std::abs(ix0 + 0.5 - (centre.x - wi)) < 1e-12) ++ix0;
        if (ix0 <= ix1 && std::abs(ix1 + 0.5 - (centre.x + wi)) < 1e-12) --ix1;
        detail::span(img, y, ox0, std::min(ox1, ix0 - 1), c, 1.0);
        detail::span(img, y, std::max(ox0, ix1 + 1), ox1, c, 1.0);
    }
}

/// Closed polyline through pts (continuous coordinates).
inline void drawPolygonOutline(ImageRGB& img, const std::vector<Vec2>& pts, RGB8 c, double thickness = 1.0) {
    for (std::size_t i = 0, n = pts.size(); i < n && n >= 2; ++i) drawLine(img, pts[i], pts[(i + 1) % n], c, thickness);
}

// ---------------------------------------------------------------------------------------------------
// Text: a built-in 5x7 bitmap font for printable ASCII (32..126); other bytes draw as '?'.

namespace detail {
/// Column-major glyphs, 5 columns per character, bit 0 = top row.
inline constexpr std::array<std::uint8_t, 95 * 5> kFont5x7 = {
    0x00, 0x00, 0x00, 0x00, 0x00, /* ' ' */ 0x00, 0x00, 0x5F, 0x00, 0x00, /* ! */
    0x00, 0x07, 0x00, 0x07, 0x00, /* " */   0x14, 0x7F, 0x14, 0x7F, 0x14, /* # */
    0x24, 0x2A, 0x7F, 0x2A, 0x12, /* $ */   0x23, 0x13, 0x08, 0x64, 0x62, /* % */
    0x36, 0x49, 0x55, 0x22, 0x50, /* & */   0x00, 0x05, 0x03, 0x00, 0x00, /* ' */
    0x00, 0x1C, 0x22, 0x41, 0x00, /* ( */   0x00, 0x41, 0x22, 0x1C, 0x00, /* ) */
    0x08, 0x2A, 0x1C, 0x2A, 0x08, /* * */   0x08, 0x08, 0x3E, 0x08, 0x08, /* + */
    0x00, 0x50, 0x30, 0x00, 0x00, /* , */   0x08, 0x08, 0x08, 0x08, 0x08, /* - */
    0x00, 0x60, 0x60, 0x00, 0x00, /* . */   0x20, 0x10, 0x08, 0x04, 0x02, /* / */
    0x3E, 0x51, 0x49, 0x45, 0x3E, /* 0 */   0x00, 0x42, 0x7F, 0x40, 0x00, /* 1 */
    0x42, 0x61, 0x51, 0x49, 0x46, /* 2 */   0x21, 0x41, 0x45, 0x4B, 0x31, /* 3 */
    0x18, 0x14, 0x12, 0x7F, 0x10, /* 4 */   0x27, 0x45, 0x45, 0x45, 0x39, /* 5 */
    0x3C, 0x4A, 0x49, 0x49, 0x30, /* 6 */   0x01, 0x71, 0x09, 0x05, 0x03, /* 7 */
    0x36, 0x49, 0x49, 0x49, 0x36, /* 8 */   0x06, 0x49, 0x49, 0x29, 0x1E, /* 9 */
    0x00, 0x36, 0x36, 0x00, 0x00, /* : */   0x00, 0x56, 0x36, 0x00, 0x00, /* ; */
    0x08, 0x14, 0x22, 0x41, 0x00, /* < */   0x14, 0x14, 0x14, 0x14, 0x14, /* = */
    0x00, 0x41, 0x22, 0x14, 0x08, /* > */   0x02, 0x01, 0x51, 0x09, 0x06, /* ? */
    0x32, 0x49, 0x79, 0x41, 0x3E, /* @ */   0x7E, 0x11, 0x11, 0x11, 0x7E, /* A */
    0x7F, 0x49, 0x49, 0x49, 0x36, /* B */   0x3E, 0x41, 0x41, 0x41, 0x22, /* C */
    0x7F, 0x41, 0x41, 0x22, 0x1C, /* D */   0x7F, 0x49, 0x49, 0x49, 0x41, /* E */
    0x7F, 0x09, 0x09, 0x09, 0x01, /* F */   0x3E, 0x41, 0x49, 0x49, 0x7A, /* G */
    0x7F, 0x08, 0x08, 0x08, 0x7F, /* H */   0x00, 0x41, 0x7F, 0x41, 0x00, /* I */
    0x20, 0x40, 0x41, 0x3F, 0x01, /* J */   0x7F, 0x08, 0x14, 0x22, 0x41, /* K */
    0x7F, 0x40, 0x40, 0x40, 0x40, /* L */   0x7F, 0x02, 0x0C, 0x02, 0x7F, /* M */
    0x7F, 0x04, 0x08, 0x10, 0x7F, /* N */   0x3E, 0x41, 0x41, 0x41, 0x3E, /* O */
    0x7F, 0x09, 0x09, 0x09, 0x06, /* P */   0x3E, 0x41, 0x51, 0x21, 0x5E, /* Q */
    0x7F, 0x09, 0x19, 0x29, 0x46, /* R */   0x46, 0x49, 0x49, 0x49, 0x31, /* S */
    0x01, 0x01, 0x7F, 0x01, 0x01, /* T */   0x3F, 0x40, 0x40, 0x40, 0x3F, /* U */
    0x1F, 0x20, 0x40, 0x20, 0x1F, /* V */   0x3F, 0x40, 0x38, 0x40, 0x3F, /* W */
    0x63, 0x14, 0x08, 0x14, 0x63, /* X */   0x07, 0x08, 0x70, 0x08, 0x07, /* Y */
    0x61, 0x51, 0x49, 0x45, 0x43, /* Z */   0x00, 0x7F, 0x41, 0x41, 0x00, /* [ */
    0x02, 0x04, 0x08, 0x10, 0x20, /* \ */   0x00, 0x41, 0x41, 0x7F, 0x00, /* ] */
    0x04, 0x02, 0x01, 0x02, 0x04, /* ^ */   0x40, 0x40, 0x40, 0x40, 0x40, /* _ */
    0x00, 0x01, 0x02, 0x04, 0x00, /* ` */   0x20, 0x54, 0x54, 0x54, 0x78, /* a */
    0x7F, 0x48, 0x44, 0x44, 0x38, /* b */   0x38, 0x44, 0x44, 0x44, 0x20, /* c */
    0x38, 0x44, 0x44, 0x48, 0x7F, /* d */   0x38, 0x54, 0x54, 0x54, 0x18, /* e */
    0x08, 0x7E, 0x09, 0x01, 0x02, /* f */   0x0C, 0x52, 0x52, 0x52, 0x3E, /* g */
    0x7F, 0x08, 0x04, 0x04, 0x78, /* h */   0x00, 0x44, 0x7D, 0x40, 0x00, /* i */
    0x20, 0x40, 0x44, 0x3D, 0x00, /* j */   0x7F, 0x10, 0x28, 0x44, 0x00, /* k */
    0x00, 0x41, 0x7F, 0x40, 0x00, /* l */   0x7C, 0x04, 0x18, 0x04, 0x78, /* m */
    0x7C, 0x08, 0x04, 0x04, 0x78, /* n */   0x38, 0x44, 0x44, 0x44, 0x38, /* o */
    0x7C, 0x14, 0x14, 0x14, 0x08, /* p */   0x08, 0x14, 0x14, 0x18, 0x7C, /* q */
    0x7C, 0x08, 0x04, 0x04, 0x08, /* r */   0x48, 0x54, 0x54, 0x54, 0x20, /* s */
    0x04, 0x3F, 0x44, 0x40, 0x20, /* t */   0x3C, 0x40, 0x40, 0x20, 0x7C, /* u */
    0x1C, 0x20, 0x40, 0x20, 0x1C, /* v */   0x3C, 0x40, 0x30, 0x40, 0x3C, /* w */
    0x44, 0x28, 0x10, 0x28, 0x44, /* x */   0x0C, 0x50, 0x50, 0x50, 0x3C, /* y */
    0x44, 0x64, 0x54, 0x4C, 0x44, /* z */   0x00, 0x08, 0x36, 0x41, 0x00, /* { */
    0x00, 0x00, 0x7F, 0x00, 0x00, /* | */   0x00, 0x41, 0x36, 0x08, 0x00, /* } */
    0x08, 0x04, 0x08, 0x10, 0x08, /* ~ */
};
} // namespace detail

/// Width in pixels of `text` drawn at `scale` (6 * scale per character, the last column included).
inline std::int64_t textWidth(std::string_view text, int scale = 1) {
    return std::int64_t(text.size()) * 6 * std::clamp(scale, 1, 1 << 12);
}
/// Height in pixels of one line of text at `scale`.
inline int textHeight(int scale = 1) { return 7 * std::clamp(scale, 1, 1 << 12); }

/// Draws `text` with its top-left corner at pixel (x, y), each font pixel a scale x scale block; clipped.
inline void drawText(ImageRGB& img, std::int64_t x, std::int64_t y, std::string_view text, RGB8 c, int scale = 1) {
    scale = std::clamp(scale, 1, 1 << 12);
    for (char ch : text) {
        if (x >= img.width()) break;
        unsigned code = static_cast<unsigned char>(ch);
        if (code < 32 || code > 126) code = '?';
        const std::uint8_t* glyph = &detail::kFont5x7[(code - 32) * 5];
        for (int col = 0; col < 5; ++col)
            for (int row = 0; row < 7; ++row)
                if (glyph[col] & (1u << row))
                    fillRect(img, x + col * scale, y + row * scale, x + (col + 1) * scale, y + (row + 1) * scale, c);
        x += 6 * scale;
    }
}

} // namespace rgvc
