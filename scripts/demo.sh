#!/usr/bin/env bash
# README command 1: set up, build (Release) and run the main job, `sage demo`,
# on the bundled models. Output goes to ./sage-demo (or the folder given).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh -DSAGE_BUILD_TESTS=OFF -DSAGE_BUILD_BENCH=OFF
build/cli/sage demo -o "${1:-sage-demo}"
