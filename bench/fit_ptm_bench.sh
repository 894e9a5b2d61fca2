#!/usr/bin/env bash
# fit-ptm against its decode limit and against relight-cli (CNR-ISTI relight), in the same run, on
# issue 14's case: 36 JPEGs of 2000x1500, RGB PTM.
#
#   bench/fit_ptm_bench.sh [BUILD_DIR=build] [WORK_DIR=/tmp/mesocap_fit_ptm_bench] [RUNS=5] [GRAIN=0.1] [RELIGHT_CLI]
#
# GRAIN=0.1: photo-like texture and sensor noise (~0.9 MB JPEGs, the issue's case); GRAIN=0: smooth
# synthetic photos (~0.2 MB, faster to decode). See bench/make_rti_set.cc. Nothing is fetched:
# RELIGHT_CLI is the path of a relight-cli you built (github.com/cnr-isti-vclab/relight); without
# it that column is left out. relight-cli runs as `relight-cli -b ptm -p 18 -I srgb FOLDER OUT.ptm`
# (RGB PTM of the stored sRGB values, as `mesocap fit-ptm --format rgb` fits them).
# Printed: medians of RUNS runs (wall clock of the whole process), and the ratios the issue asks
# for: fit-ptm / decode limit (target <= 1.5) and relight-cli / fit-ptm (target >= 10).
set -euo pipefail
BUILD=${1:-build}
WORK=${2:-/tmp/mesocap_fit_ptm_bench}
RUNS=${3:-5}
GRAIN=${4:-0.1}
RELIGHT=${5:-}
MESOCAP=$BUILD/app/mesocap
MAKE_SET=$BUILD/bench/bench_make_rti_set
DECODE=$BUILD/bench/bench_decode_jpegs
[[ -x $MESOCAP && -x $MAKE_SET && -x $DECODE ]] || { echo "build mesocap, bench_make_rti_set and bench_decode_jpegs in $BUILD first" >&2; exit 2; }
SET=$WORK/set
[[ $GRAIN == 0 ]] || SET=$WORK/set_grain$GRAIN
[[ -f $SET/capture.lp ]] || "$MAKE_SET" "$SET" 36 2000 1500 "$GRAIN"

median() { sort -n | awk '{ t[NR] = $1 } END { print (NR % 2) ? t[(NR + 1) / 2] : (t[NR / 2] + t[NR / 2 + 1]) / 2 }'; }
# Wall seconds of one run of a command (output discarded); the output file is removed first so
# every run writes a new file.
wall() {
  local out=$1; shift
  rm -rf "$out"
  /usr/bin/time -f '%e' -o "$WORK/time.txt" "$@" > /dev/null 2>&1
  cat "$WORK/time.txt"
}

decode_line=$("$DECODE" "$SET/capture.lp" "$RUNS")
decode=$(echo "$decode_line" | sed -E 's/.*median ([0-9.]+) s.*/\1/')
fit_times=() relight_times=()
for ((r = 1; r <= RUNS; r++)); do
  fit_times+=("$(wall "$WORK/out.ptm" "$MESOCAP" fit-ptm --lp "$SET/capture.lp" --out "$WORK/out.ptm" --format rgb --no-progress)")
  if [[ -n $RELIGHT ]]; then
    relight_times+=("$(wall "$WORK/relight.ptm" "$RELIGHT" -b ptm -p 18 -I srgb "$SET" "$WORK/relight.ptm")")
  fi
done
fit=$(printf '%s\n' "${fit_times[@]}" | median)
echo "36 x 2000x1500 JPEG ($SET), RGB PTM, $(nproc) cores, medians of $RUNS runs:"
echo "  $decode_line"
echo "  mesocap fit-ptm: $fit s (runs: ${fit_times[*]}); in-command split of the last run:"
python3 -c "import json,sys; t=json.load(open(sys.argv[1]))['timing']; print('    decode %.3f s, fit %.3f s, write %.3f s, total %.3f s' % tuple(t[k] for k in ('decode_seconds','fit_seconds','write_seconds','total_seconds')))" "$WORK/out.json"
echo "  fit-ptm / decode limit: $(echo "scale=2; $fit / $decode" | bc) (target <= 1.5)"
if [[ -n $RELIGHT ]]; then
  relight=$(printf '%s\n' "${relight_times[@]}" | median)
  echo "  relight-cli -b ptm: $relight s (runs: ${relight_times[*]})"
  echo "  relight-cli / fit-ptm: $(echo "scale=1; $relight / $fit" | bc)x (target >= 10)"
fi
