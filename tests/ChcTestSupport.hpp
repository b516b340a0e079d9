// Helpers of the CHC tests (header-only): scenes loaded into a FakeQueryDevice and an ObjectBvh, coherent
// camera walks, a box city with occlusion, and the BVH's structural check against recomputation.
#pragma once

#include "FakeQueryDevice.hpp"
#include "RandomScenes3D.hpp"
#include "rgvc/render/Chc.hpp"
#include "rgvc/render/ObjectBvh.hpp"

#include <cmath>
#include <random>
#include <string>
#include <unordered_set>
#include <vector>

namespace rgvc::testing {

struct ChcScene {
    std::vector<ObjectId> ids;
    std::vector<Shape<3>> shapes;
    Camera3 camera; ///< a starting camera
    double step = 1; ///< [World units] a walk's step per frame
};

inline std::vector<BvhItem> bvhItems(const ChcScene& s) {
    std::vector<BvhItem> items;
    for (std::size_t i = 0; i < s.ids.size(); ++i) items.push_back({s.ids[i], boundsOf<3>(s.shapes[i])});
    return items;
}

inline void load(const ChcScene& s, FakeQueryDevice& device, ObjectBvh& bvh) {
    for (std::size_t i = 0; i < s.ids.size(); ++i) device.setObject(s.ids[i], s.shapes[i]);
    bvh.build(bvhItems(s));
}

/// A random scene of RandomScenes3D (spheres, boxes, walls of boxes and of spheres, blocks).
inline ChcScene randomChcScene(std::uint64_t seed) {
    const reference::Scene3D r = reference::randomScene3D(seed);
    ChcScene s;
    for (const ObjectDesc<3>& o : r.objects) {
        s.ids.push_back(o.id);
        s.shapes.push_back(o.shape);
    }
    s.camera = r.camera;
    s.step = 0.4 * r.grid.voxelSize();
    // A camera that sees nothing tests little: turn it towards an object (up reset to a valid one).
    FakeQueryDevice probe(32, 24);
    for (std::size_t i = 0; i < s.ids.size(); ++i) probe.setObject(s.ids[i], s.shapes[i]);
    if (probe.referenceImage(s.camera, s.ids).visibleIds().empty() && !s.ids.empty()) {
        const Box<3> b = boundsOf<3>(s.shapes[std::size_t(seed % s.ids.size())]);
        const Vec3 d = 0.5 * (b.min + b.max) - s.camera.position;
        if (lengthSquared<3>(d) > 0) {
            s.camera.direction = d;
            const Vec3 u = safeNormalize<3>(d);
            s.camera.up = std::abs(u.y) < 0.9 ? Vec3{0, 1, 0} : Vec3{1, 0, 0};
        }
    }
    return s;
}

/// A city of box buildings on a blocks x blocks lattice (streets 4 wide), small spheres and boxes in
/// the streets and behind the buildings, and a camera at street level looking down a street (a walk
/// of up to 60 frames turning at most 0.1 degrees a frame stays in it).
inline ChcScene boxCity(std::uint64_t seed, int blocks = 12, int smallObjects = 400) {
    std::mt19937_64 rng(seed);
    using reference::seeded::uniform;
    ChcScene s;
    ObjectId next = 1;
    const double pitch = 10, size = 6;
    for (int i = 0; i < blocks; ++i)
        for (int j = 0; j < blocks; ++j) {
            const double h = uniform(rng, 4, 20);
            const Vec3 lo{i * pitch, 0, j * pitch};
            s.ids.push_back(next++);
            s.shapes.push_back(Box<3>{lo, lo + Vec3{size, h, size}});
        }
    for (int k = 0; k < smallObjects; ++k) {
        const Vec3 c{uniform(rng, -5, blocks * pitch), uniform(rng, 0.3, 3), uniform(rng, -5, blocks * pitch)};
        if (c.z > 26 && c.z < 31) continue; // the walk's street stays clear: the camera is in no object
        s.ids.push_back(next++);
        if (k % 2) s.shapes.push_back(Ball<3>{c, uniform(rng, 0.2, 0.8)});
        else s.shapes.push_back(Box<3>{c - 0.3, c + Vec3{0.5, uniform(rng, 0.3, 1.5), 0.4}});
    }
    // In the street between building rows 2 and 3 (z in (26, 30)), looking along it.
    s.camera.position = Vec3{-2, 1.7, 27.5};
    s.camera.direction = Vec3{1, -0.02, 0.03};
    s.camera.fovDeg = 60;
    s.camera.aspect = 4.0 / 3.0;
    s.step = 0.4;
    return s;
}

/// Frame `f` of a coherent walk from `start`: forward `step` per frame, turning `degPerFrame` about the
/// camera's up (so that the direction never turns parallel to it).
inline Camera3 walkCamera(const Camera3& start, double step, int f, double degPerFrame = 1.5) {
    Camera3 c = start;
    const bool upGiven = start.up.x != 0 || start.up.y != 0 || start.up.z != 0;
    const Vec3 k = upGiven ? safeNormalize<3>(start.up) : Vec3{0, 1, 0};
    Vec3 d = safeNormalize<3>(start.direction);
    Vec3 p = start.position;
    const double a = degPerFrame * 3.14159265358979323846 / 180;
    for (int i = 0; i < f; ++i) {
        d = d * std::cos(a) + glm::cross(k, d) * std::sin(a) + k * glm::dot(k, d) * (1 - std::cos(a));
        p += step * d;
    }
    c.position = p;
    c.direction = d;
    return c;
}

/// Per-node identity: stamp, parent, children and leaf objects.
struct NodeShape {
    std::uint32_t stamp;
    BvhNodeId parent, c0, c1;
    std::vector<std::uint32_t> objects;
    bool operator==(const NodeShape&) const = default;
};
inline std::vector<NodeShape> shapeOf(const ObjectBvh& bvh) {
    std::vector<NodeShape> v;
    for (BvhNodeId id = 0; id < bvh.nodeCapacity(); ++id) {
        const ObjectBvh::Node& n = bvh.node(id);
        v.push_back({n.live ? n.stamp : 0, n.parent, n.child[0], n.child[1], n.objects});
    }
    return v;
}

inline Box<3> randomBox(std::mt19937_64& rng, double extent) {
    using reference::seeded::uniform;
    const Vec3 c{uniform(rng, 0, extent), uniform(rng, 0, extent), uniform(rng, 0, extent)};
    const Vec3 h{uniform(rng, 0.1, 2), uniform(rng, 0.1, 2), uniform(rng, 0.1, 2)};
    return {c - h, c + h};
}

/// The BVH's structure checked against recomputation: links, every box the exact union of what lies
/// below, every live object in the leaf it names. Returns "" or what is wrong.
inline std::string checkBvh(const ObjectBvh& bvh) {
    std::size_t objects = 0;
    std::unordered_set<std::uint32_t> seen;
    for (BvhNodeId id = 0; id < bvh.nodeCapacity(); ++id) {
        const ObjectBvh::Node& n = bvh.node(id);
        if (!n.live) continue;
        const std::string at = "node " + std::to_string(id) + ": ";
        if (n.stamp == 0) return at + "stamp 0";
        if (id == bvh.root() ? n.parent != kNoBvhNode : n.parent == kNoBvhNode) return at + "bad parent";
        if (n.parent != kNoBvhNode && bvh.node(n.parent).child[0] != id && bvh.node(n.parent).child[1] != id)
            return at + "not a child of its parent";
        Box<3> b{Vec3(1e308), Vec3(-1e308)};
        if (n.isLeaf()) {
            if (n.child[1] != kNoBvhNode) return at + "half a leaf";
            if (n.objects.empty()) return at + "empty leaf";
            for (std::uint32_t slot : n.objects) {
                if (bvh.leafOf(slot) != id) return at + "object's leaf is another";
                if (!seen.insert(slot).second) return at + "object in two leaves";
                b = {glm::min(b.min, bvh.objectBounds(slot).min), glm::max(b.max, bvh.objectBounds(slot).max)};
                ++objects;
            }
        } else {
            for (BvhNodeId c : n.child) {
                if (c == kNoBvhNode || !bvh.node(c).live || bvh.node(c).parent != id) return at + "bad child";
                b = {glm::min(b.min, bvh.node(c).bounds.min), glm::max(b.max, bvh.node(c).bounds.max)};
            }
            if (!n.objects.empty()) return at + "interior node with objects";
        }
        if (b.min != n.bounds.min || b.max != n.bounds.max) return at + "box is not the union below it";
    }
    if (objects != bvh.objectCount()) return "leaves hold " + std::to_string(objects) + " objects, not " +
                                             std::to_string(bvh.objectCount());
    return "";
}

} // namespace rgvc::testing
