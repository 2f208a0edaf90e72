#!/usr/bin/env bash
# glb levels, MSFT_lod chains and 3D Tiles tilesets (issue 40) on the benchmark's models and the
# attribute test files, checked as users' renderers would take them:
#   bench/gltf_check.sh GAUSSLOD MODEL...
# Per model: gausslod --json --3dtiles --lod-file; every glb through the Khronos validator
# (web/validate_gltf.mjs: errors, warnings); the tileset against the levels' JSON
# (tests/cli/check_tileset.py: a chain from the coarsest level to the input, errors the certified
# distances, decreasing to 0); what the input carries (the JSON's attributes) against what the
# finest level's glb holds (images, TEXCOORD_0, COLOR_0, material colours). One line per model.
set -uo pipefail
g=$1; shift
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
work=$(mktemp -d "${TMPDIR:-/tmp}/gltf_check.XXXXXX")
trap 'rm -rf "$work"' EXIT
for m in "$@"; do
  n=$(basename "$m"); n=${n%.*}; o=$work/$n
  if ! "$g" --json "$m" "$o" --3dtiles --lod-file >"$o.json" 2>"$o.err"; then
    echo "$n FAILED: $(tail -1 "$o.err")"; continue
  fi
  v=$(node "$here/web/validate_gltf.mjs" "$o"/*.glb)
  files=$(echo "$v" | grep -c ': [0-9]* errors')
  errors=$(echo "$v" | awk -F': ' '/ errors/ {split($2, a, " "); s += a[1]} END {print s + 0}')
  warnings=$(echo "$v" | awk '/ errors, / {for (i = 1; i <= NF; i++) if ($i ~ /^warnings/) s += $(i - 1)} END {print s + 0}')
  tiles=$(python3 "$here/tests/cli/check_tileset.py" "$o" "$o.json" 2>&1 | tail -1)
  python3 - "$o" "$o.json" "$n" "$files" "$errors" "$warnings" "$tiles" <<'PY'
import json, struct, sys, glob
o, levels, n, files, errors, warnings, tiles = sys.argv[1:]
rows = [json.loads(l) for l in open(levels) if '"level"' in l]
attrs = rows[0].get("attributes", []) if rows else []
finest = sorted(glob.glob(o + "/*_LOD*.glb"))[-1]
b = open(finest, "rb").read()
j = json.loads(b[20:20 + struct.unpack("<I", b[12:16])[0]])
a = set(k for m in j["meshes"] for p in m["primitives"] for k in p["attributes"])
colours = {tuple(m["pbrMetallicRoughness"].get("baseColorFactor", [1, 1, 1, 1])) for m in j.get("materials", [])}
has = []
if j.get("images"): has.append("%d images" % len(j["images"]))
if "TEXCOORD_0" in a: has.append("uv")
if "COLOR_0" in a: has.append("vertex colours")
if len(colours) > 1 or (colours and colours != {(1, 1, 1, 1)}): has.append("%d material colours" % len(colours))
if "NORMAL" in a: has.append("normals")
want_tex = "texture" in attrs
want_col = "vertex_colour" in attrs or "face_colour" in attrs
ok_attr = (not want_tex or j.get("images")) and (not want_col or "COLOR_0" in a or len(colours) > 1 or colours != {(1, 1, 1, 1)})
print("%-26s %2d levels %2s glb %s errors %s warnings | input: %-40s | glb: %-40s %s | %s" % (
    n, len(rows), files, errors, warnings, ",".join(attrs) or "-", ", ".join(has) or "-",
    "ok" if ok_attr else "MISSING", tiles if tiles.startswith("tileset:") else "TILESET FAILED " + tiles))
PY
done
