#!/usr/bin/env bash
# The gausslod tool (and, on a sample, the meshlabserver runner) on every hostile file of the
# corpus: the exit code of the file's category, one line naming the file and the problem, no
# signal, no hang, no output left behind, never an empty "success".
# usage: test_cli_corpus.sh GAUSSLOD CORPUS_DIR WORK_DIR [RUNNER]
set -uo pipefail
tool=$1 corpus=$2 work=$3 runner=${4:-}
rm -rf "$work"; mkdir -p "$work"
failures=0 checked=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }

code_of() { # expected status and message -> the tool's exit code
  case $1 in
    cannot_open) echo 3 ;; empty | wrong_format | corrupt) echo 4 ;; too_large) echo 6 ;;
    ok) if [ -n "$2" ]; then echo 5; else echo 0; fi ;;
  esac
}
# (tabs are blanks to read: empty fields would collapse; split at a unit separator instead)
while IFS=$'\x1f' read -r file status fragment _; do
  want=$(code_of "$status" "$fragment")
  out=$work/out_$file
  timeout 30 "$tool" "$corpus/$file" "$out" >"$work/$file.stdout" 2>"$work/$file.stderr"
  rc=$?
  checked=$((checked + 1))
  if [ $rc -ge 124 ]; then
    fail "$file: exit $rc (a signal or the time limit)"; continue
  fi
  if [ "$rc" != "$want" ]; then
    fail "$file ($status): exit $rc, want $want: $(head -c 300 "$work/$file.stderr")"; continue
  fi
  if [ "$want" != 0 ]; then
    msg=$(cat "$work/$file.stderr")
    [ "$(printf '%s\n' "$msg" | wc -l)" -eq 1 ] || fail "$file: more than one line: $msg"
    case $msg in "gausslod: $corpus/$file: "?*) ;; *) fail "$file: the message does not name the file: $msg" ;; esac
    [ -z "$fragment" ] || grep -qF -- "$fragment" "$work/$file.stderr" || fail "$file: '$fragment' not in: $msg"
    [ ! -e "$out" ] || fail "$file: an error left $out"
    # --check gives the same code and message (but the memory available, which the message of a
    # file too large for it quotes and which moves between two runs, as other processes run)
    timeout 30 "$tool" --check "$corpus/$file" >/dev/null 2>"$work/$file.check"
    rc2=$?
    avail='s/only [0-9.]+ [MG]B is available/only (available) is available/'
    [ $rc2 -eq "$rc" ] && cmp -s <(sed -E "$avail" "$work/$file.check") <(sed -E "$avail" "$work/$file.stderr") ||
      fail "$file: --check exit $rc2 / message differ from the run's"
  else
    # (5 levels; an OBJ level comes with its material file <name>_LOD<i>.obj.mtl)
    n=$(ls "$out" 2>/dev/null | grep -vc '\.mtl$')
    [ "$n" -eq 5 ] || fail "$file: read fine but $n level files"
  fi
done < <(tr '\t' '\037' <"$corpus/expected.tsv")

# the runner checks its input with the tool: same codes, and meshlabserver never sees the file
if [ -n "$runner" ]; then
  for file in garbage.ply ply_1e9_vertices_binary.ply off_negative_index.off empty.obj; do
    [ -e "$corpus/$file" ] || { fail "runner sample $file is not in the corpus"; continue; }
    want=$(code_of "$(awk -F'\t' -v f="$file" '$1 == f { print $2 }' "$corpus/expected.tsv")")
    GAUSSLOD_TOOL=$tool timeout 60 "$runner" "$corpus/$file" "$work/runner_$file" >"$work/runner_$file.log" 2>&1
    rc=$?
    checked=$((checked + 1))
    [ $rc -eq "$want" ] && grep -q "$file" "$work/runner_$file.log" && ! grep -q meshlabserver "$work/runner_$file.log" ||
      fail "runner on $file: exit $rc (want $want): $(tail -3 "$work/runner_$file.log")"
  done
fi
echo "test_cli_corpus: $checked runs, $failures failure(s)"
[ $failures -eq 0 ]
