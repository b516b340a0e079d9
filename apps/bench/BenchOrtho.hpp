// rgvc_bench_views --ortho: occlusion for orthographic views against view-volume culling (BenchOrtho.cpp).
#pragma once

namespace rgvc::bench {

/// Runs the orthographic benchmark; returns the process exit code (1 on a miss).
int runOrthoBench(int frames, int spheres, int seed, int refEvery);

} // namespace rgvc::bench
