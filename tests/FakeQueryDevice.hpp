// A deterministic CPU QueryDevice for the CHC tests (header-only): a small id + depth buffer that ray
// casts spheres and boxes at pixel centres, occlusion queries that count the samples of their boxes
// passing the depth test, and answers that become ready only after a configurable number of later
// device calls, so that CHC's query queue is exercised as on a GPU.
//
// It mimics what matters of GL:
//   - Surfaces, not solids. A ray's sample of an object or a query box is the first surface crossing at
//     view depth >= near: the entry, or the exit when the near plane (or the eye) is inside the box or
//     sphere. So a query box that the near plane clips answers for its far faces only, as on GL: a
//     traversal must not query such boxes (CHC++'s camera-inside-a-node case).
//   - Depth is the view-space z (the distance along the view direction), tested per sample; the far
//     limit is the camera's `far` ball, as in ViewFrustum.
//   - Draws keep the nearest sample, ties going to the smaller id, so the final image does not depend on
//     the drawing order: the image of any set of objects is the image of that set.
//   - Queries pass where their box's sample is <= the stored depth (GL_LEQUAL), with the boxes grown by
//     a relative 1e-9, so that a box around a sphere or equal to a box object is never beaten by its own
//     object's rounding. Queries answer against what was drawn before they were issued.
//   - Latency: a query issued at device call c is ready once c + latency further calls (draws and
//     queries) were made. Fetching a query that is not ready counts as a blocking fetch.
// Misuse (an unknown id, fetching twice, a frame begun with queries unfetched) throws std::logic_error.
#pragma once

#include "rgvc/grid/Camera.hpp"
#include "rgvc/grid/Shapes.hpp"
#include "rgvc/render/QueryDevice.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

namespace rgvc::testing {

inline constexpr ObjectId kBackgroundId = std::numeric_limits<ObjectId>::max();

/// An id + depth image (row-major, top row first).
struct IdDepthImage {
    int width = 0, height = 0;
    std::vector<double> depth; ///< view z; +inf where nothing was drawn
    std::vector<ObjectId> id;  ///< kBackgroundId where nothing was drawn
    bool operator==(const IdDepthImage& o) const = default;
    /// Sorted ids that cover at least one pixel.
    std::vector<ObjectId> visibleIds() const {
        std::vector<ObjectId> v;
        for (ObjectId i : id)
            if (i != kBackgroundId) v.push_back(i);
        std::sort(v.begin(), v.end());
        v.erase(std::unique(v.begin(), v.end()), v.end());
        return v;
    }
    /// Pixels that differ from `o`, as "x,y: id a depth d vs id b depth e" lines (at most `limit`).
    std::string differences(const IdDepthImage& o, int limit = 8) const {
        std::string out;
        int n = 0;
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                const std::size_t i = std::size_t(y) * std::size_t(width) + std::size_t(x);
                if (id[i] == o.id[i] && depth[i] == o.depth[i]) continue;
                if (n++ < limit)
                    out += std::to_string(x) + "," + std::to_string(y) + ": id " + std::to_string(id[i]) + " depth " +
                           std::to_string(depth[i]) + " vs id " + std::to_string(o.id[i]) + " depth " +
                           std::to_string(o.depth[i]) + "\n";
            }
        if (n > limit) out += "... " + std::to_string(n) + " pixels differ\n";
        return out;
    }
};

class FakeQueryDevice : public QueryDevice {
public:
    /// @param nearDistance [World units] the near plane (a ChcOptions::nearDistance at least this).
    /// @param latency      [Device calls] before a query's answer is ready.
    FakeQueryDevice(int width = 64, int height = 48, double nearDistance = 0.01, int latency = 0)
        : m_width(width), m_height(height), m_near(nearDistance), m_latency(latency) {}

    void setObject(ObjectId id, const Shape<3>& shape) { m_objects[id] = shape; }
    void removeObject(ObjectId id) { m_objects.erase(id); }
    void setLatency(int k) { m_latency = k; }
    int width() const { return m_width; }
    int height() const { return m_height; }

    // --- QueryDevice
    void beginFrame(const Camera3& camera) override {
        for (const Query& q : m_queries)
            if (!q.fetched) throw std::logic_error("FakeQueryDevice: beginFrame with a query of the last frame unfetched");
        m_queries.clear();
        setCamera(camera);
        clear(m_image);
        m_inFrame = true;
    }
    void drawObjects(std::span<const ObjectId> ids) override {
        requireFrame("drawObjects");
        ++m_clock;
        ++m_drawCalls;
        for (ObjectId id : ids) drawInto(m_image, id);
        m_objectsDrawn += ids.size();
    }
    QueryHandle issueQuery(std::span<const Box<3>> boxes) override {
        requireFrame("issueQuery");
        if (boxes.empty()) throw std::logic_error("FakeQueryDevice: a query needs at least one box");
        ++m_clock;
        ++m_queriesIssued;
        m_boxesQueried += boxes.size();
        Query q;
        q.readyAt = m_clock + std::uint64_t(m_latency);
        // The samples are counted now, against what was drawn so far; only the answer is delayed.
        // A sample covered by several boxes of one query counts once (one rasterization of their union
        // would count it as often as it has front faces; once is enough for "any sample passed").
        m_mask.assign(m_image.depth.size(), 0);
        for (const Box<3>& b : boxes) {
            const Box<3> g = grown(b);
            forEachSample(g.min, g.max, [&](std::size_t i, const Vec3& dir) {
                double t;
                if (!m_mask[i] && boxSample(g, dir, t) && t <= m_image.depth[i]) m_mask[i] = 1;
            });
        }
        for (std::uint8_t m : m_mask) q.samples += m;
        m_queries.push_back(q);
        return QueryHandle(m_queries.size() - 1);
    }
    bool queryReady(QueryHandle h) override { return m_clock >= query(h).readyAt; }
    std::uint64_t queryResult(QueryHandle h) override {
        Query& q = query(h);
        if (m_clock < q.readyAt) ++m_blockingFetches;
        q.fetched = true;
        return q.samples;
    }
    void endFrame() override {
        requireFrame("endFrame");
        m_inFrame = false;
    }

    // --- For the tests
    /// The image of the frame being built (or the last one).
    const IdDepthImage& image() const { return m_image; }
    /// The image of `ids` seen from `camera`, rendered apart (the frame's image and counters untouched).
    IdDepthImage referenceImage(const Camera3& camera, std::span<const ObjectId> ids) {
        const View saved = m_view;
        setCamera(camera);
        IdDepthImage img;
        clear(img);
        for (ObjectId id : ids) drawInto(img, id);
        m_view = saved;
        return img;
    }
    std::uint64_t queriesIssued() const { return m_queriesIssued; }
    std::uint64_t boxesQueried() const { return m_boxesQueried; }
    std::uint64_t blockingFetches() const { return m_blockingFetches; }
    std::uint64_t drawCalls() const { return m_drawCalls; }
    std::uint64_t objectsDrawn() const { return m_objectsDrawn; }

private:
    struct Query {
        std::uint64_t samples = 0;
        std::uint64_t readyAt = 0;
        bool fetched = false;
    };
    struct View {
        Vec3 eye{0.0}, forward{0.0, 0.0, -1.0}, right{1.0, 0.0, 0.0}, up{0.0, 1.0, 0.0};
        double tw = 1, th = 1, far = std::numeric_limits<double>::infinity();
    };

    void requireFrame(const char* what) const {
        if (!m_inFrame) throw std::logic_error(std::string("FakeQueryDevice: ") + what + " outside a frame");
    }
    Query& query(QueryHandle h) {
        if (h >= m_queries.size() || m_queries[h].fetched)
            throw std::logic_error("FakeQueryDevice: unknown or already fetched query " + std::to_string(h));
        return m_queries[h];
    }
    void setCamera(const Camera3& c) {
        View v;
        v.eye = c.position;
        v.forward = safeNormalize<3>(c.direction);
        const bool upGiven = c.up.x != 0 || c.up.y != 0 || c.up.z != 0;
        const Vec3 up = upGiven ? safeNormalize<3>(c.up) : Vec3{0, 1, 0};
        v.right = glm::normalize(glm::cross(v.forward, up));
        v.up = glm::cross(v.right, v.forward);
        v.th = std::tan(0.5 * c.fovDeg * 3.14159265358979323846 / 180.0);
        v.tw = c.aspect * v.th;
        v.far = c.far;
        m_view = v;
    }
    void clear(IdDepthImage& img) const {
        img.width = m_width;
        img.height = m_height;
        img.depth.assign(std::size_t(m_width) * std::size_t(m_height), std::numeric_limits<double>::infinity());
        img.id.assign(img.depth.size(), kBackgroundId);
    }
    static Box<3> grown(const Box<3>& b) {
        double m = 1;
        for (int a = 0; a < 3; ++a) m = std::max({m, std::abs(b.min[a]), std::abs(b.max[a])});
        const double e = 1e-9 * m;
        return {b.min - e, b.max + e};
    }
    /// Calls f(pixel index, ray direction) for every pixel whose centre ray may meet the box.
    template <class F> void forEachSample(const Vec3& lo, const Vec3& hi, F&& f) const {
        const View& v = m_view;
        int x0 = 0, x1 = m_width - 1, y0 = 0, y1 = m_height - 1;
        // The box's corners projected, when all lie in front of the eye (else: the whole image).
        double sx0 = 1e300, sx1 = -1e300, sy0 = 1e300, sy1 = -1e300;
        bool inFront = true;
        for (int k = 0; k < 8 && inFront; ++k) {
            const Vec3 c{k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z};
            const Vec3 r = c - v.eye;
            const double z = glm::dot(r, v.forward);
            if (!(z > 1e-12)) inFront = false;
            const double sx = glm::dot(r, v.right) / (z * v.tw), sy = glm::dot(r, v.up) / (z * v.th);
            sx0 = std::min(sx0, sx);
            sx1 = std::max(sx1, sx);
            sy0 = std::min(sy0, sy);
            sy1 = std::max(sy1, sy);
        }
        if (inFront) {
            if (sx1 < -1.01 || sx0 > 1.01 || sy1 < -1.01 || sy0 > 1.01) return;
            x0 = std::max(0, int(std::floor((sx0 + 1) * 0.5 * m_width)) - 1);
            x1 = std::min(m_width - 1, int(std::ceil((sx1 + 1) * 0.5 * m_width)) + 1);
            y0 = std::max(0, int(std::floor((1 - sy1) * 0.5 * m_height)) - 1);
            y1 = std::min(m_height - 1, int(std::ceil((1 - sy0) * 0.5 * m_height)) + 1);
        }
        for (int y = y0; y <= y1; ++y) {
            const double sy = 1 - 2 * (y + 0.5) / m_height;
            for (int x = x0; x <= x1; ++x) {
                const double sx = 2 * (x + 0.5) / m_width - 1;
                const Vec3 dir = v.forward + (sx * v.tw) * v.right + (sy * v.th) * v.up;
                f(std::size_t(y) * std::size_t(m_width) + std::size_t(x), dir);
            }
        }
    }
    /// The first surface crossing at view depth >= near of the ray eye + t * dir (t = view z), within far.
    bool firstSurface(double t0, double t1, const Vec3& dir, double& t) const {
        if (t0 > t1) return false;
        if (t0 >= m_near) t = t0;
        else if (t1 >= m_near) t = t1;
        else return false;
        return std::isinf(m_view.far) || t * std::sqrt(lengthSquared<3>(dir)) <= m_view.far;
    }
    bool boxSample(const Box<3>& b, const Vec3& dir, double& t) const {
        double t0 = -std::numeric_limits<double>::infinity(), t1 = std::numeric_limits<double>::infinity();
        for (int a = 0; a < 3; ++a) {
            const double o = m_view.eye[a];
            if (dir[a] == 0) {
                if (o < b.min[a] || o > b.max[a]) return false;
                continue;
            }
            double u = (b.min[a] - o) / dir[a], w = (b.max[a] - o) / dir[a];
            if (u > w) std::swap(u, w);
            t0 = std::max(t0, u);
            t1 = std::min(t1, w);
        }
        return firstSurface(t0, t1, dir, t);
    }
    bool sphereSample(const Ball<3>& s, const Vec3& dir, double& t) const {
        const Vec3 oc = m_view.eye - s.center;
        const double a = lengthSquared<3>(dir), bh = glm::dot(oc, dir), c = lengthSquared<3>(oc) - s.radius * s.radius;
        const double disc = bh * bh - a * c;
        if (disc < 0) return false;
        const double r = std::sqrt(disc);
        return firstSurface((-bh - r) / a, (-bh + r) / a, dir, t);
    }
    void drawInto(IdDepthImage& img, ObjectId id) const {
        const auto it = m_objects.find(id);
        if (it == m_objects.end()) throw std::logic_error("FakeQueryDevice: unknown object " + std::to_string(id));
        const Shape<3>& shape = it->second;
        const Box<3> bounds = boundsOf<3>(shape);
        forEachSample(bounds.min, bounds.max, [&](std::size_t i, const Vec3& dir) {
            double t;
            const bool hit = std::holds_alternative<Ball<3>>(shape) ? sphereSample(std::get<Ball<3>>(shape), dir, t)
                                                                     : boxSample(std::get<Box<3>>(shape), dir, t);
            if (hit && (t < img.depth[i] || (t == img.depth[i] && id < img.id[i]))) {
                img.depth[i] = t;
                img.id[i] = id;
            }
        });
    }

    int m_width, m_height;
    double m_near;
    int m_latency;
    std::unordered_map<ObjectId, Shape<3>> m_objects;
    View m_view;
    IdDepthImage m_image;
    std::vector<std::uint8_t> m_mask;
    std::vector<Query> m_queries;
    std::uint64_t m_clock = 0;
    bool m_inFrame = false;
    std::uint64_t m_queriesIssued = 0, m_boxesQueried = 0, m_blockingFetches = 0, m_drawCalls = 0, m_objectsDrawn = 0;
};

} // namespace rgvc::testing
