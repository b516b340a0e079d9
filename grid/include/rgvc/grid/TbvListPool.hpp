// TbvListPool: the lists of T, one per T cell, holding TBV slots, with removal of a whole TBV in time
// proportional to its own cells.
//
// Why not SlotListPool (I's lists): removing one slot from a singly linked list walks the list, and T
// lists get long where many TBVs overlap (clustered objects; in 3D, a brick's list holds every TBV whose
// shell reaches into its 8^3 voxels). Profiling the moving-spheres benchmark showed those walks
// as 90% of the frame. Here every node is doubly linked in its cell's list, and each slot's nodes are
// known to its owner (TbvSlotNodes), so erasing a TBV unlinks its nodes directly, whatever the lists'
// lengths.
#pragma once

#include "rgvc/grid/VoxelStorage.hpp"

#include <cstdint>
#include <vector>

namespace rgvc {

/// Where one slot's nodes are: the first kInline by index, the others chained through their nodes. The
/// owner keeps it next to what it reads with the slot's nodes (TbvMatrix<3>: in the slot's box record,
/// one cache line for both). Why not a chain through every node: the nodes of a slot lie anywhere in the
/// pool, and erasing a TBV followed the chain one node at a time, each a cache miss that had to finish
/// before the next could start (the 100k room's renewals: two thirds of an erase waited on it, in perf);
/// indices in one line let the processor fetch the nodes at once.
struct TbvSlotNodes {
    static constexpr std::uint32_t kInline = 6;
    std::uint32_t node[kInline] = {}; // the first min(count, kInline) are the slot's
    std::uint32_t count = 0;        // the slot's nodes
    std::uint32_t overflow = kNone; // its nodes past kInline, chained through Node::slotNext
};

class TbvListPool {
public:
    TbvListPool() = default;
    TbvListPool(const TbvListPool&) = delete; // nodes point at their owner's list heads
    TbvListPool& operator=(const TbvListPool&) = delete;

    template <class Fn> void forEach(std::uint32_t head, Fn&& fn) const {
        for (std::uint32_t n = head; n != kNone; n = m_nodes[n].next) fn(m_nodes[n].slot);
    }

    /// Adds slot to the list whose head word is `head`, noting the node in `nodes` (the slot's). The head
    /// word must not move while the node lives (the owner's head arrays are allocated once).
    void add(std::uint32_t& head, ObjectSlot slot, TbvSlotNodes& nodes) {
        std::uint32_t n;
        if (m_free != kNone) {
            n = m_free;
            m_free = m_nodes[n].next;
        } else {
            n = std::uint32_t(m_nodes.size());
            m_nodes.emplace_back(); // amortised growth of one pool, not a per-voxel allocation
        }
        std::uint32_t chained = kNone;
        if (nodes.count < TbvSlotNodes::kInline) {
            nodes.node[nodes.count] = n;
        } else {
            chained = nodes.overflow;
            nodes.overflow = n;
        }
        ++nodes.count;
        m_nodes[n] = {slot, head, kNone, chained, &head};
        if (head != kNone) m_nodes[head].prev = n;
        head = n;
        ++m_used;
    }

    /// Removes every node noted in `nodes` (left empty), calling onHead(head) with the head word of each
    /// node's list first (the owner learns which lists changed). Returns how many.
    template <class OnHead> std::size_t eraseAll(TbvSlotNodes& nodes, OnHead&& onHead) {
        const std::uint32_t count = nodes.count;
        const std::uint32_t direct = count < TbvSlotNodes::kInline ? count : TbvSlotNodes::kInline;
        for (std::uint32_t i = 0; i < direct; ++i) unlink(nodes.node[i], onHead);
        for (std::uint32_t n = nodes.overflow; n != kNone;) {
            const std::uint32_t following = m_nodes[n].slotNext;
            unlink(n, onHead);
            n = following;
        }
        nodes.count = 0;
        nodes.overflow = kNone;
        m_used -= count;
        return count;
    }
    std::size_t eraseAll(TbvSlotNodes& nodes) {
        return eraseAll(nodes, [](const std::uint32_t*) {});
    }

    /// Nodes in use.
    std::size_t size() const { return m_used; }

private:
    struct Node {
        ObjectSlot slot;
        std::uint32_t next, prev; // in the cell's list
        std::uint32_t slotNext;   // the slot's next overflow node (TbvSlotNodes)
        std::uint32_t* head;      // the cell's head word
    };

    /// Takes node n out of its list and onto the free list.
    template <class OnHead> void unlink(std::uint32_t n, OnHead& onHead) {
        Node& node = m_nodes[n];
        onHead(static_cast<const std::uint32_t*>(node.head));
        if (node.prev == kNone) *node.head = node.next;
        else m_nodes[node.prev].next = node.next;
        if (node.next != kNone) m_nodes[node.next].prev = node.prev;
        node.next = m_free;
        m_free = n;
    }

    std::vector<Node> m_nodes;
    std::uint32_t m_free = kNone;
    std::size_t m_used = 0;
};

} // namespace rgvc
