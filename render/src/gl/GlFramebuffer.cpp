#include "rgvc/render/gl/GlFramebuffer.hpp"

#include <algorithm>
#include <cstdio>
#include <string>

namespace rgvc {

GlFramebuffer::GlFramebuffer(const GlContext& context, int width, int height, ColourFormat format)
    : m_gl(context.gl()), m_width(width), m_height(height), m_format(format) {
    GLint maxSize = 0;
    m_gl.GetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &maxSize);
    if (width < 1 || height < 1 || width > maxSize || height > maxSize)
        throw GlError("GL: a framebuffer must be 1 to " + std::to_string(maxSize) + " pixels per side, got " +
                      std::to_string(width) + " x " + std::to_string(height));
    while (m_gl.GetError() != GL_NO_ERROR) {
    }
    m_gl.GenFramebuffers(1, &m_fbo);
    m_gl.GenRenderbuffers(1, &m_colour);
    m_gl.GenRenderbuffers(1, &m_depth);
    m_gl.BindRenderbuffer(GL_RENDERBUFFER, m_colour);
    m_gl.RenderbufferStorage(GL_RENDERBUFFER, format == ColourFormat::R32ui ? GL_R32UI : GL_RGBA8, width, height);
    m_gl.BindRenderbuffer(GL_RENDERBUFFER, m_depth);
    m_gl.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, width, height);
    m_gl.BindRenderbuffer(GL_RENDERBUFFER, 0);
    m_gl.BindFramebuffer(GL_FRAMEBUFFER, m_fbo);
    m_gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, m_colour);
    m_gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, m_depth);
    const GLenum drawBuffer = GL_COLOR_ATTACHMENT0;
    m_gl.DrawBuffers(1, &drawBuffer);
    m_gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
    const GLenum status = m_gl.CheckFramebufferStatus(GL_FRAMEBUFFER);
    const GLenum error = m_gl.GetError();
    if (status != GL_FRAMEBUFFER_COMPLETE || error != GL_NO_ERROR) {
        char text[96];
        std::snprintf(text, sizeof text, "status 0x%04x, GL error 0x%04x", unsigned(status), unsigned(error));
        m_gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
        m_gl.DeleteFramebuffers(1, &m_fbo);
        m_gl.DeleteRenderbuffers(1, &m_colour);
        m_gl.DeleteRenderbuffers(1, &m_depth);
        throw GlError("GL: cannot make a " + std::to_string(width) + " x " + std::to_string(height) +
                      " framebuffer (" + text + ")");
    }
}

GlFramebuffer::~GlFramebuffer() {
    m_gl.DeleteFramebuffers(1, &m_fbo);
    m_gl.DeleteRenderbuffers(1, &m_colour);
    m_gl.DeleteRenderbuffers(1, &m_depth);
}

void GlFramebuffer::bind() const {
    m_gl.BindFramebuffer(GL_FRAMEBUFFER, m_fbo);
    m_gl.Viewport(0, 0, m_width, m_height);
}

void GlFramebuffer::clear() const {
    bind();
    m_gl.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    m_gl.DepthMask(GL_TRUE);
    if (m_format == ColourFormat::R32ui) {
        const GLuint zero[4] = {0, 0, 0, 0};
        m_gl.ClearBufferuiv(GL_COLOR, 0, zero);
    } else {
        const GLfloat black[4] = {0, 0, 0, 1};
        m_gl.ClearBufferfv(GL_COLOR, 0, black);
    }
    const GLfloat far = 0;
    m_gl.ClearBufferfv(GL_DEPTH, 0, &far);
}

namespace {

template <class T> void flipRows(std::vector<T>& pixels, std::size_t rowLength, int height) {
    for (int y = 0; y < height / 2; ++y)
        std::swap_ranges(pixels.begin() + std::ptrdiff_t(std::size_t(y) * rowLength),
                         pixels.begin() + std::ptrdiff_t(std::size_t(y + 1) * rowLength),
                         pixels.begin() + std::ptrdiff_t(std::size_t(height - 1 - y) * rowLength));
}

} // namespace

std::vector<std::uint32_t> GlFramebuffer::readIds() const {
    if (m_format != ColourFormat::R32ui) throw GlError("GL: readIds needs an R32ui framebuffer");
    std::vector<std::uint32_t> ids(std::size_t(m_width) * std::size_t(m_height));
    m_gl.BindFramebuffer(GL_READ_FRAMEBUFFER, m_fbo);
    m_gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
    m_gl.ReadPixels(0, 0, m_width, m_height, GL_RED_INTEGER, GL_UNSIGNED_INT, ids.data());
    checkGlError(m_gl, "reading the id framebuffer");
    flipRows(ids, std::size_t(m_width), m_height);
    return ids;
}

std::vector<std::uint8_t> GlFramebuffer::readRgba() const {
    if (m_format != ColourFormat::Rgba8) throw GlError("GL: readRgba needs an Rgba8 framebuffer");
    std::vector<std::uint8_t> rgba(std::size_t(m_width) * std::size_t(m_height) * 4);
    m_gl.BindFramebuffer(GL_READ_FRAMEBUFFER, m_fbo);
    m_gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
    m_gl.ReadPixels(0, 0, m_width, m_height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    checkGlError(m_gl, "reading the colour framebuffer");
    flipRows(rgba, std::size_t(m_width) * 4, m_height);
    return rgba;
}

} // namespace rgvc
