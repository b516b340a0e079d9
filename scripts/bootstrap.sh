#!/usr/bin/env bash
# One command from a fresh Debian clone to a result:
#   scripts/bootstrap.sh demo   install dependencies, build, run the headless demo on the default 2D scene
#                               (prints the PVS and its stats, writes rgvc-demo.png)
#   scripts/bootstrap.sh test   install dependencies, build, run the whole test suite (ctest); then the
#                               same suite built with AddressSanitizer + UndefinedBehaviorSanitizer
#                               (build-asan), then a short libFuzzer run of each fuzz target (clang,
#                               build-fuzz; longer runs: scripts/fuzz.sh). Fails when any stage fails.
# Environment: BUILD_DIR (default build), ASAN_BUILD_DIR (default build-asan), FUZZ_BUILD_DIR (default
# build-fuzz), JOBS (default 2), SANITIZE_CTEST_ARGS (extra ctest arguments for the sanitized run, split
# on spaces, e.g. "-E culler3d" to leave out the slowest sweeps; default: the whole suite).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"
mode=${1:-demo}
build=${BUILD_DIR:-build}
jobs=${JOBS:-2}

case "$mode" in
  demo|test) ;;
  *) echo "usage: scripts/bootstrap.sh demo|test" >&2; exit 2 ;;
esac

scripts/install-deps.sh
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release
cmake --build "$build" -j"$jobs"

if [ "$mode" = demo ]; then
  "$build/apps/rgvc" demo scenes/fig1-2d.json --out rgvc-demo.png
else
  cd "$build"
  ctest --output-on-failure -j"$jobs"
  cd "$here"
  echo "bootstrap: release build and tests passed (${SECONDS}s so far)"

  # The whole suite again under ASan + UBSan: any report aborts its test (-fno-sanitize-recover=all).
  # -O1 keeps the sanitized tests fast; assertions stay on (no NDEBUG).
  asan=${ASAN_BUILD_DIR:-build-asan}
  stage_start=$SECONDS
  cmake -S . -B "$asan" -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g1" -DRGVC_SANITIZE=ON
  cmake --build "$asan" -j"$jobs"
  (cd "$asan" &&
    ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:strict_string_checks=1:check_initialization_order=1} \
    UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1} \
    ctest --output-on-failure -j"$jobs" ${SANITIZE_CTEST_ARGS:-})
  echo "bootstrap: sanitized (ASan + UBSan) build and tests passed in $((SECONDS - stage_start))s"

  # libFuzzer smoke runs (clang): only the fuzz targets are built, only the tests labelled "fuzz" run.
  fuzz=${FUZZ_BUILD_DIR:-build-fuzz}
  stage_start=$SECONDS
  cmake -S . -B "$fuzz" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" \
    -DCMAKE_CXX_COMPILER=clang++ -DRGVC_BUILD_FUZZERS=ON
  cmake --build "$fuzz" -j"$jobs" --target fuzz_scene_loader fuzz_culler2d fuzz_culler3d fuzz_mesh_file
  (cd "$fuzz" && ctest -L fuzz --output-on-failure -j"$jobs")
  echo "bootstrap: fuzz smoke tests passed in $((SECONDS - stage_start))s; all stages passed in ${SECONDS}s"
fi
