#!/usr/bin/env bash
# Where a user waits: a progress line on a terminal only (not with --quiet, not into a file), and
# Ctrl-C (SIGINT) stops the run with exit 130, the levels written so far complete and no
# temporary file left.
#   test_cli_interrupt.sh GAUSSLOD DATA OUT
. "$(dirname "${BASH_SOURCE[0]}")/common.sh"
g=$1 data=$2 out=$3
fresh_work "$out"
m=$data/armadillo.off

# progress: on a terminal (script(1) gives the tool one), not otherwise
script -qec "'$g' --threads 1 '$m' '$out/tty'" /dev/null >"$out/tty.txt" 2>&1
check 'grep -q "%  building level" "$out/tty.txt"' "a progress line on a terminal"
script -qec "'$g' --quiet --threads 1 '$m' '$out/quiet'" /dev/null >"$out/quiet.txt" 2>&1
check '! grep -q "%  building level" "$out/quiet.txt" && grep -q "^LOD0 " "$out/quiet.txt"' "--quiet: the table, no progress line"
"$g" --threads 1 "$m" "$out/file" >"$out/file.txt" 2>"$out/file.err"
check '! grep -q "%  " "$out/file.err" && [ ! -s "$out/file.err" ]' "into a file: no progress line"

# Ctrl-C at several moments: exit 130, every level file there reads back whole, no temporary
for t in 0.5 1.5 3; do
  o=$out/int_$t
  "$g" --threads 1 "$m" "$o" >"$o.txt" 2>"$o.err" &
  pid=$!
  sleep "$t"
  kill -INT "$pid" 2>/dev/null
  wait "$pid"
  rc=$?
  if [ $rc -eq 0 ]; then
    pass "Ctrl-C after $t s: the run had ended (exit 0)"
    continue
  fi
  check '[ $rc -eq 130 ] && grep -q "interrupted: .* no partial file left" "$o.err"' "Ctrl-C after $t s: exit 130 ($rc), said so"
  check '[ -z "$(find "$o" -name ".*" -type f 2>/dev/null)" ]' "Ctrl-C after $t s: no temporary file left"
  for f in "$o"/*_LOD*.off; do
    [ -e "$f" ] || continue
    check '"$g" --check "$f" >/dev/null 2>&1' "Ctrl-C after $t s: $(basename "$f") reads back whole"
  done
done
finish cli.interrupt
