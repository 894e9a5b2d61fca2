#!/usr/bin/env bash
# Issue 12's guidance test: do sessions that follow the suggestions reach the quality of random
# hand-held sessions with 30% fewer shots? Runs bench_session_coverage twice on the same seeds:
# GUIDED shots, the first START hand-held and each later one at the guidance's first suggestion
# (`mesocap capture --guide --follow-guide`, which starts guiding after --guide-after 6 shots), and
# RANDOM hand-held shots. Prints each seed's pair and the paired differences (mean +- standard
# error over the seeds): the share of held-out pairs beating both baselines, and the median pixel W1.
#
#   bench/guidance_quality_bench.sh [BUILD_DIR=build] MATERIAL IMAGES SEEDS [START=6] [GUIDED=70] [RANDOM=100] [FLAGS]
#
# FLAGS: more bench_session_coverage options for both runs, e.g. "--regions 1" (each board shows its
# own part of the material, as on the rig).
#
# IMAGES: the mirror-image mask the guidance counts (weave 0010000, stones 1111111, corduroy
# 1110000; what `mesocap coverage` finds for each). SEEDS: comma-separated, e.g. $(seq -s, 31 50).
# About 4-10 s per seed and session on 2 cores (20 seeds of one material: 3-6 minutes).
set -euo pipefail
BUILD=${1:-build}
MATERIAL=${2:?material}
IMAGES=${3:?image mask}
SEEDS=${4:?seeds}
START=${5:-6}
GUIDED=${6:-70}
RANDOM_SHOTS=${7:-100}
read -r -a FLAGS <<< "${8:-}"
BENCH=$BUILD/bench/bench_session_coverage
[[ -x $BENCH ]] || { echo "build bench_session_coverage in $BUILD first" >&2; exit 2; }
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT

"$BENCH" --materials "$MATERIAL" --shots "$GUIDED" --guided "$START" --guide-images "$IMAGES" --seeds "$SEEDS" "${FLAGS[@]}" > "$WORK/guided.txt"
"$BENCH" --materials "$MATERIAL" --shots "$RANDOM_SHOTS" --seeds "$SEEDS" "${FLAGS[@]}" > "$WORK/random.txt"
# A result row: material shots seed views slices | share% ... | pairs | W1 stat / W1 top | chroma
rows() { awk -F'|' 'NF >= 5 && $2 ~ /%/ { split($1, a, " "); split($2, s, " "); split($4, w, " "); print a[3], s[1] + 0, w[1] }' "$1"; }
echo "$MATERIAL: $GUIDED shots guided from $START (images $IMAGES) against $RANDOM_SHOTS hand-held, same seeds${8:+, $8}"
join <(rows "$WORK/guided.txt" | sort) <(rows "$WORK/random.txt" | sort) | sort -n |
  awk '{
    printf "  seed %3d: share %5.1f%% vs %5.1f%%, median W1 %.5f vs %.5f\n", $1, $2, $4, $3, $5
    n++; d = $2 - $4; r = 100 * ($3 / $5 - 1); sd += d; sdd += d * d; sr += r; srr += r * r; sg += $2; sh += $4
  } END {
    if (n < 2) { print "fewer than two seeds: no standard error"; exit 1 }
    md = sd / n; mr = sr / n
    ed = sqrt((sdd - n * md * md) / (n - 1) / n); er = sqrt((srr - n * mr * mr) / (n - 1) / n)
    printf "  mean share: guided %.1f%%, hand-held %.1f%% (%d seeds)\n", sg / n, sh / n, n
    printf "  guided - hand-held: share %+.2f +- %.2f points, median W1 %+.2f +- %.2f%%\n", md, ed, mr, er
  }'
