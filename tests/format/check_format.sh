#!/usr/bin/env bash
# Every C++ file of the repository as .clang-format writes it (issue 38): clang-format --dry-run
# -Werror on the tracked .cpp and .h files; names the files that differ.
set -uo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
cf=${CLANG_FORMAT:-clang-format}
command -v "$cf" >/dev/null || { echo "FAIL: $cf not found (cmake/setup.sh installs clang-format)"; exit 1; }
cd "$root"
mapfile -t files < <(git ls-files '*.cpp' '*.h' 2>/dev/null || find vcg_core io tools plugin tests bench -name '*.cpp' -o -name '*.h')
[ ${#files[@]} -gt 20 ] || { echo "FAIL: only ${#files[@]} C++ files found"; exit 1; }
bad=()
for f in "${files[@]}"; do
  "$cf" --dry-run -Werror "$f" >/dev/null 2>&1 || bad+=("$f")
done
if [ ${#bad[@]} -eq 0 ]; then
  echo "ok: ${#files[@]} C++ files as .clang-format writes them"
else
  echo "FAIL: ${#bad[@]} of ${#files[@]} files differ from clang-format's output (clang-format -i them):"
  printf '  %s\n' "${bad[@]}"
  exit 1
fi
