#!/usr/bin/env bash
# The whole test suite: set up, build, run every test with CTest; then the core on its own; then
# the whole suite again under AddressSanitizer and UndefinedBehaviorSanitizer.
#
# The Release build of the whole suite is without link-time optimisation (FMCW_LTO=OFF: with it,
# every test program re-optimises the libraries whole at its link) and with precompiled headers
# (FMCW_PCH=ON: Eigen's headers are seconds of every file's compile). The core-only build keeps
# the defaults, link-time optimisation included, so that the installed libraries' LTO objects stay
# tested (install.consumer). docs/RELIABILITY.md, "The CI job's time". Each phase prints its time.
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
phase() { echo "test_all: $1 done at $(( $(date +%s) - start )) s"; }
bash scripts/setup.sh
phase setup
bash scripts/build.sh -DFMCW_LTO=OFF -DFMCW_PCH=ON
phase "Release build"
cd build
# setup.sh installed Open3D and PCL's tools: the export checks must run, not skip.
FMCW_REQUIRE_EXTERNAL_TOOLS=1 ctest --output-on-failure -j"$(nproc)"
phase "Release suite"

# The core on its own: Eigen, Ceres and OpenMP only, as a user embedding it would build it.
cd ..
cmake -S . -B build-core -DCMAKE_BUILD_TYPE=Release -DFMCW_CORE_ONLY=ON > build-core.log 2>&1 || { cat build-core.log; exit 1; }
cmake --build build-core -j"$(nproc)" >> build-core.log 2>&1 || { tail -50 build-core.log; exit 1; }
phase "core-only build"
cd build-core
ctest --output-on-failure -j"$(nproc)"
phase "core-only suite"

# ASan + UBSan: every test, the CLI they run included, stops at the first memory error, leak or
# undefined behaviour (-fno-sanitize-recover), built at -O1 as the sanitizers' documentation
# advises, with precompiled headers as the Release build. The benchmark programs are not built:
# no test runs them. FMCW_SKIP_SANITIZE=1 skips
# this part (a quicker run while developing).
cd ..
[ "${FMCW_SKIP_SANITIZE:-0}" = 1 ] && exit 0
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O1 -DNDEBUG" -DFMCW_SANITIZE=ON \
  -DFMCW_BUILD_BENCH=OFF -DFMCW_PCH=ON > build-asan.log 2>&1 || { cat build-asan.log; exit 1; }
cmake --build build-asan -j"$(nproc)" >> build-asan.log 2>&1 || { tail -50 build-asan.log; exit 1; }
phase "sanitizer build"
cd build-asan
ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 ctest --output-on-failure -j"$(nproc)"
phase "sanitizer suite"
