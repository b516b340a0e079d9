// The one error convention of rgvc's public API.
//
// Every public entry point validates its arguments before touching any state. Bad input throws
// rgvc::InvalidInput, whose what() reads "<field>: <what is wrong>" (for example
// "camera.fov_deg: must be in (0, 360], got 400"), and the object it was called on is left exactly as it
// was (strong guarantee). Hot loops (traversal, rasterization) never throw and never allocate per voxel:
// everything they could reject was rejected at the boundary.
#pragma once

#include <stdexcept>
#include <string>

namespace rgvc {

class InvalidInput : public std::invalid_argument {
public:
    InvalidInput(std::string field, const std::string& message)
        : std::invalid_argument(field + ": " + message), m_field(std::move(field)) {}

    /// The offending field, as a path ("camera.direction", "objects[3].radius").
    const std::string& field() const noexcept { return m_field; }

private:
    std::string m_field;
};

} // namespace rgvc
