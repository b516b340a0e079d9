// A GL 4.5 core context with its own default framebuffer, and the table of its entry points.
//
//   auto ctx = rgvc::createOsMesaContext(640, 480);            // headless, llvmpipe (the default)
//   auto win = rgvc::createGlfwContext(640, 480, {.visible = false}); // X11 window (Xvfb in tests)
//   const rgvc::GlFunctions& gl = ctx->gl();                   // never call gl* directly (GlFunctions.hpp)
//
// Two implementations: OSMesa renders into a buffer in our memory (no display, no GPU: Mesa's llvmpipe
// rasterizes on the CPU), GLFW opens a window on the X display. Everything else in render/gl draws into
// its own framebuffer objects, so the default framebuffer is only for showing or saving a picture.
//
// Threads: a context is current on the thread that created it (each factory leaves it current), and
// every call into render/gl for that context happens on that thread. Several contexts may exist, of
// both kinds: call makeCurrent() before using another one's objects (also after making an OSMesa context
// while a window's is current: both Mesa drivers record the current context in the shared libglapi, so
// the window's must be made current again), and destroy objects while their context is current.
#pragma once

#include "rgvc/render/gl/GlError.hpp"
#include "rgvc/render/gl/GlFunctions.hpp"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace rgvc {

class GlContext {
public:
    virtual ~GlContext() = default;
    GlContext(const GlContext&) = delete;
    GlContext& operator=(const GlContext&) = delete;

    /// Makes this context current on the calling thread. @throws GlError when the driver refuses.
    virtual void makeCurrent() = 0;
    /// Shows the default framebuffer (a window's swap; nothing for OSMesa).
    virtual void swapBuffers() {}

    /// [Pixels] size of the default framebuffer.
    int width() const { return m_width; }
    int height() const { return m_height; }
    /// The context's entry points. [Limit] call them only while this context is current.
    const GlFunctions& gl() const { return m_gl; }
    /// "OSMesa: 4.5 (Core Profile) Mesa 22.3.6, llvmpipe (LLVM 15.0.6, 256 bits)" and the like.
    const std::string& description() const { return m_description; }

    /// The default framebuffer's pixels, RGBA8, width() * height() * 4 bytes, top row first.
    std::vector<std::uint8_t> readPixels() const;

protected:
    GlContext() = default;
    /// Loads the table through `lookup` (the context must be current) and fills description().
    void load(const GlProcLookup& lookup, const std::string& api, int width, int height);

private:
    GlFunctions m_gl;
    int m_width = 0, m_height = 0;
    std::string m_description;
};

/// A headless OSMesa context: GL 4.5 core profile (llvmpipe), RGBA8 colour and 24-bit depth in memory.
/// [Pixels] [Limit] 1 <= width, height <= the driver's maximum (OSMESA_MAX_WIDTH / _HEIGHT, 16384 on
/// Mesa 22), and width * height * 4 bytes must be allocatable.
/// @throws GlError with the cause: bad size, context creation refused (no 4.5 core profile), no memory.
std::unique_ptr<GlContext> createOsMesaContext(int width, int height);

struct GlfwContextOptions {
    bool visible = false;          ///< false: a hidden window (its framebuffer still renders)
    std::string title = "rgvc";
};

/// A GLFW window with a GL 4.5 core context (needs an X display: $DISPLAY, Xvfb in tests).
/// [Pixels] [Limit] 1 <= width, height <= 16384.
/// @throws GlError with GLFW's own message: no display, no GLX 4.5 core visual, bad size.
std::unique_ptr<GlContext> createGlfwContext(int width, int height, const GlfwContextOptions& options = {});

} // namespace rgvc
