#!/usr/bin/env bash
# Real OBJ files (Debian's assimp-testmodels) through the real meshlabserver of a MeshLab prefix
# holding our OBJ plugin, and through the runner: textures, texture coordinates, materials,
# n-gons, export and re-import, a broken file; and Debian's own meshlabserver, which must still
# behave as it does without our package.
# usage: test_obj_io.sh MESHLAB_PREFIX RUNNER OBJ_DIR WORK_DIR
. "$(dirname "${BASH_SOURCE[0]}")/../cli/common.sh"
prefix=$1 runner=$2 objdir=$3 work=$4
fresh_work "$work" config runtime; chmod 700 "$work/runtime"
export XDG_CONFIG_HOME=$work/config XDG_RUNTIME_DIR=$work/runtime

# server NAME BINARY ARGS...: meshlabserver under xvfb-run, output in $work/NAME.log, sets $rc
server() {
  local name=$1 bin=$2; shift 2
  timeout 120 xvfb-run -a "$bin" "$@" >"$work/$name.log" 2>&1
  rc=$?
  echo "---- $name (exit $rc): meshlabserver $*"; grep -v '^$' "$work/$name.log" | tail -n 4
}
ml=$prefix/bin/meshlabserver
header() { LC_ALL=C sed -n '1,/^end_header/p' "$1"; }
element() { header "$1" | awk -v e="$2" '$1 == "element" && $2 == e { print $3 }'; }

# 1. the textured spider (5 textures named '.\x.jpg' in its MTL, 19 usemtl) to an ASCII PLY
server spider "$ml" -i "$objdir/spider.obj" -o "$work/spider.ply" -m wt fc sa
check '[ $rc -eq 0 ]' "spider: exit 0"
check 'grep -q "loaded has 762 vn 1368 fn" "$work/spider.log"' "spider: all 762 vertices, 1368 faces"
check '[ "$(element "$work/spider.ply" face)" = 1368 ]' "spider: 1368 faces saved"
check 'header "$work/spider.ply" | grep -q "property list uchar float texcoord"' \
  "spider: per-corner texture coordinates saved"
mapfile -t textures < <(header "$work/spider.ply" | sed -n 's/^comment TextureFile //p' | tr -d '\r')
check '[ ${#textures[@]} -eq 5 ]' "spider: 5 textures (${textures[*]})"
for t in "${textures[@]}"; do
  check '[ -f "$objdir/$t" ]' "spider: texture $t exists next to the OBJ"
done
# the first face of the PLY is the file's first face, f 1/1/1 2/2/2 3/3/3: vt 1, 2, 3 in order
vts=$(grep -m3 '^vt ' "$objdir/spider.obj" | awk '{ printf "%g %g ", $2, $3 }')
first=$(LC_ALL=C awk '/^end_header/ { h = 1; next } h && ++n == 763 {
  for (i = 6; i <= 11; i++) printf "%g ", $i; exit }' "$work/spider.ply")
check '[ "$first" = "$vts" ]' "spider: face 1's texture coordinates are vt 1, 2, 3 ($first)"
check 'header "$work/spider.ply" | grep -q "property uchar red"' "spider: material colours saved"

# 2. io_base's OBJ export of what our plugin read, and our plugin reading that back
server export "$ml" -i "$objdir/spider.obj" -o "$work/spider_out.obj" -m wt
check '[ $rc -eq 0 ] && [ "$(grep -c "^f " "$work/spider_out.obj")" = 1368 ]' \
  "export: 1368 faces written"
# (the spider's material Brusttex, texture wal69ar_small.jpg, is used by no face)
check '[ "$(grep "^map_Kd" "$work/spider_out.obj.mtl" 2>/dev/null | sort -u | wc -l)" = 4 ]' \
  "export: the MTL names the 4 textures the faces use"
server reimport "$ml" -i "$work/spider_out.obj" -o "$work/spider_again.ply" -m wt
check '[ $rc -eq 0 ] && grep -q "loaded has [0-9]* vn 1368 fn" "$work/reimport.log"' \
  "re-import of the export: 1368 faces"

# 3. several materials without textures: face colours from Kd; a concave 66-gon: 64 triangles
server regr01 "$ml" -i "$objdir/regr01.obj" -o "$work/regr01.ply" -m fc sa
check '[ $rc -eq 0 ] && grep -q "loaded has 2108 vn 2710 fn" "$work/regr01.log"' "regr01: 2710 faces"
ncolours=$(LC_ALL=C awk '/^end_header/ { h = 1; next } h && ++n > 2108 { print $(NF-3), $(NF-2), $(NF-1) }' \
  "$work/regr01.ply" | sort -u | wc -l)
check '[ "$ncolours" -ge 10 ]' "regr01: faces coloured by their materials ($ncolours colours)"
server ngon "$ml" -i "$objdir/concave_polygon.obj" -o "$work/ngon.ply"
check '[ $rc -eq 0 ] && grep -q "loaded has 64 vn 64 fn" "$work/ngon.log"' \
  "concave 66-gon: triangulated into 64 faces"

# 4. a broken file: an error naming the problem, no abort
server malformed "$ml" -i "$objdir/../invalid/malformed.obj" -o "$work/malformed.ply"
check '[ $rc -ne 0 ] && [ $rc -ne 134 ] && [ ! -e "$work/malformed.ply" ]' \
  "malformed.obj: refused (exit $rc), not an abort"
check 'grep -q "vertex 12 is not among the 8 vertices" "$work/malformed.log"' \
  "malformed.obj: the message names the bad index"

# 5. the runner on the textured OBJ: every level
GAUSSLOD_MESHLAB_PREFIX=$prefix "$runner" "$objdir/spider.obj" "$work/levels" >"$work/runner.log" 2>&1
rc=$?
cat "$work/runner.log"
check '[ $rc -eq 0 ]' "runner on spider.obj: exit 0"
for level in 4 3 2 1 0; do
  f=$work/levels/spider_LOD$level.ply
  faces=$( [ -s "$f" ] && element "$f" face)
  check '[ -n "$faces" ] && [ "$faces" -gt 0 ]' "runner: spider_LOD$level.ply has $faces faces"
  # what the input has, and nothing it lacks (issue 14): texture coordinates, its 5 textures
  # found from OUTDIR, material colours; no vertex colours
  check 'header "$f" | grep -q "property list uchar float texcoord"' \
    "runner: spider_LOD$level.ply keeps per-corner texture coordinates"
  mapfile -t lt < <(header "$f" | sed -n 's/^comment TextureFile //p' | tr -d '\r')
  check '[ "${lt[*]}" = "${textures[*]}" ]' "runner: spider_LOD$level.ply names the input's textures"
  for t in "${lt[@]}"; do
    check '[ -f "$work/levels/$t" ]' "runner: texture $t of LOD$level found from OUTDIR"
  done
  vprops=$(header "$f" | awk '$1 == "element" { e = $2 } e == "vertex" && $1 == "property" { print $NF }' | tr '\n' ' ')
  check '[ "$vprops" = "x y z " ]' "runner: spider_LOD$level.ply adds no vertex attribute ($vprops)"
  fprops=$(header "$f" | awk '$1 == "element" { e = $2 } e == "face" && $1 == "property" { print $NF }' | tr '\n' ' ')
  check '[ "$fprops" = "vertex_indices texcoord texnumber red green blue alpha " ]' \
    "runner: spider_LOD$level.ply faces: texture coordinates, texture numbers, material colours"
done
check 'grep -q "Carried to the levels: wedge texture coordinates, face colour; textures: " "$work/runner.log"' \
  "runner: says what the levels carry"

# 5b. vertex colours (an OBJ with 'v x y z r g b'): saved, each an input vertex's colour
GAUSSLOD_MESHLAB_PREFIX=$prefix "$runner" "$objdir/cube_with_vertexcolors.obj" "$work/vc" \
  >"$work/runner_vc.log" 2>&1
check '[ $? -eq 0 ]' "runner on cube_with_vertexcolors.obj: exit 0"
f=$work/vc/cube_with_vertexcolors_LOD0.ply
vprops=$(header "$f" | awk '$1 == "element" { e = $2 } e == "vertex" && $1 == "property" { print $NF }' | tr '\n' ' ')
check '[[ "$vprops" == "x y z "*"red green blue alpha " ]]' "runner: vertex colours saved ($vprops)"
# (VCG's OBJ reader truncates r * 255)
want=$(awk '$1 == "v" { printf "%d %d %d\n", int($5 * 255), int($6 * 255), int($7 * 255) }' \
  "$objdir/cube_with_vertexcolors.obj" | sort -u)
got=$(python3 - "$f" <<'PY' | sort -u
import re, struct, sys
d = open(sys.argv[1], 'rb').read()
end = d.index(b'end_header\n') + len(b'end_header\n')
head = d[:end].decode('ascii').split('\n')
assert 'format binary_little_endian 1.0' in head
n = int(re.search(r'element vertex (\d+)', d[:end].decode()).group(1))
props, inv = [], False
for line in head:
    w = line.split()
    if w[:1] == ['element']:
        inv = w[1] == 'vertex'
    elif inv and w[:1] == ['property']:
        props.append((w[2], w[1]))
size = {'float': 4, 'uchar': 1}
fmt = '<' + ''.join({'float': 'f', 'uchar': 'B'}[t] for _, t in props)
step = sum(size[t] for _, t in props)
names = [p for p, _ in props]
for i in range(n):
    v = dict(zip(names, struct.unpack_from(fmt, d, end + i * step)))
    print(v['red'], v['green'], v['blue'])
PY
)
check '[ -n "$got" ] && [ "$got" = "$want" ]' "runner: the level's vertex colours are the file's"

# 5c. a PLY with float vertex colours, which VCG 2020.09 does not read: the levels get none
GAUSSLOD_MESHLAB_PREFIX=$prefix "$runner" "$objdir/../PLY/float-color.ply" "$work/floatc" \
  >"$work/runner_floatc.log" 2>&1
check '[ $? -eq 0 ]' "runner on float-color.ply: exit 0"
vprops=$(header "$work/floatc/float-color_LOD0.ply" |
  awk '$1 == "element" { e = $2 } e == "vertex" && $1 == "property" { print $NF }' | tr '\n' ' ')
check '[ "$vprops" = "x y z " ]' "runner: float-color.ply's level adds no vertex colour ($vprops)"

# 6. the runner with a prefix lacking our OBJ plugin: a clear error instead of MeshLab's abort
mkdir -p "$work/noobj/bin" "$work/noobj/lib/x86_64-linux-gnu/meshlab/plugins"
cp -a "$prefix/bin/meshlabserver" "$work/noobj/bin/"
cp -a "$prefix/lib/x86_64-linux-gnu/meshlab/libmeshlab-common.so" "$work/noobj/lib/x86_64-linux-gnu/meshlab/"
cp -a "$prefix/lib/x86_64-linux-gnu/meshlab/plugins/." "$work/noobj/lib/x86_64-linux-gnu/meshlab/plugins/"
rm -f "$work/noobj/lib/x86_64-linux-gnu/meshlab/plugins/libgausslod_io_obj.so"
GAUSSLOD_MESHLAB_PREFIX=$work/noobj "$runner" "$objdir/spider.obj" "$work/noobj_levels" \
  >"$work/runner_noobj.log" 2>&1
rc=$?
check '[ $rc -ne 0 ] && [ $rc -ne 134 ] && grep -q "has no libgausslod_io_obj.so" "$work/runner_noobj.log"' \
  "runner without our OBJ plugin: exit $rc with a message"

# 7. Debian's meshlabserver is left as it was: without our plugin installed it still aborts
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >"$work/triangle.obj"
if [ -e /usr/lib/x86_64-linux-gnu/meshlab/plugins/libgausslod_io_obj.so ]; then
  server system /usr/bin/meshlabserver -i "$work/triangle.obj" -o "$work/system.ply"
  check '[ $rc -eq 0 ] && [ -s "$work/system.ply" ]' "system meshlabserver with our package: opens OBJ"
else
  server system /usr/bin/meshlabserver -i "$work/triangle.obj" -o "$work/system.ply"
  check '[ $rc -eq 134 ] && grep -q "import_obj.h:640" "$work/system.log"' \
    "system meshlabserver without our package: unchanged (aborts at import_obj.h:640, exit $rc)"
fi

finish test_obj_io
