// `rgvc_sim2d`: the command line, and the window and headless loops around a SimApp.
#pragma once

#include "SimApp.hpp"

#include <cstdint>
#include <string>

namespace rgvc::sim {

struct SimOptions {
    std::string scene;           ///< a 2D scene file, or empty with `generate`
    std::string generate;        ///< "city:300", ...
    std::uint64_t seed = 1;
    bool headless = false;
    long frames = -1;            ///< -1: headless 300, window until closed
    long pngEvery = 0;           ///< 0: only the last frame (headless), none (window without --out)
    std::string out;             ///< PNG folder; headless default "sim2d-frames"
    std::string script;
    SimSettings settings;
    bool help = false;
};

/// Bad usage or input: one line on stderr, exit status 2.
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

extern const char* const kUsage;

/// @throws UsageError on an unknown flag or a bad value.
SimOptions parseSimOptions(int argc, char** argv);

/// The world the options ask for. @throws UsageError, SceneError, InvalidInput.
SimWorld loadWorld(const SimOptions& options);

/// Runs the simulator as the options say and prints the summary; returns the exit status.
/// @throws UsageError, SceneError, InvalidInput, GlError, std::runtime_error (a PNG that cannot be written).
int runSim(const SimOptions& options);

} // namespace rgvc::sim
