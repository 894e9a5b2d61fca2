#!/usr/bin/env bash
# Installs what mesocap needs, builds it and runs every test (ctest). README quick start (2).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DMESOCAP_WERROR=ON >/dev/null
cmake --build build -j"$(nproc)"
cd build
ctest -j"$(nproc)" --output-on-failure --timeout 900
