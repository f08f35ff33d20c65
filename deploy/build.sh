#!/usr/bin/env bash
# Installs the dependencies and builds ecpair into ./build (RelWithDebInfo),
# as a unity build (the libraries' and programs' files compiled a few at a
# time, which makes a fresh build much cheaper; -DCMAKE_UNITY_BUILD=OFF for a
# tree you edit and rebuild often). Extra arguments go to the CMake configure
# step. ECPAIR_BUILD_TARGETS (space-separated) builds only those targets, e.g.
# the programs a demo runs; by default everything is built, the tests and
# benchmarks too.
set -euo pipefail
cd "$(dirname "$0")/.."
bash deploy/install-deps.sh
# Ninja starts a target's compiles before the libraries it links are linked
# (make waits), which keeps both cores busy. A tree configured before with
# another generator keeps it: CMake reads this only for a new tree.
export CMAKE_GENERATOR="${CMAKE_GENERATOR:-Ninja}"
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_UNITY_BUILD=ON "$@"
targets=()
for t in ${ECPAIR_BUILD_TARGETS:-}; do targets+=(--target "$t"); done
cmake --build build -j"$(nproc)" "${targets[@]}"
