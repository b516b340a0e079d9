#include "rgvc/render/gl/Meshes.hpp"

#include "rgvc/grid/Error.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>

namespace rgvc {

namespace {

constexpr double kPi = 3.14159265358979323846;

/// Fills inradius (smallest face-plane distance from the origin, in double from the float vertices that
/// are drawn) and circumradius (largest vertex distance).
void measure(Mesh& m) {
    double inr = std::numeric_limits<double>::infinity(), outr = 0;
    for (const glm::vec3& p : m.positions) outr = std::max(outr, glm::length(glm::dvec3(p)));
    for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
        const glm::dvec3 a(m.positions[m.indices[t]]), b(m.positions[m.indices[t + 1]]), c(m.positions[m.indices[t + 2]]);
        const glm::dvec3 n = glm::cross(b - a, c - a);
        const double len = glm::length(n);
        if (len > 0) inr = std::min(inr, std::abs(glm::dot(n, a)) / len);
    }
    m.inradius = std::isfinite(inr) ? inr : 0;
    m.circumradius = outr;
}

/// Float vertices of a unit-sphere mesh rounded to the sphere may sit a rounding step outside it; scale
/// each one down until its double length is at most 1, so that the drawn mesh stays inside the ball.
glm::vec3 onUnitSphere(glm::dvec3 p) {
    glm::vec3 f(p / glm::length(p));
    while (glm::length(glm::dvec3(f)) > 1.0) f *= 1.0f - 1e-7f;
    return f;
}

} // namespace

Mesh icosphere(int level) {
    if (level < 0 || level > 7) throw InvalidInput("icosphere.level", "must be in [0, 7], got " + std::to_string(level));
    // The icosahedron: vertices (0, +-1, +-t) and their cyclic permutations, t the golden ratio.
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<glm::dvec3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                                 {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    for (glm::dvec3& p : v) p = glm::normalize(p);
    std::vector<std::uint32_t> f = {0, 11, 5, 0, 5, 1,  0, 1, 7,   0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4,
                                    11, 10, 2, 10, 7, 6, 7, 1, 8, 3, 9, 4,  3, 4, 2,   3, 2, 6, 3, 6, 8,
                                    3, 8, 9,  4, 9, 5,  2, 4, 11, 6, 2, 10, 8, 6, 7,   9, 8, 1};
    for (int l = 0; l < level; ++l) {
        // Each edge's midpoint is made once (keyed by its sorted endpoints), so the mesh stays watertight.
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
        auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
            const auto key = std::minmax(a, b);
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            v.push_back(glm::normalize(v[a] + v[b]));
            const auto i = std::uint32_t(v.size() - 1);
            mid.emplace(key, i);
            return i;
        };
        std::vector<std::uint32_t> g;
        g.reserve(f.size() * 4);
        for (std::size_t i = 0; i < f.size(); i += 3) {
            const std::uint32_t a = f[i], b = f[i + 1], c = f[i + 2];
            const std::uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
            g.insert(g.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
        }
        f = std::move(g);
    }
    Mesh m;
    m.positions.reserve(v.size());
    for (const glm::dvec3& p : v) m.positions.push_back(onUnitSphere(p));
    m.indices = std::move(f);
    measure(m);
    return m;
}

Mesh uvSphere(int approxTriangles) {
    if (approxTriangles < 8 || approxTriangles > 4000000)
        throw InvalidInput("uvSphere.approxTriangles", "must be in [8, 4000000], got " + std::to_string(approxTriangles));
    // 4S(S - 1) triangles: pick the S whose count is nearest.
    int stacks = 2;
    while (std::abs(4.0 * (stacks + 1) * stacks - approxTriangles) < std::abs(4.0 * stacks * (stacks - 1) - approxTriangles))
        ++stacks;
    const int slices = 2 * stacks;
    Mesh m;
    m.positions.push_back({0, 1, 0}); // north pole
    for (int i = 1; i < stacks; ++i) {
        const double theta = kPi * i / stacks;
        for (int j = 0; j < slices; ++j) {
            const double phi = 2 * kPi * j / slices;
            m.positions.push_back(onUnitSphere({std::sin(theta) * std::cos(phi), std::cos(theta), -std::sin(theta) * std::sin(phi)}));
        }
    }
    m.positions.push_back({0, -1, 0}); // south pole
    const auto south = std::uint32_t(m.positions.size() - 1);
    auto ring = [&](int i, int j) { return std::uint32_t(1 + (i - 1) * slices + (j % slices)); };
    // phi grows counter-clockwise seen from above (+y), so (ring j, ring j+1) runs counter-clockwise.
    for (int j = 0; j < slices; ++j) m.indices.insert(m.indices.end(), {0u, ring(1, j), ring(1, j + 1)});
    for (int i = 1; i + 1 < stacks; ++i)
        for (int j = 0; j < slices; ++j) {
            const std::uint32_t a = ring(i, j), b = ring(i, j + 1), c = ring(i + 1, j), d = ring(i + 1, j + 1);
            m.indices.insert(m.indices.end(), {a, c, d, a, d, b});
        }
    for (int j = 0; j < slices; ++j) m.indices.insert(m.indices.end(), {south, ring(stacks - 1, j + 1), ring(stacks - 1, j)});
    measure(m);
    return m;
}

Mesh unitBox() {
    Mesh m;
    for (int i = 0; i < 8; ++i) m.positions.push_back({float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1)});
    // Corner index bits: x = 1, y = 2, z = 4. Two triangles per face, counter-clockwise from outside.
    m.indices = {0, 4, 6, 0, 6, 2,  // x = 0
                 1, 3, 7, 1, 7, 5,  // x = 1
                 0, 1, 5, 0, 5, 4,  // y = 0
                 2, 6, 7, 2, 7, 3,  // y = 1
                 0, 2, 3, 0, 3, 1,  // z = 0
                 4, 5, 7, 4, 7, 6}; // z = 1
    return m;
}

Mesh prism(const std::vector<glm::dvec2>& polygon, double y0, double y1) {
    const std::size_t n = polygon.size();
    if (n < 3) throw InvalidInput("prism.polygon", "a polygon needs at least 3 points");
    if (!(y0 < y1)) throw InvalidInput("prism.y1", "must exceed y0");
    double area = 0;
    for (std::size_t i = 0; i < n; ++i) area += polygon[i].x * polygon[(i + 1) % n].y - polygon[(i + 1) % n].x * polygon[i].y;
    if (!(std::abs(area) > 0)) throw InvalidInput("prism.polygon", "polygon has zero area");
    // Counter-clockwise in (x, y) of the 2D scene. Mapped to (x, z), seen from +y that is clockwise
    // (x right, z towards the viewer), so the top cap reverses the order and the bottom keeps it.
    std::vector<glm::dvec2> p(polygon);
    if (area < 0) std::reverse(p.begin(), p.end());
    Mesh m;
    for (const glm::dvec2& q : p) m.positions.push_back({float(q.x), float(y0), float(q.y)});
    for (const glm::dvec2& q : p) m.positions.push_back({float(q.x), float(y1), float(q.y)});
    const auto top = std::uint32_t(n);
    for (std::uint32_t i = 1; i + 1 < n; ++i) {
        m.indices.insert(m.indices.end(), {0, i, i + 1});                     // bottom, seen from -y
        m.indices.insert(m.indices.end(), {top, top + i + 1, top + i});       // top, seen from +y
    }
    for (std::uint32_t i = 0; i < n; ++i) {
        const std::uint32_t j = std::uint32_t((i + 1) % n);
        m.indices.insert(m.indices.end(), {i, top + j, j, i, top + i, top + j});
    }
    return m;
}

} // namespace rgvc
