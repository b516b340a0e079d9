// rgvc: the command-line front end. Dispatches to a subcommand (Commands.hpp) and guarantees that no
// exception ends the process by std::terminate: whatever escapes becomes one line on stderr.
#include "Commands.hpp"

#include <rgvc/config.hpp>

#include <cstring>
#include <exception>
#include <iostream>
#include <new>
#include <string>

#ifndef RGVC_VERSION
#define RGVC_VERSION "unknown"
#endif

namespace {

const char* const kUsage =
    "usage: rgvc <command> [arguments]\n"
    "\n"
    "Conservative visibility culling on a regular grid.\n"
    "\n"
    "commands:\n"
    "  cull SCENE.json [--frames N] [--dump-objects] [--no-occlusion] [--no-extension]\n"
    "                  run N frames of a scene file, one JSON line per frame on stdout\n"
    "  demo [...]      the visual demo (see `rgvc demo --help`)\n"
    "  help            this text\n"
    "\n"
    "options:\n"
    "  -h, --help      this text\n"
    "  --version       the version\n"
    "\n"
    "`rgvc <command> --help` describes a command. Exit status: 0 success, 2 bad input or usage\n"
    "(one line on stderr), 1 internal error.\n";

int dispatch(int argc, char** argv) {
    if (argc < 2) {
        std::cerr << "rgvc: missing command (try `rgvc --help`)\n";
        return 2;
    }
    const std::string cmd = argv[1];
    if (cmd == "-h" || cmd == "--help" || cmd == "help") {
        std::cout << kUsage;
        return 0;
    }
    if (cmd == "--version") {
        std::cout << "rgvc " << RGVC_VERSION << " (built for " << RGVC_SIMD_LEVEL << ")\n";
        return 0;
    }
    if (cmd == "cull") return rgvc::cli::runCull(argc - 1, argv + 1);
    if (cmd == "demo") return rgvc::cli::runDemo(argc - 1, argv + 1);
    std::cerr << "rgvc: unknown command '" << cmd << "' (try `rgvc --help`)\n";
    return 2;
}

} // namespace

int main(int argc, char** argv) {
    try {
        return dispatch(argc, argv);
    } catch (const std::bad_alloc&) {
        std::cerr << "rgvc: out of memory\n";
    } catch (const std::exception& e) {
        std::string what = e.what();
        for (char& c : what)
            if (c == '\n' || c == '\r') c = ' ';
        std::cerr << "rgvc: internal error: " << what << "\n";
    } catch (...) {
        std::cerr << "rgvc: internal error: unknown exception\n";
    }
    return 1;
}
