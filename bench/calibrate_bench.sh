#!/usr/bin/env bash
# Benchmark: `mesocap calibrate` with resampling at 512 texels on a default virtual session
# (100 flash shots at 3000x2000 + 15 checkerboard shots), rendered once and kept.
# Target (issue 4): under 2 minutes on 2 cores.
# Usage: bench/calibrate_bench.sh [BUILD_DIR] [SESSION_DIR] [extra calibrate options]
set -euo pipefail
build="${1:-build}"; shift || true
session="${1:-${TMPDIR:-/tmp}/mesocap-bench/session}"; shift || true
bin="$build/app/mesocap"
if [ ! -f "$session/truth.json" ]; then
  echo "calibrate bench: rendering the default session into $session (once)" >&2
  mkdir -p "$(dirname "$session")"
  "$bin" simulate --out "$session" --no-progress >&2
fi
start=$(date +%s.%N)
"$bin" calibrate "$session" --slice-size 512 --no-progress "$@" | tee /dev/stderr >/dev/null
end=$(date +%s.%N)
python3 - "$session" "$start" "$end" <<'PY'
import json, sys
session, start, end = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
wall = end - start
cal = json.load(open(f"{session}/calibration/report.json"))
idx = json.load(open(f"{session}/slices/index.json"))
print(f"calibrate bench: wall {wall:.1f} s (target < 120 s, ratio {wall/120:.2f}); "
      f"calibration {cal['seconds_total']:.1f} s, resampling {idx['seconds_total']:.1f} s "
      f"(summed over threads: read {idx['seconds_read']:.1f} s, sample {idx['seconds_sample']:.1f} s, "
      f"write {idx['seconds_write']:.1f} s); {len(idx['slices'])} slices, {len(idx['skipped'])} skipped")
PY
