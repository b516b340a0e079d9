// A conservative 1D occlusion buffer over the camera's view wedge: the 2D counterpart of
// OcclusionBuffer3D, a refinement stage after the 2D grid traversal. The grid's PVS objects, nearest
// first, are tested against the buffer of the nearer ones and drawn into it when they stay.
//
// Why a second stage. As in 3D, the grid can only use voxels *entirely* inside an object as occluders,
// so circles smaller than about two voxels occlude nothing; the buffer samples occlusion per angular
// bin instead, whatever an occluder's size against a voxel. Different bins can be covered by different
// occluders (that is fusion at bin resolution); one bin is covered by one occluder (no fusion inside it).
//
// Everything is apex-relative: the camera is the origin O, and a direction is an angle. Units: voxel
// units (the grid's local coordinates) for lengths, radians for angles.
//
// Bins. Angles are measured counter-clockwise from the wedge's direction. The buffer covers the angle
// range [-H, H], H = fov/2 (1 + 1e-9) + 1e-10 (a hair wider than the wedge, so that rounding of the
// wedge's edges never puts a direction of the view outside it), or the whole circle (H = pi) when the
// wedge is full or H would reach pi. It is split into N equal bins of width w = 2H / N; N is raised, if
// needed, until w <= 3 pi / 4 (so a full circle has at least 3 bins). Boundary ray b (b = 0..N) is the
// unit vector at angle -H + b w, computed once per begin(); for the full circle ray N is ray 0 (the very
// same vector), so the bins wrap around. Bin b is the closed arc of directions counter-clockwise from
// computed ray b to computed ray b+1: the bins therefore tile the buffer's range exactly, whatever the
// rounding of the rays, and each is an arc narrower than pi.
//
// Occluders. For a convex body K (circle, box, convex polygon; shrunk first) not containing O, let
// f(u) = inf{t > 0 : t u in int K} be the entry distance along the ray of direction u (+inf when the ray
// misses int K), and D = {u : f(u) < inf}.
//   (1) For any c, the set {u : f(u) < c} is the set of directions of points of int K ∩ B(O, c) (open
//       disc), a convex open set not containing O, so it is an open arc of width <= pi. (c = inf: D.)
//   (2) An arc A narrower than pi whose two end rays lie in an arc I of width <= pi lies inside I: else A
//       meets the complement of I, a connected arc of width >= pi holding neither end of A, so A contains
//       that whole complement and would be wider than pi.
//   So when both boundary rays of bin b pass through int K (both in D), every ray of the bin does, and
//   with c slightly above max(f(ray b), f(ray b+1)), (1) and (2) give f(u) <= max(f(ray b), f(ray b+1))
//   for every direction u of the bin: f is quasi-convex along the bin and its maximum is at an end.
//   depth(b) = min over occluders covering b of that maximum (each end's f computed with a relative
//   margin on the large side), so every ray of bin b has entered the interior of some occluder by
//   distance depth(b). depth(b) = +inf where no occluder covers b.
//   f in closed form: a circle of centre c, radius rho, |c| > rho: the unit ray u passes through the
//   interior iff c.u > 0 and |c x u| < rho, and then f(u) = c.u - sqrt(rho^2 - (c x u)^2)
//   = (|c|^2 - rho^2) / (c.u + sqrt(rho^2 - (c x u)^2)) (the product of the two roots of |t u - c| = rho;
//   the second form has no cancellation). A box or polygon is an intersection of open half-planes
//   n.x < h (unit outward normals; for a polygon also its bounding box's four, which keep the rounded
//   edge lines honest far from the polygon): along t u each gives t < h / (n.u) or t > h / (n.u), and the
//   ray passes through the interior iff the largest lower bound tEnter is below the smallest upper bound
//   tExit (and > 0: O outside); f(u) = tEnter.
//   Occluders containing or touching O are skipped: a circle when |c|^2 <= rho^2 (1 + 1e-6) (the entry
//   distances are ill-conditioned so near its surface), a box or polygon when O lies in the closed
//   intersection of its computed half-planes (then no ray has tEnter > 0). From outside by any margin the
//   argument holds as it stands: the computed region lies inside the true shrunk shape (see Rounding), so a
//   camera on a wall's face (the wall then shrunk a hair away from it) still has the rays into the wall
//   blocked. And were O truly inside the object after all, every ray would be blocked at distance 0, below
//   any depth.
//
// Occludees. A shape X (grown by its slack) is hidden when every bin its angular extent can touch has
// depth(b) < nearest(X), its smallest distance from O. Then for every point p of X in view, the direction
// of p lies in a touched bin b (the bins cover the view), so the ray towards p enters the interior of an
// occluder Y at f < depth(b) < nearest <= |p|: the open segment O..p meets int Y (the contract's
// definition of hidden; Y is another object, drawn before X was tested). A shape whose angular extent
// misses the buffer's range has no point in view and is hidden; a shape containing O (nearest 0) is
// never hidden. The angular extent of a convex set not containing O is an arc narrower than pi: for a
// disc of centre c and radius rho, the arc of half-width asin(rho / |c|) = atan2(rho, sqrt(|c|^2 - rho^2))
// around c; for a polygon or box, the smallest arc holding its vertices' directions (measured from a
// point inside it); for a polygon grown by g (its Minkowski sum with a disc, the convex hull of the discs
// at its vertices), the smallest arc holding those discs' arcs. Boxes are grown as boxes (a superset of
// the Minkowski sum).
//
// Refinement (as OcclusionBuffer3D::hiddenParts). The one-shot test compares every touched bin with the
// shape's single nearest distance, so a shape just behind an occluder fails on the bins at the edge of
// its extent where the occluder is entered farther out. Then the shape's bounding box is split into 4
// quarters, each tested with its own angular extent and nearest distance, two levels deep. Sound: the
// quarters cover the shape and each test is the same conservative test. The early-out: a point p of the
// box whose bin is not covered nearer than |p| lies in some part at every level, and that part's test
// would fail on that bin (its nearest is <= |p| and its extent holds p's direction), so no split can
// succeed; the box's centre is checked first.
//
// Order. Testing nearest first and drawing each object that stays is the same as drawing all before
// testing: an object can only be hidden by bins whose depth is below its nearest distance, and an
// object whose nearest distance is larger enters only at larger depths.
//
// Rounding: every decision errs towards "not covered" / "not hidden".
//   - Apex-relative coordinates are rounded by up to ~1 ulp of the largest coordinate involved: occluders
//     are shrunk and occludees grown internally by 32 ulp of that magnitude (pad), also covering the
//     rounding of edge normals over the bounding box.
//   - Depths carry a relative margin kRelMargin (1e-9) and an absolute one (1e-9 of the shape's scale), plus
//     a term for the conditioning of near-parallel edges (8 ulp / |n.u|); the "passes through the interior"
//     tests need room of the same size.
//   - Angles are computed by fastAtan2 (grid/internal/rgvc/grid/FastAtan2.hpp), within 1e-7 rad of the
//     true ones; an extent's end sums at most three of them. Angular extents are widened by 1e-10 rad
//     plus four such errors (4.001e-7 rad in all) and bin indices by 1e-6 bin on both sides; the rays'
//     rounding is ~1e-16 rad. (Bins are at least 2 pi / 4096 = 1.5e-3 rad wide: the widening reaches a
//     further bin for about one extent in 2,000.)
//   - Occludees must be at a nearest distance above 1e-9 of their scale (else not hidden): the extent of a
//     disc almost touching O is ill-conditioned.
//   Callers shrink occluders and grow occludees by their conversion slack (GridGeometry) and the camera's
//   (ViewWedge::slack), which covers an apex off by that much: moving the camera by s is moving every
//   object by at most s.
//
// The `far` limit of the wedge is ignored (an object beyond it is simply not hidden by the buffer).
// No allocation per draw or test after begin(), except that a polygon with more vertices than any
// before (above 60) grows the half-plane scratch once.
#pragma once

#include "rgvc/grid/Shapes.hpp"
#include "rgvc/grid/ViewWedge.hpp"

#include <cstdint>
#include <vector>

namespace rgvc {

struct OcclusionBuffer2DStats {
    std::uint32_t occludersDrawn = 0; ///< draw() calls that covered at least one bin
    std::uint32_t tested = 0;         ///< hidden() calls while active
    std::uint32_t hidden = 0;         ///< of those, answered true
    std::uint64_t binsCovered = 0;    ///< bins an occluder covered, of those not already covered nearer than it can reach
};

class OcclusionBuffer2D {
public:
    /// [Limit] most bins of a buffer (more are clamped to this).
    static constexpr int kMaxBins = 4096;
    static constexpr int kDefaultBins = 256;
    /// [Radians] narrowest wedge begin() accepts.
    static constexpr double kMinFov = 1e-5;

    /// Starts a frame over `view` (voxel units), every bin open (depth +inf).
    /// @param bins  [Limit] 1..kMaxBins requested (more: clamped); raised so that a bin is at most 3 pi / 4
    ///              wide (a full circle gets at least 3). bins() gives the count used.
    /// @return false (and the buffer hides nothing until the next successful begin) when bins < 1, the
    ///         wedge is narrower than kMinFov, or its apex or direction is not finite.
    bool begin(const ViewWedge& view, int bins = kDefaultBins);

    /// [Voxel units] nearest distance from the camera to the shape grown by `grow` (>= 0; 0 when the camera
    /// is inside it): the sort key of the front-to-back order. Boxes are grown as boxes.
    double nearestDistance(const Shape<2>& shape, double grow) const;

    /// Conservative: true only if no point of the shape grown by `grow` [voxel units, >= 0] that lies in
    /// the view wedge is visible past the occluders drawn so far (the wedge's far limit ignored).
    bool hidden(const Shape<2>& shape, double grow) { return hidden(shape, grow, nearestDistance(shape, grow)); }
    /// As above, with nearest = nearestDistance(shape, grow) already known (the front-to-back sort key).
    /// refine: whether a shape whose one extent fails is split into quarters (see Refinement above).
    bool hidden(const Shape<2>& shape, double grow, double nearest, bool refine = true);
    /// The one-extent test of a box, without the refinement.
    bool hiddenCoarse(const Box<2>& box, double grow) {
        const Shape<2> s(box);
        return hidden(s, grow, nearestDistance(s, grow), false);
    }

    /// Draws the shape shrunk by `shrink` [voxel units, >= 0] as an occluder (nothing when the shrunk shape
    /// is empty or holds or touches the camera). Ends a freeze().
    void draw(const Shape<2>& shape, double shrink);
    /// The image is final until the next draw() or begin(): its bins' maxima per block of kBlockBins are
    /// kept, and a test over many bins reads the blocks (the same answers, a block at once). One pass over
    /// the bins; for tests of wide shapes after the drawing is done (the culler's tests beyond the grid's
    /// faces: a face's slab spans most of the view). Not kept while drawing: each draw would pay it.
    void freeze();
    static constexpr int kBlockBins = 16;

    bool active() const { return m_active; }
    int bins() const { return m_bins; }
    /// [Radians] width of one bin.
    double binWidth() const { return m_binW; }
    /// Whether the bins cover the whole circle (and wrap around).
    bool fullCircle() const { return m_full; }
    /// [Voxel units] depth of bin b (0..bins()-1), +inf where no occluder covers it (for tests and pictures).
    double depthAt(int bin) const { return m_depth[std::size_t(bin)]; }
    /// Unit direction of boundary ray b (0..bins()); bin b lies counter-clockwise from ray b to ray b + 1.
    Vec2 boundaryRay(int b) const { return {m_rayX[std::size_t(b)], m_rayY[std::size_t(b)]}; }
    const OcclusionBuffer2DStats& stats() const { return m_stats; }

private:
    struct HalfPlane {
        double nx, ny, h; // open half-plane nx x + ny y < h, apex-relative, (nx, ny) unit
    };
    /// Bin coordinate of direction v (apex-relative, non-zero): radians counter-clockwise from ray 0,
    /// in [H - pi, H + pi].
    double binCoord(const Vec2& v) const;
    /// Calls f(i0, i1) for every run of bins [i0, i1] that directions with bin coordinates in [x0, x1]
    /// (modulo 2 pi) can fall in; stops and returns false as soon as f does. NaN bounds: every bin.
    template <class F> bool forEachRun(double x0, double x1, F&& f) const;
    /// Every bin of the runs of [x0, x1] has depth < nearest.
    bool coveredNearer(double x0, double x1, double nearest) const;
    /// Angular extent [x0, x1] (bin coordinates, widened) of the box [lo, hi] (apex-relative, O outside).
    void boxExtent(const Vec2& lo, const Vec2& hi, double& x0, double& x1) const;
    /// Whether the bin of point p (apex-relative) is covered nearer than |p| (true when p is outside the
    /// buffer's range: no verdict).
    bool canHide(const Vec2& p) const;
    /// The 4 quarters of the box [lo, hi] (apex-relative), each hidden by its own extent and nearest
    /// distance (nearest * (1 - kRelMargin) - pad, which must exceed minNearest), `levels` deep.
    bool hiddenParts(const Vec2& lo, const Vec2& hi, int levels, double pad, double minNearest) const;
    /// Entry distance along unit ray u into the intersection of m_planes (see the header), or -1 when the
    /// ray does not pass through it with room to spare. scale: the shape's magnitude (absolute margin).
    double planeEntry(double ux, double uy, double scale) const;
    /// Draws over the runs of [x0, x1]: fill(i0, i1, out) writes out[i], for boundary rays i0..i1, the entry
    /// distance along ray i, or < 0 where the ray does not pass through the occluder's interior.
    /// nearest: a lower bound of every entry fill writes (bins covered that near are skipped).
    template <class Fill> void drawRuns(double x0, double x1, double nearest, Fill&& fill);

    Vec2 m_apex{0.0}, m_dir{1.0, 0.0};
    double m_half = 0, m_span = 0, m_binW = 0;
    double m_invBinW = 0, m_binsPerTurn = 0; // 1 / m_binW and 2 pi / m_binW (forEachRun, canHide)
    int m_bins = 0;
    bool m_full = false, m_active = false;
    std::vector<double> m_depth;       // bins
    std::vector<double> m_blockMax;    // freeze(): per kBlockBins bins, their largest depth
    bool m_frozen = false;
    std::vector<double> m_rayX, m_rayY; // bins + 1 boundary rays (world axes)
    // cos / sin of the boundary rays' angles from the direction; they depend on H and the bin count only,
    // so they are kept while those stay (a camera walk changes neither).
    std::vector<double> m_relCos, m_relSin;
    double m_cacheHalf = -1;
    int m_cacheBins = 0;
    std::vector<HalfPlane> m_planes; // draw()'s scratch
    std::vector<double> m_entries;   // draw()'s scratch: the boundary rays' entry distances (bins + 1)
    OcclusionBuffer2DStats m_stats;
};

} // namespace rgvc
