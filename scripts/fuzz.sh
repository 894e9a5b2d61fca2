#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/, CMake option MESOCAP_FUZZ, clang with ASan + UBSan) into
# build-asan/ (scripts/asan-build.sh: the build the ASan unit tests use too) and runs each from a
# copy of its seed corpus (fuzz/corpus/<target>/; the repository is never written to). Fails
# (exit 1) when any target finds a crash, a leak, undefined behaviour, an out-of-memory or a
# timeout; the input that did it is kept under
# $FUZZ_CRASH_DIR/<target>/ (default /tmp/fuzz-crashes). Prints, per target: executions,
# coverage (cov: and ft: of libFuzzer's last stats line), exec/s, peak RSS and wall time.
#
#   scripts/fuzz.sh --seconds 30                  # CI: every target for 30 s
#   scripts/fuzz.sh --runs 1000000 -j 2           # the million-execution proof, two at a time
#   scripts/fuzz.sh --seconds 60 ptm_file lp_file # some targets only
#   scripts/fuzz.sh --make-corpus [rig_layout.json]  # rewrite fuzz/corpus/ with the project's writers
#
# Options: --runs N | --seconds S (one of them; default --seconds 60), -j N targets at a time
# (default 1; each target uses one core), --no-build (use build-asan/ as it is),
# --keep-corpus (keep the grown corpus in $FUZZ_WORK/<target>/corpus; default: a fresh copy per run).
# Environment: FUZZ_WORK (scratch, default /dev/shm/mesocap-fuzz, else /tmp/mesocap-fuzz), FUZZ_CRASH_DIR, FUZZ_EXTRA_ARGS
# (more libFuzzer flags, e.g. "-max_len=65536").
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
source scripts/asan-build.sh
BUILD=$ASAN_BUILD
ALL_TARGETS=(ptm_file lp_file session_json journal_jsonl rig_layout camera_json slice_index slice_set btf_index image image_u8 synth_files
             rig_json stages_json marked_corners mesh_files)

runs= seconds= jobs=1 build=1 make_corpus= layout= fresh=1
targets=()
while [[ $# -gt 0 ]]; do
  case $1 in
    --runs) runs=$2; shift 2 ;;
    --seconds) seconds=$2; shift 2 ;;
    -j) jobs=$2; shift 2 ;;
    --no-build) build=; shift ;;
    --keep-corpus) fresh=; shift ;;
    --make-corpus) make_corpus=1; shift; if [[ $# -gt 0 && $1 != -* ]]; then layout=$1; shift; fi ;;
    -h|--help) sed -n '2,22p' "$0"; exit 0 ;;
    -*) echo "fuzz.sh: unknown option $1" >&2; exit 2 ;;
    *) targets+=("$1"); shift ;;
  esac
done
if [[ -n $runs && -n $seconds ]]; then echo "fuzz.sh: give --runs or --seconds, not both" >&2; exit 2; fi
[[ -z $runs && -z $seconds ]] && seconds=60
[[ ${#targets[@]} -eq 0 ]] && targets=("${ALL_TARGETS[@]}")
for t in "${targets[@]}"; do
  [[ " ${ALL_TARGETS[*]} " == *" $t "* ]] || { echo "fuzz.sh: no target $t (${ALL_TARGETS[*]})" >&2; exit 2; }
done

# Scratch on tmpfs when there is one: every input is written to a file, and ext4 flushes a file
# rewritten from zero length on close (auto_da_alloc), 400 exec/s instead of 25000.
if [[ -z ${FUZZ_WORK:-} && -d /dev/shm && -w /dev/shm ]]; then FUZZ_WORK=/dev/shm/mesocap-fuzz; fi
WORK=${FUZZ_WORK:-/tmp/mesocap-fuzz}
CRASH_DIR=${FUZZ_CRASH_DIR:-/tmp/fuzz-crashes}

if [[ -n $build ]]; then
  echo "== configure + build $BUILD (clang, ASan + UBSan + libFuzzer)"
  start=$SECONDS
  configure_asan_build
  if [[ -n $make_corpus ]]; then
    cmake --build "$BUILD" -j2 --target fuzz_make_corpus
  else
    cmake --build "$BUILD" -j2 --target $(printf 'fuzz_%s ' "${targets[@]}")
  fi
  echo "== build took $((SECONDS - start)) s"
fi

if [[ -n $make_corpus ]]; then
  tmp=$(mktemp -d)
  "$BUILD/fuzz/fuzz_make_corpus" "$tmp" $layout
  rm -rf "$ROOT/fuzz/corpus"
  mv "$tmp" "$ROOT/fuzz/corpus"
  du -sh "$ROOT/fuzz/corpus"
  exit 0
fi

export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}
# Third-party leaks only (scripts/lsan.supp says which and why).
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$ROOT/scripts/lsan.supp:print_suppressions=0}

# One target: fresh scratch corpus, libFuzzer, then a summary line in $WORK/<t>/summary.
run_one() {
  local t=$1 dir=$WORK/$1
  mkdir -p "$dir" "$CRASH_DIR/$t"
  rm -f "$dir/summary"
  if [[ -n $fresh || ! -d $dir/corpus ]]; then
    rm -rf "$dir/corpus"
    cp -r "$ROOT/fuzz/corpus/$t" "$dir/corpus"
  fi
  rm -rf "$dir/tmp" && mkdir -p "$dir/tmp"
  local limit
  if [[ -n $runs ]]; then limit=-runs=$runs; else limit=-max_total_time=$seconds; fi
  local start=$(date +%s.%N) rc=0
  # shellcheck disable=SC2086
  TMPDIR=$dir/tmp "$BUILD/fuzz/fuzz_$t" "$dir/corpus" $limit -rss_limit_mb=2048 -timeout=10 \
    -print_final_stats=1 -artifact_prefix="$CRASH_DIR/$t/" ${FUZZ_EXTRA_ARGS:-} >"$dir/log" 2>&1 || rc=$?
  local wall=$(echo "$(date +%s.%N) - $start" | bc)
  local last=$(grep -E '^#[0-9]+' "$dir/log" | tail -1)
  # Final stats (or, in -fork mode, the last status line "#N: cov: ... exec/s: E ...").
  local execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$dir/log")
  local eps=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$dir/log")
  local rss=$(sed -n 's/^stat::peak_rss_mb: *//p' "$dir/log")
  [[ -z $execs ]] && execs=$(sed -n 's/^#\([0-9]*\).*/\1/p' <<<"$last")
  [[ -z $eps ]] && eps=$(sed -n 's/.* exec\/s: \([0-9]*\).*/\1/p' <<<"$last")
  [[ -z $rss ]] && rss=$(sed -n 's/.* rss: \([0-9]*\)Mb.*/\1/p' <<<"$last")
  local cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"$last")
  local ft=$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<<"$last")
  local verdict=ok
  if [[ $rc -ne 0 ]]; then
    verdict=$(grep -m1 -oE 'ERROR: (libFuzzer|AddressSanitizer|LeakSanitizer): [a-zA-Z-]+|runtime error: .*|SUMMARY: UndefinedBehaviorSanitizer: [a-z-]+|ERROR: libFuzzer: [a-z-]+' "$dir/log" | head -1)
    verdict="FAILED (exit $rc: ${verdict:-see log}) artifact: $(grep -m1 -o "Test unit written to .*" "$dir/log" | sed 's/Test unit written to //')"
  fi
  printf '%-14s execs %10s  cov %5s  ft %6s  exec/s %7s  rss %5s MB  time %7.1f s  %s\n' \
    "$t" "${execs:-?}" "${cov:-?}" "${ft:-?}" "${eps:-?}" "${rss:-?}" "$wall" "$verdict" >"$dir/summary"
  cat "$dir/summary"
  [[ $rc -eq 0 ]]
}

echo "== fuzzing ${targets[*]} (${runs:+$runs runs}${seconds:+$seconds s} each, $jobs at a time; logs in $WORK/<target>/log)"
failed=0
pids=()
for t in "${targets[@]}"; do
  run_one "$t" &
  pids+=($!)
  while [[ $(jobs -rp | wc -l) -ge $jobs ]]; do wait -n || failed=1; done
done
while [[ $(jobs -rp | wc -l) -gt 0 ]]; do wait -n || failed=1; done
# wait -n may have missed a status that was reaped already: recheck the summaries.
grep -l FAILED $(printf "$WORK/%s/summary " "${targets[@]}") >/dev/null 2>&1 && failed=1
echo "== summary"
cat $(printf "$WORK/%s/summary " "${targets[@]}")
if [[ $failed -ne 0 ]]; then
  echo "fuzz.sh: failures above; reproduce with build-asan/fuzz/fuzz_<target> <artifact>" >&2
  exit 1
fi
