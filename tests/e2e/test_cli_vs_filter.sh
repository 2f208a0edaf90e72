#!/usr/bin/env bash
# The same levels from the gausslod tool as from the filter through meshlabserver, on files
# nobody here made (Debian's assimp-testmodels): an STL triangle soup (MeshLab welds STL vertices
# on import, the tool welds them itself) and its welded copy; an OBJ with n-gons.
# The tool writes its levels as PLY here (--format ply), as the runner saves the filter's.
# usage: test_cli_vs_filter.sh RUNNER GAUSSLOD ASSIMP_MODELS WORK_DIR   (GAUSSLOD_MESHLAB_PREFIX set)
. "$(dirname "${BASH_SOURCE[0]}")/../cli/common.sh"
runner=$1 tool=$2 models=$3 work=$4
fresh_work "$work"

# the triangles of two sets of PLY files, as coordinates, compared as multisets (the tool writes
# binary PLY, MeshLab its own layout; vertex and face order may differ)
same_levels() { python3 - "$@" <<'PY'
import struct, sys
def read(path):
    data = open(path, 'rb').read()
    end = data.index(b'end_header') + len(b'end_header')
    end = data.index(b'\n', end) + 1
    lines = data[:end].decode('latin-1').splitlines()
    fmt = [l.split()[1] for l in lines if l.startswith('format')][0]
    elems = []
    for l in lines:
        w = l.split()
        if w[:1] == ['element']: elems.append((w[1], int(w[2]), []))
        elif w[:1] == ['property']: elems[-1][2].append(w[1:])
    size = {'char': 'b', 'uchar': 'B', 'int8': 'b', 'uint8': 'B', 'short': 'h', 'ushort': 'H',
            'int16': 'h', 'uint16': 'H', 'int': 'i', 'uint': 'I', 'int32': 'i', 'uint32': 'I',
            'float': 'f', 'float32': 'f', 'double': 'd', 'float64': 'd'}
    pos, tokens = end, None
    if fmt == 'ascii':
        tokens = data[end:].split(); ti = 0
    V, F = [], []
    for name, n, props in elems:
        for _ in range(n):
            rec = {}
            for p in props:
                if p[0] == 'list':
                    if tokens is not None:
                        k = int(tokens[ti]); vals = [float(x) for x in tokens[ti + 1:ti + 1 + k]]; ti += 1 + k
                    else:
                        c = struct.calcsize('<' + size[p[1]]); k = struct.unpack_from('<' + size[p[1]], data, pos)[0]; pos += c
                        c = struct.calcsize('<' + size[p[2]]); vals = list(struct.unpack_from('<%d%s' % (k, size[p[2]]), data, pos)); pos += c * k
                    rec[p[3]] = vals
                else:
                    if tokens is not None:
                        v = float(tokens[ti]); ti += 1
                    else:
                        v = struct.unpack_from('<' + size[p[0]], data, pos)[0]; pos += struct.calcsize('<' + size[p[0]])
                    rec[p[1]] = v
            if name == 'vertex': V.append((rec['x'], rec['y'], rec['z']))
            elif name == 'face': F.append([int(i) for i in rec.get('vertex_indices', rec.get('vertex_index'))])
    tris = []
    for f in F:
        t = [V[i] for i in f]
        k = t.index(min(t))
        tris.append(tuple(t[k:] + t[:k]))
    return sorted(tris)
half = len(sys.argv) // 2
bad = 0
for a, b in zip(sys.argv[1:half + 1], sys.argv[half + 1:]):
    ta, tb = read(a), read(b)
    if ta != tb:
        print(f'differ: {a} ({len(ta)} triangles) vs {b} ({len(tb)})'); bad += 1
    else:
        print(f'same: {a} = {b} ({len(ta)} triangles)')
sys.exit(1 if bad else 0)
PY
}

compare() { # NAME INPUT: the tool and the runner on INPUT give the same levels
  local name=$1 input=$2 stem
  stem=$(basename "$input"); stem=${stem%.*}
  "$tool" --format ply "$input" "$work/cli_$name" >"$work/cli_$name.log" 2>&1 || { fail "$name: tool exit $?"; return; }
  "$runner" "$input" "$work/ml_$name" >"$work/ml_$name.log" 2>&1 || { fail "$name: runner exit $?: $(tail -5 "$work/ml_$name.log")"; return; }
  local a=() b=()
  for l in 4 3 2 1 0; do a+=("$work/cli_$name/${stem}_LOD$l.ply"); b+=("$work/ml_$name/${stem}_LOD$l.ply"); done
  same_levels "${a[@]}" "${b[@]}" && pass "$name: the tool's and the filter's levels are the same triangles" ||
    fail "$name: the tool's and the filter's levels differ"
}

stl=$models/STL/Wuson.stl
compare stl_soup "$stl"
# its welded copy: the STL as MeshLab opens it (vertices unified on import), saved as PLY
mkdir -p "$work/welded"
if XDG_CONFIG_HOME=$work XDG_RUNTIME_DIR=$work xvfb-run -a "$GAUSSLOD_MESHLAB_PREFIX/bin/meshlabserver" \
     -i "$stl" -o "$work/welded/Wuson.ply" >"$work/welded.log" 2>&1 &&
   [ -s "$work/welded/Wuson.ply" ]; then
  "$tool" --format ply "$work/welded/Wuson.ply" "$work/cli_welded" >/dev/null 2>&1 || fail "welded copy: tool exit $?"
  a=() b=()
  for l in 4 3 2 1 0; do a+=("$work/cli_stl_soup/Wuson_LOD$l.ply"); b+=("$work/cli_welded/Wuson_LOD$l.ply"); done
  same_levels "${a[@]}" "${b[@]}" && pass "STL soup and its welded copy (MeshLab's): the same levels" ||
    fail "STL soup and its welded copy give other levels"
else
  fail "meshlabserver could not save the welded copy: $(tail -5 "$work/welded.log")"
fi

# an OBJ with n-gons (a concave 66-gon; MeshLab opens OBJ through GaussLOD's OBJ plugin, and both
# split polygons with GLU's tessellator)
compare obj_ngons "$models/OBJ/concave_polygon.obj"

finish test_cli_vs_filter
