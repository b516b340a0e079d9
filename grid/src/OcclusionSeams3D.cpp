// Seam fusion in the occlusion image: a pixel covered by the union of two or three boxes although by
// none of them alone.
//
// Why. A pixel counts for an occluder only when its whole cone passes through that one occluder's
// interior (OcclusionBuffer3D.hpp). Two walls of a closed room meet at an edge; seen from inside, the
// pixels along that edge have some corner rays in one wall and some in the other. The boxes overlap in
// the corner column, so those pixels are covered by one of them as long as the column's image spans a
// pixel, but with a wide field of view (a pixel of 3 degrees at 150 degrees and 128 rows) or far away it
// does not, and an object behind the room's edge shows through the gap. A cone is blocked when it lies in
// the union of the boxes' cones, and for boxes in front of the camera that is a question about convex
// polygons on the image plane: the pixel's square Q lies inside the union of the boxes' images.
//
// The test. Each box drawn this frame keeps its image polygon P (the exact hull of its corners' images,
// after clipping it to z >= zMin, the smallest z of a point of it in view: only those points matter to
// a pixel of the image). A pixel that a box covers only in part remembers the box (two per pixel). When
// a second or third box covers part of it, Q is tested against the union:
//   Q in P1 u P2 u ...  <=>  every piece of Q \ P1 lies in P2 u ...,
// where Q \ P1 is cut into convex pieces Q n H1 n ... n H(k-1) n not Hk over P1's edge half-planes Hk.
// A convex piece lies in a convex polygon when its vertices do. Rounding errs towards "not covered":
// P1's half-planes are shrunk by a margin before the pieces are cut (so the pieces cover more than
// Q \ P1), and a vertex is inside only with the margin to spare.
//
// The depth. Every ray of Q passes through some box of the union, entering it no later than the largest
// entry distance of that box over its part of Q, Q n Pk, a convex polygon. A box's entry distance is
// quasi-convex on the image plane (OcclusionBuffer3D.hpp), so that largest value is at a vertex of
// Q n Pk; rays through vertices on Pk's outline graze the box, and where rounding makes a slab test miss
// there, the box's farthest distance bounds the entry. depth = the largest over the boxes, with the
// relative margin.
//
// Cost: only pixels that two boxes both cover in part, and whose four corner rays each pass through one
// of them (the seams), run the polygon test: a few clips of a quadrilateral by at most 20 half-planes.
#include "rgvc/grid/OcclusionBuffer3D.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace rgvc {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kMaxVertices = 48; // a quadrilateral clipped by at most 20 + 20 half-planes

struct Poly {
    std::array<double, kMaxVertices> x, y;
    int n = 0;
};

/// Signed distance of p from edge e of a seam box's polygon, positive inside (SeamBox::ea, eb, ec: the
/// line through the edge with its unit inward normal, so a test costs two products, where computing it
/// from the vertices took a square root and a division each time). A degenerate edge is -inf everywhere.
/// Rounding: the image-plane coordinates are at most a few units (tan of half the field of view), so the
/// value is off by ~1e-15, far below the tests' margin (1e-9).
double edgeSide(const ImageSeamBox3D& p, int e, double px, double py) {
    return p.ea[e] * px + p.eb[e] * py + p.ec[e];
}

/// Margin of the polygon tests in image coordinates: far above the projection's rounding, far below a pixel.
double marginOf(const ImageFootprint3D& f) {
    double m = 0;
    for (int k = 0; k < f.n; ++k) m = std::max({m, std::abs(f.x[k]), std::abs(f.y[k])});
    return 1e-9 * (1 + m);
}

/// Keeps the part of `in` with side(p) >= 0 (Sutherland-Hodgman), into `out`.
template <class Side> void clip(const Poly& in, Side&& side, Poly& out) {
    out.n = 0;
    for (int k = 0; k < in.n; ++k) {
        const int m = k + 1 == in.n ? 0 : k + 1;
        const double sa = side(in.x[k], in.y[k]), sb = side(in.x[m], in.y[m]);
        if (sa >= 0 && out.n < kMaxVertices) {
            out.x[out.n] = in.x[k];
            out.y[out.n++] = in.y[k];
        }
        if ((sa >= 0) != (sb >= 0) && out.n < kMaxVertices) {
            const double t = sa / (sa - sb);
            out.x[out.n] = in.x[k] + (in.x[m] - in.x[k]) * t;
            out.y[out.n++] = in.y[k] + (in.y[m] - in.y[k]) * t;
        }
    }
}

/// Whether side(p) >= 0 at every vertex of `in`: clip() would then keep `in` as it is (the common case at
/// a seam pixel: of a box polygon's edges, one or two cut the pixel's square, the others miss it).
template <class Side> bool keepsAll(const Poly& in, Side&& side) {
    bool all = true;
    for (int k = 0; k < in.n; ++k) all = all && side(in.x[k], in.y[k]) >= 0;
    return all;
}

/// Every vertex of q inside p's polygon with the margin to spare (so q, convex, lies in it).
bool inside(const Poly& q, const ImageSeamBox3D& p, double margin) {
    for (int e = 0; e < p.poly.n; ++e)
        for (int k = 0; k < q.n; ++k)
            if (!(edgeSide(p, e, q.x[k], q.y[k]) >= margin)) return false;
    return true;
}

/// Whether the convex polygon q lies in the union of the polygons of boxes[0..n).
bool covered(const Poly& q, const ImageSeamBox3D* const* boxes, int n) {
    if (q.n < 3) return true; // nothing of positive area left
    if (n == 0) return false;
    const ImageSeamBox3D& p = *boxes[0];
    const double margin = p.margin;
    if (inside(q, p, margin)) return true;
    if (n == 1) return false;
    // The pieces of q outside p shrunk by the margin: q n H0' n ... n H(k-1)' n not Hk'. The remainder
    // ping-pongs between two buffers (a Poly is 784 bytes; copying it per edge was a third of the test).
    Poly piece, buf[2];
    const Poly* rest = &q;
    for (int e = 0, w = 0; e < p.poly.n && rest->n >= 3; ++e) {
        const auto in = [&](double x, double y) { return edgeSide(p, e, x, y) - margin; };
        // All of the remainder inside this edge's half-plane: its piece outside is empty (at most points
        // on the line itself, inside p by the margin), and the remainder stays.
        if (keepsAll(*rest, in)) continue;
        clip(*rest, [&](double x, double y) { return margin - edgeSide(p, e, x, y); }, piece);
        if (piece.n >= 3 && !covered(piece, boxes + 1, n - 1)) return false;
        clip(*rest, in, buf[w]);
        rest = &buf[w];
        w ^= 1;
    }
    return true;
}

/// The box's margin and edge lines (edgeSide), computed the first time a fusion test needs them: most
/// boxes of a cloud of small ones never meet a second box at a pixel whose corners they share.
void prepareLines(ImageSeamBox3D& b) {
    if (b.linesReady) return;
    b.linesReady = true;
    b.margin = marginOf(b.poly);
    for (int e = 0; e < b.poly.n; ++e) {
        const int m = e + 1 == b.poly.n ? 0 : e + 1;
        const double ax = b.poly.x[e], ay = b.poly.y[e], ex = b.poly.x[m] - ax, ey = b.poly.y[m] - ay;
        const double len = std::sqrt(ex * ex + ey * ey);
        if (len > 0) {
            b.ea[e] = -ey / len;
            b.eb[e] = ex / len;
            b.ec[e] = (ey * ax - ex * ay) / len;
        } else {
            b.ea[e] = b.eb[e] = 0;
            b.ec[e] = -kInf;
        }
    }
}

} // namespace

std::uint32_t OcclusionBuffer3D::addSeamBox(const Vec3& lo, const Vec3& hi) {
    if (m_seamCount >= 0xFFFEu) return 0; // the per-pixel slots hold 16 bits
    // Filled in the slot it will take, kept from earlier frames: a SeamBox is about 900 bytes, and making
    // one zeroed and copying it in cost as much as its footprint on the clusters' boxes. Only the fields
    // read before prepareLines are set; footprintOf writes the polygon.
    if (m_seamCount == m_seamBoxes.size()) m_seamBoxes.emplace_back();
    SeamBox& b = m_seamBoxes[m_seamCount];
    b.lo = lo;
    b.hi = hi;
    const Vec3 far{std::max(-lo.x, hi.x), std::max(-lo.y, hi.y), std::max(-lo.z, hi.z)};
    b.farthest = std::sqrt(lengthSquared<3>(far));
    const double nearest = std::sqrt(lengthSquared<3>(glm::clamp(Vec3(0.0), lo, hi)));
    b.nearest = nearest;
    b.area = 0;
    b.linesReady = false;
    if (!(nearest > 0) || !footprintOf(lo, hi, zMinOf(nearest), b.poly, true) || b.poly.n < 3) return 0;
    for (int k = 0; k < b.poly.n; ++k) { // shoelace
        const int m = k + 1 == b.poly.n ? 0 : k + 1;
        b.area += 0.5 * (b.poly.x[k] * b.poly.y[m] - b.poly.x[m] * b.poly.y[k]);
    }
    // Boxes whose image spans less than kMinSeamPixels pixels are left out: their seams hide next to
    // nothing, and a cloud of small boxes would run the polygon test at every shared pixel. (draw() skips
    // the call for those whose corners' rectangle is already smaller: rectOf's smallImage.)
    if (b.area < kMinSeamPixels * m_pixelW * m_pixelH) return 0;
    return ++m_seamCount; // index + 1
}

void OcclusionBuffer3D::notePartial(int i, int j, std::uint32_t box, unsigned corners) {
    const std::size_t p = std::size_t(j) * std::size_t(m_cols) + std::size_t(i);
    std::uint32_t& slots = m_partial[p];
    // The corner bits carry the image's stamp (high 16 bits; m_noteStamp): a pixel first met in this
    // image starts with empty slots, so neither array is cleared per image (memsets of the slots were
    // 4 % of the 3D city's instructions).
    std::uint32_t& tagged = m_partialCorners[p];
    const std::uint32_t stamp = m_noteStamp << 16;
    if ((tagged & 0xFFFF0000u) != stamp) {
        tagged = stamp;
        slots = 0;
    }
    auto hold = [&](unsigned bits) { tagged = stamp | bits; };
    const std::uint32_t a = slots & 0xFFFFu, b = slots >> 16;
    const unsigned ca = tagged & 0xFu, cb = (tagged >> 4) & 0xFu;
    if (a == box || b == box) return;
    if (a == 0) {
        slots = box;
        hold(corners);
        return;
    }
    // A union can only cover the pixel if every corner ray passes through one of its boxes: most pixels
    // two boxes share in part (the edges of a cloud of small boxes) stop at this test.
    double& depth = m_depth[p];
    double fused;
    // A fused depth is at least each box's nearest distance (every ray enters each box no nearer): a
    // pixel that nearer occluders already cover at that depth gains nothing (the inside of a cluster).
    const double boxNearest = m_seamBoxes[box - 1].nearest;
    if (depth <= std::max(boxNearest, m_seamBoxes[a - 1].nearest) &&
        (b == 0 || depth <= std::max(boxNearest, m_seamBoxes[b - 1].nearest))) {
        if (b == 0) {
            slots |= box << 16;
            hold(ca | (corners << 4));
        }
        return;
    }
    const std::uint32_t pairA[2] = {a, box};
    if ((ca | corners) == 0xFu && fusedDepth(i, j, pairA, 2, fused) && fused < depth) {
        depth = fused;
        ++m_stats.pixelsFused;
    }
    if (b != 0) {
        const std::uint32_t pairB[2] = {b, box}, triple[3] = {a, b, box};
        if ((cb | corners) == 0xFu && fusedDepth(i, j, pairB, 2, fused) && fused < depth) {
            depth = fused;
            ++m_stats.pixelsFused;
        }
        if ((ca | cb | corners) == 0xFu && (ca | corners) != 0xFu && (cb | corners) != 0xFu &&
            fusedDepth(i, j, triple, 3, fused) && fused < depth) {
            depth = fused;
            ++m_stats.pixelsFused;
        }
        // Both slots taken: keep the two boxes with the largest images (a wall's box, rather than the
        // small objects along its edge that were drawn before it).
        const double areaA = m_seamBoxes[a - 1].area, areaB = m_seamBoxes[b - 1].area, area = m_seamBoxes[box - 1].area;
        if (area > std::min(areaA, areaB)) {
            if (areaA < areaB) {
                slots = box | (b << 16);
                hold(corners | (cb << 4));
            } else {
                slots = a | (box << 16);
                hold(ca | (corners << 4));
            }
        }
        return;
    }
    slots |= box << 16;
    hold(ca | (corners << 4));
}

bool OcclusionBuffer3D::fusedDepth(int i, int j, const std::uint32_t* boxes, int n, double& depth) {
    // Only boxes near each other, each of the others within 1.5 voxels of the first (the walls of a room,
    // the parts of a wall, buildings side by side; measured: with touching boxes only, a room of unit-box
    // walls seen at 138 degrees let one object through its corner): boxes far apart cover a pixel's whole
    // square together mostly where one stands in front of the other, and skipping them keeps clouds of
    // small boxes cheap. A heuristic of cost only: skipping a fusion can only leave a pixel open.
    for (int k = 1; k < n; ++k) {
        const SeamBox& a = m_seamBoxes[boxes[0] - 1];
        const SeamBox& b = m_seamBoxes[boxes[k] - 1];
        for (int ax = 0; ax < 3; ++ax) {
            const double tol = 1.5; // [voxel units]
            if (a.lo[ax] > b.hi[ax] + tol || b.lo[ax] > a.hi[ax] + tol) return false;
        }
    }
    Poly q;
    const double x0 = m_cornerX[std::size_t(i)], x1 = m_cornerX[std::size_t(i) + 1];
    const double y0 = m_cornerY[std::size_t(j)], y1 = m_cornerY[std::size_t(j) + 1];
    q.n = 4; // (element by element: a braced list would zero the other 44 entries of each array)
    q.x[0] = x0, q.x[1] = x1, q.x[2] = x1, q.x[3] = x0;
    q.y[0] = y0, q.y[1] = y0, q.y[2] = y1, q.y[3] = y1;
    const SeamBox* parts[3] = {nullptr, nullptr, nullptr};
    for (int k = 0; k < n; ++k) {
        prepareLines(m_seamBoxes[boxes[k] - 1]);
        parts[k] = &m_seamBoxes[boxes[k] - 1];
    }
    if (!covered(q, parts, n)) return false;
    // The largest entry distance of each box over its part of Q (at a vertex of Q n Pk).
    depth = 0;
    for (int k = 0; k < n; ++k) {
        const SeamBox& b = m_seamBoxes[boxes[k] - 1];
        Poly buf[2]; // ping-pong, as in covered()
        const Poly* part = &q;
        for (int e = 0, w = 0; e < b.poly.n && part->n > 0; ++e) {
            const auto side = [&](double x, double y) { return edgeSide(b, e, x, y); };
            if (keepsAll(*part, side)) continue; // (clip would copy it)
            clip(*part, side, buf[w]);
            part = &buf[w];
            w ^= 1;
        }
        for (int v = 0; v < part->n; ++v) {
            const Vec3 d = glm::normalize(m_forward + part->x[v] * m_right + part->y[v] * m_up);
            double tEnter = -kInf, tExit = kInf;
            for (int a = 0; a < 3; ++a) {
                if (d[a] == 0) {
                    if (b.lo[a] > 0 || b.hi[a] < 0) tEnter = kInf;
                    continue;
                }
                double t1 = b.lo[a] / d[a], t2 = b.hi[a] / d[a];
                if (t1 > t2) std::swap(t1, t2);
                tEnter = std::max(tEnter, t1);
                tExit = std::min(tExit, t2);
            }
            const double entry = tEnter <= tExit * (1 + 1e-12) && tEnter >= 0 ? tEnter : b.farthest;
            depth = std::max(depth, std::min(entry, b.farthest));
        }
    }
    depth = depth * (1 + kRelMargin) + kRelMargin * depth;
    return true;
}

} // namespace rgvc
