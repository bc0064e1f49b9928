#!/usr/bin/env bash
# Coverage-guided fuzzing with libFuzzer (fuzz/, README.md "Tests and
# benchmarks"). Installs clang and its runtimes, builds only the fuzz
# targets and the libraries they need in build-fuzz (clang, -O1 -g,
# AddressSanitizer, UndefinedBehaviorSanitizer, LeakSanitizer), replays
# fuzz/regressions, then runs each target for SECONDS (default 60) on a copy
# of its seed corpus, as many at once as there are cores. Any finding (a
# crash, a sanitizer report, a leak, a timeout, too much memory) fails the
# run and prints the reproducer's path.
#
#   bash scripts/fuzz.sh [SECONDS] [TARGET...]
#
# TARGET: model problem formula mesh geojson solve (default: all).
set -euo pipefail
cd "$(dirname "$0")/.."

seconds="${1:-60}"
[ $# -gt 0 ] && shift
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(model problem formula mesh geojson solve)

bash scripts/install-deps.sh clang libclang-rt-14-dev libomp-dev

build=build-fuzz
start=$(date +%s)
cmake -S . -B "$build" -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" -DSAGE_FUZZ=ON \
      -DSAGE_BUILD_TESTS=OFF -DSAGE_BUILD_BENCH=OFF -DSAGE_BUILD_EXAMPLES=OFF >/dev/null
cmake --build "$build" --target sage_fuzz --parallel "$(nproc)"
echo "fuzz: built in $(( $(date +%s) - start )) s"

# Per run: copies of the seeds (libFuzzer adds what it finds there, never to
# fuzz/corpus), findings, logs, and the targets' scratch folders (TMPDIR).
run="$build/run"
rm -rf "$run"
mkdir -p "$run/tmp"
export TMPDIR="$PWD/$run/tmp"
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1

max_len() {
  case "$1" in
    formula) echo 512 ;;
    mesh | geojson) echo 16384 ;;
    *) echo 4096 ;;
  esac
}

# fuzz_one TARGET: regressions, then SECONDS of fuzzing; the exit code in rc.
fuzz_one() {
  local t="$1" exe="$PWD/$build/fuzz/sage_fuzz_$1" dir="$PWD/$run/$1"
  mkdir -p "$dir/corpus" "$dir/findings"
  cp fuzz/corpus/"$t"/* "$dir/corpus/"
  local options=(-timeout=30 -rss_limit_mb=2048 -max_len="$(max_len "$t")" -artifact_prefix="$dir/findings/"
                 -dict="$PWD/fuzz/dict/$t.dict" -print_final_stats=1)
  local rc=0
  if compgen -G "fuzz/regressions/$t/*" >/dev/null; then
    echo "== $t: replaying fuzz/regressions/$t"
    "$exe" "${options[@]}" fuzz/regressions/"$t"/* || rc=$?
  fi
  if [ "$rc" -eq 0 ]; then
    echo "== $t: fuzzing for $seconds s"
    "$exe" "${options[@]}" -max_total_time="$seconds" "$dir/corpus" || rc=$?
  fi
  echo "$rc" >"$dir/rc"
}

for t in "${targets[@]}"; do
  [ -x "$build/fuzz/sage_fuzz_$t" ] || { echo "fuzz: no target '$t'" >&2; exit 2; }
  while [ "$(jobs -rp | wc -l)" -ge "$(nproc)" ]; do wait -n || true; done
  fuzz_one "$t" >"$run/$t.log" 2>&1 &
done
wait

failed=0
for t in "${targets[@]}"; do
  log="$run/$t.log"
  rc=$(cat "$run/$t/rc" 2>/dev/null || echo 1)
  last=$(grep -a -E '^#[0-9]+' "$log" | tail -1 || true)
  speed=$(grep -a -oE 'stat::average_exec_per_sec: *[0-9]+' "$log" | tail -1 | grep -oE '[0-9]+$' || true)
  echo "fuzz: $t: exit $rc, ${speed:-?} exec/s, last: ${last:-none}"
  if [ "$rc" -ne 0 ]; then
    failed=1
    echo "---- $t: the end of $log"
    tail -n 60 "$log"
    # libFuzzer saves what it found; a saved input that fails on replay is
    # the last one it was running.
    findings=("$run/$t"/findings/{crash,leak,timeout,oom}-*)
    [ -e "${findings[0]}" ] || findings=("$(grep -a -oE '^Running: .*' "$log" | tail -1 | cut -c10-)")
    for f in "${findings[@]}"; do
      [ -e "$f" ] || continue
      echo "FINDING ($t): $f"
      echo "  reproduce: $build/fuzz/sage_fuzz_$t $f"
    done
  fi
done
echo "fuzz: ${#targets[@]} targets, $seconds s each, done in $(( $(date +%s) - start )) s"
exit "$failed"
