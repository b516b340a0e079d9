// A conservative occlusion buffer over the camera's image: the refinement stage after the 3D grid
// traversal (an object-space test in the spirit of hierarchical occlusion maps and masked software
// occlusion culling; seed 001's CHC refines the grid's PVS with GL queries in the same place).
//
// Why a second stage. The grid can only use voxels *entirely* inside an object as occluders (O, §5.1),
// so spheres smaller than about two voxels occlude nothing, and a cloud of them, which hides most of
// what lies behind it, hides nothing in H. The buffer samples occlusion at pixel resolution instead,
// and fuses any number of occluders, whatever their size against a voxel.
//
// The image. Directions of the view are forward + x right + y trueUp, |x| <= tanHalfWidth,
// |y| <= tanHalfHeight (ViewFrustum). The buffer covers that rectangle, enlarged by a relative 1e-6 so
// that rounding of the frustum's basis never puts a direction of the view outside it, with rows x cols
// pixels. Pixel (i, j) is the cone of rays through the rectangle [x_i, x_i+1] x [y_j, y_j+1] of the
// image plane at distance 1; its four corner rays span it.
//
// Occluders. depth(P) is an upper bound of the distance at which every ray of pixel P has entered the
// interior of some occluder:
//   - a pixel counts for an occluder only if its four corner rays pass through the occluder's interior.
//     The rays from an outside point through the interior of a convex body form a convex cone, and the
//     pixel's cone is the convex hull of its corner rays, so then every ray of the pixel does;
//   - the distance at which a ray enters the body is largest at a corner ray. For a sphere it grows
//     with the ray's angle to the centre direction (d/dθ of |c|cos θ - sqrt(ρ² - |c|² sin² θ) is
//     |c| sin θ (|c| cos θ / sqrt(...) - 1) >= 0 when |c| > ρ), and {angle <= β} is a convex cone, so
//     the largest angle over the pixel is at a corner. For a box the entry distance is a maximum of
//     h |x| / (n.x) over its near planes, each quasi-convex on the image plane (its sublevel sets are
//     second-order cones), so again the maximum is at a corner. A convex polytope (hull, oriented box) is
//     the same with any number of planes (drawPolytope).
//   So depth(P) = min over occluders covering P of max over P's corners of the entry distance.
// Occludees. An object is hidden when every pixel its image can touch has depth(P) < its nearest
// distance from the camera: every ray towards one of its points then passes through an occluder's
// interior before reaching it, so the open segment to that point meets that interior (the contract's
// definition of hidden). The image's pixels are bounded by an outer rectangle: exact tangent lines
// for a sphere entirely in front of the camera, the projected corners for a box entirely in front,
// and the whole image otherwise. A polytope is tested as its bounding box (which contains it).
//
// Order. Testing objects nearest first and drawing each one that stays is the same as drawing all
// before testing: an object can only be hidden by pixels whose depth is below its nearest distance,
// and an object whose nearest distance is larger enters only at larger depths. A hidden object is not
// drawn: its own pixels already have a smaller depth.
//
// Rounding. Every corner test and distance carries a relative margin (kRelMargin) on the safe side;
// callers shrink occluders and grow occludees by their conversion slack (GridGeometry) and the
// camera's (ViewFrustum::slack), which covers an apex off by that much: moving the camera by s is
// moving every object by at most s.
//
// Units: voxel units (the grid's local coordinates), like ViewFrustum.
#pragma once

#include "rgvc/grid/Shapes.hpp"
#include "rgvc/grid/ViewFrustum.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace rgvc {

struct OcclusionBufferStats {
    std::uint32_t occludersDrawn = 0; ///< objects drawn into the buffer
    std::uint32_t tested = 0;         ///< hidden() calls
    std::uint32_t hidden = 0;         ///< of those, answered true
    std::uint64_t pixelsCovered = 0;  ///< pixels an occluder covered (depth lowered or not)
    std::uint64_t pixelsFused = 0;    ///< pixels covered only by the union of two or three boxes (seams)
    std::uint32_t shadowed = 0;       ///< of the hidden, proved by a box occluder's shadow (hidden())
};

/// The image of a box seen by an OcclusionBuffer3D: a convex polygon in image coordinates (counter-
/// clockwise; n = 0: its pixel rectangle only), the pixels it can touch, and the padding that covers the
/// projection's rounding. (Internal to the buffer; public so its implementation files can share it.)
struct ImageFootprint3D {
    struct Rect {
        int i0, i1, j0, j1; // inclusive pixel ranges; empty when i0 > i1
    };
    static constexpr int kMaxVertices = 20;
    Rect rect{0, -1, 0, -1};
    int n = 0;
    double padX = 0, padY = 0;
    double x[kMaxVertices], y[kMaxVertices];
    bool covered = false; // footprintOf with coveredBelow: the rectangle alone proved the test (n = 0)
    // footprintOf with cornerWitnesses: the box's corners were read as witnesses (cornersRead), and one
    // of them was seen (cornerSeen: canHide false there, so the occludee test cannot pass).
    bool cornersRead = false, cornerSeen = false;
};

/// A box drawn into the image this frame, kept for seam fusion (OcclusionSeams3D.cpp). (Internal to the
/// buffer; public so its implementation files can share it.)
struct ImageSeamBox3D {
    Vec3 lo, hi;      // apex-relative, as drawn
    double farthest;  // [voxel units] the farthest distance of the box: a bound on any entry distance
    double nearest;   // [voxel units] its nearest distance: no entry distance is smaller
    double area;      // of its image polygon (which boxes a pixel keeps)
    ImageFootprint3D poly; // its image (exact hull of the clipped box, counter-clockwise, no padding)
    bool linesReady;  // margin, ea, eb and ec computed (the first fusion test that needs them)
    double margin;    // of the polygon tests (OcclusionSeams3D.cpp)
    // Edge k of poly (vertex k to k + 1) as a line: ea x + eb y + ec is the signed distance of (x, y)
    // from it, positive inside. Computed once per box: the tests evaluate it for every vertex of
    // every clipped piece.
    double ea[ImageFootprint3D::kMaxVertices], eb[ImageFootprint3D::kMaxVertices], ec[ImageFootprint3D::kMaxVertices];
};

/// Scratch of the per-pixel maximum of a dot product over a pixel's rays (PixelMaxDot in
/// OcclusionExact3D.cpp). (Internal to the buffer; public so its implementation files can share it.)
struct ImageMaxDotScratch {
    std::vector<int> colRow;
    std::vector<double> colVal, rowA, rowB, out;
};

class OcclusionBuffer3D {
public:
    /// [Limit] rows of a buffer; columns follow the aspect, also at most this.
    static constexpr int kMaxExtent = 2048;

    /// Starts a frame over the image of `view`, every pixel open (depth +inf).
    /// @param rows  [Limit] 1..kMaxExtent; columns = rows * aspect, rounded, clamped to 1..kMaxExtent.
    /// @return false (and the buffer hides nothing) when the view is too extreme for a useful image:
    ///         tanHalfWidth or tanHalfHeight outside [1e-4, 1e4] (fov within ~0.01 degree of 0 or 180).
    bool begin(const ViewFrustum& view, int rows);
    /// Starts a frame over the view of `coarse` (begun and drawn this frame) with factor x factor pixels
    /// for each of its pixels, each starting at its coarse pixel's depth (a true bound for every ray of
    /// the finer pixel, whose cone lies in the coarse one's). Occluders already drawn into `coarse` need
    /// not be drawn again; drawing them again only sharpens their outline.
    /// @param factor  [Limit] >= 1, with coarse.rows() * factor and coarse.cols() * factor <= kMaxExtent.
    /// @return false (and the buffer hides nothing) when `coarse` is not active or the limit is exceeded.
    bool beginRefined(const OcclusionBuffer3D& coarse, int factor);

    /// Nearest distance [voxel units] from the camera to the shape grown by `grow` (0 when the camera
    /// is inside it): the sort key of the front-to-back order.
    double nearestDistance(const Shape<3>& shape, double grow) const;

    /// Conservative: true only if no point of the shape grown by `grow` [voxel units, >= 0] that lies in
    /// the view is visible past the occluders drawn so far.
    bool hidden(const Shape<3>& shape, double grow) { return hidden(shape, grow, nearestDistance(shape, grow)); }
    /// As above, with nearest = nearestDistance(shape, grow) already known (the front-to-back sort key).
    /// @param refine  whether a box whose one footprint fails is tested further, pixel by pixel (or, for a
    ///                ball reaching behind the camera, split into parts; OcclusionTests3D.cpp): false for
    ///                callers that test finer boxes themselves when a coarse one fails
    ///                (clearHiddenVoxels), which would pay for the refinement twice.
    bool hidden(const Shape<3>& shape, double grow, double nearest, bool refine = true);
    /// The one-footprint test of a box, without the refinement (see refine above).
    bool hiddenCoarse(const Box<3>& box, double grow) {
        return hidden(Shape<3>(box), grow, nearestDistance(Shape<3>(box), grow), false);
    }

    /// Draws the shape shrunk by `shrink` [voxel units, >= 0] as an occluder (nothing when the shrunk
    /// shape is empty or holds the camera).
    void draw(const Shape<3>& shape, double shrink);
    /// As above, over the pixels of `clip` only (inclusive ranges, as pixelRect gives them): an occluder
    /// drawn again for one occludee needs only the pixels that occludee's test reads. Drawing fewer
    /// pixels is always sound (they only keep a larger depth).
    void draw(const Shape<3>& shape, double shrink, const ImageFootprint3D::Rect& clip) {
        m_clip = clip;
        draw(shape, shrink);
        m_clip = kNoClip;
    }

    /// Whether an occluder of bounding radius `radius` whose nearest point is `nearest` away [voxel units]
    /// spans at least `pixels` pixels across: smaller ones cover too little of the image to hide a block
    /// of the traversal, and the brick traversal leaves them to the refinement pass (which draws
    /// everything). A cost heuristic only: drawing less can only hide less.
    bool spans(double radius, double nearest, double pixels) const {
        return m_active && 2 * radius >= pixels * std::min(m_pixelW, m_pixelH) * std::max(nearest, 1e-300);
    }
    /// Whether some occluder drawn so far covers the pixel showing point p [voxel units, the grid's local
    /// coordinates] nearer than `limit` (a point outside the image reads the
    /// border pixel nearest to it; one behind the camera answers true: unknown). A
    /// cost heuristic for callers deciding whether to draw more (refineWithBuffer), never a verdict.
    bool coveredNearer(const Vec3& p, double limit) const;
    /// The pixels the image of the shape grown by `grow` [voxel units] can touch, as inclusive column and
    /// row ranges (empty when i0 > i1): its outer rectangle when it lies in front of the camera, else the
    /// whole image (polytopes and meshes by their bounding box). For cost heuristics (which occluders may
    /// matter to which occludee, refineWithBuffer); occludee tests use the exact footprints.
    ImageFootprint3D::Rect pixelRect(const Shape<3>& shape, double grow) const;
    int rows() const { return m_rows; }
    int cols() const { return m_cols; }
    /// Depth of pixel (col, row), +inf where no occluder covers it (for pictures and tests).
    double depthAt(int col, int row) const { return m_depth[std::size_t(row) * std::size_t(m_cols) + std::size_t(col)]; }
    const OcclusionBufferStats& stats() const { return m_stats; }
    /// Pixels some occluder covers (a finite depth), of rows() x cols(). One pass over the image.
    std::size_t coveredPixels() const;

private:
    /// Relative margin of every distance and corner test, far above the rounding of a few dozen double
    /// operations (~1e-15) and far below anything that changes a verdict in practice.
    static constexpr double kRelMargin = 1e-9;
    /// Relative enlargement of the image and of occludee rectangles: the frustum's basis and the
    /// projections are rounded, and a direction of the view must never fall outside its pixel rectangle.
    static constexpr double kImageMargin = 1e-6;

    using PixelRect = ImageFootprint3D::Rect;
    /// begin() and beginRefined() after the view, extent and depths are set: the lattice and the seams.
    void startImage();
    PixelRect wholeImage() const { return {0, m_cols - 1, 0, m_rows - 1}; }
    /// Pixels whose cones can hold a direction with image coordinates in [x0, x1] x [y0, y1].
    /// noPixel (optional): set when no pixel has all four corners (lattice points) in the range, so a
    /// shape whose image lies in it covers no pixel whole (false when the range is not a number).
    PixelRect pixelsOf(double x0, double x1, double y0, double y1, bool* noPixel = nullptr) const;
    /// Outer rectangle of the image of a sphere / box (relative to the apex). A shape reaching behind the
    /// camera (or nearly into its plane) takes the rectangle of its part in view: the box (a sphere's
    /// bounding box) clipped to z >= zMinOf(its nearest distance) (clippedRect); the whole image when the
    /// camera is inside it.
    /// noPixel (optional): as pixelsOf's, for the rectangle (a draw of the shape covers no pixel whole).
    PixelRect rectOf(const Vec3& c, double radius, bool* noPixel = nullptr) const;
    /// smallImage (optional): set when the box lies in front of the camera and its image (the hull of its
    /// corners' images) spans less than kMinSeamPixels pixels, so addSeamBox would keep nothing of it.
    /// noPixel as above.
    PixelRect rectOf(const Vec3& lo, const Vec3& hi, bool* smallImage = nullptr, bool* noPixel = nullptr) const;
    /// The images of the vertices of the box lo..hi clipped to the half-space z >= zMin (its corners with
    /// z >= zMin, and the points where its edges cross z = zMin), from its corners' camera coordinates
    /// (boxCorners) into px, py (20 each); returns their count, 0 when no point of the box has z >= zMin.
    static int clippedVertices(const double (&xc)[8], const double (&yc)[8], const double (&zc)[8], double zMin,
                               double* px, double* py);
    /// The pixels of the box lo..hi clipped to z >= zMinOf(its nearest distance): every pixel whose cone
    /// holds a direction to a point of the box in view (footprintOf's rectangle, without its polygon). The
    /// whole image when the camera is in the closed box; empty (i0 > i1) when no point of it is in view.
    PixelRect clippedRect(const Vec3& lo, const Vec3& hi, const double (&xc)[8], const double (&yc)[8], const double (&zc)[8]) const;
    /// Boxes whose image spans fewer pixels are not kept for seam fusion (addSeamBox).
    static constexpr double kMinSeamPixels = 4;
    using Footprint = ImageFootprint3D;
    /// Camera coordinates (x right, y up, z forward) of the corners of the box lo..hi (apex-relative),
    /// corner k with bit 0: x at hi, bit 1: y at hi, bit 2: z at hi (footprintOf, rectOf). A corner's
    /// coordinate on a camera axis is a sum of one product per box axis, so 18 products and two additions
    /// per corner and axis do what three dot products per corner (72 products) did.
    void boxCorners(const Vec3& lo, const Vec3& hi, double (&xc)[8], double (&yc)[8], double (&zc)[8]) const {
        const double rx[2] = {lo.x * m_right.x, hi.x * m_right.x}, ry[2] = {lo.y * m_right.y, hi.y * m_right.y},
                     rz[2] = {lo.z * m_right.z, hi.z * m_right.z};
        const double ux[2] = {lo.x * m_up.x, hi.x * m_up.x}, uy[2] = {lo.y * m_up.y, hi.y * m_up.y},
                     uz[2] = {lo.z * m_up.z, hi.z * m_up.z};
        const double fx[2] = {lo.x * m_forward.x, hi.x * m_forward.x}, fy[2] = {lo.y * m_forward.y, hi.y * m_forward.y},
                     fz[2] = {lo.z * m_forward.z, hi.z * m_forward.z};
#pragma GCC unroll 8 // (at -O2 GCC otherwise keeps the index arithmetic)
        for (int k = 0; k < 8; ++k) {
            const int a = k & 1, b = (k >> 1) & 1, c = k >> 2;
            xc[k] = rx[a] + ry[b] + rz[c];
            yc[k] = ux[a] + uy[b] + uz[c];
            zc[k] = fx[a] + fy[b] + fz[c];
        }
    }
    /// The footprint of the box (apex-relative) clipped to z >= zMin (z along forward). False when no
    /// point of the box has z >= zMin (none is in view).
    /// forSeams: always compute the polygon (otherwise a footprint of 2 x 2 pixels or less keeps n = 0).
    /// coveredBelow: when > 0 and every pixel of the footprint's rectangle has a depth below it, stops with
    /// the rectangle (n = 0) and f.covered set: an occludee test that the rectangle passes needs no polygon.
    /// cornerWitnesses (with coveredBelow > 0: the box is the occludee tested, and coveredBelow its nearest
    /// distance): the box's corners are read as witnesses (f.cornersRead) before its polygon, unless its
    /// rectangle spans 2 x 2 pixels or less or is covered; when one is seen (f.cornerSeen) it stops there
    /// and the test fails.
    bool footprintOf(const Vec3& lo, const Vec3& hi, double zMin, Footprint& f, bool forSeams = false,
                     double coveredBelow = 0, bool cornerWitnesses = false) const;
    /// The columns of pixel row j the footprint can touch; false when none.
    bool rowSpan(const Footprint& f, int j, int& i0, int& i1) const;
    /// The columns of pixel row j the footprint can touch, from the first to the last pixel not covered
    /// nearer than `nearest`; false when none is left (the row passes every per-pixel test). The
    /// rectangle's row is trimmed first, so a covered row costs no span. (Inline, defined in
    /// OcclusionRowSpans3D.hpp, for the two files that call it: out of line it cost the 3D city 0.6 %.)
    inline bool openRowSpan(const Footprint& f, int j, double nearest, int& i0, int& i1) const;
    /// Occludee tests (OcclusionBuffer3D.cpp): the smallest z of a point in view at distance >= nearest;
    /// every pixel of a footprint covered nearer than `nearest`; whether the pixel of point p (apex-relative)
    /// is covered nearer than p (else no part holding p can be hidden); the 8 halves of a box tested one
    /// by one, `levels` deep.
    double zMinOf(double nearest) const;
    bool scanFootprint(const Footprint& f, double nearest) const;
    /// (Inline, defined in OcclusionTests3D.cpp, the one file that calls it.)
    inline bool canHide(const Vec3& p) const;
    /// canHide for a point in front of the camera already projected: image coordinates (x, y), squared
    /// distance d2 from the apex. `pixel` as below.
    inline bool canHideAt(double x, double y, double d2, std::size_t& pixel) const;
    /// As canHide; `pixel` gets the index of p's pixel when it has one (else it is left as it was).
    inline bool canHide(const Vec3& p, std::size_t& pixel) const;
    /// The exact per-pixel test of a sphere (apex-relative centre, grown radius) wholly in front of the
    /// camera: every pixel showing part of it covered nearer than that part (OcclusionExact3D.cpp).
    bool hiddenBall(const Vec3& c, double radius, double nearest);
    /// The exact per-pixel test of a box (apex-relative, grown) over its footprint f: every pixel that
    /// shows part of it covered nearer than that part (OcclusionExact3D.cpp).
    bool hiddenBoxExact(const Vec3& lo, const Vec3& hi, double nearest, const Footprint& f);
    ImageMaxDotScratch m_maxDot[3]; // hiddenBall, hiddenBoxExact: one per vector tested at once
    /// centre, radius: the sphere whose bounding cube lo..hi is (parts missing it are skipped), or null.
    bool hiddenParts(const Vec3& lo, const Vec3& hi, int levels, const Vec3* centre, double radius) const;
    /// 1 / |forward + x_i right + y_j up| = 1 / sqrt(1 + x_i^2 + y_j^2) for lattice corner (i, j).
    double invLength(int i, int j) const { return m_invLen[std::size_t(j) * std::size_t(m_cols + 1) + std::size_t(i)]; }
    /// Draws an occluder over rectangle r. fillRow(j, i0, i1, out) writes out[i] for i in [i0, i1]: the entry
    /// distance along the unit ray through lattice corner (i, j), or a negative value when that ray misses
    /// the occluder's interior.
    /// onPartial(i, j, corners) is called for the pixels some but not all of whose corner rays pass through
    /// the occluder's interior, with a bit per such corner, when `partials` (a null type for none: spheres).
    /// draw() for a convex polytope: the slab test over its planes (OcclusionBuffer3D.cpp).
    void drawPolytope(const ConvexPolytope& p, double shrink);
    std::vector<Vec3> m_planeN;   // drawPolytope's apex-relative planes (kept: no allocation per draw)
    std::vector<double> m_planeC;
    std::vector<double> m_polyEnter, m_polyExit; // drawPolytope: per lattice point of a row, the bounds so far
    template <class FillRow, class OnPartial>
    /// nearest: a lower bound of every entry distance fillRow writes (rows that cannot be lowered are skipped).
    /// note: the occluder's note (m_depthNote; 0: none), written where it sets the depth.
    void drawRect(const PixelRect& r, double nearest, FillRow&& fillRow, OnPartial&& onPartial, bool partials = false,
                  std::uint32_t note = 0);
    /// Whether the open segment from the apex to every point of the box lo..hi (apex-relative) meets the
    /// interior of the convex occluder (box or polytope) that set the depth of the pixel (m_depthNote):
    /// an object-space proof that the box is hidden, exact where the image's pixels are coarse (a wall seen
    /// at a grazing angle). OcclusionTests3D.cpp derives it.
    /// pixel: the index of that pixel (row-major), as canHide found it.
    bool shadowed(const Vec3& lo, const Vec3& hi, std::size_t pixel) const;
    /// Boxes and polytopes whose image spans fewer pixels are not noted in m_depthNote (shadowed()'s candidates).
    static constexpr double kMinShadowPixels = 16;

    // Seam fusion (OcclusionSeams3D.cpp): boxes drawn this frame with their image polygons, and per pixel
    // the first two boxes that covered only part of it.
    using SeamBox = ImageSeamBox3D;
    std::uint32_t addSeamBox(const Vec3& lo, const Vec3& hi);
    void notePartial(int i, int j, std::uint32_t box, unsigned corners);
    bool fusedDepth(int i, int j, const std::uint32_t* boxes, int n, double& depth);
    std::vector<SeamBox> m_seamBoxes; // the first m_seamCount are this frame's (the rest: storage kept)
    std::uint32_t m_seamCount = 0;
    std::vector<std::uint32_t> m_partial; // per pixel: 16-bit box index + 1, twice (0: none)
    // Per pixel: the corner rays each of those boxes holds (4 bits each), and in the high 16 bits the
    // stamp of the image that wrote them (another stamp: both slots empty).
    std::vector<std::uint32_t> m_partialCorners;
    // Per pixel: the large convex occluder that last set its depth (low 16 bits: a seam box index + 1
    // below kPolytopeNote, kPolytopeNote | an m_shadowPolytopes index + 1 above; 0: none), under the stamp
    // of the image (high 16 bits; another stamp: none).
    std::vector<std::uint32_t> m_depthNote;
    std::uint32_t m_noteStamp = 0;
    static constexpr std::uint32_t kPolytopeNote = 0x8000;
    // Polytopes drawn this frame with a large image, for shadowed(): their planes (apex-relative, moved
    // in as drawn) in m_shadowN / m_shadowC from `first`.
    struct ShadowPolytope {
        std::uint32_t first, count;
    };
    std::vector<ShadowPolytope> m_shadowPolytopes;
    std::vector<Vec3> m_shadowN;
    std::vector<double> m_shadowC;

    Vec3 m_apex{0.0}, m_forward{0.0}, m_right{0.0}, m_up{0.0};
    double m_halfW = 0, m_halfH = 0, m_pixelW = 0, m_pixelH = 0;
    double m_invPixelW = 0, m_invPixelH = 0; // 1 / m_pixelW, 1 / m_pixelH: pixel indices by products
    int m_rows = 0, m_cols = 0;
    bool m_active = false;
    std::vector<double> m_depth; // rows x cols
    // The lattice of pixel corners on the image plane: x_i, y_j and the inverse lengths of their rays.
    // They depend on the fov, aspect and rows only, not on the camera's position or orientation, so they
    // are kept while those stay (a camera walk changes neither).
    std::vector<double> m_cornerX, m_cornerY, m_invLen, m_len; // m_len: |forward + x right + y up|
    double m_latticeW = -1, m_latticeH = -1;
    static constexpr ImageFootprint3D::Rect kNoClip{0, 1 << 30, 0, 1 << 30};
    ImageFootprint3D::Rect m_clip = kNoClip; // drawRect draws only these pixels (draw with a clip)
    std::vector<double> m_rowA, m_rowB; // drawRect's corner entries of two lattice rows
    std::vector<std::uint8_t> m_corners; // drawRect: per pixel of a row, which corner rays hit (4 bits)
    OcclusionBufferStats m_stats;
};

} // namespace rgvc
