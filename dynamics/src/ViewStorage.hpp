// ViewStorage<D>: one view's traversal stamps (H, V, U) over a scene's DenseStorage that several views
// read at once (Culler::cullViews). Internal to rgvc::dynamics.
//
// Why a second storage and not the scene's own stamps: DenseStorage keeps H and V in the voxel's cell
// next to I and O (one cache line per step, see VoxelStorage.hpp), so two traversals over the same cells
// would write each other's stamps. A view pass instead reads O, I and the brick pyramid from the scene
// (which nobody writes while view passes run) and writes only its own stamp arrays. The price is the
// arrays' memory, 2 bytes per voxel and 8 per brick row (V's and U's words) per view slot, allocated by the first cullViews with that many views
// and reused by every later one, and a second cache line per step.
#pragma once

#include "rgvc/grid/VoxelStorage.hpp"

#include <cstdint>
#include <cstdlib>
#include <vector>

namespace rgvc {

template <int D> class ViewStorage : public FrameMarks<D> {
public:
    static constexpr std::uint32_t kMaxStamp = DenseStorage<D>::kMaxStamp;
    /// Marks a storage whose scene part is shared: traversals leave the scene's brick pyramid alone.
    static constexpr bool kSharedScene = true;

    ViewStorage(const DenseStorage<D>& scene, std::size_t voxels)
        : FrameMarks<D>(scene.resolution()), m_scene(&scene), m_stamps(voxels) {}

    const BrickPyramid<D>& bricks() const { return m_scene->bricks(); }
    bool opaque(VoxelKey k) const { return m_scene->opaque(k); }
    std::size_t rowWord(std::uint32_t rowIndex, std::int32_t x) const { return m_scene->rowWord(rowIndex, x); }
    std::uint32_t opaqueBits(std::size_t w) const { return m_scene->opaqueBits(w); }
    bool hasIds(VoxelKey k) const { return m_scene->hasIds(k); }
    template <class Fn> void forEachId(VoxelKey k, Fn&& fn) const { m_scene->forEachId(k, fn); }
    void prefetchCell(VoxelKey k) const {
        m_scene->prefetchCell(k);
        __builtin_prefetch(&m_stamps[k]);
    }
    void prefetchIds(VoxelKey k) const { m_scene->prefetchIds(k); }

    bool occluded(VoxelKey k, std::uint32_t stamp) const { return m_stamps[k].occluded == stamp; }
    void setOccluded(VoxelKey k, std::uint32_t stamp) { m_stamps[k].occluded = std::uint16_t(stamp); }
    // V and U, the view's own: FrameMarks.
    void resetStamps() {
        for (Stamps& s : m_stamps) s = Stamps{};
        this->resetMarks();
    }

    // The scene's O and I are read-only here; the concept names their writers, which a view pass never
    // calls (the culler writes the scene through its DenseStorage between view passes).
    void addOpaque(VoxelKey, std::int32_t) { std::abort(); }
    void addId(VoxelKey, ObjectSlot) { std::abort(); }
    void removeId(VoxelKey, ObjectSlot) { std::abort(); }

private:
    struct Stamps {
        std::uint16_t occluded = 0;
    };
    const DenseStorage<D>* m_scene;
    std::vector<Stamps> m_stamps;
};

static_assert(VoxelStorage<ViewStorage<2>>);
static_assert(VoxelStorage<ViewStorage<3>>);

} // namespace rgvc
