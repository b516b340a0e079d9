// GlWalk: see GlWalk.hpp.
#include "GlWalk.hpp"

#include "BenchSupport.hpp"

#include "rgvc/render/gl/ItemBuffer.hpp"

#include <algorithm>
#include <chrono>
#include <stdexcept>

namespace rgvc::bench {

GlMethodSpec glMethod(const std::string& name, const GridGeometry3& geometry, const std::string& label) {
    GlMethodSpec m;
    if (name == "zb") m.gl = CullMethod::Zb;
    else if (name == "vfc") m.gl = CullMethod::Vfc;
    else if (name == "rgvc") {
        m.gl = CullMethod::Zb; // the grid's PVS drawn as is
        m.grid = true;
    } else if (name == "rgvc+chc") {
        m.gl = CullMethod::ChcPlusPlus;
        m.grid = true;
    } else if (name == "chc") m.gl = CullMethod::ChcPlusPlus;
    else if (name == "sw") m.gl = CullMethod::StopAndWait;
    else if (name == "ideal") {
        m.gl = CullMethod::Ideal;
        m.ideal = true;
    } else throw std::invalid_argument("unknown method '" + name + "' (zb, vfc, rgvc, rgvc+chc, chc, sw, ideal)");
    m.name = label.empty() ? name : label;
    m.geometry = geometry;
    return m;
}

std::vector<GlMethodSpec> parseGlMethods(const std::string& list, const GridGeometry3& geometry) {
    std::vector<GlMethodSpec> out;
    const std::string all = list + ",";
    for (std::size_t start = 0, comma; (comma = all.find(',', start)) != std::string::npos; start = comma + 1) {
        const std::string name = all.substr(start, comma - start);
        const bool dup = std::any_of(out.begin(), out.end(), [&](const GlMethodSpec& m) { return m.name == name; });
        if (!name.empty() && !dup) out.push_back(glMethod(name, geometry));
    }
    if (out.empty()) throw std::invalid_argument("no method given");
    return out;
}

reference::MovingSpheres3D paperWalkScene(int spheres, int statics) {
    reference::MovingSpheres3D scene = reference::movingSpheres3D(7, spheres);
    for (std::size_t i = 0; i < std::size_t(std::clamp(statics, 0, spheres)); ++i) {
        scene.velocity[i] = Vec3(0.0);
        scene.objects[i].isStatic = true;
        scene.objects[i].maxSpeed = 0;
    }
    return scene;
}

std::string resolutionLabel(const GridGeometry3& g) {
    const IVec3 r = g.resolution();
    return std::to_string(r.x) + "x" + std::to_string(r.y) + "x" + std::to_string(r.z);
}

GlWalk::GlWalk(const std::vector<ObjectDesc<3>>& objects, std::vector<GlMethodSpec> methods, const GlWalkOptions& options)
    : m_options(options) {
    m_context = createOsMesaContext(options.width, options.height);
    m_renderer = std::make_unique<SceneRenderer>(*m_context, options.renderer);
    m_device = std::make_unique<GlQueryDevice>(*m_renderer, options.width, options.height);
    std::vector<BvhItem> items;
    items.reserve(objects.size());
    for (const ObjectDesc<3>& o : objects) {
        m_renderer->setObject(o.id, o.shape);
        items.push_back({o.id, boundsOf<3>(o.shape)});
    }
    m_bvh.build(items);
    for (GlMethodSpec& spec : methods) {
        GlMethodRecord& m = m_methods.emplace_back();
        m.spec = std::move(spec);
        m.chc = std::make_unique<ChcRenderer>(*m_device, m_bvh, options.chc);
        if (!m.spec.grid) continue;
        m.culler = std::make_unique<Culler3D>(m.spec.geometry, m.spec.culler);
        for (ObjectDesc<3> o : objects) {
            // The culler's occluder lies inside the drawn mesh (seed 004 §5.1's inner model).
            o.occluderInset = std::max(o.occluderInset, m_renderer->occluderInset(o.shape));
            m.culler->addObject(o);
        }
    }
}

GlWalk::~GlWalk() = default;

void GlWalk::moveObjects(std::span<const ObjectDesc<3>> moved) {
    for (const ObjectDesc<3>& o : moved) {
        m_renderer->setObject(o.id, o.shape);
        m_bvh.update(o.id, boundsOf<3>(o.shape));
        for (GlMethodRecord& m : m_methods)
            if (m.culler) m.culler->updateObject(o.id, o.shape);
    }
    m_bvh.rebuildIfDegraded();
}

void GlWalk::frame(const Camera3& camera) {
    const ItemBufferImage img = itemBuffer(*m_renderer, camera, m_options.width, m_options.height);
    const int f = frames();
    m_visible.push_back(std::uint32_t(img.visible.size()));
    for (std::size_t k = 0; k < m_methods.size(); ++k) {
        GlMethodRecord& m = m_methods[(k + std::size_t(f)) % m_methods.size()];
        const auto t0 = std::chrono::steady_clock::now();
        double cullMs = 0;
        const ChcFrameStats* s;
        if (m.spec.grid) {
            const CullResult& r = m.culler->cull(camera);
            cullMs = r.stats.cullMs;
            m.candidates.push_back(std::uint32_t(r.pvs.size()));
            s = &m.chc->render(camera, m.spec.gl, r.pvs);
        } else if (m.spec.ideal) {
            m.candidates.push_back(std::uint32_t(img.visible.size()));
            s = &m.chc->render(camera, m.spec.gl, img.visible);
        } else {
            m.candidates.push_back(std::uint32_t(m_renderer->objectCount()));
            s = &m.chc->renderAll(camera, m.spec.gl);
        }
        m.ms.push_back(msSince(t0));
        m.cullMs.push_back(cullMs);
        m.queries.push_back(s->queries());
        m.drawn.push_back(s->objectsDrawn);
        m_drawnScratch.assign(s->drawn.begin(), s->drawn.end());
        std::sort(m_drawnScratch.begin(), m_drawnScratch.end());
        std::uint32_t misses = 0;
        for (ObjectId id : img.visible) misses += !std::binary_search(m_drawnScratch.begin(), m_drawnScratch.end(), id);
        m.misses.push_back(misses);
        m.totalMisses += misses;
    }
    m_lastVisible = img.visible;
}

const GlMethodRecord* GlWalk::method(const std::string& name) const {
    for (const GlMethodRecord& m : m_methods)
        if (m.spec.name == name) return &m;
    return nullptr;
}

const Culler3D* GlWalk::culler(const std::string& name) const {
    const GlMethodRecord* m = method(name);
    return m ? m->culler.get() : nullptr;
}

void GlWalk::clearRecords() {
    for (GlMethodRecord& m : m_methods) {
        for (auto* v : {&m.ms, &m.cullMs}) v->clear();
        for (auto* v : {&m.queries, &m.drawn, &m.candidates, &m.misses}) v->clear();
        // totalMisses stays: a miss in a warm-up frame is still a miss.
    }
    m_visible.clear();
}

std::uint64_t GlWalk::totalMisses() const {
    std::uint64_t n = 0;
    for (const GlMethodRecord& m : m_methods) n += m.totalMisses;
    return n;
}

namespace {
double mean(const std::vector<std::uint32_t>& v) {
    double s = 0;
    for (auto x : v) s += x;
    return v.empty() ? 0 : s / double(v.size());
}
} // namespace

void GlWalk::printSummary(std::FILE* out) const {
    const GlMethodRecord* zb = nullptr;
    for (const GlMethodRecord& m : m_methods)
        if (m.spec.gl == CullMethod::Zb && !m.spec.grid && !m.spec.ideal) zb = &m;
    const double zbMs = zb ? percentile(zb->ms, 0.5) : 0.0; // the "x ZB" column needs ZB in the run
    const double visible = mean(m_visible);
    std::fprintf(out, "| method | median frame ms | p95 ms | x ZB | grid cull ms | queries/frame | drawn/frame | "
                      "PVS/visible | drawn/visible | misses |\n|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n");
    for (const GlMethodRecord& m : m_methods) {
        const double med = percentile(m.ms, 0.5);
        // |PVS|: what the culling stage keeps, the grid's set for RGVC alone, what is drawn otherwise.
        const double pvs = m.spec.grid && m.spec.gl == CullMethod::Zb ? mean(m.candidates) : mean(m.drawn);
        std::fprintf(out, "| %s | %.2f | %.2f | %.2f | %.3f | %.1f | %.1f | %.2f | %.2f | %llu |\n", m.spec.name.c_str(), med,
                     percentile(m.ms, 0.95), zbMs > 0 && med > 0 ? zbMs / med : 0.0, percentile(m.cullMs, 0.5),
                     mean(m.queries), mean(m.drawn), visible > 0 ? pvs / visible : 0.0,
                     visible > 0 ? mean(m.drawn) / visible : 0.0, (unsigned long long)m.totalMisses);
    }
    std::fprintf(out, "mean |visible| (item buffer at %dx%d): %.1f over %d frames\n", m_options.width, m_options.height,
                 visible, frames());
}

void GlWalk::writeCsvRows(std::ostream& out, const std::string& prefix) const {
    for (const GlMethodRecord& m : m_methods)
        for (std::size_t f = 0; f < m.ms.size(); ++f)
            out << prefix << f << ',' << m.spec.name << ',' << m.ms[f] << ',' << m.cullMs[f] << ',' << m.queries[f] << ','
                << m.drawn[f] << ',' << m.candidates[f] << ',' << m_visible[f] << ',' << m.misses[f] << '\n';
}

} // namespace rgvc::bench
