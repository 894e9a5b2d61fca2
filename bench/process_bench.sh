#!/usr/bin/env bash
# Benchmarks of issue 11, on the default virtual session (100 flash shots + 15 checkerboard shots,
# 3000 x 2000, rendered once into WORK_DIR):
#  1. `mesocap process` with its defaults, every stage run: target under 10 minutes on 2 cores;
#  2. the GGX fit of a 256 x 256 material from the 81 x 81 reconstructed slices: target under 60 s.
# Usage: bench/process_bench.sh [BUILD_DIR] [WORK_DIR]
set -euo pipefail
build="${1:-build}"
work="${2:-${TMPDIR:-/tmp}/mesocap-process-bench}"
bin="$build/app/mesocap"
if [ ! -f "$work/rendered/journal.jsonl" ]; then
  echo "process bench: rendering the default session into $work/rendered (once)" >&2
  rm -rf "$work/rendered"
  mkdir -p "$work"
  "$bin" simulate --out "$work/rendered" --no-progress >&2
fi
rm -rf "$work/session" "$work/btf256"
cp -r "$work/rendered" "$work/session"
start=$(date +%s.%N)
"$bin" process "$work/session" --no-progress | tee "$work/process.log"
end=$(date +%s.%N)
"$bin" reconstruct "$work/session" --size 256 --out "$work/btf256" --no-progress
start_fit=$(date +%s.%N)
fit=$("$build/bench/bench_ggx_fit" "$work/btf256/index.json")
end_fit=$(date +%s.%N)
python3 - "$start" "$end" "$start_fit" "$end_fit" "$fit" <<'PY'
import json, sys
s, e, sf, ef = map(float, sys.argv[1:5])
fit = json.loads(sys.argv[5])
print(f"process bench: default 100-shot session in {e - s:.1f} s wall (target < 600 s, ratio {(e - s) / 600:.2f})")
print(f"process bench: GGX fit {fit['width']}x{fit['height']} from {fit['slices_used']} of the 81 x 81 slices in "
      f"{ef - sf:.1f} s wall, {fit['seconds']:.1f} s in the fit (target < 60 s, ratio {(ef - sf) / 60:.2f}); "
      f"median relative error {100 * fit['median_relative_error']:.1f}%, {fit['mean_iterations']:.1f} Ceres iterations a texel")
PY
