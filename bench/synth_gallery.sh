#!/usr/bin/env bash
# The synthesis gallery (synthesis-quality issue): every texture of the photograph corpus
# (tests/data/textures) cropped to 96x96 and enlarged to 256x256 by quilt and texton, and by GIMP's
# Resynthesizer engine as a peer when it is built (bench/resynth_peer/build.sh), one contact sheet
# per texture (sample | random tiling | each method) and one table of seams, statistics (subband and
# Laplacian/gradient distances, also as ratios to random tiling of 24x24 patches), repeats, texels
# used, the largest coherent region and seconds; mean of --seeds seeds (3). A second table scores
# block synthesis and quilting of a PTM rendered from each photograph (bench_synth_quality --ptm:
# Legendre coefficients synthesized, the output relit under two lights), random tiling included.
#
#   bench/synth_gallery.sh BUILD_DIR OUT_DIR [SEEDS]
#
# Writes OUT_DIR/<texture>.jpg, OUT_DIR/table.txt and OUT_DIR/table_ptm.txt. About 6 minutes on 2
# cores with the peer, plus 2.5 minutes per seed for the PTM table.
set -euo pipefail
build=${1:?usage: synth_gallery.sh BUILD_DIR OUT_DIR [SEEDS]}
out=${2:?usage: synth_gallery.sh BUILD_DIR OUT_DIR [SEEDS]}
seeds=${3:-3}
root="$(cd "$(dirname "$0")/.." && pwd)"
bench="$build/bench/bench_synth_quality"
[[ -x $bench ]] || { echo "synth_gallery: $bench is missing (cmake --build $build --target bench_synth_quality)" >&2; exit 1; }
peer="$build/peer/resynth/resynth_fill_serial"
methods=quilt,texton
peer_args=()
if [[ -x $peer ]]; then
  methods+=,resynth
  peer_args=(--peer "$peer")
else
  echo "synth_gallery: no Resynthesizer peer at $peer (bench/resynth_peer/build.sh builds it); running without it" >&2
fi
mkdir -p "$out"
: >"$out/table.txt"
: >"$out/table_ptm.txt"
first=1
while read -r name category; do
  [[ -n $name ]] || continue
  echo "synth_gallery: $name ($category)" >&2
  "$bench" "$root/tests/data/textures/$name.png" --methods "$methods" "${peer_args[@]}" --seeds "$seeds" \
    --sheet "$out/$name.jpg" | if ((first)); then cat; else tail -n +2; fi >>"$out/table.txt"
  "$bench" "$root/tests/data/textures/$name.png" --ptm --methods block,quilt --seeds "$seeds" |
    if ((first)); then cat; else tail -n +2; fi >>"$out/table_ptm.txt"
  first=0
done <"$root/tests/data/textures/corpus.txt"
cat "$out/table.txt" "$out/table_ptm.txt"
