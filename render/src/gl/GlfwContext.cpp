// A window context through GLFW (X11; under Xvfb in tests). GLFW loads libGL itself; we reach its entry
// points only through glfwGetProcAddress, so libOSMesa linked into the same binary does not interfere.
#include "rgvc/render/gl/GlContext.hpp"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <cstdio>
#include <mutex>
#include <string>

namespace rgvc {

namespace {

// GLFW reports errors through one process-wide callback; the last message becomes the GlError's cause.
// glfwInit / glfwTerminate are counted so that the library is initialised while any window exists.
std::mutex g_glfwMutex;
std::string g_lastGlfwError;
int g_glfwUsers = 0;

void onGlfwError(int code, const char* description) {
    g_lastGlfwError = std::string(description ? description : "unknown error") + " (GLFW error 0x" +
                      [](int c) {
                          char b[16];
                          std::snprintf(b, sizeof b, "%05x", unsigned(c));
                          return std::string(b);
                      }(code) +
                      ")";
}

std::string takeGlfwError() {
    std::string e = g_lastGlfwError.empty() ? std::string("no message") : g_lastGlfwError;
    g_lastGlfwError.clear();
    return e;
}

void acquireGlfw() {
    std::lock_guard<std::mutex> lock(g_glfwMutex);
    if (g_glfwUsers == 0) {
        glfwSetErrorCallback(onGlfwError);
        if (!glfwInit()) throw GlError("GLFW: glfwInit failed: " + takeGlfwError());
    }
    ++g_glfwUsers;
}

void releaseGlfw() {
    std::lock_guard<std::mutex> lock(g_glfwMutex);
    if (--g_glfwUsers == 0) glfwTerminate();
}

class GlfwContext final : public GlContext {
public:
    GlfwContext(int width, int height, const GlfwContextOptions& options) {
        const std::string size = std::to_string(width) + " x " + std::to_string(height);
        if (width < 1 || height < 1 || width > 16384 || height > 16384)
            throw GlError("GLFW: the window size must be in [1, 16384] pixels per side, got " + size);
        acquireGlfw();
        try {
            glfwDefaultWindowHints();
            glfwWindowHint(GLFW_CLIENT_API, GLFW_OPENGL_API);
            glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
            glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
            glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
            glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
            glfwWindowHint(GLFW_VISIBLE, options.visible ? GLFW_TRUE : GLFW_FALSE);
            glfwWindowHint(GLFW_DEPTH_BITS, 24);
            m_window = glfwCreateWindow(width, height, options.title.c_str(), nullptr, nullptr);
            if (!m_window) throw GlError("GLFW: cannot create a " + size + " window with a GL 4.5 core context: " + takeGlfwError());
            glfwMakeContextCurrent(m_window);
            // The framebuffer can differ from the window size (HiDPI); the framebuffer is what we draw.
            int fbWidth = width, fbHeight = height;
            glfwGetFramebufferSize(m_window, &fbWidth, &fbHeight);
            load([](const char* name) { return reinterpret_cast<void*>(glfwGetProcAddress(name)); }, "GLFW", fbWidth,
                 fbHeight);
        } catch (...) {
            if (m_window) glfwDestroyWindow(m_window);
            releaseGlfw();
            throw;
        }
    }

    ~GlfwContext() override {
        glfwDestroyWindow(m_window);
        releaseGlfw();
    }

    void makeCurrent() override {
        // Released first: GLX skips a make-current of the context it believes current, but an OSMesa
        // context made current since then has replaced it in Mesa's libglapi, which both drivers use to
        // find the current context. Released and made current again, GLX rebinds it there.
        glfwMakeContextCurrent(nullptr);
        glfwMakeContextCurrent(m_window);
        if (glfwGetCurrentContext() != m_window) throw GlError("GLFW: glfwMakeContextCurrent failed: " + takeGlfwError());
    }

    void swapBuffers() override { glfwSwapBuffers(m_window); }

private:
    GLFWwindow* m_window = nullptr;
};

} // namespace

std::unique_ptr<GlContext> createGlfwContext(int width, int height, const GlfwContextOptions& options) {
    return std::make_unique<GlfwContext>(width, height, options);
}

} // namespace rgvc
