// A bounding volume hierarchy over objects' outer bounds that persists from frame to frame: the
// hierarchy coherent hierarchical culling (Chc.hpp) keeps its per-node visibility on.
//
// CHC (seed 001, §4.1) exploits temporal coherence by remembering, per hierarchy node, whether it was
// visible and when it was last visited. That only works when a node means the same part of the scene
// from one frame to the next, so the tree is built once (binned SAH) and then *refitted*, not rebuilt,
// when objects move: a moved object updates its leaf's box and the boxes of the leaf's ancestors, and
// every node keeps its id. Objects are inserted into the leaf whose box grows least and removed with
// their leaf collapsing into its sibling, again without touching other nodes' ids.
//
// Refitting degrades the tree when objects travel far (boxes grow and overlap). The tree tracks its SAH
// cost (the sum of the boxes' surface areas, leaves weighted by their object count, over the root's) and
// rebuildIfDegraded() builds it anew when that cost exceeds `rebuildRatio` times the cost right after the
// last build. A rebuild gives every node a new stamp, so a traversal's per-node state resets.
//
// Node ids index a vector; freed ids are reused. A node's `stamp` changes whenever its id is given a new
// role (created, reused, a leaf split into an interior node, a rebuild), so per-node state kept outside
// the tree can tell that it is stale.
#pragma once

#include "rgvc/dynamics/Culler.hpp"
#include "rgvc/grid/Shapes.hpp"

#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

namespace rgvc {

/// Index of a hierarchy node, stable across refits, inserts and removes of other objects.
using BvhNodeId = std::uint32_t;
inline constexpr BvhNodeId kNoBvhNode = 0xffffffffu;

/// One object of the hierarchy: its id and outer bounds ([World units], closed, min <= max per axis).
struct BvhItem {
    ObjectId id = 0;
    Box<3> bounds;
};

/// The items of a scene's objects: their ids and outer bounds (boundsOf their shapes, world units).
inline std::vector<BvhItem> bvhItems(std::span<const ObjectDesc<3>> objects) {
    std::vector<BvhItem> items;
    items.reserve(objects.size());
    for (const ObjectDesc<3>& o : objects) items.push_back({o.id, boundsOf<3>(o.shape)});
    return items;
}

struct BvhOptions {
    /// [Objects] a node with at most this many objects becomes a leaf when built or split. [Limit] 1..64.
    int maxLeafObjects = 4;
    /// rebuildIfDegraded() rebuilds when the SAH cost exceeds this times the cost at the last build.
    /// [Limit] > 1.
    double rebuildRatio = 2.0;
};

class ObjectBvh {
public:
    struct Node {
        Box<3> bounds;                                ///< [World units] union of the subtree's object bounds.
        BvhNodeId parent = kNoBvhNode;
        BvhNodeId child[2] = {kNoBvhNode, kNoBvhNode}; ///< Both set for an interior node, neither for a leaf.
        std::vector<std::uint32_t> objects;           ///< Leaf only: object slots (see objectId()).
        std::uint32_t stamp = 0;                      ///< Changes when this id gets a new role; never 0 when live.
        bool live = false;
        bool isLeaf() const { return child[0] == kNoBvhNode; }
    };

    /// @throws InvalidInput ("bvh.max_leaf_objects", "bvh.rebuild_ratio").
    explicit ObjectBvh(const BvhOptions& options = {});

    /// Builds the tree over `items` anew (binned SAH), replacing everything. Every node gets a new stamp.
    /// @throws InvalidInput ("items[i].bounds" non-finite or min > max, "items[i].id" duplicated); the
    ///         tree is left as it was.
    void build(std::span<const BvhItem> items);
    /// Adds an object to the leaf whose box grows least (splitting it when it overflows).
    /// @throws InvalidInput ("bounds", "id" already present).
    void insert(ObjectId id, const Box<3>& bounds);
    /// The object moved: its leaf and the leaf's ancestors are refitted; no node changes id.
    /// Cost O(leaf size + depth). @throws InvalidInput ("bounds", "id" unknown).
    void update(ObjectId id, const Box<3>& bounds);
    /// Removes an object; an emptied leaf and its parent are freed, the sibling takes the parent's place
    /// (keeping its own id). @throws InvalidInput ("id" unknown).
    void remove(ObjectId id);

    /// SAH cost now over the SAH cost right after the last build (1 after a build; >= 1 usually).
    /// O(nodes): call it once a frame or less.
    double degradation() const;
    /// Rebuilds when degradation() > options.rebuildRatio. @return true when it rebuilt.
    bool rebuildIfDegraded();

    BvhNodeId root() const { return m_root; }
    const Node& node(BvhNodeId id) const { return m_nodes[id]; }
    /// Node ids are < nodeCapacity(); some of them may be free (node(id).live == false).
    std::size_t nodeCapacity() const { return m_nodes.size(); }
    std::size_t nodeCount() const { return m_nodes.size() - m_freeNodes.size(); }

    std::size_t objectCount() const { return m_slotOfId.size(); }
    bool contains(ObjectId id) const { return m_slotOfId.count(id) != 0; }
    /// Object slot of `id` (index into the per-slot accessors), or kNoSlot.
    std::uint32_t slotOf(ObjectId id) const;
    static constexpr std::uint32_t kNoSlot = 0xffffffffu;
    /// Slots are < slotCapacity(); a freed slot is reused by a later insert.
    std::size_t slotCapacity() const { return m_slots.size(); }
    ObjectId objectId(std::uint32_t slot) const { return m_slots[slot].id; }
    const Box<3>& objectBounds(std::uint32_t slot) const { return m_slots[slot].bounds; }
    BvhNodeId leafOf(std::uint32_t slot) const { return m_slots[slot].leaf; }

    /// [Count] builds and rebuilds so far.
    std::uint64_t buildCount() const { return m_builds; }
    const BvhOptions& options() const { return m_options; }

    /// Surface area of a box ([World units^2]); 0 for an inverted (empty) box.
    static double surfaceArea(const Box<3>& b);

private:
    struct Slot {
        ObjectId id = 0;
        Box<3> bounds;
        BvhNodeId leaf = kNoBvhNode;
        bool live = false;
    };

    static void validateBounds(const Box<3>& b, const char* field);
    BvhNodeId allocNode();
    void freeNode(BvhNodeId id);
    /// Sum over live nodes of surfaceArea(bounds), leaves weighted by their object count, over the
    /// root's area: the SAH cost with unit traversal and intersection costs. O(nodes).
    double sahCost() const;
    Box<3> recomputeBounds(BvhNodeId id) const;
    void refitUpward(BvhNodeId id);
    /// Builds a subtree over m_buildSlots[begin, end); returns its root id.
    BvhNodeId buildRange(std::uint32_t begin, std::uint32_t end);
    /// Splits an overflowing leaf into two children (the leaf becomes an interior node).
    void splitLeaf(BvhNodeId leaf);
    std::uint32_t allocSlot();

    BvhOptions m_options;
    std::vector<Node> m_nodes;
    std::vector<BvhNodeId> m_freeNodes;
    BvhNodeId m_root = kNoBvhNode;
    std::vector<Slot> m_slots;
    std::vector<std::uint32_t> m_freeSlots;
    std::unordered_map<ObjectId, std::uint32_t> m_slotOfId;
    std::vector<std::uint32_t> m_buildSlots; ///< scratch of build()
    std::uint32_t m_nextStamp = 1;
    double m_builtCost = 1; ///< sahCost() right after the last build
    std::uint64_t m_builds = 0;
};

} // namespace rgvc
