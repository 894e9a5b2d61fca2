#!/usr/bin/env bash
# fit-ptm speed on the issue's reference case: 36 JPEGs of 2000x1500, RGB PTM, decoding included.
# Usage: bench/fit_ptm_bench.sh [BUILD_DIR=build] [WORK_DIR=/tmp/mesocap_fit_ptm_bench] [RUNS=3] [GRAIN=0]
#   GRAIN=0: smooth synthetic photos (~0.2 MB JPEGs); GRAIN=0.1: photo-like texture and noise
#   (~0.9 MB JPEGs, slower to decode). See bench/make_rti_set.cc.
# Reference: the most used open-source RTI fitter takes ~5.4 s on this folder; the target is 5x
# faster, i.e. under 1.1 s wall for the whole process on 2 cores.
# Wall times on a shared machine are noisy: the summary gives the best and the median run, and
# the CPU time (user + sys), which other load disturbs less.
set -euo pipefail
BUILD=${1:-build}
WORK=${2:-/tmp/mesocap_fit_ptm_bench}
RUNS=${3:-3}
GRAIN=${4:-0}
MESOCAP=$BUILD/app/mesocap
MAKE_SET=$BUILD/bench/bench_make_rti_set
[[ -x $MESOCAP && -x $MAKE_SET ]] || { echo "build mesocap and bench_make_rti_set in $BUILD first" >&2; exit 2; }
SET=$WORK/set
[[ $GRAIN == 0 ]] || SET=$WORK/set_grain$GRAIN
if [[ ! -f $SET/capture.lp ]]; then
  "$MAKE_SET" "$SET" 36 2000 1500 "$GRAIN"
fi
results=$WORK/runs.txt
: > "$results"
for ((r = 1; r <= RUNS; r++)); do
  rm -f "$WORK/out.ptm" "$WORK/out.json"
  # Whole process: wall, user and sys seconds.
  /usr/bin/time -f '%e %U %S' -o "$WORK/time.txt" \
    "$MESOCAP" fit-ptm --lp "$SET/capture.lp" --out "$WORK/out.ptm" --format rgb --no-progress > /dev/null
  read -r wall user sys < "$WORK/time.txt"
  read -r total decode fit write dcpu fcpu wcpu < <(python3 -c "import json,sys; t=json.load(open(sys.argv[1]))['timing']; print(*(t[k] for k in ('total_seconds', 'decode_seconds', 'fit_seconds', 'write_seconds', 'decode_cpu_seconds', 'fit_cpu_seconds', 'write_cpu_seconds')))" "$WORK/out.json")
  printf 'run %d: wall %.3f s (process; cpu %.2f s), in-command %.3f s: decode %.3f s, fit %.3f s, write %.3f s\n' \
    "$r" "$wall" "$(echo "$user + $sys" | bc -l)" "$total" "$decode" "$fit" "$write"
  echo "$wall $user $sys $total $decode $fit $write $dcpu $fcpu $wcpu" >> "$results"
done
python3 - "$results" "$(nproc)" "$SET" <<'PY'
import statistics, sys
runs = [list(map(float, line.split())) for line in open(sys.argv[1]) if line.strip()]
cores, folder = int(sys.argv[2]), sys.argv[3]
mpix_images = 36 * 2000 * 1500 / 1e6
best = min(runs, key=lambda r: r[0])
median_wall = statistics.median(r[0] for r in runs)
wall, user, sys_, total, decode, fit, write, dcpu, fcpu, wcpu = best
print(f"fit-ptm RGB, 36 x 2000x1500 JPEG ({folder}), {cores} cores, {len(runs)} runs:")
print(f"  wall (whole process): best {wall:.3f} s, median {median_wall:.3f} s; "
      f"cpu of best run {user + sys_:.2f} s (user {user:.2f}, sys {sys_:.2f})")
print(f"  {mpix_images / wall:.1f} megapixel-images/s best, {mpix_images / median_wall:.1f} median")
print(f"  best run in-command {total:.3f} s: decode {decode:.3f} s ({100 * decode / total:.0f}%), "
      f"fit {fit:.3f} s, write {write:.3f} s, other {total - decode - fit - write:.3f} s; "
      f"process start/exit {wall - total:.3f} s")
# CPU seconds are steadier than wall on a shared machine. Idle-machine estimate: the serial
# parts (process start + exit, i.e. cpu outside the phases, and the single-threaded write) at
# their cpu time, decode and fit at cpu / cores (both scale across cores).
median_cpu = statistics.median(r[1] + r[2] for r in runs)
other_cpu = user + sys_ - dcpu - fcpu - wcpu
estimate = other_cpu + wcpu + (dcpu + fcpu) / cores
print(f"  cpu of best run: decode {dcpu:.3f} s, fit {fcpu:.3f} s, write {wcpu:.3f} s, "
      f"start/exit and rest {other_cpu:.3f} s; median cpu {median_cpu:.2f} s")
print(f"  idle-machine estimate from cpu: {estimate:.2f} s wall ({5.4 / estimate:.1f}x vs 5.4 s)")
print(f"  vs reference fitter 5.4 s: {5.4 / wall:.2f}x best, {5.4 / median_wall:.2f}x median "
      f"(target: wall < 1.1 s, i.e. >= 4.9x)")
PY
