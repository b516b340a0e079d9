// RGVC_SIMD=AVX2 (or AUTO on a machine with AVX2) compiles rgvc's own code with -mavx2, so the culler
// may execute AVX2 instructions anywhere, even in static initializers. On a CPU without AVX2 that is a
// SIGILL with no message; this file turns it into one clear line and an abort, before anything else of
// rgvc runs.
//
// Why a constructor of priority 101: the linker orders .init_array entries by priority (101 is the
// first one user code may take, below the default 65535), so this runs before every other static
// initializer of the program, including rgvc's and the application's own. This file is compiled
// without AVX (grid/CMakeLists.txt: -mno-avx -mno-avx2), so the check itself cannot fault.
#include "rgvc/config.hpp"
#include "rgvc/grid/SimdGuard.hpp"

#include <cstdio>
#include <cstdlib>

namespace rgvc::detail {

const int kSimdGuardAnchor = RGVC_SIMD_AVX2;

#if RGVC_SIMD_AVX2 && (defined(__GNUC__) || defined(__clang__)) && (defined(__x86_64__) || defined(__i386__))
namespace {
[[gnu::constructor(101)]] void checkAvx2AtStartUp() {
    __builtin_cpu_init();
    if (!__builtin_cpu_supports("avx2")) {
        std::fputs("rgvc: this build of rgvc was compiled for AVX2 (RGVC_SIMD=" RGVC_SIMD_LEVEL "), but this CPU "
                   "lacks AVX2; rebuild with cmake -DRGVC_SIMD=NONE\n",
                   stderr);
        std::abort();
    }
}
} // namespace
#endif

} // namespace rgvc::detail
