// ChcRenderer: the frame driver, the shared helpers (candidates, frustum, near plane, query boxes) and
// the baselines ZB, VFC, stop-and-wait and Ideal. CHC and CHC++ are in ChcTraversal.cpp.
#include "rgvc/render/Chc.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

namespace rgvc {

const char* cullMethodName(CullMethod m) {
    switch (m) {
    case CullMethod::Zb: return "zb";
    case CullMethod::Vfc: return "vfc";
    case CullMethod::StopAndWait: return "sw";
    case CullMethod::Chc: return "chc";
    case CullMethod::ChcPlusPlus: return "chcpp";
    case CullMethod::Ideal: return "ideal";
    }
    return "?";
}

ChcRenderer::ChcRenderer(QueryDevice& device, const ObjectBvh& bvh, const ChcOptions& options)
    : m_device(device), m_bvh(bvh), m_options(options), m_rng(options.seed) {
    const ChcOptions& o = options;
    if (!std::isfinite(o.nearDistance) || !(o.nearDistance > 0)) throw InvalidInput("chc.near_distance", "must be finite and > 0");
    if (o.assumedVisibleFrames < 0) throw InvalidInput("chc.assumed_visible_frames", "must be >= 0");
    if (o.batchSize < 1) throw InvalidInput("chc.batch_size", "must be >= 1");
    if (o.maxMultiquerySize < 1) throw InvalidInput("chc.max_multiquery_size", "must be >= 1");
    if (!std::isfinite(o.tightBoundsRatio) || !(o.tightBoundsRatio > 0))
        throw InvalidInput("chc.tight_bounds_ratio", "must be finite and > 0");
    if (o.tightBoundsDepth < 1 || o.tightBoundsDepth > 8) throw InvalidInput("chc.tight_bounds_depth", "must be in 1..8");
    if (o.tightBoundsMaxBoxes < 1) throw InvalidInput("chc.tight_bounds_max_boxes", "must be >= 1");
}

void ChcRenderer::resetCoherence() {
    for (NodeState& s : m_state) s = NodeState{};
}

const ChcFrameStats& ChcRenderer::render(const Camera3& camera, CullMethod method, std::span<const ObjectId> candidates) {
    return renderFrame(camera, method, &candidates);
}

const ChcFrameStats& ChcRenderer::renderAll(const Camera3& camera, CullMethod method) {
    return renderFrame(camera, method, nullptr);
}

const ChcFrameStats& ChcRenderer::renderFrame(const Camera3& camera, CullMethod method, std::span<const ObjectId>* candidates) {
    // Validation first: nothing changes, and the device sees nothing, when the input is rejected.
    validateCamera<3>(camera);
    static const GridGeometry3 kWorld(Vec3(0.0), 1.0, IVec3(1)); // voxel units == world units
    ViewFrustum frustum(camera, kWorld);
    if (candidates)
        for (std::size_t i = 0; i < candidates->size(); ++i)
            if (!m_bvh.contains((*candidates)[i]))
                throw InvalidInput("candidates[" + std::to_string(i) + "]",
                                   "object " + std::to_string((*candidates)[i]) + " is not in the hierarchy");

    ++m_frame;
    m_method = method;
    m_frustum = frustum;
    m_eye = camera.position;
    const double tw = frustum.tanHalfWidth(), th = frustum.tanHalfHeight();
    // The near plane's rectangle reaches nearDistance * |(1, tw, th)| from the eye; a little more for rounding.
    // Plus 1e-7 of the eye's magnitude: a device rounds coordinates (a GPU to float), so a box within
    // rounding of the near plane's reach counts as reached.
    double magnitude = 1;
    for (int a = 0; a < 3; ++a) magnitude = std::max(magnitude, std::abs(camera.position[a]));
    const double nearRadius = m_options.nearDistance * std::sqrt(1 + tw * tw + th * th) * (1 + 1e-6) + 1e-7 * magnitude;
    m_nearRadius2 = nearRadius * nearRadius;

    const std::size_t nodes = m_bvh.nodeCapacity(), slots = m_bvh.slotCapacity();
    if (m_state.size() < nodes) m_state.resize(nodes);
    if (m_nodeMark.size() < nodes) m_nodeMark.resize(nodes, 0);
    if (m_slotMark.size() < slots) m_slotMark.resize(slots, 0);

    // Candidates: mark the objects, then their leaves and ancestors up to the first marked one.
    m_allCandidates = candidates == nullptr;
    m_candidateSlots.clear();
    if (candidates) {
        for (ObjectId id : *candidates) {
            const std::uint32_t slot = m_bvh.slotOf(id);
            if (m_slotMark[slot] == m_frame) continue;
            m_slotMark[slot] = m_frame;
            m_candidateSlots.push_back(slot);
            for (BvhNodeId n = m_bvh.leafOf(slot); n != kNoBvhNode && m_nodeMark[n] != m_frame; n = m_bvh.node(n).parent)
                m_nodeMark[n] = m_frame;
        }
    }

    beginStats(method);
    const auto t0 = std::chrono::steady_clock::now();
    m_device.beginFrame(camera);
    const bool queries = method == CullMethod::StopAndWait || method == CullMethod::Chc || method == CullMethod::ChcPlusPlus;
    if (queries && candidates != nullptr && m_candidateSlots.size() <= m_options.queryMinCandidates) {
        m_stats.queriesSkipped = true;
        m_stats.approximate = false;
        method = CullMethod::Vfc;
    }
    switch (method) {
    case CullMethod::Zb:
    case CullMethod::Ideal: renderZb(); break;
    case CullMethod::Vfc: renderVfc(); break;
    case CullMethod::StopAndWait: renderStopAndWait(); break;
    case CullMethod::Chc: renderChc(false); break;
    case CullMethod::ChcPlusPlus: renderChc(true); break;
    }
    m_device.endFrame();
    m_stats.frameMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return m_stats;
}

void ChcRenderer::beginStats(CullMethod method) {
    std::vector<ObjectId> drawn = std::move(m_stats.drawn);
    drawn.clear();
    m_stats = ChcFrameStats{};
    m_stats.drawn = std::move(drawn);
    m_stats.method = method;
    m_stats.frame = m_frame;
    const bool queries = method == CullMethod::StopAndWait || method == CullMethod::Chc || method == CullMethod::ChcPlusPlus;
    m_stats.approximate = queries && m_options.visiblePixelThreshold > 0;
}

ChcRenderer::NodeState& ChcRenderer::state(BvhNodeId id) {
    NodeState& s = m_state[id];
    const std::uint32_t stamp = m_bvh.node(id).stamp;
    if (s.stamp != stamp) s = NodeState{stamp, 0, 0, 0, false};
    return s;
}

double ChcRenderer::distance2(const Box<3>& b) const {
    const Vec3 d = glm::clamp(m_eye, b.min, b.max) - m_eye;
    return lengthSquared<3>(d);
}

void ChcRenderer::pushNode(BvhNodeId id) {
    m_heap.push_back({distance2(m_bvh.node(id).bounds), id});
    std::push_heap(m_heap.begin(), m_heap.end(), [](const HeapEntry& a, const HeapEntry& b) {
        return a.distance2 > b.distance2 || (a.distance2 == b.distance2 && a.node > b.node);
    });
}

BvhNodeId ChcRenderer::popNode() {
    std::pop_heap(m_heap.begin(), m_heap.end(), [](const HeapEntry& a, const HeapEntry& b) {
        return a.distance2 > b.distance2 || (a.distance2 == b.distance2 && a.node > b.node);
    });
    const BvhNodeId id = m_heap.back().node;
    m_heap.pop_back();
    return id;
}

void ChcRenderer::pushChildren(BvhNodeId id) {
    for (BvhNodeId c : m_bvh.node(id).child)
        if (relevant(c)) pushNode(c);
}

void ChcRenderer::traverseNode(BvhNodeId id) {
    const ObjectBvh::Node& n = m_bvh.node(id);
    if (!n.isLeaf()) {
        pushChildren(id);
        return;
    }
    m_drawBatch.clear();
    for (std::uint32_t slot : n.objects)
        if (candidateSlot(slot) && inFrustum(m_bvh.objectBounds(slot))) m_drawBatch.push_back(m_bvh.objectId(slot));
    if (m_drawBatch.empty()) return;
    m_device.drawObjects(m_drawBatch);
    ++m_stats.drawCalls;
    m_stats.objectsDrawn += std::uint32_t(m_drawBatch.size());
    m_stats.drawn.insert(m_stats.drawn.end(), m_drawBatch.begin(), m_drawBatch.end());
}

void ChcRenderer::pullUp(BvhNodeId id) {
    // Seed 001, Figure 2: every visited node was set invisible; a visible node makes its ancestors visible.
    while (id != kNoBvhNode) {
        NodeState& s = state(id);
        if (s.visible) return;
        s.visible = true;
        s.invisibleFrames = 0;
        id = m_bvh.node(id).parent;
    }
}

bool ChcRenderer::gatherBoxes(BvhNodeId id, bool tight) {
    m_boxes.clear();
    const ObjectBvh::Node& n = m_bvh.node(id);
    if (!tight) {
        m_boxes.push_back(n.bounds);
        return true;
    }
    // CHC++ tight bounds: the boxes of what lies below the node (its relevant children's, down to
    // tightBoundsDepth levels, or a leaf's candidates in the frustum), when they are cheaper to
    // rasterize (smaller total area) than the node's box. Subtrees outside the frustum or without
    // candidates drop out: nothing of them will be drawn, so nothing of them needs testing.
    gatherTight(id, m_options.tightBoundsDepth);
    if (m_boxes.empty()) return false;
    if (int(m_boxes.size()) > m_options.tightBoundsMaxBoxes) {
        m_boxes.assign(1, n.bounds);
        return true;
    }
    double area = 0;
    for (const Box<3>& b : m_boxes) area += ObjectBvh::surfaceArea(b);
    if (!(area <= m_options.tightBoundsRatio * ObjectBvh::surfaceArea(n.bounds))) m_boxes.assign(1, n.bounds);
    return true;
}

void ChcRenderer::gatherTight(BvhNodeId id, int depth) {
    const ObjectBvh::Node& n = m_bvh.node(id);
    if (int(m_boxes.size()) > m_options.tightBoundsMaxBoxes) return; // over the limit already: gatherBoxes falls back
    if (n.isLeaf()) {
        for (std::uint32_t slot : n.objects) {
            const Box<3>& b = m_bvh.objectBounds(slot);
            if (candidateSlot(slot) && inFrustum(b)) m_boxes.push_back(b);
        }
        return;
    }
    for (BvhNodeId c : n.child) {
        if (!relevant(c) || !inFrustum(m_bvh.node(c).bounds)) continue;
        if (depth <= 1) m_boxes.push_back(m_bvh.node(c).bounds);
        else gatherTight(c, depth - 1);
    }
}

std::uint64_t ChcRenderer::fetch(QueryHandle q, bool ready) {
    if (ready) return m_device.queryResult(q);
    ++m_stats.blockingFetches;
    const auto t0 = std::chrono::steady_clock::now();
    const std::uint64_t samples = m_device.queryResult(q);
    m_stats.waitMs += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return samples;
}

void ChcRenderer::renderZb() {
    // ZB and Ideal: the candidates as given (Ideal's candidates are the exact visible set), one draw call.
    m_drawBatch.clear();
    if (m_allCandidates) {
        for (std::uint32_t slot = 0; slot < m_bvh.slotCapacity(); ++slot)
            if (m_bvh.leafOf(slot) != kNoBvhNode) m_drawBatch.push_back(m_bvh.objectId(slot));
    } else {
        for (std::uint32_t slot : m_candidateSlots) m_drawBatch.push_back(m_bvh.objectId(slot));
    }
    if (m_drawBatch.empty()) return;
    m_device.drawObjects(m_drawBatch);
    ++m_stats.drawCalls;
    m_stats.objectsDrawn = std::uint32_t(m_drawBatch.size());
    m_stats.drawn.assign(m_drawBatch.begin(), m_drawBatch.end());
}

void ChcRenderer::renderVfc() {
    m_heap.clear();
    if (m_bvh.root() != kNoBvhNode && relevant(m_bvh.root())) pushNode(m_bvh.root());
    while (!m_heap.empty()) { // front to back, so that a GL device's early z rejects the hidden
        const BvhNodeId id = popNode();
        ++m_stats.nodesTraversed;
        if (!inFrustum(m_bvh.node(id).bounds)) {
            ++m_stats.nodesOutsideFrustum;
            continue;
        }
        traverseNode(id);
    }
}

void ChcRenderer::renderStopAndWait() {
    // Seed 001, §3.3: query each node in the frustum, wait, and open it (or draw a leaf) when visible.
    m_heap.clear();
    if (m_bvh.root() != kNoBvhNode && relevant(m_bvh.root())) pushNode(m_bvh.root());
    while (!m_heap.empty()) {
        const BvhNodeId id = popNode();
        ++m_stats.nodesTraversed;
        const Box<3>& b = m_bvh.node(id).bounds;
        if (!inFrustum(b)) {
            ++m_stats.nodesOutsideFrustum;
            continue;
        }
        bool visible = true;
        if (nearCamera(b)) {
            ++m_stats.nodesNearCamera;
        } else {
            gatherBoxes(id, false);
            const QueryHandle q = m_device.issueQuery(m_boxes);
            ++m_stats.singleQueries;
            m_stats.queryBoxes += std::uint32_t(m_boxes.size());
            visible = fetch(q, m_device.queryReady(q)) > m_options.visiblePixelThreshold;
        }
        if (visible) traverseNode(id);
    }
}

} // namespace rgvc
