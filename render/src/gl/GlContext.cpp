#include "rgvc/render/gl/GlContext.hpp"

#include <cstring>

namespace rgvc {

void GlContext::load(const GlProcLookup& lookup, const std::string& api, int width, int height) {
    m_gl = loadGlFunctions(lookup, api);
    m_width = width;
    m_height = height;
    auto text = [&](GLenum e) {
        const GLubyte* s = m_gl.GetString(e);
        return s ? std::string(reinterpret_cast<const char*>(s)) : std::string("?");
    };
    m_description = api + ": " + text(GL_VERSION) + ", " + text(GL_RENDERER);
}

std::vector<std::uint8_t> GlContext::readPixels() const {
    const std::size_t row = std::size_t(m_width) * 4;
    std::vector<std::uint8_t> pixels(row * std::size_t(m_height));
    m_gl.BindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    m_gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
    m_gl.ReadPixels(0, 0, m_width, m_height, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
    checkGlError(m_gl, "reading the default framebuffer");
    // GL's rows run bottom to top; images run top to bottom.
    std::vector<std::uint8_t> row0(row);
    for (int y = 0; y < m_height / 2; ++y) {
        std::uint8_t* a = pixels.data() + std::size_t(y) * row;
        std::uint8_t* b = pixels.data() + std::size_t(m_height - 1 - y) * row;
        std::memcpy(row0.data(), a, row);
        std::memcpy(a, b, row);
        std::memcpy(b, row0.data(), row);
    }
    return pixels;
}

} // namespace rgvc
