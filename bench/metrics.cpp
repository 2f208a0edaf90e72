// bench_metrics: quality of a simplified mesh against its original. Prints one JSON line.
//   bench_metrics [--samples N] ORIGINAL SIMPLIFIED
//
// Distances (as MeshLab's Hausdorff filter / Metro do): both surfaces are sampled (VCG
// SurfaceSampling::Montecarlo, N area-uniform samples per surface, plus the mesh vertices, at most
// N/4 of them), and each sample's closest point on the other surface is found with a CGAL AABB tree
// over the other mesh's faces (closest point on a triangle, double precision). VCG's uniform grid
// (GridStaticPtr, what MeshLab's filter uses) was tried first: its search visits every cell within
// the distance found, which for a coarse output far from a dense input (4.7k faces against 2M)
// did not end in 15 minutes; MeshLab avoids that with a distance cut-off, which would cap the
// Hausdorff distance. Zero-area faces are not searched (no surface). All distances are in percent
// of the ORIGINAL's bounding-box diagonal.
//   hausdorff_pct   max over both directions and all samples (two-sided Hausdorff)
//   mean_pct        larger of the two one-sided area-weighted mean distances (Montecarlo samples)
//   *_ab_*          original -> simplified,  *_ba_* simplified -> original
//   hausdorff_ab_at, hausdorff_ba_at  where each direction's farthest sample lies (mesh units):
//                   the place to look at when a level's distance is worse than expected
// Normal deviation: for every Montecarlo sample (both directions), the angle between the normal of
// the face it lies on and the normal of the closest face of the other mesh. When the closest point
// lies on an edge or vertex of the other mesh (several faces equally close), the face with the
// smallest angle is taken, so that a sample exactly on a shared crease is not charged the crease.
//   normal_p95_deg, normal_max_deg  over the pooled samples of both directions
// Validity of the simplified mesh (vertices welded by exact position first):
//   nonmanifold_edges  edges with more than 2 incident faces
//   boundary_edges     edges with 1 incident face (input_boundary_edges: same in the original)
//   flipped            faces whose normal is > 90 deg from the closest original face's normal
//                      (closest to the face's centroid; ties as above)
//   degenerate         faces of zero area (counted as slivers too, not as flipped)
//   sliver_pct         percent of faces whose smallest angle is < 10 deg
#include "bench_mesh.h"

#include <vcg/complex/algorithms/clean.h>
#include <vcg/complex/algorithms/point_sampling.h>
#include <vcg/complex/algorithms/update/bounding.h>
#include <vcg/complex/algorithms/update/normal.h>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <random>
#include <unordered_map>

namespace {

class MVertex;
class MFace;
struct MUsedTypes
    : public vcg::UsedTypes<vcg::Use<MVertex>::AsVertexType, vcg::Use<MFace>::AsFaceType> {};
class MVertex : public vcg::Vertex<MUsedTypes, vcg::vertex::Coord3d, vcg::vertex::Normal3d,
                                   vcg::vertex::BitFlags, vcg::vertex::Mark> {};
class MFace : public vcg::Face<MUsedTypes, vcg::face::VertexRef, vcg::face::Normal3d,
                               vcg::face::BitFlags, vcg::face::Mark> {};
class MMesh : public vcg::tri::TriMesh<std::vector<MVertex>, std::vector<MFace>> {};

using Coord = vcg::Point3d;
using K = CGAL::Simple_cartesian<double>;
using Tri3 = K::Triangle_3;
using TriIt = std::vector<Tri3>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<K, TriIt>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;
const double kPi = 3.14159265358979323846;

struct Sample {
	Coord p;
	const MFace *face; // null for vertex samples (no normal statistics)
};

struct Collector {
	std::vector<Sample> *out;
	void AddFace(const MFace &f, const Coord &b)
	{
		out->push_back({f.cV(0)->cP() * b[0] + f.cV(1)->cP() * b[1] + f.cV(2)->cP() * b[2], &f});
	}
	void AddVert(const MVertex &v) { out->push_back({v.cP(), nullptr}); }
};

double angleDeg(const Coord &a, const Coord &b)
{
	const double na = a.Norm(), nb = b.Norm();
	if (na == 0 || nb == 0)
		return 0;
	const double c = std::max(-1.0, std::min(1.0, (a * b) / (na * nb)));
	return std::acos(c) * 180.0 / kPi;
}

/// Closest face of `m` to `p`; `dist` and the normal angle to `n`. When the closest point lies on
/// an edge or a vertex of that face, every face through that edge or vertex is equally close: the
/// smallest angle among them is taken (found through vertex-face adjacency).
struct Closest {
	MMesh *m = nullptr;
	std::vector<Tri3> tris;       // the non-degenerate faces of m
	std::vector<uint32_t> faceOf; // their face index in m
	Tree tree;
	std::vector<uint32_t> vfStart, vfFaces; // faces around each vertex (CSR)

	void build(MMesh &mesh)
	{
		m = &mesh;
		auto pt = [](const MVertex *v) { return K::Point_3(v->cP()[0], v->cP()[1], v->cP()[2]); };
		for (size_t fi = 0; fi < m->face.size(); ++fi) {
			const MFace &f = m->face[fi];
			const Tri3 t(pt(f.cV(0)), pt(f.cV(1)), pt(f.cV(2)));
			if (CGAL::cross_product(t[1] - t[0], t[2] - t[0]).squared_length() == 0)
				continue; // zero area: no surface to be close to
			tris.push_back(t);
			faceOf.push_back(uint32_t(fi));
		}
		tree.insert(tris.cbegin(), tris.cend());
		tree.build();
		tree.accelerate_distance_queries(); // kd-tree of the vertices: a close first guess per
		                                    // query
		buildAdjacency();
	}

	void buildAdjacency()
	{
		vfStart.assign(m->vert.size() + 1, 0);
		for (const MFace &f : m->face)
			for (int k = 0; k < 3; ++k)
				++vfStart[vcg::tri::Index(*m, f.cV(k)) + 1];
		for (size_t i = 1; i < vfStart.size(); ++i)
			vfStart[i] += vfStart[i - 1];
		vfFaces.assign(vfStart.back(), 0);
		std::vector<uint32_t> fill(vfStart.begin(), vfStart.end() - 1);
		for (size_t fi = 0; fi < m->face.size(); ++fi)
			for (int k = 0; k < 3; ++k)
				vfFaces[fill[vcg::tri::Index(*m, m->face[fi].cV(k))]++] = uint32_t(fi);
	}

	/// Smallest angle to n over the faces around vertex v (that also hold vertex `other`, if set).
	void around(size_t v, long other, const Coord &n, double &angle) const
	{
		for (uint32_t j = vfStart[v]; j < vfStart[v + 1]; ++j) {
			const MFace &g = m->face[vfFaces[j]];
			if (other >= 0 && vcg::tri::Index(*m, g.cV(0)) != size_t(other) &&
			    vcg::tri::Index(*m, g.cV(1)) != size_t(other) &&
			    vcg::tri::Index(*m, g.cV(2)) != size_t(other))
				continue;
			angle = std::min(angle, angleDeg(n, g.cN()));
		}
	}

	const MFace *find(const Coord &p, const Coord &n, double &dist, double &angle)
	{
		if (tris.empty()) {
			dist = std::numeric_limits<double>::infinity();
			angle = 180;
			return nullptr;
		}
		const K::Point_3 kp(p[0], p[1], p[2]);
		const auto hit = tree.closest_point_and_primitive(kp);
		const Coord q(hit.first.x(), hit.first.y(), hit.first.z());
		const MFace *f = &m->face[faceOf[size_t(hit.second - tris.cbegin())]];
		dist = vcg::Distance(p, q);
		angle = angleDeg(n, f->cN());
		if (n.Norm() == 0 || angle < 1e-9)
			return f;
		size_t vi[3];
		for (int k = 0; k < 3; ++k)
			vi[k] = vcg::tri::Index(*m, f->cV(k));
		const Coord e0 = f->cV(1)->cP() - f->cV(0)->cP(), e1 = f->cV(2)->cP() - f->cV(0)->cP();
		const double area2 = (e0 ^ e1).Norm();
		bool zero[3] = {true, true, true};
		int zeros = 3;
		if (area2 > 0) {
			zeros = 0;
			for (int k = 0; k < 3; ++k) {
				const Coord u = f->cV((k + 1) % 3)->cP() - q, v = f->cV((k + 2) % 3)->cP() - q;
				zero[k] = (u ^ v).Norm() / area2 < 1e-7; // barycentric coordinate k ~ 0
				zeros += zero[k];
			}
		}
		if (zeros == 1) { // on the edge opposite the zero coordinate
			const int k = zero[0] ? 0 : (zero[1] ? 1 : 2);
			around(vi[(k + 1) % 3], long(vi[(k + 2) % 3]), n, angle);
		} else if (zeros == 2) { // at the vertex whose coordinate is not zero
			const int k = !zero[0] ? 0 : (!zero[1] ? 1 : 2);
			around(vi[k], -1, n, angle);
		} else if (zeros == 3) { // degenerate face
			for (int k = 0; k < 3; ++k)
				around(vi[k], -1, n, angle);
		}
		return f;
	}
};

struct Direction {
	double maxDist = 0, meanDist = 0;
	size_t samples = 0;
	Coord where = Coord(0, 0, 0); ///< the sample farthest from the other surface
};

Direction measure(MMesh &from, Closest &to, int nSamples, std::vector<double> &angles)
{
	std::vector<Sample> samples;
	samples.reserve(size_t(nSamples) * 2);
	Collector col{&samples};
	vcg::tri::SurfaceSampling<MMesh, Collector>::SamplingRandomGenerator().initialize(4711);
	vcg::tri::SurfaceSampling<MMesh, Collector>::Montecarlo(from, col, nSamples);
	// Mesh order (faces are stored with spatial coherence): consecutive queries are close.
	std::stable_sort(samples.begin(), samples.end(),
	                 [](const Sample &x, const Sample &y) { return x.face < y.face; });
	const size_t areaSamples = samples.size();
	// Vertices: all of them, or a fixed random subset of nSamples / 4 (kept in mesh order).
	std::vector<const MVertex *> verts;
	for (const MVertex &v : from.vert)
		if (!v.IsD())
			verts.push_back(&v);
	const size_t maxVerts = size_t(std::max(1, nSamples / 4));
	if (verts.size() > maxVerts) {
		std::mt19937_64 rng(99);
		std::shuffle(verts.begin(), verts.end(), rng);
		verts.resize(maxVerts);
		std::sort(verts.begin(), verts.end());
	}
	for (const MVertex *v : verts)
		col.AddVert(*v);

	Direction d;
	double sum = 0;
	for (size_t i = 0; i < samples.size(); ++i) {
		const Sample &s = samples[i];
		double dist, angle;
		const Coord n = s.face ? s.face->cN() : Coord(0, 0, 0);
		to.find(s.p, n, dist, angle);
		if (dist > d.maxDist)
			d.where = s.p;
		d.maxDist = std::max(d.maxDist, dist);
		if (i < areaSamples) {
			sum += dist;
			angles.push_back(angle);
		}
	}
	d.meanDist = areaSamples ? sum / double(areaSamples) : 0;
	d.samples = samples.size();
	return d;
}

struct EdgeCounts {
	size_t nonManifold = 0, boundary = 0;
};

EdgeCounts countEdges(const MMesh &m)
{
	std::unordered_map<uint64_t, int> count;
	count.reserve(size_t(m.fn) * 2);
	for (const MFace &f : m.face) {
		if (f.IsD())
			continue;
		for (int k = 0; k < 3; ++k) {
			uint64_t a = vcg::tri::Index(m, f.cV(k)), b = vcg::tri::Index(m, f.cV((k + 1) % 3));
			if (a == b)
				continue;
			if (a > b)
				std::swap(a, b);
			++count[(a << 32) | b];
		}
	}
	EdgeCounts e;
	for (const auto &kv : count) {
		if (kv.second > 2)
			++e.nonManifold;
		else if (kv.second == 1)
			++e.boundary;
	}
	return e;
}

double minAngleDeg(const MFace &f)
{
	double best = 180;
	for (int k = 0; k < 3; ++k) {
		const Coord a = f.cV((k + 1) % 3)->cP() - f.cV(k)->cP();
		const Coord b = f.cV((k + 2) % 3)->cP() - f.cV(k)->cP();
		if (a.Norm() == 0 || b.Norm() == 0)
			return 0;
		best = std::min(best, angleDeg(a, b));
	}
	return best;
}

bool prepare(MMesh &m, const char *file)
{
	std::string err;
	if (!bench::load(m, file, err)) {
		std::fprintf(stderr, "bench_metrics: cannot read %s: %s\n", file, err.c_str());
		return false;
	}
	vcg::tri::Clean<MMesh>::RemoveDuplicateVertex(m);
	vcg::tri::Allocator<MMesh>::CompactEveryVector(m);
	vcg::tri::UpdateBounding<MMesh>::Box(m);
	vcg::tri::UpdateNormal<MMesh>::PerFaceNormalized(m);
	return true;
}

} // namespace

int main(int argc, char **argv)
{
	int nSamples = 200000;
	std::vector<std::string> files;
	for (int i = 1; i < argc; ++i) {
		const std::string a = argv[i];
		if (a == "--samples" && i + 1 < argc)
			nSamples = std::atoi(argv[++i]);
		else
			files.push_back(a);
	}
	if (files.size() != 2 || nSamples < 1) {
		std::fprintf(stderr, "usage: bench_metrics [--samples N] ORIGINAL SIMPLIFIED\n");
		return 2;
	}
	const double t0 = bench::now();
	MMesh a, b;
	if (!prepare(a, files[0].c_str()) || !prepare(b, files[1].c_str()))
		return 1;
	if (b.fn == 0) {
		std::fprintf(stderr, "bench_metrics: %s has no face\n", files[1].c_str());
		return 1;
	}
	const double diag = a.bbox.Diag();
	Closest toA, toB;
	toA.build(a);
	toB.build(b);

	std::vector<double> angles;
	const Direction ab = measure(a, toB, nSamples, angles);
	const Direction ba = measure(b, toA, nSamples, angles);
	std::sort(angles.begin(), angles.end());
	const double p95 =
	    angles.empty() ? 0
	                   : angles[std::min(angles.size() - 1, size_t(0.95 * double(angles.size())))];
	const double amax = angles.empty() ? 0 : angles.back();

	size_t flipped = 0, degenerate = 0, slivers = 0;
	for (const MFace &f : b.face) {
		if (f.IsD())
			continue;
		const double minAng = minAngleDeg(f);
		if (minAng < 10)
			++slivers;
		if (f.cN().Norm() == 0 || vcg::DoubleArea(f) <= 0) {
			++degenerate;
			continue;
		}
		const Coord c = (f.cV(0)->cP() + f.cV(1)->cP() + f.cV(2)->cP()) / 3.0;
		double dist, angle;
		toA.find(c, f.cN(), dist, angle);
		if (angle > 90)
			++flipped;
	}
	const EdgeCounts eb = countEdges(b), ea = countEdges(a);
	auto pct = [&](double d) { return diag > 0 ? 100.0 * d / diag : 0.0; };
	std::printf("{\"faces\":%d,\"vertices\":%d,\"hausdorff_pct\":%.6g,\"mean_pct\":%.6g,"
	            "\"hausdorff_ab_pct\":%.6g,\"hausdorff_ba_pct\":%.6g,\"mean_ab_pct\":%.6g,"
	            "\"mean_ba_pct\":%.6g,\"normal_p95_deg\":%.4f,\"normal_max_deg\":%.4f,"
	            "\"sliver_pct\":%.4f,\"nonmanifold_edges\":%zu,\"boundary_edges\":%zu,"
	            "\"input_boundary_edges\":%zu,\"flipped\":%zu,\"degenerate\":%zu,"
	            "\"hausdorff_ab_at\":[%.9g,%.9g,%.9g],\"hausdorff_ba_at\":[%.9g,%.9g,%.9g],"
	            "\"samples\":%zu,\"diag\":%.6g,\"seconds\":%.3f}\n",
	            b.fn, b.vn, pct(std::max(ab.maxDist, ba.maxDist)),
	            pct(std::max(ab.meanDist, ba.meanDist)), pct(ab.maxDist), pct(ba.maxDist),
	            pct(ab.meanDist), pct(ba.meanDist), p95, amax,
	            100.0 * double(slivers) / double(b.fn), eb.nonManifold, eb.boundary, ea.boundary,
	            flipped, degenerate, ab.where[0], ab.where[1], ab.where[2], ba.where[0],
	            ba.where[1], ba.where[2], ab.samples + ba.samples, diag, bench::now() - t0);
	return 0;
}
