// The front-to-back walk of a BrickPyramid<D> that the brick traversals share (BrickTraversal2D.hpp,
// BrickTraversal3D.hpp): nodes are taken from a stack, empty ones skipped in O(1), the others handed to
// the caller's test (outside the view, hidden in its occlusion image), and bricks that pass it to the
// caller's visit. What differs between 2D and 3D is only the view region, the image and how a brick's
// voxels are read; the order, the skipping and their soundness are the same, so they live here once.
//
// Order. Children are visited nearest first: with near = the child on the camera's side of the node's
// split plane on each axis, child near ^ i for i = 0 .. 2^D - 1. A ray crosses each split plane at most
// once, from the near to the far side, so the children it meets have growing sets of flipped bits, and
// a child with a superset of another's flipped bits has a larger i: no child is visited before one that
// can lie in front of it along a ray. The order matters only for effectiveness (occluders drawn before
// what they hide is tested); soundness does not depend on it when every fact in the image is true
// whenever it is drawn.
//
// Soundness of a skipped node. Empty: nothing in it can enter the PVS or reveal a TBV (BrickPyramid's
// occupied() == false is a guarantee). The caller's test says "skip" only for a node with no point in
// view or none that is visible. An object with a visible point p is then met in the brick holding p,
// whose every ancestor holds p too and so is neither empty nor skipped by the test.
#pragma once

#include "rgvc/grid/BrickPyramid.hpp"
#include "rgvc/grid/Math.hpp"

#include <cstdint>
#include <type_traits>
#include <vector>

namespace rgvc {

struct BrickWalkStats {
    std::uint64_t nodesVisited = 0; ///< nodes taken from the stack
    std::uint64_t nodesEmpty = 0;   ///< of those, skipped: nothing below them
    std::uint64_t nodesSkipped = 0; ///< of those, skipped by the caller's test (outside, hidden)
};

template <int D> struct BrickNode {
    int level;
    IVec<D> c; ///< node coordinates at its level
};

/// Walks `tree` front to back from `apex` (voxel units). For every occupied node, with its voxel box
/// lo .. hi (hi exclusive, clipped to `res`): `skip(lo, hi)` (or `skip(lo, hi, level)`) true skips it and its subtree; otherwise a
/// brick (level 0) goes to `visit(brickCoords, lo, hi)` and an interior node's children are walked,
/// nearest first. `stack` is the caller's scratch (kept between frames: no allocation once warm).
/// Cost: O(nodes taken) + what the callbacks do.
template <int D, class Skip, class Visit>
BrickWalkStats walkBricks(const BrickPyramid<D>& tree, const IVec<D>& res, const Vec<D>& apex,
                          std::vector<BrickNode<D>>& stack, Skip&& skip, Visit&& visit) {
    BrickWalkStats st;
    stack.clear();
    stack.push_back({tree.levels() - 1, IVec<D>(0)});
    while (!stack.empty()) {
        const BrickNode<D> n = stack.back();
        stack.pop_back();
        ++st.nodesVisited;
        if (!tree.occupied(n.level, n.c)) {
            ++st.nodesEmpty;
            continue;
        }
        const std::int32_t side = BrickPyramid<D>::kBrickSize << n.level; // voxels per axis
        const IVec<D> lo = n.c * side;
        const IVec<D> hi = glm::min(lo + side, res);
        bool skipped;
        if constexpr (std::is_invocable_v<Skip&, const IVec<D>&, const IVec<D>&, int>) skipped = skip(lo, hi, n.level);
        else skipped = skip(lo, hi);
        if (skipped) {
            ++st.nodesSkipped;
            continue;
        }
        if (n.level == 0) {
            visit(n.c, lo, hi);
            continue;
        }
        // Children nearest first: pushed in reverse order, so near ^ 0 pops first.
        const IVec<D> dims = tree.dims(n.level - 1);
        const std::int32_t half = side >> 1;
        int near = 0;
        for (int a = 0; a < D; ++a)
            if (apex[a] >= double(lo[a] + half)) near |= 1 << a;
        for (int i = (1 << D) - 1; i >= 0; --i) {
            const int bits = near ^ i;
            IVec<D> cc;
            bool inside = true;
            for (int a = 0; a < D; ++a) {
                cc[a] = 2 * n.c[a] + ((bits >> a) & 1);
                inside = inside && cc[a] < dims[a];
            }
            if (inside) stack.push_back({n.level - 1, cc});
        }
    }
    return st;
}

} // namespace rgvc
