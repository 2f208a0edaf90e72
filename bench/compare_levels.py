#!/usr/bin/env python3
"""Our levels against count-driven peers at equal face count, quickly, for development.

Runs a gausslod tool on models, then each peer (bench_peers) at every level's face count, and
compares Hausdorff distance, mean distance and p95 normal deviation (bench_metrics), as the
benchmark's per-peer table does (not worse: ours <= peer's; both distances below 1e-9 % equal;
normals within 0.005 deg). Peer runs and their metrics are cached by (model file, size, mtime,
method, face count, samples), so a second configuration costs only our own runs. Last, the same
counts between the peers themselves (how hard the bar is: see bench/README.md).

usage: bench/compare_levels.py [--build B] [--tool T] [--models a,b] [--peers p,q]
                               [--samples N] [--json OUT] [-- gausslod options]
  --build   bench build folder with bench_peers, bench_metrics and work/models (run_bench.sh
            made it; default <repo>/build-bench-peers)
  --tool    the gausslod tool to measure (default <repo>/build/gausslod)
  --models  names of run_bench.py's models (their PLY in work/models) or paths
            (default: the 11 development models below)
  --json    writes one JSON line per (level, peer) comparison, for diffs between runs
"""
import argparse, hashlib, json, os, statistics, subprocess, sys, tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
DEFAULT_MODELS = ["cow", "fandisk", "bunny00", "anchor", "joint", "couplingdown", "cheese",
                  "blade", "cube50_noise", "uvsphere", "bumpy_100k"]
ERRORS = [("hausdorff_pct", "H"), ("mean_pct", "mean"), ("normal_p95_deg", "p95")]


def run(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True, check=False)
    if r.returncode != 0:
        sys.exit("failed (%d): %s\n%s" % (r.returncode, " ".join(cmd), r.stderr[-2000:]))
    return r.stdout


def not_worse(key, ours, peer):
    if key == "normal_p95_deg":
        return ours <= peer + 0.005
    return ours <= peer or (ours < 1e-9 and peer < 1e-9)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(ROOT, "build-bench-peers"))
    ap.add_argument("--tool", default=os.path.join(ROOT, "build", "gausslod"))
    ap.add_argument("--models", default=",".join(DEFAULT_MODELS))
    ap.add_argument("--peers", default="cgal_gh,meshopt")
    ap.add_argument("--samples", type=int, default=50000)
    ap.add_argument("--json")
    ap.add_argument("extra", nargs="*", help="gausslod options (after --)")
    a = ap.parse_args()
    exe = lambda n: os.path.join(a.build, n)
    cache_dir = os.path.join(a.build, "work", "compare_cache")
    os.makedirs(cache_dir, exist_ok=True)
    work = tempfile.mkdtemp(prefix="compare_levels.")

    def metrics(orig, simp):
        return json.loads(run([exe("bench_metrics"), "--samples", str(a.samples), orig, simp])
                          .strip().splitlines()[-1])

    def peer(src, method, faces):
        st = os.stat(src)
        key = hashlib.sha1(("%s|%d|%d|%s|%d|%d" % (os.path.abspath(src), st.st_size,
                            int(st.st_mtime), method, faces, a.samples)).encode()).hexdigest()
        path = os.path.join(cache_dir, key + ".json")
        if os.path.exists(path):
            with open(path) as f:
                return json.load(f)
        out = os.path.join(work, "%s_%s_%d.ply" % (os.path.basename(src), method, faces))
        run([exe("bench_peers"), method, src, str(faces), out])
        m = metrics(src, out)
        with open(path, "w") as f:
            json.dump(m, f)
        return m

    peers = a.peers.split(",")
    rows = []
    for name in a.models.split(","):
        src = name if os.path.exists(name) else os.path.join(a.build, "work", "models", name + ".ply")
        label = os.path.splitext(os.path.basename(src))[0]
        od = os.path.join(work, label)
        levels = [json.loads(l) for l in run([a.tool, "--json", "--format", "ply"] + a.extra +
                                              [src, od]).splitlines() if l.startswith("{")]
        prev_faces = None
        for lv in levels:
            if lv.get("reused_finer"):
                continue  # counted once, as the benchmark does
            f = os.path.join(od, "%s_LOD%d.ply" % (label, lv["level"]))
            ours = metrics(src, f)
            for p in peers:
                theirs = peer(src, p, ours["faces"])
                row = {"model": label, "level": lv["level"], "faces": ours["faces"], "peer": p,
                       "peer_faces": theirs["faces"],
                       "bound_pct": lv.get("distance_bound_pct")}
                for k, _ in ERRORS:
                    row[k] = ours[k]
                    row["peer_" + k] = theirs[k]
                rows.append(row)
            print("%-14s L%d %7d faces  H %.4g  mean %.4g  p95 %.2f  | %s" % (
                label, lv["level"], ours["faces"], ours["hausdorff_pct"], ours["mean_pct"],
                ours["normal_p95_deg"], "  ".join(
                    "%s H %.4g mean %.4g p95 %.2f" % (r["peer"], r["peer_hausdorff_pct"],
                                                      r["peer_mean_pct"], r["peer_normal_p95_deg"])
                    for r in rows if r["model"] == label and r["level"] == lv["level"])),
                flush=True)
    print()
    for p in peers:
        rs = [r for r in rows if r["peer"] == p]
        parts = []
        for k, short in ERRORS:
            nw = sum(not_worse(k, r[k], r["peer_" + k]) for r in rs)
            ratios = [r[k] / r["peer_" + k] if r["peer_" + k] > 1e-12 else
                      (1.0 if r[k] <= 1e-12 else float("inf")) for r in rs]
            parts.append("%s %d/%d %.2f" % (short, nw, len(rs), statistics.median(ratios)))
        print("vs %-10s %s" % (p, ", ".join(parts)))
    # the same bar between the peers themselves (Hausdorff and p95 not worse, of the levels)
    levels = {}
    for r in rows:
        levels.setdefault((r["model"], r["level"]), {})[r["peer"]] = r
    for p in peers:
        cells = []
        for q in peers:
            if q == p:
                continue
            both = [v for v in levels.values() if p in v and q in v]
            cells.append("vs %s H %d, p95 %d of %d" % (q, *(
                sum(not_worse(k, v[p]["peer_" + k], v[q]["peer_" + k]) for v in both)
                for k in ("hausdorff_pct", "normal_p95_deg")), len(both)))
        if cells:
            print("peer %-10s %s" % (p, ", ".join(cells)))
    print("faces: %d over all levels" % sum(r["faces"] for r in rows if r["peer"] == peers[0]))
    if a.json:
        with open(a.json, "w") as f:
            for r in rows:
                f.write(json.dumps(r) + "\n")


if __name__ == "__main__":
    main()
