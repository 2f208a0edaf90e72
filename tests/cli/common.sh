# The preamble of the shell tests in tests/cli and tests/e2e, sourced first thing:
#   . "$(dirname "${BASH_SOURCE[0]}")/common.sh"          (tests/e2e: ../cli/common.sh)
# Strict pipes and unset names, pass/fail/check counting the failures, a fresh work folder, and
# the last line (finish) that makes the count the test's exit status.
set -uo pipefail
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }
pass() { echo "ok: $*"; }
# check 'CONDITION' TEXT: passes TEXT if CONDITION (shell code, evaluated here) holds, else fails it
check() { if eval "$1"; then pass "$2"; else fail "$2"; fi; }
# fresh_work DIR [SUB...]: DIR removed and made again, empty but for the folders DIR/SUB
fresh_work() {
  local dir=$1 sub; shift
  rm -rf "$dir"; mkdir -p "$dir"
  for sub in "$@"; do mkdir -p "$dir/$sub"; done
}
# ply_faces FILE: the face count in a PLY file's header
ply_faces() { LC_ALL=C awk '$1 == "element" && $2 == "face" { print $3; exit }' "$1"; }
# finish NAME: says how many checks failed; its status (the test's, as its last line) is 0 if none
finish() { echo "$1: $failures failure(s)"; [ "$failures" -eq 0 ]; }
