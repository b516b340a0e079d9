#include "rgvc/render/gl/GlQueryDevice.hpp"

#include <chrono>
#include <stdexcept>
#include <string>

namespace rgvc {

namespace {

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

} // namespace

GlQueryDevice::GlQueryDevice(SceneRenderer& renderer, int width, int height)
    : m_renderer(renderer), m_gl(renderer.context().gl()), m_target(renderer.context(), width, height, ColourFormat::Rgba8) {}

GlQueryDevice::~GlQueryDevice() {
    if (!m_queries.empty()) m_gl.DeleteQueries(GLsizei(m_queries.size()), m_queries.data());
}

void GlQueryDevice::beginFrame(const Camera3& camera) {
    if (m_outstanding != 0)
        throw std::logic_error("GlQueryDevice::beginFrame: " + std::to_string(m_outstanding) +
                               " queries of the previous frame were not fetched");
    m_renderer.setCamera(camera);
    m_target.clear(); // binds it and sets the viewport
    ++m_stats.frames;
}

void GlQueryDevice::drawObjects(std::span<const ObjectId> ids) {
    m_target.bind();
    m_renderer.draw(ids, DrawOutput::Colour);
}

QueryHandle GlQueryDevice::issueQuery(std::span<const Box<3>> boxes) {
    if (boxes.empty()) throw InvalidInput("boxes", "a query needs at least one box");
    for (const Box<3>& b : boxes)
        for (int a = 0; a < 3; ++a)
            if (!(b.min[a] <= b.max[a])) throw InvalidInput("boxes", "a query box needs min <= max on every axis");
    if (m_free.empty()) {
        // Grow the pool by a batch; names are made once and reused across frames.
        const std::size_t first = m_queries.size(), batch = first == 0 ? 64 : first;
        m_queries.resize(first + batch);
        m_gl.GenQueries(GLsizei(batch), m_queries.data() + first);
        m_active.resize(first + batch, 0);
        m_issuedAt.resize(first + batch, 0);
        for (std::size_t i = first + batch; i-- > first;) m_free.push_back(QueryHandle(i));
    }
    const QueryHandle q = m_free.back();
    m_free.pop_back();
    m_target.bind();
    m_gl.BeginQuery(GL_SAMPLES_PASSED, m_queries[q]);
    m_renderer.drawBoxes(boxes);
    m_gl.EndQuery(GL_SAMPLES_PASSED);
    m_active[q] = 1;
    m_issuedAt[q] = ++m_issueSerial;
    ++m_outstanding;
    ++m_stats.queriesIssued;
    m_stats.multiQueries += boxes.size() > 1;
    m_stats.boxesQueried += boxes.size();
    return q;
}

void GlQueryDevice::checkHandle(QueryHandle q, const char* what) const {
    if (q >= m_active.size() || !m_active[q])
        throw InvalidInput(what, "query handle " + std::to_string(q) + " is not outstanding");
}

bool GlQueryDevice::queryReady(QueryHandle q) {
    checkHandle(q, "queryReady");
    // A query's result becomes available only after its commands reach the GPU: flush once, on the first
    // poll, or a loop polling an unflushed query could spin forever.
    if (m_issuedAt[q] > m_flushedSerial) {
        m_gl.Flush();
        m_flushedSerial = m_issueSerial;
    }
    GLuint available = 0;
    m_gl.GetQueryObjectuiv(m_queries[q], GL_QUERY_RESULT_AVAILABLE, &available);
    return available != 0;
}

std::uint64_t GlQueryDevice::queryResult(QueryHandle q) {
    checkHandle(q, "queryResult");
    GLuint available = 0;
    m_gl.GetQueryObjectuiv(m_queries[q], GL_QUERY_RESULT_AVAILABLE, &available);
    const auto t0 = std::chrono::steady_clock::now();
    GLuint64 samples = 0;
    m_gl.GetQueryObjectui64v(m_queries[q], GL_QUERY_RESULT, &samples); // waits when not available
    if (!available) {
        ++m_stats.resultsWaited;
        m_stats.waitMs += msSince(t0);
    }
    ++m_stats.resultsFetched;
    m_active[q] = 0;
    m_free.push_back(q);
    --m_outstanding;
    return samples;
}

void GlQueryDevice::endFrame() {
    const auto t0 = std::chrono::steady_clock::now();
    m_gl.Finish();
    m_stats.finishMs += msSince(t0);
}

} // namespace rgvc
