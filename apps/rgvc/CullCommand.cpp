// `rgvc cull`: runs a scene file through the CPU visibility pipeline and prints one JSON line per frame
// (scene-format.md, "rgvc cull").
//
// Order of work, chosen so that bad input never leaves a partial answer on stdout: parse the command
// line, load and validate the scene, check that camera_path covers every frame, build the culler and add
// every object (the culler validates too); only then print frame 0. Frame t then does:
//   t > 0: advance the simulated motion one frame;
//   culler.cull(camera of frame t, placement query);  print the line.
// The motion reaches the culler through the TBV path of the library (Culler.hpp, "Dynamic scenes"): the
// culler asks the simulation for the placements it needs (last PVS, expired and revealed TBVs), so hidden
// moving objects are not re-inserted every frame. --no-tbv re-places every moving object every frame.
//
// Timing: stats.cull_ms is the library's work for the frame, as the contract defines it: the cull() call
// (CullStats::cullMs, measured inside the library), which includes the scene update (its part is printed
// as update_ms) and the placement queries it makes. Not included: file IO, stepping the simulated motion,
// building and printing the JSON. Frame 0 also reports setup_ms: building the culler and adding the
// objects, which is one-off work and so not part of any frame.
#include "Commands.hpp"
#include "GlStage.hpp"

#include "SceneFile.hpp"
#include "SceneMotion.hpp"
#include "rgvc/dynamics/Culler.hpp"
#include "rgvc/grid/OcclusionBuffer2D.hpp"
#include "rgvc/grid/OcclusionBuffer3D.hpp"
#include "rgvc/render/gl/GlError.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cstdint>
#include <iostream>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <string>
#include <unordered_set>
#include <vector>

namespace rgvc::cli {

namespace {

using ojson = nlohmann::ordered_json;
using Clock = std::chrono::steady_clock;

const char* const kCullUsage =
    "usage: rgvc cull SCENE.json [--frames N] [--dump-objects] [--no-occlusion] [--no-extension]\n"
    "                 [--no-tbv] [--filled-tbv] [--caps-every-frame] [--buffer-rows R] [--buffer-bins B]\n"
    "                 [--shells] [--image-rows R] [--image-every-frame] [--adaptive-buffer] [--gl] [--gl-method M]\n"
    "                 [--gl-size WxH] [--gl-nvp N] [--gl-tav F]\n"
    "\n"
    "Runs N frames of a scene file (the format is described in the project README) and prints one\n"
    "JSON object per frame on stdout:\n"
    "  {\"frame\": t, \"pvs\": [ids, ascending], \"stats\": {\"cull_ms\": ..., ...}}\n"
    "\n"
    "options:\n"
    "  --frames N       number of frames, 1 <= N <= 100000000 (default 1); with a camera_path, at most\n"
    "                   its length\n"
    "  --dump-objects   add \"objects\": [{\"id\": i, \"translation\": [dx, dy]}, ...] to every line: each\n"
    "                   object's translation from its frame-0 placement (ascending id)\n"
    "  --no-occlusion   view-frustum culling on the grid only (no occluders)\n"
    "  --no-extension   occlusion without occluder extension\n"
    "  --no-tbv         no temporal bounding volumes: every moving object re-placed every frame\n"
    "  --filled-tbv     TBVs written as filled regions instead of boundaries\n"
    "  --caps-every-frame  3D: grid caps on every frame (default: skipped while they do not pay)\n"
    "  --buffer-rows R  3D: rows of the occlusion buffer that refines the grid's PVS, 0..2048\n"
    "                   (default 64; 0 turns it off)\n"
    "  --buffer-bins B  2D: angular bins of the occlusion buffer that refines the grid's PVS, 0..4096\n"
    "                   (default 256; 0 turns it off)\n"
    "  --shells         3D: the paper's per-voxel shell traversal with cap polygons instead of the\n"
    "                   brick tree with its occlusion image (the default; README \"How it works\")\n"
    "  --image-rows R   3D brick tree: rows of its occlusion image, 0..2048 (default 0: 32 to 128, from the fov)\n"
    "  --image-every-frame  3D brick tree: its occlusion image on every frame (default: skipped for 1-8\n"
    "                   frames after it hid under an eighth of what the walk read, covered under 90 % of\n"
    "                   its pixels and met no mesh; stats.image_skipped)\n"
    "  --adaptive-buffer  skip the occlusion buffer's pass for 1-8 frames after it hid under a tenth of\n"
    "                   what it tested (stats.buffer_skipped)\n"
    "  --gl             3D: the GL occlusion-query stage after the CPU pipeline (headless, OSMesa): pvs is\n"
    "                   then the objects it draws (every object showing a pixel in an image of all objects\n"
    "                   at --gl-size); the CPU's PVS size goes to stats.cpu_pvs_size, the GL figures to\n"
    "                   stats.gl_*. Balls are drawn as icospheres of 1,280 triangles; the CPU culler then\n"
    "                   uses each ball shrunk to its mesh's inradius as its occluder (occluderInset)\n"
    "  --gl-method M    chcpp (default: CHC++), chc, sw (hierarchical stop-and-wait), vfc, zb\n"
    "  --gl-size WxH    [pixels] the GL stage's image, 1..16384 each (default 640x480)\n"
    "  --gl-nvp N       CHC's visible-pixel threshold n_vp (default 0; above 0 the answer is approximate:\n"
    "                   it may miss objects showing N pixels or fewer, and stats.gl_approximate says so)\n"
    "  --gl-tav F       CHC's assumed-visible frames t_av (default 0: visible leaves are queried every frame)\n"
    "  -h, --help       this text\n"
    "\n"
    "stats: cull_ms (library time of the frame, scene update included), update_ms (its scene-update\n"
    "part), cull_call_ms (= cull_ms), object_count, pvs_size, layers, voxels_visited, voxels_occluded,\n"
    "occluders_extended, occluder_voxels, shadows, voxels_marked_occluded, early_termination,\n"
    "occlusion_skipped, fallback, objects_outside_grid, placement_queries, tracked_objects,\n"
    "hidden_objects, tbvs_created, tbvs_renewed, tbvs_revealed, tbvs_refused, tbvs_held, camera_jump,\n"
    "speed_violations, grid_writes, tbv_lookups_skipped, caps_deferred, caps_from_shell, buffer_tested,\n"
    "buffer_hidden, buffer_ms, nodes_visited, nodes_empty, nodes_hidden, bricks_visited,\n"
    "image_hidden, image_skipped, tbv_image_tests, face_tbv_tests;\n"
    "frame 0 adds setup_ms.\n"
    "\n"
    "Exit status: 0 success; 2 bad input (one line \"FILE: FIELD: PROBLEM\" on stderr) or bad usage\n"
    "(one line \"rgvc cull: ...\"), and then nothing on stdout; 1 internal error.\n";

constexpr std::size_t kMaxFrames = 100000000;

struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct CullArgs {
    std::string scenePath;
    std::size_t frames = 1;
    bool dumpObjects = false;
    bool help = false;
    GlStageArgs gl;
    CullerOptions options; // the flags; objectsStayInGrid comes from the scene (sceneCullerOptions)
};

/// The value of integer flag `flag`: decimal digits only, in [lo, hi].
std::uint64_t parseInteger(const std::string& flag, const std::string& text, std::uint64_t lo, std::uint64_t hi) {
    std::uint64_t n = 0;
    const char* end = text.data() + text.size();
    auto [p, ec] = std::from_chars(text.data(), end, n);
    if (text.empty() || ec != std::errc() || p != end || n < lo || n > hi)
        throw UsageError(flag + ": must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got '" +
                         text + "'");
    return n;
}

std::size_t parseFrames(const std::string& text) { return std::size_t(parseInteger("--frames", text, 1, kMaxFrames)); }

CullArgs parseArgs(int argc, char** argv) {
    CullArgs a;
    bool optionsEnded = false;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (!optionsEnded && arg.size() > 1 && arg[0] == '-') {
            if (arg == "--") {
                optionsEnded = true;
            } else if (arg == "-h" || arg == "--help") {
                a.help = true;
            } else if (arg == "--frames") {
                if (i + 1 >= argc) throw UsageError("--frames: missing value");
                a.frames = parseFrames(argv[++i]);
            } else if (arg.rfind("--frames=", 0) == 0) {
                a.frames = parseFrames(arg.substr(9));
            } else if (arg == "--dump-objects") {
                a.dumpObjects = true;
            } else if (arg == "--no-occlusion") {
                a.options.occlusion = false;
            } else if (arg == "--no-extension") {
                a.options.occluderExtension = false;
            } else if (arg == "--no-tbv") {
                a.options.temporalBoundingVolumes = false;
            } else if (arg == "--filled-tbv") {
                a.options.tbvDiscretization = TbvDiscretization::Filled;
            } else if (arg == "--caps-every-frame") {
                a.options.adaptiveCaps = false;
            } else if (arg == "--buffer-rows") {
                if (i + 1 >= argc) throw UsageError("--buffer-rows: missing value");
                const auto rows = parseInteger("--buffer-rows", argv[++i], 0, OcclusionBuffer3D::kMaxExtent);
                a.options.occlusionBufferRows = int(rows);
            } else if (arg == "--buffer-bins") {
                if (i + 1 >= argc) throw UsageError("--buffer-bins: missing value");
                a.options.occlusionBufferBins = int(parseInteger("--buffer-bins", argv[++i], 0, OcclusionBuffer2D::kMaxBins));
            } else if (arg == "--shells") {
                a.options.hierarchical = false;
            } else if (arg == "--image-every-frame") {
                a.options.adaptiveImage = false;
            } else if (arg == "--adaptive-buffer") {
                a.options.adaptiveBuffer = true;
            } else if (arg == "--gl") {
                a.gl.enabled = true;
            } else if (arg == "--gl-method") {
                if (i + 1 >= argc) throw UsageError("--gl-method: missing value");
                a.gl.method = argv[++i];
                try {
                    GlStage::checkMethod(a.gl.method);
                } catch (const std::invalid_argument& e) {
                    throw UsageError(e.what());
                }
            } else if (arg == "--gl-nvp") {
                if (i + 1 >= argc) throw UsageError("--gl-nvp: missing value");
                a.gl.visiblePixels = parseInteger("--gl-nvp", argv[++i], 0, 1u << 30);
            } else if (arg == "--gl-tav") {
                if (i + 1 >= argc) throw UsageError("--gl-tav: missing value");
                a.gl.assumedVisibleFrames = int(parseInteger("--gl-tav", argv[++i], 0, 1000));
            } else if (arg == "--gl-size") {
                if (i + 1 >= argc) throw UsageError("--gl-size: missing value");
                const std::string v = argv[++i];
                const std::size_t x = v.find('x');
                if (x == std::string::npos) throw UsageError("--gl-size: must be WxH, e.g. 640x480, got '" + v + "'");
                a.gl.width = int(parseInteger("--gl-size width", v.substr(0, x), 1, 16384));
                a.gl.height = int(parseInteger("--gl-size height", v.substr(x + 1), 1, 16384));
            } else if (arg == "--image-rows") {
                if (i + 1 >= argc) throw UsageError("--image-rows: missing value");
                a.options.traversalImageRows = int(parseInteger("--image-rows", argv[++i], 0, OcclusionBuffer3D::kMaxExtent));
            } else {
                throw UsageError("unknown option '" + arg + "' (try `rgvc cull --help`)");
            }
        } else if (a.scenePath.empty()) {
            a.scenePath = arg;
        } else {
            throw UsageError("unexpected argument '" + arg + "': one scene file per run");
        }
    }
    if (!a.help && a.scenePath.empty()) throw UsageError("missing SCENE.json (try `rgvc cull --help`)");
    return a;
}

double msSince(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

ojson statsJson(const CullStats& s) {
    ojson j;
    j["cull_ms"] = s.cullMs;
    j["update_ms"] = s.updateMs;
    j["cull_call_ms"] = s.cullMs;
    j["object_count"] = s.objectCount;
    j["pvs_size"] = s.pvsSize;
    j["layers"] = s.layers;
    j["voxels_visited"] = s.voxelsVisited;
    j["voxels_occluded"] = s.voxelsOccluded;
    j["occluders_extended"] = s.occludersExtended;
    j["occluder_voxels"] = s.occluderVoxels;
    j["shadows"] = s.shadows;
    j["voxels_marked_occluded"] = s.voxelsMarkedOccluded;
    j["early_termination"] = s.earlyTermination;
    j["occlusion_skipped"] = s.occlusionSkipped;
    j["fallback"] = toString(s.fallback);
    j["objects_outside_grid"] = s.objectsOutsideGrid;
    j["caps_deferred"] = s.capsDeferred;
    j["caps_from_shell"] = s.capsFromShell;
    j["buffer_tested"] = s.bufferTested;
    j["buffer_hidden"] = s.bufferHidden;
    j["buffer_ms"] = s.bufferMs;
    j["buffer_skipped"] = s.bufferSkipped;
    j["nodes_visited"] = s.nodesVisited;
    j["nodes_empty"] = s.nodesEmpty;
    j["nodes_hidden"] = s.nodesHidden;
    j["bricks_visited"] = s.bricksVisited;
    j["image_hidden"] = s.imageHidden;
    j["tbv_image_tests"] = s.tbvImageTests;
    j["face_tbv_tests"] = s.faceTbvTests;
    j["image_skipped"] = s.imageSkipped;
    j["placement_queries"] = s.placementQueries;
    j["tracked_objects"] = s.trackedObjects;
    j["hidden_objects"] = s.hiddenObjects;
    j["tbvs_created"] = s.tbvsCreated;
    j["tbvs_renewed"] = s.tbvsRenewed;
    j["tbvs_revealed"] = s.tbvsRevealed;
    j["tbvs_refused"] = s.tbvsRefused;
    j["tbvs_held"] = s.tbvsHeld;
    j["camera_jump"] = s.cameraJump;
    j["speed_violations"] = s.speedViolations;
    j["grid_writes"] = s.gridWrites;
    j["tbv_lookups_skipped"] = s.tbvLookupsSkipped;
    return j;
}

// The culler validates what it is given as well; its InvalidInput names a field of its own API, so
// it is reported against the scene object it came from.
[[noreturn]] void rethrowAsScene(const Scene& scene, const std::string& field, const InvalidInput& e) {
    std::string what = e.what();
    if (field == e.field() && what.rfind(field + ": ", 0) == 0) what = what.substr(field.size() + 2);
    throw SceneError(scene.name, field, what);
}

template <int D> int runFrames(const Scene& scene, const SceneData<D>& data, const CullArgs& args) {
    // ---- Setup: everything that can reject the input happens before the first line is printed.
    const Clock::time_point setupStart = Clock::now();
    std::optional<Culler<D>> culler;
    try {
        CullerOptions options = args.options;
        options.objectsStayInGrid = motionStaysInGrid(data);
        culler.emplace(data.grid, options);
    } catch (const InvalidInput& e) {
        rethrowAsScene(scene, e.field(), e);
    } catch (const std::bad_alloc&) {
        throw SceneError(scene.name, "grid.resolution", "grid too large for the available memory");
    }
    // The GL stage (3D only) is made before any object is added: a context that cannot be made is a
    // one-line error before anything is printed.
    std::unique_ptr<GlStage> gl;
    if constexpr (D == 3)
        if (args.gl.enabled) gl = std::make_unique<GlStage>(args.gl);
    // Occludee-only objects (glass, foliage) hide nothing by the contract, but the GL stage writes depth for
    // what it draws: they are kept out of it (not drawn, so they hide nothing there either) and every one
    // of them in the CPU's PVS stays in the answer. Meshes too: the GL stage does not draw triangle meshes
    // (SceneRenderer), so they are never culled by it and hide nothing in its depth buffer; a closed
    // mesh's occlusion is the CPU's (its solid voxelization in O), which ran before.
    std::unordered_set<ObjectId> occludees;
    for (std::size_t i = 0; i < data.objects.size(); ++i) {
        try {
            ObjectDesc<D> desc = data.objects[i].desc();
            if constexpr (D == 3)
                if (gl) {
                    // The culler's occluder inside the drawn mesh (GlStage.hpp).
                    // (Not for a mesh, which GL does not draw: an inset would leave it no occluder at all.)
                    if (!std::holds_alternative<MeshSolid>(desc.shape)) desc.occluderInset = gl->occluderInset(desc.shape);
                    if (desc.role == ObjectRole::Occludee || std::holds_alternative<MeshSolid>(desc.shape)) occludees.insert(desc.id);
                    else gl->setObject(desc.id, desc.shape);
                }
            culler->addObject(desc);
        } catch (const InvalidInput& e) {
            rethrowAsScene(scene, "objects[" + std::to_string(i) + "]", e);
        }
    }
    const double setupMs = msSince(setupStart);

    SceneSimulator<D> sim(data);
    std::vector<std::size_t> byId(sim.size());
    std::iota(byId.begin(), byId.end(), std::size_t(0));
    std::sort(byId.begin(), byId.end(), [&](std::size_t a, std::size_t b) { return sim.idAt(a) < sim.idAt(b); });

    const PlacementQuery<D> placementOf = [&sim](ObjectId id) { return sim.shape(id); };
    for (std::size_t t = 0; t < args.frames; ++t) {
        if (t > 0) sim.step();
        const CullResult& r = culler->cull(data.cameraAt(t), placementOf);

        std::vector<ObjectId> pvs = r.pvs;
        // The contract's output is sorted and unique whatever the library hands back.
        if (!std::is_sorted(pvs.begin(), pvs.end()) || std::adjacent_find(pvs.begin(), pvs.end()) != pvs.end()) {
            std::sort(pvs.begin(), pvs.end());
            pvs.erase(std::unique(pvs.begin(), pvs.end()), pvs.end());
        }
        ojson stats = statsJson(r.stats);
        if constexpr (D == 3)
            if (gl) {
                if (t > 0)
                    for (std::size_t i = 0; i < sim.size(); ++i)
                        if (!occludees.count(sim.idAt(i))) gl->setObject(sim.idAt(i), sim.shapeAt(i));
                std::vector<ObjectId> drawable, kept;
                for (ObjectId id : pvs) (occludees.count(id) ? kept : drawable).push_back(id);
                const std::vector<ObjectId>& glPvs = gl->frame(data.cameraAt(t), drawable, stats);
                if (!kept.empty()) stats["gl_occludees_kept"] = kept.size();
                kept.insert(kept.end(), glPvs.begin(), glPvs.end());
                std::sort(kept.begin(), kept.end());
                pvs = std::move(kept);
            }
        ojson line;
        line["frame"] = t;
        line["pvs"] = pvs;
        line["stats"] = std::move(stats);
        if (t == 0) line["stats"]["setup_ms"] = setupMs;
        if (args.dumpObjects) {
            ojson objects = ojson::array();
            for (std::size_t i : byId) {
                const Vec<D>& tr = sim.translationAt(i);
                ojson tj = ojson::array();
                for (int a = 0; a < D; ++a) tj.push_back(tr[a]);
                objects.push_back(ojson{{"id", sim.idAt(i)}, {"translation", std::move(tj)}});
            }
            line["objects"] = std::move(objects);
        }
        // dump() writes doubles in shortest round-trip form, so a reader gets the exact translation back.
        std::cout << line.dump() << '\n';
    }
    std::cout.flush();
    if (!std::cout) {
        std::cerr << "rgvc cull: error writing to stdout\n";
        return 1;
    }
    return 0;
}

} // namespace

int runCull(int argc, char** argv) {
    CullArgs args;
    try {
        args = parseArgs(argc, argv);
    } catch (const UsageError& e) {
        std::cerr << "rgvc cull: " << e.what() << "\n";
        return 2;
    }
    if (args.help) {
        std::cout << kCullUsage;
        return 0;
    }
    try {
        Scene scene = loadScene(args.scenePath);
        requireFrames(scene, args.frames);
        if (args.gl.enabled && !GlStage::available()) {
            std::cerr << "rgvc cull: --gl: this rgvc was built without the GL stage (RGVC_WITH_GL=OFF)\n";
            return 2;
        }
        if (args.gl.enabled && scene.as<2>() != nullptr) {
            std::cerr << "rgvc cull: --gl: the GL stage renders 3D scenes; " << args.scenePath << " is 2D\n";
            return 2;
        }
        if (const SceneData<2>* s2 = scene.as<2>()) return runFrames<2>(scene, *s2, args);
        return runFrames<3>(scene, *scene.as<3>(), args);
    } catch (const SceneError& e) {
        std::cerr << e.what() << "\n";
        return 2;
    } catch (const GlError& e) {
        std::cerr << "rgvc cull: --gl: " << e.what() << "\n";
        return 2;
    }
}

} // namespace rgvc::cli
