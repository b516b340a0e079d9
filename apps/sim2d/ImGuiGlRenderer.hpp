// Draws Dear ImGui's draw lists with the project's GL entry-point table (rgvc/render/gl/GlFunctions.hpp).
//
// Why not ImGui's stock OpenGL3 backend (imgui_impl_opengl3.cpp, shipped as source by libimgui-dev):
// in 1.86 it loads GL itself, through its bundled gl3w (imgui_impl_opengl3_loader.h), which dlopens
// libGL.so.1 and resolves every gl* name there. Under an OSMesa context those are GLVND's entry points,
// not OSMesa's, which is the clash GlFunctions.hpp describes (undefined behaviour; in practice nothing is
// drawn, or a crash). Its IMGUI_IMPL_OPENGL_LOADER_CUSTOM mode instead calls the global gl* names, which
// we would have to #define onto a table one by one, for ~45 calls, some (glPolygonMode, glBindSampler,
// glIsEnabled state save/restore) of no use to us. What the backend does for a renderer that owns its
// framebuffer is small: one program, one vertex array, a font texture, a scissor per command. That is
// this file, on the table of whichever context is current, so the window and the headless PNGs draw
// through exactly the same calls.
#pragma once

#include "rgvc/render/gl/GlContext.hpp"

#include <imgui.h>

#include <cstdint>

namespace rgvc::sim {

class ImGuiGlRenderer {
public:
    /// Creates the program and buffers and uploads the font atlas of the current ImGui context.
    /// `context` must be current and stay alive, and ImGui::CreateContext() must have been called.
    /// @throws GlError when a shader does not compile or a GL call fails.
    explicit ImGuiGlRenderer(const GlContext& context);
    ~ImGuiGlRenderer();
    ImGuiGlRenderer(const ImGuiGlRenderer&) = delete;
    ImGuiGlRenderer& operator=(const ImGuiGlRenderer&) = delete;

    /// An RGBA8 texture with nearest filtering (pixel-exact voxel cells), for ImGui::Image / AddImage.
    /// [Pixels] [Limit] 1 <= width, height <= 16384. Deleted with the renderer.
    ImTextureID createTexture(int width, int height);
    /// Replaces its texels: width * height * 4 bytes, row 0 first (row 0 is texture coordinate v = 0).
    void updateTexture(ImTextureID texture, int width, int height, const std::uint8_t* rgba);

    /// Draws `data` (ImGui::GetDrawData() after ImGui::Render()) into the bound framebuffer of
    /// fbWidth x fbHeight pixels. Leaves blending and scissoring off.
    void render(const ImDrawData& data, int fbWidth, int fbHeight);

private:
    const GlFunctions& m_gl;
    GLuint m_program = 0, m_vao = 0, m_vbo = 0, m_ebo = 0, m_font = 0;
    GLint m_projection = -1, m_sampler = -1;
    std::vector<GLuint> m_textures;
};

} // namespace rgvc::sim
