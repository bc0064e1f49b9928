#!/usr/bin/env bash
# libfive beside sage on far_field_bench's 1,000 balls (128^3 grid, one
# thread): see README.md. libfive is never a build dependency of sage; this
# script needs a libfive source tree and a build of its core library:
#   LIBFIVE_SRC   (default /tmp/libfive-src)    libfive's source
#   LIBFIVE_BUILD (default /tmp/libfive-build)  its build, with libfive/src/libfive.so
#   SAGE_BUILD    (default <repo>/build)        a Release build of sage with far_field_bench
# Without them it says how to get them and stops.
#   bash bench/libfive_compare/run.sh [--runs R] [--skip-brute-grad]
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
src="${LIBFIVE_SRC:-/tmp/libfive-src}"
lfb="${LIBFIVE_BUILD:-/tmp/libfive-build}"
sage_build="${SAGE_BUILD:-$here/../../build}"
work="${WORK_DIR:-/tmp/libfive-compare}"
n=128

if [ ! -f "$lfb/libfive/src/libfive.so" ] || [ ! -d "$src/libfive/include" ]; then
  cat <<EOF
libfive is not built (looked for $lfb/libfive/src/libfive.so and $src/libfive/include).
Get and build its core library (no Studio, no bindings), e.g.:
  git clone https://github.com/libfive/libfive $src
  cmake -S $src -B $lfb -G Ninja -DCMAKE_BUILD_TYPE=Release -DENABLE_DEBUG=OFF \\
        -DBUILD_STUDIO_APP=OFF -DBUILD_GUILE_BINDINGS=OFF -DBUILD_PYTHON_BINDINGS=OFF -DBUILD_TESTS=OFF
  ninja -C $lfb libfive
(Debian 12: apt-get install libeigen3-dev libpng-dev libboost-dev; libfive adds -O3 -march=native itself.)
EOF
  exit 0
fi
if [ ! -x "$sage_build/bench/far_field_bench" ]; then
  echo "no $sage_build/bench/far_field_bench: build sage first (Release)"; exit 1
fi
mkdir -p "$work"
echo "libfive: $(git -C "$src" rev-parse HEAD 2>/dev/null || cat "$src/COMMIT" 2>/dev/null || echo 'commit unknown')"
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
echo

# sage's own benchmark, one thread; also writes the two ball models to /tmp.
for order in 0 1; do
  echo "== OMP_NUM_THREADS=1 far_field_bench $order 200,$n balls"
  OMP_NUM_THREADS=1 "$sage_build/bench/far_field_bench" "$order" "200,$n" balls
  echo
done

# sage's values and checksums (links the static libraries of sage's build,
# with far_field_bench's compile flags and link line).
S="$(cd "$here/../.." && pwd)"
libs=$(sed -n '/^build bench\/far_field_bench:/,/^$/s/^  LINK_LIBRARIES = //p' "$sage_build/build.ninja" |
       sed "s#\(^\| \)\([a-z_]*/libsage_[a-z_]*\.a\)#\1$sage_build/\2#g")
g++ -O3 -DNDEBUG -fopenmp -std=c++20 -I"$S/libsage/include" -I"$S/geometry/include" -isystem /usr/include/eigen3 \
    "$here/sage_checksum.cpp" -o "$work/sage_checksum" $libs
echo "== OMP_NUM_THREADS=1 sage_checksum $n"
OMP_NUM_THREADS=1 "$work/sage_checksum" "$n"
echo

# libfive's side: same -O3 -march=native as libfive's own build (Eigen's
# alignment must match the library's).
g++ -O3 -march=native -DEIGEN_NO_DEBUG -DNDEBUG -std=c++20 -I"$src/libfive/include" -I"$S/libsage/include" \
    -isystem /usr/include/eigen3 \
    "$here/balls.cpp" -o "$work/balls" "$lfb/libfive/src/libfive.so" -Wl,-rpath,"$lfb/libfive/src" -lpthread
echo "== balls --grid $n $*"
"$work/balls" --grid "$n" "$@" /tmp/far_field_bench_balls_minmax.json
