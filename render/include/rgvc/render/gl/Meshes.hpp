// Triangle meshes the GL stage draws, built on the CPU (no GL here), with the radii that tie them to the
// culler's shapes.
//
// §5.1 of the regular-grid paper (seed 004): the culler marks voxels opaque (O) from an *inner* model,
// contained in what is drawn, and finds objects (I, every visibility test) from an *outer* model,
// containing what is drawn. Then "culled" means "would not have changed a pixel". The sphere meshes here
// are inscribed in the unit sphere (every vertex on it), so the analytic ball of radius r is the outer
// model of the mesh scaled by r, and the ball of radius r * inradius (Mesh::inradius, the smallest
// distance from the centre to a face plane) is an inner one. Boxes and prisms are exact: inner = outer.
//
// Winding: triangles are counter-clockwise seen from outside (GL's default front face).
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace rgvc {

struct Mesh {
    std::vector<glm::vec3> positions;      ///< [Model units]
    std::vector<std::uint32_t> indices;    ///< three per triangle, counter-clockwise from outside
    /// Smallest distance from the model origin to the plane of any face ([Model units]; spheres: < 1).
    double inradius = 0;
    /// Largest distance from the model origin to any vertex ([Model units]; spheres: 1).
    double circumradius = 0;

    std::size_t triangleCount() const { return indices.size() / 3; }
};

/// Unit icosphere: an icosahedron whose triangles are split in four `level` times, vertices pushed onto
/// the unit sphere. 20 * 4^level triangles: level 3 = 1,280 (the paper's spheres are ~1,200), inradius
/// 0.9951. [Limit] 0 <= level <= 7 (327,680 triangles).
Mesh icosphere(int level);

/// Unit UV sphere (latitude-longitude): S stacks of 2S slices, triangle fans at the poles, 4S(S - 1)
/// triangles, S chosen so that the count is nearest `approxTriangles` (1,200 -> S = 18, 1,224 triangles).
/// Vertices on the unit sphere. [Limit] 8 <= approxTriangles <= 4,000,000.
Mesh uvSphere(int approxTriangles);

/// Unit box [0, 1]^3, 12 triangles (inradius and circumradius measured from the origin corner are
/// meaningless for a box: both are set to 0; a box's inner and outer models are the box itself).
Mesh unitBox();

/// A convex polygon in the xz plane (2D x -> 3D x, 2D y -> 3D z, the top view of a 2D scene) extruded
/// along y from y0 to y1: 2 * (n - 2) cap triangles and 2n side triangles. Points in either winding.
/// [Model units] [Limit] >= 3 points, convex (rgvc::validateShape checks that), y0 < y1.
Mesh prism(const std::vector<glm::dvec2>& polygon, double y0, double y1);

} // namespace rgvc
