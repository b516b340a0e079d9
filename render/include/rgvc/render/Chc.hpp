// The GL stage's traversal: render one frame over a QueryDevice and a persistent ObjectBvh with one of
// the methods the CHC paper compares (seed 001, §6.2), restricted to a set of candidate objects (the grid
// stage's PVS).
//
//   ObjectBvh bvh; bvh.build(items);                  // once; bvh.update(id, box) when objects move
//   ChcRenderer chc(device, bvh, options);
//   const ChcFrameStats& s = chc.render(camera, CullMethod::ChcPlusPlus, pvs);   // each frame
//   // s.drawn: the objects drawn, the GL stage's answer
//
// Candidates: a hierarchy node none of whose objects is a candidate is skipped as if it were outside the
// view frustum: the candidates are marked per frame and the marks pulled up their leaves' ancestors
// (O(candidates + marked ancestors)), and a leaf draws only its candidate objects. Query boxes are the
// nodes' boxes (which may also bound non-candidates: conservative, looser); CHC++'s tight bounds use the
// candidates' own boxes.
//
// Conservativeness (n_vp = 0): a node is culled only when a query of this frame over boxes containing
// every candidate of the node that lies in the frustum found no passing sample, and the device answers
// against objects actually drawn, so whatever is culled is hidden by drawn geometry. A device renders
// query boxes as surfaces, so a box that the near plane clips would give a wrong answer: every method
// treats a node whose box comes within the near plane's reach (ChcOptions::nearDistance) as visible
// without a query (CHC++'s "camera inside the node"). Per-node state never culls anything by itself:
// stale state (a rebuilt or edited hierarchy, another method last frame) costs queries, not correctness.
//
// CHC++ queries a previously visible leaf after drawing it (its answer decides the next frame only), so
// the query meets the leaf's own depth: a device whose query depth test lets ties pass (LEQUAL, or GEQUAL
// with reversed depth) keeps such a leaf visible; one with a strict test may call it invisible, which
// costs a query before drawing it next frame, not a miss.
#pragma once

#include "rgvc/render/ObjectBvh.hpp"
#include "rgvc/render/QueryDevice.hpp"

#include "rgvc/grid/Camera.hpp"
#include "rgvc/grid/ViewFrustum.hpp"

#include <cstdint>
#include <random>
#include <span>
#include <vector>

namespace rgvc {

/// The methods of one frame (seed 001, §6.2, plus CHC++).
enum class CullMethod : std::uint8_t {
    Zb,          ///< draw every candidate; no frustum test, no queries
    Vfc,         ///< hierarchical view-frustum culling
    StopAndWait, ///< hierarchical, front to back, every node's query waited for at once (§3.3)
    Chc,         ///< coherent hierarchical culling (§4, Figure 2; with §5.1 t_av and §5.2 n_vp)
    ChcPlusPlus, ///< CHC with CHC++'s batching, multiqueries, tight bounds and randomized t_av
    Ideal,       ///< draw exactly the candidates (the exact visible set, known in advance)
};

/// "zb", "vfc", "sw", "chc", "chcpp", "ideal".
const char* cullMethodName(CullMethod m);

struct ChcOptions {
    /// [World units] at least the device's near-plane distance. A node whose box comes closer to the
    /// camera than the near plane's corners (nearDistance * sqrt(1 + tan^2 + tan^2)) is visible without
    /// a query. [Limit] finite, > 0.
    double nearDistance = 0.01;
    /// n_vp (§5.2) [Samples]: a node is visible when more samples pass. 0: conservative; > 0: approximate
    /// (visible objects may be culled), and ChcFrameStats::approximate says so.
    std::uint64_t visiblePixelThreshold = 0;
    /// t_av (§5.1) [Frames]: a leaf found visible is assumed visible, without a query, until t_av frames
    /// after that query. 0 or 1: queried every frame. Conservative (it only draws more). [Limit] >= 0.
    int assumedVisibleFrames = 0;

    // CHC++ only.
    /// b: queries of previously invisible nodes wait until b are pending, then go out together (or
    /// earlier, when the traversal has nothing else to do). [Limit] >= 1.
    int batchSize = 32;
    /// Nodes invisible in the last frame are grouped into multiqueries by the CHC++ cost model.
    bool multiqueries = true;
    /// [Nodes] at most this many nodes in one multiquery. [Limit] >= 1.
    int maxMultiquerySize = 64;
    /// A node is queried with its children's (or candidates') boxes instead of its own when their
    /// total surface area is at most tightBoundsRatio times its box's.
    bool tightBounds = true;
    double tightBoundsRatio = 0.9; ///< [Limit] > 0.
    int tightBoundsDepth = 2;      ///< [Levels] below the node searched for tighter boxes. [Limit] 1..8.
    int tightBoundsMaxBoxes = 16;  ///< [Boxes] per node. [Limit] >= 1.
    /// Seeds the randomized first t_av (deterministic for a given seed).
    std::uint64_t seed = 1;
    /// [Objects] "skip what a frame doesn't need" (DESIGN.md): a query method given at most this many
    /// candidates draws them all with VFC instead, without queries (ChcFrameStats::queriesSkipped): a
    /// query costs about what drawing a small object does, so a small PVS gains nothing from them.
    /// 0: never skipped. Conservative either way (it only draws more).
    std::uint32_t queryMinCandidates = 0;
};

/// What one frame did. Counts are per frame.
struct ChcFrameStats {
    CullMethod method = CullMethod::Zb;
    std::uint64_t frame = 0;             ///< 1 for the renderer's first frame
    std::uint32_t singleQueries = 0;     ///< queries over one node (its box or its tight boxes)
    std::uint32_t multiQueries = 0;      ///< CHC++ multiqueries (several nodes in one query)
    std::uint32_t nodesInMultiQueries = 0;
    std::uint32_t multiQueryFailures = 0; ///< multiqueries that found samples; their nodes were requeried
    std::uint32_t queryBoxes = 0;        ///< boxes sent in all queries
    std::uint32_t blockingFetches = 0;   ///< results fetched while not ready (the CPU waited)
    double waitMs = 0;                   ///< [Milliseconds] spent in those blocking fetches
    double frameMs = 0;                  ///< [Milliseconds] beginFrame to the end of endFrame (traversal included)
    std::uint32_t nodesTraversed = 0;    ///< nodes taken from the traversal queue
    std::uint32_t nodesOutsideFrustum = 0;
    std::uint32_t nodesNearCamera = 0;   ///< visible without a query: the box is within the near plane's reach
    std::uint32_t nodesAssumedVisible = 0; ///< leaves not queried this frame because of t_av
    std::uint32_t drawCalls = 0;
    std::uint32_t objectsDrawn = 0;
    /// n_vp > 0 with a method that queries: visible objects may have been culled.
    bool approximate = false;
    /// The method queries, but the candidates were at most ChcOptions::queryMinCandidates: VFC ran instead.
    bool queriesSkipped = false;
    /// The objects drawn, in drawing order, each once: the GL stage's visible set.
    std::vector<ObjectId> drawn;

    std::uint32_t queries() const { return singleQueries + multiQueries; }
};

class ChcRenderer {
public:
    /// Both `device` and `bvh` must outlive the renderer; the application edits `bvh` between frames
    /// (per-node state follows node stamps). @throws InvalidInput ("chc.*") for bad options.
    ChcRenderer(QueryDevice& device, const ObjectBvh& bvh, const ChcOptions& options = {});

    /// Renders one frame of the `candidates` (ids in the hierarchy; duplicates allowed) seen from
    /// `camera` ([World units]). Between beginFrame and endFrame on the device; every query issued is
    /// fetched before it returns. The result stays valid until the next call.
    /// @throws InvalidInput ("camera.*", "candidates[i]" not in the hierarchy) before touching the device.
    const ChcFrameStats& render(const Camera3& camera, CullMethod method, std::span<const ObjectId> candidates);
    /// Same, with every object of the hierarchy a candidate.
    const ChcFrameStats& renderAll(const Camera3& camera, CullMethod method);

    const ChcFrameStats& lastStats() const { return m_stats; }
    const ChcOptions& options() const { return m_options; }
    /// Forgets every node's visibility history (the next CHC frame starts as the first).
    void resetCoherence();
    /// True when the last frame (CHC or CHC++) visited the node and classified it visible: the opened
    /// nodes and the visible termination nodes (seed 001, Figure 3), for pictures and tests.
    bool nodeVisible(BvhNodeId id) const {
        return id < m_state.size() && m_state[id].lastVisited == m_frame && m_state[id].visible &&
               m_state[id].stamp == m_bvh.node(id).stamp;
    }

private:
    struct NodeState {
        std::uint32_t stamp = 0;       ///< the node's stamp this state belongs to
        std::uint32_t lastVisited = 0; ///< frame number
        std::uint32_t nextQueryFrame = 0; ///< t_av: a visible leaf is queried again from this frame on
        std::uint32_t invisibleFrames = 0; ///< consecutive frames found invisible (multiquery history)
        bool visible = false;
    };
    struct HeapEntry {
        double distance2; ///< [World units^2] from the camera to the node's box
        BvhNodeId node;
    };
    struct Pending {
        QueryHandle handle;
        std::uint32_t first; ///< single: the node; multi: index into m_multiNodes
        std::uint32_t count; ///< 0: single query
        bool wasVisible;     ///< single: the node was drawn already this frame
    };

    const ChcFrameStats& renderFrame(const Camera3& camera, CullMethod method, std::span<const ObjectId>* candidates);
    void beginStats(CullMethod method);
    NodeState& state(BvhNodeId id);
    bool relevant(BvhNodeId id) const { return m_allCandidates || m_nodeMark[id] == m_frame; }
    bool candidateSlot(std::uint32_t slot) const { return m_allCandidates || m_slotMark[slot] == m_frame; }
    bool inFrustum(const Box<3>& b) const { return m_frustum.touchesBox(b.min, b.max); }
    bool nearCamera(const Box<3>& b) const { return distance2(b) <= m_nearRadius2; }
    double distance2(const Box<3>& b) const;
    void pushNode(BvhNodeId id);
    BvhNodeId popNode();
    void pushChildren(BvhNodeId id);
    /// Leaf: draws its candidates in the frustum; interior: pushes its relevant children.
    void traverseNode(BvhNodeId id);
    void pullUp(BvhNodeId id);
    /// Fills m_boxes with the node's query boxes (tight: CHC++); false when nothing of it needs drawing.
    bool gatherBoxes(BvhNodeId id, bool tight);
    /// The query's answer; a fetch of a result not ready yet is counted and timed as a wait.
    std::uint64_t fetch(QueryHandle q, bool ready);
    void gatherTight(BvhNodeId id, int depth);

    void renderZb();
    void renderVfc();
    void renderStopAndWait();
    void renderChc(bool plus);

    // CHC / CHC++ (ChcTraversal.cpp).
    void processNode(BvhNodeId id, bool plus);
    /// Issues the node's query (single); a node with nothing to draw is invisible at once.
    void issueSingle(BvhNodeId id, bool wasVisible, bool tight);
    void flushInvisibleQueue();
    void handleResult(const Pending& p, std::uint64_t samples, bool plus);
    void markVisible(BvhNodeId id, bool wasVisible, bool plus);
    void markInvisible(BvhNodeId id);

    QueryDevice& m_device;
    const ObjectBvh& m_bvh;
    ChcOptions m_options;
    ChcFrameStats m_stats;
    std::mt19937_64 m_rng;
    std::uint32_t m_frame = 0;
    CullMethod m_method = CullMethod::Zb;

    // Per frame.
    ViewFrustum m_frustum;
    Vec3 m_eye{0.0};
    double m_nearRadius2 = 0;
    bool m_allCandidates = true;

    // Kept across frames; sized to the hierarchy, reused (no allocation per node per frame).
    std::vector<NodeState> m_state;
    std::vector<std::uint32_t> m_nodeMark; ///< == m_frame: the subtree holds a candidate
    std::vector<std::uint32_t> m_slotMark; ///< == m_frame: the object is a candidate
    std::vector<std::uint32_t> m_candidateSlots;
    std::vector<HeapEntry> m_heap;
    std::vector<Pending> m_queue;
    std::size_t m_queueHead = 0;
    std::vector<BvhNodeId> m_multiNodes;
    std::vector<BvhNodeId> m_invisibleQueue; ///< CHC++ i-queue
    std::vector<BvhNodeId> m_visibleQueue;   ///< CHC++ v-queue
    std::size_t m_visibleHead = 0;
    std::vector<Box<3>> m_boxes;
    std::vector<Box<3>> m_groupBoxes; ///< a multiquery's boxes
    std::vector<ObjectId> m_drawBatch;
};

} // namespace rgvc
