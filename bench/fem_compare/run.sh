#!/usr/bin/env bash
# Kirsch's plate with a fitted-mesh finite-element solver (FreeFem++, from
# Debian: apt-get install freefem++), beside `solve_bench elasticity`'s
# Kirsch tables. FreeFem++ is never a build dependency of sage: without it
# this script says so and stops.
#   bash bench/fem_compare/run.sh [ELEMENTS...]   (default 16 32 64)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
if ! command -v FreeFem++-nw >/dev/null; then
  echo "FreeFem++ is not installed (apt-get install freefem++): no comparison run"
  exit 0
fi
sizes=("$@")
[ ${#sizes[@]} -eq 0 ] && sizes=(16 32 64)
for n in "${sizes[@]}"; do
  FreeFem++-nw -v 0 "$here/kirsch.edp" -n "$n" 2>&1 | grep '^P2' || true
done
