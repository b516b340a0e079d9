// OrthoOcclusionImage: the conservative occlusion image of an orthographic (parallel-ray) 3D view, the
// parallel-projection counterpart of OcclusionBuffer3D (whose facts are about rays through the camera
// point). Voxel units.
//
// The view (OrthoVolume.hpp): rays r(u, v) = origin + u right + v up + t f, t >= 0 (t is the depth), for
// (u, v) in the view box's cross-section [-W, W] x [-H, H]. The image cuts the cross-section into
// cols x rows pixels; pixel P holds a depth z(P) with the fact
//
//   every ray r(u, v), (u, v) in the closed pixel P, runs inside the interior of some occluder from a
//   depth <= z(P) on, up to the occluder's far side           (z = +inf: nothing known)
//
// which is what hides a point q behind it: q on a ray of P at depth t_q > z(P) has the segment from its
// foot on the near plane to q blocked (its part just past the occluder's entry lies in the occluder's
// interior; q inside the occluder is hidden as well). The contract's visibility (segment from q back
// along -f to the near plane, the other objects' interiors) then calls q hidden.
//
// Drawing an occluder B (a convex occluder model, or a box of opaque voxels, all inside some object's
// interior once shrunk by the slack): the entry depth e(u, v) = min {t >= 0 : r(u, v, t) in B} is a
// convex function of (u, v) over the projection of B (the fibres of the convex set B n {t >= 0}), and the
// projection is convex. So P lies entirely in the projection iff its 4 corner rays hit B, and then the
// largest entry depth over P is at a corner: z(P) = min(z(P), max of the 4 corner entries). This is seed
// 004 §4.4's occlusion shadow for parallel rays: the shadow of B is the prism of its projection, starting
// at its front surface, and only pixels the prism covers entirely carry it (§4.4: conservative
// rasterization of the shadow polygon's inner part). Entries are computed on the (cols + 1) x (rows + 1)
// corner lattice of the occluder's footprint once, shared by neighbouring pixels. B is shrunk by `slack`
// first, so a corner ray grazing B (a tangent ray, not blocked) never counts.
//
// Testing a box (a brick node, an object's bounds): hidden iff every pixel P its projection touches (the
// outer footprint, grown by the slack) has z(P) < L(P) - slack, L(P) a lower bound of the depth of the
// box's points on P's rays. A ray meets the box no earlier than it crosses each of the box's near face
// planes (x_a = lo_a where f_a > 0, hi_a where f_a < 0), and that depth is linear in (u, v); so
// L(P) = max(nearest depth of the box, max over the axes of the smallest of those depths over P's 4
// corners). A ball: pixels of its disc only, L(P) = depth of the centre - sqrt(r^2 - d^2), d the
// distance from the disc's centre to P (the nearest point of the ball on a ray at distance d from its
// centre). Both are much tighter than the box's single nearest depth for a view at an angle. Its points outside
// the cross-section are outside the view box (invisible by definition); a box entirely outside the
// cross-section is reported hidden. Strict < plus the slack keep an object's own occluder (whose entries
// are never nearer than the object's own nearest point) from hiding it.
//
// Seams (the analogue of OcclusionSeams3D.cpp for parallel rays). Two boxes meeting along a face or an
// edge (two walls of a room, two runs of opaque voxels) each cover the pixels along their shared outline
// only in part. A box's image is the convex polygon P spanned by its 8 projected corners; a pixel whose
// square Q one box covers in part remembers the box (one slot per pixel, the latest); when another box
// covers Q in part, Q is tested against the union: Q in P1 u P2 iff every convex piece of Q \ P1 (Q cut
// by P1's edge half-planes: Q n H1 n ... n H(k-1) n not Hk) has its vertices in P2. P1 is shrunk by a
// margin before the cut (the pieces then cover more than Q \ P1) and a vertex is in P2 only with the
// margin to spare. Every ray of Q then passes through the interior of one of the two boxes, entering it
// no later than that box's largest entry depth over its part of Q (Q n Pk, a convex polygon; the entry
// is convex, so the largest is at a vertex; where a grazing vertex's ray misses by rounding, the box's
// farthest depth bounds it): z = the larger of the two.
//
// Sound in any drawing order (every z is true when written); the order only decides how much is hidden
// when a box is tested. Cost: a draw O(footprint pixels); a test O(footprint pixels), stopping at the
// first pixel that does not hide. Nothing is allocated after begin() has sized the image.
#pragma once

#include "rgvc/grid/OrthoVolume.hpp"
#include "rgvc/grid/Shapes.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace rgvc {

class OrthoOcclusionImage {
public:
    /// [Limit] pixels per axis of the image.
    static constexpr int kMaxPixels = 256;

    struct Stats {
        std::uint64_t occludersDrawn = 0; ///< draws that covered at least one pixel entirely
        std::uint64_t pixelsWritten = 0;  ///< pixels whose depth a draw lowered
        std::uint64_t tests = 0;          ///< hidden() calls
        std::uint64_t seamPixels = 0;     ///< pixels covered by the union of two boxes (the seam test)
    };

    /// Starts an empty image over the view's cross-section, about one pixel per `pixelSize` voxels per
    /// axis (at least 8, at most kMaxPixels). Returns false (and draws and hides nothing) for a
    /// degenerate view.
    bool begin(const OrthoVolume<3>& view, double pixelSize = 1.0);

    /// Draws a convex occluder (voxel units): a box shrunk by slack, a ball by radius - slack, a
    /// polytope by its planes moved in by its tolerance + slack.
    void draw(const Shape<3>& occluder, double slack);
    /// Draws the box lo..hi (voxel units) shrunk by slack.
    void drawBox(const Vec3& lo, const Vec3& hi, double slack) { draw(Shape<3>(Box<3>{lo, hi}), slack); }

    /// Whether every point of the box lo..hi (grown by slack) that lies in the view's cross-section is
    /// hidden (see the top of this file).
    bool hiddenBox(const Vec3& lo, const Vec3& hi, double slack);
    /// Same for the ball (centre, radius) grown by slack.
    bool hiddenBall(const Vec3& centre, double radius, double slack);

    /// The box's depth range along f (lower bound of the nearest, upper bound of the farthest).
    void depthRange(const Vec3& lo, const Vec3& hi, double& nearest, double& farthest) const;

    const Stats& stats() const { return m_stats; }
    /// [Voxel units] the larger side of a pixel.
    double pixelSize() const { return std::max(m_du, m_dv); }
    int cols() const { return m_cols; }
    int rows() const { return m_rows; }
    /// Pixel depth (for tests and pictures): +inf where nothing is known.
    double depthAt(int col, int row) const { return m_depth[std::size_t(row) * std::size_t(m_cols) + std::size_t(col)]; }

private:
    /// The box's outer footprint in pixels, clipped to the image; false when it misses the image.
    bool footprint(const Vec3& lo, const Vec3& hi, double grow, int& c0, int& c1, int& r0, int& r1) const;
    /// Entry depth of the ray at image point (u, v) into the shape; +inf when it misses.
    double entryAt(const Shape<3>& s, double slack, double u, double v) const;
    double entry(const Shape<3>& s, double slack, int i, int j) const { return entryAt(s, slack, m_u0 + i * m_du, m_v0 + j * m_dv); }
    /// A drawn box, kept for the seam test: the box (shrunk), its image polygon (counter-clockwise),
    /// its farthest depth.
    struct Drawn {
        Box<3> box;
        double pu[8], pv[8];
        int n = 0;
        double farthest = 0;
    };
    /// Whether pixel (col, row) lies in the union of the two drawn boxes' images; its depth bound if so.
    bool unionCovers(const Drawn& a, const Drawn& b, int col, int row, double& depth) const;
    /// Largest entry depth of box d over Q n (its image), Q the pixel's square.
    double largestEntry(const Drawn& d, int col, int row) const;

    OrthoVolume<3> m_view;
    Vec3 m_origin{0.0}, m_f{0.0}, m_right{0.0}, m_up{0.0};
    double m_u0 = 0, m_v0 = 0, m_du = 1, m_dv = 1; // lattice point (i, j) = (m_u0 + i m_du, m_v0 + j m_dv)
    int m_cols = 0, m_rows = 0;
    std::vector<double> m_depth;   // rows x cols
    std::vector<double> m_lattice; // scratch: corner entries of one draw
    std::vector<Drawn> m_drawn;    // this image's boxes (the seam test), reused
    std::vector<std::int32_t> m_partial; // per pixel: the last box covering it in part (index in m_drawn), -1
    double m_margin = 0;           // polygon margin in image units
    Stats m_stats;
};

} // namespace rgvc
