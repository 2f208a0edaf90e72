#!/usr/bin/env python3
"""Writes hostile mesh files (each small) into OUTDIR and OUTDIR/expected.tsv:
file <TAB> expected status <TAB> fragment the message must contain [<TAB> faces after reading].
Status "ok" means importMesh reads the file; the fragment is then one the engine's error must
contain ("" = the engine builds levels), and the optional face count is checked after flatten.
Also links the broken-importer files Debian's assimp-testmodels ships, when installed.
Usage: make_corpus.py OUTDIR [ASSIMP_MODELS_DIR]"""
import os
import random
import shutil
import struct
import sys

out = sys.argv[1]
assimp = sys.argv[2] if len(sys.argv) > 2 else "/usr/share/assimp/models"
if os.path.isdir(out):
    shutil.rmtree(out)
os.makedirs(out)
rows = []


def add(name, data, status, fragment, faces=None):
    if data is not None:
        with open(os.path.join(out, name), "wb") as f:
            f.write(data if isinstance(data, bytes) else data.encode())
    rows.append((name, status, fragment, "" if faces is None else str(faces)))


SQUARE = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
TRIS = [(0, 1, 2), (0, 2, 3)]
# a closed tetrahedron: the engine builds levels from it
TET_V = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
TET_F = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]


def ply_ascii(verts, faces, nv=None, nf=None, fmt="{:.6f}"):
    h = "ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\n" \
        "property float z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n"
    s = h.format(len(verts) if nv is None else nv, len(faces) if nf is None else nf)
    s += "".join(" ".join(fmt.format(c) for c in v) + "\n" for v in verts)
    s += "".join(" ".join(str(x) for x in [len(f)] + list(f)) + "\n" for f in faces)
    return s.encode()


def ply_binary(verts, faces, nv=None, nf=None, count="uchar", index="int"):
    h = ("ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\n"
         "property float y\nproperty float z\nelement face {}\nproperty list {} {} vertex_indices\n"
         "end_header\n").format(len(verts) if nv is None else nv,
                                len(faces) if nf is None else nf, count, index)
    b = h.encode()
    for v in verts:
        b += struct.pack("<3f", *v)
    cf = {"uchar": "<B", "int": "<i", "ushort": "<H"}[count]
    xf = {"int": "<i", "uint": "<I"}[index]
    for f in faces:
        b += struct.pack(cf, len(f)) + b"".join(struct.pack(xf, x) for x in f)
    return b


def off(verts, faces, nv=None, nf=None, head="OFF"):
    s = "{}\n{} {} 0\n".format(head, len(verts) if nv is None else nv,
                               len(faces) if nf is None else nf)
    s += "".join(" ".join(str(c) for c in v) + "\n" for v in verts)
    s += "".join(" ".join(str(x) for x in [len(f)] + list(f)) + "\n" for f in faces)
    return s


def obj(verts, faces):
    return "".join("v {} {} {}\n".format(*v) for v in verts) + \
        "".join("f " + " ".join(str(x) for x in f) + "\n" for f in faces)


def stl_binary(tris, count=None):
    b = b"binary stl".ljust(80, b" ") + struct.pack("<I", len(tris) if count is None else count)
    for t in tris:
        b += struct.pack("<3f", 0, 0, 1) + b"".join(struct.pack("<3f", *p) for p in t) + b"\0\0"
    return b


def stl_ascii(tris):
    s = "solid test\n"
    for t in tris:
        s += "facet normal 0 0 1\n outer loop\n"
        s += "".join("  vertex {} {} {}\n".format(*p) for p in t)
        s += " endloop\nendfacet\n"
    return s + "endsolid test\n"


SOUP = [[TET_V[i] for i in f] for f in TET_F]

# ---- valid files: the guards must let them through --------------------------------------------
add("valid_ascii.ply", ply_ascii(TET_V, TET_F), "ok", "", 4)
add("valid_binary.ply", ply_binary(TET_V, TET_F), "ok", "", 4)
add("valid_binary_int_count.ply", ply_binary(TET_V, TET_F, count="int"), "ok", "", 4)
add("valid_quads.ply", ply_ascii(SQUARE, [(0, 1, 2, 3)]), "ok", "", 2)
add("valid.off", off(TET_V, TET_F), "ok", "", 4)
add("valid_blank_lines.off", "OFF\n \t\n4 4 0\n\t \r\n" + off(TET_V, TET_F)[10:], "ok", "", 4)
add("valid_coff.off", "COFF\n4 4 0\n" + "".join(
    "{} {} {} 255 0 0 255\n".format(*v) for v in TET_V) +
    "".join("3 {} {} {}\n".format(*f) for f in TET_F), "ok", "", 4)
add("valid.obj", obj(TET_V, [tuple(i + 1 for i in f) for f in TET_F]), "ok", "", 4)
# VCG 2020.09 drops faces using vertex 1: the guard rebuilds them
add("valid_vertex1_ngon.obj", obj(SQUARE, [(1, 2, 3, 4)]) + "f -4 -2 -1\n", "ok", "", 3)
add("valid_slashes.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 3//1\n",
    "ok", "", 1)
add("valid_binary.stl", stl_binary(SOUP), "ok", "", 4)
add("valid_ascii.stl", stl_ascii(SOUP), "ok", "", 4)

# ---- lying counts -----------------------------------------------------------------------------
add("ply_1e9_vertices_ascii.ply", ply_ascii(SQUARE, TRIS, nv=1000000000), "corrupt",
    "the header announces 1000000000 vertices and 2 faces but the file has only")
add("ply_1e9_vertices_binary.ply", ply_binary(SQUARE, TRIS, nv=1000000000), "corrupt",
    "the header announces 1000000000 vertices and 2 faces but the file has only")
add("ply_1e9_faces_binary.ply", ply_binary(SQUARE, TRIS, nf=1000000000), "corrupt",
    "the header announces 4 vertices and 1000000000 faces")
add("off_1e9_vertices.off", off(SQUARE, TRIS, nv=1000000000), "corrupt",
    "the header announces 1000000000 vertices and 2 faces but the file has only")
add("stl_1e9_triangles.stl", stl_binary(SOUP, count=1000000000), "corrupt",
    "the header announces 1000000000 triangles")
# a sparse file big enough for its header (24 GB of zeros, no disk used): memory is the limit
name = "ply_sparse_2e9_vertices.ply"
with open(os.path.join(out, name), "wb") as f:
    f.write(ply_binary([], [], nv=2000000000, nf=0))
    f.truncate(f.tell() + 12 * 2000000000)
add(name, None, "too_large", "of memory but only")

# ---- truncated --------------------------------------------------------------------------------
add("ply_truncated_binary.ply", ply_binary(TET_V, TET_F)[:-7], "corrupt",
    "truncated: the file ends in PLY face 3")
add("ply_truncated_ascii.ply", ply_ascii(TET_V, TET_F, fmt="{:.12f}")[:-12], "corrupt",
    "truncated")
add("stl_truncated_binary.stl", stl_binary(SOUP)[:-10], "corrupt",
    "the header announces 4 triangles")
add("stl_truncated_ascii.stl", stl_ascii(SOUP)[:-60], "corrupt", "truncated")
add("stl_no_line_break.stl", "solid nothing but a name", "corrupt", "endsolid")
add("off_truncated.off", off([(0.123456789, 0.123456789, 0.123456789)] * 4, TET_F)[:-20],
    "corrupt", "truncated")
add("obj_truncated.obj", obj(TET_V, [])[:-3], "corrupt", "fewer than 3 coordinates")

# ---- garbage with each extension --------------------------------------------------------------
rnd = random.Random(1234)
junk = bytes([0]) + bytes(rnd.getrandbits(8) for _ in range(1999))
add("garbage.ply", junk, "corrupt", "no PLY header")
add("garbage.obj", junk, "corrupt", "binary data (NUL bytes)")
add("garbage.off", junk, "corrupt", "binary data (NUL bytes)")
add("garbage.stl", junk, "corrupt", "triangles but the file has 2000 bytes")
add("garbage_tiny.stl", "hello", "corrupt", "too short for a binary STL")
add("text_garbage.off", "this is not a mesh\n", "corrupt", "no OFF header")

# ---- indices ----------------------------------------------------------------------------------
add("off_negative_index.off", off(SQUARE, [(0, -1, 2)]), "corrupt",
    "face 0 uses vertex index '-1', outside 0..3")
add("off_index_out_of_range.off", off(SQUARE, [(0, 1, 2), (0, 2, 7)]), "corrupt",
    "face 1 uses vertex index '7'")
add("off_ngon_bad_index.off", off(SQUARE, [(0, 1, 2, 3, 99)]), "corrupt",
    "uses vertex index '99'")
add("off_huge_vertex_count_face.off", off(SQUARE, [])[:-1].replace("4 0 0", "4 1 0") +
    "\n2000000000 0 1 2\n", "corrupt", "truncated: the file ends in face 0 of 1")
add("off_colormap_index.off", off(SQUARE, [(0, 1, 2)])[:-1] + " 9999\n", "corrupt",
    "colour-map index")
add("off_bad_counts.off", "OFF\nabc 1 0\n0 0 0\n", "corrupt", "bad OFF counts")
add("off_ndim.off", "nOFF\n3\n1 0 0\n0 0 0\n", "corrupt", "n-dimensional")
add("off_bad_number.off", off([(0, 0, 0), (1, "x1", 0), (0, 1, 0)], [(0, 1, 2)]), "corrupt",
    "'x1' is not a number")
add("obj_negative_index.obj", obj(SQUARE[:3], [(-9, 1, 2)]), "corrupt",
    "face uses vertex '-9' but 3 vertices")
add("obj_out_of_range.obj", obj(SQUARE[:3], [(1, 2, 9)]), "corrupt", "face uses vertex '9'")
add("obj_ngon_bad_index.obj", obj(SQUARE, [(1, 2, 3, 4, 99)]), "corrupt",
    "face uses vertex '99'")
add("obj_zero_index.obj", obj(SQUARE[:3], [(0, 1, 2)]), "corrupt", "face uses vertex '0'")
add("obj_forward_reference.obj", "v 0 0 0\nf 1 2 3\nv 1 0 0\nv 0 1 0\n", "corrupt",
    "face uses vertex '2' but 1 vertices")
add("obj_bad_normal_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//5 2//5 3//5\n", "corrupt",
    "face uses normal '5'")
add("obj_empty_texture_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
    "f 1/ 2/ 3/\n", "corrupt", "face uses texture ''")
add("obj_empty_normal_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn 0 0 1\nvn 0 0 1\n"
    "f 1// 2// 3//\n", "corrupt", "face uses normal ''")
add("obj_normal_lines_miscounted.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvnx 0 0 1\n"
    "vnx 0 0 1\nf 1 2 3\n", "corrupt", "3 lines start with 'vn' but 1 normals were found")
add("obj_normals_unused.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1 2 3\n", "ok", "", 1)
add("obj_bad_number.obj", "v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n", "corrupt",
    "'zero' is not a number")
add("obj_indented_vertex.obj", "v 0 0 0\n  v 1 0 0\nv 0 1 0\nf 1 2 3\n", "corrupt",
    "does not start its line")
add("obj_continuation_crlf.obj", "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 \\\r\n3\r\n", "corrupt",
    "continuation")
add("obj_continuation_at_end.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 \\", "corrupt",
    "no line follows")
add("obj_mrgb_short.obj", "#MRGB ff102030\n" + obj(SQUARE[:3], [(1, 2, 3)]), "corrupt",
    "#MRGB colours for 1 of 3 vertices")
add("obj_mtllib_dev_zero.obj", "mtllib /dev/zero\n" + obj(SQUARE[:3], [(1, 2, 3)]), "corrupt",
    "is not a regular file")
add("obj_colour_overflow.obj", "v 0 0 0 1 0 0\nv 1 0 0 300 0 0\nv 0 1 0 0 0 0\nf 1 2 3\n",
    "corrupt", "line 2: a vertex colour out of range")
add("off_colour_overflow.off", "COFF\n3 1 0\n0 0 0 0.5 0 0\n1 0 0 9.5 0 0\n0 1 0 0.5 0 0\n"
    "3 0 1 2\n", "corrupt", "vertex 1: colour component out of range")
add("off_face_colour_nan.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 0.5 nan 0\n",
    "corrupt", "face 0: colour component out of range")
add("obj_line_index_zero.obj", obj(SQUARE[:3], [(1, 2, 3)]) + "l 0 2\n", "corrupt",
    "line element uses vertex '0'")
add("ply_index_out_of_range.ply", ply_ascii(SQUARE, [(0, 1, 9)]), "corrupt",
    "face 0 uses vertex index 9, outside 0..3")
add("ply_negative_index_binary.ply", ply_binary(SQUARE, [(0, -1, 2)]), "corrupt",
    "uses vertex index -1")
add("ply_quad_last_index_bad.ply", ply_binary(SQUARE, [(0, 1, 2, 99)]), "corrupt",
    "uses vertex index 99")
add("ply_face_list_600.ply", ply_binary(SQUARE, [tuple([0, 1, 2] * 200)], count="int"),
    "corrupt", "has a list of 600 entries")
add("ply_face_list_2.ply", ply_binary(SQUARE, [(0, 1)]), "corrupt", "has a list of 2 entries")
add("ply_face_list_ushort_count.ply", ply_binary(SQUARE, TRIS, count="ushort", index="int"),
    "wrong_format", "is not supported")
add("ply_element_without_count.ply",
    "ply\nformat ascii 1.0\nelement vertex\nproperty float x\nend_header\n", "corrupt",
    "an element without a valid count")
add("ply_long_comment.ply", ply_ascii(SQUARE, TRIS).replace(
    b"format ascii 1.0\n", b"format ascii 1.0\ncomment " + b"x" * 600 + b"\n"), "corrupt",
    "too long")
add("ply_no_end_header.ply", "ply\nformat ascii 1.0\nelement vertex 3\n", "corrupt",
    "no end_header")
add("ply_tristrips.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
    "property float y\nproperty float z\nelement tristrips 1\n"
    "property list int int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
    "wrong_format", "tristrips")
add("ply_two_vertex_elements.ply", ply_ascii(SQUARE, [(0, 1, 5)]).replace(
    b"element face", b"element vertex 3\nproperty float x\nelement face").replace(
    b"0 1 0\n3 0", b"0 1 0\n0\n0\n0\n3 0"), "corrupt", "two PLY 'vertex' elements")
add("ply_face_without_indices.ply", ply_ascii(TET_V, TET_F).replace(b"vertex_indices",
                                                                     b"vertex_indic"),
    "corrupt", "the PLY face element has no vertex_indices list")
add("ply_blank_after_comment.ply", b"ply\ncomment x\n\nformat ascii 1.0\nend_header\n",
    "corrupt", "PLY header line 3 is blank")
add("ply_long_texture_comment.ply", ply_ascii(TET_V, TET_F).replace(
    b"format ascii 1.0\n", b"format ascii 1.0\ncomment TextureFile " + b"t" * 300 + b"\n"),
    "corrupt", "PLY texture file comment too long")
add("ply_texture_comment_ok.ply", ply_ascii(TET_V, TET_F).replace(
    b"format ascii 1.0\n", b"format ascii 1.0\ncomment TextureFile <this>.png\n"), "ok", "", 4)
add("ply_bad_number_ascii.ply", ply_ascii(SQUARE, TRIS).replace(b"1.000000 0.000000",
                                                               b"1.0abc 0.000000", 1),
    "corrupt", "unparsable number")

# ---- NaN / inf: read, then refused by the engine -----------------------------------------------
NAN_V = [(float("nan"), 0, 0)] + TET_V[1:]
add("off_nan.off", off(TET_V[:3] + [("inf", 0, 1)], TET_F), "ok", "non-finite coordinate")
add("obj_nan.obj", obj([("nan", 0, 0)] + TET_V[1:], [tuple(i + 1 for i in f) for f in TET_F]),
    "ok", "non-finite coordinate")
add("ply_nan_binary.ply", ply_binary(NAN_V, TET_F), "ok", "non-finite coordinate")
add("ply_inf_ascii.ply", ply_ascii(TET_V[:3] + [(0, 0, float("-inf"))], TET_F), "ok",
    "non-finite coordinate")
add("stl_nan_ascii.stl", stl_ascii([[("nan", 0, 0), (1, 0, 0), (0, 1, 0)]]), "ok",
    "non-finite coordinate")

# ---- empty ------------------------------------------------------------------------------------
for ext in ("ply", "obj", "off", "stl"):
    add("empty." + ext, b"", "empty", "the file is empty (0 bytes)")
add("blank.obj", " \n\t\r\n   \n", "empty", "only blanks")
add("blank.ply", "\n\n", "empty", "only blanks")
add("comments_only.obj", "# nothing\n# at all\n", "empty", "no vertex and no face")
add("comments_only.off", "# nothing\n# at all\n", "empty", "only comments or blanks")
add("zero_counts.off", "OFF\n0 0 0\n", "empty", "no vertex and no face")
add("zero_triangles.stl", stl_binary([]), "empty", "no vertex and no face")
add("no_facets.stl", "solid x\nendsolid x\n", "empty", "no vertex and no face")
add("no_elements.ply", ply_ascii([], []), "empty", "no vertex and no face")
add("points_only.ply", ply_ascii(TET_V, []), "ok", "no faces", 0)

# ---- wrong format or name -----------------------------------------------------------------------
add("ply_named.stl", ply_binary(TET_V, TET_F), "wrong_format",
    "the file is a PLY file but its name ends in .stl")
add("off_named.ply", off(TET_V, TET_F), "wrong_format",
    "the file is an OFF file but its name ends in .ply")
add("stl_named.obj", stl_ascii(SOUP), "wrong_format",
    "the file is an STL file but its name ends in .obj")
add("ply_named.off", ply_ascii(TET_V, TET_F), "wrong_format",
    "is a PLY file but its name ends in .off")
add("mesh.xyz", off(TET_V, TET_F), "wrong_format", "its name ends in .xyz, not a known extension")
add("no_extension", off(TET_V, TET_F), "wrong_format", "its name has no extension")
add("UPPER.OFF", off(TET_V, TET_F), "ok", "", 4)

# ---- not a regular file -----------------------------------------------------------------------
os.mkdir(os.path.join(out, "x.ply"))
add("x.ply", None, "cannot_open", "not a regular file (a directory)")
add("missing.obj", None, "cannot_open", "no such file")
os.mkfifo(os.path.join(out, "fifo.obj"))
add("fifo.obj", None, "cannot_open", "not a regular file (a device, pipe or socket)")
os.symlink("/dev/zero", os.path.join(out, "zero.stl"))
add("zero.stl", None, "cannot_open", "not a regular file (a device, pipe or socket)")

# ---- Debian's assimp-testmodels: broken files found by assimp's importer tests -----------------
ASSIMP = [
    ("invalid/empty.obj", "empty", "the file is empty (0 bytes)", None),
    ("invalid/empty.off", "empty", "the file is empty (0 bytes)", None),
    ("invalid/empty.ply", "empty", "the file is empty (0 bytes)", None),
    # a vertex count no file can hold
    ("invalid/OutOfMemory.off", "corrupt",
     "the header announces 353535235358 vertices and 6 faces but the file has only 309", None),
    # a face using vertex 12 of 8
    ("invalid/malformed.obj", "corrupt", "face uses vertex '12' but 8 vertices", None),
    # an empty "f" line (skipped) and an unknown material: 5 quads of a cube read
    ("invalid/malformed2.obj", "ok", "", 10),
    # counts line with two numbers
    ("OFF/invalid.off", "corrupt", "no vertex, face and edge counts", None),
]
for rel, status, fragment, faces in ASSIMP:
    src = os.path.join(assimp, rel)
    if os.path.exists(src):
        name = "assimp_" + rel.replace("/", "_")
        os.symlink(src, os.path.join(out, name))
        add(name, None, status, fragment, faces)

with open(os.path.join(out, "expected.tsv"), "w") as f:
    for r in rows:
        f.write("\t".join(r) + "\n")
print("{} files in {}".format(len(rows), out))
