#!/usr/bin/env bash
# glb levels, the MSFT_lod chain file and the 3D Tiles tileset (issue 40), on files nobody here
# made: every glb is checked by the Khronos glTF validator (npm gltf-validator, web/); what the
# input carries is in the glb (textures embedded, vertex colours); the tileset's errors are the
# levels' certified distances, coarsest at the root, the input as the leaf.
#   test_cli_gltf.sh GAUSSLOD DATA ASSIMP_MODELS WEB OUT
. "$(dirname "${BASH_SOURCE[0]}")/common.sh"
g=$1 data=$2 assimp=$3 web=$4 out=$5
here=$(dirname "${BASH_SOURCE[0]}")
fresh_work "$out"

glb_json() { # FILE: the JSON chunk of a glb
  python3 -c 'import json,struct,sys
b=open(sys.argv[1],"rb").read(); n=struct.unpack("<I",b[12:16])[0]; print(b[20:20+n].decode())' "$1"
}

for m in "$data/fandisk.off" "$assimp/OBJ/spider.obj" "$assimp/OBJ/cube_with_vertexcolors.obj" \
         "$assimp/PLY/cube_uv.ply"; do
  n=$(basename "$m"); n=${n%.*}; o="$out/$n"
  check '"$g" --json "$m" "$o" --3dtiles --lod-file >"$o.json" 2>"$o.err"' "$n: gausslod --3dtiles --lod-file"
  check 'node "$web/validate_gltf.mjs" "$o"/*.glb >"$o.valid" 2>&1' "$n: every glb valid by gltf-validator"
  cat "$o.valid"
  check '[ "$(ls "$o"/*_LOD*.glb | wc -l)" -eq "$(grep -c "\"level\"" "$o.json")" ]' "$n: one glb per level"
  # the tileset against the levels' JSON
  check 'python3 "$here/check_tileset.py" "$o" "$o.json"' "$n: tileset.json coarsest at the root, errors the certified distances, the input the leaf"
  check 'glb_json "$o/${n}_lods.glb" | python3 -c "import json,sys; j=json.load(sys.stdin)
n=j[\"nodes\"][j[\"scenes\"][0][\"nodes\"][0]]; ids=n[\"extensions\"][\"MSFT_lod\"][\"ids\"]
c=n[\"extras\"][\"MSFT_screencoverage\"]
assert j[\"extensionsUsed\"]==[\"MSFT_lod\"] and \"extensionsRequired\" not in j
assert len(c)==len(ids)+1 and all(a>=b for a,b in zip(c,c[1:])), c"' "$n: the chain file lists every level in MSFT_lod (used, not required)"
done
# what the inputs carry
check 'glb_json "$out/spider/spider_LOD0.glb" | grep -q "\"mimeType\":\"image/jpeg\""' "spider: its JPEG textures are embedded"
check 'glb_json "$out/spider/spider_LOD0.glb" | grep -q "\"TEXCOORD_0\""' "spider: texture coordinates"
check 'glb_json "$out/cube_with_vertexcolors/cube_with_vertexcolors_LOD0.glb" | grep -q "\"COLOR_0\""' "cube_with_vertexcolors: vertex colours"
check 'glb_json "$out/fandisk/fandisk_LOD0.glb" | grep -vq "\"COLOR_0\""' "fandisk: no superface colours in a renderer's file"
# bad options
check '"$g" "$data/fandisk.off" "$out/bad" --3dtiles --format ply 2>"$out/bad.err"; [ $? -eq 2 ] && grep -q "disagrees" "$out/bad.err"' "--3dtiles with --format ply is refused"
check '"$g" "$data/fandisk.off" "$out/bad2" --tiles-transform 1,2,3 2>"$out/bad2.err"; [ $? -eq 2 ]' "--tiles-transform needs 16 numbers"
check '"$g" "$data/fandisk.off" "$out/tf" --3dtiles --tiles-transform 1,0,0,0,0,1,0,0,0,0,1,0,10,20,30,1 >/dev/null 2>&1 && python3 -c "import json,sys; t=json.load(open(sys.argv[1]))[\"root\"][\"transform\"]; assert t[12:15]==[10,20,30], t" "$out/tf/tileset.json"' "--tiles-transform is the root's transform"
# --format gltf: the same as text, the buffer and the images as data URIs
check '"$g" "$assimp/OBJ/spider.obj" "$out/gltf" --format gltf >/dev/null 2>&1 && node "$web/validate_gltf.mjs" "$out/gltf"/*.gltf && grep -q "image/jpeg" "$out/gltf/spider_LOD0.gltf"' "--format gltf: valid, its textures embedded"
# batch: two inputs of one folder, each its own tileset
mkdir -p "$out/batch/in"
cp "$data/cow.off" "$data/fandisk.off" "$out/batch/in/"
printf '%s\n' "in/cow.off --3dtiles" "in/fandisk.off --3dtiles --lod-file" >"$out/batch/manifest"
check '"$g" batch "$out/batch/manifest" "$out/batch/out" >"$out/batch/records" 2>"$out/batch/err"' "batch with --3dtiles per line"
for n in cow fandisk; do
  check 'python3 -c "import json,sys; print(\"\n\".join(json.dumps(l) for l in json.load(open(sys.argv[1]))[\"levels\"]))" "$out/batch/out/in/$n.gausslod.json" >"$out/batch/$n.jsonl" &&
         python3 "$here/check_tileset.py" "$out/batch/out/in" "$out/batch/$n.jsonl" "${n}_tileset.json"' "batch: $n's tileset ${n}_tileset.json"
done
check '[ -f "$out/batch/out/in/fandisk_lods.glb" ] && [ ! -f "$out/batch/out/in/cow_lods.glb" ]' "batch: --lod-file on its line only"
finish cli.gltf
