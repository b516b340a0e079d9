#include "SimCli.hpp"

#include "WorldGenerators.hpp"

#include "rgvc/grid/Error.hpp"
#include "rgvc/render/PngWriter.hpp"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

namespace rgvc::sim {

const char* const kUsage =
    "usage: rgvc_sim2d [SCENE.json | --generate KIND:N] [options]\n"
    "\n"
    "A 2D top view of a world culled by rgvc: the viewer's wedge, the grid's layers (seed 004 Figure 1)\n"
    "and the frame's stats. In a window by default; --headless renders through OSMesa into PNG files.\n"
    "\n"
    "world:\n"
    "  SCENE.json          a 2D scene file (scene-format.md; its camera is where the viewer starts)\n"
    "  --generate KIND:N   city:N, maze:N or field:N: N moving circles and boxes in 256 x 256\n"
    "  --seed S            generator seed (default 1)\n"
    "view:\n"
    "  --size PIXELS       side of the square map (default 512); the panel adds 250 pixels on the right\n"
    "  --layers LIST       layers on at start: all (default), none, or a comma list of\n"
    "                      o,os,h,i,t,view,visited,occluders,pvs,hidden\n"
    "  --spawn SHAPE       what a click spawns first: circle (default), box, polygon\n"
    "  --paused            start with the world's motion paused\n"
    "  --no-panel          start with the panel hidden (tab shows it)\n"
    "  --speed UNITS       viewer speed per frame (default: half a voxel)\n"
    "run:\n"
    "  --headless          no window: OSMesa, writes PNG frames\n"
    "  --frames N          frames to run (headless default 300; window: until closed)\n"
    "  --png-every K       write every K-th frame as DIR/frame-NNNNNN.png (headless default: the last)\n"
    "  --out DIR           folder of the PNG frames (headless default sim2d-frames)\n"
    "  --script FILE       scripted input: 'FRAME key|hold|mouse|click|press|release|look|wheel|quit ...'\n"
    "  -h, --help          this text\n"
    "\n"
    "keys: W S / Up Down move, A D strafe, Left Right / Q E turn, right drag mouse look, wheel fov,\n"
    "click spawn / grab, drag move, C B P shape, Space pause, N step, 1-9 0 layers, R reset, Tab panel,\n"
    "Esc quit. Exit status: 0 done, 2 bad input (one line on stderr).\n";

namespace {

long parseInteger(const std::string& option, const std::string& text, long lo, long hi) {
    std::size_t used = 0;
    long v = 0;
    try {
        v = std::stol(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (text.empty() || used != text.size() || v < lo || v > hi)
        throw UsageError(option + ": expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got '" +
                         text + "'");
    return v;
}

double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// The window's input: key presses from the callback, the rest polled each frame.
struct LiveInput {
    std::vector<Key> pressed;
    double wheel = 0;
    bool leftPressed = false, leftReleased = false;
    bool haveLast = false;
    double lastX = 0;
};

std::optional<Key> fromGlfw(int key) {
    if (key >= GLFW_KEY_A && key <= GLFW_KEY_Z) return Key(key - GLFW_KEY_A);
    if (key >= GLFW_KEY_0 && key <= GLFW_KEY_9) return digitKey(key - GLFW_KEY_0);
    switch (key) {
    case GLFW_KEY_SPACE: return Key::Space;
    case GLFW_KEY_TAB: return Key::Tab;
    case GLFW_KEY_ESCAPE: return Key::Escape;
    case GLFW_KEY_LEFT: return Key::Left;
    case GLFW_KEY_RIGHT: return Key::Right;
    case GLFW_KEY_UP: return Key::Up;
    case GLFW_KEY_DOWN: return Key::Down;
    default: return std::nullopt;
    }
}

int toGlfw(Key k) {
    const int i = int(k);
    if (i < 26) return GLFW_KEY_A + i;
    if (i < 36) return GLFW_KEY_0 + i - 26;
    const int named[] = {GLFW_KEY_SPACE, GLFW_KEY_TAB, GLFW_KEY_ESCAPE, GLFW_KEY_LEFT, GLFW_KEY_RIGHT, GLFW_KEY_UP, GLFW_KEY_DOWN};
    return named[i - 36];
}

LiveInput& live(GLFWwindow* w) { return *static_cast<LiveInput*>(glfwGetWindowUserPointer(w)); }

InputFrame pollWindow(GLFWwindow* window) {
    LiveInput& l = live(window);
    l.pressed.clear();
    l.wheel = 0;
    l.leftPressed = l.leftReleased = false;
    glfwPollEvents();
    InputFrame f;
    f.pressed = l.pressed;
    for (int i = 0; i < kKeyCount; ++i) f.down[std::size_t(i)] = glfwGetKey(window, toGlfw(Key(i))) == GLFW_PRESS;
    double x = 0, y = 0;
    glfwGetCursorPos(window, &x, &y);
    f.mouse = Vec2(x, y);
    f.leftDown = glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
    f.leftPressed = l.leftPressed;
    f.leftReleased = l.leftReleased;
    // Mouse look: horizontal motion while the right button is held.
    const bool looking = glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
    if (looking && l.haveLast) f.lookDx = x - l.lastX;
    l.haveLast = looking;
    l.lastX = x;
    f.wheel = l.wheel;
    f.quit = glfwWindowShouldClose(window);
    return f;
}

} // namespace

SimOptions parseSimOptions(int argc, char** argv) {
    SimOptions o;
    bool haveScene = false;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) throw UsageError(arg + ": missing value");
            return argv[++i];
        };
        if (arg == "-h" || arg == "--help") o.help = true;
        else if (arg == "--generate") o.generate = value();
        else if (arg == "--seed") o.seed = std::uint64_t(parseInteger(arg, value(), 0, 2147483647));
        else if (arg == "--size") o.settings.mapSize = int(parseInteger(arg, value(), 16, 8192));
        else if (arg == "--layers") {
            try {
                o.settings.layers = Layers::parse(value());
            } catch (const InvalidInput& e) {
                throw UsageError(e.what());
            }
        } else if (arg == "--spawn") {
            const std::string s = value();
            if (s == "circle") o.settings.spawn = SpawnKind::Circle;
            else if (s == "box") o.settings.spawn = SpawnKind::Box;
            else if (s == "polygon") o.settings.spawn = SpawnKind::Polygon;
            else throw UsageError("--spawn: expected circle, box or polygon, got '" + s + "'");
        } else if (arg == "--paused") o.settings.paused = true;
        else if (arg == "--no-panel") o.settings.panel = false;
        else if (arg == "--speed") {
            const std::string s = value();
            std::size_t used = 0;
            double v = 0;
            try {
                v = std::stod(s, &used);
            } catch (const std::exception&) {
                used = 0;
            }
            if (used != s.size() || !(v > 0) || !std::isfinite(v) || v > 1e6)
                throw UsageError("--speed: expected a positive number, got '" + s + "'");
            o.settings.speed = v;
        } else if (arg == "--headless") o.headless = true;
        else if (arg == "--frames") o.frames = parseInteger(arg, value(), 1, 100000000);
        else if (arg == "--png-every") o.pngEvery = parseInteger(arg, value(), 1, 100000000);
        else if (arg == "--out") {
            o.out = value();
            if (o.out.empty()) throw UsageError("--out: empty path");
        } else if (arg == "--script") o.script = value();
        else if (arg.size() > 1 && arg[0] == '-') throw UsageError("unknown option '" + arg + "' (try --help)");
        else {
            if (haveScene) throw UsageError("more than one scene file given ('" + o.scene + "', '" + arg + "')");
            o.scene = arg;
            haveScene = true;
        }
    }
    if (!o.help && o.scene.empty() == o.generate.empty())
        throw UsageError(o.scene.empty() ? "no world: give a SCENE.json or --generate KIND:N (try --help)"
                                         : "give either a scene file or --generate, not both");
    return o;
}

SimWorld loadWorld(const SimOptions& options) {
    if (!options.generate.empty()) return generateWorld(parseGeneratorSpec(options.generate), options.seed);
    const Scene scene = loadScene(options.scene);
    const SceneData2* data = scene.as<2>();
    if (!data)
        throw UsageError(options.scene + ": the simulator shows 2D scenes only (this one has " +
                         std::to_string(scene.dimensions) + " dimensions)");
    return SimWorld::fromScene(std::filesystem::path(options.scene).filename().string(), *data);
}

int runSim(const SimOptions& options) {
    SimWorld world = loadWorld(options);
    std::optional<InputScript> script;
    if (!options.script.empty()) script = InputScript::load(options.script);
    const long frames = options.frames > 0 ? options.frames : options.headless ? 300 : -1;
    const std::string out = !options.out.empty() ? options.out : options.headless ? "sim2d-frames" : "";
    const long every = options.pngEvery > 0 ? options.pngEvery : frames > 0 ? frames : 0;
    if (!out.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(out, ec);
        if (ec) throw UsageError("--out: cannot create '" + out + "': " + ec.message());
    }

    const int height = options.settings.mapSize, width = SimApp::windowWidth(height);
    std::unique_ptr<GlContext> context =
        options.headless ? createOsMesaContext(width, height)
                         : createGlfwContext(width, height, {.visible = true, .title = "rgvc_sim2d: " + world.name()});
    GLFWwindow* window = options.headless ? nullptr : glfwGetCurrentContext(); // the context's window
    LiveInput liveInput;
    if (window) {
        glfwSetWindowUserPointer(window, &liveInput);
        glfwSetKeyCallback(window, [](GLFWwindow* w, int key, int, int action, int) {
            if (action != GLFW_PRESS) return;
            if (const std::optional<Key> k = fromGlfw(key)) live(w).pressed.push_back(*k);
        });
        glfwSetScrollCallback(window, [](GLFWwindow* w, double, double dy) { live(w).wheel += dy; });
        glfwSetMouseButtonCallback(window, [](GLFWwindow* w, int button, int action, int) {
            if (button != GLFW_MOUSE_BUTTON_LEFT) return;
            (action == GLFW_PRESS ? live(w).leftPressed : live(w).leftReleased) = true;
        });
    }

    std::string name = world.name();
    SimApp app(*context, std::move(world), options.settings);
    std::vector<double> frameMs, cullMs;
    std::size_t written = 0;
    long f = 0;
    const auto runStart = std::chrono::steady_clock::now();
    for (; frames < 0 || f < frames; ++f) {
        InputFrame in;
        if (window) in = pollWindow(window);
        if (script) in.merge(script->next(std::size_t(f)));
        const auto t0 = std::chrono::steady_clock::now();
        app.frame(in);
        context->gl().Finish(); // the frame's time includes drawing it
        frameMs.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        cullMs.push_back(app.stats().cull.cullMs);
        if (!out.empty() && every > 0 && (f + 1) % every == 0) {
            char file[32];
            std::snprintf(file, sizeof file, "frame-%06ld.png", f);
            writePng((std::filesystem::path(out) / file).string(), app.readImage());
            ++written;
        }
        if (window) context->swapBuffers();
        if (app.quitRequested()) {
            ++f;
            break;
        }
    }
    const double wallS = std::chrono::duration<double>(std::chrono::steady_clock::now() - runStart).count();
    const double medFrame = median(frameMs);
    std::printf("rgvc_sim2d: %s, %ld frames %s (%s), %zu objects at the end, |PVS| %u\n", name.c_str(), f,
                options.headless ? "headless" : "in a window", context->description().c_str(), app.world().objects().size(),
                app.stats().cull.pvsSize);
    std::printf("frame (cull + draw + finish): median %.3f ms = %.1f fps; cull median %.3f ms; loop %.1f fps with PNG writes\n",
                medFrame, medFrame > 0 ? 1000.0 / medFrame : 0.0, median(cullMs), wallS > 0 ? double(f) / wallS : 0.0);
    if (written > 0) std::printf("wrote %zu PNG frame%s to %s\n", written, written == 1 ? "" : "s", out.c_str());
    return 0;
}

} // namespace rgvc::sim
