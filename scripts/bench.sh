#!/usr/bin/env bash
# Builds Release with the benchmarks, runs bench_stages, bench_monoslam and bench_tracking (each
# pinned to one core when taskset exists, repeated so the medians are stable), times whole
# `slamcmp run`s of the rendered tv1 against decoding the same files alone, and writes
# docs/benchmarks.md. About 4 minutes on an idle machine, plus about 2 minutes the first time to
# render tv1 (120 frames and whole) and board_leaves into $TMPDIR (cached there as slamcmp-bench-*).
#   BUILD_DIR (default build), REPETITIONS (default 3) may be set.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${BUILD_DIR:-build}
REPS=${REPETITIONS:-3}
WORK=$(mktemp -d "${TMPDIR:-/tmp}/slamcmp-bench-run.XXXXXX")
trap 'if [[ $? == 0 ]]; then rm -rf "$WORK"; else echo "bench.sh failed: logs in $WORK" >&2; fi' EXIT

cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DSLAMCMP_BUILD_BENCHMARKS=ON > "$WORK/cmake.log" 2>&1 ||
  { cat "$WORK/cmake.log"; exit 1; }
cmake --build "$BUILD_DIR" -j"$(nproc)" --target slamcmp decode_only bench_stages bench_monoslam bench_tracking bench_report \
  > "$WORK/build.log" 2>&1 || { tail -n 60 "$WORK/build.log"; exit 1; }
BENCH="$BUILD_DIR/benchmarks"
TIMEFORMAT='%R %U %S'
SLAMCMP="$BUILD_DIR/eval/slamcmp"

PIN=()
if command -v taskset > /dev/null; then PIN=(taskset -c "$(($(nproc) - 1))"); fi
LOAD_BEFORE=$(cut -d' ' -f1-3 /proc/loadavg)

# Google Benchmark's JSON, medians over REPS repetitions.
run_bench() {  # name
  echo "running $1 (${REPS} repetitions)"
  "${PIN[@]}" "$BENCH/$1" --benchmark_repetitions="$REPS" --benchmark_report_aggregates_only=true \
    --benchmark_out="$WORK/$1.json" --benchmark_out_format=json > "$WORK/$1.log" 2>&1 ||
    { tail -n 30 "$WORK/$1.log"; exit 1; }
}
run_bench bench_stages    # renders tv1 (120 frames) and board_leaves (160) into $TMPDIR if not cached
run_bench bench_monoslam
run_bench bench_tracking

# The back-ends and modes as bench_tracking registers them from the registry:
# BM_Track/<backend>[@none][/<mode>] (@none: started without the board, `--init none`).
mapfile -t METHODS < <("$BENCH/bench_tracking" --benchmark_list_tests | sed -n 's|^BM_Track/||p' | sed 's|/min_time:.*||')

# Whole runs on the whole tv1 (337 frames) that BM_DecodeSequence decoded, each against a process
# that only decodes the same files (decode_only), on one core and on all; the repetitions
# interleave them so that both see the same machine.
SEQUENCE="${TMPDIR:-/tmp}/slamcmp-bench-tv1-0"
: > "$WORK/runs.tsv"
timed() {  # label cores command...: bash's `time` (wall, user and system seconds, all threads)
  local label=$1 cores=$2
  shift 2
  { time "$@" > "$WORK/run.log" 2>&1 || { cat "$WORK/run.log"; exit 1; }; } 2> "$WORK/time.txt"
  read -r real user sys < "$WORK/time.txt"
  echo "$label $cores $real $(awk -v u="$user" -v s="$sys" 'BEGIN { printf "%.3f", u + s }')" >> "$WORK/runs.tsv"
}
for cores in 1 "$(nproc)"; do
  pin=()
  [[ $cores == 1 ]] && pin=("${PIN[@]}")
  echo "timing whole runs on $cores core(s) (${REPS} repetitions)"
  for ((r = 0; r < REPS; ++r)); do
    timed decode_only "$cores" "${pin[@]}" "$BENCH/decode_only" "$SEQUENCE"
    for what in "${METHODS[@]}"; do
      mode_args=()
      [[ $what == */* ]] && mode_args=(--mode "${what#*/}")
      backend=${what%%/*}
      [[ $backend == *@none ]] && mode_args+=(--init none) && backend=${backend%@none}
      timed "$what" "$cores" "${pin[@]}" "$SLAMCMP" run --backend "$backend" "${mode_args[@]}" \
        --sequence "$SEQUENCE" --out "$WORK/run"
    done
  done
done
for ((r = 0; r < REPS; ++r)); do  # the fixed cost of starting the process, included above
  timed process_start 1 "${PIN[@]}" "$SLAMCMP" --help
done

MACHINE="$(lscpu | sed -n 's/^Model name: *//p' | head -n 1), $(nproc) cores; load average $LOAD_BEFORE before, \
$(cut -d' ' -f1-3 /proc/loadavg) after (other work on the machine inflates every figure); $(date -u +%Y-%m-%d)."
mkdir -p docs
"$BENCH/bench_report" --stages "$WORK/bench_stages.json" --monoslam "$WORK/bench_monoslam.json" \
  --tracking "$WORK/bench_tracking.json" --runs "$WORK/runs.tsv" --targets benchmarks/targets.txt --preset tv1 --machine "$MACHINE" \
  --out docs/benchmarks.md > /dev/null
echo "wrote docs/benchmarks.md"
