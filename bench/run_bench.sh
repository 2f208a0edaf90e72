#!/usr/bin/env bash
# GaussLOD benchmark: builds what it needs, runs every method on every model, writes
# bench/results/RESULTS.md (+ PNG plots, raw.jsonl). See bench/README.md.
#   bench/run_bench.sh            full run (~20 min on 2 cores)
#   bench/run_bench.sh --quick    smoke test (4 small models, ~2 min) -> bench/results/quick/
# Other options are passed to run_bench.py (--models a,b --methods ... --samples N ...).
# Environment: BENCH_BUILD (build folder, default <repo>/build-bench-peers), BENCH_JOBS (2).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(dirname "$here")"
build="${BENCH_BUILD:-$root/build-bench-peers}"
jobs="${BENCH_JOBS:-2}"

# the peers and tools from Debian, installed when missing (as root; apt-get update first)
bash "$root/cmake/setup.sh"
want=(libmeshoptimizer-dev libopenmesh-dev time gnuplot-nox blender)
need=()
for p in "${want[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || need+=("$p")
done
if [ ${#need[@]} -gt 0 ] && [ "$(id -u)" = 0 ]; then
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null
fi
missing=()
for tool in cmake g++ python3 /usr/bin/time gnuplot; do
  command -v "$tool" >/dev/null 2>&1 || missing+=("$tool")
done
[ -f /usr/include/meshoptimizer.h ] || missing+=("libmeshoptimizer-dev")
[ -f /usr/include/OpenMesh/Tools/Decimater/DecimaterT.hh ] || missing+=("libopenmesh-dev")
if [ ${#missing[@]} -gt 0 ]; then
  echo "run_bench.sh: missing ${missing[*]} (Debian: apt-get install libmeshoptimizer-dev libopenmesh-dev time gnuplot-nox;" \
       "optional peers: meshlab xvfb xauth blender)" >&2
  exit 1
fi
command -v meshlabserver >/dev/null 2>&1 && command -v xvfb-run >/dev/null 2>&1 \
  || echo "run_bench.sh: meshlabserver/xvfb-run not found: MeshLab rows will say so" >&2
command -v blender >/dev/null 2>&1 || echo "run_bench.sh: blender not found: Blender rows will say so" >&2

if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
cmake --build "$build" -j"$jobs" --target gausslod bench_gen bench_load bench_peers bench_metrics bench_texdev

export BENCH_CMDLINE="bench/run_bench.sh${*:+ $*}"
python3 "$here/run_bench.py" --build "$build" "$@"
# the face budgets users ask for (issue 37): organic models and a textured scan, every peer at
# our levels' counts -> BUDGETS.md beside RESULTS.md (not with --quick)
case " $* " in
  *" --quick "*) ;;
  *) results=$root/bench/results prev=
     for a in "$@"; do case $prev in --results) results=$a ;; esac; prev=$a; done
     python3 "$here/budget_rows.py" --build "$build" --results "$results" ;;
esac
