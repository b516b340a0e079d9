// The GL stage's one error: a context that cannot be made or a GL resource that cannot be created.
//
// Thrown with the cause in what(): "OSMesa: width and height must be in [1, 16384], got 0 x 0",
// "GLFW: X11: Failed to open display :99", "GL: shader compile failed: ...". Nothing in render/gl
// crashes or aborts on a missing driver or display; callers catch GlError and report it (the CLI exits 2
// with the message on one line). Bad arguments that are not about GL (an unknown object id, an invalid
// shape) stay rgvc::InvalidInput, as everywhere else in rgvc.
//
// A header of its own, without GL headers, so that code which only reports failures (the CLI) catches
// it without seeing any GL type.
#pragma once

#include <stdexcept>
#include <string>

namespace rgvc {

class GlError : public std::runtime_error {
public:
    explicit GlError(const std::string& message) : std::runtime_error(message) {}
};

} // namespace rgvc
