#!/usr/bin/env bash
# One command from a fresh Debian clone to a result:
#   scripts/bootstrap.sh demo   install dependencies, build, run the headless demo on the default 2D scene
#                               (prints the PVS and its stats, writes rgvc-demo.png)
#   scripts/bootstrap.sh test   install dependencies, build, run the whole test suite (ctest)
# Environment: BUILD_DIR (default build), JOBS (default 2).
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
fi
