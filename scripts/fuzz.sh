#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan + UBSan, coverage) and runs each one for a bounded
# time from the committed seed corpus (tests/fuzz/corpus/<target>). Inputs the fuzzer finds go
# to build-fuzz/corpus/<target>, crashes to build-fuzz/artifacts/<target>/; a crash fails the
# script and prints the command that replays it.
#   scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]      defaults: 60, pcd scenario mesh mcap
# Each target's dictionary is tests/fuzz/<target>.dict, but mesh's is tests/fuzz/gltf.dict.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
shift || true
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(pcd scenario mesh mcap)
build=${FMCW_FUZZ_BUILD:-build-fuzz}

bash scripts/setup.sh --fuzz
# -Wno-pass-failed: clang reports an `omp simd` loop it chose not to vectorise as an error under
# -Werror (core/src/ego_twist.cpp); gcc, the project's compiler, has no such warning.
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++-14 -DFMCW_FUZZ=ON \
  -DCMAKE_CXX_FLAGS=-Wno-pass-failed -DFMCW_BUILD_TESTS=OFF -DFMCW_BUILD_BENCH=OFF > "$build.log" 2>&1 || { cat "$build.log"; exit 1; }
cmake --build "$build" -j"$(nproc)" --target "${targets[@]/#/fuzz_}" >> "$build.log" 2>&1 || { tail -50 "$build.log"; exit 1; }

status=0
for t in "${targets[@]}"; do
  mkdir -p "$build/corpus/$t" "$build/artifacts/$t"
  log="$build/fuzz_$t.log"
  dict="tests/fuzz/$t.dict"
  [ "$t" = mesh ] && dict=tests/fuzz/gltf.dict
  echo "fuzz_$t: ${seconds} s"
  # -timeout: an input taking over 10 s is a hang; -rss_limit_mb: one over 2 GB a runaway allocation.
  if ! "$build/bin/fuzz_$t" "$build/corpus/$t" "tests/fuzz/corpus/$t" -dict="$dict" \
      -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=16384 -print_final_stats=1 \
      -artifact_prefix="$build/artifacts/$t/" > "$log" 2>&1; then
    status=1
    grep -E "ERROR|SUMMARY|Test unit written" "$log" || tail -30 "$log"
    echo "fuzz_$t: FAILED; replay with $build/bin/fuzz_$t $build/artifacts/$t/<file> (log: $log)"
  fi
  grep -E "^stat::number_of_executed_units|^stat::peak_rss_mb|^#[0-9]+ *DONE" "$log" || true
done
exit $status
