#!/usr/bin/env bash
# The gausslod tool under valgrind's memcheck on small files users have (Debian's importer test
# models: textured OBJ with materials, an OBJ with unused vertices, PLY with per-vertex texture
# coordinates, OFF, binary STL) and on two VCG leaves half-read (an STOFF file, an ASCII PLY with
# s, t), each written in its own format and as OBJ: no read of unset memory, no invalid access
# (DESIGN 49). The tool's own exit code may be any of its codes; valgrind's errors exit 99.
# usage: test_valgrind.sh GAUSSLOD ASSIMP_MODELS WORK_DIR
set -uo pipefail
tool=$1 models=$2 work=$3
rm -rf "$work"; mkdir -p "$work"
command -v valgrind >/dev/null || { echo "FAIL: valgrind is not installed (cmake/setup.sh installs it)"; exit 1; }
printf 'STOFF\n4 2 0\n0 0 0 0 0\n1 0 0 1 0\n1 1 0 1 1\n0 1 0 0 1\n3 0 1 2\n3 0 2 3\n' >"$work/st.off"
printf 'ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty float s\nproperty float t\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0 0 0\n1 0 0 1 0\n1 1 0 1 1\n0 1 0 0 1\n3 0 1 2\n3 0 2 3\n' >"$work/st.ply"
files=("$work/st.off" "$work/st.ply")
for f in PLY/cube_uv.ply OBJ/spider.obj OBJ/multiple_spaces.obj OBJ/cube_usemtl.obj OFF/Cube.off \
         STL/Spider_binary.stl; do
  if [ -f "$models/$f" ]; then files+=("$models/$f"); else echo "FAIL: missing $models/$f"; exit 1; fi
done
failures=0 runs=0
for f in "${files[@]}"; do
  for opts in "" "--format obj"; do
    name=$(basename "$f")${opts:+_obj}
    # shellcheck disable=SC2086
    timeout 300 valgrind -q --error-exitcode=99 --track-origins=yes "$tool" $opts "$f" \
      "$work/out_$name" >"$work/$name.stdout" 2>"$work/$name.stderr"
    rc=$?
    runs=$((runs + 1))
    if [ $rc -eq 99 ] || [ $rc -ge 124 ] || grep -q '^==[0-9]*== ' "$work/$name.stderr"; then
      echo "FAIL: $f ${opts:-(own format)}: exit $rc"; head -30 "$work/$name.stderr"
      failures=$((failures + 1))
    fi
  done
done
echo "$runs valgrind runs of gausslod on ${#files[@]} files, $failures with errors"
[ $failures -eq 0 ]
