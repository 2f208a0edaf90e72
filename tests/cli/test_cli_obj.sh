#!/usr/bin/env bash
# The gausslod tool reads real OBJ files whole (VCG 2020.09's importer, fixed in
# vcg_core/gausslod/obj_import.h, skipped every face using the first vertex) and refuses a broken
# one with a message.
# usage: test_cli_obj.sh GAUSSLOD OBJ_DIR WORK_DIR
. "$(dirname "${BASH_SOURCE[0]}")/common.sh"
tool=$1 objdir=$2 work=$3
fresh_work "$work"
input_faces() { "$tool" "$1" "$work/$(basename "$1" .obj)" 2>&1 | awk '$1 == "input" && $2 ~ /^[0-9]+$/ { print $2 }'; }

printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >"$work/triangle.obj"
n=$(input_faces "$work/triangle.obj"); check '[ "$n" = 1 ]' "one triangle read ($n)"
n=$(input_faces "$objdir/spider.obj"); check '[ "$n" = 1368 ]' "spider.obj: 1368 faces read ($n)"
n=$(input_faces "$objdir/regr01.obj"); check '[ "$n" = 2710 ]' "regr01.obj: 2710 faces read ($n)"
"$tool" "$objdir/../invalid/malformed.obj" "$work/malformed" >"$work/malformed.log" 2>&1
rc=$?
check '[ $rc -ne 0 ] && grep -q "vertex .12. but 8 vertices" "$work/malformed.log"' \
  "malformed.obj: refused (exit $rc) naming the bad index"
finish test_cli_obj
