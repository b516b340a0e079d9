#include "SimApp.hpp"

#include "rgvc/grid/Error.hpp"

#include <imgui.h>

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <numbers>

namespace rgvc::sim {

namespace {

constexpr double kDegToRad = std::numbers::pi / 180;

ImU32 colour(RGB8 c, double alpha = 1) { return IM_COL32(c.r, c.g, c.b, int(std::lround(alpha * 255))); }
ImVec2 im(const Vec2& v) { return ImVec2(float(v.x), float(v.y)); }

CullerOptions cullerOptions(const SimWorld& world) {
    CullerOptions o;
    o.objectsStayInGrid = world.staysInGrid(); // as `rgvc cull` promises for scene files (SceneMotion.hpp)
    return o;
}

} // namespace

SimApp::SimApp(GlContext& context, SimWorld world, const SimSettings& settings)
    : m_context(context), m_world(std::move(world)), m_settings(settings), m_culler(m_world.grid(), cullerOptions(m_world)),
      m_statics(m_world.grid()), m_camera(m_world.startCamera()) {
    if (m_settings.mapSize < 16 || m_settings.mapSize > 8192)
        throw InvalidInput("--size", "the map must be 16 to 8192 pixels, got " + std::to_string(m_settings.mapSize));
    if (m_settings.speed <= 0) m_settings.speed = 0.5 * m_world.grid().voxelSize();
    for (const SimObject& o : m_world.objects()) {
        m_culler.addObject(o.desc());
        if (o.isStatic) m_statics.addObject(o.desc());
    }
    m_headingDeg = std::atan2(m_camera.direction.y, m_camera.direction.x) / kDegToRad;
    m_map = MapTransform::fit(m_world.bounds(), m_settings.mapSize, m_settings.mapSize);

    m_imgui = ImGui::CreateContext();
    ImGui::SetCurrentContext(m_imgui);
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr; // no imgui.ini next to the user's files
    io.LogFilename = nullptr;
    ImGui::StyleColorsDark();
    ImGuiStyle& style = ImGui::GetStyle();
    style.WindowRounding = 0;
    style.ItemSpacing.y = 3;
    style.FramePadding.y = 1;
    try {
        m_renderer = std::make_unique<ImGuiGlRenderer>(m_context);
        const IVec2 res = m_world.grid().resolution();
        m_voxelTexture = m_renderer->createTexture(res.x, res.y);
        m_voxelRgba.assign(std::size_t(res.x) * std::size_t(res.y) * 4, 255);
    } catch (...) {
        m_renderer.reset();
        ImGui::DestroyContext(m_imgui);
        throw;
    }
}

SimApp::~SimApp() {
    m_renderer.reset(); // its GL objects go while the context is still current
    ImGui::DestroyContext(m_imgui);
}

void SimApp::handleKeys(const InputFrame& in) {
    for (Key k : in.pressed) {
        const int code = int(k);
        if (code >= int(Key::Num0) && code <= int(Key::Num0) + 9) {
            const int digit = code - int(Key::Num0);
            m_settings.layers.toggle(Layer(digit == 0 ? 9 : digit - 1));
        } else if (k == letterKey('c')) {
            m_settings.spawn = SpawnKind::Circle;
        } else if (k == letterKey('b')) {
            m_settings.spawn = SpawnKind::Box;
        } else if (k == letterKey('p')) {
            m_settings.spawn = SpawnKind::Polygon;
        } else if (k == Key::Space) {
            m_settings.paused = !m_settings.paused;
        } else if (k == letterKey('n')) {
            m_stepOnce = true;
        } else if (k == Key::Tab) {
            m_settings.panel = !m_settings.panel;
        } else if (k == letterKey('r')) {
            m_camera = m_world.startCamera();
            m_headingDeg = std::atan2(m_camera.direction.y, m_camera.direction.x) / kDegToRad;
        } else if (k == Key::Escape) {
            m_quit = true;
        }
    }
    m_quit = m_quit || in.quit;
}

void SimApp::moveViewer(const InputFrame& in) {
    auto held = [&](Key k) { return in.isDown(k) ? 1.0 : 0.0; };
    const double turn = held(Key::Left) + held(letterKey('q')) - held(Key::Right) - held(letterKey('e'));
    m_headingDeg += turn * m_settings.turnDeg - in.lookDx * m_settings.lookDegPerPixel;
    m_headingDeg = std::remainder(m_headingDeg, 360.0);
    const Vec2 forward(std::cos(m_headingDeg * kDegToRad), std::sin(m_headingDeg * kDegToRad));
    const Vec2 right(forward.y, -forward.x);
    const double ahead = held(letterKey('w')) + held(Key::Up) - held(letterKey('s')) - held(Key::Down);
    const double side = held(letterKey('d')) - held(letterKey('a'));
    Vec2 step = ahead * forward + side * right;
    if (glm::length(step) > 0) step = glm::normalize(step) * m_settings.speed;
    m_camera.position += step;
    m_camera.direction = forward;
    if (in.wheel != 0) m_camera.fovDeg = std::clamp(m_camera.fovDeg * std::pow(0.9, in.wheel), 5.0, 360.0);
}

void SimApp::syncObject(std::size_t index) {
    const SimObject& o = m_world.objects()[index];
    m_culler.updateObject(o.id, o.shape());
    if (o.isStatic) {
        m_statics.updateObject(o.id, o.shape());
        m_staticDirty = true;
    }
}

void SimApp::handleMouse(const InputFrame& in, bool panelHasMouse) {
    if (!in.mouse) return;
    const Vec2 cursor = *in.mouse;
    const bool onMap = cursor.x >= 0 && cursor.y >= 0 && cursor.x < m_settings.mapSize && cursor.y < m_settings.mapSize;
    const Vec2 world = m_map.toWorld(cursor);
    if (in.leftPressed && onMap && !panelHasMouse && !m_dragged) {
        std::optional<std::size_t> hit = m_world.pick(world);
        if (!hit) {
            hit = m_world.spawn(m_settings.spawn, world);
            m_culler.addObject(m_world.objects()[*hit].desc());
        }
        m_dragged = hit;
        m_grabOffset = world - m_world.objects()[*hit].translation;
    }
    if (m_dragged && (in.leftDown || in.leftPressed)) {
        // Kept inside the grid: the culler's objectsStayInGrid promise (and the motion's reflection)
        // assume moving objects stay in; a larger-than-grid object is left where the cursor puts it.
        const SimObject& o = m_world.objects()[*m_dragged];
        Vec2 t = world - m_grabOffset;
        const Box<2> b = boundsOf<2>(o.shape0), g = m_world.bounds();
        for (int a = 0; a < 2; ++a)
            if (b.max[a] - b.min[a] <= g.max[a] - g.min[a]) t[a] = std::clamp(t[a], g.min[a] - b.min[a], g.max[a] - b.max[a]);
        if (t != o.translation) {
            m_world.moveTo(*m_dragged, t);
            syncObject(*m_dragged);
        }
    }
    if (in.leftReleased) m_dragged.reset();
}

void SimApp::refreshStaticMask() {
    if (!m_staticDirty) return;
    const IVec2 res = m_world.grid().resolution();
    m_staticMask.assign(std::size_t(res.x) * std::size_t(res.y), 0);
    for (int y = 0; y < res.y; ++y)
        for (int x = 0; x < res.x; ++x)
            m_staticMask[std::size_t(y) * std::size_t(res.x) + std::size_t(x)] = m_statics.voxelState({x, y}).opaque;
    m_staticDirty = false;
}

void SimApp::fillVoxelTexture() {
    refreshStaticMask();
    // A cell's colour depends on seven flags only: the 128 colours under this frame's layers are made
    // once, so the per-voxel work is the state lookup and a table read (layeredVoxelColor and its
    // blend's rounding per voxel were a fifth of the main thread's time at 256 x 256).
    std::array<RGB8, 128> table;
    for (unsigned bits = 0; bits < 128; ++bits) {
        VoxelState s;
        s.inGrid = true;
        s.opaque = bits & 1;
        s.occluded = bits & 2;
        s.visited = bits & 4;
        s.occluder = bits & 8;
        s.hasIds = bits & 16;
        s.hasTbv = bits & 32;
        table[bits] = layeredVoxelColor(s, (bits & 64) != 0, m_settings.layers);
    }
    const IVec2 res = m_world.grid().resolution();
    for (int y = 0; y < res.y; ++y)
        for (int x = 0; x < res.x; ++x) {
            const std::size_t i = std::size_t(y) * std::size_t(res.x) + std::size_t(x);
            const VoxelState s = m_culler.voxelState({x, y});
            const unsigned bits = unsigned(s.opaque) | unsigned(s.occluded) << 1 | unsigned(s.visited) << 2 |
                                  unsigned(s.occluder) << 3 | unsigned(s.hasIds) << 4 | unsigned(s.hasTbv) << 5 |
                                  unsigned(m_staticMask[i] != 0) << 6;
            const RGB8 c = table[bits];
            std::uint8_t* p = &m_voxelRgba[i * 4];
            p[0] = c.r;
            p[1] = c.g;
            p[2] = c.b;
            p[3] = 255;
        }
    m_renderer->updateTexture(m_voxelTexture, res.x, res.y, m_voxelRgba.data());
}

void SimApp::drawMap() {
    ImDrawList& dl = *ImGui::GetBackgroundDrawList();
    // Crisp fills: a PVS object's pixels are exactly those whose centre its (tessellated) shape covers,
    // with no feathered fringe of mixed colour (the tests compare colours pixel by pixel).
    dl.Flags &= ~ImDrawListFlags_AntiAliasedFill;
    const float side = float(m_settings.mapSize);
    dl.PushClipRect(ImVec2(0, 0), ImVec2(side, side));
    // Around the grid: the clear colour (frame()); no full-map rectangle, whose 262,144 blended
    // fragments at 512 x 512 cost llvmpipe as much as the voxel image itself.
    // Row 0 of the texture is voxel row y = 0, the bottom of the map: v runs upwards.
    const Box<2> g = m_world.bounds();
    dl.AddImage(m_voxelTexture, im(m_map.toWindow({g.min.x, g.max.y})), im(m_map.toWindow({g.max.x, g.min.y})), ImVec2(0, 1),
                ImVec2(1, 0));

    const float scale = float(m_map.scale);
    std::vector<ImVec2> points;
    auto drawShape = [&](const Shape<2>& s, ImU32 fill) {
        std::visit(
            [&](const auto& x) {
                using T = std::decay_t<decltype(x)>;
                if constexpr (std::is_same_v<T, Ball<2>>) {
                    dl.AddCircleFilled(im(m_map.toWindow(x.center)), float(x.radius) * scale, fill);
                } else if constexpr (std::is_same_v<T, Box<2>>) {
                    dl.AddRectFilled(im(m_map.toWindow({x.min.x, x.max.y})), im(m_map.toWindow({x.max.x, x.min.y})), fill);
                } else {
                    points.clear();
                    for (const Vec2& p : x.points) points.push_back(im(m_map.toWindow(p)));
                    dl.AddConvexPolyFilled(points.data(), int(points.size()), fill);
                }
            },
            s);
    };
    const ImU32 pvsFill = colour(picture::kPvs, palette::kObjectAlpha);
    const ImU32 hiddenFill = colour(picture::kHidden, palette::kObjectAlpha);
    const std::vector<SimObject>& objects = m_world.objects();
    for (std::size_t i = 0; i < objects.size(); ++i) {
        const bool pvs = inPvs(i);
        if (pvs ? m_settings.layers[Layer::Pvs] : m_settings.layers[Layer::Hidden])
            drawShape(objects[i].shape(), pvs ? pvsFill : hiddenFill);
    }
    if (m_dragged) {
        const Box<2> b = boundsOf<2>(objects[*m_dragged].shape());
        dl.AddRect(im(m_map.toWindow({b.min.x, b.max.y})), im(m_map.toWindow({b.max.x, b.min.y})), colour(picture::kView), 0,
                   0, 1.5f);
    }

    if (m_settings.layers[Layer::View]) {
        const ImU32 ink = colour(picture::kView);
        const Vec2 eye = m_map.toWindow(m_camera.position);
        const double reach = std::isfinite(m_camera.far) ? m_camera.far : 2 * glm::length(g.max - g.min);
        const double h = m_headingDeg * kDegToRad, halfFov = 0.5 * m_camera.fovDeg * kDegToRad;
        auto screenDir = [](double a) { return Vec2(std::cos(a), -std::sin(a)); }; // y flips on screen
        if (m_camera.fovDeg < 360)
            for (double edge : {h - halfFov, h + halfFov}) dl.AddLine(im(eye), im(eye + screenDir(edge) * reach * m_map.scale), ink, 1.5f);
        if (std::isfinite(m_camera.far))
            dl.PathArcTo(im(eye), float(m_camera.far * m_map.scale), float(-h - halfFov), float(-h + halfFov), 48), dl.PathStroke(ink, 0, 1.0f);
        // The line of sight, dashed: 6 pixels on, 4 off.
        const Vec2 d = screenDir(h);
        const double length = reach * m_map.scale;
        for (double s = 0; s < length; s += 10) dl.AddLine(im(eye + d * s), im(eye + d * std::min(s + 6, length)), ink, 1.0f);
        dl.AddCircleFilled(im(eye), 3.5f, ink);
    }
    dl.PopClipRect();
}

void SimApp::drawPanel() {
    const float side = float(m_settings.mapSize);
    ImGui::SetNextWindowPos(ImVec2(side, 0));
    ImGui::SetNextWindowSize(ImVec2(float(kPanelWidth), side));
    ImGui::Begin("rgvc_sim2d", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
    const CullStats& s = m_stats.cull;
    ImGui::Text("%s  frame %zu%s", m_world.name().c_str(), m_stats.frame, m_settings.paused ? "  PAUSED" : "");
    ImGui::Text("|PVS| %u of %zu objects", s.pvsSize, m_stats.objects);
    ImGui::Text("cull %.3f ms (update %.3f)", s.cullMs, s.updateMs);
    ImGui::Text("voxels visited %llu, occluded %llu", (unsigned long long)s.voxelsVisited, (unsigned long long)s.voxelsOccluded);
    ImGui::Text("TBVs created %u, revealed %u", s.tbvsCreated, s.tbvsRevealed);
    ImGui::Text("  renewed %u, objects hidden %u", s.tbvsRenewed, s.hiddenObjects);
    ImGui::Text("fallback %s%s", toString(s.fallback), s.cameraJump ? ", camera jump" : "");
    ImGui::Text("frame %.2f ms, %.1f fps", m_stats.frameMs, m_stats.fps);
    ImGui::Text("at (%.1f, %.1f) %.0f°, fov %.0f°", m_camera.position.x, m_camera.position.y, m_headingDeg, m_camera.fovDeg);
    ImGui::Separator();
    int spawn = int(m_settings.spawn);
    ImGui::Text("click spawns:");
    ImGui::RadioButton("circle", &spawn, 0);
    ImGui::SameLine();
    ImGui::RadioButton("box", &spawn, 1);
    ImGui::SameLine();
    ImGui::RadioButton("polygon", &spawn, 2);
    m_settings.spawn = SpawnKind(spawn);
    ImGui::Separator();
    for (int i = 0; i < kLayerCount; ++i) {
        char label[32];
        std::snprintf(label, sizeof label, "%d %s", layerDigit(Layer(i)), layerName(Layer(i)));
        ImGui::Checkbox(label, &m_settings.layers.on[std::size_t(i)]);
        if (i % 2 == 0) ImGui::SameLine(125);
    }
    ImGui::Separator();
    static const char* const keys[][2] = {
        {"W S, Up Down", "move"},       {"A D", "strafe"},        {"Left Right, Q E", "turn"},
        {"right drag", "mouse look"},   {"wheel", "field of view"}, {"click", "spawn / grab"},
        {"drag", "move an object"},     {"C B P", "spawn shape"},  {"Space, N", "pause, step"},
        {"1 ... 0", "layers"},          {"R, Tab, Esc", "reset, panel, quit"}};
    for (const auto& k : keys) {
        ImGui::TextUnformatted(k[0]);
        ImGui::SameLine(118);
        ImGui::TextUnformatted(k[1]);
    }
    ImGui::End();
}

void SimApp::frame(const InputFrame& in) {
    const auto start = std::chrono::steady_clock::now();
    if (m_lastStart != std::chrono::steady_clock::time_point{}) {
        m_stats.frameMs = std::chrono::duration<double, std::milli>(start - m_lastStart).count();
        m_recentMs.push_back(m_stats.frameMs);
        if (m_recentMs.size() > 30) m_recentMs.erase(m_recentMs.begin());
        double sum = 0;
        for (double ms : m_recentMs) sum += ms;
        m_stats.fps = sum > 0 ? 1000.0 * double(m_recentMs.size()) / sum : 0;
    }
    m_lastStart = start;

    ImGui::SetCurrentContext(m_imgui);
    ImGuiIO& io = ImGui::GetIO();
    const bool panelHasMouse = io.WantCaptureMouse; // from the last frame, as ImGui intends
    handleKeys(in);
    moveViewer(in);
    handleMouse(in, panelHasMouse);
    if (!m_settings.paused || m_stepOnce) m_world.step();
    m_stepOnce = false;

    const SimWorld& w = m_world;
    const CullResult& r = m_culler.cull(m_camera, [&w](ObjectId id) { return w.objects()[w.indexOf(id)].shape(); });
    m_inPvs.assign(w.objects().size(), false);
    for (ObjectId id : r.pvs) m_inPvs[w.indexOf(id)] = true;
    m_stats.cull = r.stats;
    m_stats.frame = w.frame();
    m_stats.objects = w.objects().size();

    fillVoxelTexture();
    io.DisplaySize = ImVec2(float(m_context.width()), float(m_context.height()));
    io.DeltaTime = 1.0f / 60; // the world moves per frame, and so does the panel
    io.MousePos = in.mouse ? im(*in.mouse) : ImVec2(-FLT_MAX, -FLT_MAX);
    io.MouseDown[0] = in.leftDown || in.leftPressed;
    io.MouseWheel = panelHasMouse ? float(in.wheel) : 0.0f;
    ImGui::NewFrame();
    drawMap();
    if (m_settings.panel) drawPanel();
    ImGui::Render();

    const GlFunctions& gl = m_context.gl();
    gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
    gl.Viewport(0, 0, m_context.width(), m_context.height());
    gl.ClearColor(palette::kOutside.r / 255.0f, palette::kOutside.g / 255.0f, palette::kOutside.b / 255.0f, 1);
    gl.Clear(GL_COLOR_BUFFER_BIT);
    m_renderer->render(*ImGui::GetDrawData(), m_context.width(), m_context.height());
}

ImageRGB SimApp::readImage() const {
    const std::vector<std::uint8_t> rgba = m_context.readPixels();
    ImageRGB img(m_context.width(), m_context.height());
    std::uint8_t* out = img.data();
    for (std::size_t i = 0, n = rgba.size() / 4; i < n; ++i) {
        out[3 * i] = rgba[4 * i];
        out[3 * i + 1] = rgba[4 * i + 1];
        out[3 * i + 2] = rgba[4 * i + 2];
    }
    return img;
}

} // namespace rgvc::sim
