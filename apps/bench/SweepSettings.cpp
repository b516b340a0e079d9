// rgvc_sweep's settings (SweepSettings.hpp).
#include "SweepSettings.hpp"

namespace rgvc::bench {

namespace {

SweepSetting with(std::string name, std::string factor, auto edit) {
    SweepSetting s;
    s.name = std::move(name);
    s.factor = std::move(factor);
    edit(s);
    return s;
}

// The resolution factor's names: "voxel x0.5", "voxel x2", "voxel x4".
std::string voxelName(double k) { return std::string("voxel x") + (k == 0.5 ? "0.5" : k == 2.0 ? "2" : "4"); }

} // namespace

std::vector<SweepSetting> sweepSettings(int dims, bool quick) {
    std::vector<SweepSetting> v;
    auto add = [&](std::string name, std::string factor, auto edit) { v.push_back(with(std::move(name), std::move(factor), edit)); };
    // A combination "voxel x<k> + <what>": the voxel size scaled by k, then edit's change.
    auto addVoxelCombo = [&](double k, const std::string& what, auto edit) {
        add(voxelName(k) + " + " + what, "combo", [k, edit](SweepSetting& s) {
            s.voxelScale = k;
            edit(s);
        });
    };
    const bool three = dims == 3;
    add("base", "base", [](SweepSetting&) {});
    for (double k : {0.5, 2.0, 4.0}) {
        if (quick && k != 2.0) continue;
        add(voxelName(k), "resolution", [k](SweepSetting& s) { s.voxelScale = k; });
    }
    add("extension off", "extension", [](SweepSetting& s) { s.options.occluderExtension = false; });
    if (three) {
        add("shells", "core", [](SweepSetting& s) { s.options.hierarchical = false; });
        if (!quick) {
            add("shells caps every frame", "core", [](SweepSetting& s) {
                s.options.hierarchical = false;
                s.options.adaptiveCaps = false;
            });
            for (int rows : {32, 64, 128})
                add("image " + std::to_string(rows), "image", [rows](SweepSetting& s) { s.options.traversalImageRows = rows; });
        }
    }
    for (int n : {0, 16, 64, 256}) {
        const int base = three ? 64 : 256;
        if (n == base || (quick && n != 0)) continue;
        const std::string unit = three ? " rows" : " bins";
        add(n == 0 ? "buffer off" : "buffer " + std::to_string(n) + unit, "buffer", [n, three](SweepSetting& s) {
            if (three) s.options.occlusionBufferRows = n;
            else s.options.occlusionBufferBins = n;
        });
    }
    if (!quick) add("adaptive buffer", "buffer", [](SweepSetting& s) { s.options.adaptiveBuffer = true; });
    if (!quick) {
        if (three) add("tbv shell", "tbv", [](SweepSetting& s) { s.options.tbvDiscretization = TbvDiscretization::Shell; });
        add("tbv filled", "tbv", [](SweepSetting& s) { s.options.tbvDiscretization = TbvDiscretization::Filled; });
    }
    add("tbv off", "tbv", [](SweepSetting& s) { s.options.temporalBoundingVolumes = false; });
    add("vfc (no occlusion)", "baseline", [](SweepSetting& s) {
        s.options.occlusion = false;
        s.options.occlusionBufferRows = 0;
        s.options.occlusionBufferBins = 0;
    });
    if (three) {
        for (const char* m : {"vfc", "sw", "chc", "chcpp"}) {
            if (quick && std::string(m) != "chcpp") continue;
            add(std::string("gl ") + m, "gl", [m](SweepSetting& s) { s.glMethod = m; });
        }
        for (std::uint64_t n : {1, 8, 32}) {
            if (quick && n != 8) continue;
            add("chcpp n_vp " + std::to_string(n), "nvp", [n](SweepSetting& s) {
                s.glMethod = "chcpp";
                s.visiblePixels = n;
            });
        }
    }
    if (quick) return v;
    // Combinations: the pairs a user tuning one scene would try next.
    if (three) {
        add("shells + voxel x2", "combo", [](SweepSetting& s) {
            s.options.hierarchical = false;
            s.voxelScale = 2;
        });
        add("image 128 + buffer 256 rows", "combo", [](SweepSetting& s) {
            s.options.traversalImageRows = 128;
            s.options.occlusionBufferRows = 256;
        });
        addVoxelCombo(2, "buffer 256 rows", [](SweepSetting& s) { s.options.occlusionBufferRows = 256; });
        addVoxelCombo(0.5, "gl chcpp", [](SweepSetting& s) { s.glMethod = "chcpp"; });
        addVoxelCombo(2, "gl chcpp", [](SweepSetting& s) { s.glMethod = "chcpp"; });
    } else {
        addVoxelCombo(2, "extension off", [](SweepSetting& s) { s.options.occluderExtension = false; });
        addVoxelCombo(0.5, "buffer 64 bins", [](SweepSetting& s) { s.options.occlusionBufferBins = 64; });
        addVoxelCombo(2, "buffer off", [](SweepSetting& s) { s.options.occlusionBufferBins = 0; });
    }
    addVoxelCombo(2, "tbv off", [](SweepSetting& s) { s.options.temporalBoundingVolumes = false; });
    return v;
}

std::string coreName(const SweepSetting& s, int dims) {
    if (!s.options.occlusion) return "vfc";
    if (dims == 2) return "wedge";
    if (s.options.hierarchical) return "bricks";
    return s.options.adaptiveCaps ? "shells" : "shells-caps-every-frame";
}

std::string bufferName(const SweepSetting& s, int dims) {
    const int n = dims == 3 ? s.options.occlusionBufferRows : s.options.occlusionBufferBins;
    if (!s.options.occlusion || n == 0) return "off";
    return std::to_string(n) + (dims == 3 ? " rows" : " bins") + (s.options.adaptiveBuffer ? " adaptive" : "");
}

std::string tbvName(const CullerOptions& o) {
    if (!o.temporalBoundingVolumes) return "off";
    switch (o.tbvDiscretization) {
    case TbvDiscretization::Boundary: return "boundary";
    case TbvDiscretization::Filled: return "filled";
    case TbvDiscretization::Shell: return "shell";
    }
    return "?";
}

} // namespace rgvc::bench
