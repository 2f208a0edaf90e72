#!/usr/bin/env bash
# The README's two commands:
#   bash cmake/dev.sh demo [MESH] : set up, build, run GaussLOD through meshlabserver on MESH
#                                    (default: Debian's fandisk model), writing every level to
#                                    out/<name>/ and printing the per-level table.
#   bash cmake/dev.sh test        : set up, build, run the whole test suite (unit, plugin,
#                                    meshlabserver end-to-end, GUI under Xvfb, then the core and
#                                    its tests again under AddressSanitizer + UBSan).
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
    ctest --test-dir build --output-on-failure -j1
    echo "== core and its tests under AddressSanitizer + UndefinedBehaviorSanitizer"
    configure_build build-asan -DGAUSSLOD_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo
    ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
      ctest --test-dir build-asan --output-on-failure -j1
    echo "== libFuzzer on the core (${GAUSSLOD_FUZZ_SECONDS:-60} s; GAUSSLOD_FUZZ_SECONDS to change)"
    CXX=clang++ configure_build build-fuzz -DGAUSSLOD_FUZZ=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo
    # known crash inputs first (each must now pass), then a bounded random run
    regressions=(tests/fuzz/regressions/*)
    [ -e "${regressions[0]}" ] && build-fuzz/tests/fuzz/fuzz_gausslod "${regressions[@]}"
    mkdir -p build-fuzz/corpus
    if ! build-fuzz/tests/fuzz/fuzz_gausslod -max_total_time="${GAUSSLOD_FUZZ_SECONDS:-60}" \
      -timeout=20 -rss_limit_mb=4096 -artifact_prefix=build-fuzz/ -print_final_stats=1 \
      build-fuzz/corpus >build-fuzz/fuzz.log 2>&1; then
      tail -n 60 build-fuzz/fuzz.log
      echo "fuzz: FAILED; the crash input is in build-fuzz/ (crash-*): fix, then add it to tests/fuzz/regressions/"
      exit 1
    fi
    grep -E '^(Done|stat::number_of_executed_units|stat::new_units_added)' build-fuzz/fuzz.log || true
    echo "fuzz: passed (no crash, no invariant broken)"
    echo "== libFuzzer on the file readers (${GAUSSLOD_FUZZ_READERS_SECONDS:-30} s; GAUSSLOD_FUZZ_READERS_SECONDS to change)"
    reader_regressions=(tests/fuzz/reader_regressions/*)
    [ -e "${reader_regressions[0]}" ] && build-fuzz/tests/fuzz/fuzz_readers "${reader_regressions[@]}"
    mkdir -p build-fuzz/reader_corpus
    if ! build-fuzz/tests/fuzz/fuzz_readers -max_total_time="${GAUSSLOD_FUZZ_READERS_SECONDS:-30}" \
      -timeout=20 -rss_limit_mb=4096 -artifact_prefix=build-fuzz/readers- -print_final_stats=1 \
      build-fuzz/reader_corpus tests/fuzz/reader_seeds >build-fuzz/fuzz_readers.log 2>&1; then
      tail -n 60 build-fuzz/fuzz_readers.log
      echo "fuzz: FAILED; the crash input is in build-fuzz/ (readers-crash-*): fix, then add it to tests/fuzz/reader_regressions/"
      exit 1
    fi
    grep -E '^(Done|stat::number_of_executed_units|stat::new_units_added)' build-fuzz/fuzz_readers.log || true
    echo "fuzz: readers passed (no crash, no leak, no invariant broken)"
    # reached only if every stage passed (set -e): CTest suite, sanitizer suite, fuzzing
    echo "suites: 3 passed, 0 failed"
    ;;
  *)
    echo "usage: bash cmake/dev.sh demo [MESH] | test" >&2
    exit 2
    ;;
esac
