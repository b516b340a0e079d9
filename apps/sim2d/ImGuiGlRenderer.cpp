#include "ImGuiGlRenderer.hpp"

#include "rgvc/render/gl/GlProgram.hpp"

#include <cstddef>

namespace rgvc::sim {

namespace {

const char* const kVertex = R"(
layout(location = 0) in vec2 inPosition;
layout(location = 1) in vec2 inUv;
layout(location = 2) in vec4 inColour;
uniform mat4 uProjection;
out vec2 uv;
out vec4 colour;
void main() {
    uv = inUv;
    colour = inColour;
    gl_Position = uProjection * vec4(inPosition, 0.0, 1.0);
}
)";

const char* const kFragment = R"(
in vec2 uv;
in vec4 colour;
uniform sampler2D uTexture;
layout(location = 0) out vec4 outColour;
void main() { outColour = colour * texture(uTexture, uv); }
)";

GLuint toName(ImTextureID t) { return GLuint(reinterpret_cast<std::uintptr_t>(t)); }
ImTextureID toId(GLuint name) { return reinterpret_cast<ImTextureID>(std::uintptr_t(name)); }

} // namespace

ImGuiGlRenderer::ImGuiGlRenderer(const GlContext& context) : m_gl(context.gl()) {
    const GlFunctions& gl = m_gl;
    m_program = linkGlProgram(gl, "ImGui draw lists", kVertex, kFragment);
    m_projection = gl.GetUniformLocation(m_program, "uProjection");
    m_sampler = gl.GetUniformLocation(m_program, "uTexture");
    gl.GenVertexArrays(1, &m_vao);
    gl.GenBuffers(1, &m_vbo);
    gl.GenBuffers(1, &m_ebo);
    gl.BindVertexArray(m_vao);
    gl.BindBuffer(GL_ARRAY_BUFFER, m_vbo);
    gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, m_ebo); // recorded in the vertex array
    gl.EnableVertexAttribArray(0);
    gl.EnableVertexAttribArray(1);
    gl.EnableVertexAttribArray(2);
    gl.VertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, sizeof(ImDrawVert), reinterpret_cast<void*>(offsetof(ImDrawVert, pos)));
    gl.VertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, sizeof(ImDrawVert), reinterpret_cast<void*>(offsetof(ImDrawVert, uv)));
    gl.VertexAttribPointer(2, 4, GL_UNSIGNED_BYTE, GL_TRUE, sizeof(ImDrawVert), reinterpret_cast<void*>(offsetof(ImDrawVert, col)));
    gl.BindVertexArray(0);

    // The font atlas: ImGui rasterizes its embedded font (ProggyClean) into RGBA32.
    ImGuiIO& io = ImGui::GetIO();
    io.BackendRendererName = "rgvc_sim2d (GlFunctions)";
    // render() honours ImDrawCmd::VtxOffset, so lists past 65,536 vertices keep 16-bit indices.
    io.BackendFlags |= ImGuiBackendFlags_RendererHasVtxOffset;
    unsigned char* pixels = nullptr;
    int w = 0, h = 0;
    io.Fonts->GetTexDataAsRGBA32(&pixels, &w, &h);
    gl.GenTextures(1, &m_font);
    gl.BindTexture(GL_TEXTURE_2D, m_font);
    // Nearest: ProggyClean is a pixel font drawn at its size (texels map 1:1 to pixels), and llvmpipe's
    // nearest sampling is cheaper than bilinear on every fragment (untextured shapes sample it too).
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    gl.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    gl.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
    io.Fonts->SetTexID(toId(m_font));
    checkGlError(gl, "creating the ImGui renderer");
}

ImGuiGlRenderer::~ImGuiGlRenderer() {
    const GlFunctions& gl = m_gl;
    for (GLuint t : m_textures) gl.DeleteTextures(1, &t);
    gl.DeleteTextures(1, &m_font);
    gl.DeleteBuffers(1, &m_vbo);
    gl.DeleteBuffers(1, &m_ebo);
    gl.DeleteVertexArrays(1, &m_vao);
    gl.DeleteProgram(m_program);
}

ImTextureID ImGuiGlRenderer::createTexture(int width, int height) {
    if (width < 1 || height < 1 || width > 16384 || height > 16384)
        throw GlError("ImGui renderer: texture size must be in [1, 16384], got " + std::to_string(width) + " x " +
                      std::to_string(height));
    const GlFunctions& gl = m_gl;
    GLuint t = 0;
    gl.GenTextures(1, &t);
    m_textures.push_back(t);
    gl.BindTexture(GL_TEXTURE_2D, t);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    gl.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    checkGlError(gl, "creating a texture");
    return toId(t);
}

void ImGuiGlRenderer::updateTexture(ImTextureID texture, int width, int height, const std::uint8_t* rgba) {
    const GlFunctions& gl = m_gl;
    gl.BindTexture(GL_TEXTURE_2D, toName(texture));
    gl.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    gl.TexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
}

void ImGuiGlRenderer::render(const ImDrawData& data, int fbWidth, int fbHeight) {
    const GlFunctions& gl = m_gl;
    gl.Viewport(0, 0, fbWidth, fbHeight);
    gl.Enable(GL_BLEND);
    gl.BlendEquation(GL_FUNC_ADD);
    gl.BlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    gl.Disable(GL_CULL_FACE);
    gl.Disable(GL_DEPTH_TEST);
    gl.Enable(GL_SCISSOR_TEST);

    // Orthographic projection of ImGui's display rectangle, y down (column-major).
    const float l = data.DisplayPos.x, r = data.DisplayPos.x + data.DisplaySize.x;
    const float t = data.DisplayPos.y, b = data.DisplayPos.y + data.DisplaySize.y;
    const float projection[16] = {2 / (r - l), 0, 0, 0, 0, 2 / (t - b), 0, 0, 0, 0, -1, 0,
                                  (r + l) / (l - r), (t + b) / (b - t), 0, 1};
    gl.UseProgram(m_program);
    gl.UniformMatrix4fv(m_projection, 1, GL_FALSE, projection);
    gl.Uniform1i(m_sampler, 0);
    gl.ActiveTexture(GL_TEXTURE0);
    gl.BindVertexArray(m_vao);
    gl.BindBuffer(GL_ARRAY_BUFFER, m_vbo);

    const float sx = data.DisplaySize.x > 0 ? fbWidth / data.DisplaySize.x : 1;
    const float sy = data.DisplaySize.y > 0 ? fbHeight / data.DisplaySize.y : 1;
    for (int n = 0; n < data.CmdListsCount; ++n) {
        const ImDrawList& list = *data.CmdLists[n];
        gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(list.VtxBuffer.Size) * GLsizeiptr(sizeof(ImDrawVert)), list.VtxBuffer.Data,
                      GL_STREAM_DRAW);
        gl.BufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(list.IdxBuffer.Size) * GLsizeiptr(sizeof(ImDrawIdx)),
                      list.IdxBuffer.Data, GL_STREAM_DRAW);
        for (const ImDrawCmd& cmd : list.CmdBuffer) {
            if (cmd.UserCallback) {
                // ImDrawCallback_ResetRenderState is the only callback ImGui itself emits; ours set none.
                if (cmd.UserCallback != ImDrawCallback_ResetRenderState) cmd.UserCallback(&list, &cmd);
                continue;
            }
            const float x0 = (cmd.ClipRect.x - data.DisplayPos.x) * sx, y0 = (cmd.ClipRect.y - data.DisplayPos.y) * sy;
            const float x1 = (cmd.ClipRect.z - data.DisplayPos.x) * sx, y1 = (cmd.ClipRect.w - data.DisplayPos.y) * sy;
            if (x1 <= x0 || y1 <= y0) continue;
            gl.Scissor(GLint(x0), GLint(float(fbHeight) - y1), GLsizei(x1 - x0), GLsizei(y1 - y0));
            gl.BindTexture(GL_TEXTURE_2D, toName(cmd.GetTexID()));
            gl.DrawElementsBaseVertex(GL_TRIANGLES, GLsizei(cmd.ElemCount),
                                      sizeof(ImDrawIdx) == 2 ? GL_UNSIGNED_SHORT : GL_UNSIGNED_INT,
                                      reinterpret_cast<void*>(std::uintptr_t(cmd.IdxOffset * sizeof(ImDrawIdx))),
                                      GLint(cmd.VtxOffset));
        }
    }
    gl.BindVertexArray(0);
    gl.UseProgram(0);
    gl.Disable(GL_SCISSOR_TEST);
    gl.Disable(GL_BLEND);
    checkGlError(gl, "drawing the ImGui draw lists");
}

} // namespace rgvc::sim
