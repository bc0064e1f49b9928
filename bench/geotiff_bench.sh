#!/bin/bash
# GeoTIFF against .vti: the whole `sage field` run of each MODEL at N x N
# points, written alternately as .vti and .tif (ZSTD, the default, and
# DEFLATE), RUNS times each; prints the median wall times, their ratio to
# the .vti run and the files' sizes. The baseline (.vti) runs in the same
# loop, so the machine's noise hits both alike.
#
# Usage: bench/geotiff_bench.sh [SAGE] [N] [RUNS] MODEL...
#        (defaults build/cli/sage, 1000, 11; MODEL defaults to the island
#        of examples/ and Lake Vanern from ../shared/data/gis)
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
sage=${1:-$here/build/cli/sage}
n=${2:-1000}
runs=${3:-11}
shift $(($# < 3 ? $# : 3))
models=("$@")
[ ${#models[@]} -gt 0 ] || models=("$here/examples/models/island_with_lake.geojson"
  "$here/../shared/data/gis/lake_vanern_se_osm.geojson")
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

median() { sort -n "$1" | awk '{a[NR] = $1} END {print a[int((NR + 1) / 2)]}'; }

printf '| model | points | .vti s | .tif ZSTD s | ratio | .tif DEFLATE s | ratio | .vti MB | ZSTD MB | DEFLATE MB |\n'
printf '|---|---|---|---|---|---|---|---|---|---|\n'
for model in "${models[@]}"; do
  rm -f "$out"/t_*
  for _ in $(seq "$runs"); do
    for kind in vti zstd deflate; do
      case $kind in
        vti) file=$out/f.vti args=() ;;
        zstd) file=$out/z.tif args=() ;;
        deflate) file=$out/d.tif args=(--compression deflate) ;;
      esac
      /usr/bin/time -a -o "$out/t_$kind" -f %e "$sage" field "$model" --grid "${n}x$n" -q "${args[@]}" -o "$file"
    done
  done
  vti=$(median "$out/t_vti") zstd=$(median "$out/t_zstd") deflate=$(median "$out/t_deflate")
  mb() { awk -v b="$(stat -c %s "$1")" 'BEGIN {printf "%.1f", b / 1e6}'; }
  awk -v m="$(basename "$model")" -v n="$n" -v v="$vti" -v z="$zstd" -v d="$deflate" \
    -v mv="$(mb "$out/f.vti")" -v mz="$(mb "$out/z.tif")" -v md="$(mb "$out/d.tif")" \
    'BEGIN {printf "| %s | %d x %d | %.2f | %.2f | %.2f | %.2f | %.2f | %s | %s | %s |\n", m, n, n, v, z, z / v, d, d / v, mv, mz, md}'
done
