// rgvc_sim2d (apps/sim2d): the simulator run headless through OSMesa with scripted input, its picture
// read back and checked against the culler's state pixel by pixel; the same under Xvfb in a GLFW window
// ([sim-window], run by its own ctest entry through xvfb-run); the script parser, the generators, and
// the command line's bad input (exit 2, one line).
#include "GlTestSupport.hpp"

#include "SimApp.hpp"
#include "SimCli.hpp"
#include "SimInput.hpp"
#include "WorldGenerators.hpp"
#include "ExactVisibility2D.hpp"

#include "rgvc/grid/Error.hpp"
#include "rgvc/render/gl/GlContext.hpp"

#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

using namespace rgvc;
using namespace rgvc::sim;
namespace fs = std::filesystem;

namespace {

constexpr int kMap = 512;

/// The fill of an object over an empty cell: picture colour `c` blended at kObjectAlpha over white.
RGB8 fillOverEmpty(RGB8 c) { return blendColor(picture::kEmpty, c, std::lround(palette::kObjectAlpha * 255) / 255.0); }

bool near(RGB8 a, RGB8 b, int tol = 3) {
    return std::abs(a.r - b.r) <= tol && std::abs(a.g - b.g) <= tol && std::abs(a.b - b.b) <= tol;
}

/// Whether a pixel centre lies in `s` or within one pixel of it (the circles are drawn tessellated, with
/// at most 0.3 pixels of error; the pixel grid rounds by up to half a pixel).
bool nearShape(const Shape<2>& s, const MapTransform& map, const Vec2& pixelCentre) {
    const Box<2> b = boundsOf<2>(s);
    const Vec2 w = map.toWorld(pixelCentre);
    const double slack = 1.0 / map.scale;
    if (w.x < b.min.x - slack || w.x > b.max.x + slack || w.y < b.min.y - slack || w.y > b.max.y + slack) return false;
    for (const Vec2& d : {Vec2(0, 0), Vec2(1, 0), Vec2(-1, 0), Vec2(0, 1), Vec2(0, -1)})
        if (shapeContains(s, map.toWorld(pixelCentre + d))) return true;
    return false;
}

struct PictureCheck {
    int pvsPixels = 0, hiddenPixels = 0;      ///< pixels of either colour on the map
    int strayPvs = 0, strayHidden = 0;        ///< of those, not on an object of that kind
    int pvsObjectsChecked = 0, hiddenObjectsChecked = 0;
    int wrongObjects = 0;                     ///< objects whose own centre pixel shows the other colour
};

/// With only the PVS and hidden layers on (cells white): every pixel of the PVS colour lies on a PVS
/// object and every pixel of the hidden colour on a hidden one, and each object whose centre pixel it
/// alone covers shows its own colour there.
PictureCheck checkPicture(const SimApp& app, const ImageRGB& img) {
    const RGB8 pvs = fillOverEmpty(picture::kPvs), hidden = fillOverEmpty(picture::kHidden);
    const std::vector<SimObject>& objects = app.world().objects();
    std::vector<Shape<2>> shapes;
    for (const SimObject& o : objects) shapes.push_back(o.shape());
    PictureCheck c;
    const Box<2> g = app.world().bounds();
    for (int y = 0; y < kMap; ++y)
        for (int x = 0; x < kMap; ++x) {
            const RGB8 p = img.at(x, y);
            const bool isPvs = near(p, pvs), isHidden = near(p, hidden);
            if (!isPvs && !isHidden) continue;
            const Vec2 centre(x + 0.5, y + 0.5);
            bool onKind = false;
            for (std::size_t i = 0; i < objects.size() && !onKind; ++i)
                onKind = app.inPvs(i) == isPvs && nearShape(shapes[i], app.map(), centre);
            (isPvs ? c.pvsPixels : c.hiddenPixels) += 1;
            if (!onKind) (isPvs ? c.strayPvs : c.strayHidden) += 1;
        }
    for (std::size_t i = 0; i < objects.size(); ++i) {
        const Box<2> b = boundsOf<2>(shapes[i]);
        const Vec2 centreWorld = 0.5 * (b.min + b.max);
        if (centreWorld.x < g.min.x || centreWorld.y < g.min.y || centreWorld.x >= g.max.x || centreWorld.y >= g.max.y) continue;
        const Vec2 px = glm::floor(app.map().toWindow(centreWorld));
        const Vec2 pc = px + 0.5;
        int covering = 0;
        for (std::size_t j = 0; j < objects.size(); ++j) covering += nearShape(shapes[j], app.map(), pc) ? 1 : 0;
        if (covering != 1 || !shapeContains(shapes[i], app.map().toWorld(pc))) continue;
        const RGB8 p = img.at(int(px.x), int(px.y));
        const bool ok = near(p, app.inPvs(i) ? pvs : hidden);
        (app.inPvs(i) ? c.pvsObjectsChecked : c.hiddenObjectsChecked) += 1;
        if (!ok) {
            ++c.wrongObjects;
            UNSCOPED_INFO("object " << objects[i].id << (app.inPvs(i) ? " (PVS)" : " (hidden)") << " at pixel (" << px.x
                                    << ", " << px.y << ") shows " << p);
        }
    }
    return c;
}

void requireExact(const PictureCheck& c) {
    INFO("PVS pixels " << c.pvsPixels << ", hidden pixels " << c.hiddenPixels << ", objects checked " << c.pvsObjectsChecked
                       << " PVS + " << c.hiddenObjectsChecked << " hidden");
    CHECK(c.strayPvs == 0);
    CHECK(c.strayHidden == 0);
    CHECK(c.wrongObjects == 0);
    // Not vacuous: both kinds are on the picture and checked object by object.
    CHECK(c.pvsPixels > 50);
    CHECK(c.hiddenPixels > 1000);
    CHECK(c.pvsObjectsChecked >= 2);
    CHECK(c.hiddenObjectsChecked >= 50);
}

/// The scripted walk of the tests: forward 20 frames (10 units), a box spawned on an empty street
/// spot ahead of the viewer at frame 22, then frames to 30.
const char* const kWalkScript = R"(# the tests' walk
0  key b            # click spawns boxes
0  hold w 20        # forward, 0.5 units a frame
22 click 180 257    # world (90, 128.5): the street the viewer walks along
)";

/// Runs the walk on `ctx` and checks what the tests check; `mapSize` must be kMap.
void runWalkAndCheck(GlContext& ctx, bool swap) {
    const SimWorld world = generateWorld(parseGeneratorSpec("city:300"), 1);
    const std::size_t before = world.objects().size();
    const Camera2 start = world.startCamera();
    SimSettings settings;
    settings.layers = Layers::parse("pvs,hidden");
    SimApp app(ctx, world, settings);
    InputScript script = InputScript::parse(kWalkScript, "walk");
    for (std::size_t f = 0; f < 30; ++f) {
        app.frame(script.next(f));
        if (swap) ctx.swapBuffers();
    }
    ctx.gl().Finish();
    INFO("seed 1, city:300");
    // The viewer moved 20 half-unit steps along its heading.
    const Vec2 moved = app.camera().position - start.position;
    CHECK(glm::length(moved) == Approx(10.0).margin(1e-9));
    CHECK(glm::dot(moved, glm::normalize(start.direction)) == Approx(10.0).margin(1e-9));
    // The click spawned one box where it was.
    REQUIRE(app.world().objects().size() == before + 1);
    CHECK(app.spawnKind() == SpawnKind::Box);
    const SimObject& spawned = app.world().objects().back();
    REQUIRE(std::holds_alternative<Box<2>>(spawned.shape()));
    const Box<2> b = std::get<Box<2>>(spawned.shape());
    const Vec2 clicked = app.map().toWorld({180, 257});
    CHECK(0.5 * (b.min.x + b.max.x) == Approx(clicked.x));
    CHECK(0.5 * (b.min.y + b.max.y) == Approx(clicked.y));
    CHECK(app.culler().hasObject(spawned.id));
    // Drawn in the colour of the culler's verdict, which holds it when it is exactly visible.
    const std::size_t last = app.world().objects().size() - 1;
    std::vector<Shape<2>> shapes;
    for (const SimObject& o : app.world().objects()) shapes.push_back(o.shape());
    if (reference::exactVisible2D(shapes, app.camera())[last]) CHECK(app.inPvs(last));
    const ImageRGB img = app.readImage();
    CHECK(near(img.at(180, 257), fillOverEmpty(app.inPvs(last) ? picture::kPvs : picture::kHidden)));
    requireExact(checkPicture(app, img));

    // The view layer on: the camera dot is drawn where the viewer now is, not where it started.
    InputFrame toggleView;
    toggleView.pressed = {digitKey(6)};
    app.frame(toggleView);
    ctx.gl().Finish();
    const ImageRGB withView = app.readImage();
    const Vec2 eye = app.map().toWindow(app.camera().position), eye0 = app.map().toWindow(start.position);
    CHECK(withView.at(int(eye.x), int(eye.y)) == picture::kView);
    CHECK(withView.at(int(eye0.x), int(eye0.y)) != picture::kView);
}

std::string quote(const std::string& s) { return "'" + s + "'"; }

struct Run {
    int status = -1;
    std::string out, err;
};

fs::path tempDir() {
    static const fs::path dir = [] {
        fs::path d = fs::temp_directory_path() / ("rgvc-test-sim2d-" + std::to_string(::getpid()));
        fs::create_directories(d);
        return d;
    }();
    return dir;
}

Run runSim2d(const std::string& args) {
    const std::string errFile = (tempDir() / "stderr.txt").string();
    const std::string cmd = quote(RGVC_SIM2D_PATH) + " " + args + " 2>" + quote(errFile);
    Run r;
    FILE* p = ::popen(cmd.c_str(), "r");
    REQUIRE(p != nullptr);
    char buf[4096];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) r.out.append(buf, n);
    const int st = ::pclose(p);
    r.status = WIFEXITED(st) ? WEXITSTATUS(st) : 128;
    std::ifstream e(errFile, std::ios::binary);
    r.err.assign(std::istreambuf_iterator<char>(e), std::istreambuf_iterator<char>());
    return r;
}

void checkRejected(const Run& r, const std::string& needle) {
    INFO("stderr: " << r.err);
    CHECK(r.status == 2);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK(r.err.rfind("rgvc_sim2d: ", 0) == 0);
    CHECK(r.err.find(needle) != std::string::npos);
}

std::string writeTemp(const std::string& name, const std::string& text) {
    const fs::path p = tempDir() / name;
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
}

} // namespace

TEST_CASE("sim2d headless: the scripted walk moves the viewer, spawns a box, and the PVS layer is where the culler says", "[sim]") {
    auto ctx = createOsMesaContext(SimApp::windowWidth(kMap), kMap);
    runWalkAndCheck(*ctx, false);
}

TEST_CASE("sim2d window: the same walk in a GLFW window under Xvfb, read back", "[sim][sim-window][.]") {
    REQUIRE(std::getenv("DISPLAY") != nullptr);
    auto ctx = createGlfwContext(SimApp::windowWidth(kMap), kMap, {.visible = true, .title = "test_sim2d"});
    gl_test::pinLoadedLibraries();
    INFO(ctx->description());
    REQUIRE(ctx->width() == SimApp::windowWidth(kMap));
    runWalkAndCheck(*ctx, true);
}

TEST_CASE("sim2d: layer keys, pause and drag act on the picture and the world", "[sim]") {
    auto ctx = createOsMesaContext(SimApp::windowWidth(kMap), kMap);
    SimSettings settings;
    settings.layers = Layers::parse("pvs,hidden");
    SimApp app(*ctx, generateWorld(parseGeneratorSpec("field:50"), 3), settings);
    InputScript script = InputScript::parse("0 key 9\n0 key 0\n1 key space\n", "keys");
    app.frame(script.next(0));
    // Both object layers off: no object colour anywhere on the map.
    CHECK_FALSE(app.layers()[Layer::Pvs]);
    CHECK_FALSE(app.layers()[Layer::Hidden]);
    const ImageRGB img = app.readImage();
    int coloured = 0;
    for (int y = 0; y < kMap; ++y)
        for (int x = 0; x < kMap; ++x)
            coloured += near(img.at(x, y), fillOverEmpty(picture::kPvs)) || near(img.at(x, y), fillOverEmpty(picture::kHidden));
    CHECK(coloured == 0);
    // Space pauses: the world's frame stops.
    app.frame(script.next(1));
    CHECK(app.paused());
    const std::size_t frozen = app.world().frame();
    const Vec2 t0 = app.world().objects()[45].translation;
    app.frame(script.next(2));
    CHECK(app.world().frame() == frozen);
    CHECK(app.world().objects()[45].translation == t0);
    // A drag: press on object 45, move, release; it follows the cursor by the same amount.
    const Box<2> b = boundsOf<2>(app.world().objects()[45].shape());
    const Vec2 grab = app.map().toWindow(0.5 * (b.min + b.max));
    InputFrame press;
    press.mouse = grab;
    press.leftPressed = press.leftDown = true;
    app.frame(press);
    InputFrame move = press;
    move.leftPressed = false;
    move.mouse = grab + Vec2(20, -10);
    app.frame(move);
    InputFrame release = move;
    release.leftDown = false;
    release.leftReleased = true;
    app.frame(release);
    const Vec2 moved = app.world().objects()[45].translation - t0;
    CHECK(moved.x == Approx(20 / app.map().scale));
    CHECK(moved.y == Approx(10 / app.map().scale));
    CHECK(app.world().objects().size() == 90); // grabbing spawns nothing
}

TEST_CASE("sim2d input scripts: events per frame, and bad lines named by file and line", "[sim]") {
    InputScript s = InputScript::parse("# c\n2 hold a 2\n2 key 3\n3 press 10 20\n4 mouse 15 25\n5 release 15 25\n6 wheel -2\n6 look 4\n7 quit\n", "t");
    CHECK(s.lastFrame() == 7);
    CHECK_FALSE(s.next(0).isDown(letterKey('a')));
    s.next(1);
    const InputFrame f2 = s.next(2);
    CHECK(f2.isDown(letterKey('a')));
    CHECK(f2.wasPressed(digitKey(3)));
    const InputFrame f3 = s.next(3);
    CHECK(f3.isDown(letterKey('a')));
    CHECK((f3.leftPressed && f3.leftDown && *f3.mouse == Vec2(10, 20)));
    const InputFrame f4 = s.next(4);
    CHECK_FALSE(f4.isDown(letterKey('a')));
    CHECK((f4.leftDown && !f4.leftPressed && *f4.mouse == Vec2(15, 25)));
    const InputFrame f5 = s.next(5);
    CHECK((f5.leftReleased && !f5.leftDown));
    const InputFrame f6 = s.next(6);
    CHECK(f6.wheel == -2);
    CHECK(f6.lookDx == 4);
    CHECK(s.next(7).quit);

    auto rejects = [](const std::string& text, const std::string& needle) {
        INFO(text);
        try {
            InputScript::parse(text, "s.txt");
            FAIL("accepted");
        } catch (const InvalidInput& e) {
            CHECK(std::string(e.what()).find(needle) != std::string::npos);
        }
    };
    rejects("0 key w\n1 jump\n", "s.txt:2: unknown event 'jump'");
    rejects("0 key enter\n", "s.txt:1: unknown key 'enter'");
    rejects("-1 key w\n", "s.txt:1: the frame");
    rejects("0 hold w 0\n", "s.txt:1: the hold's length");
    rejects("0 click 1\n", "s.txt:1: expected 'FRAME click X Y'");
    rejects("0 mouse 1 nan\n", "s.txt:1: Y must be a finite number");
}

TEST_CASE("sim2d generators: fixed seeds, the asked number of movers, bad specs refused", "[sim]") {
    for (const std::string& kind : generatorKinds()) {
        INFO(kind);
        const SimWorld a = generateWorld(parseGeneratorSpec(kind + ":120"), 7);
        const SimWorld b = generateWorld(parseGeneratorSpec(kind + ":120"), 7);
        std::size_t movers = 0;
        for (const SimObject& o : a.objects()) movers += o.isStatic ? 0 : 1;
        CHECK(movers == 120);
        REQUIRE(a.objects().size() == b.objects().size());
        for (std::size_t i = 0; i < a.objects().size(); ++i) {
            const Box<2> ba = boundsOf<2>(a.objects()[i].shape()), bb = boundsOf<2>(b.objects()[i].shape());
            CHECK((ba.min == bb.min && ba.max == bb.max && a.objects()[i].velocity == b.objects()[i].velocity));
        }
        CHECK(a.staysInGrid());
    }
    CHECK_THROWS_AS(parseGeneratorSpec("town:5"), InvalidInput);
    CHECK_THROWS_AS(parseGeneratorSpec("city"), InvalidInput);
    CHECK_THROWS_AS(parseGeneratorSpec("city:-1"), InvalidInput);
    CHECK_THROWS_AS(parseGeneratorSpec("city:12x"), InvalidInput);
}

TEST_CASE("rgvc_sim2d command line: headless PNG frames, bad flags, scripts and scenes exit 2 with one line", "[sim]") {
    const fs::path out = tempDir() / "frames";
    const std::string script = writeTemp("walk.txt", kWalkScript);
    const Run ok = runSim2d("--generate city:200 --headless --frames 6 --png-every 3 --size 128 --script " + quote(script) +
                            " --out " + quote(out.string()));
    INFO("stdout: " << ok.out << "\nstderr: " << ok.err);
    CHECK(ok.status == 0);
    CHECK(ok.out.find("wrote 2 PNG frames") != std::string::npos);
    for (const char* name : {"frame-000002.png", "frame-000005.png"}) {
        std::ifstream png(out / name, std::ios::binary);
        std::string head(8, '\0');
        png.read(head.data(), 8);
        CHECK(head == std::string("\x89PNG\r\n\x1a\n", 8));
    }
    const Run scene = runSim2d(quote(std::string(RGVC_SCENES_DIR) + "/small-2d.json") + " --headless --frames 2 --size 64 --out " +
                               quote((tempDir() / "scene").string()));
    CHECK(scene.status == 0);

    checkRejected(runSim2d("--generate city:10 --headless --bogus"), "unknown option '--bogus'");
    checkRejected(runSim2d("--headless --frames 2"), "no world");
    checkRejected(runSim2d("--generate town:10 --headless"), "--generate: unknown world 'town'");
    checkRejected(runSim2d("--generate city:10 --headless --frames 0"), "--frames");
    checkRejected(runSim2d("--generate city:10 --headless --layers pvs,x"), "unknown layer 'x'");
    checkRejected(runSim2d("--generate city:10 --headless --script " + quote(writeTemp("bad.txt", "0 key w\n3 teleport\n"))),
                  "bad.txt:2: unknown event 'teleport'");
    checkRejected(runSim2d("--generate city:10 --headless --script " + quote((tempDir() / "missing.txt").string())),
                  "cannot read the script file");
    checkRejected(runSim2d(quote(writeTemp("bad.json", "{\"dimensions\": 2, \"grid\": 5}")) + " --headless"), "bad.json");
    checkRejected(runSim2d(quote(std::string(RGVC_SCENES_DIR) + "/small-3d.json") + " --headless"), "2D scenes only");
}

TEST_CASE("sim2d: every frame of the README walk reports every exactly visible object, spawned and dragged ones too", "[sim]") {
    auto ctx = createOsMesaContext(SimApp::windowWidth(kMap), kMap);
    SimApp app(*ctx, generateWorld(parseGeneratorSpec("city:300"), 1), {});
    InputScript script = InputScript::load(std::string(RGVC_SCENES_DIR) + "/sim2d-walk.txt");
    int visibleChecked = 0;
    for (std::size_t f = 0; f < 60; ++f) {
        app.frame(script.next(f));
        std::vector<Shape<2>> shapes;
        for (const SimObject& o : app.world().objects()) shapes.push_back(o.shape());
        const std::vector<bool> visible = reference::exactVisible2D(shapes, app.camera());
        for (std::size_t i = 0; i < shapes.size(); ++i) {
            if (!visible[i]) continue;
            ++visibleChecked;
            INFO("frame " << f << ", seed 1, object id " << app.world().objects()[i].id);
            CHECK(app.inPvs(i));
        }
    }
    CHECK(app.world().objects().size() == 434); // the pentagon and the box
    CHECK(visibleChecked > 100);
}
