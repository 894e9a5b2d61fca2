#!/usr/bin/env bash
# Start-up time of the CLI (issue 14: `mesocap --version` and `--help` under 30 ms, median of 10
# warm runs). Times the `mesocap` launcher (app/launcher.cc) and, for comparison, the same
# requests sent straight to mesocap-commands, which loads every library the commands need.
#
#   bench/startup_bench.sh [BUILD_DIR=build] [RUNS=10]
set -euo pipefail
BUILD=${1:-build}
RUNS=${2:-10}
APP=$BUILD/app
[[ -x $APP/mesocap && -x $APP/mesocap-commands ]] || { echo "build the mesocap target in $BUILD first" >&2; exit 2; }

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

printf '%-34s %10s %18s %8s\n' "request" "mesocap ms" "mesocap-commands ms" "ratio"
for request in "--version" "--help" "fit-ptm --help" "synth --help"; do
  # shellcheck disable=SC2086
  launcher=$(median_ms "$APP/mesocap" $request)
  # shellcheck disable=SC2086
  direct=$(median_ms "$APP/mesocap-commands" $request)
  printf '%-34s %10s %18s %8s\n' "$request" "$launcher" "$direct" "$(echo "scale=1; $direct / $launcher" | bc)"
done
echo "shared libraries loaded: mesocap $(ldd "$APP/mesocap" | wc -l), mesocap-commands $(ldd "$APP/mesocap-commands" | wc -l)"
