#!/usr/bin/env bash
# The workflow through a real Slurm (issue 52): starts a one-node Slurm on this machine
# (scripts/slurm-local.sh: munge, slurmctld, slurmd, localhost only, in a temporary folder), runs
# workflow/Snakefile with the Slurm profile (workflow/slurm/) on three small virtual sessions with
# the reconstruct stage in 2 shards, and proves from Slurm's own job-completion log that every job
# of every session ran as a Slurm job and completed. Then checks the sessions' outputs against
# `mesocap process` on a copy of each. Stops everything it started, also when it fails.
#
#   bash scripts/slurm-test.sh [MESOCAP]     # default build/app/mesocap; exit 0 when all holds
# Needs root and Debian's slurm-wlm, munge and snakemake (scripts/install-deps.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
REPO=$PWD
MESOCAP=$(realpath "${1:-${MESOCAP_BIN:-build/app/mesocap}}")
SHARDS=2
SESSIONS=(weave stones corduroy)
OPTIONS='--camera {session}/truth.json --slice-size 32 --btf-grid coarse --btf-size 32'

WORK=$(mktemp -d /tmp/mesocap-slurm-test.XXXXXX)
# shellcheck source=scripts/slurm-local.sh
source scripts/slurm-local.sh
cleanup() {
  local status=$?
  slurm_local_stop "$WORK/slurm" || true
  if ((status == 0)); then rm -rf "$WORK"; else echo "slurm-test: FAILED; kept $WORK" >&2; fi
}
trap cleanup EXIT
fail() { echo "slurm-test: $*" >&2; exit 1; }

echo "slurm-test: [1/4] three virtual sessions in $WORK/sessions"
for material in "${SESSIONS[@]}"; do
  "$MESOCAP" simulate --out "$WORK/sessions/$material" --material "$material" --shots 10 --calib-shots 0 \
    --width 1500 --height 1000 --no-progress > /dev/null
done
cp -r "$WORK/sessions" "$WORK/reference"

echo "slurm-test: [2/4] a one-node Slurm"
slurm_local_start "$WORK/slurm"
sinfo

echo "slurm-test: [3/4] the workflow through Slurm (shards=$SHARDS)"
mkdir -p "$WORK/run"
# CI=true: Snakemake 7.21 polls cluster jobs every second instead of every ten.
(cd "$WORK/run" && CI=true snakemake -s "$REPO/workflow/Snakefile" --profile "$REPO/workflow/slurm" \
  --configfile "$REPO/workflow/config.yaml" "$REPO/workflow/slurm/one-core-jobs.yaml" --keep-going \
  --config sessions="$WORK/sessions" mesocap="$MESOCAP" shards=$SHARDS "process_options=$OPTIONS") ||
  fail "the workflow failed (its log: $WORK/run/.snakemake/log/)"

echo "slurm-test: [4/4] Slurm's job-completion log, then the outputs"
JOBCOMP=$(slurm_local_jobcomp)
JOBS=(calibrate resample fit_ptm reconstruct export report)
for ((i = 1; i <= SHARDS; i++)); do JOBS+=("reconstruct_shard" "export_shard"); done
expected=$((${#SESSIONS[@]} * ${#JOBS[@]}))
completed=$(grep -c 'JobState=COMPLETED' "$JOBCOMP" || true)
failed=$(grep -v -c 'JobState=COMPLETED' "$JOBCOMP" || true)
echo "slurm-test: $completed Slurm jobs completed, $failed not (expected $expected completed)"
((failed == 0)) || fail "Slurm jobs did not complete: $(grep -v 'JobState=COMPLETED' "$JOBCOMP")"
((completed == expected)) || fail "$completed Slurm jobs completed, not $expected"
for material in "${SESSIONS[@]}"; do
  for rule in calibrate resample fit_ptm reconstruct export report; do
    grep -q "Name=smk-$rule-session=$material JobState=COMPLETED" "$JOBCOMP" ||
      fail "no completed Slurm job of $rule for $material in $JOBCOMP"
  done
  for rule in reconstruct_shard export_shard; do
    shards=$(grep -c "Name=smk-$rule-index=[0-9]*,session=$material JobState=COMPLETED" "$JOBCOMP" || true)
    ((shards == SHARDS)) || fail "$shards completed $rule jobs for $material, not $SHARDS"
  done
done

# The same outputs as `mesocap process` on each session alone: the .ptm and glTF texture bytes
# (the slices' pixels are compared in tests/e2e/workflow_test, run locally).
for material in "${SESSIONS[@]}"; do
  ref="$WORK/reference/$material"
  "$MESOCAP" process "$ref" ${OPTIONS//\{session\}/$ref} --no-progress > /dev/null 2>&1
  for f in "$ref"/ptm/*.ptm "$ref"/export/gltf/{base_color,metallic_roughness,normal}.png; do
    cmp -s "$f" "$WORK/sessions/$material/${f#"$ref/"}" || fail "$material: ${f#"$ref/"} differs from process's"
  done
done
echo "slurm-test: OK: ${#SESSIONS[@]} sessions, $completed Slurm jobs completed (from $JOBCOMP), outputs as process's"
