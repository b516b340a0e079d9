// FaceTbvs: per face of the grid, the hidden objects whose TBV reaches past that face, with their TBVs'
// boxes. Internal to rgvc::dynamics.
//
// Why. T stores only the in-grid voxels of a TBV (TbvRegion.hpp), and a camera in the grid meets an object
// inside the grid through them: the segment between the two stays in the (convex) grid. An object that may
// leave the grid while hidden is another matter: a ray to it can leave the grid before it enters the TBV,
// and no voxel of T lies on it. Before, such TBVs were shortened to fit inside the grid (or refused, the
// object then placed every frame), unless the application promised that its objects stay in the grid
// (CullerOptions::objectsStayInGrid). Now they reach past the bounds as with the promise, and every view
// tests the parts beyond the faces against the view and its occlusion image instead
// (Culler<D>::Impl::revealFaceTbvs, TbvPolicy.cpp, which derives why that reveals what it must):
//   - one test per face first, of its slab (a closed room's walls hide all six at once);
//   - none where the face's layer of voxels is all opaque (a ground under the whole grid hides what lies
//     beneath it);
//   - a visible slab with more than 16 TBVs tested in 4 x 4 tiles (4 in 2D);
//   - then one test per part that meets a visible tile.
// The boxes are kept here, not read from the objects' records: a record is ~850 bytes, and the 100k room
// has tens of thousands of such TBVs.
#pragma once

#include "SlotSet.hpp"
#include "rgvc/grid/Shapes.hpp"
#include "rgvc/grid/VoxelStorage.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

namespace rgvc {

template <int D> class FaceTbvs {
public:
    /// Face 2a is the grid's side x_a = 0, face 2a + 1 its side x_a = resolution[a].
    static constexpr int kFaces = 2 * D;

    struct Face {
        SlotSet slots;
        std::vector<Box<D>> boxes;  // [voxel units] parallel to slots: the TBV's box
        double reach = 0;           // [voxel units] at least how far any part reaches past the face
    };

    /// A new slot exists (the culler's slots only grow).
    void addSlot() {
        for (auto& p : m_pos) p.push_back(kNone);
    }
    /// Notes the region's box (voxel units) in every face it reaches past. Returns the faces (bit f).
    std::uint8_t insert(ObjectSlot slot, const Box<D>& region, const IVec<D>& resolution) {
        std::uint8_t mask = 0;
        for (int a = 0; a < D; ++a) {
            const double res = double(resolution[a]);
            if (region.min[a] < 0) {
                add(2 * a, slot, region, -region.min[a]);
                mask = std::uint8_t(mask | (1u << (2 * a)));
            }
            if (region.max[a] > res) {
                add(2 * a + 1, slot, region, region.max[a] - res);
                mask = std::uint8_t(mask | (1u << (2 * a + 1)));
            }
        }
        return mask;
    }
    /// Takes the slot out of the faces of `mask` (insert's answer).
    void erase(ObjectSlot slot, std::uint8_t mask) {
        for (int f = 0; f < kFaces; ++f) {
            if (!(mask & (1u << f))) continue;
            Face& face = m_faces[std::size_t(f)];
            // The boxes follow the slots' swap-remove (SlotSet::erase).
            const std::uint32_t i = face.slots.erase(slot, m_pos[std::size_t(f)]);
            if (i + 1 < face.boxes.size()) face.boxes[i] = face.boxes.back();
            face.boxes.pop_back();
            if (face.slots.empty()) face.reach = 0;
        }
    }
    const Face& face(int f) const { return m_faces[std::size_t(f)]; }

private:
    void add(int f, ObjectSlot slot, const Box<D>& box, double reach) {
        Face& face = m_faces[std::size_t(f)];
        face.slots.insert(slot, m_pos[std::size_t(f)]);
        face.boxes.push_back(box); // amortised, as the slots: never more boxes than the scene has objects
        face.reach = std::max(face.reach, reach);
    }

    std::array<Face, kFaces> m_faces;
    std::array<std::vector<std::uint32_t>, kFaces> m_pos; // per face and slot: its index there, or kNone
};

} // namespace rgvc
