// An offscreen render target: one colour attachment (RGBA8 for pictures, R32UI for item ids) and a 32-bit
// float depth attachment, in the context that is current when it is made.
//
// Why its own depth buffer and not the context's: the renderer uses reversed depth (1 at the near plane,
// 0 at infinity, glClipControl zero-to-one) with a float depth buffer, whose precision is relative
// (about 1e-7 of the distance at every distance). The contexts' default framebuffers have 24-bit fixed
// depth, where reversed depth gains nothing.
#pragma once

#include "rgvc/render/gl/GlContext.hpp"

#include <cstdint>
#include <vector>

namespace rgvc {

enum class ColourFormat : std::uint8_t {
    Rgba8, ///< 8-bit RGBA, for pictures
    R32ui, ///< one 32-bit unsigned integer per pixel, for ids (the item buffer)
};

class GlFramebuffer {
public:
    /// [Pixels] [Limit] 1 <= width, height <= GL_MAX_RENDERBUFFER_SIZE (16384 on llvmpipe).
    /// @throws GlError for a bad size or an incomplete framebuffer (with the GL status).
    GlFramebuffer(const GlContext& context, int width, int height, ColourFormat format);
    ~GlFramebuffer();
    GlFramebuffer(const GlFramebuffer&) = delete;
    GlFramebuffer& operator=(const GlFramebuffer&) = delete;

    /// Binds it for drawing and reading and sets the viewport to its size.
    void bind() const;
    /// Clears colour (to 0) and depth (to 0: reversed depth's "infinitely far").
    void clear() const;

    int width() const { return m_width; }
    int height() const { return m_height; }
    ColourFormat format() const { return m_format; }
    GLuint name() const { return m_fbo; }

    /// R32ui only: width * height ids, top row first.
    std::vector<std::uint32_t> readIds() const;
    /// Rgba8 only: width * height * 4 bytes, top row first.
    std::vector<std::uint8_t> readRgba() const;

private:
    const GlFunctions& m_gl;
    int m_width, m_height;
    ColourFormat m_format;
    GLuint m_fbo = 0, m_colour = 0, m_depth = 0;
};

} // namespace rgvc
