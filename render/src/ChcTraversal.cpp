// ChcRenderer: coherent hierarchical culling (seed 001, §4 and §5.1-5.2) and what CHC++ (Mattausch,
// Bittner and Wimmer, EG 2008) adds to it: batched queries of previously invisible nodes, multiqueries,
// tight bounds and a randomized first t_av. The camera-inside-a-node rule is shared with every method
// (see Chc.hpp).
#include "rgvc/render/Chc.hpp"

#include <algorithm>
#include <cmath>

namespace rgvc {

namespace {

/// CHC++'s estimate of the probability that a node found invisible in each of the last `frames` frames
/// stays invisible this frame: 0.99 - 0.7 e^(-frames), fitted in the CHC++ paper over several scenes.
double keepInvisibleProbability(std::uint32_t frames) { return 0.99 - 0.7 * std::exp(-double(std::min(frames, 50u))); }

} // namespace

void ChcRenderer::renderChc(bool plus) {
    m_heap.clear();
    m_queue.clear();
    m_queueHead = 0;
    m_multiNodes.clear();
    m_invisibleQueue.clear();
    m_visibleQueue.clear();
    m_visibleHead = 0;
    if (m_bvh.root() != kNoBvhNode && relevant(m_bvh.root())) pushNode(m_bvh.root());
    const bool tight = plus && m_options.tightBounds;
    for (;;) {
        // PART 1 (Figure 2): fetch the finished queries in issue order; wait only when there is nothing
        // else to do. CHC++ first issues its pending batch and then its previously visible nodes' queries
        // (the v-queue) to fill the time it would otherwise wait.
        while (m_queueHead < m_queue.size()) {
            const Pending p = m_queue[m_queueHead]; // a copy: handleResult may append to m_queue
            const bool ready = m_device.queryReady(p.handle);
            if (!ready) {
                if (!m_heap.empty()) break;
                if (plus && !m_invisibleQueue.empty()) {
                    flushInvisibleQueue();
                    continue;
                }
                if (plus && m_visibleHead < m_visibleQueue.size()) {
                    issueSingle(m_visibleQueue[m_visibleHead++], true, tight);
                    continue;
                }
            }
            ++m_queueHead;
            handleResult(p, fetch(p.handle, ready), plus);
        }
        // PART 2: the front-to-back traversal (§4.4: a priority queue on the distance to the node's box).
        if (!m_heap.empty()) {
            processNode(popNode(), plus);
            continue;
        }
        if (plus && !m_invisibleQueue.empty()) {
            flushInvisibleQueue();
            continue;
        }
        if (plus && m_visibleHead < m_visibleQueue.size()) {
            // The previously visible nodes' queries decide the next frame only: issued last, they test
            // against the whole frame's depth (CHC++).
            while (m_visibleHead < m_visibleQueue.size()) issueSingle(m_visibleQueue[m_visibleHead++], true, tight);
            continue;
        }
        if (m_queueHead >= m_queue.size()) break;
    }
}

void ChcRenderer::processNode(BvhNodeId id, bool plus) {
    ++m_stats.nodesTraversed;
    const ObjectBvh::Node& n = m_bvh.node(id);
    if (!inFrustum(n.bounds)) {
        ++m_stats.nodesOutsideFrustum;
        return;
    }
    NodeState& s = state(id);
    // Figure 2, lines 21-27: previously visible = visible and visited in the last frame; an interior
    // such node was opened. Every visited node starts invisible; visibility is pulled up from below.
    const bool wasVisible = s.visible && s.lastVisited + 1 == m_frame;
    s.visible = false;
    s.lastVisited = m_frame;
    if (nearCamera(n.bounds)) {
        // The near plane may clip the box: a query would count only its far faces. Visible, no query.
        ++m_stats.nodesNearCamera;
        pullUp(id);
        traverseNode(id);
        return;
    }
    if (wasVisible && !n.isLeaf()) { // opened: no query (§4.1; seed 000, hierarchy updating)
        traverseNode(id);
        return;
    }
    if (wasVisible) {
        // A previously visible leaf is drawn at once; its query only decides the next frame (§4.1).
        if (m_options.assumedVisibleFrames > 1 && m_frame < s.nextQueryFrame) { // §5.1: t_av
            ++m_stats.nodesAssumedVisible;
            pullUp(id);
        } else if (plus) {
            m_visibleQueue.push_back(id);
        } else {
            issueSingle(id, true, false);
        }
        traverseNode(id);
        return;
    }
    if (plus) { // CHC++: batch the previously invisible nodes' queries
        m_invisibleQueue.push_back(id);
        if (int(m_invisibleQueue.size()) >= m_options.batchSize) flushInvisibleQueue();
    } else {
        issueSingle(id, false, false);
    }
}

void ChcRenderer::issueSingle(BvhNodeId id, bool wasVisible, bool tight) {
    if (!gatherBoxes(id, tight)) { // no candidate of it lies in the frustum: nothing to draw, nothing to ask
        markInvisible(id);
        return;
    }
    const QueryHandle q = m_device.issueQuery(m_boxes);
    ++m_stats.singleQueries;
    m_stats.queryBoxes += std::uint32_t(m_boxes.size());
    m_queue.push_back({q, id, 0, wasVisible});
}

void ChcRenderer::flushInvisibleQueue() {
    const bool tight = m_options.tightBounds;
    std::vector<BvhNodeId>& iq = m_invisibleQueue;
    if (!m_options.multiqueries) {
        for (BvhNodeId id : iq) issueSingle(id, false, tight);
        iq.clear();
        return;
    }
    // CHC++ multiqueries: one query for several nodes expected to stay invisible. The nodes invisible
    // longest come first; a group grows while the value n / E[cost] grows, where a query costs 1 and a
    // failed one (probability 1 - prod p_i) costs n more for the individual requeries.
    for (BvhNodeId id : iq) state(id); // refresh stale states before reading their history
    std::sort(iq.begin(), iq.end(), [&](BvhNodeId a, BvhNodeId b) {
        const std::uint32_t fa = m_state[a].invisibleFrames, fb = m_state[b].invisibleFrames;
        return fa > fb || (fa == fb && a < b);
    });
    std::size_t i = 0;
    while (i < iq.size()) {
        std::size_t j = i;
        double keepAll = 1, bestValue = 0;
        while (j < iq.size() && int(j - i) < m_options.maxMultiquerySize) {
            const double keep = keepAll * keepInvisibleProbability(m_state[iq[j]].invisibleFrames);
            const double n = double(j - i + 1);
            const double value = n == 1 ? 1.0 : n / (1 + (1 - keep) * n);
            if (j > i && value < bestValue) break;
            keepAll = keep;
            bestValue = value;
            ++j;
        }
        if (j - i == 1) {
            issueSingle(iq[i], false, tight);
            i = j;
            continue;
        }
        // The group's boxes: each node's (tight) boxes; a node with nothing to draw drops out, invisible.
        m_groupBoxes.clear();
        const std::size_t first = m_multiNodes.size();
        for (std::size_t k = i; k < j; ++k) {
            if (!gatherBoxes(iq[k], tight)) {
                markInvisible(iq[k]);
                continue;
            }
            m_multiNodes.push_back(iq[k]);
            m_groupBoxes.insert(m_groupBoxes.end(), m_boxes.begin(), m_boxes.end());
        }
        const std::size_t count = m_multiNodes.size() - first;
        if (count == 1) {
            const BvhNodeId only = m_multiNodes.back();
            m_multiNodes.pop_back();
            issueSingle(only, false, tight);
        } else if (count > 1) {
            const QueryHandle q = m_device.issueQuery(m_groupBoxes);
            ++m_stats.multiQueries;
            m_stats.nodesInMultiQueries += std::uint32_t(count);
            m_stats.queryBoxes += std::uint32_t(m_groupBoxes.size());
            m_queue.push_back({q, std::uint32_t(first), std::uint32_t(count), false});
        }
        i = j;
    }
    iq.clear();
}

void ChcRenderer::handleResult(const Pending& p, std::uint64_t samples, bool plus) {
    const bool visible = samples > m_options.visiblePixelThreshold;
    if (p.count == 0) {
        if (visible) markVisible(p.first, p.wasVisible, plus);
        else markInvisible(p.first);
        return;
    }
    if (!visible) {
        for (std::uint32_t k = 0; k < p.count; ++k) markInvisible(m_multiNodes[p.first + k]);
        return;
    }
    // Something of the group is visible: ask each node on its own (CHC++).
    ++m_stats.multiQueryFailures;
    for (std::uint32_t k = 0; k < p.count; ++k) issueSingle(m_multiNodes[p.first + k], false, m_options.tightBounds);
}

void ChcRenderer::markVisible(BvhNodeId id, bool wasVisible, bool plus) {
    pullUp(id);
    const int tav = m_options.assumedVisibleFrames;
    if (tav > 1 && m_bvh.node(id).isLeaf()) {
        // §5.1; CHC++ draws the first interval of a node that just became visible at random from
        // [1, t_av], so that nodes that appear together are not all queried again in the same frame.
        const int interval = plus && !wasVisible ? 1 + int(m_rng() % std::uint64_t(tav)) : tav;
        state(id).nextQueryFrame = m_frame + std::uint32_t(interval);
    }
    if (!wasVisible) traverseNode(id); // pull-down: open it, or draw the leaf
}

void ChcRenderer::markInvisible(BvhNodeId id) {
    NodeState& s = state(id);
    if (s.invisibleFrames < 0xffffu) ++s.invisibleFrames;
}

} // namespace rgvc
