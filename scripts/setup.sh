#!/usr/bin/env bash
# Installs every build and test dependency from Debian 12 packages.
# A quick no-op when everything is already there.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config python3
  libembree-dev          # ray tracing kernels (Embree 3)
  libopenmesh-dev        # mesh files, patches and charts (half-edge meshes)
  libopenimageio-dev     # image files in and out, every format it has (a plugin, bake/io)
  libpng-dev             # tests write PNG files as another tool would
  openimageio-tools      # maketx (a test's .tx), idiff/oiiotool for looking at failed image tests
  python3-numpy python3-openimageio  # bench/*.py (bench only)
  python3-pip            # PyPI's pyoidn (Open Image Denoise) into the build tree (scripts/install-pypi.sh)
  libtbb-dev             # parallel loops
  libglm-dev             # vector maths
  libtomlplusplus-dev    # the native scene format (TOML, with source positions)
  nlohmann-json3-dev     # bake manifests and render reports
  libtinygltf-dev libstb-dev  # glTF 2.0 in and out (stb: only the tests' independent image writer)
  libcli11-dev           # the command line
  libglfw3-dev libosmesa6-dev python3-glad libimgui-dev  # the viewer
  libgtest-dev libgmock-dev libbenchmark-dev xvfb xauth  # tests and benchmarks
  xdotool                # the window tests send real key and mouse events
  strace                 # the install test: no file of the source tree is opened
  chromium               # the export's three.js check (tests/web), headless
  blender                # Blender 3.4: scenes made in Blender, Cycles references (tests/blender)
)
# Node and npm run the glTF validator and the three.js check (npm packages into build/npm, by
# scripts/test.sh). Debian's only where the commands are missing: a machine may have Node from
# elsewhere, whose npm is built in and conflicts with Debian's npm package.
command -v node > /dev/null || packages+=(nodejs)
command -v npm > /dev/null || packages+=(npm)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  exit 0
fi

sudo=""
if [[ $(id -u) -ne 0 ]]; then sudo="sudo"; fi
echo "setup: installing ${missing[*]}"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
