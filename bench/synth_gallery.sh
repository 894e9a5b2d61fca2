#!/usr/bin/env bash
# The synthesis gallery (synthesis-quality issue): every texture of the photograph corpus
# (tests/data/textures) cropped to 96x96 and enlarged to 256x256 by quilt and texton, and by GIMP's
# Resynthesizer engine as a peer when it is built (bench/resynth_peer/build.sh), one contact sheet
# per texture (sample | random tiling | each method) and one table of seams, statistics (subband and
# Laplacian/gradient distances, also as ratios to random tiling of 24x24 patches), repeats, texels
# used, the largest coherent region and seconds; mean of --seeds seeds (3).
#
#   bench/synth_gallery.sh BUILD_DIR OUT_DIR [SEEDS]
#
# Writes OUT_DIR/<texture>.jpg and OUT_DIR/table.txt. About 6 minutes on 2 cores with the peer.
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
first=1
while read -r name category; do
  [[ -n $name ]] || continue
  echo "synth_gallery: $name ($category)" >&2
  "$bench" "$root/tests/data/textures/$name.png" --methods "$methods" "${peer_args[@]}" --seeds "$seeds" \
    --sheet "$out/$name.jpg" | if ((first)); then cat; else tail -n +2; fi >>"$out/table.txt"
  first=0
done <"$root/tests/data/textures/corpus.txt"
cat "$out/table.txt"
