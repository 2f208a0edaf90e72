#!/usr/bin/env bash
# gausslod batch on a manifest of several hundred real files and some bad ones: killed with
# SIGKILL half way and restarted, every good file is done once, every bad one reported, nothing
# lost or half written; a third run redoes nothing; GNU parallel (local jobs and the
# --sshloginfile form, with ':' = this machine) and the Slurm array script split the manifest
# into disjoint parts whose outputs are the same files; with --levels-by faces or error on a
# manifest line, each level of the record carries what `gausslod --json` prints for it (target,
# whether reached, tolerance, trials). (Levels as binary PLY, --format ply; OBJ levels with their
# material files in batch: test_cli_attributes.sh.)
# usage: test_batch.sh GAUSSLOD DATA_DIR WORK_DIR SLURM_SCRIPT
. "$(dirname "${BASH_SOURCE[0]}")/common.sh"
tool=$1 data=$(cd "$2" && pwd) work=$3 slurm=$4
fresh_work "$work" in/sub

# --- 300 good inputs (links to 10 of Debian's small CGAL models), 20 bad ones ------------------
models=(joint pig helmet anchor rotor eight nefertiti dragknob part blob)
: >"$work/manifest.txt"
echo "# made by test_batch.sh" >>"$work/manifest.txt"
for i in $(seq -w 0 299); do
  m=${models[$((10#$i % 10))]}
  dir=in; [ $((10#$i % 3)) = 0 ] && dir=in/sub
  ln -s "$data/$m.off" "$work/$dir/m$i.off"
  echo "$dir/m$i.off" >>"$work/manifest.txt"
done
for i in $(seq -w 0 19); do
  case $((10#$i % 5)) in
    0) head -c 3000 /dev/urandom >"$work/in/bad$i.ply" ;;
    1) : >"$work/in/bad$i.off" ;;
    2) printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n' >"$work/in/bad$i.off" ;;
    3) printf 'ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n1 1 1\n' >"$work/in/bad$i.ply" ;;
    4) ;; # missing file
  esac
  ext=ply; [ -e "$work/in/bad$i.off" ] && ext=off
  echo "in/bad$i.$ext" >>"$work/manifest.txt"
done
good=300 bad=20
(cd "$work" && grep -v '^#' manifest.txt | shuf --random-source=<(yes) >manifest.txt.shuf &&
  { echo "# made by test_batch.sh"; cat manifest.txt.shuf; } >manifest.txt)

# the superface levels (no level continued by collapses, no certified distance): what is tested
# here is the batch, on many files; the continued levels and the certified distance are tested
# on their own (test_cli_targets.sh, core tests)
superfaces_only="--complete-chain false --certify-distance false"

# --- 1. run, SIGKILL after a third of the records, restart ---------------------------------------
"$tool" batch --threads 1 --format ply $superfaces_only "$work/manifest.txt" "$work/out" >"$work/run1.jsonl" 2>"$work/run1.err" &
pid=$!
for _ in $(seq 600); do
  [ "$(find "$work/out" -name '*.gausslod.json' 2>/dev/null | wc -l)" -ge 100 ] && break
  kill -0 $pid 2>/dev/null || break
  sleep 0.05
done
if kill -0 $pid 2>/dev/null; then
  kill -9 $pid; wait $pid 2>/dev/null
  pass "killed with SIGKILL after $(wc -l <"$work/run1.jsonl") results"
else
  fail "the first run ended before it could be killed (make the manifest longer)"
fi
# a level file under its final name is never partial (binary PLY: the size the header says)
check_ply() { python3 - "$@" <<'PY'
import os, sys
bad = 0
for f in sys.argv[1:]:
    data = open(f, 'rb').read()
    end = data.find(b'end_header\n') + len(b'end_header\n')
    counts = {}
    for line in data[:end].decode().splitlines():
        w = line.split()
        if w[:1] == ['element']:
            counts[w[1]] = int(w[2])
    # vertex: 3 doubles or floats; the writer's layout is fixed: find it from the properties
    header = data[:end].decode()
    vsize = sum({'float': 4, 'double': 8, 'uchar': 1, 'int': 4}[l.split()[1]]
                for l in header.split('element vertex')[1].split('element face')[0].splitlines()
                if l.startswith('property'))
    fprops = [l for l in header.split('element face')[1].splitlines() if l.startswith('property')]
    fsize = 1 + 3 * 4 + sum({'uchar': 1, 'float': 4, 'int': 4}[l.split()[1]]
                            for l in fprops if not l.startswith('property list'))
    if len(data) != end + counts['vertex'] * vsize + counts['face'] * fsize:
        print('partial or wrong size:', f); bad += 1
sys.exit(1 if bad else 0)
PY
}
mapfile -t levels < <(find "$work/out" -name '*_LOD*.ply')
[ ${#levels[@]} -gt 0 ] && check_ply "${levels[@]}" && pass "after the kill: ${#levels[@]} level files, none partial" ||
  fail "after the kill: a level file is partial"

"$tool" batch --threads 1 --format ply $superfaces_only "$work/manifest.txt" "$work/out" >"$work/run2.jsonl" 2>"$work/run2.err"; rc=$?
[ $rc -eq 1 ] && pass "restart: exit 1 (some inputs failed)" || fail "restart: exit $rc, want 1"
python3 - "$work" $good $bad <<'PY' && pass "every good file done once, every bad one reported" || fail "batch results wrong (above)"
import json, sys, collections
work, good, bad = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
done = collections.Counter(); errors = set(); cached = set(); problems = []
for run in ('run1', 'run2'):
    for line in open(f'{work}/{run}.jsonl'):
        r = json.loads(line)
        if r['status'] == 'ok':
            assert len(r['levels']) == 5 and r['faces'] > 0, r
            if r['cached']: cached.add(r['input'])
            else: done[r['input']] += 1
        else:
            assert r['code'] in (3, 4, 5) and r['message'], r
            errors.add(r['input'])
run2 = [json.loads(l) for l in open(f'{work}/run2.jsonl')]
if len(run2) != good + bad: problems.append(f'run 2 printed {len(run2)} lines, want {good + bad}')
if len(done) != good: problems.append(f'{len(done)} good files done, want {good}')
twice = [k for k, n in done.items() if n != 1]
if twice: problems.append(f'done more than once: {twice[:5]}')
if len(errors) != bad: problems.append(f'{len(errors)} bad files reported, want {bad}')
if not cached: problems.append('nothing of run 1 was reused')
print(f'{len(done)} done once, {len(cached)} reused from the killed run, {len(errors)} errors')
for p in problems: print('problem:', p)
sys.exit(1 if problems else 0)
PY
left=$(find "$work/out" -name '*.part-*' | wc -l)
[ "$left" -eq 0 ] && pass "no temporary file left" || fail "$left temporary files left"
n=$(find "$work/out" -name '*_LOD*.ply' | wc -l)
[ "$n" -eq $((good * 5)) ] && pass "$n level files" || fail "$n level files, want $((good * 5))"
mapfile -t levels < <(find "$work/out" -name '*_LOD*.ply')
check_ply "${levels[@]}" || fail "a level file is partial after the restart"

# --- 2. a third run redoes nothing ------------------------------------------------------------------
"$tool" batch --threads 1 --format ply $superfaces_only "$work/manifest.txt" "$work/out" >"$work/run3.jsonl" 2>/dev/null
c=$(grep -c '"cached":true' "$work/run3.jsonl"); e=$(grep -c '"status":"error"' "$work/run3.jsonl")
[ "$c" -eq $good ] && [ "$e" -eq $bad ] && pass "third run: $c cached, $e errors again" ||
  fail "third run: $c cached (want $good), $e errors (want $bad)"

# --- 3. GNU parallel, local jobs and --sshloginfile (':' is this machine) -------------------------
same_files() { # DIR: every level file equal to the first run's
  local d=$1 diff=0 f
  while read -r f; do cmp -s "$work/out/$f" "$d/$f" || diff=$((diff + 1)); done < <(cd "$work/out" && find . -name '*_LOD*.ply')
  [ "$(find "$d" -name '*_LOD*.ply' | wc -l)" -eq $((good * 5)) ] && [ $diff -eq 0 ]
}
if command -v parallel >/dev/null; then
  parallel --will-cite -j 2 "$tool" batch --threads 1 --format ply $superfaces_only "$work/manifest.txt" "$work/par" --part {}/4 ::: 0 1 2 3 \
    >"$work/par.jsonl" 2>/dev/null
  lines=$(grep -c . "$work/par.jsonl"); uniq=$(grep -o '"line":[0-9]*' "$work/par.jsonl" | sort -u | wc -l)
  [ "$lines" -eq $((good + bad)) ] && [ "$uniq" -eq "$lines" ] && same_files "$work/par" &&
    pass "GNU parallel -j 2, 4 parts: every line once, the same files" ||
    fail "GNU parallel: $lines lines, $uniq distinct (want $((good + bad)))"
  printf '2/:\n' >"$work/sshlogins"
  parallel --will-cite --sshloginfile "$work/sshlogins" "$tool" batch --threads 1 --format ply $superfaces_only "$work/manifest.txt" \
    "$work/ssh" --part {}/3 ::: 0 1 2 >"$work/ssh.jsonl" 2>/dev/null
  lines=$(grep -c . "$work/ssh.jsonl")
  [ "$lines" -eq $((good + bad)) ] && same_files "$work/ssh" &&
    pass "GNU parallel --sshloginfile: every line once, the same files" || fail "--sshloginfile: $lines lines"
else
  fail "GNU parallel is not installed (Debian package parallel; cmake/setup.sh installs it)"
fi

# --- 4. the Slurm array script: task k of N takes the manifest's data lines i with i % N == k -----
: >"$work/slurm.jsonl"
for k in 0 1 2 3 4; do
  SLURM_ARRAY_TASK_ID=$((k + 10)) SLURM_ARRAY_TASK_MIN=10 SLURM_ARRAY_TASK_COUNT=5 GAUSSLOD=$tool \
    bash "$slurm" "$work/manifest.txt" "$work/slurm" --threads 1 --format ply $superfaces_only >"$work/slurm$k.jsonl" 2>/dev/null
  cat "$work/slurm$k.jsonl" >>"$work/slurm.jsonl"
done
python3 - "$work" <<'PY' && same_files "$work/slurm" && pass "Slurm array (ids 10..14): each task its lines, every line once" || fail "Slurm array mapping wrong"
import json, sys
work = sys.argv[1]
data = [l for l in open(f'{work}/manifest.txt') if l.strip() and not l.startswith('#')]
for k in range(5):
    lines = [json.loads(l)['line'] for l in open(f'{work}/slurm{k}.jsonl')]
    want = [i + 2 for i in range(len(data)) if i % 5 == k]  # manifest line numbers (a comment first)
    assert lines == want, (k, lines[:5], want[:5])
PY

# --- 5. levels by target: each level of a record is what `gausslod --json` prints for it -----------
# (levels_by, target_faces, target_error_pct, target_reached, tolerance_pct, trials and the rest)
mkdir -p "$work/tgt"
targets=("fandisk --levels-by faces:50%,25%" "cow --levels-by error:0.05%,0.2%" joint) # name options
: >"$work/tgt/manifest.txt"
for t in "${targets[@]}"; do
  read -r name opts <<<"$t"
  ln -s "$data/$name.off" "$work/tgt/$name.off"
  echo "$name.off $opts" >>"$work/tgt/manifest.txt"
  # shellcheck disable=SC2086 # (opts: several words)
  "$tool" --threads 1 --format ply --json $opts "$work/tgt/$name.off" "$work/tgt/single" \
    >"$work/tgt_$name.jsonl" 2>/dev/null || fail "$name --json: exit $?"
done
for run in 1 2; do
  "$tool" batch --threads 1 --format ply "$work/tgt/manifest.txt" "$work/tgt/out" >"$work/tgt$run.jsonl" 2>/dev/null ||
    fail "levels by target: batch run $run: exit $?"
done
if python3 - "$work" <<'PY'
import json, sys
work = sys.argv[1]
run1 = [json.loads(l) for l in open(f'{work}/tgt1.jsonl')]
run2 = [json.loads(l) for l in open(f'{work}/tgt2.jsonl')]
stored = [json.loads(open(f'{work}/tgt/out/{n}.gausslod.json').read()) for n in ('fandisk', 'cow', 'joint')]
assert [r['status'] for r in run1] == ['ok'] * 3, run1
assert [r['cached'] for r in run2] == [True] * 3, run2
target = ('levels_by', 'target_faces', 'target_error_pct', 'target_reached', 'tolerance_pct', 'trials')
timing = ('seconds', 'seconds_partition', 'seconds_borders', 'seconds_triangulation', 'seconds_checks',
          'seconds_placement', 'seconds_collapse', 'seconds_hausdorff')
for recs in (run1, run2, stored):
    fandisk, cow, joint = recs
    # faces:50%,25% of fandisk's 12946 faces: LOD1 6473, LOD0 3236, both reachable (test_cli_targets.sh)
    want = {1: 12946 * 50 // 100, 0: 12946 * 25 // 100}
    assert fandisk['faces'] == 12946 and [l['level'] for l in fandisk['levels']] == [1, 0], fandisk
    for l in fandisk['levels']:
        assert all(k in l for k in target), l
        assert l['levels_by'] == 'faces' and l['target_error_pct'] is None, l
        assert l['target_faces'] == want[l['level']] and l['target_reached'] is True, l
        assert 0 < l['faces'] <= l['target_faces'], l
        # (a superface level searched its tolerance; a level made by collapses after one that
        # was, DESIGN 51, builds none: 0 trials)
        assert (l['tolerance_pct'] > 0 and 1 <= l['trials'] <= 11) or \
            (l['reduced'] and l['trials'] == 0), l
    # error:0.05%,0.2% of the cow: LOD1 0.05 %, LOD0 0.2 %, each within its tolerance
    want = {1: 0.05, 0: 0.2}
    assert [l['level'] for l in cow['levels']] == [1, 0], cow
    for l in cow['levels']:
        assert all(k in l for k in target), l
        assert l['levels_by'] == 'error' and l['target_faces'] is None, l
        assert abs(l['target_error_pct'] - want[l['level']]) < 1e-9, l
        assert l['target_reached'] is True and l['trials'] in (0, 1), l
        assert 0 < min(l['distance_bound_pct'], l['hausdorff_pct']) <= l['target_error_pct'] + 1e-4, l
    # angle (the default): the target members are there, null
    assert len(joint['levels']) == 5, joint
    for l in joint['levels']:
        assert l['levels_by'] == 'angle' and l['target_faces'] is None and l['target_error_pct'] is None, l
    # the very members and values of the single-file --json lines (but times and file names)
    for rec, name in ((fandisk, 'fandisk'), (cow, 'cow'), (joint, 'joint')):
        single = [json.loads(l) for l in open(f'{work}/tgt_{name}.jsonl')]
        assert len(single) == len(rec['levels']), (name, single)
        for a, b in zip(rec['levels'], single):
            assert list(a) == list(b), (name, list(a), list(b))
            for k in a:
                assert k in timing or k == 'file' or a[k] == b[k], (name, a['level'], k, a[k], b[k])
print('levels by target: 3 inputs, records as the --json lines (printed, cached, stored)')
PY
then pass "levels by target: records carry the --json level members (targets, tolerance, trials)"
else fail "levels by target: batch records (above)"; fi

finish test_batch
