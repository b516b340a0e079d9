// The headless context: OSMesa on llvmpipe, rendering into a buffer in our memory.
#include "rgvc/render/gl/GlContext.hpp"

// After glcorearb.h (through GlContext.hpp): osmesa.h pulls in the legacy GL/gl.h, whose declarations
// of the same 1.x functions are compatible; in the other order glcorearb.h would skip its 1.x typedefs.
#include <GL/osmesa.h>

#include <limits>
#include <new>
#include <string>
#include <vector>

namespace rgvc {

namespace {

class OsMesaContext final : public GlContext {
public:
    OsMesaContext(int width, int height) {
        // Size checks first: OSMesaMakeCurrent accepts sizes past its own maximum (100000 x 100000
        // "succeeds" on Mesa 22), and the buffer must be allocated before it is called.
        const std::string size = std::to_string(width) + " x " + std::to_string(height);
        if (width < 1 || height < 1)
            throw GlError("OSMesa: the framebuffer size must be at least 1 x 1 pixels, got " + size);

        // GL 4.5 core: the GL stage uses glClipControl, base-instance draws and shader storage buffers.
        const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24, OSMESA_STENCIL_BITS, 0,
                               OSMESA_ACCUM_BITS, 0, OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                               OSMESA_CONTEXT_MAJOR_VERSION, 4, OSMESA_CONTEXT_MINOR_VERSION, 5, 0};
        m_context = OSMesaCreateContextAttribs(attribs, nullptr);
        if (!m_context)
            throw GlError("OSMesa: OSMesaCreateContextAttribs refused a GL 4.5 core profile context "
                          "(is Mesa's llvmpipe installed? Debian: libosmesa6)");
        try {
            // The limits are read from a context made current on a 1 x 1 buffer, before the real one exists.
            m_pixels.assign(4, 0);
            if (!OSMesaMakeCurrent(m_context, m_pixels.data(), GL_UNSIGNED_BYTE, 1, 1))
                throw GlError("OSMesa: OSMesaMakeCurrent failed on a 1 x 1 buffer");
            GLint maxWidth = 0, maxHeight = 0;
            OSMesaGetIntegerv(OSMESA_MAX_WIDTH, &maxWidth);
            OSMesaGetIntegerv(OSMESA_MAX_HEIGHT, &maxHeight);
            if (width > maxWidth || height > maxHeight)
                throw GlError("OSMesa: the framebuffer size must be at most " + std::to_string(maxWidth) + " x " +
                              std::to_string(maxHeight) + " pixels, got " + size);
            try {
                m_pixels.assign(std::size_t(width) * std::size_t(height) * 4, 0);
            } catch (const std::bad_alloc&) {
                throw GlError("OSMesa: cannot allocate the " + size + " framebuffer");
            }
            m_width = width;
            m_height = height;
            makeCurrent();
            load([](const char* name) { return reinterpret_cast<void*>(OSMesaGetProcAddress(name)); }, "OSMesa",
                 width, height);
        } catch (...) {
            OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0);
            OSMesaDestroyContext(m_context);
            throw;
        }
    }

    ~OsMesaContext() override {
        // Leave nothing current that points into the buffer we free.
        if (OSMesaGetCurrentContext() == m_context) OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0);
        OSMesaDestroyContext(m_context);
    }

    void makeCurrent() override {
        if (!OSMesaMakeCurrent(m_context, m_pixels.data(), GL_UNSIGNED_BYTE, m_width, m_height))
            throw GlError("OSMesa: OSMesaMakeCurrent failed for the " + std::to_string(m_width) + " x " +
                          std::to_string(m_height) + " framebuffer");
        // OSMesa's buffer is stored top row first unless told otherwise; GL's convention (row 0 at the
        // bottom) keeps readPixels() the same for both implementations.
        OSMesaPixelStore(OSMESA_Y_UP, 1);
    }

private:
    OSMesaContext m_context = nullptr;
    std::vector<unsigned char> m_pixels;
    int m_width = 0, m_height = 0;
};

} // namespace

std::unique_ptr<GlContext> createOsMesaContext(int width, int height) {
    return std::make_unique<OsMesaContext>(width, height);
}

} // namespace rgvc
