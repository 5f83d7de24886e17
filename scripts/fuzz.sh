#!/usr/bin/env bash
# Builds the libFuzzer targets of fuzz/ (clang, AddressSanitizer + UndefinedBehaviorSanitizer) into
# build-fuzz/ and runs each for a bounded time, growing its corpus in build-fuzz/corpus/<target>
# from the seeds in fuzz/seeds/<target>. A crash leaves its input in build-fuzz/crashes/<target>/
# (turn it into a case of tests/bad_inputs) and makes the script fail.
# Usage: scripts/fuzz.sh [SECONDS_PER_TARGET (default 60)] [TARGET ...]
#   targets: sequence_list trajectory camera_yaml target_yaml frames_csv options cli run (default: all)
#   FUZZ_FLAGS: more libFuzzer flags, e.g. "-fork=1 -ignore_crashes=1" to go on past a crash and
#   collect every one in the time given.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(sequence_list trajectory camera_yaml target_yaml frames_csv options cli run)

# clang and its libFuzzer runtime, installed if missing (Debian 12: clang 14).
probe=$(mktemp -d)
echo 'extern "C" int LLVMFuzzerTestOneInput(const unsigned char*, unsigned long) { return 0; }' > "$probe/p.cc"
if ! clang++ -fsanitize=fuzzer "$probe/p.cc" -o "$probe/p" > /dev/null 2>&1; then
  sudo_cmd=""
  [ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
  $sudo_cmd apt-get install -y clang libclang-rt-14-dev
fi
rm -rf "$probe"

build=build-fuzz
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  -DSLAMCMP_FUZZ=ON -DSLAMCMP_BUILD_TESTS=OFF -DSLAMCMP_BUILD_BENCHMARKS=OFF > "$build.log" 2>&1 ||
  { cat "$build.log"; exit 1; }
cmake --build "$build" -j"$(nproc)" --target "${targets[@]/#/fuzz_}" >> "$build.log" 2>&1 ||
  { tail -n 60 "$build.log"; exit 1; }

status=0
summary=""
for t in "${targets[@]}"; do
  mkdir -p "$build/corpus/$t" "$build/crashes/$t"
  log="$build/fuzz_$t.log"
  echo "fuzzing $t for ${seconds} s (log: $log)"
  # shellcheck disable=SC2086  # FUZZ_FLAGS is a list of flags
  if "$build/fuzz/fuzz_$t" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 ${FUZZ_FLAGS:-} \
       -artifact_prefix="$build/crashes/$t/" "$build/corpus/$t" "fuzz/seeds/$t" > "$log" 2>&1; then
    result="ok"
  else
    result="FAILED (input in $build/crashes/$t/)"
    status=1
  fi
  runs=$(grep -o 'Done [0-9]* runs in [0-9]* second' "$log" | tail -n 1 || true)
  [ -n "$runs" ] || runs=$(grep -o '#[0-9]*: cov: [0-9]* ft: [0-9]* corp: [0-9]*/[0-9]*[a-zA-Z]* exec/s: [0-9]*' "$log" | tail -n 1 || true)
  summary+="$t: $result; ${runs:-no run count (see log)}; corpus $(ls "$build/corpus/$t" | wc -l) inputs"$'\n'
done
printf '%s' "$summary"
exit $status
