#!/usr/bin/env python3
"""GaussLOD against peer simplifiers: runs everything, measures, writes results/RESULTS.md.

Called by bench/run_bench.sh after the build (see bench/README.md). Every figure in the report is
measured in this run; nothing is carried over from an earlier one.
"""
import argparse
import datetime
import json
import math
import os
import select
import shutil
import signal
import subprocess
import sys
import tempfile
import time

BENCH = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(BENCH)
DATA = os.path.join(ROOT, ".deps", "cgal-data", "data", "meshes")

QUADRIC = "Simplification: Quadric Edge Collapse Decimation"
SELECT_NONE = "Select None"

# name, source, group(s). "cad" marks the models of the normal-deviation bar.
MODELS = [
    {"name": "cow", "off": "cow.off", "groups": ["real"]},
    {"name": "fandisk", "off": "fandisk.off", "groups": ["real", "cad"]},
    {"name": "bunny00", "off": "bunny00.off", "groups": ["real"]},
    {"name": "anchor", "off": "anchor.off", "groups": ["cad"]},
    {"name": "joint", "off": "joint.off", "groups": ["cad"]},
    {"name": "couplingdown", "off": "couplingdown.off", "groups": ["cad"]},
    {"name": "cheese", "off": "cheese.off", "groups": ["cad"]},
    {"name": "blade", "off": "blade.off", "groups": ["cad"]},
    {"name": "cube50", "gen": ["cube", "50"], "groups": ["synthetic", "gridcube"]},
    {"name": "cube50_noise", "gen": ["cube", "50", "@OUT", "1e-4"], "groups": ["synthetic"]},
    {"name": "uvsphere", "gen": ["sphere", "128", "64"], "groups": ["synthetic"]},
    {"name": "bumpy_100k", "gen": ["bumpy", "224", "224"], "groups": ["synthetic", "small"]},
    # The speed bars' mesh (>= 1M faces): peers only at GaussLOD's coarsest level (time budget).
    {"name": "bumpy_1m", "gen": ["bumpy", "708", "708"], "groups": ["synthetic", "speed"], "peers": "coarsest"},
    # The scaling bar's mesh (2M faces): GaussLOD only (Blender alone would take ~9 min here).
    {"name": "bumpy_2m", "gen": ["bumpy", "1000", "1000"], "groups": ["synthetic", "scale"], "peers": "none"},
    # The speed meshes the issue names (#18's "Done when"): the 1.92M-face grid cube and
    # fandisk_large subdivided to 2.03M faces; GaussLOD and meshopt to its coarsest level, times
    # only (no quality metrics: the same surfaces as cube50 and fandisk).
    {"name": "cube400", "gen": ["cube", "400"], "groups": ["synthetic", "issue_speed"],
     "peers": "speed", "metrics": False},
    {"name": "fandisk_large_x64", "gen": ["subdivide", "3", "@DATA/fandisk_large.off", "@OUT"],
     "groups": ["real", "issue_speed"], "peers": "speed", "metrics": False},
]
QUICK = ["cube50", "fandisk", "anchor", "bumpy_100k"]

PEERS = ["meshopt", "cgal_gh", "meshlab_quadric", "meshlab_quadric_planar", "openmesh_quadric",
         "blender_planar", "openmesh_nd"]
# the four quadric methods of the issue's normal-deviation bar
QUADRIC_PEERS = PEERS[:4]
# run to a face count (GaussLOD's level's), and run at an angle (the face count is theirs)
COUNT_PEERS = PEERS[:5]
ANGLE_PEERS = ["blender_planar", "openmesh_nd"]
# GaussLOD with a distance tolerance (% of the diagonal), run on the CAD models besides the
# defaults; the quadric peers are run at its face counts too (rows with "variant": "dist")
DIST_PCT = 0.1
LABEL = {
    "gausslod": "GaussLOD",
    "gausslod_dist": "GaussLOD, distance tolerance %g %%" % DIST_PCT,
    "meshopt": "meshopt_simplify",
    "cgal_gh": "CGAL GH plane",
    "meshlab_quadric": "MeshLab quadric",
    "meshlab_quadric_planar": "MeshLab quadric+planar",
    "openmesh_quadric": "OpenMesh quadric",
    "blender_planar": "Blender planar",
    "openmesh_nd": "OpenMesh normal-deviation",
}


def sweep_angles(levels):
    """Angles the angle-driven peers run at: every level's angle (sqrt(2)*90/3^L), the geometric
    midpoint between neighbouring levels' angles, and a third of the finest level's angle, so that
    their (faces, error) curve brackets the levels' face counts for interpolation."""
    a = sorted({round(l["bound_deg"], 6) for l in levels})
    out = set(a)
    out.update(round(math.sqrt(x * y), 6) for x, y in zip(a, a[1:]))
    if a:
        out.add(round(a[0] / 3.0, 6))
    return sorted(out)


def log(msg):
    print("[bench %s] %s" % (time.strftime("%H:%M:%S"), msg), flush=True)


# ---- running processes ---------------------------------------------------------------------------

def run(cmd, timeout, env=None, time_wrap=True, wrap_prefix=None):
    """Runs cmd under /usr/bin/time -v (peak RSS of that process). stdout is read as it comes
    (chunks with arrival times, for meshlabserver's unbuffered log). Returns a dict."""
    tfile = tempfile.NamedTemporaryFile(prefix="bench_time_", delete=False)
    tfile.close()
    full = list(cmd)
    if time_wrap:
        full = ["/usr/bin/time", "-v", "-o", tfile.name] + full
    if wrap_prefix:
        full = list(wrap_prefix) + full
    errf = tempfile.TemporaryFile()
    t0 = time.perf_counter()
    p = subprocess.Popen(full, stdout=subprocess.PIPE, stderr=errf, env=env, start_new_session=True)
    chunks = []
    timed_out = False
    fd = p.stdout.fileno()
    while True:
        left = timeout - (time.perf_counter() - t0)
        if left <= 0:
            timed_out = True
            break
        r, _, _ = select.select([fd], [], [], min(left, 5.0))
        if not r:
            continue
        c = os.read(fd, 1 << 16)
        if not c:
            break
        chunks.append((time.perf_counter() - t0, c))
    if timed_out:
        try:
            os.killpg(p.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    p.wait()
    wall = time.perf_counter() - t0
    errf.seek(0)
    stderr = errf.read().decode("utf-8", "replace")
    errf.close()
    peak_kb = None
    try:
        with open(tfile.name) as f:
            for line in f:
                if "Maximum resident set size" in line:
                    peak_kb = int(line.split(":")[1])
    except OSError:
        pass
    os.unlink(tfile.name)
    out = b"".join(c for _, c in chunks).decode("utf-8", "replace")
    return {"rc": p.returncode, "stdout": out, "stderr": stderr, "wall": wall, "chunks": chunks,
            "peak_mb": (peak_kb / 1024.0) if peak_kb else None, "timed_out": timed_out}


def first_mark(res, text):
    """Arrival time of the stdout chunk that holds the first occurrence of text."""
    seen = b""
    key = text.encode()
    for t, c in res["chunks"]:
        seen += c
        if key in seen:
            return t
    return None


def json_lines(text):
    out = []
    for line in text.splitlines():
        line = line.strip()
        if line.startswith("{"):
            try:
                out.append(json.loads(line))
            except ValueError:
                pass
    return out


def fail_reason(res):
    if res["timed_out"]:
        return "timeout"
    tail = (res["stderr"].strip().splitlines() or res["stdout"].strip().splitlines() or [""])[-1]
    return "rc=%s %s" % (res["rc"], tail[:120])


# ---- the bench ------------------------------------------------------------------------------------

class Bench:
    def __init__(self, args):
        self.args = args
        self.build = args.build
        self.work = os.path.join(self.build, "work")
        os.makedirs(self.work, exist_ok=True)
        self.exe = {n: os.path.join(self.build, n) for n in
                    ["gausslod", "bench_gen", "bench_load", "bench_peers", "bench_metrics"]}
        self.rows = []       # one per (model, method, level)
        self.speed_rows = [] # the same, for the times-only models (no quality metrics)
        self.models = {}     # name -> info (faces, load peak, gausslod totals, ...)
        self.xdg = tempfile.mkdtemp(prefix="bench_xdg_")
        os.chmod(self.xdg, 0o700)
        self.ml_env = dict(os.environ, XDG_CONFIG_HOME=self.xdg, XDG_RUNTIME_DIR=self.xdg)
        self.have_meshlab = shutil.which("meshlabserver") and shutil.which("xvfb-run")
        self.have_blender = shutil.which("blender")

    # -- inputs
    def prepare(self, m):
        d = os.path.join(self.work, "models")
        os.makedirs(d, exist_ok=True)
        out = os.path.join(d, m["name"] + ".ply")
        if os.path.exists(out):
            return out
        if "off" in m:
            cmd = [self.exe["bench_gen"], "convert", os.path.join(DATA, m["off"]), out]
        else:
            g = [x.replace("@DATA", DATA) for x in m["gen"]]
            if "@OUT" in g:
                g[g.index("@OUT")] = out
            else:
                g.append(out)
            cmd = [self.exe["bench_gen"]] + g
        r = run(cmd, 600, time_wrap=False)
        if r["rc"] != 0 or not os.path.exists(out):
            raise RuntimeError("cannot make %s: %s" % (out, fail_reason(r)))
        return out

    # -- quality of one output
    def metrics(self, orig, simp):
        r = run([self.exe["bench_metrics"], "--samples", str(self.args.samples), orig, simp], 1800,
                time_wrap=False)
        js = json_lines(r["stdout"])
        if r["rc"] != 0 or not js:
            return None, fail_reason(r)
        return js[0], None

    def add_row(self, model, method, level, target, res, orig, note="", sweep=False, metrics=True):
        """res: dict with file, seconds, peak_mb, faces (or error). sweep: an angle-driven peer's
        run at an angle of no level (level None). metrics=False: times only (no bench_metrics)."""
        row = {"model": model, "method": method, "level": level, "target": target,
               "seconds": res.get("seconds"), "peak_mb": res.get("peak_mb"),
               "wall": res.get("wall"), "note": note, "error": res.get("error")}
        if sweep:
            row["sweep"] = True
        for k in ("angle_deg", "timing", "extra"):
            if k in res:
                row[k] = res[k]
        if not row["error"]:
            if res.get("faces") == 0:
                row["error"] = "empty output (0 faces)"
                row["faces"] = 0
            elif not os.path.exists(res["file"]):
                row["error"] = "no output file"
            elif not metrics:
                row["faces"] = res.get("faces")
            else:
                met, err = self.metrics(orig, res["file"])
                if met is None:
                    row["error"] = "metrics failed: " + err
                else:
                    row.update({k: met[k] for k in met if k not in ("seconds",)})
                    row["metrics_seconds"] = met["seconds"]
        (self.rows if metrics else self.speed_rows).append(row)
        with open(os.path.join(self.work, "rows.jsonl"), "a") as f:
            f.write(json.dumps(row) + "\n")
        return row

    # -- GaussLOD
    def gausslod(self, name, ply, extra=(), tag="gausslod"):
        outdir = os.path.join(self.work, "out", name, tag)
        shutil.rmtree(outdir, ignore_errors=True)
        # (BENCH_GAUSSLOD_ARGS: options for every GaussLOD run, to measure a variant)
        variant = os.environ.get("BENCH_GAUSSLOD_ARGS", "").split()
        r = run([self.exe["gausslod"], "--json"] + variant + list(extra) + [ply, outdir], 3600)
        levels = json_lines(r["stdout"])
        if r["rc"] != 0 or not levels:
            return None, r, fail_reason(r)
        return levels, r, None

    # -- peers
    def peer_inproc(self, method, ply, target, out):
        """target: a face count, or for openmesh_nd the angle in degrees."""
        arg = ("%.6f" % target) if method == "openmesh_nd" else str(target)
        r = run([self.exe["bench_peers"], method, ply, arg, out], self.args.timeout)
        js = json_lines(r["stdout"])
        if r["rc"] != 0 or not js:
            return {"error": fail_reason(r), "peak_mb": r["peak_mb"], "wall": r["wall"]}
        j = js[0]
        extra = {k: j[k] for k in ("collapse_seconds", "skipped_input_faces", "result_error", "collapses",
                                   "version") if k in j}
        res = {"file": out, "faces": j["faces"], "seconds": j["seconds"], "peak_mb": r["peak_mb"],
               "wall": r["wall"], "extra": extra}
        if method == "openmesh_nd":
            res["angle_deg"] = target
        return res

    def mlx(self, filters):
        parts = ['<!DOCTYPE FilterScript>', '<FilterScript>']
        for name, params in filters:
            parts.append(' <filter name="%s">' % name)
            for ptype, pname, value in params:
                parts.append('  <Param type="%s" name="%s" value="%s"/>' % (ptype, pname, value))
            parts.append(' </filter>')
        parts.append('</FilterScript>')
        return "\n".join(parts) + "\n"

    @staticmethod
    def quadric_params(target, planar):
        # Every parameter of the filter (meshfilter.cpp, FP_QUADRIC_SIMPLIFICATION), MeshLab's
        # defaults except the target and PlanarQuadric.
        b = lambda v: "true" if v else "false"
        return [("RichInt", "TargetFaceNum", str(target)), ("RichFloat", "TargetPerc", "0"),
                ("RichFloat", "QualityThr", "0.3"), ("RichBool", "PreserveBoundary", "false"),
                ("RichFloat", "BoundaryWeight", "1"), ("RichBool", "PreserveNormal", "false"),
                ("RichBool", "PreserveTopology", "false"), ("RichBool", "OptimalPlacement", "true"),
                ("RichBool", "PlanarQuadric", b(planar)), ("RichFloat", "PlanarWeight", "0.001"),
                ("RichBool", "QualityWeight", "false"), ("RichBool", "AutoClean", "true"),
                ("RichBool", "Selected", "false")]

    SELECT_NONE_PARAMS = [("RichBool", "allFaces", "true"), ("RichBool", "allVerts", "true")]

    def meshlab_run(self, ply, out, filters, tag):
        script = out + "." + tag + ".mlx"
        with open(script, "w") as f:
            f.write(self.mlx(filters))
        if os.path.exists(out):
            os.unlink(out)
        # time -v wraps meshlabserver itself (not Xvfb); stdbuf -o0: its log arrives as written.
        r = run(["stdbuf", "-o0", "/usr/bin/time", "-v", "-o", out + ".time",
                 "meshlabserver", "-i", ply, "-o", out, "-s", script],
                self.args.timeout, env=self.ml_env, time_wrap=False, wrap_prefix=["xvfb-run", "-a"])
        try:
            with open(out + ".time") as f:
                for line in f:
                    if "Maximum resident set size" in line:
                        r["peak_mb"] = int(line.split(":")[1]) / 1024.0
        except OSError:
            pass
        return r

    def meshlab_baseline(self, name, ply):
        """Gap between two cheap filters: what meshlabserver spends between filters anyway."""
        out = os.path.join(self.work, "out", name, "meshlab_baseline.ply")
        r = self.meshlab_run(ply, out, [(SELECT_NONE, self.SELECT_NONE_PARAMS)] * 2, "base")
        t1 = first_mark(r, "filter: " + SELECT_NONE)
        seen = b"".join(c for _, c in r["chunks"])
        idx = seen.find(("filter: " + SELECT_NONE).encode())
        t2 = None
        if idx >= 0:
            second = ("filter: " + SELECT_NONE).encode()
            acc = b""
            for t, c in r["chunks"]:
                acc += c
                if acc.count(second) >= 2:
                    t2 = t
                    break
        ok = r["rc"] == 0 and os.path.exists(out) and t1 is not None and t2 is not None
        return {"gap": (t2 - t1) if ok else None, "wall": r["wall"], "error": None if ok else fail_reason(r)}

    def meshlab_quadric(self, name, ply, target, planar, base):
        tag = "meshlab_quadric_planar" if planar else "meshlab_quadric"
        out = os.path.join(self.work, "out", name, "%s_%d.ply" % (tag, target))
        r = self.meshlab_run(ply, out, [(QUADRIC, self.quadric_params(target, planar)),
                                        (SELECT_NONE, self.SELECT_NONE_PARAMS)], "q")
        t1 = first_mark(r, "filter: " + QUADRIC)
        t2 = first_mark(r, "filter: " + SELECT_NONE)
        res = {"peak_mb": r.get("peak_mb"), "wall": r["wall"]}
        if r["timed_out"] or not os.path.exists(out) or t1 is None or t2 is None \
                or "Problem with filter" in r["stdout"]:
            res["error"] = fail_reason(r) if (r["timed_out"] or r["rc"]) else \
                "no output / filter did not run (rc=%s)" % r["rc"]
            return res
        faces = None
        for line in r["stdout"].splitlines():
            if " saved as " in line and " fn)" in line:
                try:
                    faces = int(line.rsplit("vn", 1)[1].split("fn")[0])
                except (ValueError, IndexError):
                    pass
        gap = t2 - t1
        res.update({"file": out, "faces": faces, "seconds": max(0.0, gap - (base["gap"] or 0.0)),
                    "timing": "log-gap", "extra": {"gap_seconds": gap, "baseline_gap_seconds": base["gap"],
                                                   "baseline_wall": base["wall"]}})
        return res

    def blender(self, name, ply, angle):
        out = os.path.join(self.work, "out", name, "blender_planar_%.4f.ply" % angle)
        if os.path.exists(out):
            os.unlink(out)
        r = run(["blender", "-b", "-noaudio", "--factory-startup", "--python",
                 os.path.join(BENCH, "blender_planar.py"), "--", ply, out, "%.6f" % angle],
                self.args.blender_timeout)
        js = None
        for line in r["stdout"].splitlines():
            if line.startswith("BENCH_JSON "):
                js = json.loads(line[len("BENCH_JSON "):])
        res = {"peak_mb": r["peak_mb"], "wall": r["wall"], "angle_deg": angle}
        if js is None:
            res["error"] = fail_reason(r)
            return res
        res.update({"file": out, "faces": js["faces"], "seconds": js["seconds"],
                    "extra": {"dissolve_seconds": js["dissolve_seconds"], "version": js["version"]}})
        return res

    # -- one model
    def model(self, m):
        name = m["name"]
        peers = m.get("peers", "all")
        if peers == "coarsest" and self.args.big_all_levels:
            peers = "all"
        log("model %s: preparing" % name)
        ply = self.prepare(m)
        os.makedirs(os.path.join(self.work, "out", name), exist_ok=True)
        info = {"name": name, "groups": m["groups"], "ply": ply, "peers": m.get("peers", "all")}
        self.models[name] = info
        lr = run([self.exe["bench_load"], ply], 600)
        lj = json_lines(lr["stdout"])
        info["faces_in"] = lj[0]["faces"] if lj else None
        info["load_peak_mb"] = lr["peak_mb"]
        info["tool_load_peak_mb"] = run([self.exe["bench_load"], "--tool", ply], 600)["peak_mb"]
        log("model %s: %s faces; GaussLOD" % (name, info["faces_in"]))
        levels, gr, err = self.gausslod(name, ply)
        info["gausslod_peak_mb"] = gr["peak_mb"]
        info["gausslod_wall"] = gr["wall"]
        if err:
            info["gausslod_error"] = err
            self.add_row(name, "gausslod", None, None, {"error": err, "peak_mb": gr["peak_mb"]}, ply)
            return
        info["gausslod_seconds"] = sum(l["seconds"] for l in levels)
        info["levels"] = levels
        metrics = m.get("metrics", True)
        for l in levels:
            self.add_row(name, "gausslod", l["level"], None,
                         {"file": l["file"], "faces": l["faces"], "seconds": l["seconds"],
                          "peak_mb": gr["peak_mb"], "extra": {k: l.get(k) for k in
                                                              ("fallbacks", "superfaces", "bound_deg",
                                                               "distance_bound_pct")}},
                         ply, metrics=metrics)
        targets = levels
        if peers == "speed":  # meshopt to the coarsest level, three runs (the fastest counts)
            coarsest = min(levels, key=lambda l: l["level"])
            for run_no in range(3):
                log("model %s L%d: meshopt (%d faces), run %d" % (name, coarsest["level"], coarsest["faces"], run_no + 1))
                res = self.run_peer("meshopt", name, ply, info, coarsest["faces"])
                self.add_row(name, "meshopt", coarsest["level"], coarsest["faces"], res, ply,
                             "speed run %d" % (run_no + 1), metrics=False)
            return
        if peers == "coarsest":
            targets = [min(levels, key=lambda l: l["level"])]  # coarsest only (time budget)
        elif peers == "none":
            targets = []
        methods = [p for p in PEERS if p in self.args.methods]
        done = {}
        for l in targets:
            lv, F, angle = l["level"], l["faces"], l["bound_deg"]
            for meth in methods:
                by_angle = meth in ANGLE_PEERS
                key = (meth, round(angle, 6) if by_angle else F)
                if key in done:
                    prev = done[key]
                    row = dict(prev)
                    row["level"] = lv
                    row["note"] = "same run as L%d" % prev["level"]
                    self.rows.append(row)
                    continue
                log("model %s L%d: %s (%s)" % (name, lv, meth, "%.4f deg" % angle if by_angle else "%d faces" % F))
                res = self.run_peer(meth, name, ply, info, angle if by_angle else F)
                done[key] = self.add_row(name, meth, lv, None if by_angle else F, res, ply)
        # The angle-driven peers at more angles than the levels' (a curve to interpolate at the
        # levels' face counts); not on the big meshes whose peers run at the coarsest level only.
        if peers == "all":
            for angle in sweep_angles(levels):
                for meth in [p for p in ANGLE_PEERS if p in methods]:
                    if (meth, angle) in done:
                        continue
                    log("model %s sweep: %s (%.4f deg)" % (name, meth, angle))
                    res = self.run_peer(meth, name, ply, info, angle)
                    done[(meth, angle)] = self.add_row(name, meth, None, None, res, ply, "angle sweep",
                                                       sweep=True)
        if "cad" in m["groups"] and peers == "all":
            self.distance_variant(name, ply, info, done, methods)

    def run_peer(self, meth, name, ply, info, target):
        """One peer run; target: face count, or the angle for the angle-driven peers."""
        if meth in ("meshopt", "cgal_gh", "openmesh_quadric", "openmesh_nd"):
            tag = ("%.4f" % target) if meth == "openmesh_nd" else "%d" % target
            out = os.path.join(self.work, "out", name, "%s_%s.ply" % (meth, tag))
            return self.peer_inproc(meth, ply, target, out)
        if meth.startswith("meshlab"):
            if not self.have_meshlab:
                return {"error": "meshlabserver or xvfb-run not installed"}
            if info.get("meshlab_baseline") is None:
                info["meshlab_baseline"] = self.meshlab_baseline(name, ply)
            return self.meshlab_quadric(name, ply, target, meth.endswith("planar"), info["meshlab_baseline"])
        if not self.have_blender:
            return {"error": "blender not installed"}
        return self.blender(name, ply, target)

    def distance_variant(self, name, ply, info, done, methods):
        """GaussLOD with a distance tolerance, and the quadric peers at its face counts."""
        log("model %s: GaussLOD --max-distance %g" % (name, DIST_PCT))
        levels, gr, err = self.gausslod(name, ply, ["--max-distance", str(DIST_PCT), "--distance-growth", "1"],
                                        "gausslod_dist")
        if err:
            self.add_row(name, "gausslod_dist", None, None, {"error": err, "peak_mb": gr["peak_mb"]}, ply)
            return
        info["dist_seconds"] = sum(l["seconds"] for l in levels)
        for l in levels:
            lv, F = l["level"], l["faces"]
            self.add_row(name, "gausslod_dist", lv, None,
                         {"file": l["file"], "faces": F, "seconds": l["seconds"], "peak_mb": gr["peak_mb"]}, ply)
            for meth in [q for q in COUNT_PEERS if q in methods]:
                key = (meth, F)
                if key in done:
                    row = dict(done[key])
                else:
                    log("model %s distance L%d: %s (%d faces)" % (name, lv, meth, F))
                    res = self.run_peer(meth, name, ply, info, F)
                    row = done[key] = self.add_row(name, meth, lv, F, res, ply)
                    self.rows.pop()  # (re-added below as a variant row)
                row = dict(row)
                row.update({"level": lv, "variant": "dist", "note": "at the distance variant's L%d" % lv})
                self.rows.append(row)

    def run_all(self, models):
        t0 = time.perf_counter()
        open(os.path.join(self.work, "rows.jsonl"), "w").close()
        for m in models:
            try:
                self.model(m)
            except Exception as e:  # keep going: the report says what failed
                log("model %s failed: %s" % (m["name"], e))
                self.models.setdefault(m["name"], {"name": m["name"], "groups": m["groups"]})["error"] = str(e)
        self.total_wall = time.perf_counter() - t0
        shutil.rmtree(self.xdg, ignore_errors=True)


# ---- report ---------------------------------------------------------------------------------------

def fmt(v, spec="%.3g"):
    if v is None:
        return "–"
    if isinstance(v, float) and math.isnan(v):
        return "–"
    return spec % v


def machine_line():
    cpu = "?"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    nproc = subprocess.run(["nproc"], capture_output=True, text=True).stdout.strip()
    mem = "?"
    try:
        with open("/proc/meminfo") as f:
            mem = "%.1f GiB" % (int(f.readline().split()[1]) / 1024.0 / 1024.0)
    except OSError:
        pass
    return "nproc %s, CPU %s, RAM %s" % (nproc, cpu, mem)


def versions():
    out = []
    for pkg in ["libmeshoptimizer-dev", "libcgal-dev", "libopenmesh-dev", "meshlab", "blender"]:
        v = subprocess.run(["dpkg-query", "-W", "-f", "${Version}", pkg], capture_output=True,
                           text=True).stdout.strip()
        out.append("%s %s" % (pkg, v or "(not installed)"))
    return ", ".join(out)


# The three errors of the per-peer comparison: row key, label, what counts as zero (double
# rounding for distances), tolerance of "not worse", interpolation in log scale.
ZERO_PCT = 1e-9      # % of the diagonal
NORMAL_TOL = 0.005   # degrees
ERRORS = [("hausdorff_pct", "Hausdorff", ZERO_PCT, 0.0, True),
          ("mean_pct", "mean dist", ZERO_PCT, 0.0, True),
          ("normal_p95_deg", "p95 normal dev", NORMAL_TOL, NORMAL_TOL, False)]


def usable(r):
    return (not r.get("error") and r.get("faces") and all(r.get(k) is not None for k, *_ in ERRORS))


def curve(rows, model, meth):
    """An angle-driven peer's runs on a model as (faces, row), sorted by faces; of several runs
    with the same face count the one with the lowest Hausdorff distance (the peer's best)."""
    best = {}
    for r in rows:
        if r["model"] == model and r["method"] == meth and usable(r):
            if r["faces"] not in best or r["hausdorff_pct"] < best[r["faces"]]["hausdorff_pct"]:
                best[r["faces"]] = r
    return sorted(best.items())


def interpolate(points, faces):
    """The peer's errors at `faces` from its (faces, row) curve: the run itself when a run has
    that count, otherwise between the two runs around it, linear in log(faces) (distances in
    log scale when both are above zero). None when the curve does not reach that count."""
    for i, (f, r) in enumerate(points):
        if f == faces:
            return {k: r[k] for k, *_ in ERRORS}
        if f > faces:
            if i == 0:
                return None
            f0, r0 = points[i - 1]
            t = (math.log(faces) - math.log(f0)) / (math.log(f) - math.log(f0))
            out = {}
            for k, _, zero, _, logy in ERRORS:
                a, b = r0[k], r[k]
                if logy and a > zero and b > zero:
                    out[k] = math.exp(math.log(a) + t * (math.log(b) - math.log(a)))
                else:
                    out[k] = a + t * (b - a)
            return out
    return None


def judge(a, b, zero, tol):
    """(not worse, ratio a/b) for our error a against the peer's b; both at zero: equal."""
    if a <= zero and b <= zero:
        return True, 1.0
    return a <= b + tol, (float("inf") if b <= zero else max(a, zero) / b)


def median(xs):
    xs = sorted(xs)
    if not xs:
        return float("nan")
    n = len(xs)
    return xs[n // 2] if n % 2 else (xs[n // 2 - 1] + xs[n // 2]) / 2.0


def our_levels(rows, method):
    """Our level meshes; a level that reused the finer level's mesh counted once."""
    seen = set()
    for g in rows:
        if g["method"] != method or g["level"] is None or not usable(g):
            continue
        key = (g["model"], g["faces"], g["hausdorff_pct"])
        if key not in seen:
            seen.add(key)
            yield g


def peer_comparisons(rows, meth, method="gausslod", variant=None):
    """Every comparison of our levels with one peer at equal face count. Returns (comparisons,
    skipped): comparisons are dicts (model, level, faces, peer_faces, ours, peer); skipped lists
    levels the peer ran on but that could not be compared, with the reason."""
    comps, skipped = [], []
    curves = {}
    for g in our_levels(rows, method):
        if meth in ANGLE_PEERS:
            if g["model"] not in curves:
                curves[g["model"]] = curve(rows, g["model"], meth)
            pts = curves[g["model"]]
            if not pts:
                continue  # the peer did not run on this model
            # bumpy_1m-like models: the peer ran at one angle only, no curve to read
            if len(pts) < 2 and pts[0][0] != g["faces"]:
                skipped.append("%s L%d: one run only (%d faces)" % (g["model"], g["level"], pts[0][0]))
                continue
            vals = interpolate(pts, g["faces"])
            if vals is None:
                skipped.append("%s L%d: %d faces outside the sweep's %d-%d" % (
                    g["model"], g["level"], g["faces"], pts[0][0], pts[-1][0]))
                continue
            comps.append({"model": g["model"], "level": g["level"], "faces": g["faces"],
                          "peer_faces": g["faces"], "ours": g, "peer": vals})
        else:
            p = next((r for r in rows if r["model"] == g["model"] and r["method"] == meth
                      and r["level"] == g["level"] and r.get("variant") == variant), None)
            if p is None:
                continue  # not run on this model (e.g. the scaling mesh)
            if not usable(p):
                skipped.append("%s L%d: %s" % (g["model"], g["level"], p.get("error") or "no metrics"))
                continue
            comps.append({"model": g["model"], "level": g["level"], "faces": g["faces"],
                          "peer_faces": p["faces"], "ours": g, "peer": p})
    return comps, skipped


def pareto_section(bench):
    """Per peer: our levels against it at equal face count (issue 17's "Done when" table)."""
    rows = bench.rows
    L = ["## Our levels against each peer at equal face count", ""]
    L.append("Every GaussLOD level (default parameters; a level that reused the finer level's mesh counted "
             "once) against each peer at that level's face count. Count-driven peers ran to that count; the "
             "angle-driven ones (Blender planar, OpenMesh normal-deviation) ran at a sweep of angles (the "
             "levels' angles, the geometric midpoints between them and a third of the finest) and their "
             "errors are interpolated at our face count between the two runs around it (linear in log faces, "
             "distances in log scale); a level outside the sweep's face range is not compared. "
             "\"not worse\": ours <= peer's (distances: both below %g %% count as equal; normals: %g° "
             "tolerance). Ratio: ours / peer's. Bar: not worse in >= 80 %% of the levels and median ratio "
             "<= 1.0, per error." % (ZERO_PCT, NORMAL_TOL))
    L.append("")
    for method, variant, title in (("gausslod", None, None),
                                   ("gausslod_dist", "dist", "With the distance tolerance (`--max-distance %g "
                                    "--distance-growth 1`, CAD models; count-driven peers rerun at its face "
                                    "counts)" % DIST_PCT)):
        tab = []
        per_model = {}
        details = []
        for meth in PEERS:
            comps, skipped = peer_comparisons(rows, meth, method, variant)
            if not comps and not skipped:
                continue
            n = len(comps)
            cells, verdicts = [], []
            for k, label, zero, tol, _ in ERRORS:
                js = [judge(c["ours"][k], c["peer"][k], zero, tol) for c in comps]
                good = sum(1 for ok_, _ in js if ok_)
                med = median([r for _, r in js])
                cells.append("%d / %d, %s" % (good, n, "inf" if med == float("inf") else "%.2f" % med))
                met = n > 0 and good >= 0.8 * n and med <= 1.0
                verdicts.append("%s %s" % (label.split()[0] if k != "normal_p95_deg" else "p95",
                                           "met" if met else "MISSED"))
            fr = [c["peer_faces"] / float(c["faces"]) for c in comps]
            faces_cell = "interpolated" if meth in ANGLE_PEERS else (
                "%.3f (%.3f-%.3f)" % (median(fr), min(fr), max(fr)) if fr else "–")
            tab.append("| %s | %d%s | %s | %s | %s | %s | %s |" % (
                LABEL[meth], n, " (+%d not compared)" % len(skipped) if skipped else "", cells[0], cells[1],
                cells[2], faces_cell, ", ".join(verdicts)))
            for c in comps:
                pm = per_model.setdefault(c["model"], {}).setdefault(meth, [0, 0, []])
                ok_, r = judge(c["ours"]["hausdorff_pct"], c["peer"]["hausdorff_pct"], ZERO_PCT, 0.0)
                pm[0] += int(ok_)
                pm[1] += 1
                pm[2].append(r)
            lines = ["%s L%d, %d faces%s: Hausdorff %.3g vs %.3g %%, mean %.3g vs %.3g %%, p95 %.2f vs %.2f°" % (
                c["model"], c["level"], c["faces"],
                "" if c["peer_faces"] == c["faces"] else " (peer %d)" % c["peer_faces"],
                c["ours"]["hausdorff_pct"], c["peer"]["hausdorff_pct"], c["ours"]["mean_pct"],
                c["peer"]["mean_pct"], c["ours"]["normal_p95_deg"], c["peer"]["normal_p95_deg"]) for c in comps]
            lines += ["not compared: " + x for x in skipped]
            details.append(("%s: every comparison (ours vs peer)" % LABEL[meth], lines))
        if not tab:
            continue
        if title:
            L.append("### " + title)
            L.append("")
        L.append("| peer | levels compared | Hausdorff: not worse, median ratio | mean dist: not worse, median ratio "
                 "| p95 normal dev: not worse, median ratio | peer faces / ours (median, range) "
                 "| bar met (>= 80 % and median <= 1.0) |")
        L.append("|---|---|---|---|---|---|---|")
        L.extend(tab)
        L.append("")
        peers_here = [p for p in PEERS if any(p in v for v in per_model.values())]
        L.append("Hausdorff per model (not worse / compared, median ratio):")
        L.append("")
        L.append("| model | " + " | ".join(LABEL[p] for p in peers_here) + " |")
        L.append("|---|" + "---|" * len(peers_here))
        for model, v in per_model.items():
            L.append("| %s | %s |" % (model, " | ".join(
                ("%d / %d, %s" % (v[p][0], v[p][1], "inf" if median(v[p][2]) == float("inf")
                                  else "%.2f" % median(v[p][2]))) if p in v else "–" for p in peers_here)))
        for summary, lines in details:
            L.extend(["", "<details><summary>%s</summary>" % summary, ""])
            L.extend("- " + x for x in lines)
            L.append("</details>")
        L.append("")
    return L


def cross_section(bench):
    """The bar of the table above held between the methods themselves, at the same face counts:
    how often each method is not worse than each other one, and how often it is beaten in both
    Hausdorff distance and p95 normal deviation at once (dominated), so that the bar can be read
    against what the peers achieve among themselves."""
    rows = bench.rows
    at = {}  # (model, level) -> method -> errors at our level's face count
    for g in our_levels(rows, "gausslod"):
        at[(g["model"], g["level"])] = {"gausslod": g}
    for meth in PEERS:
        for c in peer_comparisons(rows, meth)[0]:
            at[(c["model"], c["level"])][meth] = c["peer"]
    methods = ["gausslod"] + [m for m in PEERS if any(m in v for v in at.values())]
    if len(methods) < 2:
        return []
    label = dict(LABEL, gausslod="GaussLOD")
    H, N = ERRORS[0], ERRORS[2]

    def not_worse(v, a, b):
        """Is a not worse than b at this level, (in Hausdorff, in p95)?"""
        return (judge(v[a][H[0]], v[b][H[0]], H[2], H[3])[0], judge(v[a][N[0]], v[b][N[0]], N[2], N[3])[0])

    def pair(a, b):
        """(levels, a not worse in Hausdorff, in p95, a dominated by b) over the levels both have."""
        n = good_h = good_n = beaten = 0
        for v in at.values():
            if a not in v or b not in v:
                continue
            ok_h, ok_n = not_worse(v, a, b)
            n += 1
            good_h += ok_h
            good_n += ok_n
            beaten += not ok_h and not ok_n
        return n, good_h, good_n, beaten

    L = ["### The same bar between the methods themselves", ""]
    L.append("Each row's method against each column's, at the face counts of our levels (the runs of the table "
             "above; angle-driven peers interpolated as there): levels compared; not worse in Hausdorff distance; "
             "not worse in p95 normal deviation; dominated (worse in both at once). The bar above asks >= 80 % in "
             "each of the first two against every peer.")
    L.append("")
    L.append("| row against column | " + " | ".join(label[m] for m in methods) + " |")
    L.append("|---|" + "---|" * len(methods))
    for a in methods:
        cells = []
        for b in methods:
            if a == b:
                cells.append("–")
                continue
            n, gh, gn, beaten = pair(a, b)
            cells.append("%d: H %d, p95 %d, dom. %d" % (n, gh, gn, beaten) if n else "–")
        L.append("| %s | %s |" % (label[a], " | ".join(cells)))
    L.append("")
    meets = []
    for a in methods:
        others = [pair(a, b) for b in methods if b != a]
        others = [x for x in others if x[0]]
        ok = sum(1 for n, gh, gn, _ in others if gh >= 0.8 * n and gn >= 0.8 * n)
        meets.append("%s %d of %d" % (label[a], ok, len(others)))
    compared = {k: v for k, v in at.items() if len(v) > 1}
    dominated = sorted(k for k, v in compared.items()
                       if any(b != "gausslod" and not any(not_worse(v, "gausslod", b)) for b in v))
    L.append("Methods that meet the 80 %% part of the bar (Hausdorff and p95) against how many of the others: %s. "
             "GaussLOD levels dominated by at least one peer: %d of %d%s." % (
                 "; ".join(meets), len(dominated), len(compared),
                 " (%s)" % ", ".join("%s L%d" % k for k in dominated) if dominated else ""))
    L.append("")
    return L


PLOT_STYLE = {"gausslod": "lw 2 pt 7 lc rgb '#d62728'", "gausslod_dist": "lw 2 dt 2 pt 6 lc rgb '#e377c2'",
              "meshopt": "pt 5 lc rgb '#1f77b4'", "cgal_gh": "pt 9 lc rgb '#2ca02c'",
              "meshlab_quadric": "pt 11 lc rgb '#9467bd'", "meshlab_quadric_planar": "pt 13 lc rgb '#8c564b'",
              "openmesh_quadric": "pt 15 lc rgb '#17becf'", "blender_planar": "pt 3 lc rgb '#ff7f0e'",
              "openmesh_nd": "dt 3 pt 2 lc rgb '#7f7f7f'"}


def plot(bench, resdir, name, rows):
    """Hausdorff, mean distance and p95 normal deviation vs faces (three panels), one line per
    method: every run, sweeps included; GaussLOD's points labelled with their level."""
    if not shutil.which("gnuplot"):
        return None
    d = os.path.join(bench.work, "plot")
    os.makedirs(d, exist_ok=True)
    series = []
    for meth in ["gausslod", "gausslod_dist"] + PEERS:
        pts = sorted({(r["faces"], r["hausdorff_pct"], r["mean_pct"], r["normal_p95_deg"])
                      for r in rows if r["method"] == meth and usable(r)})
        if not pts:
            continue
        fn = os.path.join(d, "%s_%s.dat" % (name, meth))
        with open(fn, "w") as f:
            for p in pts:
                f.write("%d %.9g %.9g %.9g\n" % p)
        series.append((fn, LABEL[meth], meth, pts))
    if not series:
        return None
    png = os.path.join(resdir, "error_%s.png" % name)
    gp = ["set terminal pngcairo size 900,1100 font 'Sans,10'", "set output '%s'" % png,
          "set termoption noenhanced", "set multiplot layout 3,1 title 'Error vs face count: %s'" % name,
          "set logscale x", "set grid", "set key outside right top", "set format x '%.0s%c'",
          "set lmargin at screen 0.09", "set rmargin at screen 0.66",
          "set format y '%g'", "set xlabel 'faces (log)'"]
    levels = sorted({(r["faces"], r["level"]) for r in rows if r["method"] == "gausslod" and usable(r)})
    for col, (k, label, _, _, logy) in enumerate(ERRORS):
        vals = [p[col + 1] for _, _, _, pts in series for p in pts]
        logy = logy and all(v > 0 for v in vals)
        gp.append("%s logscale y" % ("set" if logy else "unset"))
        clip = ""
        if k == "normal_p95_deg":
            # linear (zeros are common); a peer's folded faces (180°) would flatten our curve
            ours = [p[col + 1] for _, _, m, pts in series if m.startswith("gausslod") for p in pts]
            top = max([10.0] + [2.5 * v for v in ours])
            gp.append("set yrange [0:%g]" % top)
            clip = ", clipped at %.0f" % top if max(vals) > top else ""
        gp.append("set ylabel '%s%s%s%s'" % (label, " °" if k == "normal_p95_deg" else ", % of diagonal",
                                              " (log)" if logy else "", clip))
        gp.append("unset label")
        for f, lv in levels:
            v = next(r[k] for r in rows if r["method"] == "gausslod" and r["faces"] == f and usable(r))
            if not logy or v > 0:
                gp.append("set label 'L%d' at %d,%.9g offset 0.6,0.6 font ',8' tc rgb '#d62728'" % (lv, f, v))
        gp.append("plot " + ", ".join("'%s' using 1:%d with linespoints %s title '%s'" % (
            fn, col + 2, PLOT_STYLE[m], t) for fn, t, m, _ in series))
        gp.append("unset key")  # one legend, on the first panel
    gp.append("unset multiplot")
    script = os.path.join(d, name + ".gp")
    with open(script, "w") as f:
        f.write("\n".join(gp) + "\n")
    r = subprocess.run(["gnuplot", script], capture_output=True, text=True)
    return os.path.basename(png) if r.returncode == 0 and os.path.exists(png) else None


def bars(bench):
    """The issue's bars as measured ratios. Returns Markdown lines."""
    rows, models = bench.rows, bench.models
    L = []

    def ok(flag):
        return "**met**" if flag else "**MISSED**"

    big = next((m for m in models.values() if "speed" in m.get("groups", []) and m.get("levels")), None)
    scale = next((m for m in models.values() if "scale" in m.get("groups", []) and m.get("levels")), None)
    small = next((m for m in models.values() if "small" in m.get("groups", []) and m.get("levels")), None)

    def peer_row(model, meth, level, variant=None):
        for r in rows:
            if r["model"] == model and r["method"] == meth and r["level"] == level and r.get("variant") == variant:
                return r
        return None

    def details(summary, lines):
        """A folded Markdown list after an empty line."""
        L.extend(["", "<details><summary>%s</summary>" % summary, ""])
        L.extend("- " + x for x in lines)
        L.append("</details>")

    def cad_levels(method="gausslod"):
        """GaussLOD's levels of the CAD models; a level that reused the finer level's mesh once."""
        seen = set()
        for g in rows:
            if g["method"] != method or g.get("error") or "cad" not in models.get(g["model"], {}).get("groups", []):
                continue
            key = (g["model"], g["faces"], g.get("hausdorff_pct"))
            if key not in seen:
                seen.add(key)
                yield g

    L.append("### Speed (GaussLOD: all 5 levels, engine time summed over levels, in-process)")
    if big:
        g = big["gausslod_seconds"]
        coarse = min(l["level"] for l in big["levels"])
        cf = [l for l in big["levels"] if l["level"] == coarse][0]["faces"]
        L.append("Mesh `%s`: %s input faces; GaussLOD %.2f s for all %d levels (process wall %.2f s); "
                 "peers run once, to GaussLOD's coarsest level L%d (%d faces; Blender at that level's "
                 "angle %.2f deg)." % (big["name"], big["faces_in"], g, len(big["levels"]),
                                       big["gausslod_wall"], coarse, cf, big["levels"][-1]["bound_deg"]))
        L.append("")
        L.append("| bar | peer time (s) | ratio | wanted | verdict |")
        L.append("|---|---|---|---|---|")
        r = peer_row(big["name"], "meshopt", coarse)
        if r and r.get("seconds") is not None and not r.get("error"):
            ratio = g / r["seconds"]
            L.append("| GaussLOD time / meshopt_simplify time | %.3f | %.2f | <= 1.0 | %s |" % (r["seconds"], ratio, ok(ratio <= 1.0)))
        else:
            L.append("| GaussLOD time / meshopt_simplify time | – | – | <= 1.0 | not measured (%s) |" % (r and r.get("error")))
        for meth in ("meshlab_quadric", "meshlab_quadric_planar"):
            r = peer_row(big["name"], meth, coarse)
            if r and r.get("seconds") is not None and not r.get("error"):
                ratio = r["seconds"] / g
                L.append("| %s time / GaussLOD time | %.2f | %.2f | >= 20 | %s |" % (LABEL[meth], r["seconds"], ratio, ok(ratio >= 20)))
            else:
                L.append("| %s time / GaussLOD time | – | – | >= 20 | not measured (%s) |" % (LABEL[meth], r and r.get("error")))
        r = peer_row(big["name"], "blender_planar", coarse)
        if r and r.get("seconds") is not None:
            ratio = r["seconds"] / g
            L.append("| Blender planar time / GaussLOD time | %.2f | %.2f | >= 100 | %s |" % (r["seconds"], ratio, ok(ratio >= 100)))
        else:
            L.append("| Blender planar time / GaussLOD time | – | – | >= 100 | not measured (%s) |" % (r and r.get("error")))
        L.append("")
        L.append("MeshLab times are the filter's own span in meshlabserver's unbuffered log (from `filter: %s` "
                 "to the next filter's line) minus the same span between two `Select None` filters on the same "
                 "mesh; loading and saving are excluded. meshopt/CGAL/Blender: in-process wall clock around the "
                 "simplification call(s). Process wall clocks are in the raw rows (`raw.jsonl`)." % QUADRIC)
    else:
        L.append("Not measured: the >= 1M-face mesh was not run (`--quick` or it failed).")
    L.append("")
    issue = [m for m in models.values() if "issue_speed" in m.get("groups", [])]
    L.append("### Speed on the issue's meshes (all 5 levels vs meshopt_simplify to the coarsest level)")
    if issue:
        L.append("The meshes issue 18 names: the grid cube with 1.92M faces and fandisk_large subdivided "
                 "3 times (2.03M faces, the same surface). GaussLOD: engine time summed over the levels "
                 "(in-process) and the whole `gausslod` process (read, 5 levels, write); meshopt: the "
                 "fastest of three in-process runs to GaussLOD's coarsest face count.")
        L.append("")
        L.append("| mesh | faces | coarsest level | GaussLOD engine s | process s | meshopt s | engine / meshopt (wanted <= 1.0) | process / meshopt (wanted <= 1.3) |")
        L.append("|---|---|---|---|---|---|---|---|")
        for m in issue:
            if not m.get("levels"):
                L.append("| %s | – | – | – | – | – | FAILED: %s | |" % (m["name"], m.get("gausslod_error")))
                continue
            coarse = min(m["levels"], key=lambda l: l["level"])
            mo = [r["seconds"] for r in bench.speed_rows
                  if r["model"] == m["name"] and r["method"] == "meshopt" and r.get("seconds") and not r.get("error")]
            if not mo:
                L.append("| %s | %s | L%d, %d faces | %.2f | %.2f | – | not measured | |" % (
                    m["name"], m["faces_in"], coarse["level"], coarse["faces"], m["gausslod_seconds"], m["gausslod_wall"]))
                continue
            t = min(mo)
            e, w = m["gausslod_seconds"] / t, m["gausslod_wall"] / t
            L.append("| %s | %s | L%d, %d faces | %.2f | %.2f | %.3f | %.2f %s | %.2f %s |" % (
                m["name"], m["faces_in"], coarse["level"], coarse["faces"], m["gausslod_seconds"],
                m["gausslod_wall"], t, e, ok(e <= 1.0), w, ok(w <= 1.3)))
        L.append("")
        L.append("Per level (faces, seconds): " + "; ".join(
            "%s %s" % (m["name"], ", ".join("L%d %d f %.2f s" % (l["level"], l["faces"], l["seconds"])
                                             for l in m.get("levels", []))) for m in issue) + ".")
    else:
        L.append("Not measured: the issue's meshes were not run (`--quick` or `--models`).")
    L.append("")
    L.append("### Scaling (GaussLOD engine time per input face, all 5 levels)")
    if scale and small:
        pf_big = scale["gausslod_seconds"] / scale["faces_in"]
        pf_small = small["gausslod_seconds"] / small["faces_in"]
        ratio = pf_big / pf_small
        L.append("| meshes | seconds | us per face | ratio | wanted | verdict |")
        L.append("|---|---|---|---|---|---|")
        L.append("| %s (%d faces) / %s (%d faces) | %.3f / %.3f | %.3f / %.3f | %.2f | <= 1.5 | %s |" % (
            scale["name"], scale["faces_in"], small["name"], small["faces_in"], scale["gausslod_seconds"],
            small["gausslod_seconds"], pf_big * 1e6, pf_small * 1e6, ratio, ok(ratio <= 1.5)))
        if big:
            L.append("")
            L.append("For reference, %s (%d faces): %.3f s, %.3f us per face." % (
                big["name"], big["faces_in"], big["gausslod_seconds"], big["gausslod_seconds"] / big["faces_in"] * 1e6))
    else:
        L.append("Not measured: the 2M-face or the 100k-face mesh was not run (`--quick` or it failed).")
    L.append("")

    L.append("### Peak memory (GaussLOD tool, all 5 levels incl. writing them, vs loading the mesh alone)")
    L.append("| model | input faces | load-only peak MB (as the tool reads it) | GaussLOD peak MB | ratio | wanted "
             "| verdict | load into VCG's mesh, peak MB | ratio to it |")
    L.append("|---|---|---|---|---|---|---|---|---|")
    for m in models.values():
        own, vcg, peak = m.get("tool_load_peak_mb"), m.get("load_peak_mb"), m.get("gausslod_peak_mb")
        if own and peak and m.get("levels"):
            ratio = peak / own
            mark = " (a bar mesh)" if ("speed" in m["groups"] or "scale" in m["groups"]) else ""
            L.append("| %s%s | %s | %.1f | %.1f | %.2f | <= 3 | %s | %s | %s |" % (
                m["name"], mark, m["faces_in"], own, peak, ratio, ok(ratio <= 3),
                fmt(vcg, "%.1f"), fmt(peak / vcg if vcg else None, "%.2f")))
    L.append("")
    L.append("Both peaks are whole-process maximum resident sets from `/usr/bin/time -v`; small meshes are "
             "dominated by the process's fixed footprint, the bar is about the large one. Loading alone is "
             "`bench_load --tool`: the tool's own read (since DESIGN 43 a plain binary PLY goes straight into "
             "the engine's flat arrays, without a VCG mesh). The last two columns are the reference of the "
             "runs before DESIGN 43: the mesh loaded into VCG's mesh type by the guarded VCG importers "
             "(`bench_load`), as MeshLab holds it.")
    L.append("")

    L.append("### Exactness on the grid cube (each side a 50 x 50 grid)")
    cube = [r for r in rows if "gridcube" in models.get(r["model"], {}).get("groups", []) and r["method"] == "gausslod"]
    if cube:
        good = all(not r.get("error") and r.get("faces") == 12 and r.get("hausdorff_pct", 1) <= 1e-9 for r in cube)
        L.append("Wanted: 12 triangles and zero Hausdorff at every level (zero = below 1e-9 %% of the diagonal, "
                 "i.e. double rounding). Measured: %s. %s" % (
                     "; ".join("L%s %s faces, %s %%" % (r["level"], r.get("faces"), fmt(r.get("hausdorff_pct"), "%.2g")) for r in cube),
                     ok(good)))
    else:
        L.append("Not measured (cube not run).")
    L.append("")

    L.append("### Quality vs Blender planar (GaussLOD level L vs Blender at L's angle sqrt(2)*90/3^L)")
    ZERO = 1e-9  # Hausdorff below this (% of the diagonal) is double rounding: equal

    def le(a, b, zero=0.0):
        return a <= b or (a <= zero and b <= zero)

    def lt(a, b, zero=0.0):
        return a < b and not (a <= zero and b <= zero)

    comp = {k: [0, 0, 0] for k in ("faces", "hausdorff", "slivers")}  # not worse, strictly better, n
    empty = []
    lines = []
    for g in rows:
        if g["method"] != "gausslod" or g.get("error"):
            continue
        b = peer_row(g["model"], "blender_planar", g["level"])
        if not b:
            continue
        if b.get("error") or b.get("hausdorff_pct") is None:
            empty.append("%s L%s (%s)" % (g["model"], g["level"], b.get("error")))
            continue
        pairs = (("faces", g["faces"], b["faces"], 0.0), ("hausdorff", g["hausdorff_pct"], b["hausdorff_pct"], ZERO),
                 ("slivers", g["sliver_pct"], b["sliver_pct"], 0.0))
        allok = True
        for k, x, y, z in pairs:
            comp[k][0] += int(le(x, y, z))
            comp[k][1] += int(lt(x, y, z))
            comp[k][2] += 1
            allok = allok and le(x, y, z)
        if not allok:
            lines.append("%s L%d: faces %d vs %d, Hausdorff %.3g vs %.3g %%, slivers %.1f vs %.1f %%" % (
                g["model"], g["level"], g["faces"], b["faces"], g["hausdorff_pct"], b["hausdorff_pct"],
                g["sliver_pct"], b["sliver_pct"]))
    n = comp["faces"][2]
    if n:
        allgood = all(v[0] == v[2] for v in comp.values())
        L.append("Wanted: fewer faces, lower Hausdorff, fewer slivers. Over %d comparisons where both produced a mesh, "
                 "GaussLOD is not worse / strictly better in: faces %d / %d, Hausdorff %d / %d, slivers %d / %d. "
                 "%s (met = not worse in all three, every time; equal counts as not worse)." % (
                     n, comp["faces"][0], comp["faces"][1], comp["hausdorff"][0], comp["hausdorff"][1],
                     comp["slivers"][0], comp["slivers"][1], ok(allgood)))
        if lines:
            details("%d comparisons where GaussLOD is worse in at least one (GaussLOD vs Blender)" % len(lines),
                    lines)
    else:
        L.append("Not measured (Blender did not run).")
    if empty:
        L.append("")
        L.append("Blender produced no usable mesh in %d case(s), not counted above: %s." % (len(empty), "; ".join(empty)))
    L.append("")

    L.append("### Quality vs quadric methods on CAD models (p95 normal deviation, same face count)")
    quad = QUADRIC_PEERS

    def p95_tally(method, variant):
        """Per quadric peer: [not worse (<= 0.005 deg tolerance), strictly lower, n]; worse lines."""
        tally = {q: [0, 0, 0] for q in quad}
        worse = []
        for g in cad_levels(method):
            for q in quad:
                p = peer_row(g["model"], q, g["level"], variant)
                if not p or p.get("error") or p.get("normal_p95_deg") is None:
                    continue
                tally[q][2] += 1
                a, b = g["normal_p95_deg"], p["normal_p95_deg"]
                tally[q][1] += int(a < b - 0.005)
                if a <= b + 0.005:
                    tally[q][0] += 1
                else:
                    worse.append("%s L%d vs %s: %.2f vs %.2f deg" % (g["model"], g["level"], LABEL[q], a, b))
        return tally, worse

    def tally_text(tally):
        return ", ".join("%s %d / %d / %d" % (LABEL[q], tally[q][0], tally[q][1], tally[q][2]) for q in quad)

    tally, worse = p95_tally("gausslod", None)
    if any(v[2] for v in tally.values()):
        allgood = all(v[0] == v[2] for v in tally.values())
        L.append("Wanted: GaussLOD's p95 normal deviation lower. Not higher / strictly lower / comparisons "
                 "(a level that reused the finer level's mesh counted once): " + tally_text(tally)
                 + ". %s (met = not higher in every comparison, 0.005 deg tolerance)." % ok(allgood))
        if worse:
            details("%d comparisons where GaussLOD's p95 is higher" % len(worse), worse)
        dtally, _ = p95_tally("gausslod_dist", "dist")
        if any(v[2] for v in dtally.values()):
            L.append("")
            L.append("With the %g %% distance tolerance (the quadric methods at its face counts): %s." % (
                DIST_PCT, tally_text(dtally)))
    else:
        L.append("Not measured.")
    L.append("")

    # the issue: "report the Hausdorff ratio to the best of them honestly, and work it down"
    def hausdorff_vs_quadric(method, variant):
        """(ratios, lines): the method's Hausdorff / the best quadric peer's at its face counts."""
        ratios, lines = [], []
        for g in cad_levels(method):
            if g.get("hausdorff_pct") is None:
                continue
            best = None
            for q in quad:
                p = peer_row(g["model"], q, g["level"], variant)
                if p and not p.get("error") and p.get("hausdorff_pct") is not None:
                    if best is None or p["hausdorff_pct"] < best[1]:
                        best = (q, p["hausdorff_pct"])
            if best is None:
                continue
            zero = 1e-9  # % of the diagonal: double rounding
            h, hb = g["hausdorff_pct"], best[1]
            r = 1.0 if h <= zero and hb <= zero else (float("inf") if hb <= zero else max(h, zero) / hb)
            ratios.append(r)
            lines.append("%s L%d (%d faces): %.3g %% vs %.3g %% (%s): %s" % (
                g["model"], g["level"], g["faces"], h, hb, LABEL[best[0]],
                "inf" if r == float("inf") else "%.2f" % r))
        return ratios, lines

    def ratio_summary(ratios):
        finite = sorted(x for x in ratios if x != float("inf"))
        med = finite[len(finite) // 2] if finite else float("nan")
        return "%d comparisons, not higher in %d, median ratio %.2f, largest %s" % (
            len(ratios), sum(1 for x in ratios if x <= 1.0), med,
            "inf" if max(ratios) == float("inf") else "%.2f" % max(ratios))

    L.append("### Hausdorff distance vs the best quadric method on CAD models (same face count)")
    ratios, lines = hausdorff_vs_quadric("gausslod", None)
    if ratios:
        L.append("GaussLOD's Hausdorff distance divided by the lowest of the four quadric methods' at the same "
                 "face count, per CAD level (a level that reused the finer level's mesh counted once): "
                 "%s. The issue asks to report it and work it down (no fixed bar)." % ratio_summary(ratios))
        details("every comparison (GaussLOD vs the best quadric method: ratio)", lines)
    else:
        L.append("Not measured.")
    dratios, dlines = hausdorff_vs_quadric("gausslod_dist", "dist")
    if dratios:
        L.append("")
        L.append("With a uniform distance tolerance (`--max-distance %g --distance-growth 1`: no removed input vertex, and no point of an "
                 "input face, farther than %g %% of the diagonal from the output, as GaussLOD measures it), the "
                 "quadric methods run again at those levels' face counts: %s." % (
                     DIST_PCT, DIST_PCT, ratio_summary(dratios)))
        details("every comparison with the distance tolerance (ratio)", dlines)
    L.append("")

    L.append("### Validity of GaussLOD's output (all models, all levels)")
    gl = [r for r in rows if r["method"] == "gausslod" and not r.get("error")]
    nm = sum(r.get("nonmanifold_edges", 0) for r in gl)
    fl = sum(r.get("flipped", 0) for r in gl)
    bad = ["%s L%d: %d non-manifold edges, %d flipped" % (r["model"], r["level"], r["nonmanifold_edges"], r["flipped"])
           for r in gl if r.get("nonmanifold_edges") or r.get("flipped")]
    L.append("Wanted: zero non-manifold edges and zero flipped faces. Measured over %d level meshes: %d non-manifold "
             "edges, %d flipped faces. %s" % (len(gl), nm, fl, ok(nm == 0 and fl == 0)))
    if bad:
        L.append("")
        for x in bad:
            L.append("- " + x)
    L.append("")
    return L


def bound_section(bench):
    """Our levels' reported distance bound (DESIGN 23) against the Hausdorff distance measured here:
    the bound must never be below it."""
    L = ["### Reported distance bound vs measured Hausdorff distance (our levels)", ""]
    pairs = []
    for r in our_levels(bench.rows, "gausslod"):
        b = (r.get("extra") or {}).get("distance_bound_pct")
        if b is not None:
            pairs.append((r["model"], r["level"], b, r["hausdorff_pct"]))
    if not pairs:
        return L + ["No level reported a bound (distance tolerance off).", ""]
    # (distances below 1e-9 % are double rounding, as for the grid cube's exactness: an exact
    # level's bound is 0 while the sampled distance may be 1e-14 %)
    below = [p for p in pairs if p[2] < p[3] * (1 - 1e-6) and p[3] > 1e-9]
    ratios = [p[2] / p[3] for p in pairs if p[3] > 1e-9]
    L.append("%d levels: bound below the measured Hausdorff distance in **%d** (wanted: 0); bound / measured: "
             "median %s, min %s, max %s (a sampled distance is at most the true one, so the bound is expected "
             "above it)." % (len(pairs), len(below), fmt(median(ratios)), fmt(min(ratios) if ratios else None),
                             fmt(max(ratios) if ratios else None)))
    for m, lvl, b, h in below:
        L.append("- BELOW: %s LOD%s bound %s %% < Hausdorff %s %%" % (m, lvl, fmt(b), fmt(h)))
    L.append("")
    return L


def report(bench, resdir, cmdline):
    os.makedirs(resdir, exist_ok=True)
    for f in os.listdir(resdir):  # the plots' earlier name (Hausdorff only): stale
        if f.startswith("hausdorff_") and f.endswith(".png"):
            os.unlink(os.path.join(resdir, f))
    rows = bench.rows
    with open(os.path.join(resdir, "raw.jsonl"), "w") as f:
        for r in rows + bench.speed_rows:
            f.write(json.dumps(r) + "\n")
    L = ["# GaussLOD vs peer simplifiers", ""]
    L.append("Generated by `%s` on %s (run took %.1f min)." % (
        cmdline, datetime.datetime.now().strftime("%Y-%m-%d %H:%M:%S %Z").strip(), bench.total_wall / 60.0))
    L.append("")
    L.append("Machine: %s. Peers: %s." % (machine_line(), versions()))
    L.append("")
    L.append("Distances: two-sided, %d Montecarlo samples per surface plus its vertices (at most a quarter of that), "
             "in %% of the original's bounding-box diagonal. Columns are explained in `bench/README.md`. Every figure below was "
             "measured in this run; a failed run is listed with its error." % bench.args.samples)
    L.append("")
    L.append("## Bars of the issue")
    L.append("")
    L += bars(bench)
    L += pareto_section(bench)
    L += cross_section(bench)
    L += bound_section(bench)
    L.append("## Results per model")
    L.append("")
    for name, m in bench.models.items():
        if "issue_speed" in m["groups"]:
            continue  # (times only: the speed section above)
        mrows = [r for r in rows if r["model"] == name]
        L.append("### %s" % name)
        L.append("")
        if m.get("error"):
            L.append("Failed: %s" % m["error"])
            L.append("")
            continue
        L.append("Input: %s faces (%s); load-only peak %s MB (%s MB into VCG's mesh). GaussLOD engine total %s s "
                 "for %d levels%s." % (
            m.get("faces_in"), ", ".join(m["groups"]), fmt(m.get("tool_load_peak_mb"), "%.1f"),
            fmt(m.get("load_peak_mb"), "%.1f"),
            fmt(m.get("gausslod_seconds"), "%.3f"), len(m.get("levels", [])),
            {"coarsest": "; peers only at the coarsest level (time budget; `--big-all-levels` runs all)",
             "none": "; GaussLOD only (scaling bar), no peers"}.get(
                 "all" if bench.args.big_all_levels and m.get("peers") == "coarsest" else m.get("peers", "all"), "")))
        L.append("")
        L.append("| method | level | target | faces | Hausdorff % | mean dist % | normal p95 ° | normal max ° | slivers % | non-manifold edges | flipped | seconds | peak MB | note |")
        L.append("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
        order = {k: i for i, k in enumerate(["gausslod", "gausslod_dist"] + PEERS)}
        for r in sorted(mrows, key=lambda r: (-(r["level"] if r["level"] is not None else -1), order.get(r["method"], 9),
                                              -(r.get("angle_deg") or 0))):
            target = r["target"] if r["target"] is not None else (
                "%.2f°" % r["angle_deg"] if r.get("angle_deg") is not None else "–")
            note = r.get("note") or ""
            if r.get("error"):
                note = (note + "; " if note else "") + "FAILED: " + r["error"]
            ex = r.get("extra") or {}
            if r["method"] == "gausslod" and ex.get("fallbacks"):
                note = (note + "; " if note else "") + "%d fallbacks" % ex["fallbacks"]
            if ex.get("skipped_input_faces"):
                note = (note + "; " if note else "") + "%s skipped %d non-manifold input faces" % (
                    "OpenMesh" if r["method"].startswith("openmesh") else "CGAL", ex["skipped_input_faces"])
            L.append("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
                LABEL[r["method"]], "L%d" % r["level"] if r["level"] is not None else "–", target, fmt(r.get("faces"), "%d"),
                fmt(r.get("hausdorff_pct"), "%.4g"), fmt(r.get("mean_pct"), "%.3g"),
                fmt(r.get("normal_p95_deg"), "%.2f"), fmt(r.get("normal_max_deg"), "%.1f"),
                fmt(r.get("sliver_pct"), "%.1f"), fmt(r.get("nonmanifold_edges"), "%d"),
                fmt(r.get("flipped"), "%d"), fmt(r.get("seconds"), "%.3f"), fmt(r.get("peak_mb"), "%.0f"), note))
        L.append("")
        png = plot(bench, resdir, name, mrows)
        if png:
            L.append("![Hausdorff, mean distance and p95 normal deviation vs faces, %s](%s)" % (name, png))
            L.append("")
    with open(os.path.join(resdir, "RESULTS.md"), "w") as f:
        f.write("\n".join(L) + "\n")
    return os.path.join(resdir, "RESULTS.md")


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--build", required=True, help="build folder of bench/ (holds the programs)")
    ap.add_argument("--quick", action="store_true", help="small subset (%s)" % ", ".join(QUICK))
    ap.add_argument("--models", help="comma-separated model names (default: all, or the quick set)")
    ap.add_argument("--methods", default=",".join(PEERS), help="peers to run (default: all)")
    ap.add_argument("--samples", type=int, help="Montecarlo samples per surface (200000; quick 50000)")
    ap.add_argument("--timeout", type=float, default=900, help="per peer run, seconds")
    ap.add_argument("--blender-timeout", type=float, default=1200, help="per Blender run, seconds")
    ap.add_argument("--big-all-levels", action="store_true", help="run the peers at every level of bumpy_1m too")
    ap.add_argument("--results", help="output folder (default bench/results, --quick: bench/results/quick)")
    args = ap.parse_args()
    args.methods = args.methods.split(",")
    if args.samples is None:
        args.samples = 50000 if args.quick else 200000
    names = args.models.split(",") if args.models else (QUICK if args.quick else [m["name"] for m in MODELS])
    unknown = [n for n in names if n not in {m["name"] for m in MODELS}]
    if unknown:
        sys.exit("unknown model(s): %s" % ", ".join(unknown))
    models = [m for m in MODELS if m["name"] in names]
    resdir = args.results or os.path.join(BENCH, "results", "quick" if args.quick else "")
    resdir = os.path.normpath(resdir)
    bench = Bench(args)
    bench.run_all(models)
    cmdline = os.environ.get("BENCH_CMDLINE", "bench/run_bench.py " + " ".join(sys.argv[1:]))
    out = report(bench, resdir, cmdline)
    log("wrote %s (%.1f min)" % (out, bench.total_wall / 60.0))


if __name__ == "__main__":
    main()
