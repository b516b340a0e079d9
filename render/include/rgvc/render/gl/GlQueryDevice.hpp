// The QueryDevice (rgvc/render/QueryDevice.hpp) on GL: objects drawn instanced by a SceneRenderer into
// the device's own framebuffer, occlusion queries counting GL_SAMPLES_PASSED over boxes.
//
//   rgvc::GlQueryDevice device(renderer, 640, 480);
//   device.beginFrame(camera);                     // binds and clears the framebuffer
//   device.drawObjects(ids);                       // one instanced draw per mesh kind
//   rgvc::QueryHandle q = device.issueQuery(boxes); // one instanced box draw, no colour or depth writes
//   if (device.queryReady(q)) samples = device.queryResult(q);
//   device.endFrame();                             // glFinish
//
// Query objects come from a pool and go back to it when their result is fetched, so a steady state
// allocates nothing. Results are read with GL_QUERY_RESULT_AVAILABLE first, so stats() can tell the
// queries whose result was waited for (the stalls CHC exists to avoid) from those that were ready.
#pragma once

#include "rgvc/render/QueryDevice.hpp"
#include "rgvc/render/gl/GlFramebuffer.hpp"
#include "rgvc/render/gl/SceneRenderer.hpp"

#include <cstdint>
#include <vector>

namespace rgvc {

/// Counters since construction or resetStats().
struct GlQueryStats {
    std::uint64_t frames = 0;
    std::uint64_t queriesIssued = 0;   ///< issueQuery calls
    std::uint64_t multiQueries = 0;    ///< of those, queries over more than one box
    std::uint64_t boxesQueried = 0;    ///< boxes over all queries
    std::uint64_t resultsFetched = 0;  ///< queryResult calls
    std::uint64_t resultsWaited = 0;   ///< of those, results that were not available yet (a stall)
    double waitMs = 0;                 ///< [Milliseconds] time spent in queryResult waiting for results
    double finishMs = 0;               ///< [Milliseconds] time spent in endFrame's glFinish
};

class GlQueryDevice final : public QueryDevice {
public:
    /// A device drawing `renderer`'s objects into its own RGBA8 + float depth framebuffer of
    /// width x height. [Pixels] [Limit] as GlFramebuffer. @throws GlError.
    GlQueryDevice(SceneRenderer& renderer, int width, int height);
    ~GlQueryDevice() override;

    /// Binds and clears the framebuffer, sets the renderer's camera.
    /// @throws std::logic_error when queries of the previous frame were not fetched (QueryDevice's rule).
    void beginFrame(const Camera3& camera) override;
    void drawObjects(std::span<const ObjectId> ids) override;
    /// @throws InvalidInput for an empty box list or a box with min > max.
    QueryHandle issueQuery(std::span<const Box<3>> boxes) override;
    /// @throws InvalidInput for a handle that is not outstanding.
    bool queryReady(QueryHandle q) override;
    /// @throws InvalidInput for a handle that is not outstanding.
    std::uint64_t queryResult(QueryHandle q) override;
    void endFrame() override;

    /// Queries issued and not yet fetched.
    std::size_t outstandingQueries() const { return m_outstanding; }
    const GlQueryStats& stats() const { return m_stats; }
    void resetStats() { m_stats = {}; }
    /// The frame's picture (valid after endFrame).
    const GlFramebuffer& framebuffer() const { return m_target; }
    SceneRenderer& renderer() const { return m_renderer; }

private:
    void checkHandle(QueryHandle q, const char* what) const;

    SceneRenderer& m_renderer;
    const GlFunctions& m_gl;
    GlFramebuffer m_target;
    std::vector<GLuint> m_queries;       // the pool: every query object made, by handle
    std::vector<QueryHandle> m_free;     // handles not in use
    std::vector<std::uint8_t> m_active;  // by handle: issued and not fetched
    std::vector<std::uint64_t> m_issuedAt; // by handle: issue serial; flushed when <= m_flushedSerial
    std::uint64_t m_issueSerial = 0, m_flushedSerial = 0;
    std::size_t m_outstanding = 0;
    GlQueryStats m_stats;
};

} // namespace rgvc
