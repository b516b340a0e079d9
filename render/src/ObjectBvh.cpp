// ObjectBvh: binned-SAH build, refit, insert and remove with stable node ids (see ObjectBvh.hpp).
#include "rgvc/render/ObjectBvh.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace rgvc {

namespace {

Box<3> emptyBox() {
    constexpr double inf = std::numeric_limits<double>::infinity();
    return {Vec3(inf), Vec3(-inf)};
}
Box<3> unite(const Box<3>& a, const Box<3>& b) { return {glm::min(a.min, b.min), glm::max(a.max, b.max)}; }
Vec3 centroid(const Box<3>& b) { return 0.5 * (b.min + b.max); }
bool sameBox(const Box<3>& a, const Box<3>& b) { return a.min == b.min && a.max == b.max; }

constexpr int kBins = 16;

} // namespace

ObjectBvh::ObjectBvh(const BvhOptions& options) : m_options(options) {
    if (options.maxLeafObjects < 1 || options.maxLeafObjects > 64)
        throw InvalidInput("bvh.max_leaf_objects", "must be in 1..64, got " + std::to_string(options.maxLeafObjects));
    if (!std::isfinite(options.rebuildRatio) || !(options.rebuildRatio > 1))
        throw InvalidInput("bvh.rebuild_ratio", "must be finite and > 1");
}

double ObjectBvh::surfaceArea(const Box<3>& b) {
    const Vec3 e = b.max - b.min;
    if (e.x < 0 || e.y < 0 || e.z < 0) return 0;
    return 2 * (e.x * e.y + e.y * e.z + e.z * e.x);
}

void ObjectBvh::validateBounds(const Box<3>& b, const char* field) {
    if (!allFinite<3>(b.min) || !allFinite<3>(b.max)) throw InvalidInput(field, "must be finite");
    for (int a = 0; a < 3; ++a)
        if (!(b.min[a] <= b.max[a])) throw InvalidInput(field, "min must not exceed max on any axis");
}

std::uint32_t ObjectBvh::slotOf(ObjectId id) const {
    const auto it = m_slotOfId.find(id);
    return it == m_slotOfId.end() ? kNoSlot : it->second;
}

BvhNodeId ObjectBvh::allocNode() {
    BvhNodeId id;
    if (!m_freeNodes.empty()) {
        id = m_freeNodes.back();
        m_freeNodes.pop_back();
    } else {
        id = BvhNodeId(m_nodes.size());
        m_nodes.emplace_back();
    }
    Node& n = m_nodes[id];
    n.bounds = emptyBox();
    n.parent = kNoBvhNode;
    n.child[0] = n.child[1] = kNoBvhNode;
    n.objects.clear();
    n.stamp = m_nextStamp++;
    n.live = true;
    return id;
}

void ObjectBvh::freeNode(BvhNodeId id) {
    Node& n = m_nodes[id];
    n.live = false;
    n.objects.clear();
    n.child[0] = n.child[1] = n.parent = kNoBvhNode;
    m_freeNodes.push_back(id);
}

std::uint32_t ObjectBvh::allocSlot() {
    if (!m_freeSlots.empty()) {
        const std::uint32_t s = m_freeSlots.back();
        m_freeSlots.pop_back();
        return s;
    }
    m_slots.emplace_back();
    return std::uint32_t(m_slots.size() - 1);
}

Box<3> ObjectBvh::recomputeBounds(BvhNodeId id) const {
    const Node& n = m_nodes[id];
    if (!n.isLeaf()) return unite(m_nodes[n.child[0]].bounds, m_nodes[n.child[1]].bounds);
    Box<3> b = emptyBox();
    for (std::uint32_t s : n.objects) b = unite(b, m_slots[s].bounds);
    return b;
}

void ObjectBvh::refitUpward(BvhNodeId id) {
    // A node whose box comes out unchanged leaves its ancestors' boxes unchanged too: stop there.
    while (id != kNoBvhNode) {
        const Box<3> b = recomputeBounds(id);
        if (sameBox(b, m_nodes[id].bounds)) return;
        m_nodes[id].bounds = b;
        id = m_nodes[id].parent;
    }
}

double ObjectBvh::sahCost() const {
    if (m_root == kNoBvhNode) return 0;
    const double rootArea = surfaceArea(m_nodes[m_root].bounds);
    if (!(rootArea > 0)) return 1;
    double sum = 0;
    for (const Node& n : m_nodes)
        if (n.live) sum += surfaceArea(n.bounds) * (n.isLeaf() ? double(n.objects.size()) : 1.0);
    return sum / rootArea;
}

double ObjectBvh::degradation() const {
    if (m_root == kNoBvhNode || !(m_builtCost > 0)) return 1;
    return sahCost() / m_builtCost;
}

bool ObjectBvh::rebuildIfDegraded() {
    if (!(degradation() > m_options.rebuildRatio)) return false;
    std::vector<BvhItem> items;
    items.reserve(m_slotOfId.size());
    for (const Slot& s : m_slots)
        if (s.live) items.push_back({s.id, s.bounds});
    build(items);
    return true;
}

void ObjectBvh::build(std::span<const BvhItem> items) {
    // Validate everything first: a rejected build leaves the tree as it was.
    std::unordered_map<ObjectId, std::uint32_t> slotOfId;
    slotOfId.reserve(items.size());
    for (std::size_t i = 0; i < items.size(); ++i) {
        const std::string field = "items[" + std::to_string(i) + "]";
        validateBounds(items[i].bounds, (field + ".bounds").c_str());
        if (!slotOfId.emplace(items[i].id, std::uint32_t(i)).second)
            throw InvalidInput(field + ".id", "duplicate object id " + std::to_string(items[i].id));
    }
    m_slotOfId = std::move(slotOfId);
    m_nodes.clear();
    m_freeNodes.clear();
    m_freeSlots.clear();
    m_slots.assign(items.size(), Slot{});
    for (std::size_t i = 0; i < items.size(); ++i) m_slots[i] = Slot{items[i].id, items[i].bounds, kNoBvhNode, true};
    m_buildSlots.resize(items.size());
    for (std::size_t i = 0; i < items.size(); ++i) m_buildSlots[i] = std::uint32_t(i);
    m_root = items.empty() ? kNoBvhNode : buildRange(0, std::uint32_t(items.size()));
    m_builtCost = sahCost();
    ++m_builds;
}

BvhNodeId ObjectBvh::buildRange(std::uint32_t begin0, std::uint32_t end0) {
    // An explicit stack: a binned SAH split may peel off a few objects at a time in skewed scenes, and
    // the depth must not be bounded by the call stack.
    struct Task {
        std::uint32_t begin, end;
        BvhNodeId parent;
        int which;
    };
    std::vector<Task> stack{{begin0, end0, kNoBvhNode, 0}};
    BvhNodeId top = kNoBvhNode;
    while (!stack.empty()) {
        const Task t = stack.back();
        stack.pop_back();
        const BvhNodeId id = allocNode();
        if (t.parent == kNoBvhNode) top = id;
        else m_nodes[t.parent].child[t.which] = id;
        m_nodes[id].parent = t.parent;

        Box<3> bounds = emptyBox(), cbounds = emptyBox();
        for (std::uint32_t i = t.begin; i < t.end; ++i) {
            const Box<3>& b = m_slots[m_buildSlots[i]].bounds;
            bounds = unite(bounds, b);
            const Vec3 c = centroid(b);
            cbounds = unite(cbounds, Box<3>{c, c});
        }
        m_nodes[id].bounds = bounds;
        const std::uint32_t count = t.end - t.begin;
        if (count <= std::uint32_t(m_options.maxLeafObjects)) {
            for (std::uint32_t i = t.begin; i < t.end; ++i) {
                m_nodes[id].objects.push_back(m_buildSlots[i]);
                m_slots[m_buildSlots[i]].leaf = id;
            }
            continue;
        }
        // Binned SAH (Wald 2007) along the centroids' longest axis.
        const Vec3 ext = cbounds.max - cbounds.min;
        const int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
        std::uint32_t mid = t.begin + count / 2;
        auto* first = m_buildSlots.data() + t.begin;
        auto* last = m_buildSlots.data() + t.end;
        auto key = [&](std::uint32_t s) { return centroid(m_slots[s].bounds)[axis]; };
        bool split = false;
        if (ext[axis] > 0) {
            const double scale = kBins / ext[axis];
            auto binOf = [&](std::uint32_t s) {
                return std::clamp(int((key(s) - cbounds.min[axis]) * scale), 0, kBins - 1);
            };
            Box<3> binBox[kBins];
            std::uint32_t binCount[kBins] = {};
            for (int b = 0; b < kBins; ++b) binBox[b] = emptyBox();
            for (auto* p = first; p != last; ++p) {
                const int b = binOf(*p);
                binBox[b] = unite(binBox[b], m_slots[*p].bounds);
                ++binCount[b];
            }
            double rightArea[kBins];
            std::uint32_t rightCount[kBins];
            Box<3> acc = emptyBox();
            std::uint32_t n = 0;
            for (int b = kBins - 1; b > 0; --b) {
                acc = unite(acc, binBox[b]);
                n += binCount[b];
                rightArea[b] = surfaceArea(acc);
                rightCount[b] = n;
            }
            acc = emptyBox();
            n = 0;
            double best = std::numeric_limits<double>::infinity();
            int bestBin = -1;
            for (int b = 1; b < kBins; ++b) { // split before bin b
                acc = unite(acc, binBox[b - 1]);
                n += binCount[b - 1];
                if (n == 0 || rightCount[b] == 0) continue;
                const double cost = surfaceArea(acc) * n + rightArea[b] * rightCount[b];
                if (cost < best) {
                    best = cost;
                    bestBin = b;
                }
            }
            if (bestBin > 0) {
                auto* m = std::partition(first, last, [&](std::uint32_t s) { return binOf(s) < bestBin; });
                mid = std::uint32_t(m - m_buildSlots.data());
                split = mid > t.begin && mid < t.end;
            }
        }
        if (!split) { // all centroids in one bin (or coincident): the median by centroid, then by slot
            mid = t.begin + count / 2;
            std::nth_element(first, m_buildSlots.data() + mid, last,
                             [&](std::uint32_t a, std::uint32_t b) { return key(a) < key(b) || (key(a) == key(b) && a < b); });
        }
        stack.push_back({mid, t.end, id, 1});
        stack.push_back({t.begin, mid, id, 0});
    }
    return top;
}

void ObjectBvh::insert(ObjectId id, const Box<3>& bounds) {
    validateBounds(bounds, "bounds");
    if (contains(id)) throw InvalidInput("id", "object " + std::to_string(id) + " is already in the hierarchy");
    const std::uint32_t slot = allocSlot();
    m_slots[slot] = Slot{id, bounds, kNoBvhNode, true};
    m_slotOfId.emplace(id, slot);
    if (m_root == kNoBvhNode) {
        m_root = allocNode();
        m_nodes[m_root].objects.push_back(slot);
        m_nodes[m_root].bounds = bounds;
        m_slots[slot].leaf = m_root;
        if (m_builtCost <= 0) m_builtCost = 1;
        return;
    }
    // Descend towards the child whose box grows least (ties: the smaller box).
    BvhNodeId n = m_root;
    while (!m_nodes[n].isLeaf()) {
        BvhNodeId pick = kNoBvhNode;
        double bestGrowth = 0, bestArea = 0;
        for (BvhNodeId c : m_nodes[n].child) {
            const double area = surfaceArea(m_nodes[c].bounds);
            const double growth = surfaceArea(unite(m_nodes[c].bounds, bounds)) - area;
            if (pick == kNoBvhNode || growth < bestGrowth || (growth == bestGrowth && area < bestArea)) {
                pick = c;
                bestGrowth = growth;
                bestArea = area;
            }
        }
        n = pick;
    }
    m_nodes[n].objects.push_back(slot);
    m_slots[slot].leaf = n;
    if (m_nodes[n].objects.size() > std::size_t(m_options.maxLeafObjects)) splitLeaf(n);
    refitUpward(n);
}

void ObjectBvh::splitLeaf(BvhNodeId leaf) {
    std::vector<std::uint32_t> objs = std::move(m_nodes[leaf].objects);
    m_nodes[leaf].objects.clear();
    Box<3> cb = emptyBox();
    for (std::uint32_t s : objs) {
        const Vec3 c = centroid(m_slots[s].bounds);
        cb = unite(cb, Box<3>{c, c});
    }
    const Vec3 ext = cb.max - cb.min;
    const int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
    std::sort(objs.begin(), objs.end(), [&](std::uint32_t a, std::uint32_t b) {
        const double ka = centroid(m_slots[a].bounds)[axis], kb = centroid(m_slots[b].bounds)[axis];
        return ka < kb || (ka == kb && a < b);
    });
    const std::size_t half = objs.size() / 2;
    const BvhNodeId kids[2] = {allocNode(), allocNode()}; // may reallocate m_nodes: index, don't hold refs
    for (int k = 0; k < 2; ++k) {
        Node& c = m_nodes[kids[k]];
        c.parent = leaf;
        c.objects.assign(objs.begin() + (k == 0 ? 0 : std::ptrdiff_t(half)),
                         k == 0 ? objs.begin() + std::ptrdiff_t(half) : objs.end());
        for (std::uint32_t s : c.objects) m_slots[s].leaf = kids[k];
        c.bounds = recomputeBounds(kids[k]);
    }
    Node& n = m_nodes[leaf];
    n.child[0] = kids[0];
    n.child[1] = kids[1];
    n.stamp = m_nextStamp++; // a leaf became an interior node: its per-node state no longer applies
}

void ObjectBvh::update(ObjectId id, const Box<3>& bounds) {
    validateBounds(bounds, "bounds");
    const std::uint32_t slot = slotOf(id);
    if (slot == kNoSlot) throw InvalidInput("id", "object " + std::to_string(id) + " is not in the hierarchy");
    m_slots[slot].bounds = bounds;
    refitUpward(m_slots[slot].leaf);
}

void ObjectBvh::remove(ObjectId id) {
    const std::uint32_t slot = slotOf(id);
    if (slot == kNoSlot) throw InvalidInput("id", "object " + std::to_string(id) + " is not in the hierarchy");
    const BvhNodeId leaf = m_slots[slot].leaf;
    auto& objs = m_nodes[leaf].objects;
    objs.erase(std::find(objs.begin(), objs.end(), slot));
    m_slots[slot].live = false;
    m_slots[slot].leaf = kNoBvhNode;
    m_freeSlots.push_back(slot);
    m_slotOfId.erase(id);
    if (!objs.empty()) {
        refitUpward(leaf);
        return;
    }
    if (leaf == m_root) {
        freeNode(leaf);
        m_root = kNoBvhNode;
        return;
    }
    // The emptied leaf goes with its parent; the sibling (and its subtree, ids unchanged) moves up.
    const BvhNodeId parent = m_nodes[leaf].parent;
    const BvhNodeId sibling = m_nodes[parent].child[0] == leaf ? m_nodes[parent].child[1] : m_nodes[parent].child[0];
    const BvhNodeId grand = m_nodes[parent].parent;
    m_nodes[sibling].parent = grand;
    if (grand == kNoBvhNode) m_root = sibling;
    else m_nodes[grand].child[m_nodes[grand].child[0] == parent ? 0 : 1] = sibling;
    freeNode(leaf);
    freeNode(parent);
    refitUpward(grand);
}

} // namespace rgvc
