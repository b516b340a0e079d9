// rgvc::Culler: the public, per-frame visibility API a game links against.
//
//   rgvc::GridGeometry2 grid({0, 0}, 1.0, {256, 256});
//   rgvc::Culler2D culler(grid);
//   culler.addObject({.id = 7, .shape = rgvc::Ball<2>{{40, 30}, 3.5}});
//   culler.addObject({.id = 8, .shape = rgvc::Box<2>{{60, 10}, {70, 90}}, .isStatic = true});
//   const rgvc::CullResult& r = culler.cull({.position = {10.5, 20.25}, .direction = {1, 0.2}, .fovDeg = 90});
//   for (rgvc::ObjectId id : r.pvs) draw(id);   // every visible object is in r.pvs
//   culler.updateObject(7, rgvc::Ball<2>{{41, 30}, 3.5});   // the object moved (push), or:
//   culler.cull(camera, [&](rgvc::ObjectId id) { return world.shapeOf(id); });   // pull: asked only when needed
//
// Dynamic scenes (seed 004 §2, §4.1, §4.5; Sudarsky and Gotsman's temporal bounding volumes). The
// application owns the motion. Every frame, cull(camera, placementOf) asks for the current placement of
// exactly the non-static objects it needs (at most once each per frame):
//   - the objects of the last PVS (re-rasterized into O and I, writing only their footprints' difference);
//   - objects whose TBV expired (a new TBV is built around their current placement);
//   - objects whose TBV the traversal met in a visited, non-occluded voxel (rasterized at once and
//     classified in the same frame).
// An object that leaves the PVS is taken out of O and I and gets a TBV: a disc (2D) or cube (3D) that
// contains it for `validity` frames given its maxSpeed, discretized into T (TbvMatrix.hpp). Hidden moving
// objects therefore cost nothing until their TBV expires or becomes visible, and the frame's cost follows
// the visible set, not the scene. Static objects are rasterized once and never asked for.
// cull(camera) is cull(camera, placements as last given to addObject/updateObject). updateObject on a
// hidden object costs O(1) while the new placement stays inside its TBV.
//
// The TBV conditions of §4.1: with the default boundary discretization, a TBV must not contain the camera's
// voxel, and the camera's voxel moves by at most one voxel per axis from one cull() to the next. The
// culler keeps both: it sizes each TBV's validity to stay clear of the camera's voxel and inside the grid
// (unless CullerOptions::objectsStayInGrid promises that objects never leave it), or keeps the object in
// O and I if it cannot (stats.tbvsRefused), and after a larger camera move it
// checks every TBV against the new camera voxel (stats.cameraJump). maxSpeed is a promise: an object
// found outside its TBV is counted in stats.speedViolations, and the frames before may have missed it.
//
// Guarantee: `cull` returns a superset of the objects visible from the camera (the contract's
// definition: some point of the object lies in the closed view region and the open segment to it meets
// no other object's interior; objects that touch along a face are fused, as occluder fusion implies).
// Objects and cameras outside the grid are legal; they take a conservative fallback reported in stats.
//
// Errors: every member validates its arguments and throws rgvc::InvalidInput ("field: what") before
// changing anything (see rgvc/grid/Error.hpp). Misuse throws std::logic_error instead of corrupting
// anything: a member called on a moved-from culler (assign a new culler to reuse the variable), and a
// member other than hasObject, objectCount, grid and options called from inside the placement query
// (which runs in the middle of cull(): objects half classified, the PVS half built); the query's call
// then fails, and cull() completes the frame conservatively and rethrows that logic_error.
//
// Lifetimes: the CullResult& that cull() and lastResult() return stays valid, and unchanged, until the
// next cull(), or until the culler is destroyed or moved. updateObject on a hidden object while cull()
// is given a placement query is a teleport: the pushed placement replaces the object's current one at
// once (one pushed outside its TBV goes back into O and I and is classified by the next frame).
//
// Threads: a culler is not thread-safe: call its members from one thread at a time (one culler per
// thread, or a lock around it). The placement query is called on the thread that called cull() or
// cullViews(), never concurrently. Different cullers share nothing. cullViews() itself runs its per-view
// passes concurrently on a TaskExecutor; those passes only read the scene and write their own view's
// scratch state, and the call returns after all of them have finished.
//
// Several views per frame (split screen, shadow cascades, cube-map faces): cullViews(cameras) is one
// frame with one scene update and one cull per camera, run in parallel. The frame, step by step:
//   1. the scene update (as in cull(), above), once, with the camera conditions of every view: a boundary
//      TBV stays clear of every camera's voxel, and a camera that moved by more than one voxel since the
//      same view of the last frame (or a change in the number of views) makes every TBV be checked
//      against every camera voxel;
//   2. one pass per view, concurrently: the grid traversal, the occlusion image and buffer, over the
//      scene as the update left it. A pass writes nothing the others read (its own traversal stamps,
//      6 bytes per voxel per view, allocated once per view slot). A TBV that a view meets in a visible
//      voxel cannot be revealed there (revealing writes O, I and T, which the other views read), so that
//      view reports the hidden object (a superset: it is somewhere in its TBV) and records it;
//   3. the reveals, on the calling thread, in the fixed order view 0, 1, ..., each view's in the order
//      it met them: a TBV met by any view is revealed for all (the object goes back into O and I, so the
//      next frame classifies it in every view). Objects in any view's PVS count as "in the last PVS" for
//      the next scene update.
// Each view's PVS is therefore a function of the scene and its camera alone: the same whatever the
// executor, the number of threads or the scheduling (tests: test_views). It equals cull(camera) for
// that camera except where a TBV was met (cull() reveals and classifies it in the same frame, so it may
// cull it; cullViews reports it) and except that CullerOptions::adaptiveCaps, adaptiveBuffer and
// adaptiveImage, per-view schedules, are not used by cullViews (caps, the walk's image and the buffer
// pass run every frame).
#pragma once

#include "rgvc/grid/Camera.hpp"
#include "rgvc/grid/GridGeometry.hpp"
#include "rgvc/grid/Shapes.hpp"
#include "rgvc/grid/TbvMatrix.hpp"

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace rgvc {

/// The user's object id: any non-negative integer, unique within a culler.
using ObjectId = std::uint64_t;

/// What an object does for visibility (scene-format.md's `role`).
enum class ObjectRole : std::uint8_t {
    Both,     ///< hides what lies behind it and is reported when visible (the default)
    Occludee, ///< never hides anything (glass, foliage, particles): no O, never drawn into an image
    Occluder, ///< hides what lies behind it and is never reported (level geometry drawn elsewhere)
};
/// "both", "occludee", "occluder".
const char* toString(ObjectRole r);

template <int D> struct ObjectDesc {
    ObjectId id = 0;
    /// [World units] current placement. A triangle mesh (MeshSolid, 3D) is its own two models: the voxels
    /// it touches for I and its hull for visibility, a closed mesh's solid voxelization for O. An open mesh
    /// occludes nothing: addObject and updateObject refuse one (InvalidInput naming ".role" and the edges
    /// that leave it open) unless role is Occludee.
    Shape<D> shape;
    bool isStatic = false; ///< Never moves (§4.5): discretized once, never asked for, never given a TBV.
    /// [World units per frame] [Limit] finite, >= 0. Bounds how far the object moves between two cull()
    /// calls; sizes its TBVs. 0: the object moves only by updateObject, so, like a static one, it is
    /// never asked for its placement and never gets a TBV.
    double maxSpeed = 0;
    /// [World units] [Limit] finite, >= 0. The occluder model is the shape shrunk by this much
    /// (insetShape): O holds only voxels entirely inside it, and the occlusion images draw it; I and every
    /// visibility test keep the shape itself. Seed 004 §5.1's principle for objects drawn as meshes that
    /// differ from the analytic shape: give the shape that contains the drawn mesh, and the inset that
    /// puts the occluder inside it (a sphere drawn as an inscribed mesh of inradius r_in: r - r_in). Then
    /// nothing the grid hides could have changed a pixel. 0: the shape itself occludes. A mesh is never
    /// eroded: any positive inset leaves it no occluder.
    double occluderInset = 0;
    /// Occludee: as if the inset left nothing (it occludes nothing). Occluder: culled as usual (it is held
    /// and tracked like any object, so it keeps occluding while in view) but left out of CullResult::pvs.
    ObjectRole role = ObjectRole::Both;
};

/// The application's answer to "where is object `id` now?", in world units. Called by cull() only for
/// non-static objects, at most once per object per cull(). Must return a valid shape (validateShape) for
/// an id the culler holds. If it throws or returns an invalid shape, cull() still completes conservatively
/// (the object is reported in the PVS until a later query succeeds) and then rethrows the exception, or
/// throws InvalidInput naming the object; lastResult() holds the frame's result.
template <int D> using PlacementQuery = std::function<Shape<D>(ObjectId)>;


/// Which conservative shortcut a frame took instead of the full grid algorithm.
enum class Fallback : std::uint8_t {
    None,              ///< grid traversal only
    CameraOutsideGrid, ///< camera outside the grid box: every object touching the view region is reported
    /// An orthographic camera (Camera::projection) in 2D, or in 3D with CullerOptions::orthographicOcclusion
    /// false: every object touching its view box is reported (an exact test, OrthoVolume.hpp), no occlusion.
    Orthographic,
    /// An orthographic 3D camera with CullerOptions::orthographicOcclusion: the objects touching its view
    /// box that the parallel-ray occlusion image does not hide (OrthoPass.cpp); hidden objects are tested
    /// by their TBV boxes (stats.orthoTbvBoxTests), not through T.
    OrthographicOcclusion,
};
const char* toString(Fallback f);

struct CullStats {
    double cullMs = 0;                    ///< wall time of this cull() call, scene update included
    double updateMs = 0;                  ///< of cullMs: the scene update before the traversal (§4.1)
    std::uint32_t objectCount = 0;
    std::uint32_t pvsSize = 0;
    std::uint32_t layers = 0;             ///< chess-metric layers traversed
    std::uint64_t voxelsVisited = 0;      ///< in-grid voxels of the view region the traversal reached
    std::uint64_t voxelsOccluded = 0;     ///< of those, found in H and skipped
    std::uint64_t occludersExtended = 0;  ///< opaque voxels that started an occluder extension (§4.3)
    std::uint64_t occluderVoxels = 0;     ///< voxels aggregated into extended occluders
    std::uint64_t shadows = 0;            ///< occlusion polygons rasterized into H (§4.4)
    std::uint64_t voxelsMarkedOccluded = 0;
    bool earlyTermination = false;        ///< a layer was all occluded or opaque (§4.2)
    // Scene discretization of this frame (§4.1). Its time is part of cullMs, including placement queries.
    std::uint32_t placementQueries = 0;   ///< calls of the placement query
    std::uint32_t trackedObjects = 0;     ///< moving objects (not static, maxSpeed > 0) held in O and I after the frame
    std::uint32_t hiddenObjects = 0;      ///< objects held only by a TBV after the frame
    std::uint32_t tbvsCreated = 0;        ///< objects that left the PVS and got a TBV
    std::uint32_t tbvsRenewed = 0;        ///< expired TBVs rebuilt around the object's current placement
    std::uint32_t tbvsRevealed = 0;       ///< TBVs met in a visited, non-occluded voxel: object re-inserted
    std::uint32_t tbvsRefused = 0;        ///< objects kept in O and I: a TBV would touch the camera voxel or leave the grid
    std::uint32_t tbvsHeld = 0;           ///< objects kept in O and I for a few frames: their last TBV was revealed while they stayed hidden
    bool cameraJump = false;              ///< boundary TBVs existed and the camera voxel moved > 1 voxel on some axis (or entered the grid): every TBV was checked against it
    std::uint32_t tbvsRevealedByJump = 0; ///< of those, TBVs that held the new camera voxel
    std::uint32_t speedViolations = 0;    ///< objects found outside their TBV: they moved faster than maxSpeed
                                          ///< (or left the grid, breaking CullerOptions::objectsStayInGrid)
    std::uint32_t parkedObjects = 0;      ///< objects whose placement query failed; always in the PVS
    std::uint64_t gridWrites = 0;         ///< I, O and T incidences written by this frame's update
    bool tbvLookupsSkipped = false;       ///< no TBV existed during the traversal: T was not read at all
    bool tbvMatrixAllocated = false;      ///< T exists (it is allocated by the first TBV, never before)
    bool occlusionSkipped = false;        ///< no opaque voxel was met: no occlusion work at all
    Fallback fallback = Fallback::None;
    std::uint32_t objectsOutsideGrid = 0; ///< objects partly outside the grid, tested against the view region
    bool capsDeferred = false;            ///< 3D adaptiveCaps: this frame started without caps
    std::uint32_t capsFromShell = 0;      ///< of such a frame: the shell where a wall switched them on (0: none)
    std::uint32_t bufferTested = 0;       ///< grid-PVS objects tested against the occlusion buffer (3D rows, 2D bins)
    std::uint32_t bufferHidden = 0;       ///< of those, hidden by it and left out of the PVS
    double bufferMs = 0;                  ///< of cullMs: the occlusion buffer's time
    bool bufferSkipped = false;           ///< CullerOptions::adaptiveBuffer skipped the buffer's pass this frame
    bool imageSkipped = false;            ///< CullerOptions::adaptiveImage walked without the occlusion image this frame
    // 3D hierarchical traversal (CullerOptions::hierarchical): the brick tree's work.
    std::uint64_t nodesVisited = 0;       ///< brick-tree nodes (interior and bricks) taken out of the queue
    std::uint64_t nodesEmpty = 0;         ///< of those, skipped as empty (no ids, no TBV below them)
    std::uint64_t nodesHidden = 0;        ///< of those, skipped as hidden behind the occlusion image
    std::uint64_t bricksVisited = 0;      ///< 8x8x8 bricks whose voxels were read
    std::uint32_t imageHidden = 0;        ///< objects met in visited bricks that the traversal's image hid
    std::uint64_t tbvImageTests = 0;      ///< visited voxels' boxes holding TBVs tested against that image (each brick's octree, 2D quadtree)
    std::uint32_t faceTbvTests = 0;       ///< TBVs reaching past the grid (objectsStayInGrid off): faces' slabs and then TBV parts beyond them tested against the view
    std::uint32_t orthoTbvBoxTests = 0;   ///< orthographic occlusion: hidden objects whose TBV box was tested (all of them)
};

struct CullResult {
    std::vector<ObjectId> pvs; ///< sorted ascending, no duplicates
    CullStats stats;
};

/// Runs independent tasks, possibly at once: cullViews' per-view passes. An engine with a job system of
/// its own implements it to run them there (as bvh v2 takes executors); rgvc/dynamics/TbbExecutor.hpp
/// runs them on a TBB task arena, SerialExecutor on the calling thread.
class TaskExecutor {
public:
    virtual ~TaskExecutor() = default;
    /// Calls task(i) exactly once for every i in [0, count), on any threads and in any order, and
    /// returns when every call has returned. rgvc's tasks never throw (they catch and report their own
    /// failures), never call back into the executor, and take no locks.
    virtual void parallelFor(std::size_t count, const std::function<void(std::size_t)>& task) = 0;
};

/// Runs the tasks one after another on the calling thread, in index order.
class SerialExecutor final : public TaskExecutor {
public:
    void parallelFor(std::size_t count, const std::function<void(std::size_t)>& task) override {
        for (std::size_t i = 0; i < count; ++i) task(i);
    }
};

/// [Limit] the most cameras one cullViews() call takes.
inline constexpr std::size_t kMaxViews = 64;

/// What cullViews() returns: one CullResult per camera, and the frame's scene-wide work.
struct MultiCullResult {
    /// In the cameras' order. Each pvs is sorted ascending; each stats holds that view's pass (traversal,
    /// buffer, pvsSize, cullMs: the pass's wall time, on its thread) and the scene counts after the frame.
    std::vector<CullResult> views;
    /// The scene update and the reveals after the views: placementQueries, tbvs*, speedViolations,
    /// gridWrites, the tracked/hidden/parked counts after the frame, updateMs; cullMs: the whole call.
    /// tbvsRevealed counts the TBVs met by some view and revealed after the passes.
    CullStats scene;
};

/// Per-voxel state after the last cull (for pictures, debugging and tests).
struct VoxelState {
    bool inGrid = false;
    bool opaque = false;   ///< O (including Os)
    bool occluded = false; ///< H (CullerOptions::hierarchical: hidden in the walk's occlusion image)
    bool visited = false;  ///< reached by the traversal
    bool occluder = false; ///< part of an extended occluder
    bool hasIds = false;   ///< I non-empty
    bool hasTbv = false;   ///< some TBV is discretized into this voxel (T)
};

/// CullerOptions::traversalImageRows = 0: the pixel size, and the row limits.
inline constexpr double kAutoImagePixelTan = 0.04;
inline constexpr int kAutoImageMinRows = 32, kAutoImageMaxRows = 128;

struct CullerOptions {
    /// Use occlusion at all. false = view-frustum culling on the grid only (the VFC baseline).
    bool occlusion = true;
    /// 2D: extend opaque voxels into larger virtual occluders (§4.3). false = each run of opaque voxels
    /// in one layer side is its own occluder (no L arms, no use of occluded voxels).
    /// 3D: test each voxel against the caps of shells k-1, k-2, k-4, ... (true) or only k-1 (false:
    /// layer-by-layer propagation).
    bool occluderExtension = true;
    /// Hidden non-static objects are held by temporal bounding volumes (true), or every non-static object
    /// is re-placed in O and I every frame (false: the re-insert baseline).
    bool temporalBoundingVolumes = true;
    /// How a TBV is written into T (TbvMatrix.hpp): its boundary (the paper's choice) or its whole region.
    TbvDiscretization tbvDiscretization = TbvDiscretization::Boundary;
    /// [Frames] [Limit] 1..65536. The longest validity of a TBV of a moving object.
    std::uint32_t tbvMaxFrames = 1024;
    /// [Voxels] [Limit] finite, >= 0. A TBV's radius grows by at most this over its validity: slow objects
    /// get long validities, fast ones short. An object whose TBV is revealed while it stays hidden gets
    /// half the growth next time (down to 1/16), and back up after two validities unrevealed. 0 picks the
    /// measured default: 32 in 2D, where a renewal writes contiguous runs of a ring whose length grows
    /// only linearly with the radius, so fewer, larger renewals win (README, "Dynamic scenes"); 4 in 3D
    /// with `hierarchical`, where T writes a list node per 8^3 brick the cube's shell reaches, a number
    /// that grows with the square of the side while renewals fall only linearly, and larger cubes are
    /// revealed more often next to the view (README, "Scene classes": 5-14 % fewer instructions per
    /// frame than 8 on the classes with movers, the 100k room 15-20 % faster); 8 in 3D without it (the
    /// per-voxel core, last measured with the projection-plane T of an earlier version).
    double tbvMaxGrowth = 0;
    /// A promise from the application: a moving object that is entirely inside the grid never leaves it
    /// (the world's walls keep it in, as the scene format's motion does: it reflects at the grid bounds).
    /// TBVs reach past the grid's bounds with or without it, and T stores their in-grid voxels. With the
    /// promise that is all: the camera (the only case with TBVs) and the object are in the grid, so the
    /// segment between them is too, and it enters the disc or cube through a part of its boundary inside
    /// the grid. A placement found outside the grid while its TBV was live then counts in
    /// stats.speedViolations (the frames before may have missed it). false (default): no promise; an object
    /// may leave the grid while hidden, and each perspective view also tests the parts of TBVs beyond the
    /// grid's faces against the view and its occlusion image (a face at a time first; stats.faceTbvTests).
    /// Past a face whose beyond the last test found in view, new TBVs still stay inside the grid (each
    /// would cost that test every frame). (What it cost when every TBV had to fit inside the grid: README,
    /// "Scene classes".)
    bool objectsStayInGrid = false;
    /// 3D only: [Pixels] [Limit] 0..2048. Rows of the occlusion buffer that refines the grid's PVS
    /// (OcclusionBuffer3D.hpp): the PVS objects, nearest first, are tested against the image of the
    /// nearer ones and drawn into it, so clouds of objects smaller than a voxel, which leave O empty,
    /// still hide what is behind them. Columns follow the aspect. 0 turns the stage off. Only the reported
    /// PVS shrinks: TBVs and tracking follow the grid's verdict, so an object the buffer hides stays in O
    /// and I (cheap to reveal) instead of flipping between tracked and hidden. Ignored in 2D and when
    /// `occlusion` is false.
    int occlusionBufferRows = 64;
    /// Hierarchical only. 3D: the occlusion buffer's pass starts from the traversal's image (drawn during
    /// the brick walk) cut into finer pixels, ceil(occlusionBufferRows / traversal rows) per side, each
    /// starting at its coarse pixel's depth (OcclusionBuffer3D::beginRefined), and draws the occluders the
    /// walk drew again only where they may matter: once an object whose centre is already behind some
    /// occluder fails its test, the walk's occluders nearer than it whose image rectangles meet its own are
    /// drawn at the finer resolution over that object's pixels and it is tested again (up to 32 such
    /// occluders; more, as in a cloud of large spheres, are all drawn in order). false: a fresh image of occlusionBufferRows rows into
    /// which every kept object is drawn again (the walls and buildings the walk drew, twice per frame).
    /// Both are conservative and about as tight (README, "Scene classes": 22-32 % fewer instructions in
    /// closed rooms and 3D cities, |PVS| unchanged in the rooms).
    /// 2D: the walk draws every object it keeps into its angular image, so the pass draws nothing: each
    /// kept object is tested once more against the walk's finished image (hiding what the walk met before
    /// a nearer occluder was drawn), when that image has at least occlusionBufferBins bins; with fewer (a
    /// view under ~29 degrees) or false, a fresh buffer of occlusionBufferBins bins into which every kept
    /// object is drawn nearest first (README, "Scene classes": the 2D city 10 % and random scenes 5 %
    /// faster, |PVS| within 0.5 %).
    bool bufferFromTraversalImage = true;
    /// 2D only: [Bins] [Limit] 0..4096. Angular bins of the 2D occlusion buffer (OcclusionBuffer2D.hpp)
    /// that refines the grid's PVS as the 3D buffer does: objects smaller than a voxel, which leave O
    /// empty, still hide what is behind them. 0 turns the stage off. Ignored when `occlusion` is false.
    /// With `hierarchical` and bufferFromTraversalImage the pass uses the walk's image instead whenever it
    /// has at least this many bins (see there).
    int occlusionBufferBins = 256;
    /// 3D only: skip the grid's caps on frames where they have not been paying. After a frame whose caps
    /// hid under a tenth of the visited voxels without ending the traversal early, the next 1, then 2, 4
    /// and at most 8 frames start without caps (a view-frustum traversal that still reads O) and switch
    /// them on at the first shell that is at least half opaque (a wall); any frame whose caps pay resets
    /// the schedule. What is skipped is occlusion, never conservativeness: a frame without caps reports a
    /// superset. On the paper's scene at 1-unit voxels the caps hide ~5% of the voxels and cost as much as
    /// the rest of the traversal; the occlusion buffer does the culling there. false: caps every frame.
    bool adaptiveCaps = true;
    /// Skip the occlusion buffer's pass (occlusionBufferRows, occlusionBufferBins) on frames after it has
    /// not been paying: after a pass that hid under a tenth of the objects it tested, the next 1, then 2,
    /// 4 and at most 8 frames report the grid's PVS as it is (stats.bufferSkipped); a pass that pays resets
    /// the schedule. What is skipped is tightness, never conservativeness. Where the grid's own image
    /// already hides what there is to hide (3D cities, buildings), the pass cost a third of the frame for
    /// 1-4 % of the PVS; in clouds of small objects it hides most of them and keeps running. Off by
    /// default: in closed rooms the pass is what hides the last objects outside (the traversal's image
    /// alone lets one through now and then at a room's corner), and a skipped frame reports them.
    bool adaptiveBuffer = false;
    /// 3D hierarchical only: walk without the occlusion image on frames after it has not been paying.
    /// After a frame whose image met no mesh occluder in view, left some pixel open, and either hid
    /// fewer occupied bricks in view than an eighth of those the walk read and covered under nine
    /// tenths of its pixels, or drew more than 1.5 fused boxes of O per brick it hid (a cloud of
    /// spheres filling voxels of O), the next 1, then 2, 4 and at most 8 frames walk as view-frustum
    /// culling does (every TBV met in view revealed; stats.imageSkipped), and the occlusion buffer's
    /// pass draws every kept object into a fresh image;
    /// a frame whose image pays resets the schedule. What is skipped is the walk's occlusion, never
    /// conservativeness; the buffer's pass still hides most of what the image would have.
    /// Where the image pays: behind closed walls and in streets (the whole image covered), in
    /// the game world's buildings, and wherever a mesh is in view (meshes occlude only through O, which
    /// the buffer's fresh image cannot draw). Where it does not: clouds of small objects and large, mostly
    /// empty worlds, where it hides almost nothing the walk would read and costs draws and tests (README,
    /// "Scene classes": clusters and the large world 12-14 % fewer instructions), and clouds of larger
    /// spheres, where it hides bricks but draws a fused box for each sphere's interior (scenes/
    /// spheres-3d.json: 33 % fewer instructions). cull() only (cullViews' views keep the image every
    /// frame). A skipped frame keeps in O and I the movers the image would have given TBVs, and lets
    /// through what only the walk's fused boxes hide (seams between spheres): tightness for time.
    /// false: the image every frame (the bench's `fullimg`).
    bool adaptiveImage = true;
    /// The output-sensitive core (BrickTraversal3D.hpp, BrickTraversal2D.hpp). The grid's 8^D bricks
    /// form an implicit octree (quadtree in 2D) whose nodes know whether anything (an id or a TBV) lies
    /// below them; the tree is walked front to back, empty nodes are skipped in O(1), every node is tested
    /// against a conservative occlusion image of the occluders met so far (from the camera point, so it
    /// holds however walls are turned: 3D a depth image, 2D an angular one), and only non-empty, not
    /// hidden bricks read their voxels. false: the paper's per-voxel traversals, kept to compare: the 3D
    /// shells with cap polygons (FrustumTraversal3D.hpp), the 2D chess rings with occluder extension and
    /// H (FrustumTraversal2D.hpp).
    bool hierarchical = true;
    /// 3D hierarchical only: [Pixels] [Limit] 0..2048. Rows of the traversal's occlusion image. 0 (the
    /// default) follows the view: pixels of kAutoImagePixelTan in the image plane at distance 1, between
    /// 32 and 128 rows (32 at a vertical fov of 60 degrees or less, 50 at 90, 87 at 120, 128 from 135 on).
    /// Drawing into the image is most of the traversal's cost, and a narrow view needs fewer rows for the
    /// same angular detail (README, "Output-sensitive core": the figures that chose the constants).
    int traversalImageRows = 0;
    /// 2D hierarchical only: [Bins] [Limit] 0..4096. Angular bins of the traversal's image. 0 (the
    /// default) follows the view: bins of 0.002 rad, at least 64 (786 at 90 degrees, 3,142 for the full
    /// circle, capped at 4,096), fine enough that a closed room's corner closes (BrickPass.cpp).
    int traversalImageBins = 0;
    /// 3D orthographic cameras: occlusion with parallel rays (true: the brick tree walked front to back
    /// along the view direction with a conservative depth image over the view box's cross-section, one
    /// pixel per voxel up to 256 per axis; OrthoPass.cpp, OrthoOcclusionImage.hpp; stats.fallback =
    /// OrthographicOcclusion), or exact view-volume culling only (false, the default, and always in 2D:
    /// stats.fallback = Orthographic). Ignored when `occlusion` is false (view-volume culling).
    /// Off by default because the views orthographic cameras serve most (shadow cascades, top-down and
    /// editor views) look at open content: on the README's cascade over a city the occlusion pass costs
    /// 3.5 ms where view-volume culling costs 0.2 ms, for 9 % fewer objects. Turn it on for views that look
    /// through walls and floors (side views of a building's storeys, a level seen from below).
    bool orthographicOcclusion = false;
    /// Memory of the grid's per-voxel arrays (about 13 bytes a voxel) taken where it is written, not at
    /// construction (true), or all of it at construction (false, the default). With true an empty 512^3
    /// culler is made in 0.4 s and holds about 1 byte a voxel (the brick walks' O flags, V and U) plus the
    /// pages objects have written, instead of 1.7 GiB after 6.7 s; but each 4 KiB page an object first
    /// writes costs a page fault during that frame (a moving object entering space no object has been in):
    /// on rgvc_bench_classes' large world, half of whose objects fly through it, the first 35 frames took
    /// 2.2x as long (README, "Large worlds"). For large worlds whose objects stay in a part of them (a map
    /// with its own terrain, a level whose movers keep to its rooms), or to cap memory.
    bool lazyStorage = false;
};

template <int D> class Culler {
public:
    /// @param grid  [Limit] 2D: at most 2^20 voxels per axis (exact integer occlusion arithmetic).
    /// @throws InvalidInput when the grid is too large per axis or needs more memory than can be
    ///         allocated ("grid.resolution").
    explicit Culler(const GridGeometry<D>& grid, const CullerOptions& options = {});
    ~Culler();
    Culler(Culler&&) noexcept;
    Culler& operator=(Culler&&) noexcept;

    const GridGeometry<D>& grid() const;
    const CullerOptions& options() const;

    /// Adds an object at its current placement.
    /// @throws InvalidInput on a duplicate id, an invalid shape or a negative/non-finite maxSpeed.
    void addObject(const ObjectDesc<D>& object);
    /// Moves or reshapes an object (push). Cost: proportional to its old and new voxel footprints, or O(1)
    /// for a hidden object whose new placement stays inside its TBV.
    /// @throws InvalidInput on an unknown id or an invalid shape.
    void updateObject(ObjectId id, const Shape<D>& shape);
    /// @throws InvalidInput on an unknown id.
    void removeObject(ObjectId id);
    bool hasObject(ObjectId id) const;
    std::size_t objectCount() const;
    /// Every object the culler holds, sorted by id, as it was added (isStatic, maxSpeed, occluderInset,
    /// role) at the placement the culler knows now: the last one given to addObject or updateObject or
    /// returned by the placement query (a hidden object's is the one it had when last asked, possibly
    /// older than the application's). For scene dumps (rgvc::sceneToJson, apps/scene/SceneWriter.hpp).
    /// Cost: O(n log n) and a copy of every shape.
    std::vector<ObjectDesc<D>> objects() const;

    /// Computes the potentially visible set for one camera; objects are where add/updateObject put them.
    /// @throws InvalidInput on an invalid camera (see validateCamera), before changing anything.
    const CullResult& cull(const Camera<D>& camera);
    /// One frame of a dynamic scene: asks placementOf for the objects it needs (see the top of this file).
    /// @throws InvalidInput on an invalid camera (before changing anything) or on an invalid placement
    ///         (after completing the frame conservatively); rethrows what placementOf threw (likewise).
    const CullResult& cull(const Camera<D>& camera, const PlacementQuery<D>& placementOf);
    /// cull()'s last result (cullViews() leaves it alone).
    const CullResult& lastResult() const;

    /// One frame seen from several cameras: one scene update, then one pass per camera, run concurrently
    /// on `executor` (null: the culler's own TBB task arena, made at the first call, as many threads as
    /// TBB allows), then the reveals (see the top of this file for the steps and how views combine).
    /// @param cameras  [Limit] 1..kMaxViews, each valid (validateCamera); checked before changing anything.
    /// @param executor must outlive the call; it is not kept.
    /// @return valid, unchanged, until the next cullViews(), or until the culler is destroyed or moved.
    /// Memory: 6 bytes per grid voxel per view slot (its traversal stamps), kept for the next call.
    /// @throws InvalidInput on an empty or too long span or an invalid camera ("cameras[i].fov_deg");
    ///         placement failures as cull() (after completing the frame conservatively).
    const MultiCullResult& cullViews(std::span<const Camera<D>> cameras, TaskExecutor* executor = nullptr);
    const MultiCullResult& cullViews(std::span<const Camera<D>> cameras, const PlacementQuery<D>& placementOf,
                                     TaskExecutor* executor = nullptr);

    /// State of voxel v after the last cull; inGrid = false outside the grid.
    VoxelState voxelState(const IVec<D>& v) const;

private:
    struct Impl;
    /// The state, or std::logic_error for a moved-from culler or a call from inside the placement query
    /// (unless `allowedInQuery`).
    Impl& checked(const char* what, bool allowedInQuery = false) const;
    std::unique_ptr<Impl> m_impl;
};

using Culler2D = Culler<2>;
using Culler3D = Culler<3>;

} // namespace rgvc
