#!/usr/bin/env bash
# Longer libFuzzer runs of rgvc's fuzz targets (tests/fuzz; ctest runs only a short smoke test of each:
# a fixed count of inputs from a fixed seed). These explore freely: a random seed, the kept corpus.
#
#   scripts/fuzz.sh [TARGET...]            fuzz each target for SECONDS (default: all targets)
#   scripts/fuzz.sh repro TARGET FILE...   replay inputs (a crash-*/timeout-* file from artifacts/) once
#   scripts/fuzz.sh minimize TARGET FILE   shrink a crashing input to a smaller one that still crashes
#
# TARGET: scene_loader (bytes -> parseScene), culler2d or culler3d (bytes -> Culler2D/Culler3D
#         add/update/remove/cull), mesh_file (bytes -> an .obj/.gltf/.glb file -> the mesh's culler shape).
# Environment:
#   SECONDS_PER_TARGET  fuzzing time per target (default 600)
#   FORKS               parallel fuzzing processes per target (libFuzzer -fork; default 1)
#   BUILD_DIR           clang fuzz build (default build-fuzz), configured here when missing
#   RGVC_FUZZ_REFERENCE=1  culler2d/culler3d also check tame frames against the reference (slower; misses
#                       become findings)
# What the fuzzers learn is kept in BUILD_DIR/tests/fuzz/corpus/TARGET (pass it on to later runs);
# findings go to BUILD_DIR/tests/fuzz/artifacts/TARGET-crash-*. To keep a finding as a regression test,
# copy it into tests/fuzz/corpus/TARGET/ once it is fixed: ctest's fuzz_*:seeds test replays that folder.
#
# Examples:
#   scripts/fuzz.sh                                   # all targets, 10 minutes each
#   SECONDS_PER_TARGET=3600 FORKS=2 scripts/fuzz.sh culler2d
#   scripts/fuzz.sh repro culler2d build-fuzz/tests/fuzz/artifacts/culler2d-crash-1234abcd
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"
build=${BUILD_DIR:-build-fuzz}
seconds=${SECONDS_PER_TARGET:-600}
forks=${FORKS:-1}
jobs=${JOBS:-2}

usage() { sed -n '2,23p' "$0" >&2; exit 2; }

flags_for() { # the same flags as the ctest smoke tests (tests/fuzz/CMakeLists.txt)
  local t=$1
  local f=(-timeout=10 -rss_limit_mb=2048 "-artifact_prefix=$build/tests/fuzz/artifacts/$t-")
  if [ "$t" = scene_loader ]; then f+=(-max_len=8192 "-dict=tests/fuzz/scene.dict");
  elif [ "$t" = mesh_file ]; then f+=(-max_len=4096); else f+=(-max_len=1024); fi
  printf '%s\n' "${f[@]}"
}

check_target() {
  case "$1" in scene_loader|culler2d|culler3d|mesh_file) ;; *) echo "fuzz.sh: unknown target '$1' (scene_loader, culler2d, culler3d or mesh_file)" >&2; exit 2 ;; esac
}

build_fuzzers() {
  command -v clang++ >/dev/null || { echo "fuzz.sh: clang++ not found (scripts/install-deps.sh installs it)" >&2; exit 1; }
  if [ ! -f "$build/CMakeCache.txt" ]; then
    # The same configuration as scripts/bootstrap.sh test, so that both can share build-fuzz.
    cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" \
      -DCMAKE_CXX_COMPILER=clang++ -DRGVC_BUILD_FUZZERS=ON
  fi
  cmake --build "$build" -j"$jobs" --target fuzz_scene_loader fuzz_culler2d fuzz_culler3d fuzz_mesh_file
  mkdir -p "$build/tests/fuzz/artifacts"
}

mode=${1:-}
case "$mode" in
  -h|--help) usage ;;
  repro)
    [ $# -ge 3 ] || usage
    check_target "$2"
    build_fuzzers
    mapfile -t flags < <(flags_for "$2")
    exec "$build/tests/fuzz/fuzz_$2" "${flags[@]}" -runs=1 "${@:3}"
    ;;
  minimize)
    [ $# -eq 3 ] || usage
    check_target "$2"
    build_fuzzers
    mapfile -t flags < <(flags_for "$2")
    exec "$build/tests/fuzz/fuzz_$2" "${flags[@]}" -minimize_crash=1 -max_total_time="$seconds" "$3"
    ;;
esac

targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(scene_loader culler2d culler3d mesh_file)
for t in "${targets[@]}"; do check_target "$t"; done
build_fuzzers

status=0
for t in "${targets[@]}"; do
  corpus="$build/tests/fuzz/corpus/$t"
  mkdir -p "$corpus"
  seeds=(tests/fuzz/corpus/"$t")
  [ "$t" = scene_loader ] && seeds+=(scenes)
  mapfile -t flags < <(flags_for "$t")
  extra=()
  [ "$forks" -gt 1 ] && extra+=(-fork="$forks" -ignore_crashes=0)
  echo "fuzz.sh: fuzz_$t for ${seconds}s (corpus $corpus, findings $build/tests/fuzz/artifacts/$t-*)"
  if ! "$build/tests/fuzz/fuzz_$t" "${flags[@]}" "${extra[@]}" -max_total_time="$seconds" -print_final_stats=1 \
       "$corpus" "${seeds[@]}"; then
    echo "fuzz.sh: fuzz_$t found a bug; reproduce with: scripts/fuzz.sh repro $t $build/tests/fuzz/artifacts/$t-<file>" >&2
    status=1
  fi
done
exit $status
