// Instanced drawing of an rgvc scene (balls, boxes, and 2D shapes extruded to prisms) in a GL 4.5 context.
//
//   auto ctx = rgvc::createOsMesaContext(640, 480);
//   rgvc::SceneRenderer renderer(*ctx);                  // uploads the sphere and box meshes once
//   renderer.setObject(7, rgvc::Ball<3>{{0, 0, -5}, 1}); // adds, or moves when id 7 is already there
//   renderer.setPrism(8, rgvc::Ball<2>{{3, -5}, 1}, 0, 2); // a 2D shape in x/z, extruded over y in [0, 2]
//   rgvc::GlFramebuffer target(*ctx, 640, 480, rgvc::ColourFormat::Rgba8);
//   target.clear();                                      // binds it too
//   renderer.setCamera(camera);
//   renderer.draw(ids, rgvc::DrawOutput::Colour);        // any subset, one instanced draw per kind
//
// What lives where. The meshes (one sphere, one unit box, one unit n-gon prism for circles) are uploaded
// once; a convex polygon prism has its own slice of a shared polygon vertex and index buffer, written
// when its shape changes (a translated copy of the same polygon only moves its instance). Every object
// has a slot in one instance buffer (a shader storage buffer: offset and scale of the unit mesh);
// setObject writes the CPU copy and marks the slot dirty, and the next draw uploads only dirty slots,
// merged into runs (glBufferSubData per run): a frame where 10 of 100,000 objects moved uploads about
// 10 instances. A draw gathers the slots of the requested ids into a per-draw list, streamed into a ring
// buffer and read as an instanced vertex attribute through the base instance, so drawing a subset never
// touches the instance buffer.
//
// The camera (rgvc::Camera3 has no near plane): the projection is perspective with a near plane at
// SceneRendererOptions::nearPlane and no far plane, reversed depth (1 at the near plane, 0 at infinity,
// GL_GEQUAL) into float depth buffers (GlFramebuffer). A finite Camera3::far cuts the view by the ball
// of that radius, as the culler's view region does, by discarding fragments farther than `far`. Geometry
// nearer than the near plane is clipped: an object closer than that to the camera is not drawn there.
//
// Precision: positions are sent relative to an anchor (the first object's centre), and the camera
// transform is applied relative to the eye in the vertex shader, so float rounding is relative to the
// scene's size, not to its distance from the world origin. Box corners are rounded inwards to float
// (the drawn box lies in the analytic one); query boxes (drawBoxes) outwards (they cover their box).
//
// Lifetime: a renderer holds GL objects of its context; destroy it before the context.
//
// The outer/inner model (seed 004 §5.1): a drawn sphere is the mesh scaled by the ball's radius, inside
// the analytic ball; sphereInradius() * radius is the radius of a ball inside what is drawn. A circle
// prism is the regular n-gon inscribed in the circle (SceneRendererOptions::prismSides), which contains
// the circle of radius r * circleInradius() = r * cos(pi / n); box and polygon prisms are exact (up to
// float rounding, which occluderInset's margin covers).
//
// Prisms (setPrism): the 2D scene's top view. A 2D point (x, y) is the world point (x, *, y): 2D x is
// world x, 2D y is world z, and world y (up) is the extrusion axis.
#pragma once

#include "rgvc/dynamics/Culler.hpp"
#include "rgvc/grid/Camera.hpp"
#include "rgvc/grid/Shapes.hpp"
#include "rgvc/render/gl/GlContext.hpp"
#include "rgvc/render/gl/Meshes.hpp"

#include <glm/mat4x4.hpp>

#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

namespace rgvc {

struct SceneRendererOptions {
    /// The unit-sphere mesh balls are drawn with (inscribed in the unit sphere). Default: icosphere
    /// level 3, 1,280 triangles, inradius 0.9951.
    Mesh sphere = icosphere(3);
    /// [World units] distance of the near clipping plane. [Limit] > 0. With reversed float depth the
    /// depth precision does not depend on it; it only clips what is nearer. 1e-3 suits scenes whose
    /// objects are 0.01 to 1,000 units; scale it with the scene.
    double nearPlane = 1e-3;
    /// Sides of the regular polygon a circle prism is drawn with (inscribed in the circle). [Limit] 3 to
    /// 4,096. 32 sides lose r * (1 - cos(pi / 32)) = 0.0048 r at the edges' midpoints.
    int prismSides = 32;
    /// Draw only front faces. Off by default: a camera inside an object then sees the object's inside
    /// (it hides everything else, as a closed solid does), which the item buffer needs.
    bool cullBackFaces = false;
};

/// What draw() writes into the bound framebuffer's colour attachment.
enum class DrawOutput : std::uint8_t {
    Colour, ///< RGBA8 target: a colour per object, shaded by the face's angle to the view
    /// R32ui target: the object's item id (itemOf), 0 where nothing is drawn. Drawn in two passes so
    /// that a face seen from inside an object (a back face: the camera is in that object) hides what
    /// lies on it: back faces first, pulled nearer by a polygon offset, then front faces with a strict
    /// depth test. A face of Y lying on X's inner side is reached only through X's interior, so Y does
    /// not show there (scene-format.md's visibility), and coplanar ties go that way.
    ItemId,
};

/// Counters since construction or resetStats().
struct RenderStats {
    std::uint64_t objectsDrawn = 0;   ///< instances drawn by draw() (prisms included)
    std::uint64_t prismsDrawn = 0;    ///< of those, prisms (setPrism)
    std::uint64_t trianglesDrawn = 0; ///< their triangles (prisms included)
    std::uint64_t drawCalls = 0;      ///< instanced draw calls (objects and boxes)
    std::uint64_t boxesDrawn = 0;     ///< boxes drawn by drawBoxes()
    std::uint64_t instancesUploaded = 0; ///< instance records sent to the GPU (moved or added objects)
    std::uint64_t uploadCalls = 0;       ///< glBufferSubData / glBufferData calls for them and for polygon meshes
    /// Polygon-prism mesh vertices sent to the GPU (a polygon prism that was added or changed shape; a
    /// translated copy of the same polygon sends none, only its instance).
    std::uint64_t polygonVerticesUploaded = 0;
};

class SceneRenderer {
public:
    /// Builds the programs and uploads the meshes in `context`, which must be current.
    /// @throws GlError when a shader does not compile or a buffer cannot be made; InvalidInput for bad
    /// options (nearPlane <= 0, an empty sphere mesh, prismSides outside [3, 4096]).
    explicit SceneRenderer(GlContext& context, const SceneRendererOptions& options = {});
    ~SceneRenderer();
    SceneRenderer(const SceneRenderer&) = delete;
    SceneRenderer& operator=(const SceneRenderer&) = delete;

    /// Adds object `id` with `shape` ([World units]; a Ball<3>, a Box<3> or a ConvexPolytope: an obb or hull,
    /// drawn as its boundary triangles scaled towards their centroid by a little more than the float
    /// rounding moves a facet, so that the mesh lies inside the analytic shape and contains it shrunk by
    /// occluderInset), or moves it (or changes its
    /// shape) when it is already there. The GPU copy is updated at the next draw. O(1).
    /// @throws InvalidInput for an invalid shape (validateShape); the renderer is unchanged.
    void setObject(ObjectId id, const Shape<3>& shape);
    /// Adds (or moves, or reshapes) object `id` as the 2D `shape` ([World units]: a Ball<2>, Box<2> or
    /// ConvexPolygon in the x/z plane, 2D x -> world x, 2D y -> world z) extruded over world y in
    /// [y0, y1]. A circle is drawn as its inscribed prismSides-gon, a box as the Box<3> it spans (rounded
    /// inwards like setObject's boxes), a polygon exactly (its float vertices). Updates at the next draw
    /// what changed: the instance, plus the polygon's mesh slice when its shape (not only its position)
    /// changed. An id set by setObject becomes a prism, and back. O(1) for circles and boxes, O(points) for
    /// polygons. [Limit] a valid 2D shape (validateShape), finite y0 < y1.
    /// @throws InvalidInput naming the field ("prism 7.radius", "prism 7.y1", ...); the renderer is unchanged.
    void setPrism(ObjectId id, const Shape<2>& shape, double y0, double y1);
    /// Removes `id` (its slot is reused by a later setObject). Unknown ids are ignored.
    void removeObject(ObjectId id);
    bool contains(ObjectId id) const { return m_slotOf.count(id) != 0; }
    std::size_t objectCount() const { return m_slotOf.size(); }
    /// Every object's id, ascending.
    std::vector<ObjectId> ids() const;

    /// The item id draw(..., ItemId) writes for `id` (>= 1; 0 is "nothing"). Stable until `id` is
    /// removed. @throws InvalidInput for an unknown id.
    std::uint32_t itemOf(ObjectId id) const;
    /// The object of item `item`, false when no object has it now.
    bool objectOfItem(std::uint32_t item, ObjectId& id) const;

    /// Sets the camera of the following draws. [Limit] a valid camera (validateCamera); its aspect is
    /// used as given, whatever the target's size (pixels are then not square). `nearPlane` ([World
    /// units], > 0) overrides the options' near plane for this camera; 0 keeps the options' value.
    /// @throws InvalidInput for an invalid camera or a negative nearPlane.
    void setCamera(const Camera3& camera, double nearPlane = 0);
    const Camera3& camera() const { return m_camera; }

    /// Draws the objects `ids` (in any order; duplicates are drawn twice) into the bound framebuffer,
    /// depth test and depth writes on, colour writes on. [Limit] every id is held; a setCamera() before.
    /// @throws InvalidInput naming an unknown id (before anything is drawn).
    void draw(std::span<const ObjectId> ids, DrawOutput output);
    /// Draws every object.
    void drawAll(DrawOutput output);
    /// Draws `boxes` ([World units], rounded outwards to float) with depth test on and colour and depth
    /// writes off, in one instanced draw: what an occlusion query counts. Restores the write masks.
    void drawBoxes(std::span<const Box<3>> boxes);

    /// True when `point` ([World units]) lies in what is drawn for `id` (the float box, the sphere mesh's
    /// convex polyhedron, or the prism: its y slab and its drawn 2D polygon) grown by `tolerance` ([World
    /// units], >= 0; on the surface counts). [Limit] id is held. O(1) for boxes, O(triangles) for spheres
    /// whose ball holds the point, O(sides) for circle and polygon prisms.
    bool drawnShapeContains(ObjectId id, const Vec3& point, double tolerance = 0) const;
    /// [World units] a lower bound of the distance from `point` to what is drawn for `id` (0 inside). For
    /// a prism: the y slab's distance combined with the 2D distance to the circle (which holds the drawn
    /// n-gon) or to the polygon's farthest edge line.
    double distanceToDrawn(ObjectId id, const Vec3& point) const;
    /// [World units] the largest distance of any drawn vertex from the anchor, positions are sent
    /// relative to: the scale that float rounding of drawn positions is relative to (about 6e-8 of it).
    double drawnExtent() const { return m_extent; }
    /// [World units] the point positions are sent relative to (the first object's centre).
    const Vec3& anchor() const { return m_anchor; }

    /// [World units] the ObjectDesc::occluderInset that puts the culler's occluder model of `shape` inside
    /// what this renderer draws for it: radius * (1 - sphereInradius()) for a ball, plus a margin of 1e-6
    /// of the shape's distance from the anchor and size for float rounding (boxes: that margin only).
    /// Give the culler the analytic shape (the outer model: it contains what is drawn) with this inset.
    double occluderInset(const Shape<3>& shape) const;
    /// [World units] the same for the prism setPrism(id, shape, y0, y1) draws, for a 2D culler given the
    /// analytic 2D shape (or a 3D occluder model of the prism): radius * (1 - circleInradius()) for a
    /// circle, plus the float-rounding margin (boxes and polygons: the margin only). Does not validate.
    double occluderInset(const Shape<2>& shape, double y0, double y1) const;
    /// A drawn circle prism of radius r contains the circle of radius r * circleInradius() (cos(pi / n),
    /// from the float vertices that are drawn) and lies in the circle of radius r.
    double circleInradius() const { return m_circleInradius; }
    int prismSides() const { return m_options.prismSides; }

    /// The unit-sphere mesh and its inradius: a drawn ball of radius r contains the ball of radius
    /// r * sphereInradius() (the inner model) and lies in the ball of radius r (the outer model).
    const Mesh& sphereMesh() const { return m_options.sphere; }
    double sphereInradius() const { return m_options.sphere.inradius; }
    /// [World units] the near plane of the options, and of the current camera.
    double nearPlane() const { return m_options.nearPlane; }
    double cameraNearPlane() const { return m_cameraNear; }

    const RenderStats& stats() const { return m_stats; }
    void resetStats() { m_stats = {}; }
    GlContext& context() const { return m_context; }

private:
    // Box prisms are BoxKind (a Box<3>). Circle prisms instance the unit n-gon prism; polygon prisms
    // have a mesh slice each and are drawn in one multi-draw-indirect call per pass.
    enum Kind : std::uint8_t { SphereKind = 0, BoxKind = 1, CircleKind = 2, PolygonKind = 3, KindCount = 4 };
    struct Instance {
        float offset[4]; ///< xyz: model origin relative to the anchor
        float scale[4];  ///< xyz: per-axis scale of the unit mesh
    };
    struct Slot {
        ObjectId id = 0;
        Kind kind = SphereKind;
        bool used = false;
        bool dirty = false;
        bool prism = false;
    };
    /// A polygon prism's mesh: a slice of the polygon buffers. The mesh is the polygon relative to its
    /// first point, extruded over [0, 1] (the instance offsets and scales it).
    struct PolygonMesh {
        std::uint32_t firstVertex = 0, capacity = 0; // capacity in polygon points (2 vertices each)
        std::uint32_t firstIndex = 0, points = 0;    // points in use
        std::vector<glm::dvec2> relative;            // the points given, minus the first (for "same shape?")
        std::vector<glm::dvec2> drawn;               // the float mesh points (x, z), as doubles
        std::vector<glm::dvec3> edges;               // drawn edge lines: unit outward normal (x, z), offset
        /// Indices drawn: 12 points - 12 for a prism; 3 per triangle for a polytope (whose mesh is its
        /// boundary triangles, vertices relative to the first one, in the same kind of slice).
        std::uint32_t indexCount = 0;
        std::vector<glm::dvec4> planes;              // polytopes: the drawn facets (unit outward n, offset), mesh frame
        std::vector<glm::dvec3> polytopeKey;         // polytopes: the vertices given, minus the first ("same shape?")
        bool dirty = false;                          // in m_dirtyPolygons, not uploaded yet
    };
    struct PolygonSlice {
        std::uint32_t firstVertex = 0, capacity = 0, firstIndex = 0;
    };
    struct DrawCommand { // glMultiDrawElementsIndirect's record
        std::uint32_t count, instanceCount, firstIndex;
        std::int32_t baseVertex;
        std::uint32_t baseInstance;
    };
    struct Ring {
        GLuint buffer = 0;
        std::size_t capacity = 0, cursor = 0; // bytes
    };

    void init();
    void release();
    /// The slot of `id`, made when it is new; `added` says which.
    std::uint32_t slotFor(ObjectId id, bool& added);
    void anchorAt(const glm::dvec3& centre);
    void markDirty(std::uint32_t slot);
    void updateExtent(const Instance& inst);
    /// Frees the polygon mesh of `slot`, if it has one.
    void releasePolygon(std::uint32_t slot);
    /// setObject for a convex polytope (obb, hull): its triangles in a polygon slice.
    void setPolytope(std::uint32_t slot, bool added, const ConvexPolytope& poly);
    PolygonSlice allocatePolygon(std::uint32_t points);
    void uploadPolygons();
    void uploadDirty();
    void applyState();
    /// Appends `bytes` to the ring; returns the byte offset where they start.
    std::size_t stream(Ring& ring, const void* data, std::size_t bytes, std::size_t alignment);
    void drawSlots(DrawOutput output);
    void drawLists();

    GlContext& m_context;
    const GlFunctions& m_gl;
    SceneRendererOptions m_options;

    // CPU side of the objects.
    std::unordered_map<ObjectId, std::uint32_t> m_slotOf;
    std::vector<Slot> m_slots;
    std::vector<Instance> m_instances;
    std::vector<std::uint32_t> m_freeSlots, m_dirtySlots;
    bool m_hasAnchor = false;
    glm::dvec3 m_anchor{0.0};
    double m_extent = 0;
    std::size_t m_gpuCapacity = 0; // instance slots allocated in m_instanceBuffer

    // The sphere mesh's face planes (unit normal, offset), for drawnShapeContains.
    std::vector<glm::dvec4> m_spherePlanes;
    // The unit n-gon's edge lines in (x, z) (unit outward normal, offset) and its inradius.
    std::vector<glm::dvec3> m_circleEdges;
    double m_circleInradius = 0;

    // Polygon prisms: meshes by slot, the CPU copy of the polygon buffers, free slices, dirty slices.
    std::unordered_map<std::uint32_t, PolygonMesh> m_polygons;
    std::vector<glm::vec3> m_polyPositions;
    std::vector<std::uint32_t> m_polyIndices;
    std::vector<PolygonSlice> m_freePolygons;
    std::vector<std::uint32_t> m_dirtyPolygons; // slots
    std::size_t m_polyGpuVertices = 0, m_polyGpuIndices = 0;
    std::vector<DrawCommand> m_commands;
    std::uint64_t m_listPrisms = 0; // prisms in the current draw lists

    // Per-draw scratch: slots of the requested ids, by kind.
    std::vector<std::uint32_t> m_drawList[KindCount];
    std::vector<float> m_boxScratch; // (min, max) per query box, anchor-relative

    // Camera.
    Camera3 m_camera;
    glm::mat4 m_viewProjection{1.0f};
    glm::vec3 m_eye{0.0f};
    float m_farSquared = 0;
    double m_cameraNear = 0;
    bool m_farClip = false;

    // GL objects.
    GLuint m_meshVbo = 0, m_meshIbo = 0, m_objectVao = 0, m_boxVao = 0, m_instanceBuffer = 0;
    GLuint m_polyVbo = 0, m_polyIbo = 0, m_polyVao = 0;
    Ring m_listRing, m_boxRing, m_commandRing;
    GLuint m_objectProgram[2][2] = {}; // [output][farClip]
    GLuint m_boxProgram[2] = {};       // [farClip]
    GLint m_indexOffset[KindCount] = {}, m_indexCount[KindCount] = {}, m_baseVertex[KindCount] = {};

    RenderStats m_stats;
};

} // namespace rgvc
