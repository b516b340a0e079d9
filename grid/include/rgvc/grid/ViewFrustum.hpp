// The 3D view region in voxel units: a symmetric perspective frustum with apex at the camera and no
// near plane, optionally cut by the closed ball of radius `far`; and the conservative box tests.
#pragma once

#include "rgvc/grid/Camera.hpp"
#include "rgvc/grid/GridGeometry.hpp"
#include "rgvc/grid/Math.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace rgvc {

class ViewFrustum {
public:
    ViewFrustum() = default;
    /// @param camera  validated camera (see validateCamera), world units. `up` zero means (0, 1, 0).
    /// @throws InvalidInput ("camera.up") when up is parallel to the direction.
    ViewFrustum(const Camera3& camera, const GridGeometry3& grid);

    const Vec3& apex() const { return m_apex; }
    const Vec3& forward() const { return m_forward; }
    /// Unit vectors of the image: right = forward x up, trueUp = right x forward (orthonormal with forward).
    const Vec3& right() const { return m_right; }
    const Vec3& trueUp() const { return m_trueUp; }
    /// Half extents of the image on the plane at distance 1 along forward: the view's directions are
    /// forward + x right + y trueUp with |x| <= tanHalfWidth(), |y| <= tanHalfHeight().
    double tanHalfWidth() const { return m_tanHalfWidth; }
    double tanHalfHeight() const { return m_tanHalfHeight; }
    double far() const { return m_far; }
    /// [Voxel units] tolerance of the touch tests: the grid's conversionSlack().
    double slack() const { return m_slack; }
    /// Unit directions of the four edge rays (the frustum is the cone they span).
    const Vec3& edge(int i) const { return m_edges[i]; }
    /// Inward unit normals of the four side planes through the apex.
    const Vec3& sideNormal(int i) const { return m_normals[i]; }

    /// Conservative: true whenever the closed box meets the closed view region. Tests the four side
    /// planes and the far ball separately, so it may also answer true for boxes near the frustum's edges
    /// (never false for a box that touches it).
    bool touchesBox(const Vec3& lo, const Vec3& hi) const { return withinFar(lo, hi) && touchesCone(lo, hi); }
    bool touchesVoxel(const IVec3& v) const { return touchesBox(Vec3(v), Vec3(v) + 1.0); }
    bool touchesCone(const Vec3& lo, const Vec3& hi) const;
    bool withinFar(const Vec3& lo, const Vec3& hi) const;
    bool containsPoint(const Vec3& p) const;

private:
    Vec3 m_apex{0.0}, m_forward{0.0, 0.0, -1.0}, m_right{1.0, 0.0, 0.0}, m_trueUp{0.0, 1.0, 0.0};
    double m_tanHalfWidth = 1, m_tanHalfHeight = 1;
    Vec3 m_edges[4]{};
    Vec3 m_normals[4]{};
    double m_far = 0, m_slack = kConservativeSlack;
};

/// Clips the row of voxels c + o with o[b1] in [u0, u1] to those that touch the frustum's cone, with
/// the same test as ViewFrustum::touchesCone (the box corner farthest along each inward side normal),
/// solved for the row coordinate: each side plane bounds u from one side. Cost O(1) per row instead
/// of four dot products per voxel. planes: bit i set = side plane i is tested (a caller that knows a
/// whole block lies on the inner side of plane i skips it: every row of the block passes it unclipped).
inline bool clipVoxelRow(const ViewFrustum& f, const IVec3& c, const IVec3& o, int b1, std::int32_t& u0,
                         std::int32_t& u1, unsigned planes = 0xF) {
    const Vec3& apex = f.apex();
    for (int i = 0; i < 4; ++i) {
        if (((planes >> i) & 1) == 0) continue;
        const Vec3& n = f.sideNormal(i);
        double rest = 0;
        for (int ax = 0; ax < 3; ++ax) {
            if (ax == b1) continue;
            const double lo = double(c[ax] + o[ax]);
            rest += n[ax] * ((n[ax] > 0 ? lo + 1.0 : lo) - apex[ax]);
        }
        // n_b1 * (x + delta - apex_b1) + rest >= -slack, x = c[b1] + u, delta = 1 if n_b1 > 0.
        const double slack = f.slack() + 1e-12 * (std::abs(rest) + 1.0);
        const double nb = n[b1];
        if (nb == 0) {
            if (rest < -slack) return false;
            continue;
        }
        const double bound = (-slack - rest) / nb; // x + delta - apex_b1 >= bound (nb > 0) or <= (nb < 0)
        // Clamped to +-1e9 before rounding (row offsets are far smaller; bound can be huge when nb is
        // tiny), which also lets the rounding be integer conversions: std::ceil and std::floor are
        // library calls on x86-64 without SSE4.1, and this runs for every row of every shell.
        // A NaN bound (degenerate planes, found by fuzz_culler3d) clips nothing, as std::ceil's NaN did.
        if (std::isnan(bound)) continue;
        if (nb > 0) {
            const double x = std::clamp(bound + apex[b1] - 1.0 - c[b1] - 1e-9, -1e9, 1e9);
            const auto u = std::int32_t(x) + std::int32_t(double(std::int32_t(x)) < x); // ceil
            if (u > u0) u0 = u;
        } else {
            const double x = std::clamp(bound + apex[b1] - c[b1] + 1e-9, -1e9, 1e9);
            const auto u = std::int32_t(x) - std::int32_t(double(std::int32_t(x)) > x); // floor
            if (u < u1) u1 = u;
        }
        if (u0 > u1) return false;
    }
    return true;
}

/// clipVoxelRow for rows along x (b1 = 0, c = 0, o = (0, y, z)), with the planes' per-axis terms chosen
/// once: the brick traversal clips each of a brick's 64 rows against the one or two side planes the
/// brick straddles. The same arithmetic in the same order as clipVoxelRow (rest = term_y + term_z, the
/// same slack, bound and rounding), so the same spans.
class VoxelRowClipper {
public:
    VoxelRowClipper(const ViewFrustum& f, unsigned planes) : m_slack(f.slack()), m_apexX(f.apex().x) {
        const Vec3& apex = f.apex();
        for (int i = 0; i < 4; ++i) {
            if (((planes >> i) & 1) == 0) continue;
            const Vec3& n = f.sideNormal(i);
            Plane& p = m_planes[m_count++];
            p.ny = n.y;
            p.nz = n.z;
            p.nb = n.x;
            p.addY = n.y > 0 ? 1.0 : 0.0;
            p.addZ = n.z > 0 ? 1.0 : 0.0;
            p.apexY = apex.y;
            p.apexZ = apex.z;
        }
    }
    /// The voxels x in [u0, u1] of row (y, z) that touch the cone; false when none.
    bool clip(std::int32_t y, std::int32_t z, std::int32_t& u0, std::int32_t& u1) const {
        for (int k = 0; k < m_count; ++k) {
            const Plane& p = m_planes[k];
            if (!applyPlane(p, p.ny * ((double(y) + p.addY) - p.apexY) + p.nz * ((double(z) + p.addZ) - p.apexZ), u0, u1)) return false;
        }
        return true;
    }
    /// clip() for the 64 rows of an 8^3 brick at once: entry 8 dz + dy is row (y0 + dy, z0 + dz). u0 and
    /// u1 hold the rows' spans on entry and their clipped spans on return; a row clip() empties has
    /// u0 > u1 (not set to 1, 0 as clip() does). The same arithmetic in the same order as clip(), plane
    /// by plane over all 64 rows in branch-free loops, which GCC vectorizes (4 rows per AVX2
    /// instruction, also at -O2): called row by row, clip() cost 80 instructions a row, an eighth of the
    /// game world's frame in rgvc_bench_classes, for bricks at the view's edges. Rows beyond the grid's
    /// bounds are computed too; the caller reads the ones it has.
    void clipBrick(std::int32_t y0, std::int32_t z0, std::int32_t u0[64], std::int32_t u1[64]) const {
        for (int k = 0; k < m_count; ++k) {
            // Copies: stores into u0 and u1 could alias the members for all the compiler knows.
            const Plane p = m_planes[k];
            const double baseSlack = m_slack, apexX = m_apexX;
            auto rest = [&](int i) {
                return p.ny * ((double(y0 + (i & 7)) + p.addY) - p.apexY) + p.nz * ((double(z0 + (i >> 3)) + p.addZ) - p.apexZ);
            };
            // clip()'s clamp to +-1e9 and its NaN test are selects on doubles, which GCC does not
            // if-convert under -ftrapping-math (the loop stays scalar). The bound is linear in the row
            // but for the slack's tiny term, so a bound on its magnitude over the brick tells when the
            // clamp cannot act (then no NaN either: every term is finite); otherwise clip()'s code runs
            // row by row for this plane.
            const double ry = std::max(std::abs((double(y0) + p.addY) - p.apexY), std::abs((double(y0 + 7) + p.addY) - p.apexY));
            const double rz = std::max(std::abs((double(z0) + p.addZ) - p.apexZ), std::abs((double(z0 + 7) + p.addZ) - p.apexZ));
            const double rmax = std::abs(p.ny) * ry + std::abs(p.nz) * rz;
            const double xmax = (baseSlack + 1e-12 * (rmax + 1.0) + rmax) / std::abs(p.nb) + std::abs(apexX) + 2.0;
            if (p.nb == 0) {
                for (int i = 0; i < 64; ++i) {
                    const double r = rest(i);
                    const double slack = baseSlack + 1e-12 * (std::abs(r) + 1.0);
                    u1[i] = r < -slack ? std::int32_t(-1) << 30 : u1[i];
                }
            } else if (!(xmax < 1e8)) {
                for (int i = 0; i < 64; ++i)
                    if (!applyPlane(p, rest(i), u0[i], u1[i])) u1[i] = std::int32_t(-1) << 30;
            } else if (p.nb > 0) {
                for (int i = 0; i < 64; ++i) {
                    const double r = rest(i);
                    const double slack = baseSlack + 1e-12 * (std::abs(r) + 1.0);
                    const double x = (-slack - r) / p.nb + apexX - 1.0 - 0.0 - 1e-9;
                    const std::int32_t t = std::int32_t(x);
                    const std::int32_t u = t + std::int32_t(double(t) < x); // ceil
                    u0[i] = u > u0[i] ? u : u0[i];
                }
            } else {
                for (int i = 0; i < 64; ++i) {
                    const double r = rest(i);
                    const double slack = baseSlack + 1e-12 * (std::abs(r) + 1.0);
                    const double x = (-slack - r) / p.nb + apexX - 0.0 + 1e-9;
                    const std::int32_t t = std::int32_t(x);
                    const std::int32_t u = t - std::int32_t(double(t) > x); // floor
                    u1[i] = u < u1[i] ? u : u1[i];
                }
            }
        }
    }

private:
    struct Plane {
        double ny, nz, nb, addY, addZ, apexY, apexZ;
    };
    /// One plane's bound on a row whose other terms are `rest`; false when it empties the row.
    bool applyPlane(const Plane& p, double rest, std::int32_t& u0, std::int32_t& u1) const {
        const double slack = m_slack + 1e-12 * (std::abs(rest) + 1.0);
        if (p.nb == 0) return !(rest < -slack);
        const double bound = (-slack - rest) / p.nb;
        if (std::isnan(bound)) return true;
        if (p.nb > 0) {
            const double x = std::clamp(bound + m_apexX - 1.0 - 0.0 - 1e-9, -1e9, 1e9);
            const auto u = std::int32_t(x) + std::int32_t(double(std::int32_t(x)) < x); // ceil
            if (u > u0) u0 = u;
        } else {
            const double x = std::clamp(bound + m_apexX - 0.0 + 1e-9, -1e9, 1e9);
            const auto u = std::int32_t(x) - std::int32_t(double(std::int32_t(x)) > x); // floor
            if (u < u1) u1 = u;
        }
        return u0 <= u1;
    }
    Plane m_planes[4];
    int m_count = 0;
    double m_slack, m_apexX;
};

} // namespace rgvc
