#!/usr/bin/env bash
# The certified Hausdorff distance (DESIGN 52) against the benchmark's sampled one, per level:
#   bench/certified_check.sh GAUSSLOD BENCH_METRICS LEVELS_BY MESH...
# (GAUSSLOD: build/gausslod; BENCH_METRICS: build-bench-peers/bench_metrics, built by
# bench/run_bench.sh; LEVELS_BY: angle, faces:50%,... or error:...). One line per level: faces,
# certified and sampled Hausdorff (% of the diagonal), their ratio, the construction's bound over
# the sampled distance, whether the search converged, certification and level seconds.
# bench/certified_summary.py summarises the lines (bench/results/CERTIFIED.md).
set -euo pipefail
g=$1 metrics=$2 by=$3; shift 3
work=$(mktemp -d "${TMPDIR:-/tmp}/certified.XXXXXX")
trap 'rm -rf "$work"' EXIT
for m in "$@"; do
  n=$(basename "$m"); n=${n%.*}; out=$work/$n; mkdir -p "$out"
  "$g" --json "$m" "$out" --levels-by "$by" >"$out/levels.json" 2>/dev/null || { echo "$n FAILED"; continue; }
  python3 - "$m" "$out" "$n" "${m##*.}" "$metrics" <<'PY'
import json, subprocess, sys
m, out, n, ext, metrics = sys.argv[1:]
for line in open(out + '/levels.json'):
    j = json.loads(line)
    if 'level' not in j:
        continue
    f = f"{out}/{n}_LOD{j['level']}.{ext}"
    r = json.loads(subprocess.run([metrics, '--samples', '100000', m, f], capture_output=True,
                                  text=True, check=True).stdout)
    h, s, b = j['hausdorff_pct'], r['hausdorff_pct'], j.get('distance_bound_pct') or -1
    nan = float('nan')
    print(f"{n:14s} LOD{j['level']} {j['faces']:7d} cert {h:.5f} sampled {s:.5f} "
          f"ratio {h / s if s > 0 else nan:.3f} bound/sampled {b / s if s > 0 else nan:.2f} "
          f"conv {j['hausdorff_converged']} tcert {j['seconds_hausdorff']:.2f} "
          f"tlevel {j['seconds']:.2f}", flush=True)
PY
done
