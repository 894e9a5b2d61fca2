#!/usr/bin/env bash
# Issue 12's account on calibrated sessions: the statistical BTF reconstructed from what a
# session's photos give after calibration (JPEG shots, noise, estimated poses, flash positions
# and power, resampled slices), scored on 240 held-out Bonn pairs against the material's true
# BTF (`mesocap evaluate --session`), next to the same session's geometry with true slices at the
# true lights (bench_session_coverage: what coverage alone allows). Sessions are kept in WORK, so
# a second run only scores.
#
#   bench/calibrated_session_bench.sh [BUILD_DIR=build] [WORK=/tmp/mesocap_calibrated_sessions]
#                                     [SHOTS=100] [MATERIALS=weave,stones,corduroy] [SEEDS=21,22]
#                                     [SIZE=64] [WIDTH=3000] [HEIGHT=2000] [FORMAT=jpg]
# At 3000x2000 a 60 deg board's patch spans about 115 pixels up its slope: SIZE above 64 scores
# the camera's blur more than the reconstruction. FORMAT png (16-bit linear shots) shows what the
# JPEGs' 8 bits and halved chroma resolution cost.
# EVALUATE_ARGS (environment) is passed to every `mesocap evaluate`, e.g. "--linear-from-top-view"
# for the paper's view blend next to the default.
set -euo pipefail
BUILD=${1:-build}
WORK=${2:-/tmp/mesocap_calibrated_sessions}
IFS=, read -ra SHOTS <<< "${3:-100}"
IFS=, read -ra MATERIALS <<< "${4:-weave,stones,corduroy}"
IFS=, read -ra SEEDS <<< "${5:-21,22}"
SIZE=${6:-64}
WIDTH=${7:-3000}
HEIGHT=${8:-2000}
FORMAT=${9:-jpg}
MESOCAP=$BUILD/app/mesocap
COVERAGE=$BUILD/bench/bench_session_coverage
[[ -x $MESOCAP && -x $COVERAGE ]] || { echo "build the mesocap and bench_session_coverage targets in $BUILD first" >&2; exit 2; }
mkdir -p "$WORK"

printf '%-9s %5s %4s | calibrated: beats both  all inside  near   far | pairs in/near/far | median W1 st / top | chroma wins | sat. off med / worst | true slices: all\n' \
  material shots seed
for material in "${MATERIALS[@]}"; do
  for shots in "${SHOTS[@]}"; do
    for seed in "${SEEDS[@]}"; do
      session=$WORK/$material-$shots-$seed-${WIDTH}x$HEIGHT-$FORMAT
      if [[ ! -f $session/slices/index.json ]]; then
        rm -rf "$session"
        "$MESOCAP" simulate --out "$session" --material "$material" --shots "$shots" --seed "$seed" \
          --width "$WIDTH" --height "$HEIGHT" --format "$FORMAT" --no-progress >/dev/null
        "$MESOCAP" calibrate "$session" --slice-size $((2 * SIZE)) --no-progress >"$WORK/calibrate.log" 2>&1 ||
          { cat "$WORK/calibrate.log" >&2; exit 1; }
      fi
      rm -rf "$session/evaluation"
      "$MESOCAP" evaluate --session "$session" --out "$session/evaluation" --size "$SIZE" --pairs 240 --no-progress \
        ${EVALUATE_ARGS:-} >/dev/null
      true_slices=$("$COVERAGE" --shots "$shots" --seeds "$seed" --materials "$material" --size "$SIZE" |
        awk -v m="$material" '$1 == m { print $7 }')
      node -e '
        const j = JSON.parse(require("fs").readFileSync(process.argv[1]));
        const pc = x => `${(100 * x).toFixed(1)}%`.padStart(6);
        const c = j.by_light_coverage, st = j.methods.statistical, top = j.methods.top_view;
        console.log(`${process.argv[2].padEnd(9)} ${process.argv[3].padStart(5)} ${process.argv[4].padStart(4)} |` +
          `                      ${pc(j.fraction_beating_both_wasserstein_pixels)} ${pc(c.inside.fraction_beating_both_wasserstein_pixels)}` +
          ` ${pc(c.near.fraction_beating_both_wasserstein_pixels)} ${pc(c.far.fraction_beating_both_wasserstein_pixels)} |` +
          ` ${c.inside.pairs}/${c.near.pairs}/${c.far.pairs}`.padEnd(19) + `| ${st.median_wasserstein_pixels.toFixed(5)} / ` +
          `${top.median_wasserstein_pixels.toFixed(5)} | ${pc(j.fraction_beating_both_wasserstein_chromaticity)}       |` +
          ` ${pc(st.median_saturation_error)} / ${pc(st.worst_saturation_error)}      | ${process.argv[5]}`);
      ' "$session/evaluation/evaluation.json" "$material" "$shots" "$seed" "$true_slices"
    done
  done
done
