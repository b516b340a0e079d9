// Regular grid geometry: cubic voxels, world <-> voxel mapping.
//
// Bounds convention (the scene-format contract): voxel v covers the *closed* box
//   [origin + v*d, origin + (v+1)*d]   on every axis,
// so neighbouring voxels share their faces. A world point on a shared face lies in both voxels;
// `voxelOf` picks the one with the larger index (floor), which is only a choice of representative:
// every conservative test in rgvc treats voxels as closed sets.
//
// Voxel units: local(p) = (p - origin) / d. In voxel units voxel v is [v, v+1] and its centre is v + 0.5.
#pragma once

#include "rgvc/grid/Error.hpp"
#include "rgvc/grid/Math.hpp"

#include <algorithm>
#include <cstddef>
#include <limits>
#include <string>

namespace rgvc {

template <int D> class GridGeometry {
public:
    static_assert(D == 2 || D == 3, "rgvc grids are 2D or 3D");

    /// Largest voxel count accepted, 2^31 - 1, so that linear indices fit in 32 bits.
    static constexpr std::int64_t kMaxVoxels = std::numeric_limits<std::int32_t>::max();

    GridGeometry() = default;

    /// @param origin     [World units] lower corner of voxel 0. Finite.
    /// @param voxelSize  [World units] edge length d of every voxel. Finite, > 0.
    /// @param resolution [Voxels] per axis. Each >= 1; the product <= kMaxVoxels.
    /// @throws InvalidInput ("grid.origin", "grid.voxel_size", "grid.resolution").
    GridGeometry(const Vec<D>& origin, double voxelSize, const IVec<D>& resolution)
        : m_origin(origin), m_voxelSize(voxelSize), m_resolution(resolution) {
        if (!allFinite<D>(origin)) throw InvalidInput("grid.origin", "must be finite");
        if (!std::isfinite(voxelSize) || !(voxelSize > 0))
            throw InvalidInput("grid.voxel_size", "must be finite and > 0, got " + std::to_string(voxelSize));
        std::int64_t count = 1;
        for (int i = 0; i < D; ++i) {
            if (resolution[i] < 1)
                throw InvalidInput("grid.resolution", "every axis must be >= 1, got " + std::to_string(resolution[i]));
            count *= resolution[i];
            if (count > kMaxVoxels)
                throw InvalidInput("grid.resolution", "more than 2^31-1 voxels in all");
        }
        // The far corner must stay finite and distinct from the origin in double precision.
        for (int i = 0; i < D; ++i) {
            double farCorner = origin[i] + voxelSize * resolution[i];
            if (!std::isfinite(farCorner) || farCorner == origin[i])
                throw InvalidInput("grid.voxel_size", "too small or too large for the origin's magnitude");
        }
        m_invVoxelSize = 1.0 / voxelSize;
        if (!std::isfinite(m_invVoxelSize)) // a subnormal size: world-to-voxel conversion would overflow
            throw InvalidInput("grid.voxel_size", "too small: 1 / voxel_size overflows");
    }

    const Vec<D>& origin() const { return m_origin; }
    double voxelSize() const { return m_voxelSize; }
    const IVec<D>& resolution() const { return m_resolution; }
    std::size_t voxelCount() const {
        std::size_t n = 1;
        for (int i = 0; i < D; ++i) n *= std::size_t(m_resolution[i]);
        return n;
    }

    /// [Voxel units] from world coordinates.
    Vec<D> toLocal(const Vec<D>& world) const { return (world - m_origin) * m_invVoxelSize; }
    /// [World units] from voxel units.
    Vec<D> toWorld(const Vec<D>& local) const { return m_origin + local * m_voxelSize; }
    /// [World units] lengths to voxel units.
    double toLocalLength(double worldLength) const { return worldLength * m_invVoxelSize; }

    /// [Voxel units] slack that covers the rounding of the world-to-voxel conversion of a point of
    /// magnitude up to `worldMagnitude` (and of the grid's own corners): (p - origin) / d is off by at most
    /// a few ulps of max(|p|, |origin|) / d. We allow 16 ulps (16 * 2^-52 * M / d) on top of
    /// kConservativeSlack: ~1e-9 voxel for any grid of ordinary size, 4e-6 voxel for a grid at 1e6 with
    /// 1e-3 voxels. The conservative tests widen accordingly.
    double conversionSlack(double worldMagnitude = 0) const {
        double m = std::abs(worldMagnitude);
        for (int i = 0; i < D; ++i)
            m = std::max(m, std::max(std::abs(m_origin[i]), std::abs(m_origin[i] + m_voxelSize * m_resolution[i])));
        return kConservativeSlack + 16 * 2.220446049250313e-16 * m * m_invVoxelSize;
    }

    /// The voxel whose closed box contains the local point (floor); may lie outside the grid.
    /// Coordinates are clamped to +-2^30 so that the result is always representable.
    static IVec<D> voxelOfLocal(const Vec<D>& local) {
        IVec<D> v;
        for (int i = 0; i < D; ++i) {
            double f = std::floor(local[i]);
            f = f < -1073741824.0 ? -1073741824.0 : (f > 1073741824.0 ? 1073741824.0 : f);
            v[i] = std::int32_t(f);
        }
        return v;
    }
    IVec<D> voxelOf(const Vec<D>& world) const { return voxelOfLocal(toLocal(world)); }

    bool contains(const IVec<D>& v) const {
        for (int i = 0; i < D; ++i)
            if (v[i] < 0 || v[i] >= m_resolution[i]) return false;
        return true;
    }
    /// True when the local point lies in the closed grid box [0, resolution].
    bool containsLocal(const Vec<D>& local) const {
        for (int i = 0; i < D; ++i)
            if (!(local[i] >= 0.0 && local[i] <= double(m_resolution[i]))) return false;
        return true;
    }

    /// Row-major linear index (x fastest). Requires contains(v).
    std::uint32_t linearIndex(const IVec<D>& v) const {
        std::uint32_t i = std::uint32_t(v[D - 1]);
        for (int a = D - 2; a >= 0; --a) i = i * std::uint32_t(m_resolution[a]) + std::uint32_t(v[a]);
        return i;
    }

private:
    Vec<D> m_origin{0.0};
    double m_voxelSize = 1.0;
    double m_invVoxelSize = 1.0;
    IVec<D> m_resolution{1};
};

using GridGeometry2 = GridGeometry<2>;
using GridGeometry3 = GridGeometry<3>;

} // namespace rgvc
