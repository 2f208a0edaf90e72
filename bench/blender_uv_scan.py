# A textured mesh as photogrammetry delivers scans, made by Blender, headless:
#   blender -b -noaudio --factory-startup --python bench/blender_uv_scan.py -- IN.ply OUT.obj [box]
# IN.ply is UV-unwrapped with Smart UV Project (many charts, one atlas), given one material with a
# 1024 x 1024 generated colour-grid texture (saved next to OUT.obj as a PNG), and written as an OBJ
# with its MTL. With "box" the input is ignored: a cube subdivided 4 times, its top and bottom
# faces given a second material, unwrapped the same way (a CAD-like textured part whose geometry
# needs 12 triangles). Prints one line "BENCH_JSON {...}".
import json
import os
import sys

import bpy

argv = sys.argv[sys.argv.index("--") + 1:]
src, dst = argv[0], argv[1]
box = len(argv) > 2 and argv[2] == "box"

bpy.ops.object.select_all(action="SELECT")
bpy.ops.object.delete()
if box:
    bpy.ops.mesh.primitive_cube_add(size=2)
    obj = bpy.context.active_object
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="SELECT")
    bpy.ops.mesh.subdivide(number_cuts=4)
    bpy.ops.object.mode_set(mode="OBJECT")
else:
    bpy.ops.import_mesh.ply(filepath=src)
    obj = bpy.context.selected_objects[0]
bpy.context.view_layer.objects.active = obj
obj.select_set(True)

stem = os.path.splitext(os.path.basename(dst))[0]
folder = os.path.dirname(os.path.abspath(dst))
materials = []
for i, grid in enumerate(["COLOR_GRID", "UV_GRID"][: 2 if box else 1]):
    img = bpy.data.images.new("%s_tex%d" % (stem, i), 1024, 1024)
    img.generated_type = grid
    img.filepath_raw = os.path.join(folder, "%s_tex%d.png" % (stem, i))
    img.file_format = "PNG"
    img.save()
    mat = bpy.data.materials.new("%s_mat%d" % (stem, i))
    mat.use_nodes = True
    tex = mat.node_tree.nodes.new("ShaderNodeTexImage")
    tex.image = img
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    mat.node_tree.links.new(tex.outputs["Color"], bsdf.inputs["Base Color"])
    obj.data.materials.append(mat)
    materials.append(mat)
if box:  # top and bottom faces: the second material
    for p in obj.data.polygons:
        if abs(p.normal.z) > 0.9:
            p.material_index = 1

bpy.ops.object.mode_set(mode="EDIT")
bpy.ops.mesh.select_all(action="SELECT")
bpy.ops.uv.smart_project(angle_limit=1.15192, island_margin=0.002)
bpy.ops.mesh.quads_convert_to_tris()
bpy.ops.object.mode_set(mode="OBJECT")

bpy.ops.wm.obj_export(filepath=dst, export_selected_objects=True, export_uv=True,
                      export_normals=False, export_materials=True, path_mode="RELATIVE",
                      export_triangulated_mesh=True)
print("BENCH_JSON " + json.dumps({
    "faces": len(obj.data.polygons), "vertices": len(obj.data.vertices),
    "uv_charts_hint": "smart_project", "file": dst}), flush=True)
