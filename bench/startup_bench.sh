#!/usr/bin/env bash
# Start-up time of the CLI (issue 14: `mesocap --version` and `--help` under 30 ms, median of 10
# warm runs). OpenImageIO is loaded only by an image that needs it (core/image_codec.h); the last
# row times the first image it reads, a PNG, for comparison.
#
#   bench/startup_bench.sh [BUILD_DIR=build] [RUNS=10]
set -euo pipefail
BUILD=${1:-build}
RUNS=${2:-10}
MESOCAP=$BUILD/app/mesocap
[[ -x $MESOCAP ]] || { echo "build the mesocap target in $BUILD first" >&2; exit 2; }

# Median wall time of RUNS runs of a command line, in milliseconds (one warm-up run first).
median_ms() {
  "$@" >/dev/null 2>&1 || true
  local times=()
  for ((r = 0; r < RUNS; r++)); do
    local start=$(date +%s%N)
    "$@" >/dev/null 2>&1 || true
    times+=($((($(date +%s%N) - start) / 1000)))
  done
  printf '%s\n' "${times[@]}" | sort -n | awk '{ t[NR] = $1 } END { m = (NR % 2) ? t[(NR + 1) / 2] : (t[NR / 2] + t[NR / 2 + 1]) / 2; printf "%.1f", m / 1000 }'
}

WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
printf 'P3\n1 1\n255\n128 128 128\n' > "$WORK/grey.ppm"
printf '%-44s %10s\n' "request" "median ms"
for request in "--version" "--help" "fit-ptm --help" "synth --help"; do
  # shellcheck disable=SC2086
  printf '%-44s %10s\n' "$request" "$(median_ms "$MESOCAP" $request)"
done
# A command that reads an image through OpenImageIO: start-up plus loading the module.
printf '%-44s %10s\n' "synth (1x1 .ppm input: loads OpenImageIO)" \
  "$(median_ms "$MESOCAP" synth --method quilt --input "$WORK/grey.ppm" --size 8x8 --out "$WORK/out" --no-progress)"
echo "shared libraries at start: $(ldd "$MESOCAP" | wc -l)"
