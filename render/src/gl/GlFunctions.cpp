#include "rgvc/render/gl/GlFunctions.hpp"

#include "rgvc/render/gl/GlError.hpp"

#include <cstdio>

namespace rgvc {

namespace {

#define RGVC_GL_NAME(type, name) "gl" #name,
constexpr const char* kNames[] = {RGVC_GL_FUNCTIONS(RGVC_GL_NAME)};
#undef RGVC_GL_NAME

} // namespace

int GlFunctions::count() { return int(sizeof(kNames) / sizeof(kNames[0])); }

const char* GlFunctions::name(int index) { return kNames[index]; }

bool GlFunctions::loaded(int index) const {
    int i = 0;
    bool result = false;
#define RGVC_GL_LOADED(type, name)                                                                         \
    if (i++ == index) result = name != nullptr;
    RGVC_GL_FUNCTIONS(RGVC_GL_LOADED)
#undef RGVC_GL_LOADED
    return result;
}

GlFunctions loadGlFunctions(const GlProcLookup& lookup, const std::string& api) {
    GlFunctions gl;
    // A null address is a missing function. (OSMesaGetProcAddress returns a no-op dispatch stub for any
    // gl* name it does not know rather than null, so the version check below is what catches an old
    // driver there.)
#define RGVC_GL_LOAD(type, name)                                                                           \
    gl.name = reinterpret_cast<type>(lookup("gl" #name));                                                  \
    if (!gl.name) throw GlError(api + ": the GL driver has no entry point gl" #name);
    RGVC_GL_FUNCTIONS(RGVC_GL_LOAD)
#undef RGVC_GL_LOAD

    GLint major = 0, minor = 0;
    gl.GetIntegerv(GL_MAJOR_VERSION, &major);
    gl.GetIntegerv(GL_MINOR_VERSION, &minor);
    if (major < 4 || (major == 4 && minor < 5)) {
        const GLubyte* version = gl.GetString(GL_VERSION);
        const GLubyte* renderer = gl.GetString(GL_RENDERER);
        throw GlError(api + ": the GL stage needs an OpenGL 4.5 core context, the driver gave " +
                      (version ? reinterpret_cast<const char*>(version) : "no version") + " (" +
                      (renderer ? reinterpret_cast<const char*>(renderer) : "unknown renderer") + ")");
    }
    while (gl.GetError() != GL_NO_ERROR) {
    }
    return gl;
}

void checkGlError(const GlFunctions& gl, const char* what) {
    const GLenum first = gl.GetError();
    if (first == GL_NO_ERROR) return;
    while (gl.GetError() != GL_NO_ERROR) {
    }
    char code[16];
    std::snprintf(code, sizeof code, "0x%04x", unsigned(first));
    const char* name = first == GL_OUT_OF_MEMORY       ? " (out of memory)"
                       : first == GL_INVALID_VALUE     ? " (invalid value)"
                       : first == GL_INVALID_OPERATION ? " (invalid operation)"
                       : first == GL_INVALID_ENUM      ? " (invalid enum)"
                                                       : "";
    throw GlError(std::string("GL: ") + what + ": GL error " + code + name);
}

} // namespace rgvc
