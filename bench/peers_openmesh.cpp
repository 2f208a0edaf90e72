// OpenMesh's decimater (Debian libopenmesh-dev), the two bench_peers methods built on it:
//   openmesh_quadric IN TARGET_FACES OUT.ply
//       DecimaterT with ModQuadricT (quadric error as the cost, no error bound), run to the face
//       count.
//   openmesh_nd IN ANGLE_DEG OUT.ply
//       the same plus ModNormalDeviationT as a binary constraint: a collapse is refused when the
//       normal cone of the faces merged into any face would open wider than ANGLE_DEG (OpenMesh's
//       normal deviation, the cone's full aperture). Run with no face target: it stops when no
//       collapse is legal, so the angle alone sets the face count (like Blender's planar angle).
// OpenMesh collapses halfedges (a vertex moves onto its neighbour, no optimal placement); that is
// its decimater as shipped. Timing: wall clock in-process from the flat arrays to the simplified
// mesh (building the OpenMesh mesh included, the decimation alone reported too).
// Kept in a translation unit of its own so that the CGAL one is not recompiled for it.
#include "peers_openmesh.h"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalDeviationT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include <OpenMesh/Core/System/omstream.hh>

#include <cstdio>

namespace {

/// Double-precision points and normals (the quadrics are double anyway; CGAL runs in double too).
struct DoubleTraits : public OpenMesh::DefaultTraits {
	typedef OpenMesh::Vec3d Point;
	typedef OpenMesh::Vec3d Normal;
};
using OMesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;
using Decimater = OpenMesh::Decimater::DecimaterT<OMesh>;
using ModQuadric = OpenMesh::Decimater::ModQuadricT<OMesh>::Handle;
using ModNormalDev = OpenMesh::Decimater::ModNormalDeviationT<OMesh>::Handle;

/// Builds the OpenMesh mesh; faces OpenMesh refuses (non-manifold) are counted, not added.
size_t build(const bench::Flat &in, OMesh &om)
{
	om.reserve(in.vn(), in.fn() * 3 / 2, in.fn());
	std::vector<OMesh::VertexHandle> vh(in.vn());
	for (size_t i = 0; i < in.vn(); ++i)
		vh[i] = om.add_vertex(OMesh::Point(in.pos[3 * i], in.pos[3 * i + 1], in.pos[3 * i + 2]));
	size_t skipped = 0;
	for (size_t f = 0; f < in.fn(); ++f) {
		const OMesh::FaceHandle fh =
		    om.add_face(vh[in.tri[3 * f]], vh[in.tri[3 * f + 1]], vh[in.tri[3 * f + 2]]);
		if (!fh.is_valid())
			++skipped;
	}
	return skipped;
}

bool write(const OMesh &om, const std::string &out)
{
	std::vector<double> pos;
	std::vector<uint32_t> tri;
	pos.reserve(om.n_vertices() * 3);
	tri.reserve(om.n_faces() * 3);
	for (const OMesh::VertexHandle v : om.vertices()) {
		const OMesh::Point &p = om.point(v);
		pos.insert(pos.end(), {p[0], p[1], p[2]});
	}
	for (const OMesh::FaceHandle f : om.faces())
		for (const OMesh::VertexHandle v : om.fv_range(f))
			tri.push_back(uint32_t(v.idx()));
	return bench::writePly(out, pos, tri);
}

} // namespace

int runOpenMesh(const bench::Flat &in, bool normalDeviation, double value, const std::string &out)
{
	omerr().disable(); // "Mesh has no face normals..." and complex-edge warnings on stderr
	const double t0 = bench::now();
	OMesh om;
	const size_t skipped = build(in, om);
	om.request_face_normals();
	om.update_face_normals();
	Decimater dec(om);
	ModQuadric quadric;
	dec.add(quadric);
	dec.module(quadric).unset_max_err();
	ModNormalDev nd;
	if (normalDeviation) {
		dec.add(nd);
		dec.module(nd).set_normal_deviation(value);
		dec.module(nd).set_binary(true);
	}
	if (!dec.initialize()) {
		std::fprintf(stderr, "bench_peers: OpenMesh decimater did not initialize\n");
		return 1;
	}
	const double t1 = bench::now();
	const size_t target = normalDeviation ? 0 : size_t(value);
	const size_t collapses = dec.decimate_to_faces(0, target);
	const double t2 = bench::now();
	om.garbage_collection();
	const size_t faces = om.n_faces();
	if (!write(om, out)) {
		std::fprintf(stderr, "bench_peers: cannot write %s\n", out.c_str());
		return 1;
	}
	std::printf(
	    "{\"method\":\"%s\",\"version\":\"%d.%d\",%s\"faces\":%zu,\"seconds\":%.6f,"
	    "\"collapse_seconds\":%.6f,\"collapses\":%zu,\"skipped_input_faces\":%zu,\"file\":%s}\n",
	    normalDeviation ? "openmesh_nd" : "openmesh_quadric", OM_GET_VER, OM_GET_MAJ,
	    (normalDeviation ? "\"angle_deg\":" + std::to_string(value) + ","
	                     : "\"target\":" + std::to_string(target) + ",")
	        .c_str(),
	    faces, t2 - t0, t2 - t1, collapses, skipped, bench::jsonStr(out).c_str());
	return 0;
}
