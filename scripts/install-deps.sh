#!/usr/bin/env bash
# Installs every Debian 12 package mesocap builds, tests or benchmarks with.
# Both README quick-start commands call this; it is idempotent and quiet when all is present.
set -euo pipefail

packages=(
  build-essential cmake pkg-config git ca-certificates
  libopencv-dev libopencv-contrib-dev libceres-dev libeigen3-dev
  libgphoto2-dev libexif-dev dpkg-dev
  libopenimageio-dev openimageio-tools libopenexr-dev libjpeg62-turbo-dev
  libapriltag-dev
  libtbb-dev libcli11-dev nlohmann-json3-dev libspdlog-dev libfftw3-dev
  libmaxflow-dev libcgal-dev libxxhash-dev libtinygltf-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libpng-dev  # the Resynthesizer peer's driver (bench/resynth_peer/build.sh)
  ccache  # every build compiles through it (CMakeLists.txt)
  chromium  # the report page's viewer is tested in it, headless (tests/e2e/process_test)
  ninja-build clang libclang-rt-14-dev  # sanitizer builds and libFuzzer targets (scripts/sanitize.sh, fuzz.sh)
  libassimp-dev libembree-dev  # mesh files and ray casting for decorate and render (mesh/mesh_backend_module.cc)
  libcpp-httplib-dev  # the capture console's web server (app/console_server.cc)
  python3-websocket  # drives the console's page in Chromium over DevTools (scripts/console_browser.py)
  snakemake slurm-wlm munge  # the workflow over many sessions, and its one-node Slurm test (scripts/slurm-test.sh)
)

# Node.js and npm for the glTF validator: Debian's, unless the machine already has an npm (e.g.
# NodeSource's nodejs, which conflicts with Debian's npm package).
command -v npm >/dev/null || packages+=(nodejs npm)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  # A fresh machine needs about 2 minutes here: say what happens, and let apt show its progress
  # (one line per package unpacked and set up) rather than stay silent.
  echo "install-deps: ${#missing[@]} packages to install: ${missing[*]}"
  SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  echo "install-deps: [1/2] apt-get update"
  $SUDO apt-get update -q | { grep -v -E '^(Hit|Get|Ign|Reading)' || true; }
  echo "install-deps: [2/2] apt-get install (downloading, then unpacking and setting up each package)"
  $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}" |
    { grep --line-buffered -E '^(Need to get|After this operation|Fetched|Unpacking|Setting up) ' | sed -u 's/^/  /' || true; }
  echo "install-deps: done"
fi

# The Khronos glTF validator (the glTF export's tests run it): from the npm registry, pinned.
GLTF_VALIDATOR_VERSION=2.0.0-dev.3.10
if ! [ -f "$(npm root -g 2>/dev/null)/gltf-validator/package.json" ] ||
   ! grep -q "\"version\": \"$GLTF_VALIDATOR_VERSION\"" "$(npm root -g)/gltf-validator/package.json"; then
  echo "install-deps: npm install -g gltf-validator@$GLTF_VALIDATOR_VERSION"
  npm install -g --no-audit --no-fund "gltf-validator@$GLTF_VALIDATOR_VERSION" | sed -u 's/^/  /'
fi
