#!/usr/bin/env bash
# README command 2: set up, build (Release) and run the whole test suite.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh -DSAGE_BUILD_TESTS=ON -DSAGE_BUILD_BENCH=ON
ctest --test-dir build --output-on-failure --parallel "$(nproc)"
