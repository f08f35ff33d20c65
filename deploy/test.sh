#!/usr/bin/env bash
# README's test command: install, build, run every test. Run as root: the
# tests labelled `netns` create network namespaces (ctest -LE netns skips them).
set -euo pipefail
cd "$(dirname "$0")/.."
bash deploy/build.sh
ctest --test-dir build --output-on-failure -j2
