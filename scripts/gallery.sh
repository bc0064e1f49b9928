#!/usr/bin/env bash
# Renders every model of examples/gallery/ with an existing build
# (build/cli/sage; this script builds nothing) into small PNGs, by
# default docs/gallery/NAME.png at 320x240. CSG models (csg_*) colour each
# named primitive (--materials).
#
# Usage: scripts/gallery.sh [OUT_DIR] [WIDTHxHEIGHT]
set -euo pipefail
cd "$(dirname "$0")/.."
sage=build/cli/sage
out="${1:-docs/gallery}"
size="${2:-320x240}"
if [ ! -x "$sage" ]; then
  echo "gallery.sh: $sage not found; build first (scripts/build.sh)" >&2
  exit 1
fi
mkdir -p "$out"
for model in examples/gallery/*.json; do
  name=$(basename "$model" .json)
  extra=()
  case "$name" in csg_*) extra=(--materials) ;; esac
  "$sage" render "$model" -o "$out/$name.png" --size "$size" "${extra[@]}"
done
