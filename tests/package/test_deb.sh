#!/usr/bin/env bash
# The Debian package: cpack -G DEB builds it from the build tree; its file list and its
# dependency on exactly the installed meshlab are checked.
# usage: test_deb.sh BUILD_DIR WORK_DIR
set -euo pipefail
build=$1 work=$2
rm -rf "$work"; mkdir -p "$work"
(cd "$work" && cpack --config "$build/CPackConfig.cmake" -G DEB >cpack.log 2>&1) ||
  { cat "$work/cpack.log"; echo "FAIL: cpack failed"; exit 1; }
deb=$(ls "$work"/*.deb)
echo "built $deb"
dpkg-deb -c "$deb" | awk '{print $6}' | tee "$work/files.txt"
failures=0
for f in ./usr/lib/x86_64-linux-gnu/meshlab/plugins/libfilter_gausslod.so ./usr/bin/gausslod \
         ./usr/share/gausslod/gausslod_default.mlx ./usr/share/gausslod/gausslod_cad.mlx \
         ./usr/share/gausslod/gausslod_paper.mlx ./usr/share/gausslod/gausslod_game.mlx \
         ./usr/share/gausslod/run_gausslod.sh; do
  grep -qx "$f" "$work/files.txt" || { echo "FAIL: $f not in the package"; failures=$((failures + 1)); }
done
depends=$(dpkg-deb -f "$deb" Depends)
echo "Depends: $depends"
want="meshlab (= $(dpkg-query -W -f='${Version}' meshlab))"
case "$depends" in
  *"$want"*) echo "ok: depends on $want" ;;
  *) echo "FAIL: Depends lacks '$want'"; failures=$((failures + 1)) ;;
esac
# nothing outside /usr
if grep -v '^\./usr/\|^\./$' "$work/files.txt"; then echo "FAIL: files outside /usr"; failures=$((failures + 1)); fi
[ $failures -eq 0 ] && echo "all checks passed"
exit $failures
