#!/usr/bin/env bash
# Where a calibrated session's colour turns grey (issue 12, docs/reconstruction.md "The white
# specular lobe"): the same hand-held shots stored four ways, each calibrated and evaluated alike.
#
#   bench/shot_encoding_bench.sh [BUILD_DIR=build] MATERIAL SEED [SHOTS=70] [WORK=/tmp/mesocap_shot_encoding]
#
# Renders one session as 16-bit linear PNG (`mesocap simulate --format png`), copies it with its
# shots re-encoded by oiiotool as 8-bit sRGB PNG, JPEG quality 95 with full-resolution colour
# (4:4:4) and JPEG 95 with half-resolution colour (4:2:0, as the rig's own JPEG shots), calibrates
# each with the rig's true camera and layout, and renders true slices at the PNG session's lights
# and views (bench_true_session_slices). Prints, per encoding: the top board's slices' red
# chromaticity less the true slice's (median by the light's elevation), and what `mesocap
# evaluate` fits and scores (white lobe, body colour, pairs whose 95th-percentile saturation is off
# by more than 15%, shares beating both baselines). About 13 minutes for 70 shots on 2 cores, 6 of
# them rendering, which a rerun with the same arguments skips.
set -euo pipefail
BUILD=${1:-build}
MATERIAL=${2:?material}
SEED=${3:?seed}
SHOTS=${4:-70}
WORK=${5:-/tmp/mesocap_shot_encoding}
MESOCAP=$BUILD/app/mesocap
TRUE_SLICES=$BUILD/bench/bench_true_session_slices
[[ -x $MESOCAP && -x $TRUE_SLICES ]] || { echo "build mesocap and bench_true_session_slices in $BUILD first" >&2; exit 2; }
command -v oiiotool > /dev/null || { echo "oiiotool (openimageio-tools) is needed" >&2; exit 2; }
PNG=$WORK/png16
# The rendering (about 6 minutes for 70 shots) is kept for a rerun with the same arguments.
RENDERED="$MATERIAL $SEED $SHOTS"
if [[ $(cat "$WORK/rendered.txt" 2> /dev/null) != "$RENDERED" ]]; then
  rm -rf "$WORK"
  mkdir -p "$WORK"
  echo "rendering $SHOTS shots of $MATERIAL, seed $SEED, as 16-bit linear PNG"
  "$MESOCAP" simulate --out "$PNG" --material "$MATERIAL" --seed "$SEED" --shots "$SHOTS" --calib-shots 0 \
    --width 3000 --height 2000 --format png --no-progress > "$WORK/simulate.log"
  echo "$RENDERED" > "$WORK/rendered.txt"
fi
rm -rf "$PNG"/{calibration,slices} "$WORK"/{png8,jpg444,jpg420,true} "$WORK"/*.eval

# A copy of the PNG session whose shots are re-encoded (extension $2, oiiotool options after it).
encode() {
  local name=$1 ext=$2
  shift 2
  local out=$WORK/$name
  mkdir -p "$out/shots"
  for f in "$PNG"/*; do [[ $(basename "$f") == shots ]] || cp -r "$f" "$out/"; done
  sed "s/\.png\"/.$ext\"/g" "$PNG/journal.jsonl" > "$out/journal.jsonl"
  find "$PNG/shots" -name '*.png' -print0 |
    xargs -0 -P "$(nproc)" -I{} sh -c 'shot=$1 ext=$2; shift 2
      oiiotool "$shot" --iscolorspace linear --tocolorspace sRGB -d uint8 "$@" -o "$0/$(basename "$shot" .png).$ext"' \
      "$out/shots" {} "$ext" "$@"
}
echo "re-encoding the shots"
encode png8 png
encode jpg444 jpg --attrib Compression jpeg:95 --attrib jpeg:subsampling 4:4:4
encode jpg420 jpg --attrib Compression jpeg:95 --attrib jpeg:subsampling 4:2:0

ENCODINGS=(png16 png8 jpg444 jpg420)
for name in "${ENCODINGS[@]}"; do
  echo "calibrating $name"
  "$MESOCAP" calibrate "$WORK/$name" --camera "$PNG/truth.json" --layout "$PNG/rig_layout.json" --slice-size 128 \
    --no-progress > "$WORK/$name.calibrate.log"
done
echo "rendering true slices at the session's lights"
"$TRUE_SLICES" "$WORK/png16" "$WORK/true" > "$WORK/true.log"
for name in "${ENCODINGS[@]}" true; do
  "$MESOCAP" evaluate --session "$WORK/$name" --size 64 --pairs 240 --out "$WORK/$name.eval" --no-progress \
    > "$WORK/$name.evaluate.log"
done

python3 - "$WORK" "${ENCODINGS[@]}" <<'EOF'
import functools, json, re, statistics, subprocess, sys
work, names = sys.argv[1], sys.argv[2:]

@functools.lru_cache(maxsize=None)  # each true slice is compared with every encoding's
def mean_rgb(path):
    out = subprocess.run(['oiiotool', '--stats', path], capture_output=True, text=True, check=True).stdout
    return [float(v) for v in re.search(r'Stats Avg: (\S+) (\S+) (\S+)', out).groups()]

def red(rgb):
    return rgb[0] / sum(rgb)

def slices(name):
    with open(f'{work}/{name}/slices/index.json') as f:
        return {s['file']: s for s in json.load(f)['slices']}

def top_board(index):  # the board seen nearest head-on
    views = {}
    for s in index.values():
        views.setdefault(s['board'], []).append(s['theta_o_deg'])
    return min(views, key=lambda b: statistics.median(views[b]))

truth = slices('true')
bins = [(0, 20), (20, 40), (40, 60), (60, 90)]
print('\nred chromaticity less the true slice\'s, top board, median by light elevation '
      + ' / '.join(f'{a}-{b}' for a, b in bins) + ' deg; then evaluate:')
rows = names + ['true']
for name in rows:
    with open(f'{work}/{name}.eval/evaluation.json') as f:
        e = json.load(f)
    cells = []
    if name != 'true':
        index = slices(name)
        top = top_board(index)
        shifts = {b: [] for b in bins}
        for file, s in index.items():
            if s['board'] != top or file not in truth:
                continue
            for b in bins:
                if b[0] <= s['theta_i_deg'] < b[1]:
                    shifts[b].append(red(mean_rgb(f'{work}/{name}/slices/{file}')) - red(mean_rgb(f'{work}/true/slices/{file}')))
        cells = [f'{statistics.median(v):+.4f}' if v else '-' for v in shifts.values()]
    off = [abs(p['statistical']['saturation_ratio'] - 1) for p in e['pairs']]
    lobe = e['white_lobe']
    print(f'  {name:7s} {" / ".join(cells) if cells else "(the truth)":40s} body red {lobe["body_chromaticity"][0]:.4f}, '
          f'lobe {lobe["strength"]:.2f}, saturation off > 15% on {sum(o > 0.15 for o in off)} of {len(off)} pairs, '
          f'beats both: pixels {100 * e["fraction_beating_both_wasserstein_pixels"]:.1f}%, '
          f'chromaticity {100 * e["fraction_beating_both_wasserstein_chromaticity"]:.1f}%')
EOF
