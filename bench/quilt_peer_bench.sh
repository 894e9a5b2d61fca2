#!/usr/bin/env bash
# Benchmark (issue 9): graphcut quilting of a 512x512 RGB output from a 128x128 sample (the
# virtual weave, head-on, 8-bit sRGB PNG) by `mesocap synth --method quilt`, and, when a command
# for a peer implementation is given, by the peer on the same PNG in the same run; prints the
# ratio. The peer is built by whoever runs this (nothing is fetched here): PEER_CMD is a command
# line with {in} and {out} placeholders, e.g. for a build of frvdecQAQ/graphcut-textures with a
# small driver: "/tmp/peer-graphcut/build/gc_driver {in} {out} 512 512 global 50 0.1 0".
# Usage: bench/quilt_peer_bench.sh [BUILD_DIR] [PEER_CMD] [RUNS=3]
set -euo pipefail
build="$(realpath "${1:-build}")"
peer="${2:-}"
runs="${3:-3}"
work="${TMPDIR:-/tmp}/mesocap-quilt-peer-bench"
rm -rf "$work"
mkdir -p "$work"
"$build/app/mesocap" simulate --true-btf --material weave --theta-i 0 --phi-i 0 --theta-o 0 --phi-o 0 --size 128 \
  --out "$work/weave128.exr" > /dev/null
oiiotool "$work/weave128.exr" --colorconvert linear sRGB -d uint8 -o "$work/weave128.png"

seconds() { /usr/bin/time -f '%e' -o "$work/time" "$@" > /dev/null 2>&1; cat "$work/time"; }
ours=()
for run in $(seq "$runs"); do
  ours+=("$(seconds "$build/app/mesocap" synth --method quilt --input "$work/weave128.png" --size 512x512 --seed "$run" \
    --out "$work/ours$run" --no-progress)")
done
theirs=()
if [ -n "$peer" ]; then
  for run in $(seq "$runs"); do
    cmd="${peer//\{in\}/$work/weave128.png}"
    cmd="${cmd//\{out\}/$work/peer$run}"
    theirs+=("$(seconds bash -c "$cmd")")
  done
fi
python3 - "${ours[*]}" "${theirs[*]:-}" <<'PY'
import statistics, sys
ours = [float(x) for x in sys.argv[1].split()]
theirs = [float(x) for x in sys.argv[2].split()] if sys.argv[2].strip() else []
line = f"quilt peer bench: mesocap quilt 512x512 RGB from 128x128: median {statistics.median(ours):.2f} s wall ({', '.join(f'{x:.2f}' for x in ours)}; target < 3 s)"
if theirs:
    line += (f"; peer median {statistics.median(theirs):.1f} s ({', '.join(f'{x:.1f}' for x in theirs)}); "
             f"mesocap {statistics.median(theirs) / statistics.median(ours):.0f}x faster")
print(line)
PY
