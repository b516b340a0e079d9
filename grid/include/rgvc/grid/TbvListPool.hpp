// TbvListPool: the lists of T, one per T cell, holding TBV slots, with removal of a whole TBV in time
// proportional to its own cells.
//
// Why not SlotListPool (I's lists): removing one slot from a singly linked list walks the list, and T
// lists get long where many TBVs overlap (clustered objects; in 3D, a brick's list holds every TBV whose
// shell reaches into its 8^3 voxels). Profiling the moving-spheres benchmark showed those walks
// as 90% of the frame. Here every node is doubly linked in its cell's list and also chained to the other
// nodes of its slot, so erasing a TBV unlinks its nodes directly, whatever the lists' lengths.
#pragma once

#include "rgvc/grid/VoxelStorage.hpp"

#include <cstdint>
#include <vector>

namespace rgvc {

class TbvListPool {
public:
    TbvListPool() = default;
    TbvListPool(const TbvListPool&) = delete; // nodes point at their owner's list heads
    TbvListPool& operator=(const TbvListPool&) = delete;

    template <class Fn> void forEach(std::uint32_t head, Fn&& fn) const {
        for (std::uint32_t n = head; n != kNone; n = m_nodes[n].next) fn(m_nodes[n].slot);
    }

    /// Adds slot to the list whose head word is `head`. The head word must not move while the node lives
    /// (the owner's head arrays are allocated once).
    void add(std::uint32_t& head, ObjectSlot slot) {
        if (slot >= m_slotFirst.size()) m_slotFirst.resize(std::size_t(slot) + 1, kNone);
        std::uint32_t n;
        if (m_free != kNone) {
            n = m_free;
            m_free = m_nodes[n].next;
        } else {
            n = std::uint32_t(m_nodes.size());
            m_nodes.emplace_back(); // amortised growth of one pool, not a per-voxel allocation
        }
        m_nodes[n] = {slot, head, kNone, m_slotFirst[slot], &head};
        if (head != kNone) m_nodes[head].prev = n;
        head = n;
        m_slotFirst[slot] = n;
        ++m_used;
    }

    /// Removes every node of slot, calling onHead(head) with the head word of each node's list first
    /// (the owner learns which lists changed). Returns how many.
    template <class OnHead> std::size_t eraseAll(ObjectSlot slot, OnHead&& onHead) {
        if (slot >= m_slotFirst.size()) return 0;
        std::size_t count = 0;
        for (std::uint32_t n = m_slotFirst[slot]; n != kNone;) {
            Node& node = m_nodes[n];
            onHead(static_cast<const std::uint32_t*>(node.head));
            if (node.prev == kNone) *node.head = node.next;
            else m_nodes[node.prev].next = node.next;
            if (node.next != kNone) m_nodes[node.next].prev = node.prev;
            const std::uint32_t following = node.slotNext;
            node.next = m_free;
            m_free = n;
            n = following;
            ++count;
        }
        m_slotFirst[slot] = kNone;
        m_used -= count;
        return count;
    }
    std::size_t eraseAll(ObjectSlot slot) {
        return eraseAll(slot, [](const std::uint32_t*) {});
    }

    /// Nodes in use.
    std::size_t size() const { return m_used; }

private:
    struct Node {
        ObjectSlot slot;
        std::uint32_t next, prev; // in the cell's list
        std::uint32_t slotNext;   // the slot's next node
        std::uint32_t* head;      // the cell's head word
    };
    std::vector<Node> m_nodes;
    std::vector<std::uint32_t> m_slotFirst; // per slot: its first node
    std::uint32_t m_free = kNone;
    std::size_t m_used = 0;
};

} // namespace rgvc
