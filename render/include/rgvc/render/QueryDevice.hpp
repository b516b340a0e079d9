// What coherent hierarchical culling needs from a renderer: draw objects, and ask how many samples of a
// set of boxes pass the depth test. GL-free, so that the CHC traversal (Chc.hpp) is tested with a
// deterministic device (tests) and runs on the GL one (gl/GlQueryDevice.hpp) unchanged, as bvh v2 passes
// its executors in.
//
// Semantics a device must keep (seed 001, §3):
//   - drawObjects renders the objects with depth test and depth writes on, into the frame being built.
//   - issueQuery renders the boxes with depth test on and colour and depth writes off, counting the
//     samples that pass against everything drawn so far in this frame; the answer is fetched later.
//     Several boxes in one query are a CHC++ multiquery (or a node's tight bounds): the count is over all.
//   - A query's answer reflects exactly the objects drawn before it was issued, so a query issued early
//     can only count more samples than one issued late: answers are conservative in issue order.
//   - beginFrame clears depth (and colour); queries of an earlier frame must all have been fetched.
#pragma once

#include "rgvc/dynamics/Culler.hpp"
#include "rgvc/grid/Shapes.hpp"

#include <cstdint>
#include <span>

namespace rgvc {

/// A query issued by a QueryDevice, valid until its result is fetched.
using QueryHandle = std::uint32_t;

class QueryDevice {
public:
    virtual ~QueryDevice() = default;

    /// Starts a frame seen from `camera` (world units; the device keeps its own near plane).
    virtual void beginFrame(const Camera3& camera) = 0;
    /// Draws these objects (ids the device holds) with depth writes. [Limit] every id is known to the device.
    virtual void drawObjects(std::span<const ObjectId> ids) = 0;
    /// Issues one occlusion query over the union of `boxes` ([World units], axis-aligned, closed).
    /// [Limit] boxes.size() >= 1.
    virtual QueryHandle issueQuery(std::span<const Box<3>> boxes) = 0;
    /// True when the answer of `q` can be fetched without waiting.
    virtual bool queryReady(QueryHandle q) = 0;
    /// [Samples] the number of samples of the query's boxes that passed the depth test. Waits if needed;
    /// releases the handle.
    virtual std::uint64_t queryResult(QueryHandle q) = 0;
    /// Ends the frame (glFinish on GL): the frame time a benchmark measures ends here.
    virtual void endFrame() = 0;
};

} // namespace rgvc
