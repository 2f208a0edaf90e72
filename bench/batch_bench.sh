#!/usr/bin/env bash
# Files per second: `gausslod batch` on a manifest of N small real models (links to 10 of Debian's
# CGAL models, 168-1,300 faces) against running the tool once per file, and against two batch
# parts under GNU parallel (levels as PLY, as before the format followed the input).
# usage: bench/batch_bench.sh [GAUSSLOD] [N]   (default build/gausslod 600)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
tool=$(realpath "${1:-$here/build/gausslod}") n=${2:-600}
data=$here/.deps/cgal-data/data/meshes
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
models=(joint pig helmet anchor rotor eight nefertiti dragknob part blob)
mkdir -p "$work/in"
for i in $(seq 0 $((n - 1))); do
  ln -s "$data/${models[$((i % 10))]}.off" "$work/in/m$i.off"; echo "in/m$i.off"
done >"$work/manifest.txt"
secs() { local t0 t1; t0=$(date +%s.%N); "$@" >/dev/null 2>&1 || true; t1=$(date +%s.%N); awk -v a="$t0" -v b="$t1" 'BEGIN { print b - a }'; }
a=$(secs "$tool" batch --threads 1 --format ply "$work/manifest.txt" "$work/batch")
b=$(secs bash -c "cd '$work' && while read -r f; do '$tool' --threads 1 --format ply \"\$f\" out1/\$(dirname \"\$f\"); done <manifest.txt")
c=$(secs parallel --will-cite -j 2 "$tool" batch --threads 1 --format ply "$work/manifest.txt" "$work/par" --part {}/2 ::: 0 1)
d=$(secs "$tool" batch --threads 1 --format ply "$work/manifest.txt" "$work/batch")
printf '%-44s %8s %10s\n' "$n files ($(nproc) cores)" seconds files/s
for row in "gausslod batch (1 process, 1 thread):$a" "gausslod once per file (1 thread):$b" \
           "GNU parallel -j 2, batch --part K/2:$c" "gausslod batch again (all done, skipped):$d"; do
  printf '%-44s %8.2f %10.0f\n' "${row%%:*}" "${row##*:}" "$(awk -v n="$n" -v s="${row##*:}" 'BEGIN { print n / s }')"
done
