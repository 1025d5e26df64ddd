#!/usr/bin/env bash
# Installs a build tree into a temporary prefix, then configures, builds and runs the consumer
# project (tests/install/consumer, outside the project's CMake tree) against it:
# find_package(fmcw) must find the package and its dependencies, fmcw::core must link, and the
# consumer's MotionPipeline run must return the known ego velocity.
# With EXPECT_CLI=1 the fmcw CLI must be installed too and run from the prefix.
#   install_and_build.sh BUILD_DIR SOURCE_DIR [CXX_COMPILER]
set -euo pipefail
build=$1
src=$2
cxx=${3:-c++}
work=$(mktemp -d "${TMPDIR:-/tmp}/fmcw_install.XXXXXX")
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" > "$work/install.log" || { cat "$work/install.log"; exit 1; }
for f in lib/cmake/fmcw/fmcwConfig.cmake lib/cmake/fmcw/fmcwConfigVersion.cmake include/fmcw/core/motion_pipeline.hpp; do
  [ -f "$work/prefix/$f" ] || { echo "not installed: $f"; exit 1; }
done
if [ "${EXPECT_CLI:-0}" = 1 ]; then
  "$work/prefix/bin/fmcw" --version > /dev/null || { echo "installed bin/fmcw does not run"; exit 1; }
  [ -f "$work/prefix/include/fmcw/io/mcap_reader.hpp" ] || { echo "not installed: fmcw::io headers"; exit 1; }
fi
# -fno-lto: the libraries' machine code is linked as it is (they are fat LTO objects); without it
# GCC optimises the whole of them again at the link, 20 s of CPU instead of 1.
cmake -S "$src/tests/install/consumer" -B "$work/build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER="$cxx" \
  -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_EXE_LINKER_FLAGS=-fno-lto > "$work/configure.log" 2>&1 || { cat "$work/configure.log"; exit 1; }
cmake --build "$work/build" -j2 > "$work/build.log" 2>&1 || { tail -40 "$work/build.log"; exit 1; }
"$work/build/fmcw_consumer" "$work"
