// SlotSet: a set of object slots with O(1) insert, erase and dense iteration. The culler keeps one per
// object state (tracked, hidden, parked, outside the grid) so that each frame walks only the objects
// it must, never the whole scene.
#pragma once

#include "rgvc/grid/VoxelStorage.hpp"

#include <cstdint>
#include <vector>

namespace rgvc {

class SlotSet {
public:
    /// pos: the member's position, stored by its owner; kNone when not a member. Returns the new member's
    /// index (the last), so that an owner can keep data parallel to the members (FaceTbvs.hpp).
    std::uint32_t insert(ObjectSlot s, std::vector<std::uint32_t>& pos) {
        const auto i = std::uint32_t(m_slots.size());
        pos[s] = i;
        m_slots.push_back(s); // amortised: the set never holds more slots than the scene has objects
        return i;
    }
    /// Erase swaps the last member into the hole: a loop erasing slots()[i] re-reads index i next. Returns
    /// the hole's index, which now holds the former last member (or is past the end when s was last).
    std::uint32_t erase(ObjectSlot s, std::vector<std::uint32_t>& pos) {
        const std::uint32_t i = pos[s];
        const ObjectSlot last = m_slots.back();
        m_slots[i] = last;
        pos[last] = i;
        m_slots.pop_back();
        pos[s] = kNone;
        return i;
    }
    static bool contains(ObjectSlot s, const std::vector<std::uint32_t>& pos) { return pos[s] != kNone; }

    std::size_t size() const { return m_slots.size(); }
    bool empty() const { return m_slots.empty(); }
    ObjectSlot operator[](std::size_t i) const { return m_slots[i]; }

private:
    std::vector<ObjectSlot> m_slots;
};

} // namespace rgvc
