#!/usr/bin/env bash
# The README's two commands:
#   bash cmake/dev.sh demo [MESH] : set up, build, run GaussLOD through meshlabserver on MESH
#                                    (default: Debian's fandisk model), writing every level to
#                                    out/<name>/ and printing the per-level table.
#   bash cmake/dev.sh test        : set up, build, run the whole test suite (unit, plugin,
#                                    meshlabserver end-to-end, GUI under Xvfb, then the core and
#                                    its tests again under AddressSanitizer + UBSan); both CTest
#                                    runs use nproc jobs (-j"$jobs"); the tests that must run
#                                    alone say so (RUN_SERIAL: the GUI test, the package test).
# Both are idempotent: a second run only rebuilds what changed.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$here"
jobs=$(nproc 2>/dev/null || echo 2)

bash cmake/setup.sh

configure_build() { # DIR [cmake args...]
  local dir=$1; shift
  if [ ! -f "$dir/CMakeCache.txt" ]; then
    cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
  fi
  cmake --build "$dir" -j"$jobs"
}

# seed_costs DIR FILE: CTest starts the longest tests first when it knows their times (DIR's
# Testing/Temporary/CTestCostData.txt, rewritten after every run); a fresh build tree starts
# from the times of a recent run, tests/ctest_costs/FILE, so that no long test starts last while
# the other jobs sit idle. Only the order changes.
seed_costs() {
  local dir=$1 file=tests/ctest_costs/$2
  mkdir -p "$dir/Testing/Temporary"
  [ -f "$dir/Testing/Temporary/CTestCostData.txt" ] || cp "$file" "$dir/Testing/Temporary/CTestCostData.txt"
}

# fuzz NAME TARGET REGRESSIONS SECONDS [SEEDS]: the known crash inputs of tests/fuzz/REGRESSIONS
# first (each must now pass), then a bounded random run (SECONDS) from build-fuzz/NAME-corpus.
fuzz() {
  local name=$1 target=build-fuzz/tests/fuzz/$2 regressions=tests/fuzz/$3 seconds=$4 seeds=${5:-}
  echo "== libFuzzer: $name ($seconds s)"
  local known=("$regressions"/*)
  [ -e "${known[0]}" ] && "$target" "${known[@]}"
  mkdir -p "build-fuzz/$name-corpus"
  if ! "$target" -max_total_time="$seconds" -timeout=20 -rss_limit_mb=4096 \
    -artifact_prefix="build-fuzz/$name-" -print_final_stats=1 "build-fuzz/$name-corpus" $seeds \
    >"build-fuzz/$name.log" 2>&1; then
    tail -n 60 "build-fuzz/$name.log"
    echo "fuzz: $name FAILED; the crash input is build-fuzz/$name-crash-*: fix, then add it to $regressions/"
    exit 1
  fi
  grep -E '^(Done|stat::number_of_executed_units|stat::new_units_added)' "build-fuzz/$name.log" || true
  echo "fuzz: $name passed (no crash, no leak, no invariant broken)"
}

case "${1:-}" in
  demo)
    mesh=${2:-.deps/cgal-data/data/meshes/fandisk.off}
    configure_build build
    name=$(basename "$mesh"); name=${name%.*}
    GAUSSLOD_MESHLAB_PREFIX="$here/build/meshlab-prefix" \
      meshlab_scripts/run_gausslod.sh "$mesh" "out/$name"
    ;;
  test)
    configure_build build
    seed_costs build release.txt
    ctest --test-dir build --output-on-failure -j"$jobs"
    echo "== core and its tests under AddressSanitizer + UndefinedBehaviorSanitizer"
    configure_build build-asan -DGAUSSLOD_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo
    seed_costs build-asan asan.txt
    ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
      ctest --test-dir build-asan --output-on-failure -j"$jobs"
    CXX=clang++ configure_build build-fuzz -DGAUSSLOD_FUZZ=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo
    fuzz engine fuzz_gausslod regressions "${GAUSSLOD_FUZZ_SECONDS:-60}"
    fuzz readers fuzz_readers reader_regressions "${GAUSSLOD_FUZZ_READERS_SECONDS:-30}" \
      tests/fuzz/reader_seeds
    # reached only if every stage passed (set -e): CTest suite, sanitizer suite, fuzzing
    echo "suites: 3 passed, 0 failed"
    ;;
  *)
    echo "usage: bash cmake/dev.sh demo [MESH] | test" >&2
    exit 2
    ;;
esac
