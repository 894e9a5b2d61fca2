#!/usr/bin/env bash
# Installs what mesocap needs, builds it and runs the demo: the virtual rig through every
# working stage, results and a report in one folder (default ./mesocap-demo). README quick start (1).
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-mesocap-demo}"
bash scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)"
./build/app/mesocap demo --out "$out"
