// rgvc::Culler: the public, per-frame visibility API a game links against.
//
//   rgvc::GridGeometry2 grid({0, 0}, 1.0, {256, 256});
//   rgvc::Culler2D culler(grid);
//   culler.addObject({.id = 7, .shape = rgvc::Ball<2>{{40, 30}, 3.5}});
//   culler.addObject({.id = 8, .shape = rgvc::Box<2>{{60, 10}, {70, 90}}, .isStatic = true});
//   const rgvc::CullResult& r = culler.cull({.position = {10.5, 20.25}, .direction = {1, 0.2}, .fovDeg = 90});
//   for (rgvc::ObjectId id : r.pvs) draw(id);   // every visible object is in r.pvs
//   culler.updateObject(7, rgvc::Ball<2>{{41, 30}, 3.5});   // the object moved
//
// Guarantee: `cull` returns a superset of the objects visible from the camera (the contract's
// definition: some point of the object lies in the closed view region and the open segment to it meets
// no other object's interior; objects that touch along a face are fused, as occluder fusion implies).
// Objects and cameras outside the grid are legal; they take a conservative fallback reported in stats.
//
// Errors: every member validates its arguments and throws rgvc::InvalidInput ("field: what") before
// changing anything (see rgvc/grid/Error.hpp). Not thread-safe: one culler per thread.
#pragma once

#include "rgvc/grid/Camera.hpp"
#include "rgvc/grid/GridGeometry.hpp"
#include "rgvc/grid/Shapes.hpp"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace rgvc {

/// The user's object id: any non-negative integer, unique within a culler.
using ObjectId = std::uint64_t;

template <int D> struct ObjectDesc {
    ObjectId id = 0;
    Shape<D> shape;        ///< [World units] current placement.
    bool isStatic = false; ///< Never moves (§4.5): discretized once.
    double maxSpeed = 0;   ///< [World units per frame] >= 0; bounds the motion of hidden objects.
};

/// Which conservative shortcut a frame took instead of the full grid algorithm.
enum class Fallback : std::uint8_t {
    None,              ///< grid traversal only
    CameraOutsideGrid, ///< camera outside the grid box: every object touching the view region is reported
};
const char* toString(Fallback f);

struct CullStats {
    double cullMs = 0;                    ///< wall time of this cull() call
    std::uint32_t objectCount = 0;
    std::uint32_t pvsSize = 0;
    std::uint32_t layers = 0;             ///< chess-metric layers traversed
    std::uint64_t voxelsVisited = 0;      ///< in-grid voxels of the view region the traversal reached
    std::uint64_t voxelsOccluded = 0;     ///< of those, found in H and skipped
    std::uint64_t occludersExtended = 0;  ///< opaque voxels that started an occluder extension (§4.3)
    std::uint64_t occluderVoxels = 0;     ///< voxels aggregated into extended occluders
    std::uint64_t shadows = 0;            ///< occlusion polygons rasterized into H (§4.4)
    std::uint64_t voxelsMarkedOccluded = 0;
    bool earlyTermination = false;        ///< a layer was all occluded or opaque (§4.2)
    bool occlusionSkipped = false;        ///< no opaque voxel was met: no occlusion work at all
    Fallback fallback = Fallback::None;
    std::uint32_t objectsOutsideGrid = 0; ///< objects partly outside the grid, tested against the view region
};

struct CullResult {
    std::vector<ObjectId> pvs; ///< sorted ascending, no duplicates
    CullStats stats;
};

/// Per-voxel state after the last cull (for pictures, debugging and tests).
struct VoxelState {
    bool inGrid = false;
    bool opaque = false;   ///< O (including Os)
    bool occluded = false; ///< H
    bool visited = false;  ///< reached by the traversal
    bool occluder = false; ///< part of an extended occluder
    bool hasIds = false;   ///< I non-empty
};

struct CullerOptions {
    /// Use occlusion at all. false = view-frustum culling on the grid only (the VFC baseline).
    bool occlusion = true;
    /// 2D: extend opaque voxels into larger virtual occluders (§4.3). false = each run of opaque voxels
    /// in one layer side is its own occluder (no L arms, no use of occluded voxels).
    /// 3D: test each voxel against the caps of shells k-1, k-2, k-4, ... (true) or only k-1 (false:
    /// layer-by-layer propagation).
    bool occluderExtension = true;
};

template <int D> class Culler {
public:
    /// @param grid  [Limit] 2D: at most 2^20 voxels per axis (exact integer occlusion arithmetic).
    /// @throws InvalidInput when the grid is too large per axis or needs more memory than can be
    ///         allocated ("grid.resolution").
    explicit Culler(const GridGeometry<D>& grid, const CullerOptions& options = {});
    ~Culler();
    Culler(Culler&&) noexcept;
    Culler& operator=(Culler&&) noexcept;

    const GridGeometry<D>& grid() const;
    const CullerOptions& options() const;

    /// Adds an object at its current placement.
    /// @throws InvalidInput on a duplicate id, an invalid shape or a negative/non-finite maxSpeed.
    void addObject(const ObjectDesc<D>& object);
    /// Moves or reshapes an object. Cost: proportional to its old and new voxel footprints.
    /// @throws InvalidInput on an unknown id or an invalid shape.
    void updateObject(ObjectId id, const Shape<D>& shape);
    /// @throws InvalidInput on an unknown id.
    void removeObject(ObjectId id);
    bool hasObject(ObjectId id) const;
    std::size_t objectCount() const;

    /// Computes the potentially visible set for one camera.
    /// @throws InvalidInput on an invalid camera (see validateCamera).
    const CullResult& cull(const Camera<D>& camera);
    const CullResult& lastResult() const;

    /// State of voxel v after the last cull; inGrid = false outside the grid.
    VoxelState voxelState(const IVec<D>& v) const;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

using Culler2D = Culler<2>;
using Culler3D = Culler<3>;

} // namespace rgvc
