#!/usr/bin/env bash
# Benchmarks of issue 52 (figures in docs/benchmarks.md, "Workflow"):
#  1. sharding's extra work: the reconstruct, synth (roller, 256 x 256) and export (GGX fit)
#     stages of one virtual session (40 flash shots at 3000 x 2000, the Bonn grid at 128 texels)
#     run whole and as 8 shards + merge, every job with the same threads (BENCH_THREADS, default
#     1: a one-core job, so no thread waits on another); summed CPU time (user + sys) of the shard
#     jobs and the merge against the whole stage's (target < 5%), each job's the least of
#     BENCH_REPEATS runs (default 3: this VM's CPU times vary by several % from run to run);
#  2. the workflow on three small sessions (10 shots, Bonn grid at 64 texels) locally with 1 and
#     2 cores, and through a one-node Slurm (scripts/slurm-local.sh): wall time;
#  3. the per-stage CPU times of run 1, for the projection to 100 materials at 81x81x512^2.
# Usage: bench/workflow_bench.sh [BUILD_DIR] [WORK_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
REPO=$PWD
build=$(realpath "${1:-build}")
work="${2:-${TMPDIR:-/tmp}/mesocap-workflow-bench}"
bin="$build/app/mesocap"
mkdir -p "$work"
cpu() {  # CPU seconds (user + sys) of a command, its output to $work/last.log
  /usr/bin/time -f "%U %S" -o "$work/time.txt" "$@" > "$work/last.log" 2>&1 || { cat "$work/last.log" >&2; return 1; }
  awk '{ printf "%.2f", $1 + $2 }' "$work/time.txt"
}

# 1. Sharding's extra work, stage by stage.
if [ ! -f "$work/big/journal.jsonl" ]; then
  rm -rf "$work/big"
  "$bin" simulate --out "$work/big" --shots 40 --no-progress > /dev/null
fi
threads=${BENCH_THREADS:-1}
repeats=${BENCH_REPEATS:-3}
OPT="--camera $work/big/truth.json --synth roller --synth-size 256x256 --no-progress --threads $threads"
rm -rf "$work/whole" "$work/sharded"
cp -r "$work/big" "$work/whole"
declare -A stage_cpu
for stage in calibrate resample fit-ptm; do stage_cpu[$stage]=$(cpu "$bin" process "$work/whole" --stage $stage $OPT); done
cp -r "$work/whole" "$work/sharded"
keep_least() {  # JOB COMMAND...: best[JOB] = the least CPU time of COMMAND so far
  local job=$1 t; shift
  t=$(cpu "$@")
  best[$job]=$(python3 -c "import sys; print(min(float(x) for x in sys.argv[1:] if x))" "$t" "${best[$job]:-}")
}
for stage in reconstruct synth export; do
  declare -A best=()
  for r in $(seq "$repeats"); do  # every job forced: each repeat redoes it whole
    keep_least whole "$bin" process "$work/whole" --stage $stage --force $stage $OPT
    for i in 1 2 3 4 5 6 7 8; do keep_least $i "$bin" process "$work/sharded" --stage $stage --force $stage --shard $i/8 $OPT; done
    keep_least merge "$bin" process "$work/sharded" --stage $stage --force $stage --merge 8 $OPT
  done
  stage_cpu[$stage]=${best[whole]}
  python3 - "$stage" "$threads" "$repeats" "${best[whole]}" "${best[merge]}" "${best[1]}" "${best[2]}" "${best[3]}" "${best[4]}" \
    "${best[5]}" "${best[6]}" "${best[7]}" "${best[8]}" <<'PY'
import sys
stage, threads, repeats = sys.argv[1:4]
whole, merge, *shards = map(float, sys.argv[4:])
print(f"workflow bench: {stage} ({threads} thread(s) a job, least of {repeats}): whole {whole:.2f} CPU s; "
      f"8 shards {sum(shards):.2f} ({' '.join(f'{t:.2f}' for t in shards)}) + merge {merge:.2f} = "
      f"{sum(shards) + merge:.2f} CPU s: {100 * (sum(shards) + merge - whole) / whole:+.1f}% (target < 5%)")
PY
done
for stage in calibrate resample fit-ptm reconstruct synth export; do
  echo "workflow bench: stage $stage of the 40-shot session (Bonn grid, 128 texels, roller 256x256): ${stage_cpu[$stage]} CPU s"
done

# 2. Three small sessions locally with 1 and 2 cores, and through Slurm.
if [ ! -d "$work/small3" ]; then
  for m in weave stones corduroy; do
    "$bin" simulate --out "$work/small3/$m" --material $m --shots 10 --calib-shots 0 --width 1500 --height 1000 \
      --no-progress > /dev/null
  done
fi
SMALL_OPT='--camera {session}/truth.json --slice-size 64 --btf-grid bonn --btf-size 64'
run_workflow() {  # label, then snakemake arguments
  local label=$1; shift
  rm -rf "$work/wf" "$work/wf_run" && cp -r "$work/small3" "$work/wf" && mkdir -p "$work/wf_run"
  local start=$(date +%s.%N)
  (cd "$work/wf_run" && CI=true snakemake -s "$REPO/workflow/Snakefile" --keep-going \
    --config sessions="$work/wf" mesocap="$bin" shards=2 "process_options=$SMALL_OPT" "$@" > "$work/wf.log" 2>&1) ||
    { tail -30 "$work/wf.log" >&2; return 1; }
  echo "workflow bench: 3 sessions (10 shots, Bonn grid at 64 texels, 2 shards), $label: $(echo "$(date +%s.%N) - $start" | bc | xargs printf %.1f) s wall"
}
run_workflow "local, --cores 1" --cores 1
run_workflow "local, --cores 2" --cores 2
# shellcheck source=scripts/slurm-local.sh
source scripts/slurm-local.sh
trap 'slurm_local_stop "$work/slurm"' EXIT
rm -rf "$work/slurm"
slurm_local_start "$work/slurm"
run_workflow "one-node Slurm (2 cores, a job per core)" --profile "$REPO/workflow/slurm" \
  --configfile "$REPO/workflow/config.yaml" "$REPO/workflow/slurm/one-core-jobs.yaml"
