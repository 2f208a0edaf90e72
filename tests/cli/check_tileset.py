#!/usr/bin/env python3
"""A tileset written by gausslod --3dtiles against its levels' JSON lines (test_cli_gltf.sh):
    check_tileset.py OUTDIR LEVELS.jsonl [TILESET_NAME]
A chain of single children from the coarsest level (the root) to the input (the leaf, error 0),
refinement REPLACE, every content file present, errors never increasing down the chain, each
level's error at least its certified distance (a coarser level may carry a finer one's larger
figure; the JSON has 6 digits), the tileset's own error above the root's."""
import json, os, sys

d, levels = sys.argv[1], [json.loads(l) for l in open(sys.argv[2]) if '"level"' in l]
t = json.load(open(os.path.join(d, sys.argv[3] if len(sys.argv) > 3 else "tileset.json")))
assert t["asset"]["version"] == "1.1", t["asset"]
chain, tile = [], t["root"]
while True:
    chain.append(tile)
    assert tile["refine"] == "REPLACE", tile
    assert os.path.isfile(os.path.join(d, tile["content"]["uri"])), tile["content"]
    if "children" not in tile:
        break
    assert len(tile["children"]) == 1
    tile = tile["children"][0]
by_level = {l["level"]: l for l in levels}
names = [c["content"]["uri"] for c in chain]
assert len(chain) == len(levels) + 1, names
assert chain[-1]["geometricError"] == 0 and names[-1].endswith("_full.glb"), names
errs = [c["geometricError"] for c in chain]
assert all(a >= b for a, b in zip(errs, errs[1:])), errs
for c, lv in zip(chain, sorted(by_level)):
    assert c["content"]["uri"].endswith("_LOD%d.glb" % lv), (c["content"]["uri"], lv)
    h = by_level[lv]["hausdorff"]
    assert c["geometricError"] >= h * (1 - 1e-5), (c["geometricError"], h)
    finer = max(by_level[k]["hausdorff"] for k in by_level if k >= lv)
    assert c["geometricError"] <= finer * (1 + 1e-5), (c["geometricError"], finer)
assert t["geometricError"] >= errs[0]
print("tileset:", " ".join("%s %.3g" % (n, e) for n, e in zip(names, errs)))
