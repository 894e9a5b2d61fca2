#!/usr/bin/env bash
# Benchmark: render a default virtual session (100 shots at 3000x2000 + 15 checkerboard shots)
# and report the total and per-shot time. Target (issue 2): under 5 minutes on 2 cores.
# Usage: bench/simulate_bench.sh [BUILD_DIR] [extra simulate options]
set -euo pipefail
build="${1:-build}"; shift || true
bin="$build/app/mesocap"
out="$(mktemp -d)/session"
trap 'rm -rf "$(dirname "$out")"' EXIT
start=$(date +%s.%N)
"$bin" simulate --out "$out" --no-progress "$@" | tee /dev/stderr >/dev/null
end=$(date +%s.%N)
python3 - "$out/simulate_report.json" "$start" "$end" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
wall = float(sys.argv[3]) - float(sys.argv[2])
print(f"simulate bench: wall {wall:.1f} s (target < 300 s, ratio {wall/300:.2f}); "
      f"prepare {r['prepare_s']:.1f} s, {r['per_shot_s']:.2f} s/flash shot, {r['per_calib_shot_s']:.2f} s/checkerboard shot; "
      f"{r['shots_written']} + {r['calib_shots_written']} shots")
PY
