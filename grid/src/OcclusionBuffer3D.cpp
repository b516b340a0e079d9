#include "rgvc/grid/OcclusionBuffer3D.hpp"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <limits>
#include <type_traits>

namespace rgvc {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

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

namespace {

/// out[F i + k] = src[i] for i < n, k < F (beginRefined's row spread, F a constant).
template <int F> void spreadRow(const double* src, int n, double* out) {
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < F; ++k) out[std::size_t(i) * F + std::size_t(k)] = src[i];
}

} // namespace

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
    // The first fine row of each coarse row is spread from it (no division per pixel, which was 3.6 %
    // of the 3D city's instructions), the other factor - 1 rows copied from that one. The usual factors
    // (the walk's 16 to 64 rows refined to 64) spread with the factor a constant, which the compiler
    // vectorizes: a std::fill_n per coarse pixel was 7-14 % of the instructions of the small scene files
    // through `rgvc cull` (small-3d.json, polytopes-3d.json, mesh-3d.json).
    for (int cj = 0; cj < coarse.m_rows; ++cj) {
        const double* src = coarse.m_depth.data() + std::size_t(cj) * std::size_t(coarse.m_cols);
        double* first = m_depth.data() + std::size_t(cj) * std::size_t(factor) * std::size_t(m_cols);
        switch (factor) {
        case 1: std::copy_n(src, coarse.m_cols, first); break;
        case 2: spreadRow<2>(src, coarse.m_cols, first); break;
        case 3: spreadRow<3>(src, coarse.m_cols, first); break;
        case 4: spreadRow<4>(src, coarse.m_cols, first); break;
        default:
            for (int ci = 0; ci < coarse.m_cols; ++ci) std::fill_n(first + std::size_t(ci) * std::size_t(factor), factor, src[ci]);
        }
        for (int k = 1; k < factor; ++k) std::copy_n(first, m_cols, first + std::size_t(k) * std::size_t(m_cols));
    }
    startImage();
    return true;
}

void OcclusionBuffer3D::startImage() {
    m_pixelW = 2 * m_halfW / m_cols;
    m_pixelH = 2 * m_halfH / m_rows;
    m_invPixelW = 1 / m_pixelW;
    m_invPixelH = 1 / m_pixelH;
    // m_depthNote and the seams' slots are cleared by a stamp (a memset per image was a third of what
    // the notes cost the 3D city, and the slots' 4 % of its instructions): entries of earlier images carry
    // an older stamp (m_depthNote's high 16 bits, m_partialCorners' for the slots; notePartial). 0 is
    // never a live stamp.
    m_partial.resize(std::size_t(m_rows) * std::size_t(m_cols));
    m_depthNote.resize(std::size_t(m_rows) * std::size_t(m_cols));
    m_partialCorners.resize(std::size_t(m_rows) * std::size_t(m_cols));
    if (++m_noteStamp > 0xFFFFu) {
        std::fill(m_depthNote.begin(), m_depthNote.end(), 0);
        std::fill(m_partialCorners.begin(), m_partialCorners.end(), 0);
        m_noteStamp = 1;
    }
    m_seamCount = 0;
    m_shadowPolytopes.clear();
    m_shadowN.clear();
    m_shadowC.clear();
    if (m_latticeW != m_halfW || m_latticeH != m_halfH || m_cornerX.size() != std::size_t(m_cols + 1) ||
        m_cornerY.size() != std::size_t(m_rows + 1)) {
        m_cornerX.resize(std::size_t(m_cols + 1));
        m_cornerY.resize(std::size_t(m_rows + 1));
        for (int i = 0; i <= m_cols; ++i) m_cornerX[std::size_t(i)] = -m_halfW + i * m_pixelW;
        for (int j = 0; j <= m_rows; ++j) m_cornerY[std::size_t(j)] = -m_halfH + j * m_pixelH;
        m_invLen.resize(std::size_t(m_rows + 1) * std::size_t(m_cols + 1));
        m_len.resize(m_invLen.size());
        // forward, right and up are orthonormal: |forward + x right + y up|^2 = 1 + x^2 + y^2.
        for (int j = 0; j <= m_rows; ++j)
            for (int i = 0; i <= m_cols; ++i) {
                const double x = m_cornerX[std::size_t(i)], y = m_cornerY[std::size_t(j)];
                const std::size_t k = std::size_t(j) * std::size_t(m_cols + 1) + std::size_t(i);
                m_len[k] = std::sqrt(1.0 + x * x + y * y);
                m_invLen[k] = 1.0 / m_len[k];
            }
        m_latticeW = m_halfW;
        m_latticeH = m_halfH;
    }
    m_rowA.resize(std::size_t(m_cols + 1));
    m_polyEnter.resize(std::size_t(m_cols + 1));
    m_polyExit.resize(std::size_t(m_cols + 1));
    m_rowB.resize(std::size_t(m_cols + 1));
    m_corners.resize(std::size_t(m_cols + 1));
    m_active = true;
}

std::size_t OcclusionBuffer3D::coveredPixels() const {
    std::size_t n = 0;
    for (const double d : m_depth) n += d < kInf; // vectorized
    return n;
}

OcclusionBuffer3D::PixelRect OcclusionBuffer3D::pixelsOf(double x0, double x1, double y0, double y1, bool* noPixel) const {
    // Pixel i covers [-halfW + i w, -halfW + (i + 1) w]; a small index margin keeps a direction on a
    // pixel boundary in both neighbours despite rounding. (Times the inverse of the pixel's size: within
    // an ulp or two of the quotient, far inside the margin.)
    const double f0 = (x0 + m_halfW) * m_invPixelW - 1e-6, f1 = (x1 + m_halfW) * m_invPixelW + 1e-6;
    const double g0 = (y0 + m_halfH) * m_invPixelH - 1e-6, g1 = (y1 + m_halfH) * m_invPixelH + 1e-6;
    if (noPixel != nullptr) *noPixel = false;
    // Bounds computed from overflowing coordinates (inf - inf) are NaN: nothing is known, so the whole
    // image (found by fuzz_culler3d).
    if (std::isnan(f0) || std::isnan(f1) || std::isnan(g0) || std::isnan(g1)) return wholeImage();
    // A pixel whose four corners (lattice points, lines 0..count) lie in the range has two consecutive
    // lattice lines in [f, f'] on each axis (the same index margin, far above the indices' rounding).
    if (noPixel != nullptr) {
        auto lines = [](double fa, double fb, int count) {
            return std::min(std::floor(fb), double(count)) - std::max(std::ceil(fa), 0.0) >= 1;
        };
        *noPixel = !(lines(f0, f1, m_cols) && lines(g0, g1, m_rows));
    }
    // The first index is floor(f) clamped to [0, count] (count: past the last, an empty range), the last
    // floor(f) clamped to [-1, count - 1] (-1: before the first). Clamped before the conversion, so no
    // coordinate overflows an int; a non-negative value truncates to its floor.
    auto first = [](double f, int count) { return int(std::clamp(f, 0.0, double(count))); };
    auto last = [](double f, int count) { return f < 0 ? -1 : int(std::min(f, double(count - 1))); };
    PixelRect r{first(f0, m_cols), last(f1, m_cols), first(g0, m_rows), last(g1, m_rows)};
    if (r.i0 > r.i1 || r.j0 > r.j1) r.i0 = 1, r.i1 = 0;
    return r;
}

OcclusionBuffer3D::PixelRect OcclusionBuffer3D::rectOf(const Vec3& c, double radius, bool* noPixel) const {
    if (noPixel != nullptr) *noPixel = false;
    // In camera coordinates (X, Y, Z) = (c.right, c.up, c.forward) the image coordinate x = X / Z over
    // the sphere takes the values over the disc of centre (cx, cz) and radius rho in the XZ plane; its
    // extremes are the tangents X = m Z from the origin: (cx - m cz)^2 = rho^2 (1 + m^2), so
    // m = (cx cz +- rho sqrt(cx^2 + cz^2 - rho^2)) / (cz^2 - rho^2), when the disc lies in Z > 0.
    const double cx = glm::dot(c, m_right), cy = glm::dot(c, m_up), cz = glm::dot(c, m_forward);
    if (!(cz > radius * 1.001)) { // reaching behind the camera (or nearly into its plane): its bounding box's part in view
        const Vec3 lo = c - radius, hi = c + radius;
        double xc[8], yc[8], zc[8];
        boxCorners(lo, hi, xc, yc, zc);
        return clippedRect(lo, hi, xc, yc, zc);
    }
    const double den = cz * cz - radius * radius, invDen = 1 / den;
    auto range = [&](double cw, double& lo, double& hi) {
        const double root = radius * std::sqrt(cw * cw + cz * cz - radius * radius);
        lo = (cw * cz - root) * invDen; // (padded by 1e-8 relative below, far above the product's ulps)
        hi = (cw * cz + root) * invDen;
        const double pad = 1e-8 * (std::abs(lo) + std::abs(hi) + 1.0);
        lo -= pad;
        hi += pad;
    };
    double x0, x1, y0, y1;
    range(cx, x0, x1);
    range(cy, y0, y1);
    return pixelsOf(x0, x1, y0, y1, noPixel);
}

OcclusionBuffer3D::PixelRect OcclusionBuffer3D::rectOf(const Vec3& lo, const Vec3& hi, bool* smallImage, bool* noPixel) const {
    // A box entirely in front of the camera: its image is the convex hull of its corners' images.
    if (smallImage != nullptr) *smallImage = false;
    if (noPixel != nullptr) *noPixel = false;
    double x0 = kInf, x1 = -kInf, y0 = kInf, y1 = -kInf;
    // One reciprocal per corner instead of two quotients: the result is padded by 1e-8 relative below, far
    // above the few ulps either form is off by.
    double xc[8], yc[8], zc[8];
    boxCorners(lo, hi, xc, yc, zc);
    // A corner nearly in the camera's plane (z at most 1e-6 of its distance) makes the image unbounded
    // for practical purposes: the box's part in view instead (clippedRect). (|q|^2 from the corner's
    // coordinates directly.)
    const double sx[2] = {lo.x * lo.x, hi.x * hi.x}, sy[2] = {lo.y * lo.y, hi.y * hi.y}, sz[2] = {lo.z * lo.z, hi.z * hi.z};
#pragma GCC unroll 8
    for (int k = 0; k < 8; ++k) {
        const double z = zc[k];
        if (!(z > 0) || !(z * z > 1e-12 * (sx[k & 1] + sy[(k >> 1) & 1] + sz[k >> 2]))) return clippedRect(lo, hi, xc, yc, zc);
        const double inv = 1.0 / z;
        const double x = xc[k] * inv, y = yc[k] * inv;
        x0 = std::min(x0, x);
        x1 = std::max(x1, x);
        y0 = std::min(y0, y);
        y1 = std::max(y1, y);
    }
    const double padX = 1e-8 * (std::abs(x0) + std::abs(x1) + 1.0), padY = 1e-8 * (std::abs(y0) + std::abs(y1) + 1.0);
    // addSeamBox keeps a box whose image polygon has at least kMinSeamPixels pixels of area. The polygon
    // (the hull of the images of the box's points with z >= zMin, all in front here: a segment in front
    // projects to a segment) lies in the padded rectangle of the corners' images, so a rectangle of less
    // area proves it smaller without computing it: the same boxes are kept, and a cloud of small boxes
    // no longer pays a footprint per draw (a tenth of the clusters' refinement pass in callgrind).
    if (smallImage != nullptr) *smallImage = (x1 - x0 + 2 * padX) * (y1 - y0 + 2 * padY) < kMinSeamPixels * m_pixelW * m_pixelH;
    return pixelsOf(x0 - padX, x1 + padX, y0 - padY, y1 + padY, noPixel);
}

template <class FillRow, class OnPartial>
void OcclusionBuffer3D::drawRect(const PixelRect& whole, double nearest, FillRow&& fillRow, OnPartial&& onPartial, bool partials,
                                  std::uint32_t note) {
    const PixelRect r{std::max(whole.i0, m_clip.i0), std::min(whole.i1, m_clip.i1), std::max(whole.j0, m_clip.j0),
                      std::min(whole.j1, m_clip.j1)};
    if (r.i0 > r.i1 || r.j0 > r.j1) return;
    // Two lattice rows at a time; the pixel loop uses selects, not jumps.
    // The pixels whose depth is at most `nearest` (no entry into the occluder is nearer, so no depth can
    // fall there) are skipped at both ends of each row, and a row holding only such pixels is skipped
    // whole, with its rim: a fused depth at a pixel the occluder covers in part is no smaller either,
    // since some of the pixel's rays enter only this occluder (and the seams' fused depths are at least
    // each box's nearest distance). A building behind nearer ones, an object at the edge of a nearer
    // one, or an occluder the inherited image already holds, draws only the part of each row where it
    // can still lower something (skipping whole rows only, the 3D city's frames took 8 % more instructions).
    int inA = -1;          // the lattice row m_rowA holds,
    int aLo = 0, aHi = -1; // over these lattice points
    std::uint64_t covered = 0;
    for (int j = r.j0; j <= r.j1; ++j) {
        double* row = m_depth.data() + std::size_t(j) * std::size_t(m_cols);
        // Scanned from its ends inwards: an occluder in front of open space (most draws, a few pixels
        // wide) stops at once.
        int i0 = r.i0, i1 = r.i1;
        while (i0 <= i1 && !(row[i0] > nearest)) ++i0;
        if (i0 > i1) continue;
        while (!(row[i1] > nearest)) --i1; // stops at i0
        if (inA != j || aLo > i0 || aHi < i1 + 1) fillRow(j, i0, i1 + 1, m_rowA.data());
        fillRow(j + 1, i0, i1 + 1, m_rowB.data());
        inA = j + 1;
        aLo = i0;
        aHi = i1 + 1;
        const double* a = m_rowA.data();
        const double* b = m_rowB.data();
        if (note == 0) {
            for (int i = i0; i <= i1; ++i) { // branch-free: vectorized
                const double e = std::max(std::max(a[i], a[i + 1]), std::max(b[i], b[i + 1]));
                const double lo = std::min(std::min(a[i], a[i + 1]), std::min(b[i], b[i + 1]));
                const bool in = lo >= 0; // every corner ray passes through the interior
                covered += in;
                const double m = std::min(row[i], e);
                row[i] = in ? m : row[i];
            }
        } else {
            // The same, noting the occluder where it sets the depth (shadowed() takes it as the candidate).
            std::uint32_t* notes = m_depthNote.data() + std::size_t(j) * std::size_t(m_cols);
            const std::uint32_t tag = m_noteStamp << 16 | note;
            for (int i = i0; i <= i1; ++i) {
                const double e = std::max(std::max(a[i], a[i + 1]), std::max(b[i], b[i + 1]));
                const double lo = std::min(std::min(a[i], a[i + 1]), std::min(b[i], b[i + 1]));
                const bool set = (lo >= 0) & (e <= row[i]);
                covered += lo >= 0;
                row[i] = set ? e : row[i];
                notes[i] = set ? tag : notes[i];
            }
        }
        if constexpr (!std::is_same_v<std::decay_t<OnPartial>, std::nullptr_t>)
            if (partials) {
                // The pixels with some but not all corner rays through the interior (the footprint's
                // rim), handed on with their corner bits: 0, 1 on row j, 2, 3 on j + 1. The occluder is
                // convex, so the directions through its interior are a convex cone, whose image meets a
                // lattice row in one segment: the hits of row j are one run [la, ra] of lattice points,
                // those of row j + 1 one run [lb, rb]. Corners of a pixel differ only where a run starts
                // or ends: the pixels [min(la, lb) - 1, max(la, lb)] and [min(ra, rb) - 1, max(ra, rb)],
                // or [l - 1, r] where the other row has none (over the row's pixels drawn, [i0, i1]: a
                // segment's part in an interval is one run still). The runs' ends are found from the
                // span's ends inward, so a wide wall costs a few pixels a row, not its width (the corner bytes
                // of every pixel were 6 % of the 3D city's instructions). Rounding could break a run in
                // two at a grazing corner ray; a pixel partial only through such a break is then not
                // handed on, which only leaves it out of the seams' fused depths: less occlusion.
                std::uint8_t* c = m_corners.data();
                auto span = [&](int from, int to) {
                    from = std::max(from, i0);
                    to = std::min(to, i1);
                    for (int i = from; i <= to; ++i) // branch-free: vectorized
                        c[i] = std::uint8_t(std::uint8_t(a[i] >= 0) | std::uint8_t(a[i + 1] >= 0) << 1 |
                                            std::uint8_t(b[i] >= 0) << 2 | std::uint8_t(b[i + 1] >= 0) << 3);
                    for (int i = from; i <= to; ++i)
                        if (c[i] != 0 && c[i] != 15) onPartial(i, j, unsigned(c[i]));
                    return to;
                };
                // A narrow rectangle (the small boxes of a cloud) is done whole: the scans cost more there.
                constexpr int kNarrow = 24;
                const int n0 = i0, n1 = i1 + 1; // lattice points of the row's pixels drawn
                // Four lattice points a step while all four miss (one branch per four: the scans over a
                // box's empty rectangle corners were a tenth of scenes/maze-3d.json's instructions), then
                // one at a time.
                auto firstHit = [&](const double* v) {
                    int k = n0;
                    while (k + 3 <= n1 && !((v[k] >= 0) | (v[k + 1] >= 0) | (v[k + 2] >= 0) | (v[k + 3] >= 0))) k += 4;
                    while (k <= n1 && !(v[k] >= 0)) ++k;
                    return k;
                };
                auto lastHit = [&](const double* v, int from) {
                    int k = n1;
                    while (k - 3 > from && !((v[k] >= 0) | (v[k - 1] >= 0) | (v[k - 2] >= 0) | (v[k - 3] >= 0))) k -= 4;
                    while (k > from && !(v[k] >= 0)) --k;
                    return k;
                };
                if (i1 - i0 < kNarrow) {
                    span(i0, i1);
                } else {
                    const int la = firstHit(a), lb = firstHit(b);
                    const bool hitA = la <= n1, hitB = lb <= n1;
                    if (hitA && hitB) {
                        const int ra = lastHit(a, la), rb = lastHit(b, lb);
                        const int end = span(std::min(la, lb) - 1, std::max(la, lb));
                        span(std::max(std::min(ra, rb) - 1, end + 1), std::max(ra, rb));
                    } else if (hitA || hitB) {
                        const int l = hitA ? la : lb;
                        span(l - 1, lastHit(hitA ? a : b, l));
                    }
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
        // A sphere whose image cannot hold a whole pixel writes nothing (spheres have no partial pixels:
        // no seams): most of a cloud of small spheres at a distance (the clusters' and the large world's
        // refinement pass drew 640 and 270 such spheres and small boxes a frame, for nothing).
        bool noPixel = false;
        const PixelRect rect = rectOf(c, rho, &noPixel);
        if (noPixel) return;
        // Every entry written is at least the sphere's nearest distance |c| - rho (drawRect's row skip).
        drawRect(rect, (len - rho) * (1 - 1e-6), [&](int j, int i0, int i1, double* out) {
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
    bool smallImage = false, noPixel = false;
    const PixelRect rect = rectOf(lo, hi, &smallImage, &noPixel);
    // Too small for the seams (below) and for a whole pixel: the draw would write nothing.
    if (smallImage && noPixel) return;
    const std::uint32_t seam = smallImage ? 0 : addSeamBox(lo, hi);
    // The box is noted in m_depthNote (shadowed()'s candidates) when its image is large: a box hides
    // another in object space only when its image holds the other's, and the notes cost a store per
    // pixel (noting the clusters' small boxes too cost 1.6 % of their instructions, for 1.2 % of |PVS|).
    const std::uint32_t shadowNote =
        seam != 0 && seam < kPolytopeNote && m_seamBoxes[seam - 1].area >= kMinShadowPixels * m_pixelW * m_pixelH ? seam : 0;
    // Every entry written is at least the box's nearest distance (drawRect's row skip).
    const double nearest = std::sqrt(lengthSquared<3>(glm::clamp(Vec3(0.0), lo, hi))) * (1 - 1e-6);
    auto onPartial = [&](int i, int j, unsigned corners) { notePartial(i, j, seam, corners); };
    bool onPlane = false; // the camera on a face plane: 0 / 0 in the slab test below
    for (int a = 0; a < 3; ++a) onPlane = onPlane || lo[a] == 0 || hi[a] == 0;
    if (onPlane) {
        drawRect(rect, nearest, [&](int j, int i0, int i1, double* out) {
            for (int i = i0; i <= i1; ++i) out[i] = entry(i, j);
        }, onPartial, seam != 0, shadowNote);
        return;
    }
    // The same slab test as `entry`, branch-free so that the compiler vectorizes the row (the box draw
    // was the largest cost of the brick traversal: 44% of its instructions on the game world of
    // rgvc_bench_classes). Along the unnormalized corner ray D = forward + x right + y up, a point is
    // s D, and the distance is t = s |D| = s / invLength; the conditions scale by |D| > 0, so they read
    // the same in s, with the 1e-300 kept un-divided (stricter, |D| >= 1). No face plane holds the camera,
    // so every lo / D and hi / D is a number or an infinity of the right sign, never 0 / 0.
    // Three reciprocals, not six quotients, and |D| from its lattice, not a seventh division: the row was
    // bound by the divider. lo * (1 / d) is within 2 ulps of lo / d (and an infinity of the same sign where
    // d is 0 or 1 / d overflows, which only takes the ray out of the test), far inside the relative margin
    // m = 1e-9 that every entry and "passes through" test carries.
    const double m = kRelMargin, pad = kRelMargin * scale;
    const double* xs = m_cornerX.data();
    drawRect(rect, nearest, [&](int j, int i0, int i1, double* out) {
        const double y = m_cornerY[std::size_t(j)];
        const Vec3 b = m_forward + y * m_up, r = m_right;
        const double* len = m_len.data() + std::size_t(j) * std::size_t(m_cols + 1);
        for (int i = i0; i <= i1; ++i) {
            const double x = xs[i];
            const double dx = b.x + x * r.x, dy = b.y + x * r.y, dz = b.z + x * r.z;
            const double rx = 1.0 / dx, ry = 1.0 / dy, rz = 1.0 / dz;
            const double x1 = lo.x * rx, x2 = hi.x * rx, y1 = lo.y * ry, y2 = hi.y * ry, z1 = lo.z * rz, z2 = hi.z * rz;
            const double e = std::max(std::max(std::min(x1, x2), std::min(y1, y2)), std::min(z1, z2));
            const double f = std::min(std::min(std::max(x1, x2), std::max(y1, y2)), std::max(z1, z2));
            const bool ok = (e > 0) & (f - e > m * f + 1e-300);
            const double t = (e * len[i]) * (1 + m) + pad;
            out[i] = ok ? t : -1.0;
        }
    }, onPartial, seam != 0, shadowNote);
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
    // Every entry written is at least the nearest distance of the bounding box (drawRect's row skip).
    const double nearest = std::sqrt(lengthSquared<3>(glm::clamp(Vec3(0.0), lo, hi))) * (1 - 1e-6);
    bool noPixel = false;
    const PixelRect rect = rectOf(lo, hi, nullptr, &noPixel);
    if (noPixel) return; // no whole pixel in its bounding box's image: nothing to write (no seams either)
    // A polytope whose bounding box's image spans kMinShadowPixels or more is kept for shadowed(), with
    // the planes it is drawn with, and noted where it sets the depth (as large boxes are).
    std::uint32_t note = 0;
    if (double(rect.i1 - rect.i0 + 1) * double(rect.j1 - rect.j0 + 1) >= kMinShadowPixels &&
        m_shadowPolytopes.size() + 1 < kPolytopeNote) {
        m_shadowPolytopes.push_back({std::uint32_t(m_shadowN.size()), std::uint32_t(np)});
        m_shadowN.insert(m_shadowN.end(), m_planeN.begin(), m_planeN.end());
        m_shadowC.insert(m_shadowC.end(), m_planeC.begin(), m_planeC.end());
        note = kPolytopeNote | std::uint32_t(m_shadowPolytopes.size());
    }
    // Plane by plane over the row's lattice points, branch-free, so that the compiler vectorizes the
    // points (one point at a time, plane after plane with a branch each, the fill was half of
    // scenes/polytopes-3d.json's instructions through `rgvc cull`). Along lattice row j, D = b + x right
    // with b = forward + y_j up, so n.D = n.b + x (n.right): two dot products per plane and row, one
    // product and sum per point; that differs from n.D by a few ulps, far inside the margin m.
    // Each plane bounds one side only, by the apex's side of it:
    //   - c > 0 (the apex inside the half-space): where n.D > 0 the ray leaves at c / n.D > 0, an exit;
    //     where n.D < 0 its entry bound c / n.D is negative, which never decides (the test needs a
    //     positive entry, and some plane with c <= 0 exists, or the apex would be inside and the draw
    //     skipped above); where n.D = 0 it stays inside that plane;
    //   - c <= 0 (the apex outside, or on it): where n.D < 0 the ray enters at c / n.D >= 0; otherwise it
    //     never reaches the half-space's interior past the apex (an exit <= 0, or parallel outside), and
    //     an entry of +inf fails the test below, as that exit did.
    // So the same verdicts and entries as taking every bound of every plane, with one of the two
    // updates per plane. (c / 0 is an infinity or NaN only where its select drops it.)
    double* enter = m_polyEnter.data();
    double* exit = m_polyExit.data();
    const double* xs = m_cornerX.data();
    drawRect(rect, nearest, [&](int j, int i0, int i1, double* out) {
        const double y = m_cornerY[std::size_t(j)];
        const Vec3 b = m_forward + y * m_up;
        const double* inv = m_invLen.data() + std::size_t(j) * std::size_t(m_cols + 1);
        for (int i = i0; i <= i1; ++i) {
            enter[i] = -kInf;
            exit[i] = kInf;
        }
        for (std::size_t k = 0; k < np; ++k) {
            const double a0 = glm::dot(normals[k], b), a1 = glm::dot(normals[k], m_right), c = offsets[k];
            // n.D is linear along the row: its signs at the row's two ends bound it over the points
            // between (a few ulps apart from the loop's values, which only matters at a sign change,
            // where the loop runs).
            const double d0 = a0 + xs[i0] * a1, d1 = a0 + xs[i1] * a1;
            if (c > 0) {
                if (d0 < 0 && d1 < 0) continue; // no exit through this plane on the row
                for (int i = i0; i <= i1; ++i) {
                    const double den = a0 + xs[i] * a1;
                    exit[i] = den > 0 ? std::min(exit[i], c / den) : exit[i];
                }
            } else {
                if (d0 > 0 && d1 > 0) { // the whole row misses the half-space's interior past the apex
                    for (int i = i0; i <= i1; ++i) out[i] = -1.0;
                    return;
                }
                for (int i = i0; i <= i1; ++i) {
                    const double den = a0 + xs[i] * a1;
                    enter[i] = den < 0 ? std::max(enter[i], c / den) : kInf;
                }
            }
        }
        for (int i = i0; i <= i1; ++i) {
            const double e = enter[i], f = exit[i];
            const bool ok = (e > 0) & (f - e > m * f + 1e-300);
            out[i] = ok ? (e / inv[i]) * (1 + m) + pad : -1.0;
        }
    }, nullptr, false, note);
}

} // namespace rgvc
