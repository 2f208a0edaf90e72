#!/usr/bin/env bash
# run_gausslod.sh INPUT OUTDIR [SCRIPT.mlx] [--format glb|gltf] [--lod-file] [--3dtiles]
#                 [--tiles-transform M]
#
# Runs the GaussLOD MeshLab filter on INPUT with meshlabserver (under xvfb-run: meshlabserver 2020.09
# needs an X server) and saves every layer the filter adds as OUTDIR/<name>_LOD<level>.ply, with
# the attributes the input has (vertex colour and quality, vertex and wedge texture coordinates
# with the texture file names, face colours: OBJ materials arrive as face colours and texture
# indices) and nothing it lacks. Textures named by a relative path are copied to the same relative
# path under OUTDIR (when OUTDIR is not the input's folder), so that the levels find them.
# SCRIPT defaults to gausslod_default.mlx next to this file; it must hold the GaussLOD filter, and
# its maxLevel/outputLevels say which levels come out (layers 1..N, finest first, after the input).
# The glTF options (as the gausslod tool's: glb or gltf levels, the MSFT_lod chain file, a 3D Tiles
# tileset with the certified distances) also write the levels for renderers into OUTDIR: the tool
# makes them with the script's parameters (gausslod --from-mlx), and the runner checks that they
# have the face counts of MeshLab's layers (exit 1 if not).
#
# meshlabserver: $GAUSSLOD_MESHLAB_PREFIX/bin/meshlabserver if that variable is set, else the
# build tree's private prefix <repo>/build/meshlab-prefix, else the system meshlabserver if the
# plugin is installed system-wide. An OBJ input needs our OBJ plugin beside it (Debian's MeshLab
# 2020.09 aborts on every OBJ file without it). $GAUSSLOD_SERVER_WRAPPER, if set, is put before it
# (words split at blanks: a debugger or `valgrind --log-file=...`).
#
# The input is first read and checked by the gausslod tool ($GAUSSLOD_TOOL, else the build tree's,
# else gausslod on PATH): the same reader, messages and exit codes as the tool, since Debian's
# meshlabserver aborts or crashes on some broken files instead of saying what is wrong.
#
# Exit status (as the gausslod tool's): 0 = every level saved; 1 = meshlabserver or the filter
# failed; 2 = bad usage or script; 3 = the input cannot be opened; 4 = not a readable mesh file;
# 5 = nothing to simplify (no faces, bad coordinates); 6 = not enough memory; 7 = an expected
# output file is missing or empty.
set -euo pipefail

me=$(basename "$0")
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(cd "$here/.." && pwd)
filter_name="Gauss Sphere LOD: Merge Near-Coplanar Faces"
plugin_so=libfilter_gausslod.so
obj_plugin_so=libgausslod_io_obj.so
multiarch=x86_64-linux-gnu

die() { local code=$1; shift; echo "$me: error: $*" >&2; exit "$code"; }

usage="usage: $me INPUT OUTDIR [SCRIPT.mlx] [--format glb|gltf] [--lod-file] [--3dtiles] [--tiles-transform M]"
[ $# -ge 2 ] || { echo "$usage" >&2; exit 2; }
input=$1 outdir=$2; shift 2
script=$here/gausslod_default.mlx
if [ $# -gt 0 ] && [[ $1 != --* ]]; then script=$1; shift; fi
gltf_opts=()
while [ $# -gt 0 ]; do
  case $1 in
    --lod-file | --3dtiles) gltf_opts+=("$1"); shift ;;
    --format | --tiles-transform)
      [ $# -ge 2 ] || { echo "$me: $1 needs a value" >&2; exit 2; }
      [ "$1" != --format ] || [ "$2" = glb ] || [ "$2" = gltf ] ||
        { echo "$me: --format here is glb or gltf (MeshLab's layers are saved as PLY)" >&2; exit 2; }
      gltf_opts+=("$1" "$2"); shift 2 ;;
    *) echo "$usage" >&2; exit 2 ;;
  esac
done

[ -e "$input" ] || die 3 "input file not found: $input"
[ -f "$input" ] && [ -r "$input" ] || die 3 "input is not a readable file: $input"
[ -s "$input" ] || die 4 "input file is empty: $input"
[ -f "$script" ] && [ -r "$script" ] || die 2 "script not found: $script"
grep -qF "name=\"$filter_name\"" "$script" || die 2 "script $script does not run the filter '$filter_name'"

# --- the input, checked by the gausslod tool ---------------------------------------------------------
tool=${GAUSSLOD_TOOL:-}
[ -n "$tool" ] || { [ -x "$repo/build/gausslod" ] && tool=$repo/build/gausslod; } ||
  tool=$(command -v gausslod || true)
if [ -n "$tool" ]; then
  set +e
  check=$("$tool" --check "$input" 2>&1)
  rc=$?
  set -e
  [ $rc -eq 0 ] || die "$rc" "${check#gausslod: }"
else
  echo "$me: warning: no gausslod tool to check $input first (GAUSSLOD_TOOL)" >&2
fi

# --- meshlabserver with the GaussLOD plugin --------------------------------------------------------
if [ -n "${GAUSSLOD_MESHLAB_PREFIX:-}" ]; then
  server=$GAUSSLOD_MESHLAB_PREFIX/bin/meshlabserver
  plugdir=$GAUSSLOD_MESHLAB_PREFIX/lib/$multiarch/meshlab/plugins
  [ -x "$server" ] || die 2 "GAUSSLOD_MESHLAB_PREFIX=$GAUSSLOD_MESHLAB_PREFIX has no bin/meshlabserver"
  [ -e "$plugdir/$plugin_so" ] ||
    die 2 "GAUSSLOD_MESHLAB_PREFIX=$GAUSSLOD_MESHLAB_PREFIX has no plugins/$plugin_so"
elif [ -x "$repo/build/meshlab-prefix/bin/meshlabserver" ]; then
  server=$repo/build/meshlab-prefix/bin/meshlabserver
  plugdir=$repo/build/meshlab-prefix/lib/$multiarch/meshlab/plugins
elif [ -e "/usr/lib/$multiarch/meshlab/plugins/$plugin_so" ] && command -v meshlabserver >/dev/null; then
  server=$(command -v meshlabserver)
  plugdir=/usr/lib/$multiarch/meshlab/plugins
else
  die 2 "no meshlabserver with the GaussLOD plugin: build the project (cmake --build build), set" \
        "GAUSSLOD_MESHLAB_PREFIX, or install the plugin"
fi
command -v xvfb-run >/dev/null || die 2 "xvfb-run not found (Debian package xvfb)"
if [[ ${input,,} == *.obj ]] && [ ! -e "$plugdir/$obj_plugin_so" ]; then
  die 2 "$input is an OBJ file and $plugdir has no $obj_plugin_so: Debian's MeshLab 2020.09" \
        "aborts on every OBJ file without it (build the project or install its package)"
fi

# --- which levels the script asks for (finest first = the order of the new layers) ---------------
param() { # value of <Param name="$1" ...> in the script, or empty
  grep -o "<Param[^>]*name=\"$1\"[^>]*>" "$script" | head -n1 | grep -o 'value="[^"]*"' |
    sed 's/^value="//; s/"$//' || true
}
max_level=$(param maxLevel); max_level=${max_level:-5}
# levels by target (levelsBy 1 = face budgets or 2 = error targets, the list in levelTargets; in a
# script written when levelsBy was text, "faces:50%,25%" or "error:0.01%,0.2%"): one level per
# target; a bad list is the filter's to explain
levels_by=$(param levelsBy | tr -d ' ' | tr '[:upper:]' '[:lower:]')
case $levels_by in
  1 | 2) targets=$(param levelTargets | tr -d ' ')
         [ -n "$targets" ] && max_level=$(echo "$targets" | awk -F, '{ print NF }') ;;
  faces:?* | error:?*) max_level=$(echo "${levels_by#*:}" | awk -F, '{ print NF }') ;;
esac
output_levels=$(param outputLevels); output_levels=${output_levels:-all}
[[ $max_level =~ ^[0-9]+$ ]] && [ "$max_level" -ge 1 ] ||
  die 2 "maxLevel '$max_level' in $script is not a positive number"
levels=()
if [ "$(echo "$output_levels" | tr -d ' ' | tr '[:upper:]' '[:lower:]')" = all ]; then
  for ((l = max_level - 1; l >= 0; l--)); do levels+=("$l"); done
else
  mapfile -t levels < <(echo "$output_levels" | tr ',' '\n' | tr -d ' ')
  for l in "${levels[@]}"; do
    [[ $l =~ ^[0-9]+$ ]] && [ "$l" -lt "$max_level" ] ||
      die 2 "outputLevels '$output_levels' in $script: '$l' is not a level of 0..$((max_level - 1))"
  done
  mapfile -t levels < <(printf '%s\n' "${levels[@]}" | sort -rnu) # finest first, as the layers
fi
[ ${#levels[@]} -gt 0 ] || die 2 "outputLevels '$output_levels' in $script selects no level"
# What meshlabserver saves: texture coordinates and face colours are optional components of
# MeshLab's mesh (saved only if the layer has them); vertex colour and quality are always there, so
# they are saved only if the input file has them as VCG reads them (PLY: uchar red or diffuse_red,
# quality or confidence vertex properties; OBJ 'v' lines with colours; OFF's C prefix).
vertex_attributes() { # prints vc and/or vq
  case ${input,,} in
    *.ply)
      LC_ALL=C awk '
        $1 == "element" { inv = ($2 == "vertex") }
        inv && $1 == "property" && ($2 == "uchar" || $2 == "uint8") && $NF ~ /^(red|diffuse_red)$/ { c = 1 }
        inv && $1 == "property" && $NF ~ /^(quality|confidence)$/ { q = 1 }
        $1 == "end_header" { exit }
        END { if (c) print "vc"; if (q) print "vq" }' "$input" 2>/dev/null || true ;;
    *.obj) LC_ALL=C awk '$1 == "v" && NF >= 7 { print "vc"; exit }' "$input" 2>/dev/null || true ;;
    *.off) head -c 5 "$input" | grep -q '^C' && echo vc || true ;;
  esac
}
mapfile -t vertex_mask < <(vertex_attributes)
save_mask=(-m fc wt vt "${vertex_mask[@]}")

# --- run -----------------------------------------------------------------------------------------
mkdir -p "$outdir" || die 2 "cannot create output folder $outdir"
outdir=$(cd "$outdir" && pwd)
input_abs=$(cd "$(dirname "$input")" && pwd)/$(basename "$input")
name=$(basename "$input"); name=${name%.*}
tmp=$(mktemp -d "${TMPDIR:-/tmp}/gausslod-run.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/config" "$tmp/runtime"; chmod 700 "$tmp/runtime"

# a script written before the filter had its levelsBy, levelTargets, placeVertices,
# completeChain or certifyDistance parameter: meshlabserver 2020.09 aborts on a script that lacks
# any of the filter's parameters, so a copy gets them with what such a script meant (levels by
# angle, or its levelsBy text, which the filter still reads; output vertices at their input
# positions; the paper's levels, not continued by collapses; the distance certified, which
# changes no level)
run_script=$script
missing=()
grep -q 'name="levelsBy"' "$script" ||
  missing+=('<Param type="RichString" name="levelsBy" value="angle" description="Levels by"/>')
grep -q 'name="levelTargets"' "$script" ||
  missing+=('<Param type="RichString" name="levelTargets" value="" description="Targets"/>')
grep -q 'name="placeVertices"' "$script" ||
  missing+=('<Param type="RichBool" name="placeVertices" value="false" description="Place vertices on the surface"/>')
grep -q 'name="completeChain"' "$script" ||
  missing+=('<Param type="RichBool" name="completeChain" value="false" description="Keep every level a real step"/>')
grep -q 'name="certifyDistance"' "$script" ||
  missing+=('<Param type="RichBool" name="certifyDistance" value="true" description="Certify the distance"/>')
if [ ${#missing[@]} -gt 0 ]; then
  run_script=$tmp/script.mlx
  awk -v f="$filter_name" -v add="$(printf '  %s\n' "${missing[@]}")" '
    index($0, "<filter") && index($0, "name=\"" f "\"") { in_filter = 1 }
    in_filter && /<\/filter>/ {
      printf "%s", add
      in_filter = 0
    }
    { print }' "$script" >"$run_script"
fi
outputs=() args=(-i "$input_abs" -s "$run_script")
for i in "${!levels[@]}"; do
  f=$outdir/${name}_LOD${levels[$i]}.ply
  rm -f "$f"
  outputs+=("$f")
  args+=(-o "$f" -l "$((i + 1))" "${save_mask[@]}")
done

log=$tmp/meshlabserver.log
echo "$me: $server on $input (levels ${levels[*]}) -> $outdir"
set +e
# ($GAUSSLOD_SERVER_WRAPPER: words put before meshlabserver, e.g. a valgrind command)
read -r -a wrapper <<<"${GAUSSLOD_SERVER_WRAPPER:-}"
XDG_CONFIG_HOME=$tmp/config XDG_RUNTIME_DIR=$tmp/runtime \
  xvfb-run -a "${wrapper[@]}" "$server" "${args[@]}" >"$log" 2>&1
rc=$?
set -e

loaded=$(grep -o 'loaded has [0-9]* vn [0-9]* fn' "$log" | head -n1 || true)
show_log() { echo "---- meshlabserver output (last 25 lines) ----" >&2; tail -n 25 "$log" >&2; }
if [ -z "$loaded" ]; then
  show_log
  reason=$(grep -o 'GaussLOD OBJ import: .*' "$log" | head -n1 || true) # meshlabserver omits it
  die 4 "could not read a mesh from $input (meshlabserver exit status $rc)${reason:+: $reason}"
fi
in_faces=$(echo "$loaded" | awk '{print $5}')
in_verts=$(echo "$loaded" | awk '{print $3}')
if [ "$in_faces" = 0 ]; then
  die 5 "$input has no faces ($in_verts vertices): GaussLOD needs a triangle mesh"
fi
if [ $rc -ne 0 ] || grep -q 'Problem with filter\|Failed to apply script' "$log"; then
  show_log
  reason=$(grep -o 'GaussLOD failed: .*' "$log" | head -n1 || true)
  die 1 "meshlabserver failed (exit status $rc) running $script on $input${reason:+: $reason}"
fi

# the filter's own log line of a level: superfaces, fallbacks, measured normal deviation, seconds
level_stats() {
  grep -m1 "^LOG: [0-9]* LOD$1 (" "$log" | LC_ALL=C sed -E -n \
    's/.*bound ([0-9.]+) deg\): .* ([0-9,]+) superfaces, ([0-9,]+) fallbacks.*max ([0-9.]+) deg, mean ([0-9.]+) deg; ([0-9.]+) s.*/\1 \2 \3 \4 \5 \6/p' |
    tr -d ','
}
# the level's vertices placed on the surface (0 if none)
level_placed() {
  grep -m1 "^LOG: [0-9]* LOD$1 (" "$log" | LC_ALL=C sed -E -n 's/.*; ([0-9,]+) vertices placed on the surface.*/\1/p' |
    tr -d ','
}
# the level's proven distance bound (% of the diagonal), if the tolerance is on
level_distance() {
  grep -m1 "^LOG: [0-9]* LOD$1 (" "$log" | LC_ALL=C sed -E -n 's/.*; distance to the input at most ([0-9.]+) % of the diagonal.*/\1/p'
}
# the level's certified Hausdorff distance (% of the diagonal), if certified (DESIGN 52)
level_hausdorff() {
  grep -m1 "^LOG: [0-9]* LOD$1 (" "$log" | LC_ALL=C sed -E -n 's/.*; Hausdorff distance to the input certified at most ([0-9.]+) % of the diagonal.*/\1/p'
}
# levels by target: the level's target and whether it was reached
level_target() {
  grep -m1 "^LOG: [0-9]* LOD$1 (" "$log" | LC_ALL=C sed -E -n 's/.*; target (.*), distance tolerance ([0-9.e+-]+) %.*/target \1, tolerance \2 %/p'
}
missing=0
fmt='%-6s %10s %10s %10s %9s %9s %9s %9s %8s %9s %10s %10s  %s\n'
repairs=$(grep -m1 -o 'Input repairs (the input layer is unchanged): .*' "$log" || true)
[ -z "$repairs" ] || echo "${repairs/ (the input layer is unchanged)/}"
carried=$(grep -m1 -o 'Carried to the levels: .*' "$log" || true)
[ -z "$carried" ] || echo "$carried"
# textures named relative to the input's folder: copied to the same place under OUTDIR
in_dir=$(dirname "$input_abs")
textures=$(echo "$carried" | sed -n 's/.*; textures: //p' | sed 's/; [a-z].*//')
if [ -n "$textures" ] && [ "$in_dir" != "$outdir" ]; then
  while IFS= read -r t; do
    [ -n "$t" ] || continue
    case $t in
      /*) continue ;; # absolute: found from anywhere
      ../* | */../*)
        echo "$me: warning: texture $t is outside the input's folder: not copied" >&2
        continue ;;
    esac
    if [ -f "$in_dir/$t" ]; then
      mkdir -p "$outdir/$(dirname "$t")"
      cp -p "$in_dir/$t" "$outdir/$t"
    else
      echo "$me: warning: texture $t not found next to $input" >&2
    fi
  done < <(echo "$textures" | sed 's/ | /\n/g')
fi
printf "$fmt" level faces vertices superfaces fallbacks bound maxdev meandev seconds placed distbound% hausdorff% file
printf "$fmt" input "$in_faces" "$in_verts" - - - - - - - - - "$input"
for i in "${!levels[@]}"; do
  f=${outputs[$i]}
  if [ ! -s "$f" ]; then
    echo "$me: missing or empty output for level ${levels[$i]}: $f" >&2
    missing=1
    continue
  fi
  counts=$(LC_ALL=C awk '
    NR == 1 && $0 !~ /^ply\r?$/ { exit 1 }
    $1 == "element" && $2 == "vertex" { v = $3 }
    $1 == "element" && $2 == "face" { fc = $3 }
    $1 == "end_header" { print fc + 0, v + 0; ok = 1; exit }
    END { if (!ok) exit 1 }' "$f") || { echo "$me: not a PLY file: $f" >&2; missing=1; continue; }
  read -r faces verts <<<"$counts"
  read -r bound sf fb maxdev meandev secs <<<"$(level_stats "${levels[$i]}")" || true
  dist=$(level_distance "${levels[$i]}")
  haus=$(level_hausdorff "${levels[$i]}")
  placed=$(level_placed "${levels[$i]}")
  [ -n "$dist" ] && placed=${placed:-0}
  printf "$fmt" "LOD${levels[$i]}" "$faces" "$verts" "${sf:--}" "${fb:--}" "${bound:--}" \
    "${maxdev:--}" "${meandev:--}" "${secs:--}" "${placed:--}" "${dist:--}" "${haus:--}" "$f"
  target=$(level_target "${levels[$i]}")
  [ -z "$target" ] || echo "       $target"
done
if [ $missing -ne 0 ]; then
  show_log
  die 7 "meshlabserver did not save every level (see above)"
fi

# --- the levels for renderers (glTF options): the tool, with the script's parameters ------------
if [ ${#gltf_opts[@]} -gt 0 ]; then
  [ -n "$tool" ] || die 2 "the glTF options need the gausslod tool (GAUSSLOD_TOOL)"
  set +e
  "$tool" --json --from-mlx "$run_script" "${gltf_opts[@]}" "$input" "$outdir" >"$tmp/gltf.jsonl" 2>"$tmp/gltf.err"
  rc=$?
  set -e
  [ $rc -eq 0 ] || die "$rc" "gausslod --from-mlx: $(tail -n1 "$tmp/gltf.err")"
  for i in "${!levels[@]}"; do
    want=$(LC_ALL=C awk '$1 == "element" && $2 == "face" { print $3; exit }' "${outputs[$i]}")
    got=$(grep -o "{\"level\":${levels[$i]},\"faces\":[0-9]*" "$tmp/gltf.jsonl" | grep -o '[0-9]*$' || true)
    [ "$got" = "$want" ] ||
      die 1 "the tool's LOD${levels[$i]} has ${got:-no} faces, MeshLab's layer $want: the glTF levels are not the layers"
  done
  grep -o '"file":"[^"]*"' "$tmp/gltf.jsonl" | sed 's/"file":"//; s/"$//; s/^/glTF: /'
  for f in "$outdir/${name}_lods.glb" "$outdir/${name}_full.glb" "$outdir/tileset.json"; do
    [ ! -f "$f" ] || [ "$f" -ot "$tmp/gltf.jsonl" ] || echo "glTF: $f"
  done
fi
