#!/usr/bin/env bash
# Benchmark (issue 12): the statistical BTF's colour by the colour space its histograms are
# matched in (rgb: the paper's; pca; chromaticity: the default), on the three textured virtual
# materials with `mesocap evaluate` at the acceptance test's settings (64x64 texels, 3x3 samples,
# 240 held-out Bonn pairs). Prints per run the share of pairs where the reconstruction beats both
# baselines on pixel and on chromaticity W1, and the 95th-percentile saturation error against
# the truth (median, worst, pairs off by more than 15%). About 9 x 40 s on 2 cores.
# Usage: bench/colour_space_bench.sh [BUILD_DIR] [WORK_DIR]
set -euo pipefail
build="$(realpath "${1:-build}")"
work="${2:-${TMPDIR:-/tmp}/mesocap-colour-bench}"
rm -rf "$work"
mkdir -p "$work"
for material in weave stones corduroy; do
  for space in rgb pca chromaticity; do
    "$build/app/mesocap" evaluate --material "$material" --size 64 --samples-per-axis 3 --pairs 240 \
      --colour-space "$space" --out "$work/$material-$space" --no-progress > /dev/null
    python3 - "$work/$material-$space/evaluation.json" "$material" "$space" <<'PY'
import json, sys
e = json.load(open(sys.argv[1]))
s = e["methods"]["statistical"]
off = sum(abs(p["statistical"]["saturation_ratio"] - 1) > 0.15 for p in e["pairs"])
off_top = sum(abs(p["top_view"]["saturation_ratio"] - 1) > 0.15 for p in e["pairs"])
print(f"colour bench: {sys.argv[2]:8s} {sys.argv[3]:12s} beats both: pixel W1 {100 * e['fraction_beating_both_wasserstein_pixels']:.0f}%, "
      f"chromaticity W1 {100 * e['fraction_beating_both_wasserstein_chromaticity']:.0f}%; median pixel W1 "
      f"{s['median_wasserstein_pixels']:.5f}; saturation p95 off by {100 * s['median_saturation_error']:.1f}% median, "
      f"{100 * s['worst_saturation_error']:.0f}% worst, {off} of {e['held_out_pairs']} pairs > 15% (top view {off_top})")
PY
  done
done
