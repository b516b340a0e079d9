// rgvc_sweep's results (SweepReport.hpp).
#include "SweepReport.hpp"

#include <cstdio>

namespace rgvc::bench {

double judgedMs(const SweepRow& r) { return r.medianFrameMs >= 0 ? r.medianFrameMs : r.medianCullMs; }

namespace {
bool eligible(const SweepRow& r) { return !r.setting.approximate() && r.misses == 0 && r.ratio >= 0; }
} // namespace

void markPareto(std::vector<SweepRow>& rows) {
    for (SweepRow& p : rows) {
        p.pareto = false;
        if (!eligible(p)) continue;
        bool dominated = false;
        for (const SweepRow& q : rows) {
            if (&q == &p || q.scene != p.scene || !eligible(q)) continue;
            const double tq = judgedMs(q), tp = judgedMs(p);
            if (tq <= tp && q.ratio <= p.ratio && (tq < tp || q.ratio < p.ratio)) {
                dominated = true;
                break;
            }
        }
        p.pareto = !dominated;
    }
}

SweepBest bestOf(const std::vector<SweepRow>& rows, const std::string& scene) {
    SweepBest b;
    for (const SweepRow& r : rows)
        if (r.scene == scene && r.pareto && (!b.fastest || judgedMs(r) < judgedMs(*b.fastest))) b.fastest = &r;
    if (!b.fastest) return b;
    for (const SweepRow& r : rows)
        if (r.scene == scene && r.pareto && judgedMs(r) <= 1.5 * judgedMs(*b.fastest) &&
            (!b.tightest || r.ratio < b.tightest->ratio))
            b.tightest = &r;
    return b;
}

void writeCsv(std::ostream& out, const std::vector<std::string>& header, const std::vector<SweepRow>& rows) {
    for (const std::string& h : header) out << "# " << h << "\n";
    out << "scene,dims,setting,factor,approximate,voxel_size,grid,extension,core,image_rows,buffer,tbv,gl_method,n_vp,"
           "median_cull_ms,p90_cull_ms,median_frame_ms,mean_answer,mean_visible,overestimation,misses,miss_reference,"
           "checked_frames,pareto,time_ms\n";
    char buf[256];
    for (const SweepRow& r : rows) {
        const SweepSetting& s = r.setting;
        out << r.scene << ',' << r.dims << ',' << s.name << ',' << s.factor << ',' << (s.approximate() ? 1 : 0) << ','
            << r.voxelSize << ',' << r.grid << ',' << (s.options.occluderExtension ? "on" : "off") << ','
            << coreName(s, r.dims) << ',' << (r.dims == 3 && s.options.hierarchical ? s.options.traversalImageRows : 0)
            << ',' << bufferName(s, r.dims) << ',' << tbvName(s.options) << ',' << s.glMethod << ',' << s.visiblePixels;
        std::snprintf(buf, sizeof buf, ",%.4f,%.4f,%.4f,%.2f,%.2f,%.4f,", r.medianCullMs, r.p90CullMs, r.medianFrameMs,
                      r.meanAnswer, r.meanVisible, r.ratio);
        out << buf << r.misses << ',' << r.missReference << ',' << r.checkedFrames << ',' << (r.pareto ? 1 : 0);
        std::snprintf(buf, sizeof buf, ",%.4f\n", judgedMs(r));
        out << buf;
    }
}

void printSceneTable(const std::vector<SweepRow>& rows, const std::string& scene) {
    std::printf("\n| %s: setting | grid | cull ms (median) | p90 | frame ms (median) | mean \\|answer\\| | "
                "\\|answer\\|/\\|visible\\| | misses | front |\n|---|---|--:|--:|--:|--:|--:|--:|:-:|\n",
                scene.c_str());
    for (const SweepRow& r : rows) {
        if (r.scene != scene) continue;
        char frame[32], ratio[32];
        std::snprintf(frame, sizeof frame, r.medianFrameMs >= 0 ? "%.2f" : "-", r.medianFrameMs);
        std::snprintf(ratio, sizeof ratio, r.ratio >= 0 ? "%.3f" : "-", r.ratio);
        std::printf("| %s%s | %s | %.3f | %.3f | %s | %.1f | %s | %s%llu%s | %s |\n", r.setting.name.c_str(),
                    r.setting.approximate() ? " (approximate)" : "", r.grid.c_str(), r.medianCullMs, r.p90CullMs, frame,
                    r.meanAnswer, ratio, r.misses && !r.setting.approximate() ? "**" : "",
                    (unsigned long long)r.misses, r.misses && !r.setting.approximate() ? "**" : "", r.pareto ? "*" : "");
    }
}

void printBestTable(const std::vector<SweepRow>& rows, const std::vector<std::string>& scenes) {
    std::printf("\n| scene | fastest on the front | time ms | \\|answer\\|/\\|visible\\| | tightest within 1.5x | time ms | "
                "\\|answer\\|/\\|visible\\| | base: time ms | base: ratio |\n|---|---|--:|--:|---|--:|--:|--:|--:|\n");
    for (const std::string& scene : scenes) {
        const SweepBest b = bestOf(rows, scene);
        const SweepRow* base = nullptr;
        for (const SweepRow& r : rows)
            if (r.scene == scene && r.setting.name == "base") base = &r;
        if (!b.fastest) {
            std::printf("| %s | (none with 0 misses) | | | | | | | |\n", scene.c_str());
            continue;
        }
        std::printf("| %s | %s | %.3f | %.3f | %s | %.3f | %.3f | %.3f | %.3f |\n", scene.c_str(),
                    b.fastest->setting.name.c_str(), judgedMs(*b.fastest), b.fastest->ratio,
                    b.tightest->setting.name.c_str(), judgedMs(*b.tightest), b.tightest->ratio,
                    base ? judgedMs(*base) : 0.0, base ? base->ratio : 0.0);
    }
}

} // namespace rgvc::bench
