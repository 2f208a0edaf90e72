#!/usr/bin/env python3
"""GaussLOD's levels against CGAL's Garland-Heckbert edge collapse at the same face counts.

For each model and each configuration of the distance tolerance, runs the gausslod tool, then
bench_peers cgal_gh at every level's face count, and compares two-sided Hausdorff distances
(bench_metrics). Prints one line per configuration: the median and geometric mean of
ours / CGAL's, and in how many levels ours is not worse; then every level.

usage: bench/pareto_gh.py BENCH_BUILD GAUSSLOD MODELS CONFIGS [SAMPLES]
  BENCH_BUILD  folder with bench_peers and bench_metrics (cmake -S bench -B build-bench)
  GAUSSLOD     the gausslod tool
  MODELS       comma list of OFF files (paths)
  CONFIGS      comma list of label:max-distance%:growth, e.g. off:0:1,default:0.02:2
"""
import json, math, os, statistics, subprocess, sys, tempfile


def run(cmd):
    return subprocess.run(cmd, capture_output=True, text=True, check=False).stdout


def main():
    if len(sys.argv) < 5:
        sys.exit(__doc__)
    bench, tool, models, configs = sys.argv[1:5]
    samples = sys.argv[5] if len(sys.argv) > 5 else '20000'
    work = tempfile.mkdtemp(prefix='pareto_gh.')

    def metrics(orig, simp):
        lines = run([os.path.join(bench, 'bench_metrics'), '--samples', samples, orig, simp])
        return json.loads(lines.strip().splitlines()[-1])

    peer = {}

    def gh(src, faces):
        if (src, faces) not in peer:
            out = os.path.join(work, '%s_gh_%d.ply' % (os.path.basename(src), faces))
            run([os.path.join(bench, 'bench_peers'), 'cgal_gh', src, str(faces), out])
            peer[(src, faces)] = metrics(src, out)['hausdorff_pct']
        return peer[(src, faces)]

    for config in configs.split(','):
        label, dist, growth = config.split(':')
        ratios, detail = [], []
        for src in models.split(','):
            od = os.path.join(work, '%s_%s' % (os.path.basename(src), label))
            run([tool, '--format', 'ply', '--max-distance', dist, '--distance-growth', growth,
                 src, od])
            for f in sorted(os.listdir(od)):
                m = metrics(src, os.path.join(od, f))
                r = m['hausdorff_pct'] / max(gh(src, m['faces']), 1e-9)
                ratios.append(r)
                detail.append('  %-28s %7d faces  %.4f %%  cgal_gh %.4f %%  ratio %.2f' % (
                    f, m['faces'], m['hausdorff_pct'], gh(src, m['faces']), r))
        print('%-10s max-distance %s %% growth %s: median ratio %.2f, geometric mean %.2f, '
              'not worse in %d of %d levels' % (
                  label, dist, growth, statistics.median(ratios),
                  math.exp(sum(math.log(max(r, 1e-9)) for r in ratios) / len(ratios)),
                  sum(1 for r in ratios if r <= 1.0), len(ratios)))
        print('\n'.join(detail), flush=True)


if __name__ == '__main__':
    main()
