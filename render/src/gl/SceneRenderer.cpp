#include "rgvc/render/gl/SceneRenderer.hpp"

#include "GlProgram.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

namespace rgvc {

namespace {

// Uniform locations, fixed in the shaders (layout(location)) so that no lookup happens per draw.
constexpr GLint kViewProjection = 0, kEye = 1, kFarSquared = 2;
// Vertex attributes.
constexpr GLuint kPosition = 0, kSlot = 1, kBoxMin = 2, kBoxMax = 3;

const char* const kObjectVertex = R"(
layout(location = 0) in vec3 aPosition;
layout(location = 1) in uint aSlot;
struct Instance { vec4 offset; vec4 scale; };
layout(std430, binding = 0) readonly buffer Instances { Instance instances[]; };
layout(location = 0) uniform mat4 uViewProjection;
layout(location = 1) uniform vec3 uEye;
out vec3 vFromEye;
flat out uint vItem;
void main() {
    Instance inst = instances[aSlot];
    vec3 p = (inst.offset.xyz - uEye) + aPosition * inst.scale.xyz;
    vFromEye = p;
    vItem = aSlot + 1u;
    gl_Position = uViewProjection * vec4(p, 1.0);
}
)";

const char* const kObjectFragment = R"(
in vec3 vFromEye;
flat in uint vItem;
layout(location = 2) uniform float uFarSquared;
#if ITEM_OUTPUT
layout(location = 0) out uint oItem;
#else
layout(location = 0) out vec4 oColour;
#endif
void main() {
#if FAR_CLIP
    if (dot(vFromEye, vFromEye) > uFarSquared) discard;
#endif
#if ITEM_OUTPUT
    oItem = vItem;
#else
    // A colour per item, darker where the face turns away from the view.
    vec3 n = normalize(cross(dFdx(vFromEye), dFdy(vFromEye)));
    float light = 0.35 + 0.65 * abs(dot(n, normalize(vFromEye)));
    uint h = vItem * 2654435761u;
    vec3 base = 0.3 + 0.7 * vec3(float(h & 255u), float((h >> 8) & 255u), float((h >> 16) & 255u)) / 255.0;
    oColour = vec4(base * light, 1.0);
#endif
}
)";

const char* const kBoxVertex = R"(
layout(location = 0) in vec3 aPosition;
layout(location = 2) in vec3 aMin;
layout(location = 3) in vec3 aMax;
layout(location = 0) uniform mat4 uViewProjection;
layout(location = 1) uniform vec3 uEye;
out vec3 vFromEye;
void main() {
    vec3 p = (aMin - uEye) + aPosition * (aMax - aMin);
    vFromEye = p;
    gl_Position = uViewProjection * vec4(p, 1.0);
}
)";

const char* const kBoxFragment = R"(
in vec3 vFromEye;
layout(location = 2) uniform float uFarSquared;
void main() {
#if FAR_CLIP
    if (dot(vFromEye, vFromEye) > uFarSquared) discard;
#endif
}
)";

/// The float nearest x towards -infinity (down) or +infinity (up).
float floatDown(double x) {
    float f = float(x);
    return double(f) > x ? std::nextafter(f, -INFINITY) : f;
}
float floatUp(double x) {
    float f = float(x);
    return double(f) < x ? std::nextafter(f, INFINITY) : f;
}

} // namespace

SceneRenderer::SceneRenderer(GlContext& context, const SceneRendererOptions& options)
    : m_context(context), m_gl(context.gl()), m_options(options) {
    if (!(m_options.nearPlane > 0) || !std::isfinite(m_options.nearPlane))
        throw InvalidInput("SceneRendererOptions.nearPlane", "must be finite and > 0");
    if (m_options.sphere.indices.empty() || m_options.sphere.positions.empty())
        throw InvalidInput("SceneRendererOptions.sphere", "the sphere mesh is empty");
    if (m_options.prismSides < 3 || m_options.prismSides > 4096)
        throw InvalidInput("SceneRendererOptions.prismSides", "must be in [3, 4096], got " + std::to_string(m_options.prismSides));
    try {
        init();
    } catch (...) {
        release(); // deleting names that were never made (0) is a no-op
        throw;
    }
}

void SceneRenderer::init() {
    const GlFunctions& gl = m_gl;
    while (gl.GetError() != GL_NO_ERROR) {
    }

    for (int output = 0; output < 2; ++output)
        for (int far = 0; far < 2; ++far) {
            const std::string defines = std::string("#define ITEM_OUTPUT ") + (output ? "1" : "0") + "\n#define FAR_CLIP " +
                                        (far ? "1" : "0") + "\n";
            m_objectProgram[output][far] = gl_detail::linkProgram(gl, "object", kObjectVertex, kObjectFragment, defines);
        }
    for (int far = 0; far < 2; ++far)
        m_boxProgram[far] = gl_detail::linkProgram(gl, "query box", kBoxVertex, kBoxFragment,
                                                   std::string("#define FAR_CLIP ") + (far ? "1" : "0") + "\n");

    const Mesh& sphere = m_options.sphere;
    for (std::size_t t = 0; t + 2 < sphere.indices.size(); t += 3) {
        const glm::dvec3 a(sphere.positions[sphere.indices[t]]), b(sphere.positions[sphere.indices[t + 1]]),
            c(sphere.positions[sphere.indices[t + 2]]);
        const glm::dvec3 n = glm::cross(b - a, c - a);
        if (glm::length(n) > 0) m_spherePlanes.emplace_back(glm::normalize(n), glm::dot(glm::normalize(n), a));
    }

    // The unit circle prism: the regular n-gon inscribed in the unit circle (float vertices scaled down
    // until they lie in it, as the sphere meshes do), extruded over y in [0, 1]. Its edge lines and
    // inradius come from those float vertices, which is what is drawn.
    const int sides = m_options.prismSides;
    std::vector<glm::dvec2> ngon;
    for (int k = 0; k < sides; ++k) {
        const double a = 2.0 * 3.14159265358979323846 * k / sides;
        glm::vec2 f(float(std::cos(a)), float(std::sin(a)));
        while (glm::length(glm::dvec2(f)) > 1.0) f *= 1.0f - 1e-7f;
        ngon.emplace_back(f);
    }
    m_circleInradius = 1.0;
    for (int k = 0; k < sides; ++k) {
        const glm::dvec2 a = ngon[std::size_t(k)], e = ngon[std::size_t((k + 1) % sides)] - a;
        const glm::dvec2 n = glm::normalize(glm::dvec2(e.y, -e.x)); // outward: the n-gon is counter-clockwise
        m_circleEdges.emplace_back(n, glm::dot(n, a));
        m_circleInradius = std::min(m_circleInradius, glm::dot(n, a));
    }
    const Mesh circle = prism(ngon, 0, 1);

    // The instanced meshes in one vertex and one index buffer: the sphere, the unit box, the unit n-gon
    // prism. Polygon prisms have buffers of their own (m_polyVbo, m_polyIbo).
    const Mesh box = unitBox();
    const Mesh* meshes[PolygonKind] = {&m_options.sphere, &box, &circle};
    std::vector<glm::vec3> positions;
    std::vector<std::uint32_t> indices;
    for (int k = 0; k < PolygonKind; ++k) {
        m_baseVertex[k] = GLint(positions.size());
        m_indexOffset[k] = GLint(indices.size());
        m_indexCount[k] = GLint(meshes[k]->indices.size());
        positions.insert(positions.end(), meshes[k]->positions.begin(), meshes[k]->positions.end());
        indices.insert(indices.end(), meshes[k]->indices.begin(), meshes[k]->indices.end());
    }
    gl.GenBuffers(1, &m_meshVbo);
    gl.BindBuffer(GL_ARRAY_BUFFER, m_meshVbo);
    gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(positions.size() * sizeof(glm::vec3)), positions.data(), GL_STATIC_DRAW);
    gl.GenBuffers(1, &m_meshIbo);
    gl.GenBuffers(1, &m_instanceBuffer);
    gl.GenBuffers(1, &m_listRing.buffer);
    gl.GenBuffers(1, &m_boxRing.buffer);
    gl.GenBuffers(1, &m_commandRing.buffer);
    gl.GenBuffers(1, &m_polyVbo);
    gl.GenBuffers(1, &m_polyIbo);

    // The attributes the object VAOs share: positions per vertex from `vbo`, the slot per instance from
    // the draw list ring (recorded in the bound VAO).
    auto positionAttribute = [&](GLuint vbo) {
        gl.BindBuffer(GL_ARRAY_BUFFER, vbo);
        gl.EnableVertexAttribArray(kPosition);
        gl.VertexAttribPointer(kPosition, 3, GL_FLOAT, GL_FALSE, sizeof(glm::vec3), nullptr);
    };
    auto slotAttribute = [&] {
        gl.BindBuffer(GL_ARRAY_BUFFER, m_listRing.buffer);
        gl.EnableVertexAttribArray(kSlot);
        gl.VertexAttribIPointer(kSlot, 1, GL_UNSIGNED_INT, sizeof(std::uint32_t), nullptr);
        gl.VertexAttribDivisor(kSlot, 1);
    };

    // Objects: mesh positions per vertex, the slot per instance (from the draw list ring).
    gl.GenVertexArrays(1, &m_objectVao);
    gl.BindVertexArray(m_objectVao);
    gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, m_meshIbo); // recorded in the VAO
    gl.BufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(indices.size() * sizeof(std::uint32_t)), indices.data(), GL_STATIC_DRAW);
    positionAttribute(m_meshVbo);
    m_listRing.capacity = 1 << 20;
    gl.BindBuffer(GL_ARRAY_BUFFER, m_listRing.buffer);
    gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(m_listRing.capacity), nullptr, GL_STREAM_DRAW);
    slotAttribute();

    // Polygon prisms: their own mesh buffers, the same slot attribute (one instance per draw command,
    // its base instance pointing into the draw list).
    gl.GenVertexArrays(1, &m_polyVao);
    gl.BindVertexArray(m_polyVao);
    gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, m_polyIbo);
    positionAttribute(m_polyVbo);
    slotAttribute();
    m_commandRing.capacity = 1 << 16;
    gl.BindBuffer(GL_ARRAY_BUFFER, m_commandRing.buffer);
    gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(m_commandRing.capacity), nullptr, GL_STREAM_DRAW);

    // Query boxes: the unit box per vertex, (min, max) per instance (from the box ring).
    gl.GenVertexArrays(1, &m_boxVao);
    gl.BindVertexArray(m_boxVao);
    gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, m_meshIbo);
    positionAttribute(m_meshVbo);
    m_boxRing.capacity = 1 << 20;
    gl.BindBuffer(GL_ARRAY_BUFFER, m_boxRing.buffer);
    gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(m_boxRing.capacity), nullptr, GL_STREAM_DRAW);
    gl.EnableVertexAttribArray(kBoxMin);
    gl.VertexAttribPointer(kBoxMin, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
    gl.VertexAttribDivisor(kBoxMin, 1);
    gl.EnableVertexAttribArray(kBoxMax);
    gl.VertexAttribPointer(kBoxMax, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<void*>(3 * sizeof(float)));
    gl.VertexAttribDivisor(kBoxMax, 1);
    gl.BindVertexArray(0);
    gl.BindBuffer(GL_ARRAY_BUFFER, 0);

    Camera3 defaultCamera;
    defaultCamera.direction = {0, 0, -1};
    setCamera(defaultCamera);
    checkGlError(gl, "creating the scene renderer");
}

SceneRenderer::~SceneRenderer() { release(); }

void SceneRenderer::release() {
    const GlFunctions& gl = m_gl;
    for (auto& p : m_objectProgram)
        for (GLuint& q : p)
            if (q) gl.DeleteProgram(q), q = 0;
    for (GLuint& q : m_boxProgram)
        if (q) gl.DeleteProgram(q), q = 0;
    GLuint buffers[] = {m_meshVbo, m_meshIbo, m_instanceBuffer, m_listRing.buffer, m_boxRing.buffer, m_commandRing.buffer, m_polyVbo, m_polyIbo};
    gl.DeleteBuffers(8, buffers);
    GLuint vaos[] = {m_objectVao, m_boxVao, m_polyVao};
    gl.DeleteVertexArrays(3, vaos);
    m_meshVbo = m_meshIbo = m_instanceBuffer = m_listRing.buffer = m_boxRing.buffer = m_objectVao = m_boxVao = 0;
    m_commandRing.buffer = m_polyVbo = m_polyIbo = m_polyVao = 0;
}

void SceneRenderer::anchorAt(const glm::dvec3& centre) {
    if (m_hasAnchor) return;
    m_anchor = centre;
    m_hasAnchor = true;
}

std::uint32_t SceneRenderer::slotFor(ObjectId id, bool& added) {
    auto it = m_slotOf.find(id);
    added = it == m_slotOf.end();
    if (!added) return it->second;
    std::uint32_t slot;
    if (!m_freeSlots.empty()) {
        slot = m_freeSlots.back();
        m_freeSlots.pop_back();
    } else {
        slot = std::uint32_t(m_slots.size());
        m_slots.emplace_back();
        m_instances.emplace_back();
    }
    m_slotOf.emplace(id, slot);
    m_slots[slot].id = id;
    m_slots[slot].used = true;
    return slot;
}

void SceneRenderer::markDirty(std::uint32_t slot) {
    Slot& info = m_slots[slot];
    if (!info.dirty) {
        info.dirty = true;
        m_dirtySlots.push_back(slot);
    }
}

void SceneRenderer::updateExtent(const Instance& inst) {
    for (int a = 0; a < 3; ++a)
        m_extent = std::max(m_extent, std::abs(double(inst.offset[a])) + std::abs(double(inst.scale[a])));
}

void SceneRenderer::setObject(ObjectId id, const Shape<3>& shape) {
    Shape<3> s = shape;
    validateShape<3>(s, [&] { return "object " + std::to_string(id); });
    // Triangle meshes are not drawn (yet): drawing their hull would write depth where the mesh has none
    // (a concave mesh's notch) and cull what is seen through it. Callers keep them out, as they keep
    // occludees (rgvc cull --gl does: the CPU's mesh occluders already hid what is behind them).
    if (std::holds_alternative<MeshSolid>(s))
        throw InvalidInput("object " + std::to_string(id) + ".shape", "the GL stage does not draw meshes: keep mesh objects out of it");
    const Box<3> bounds = boundsOf<3>(s);
    anchorAt(0.5 * (bounds.min + bounds.max));
    bool added = false;
    const std::uint32_t slot = slotFor(id, added);
    releasePolygon(slot);
    Instance& inst = m_instances[slot];
    Slot& info = m_slots[slot];
    info.prism = false;
    if (const Ball<3>* ball = std::get_if<Ball<3>>(&s)) {
        info.kind = SphereKind;
        const glm::dvec3 c = ball->center - m_anchor;
        for (int a = 0; a < 3; ++a) inst.offset[a] = float(c[a]);
        // Rounded down: the mesh, inside the unit sphere, stays inside the ball (up to the centre's rounding).
        const float r = floatDown(ball->radius);
        inst.scale[0] = inst.scale[1] = inst.scale[2] = r;
    } else if (const ConvexPolytope* poly = std::get_if<ConvexPolytope>(&s)) {
        setPolytope(slot, added, *poly);
        return;
    } else {
        const Box<3>& box = std::get<Box<3>>(s);
        info.kind = BoxKind;
        for (int a = 0; a < 3; ++a) {
            // Inwards: min rounded up, max down (then the extent down), so the drawn box lies in the analytic one.
            const float lo = floatUp(box.min[a] - m_anchor[a]);
            const float hi = floatDown(box.max[a] - m_anchor[a]);
            inst.offset[a] = lo;
            inst.scale[a] = std::max(0.0f, floatDown(double(hi) - double(lo)));
        }
    }
    inst.offset[3] = inst.scale[3] = 0;
    updateExtent(inst);
    markDirty(slot);
}

namespace {

/// How a polytope is drawn: scaled about its vertices' centroid by 1 - pull before the float rounding.
/// Scaling by k moves each facet plane in by (1 - k) h, h its distance from the centroid (>= hMin), and the
/// rounding moves points by at most delta = 2^-23 (|first vertex - anchor| + reach) (the instance offset
/// and the mesh positions are each rounded once, relative error 2^-24). pull = max(4e-7, 2 delta / hMin)
/// keeps the drawn mesh inside the analytic shape; the mesh then contains the shape shrunk by
/// pull * reach + delta (occluderInset adds that).
struct PolytopeDraw {
    glm::dvec3 centroid{0.0};
    double pull = 0, reach = 0, delta = 0;
};
PolytopeDraw polytopeDraw(const ConvexPolytope& poly, const glm::dvec3& anchor) {
    PolytopeDraw d;
    for (const Vec3& v : poly.vertices) d.centroid += v;
    d.centroid /= double(poly.vertices.size());
    for (const Vec3& v : poly.vertices) d.reach = std::max(d.reach, glm::length(v - d.centroid));
    double hMin = std::numeric_limits<double>::infinity();
    for (const HalfSpace& h : poly.planes) hMin = std::min(hMin, h.offset - glm::dot(h.normal, d.centroid));
    d.delta = 0x1p-23 * (glm::length(poly.vertices[0] - anchor) + 2 * d.reach);
    d.pull = std::min(0.5, std::max(4e-7, hMin > 0 ? 2 * d.delta / hMin : 0.5));
    return d;
}

} // namespace

void SceneRenderer::setPolytope(std::uint32_t slot, bool added, const ConvexPolytope& poly) {
    // The polytope's boundary triangles in a polygon slice (PolygonKind, one draw command each). A slice
    // for V points holds 2V vertices and 12V - 12 indices; a triangulated convex polytope has 2V - 4
    // triangles, 6V - 12 indices, so V points fit. The vertices are pulled towards the centroid before
    // the float rounding so that the drawn mesh lies inside the analytic shape (polytopeDraw).
    const auto m = std::uint32_t(poly.vertices.size());
    anchorAt(0.5 * (poly.boundsMin + poly.boundsMax));
    const PolytopeDraw draw = polytopeDraw(poly, m_anchor);
    const glm::dvec3 centroid = draw.centroid;
    const double keep = 1.0 - draw.pull;
    std::vector<glm::dvec3> relative(m);
    for (std::uint32_t i = 0; i < m; ++i) relative[i] = poly.vertices[i] - poly.vertices[0];
    Slot& info = m_slots[slot];
    auto it = info.kind == PolygonKind && !added ? m_polygons.find(slot) : m_polygons.end();
    if (it != m_polygons.end() && it->second.polytopeKey != relative) it = m_polygons.end();
    const glm::dvec3 first = centroid + (poly.vertices[0] - centroid) * keep;
    if (it == m_polygons.end()) {
        releasePolygon(slot);
        const PolygonSlice slice = allocatePolygon(std::max<std::uint32_t>(m, 2));
        PolygonMesh pm;
        pm.firstVertex = slice.firstVertex;
        pm.capacity = slice.capacity;
        pm.firstIndex = slice.firstIndex;
        pm.points = slice.capacity;
        pm.indexCount = std::uint32_t(3 * poly.triangles.size());
        for (std::uint32_t i = 0; i < m; ++i) {
            const glm::dvec3 v = centroid + (poly.vertices[i] - centroid) * keep - first;
            m_polyPositions[pm.firstVertex + i] = glm::vec3(v);
        }
        for (std::size_t t = 0; t < poly.triangles.size(); ++t)
            for (int k = 0; k < 3; ++k) m_polyIndices[pm.firstIndex + 3 * t + std::size_t(k)] = poly.triangles[t][std::size_t(k)];
        // The drawn facets, from the float mesh (for drawnShapeContains and distanceToDrawn).
        for (const auto& t : poly.triangles) {
            const glm::dvec3 a(m_polyPositions[pm.firstVertex + t[0]]), b(m_polyPositions[pm.firstVertex + t[1]]),
                c(m_polyPositions[pm.firstVertex + t[2]]);
            const glm::dvec3 n = glm::cross(b - a, c - a);
            const double len = glm::length(n);
            if (len > 0) pm.planes.emplace_back(n / len, glm::dot(n / len, a));
        }
        pm.polytopeKey = std::move(relative);
        it = m_polygons.emplace(slot, std::move(pm)).first;
        m_dirtyPolygons.push_back(slot);
        it->second.dirty = true;
    }
    info.kind = PolygonKind;
    info.prism = false;
    Instance& inst = m_instances[slot];
    for (int a = 0; a < 3; ++a) inst.offset[a] = float(first[a] - m_anchor[a]);
    inst.scale[0] = inst.scale[1] = inst.scale[2] = 1;
    inst.offset[3] = inst.scale[3] = 0;
    double reach = 0;
    for (const Vec3& v : poly.vertices) reach = std::max(reach, glm::length(v - poly.vertices[0]));
    for (int a = 0; a < 3; ++a) m_extent = std::max(m_extent, std::abs(double(inst.offset[a])) + reach);
    markDirty(slot);
}

void SceneRenderer::setPrism(ObjectId id, const Shape<2>& shape, double y0, double y1) {
    Shape<2> s = shape;
    const auto field = [&] { return "prism " + std::to_string(id); };
    validateShape<2>(s, field); // polygons come back counter-clockwise
    if (!std::isfinite(y0)) throw InvalidInput(field() + ".y0", "must be finite");
    if (!std::isfinite(y1)) throw InvalidInput(field() + ".y1", "must be finite");
    if (!(y0 < y1)) throw InvalidInput(field() + ".y1", "must exceed y0 (" + std::to_string(y0) + "), got " + std::to_string(y1));
    if (const Box<2>* b = std::get_if<Box<2>>(&s)) {
        // Exactly the box it spans: drawn (and rounded) as setObject's boxes are.
        setObject(id, Box<3>{{b->min.x, y0, b->min.y}, {b->max.x, y1, b->max.y}});
        m_slots[m_slotOf.at(id)].prism = true;
        return;
    }
    const Box<2> bounds = boundsOf<2>(s);
    anchorAt({0.5 * (bounds.min.x + bounds.max.x), 0.5 * (y0 + y1), 0.5 * (bounds.min.y + bounds.max.y)});
    // The y slab, inwards as for boxes: the drawn prism lies in [y0, y1].
    const float lo = floatUp(y0 - m_anchor.y), hi = floatDown(y1 - m_anchor.y);
    const float height = std::max(0.0f, floatDown(double(hi) - double(lo)));

    if (const Ball<2>* circle = std::get_if<Ball<2>>(&s)) {
        bool added = false;
        const std::uint32_t slot = slotFor(id, added);
        releasePolygon(slot);
        Slot& info = m_slots[slot];
        info.kind = CircleKind;
        info.prism = true;
        Instance& inst = m_instances[slot];
        const float r = floatDown(circle->radius); // the n-gon in the unit circle stays in the circle
        inst.offset[0] = float(circle->center.x - m_anchor.x);
        inst.offset[1] = lo;
        inst.offset[2] = float(circle->center.y - m_anchor.z);
        inst.scale[0] = inst.scale[2] = r;
        inst.scale[1] = height;
        inst.offset[3] = inst.scale[3] = 0;
        updateExtent(inst);
        markDirty(slot);
        return;
    }

    const std::vector<Vec2>& pts = std::get<ConvexPolygon>(s).points;
    const auto m = std::uint32_t(pts.size());
    std::vector<glm::dvec2> relative(pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) relative[i] = pts[i] - pts[0];
    // Everything that can throw (the mesh) before the renderer changes.
    const Mesh mesh = prism(relative, 0, 1);
    bool added = false;
    const std::uint32_t slot = slotFor(id, added);
    Slot& info = m_slots[slot];
    auto it = info.kind == PolygonKind && !added ? m_polygons.find(slot) : m_polygons.end();
    if (it == m_polygons.end() || it->second.relative != relative) {
        // A new shape (not only a new position): write its mesh slice, in place when it fits.
        if (it != m_polygons.end() && it->second.capacity < m) {
            releasePolygon(slot);
            it = m_polygons.end();
        }
        if (it == m_polygons.end()) {
            releasePolygon(slot); // a stale mesh of a removed polygon prism cannot be here, but be sure
            const PolygonSlice slice = allocatePolygon(m);
            PolygonMesh pm;
            pm.firstVertex = slice.firstVertex;
            pm.capacity = slice.capacity;
            pm.firstIndex = slice.firstIndex;
            it = m_polygons.emplace(slot, std::move(pm)).first;
        }
        PolygonMesh& pm = it->second;
        pm.points = m;
        pm.indexCount = 12 * m - 12;
        pm.polytopeKey.clear();
        pm.planes.clear();
        pm.relative = std::move(relative);
        std::copy(mesh.positions.begin(), mesh.positions.end(), m_polyPositions.begin() + pm.firstVertex);
        std::copy(mesh.indices.begin(), mesh.indices.end(), m_polyIndices.begin() + pm.firstIndex);
        // Drawn edge lines from the float points (counter-clockwise, as prism() keeps them).
        pm.drawn.clear();
        pm.edges.clear();
        for (std::uint32_t i = 0; i < m; ++i) pm.drawn.emplace_back(mesh.positions[i].x, mesh.positions[i].z);
        for (std::uint32_t i = 0; i < m; ++i) {
            const glm::dvec2 a = pm.drawn[i], e = pm.drawn[(i + 1) % m] - a;
            if (!(glm::length(e) > 0)) continue;
            const glm::dvec2 n = glm::normalize(glm::dvec2(e.y, -e.x));
            pm.edges.emplace_back(n, glm::dot(n, a));
        }
        if (!pm.dirty) m_dirtyPolygons.push_back(slot);
        pm.dirty = true;
    }
    info.kind = PolygonKind;
    info.prism = true;
    Instance& inst = m_instances[slot];
    inst.offset[0] = float(pts[0].x - m_anchor.x);
    inst.offset[1] = lo;
    inst.offset[2] = float(pts[0].y - m_anchor.z);
    inst.scale[0] = inst.scale[2] = 1;
    inst.scale[1] = height;
    inst.offset[3] = inst.scale[3] = 0;
    double reachX = 0, reachZ = 0;
    for (const glm::dvec2& q : it->second.drawn) reachX = std::max(reachX, std::abs(q.x)), reachZ = std::max(reachZ, std::abs(q.y));
    m_extent = std::max({m_extent, std::abs(double(inst.offset[0])) + reachX, std::abs(double(inst.offset[1])) + double(height),
                         std::abs(double(inst.offset[2])) + reachZ});
    markDirty(slot);
}

SceneRenderer::PolygonSlice SceneRenderer::allocatePolygon(std::uint32_t points) {
    // First fit among freed slices; otherwise a new one at the end of the buffers.
    for (std::size_t i = 0; i < m_freePolygons.size(); ++i)
        if (m_freePolygons[i].capacity >= points) {
            const PolygonSlice r = m_freePolygons[i];
            m_freePolygons[i] = m_freePolygons.back();
            m_freePolygons.pop_back();
            return r;
        }
    PolygonSlice r;
    r.firstVertex = std::uint32_t(m_polyPositions.size());
    r.firstIndex = std::uint32_t(m_polyIndices.size());
    r.capacity = points;
    m_polyPositions.resize(m_polyPositions.size() + 2 * std::size_t(points));
    m_polyIndices.resize(m_polyIndices.size() + 12 * std::size_t(points) - 12);
    return r;
}

void SceneRenderer::releasePolygon(std::uint32_t slot) {
    auto it = m_polygons.find(slot);
    if (it == m_polygons.end()) return;
    m_freePolygons.push_back({it->second.firstVertex, it->second.capacity, it->second.firstIndex});
    m_polygons.erase(it); // an entry left in m_dirtyPolygons finds no mesh (or a newer dirty one) and is skipped
}

void SceneRenderer::removeObject(ObjectId id) {
    auto it = m_slotOf.find(id);
    if (it == m_slotOf.end()) return;
    const std::uint32_t slot = it->second;
    m_slotOf.erase(it);
    releasePolygon(slot);
    m_slots[slot].used = false;
    m_slots[slot].prism = false;
    m_freeSlots.push_back(slot);
    // The GPU record stays as it was: nothing draws an unused slot.
}

std::vector<ObjectId> SceneRenderer::ids() const {
    std::vector<ObjectId> r;
    r.reserve(m_slotOf.size());
    for (const auto& [id, slot] : m_slotOf) r.push_back(id);
    std::sort(r.begin(), r.end());
    return r;
}

std::uint32_t SceneRenderer::itemOf(ObjectId id) const {
    auto it = m_slotOf.find(id);
    if (it == m_slotOf.end()) throw InvalidInput("ids", "object " + std::to_string(id) + " is not in the renderer");
    return it->second + 1;
}

bool SceneRenderer::objectOfItem(std::uint32_t item, ObjectId& id) const {
    if (item == 0 || item > m_slots.size() || !m_slots[item - 1].used) return false;
    id = m_slots[item - 1].id;
    return true;
}

void SceneRenderer::setCamera(const Camera3& camera, double nearPlane) {
    validateCamera<3>(camera);
    if (!(nearPlane >= 0) || !std::isfinite(nearPlane)) throw InvalidInput("nearPlane", "must be finite and >= 0");
    const double near = nearPlane > 0 ? nearPlane : m_options.nearPlane;
    const glm::dvec3 forward = glm::normalize(camera.direction);
    const glm::dvec3 up = cameraUp(camera); // the culler's frustum reads the same up
    if (!(glm::length(glm::cross(forward, up)) > 1e-12)) throw InvalidInput("camera.up", "must not be parallel to camera.direction");
    m_camera = camera;
    // The view rotation only (the eye is subtracted in the vertex shader); glm::lookAt's right = forward x
    // up, true up = right x forward, as rgvc's ViewFrustum builds them.
    const glm::dmat4 view = glm::lookAt(glm::dvec3(0.0), forward, up);
    // Reversed-depth infinite perspective for clip z in [0, 1]: z_clip = near, w_clip = -z_view, so depth
    // = near / distance along the view axis: 1 at the near plane, towards 0 at infinity.
    const double f = 1.0 / std::tan(0.5 * glm::radians(camera.fovDeg));
    glm::dmat4 projection(0.0);
    projection[0][0] = f / camera.aspect;
    projection[1][1] = f;
    projection[2][3] = -1.0;
    projection[3][2] = near;
    m_cameraNear = near;
    m_viewProjection = glm::mat4(projection * view);
    m_eye = glm::vec3(camera.position - m_anchor);
    m_farClip = std::isfinite(camera.far);
    m_farSquared = m_farClip ? float(camera.far * camera.far) : 0.0f;
}

void SceneRenderer::uploadPolygons() {
    const GlFunctions& gl = m_gl;
    if (m_dirtyPolygons.empty()) return;
    // Uploaded through GL_ARRAY_BUFFER, index data too: binding GL_ELEMENT_ARRAY_BUFFER would change
    // whichever vertex array is bound.
    if (m_polyGpuVertices < m_polyPositions.size() || m_polyGpuIndices < m_polyIndices.size()) {
        // Grown: reallocate both (doubling) and send all of both once.
        m_polyGpuVertices = std::max<std::size_t>(4096, std::max(m_polyPositions.size(), 2 * m_polyGpuVertices));
        m_polyGpuIndices = std::max<std::size_t>(4 * 4096, std::max(m_polyIndices.size(), 2 * m_polyGpuIndices));
        gl.BindBuffer(GL_ARRAY_BUFFER, m_polyVbo);
        gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(m_polyGpuVertices * sizeof(glm::vec3)), nullptr, GL_DYNAMIC_DRAW);
        gl.BufferSubData(GL_ARRAY_BUFFER, 0, GLsizeiptr(m_polyPositions.size() * sizeof(glm::vec3)), m_polyPositions.data());
        gl.BindBuffer(GL_ARRAY_BUFFER, m_polyIbo);
        gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(m_polyGpuIndices * sizeof(std::uint32_t)), nullptr, GL_DYNAMIC_DRAW);
        gl.BufferSubData(GL_ARRAY_BUFFER, 0, GLsizeiptr(m_polyIndices.size() * sizeof(std::uint32_t)), m_polyIndices.data());
        m_stats.polygonVerticesUploaded += m_polyPositions.size();
        m_stats.uploadCalls += 4;
        for (auto& [slot, pm] : m_polygons) pm.dirty = false;
        m_dirtyPolygons.clear();
        return;
    }
    for (std::uint32_t slot : m_dirtyPolygons) {
        auto it = m_polygons.find(slot);
        if (it == m_polygons.end() || !it->second.dirty) continue;
        PolygonMesh& pm = it->second;
        gl.BindBuffer(GL_ARRAY_BUFFER, m_polyVbo);
        gl.BufferSubData(GL_ARRAY_BUFFER, GLintptr(pm.firstVertex * sizeof(glm::vec3)), GLsizeiptr(2 * pm.points * sizeof(glm::vec3)),
                         &m_polyPositions[pm.firstVertex]);
        gl.BindBuffer(GL_ARRAY_BUFFER, m_polyIbo);
        gl.BufferSubData(GL_ARRAY_BUFFER, GLintptr(pm.firstIndex * sizeof(std::uint32_t)),
                         GLsizeiptr((12 * pm.points - 12) * sizeof(std::uint32_t)), &m_polyIndices[pm.firstIndex]);
        m_stats.polygonVerticesUploaded += 2 * pm.points;
        m_stats.uploadCalls += 2;
        pm.dirty = false;
    }
    m_dirtyPolygons.clear();
}

void SceneRenderer::uploadDirty() {
    const GlFunctions& gl = m_gl;
    uploadPolygons();
    gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, m_instanceBuffer);
    if (m_gpuCapacity < m_instances.size()) {
        // Grown: reallocate (doubling) and send everything once.
        m_gpuCapacity = std::max<std::size_t>(1024, std::max(m_instances.size(), 2 * m_gpuCapacity));
        gl.BufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(m_gpuCapacity * sizeof(Instance)), nullptr, GL_DYNAMIC_DRAW);
        gl.BufferSubData(GL_SHADER_STORAGE_BUFFER, 0, GLsizeiptr(m_instances.size() * sizeof(Instance)), m_instances.data());
        m_stats.instancesUploaded += m_instances.size();
        m_stats.uploadCalls += 2;
        for (std::uint32_t s : m_dirtySlots) m_slots[s].dirty = false;
        m_dirtySlots.clear();
        return;
    }
    if (m_dirtySlots.empty()) return;
    std::sort(m_dirtySlots.begin(), m_dirtySlots.end());
    // Runs of dirty slots, joined across gaps of up to 8 clean slots (256 bytes): one call for a cluster
    // of movers, without re-sending much that did not move.
    std::size_t i = 0;
    while (i < m_dirtySlots.size()) {
        std::size_t j = i;
        while (j + 1 < m_dirtySlots.size() && m_dirtySlots[j + 1] - m_dirtySlots[j] <= 9) ++j;
        const std::uint32_t first = m_dirtySlots[i], last = m_dirtySlots[j];
        const std::size_t count = std::size_t(last - first + 1);
        gl.BufferSubData(GL_SHADER_STORAGE_BUFFER, GLintptr(first * sizeof(Instance)), GLsizeiptr(count * sizeof(Instance)),
                         &m_instances[first]);
        m_stats.instancesUploaded += count;
        ++m_stats.uploadCalls;
        i = j + 1;
    }
    for (std::uint32_t s : m_dirtySlots) m_slots[s].dirty = false;
    m_dirtySlots.clear();
}

std::size_t SceneRenderer::stream(Ring& ring, const void* data, std::size_t bytes, std::size_t alignment) {
    const GlFunctions& gl = m_gl;
    gl.BindBuffer(GL_ARRAY_BUFFER, ring.buffer);
    std::size_t at = (ring.cursor + alignment - 1) / alignment * alignment;
    if (at + bytes > ring.capacity) {
        // Orphan the storage (the driver keeps the old one alive for draws in flight) and start over;
        // grow when one draw needs more than all of it.
        while (ring.capacity < bytes) ring.capacity *= 2;
        gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(ring.capacity), nullptr, GL_STREAM_DRAW);
        at = 0;
    }
    gl.BufferSubData(GL_ARRAY_BUFFER, GLintptr(at), GLsizeiptr(bytes), data);
    ring.cursor = at + bytes;
    return at;
}

void SceneRenderer::applyState() {
    const GlFunctions& gl = m_gl;
    gl.ClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    gl.Enable(GL_DEPTH_TEST);
    gl.DepthFunc(GL_GEQUAL); // reversed depth: nearer is greater; ties pass (a face on a face shows)
    if (m_options.cullBackFaces) {
        gl.Enable(GL_CULL_FACE);
        gl.CullFace(GL_BACK);
        gl.FrontFace(GL_CCW);
    } else {
        gl.Disable(GL_CULL_FACE);
    }
}

void SceneRenderer::draw(std::span<const ObjectId> ids, DrawOutput output) {
    for (auto& list : m_drawList) list.clear();
    m_listPrisms = 0;
    for (ObjectId id : ids) {
        auto it = m_slotOf.find(id);
        if (it == m_slotOf.end()) {
            for (auto& list : m_drawList) list.clear();
            throw InvalidInput("ids", "object " + std::to_string(id) + " is not in the renderer");
        }
        const Slot& info = m_slots[it->second];
        m_drawList[info.kind].push_back(it->second);
        m_listPrisms += info.prism;
    }
    drawSlots(output);
}

void SceneRenderer::drawAll(DrawOutput output) {
    for (auto& list : m_drawList) list.clear();
    m_listPrisms = 0;
    for (std::uint32_t s = 0; s < m_slots.size(); ++s)
        if (m_slots[s].used) {
            m_drawList[m_slots[s].kind].push_back(s);
            m_listPrisms += m_slots[s].prism;
        }
    drawSlots(output);
}

void SceneRenderer::drawSlots(DrawOutput output) {
    if (std::all_of(std::begin(m_drawList), std::end(m_drawList), [](const auto& list) { return list.empty(); })) return;
    const GlFunctions& gl = m_gl;
    uploadDirty();
    applyState();
    gl.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl.DepthMask(GL_TRUE);
    const GLuint program = m_objectProgram[output == DrawOutput::ItemId][m_farClip];
    gl.UseProgram(program);
    gl.UniformMatrix4fv(kViewProjection, 1, GL_FALSE, glm::value_ptr(m_viewProjection));
    gl.Uniform3f(kEye, m_eye.x, m_eye.y, m_eye.z);
    gl.Uniform1f(kFarSquared, m_farSquared);
    gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, m_instanceBuffer);
    gl.BindVertexArray(m_objectVao);
    if (output == DrawOutput::ItemId) {
        // Back faces first, nearer by a few depth steps (reversed depth: a positive offset is nearer),
        // so that they win ties against front faces on them; then front faces, strictly nearer only.
        // Units only, no slope factor: at grazing angles the slope term pulls a back face nearer than
        // another object's front face that truly lies in front of it, and the hidden object shows.
        // 8 units of a float depth buffer are 8 steps of the depth's own exponent, ~1e-6 of it.
        gl.Enable(GL_CULL_FACE);
        gl.FrontFace(GL_CCW);
        gl.CullFace(GL_FRONT);
        gl.Enable(GL_POLYGON_OFFSET_FILL);
        gl.PolygonOffset(0.0f, 8.0f);
        drawLists();
        gl.Disable(GL_POLYGON_OFFSET_FILL);
        gl.CullFace(GL_BACK);
        gl.DepthFunc(GL_GREATER);
        drawLists();
        gl.DepthFunc(GL_GEQUAL);
        if (!m_options.cullBackFaces) gl.Disable(GL_CULL_FACE);
    } else {
        drawLists();
    }
    gl.BindVertexArray(0);
    for (const auto& list : m_drawList) {
        m_stats.objectsDrawn += list.size();
    }
    for (int k = 0; k < PolygonKind; ++k) m_stats.trianglesDrawn += m_drawList[k].size() * std::uint64_t(m_indexCount[k] / 3);
    for (std::uint32_t slot : m_drawList[PolygonKind]) m_stats.trianglesDrawn += m_polygons.at(slot).indexCount / 3;
    m_stats.prismsDrawn += m_listPrisms;
}

void SceneRenderer::drawLists() {
    const GlFunctions& gl = m_gl;
    for (int k = 0; k < KindCount; ++k) {
        const std::vector<std::uint32_t>& list = m_drawList[k];
        if (list.empty()) continue;
        const std::size_t at = stream(m_listRing, list.data(), list.size() * sizeof(std::uint32_t), sizeof(std::uint32_t));
        if (k == PolygonKind) {
            // A mesh slice each: one command per polygon, one instance each, whose base instance reads
            // its slot from the draw list; all of them in one call.
            m_commands.clear();
            for (std::size_t i = 0; i < list.size(); ++i) {
                const PolygonMesh& pm = m_polygons.at(list[i]);
                m_commands.push_back({pm.indexCount, 1, pm.firstIndex, std::int32_t(pm.firstVertex),
                                      std::uint32_t(at / sizeof(std::uint32_t) + i)});
            }
            const std::size_t cmdAt = stream(m_commandRing, m_commands.data(), m_commands.size() * sizeof(DrawCommand), sizeof(std::uint32_t));
            gl.BindBuffer(GL_DRAW_INDIRECT_BUFFER, m_commandRing.buffer);
            gl.BindVertexArray(m_polyVao);
            gl.MultiDrawElementsIndirect(GL_TRIANGLES, GL_UNSIGNED_INT, reinterpret_cast<void*>(cmdAt), GLsizei(m_commands.size()),
                                         sizeof(DrawCommand));
            gl.BindVertexArray(m_objectVao);
            gl.BindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
            ++m_stats.drawCalls;
            continue;
        }
        gl.DrawElementsInstancedBaseVertexBaseInstance(GL_TRIANGLES, m_indexCount[k], GL_UNSIGNED_INT,
                                                       reinterpret_cast<void*>(std::size_t(m_indexOffset[k]) * sizeof(std::uint32_t)),
                                                       GLsizei(list.size()), m_baseVertex[k], GLuint(at / sizeof(std::uint32_t)));
        ++m_stats.drawCalls;
    }
}

bool SceneRenderer::drawnShapeContains(ObjectId id, const Vec3& point, double tolerance) const {
    const std::uint32_t slot = itemOf(id) - 1;
    const Instance& inst = m_instances[slot];
    const glm::dvec3 p = point - m_anchor;
    const glm::dvec3 o(inst.offset[0], inst.offset[1], inst.offset[2]), sc(inst.scale[0], inst.scale[1], inst.scale[2]);
    const Kind kind = m_slots[slot].kind;
    if (kind == BoxKind) {
        for (int a = 0; a < 3; ++a)
            if (!(p[a] >= o[a] - tolerance && p[a] <= o[a] + sc[a] + tolerance)) return false;
        return true;
    }
    if (kind == PolygonKind && !m_polygons.at(slot).planes.empty()) { // a polytope
        const glm::dvec3 q = p - o;
        for (const glm::dvec4& pl : m_polygons.at(slot).planes)
            if (!(glm::dot(glm::dvec3(pl), q) <= pl.w + tolerance)) return false;
        return true;
    }
    if (kind == CircleKind || kind == PolygonKind) {
        if (!(p.y >= o.y - tolerance && p.y <= o.y + sc.y + tolerance)) return false;
        if (kind == PolygonKind) {
            const glm::dvec2 q(p.x - o.x, p.z - o.z);
            for (const glm::dvec3& e : m_polygons.at(slot).edges)
                if (!(e.x * q.x + e.y * q.y <= e.z + tolerance)) return false;
            return true;
        }
        const glm::dvec2 q = glm::dvec2(p.x - o.x, p.z - o.z) / sc.x; // in the unit n-gon's frame
        const double t = tolerance / sc.x;
        if (!(glm::dot(q, q) <= (1.0 + t) * (1.0 + t))) return false;
        for (const glm::dvec3& e : m_circleEdges)
            if (!(e.x * q.x + e.y * q.y <= e.z + t)) return false;
        return true;
    }
    const glm::dvec3 q = (p - o) / sc.x; // in the unit mesh's frame
    const double t = tolerance / sc.x;
    if (!(glm::dot(q, q) <= (1.0 + t) * (1.0 + t))) return false;
    for (const glm::dvec4& plane : m_spherePlanes)
        if (!(glm::dot(glm::dvec3(plane), q) <= plane.w + t)) return false;
    return true;
}

double SceneRenderer::occluderInset(const Shape<3>& shape) const {
    const Box<3> b = boundsOf<3>(shape);
    const glm::dvec3 anchor = m_hasAnchor ? m_anchor : 0.5 * (b.min + b.max);
    const double reach = std::max(glm::length(b.min - anchor), glm::length(b.max - anchor)) + glm::length(b.max - b.min);
    const double margin = 1e-6 * reach;
    if (const Ball<3>* ball = std::get_if<Ball<3>>(&shape)) return ball->radius * (1.0 - m_options.sphere.inradius) + margin;
    if (const ConvexPolytope* poly = std::get_if<ConvexPolytope>(&shape)) {
        const PolytopeDraw d = polytopeDraw(*poly, anchor);
        return d.pull * d.reach + 2 * d.delta + margin;
    }
    return margin;
}

double SceneRenderer::occluderInset(const Shape<2>& shape, double y0, double y1) const {
    const Box<2> b2 = boundsOf<2>(shape);
    const Box<3> b{{b2.min.x, y0, b2.min.y}, {b2.max.x, y1, b2.max.y}};
    const glm::dvec3 anchor = m_hasAnchor ? m_anchor : 0.5 * (b.min + b.max);
    const double reach = std::max(glm::length(b.min - anchor), glm::length(b.max - anchor)) + glm::length(b.max - b.min);
    const double margin = 1e-6 * reach;
    if (const Ball<2>* circle = std::get_if<Ball<2>>(&shape)) return circle->radius * (1.0 - m_circleInradius) + margin;
    return margin;
}

double SceneRenderer::distanceToDrawn(ObjectId id, const Vec3& point) const {
    const std::uint32_t slot = itemOf(id) - 1;
    const Instance& inst = m_instances[slot];
    const glm::dvec3 p = point - m_anchor;
    const glm::dvec3 o(inst.offset[0], inst.offset[1], inst.offset[2]), sc(inst.scale[0], inst.scale[1], inst.scale[2]);
    const Kind kind = m_slots[slot].kind;
    if (kind == BoxKind) return glm::length(p - glm::clamp(p, o, o + sc));
    if (kind == PolygonKind && !m_polygons.at(slot).planes.empty()) { // a polytope: its largest plane excess, a lower bound
        double d = 0;
        for (const glm::dvec4& pl : m_polygons.at(slot).planes) d = std::max(d, glm::dot(glm::dvec3(pl), p - o) - pl.w);
        return d;
    }
    if (kind == CircleKind || kind == PolygonKind) {
        // The prism lies in (its y slab) x (the circle, or each edge's half-plane): the distance to that
        // set is a lower bound.
        const double dy = std::max({0.0, o.y - p.y, p.y - (o.y + sc.y)});
        const glm::dvec2 q(p.x - o.x, p.z - o.z);
        double d2 = 0;
        if (kind == CircleKind) {
            d2 = std::max(0.0, glm::length(q) - sc.x);
        } else {
            for (const glm::dvec3& e : m_polygons.at(slot).edges) d2 = std::max(d2, e.x * q.x + e.y * q.y - e.z);
        }
        return std::sqrt(d2 * d2 + dy * dy);
    }
    return std::max(0.0, glm::length(p - o) - sc.x); // the mesh lies in the ball of radius scale
}

void SceneRenderer::drawBoxes(std::span<const Box<3>> boxes) {
    if (boxes.empty()) return;
    const GlFunctions& gl = m_gl;
    std::vector<float>& data = m_boxScratch; // kept: a query per node must not allocate per call
    data.clear();
    for (const Box<3>& b : boxes) {
        for (int a = 0; a < 3; ++a) data.push_back(floatDown(b.min[a] - m_anchor[a]));
        for (int a = 0; a < 3; ++a) data.push_back(floatUp(b.max[a] - m_anchor[a]));
    }
    applyState();
    gl.ColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    gl.DepthMask(GL_FALSE);
    // A query box must count samples from inside too: never cull its faces.
    gl.Disable(GL_CULL_FACE);
    gl.UseProgram(m_boxProgram[m_farClip]);
    gl.UniformMatrix4fv(kViewProjection, 1, GL_FALSE, glm::value_ptr(m_viewProjection));
    gl.Uniform3f(kEye, m_eye.x, m_eye.y, m_eye.z);
    gl.Uniform1f(kFarSquared, m_farSquared);
    gl.BindVertexArray(m_boxVao);
    const std::size_t stride = 6 * sizeof(float);
    const std::size_t at = stream(m_boxRing, data.data(), data.size() * sizeof(float), stride);
    gl.DrawElementsInstancedBaseVertexBaseInstance(GL_TRIANGLES, m_indexCount[BoxKind], GL_UNSIGNED_INT,
                                                   reinterpret_cast<void*>(std::size_t(m_indexOffset[BoxKind]) * sizeof(std::uint32_t)),
                                                   GLsizei(boxes.size()), m_baseVertex[BoxKind], GLuint(at / stride));
    gl.BindVertexArray(0);
    gl.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl.DepthMask(GL_TRUE);
    ++m_stats.drawCalls;
    m_stats.boxesDrawn += boxes.size();
}

} // namespace rgvc
