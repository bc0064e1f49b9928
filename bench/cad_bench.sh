#!/bin/bash
# CAD files end to end (issue 42's goals): for each STEP file, its field
# (exact, or the tessellation's), the median wall seconds of `sage info`,
# of `sage field --grid 64x64x64` and of a heat solve at degree 2 and 48
# cells (u = 0 on face 1, unit source, the other faces insulated), with
# the solve's peak MB. The baseline, run in the same loop, is the bundled
# CSG block with a channel solved at the same degree and cells: machines
# differ, the ratio to it less.
#
# Usage: bench/cad_bench.sh [SAGE] [RUNS] STEP...
#        (defaults build/cli/sage, 3; the bundled l_bracket.step and
#        ../shared/data/brep/gmsh_t20_data.step)
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
sage=${1:-$here/build/cli/sage}
runs=${2:-3}
shift $(($# < 2 ? $# : 2))
parts=("$@")
[ ${#parts[@]} -gt 0 ] || parts=("$here/examples/models/l_bracket.step" "$here/../shared/data/brep/gmsh_t20_data.step")
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

median() { sort -n "$1" | awk '{a[NR] = $1} END {print a[int((NR + 1) / 2)]}'; }
solve() {  # problem, label: appends seconds and peak KB
  /usr/bin/time -a -o "$out/t_$2" -f "%e %M" "$sage" solve "$1" -o "$out/u.vtu" --degree 2 --cells 48 --quiet \
    > /dev/null
}

printf '| part | faces | triangles | field | info s | field 64^3 s | solve s (deg 2, 48 cells) | peak MB | solve / CSG block |\n'
printf '|---|---|---|---|---|---|---|---|---|\n'
for part in "${parts[@]}"; do
  rm -f "$out"/t_*
  printf '{ "domain": "%s", "source": 1, "boundary": { "face:1": { "type": "dirichlet" },\n' "$part" > "$out/p.json"
  printf '  "default": { "type": "neumann" } } }\n' >> "$out/p.json"
  for _ in $(seq "$runs"); do
    /usr/bin/time -a -o "$out/t_info" -f %e "$sage" info "$part" > "$out/info.txt"
    /usr/bin/time -a -o "$out/t_field" -f %e "$sage" field "$part" --grid 64x64x64 -q -o "$out/f.vti"
    solve "$out/p.json" part
    solve "$here/examples/problems/block_with_hole.json" csg
  done
  faces=$(sed -n 's/^faces: *\([0-9]*\).*/\1/p' "$out/info.txt")
  triangles=$(grep -o '[0-9]* triangles;' "$out/info.txt" | grep -o '[0-9]*')
  kind=tessellated
  grep -q 'note: *exact field' "$out/info.txt" && kind=exact
  cut -d' ' -f1 "$out/t_part" > "$out/s_part"
  cut -d' ' -f1 "$out/t_csg" > "$out/s_csg"
  cut -d' ' -f2 "$out/t_part" > "$out/m_part"
  part_s=$(median "$out/s_part") csg_s=$(median "$out/s_csg")
  printf '| %s | %s | %s | %s | %s | %s | %s | %.0f | %.2f |\n' "$(basename "$part")" "$faces" "$triangles" "$kind" \
    "$(median "$out/t_info")" "$(median "$out/t_field")" "$part_s" "$(awk -v k="$(median "$out/m_part")" \
    'BEGIN {print k / 1024}')" "$(awk -v a="$part_s" -v b="$csg_s" 'BEGIN {print a / b}')"
done
