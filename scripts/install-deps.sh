#!/usr/bin/env bash
# Installs the Debian packages rgvc needs. Idempotent: packages already present are not reinstalled,
# and apt is not touched at all when nothing is missing.
#
# Usage: scripts/install-deps.sh        (as root, or as a user with sudo)
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libglm-dev                      # vector maths (header-only)
  libopenvdb-dev libboost-iostreams-dev  # sparse grid backend (RGVC_WITH_OPENVDB); its CMake module needs boost-iostreams
  libosmesa6-dev libglfw3-dev     # headless GL 4.5 core (llvmpipe) and windows (RGVC_WITH_GL)
  libgl-dev                       # GL/glcorearb.h, the GL stage's entry-point types
  xvfb xauth                      # the GL window test runs under xvfb-run (fails without it)
  catch2                          # unit tests (v2.13)
  clang libclang-rt-14-dev        # libFuzzer targets (RGVC_BUILD_FUZZERS) and their sanitizer runtimes
  libtbb-dev                      # OpenVDB's threading; parallel benchmarks
  nlohmann-json3-dev              # scene files
  libpng-dev                      # pictures
  libimgui-dev                    # the 2D simulator's panel (Dear ImGui; GLFW + OpenGL3 backends)
  gnuplot-nox                     # the benchmarks' PNG plots, drawn from their CSV
  libtinyobjloader-dev libtinygltf-dev  # mesh loading (OBJ, glTF 2.0)
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if ((${#missing[@]} == 0)); then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  sudo_cmd=(sudo)
fi

echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
echo "install-deps: done"
