// `rgvc demo [SCENE.json] [--out PATH.png] [--frames N] [--runs N] [--size PIXELS]`: culls a scene,
// prints a summary and writes a picture: for a 2D scene the grid in the style of the paper's Figure 1
// (rgvc::render), for a 3D scene a top view of the grid beside the view from the camera (Demo3D.cpp).
// With --frames N the scene's motion runs through the culler's TBV path first (as `rgvc cull` does), so the
// picture shows the TBV boundaries in T of the hidden moving objects.
//
// The default scene is RGVC_DEFAULT_SCENE (set by apps/CMakeLists.txt to the source tree's
// scenes/fig1-2d.json), else scenes/fig1-2d.json relative to the current directory.
#include "Demo3D.hpp"
#include "SceneFile.hpp"
#include "SceneMotion.hpp"

#include "rgvc/dynamics/Culler.hpp"
#include "rgvc/grid/Error.hpp"
#include "rgvc/render/GridPicture.hpp"
#include "rgvc/render/PngWriter.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace rgvc::cli {

int runDemo(int argc, char** argv);

namespace {

const char* const kDemoUsage =
    "usage: rgvc demo [SCENE.json] [--out PATH.png] [--frames N] [--runs N] [--size PIXELS]\n"
    "\n"
    "Culls a scene for its camera, prints a summary and writes a picture after the last cull.\n"
    "2D: the grid in the style of Figure 1 of the paper: opaque voxels dark gray, occluded light gray,\n"
    "visited pale yellow, extended occluders purple, TBV boundaries (T) teal, PVS objects blue, hidden\n"
    "objects red, view edges solid, line of sight dashed, camera a black dot.\n"
    "3D: left, a top view (x right, z down) of the grid's columns (any opaque voxel dark gray, T teal,\n"
    "read pale yellow, in view and hidden light gray) with the objects' footprints (PVS blue, culled\n"
    "red) and the camera; right, the view from the camera ray cast at pixel centres (PVS objects blue,\n"
    "culled ones red: a red pixel would be a miss, and the summary counts them).\n"
    "\n"
    "arguments:\n"
    "  SCENE.json      a 2D or 3D scene file (default: the repository's scenes/fig1-2d.json)\n"
    "  --out PATH.png  where to write the picture (default: rgvc-demo.png)\n"
    "  --frames N      run the scene's motion for N frames first (default: 1, just frame 0)\n"
    "  --runs N        cull the last frame N times and report the median time (default: 10)\n"
    "  --size PIXELS   about the longer side of the grid in the picture (default: 1024)\n"
    "  -h, --help      this text\n"
    "\n"
    "Exit status: 0 success, 2 bad input or usage, or the picture cannot be written (one line on stderr).\n";

/// Bad usage or input: reported as one line, exit status 2.
struct DemoError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

bool fileExists(const std::string& path) {
    std::error_code ec;
    return std::filesystem::is_regular_file(path, ec);
}

std::string defaultScene() {
    std::vector<std::string> tried;
#ifdef RGVC_DEFAULT_SCENE
    if (fileExists(RGVC_DEFAULT_SCENE)) return RGVC_DEFAULT_SCENE;
    tried.push_back(RGVC_DEFAULT_SCENE);
#endif
    const std::string local = "scenes/fig1-2d.json";
    if (fileExists(local)) return local;
    tried.push_back(local);
    std::string msg = "no scene given and the default scene was not found (looked at";
    for (std::size_t i = 0; i < tried.size(); ++i) msg += (i ? ", " : " ") + tried[i];
    throw DemoError(msg + ")");
}

long parseCount(const std::string& option, const char* text, long lo, long hi) {
    std::string s = text;
    std::size_t used = 0;
    long v = 0;
    try {
        v = std::stol(s, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != s.size() || s.empty() || v < lo || v > hi)
        throw DemoError(option + ": expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                        "], got '" + s + "'");
    return v;
}

std::string fmt(double v) {
    std::ostringstream os;
    os << v;
    return os.str();
}

std::string fmt(const Vec2& v) {
    std::ostringstream os;
    os << '(' << v.x << ", " << v.y << ')';
    return os.str();
}

struct DemoArgs {
    std::string scene;
    std::string out = "rgvc-demo.png";
    long runs = 10;
    long frames = 1;
    long size = 1024;
    bool help = false;
};

DemoArgs parseArgs(int argc, char** argv) {
    DemoArgs a;
    bool haveScene = false;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        auto value = [&]() -> const char* {
            if (i + 1 >= argc) throw DemoError(arg + ": missing value");
            return argv[++i];
        };
        if (arg == "-h" || arg == "--help") {
            a.help = true;
        } else if (arg == "--out") {
            a.out = value();
            if (a.out.empty()) throw DemoError("--out: empty path");
        } else if (arg == "--frames") {
            a.frames = parseCount(arg, value(), 1, 1000000);
        } else if (arg == "--runs") {
            a.runs = parseCount(arg, value(), 1, 1000000);
        } else if (arg == "--size") {
            a.size = parseCount(arg, value(), 16, 8192);
        } else if (arg.size() > 1 && arg[0] == '-') {
            throw DemoError("unknown option '" + arg + "' (try `rgvc demo --help`)");
        } else {
            if (haveScene) throw DemoError("more than one scene file given ('" + a.scene + "', '" + arg + "')");
            a.scene = arg;
            haveScene = true;
        }
    }
    return a;
}

double medianOf(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string fmt(const Vec3& v) {
    std::ostringstream os;
    os << '(' << v.x << ", " << v.y << ", " << v.z << ')';
    return os.str();
}

/// The 3D demo: the scene's motion through the culler's TBV path, the last frame culled `runs` times,
/// the two-panel picture (Demo3D.hpp) and a summary that counts the picture's pixels showing a culled object.
int demo3D(const DemoArgs& args, const std::string& scenePath, const Scene& scene) {
    const SceneData3& data = *scene.as<3>();
    requireFrames(scene, std::size_t(args.frames));
    const std::size_t lastFrame = std::size_t(args.frames) - 1;
    const Camera3 camera = data.cameraAt(lastFrame);
    Culler3D culler(data.grid, sceneCullerOptions(data));
    std::vector<ObjectDesc<3>> objects;
    objects.reserve(data.objects.size());
    for (const SceneObject<3>& o : data.objects) {
        objects.push_back(o.desc());
        culler.addObject(objects.back());
    }
    SceneSimulator3 sim(data);
    const PlacementQuery<3> placementOf = [&sim](ObjectId id) { return sim.shape(id); };
    for (std::size_t t = 0; t < lastFrame; ++t) {
        culler.cull(data.cameraAt(t), placementOf);
        sim.step();
    }
    for (std::size_t i = 0; i < objects.size(); ++i) objects[i].shape = sim.shapeAt(i);
    std::vector<double> timesMs;
    for (long run = 0; run < args.runs; ++run) {
        const auto t0 = std::chrono::steady_clock::now();
        culler.cull(camera, placementOf);
        timesMs.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    const CullResult& r = culler.lastResult();
    const CullStats& s = r.stats;
    const GridGeometry3& g = data.grid;
    const std::string caption = std::filesystem::path(scenePath).filename().string() + "   grid " +
                                std::to_string(g.resolution().x) + " x " + std::to_string(g.resolution().y) + " x " +
                                std::to_string(g.resolution().z) + "   " + std::to_string(objects.size()) +
                                " objects   |PVS| " + std::to_string(r.pvs.size()) +
                                (lastFrame > 0 ? "   frame " + std::to_string(lastFrame) : "");
    const Demo3DResult pic = drawDemo3D(culler, camera, objects, int(std::max<long>(args.size, 128)), caption);
    try {
        writePng(args.out, pic.image);
    } catch (const std::runtime_error& e) {
        throw DemoError(std::string("cannot write the picture: ") + e.what());
    }
    std::ostringstream os;
    os << "scene:    " << scenePath << "\n";
    os << "grid:     " << g.resolution().x << " x " << g.resolution().y << " x " << g.resolution().z << " voxels of "
       << fmt(g.voxelSize()) << ", origin " << fmt(g.origin()) << "\n";
    os << "camera:   position " << fmt(camera.position) << ", direction " << fmt(camera.direction) << ", fov "
       << fmt(camera.fovDeg) << " deg, aspect " << fmt(camera.aspect) << "\n";
    os << "objects:  " << objects.size() << "\n";
    os << "|PVS|:    " << r.pvs.size() << "\n";
    os << "stats:    nodes visited " << s.nodesVisited << " (empty " << s.nodesEmpty << ", hidden " << s.nodesHidden
       << "), bricks read " << s.bricksVisited << ", voxels read " << s.voxelsVisited << ", objects the image hid "
       << s.imageHidden << ", fallback " << toString(s.fallback) << "\n";
    os << "dynamics: frame " << lastFrame << ", hidden by TBVs " << s.hiddenObjects << ", TBVs revealed "
       << s.tbvsRevealed << "\n";
    os << "cull:     median " << fmt(medianOf(timesMs)) << " ms over " << timesMs.size() << " runs\n";
    os << "view:     " << pic.pixelsCovered << " pixels show an object; " << pic.pixelsShownButCulled
       << " show one the culler left out (must be 0)\n";
    std::error_code ec;
    std::filesystem::path abs = std::filesystem::absolute(args.out, ec);
    os << "picture:  " << (ec ? args.out : abs.string()) << " (" << pic.image.width() << " x " << pic.image.height()
       << " pixels)\n";
    std::cout << os.str();
    return pic.pixelsShownButCulled == 0 ? 0 : 1;
}

int demo(const DemoArgs& args) {
    const std::string scenePath = args.scene.empty() ? defaultScene() : args.scene;
    const Scene scene = loadScene(scenePath);
    if (scene.as<3>() != nullptr) return demo3D(args, scenePath, scene);
    const SceneData2* data = scene.as<2>();

    requireFrames(scene, std::size_t(args.frames));
    const std::size_t lastFrame = std::size_t(args.frames) - 1;
    const Camera2 camera = data->cameraAt(lastFrame);
    Culler2D culler(data->grid, sceneCullerOptions(*data));
    std::vector<ObjectDesc<2>> objects;
    objects.reserve(data->objects.size());
    std::size_t staticCount = 0;
    for (const SceneObject<2>& o : data->objects) {
        objects.push_back(o.desc());
        culler.addObject(objects.back());
        staticCount += o.isStatic ? 1 : 0;
    }
    // The motion reaches the culler through its placement queries (the TBV path).
    SceneSimulator2 sim(*data);
    const PlacementQuery<2> placementOf = [&sim](ObjectId id) { return sim.shape(id); };
    for (std::size_t t = 0; t < lastFrame; ++t) {
        culler.cull(data->cameraAt(t), placementOf);
        sim.step();
    }
    for (std::size_t i = 0; i < objects.size(); ++i) objects[i].shape = sim.shapeAt(i);

    std::vector<double> timesMs;
    timesMs.reserve(std::size_t(args.runs));
    for (long run = 0; run < args.runs; ++run) {
        const auto t0 = std::chrono::steady_clock::now();
        culler.cull(camera, placementOf);
        const auto t1 = std::chrono::steady_clock::now();
        timesMs.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    }
    const double firstMs = timesMs.front();
    std::vector<double> sorted = timesMs;
    std::sort(sorted.begin(), sorted.end());
    const std::size_t n = sorted.size();
    const double medianMs = n % 2 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);

    const CullResult& r = culler.lastResult();
    const CullStats& s = r.stats;
    const GridGeometry2& g = data->grid;

    GridPictureOptions opt;
    opt.maxPixels = int(args.size);
    opt.caption = std::filesystem::path(scenePath).filename().string() + "   grid " +
                  std::to_string(g.resolution().x) + " x " + std::to_string(g.resolution().y) + "   " +
                  std::to_string(objects.size()) + " objects   camera " + fmt(camera.position) + " fov " +
                  fmt(camera.fovDeg) + (lastFrame > 0 ? "   frame " + std::to_string(lastFrame) : "");
    const ImageRGB img = drawGridPicture(culler, camera, objects, opt);
    try {
        writePng(args.out, img);
    } catch (const std::runtime_error& e) {
        throw DemoError(std::string("cannot write the picture: ") + e.what());
    }

    std::ostringstream os;
    os << "scene:    " << scenePath << "\n";
    os << "grid:     " << g.resolution().x << " x " << g.resolution().y << " voxels of " << fmt(g.voxelSize())
       << ", origin " << fmt(g.origin()) << "\n";
    os << "camera:   position " << fmt(camera.position) << ", direction " << fmt(camera.direction) << ", fov "
       << fmt(camera.fovDeg) << " deg, far " << fmt(camera.far) << "\n";
    os << "objects:  " << objects.size() << " (" << staticCount << " static, " << objects.size() - staticCount
       << " dynamic)\n";
    os << "|PVS|:    " << r.pvs.size() << "\n";
    os << "PVS ids: ";
    const std::size_t shown = std::min<std::size_t>(r.pvs.size(), 200);
    for (std::size_t i = 0; i < shown; ++i) os << ' ' << r.pvs[i];
    if (shown < r.pvs.size()) os << " ... (" << r.pvs.size() - shown << " more)";
    if (r.pvs.empty()) os << " (none)";
    os << "\n";
    os << "stats:    layers " << s.layers << ", voxels visited " << s.voxelsVisited << ", occluded "
       << s.voxelsOccluded << ", occluders extended " << s.occludersExtended << ", occluder voxels "
       << s.occluderVoxels << ", shadows " << s.shadows << ", voxels marked occluded " << s.voxelsMarkedOccluded
       << "\n";
    os << "          early termination " << (s.earlyTermination ? "yes" : "no") << ", occlusion skipped "
       << (s.occlusionSkipped ? "yes" : "no") << ", fallback " << toString(s.fallback)
       << ", objects outside the grid " << s.objectsOutsideGrid << "\n";
    os << "dynamics: frame " << lastFrame << ", objects in O and I " << s.trackedObjects << " moving + " << staticCount
       << " static, hidden by TBVs " << s.hiddenObjects << ", placements asked " << s.placementQueries
       << ", TBVs revealed " << s.tbvsRevealed << "\n";
    os << "cull:     median " << fmt(medianMs) << " ms over " << n << " run" << (n == 1 ? "" : "s") << " (first "
       << fmt(firstMs) << " ms)\n";
    std::error_code ec;
    std::filesystem::path abs = std::filesystem::absolute(args.out, ec);
    os << "picture:  " << (ec ? args.out : abs.string()) << " (" << img.width() << " x " << img.height()
       << " pixels)\n";
    std::cout << os.str();
    return 0;
}

/// One line, whatever the message holds.
std::string oneLine(std::string s) {
    for (char& c : s)
        if (c == '\n' || c == '\r') c = ' ';
    return s;
}

} // namespace

int runDemo(int argc, char** argv) {
    try {
        const DemoArgs args = parseArgs(argc, argv);
        if (args.help) {
            std::cout << kDemoUsage;
            return 0;
        }
        return demo(args);
    } catch (const DemoError& e) {
        std::cerr << "rgvc demo: " << oneLine(e.what()) << "\n";
    } catch (const SceneError& e) {
        std::cerr << "rgvc demo: " << oneLine(e.what()) << "\n";
    } catch (const InvalidInput& e) {
        std::cerr << "rgvc demo: " << oneLine(e.what()) << "\n";
    }
    return 2;
}

} // namespace rgvc::cli
