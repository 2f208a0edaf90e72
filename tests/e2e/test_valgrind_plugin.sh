#!/usr/bin/env bash
# The filter and our OBJ plugin in the real meshlabserver under valgrind's memcheck (through the
# runner's GAUSSLOD_SERVER_WRAPPER): no error whose stack passes through our code (MeshLab's own
# and the dynamic loader's reports are not ours) on files whose attributes VCG's readers leave
# partly unset (DESIGN 49): an OBJ with as many `vt` as `v` lines and a vertex no face uses,
# assimp's PLY with per-vertex texture coordinates, and its textured, multi-material spider.
# usage: test_valgrind_plugin.sh RUNNER ASSIMP_MODELS WORK_DIR
. "$(dirname "${BASH_SOURCE[0]}")/../cli/common.sh"
runner=$1 models=$2 work=$3
fresh_work "$work"
command -v valgrind >/dev/null || { echo "FAIL: valgrind is not installed (cmake/setup.sh installs it)"; exit 1; }
printf 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 5 5 5\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 1 1\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n' \
  >"$work/unused_vertex.obj"
for f in "$work/unused_vertex.obj" "$models/PLY/cube_uv.ply" "$models/OBJ/spider.obj"; do
  name=$(basename "$f"); name=${name%.*}
  GAUSSLOD_SERVER_WRAPPER="valgrind -q --num-callers=40 --log-file=$work/$name.vg" \
    timeout 600 bash "$runner" "$f" "$work/out_$name" >"$work/$name.log" 2>&1
  rc=$?
  check '[ $rc -eq 0 ]' "$name: the runner under valgrind exits 0 (got $rc)"
  check '[ -f "$work/$name.vg" ]' "$name: valgrind wrote its log"
  # error records (blank lines apart) with a frame of ours
  ours=$(awk '/^==[0-9]+== *$/ { if (rec ~ /gausslod|GaussLod/) n++; rec=""; next }
              { rec = rec "\n" $0 } END { if (rec ~ /gausslod|GaussLod/) n++; print n + 0 }' "$work/$name.vg")
  check '[ "$ours" = 0 ]' "$name: no valgrind error in our code (got $ours; $work/$name.vg)"
done
finish valgrind_plugin
