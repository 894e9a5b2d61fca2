#!/usr/bin/env bash
# Benchmark (issue 9): peak memory and wall time of `mesocap synth-apply`, a quilting map with
# rotated patches applied to the full 81 x 81 reconstructed BTF at 256x256 (6561 slices, streamed
# slice by slice). Target: peak under 2 GiB. The BTF is the reconstruct bench's out256 (made once,
# with its input set, under WORK_DIR); the map is found by quilting its head-on slice.
# Usage: bench/map_apply_bench.sh [BUILD_DIR] [WORK_DIR] [OUTPUT_SIDE=512]
set -euo pipefail
build="$(realpath "${1:-build}")"
work="${2:-${TMPDIR:-/tmp}/mesocap-reconstruct-bench}"
side="${3:-512}"
bin="$build/app/mesocap"
mkdir -p "$work"
cd "$work"
if [ ! -f set256/index.json ]; then
  echo "map-apply bench: rendering the 13 x 81 input slice set at 256 (once)" >&2
  "$build/bench/bench_make_btf_slice_set" set256 256 weave >&2
fi
if [ ! -f out256/index.json ]; then
  echo "map-apply bench: reconstructing the 81 x 81 BTF at 256 (once, ~10 min on 2 cores)" >&2
  "$bin" reconstruct --slices set256/index.json --out out256 --no-progress >&2
fi
head_on=$(python3 - <<'PY'
import json
index = json.load(open("out256/index.json"))
s = min(index["slices"], key=lambda s: (s["theta_o_deg"], s["theta_i_deg"]))
print("out256/" + s["file"])
PY
)
rm -rf map_quilt applied
"$bin" synth --method quilt --rotations 4 --input "$head_on" --size "${side}x${side}" --seed 1 --out map_quilt --no-progress >&2
/usr/bin/time -f '%M %e' -o apply.time "$bin" synth-apply --map map_quilt/map.exr --input out256 --out applied --no-progress >&2
read -r peak_kib wall < apply.time
python3 - "$peak_kib" "$wall" "$side" <<'PY'
import json, sys
peak_mib = int(sys.argv[1]) / 1024; wall = float(sys.argv[2]); side = int(sys.argv[3])
report = json.load(open("applied/report.json"))
slices = len(json.load(open("applied/index.json"))["slices"])
print(f"map-apply bench: {slices} slices of {side}x{side} from the 256x256 81x81 BTF in {wall:.1f} s wall "
      f"({wall / slices * 1000:.1f} ms/slice incl. EXR writing); peak RSS {peak_mib:.0f} MiB "
      f"(target < 2048 MiB, ratio {peak_mib / 2048:.2f}); report.json memory_peak_mib {report.get('memory_peak_mib')}")
PY
rm -rf applied
