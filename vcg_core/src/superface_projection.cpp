// 2.4 A superface seen on the plane of its projection (superface_projection.h): its kept ring
// vertices and normal, its projected job; and the job of triangles given from outside
// (jobFromTriangles, for vertex placement).
#include "superface_projection.h"

#include <stdexcept>

namespace gausslod {
namespace detail {

namespace {

// w.job.same for w.ringVerts: a vertex met again on the rings (the superface's border touches
// itself there) is the vertex of its first position. (w.vertQuery, -1 between superfaces, marks
// the vertices seen here.)
void sameRingVertices(const Topology &t, Scratch &w)
{
	w.job.same.clear();
	if (w.vertQuery.size() != t.nV)
		w.vertQuery.assign(t.nV, -1);
	for (size_t i = 0; i < w.ringVerts.size(); ++i) {
		int32_t &seen = w.vertQuery[size_t(w.ringVerts[i])];
		if (seen < 0) {
			seen = int32_t(i);
			continue;
		}
		if (w.job.same.empty())
			w.job.same.assign(w.ringVerts.size(), -1);
		w.job.same[i] = seen;
	}
	for (const int32_t v : w.ringVerts)
		w.vertQuery[size_t(v)] = -1;
}

} // namespace

bool keptRingVertices(const TriangulationInput &in, int32_t s, Scratch &w)
{
	w.ringVerts.clear();
	w.ringUV.clear();
	w.ringVertStart.assign(1, 0);
	const bool uv = in.limits.maxTexError > 0;
	for (int32_t r = in.rings.sfStart[size_t(s)]; r < in.rings.sfStart[size_t(s) + 1]; ++r) {
		for (int32_t i = in.rings.start[size_t(r)]; i < in.rings.start[size_t(r) + 1]; ++i) {
			const int32_t v = in.t.heFrom(in.rings.he[size_t(i)]);
			if (!in.b.keep[size_t(v)])
				continue;
			w.ringVerts.push_back(v);
			if (uv) {
				const int32_t h = in.rings.he[size_t(i)];
				w.ringUV.push_back(in.t.UV[2 * size_t(h)]);
				w.ringUV.push_back(in.t.UV[2 * size_t(h) + 1]);
			}
		}
		if (int32_t(w.ringVerts.size()) - w.ringVertStart.back() < 3)
			return false;
		w.ringVertStart.push_back(int32_t(w.ringVerts.size()));
	}
	sameRingVertices(in.t, w);
	return w.ringVertStart.size() >= 2;
}

// The triangulation job of superface s on the plane orthogonal to N (U x V = N): its kept ring
// vertices, the centroid of each of its faces as a query, and with the distance tolerance or the
// texture check every vertex of its faces once (see distanceCheck). `queriesKept`: the queries
// are those of the previous pass (the same faces, N and origin: only the vertices changed).
void projectSuperface(const TriangulationInput &in, int32_t s, const Vec3 &N, Scratch &w,
                      bool queriesKept)
{
	const Topology &t = in.t;
	const int32_t fb = in.faces.begin(s), fe = in.faces.end(s);
	const Vec3 U = planeAxis(N);
	const Vec3 V = N ^ U;
	const Vec3 origin = t.pos(w.ringVerts[0]);
	auto project = [&](const Vec3 &p, double *xy) {
		const Vec3 q = p - origin;
		xy[0] = q.dot(U), xy[1] = q.dot(V);
	};
	w.job.xy.resize(2 * w.ringVerts.size());
	for (size_t i = 0; i < w.ringVerts.size(); ++i)
		project(in.out(w.ringVerts[i]), &w.job.xy[2 * i]);
	w.job.ringStart = w.ringVertStart;
	if (queriesKept)
		return;
	w.job.queryXY.resize(2 * size_t(fe - fb));
	for (int32_t i = fb; i < fe; ++i) {
		const int32_t f = in.faces.face[size_t(i)];
		const Vec3 c = (t.pos(t.T[3 * f]) + t.pos(t.T[3 * f + 1]) + t.pos(t.T[3 * f + 2])) / 3.0;
		project(c, &w.job.queryXY[2 * size_t(i - fb)]);
	}
	if (!(in.limits.maxDistance > 0) && !(in.limits.maxTexError > 0))
		return;
	if (w.vertQuery.size() != t.nV)
		w.vertQuery.assign(t.nV, -1);
	w.cornerQuery.resize(3 * size_t(fe - fb));
	w.flip.queryVertex.clear();
	int32_t next = 0;
	for (int32_t i = fb; i < fe; ++i)
		for (int k = 0; k < 3; ++k) {
			const int32_t v = t.T[3 * in.faces.face[size_t(i)] + k];
			int32_t &q = w.vertQuery[size_t(v)];
			if (q < 0) {
				q = next++;
				w.touched.push_back(v);
				w.flip.queryVertex.push_back(v);
				double xy[2];
				project(t.pos(v), xy);
				w.job.queryXY.push_back(xy[0]);
				w.job.queryXY.push_back(xy[1]);
			}
			w.cornerQuery[3 * size_t(i - fb) + size_t(k)] = q;
		}
	for (const int32_t v : w.touched)
		w.vertQuery[size_t(v)] = -1;
	w.touched.clear();
}

bool projectionNormal(const TriangulationInput &in, int32_t s, Vec3 &N, bool &unchanged, Scratch &w)
{
	const Topology &t = in.t;
	const int32_t fb = in.faces.begin(s), fe = in.faces.end(s);
	const bool cache = fe - fb <= kMaxCachedNormals;
	w.sfNormal.resize(cache ? size_t(fe - fb) : 0);
	N = Vec3(0, 0, 0);
	for (int32_t i = fb; i < fe; ++i) {
		const int32_t f = in.faces.face[size_t(i)];
		Vec3 n;
		double area;
		t.faceNormal.normalAndArea(size_t(f), n, area); // (= faceNormal[f], faceArea[f])
		N += n * area;
		if (cache)
			w.sfNormal[size_t(i - fb)] = n;
	}
	if (!(N.Norm() > 0))
		return false;
	N.Normalize();
	unchanged = true;
	for (int32_t i = fb; i < fe; ++i) {
		const int32_t f = in.faces.face[size_t(i)];
		if (!(sfFaceNormal(in, s, i - fb, w).dot(N) > 1e-6))
			return false; // the projection on the best-fit plane folds
		for (int k = 0; k < 3; ++k)
			unchanged = unchanged && in.b.keep[size_t(t.T[3 * f + k])];
	}
	return true;
}

int32_t cornerAt(const TriangulationInput &in, int32_t s, int32_t v)
{
	const Topology &t = in.t;
	for (int32_t q = t.vfStart[size_t(v)]; q < t.vfStart[size_t(v) + 1]; ++q) {
		const int32_t f = t.vfFace[size_t(q)];
		if (in.p.label[size_t(f)] == s)
			for (int k = 0; k < 3; ++k)
				if (t.T[3 * f + k] == v)
					return 3 * f + k;
	}
	throw std::logic_error("an inserted vertex is no vertex of its superface");
}

namespace {

// jobFromTriangles takes the previous query's triangle for a query whose smallest barycentric
// coordinate in it is above this (far from rounding: no other triangle can claim the query).
constexpr double kHintMargin = 1e-9;

// After the ring vertices (w.ringVerts[0 .. ringCount)), the inside vertices of the triangles, in
// triangle order, each once; w.localOf[v] = each vertex's job index (its first position).
void addInsideVertices(const TriangulationInput &in, int32_t s, const int32_t *tris, size_t ntri,
                       Scratch &w)
{
	const Topology &t = in.t;
	if (w.localOf.size() != t.nV)
		w.localOf.assign(t.nV, -1);
	for (size_t i = 0; i < w.ringVerts.size(); ++i)
		if (w.localOf[size_t(w.ringVerts[i])] < 0) // (a vertex met twice: its first position)
			w.localOf[size_t(w.ringVerts[i])] = int32_t(i);
	for (size_t k = 0; k < 3 * ntri; ++k) {
		const int32_t v = tris[k];
		if (w.localOf[size_t(v)] >= 0)
			continue;
		w.localOf[size_t(v)] = int32_t(w.ringVerts.size());
		w.ringVerts.push_back(v);
		if (in.limits.maxTexError > 0) { // (its texture coordinates: a corner of the superface)
			const int32_t corner = cornerAt(in, s, v);
			w.ringUV.push_back(t.UV[2 * size_t(corner)]);
			w.ringUV.push_back(t.UV[2 * size_t(corner) + 1]);
		}
	}
}

// The job's triangles (in job indices) and their projected corners (w.boundXY), twice their
// signed areas (w.triArea), and the grid over them (w.cellStart, w.cellTri).
void jobTriangles(const int32_t *tris, const uint8_t *bits, size_t ntri, Scratch &w,
                  TriangleGrid &grid)
{
	w.job.tris.resize(3 * ntri);
	w.job.constrained.resize(ntri);
	for (size_t k = 0; k < ntri; ++k) {
		for (size_t c = 0; c < 3; ++c)
			w.job.tris[3 * k + c] = w.localOf[size_t(tris[3 * k + c])];
		w.job.constrained[k] = uint8_t(bits[k] & kBorderBits);
	}
	w.boundXY.resize(6 * ntri);
	for (size_t k = 0; k < ntri; ++k)
		for (size_t c = 0; c < 3; ++c) {
			const double *xy = &w.job.xy[2 * size_t(w.job.tris[3 * k + c])];
			w.boundXY[6 * k + 2 * c] = xy[0], w.boundXY[6 * k + 2 * c + 1] = xy[1];
		}
	grid.build(w.boundXY.data(), ntri, w);
	w.triArea.resize(ntri); // (twice each triangle's signed area, once)
	for (size_t k = 0; k < ntri; ++k)
		w.triArea[k] = orient2(&w.boundXY[6 * k], &w.boundXY[6 * k + 2], &w.boundXY[6 * k + 4]);
}

// Every query in the triangle that holds it, else (just outside the triangles, at a border) the
// one it is least outside of among those of its grid cell, into w.job.queryTri.
//
// Consecutive queries (a face's centroid, the faces of a superface in order) mostly fall in the
// same triangle: the last triangle found is tried first, and taken if the query is inside it by
// more than kHintMargin of its barycentric coordinates, and only where the triangles all have one
// orientation: they then overlap only where the projection folds over itself, so elsewhere no
// other triangle holds such a query by the predicates below and the scan would find the same one
// (in a fold, the triangle tried first is taken: it lies over the query all the same).
void locateQueries(size_t ntri, const TriangleGrid &grid, Scratch &w)
{
	bool oneSide = true;
	for (size_t k = 0; k < ntri && oneSide; ++k)
		oneSide = w.triArea[0] > 0 ? w.triArea[k] > 0 : w.triArea[k] < 0;
	int32_t hint = -1;
	const size_t nq = w.job.queryXY.size() / 2;
	w.job.queryTri.assign(nq, -1);
	for (size_t q = 0; q < nq; ++q) {
		const double *p = &w.job.queryXY[2 * q];
		if (hint >= 0) {
			const double *a = &w.boundXY[6 * size_t(hint)], *b = a + 2, *d = a + 4;
			const double area = w.triArea[size_t(hint)];
			const double o0 = orient2(b, d, p), o1 = orient2(d, a, p), o2 = orient2(a, b, p);
			// (the smallest barycentric coordinate: orientation / area, of either sign)
			const double lo = area > 0 ? std::min({o0, o1, o2}) : std::max({o0, o1, o2});
			if (lo / area > kHintMargin) {
				w.job.queryTri[q] = hint;
				continue;
			}
		}
		const size_t c = size_t(grid.at(p[1], 1)) * size_t(grid.side) + size_t(grid.at(p[0], 0));
		double best = -HUGE_VAL;
		for (int32_t i = w.cellStart[c]; i < w.cellStart[c + 1]; ++i) {
			const size_t k = size_t(w.cellTri[size_t(i)]);
			const double *a = &w.boundXY[6 * k], *b = a + 2, *d = a + 4;
			const double area = w.triArea[k];
			if (!(std::fabs(area) > 0))
				continue;
			// the smallest barycentric coordinate of p, lo / area (>= 0: inside or on the
			// triangle, the first such one is taken; its sign is lo's or the opposite, so the
			// division is only needed to rank the triangles p is outside of)
			const double lo = std::min({orient2(b, d, p), orient2(d, a, p), orient2(a, b, p)});
			if (area > 0 ? lo >= 0 : lo <= 0) {
				w.job.queryTri[q] = int32_t(k);
				if (oneSide)
					hint = int32_t(k);
				break;
			}
			const double m = lo / area;
			if (m > best)
				best = m, w.job.queryTri[q] = int32_t(k);
		}
	}
}

} // namespace

bool jobFromTriangles(const TriangulationInput &in, int32_t s, const int32_t *tris,
                      const uint8_t *bits, size_t ntri, Vec3 &N, Scratch &w)
{
	bool unchanged = false;
	if (in.rings.broken[size_t(s)] || !projectionNormal(in, s, N, unchanged, w))
		return false;
	for (const int32_t v : w.steiner) // (the previous superface's)
		w.steinerMark[size_t(v)] = 0;
	w.steiner.clear();
	if (!keptRingVertices(in, s, w) || ntri == 0)
		return false;
	const size_t ringCount = w.ringVerts.size();
	addInsideVertices(in, s, tris, ntri, w);
	bool ok = true;
	const bool oneTriangle = w.ringVertStart.size() == 2 && ringCount == 3 && ntri == 1;
	if (!oneTriangle) {
		projectSuperface(in, s, N, w, false);
		TriangleGrid grid;
		jobTriangles(tris, bits, ntri, w, grid);
		locateQueries(ntri, grid, w);
	} else if (w.ringVerts.size() != 3) {
		ok = false;
	}
	for (const int32_t v : w.ringVerts)
		w.localOf[size_t(v)] = -1;
	return ok;
}

} // namespace detail
} // namespace gausslod
