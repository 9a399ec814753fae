#!/usr/bin/env bash
# ctest driver: install the build tree into a scratch prefix, then configure, build and run
# the consumer project against it. Args: BUILD_DIR SOURCE_DIR SCRATCH_DIR
set -euo pipefail
build=$1 src=$2 scratch=$3
rm -rf "$scratch"
cmake --install "$build" --prefix "$scratch/prefix" > "$scratch.install.log" 2>&1 \
  || { cat "$scratch.install.log"; exit 1; }
cmake -S "$src/tests/consumer" -B "$scratch/build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$scratch/prefix"
cmake --build "$scratch/build"
out=$("$scratch/build/consumer")
echo "$out"
[ "$out" = "V=4 E=6 F=4" ]
