# Blender's Decimate modifier in "Planar" mode (limited dissolve), then Triangulate, headless:
#   blender -b -noaudio --factory-startup --python bench/blender_planar.py -- IN.ply OUT.ply ANGLE_DEG
# Prints one line "BENCH_JSON {...}" with the face count of the result and the in-process wall
# time of applying the two modifiers (import and export excluded).
import json
import math
import sys
import time

import bpy

argv = sys.argv[sys.argv.index("--") + 1:]
src, dst, angle = argv[0], argv[1], float(argv[2])

# Empty scene (factory startup has a cube, a camera and a light).
bpy.ops.object.select_all(action="SELECT")
bpy.ops.object.delete()

bpy.ops.import_mesh.ply(filepath=src)
obj = bpy.context.selected_objects[0]
bpy.context.view_layer.objects.active = obj
faces_in = len(obj.data.polygons)

dec = obj.modifiers.new("Decimate", "DECIMATE")
dec.decimate_type = "DISSOLVE"
dec.angle_limit = math.radians(angle)
dec.use_dissolve_boundaries = False
dec.delimit = {"NORMAL"}
tri = obj.modifiers.new("Triangulate", "TRIANGULATE")
tri.quad_method = "BEAUTY"
tri.ngon_method = "BEAUTY"
tri.min_vertices = 4

t0 = time.perf_counter()
bpy.ops.object.modifier_apply(modifier="Decimate")
t1 = time.perf_counter()
bpy.ops.object.modifier_apply(modifier="Triangulate")
t2 = time.perf_counter()

faces_out = len(obj.data.polygons)
non_tri = sum(1 for p in obj.data.polygons if len(p.vertices) != 3)
bpy.ops.export_mesh.ply(filepath=dst, use_selection=True, use_mesh_modifiers=False,
                        use_normals=False, use_uv_coords=False, use_colors=False)
print("BENCH_JSON " + json.dumps({
    "method": "blender_planar", "version": bpy.app.version_string, "angle_deg": angle,
    "faces_in": faces_in, "faces": faces_out, "non_triangles": non_tri,
    "seconds": t2 - t0, "dissolve_seconds": t1 - t0, "triangulate_seconds": t2 - t1,
    "file": dst}), flush=True)
