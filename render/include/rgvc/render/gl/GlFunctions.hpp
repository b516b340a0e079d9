// The one table of GL entry points that render/gl calls, loaded from the current context.
//
// Why a table and not direct calls: libOSMesa and libGL (GLVND, which GLFW's GLX context goes through)
// both export every gl* symbol. A binary that links both, or links one and runs with the other's context
// current, would call whichever library the dynamic linker bound first, which is not necessarily the one
// that owns the current context (OSMesa's glClear on a GLX context is undefined behaviour, and the other
// way round). Entry points fetched through the context's own OSMesaGetProcAddress / glfwGetProcAddress
// always belong to that context's driver, so render/gl never names a gl* function directly: it calls
// `gl.Clear(...)` on the table its context loaded.
//
// Why no loader library (glad, epoxy, GLEW): Debian 12 ships libepoxy and GLEW, and both find entry points
// through GLX or EGL only. libepoxy asks which of the two owns the current context and, when neither does
// (an OSMesa context is neither), exits the process with "Couldn't find current GLX or EGL context"
// (anholt/libepoxy issues #36, #163): a crash where we promise a GlError. Debian's GLEW is its GLX build
// (glXGetProcAddressARB), which resolves against libGL, the wrong library by the reasoning above. glad
// (generated code, not packaged in Debian) would work with any get-proc function but adds a generator
// step for the ~70 functions below.
// The X-macro list below is that generator, in 100 lines.
//
// The PFN types come from Khronos' <GL/glcorearb.h> (core profile only, no prototypes since
// GL_GLEXT_PROTOTYPES is not defined), so a call with the wrong argument types does not compile.
#pragma once

#include <GL/glcorearb.h>

#include <functional>
#include <string>

namespace rgvc {

// X(PFN type, member name, GL name without the "gl" prefix). Every entry must be present in a GL 4.5
// core context; a new call joins by adding a line.
#define RGVC_GL_FUNCTIONS(X)                                                                                 \
    X(PFNGLGETSTRINGPROC, GetString)                                                                         \
    X(PFNGLGETSTRINGIPROC, GetStringi)                                                                       \
    X(PFNGLGETINTEGERVPROC, GetIntegerv)                                                                     \
    X(PFNGLGETERRORPROC, GetError)                                                                           \
    X(PFNGLVIEWPORTPROC, Viewport)                                                                           \
    X(PFNGLCLEARPROC, Clear)                                                                                 \
    X(PFNGLCLEARCOLORPROC, ClearColor)                                                                       \
    X(PFNGLCLEARDEPTHPROC, ClearDepth)                                                                       \
    X(PFNGLCLEARBUFFERUIVPROC, ClearBufferuiv)                                                               \
    X(PFNGLCLEARBUFFERFVPROC, ClearBufferfv)                                                                 \
    X(PFNGLENABLEPROC, Enable)                                                                               \
    X(PFNGLDISABLEPROC, Disable)                                                                             \
    X(PFNGLCULLFACEPROC, CullFace)                                                                           \
    X(PFNGLFRONTFACEPROC, FrontFace)                                                                         \
    X(PFNGLDEPTHFUNCPROC, DepthFunc)                                                                         \
    X(PFNGLDEPTHMASKPROC, DepthMask)                                                                         \
    X(PFNGLCOLORMASKPROC, ColorMask)                                                                         \
    X(PFNGLPOLYGONOFFSETPROC, PolygonOffset)                                                                 \
    X(PFNGLCLIPCONTROLPROC, ClipControl)                                                                     \
    X(PFNGLFINISHPROC, Finish)                                                                               \
    X(PFNGLFLUSHPROC, Flush)                                                                                 \
    X(PFNGLREADPIXELSPROC, ReadPixels)                                                                       \
    X(PFNGLPIXELSTOREIPROC, PixelStorei)                                                                     \
    X(PFNGLGENBUFFERSPROC, GenBuffers)                                                                       \
    X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                                                                 \
    X(PFNGLBINDBUFFERPROC, BindBuffer)                                                                       \
    X(PFNGLBINDBUFFERBASEPROC, BindBufferBase)                                                               \
    X(PFNGLBUFFERDATAPROC, BufferData)                                                                       \
    X(PFNGLBUFFERSUBDATAPROC, BufferSubData)                                                                 \
    X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays)                                                             \
    X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays)                                                       \
    X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                                                             \
    X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray)                                             \
    X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer)                                                     \
    X(PFNGLVERTEXATTRIBIPOINTERPROC, VertexAttribIPointer)                                                   \
    X(PFNGLVERTEXATTRIBDIVISORPROC, VertexAttribDivisor)                                                     \
    X(PFNGLCREATESHADERPROC, CreateShader)                                                                   \
    X(PFNGLSHADERSOURCEPROC, ShaderSource)                                                                   \
    X(PFNGLCOMPILESHADERPROC, CompileShader)                                                                 \
    X(PFNGLGETSHADERIVPROC, GetShaderiv)                                                                     \
    X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)                                                           \
    X(PFNGLDELETESHADERPROC, DeleteShader)                                                                   \
    X(PFNGLCREATEPROGRAMPROC, CreateProgram)                                                                 \
    X(PFNGLATTACHSHADERPROC, AttachShader)                                                                   \
    X(PFNGLLINKPROGRAMPROC, LinkProgram)                                                                     \
    X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                                                                   \
    X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)                                                         \
    X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                                                                 \
    X(PFNGLUSEPROGRAMPROC, UseProgram)                                                                       \
    X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)                                                       \
    X(PFNGLUNIFORMMATRIX4FVPROC, UniformMatrix4fv)                                                           \
    X(PFNGLUNIFORM3FPROC, Uniform3f)                                                                         \
    X(PFNGLUNIFORM1FPROC, Uniform1f)                                                                         \
    X(PFNGLDRAWELEMENTSINSTANCEDBASEVERTEXBASEINSTANCEPROC, DrawElementsInstancedBaseVertexBaseInstance)     \
    X(PFNGLMULTIDRAWELEMENTSINDIRECTPROC, MultiDrawElementsIndirect)                                         \
    X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers)                                                             \
    X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)                                                       \
    X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                                                             \
    X(PFNGLGENRENDERBUFFERSPROC, GenRenderbuffers)                                                           \
    X(PFNGLDELETERENDERBUFFERSPROC, DeleteRenderbuffers)                                                     \
    X(PFNGLBINDRENDERBUFFERPROC, BindRenderbuffer)                                                           \
    X(PFNGLRENDERBUFFERSTORAGEPROC, RenderbufferStorage)                                                     \
    X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, FramebufferRenderbuffer)                                             \
    X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus)                                               \
    X(PFNGLDRAWBUFFERSPROC, DrawBuffers)                                                                     \
    X(PFNGLREADBUFFERPROC, ReadBuffer)                                                                       \
    X(PFNGLGENQUERIESPROC, GenQueries)                                                                       \
    X(PFNGLDELETEQUERIESPROC, DeleteQueries)                                                                 \
    X(PFNGLBEGINQUERYPROC, BeginQuery)                                                                       \
    X(PFNGLENDQUERYPROC, EndQuery)                                                                           \
    X(PFNGLGETQUERYOBJECTUIVPROC, GetQueryObjectuiv)                                                         \
    X(PFNGLGETQUERYOBJECTUI64VPROC, GetQueryObjectui64v)                                                     \
    /* Textures, blending and scissoring: the 2D simulator's draw-list renderer (apps/sim2d). */             \
    X(PFNGLGENTEXTURESPROC, GenTextures)                                                                     \
    X(PFNGLDELETETEXTURESPROC, DeleteTextures)                                                               \
    X(PFNGLBINDTEXTUREPROC, BindTexture)                                                                     \
    X(PFNGLACTIVETEXTUREPROC, ActiveTexture)                                                                 \
    X(PFNGLTEXIMAGE2DPROC, TexImage2D)                                                                       \
    X(PFNGLTEXSUBIMAGE2DPROC, TexSubImage2D)                                                                 \
    X(PFNGLTEXPARAMETERIPROC, TexParameteri)                                                                 \
    X(PFNGLBLENDEQUATIONPROC, BlendEquation)                                                                 \
    X(PFNGLBLENDFUNCSEPARATEPROC, BlendFuncSeparate)                                                         \
    X(PFNGLSCISSORPROC, Scissor)                                                                             \
    X(PFNGLUNIFORM1IPROC, Uniform1i)                                                                         \
    X(PFNGLDRAWELEMENTSBASEVERTEXPROC, DrawElementsBaseVertex)

/// GL entry points of one context. Members are named after the GL function without its "gl" prefix.
/// [Limit] valid only while the context that loaded them exists, and called only while it is current.
struct GlFunctions {
#define RGVC_GL_MEMBER(type, name) type name = nullptr;
    RGVC_GL_FUNCTIONS(RGVC_GL_MEMBER)
#undef RGVC_GL_MEMBER

    /// Number of entries in the table (for tests and diagnostics).
    static int count();
    /// The GL name ("glClear") of entry `index`, and whether it is loaded. [Limit] 0 <= index < count().
    static const char* name(int index);
    bool loaded(int index) const;
};

/// Address of a GL function by its full name ("glClear"), as the current context's driver gives it.
using GlProcLookup = std::function<void*(const char* name)>;

/// Loads every entry of the table through `lookup` (the context must be current), then checks that the
/// context is GL 4.5 or later. `api` names the lookup in errors ("OSMesa", "GLFW").
/// @throws GlError naming the first missing entry point, or the version found when it is below 4.5.
GlFunctions loadGlFunctions(const GlProcLookup& lookup, const std::string& api);

/// Throws GlError("<what>: GL error 0x0502") when glGetError reports an error (and drains the queue).
void checkGlError(const GlFunctions& gl, const char* what);

} // namespace rgvc
