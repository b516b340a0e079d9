// The simulated motion of a scene file's objects (scene-format.md: "position(t+1) = position(t) + velocity,
// reflecting the velocity component on an axis whenever the shape's bounding box would leave the grid bounds").
//
// The exact rule, per object, per frame, per axis a, independently (this is what `rgvc cull --dump-objects`
// prints, and what a checker must reproduce bit for bit; all in double precision, world units):
//
//   lo, hi   = the object's bounding box on axis a now (frame-0 box + translation, both in world units)
//   G.lo, G.hi = the grid bounds on axis a: origin[a] and origin[a] + voxel_size * resolution[a]
//   if (v[a] > 0 && hi + v[a] > G.hi) or (v[a] < 0 && lo + v[a] < G.lo):   v[a] = -v[a]
//   translation[a] += v[a]
//
// That is: when the step would carry the box past a bound it is moving towards, the velocity component
// flips and the step is taken with the flipped component (the object does not stop at the wall, and is
// not mirrored about it). Touching a bound (hi + v == G.hi) is inside: bounds are closed.
//
// Consequences, all intended:
// - The displacement per frame is exactly the (possibly flipped) velocity, so its length is always
//   |velocity| <= max_speed, which is what the culler's TBVs rely on.
// - An object that starts partly or wholly outside the grid is never stuck: the test only fires when the
//   step moves the box further past the bound it is moving towards, so an object moving back in is left
//   alone, and one moving away is turned around at once. It comes back into the grid (or, if it is wider
//   than the grid on that axis, oscillates by |v[a]| in place) and then bounces normally.
// - A step larger than the free room on an axis may overshoot the opposite bound for a frame; the next
//   frame turns it around. Translations stay bounded either way.
// - Static objects and objects with zero velocity never move.
#pragma once

#include "SceneFile.hpp"

#include <cstddef>
#include <unordered_map>
#include <vector>

namespace rgvc {

/// One axis of the rule above, exposed for tests and for anyone reimplementing it.
/// @param lo, hi         [World units] the bounding box on the axis now.
/// @param gridLo, gridHi [World units] the grid bounds on the axis.
/// @param v              [World units per frame] velocity component; flipped in place when it reflects.
/// @return the step to add to the translation (the possibly flipped v).
double reflectStep(double lo, double hi, double gridLo, double gridHi, double& v);

/// Whether the rule keeps every moving object that is entirely inside the grid inside it for good, which
/// is what CullerOptions::objectsStayInGrid asks the application to promise. True when on every axis
/// 2 |v[a]| <= (grid extent - box extent) for every moving object: a step reflects only when the box is
/// within |v| of the bound it approaches, so the opposite bound is more than (E - w) - |v| >= |v| away and
/// the reflected step lands inside. (Wider objects or faster ones can overshoot the opposite bound for a
/// frame; scenes with such objects get no promise.) A margin of 1e-9 of the extent covers rounding.
template <int D> bool motionStaysInGrid(const SceneData<D>& scene);

/// The culler options `rgvc cull` and `rgvc demo` use for a scene: the defaults, plus objectsStayInGrid
/// when motionStaysInGrid says the scene's motion keeps the promise.
template <int D> CullerOptions sceneCullerOptions(const SceneData<D>& scene) {
    CullerOptions o;
    o.objectsStayInGrid = motionStaysInGrid(scene);
    return o;
}

/// Steps every object of a scene by the rule above, frame after frame.
template <int D> class SceneSimulator {
public:
    /// @param scene  a validated scene (loadScene); copied, so the scene may go away.
    explicit SceneSimulator(const SceneData<D>& scene);

    /// The frame the current state belongs to (0 after construction).
    std::size_t frame() const { return m_frame; }
    /// Advances every object by one frame.
    void step();

    /// Objects by position in the scene's file order, index < size(). (Indexed accessors carry an "At"
    /// suffix because ObjectId and std::size_t are the same type on LP64.)
    std::size_t size() const { return m_objects.size(); }
    ObjectId idAt(std::size_t index) const { return m_objects[index].id; }
    bool isStaticAt(std::size_t index) const { return m_objects[index].isStatic; }
    /// [World units] translation from the frame-0 placement at the current frame.
    const Vec<D>& translationAt(std::size_t index) const { return m_state[index].translation; }
    /// [World units per frame] the velocity the next step starts from (signs flipped by reflections so far).
    const Vec<D>& velocityAt(std::size_t index) const { return m_state[index].velocity; }
    /// True when the last step() changed the object's translation (false before the first step).
    bool movedAt(std::size_t index) const { return m_state[index].moved; }
    /// [World units] the object's shape at the current frame: its frame-0 shape translated.
    Shape<D> shapeAt(std::size_t index) const;

    /// The same, by object id. @throws std::out_of_range on an unknown id.
    std::size_t indexOf(ObjectId id) const;
    const Vec<D>& translation(ObjectId id) const { return translationAt(indexOf(id)); }
    const Vec<D>& velocity(ObjectId id) const { return velocityAt(indexOf(id)); }
    Shape<D> shape(ObjectId id) const { return shapeAt(indexOf(id)); }

    /// [World units] the grid bounds the rule reflects at.
    const Box<D>& bounds() const { return m_bounds; }

private:
    struct State {
        Vec<D> translation{0.0};
        Vec<D> velocity{0.0};
        bool moved = false;
    };
    std::vector<SceneObject<D>> m_objects;
    std::vector<Box<D>> m_frame0Bounds;
    std::vector<State> m_state;
    std::unordered_map<ObjectId, std::size_t> m_index;
    Box<D> m_bounds;
    std::size_t m_frame = 0;
};

using SceneSimulator2 = SceneSimulator<2>;
using SceneSimulator3 = SceneSimulator<3>;

} // namespace rgvc
