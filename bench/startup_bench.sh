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

# Median wall time of RUNS runs of a command line, in milliseconds (one warm-up run first): the
# time from spawning the process to reaping it (Python's perf_counter around subprocess.run; no
# shell or `date` process inside the interval).
median_ms() {
  python3 - "$RUNS" "$@" <<'PY'
import statistics, subprocess, sys, time
runs, command = int(sys.argv[1]), sys.argv[2:]
quiet = dict(stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
subprocess.run(command, **quiet)
times = []
for _ in range(runs):
    start = time.perf_counter()
    subprocess.run(command, **quiet)
    times.append(time.perf_counter() - start)
print(f"{1000 * statistics.median(times):.1f}")
PY
}

WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
printf 'P3\n1 1\n255\n128 128 128\n' > "$WORK/grey.ppm"
printf '%-44s %10s\n' "request" "median ms"
printf '%-44s %10s\n' "(/bin/true: the cost of spawning a process)" "$(median_ms /bin/true)"
for request in "--version" "--help" "fit-ptm --help" "synth --help"; do
  # shellcheck disable=SC2086
  printf '%-44s %10s\n' "$request" "$(median_ms "$MESOCAP" $request)"
done
# A command that reads an image through OpenImageIO: start-up plus loading the module.
printf '%-44s %10s\n' "synth (1x1 .ppm input: loads OpenImageIO)" \
  "$(median_ms "$MESOCAP" synth --method quilt --input "$WORK/grey.ppm" --size 8x8 --out "$WORK/out" --no-progress)"
echo "shared libraries at start: $(ldd "$MESOCAP" | wc -l)"
