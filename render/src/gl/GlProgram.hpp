// Internal: compiling and linking GLSL programs, failures as GlError with the driver's log.
#pragma once

#include "rgvc/render/gl/GlFunctions.hpp"

#include <string>

namespace rgvc::gl_detail {

/// Links a program from vertex and fragment sources; `defines` ("#define X 1\n"...) goes after the
/// #version line of both. @throws GlError with the compile or link log, naming `what`.
GLuint linkProgram(const GlFunctions& gl, const char* what, const std::string& vertex, const std::string& fragment,
                   const std::string& defines);

} // namespace rgvc::gl_detail
