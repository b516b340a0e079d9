#include "GlProgram.hpp"
#include "rgvc/render/gl/GlProgram.hpp"

#include "rgvc/render/gl/GlError.hpp"

#include <vector>

namespace rgvc::gl_detail {

namespace {

GLuint compile(const GlFunctions& gl, GLenum stage, const char* what, const std::string& source, const std::string& defines) {
    const std::string text = "#version 450 core\n" + defines + source;
    const GLuint shader = gl.CreateShader(stage);
    const char* src = text.c_str();
    gl.ShaderSource(shader, 1, &src, nullptr);
    gl.CompileShader(shader);
    GLint ok = 0;
    gl.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        GLint length = 0;
        gl.GetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
        std::vector<char> log(std::size_t(length > 0 ? length : 1), '\0');
        gl.GetShaderInfoLog(shader, GLsizei(log.size()), nullptr, log.data());
        gl.DeleteShader(shader);
        throw GlError(std::string("GL: ") + what + (stage == GL_VERTEX_SHADER ? " vertex" : " fragment") +
                      " shader does not compile: " + log.data());
    }
    return shader;
}

} // namespace

GLuint linkProgram(const GlFunctions& gl, const char* what, const std::string& vertex, const std::string& fragment,
                   const std::string& defines) {
    const GLuint vs = compile(gl, GL_VERTEX_SHADER, what, vertex, defines);
    GLuint fs = 0;
    try {
        fs = compile(gl, GL_FRAGMENT_SHADER, what, fragment, defines);
    } catch (...) {
        gl.DeleteShader(vs);
        throw;
    }
    const GLuint program = gl.CreateProgram();
    gl.AttachShader(program, vs);
    gl.AttachShader(program, fs);
    gl.LinkProgram(program);
    gl.DeleteShader(vs); // flagged for deletion; freed with the program
    gl.DeleteShader(fs);
    GLint ok = 0;
    gl.GetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        GLint length = 0;
        gl.GetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
        std::vector<char> log(std::size_t(length > 0 ? length : 1), '\0');
        gl.GetProgramInfoLog(program, GLsizei(log.size()), nullptr, log.data());
        gl.DeleteProgram(program);
        throw GlError(std::string("GL: ") + what + " program does not link: " + log.data());
    }
    return program;
}

} // namespace rgvc::gl_detail

namespace rgvc {

GLuint linkGlProgram(const GlFunctions& gl, const char* what, const std::string& vertex, const std::string& fragment,
                     const std::string& defines) {
    return gl_detail::linkProgram(gl, what, vertex, fragment, defines);
}

} // namespace rgvc
