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
  libmaxflow-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  ninja-build clang libclang-rt-14-dev  # sanitizer builds and libFuzzer targets (scripts/sanitize.sh, fuzz.sh)
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "install-deps: installing ${missing[*]}"
  SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
