// 2.4 Re-triangulating a superface: 2D constrained Delaunay triangulation of its projected border
// rings (outer ring and holes), keeping the triangles inside the domain. This is the only
// translation unit that includes CGAL (it compiles slowly).
#include "engine.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <deque>

namespace gausslod {
namespace detail {

namespace {

struct FaceInfo {
	int nesting = -1; ///< number of ring edges crossed from outside; odd = inside the superface
	int tri = -1;     ///< index of the output triangle
};

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_2<int32_t, K>;
using Fbi = CGAL::Triangulation_face_base_with_info_2<FaceInfo, K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<K, Fbi>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
// Crossing ring edges would need new vertices: refuse them (exception) instead.
using Itag = CGAL::No_constraint_intersection_requiring_constructions_tag;
using CDT = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, Itag>;
using Point = K::Point_2;

// Flood fill from the infinite face; crossing a ring edge increments the nesting level.
void markNesting(CDT &cdt)
{
	for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f)
		f->info().nesting = -1;
	std::deque<CDT::Face_handle> border{cdt.infinite_face()};
	cdt.infinite_face()->info().nesting = 0;
	std::vector<CDT::Face_handle> region;
	while (!border.empty()) {
		CDT::Face_handle seed = border.front();
		border.pop_front();
		const int level = seed->info().nesting;
		region.assign(1, seed);
		for (size_t q = 0; q < region.size(); ++q) {
			CDT::Face_handle f = region[q];
			for (int i = 0; i < 3; ++i) {
				CDT::Face_handle n = f->neighbor(i);
				if (n->info().nesting != -1)
					continue;
				if (f->is_constrained(i)) {
					n->info().nesting = level + 1;
					border.push_back(n);
				} else {
					n->info().nesting = level;
					region.push_back(n);
				}
			}
		}
	}
}

bool inside(CDT::Face_handle f) { return f->info().nesting % 2 == 1; }

// Inserts the points (one vertex for points that job.same says are one): vh[i] the vertex of
// point i; `distinct` the points that are vertices of their own. False if two points project to
// the same place.
bool insertPoints(const TriangulationJob &job, CDT &cdt, std::vector<CDT::Vertex_handle> &vh,
                  size_t &distinct)
{
	const size_t n = vh.size();
	CDT::Vertex_handle hint;
	distinct = n;
	for (size_t i = 0; i < n; ++i) {
		if (i < job.same.size() && job.same[i] >= 0) { // a ring touching itself: one vertex
			vh[i] = vh[size_t(job.same[i])];
			--distinct;
			continue;
		}
		const size_t before = cdt.number_of_vertices();
		vh[i] = cdt.insert(Point(job.xy[2 * i], job.xy[2 * i + 1]),
		                   hint == CDT::Vertex_handle() ? CDT::Face_handle() : hint->face());
		if (cdt.number_of_vertices() == before)
			return false; // two ring vertices project to the same point
		vh[i]->info() = int32_t(i);
		hint = vh[i];
	}
	return true;
}

// Calls f(i, j) for every ring edge i -> j (local vertex indices); false stops (then false).
template <class Fn>
bool allRingEdges(const TriangulationJob &job, Fn f)
{
	for (size_t r = 0; r + 1 < job.ringStart.size(); ++r) {
		const int32_t b = job.ringStart[r], e = job.ringStart[r + 1];
		for (int32_t i = b; i < e; ++i)
			if (!f(size_t(i), size_t(i + 1 < e ? i + 1 : b)))
				return false;
	}
	return true;
}

// Every ring edge must be an edge of the triangulation (not split by a vertex lying on it) with
// the superface on its left: rings are traced with the superface on their left.
bool ringsBoundInside(const TriangulationJob &job, const CDT &cdt,
                      const std::vector<CDT::Vertex_handle> &vh)
{
	return allRingEdges(job, [&](size_t i, size_t j) {
		CDT::Face_handle fh;
		int idx;
		if (!cdt.is_edge(vh[i], vh[j], fh, idx))
			return false;
		CDT::Face_handle left = fh, right = fh->neighbor(idx);
		if (fh->vertex(CDT::ccw(idx)) != vh[i])
			std::swap(left, right);
		return !cdt.is_infinite(left) && inside(left) && !inside(right);
	});
}

// The triangles inside the domain into job.tris, with their ring edges' bits.
void insideTriangles(CDT &cdt, TriangulationJob &job)
{
	for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
		if (!inside(f))
			continue;
		f->info().tri = int(job.tris.size() / 3);
		uint8_t bits = 0;
		for (int k = 0; k < 3; ++k) {
			job.tris.push_back(f->vertex(k)->info());
			// our edge k = (v_k, v_k+1) is CGAL's edge opposite vertex k+2
			if (f->is_constrained((k + 2) % 3))
				bits |= uint8_t(1u << k);
		}
		job.constrained.push_back(bits);
	}
}

// The triangle of each query. A query just outside the domain (an input face cut off by a
// straightened border) is given the inside triangle across the ring edge of the face it falls
// in, if any.
void locateQueries(const CDT &cdt, TriangulationJob &job)
{
	CDT::Face_handle loc;
	for (size_t q = 0; q < job.queryTri.size(); ++q) {
		loc = cdt.locate(Point(job.queryXY[2 * q], job.queryXY[2 * q + 1]), loc);
		if (inside(loc) && !cdt.is_infinite(loc)) {
			job.queryTri[q] = loc->info().tri;
			continue;
		}
		for (int i = 0; i < 3; ++i) {
			CDT::Face_handle n = loc->neighbor(i);
			if (loc->is_constrained(i) && !cdt.is_infinite(n) && inside(n)) {
				job.queryTri[q] = n->info().tri;
				break;
			}
		}
	}
}

} // namespace

bool triangulateRings(TriangulationJob &job, bool smallRings)
{
	job.tris.clear();
	job.constrained.clear();
	const bool ringsOnly = job.xy.size() / 2 == size_t(job.ringStart.back());
	if (smallRings && ringsOnly && job.same.empty() && triangulateSmallRing(job) == SmallRing::Done)
		return true;
	job.queryTri.assign(job.queryXY.size() / 2, -1);
	const size_t n = job.xy.size() / 2;
	if (n < 3 || job.ringStart.size() < 2)
		return false;
	try {
		CDT cdt;
		std::vector<CDT::Vertex_handle> vh(n);
		size_t distinct = n; // (points that are vertices of their own)
		if (!insertPoints(job, cdt, vh, distinct))
			return false;
		const bool constrained = allRingEdges(job, [&](size_t i, size_t j) {
			CDT::Face_handle fh;
			int idx;
			if (cdt.is_edge(vh[i], vh[j], fh, idx) && fh->is_constrained(idx))
				return false; // the same edge twice: the domain is degenerate
			cdt.insert_constraint(vh[i], vh[j]);
			return true;
		});
		if (!constrained)
			return false;
		if (cdt.number_of_vertices() != distinct)
			return false;
		if (cdt.dimension() != 2)
			return false; // every ring vertex projects onto one line: no area to triangulate
		markNesting(cdt);
		if (!ringsBoundInside(job, cdt, vh))
			return false;
		insideTriangles(cdt, job);
		locateQueries(cdt, job);
	} catch (...) {
		return false; // crossing ring edges (or any CGAL precondition): not a valid domain
	}
	return !job.tris.empty();
}

} // namespace detail
} // namespace gausslod
