// The subcommands of the `rgvc` executable. main.cpp picks one by its first argument and hands it
// the rest.
//
// Calling convention, shared by every subcommand:
// - argv[0] is the subcommand's own name ("cull", "demo"); argv[1..argc-1] are its arguments.
// - Returns the process exit status: 0 success, 2 bad input or bad usage (then exactly one line on
//   stderr and, for commands with a machine-readable answer, nothing on stdout), 1 anything else.
// - May throw; main() turns any escaping exception into one stderr line and status 1, so that the
//   program never ends by std::terminate.
// - `--help` / `-h` print the command's usage on stdout and return 0.
#pragma once

namespace rgvc::cli {

/// `rgvc cull SCENE.json [--frames N] [--dump-objects] [--no-occlusion] [--no-extension]`:
/// one JSON line per frame on stdout (scene-format.md). Defined in CullCommand.cpp.
int runCull(int argc, char** argv);

/// `rgvc demo ...`: the interactive / picture demo. Defined in DemoCommand.cpp (render module).
int runDemo(int argc, char** argv);

} // namespace rgvc::cli
