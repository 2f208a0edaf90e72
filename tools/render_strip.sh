#!/usr/bin/env bash
# render_strip.sh MESH OUT.png [LEVEL...]: the input and its levels (default 4 2 0) side by side,
# faces coloured by superface, in one PNG: gausslod (default parameters) + render_levels + Debian's
# imagemagick. Run after a build (build/gausslod, build/render_levels).
#   env: GAUSSLOD_BUILD (default <repo>/build), VIEW="yaw pitch" in degrees (default "30 25"),
#        SIZE per picture in pixels (default 480)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${GAUSSLOD_BUILD:-$here/build}
[ $# -ge 2 ] || { echo "usage: render_strip.sh MESH OUT.png [LEVEL...]" >&2; exit 2; }
mesh=$1 out=$2; shift 2
levels=("$@"); [ ${#levels[@]} -gt 0 ] || levels=(4 2 0)
read -r yaw pitch <<<"${VIEW:-30 25}"
for tool in "$build/gausslod" "$build/render_levels"; do
  [ -x "$tool" ] || { echo "render_strip.sh: $tool not built" >&2; exit 2; }
done
# Debian's imagemagick (a different `convert` earlier on PATH may be something else)
convert=/usr/bin/convert
[ -x "$convert" ] || convert=$(command -v convert) ||
  { echo "render_strip.sh: imagemagick's convert not found" >&2; exit 2; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
"$build/gausslod" --format ply "$mesh" "$tmp" >"$tmp/table.txt"
name=$(basename "$mesh"); name=${name%.*}
files=("$mesh")
for l in "${levels[@]}"; do files+=("$tmp/${name}_LOD$l.ply"); done
"$build/render_levels" "$tmp/strip.ppm" "${SIZE:-480}" "$yaw" "$pitch" "${files[@]}"
"$convert" "$tmp/strip.ppm" -trim -bordercolor white -border 10 "$out"
cat "$tmp/table.txt"
echo "render_strip.sh: wrote $out"
