#!/usr/bin/env bash
# The real MeshLab GUI (private prefix with the built plugin) on its own Xvfb display:
#   1. opens cow.off;
#   2. Filters > Remeshing, Simplification and Reconstruction > our filter, with the keyboard
#      (fails if the entry is not there: the dialog that opens must carry the filter's name);
#   3. Apply with the default parameters (a click on the dialog's Apply button);
#   4. File > Save Project: MeshLab asks for a file for every new layer, in layer order, in a dialog
#      titled 'Save "<layer label>" Layer'; the test answers each one, then saves the .mlp project;
#   5. checks one layer per level (labels, order, saved PLY face counts, project file) and the log;
#   6. File > Import Mesh of a real textured OBJ (our OBJ plugin: Debian's own aborts on it), the
#      filter again on it (Filters > Apply filter: its dialog, Apply), one layer per level;
#   7. leaves screenshots (import -window root) in OUT_DIR (the dialog: 2b_dialog.png, the OBJ:
#      5_obj_loaded.png, its levels: 6_obj_levels.png).
# usage: test_gui_filter.sh MESHLAB_PREFIX MENU_INDEX_TOOL DATA_DIR OUT_DIR OBJ_FILE
set -uo pipefail

prefix=$1 menu_index=$2 data=$3 out=$4 obj=$5
filter="Gauss Sphere LOD: Merge Near-Coplanar Faces"
levels=(4 3 2 1 0) # default maxLevel 5, finest first = layer order
plugdir=$prefix/lib/x86_64-linux-gnu/meshlab/plugins

rm -rf "$out"; mkdir -p "$out/config" "$out/runtime" "$out/saved"; chmod 700 "$out/runtime"
export XDG_CONFIG_HOME=$out/config XDG_RUNTIME_DIR=$out/runtime
unset WAYLAND_DISPLAY
xvfb_pid= meshlab_pid=
cleanup() {
  [ -n "$meshlab_pid" ] && kill "$meshlab_pid" 2>/dev/null && wait "$meshlab_pid" 2>/dev/null
  [ -n "$xvfb_pid" ] && kill "$xvfb_pid" 2>/dev/null && wait "$xvfb_pid" 2>/dev/null
}
trap cleanup EXIT

die() {
  echo "FAIL: $*" >&2
  [ -n "${DISPLAY:-}" ] && import -window root "$out/failure.png" 2>/dev/null &&
    echo "screenshot of the failure: $out/failure.png" >&2
  if [ -s "$out/meshlab.stderr" ]; then
    echo "---- meshlab stderr (last 15 lines) ----" >&2; tail -n 15 "$out/meshlab.stderr" >&2
  fi
  exit 1
}
step() { echo "[$((SECONDS))s] $*"; }

for tool in Xvfb xdotool import; do
  command -v $tool >/dev/null || die "$tool not found (Debian packages xvfb, xdotool, imagemagick)"
done
[ -x "$prefix/bin/meshlab" ] || die "no $prefix/bin/meshlab: build the meshlab_prefix target"

# wait_for SECONDS COMMAND...: polls COMMAND every 0.1 s until it succeeds
wait_for() {
  local limit=$1; shift
  local end=$((SECONDS + limit))
  until "$@" 2>/dev/null; do
    [ $SECONDS -lt $end ] || return 1
    sleep 0.1
  done
}
window() { xdotool search --onlyvisible --name "$1" 2>/dev/null | head -n1 | grep .; }
window_id() { wait_for "$2" window "$1" >/dev/null && window "$1"; }
logged() { grep -qF -- "$1" "$out/meshlab.stderr"; }
# focus a window and type into it (there is no window manager to give modal dialogs the focus)
type_into() { xdotool windowfocus --sync "$1" && xdotool type --delay 5 "$2"; }
key_into() { xdotool windowfocus --sync "$1" && xdotool key "$2"; }

# ---- 1. X server and MeshLab ---------------------------------------------------------------------
step "starting Xvfb"
exec 3>"$out/xvfb.display"
Xvfb -displayfd 3 -screen 0 1280x1400x24 -nolisten tcp >"$out/xvfb.log" 2>&1 &
xvfb_pid=$!
exec 3>&-
wait_for 10 grep -q '[0-9]' "$out/xvfb.display" || die "Xvfb did not start ($(cat "$out/xvfb.log"))"
export DISPLAY=:$(tr -d '\n' <"$out/xvfb.display")

step "starting $prefix/bin/meshlab cow.off on $DISPLAY"
"$prefix/bin/meshlab" "$data/cow.off" >"$out/meshlab.stdout" 2>"$out/meshlab.stderr" &
meshlab_pid=$!
main=$(window_id '^MeshLab 20[0-9.]* - ' 60) || die "the MeshLab main window did not appear"
wait_for 60 logged "All files opened" || die "MeshLab did not open cow.off"
kill -0 $meshlab_pid || die "MeshLab exited"
# no window manager: size the main window ourselves (Qt may still be settling its first geometry)
resized() {
  xdotool windowsize "$main" 1280 1000 && sleep 0.2 &&
    xdotool getwindowgeometry "$main" | grep -q 'Geometry: 1280x1000'
}
wait_for 10 resized || echo "warning: could not resize the MeshLab window"
sleep 0.5 # let a frame render
import -window root "$out/1_cow_loaded.png"

# ---- 2. the menu ---------------------------------------------------------------------------------
index=$("$menu_index" "$plugdir" "$filter" 2>"$out/menu_index.log") ||
  die "'$filter' is not in Filters > Remeshing, Simplification and Reconstruction:" \
      "$(grep menu_index: "$out/menu_index.log")"
step "opening Filters > Remeshing, Simplification and Reconstruction > entry $index"
# Alt+L opens "Fi&lters" on its first enabled entry ("Show current filter script"); the fourth
# entry below it is the Remeshing submenu; Right opens it on its first entry.
keys=(Down Down Down Down Right)
for ((i = 0; i < index; i++)); do keys+=(Down); done
dialog=
for attempt in 1 2; do
  key_into "$main" alt+l
  sleep 0.3
  xdotool key --delay 60 "${keys[@]}"
  sleep 0.3
  import -window root "$out/2_menu.png"
  xdotool key Return
  dialog=$(window_id "^$filter\$" 15) && break
  opened=$(xdotool search --onlyvisible --name . getwindowname %@ 2>/dev/null | tr '\n' ';')
  echo "attempt $attempt: the menu entry did not open the '$filter' dialog (windows: $opened)"
  xdotool key Escape Escape Escape
done
[ -n "$dialog" ] || die "Filters > Remeshing, Simplification and Reconstruction > entry $index" \
  "did not open the '$filter' dialog"

# ---- 3. Apply with the defaults ------------------------------------------------------------------
step "filter dialog open; clicking Apply"
sleep 0.3 # let the dialog lay itself out
import -window root "$out/2b_dialog.png"
eval "$(xdotool getwindowgeometry --shell "$dialog")"
# the dialog ends with two rows of buttons: Default|Help, Close|Apply (Apply = bottom right)
xdotool mousemove --window "$dialog" $((WIDTH * 3 / 4)) $((HEIGHT - 23)) click 1
wait_for 60 logged "Applied filter $filter" || {
  logged "GaussLOD failed" && die "the filter failed: $(grep 'GaussLOD failed' "$out/meshlab.stderr")"
  die "the filter was not applied within 60 s"
}
step "filter applied; closing the dialog"
eval "$(xdotool getwindowgeometry --shell "$dialog")"
xdotool mousemove --window "$dialog" $((WIDTH / 4)) $((HEIGHT - 23)) click 1 # Close
wait_for 10 eval '! window "^$filter\$"' || echo "warning: the filter dialog did not close"
sleep 0.5
import -window root "$out/3_after_filter.png"
# cosmetic: Ctrl+click on the eye of the last layer row (LOD0) shows that layer alone; the position
# holds for the 1280x1000 main window set above
if xdotool getwindowgeometry "$main" | grep -q 'Geometry: 1280x1000'; then
  xdotool mousemove --window "$main" 849 268 keydown ctrl click 1 keyup ctrl
  sleep 0.7
  import -window root "$out/3b_coarsest_level_only.png"
fi

# ---- 4. save every layer through MeshLab's own project saving ------------------------------------
key_into "$main" ctrl+s
labels=()
for i in "${!levels[@]}"; do
  save=$(window_id '^Save ".*" Layer$' 15) || die "no save dialog for layer $((i + 1))"
  title=$(xdotool getwindowname "$save")
  label=${title#Save \"}; label=${label%\" Layer}
  labels+=("$label")
  type_into "$save" "$out/saved/layer$((i + 1)).ply" && xdotool key Return
  options=$(window_id '^Choose Saving Options' 15) || die "no saving options dialog for '$label'"
  key_into "$options" Return
  wait_for 15 test -s "$out/saved/layer$((i + 1)).ply" || die "layer '$label' was not saved"
  wait_for 15 eval '! window "^Choose Saving Options"' || die "saving options dialog did not close"
done
project=$(window_id '^Save Project File$' 15) || die "no project save dialog after ${#levels[@]} layers"
type_into "$project" "$out/saved/project.mlp" && xdotool key Return
wait_for 15 grep -q '</MeshLabProject>' "$out/saved/project.mlp" || die "project not saved"
! window '^Save ".*" Layer$' >/dev/null || die "MeshLab asks to save more layers than levels"
import -window root "$out/4_saved.png"
step "project saved"

# ---- 5. checks -----------------------------------------------------------------------------------
failures=0
check() { if eval "$1"; then echo "ok: $2"; else echo "FAIL: $2" >&2; failures=$((failures + 1)); fi; }
ply_faces() {
  LC_ALL=C awk '$1 == "element" && $2 == "face" { print $3 } $1 == "end_header" { exit }' "$1"
}
bound() { awk -v l="$1" 'BEGIN { printf "%.3g", sqrt(2) * 90 / 3 ^ l }'; }

mlp=$out/saved/project.mlp
check '[ "$(grep -c "<MLMesh " "$mlp")" -eq $((1 + ${#levels[@]})) ]' \
  "project has the input + ${#levels[@]} layers"
check 'grep -q "<MLMesh [^>]*label=\"cow.off\"" "$mlp"' "the input layer is still there"
prev=
for i in "${!levels[@]}"; do
  level=${levels[$i]} label=${labels[$i]} file=$out/saved/layer$((i + 1)).ply
  faces=$(ply_faces "$file")
  echo "layer $((i + 1)): '$label', saved with $faces faces"
  # (the default distance tolerance is on: the label ends with the level's distance bound; a
  # level continued by collapses to a real step, DESIGN 51, names no angle)
  re="^cow LOD$level \\(([0-9,]+) f(, <=$(bound "$level" | sed 's/\./\\./') deg)?, <=[0-9.e-]+ %\\)\$"
  check '[[ $label =~ $re ]]' "layer $((i + 1)) is LOD$level: '$label'"
  check '[ "${BASH_REMATCH[1]//,/}" = "$faces" ]' "LOD$level label face count = saved faces ($faces)"
  xml_label=$(printf '%s' "$label" | sed 's/</\&lt;/g')
  check 'grep -qF "label=\"$xml_label\"" "$mlp"' "LOD$level in the project file"
  check '[ -z "$prev" ] || [ "$faces" -le "$prev" ]' "LOD$level has no more faces than the finer level"
  check 'logged "LOD$level (" ' "the log has a line for LOD$level"
  prev=$faces
done
check 'logged "${#levels[@]} layer(s) added"' "the log reports ${#levels[@]} layers added"
check '! logged "GaussLOD failed"' "no filter error in the log"
check 'kill -0 $meshlab_pid' "MeshLab is still running"

# ---- 6. a textured OBJ through File > Import Mesh, and the filter on it --------------------------
obj_name=$(basename "$obj" .obj)
step "File > Import Mesh $obj"
opened_before=$(grep -c "All files opened" "$out/meshlab.stderr")
key_into "$main" ctrl+i
import_dialog=$(window_id '^Import Mesh$' 15) || die "no Import Mesh dialog"
type_into "$import_dialog" "$obj" && xdotool key Return
imported_or_gone() {
  [ "$(grep -c "All files opened" "$out/meshlab.stderr")" -gt $opened_before ] || ! kill -0 $meshlab_pid
}
wait_for 60 imported_or_gone || die "MeshLab did not import $obj"
kill -0 $meshlab_pid || die "MeshLab exited importing $obj (Debian's OBJ importer aborts)"
sleep 0.7
import -window root "$out/5_obj_loaded.png"
applied_before=$(grep -c "Applied filter $filter" "$out/meshlab.stderr")
key_into "$main" ctrl+p # Filters > Apply filter: the last filter's dialog, on the current layer
dialog=$(window_id "^$filter\$" 15) || die "Filters > Apply filter did not open the dialog"
sleep 0.3
eval "$(xdotool getwindowgeometry --shell "$dialog")"
xdotool mousemove --window "$dialog" $((WIDTH * 3 / 4)) $((HEIGHT - 23)) click 1
wait_for 60 eval '[ "$(grep -c "Applied filter $filter" "$out/meshlab.stderr")" -gt $applied_before ]' ||
  die "the filter was not applied to $obj_name within 60 s"
eval "$(xdotool getwindowgeometry --shell "$dialog")"
xdotool mousemove --window "$dialog" $((WIDTH / 4)) $((HEIGHT - 23)) click 1 # Close
sleep 0.7
import -window root "$out/6_obj_levels.png"
check 'logged "Opened mesh $obj"' "the log says $obj_name.obj was opened"
check '! logged "Failure of loading texture"' "every texture of $obj_name.obj was found"
check '[ "$(grep -c "layer(s) added" "$out/meshlab.stderr")" -eq 2 ]' \
  "the filter added the levels of $obj_name too"
check '! logged "GaussLOD failed"' "no filter error on $obj_name"
check 'kill -0 $meshlab_pid' "MeshLab is still running"

[ $failures -eq 0 ] || die "$failures check(s) failed"
step "all checks passed; screenshots in $out"
