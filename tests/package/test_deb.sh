#!/usr/bin/env bash
# The Debian package: cpack -G DEB builds it from the build tree; its file list and its
# dependency on exactly the installed meshlab are checked, and Debian's meshlabserver, given the
# package's plugins where the package puts them (unpacked under WORK_DIR/root, no system change),
# opens OBJ_FILE.
# usage: test_deb.sh BUILD_DIR WORK_DIR OBJ_FILE
set -euo pipefail
build=$1 work=$2 obj=$3
rm -rf "$work"; mkdir -p "$work"
(cd "$work" && cpack --config "$build/CPackConfig.cmake" -G DEB >cpack.log 2>&1) ||
  { cat "$work/cpack.log"; echo "FAIL: cpack failed"; exit 1; }
deb=$(ls "$work"/*.deb)
echo "built $deb"
dpkg-deb -c "$deb" | awk '{print $6}' | tee "$work/files.txt"
failures=0
for f in ./usr/lib/x86_64-linux-gnu/meshlab/plugins/libfilter_gausslod.so \
         ./usr/lib/x86_64-linux-gnu/meshlab/plugins/libgausslod_io_obj.so ./usr/bin/gausslod \
         ./usr/share/gausslod/gausslod_default.mlx ./usr/share/gausslod/gausslod_cad.mlx \
         ./usr/share/gausslod/gausslod_paper.mlx ./usr/share/gausslod/gausslod_game.mlx \
         ./usr/share/gausslod/gausslod_budget.mlx \
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
# the installed layout: /usr/bin/meshlabserver finds its plugins in ../lib/<multiarch>/meshlab
root=$work/root lib=$work/root/usr/lib/x86_64-linux-gnu/meshlab
dpkg-deb -x "$deb" "$root"
cp /usr/bin/meshlabserver "$root/usr/bin/"
ln -s /usr/lib/x86_64-linux-gnu/meshlab/libmeshlab-common.so "$lib/"
for p in /usr/lib/x86_64-linux-gnu/meshlab/plugins/*.so; do
  [ -e "$lib/plugins/$(basename "$p")" ] || ln -s "$p" "$lib/plugins/"
done
mkdir -p "$work/config" "$work/runtime"; chmod 700 "$work/runtime"
XDG_CONFIG_HOME=$work/config XDG_RUNTIME_DIR=$work/runtime timeout 120 \
  xvfb-run -a "$root/usr/bin/meshlabserver" -i "$obj" -o "$work/obj.ply" -m wt >"$work/obj.log" 2>&1 ||
  true
faces=$(grep -c '^f ' "$obj")
if grep -q "loaded has [0-9]* vn $faces fn" "$work/obj.log" && grep -q "comment TextureFile" "$work/obj.ply"
then
  echo "ok: with the package's plugins meshlabserver opens $(basename "$obj") ($faces faces, textured)"
else
  tail -n 5 "$work/obj.log"; echo "FAIL: meshlabserver with the package's plugins cannot open $obj"
  failures=$((failures + 1))
fi
[ $failures -eq 0 ] && echo "all checks passed"
exit $failures
