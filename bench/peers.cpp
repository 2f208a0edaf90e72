// bench_peers: peer simplifiers run in-process to a target face count.
//   bench_peers meshopt IN TARGET_FACES OUT.ply
//   bench_peers cgal_gh IN TARGET_FACES OUT.ply
//   bench_peers cgal_gh_input_positions IN TARGET_FACES OUT.ply
//   bench_peers openmesh_quadric IN TARGET_FACES OUT.ply
//   bench_peers openmesh_nd IN ANGLE_DEG OUT.ply
// meshopt: meshoptimizer's meshopt_simplify (edge collapse with quadric error; version from
//          MESHOPTIMIZER_VERSION), options 0, target error unbounded so only the count stops it.
// cgal_gh: CGAL Surface_mesh_simplification::edge_collapse with GarlandHeckbert_plane_policies
//          (classic Garland-Heckbert plane quadrics, cost and placement), stopped at the face
//          count.
// cgal_gh_input_positions: the same collapses, then every vertex left back at the input position
//          of the input vertex it is (a diagnostic, not a peer: what GH's choice of vertices and
//          connectivity gives without its placement; DESIGN 30).
// openmesh_*: OpenMesh's DecimaterT with ModQuadricT, alone to the face count or with
//          ModNormalDeviationT as far as the angle allows (peers_openmesh.cpp).
// Timing: wall clock in-process, from the flat arrays in memory to the simplified mesh (for CGAL
// this includes building the Surface_mesh; the collapse alone is reported too). Loading and
// writing are excluded. Prints one JSON line.
#include "bench_mesh.h"
#include "peers_openmesh.h"

#include <meshoptimizer.h>

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/GarlandHeckbert_plane_policies.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>

#include <cstdlib>

namespace {

using K = CGAL::Simple_cartesian<double>;
using SM = CGAL::Surface_mesh<K::Point_3>;
namespace SMS = CGAL::Surface_mesh_simplification;

/// Stops when the live face count of the Surface_mesh has reached the target (CGAL 5.5 has only
/// an edge-count predicate).
struct FaceCountStop {
	const SM *mesh;
	size_t target;
	template <typename F, typename Profile>
	bool operator()(const F &, const Profile &, std::size_t, std::size_t) const
	{
		return mesh->number_of_faces() <= target;
	}
};

int runMeshopt(const bench::Flat &in, size_t target, const std::string &out)
{
	std::vector<uint32_t> dst(in.tri.size());
	float resultError = 0;
	const double t0 = bench::now();
	const size_t n =
	    meshopt_simplify(dst.data(), in.tri.data(), in.tri.size(), in.pos.data(), in.vn(),
	                     3 * sizeof(float), target * 3, 1e6f, 0, &resultError);
	const double secs = bench::now() - t0;
	dst.resize(n);
	if (!bench::writePly(out, in.pos, dst)) {
		std::fprintf(stderr, "bench_peers: cannot write %s\n", out.c_str());
		return 1;
	}
	std::printf(
	    "{\"method\":\"meshopt\",\"version\":%d,\"target\":%zu,\"faces\":%zu,\"seconds\":%.6f,"
	    "\"result_error\":%.6g,\"file\":%s}\n",
	    MESHOPTIMIZER_VERSION, target, n / 3, secs, double(resultError),
	    bench::jsonStr(out).c_str());
	return 0;
}

int runCgal(const bench::Flat &in, size_t target, const std::string &out, bool inputPositions)
{
	const double t0 = bench::now();
	SM sm;
	std::vector<SM::Vertex_index> vid(in.vn());
	for (size_t i = 0; i < in.vn(); ++i)
		vid[i] = sm.add_vertex(K::Point_3(in.pos[3 * i], in.pos[3 * i + 1], in.pos[3 * i + 2]));
	size_t skipped = 0;
	for (size_t f = 0; f < in.fn(); ++f) {
		const SM::Face_index fi =
		    sm.add_face(vid[in.tri[3 * f]], vid[in.tri[3 * f + 1]], vid[in.tri[3 * f + 2]]);
		if (fi == SM::null_face())
			++skipped; // would make the Surface_mesh non-manifold: CGAL cannot take it
	}
	const double t1 = bench::now();
	SMS::GarlandHeckbert_plane_policies<SM, K> gh(sm);
	FaceCountStop stop{&sm, target};
	const int removed = SMS::edge_collapse(
	    sm, stop, CGAL::parameters::get_cost(gh.get_cost()).get_placement(gh.get_placement()));
	const double t2 = bench::now();
	if (inputPositions) // (vertex indices are the input's until the garbage is collected)
		for (SM::Vertex_index v : sm.vertices()) {
			const size_t i = size_t(v);
			sm.point(v) = K::Point_3(in.pos[3 * i], in.pos[3 * i + 1], in.pos[3 * i + 2]);
		}
	sm.collect_garbage();
	std::vector<double> pos;
	std::vector<uint32_t> tri;
	pos.reserve(sm.number_of_vertices() * 3);
	for (SM::Vertex_index v : sm.vertices()) {
		const K::Point_3 &p = sm.point(v);
		pos.insert(pos.end(), {p.x(), p.y(), p.z()});
	}
	for (SM::Face_index f : sm.faces())
		for (SM::Vertex_index v : vertices_around_face(sm.halfedge(f), sm))
			tri.push_back(uint32_t(v));
	if (!bench::writePly(out, pos, tri)) {
		std::fprintf(stderr, "bench_peers: cannot write %s\n", out.c_str());
		return 1;
	}
	std::printf(
	    "{\"method\":\"%s\",\"version\":%d,\"target\":%zu,\"faces\":%zu,\"seconds\":%.6f,"
	    "\"collapse_seconds\":%.6f,\"removed_edges\":%d,\"skipped_input_faces\":%zu,\"file\":%s}\n",
	    inputPositions ? "cgal_gh_input_positions" : "cgal_gh", CGAL_VERSION_NR / 1000, target,
	    tri.size() / 3, t2 - t0, t2 - t1, removed, skipped, bench::jsonStr(out).c_str());
	return 0;
}

} // namespace

int main(int argc, char **argv)
{
	if (argc != 5) {
		std::fprintf(stderr,
		             "usage: bench_peers meshopt|cgal_gh|cgal_gh_input_positions|openmesh_quadric "
		             "IN TARGET_FACES OUT.ply\n"
		             "       bench_peers openmesh_nd IN ANGLE_DEG OUT.ply\n");
		return 2;
	}
	const std::string method = argv[1], in = argv[2], out = argv[4];
	const bool byAngle = method == "openmesh_nd";
	const double angle = std::atof(argv[3]);
	const long target = byAngle ? 1 : std::atol(argv[3]);
	if (target < 1 || (byAngle && !(angle > 0 && angle <= 360))) {
		std::fprintf(stderr, "bench_peers: bad target %s\n", argv[3]);
		return 2;
	}
	bench::FMesh m;
	std::string err;
	if (!bench::load(m, in, err)) {
		std::fprintf(stderr, "bench_peers: cannot read %s: %s\n", in.c_str(), err.c_str());
		return 1;
	}
	const bench::Flat flat = bench::flatten(m);
	m.Clear();
	if (method == "meshopt")
		return runMeshopt(flat, size_t(target), out);
	if (method == "cgal_gh" || method == "cgal_gh_input_positions")
		return runCgal(flat, size_t(target), out, method != "cgal_gh");
	if (method == "openmesh_quadric")
		return runOpenMesh(flat, false, double(target), out);
	if (byAngle)
		return runOpenMesh(flat, true, angle, out);
	std::fprintf(stderr, "bench_peers: unknown method %s\n", method.c_str());
	return 2;
}
