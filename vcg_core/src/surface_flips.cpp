// Beyond the paper (with the distance tolerance): a data-dependent choice of diagonals. The
// constrained Delaunay triangulation of a superface picks its diagonals by angles alone; where a
// triangle is far from the removed vertices under it, flipping an edge it shares with a neighbour
// (the two forming a convex quadrilateral in the projection) is kept if it brings the farther of
// the two closer to the vertices under them. Fewer superfaces then need inside vertices or a
// split (greedy terrain simplification with data-dependent triangulation, as Garland and
// Heckbert's terrain work does). The same flips, measured at the face centroids too, polish the
// accepted triangulation of a superface (polishDiagonals, superface_triangulation.cpp).
#include "level_passes.h"

namespace gausslod {
namespace detail {

namespace {

// 2x the signed area of the 2D triangle (a, b, c).
inline double orient(const double *a, const double *b, const double *c)
{
	return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

// The triangulation being flipped: job.tris with, per half-edge 3k+e (edge e of triangle k, from
// corner e to corner e+1), the opposite half-edge (-1: a ring edge or none), and per triangle
// the list of queries it holds.
struct Mesh2 {
	TriangulationJob &job;
	FlipScratch &f;
	const TriangulationInput &in;
	const Topology &t;
	const std::vector<int32_t> &verts; ///< local vertex -> input vertex (Scratch::ringVerts)
	size_t faces;                      ///< centroid queries come first, then vertex queries
	const Vec3 &N;
	const LevelLimits &limits;
	/// with the face centroids' distances too: the superface's faces (else the vertices decide)
	const int32_t *centroidFace;

	const double *xy(int32_t v) const { return &job.xy[2 * size_t(v)]; }
	Vec3 pos(int32_t v) const { return in.out(verts[size_t(v)]); }

	// The distance of the vertex queries in list `head` to the plane of triangle (a, b, c), as
	// the tolerance measures it (checkDivisor); -1 if the triangle is degenerate.
	double error(int32_t a, int32_t b, int32_t c, int32_t head, const double *side = nullptr,
	             double sign = 0) const
	{
		const Vec3 A = pos(a);
		Vec3 n = (pos(b) - A) ^ (pos(c) - A);
		const double len = n.Norm();
		if (!(len > 0))
			return -1;
		n /= len;
		const double div = checkDivisor(limits, n, N);
		if (!(div > 0))
			return -1;
		double worst = 0;
		for (int32_t q = head; q >= 0; q = f.next[size_t(q)]) {
			if (size_t(q) < faces && !centroidFace)
				continue; // (a face centroid: the vertices decide)
			if (side && sign * orient(side, side + 2, &job.queryXY[2 * size_t(q)]) < 0)
				continue;
			Vec3 p;
			if (size_t(q) < faces) {
				const int32_t *c = &t.T[3 * size_t(centroidFace[q])];
				p = (t.pos(c[0]) + t.pos(c[1]) + t.pos(c[2])) / 3.0;
			} else {
				p = t.pos(f.queryVertex[size_t(q) - faces]);
			}
			worst = std::max(worst, std::fabs((p - A).dot(n)) / div);
		}
		return worst;
	}

	int32_t corner(int32_t h, int i) const { return job.tris[size_t(h - h % 3 + (h % 3 + i) % 3)]; }
	void setTwin(int32_t h, int32_t g)
	{
		f.twin[size_t(h)] = g;
		if (g >= 0)
			f.twin[size_t(g)] = h;
	}
	void listQueries(size_t ntri, size_t nq);
	void linkTwins(size_t ntri);
	bool tryFlip(int32_t h, double threshold, size_t &budget);
	void applyFlip(int32_t h, int32_t g, const int32_t abcd[4], const double cd[4], int32_t merged,
	               double e1, double e2);
};

// Per triangle, its queries (linked lists, in query order).
void Mesh2::listQueries(size_t ntri, size_t nq)
{
	f.head.assign(ntri, -1);
	f.next.assign(nq, -1);
	for (size_t q = nq; q-- > 0;) {
		const int32_t k = job.queryTri[q];
		if (k >= 0)
			f.next[q] = f.head[size_t(k)], f.head[size_t(k)] = int32_t(q);
	}
}

// Opposite half-edges (directed edges sorted by key); a ring edge has none (it is never flipped).
void Mesh2::linkTwins(size_t ntri)
{
	f.edges.clear();
	for (size_t h = 0; h < 3 * ntri; ++h) {
		const int32_t a = job.tris[h], b = job.tris[h - h % 3 + (h % 3 + 1) % 3];
		f.edges.push_back(std::make_pair(
		    uint64_t(uint32_t(std::min(a, b))) << 32 | uint32_t(std::max(a, b)), int32_t(h)));
	}
	std::sort(f.edges.begin(), f.edges.end());
	f.twin.assign(3 * ntri, -1);
	for (size_t i = 0; i + 1 < f.edges.size(); ++i)
		if (f.edges[i].first == f.edges[i + 1].first) {
			const int32_t h = f.edges[i].second, g = f.edges[i + 1].second;
			const bool ringEdge = (job.constrained[size_t(h / 3)] >> (h % 3)) & 1u;
			if (!ringEdge) // (a ring edge is never flipped)
				f.twin[size_t(h)] = g, f.twin[size_t(g)] = h;
			++i;
		}
}

// Flips the edge of half-edge h if both its triangles form a strictly convex quadrilateral and
// the flip brings the farther of them closer (each try costs one of `budget`). True if flipped.
bool Mesh2::tryFlip(int32_t h, double threshold, size_t &budget)
{
	const int32_t g = f.twin[size_t(h)];
	if (g < 0)
		return false;
	const int32_t k1 = h / 3, k2 = g / 3;
	const double before = std::max(f.err[size_t(k1)], f.err[size_t(k2)]);
	if (!(before > threshold))
		return false;
	// triangle k1 = (a, b, c) from h = a -> b, triangle k2 = (b, a, d) from g = b -> a; the
	// quadrilateral a, d, b, c (counterclockwise) gets the diagonal c - d
	const int32_t a = corner(h, 0), b = corner(h, 1), c = corner(h, 2), d = corner(g, 2);
	const double area =
	    std::fabs(orient(xy(a), xy(b), xy(c))) + std::fabs(orient(xy(b), xy(a), xy(d)));
	const double minArea = 1e-9 * area;
	if (!(orient(xy(a), xy(d), xy(c)) > minArea) || !(orient(xy(d), xy(b), xy(c)) > minArea))
		return false; // not strictly convex
	--budget;
	// both lists, split by the new diagonal: orient(c, d, p) < 0 in (a, d, c)
	const double cd[4] = {xy(c)[0], xy(c)[1], xy(d)[0], xy(d)[1]};
	int32_t merged = -1;
	for (const int32_t k : {k1, k2})
		for (int32_t q = f.head[size_t(k)], nx; q >= 0; q = nx) {
			nx = f.next[size_t(q)];
			f.next[size_t(q)] = merged, merged = q;
		}
	const double e1 = error(a, d, c, merged, cd, -1.0), e2 = error(d, b, c, merged, cd, 1.0);
	if (!(e1 >= 0 && e2 >= 0) || !(std::max(e1, e2) < before * (1 - 1e-9))) {
		// keep: rebuild the two lists as they were
		f.head[size_t(k1)] = f.head[size_t(k2)] = -1;
		for (int32_t q = merged, nx; q >= 0; q = nx) {
			nx = f.next[size_t(q)];
			const int32_t k = job.queryTri[size_t(q)];
			f.next[size_t(q)] = f.head[size_t(k)], f.head[size_t(k)] = q;
		}
		return false;
	}
	const int32_t abcd[4] = {a, b, c, d};
	applyFlip(h, g, abcd, cd, merged, e1, e2);
	return true;
}

// The flip of tryFlip: k1 = (a, d, c), k2 = (d, b, c), their twins, ring bits, queries (the
// merged list split by the diagonal cd) and errors e1, e2; their edges go back on the queue.
void Mesh2::applyFlip(int32_t h, int32_t g, const int32_t abcd[4], const double cd[4],
                      int32_t merged, double e1, double e2)
{
	const int32_t a = abcd[0], b = abcd[1], c = abcd[2], d = abcd[3];
	const int32_t k1 = h / 3, k2 = g / 3;
	const int32_t tAD = f.twin[size_t(3 * k2 + (g % 3 + 1) % 3)],
	              tDB = f.twin[size_t(3 * k2 + (g % 3 + 2) % 3)],
	              tBC = f.twin[size_t(3 * k1 + (h % 3 + 1) % 3)],
	              tCA = f.twin[size_t(3 * k1 + (h % 3 + 2) % 3)];
	const uint8_t c1 = job.constrained[size_t(k1)], c2 = job.constrained[size_t(k2)];
	auto bit = [](uint8_t bits, int32_t e) { return uint8_t((bits >> (e % 3)) & 1u); };
	const uint8_t bAD = bit(c2, g % 3 + 1), bDB = bit(c2, g % 3 + 2), bBC = bit(c1, h % 3 + 1),
	              bCA = bit(c1, h % 3 + 2);
	int32_t *t1 = &job.tris[3 * size_t(k1)], *t2 = &job.tris[3 * size_t(k2)];
	t1[0] = a, t1[1] = d, t1[2] = c;
	t2[0] = d, t2[1] = b, t2[2] = c;
	job.constrained[size_t(k1)] = uint8_t(bAD | 0u << 1 | bCA << 2);
	job.constrained[size_t(k2)] = uint8_t(bDB | bBC << 1 | 0u << 2);
	setTwin(3 * k1 + 0, tAD);
	setTwin(3 * k1 + 1, 3 * k2 + 2);
	setTwin(3 * k1 + 2, tCA);
	setTwin(3 * k2 + 0, tDB);
	setTwin(3 * k2 + 1, tBC);
	f.head[size_t(k1)] = f.head[size_t(k2)] = -1;
	for (int32_t q = merged, nx; q >= 0; q = nx) {
		nx = f.next[size_t(q)];
		const int32_t k = orient(cd, cd + 2, &job.queryXY[2 * size_t(q)]) < 0 ? k1 : k2;
		job.queryTri[size_t(q)] = k;
		f.next[size_t(q)] = f.head[size_t(k)], f.head[size_t(k)] = q;
	}
	f.err[size_t(k1)] = e1, f.err[size_t(k2)] = e2;
	for (const int32_t k : {k1, k2})
		for (int e = 0; e < 3; ++e)
			if (f.twin[3 * size_t(k) + size_t(e)] >= 0)
				f.queue.push_back(3 * k + e);
}

} // namespace

bool flipTowardSurface(const TriangulationInput &in, int32_t s, const Vec3 &N, Scratch &w,
                       double from, bool centroids)
{
	TriangulationJob &job = w.job;
	const size_t ntri = job.tris.size() / 3;
	const size_t faces = size_t(in.faces.end(s) - in.faces.begin(s));
	const size_t nq = job.queryTri.size();
	if (ntri < 2 || nq <= faces || w.flip.queryVertex.size() != nq - faces)
		return false;
	FlipScratch &f = w.flip;
	Mesh2 m{job,  f,           in,
	        in.t, w.ringVerts, faces,
	        N,    in.limits,   centroids ? &in.faces.face[size_t(in.faces.begin(s))] : nullptr};
	m.listQueries(ntri, nq);
	f.err.resize(ntri);
	const double threshold = from * in.limits.maxDistance;
	bool any = false;
	for (size_t k = 0; k < ntri; ++k) {
		const int32_t *v = &job.tris[3 * k];
		f.err[k] = m.error(v[0], v[1], v[2], f.head[k]);
		any = any || f.err[k] > threshold;
	}
	if (!any)
		return false;
	m.linkTwins(ntri);
	// the edges of the triangles too far, then of those a flip changes
	f.queue.clear();
	for (size_t k = 0; k < ntri; ++k)
		if (f.err[k] > threshold)
			for (int e = 0; e < 3; ++e)
				if (f.twin[3 * k + size_t(e)] >= 0)
					f.queue.push_back(int32_t(3 * k + size_t(e)));
	size_t budget = kFlipBudget * ntri;
	bool flipped = false;
	while (!f.queue.empty() && budget > 0) {
		const int32_t h = f.queue.back();
		f.queue.pop_back();
		flipped = m.tryFlip(h, threshold, budget) || flipped;
	}
	return flipped;
}

} // namespace detail
} // namespace gausslod
