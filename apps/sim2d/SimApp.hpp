// One simulator: a world, its culler, the viewer, and the picture of each frame (map + ImGui panel)
// drawn into the current context's default framebuffer. main.cpp runs it in a window or headless; the
// tests run it the same way and read the framebuffer back.
//
//   auto ctx = rgvc::createOsMesaContext(SimApp::windowWidth(512), 512);
//   rgvc::sim::SimApp app(*ctx, std::move(world), {});
//   app.frame(input);                     // move, spawn, drag, step, cull, draw
//   ImageRGB img = app.readImage();       // what the window shows
//
// The frame's order: keys and mouse act (layers, pause, viewer, spawn, drag), the world steps unless
// paused, the culler culls for the viewer's camera (the pull API: it asks the world for the placements it
// needs), then the map and the panel are drawn with this frame's culling state and stats.
#pragma once

#include "ImGuiGlRenderer.hpp"
#include "SimInput.hpp"
#include "SimView.hpp"
#include "SimWorld.hpp"

#include "rgvc/dynamics/Culler.hpp"
#include "rgvc/render/Image.hpp"
#include "rgvc/render/gl/GlContext.hpp"

#include <chrono>
#include <memory>
#include <optional>
#include <vector>

struct ImGuiContext;

namespace rgvc::sim {

struct SimSettings {
    int mapSize = 512;             ///< [Pixels] side of the square map; the panel is kPanelWidth to its right
    Layers layers;                 ///< enabled at start
    SpawnKind spawn = SpawnKind::Circle;
    bool paused = false;
    bool panel = true;             ///< false: the panel's column stays empty (key tab toggles)
    double speed = 0;              ///< [World units per frame] viewer speed; 0: half a voxel
    double turnDeg = 2;            ///< [Degrees per frame] arrow / Q / E turning
    double lookDegPerPixel = 0.25; ///< [Degrees per pixel] mouse look
};

/// Per-frame numbers of the panel (and of `--stats` output).
struct SimFrameStats {
    std::size_t frame = 0;
    std::size_t objects = 0;
    CullStats cull;
    double frameMs = 0;  ///< [ms] wall time of the previous frame: from its start to this frame's start
    double fps = 0;      ///< over the last 30 frames
};

class SimApp {
public:
    static constexpr int kPanelWidth = 250; ///< [Pixels]
    /// [Pixels] the window width for a map of `mapSize` pixels.
    static int windowWidth(int mapSize) { return mapSize + kPanelWidth; }

    /// `context` must be current, of windowWidth(settings.mapSize) x settings.mapSize pixels, and outlive
    /// the app. @throws GlError (GL), InvalidInput (a world the culler refuses).
    SimApp(GlContext& context, SimWorld world, const SimSettings& settings);
    ~SimApp();
    SimApp(const SimApp&) = delete;
    SimApp& operator=(const SimApp&) = delete;

    /// Runs one frame with this input and draws it (see the top of this file).
    void frame(const InputFrame& input);
    /// The default framebuffer after the last frame, top row first.
    ImageRGB readImage() const;
    bool quitRequested() const { return m_quit; }

    // State, for the tests and the stats line.
    const SimWorld& world() const { return m_world; }
    const Culler2D& culler() const { return m_culler; }
    const Camera2& camera() const { return m_camera; }
    const MapTransform& map() const { return m_map; }
    const Layers& layers() const { return m_settings.layers; }
    SpawnKind spawnKind() const { return m_settings.spawn; }
    bool paused() const { return m_settings.paused; }
    const SimFrameStats& stats() const { return m_stats; }
    /// Whether object `index` of world() is in the last PVS.
    bool inPvs(std::size_t index) const { return index < m_inPvs.size() && m_inPvs[index]; }
    /// [Pixels] the panel's column: x from mapSize on.
    int mapSize() const { return m_settings.mapSize; }

private:
    void handleKeys(const InputFrame& in);
    void moveViewer(const InputFrame& in);
    void handleMouse(const InputFrame& in, bool panelHasMouse);
    void syncObject(std::size_t index);
    void refreshStaticMask();
    void fillVoxelTexture();
    void drawMap();
    void drawPanel();

    GlContext& m_context;
    SimWorld m_world;
    SimSettings m_settings;
    Culler2D m_culler;
    /// The static objects alone: its O is exactly Os, the static part of the main culler's O
    /// (VoxelStorage.hpp: "Os is O's static part"), which VoxelState does not separate.
    Culler2D m_statics;
    std::vector<std::uint8_t> m_staticMask;
    bool m_staticDirty = true;

    Camera2 m_camera;
    double m_headingDeg = 0;
    MapTransform m_map;

    std::optional<std::size_t> m_dragged;
    Vec2 m_grabOffset{0.0};
    bool m_quit = false, m_stepOnce = false;

    std::vector<bool> m_inPvs;
    SimFrameStats m_stats;
    std::chrono::steady_clock::time_point m_lastStart{};
    std::vector<double> m_recentMs;

    ImGuiContext* m_imgui = nullptr;
    std::unique_ptr<ImGuiGlRenderer> m_renderer;
    ImTextureID m_voxelTexture{};
    std::vector<std::uint8_t> m_voxelRgba;
};

} // namespace rgvc::sim
