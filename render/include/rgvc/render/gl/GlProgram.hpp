// Compiling and linking a GLSL 4.50 program on a context's entry-point table, for users of render/gl
// that draw with shaders of their own (the 2D simulator's draw-list renderer, apps/sim2d).
#pragma once

#include "rgvc/render/gl/GlFunctions.hpp"

#include <string>

namespace rgvc {

/// Links a program from vertex and fragment sources (without their #version line: "#version 450 core"
/// is prepended, then `defines`). The context that loaded `gl` must be current.
/// @throws GlError with the driver's compile or link log, naming `what`.
GLuint linkGlProgram(const GlFunctions& gl, const char* what, const std::string& vertex, const std::string& fragment,
                     const std::string& defines = {});

} // namespace rgvc
