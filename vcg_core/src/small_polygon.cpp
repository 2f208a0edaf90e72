// 2.4 Re-triangulating a superface, fast path: one small ring (most superfaces at the fine levels)
// is triangulated here without CGAL, by ear clipping and Lawson flips, with every predicate
// evaluated in doubles and used only when its sign is certain (Shewchuk's error bounds for the
// plain double evaluation, doubled). Whatever is not certain, or not the common case, is left to
// the CGAL path (triangulateRings), which then decides: a cocircular quadruple, collinear
// consecutive vertices, a vertex on or near another edge, crossing edges, a clockwise ring, a
// query on an edge, a query whose answer CGAL's walk would pick among several.
//
// When this path answers, it answers as the CGAL path does. Its triangles are those of CGAL's
// constrained Delaunay triangulation (in another order): every diagonal is certainly locally
// Delaunay, so no four vertices of a quad are cocircular and the triangulation is unique. A query
// inside the ring is given the one triangle it is certainly inside. A query outside the ring is
// located as CGAL locates it in its triangulation of the convex hull: in a pocket (the region
// between a hull edge and the ring, triangulated the same way) or beyond exactly one hull edge,
// and given the inside triangle across the one ring edge of that face (none: -1; two: not
// handled, CGAL's choice depends on its storage order).
#include "engine.h"

#include <algorithm>
#include <cmath>

namespace gausslod {
namespace detail {

namespace {

constexpr double kEps = 1.1102230246251565e-16; // 2^-53
constexpr double kOrientBound = 2 * (3.0 + 16.0 * kEps) * kEps;
constexpr double kInCircleBound = 2 * (10.0 + 96.0 * kEps) * kEps;
constexpr size_t kMaxTris = kSmallRingMax - 2;

struct P2 {
	double x, y;
};

// +1: c left of a -> b, -1: right, 0: not certain (or not finite)
int orient(const P2 &a, const P2 &b, const P2 &c)
{
	const double l = (a.x - c.x) * (b.y - c.y), r = (a.y - c.y) * (b.x - c.x);
	const double det = l - r, bound = kOrientBound * (std::fabs(l) + std::fabs(r));
	return det > bound ? 1 : det < -bound ? -1 : 0;
}

// +1: d inside the circle through a, b, c (counterclockwise), -1: outside, 0: not certain
int inCircle(const P2 &a, const P2 &b, const P2 &c, const P2 &d)
{
	const double adx = a.x - d.x, ady = a.y - d.y, bdx = b.x - d.x, bdy = b.y - d.y;
	const double cdx = c.x - d.x, cdy = c.y - d.y;
	const double bc1 = bdx * cdy, bc2 = cdx * bdy, ca1 = cdx * ady, ca2 = adx * cdy;
	const double ab1 = adx * bdy, ab2 = bdx * ady;
	const double al = adx * adx + ady * ady, bl = bdx * bdx + bdy * bdy, cl = cdx * cdx + cdy * cdy;
	const double det = al * (bc1 - bc2) + bl * (ca1 - ca2) + cl * (ab1 - ab2);
	const double permanent = (std::fabs(bc1) + std::fabs(bc2)) * al +
	                         (std::fabs(ca1) + std::fabs(ca2)) * bl +
	                         (std::fabs(ab1) + std::fabs(ab2)) * cl;
	const double bound = kInCircleBound * permanent;
	return det > bound ? 1 : det < -bound ? -1 : 0;
}

bool certainlyInside(const P2 *p, const int32_t *t, const P2 &x)
{
	return orient(p[t[0]], p[t[1]], x) > 0 && orient(p[t[1]], p[t[2]], x) > 0 &&
	       orient(p[t[2]], p[t[0]], x) > 0;
}

// Constrained Delaunay triangulation of a simple counterclockwise polygon (point indices
// poly[0..m), m <= kSmallRingMax, no straight vertex: certified by the caller): ear clipping, then
// Lawson flips of the diagonals. Appends counterclockwise triangles to tri / nt. False when a
// predicate it needs is not certain (or a cocircular quad makes the answer not unique).
bool triangulatePolygon(const P2 *p, const int32_t *poly, size_t m, int32_t *tri, size_t &nt)
{
	const size_t first = nt;
	size_t nxt[kSmallRingMax] = {}, prv[kSmallRingMax] = {};
	for (size_t i = 0; i < m; ++i)
		nxt[i] = i + 1 == m ? 0 : i + 1, prv[i] = i == 0 ? m - 1 : i - 1;
	auto emit = [&](size_t a, size_t b, size_t c) {
		tri[3 * nt] = poly[a], tri[3 * nt + 1] = poly[b], tri[3 * nt + 2] = poly[c];
		++nt;
	};
	// ears: a certainly convex corner with every other remaining vertex certainly outside
	size_t v = 0;
	for (size_t remaining = m, tries = 0; remaining > 3;) {
		const size_t a = prv[v], c = nxt[v];
		const P2 &pa = p[poly[a]], &pv = p[poly[v]], &pc = p[poly[c]];
		bool ear = orient(pa, pv, pc) > 0;
		for (size_t r = nxt[c]; ear && r != a; r = nxt[r]) {
			const P2 &pr = p[poly[r]];
			ear = orient(pa, pv, pr) < 0 || orient(pv, pc, pr) < 0 || orient(pc, pa, pr) < 0;
		}
		if (!ear) {
			if (++tries > remaining)
				return false;
			v = c;
			continue;
		}
		emit(a, v, c);
		nxt[a] = c, prv[c] = a;
		--remaining, tries = 0;
		v = c;
	}
	if (orient(p[poly[prv[v]]], p[poly[v]], p[poly[nxt[v]]]) <= 0)
		return false;
	emit(prv[v], v, nxt[v]);

	// flips until every diagonal is certainly locally Delaunay (polygon edges stay)
	int32_t pos[kSmallRingMax]; // point index (< kSmallRingMax) -> position in poly
	for (size_t i = 0; i < m; ++i)
		pos[poly[i]] = int32_t(i);
	auto boundary = [&](int32_t a, int32_t b) {
		const int32_t d = std::abs(pos[a] - pos[b]);
		return d == 1 || d == int32_t(m) - 1;
	};
	size_t flips = 0;
	for (bool flipped = true; flipped;) {
		flipped = false;
		for (size_t t = first; t < nt; ++t)
			for (size_t k = 0; k < 3; ++k) {
				const int32_t a = tri[3 * t + k], b = tri[3 * t + (k + 1) % 3];
				if (a > b || boundary(a, b))
					continue; // (each diagonal once, from its side where it runs upwards)
				const int32_t c = tri[3 * t + (k + 2) % 3];
				size_t u = first, j = 3;
				for (; u < nt && j == 3; ++u)
					for (j = 0; j < 3; ++j)
						if (tri[3 * u + j] == b && tri[3 * u + (j + 1) % 3] == a)
							break;
				if (j == 3)
					return false; // (cannot happen: a diagonal has two sides)
				--u;
				const int32_t d = tri[3 * u + (j + 2) % 3];
				const int in = inCircle(p[a], p[b], p[c], p[d]);
				if (in == 0)
					return false; // cocircular (or not certain)
				if (in > 0) {     // quad a d b c (counterclockwise): diagonal c d instead of a b
					if (++flips > 4 * m * m)
						return false; // (cannot happen: certain flips end)
					tri[3 * t] = c, tri[3 * t + 1] = a, tri[3 * t + 2] = d;
					tri[3 * u] = d, tri[3 * u + 1] = b, tri[3 * u + 2] = c;
					flipped = true;
				}
			}
	}
	return true;
}

// What lies outside the ring, as CGAL's triangulation of the convex hull has it: the pockets'
// triangles and the hull edges (each with its ring-order start vertex).
struct Outside {
	int32_t tri[3 * 2 * kSmallRingMax];
	size_t nt = 0;
	int32_t hull[kSmallRingMax]; ///< hull vertices, counterclockwise (= ring order)
	size_t nh = 0;
};

bool buildOutside(const P2 *p, size_t n, Outside &o)
{
	// Andrew's monotone chain on the ring's vertices (a straight hull vertex: not certain)
	int32_t order[kSmallRingMax];
	for (size_t i = 0; i < n; ++i)
		order[i] = int32_t(i);
	std::sort(order, order + n, [&](int32_t a, int32_t b) {
		return p[a].x < p[b].x || (p[a].x == p[b].x && p[a].y < p[b].y);
	});
	int32_t h[2 * kSmallRingMax];
	size_t k = 0;
	for (int pass = 0; pass < 2; ++pass) {
		const size_t base = k;
		for (size_t s = 0; s < n; ++s) {
			const int32_t q = pass == 0 ? order[s] : order[n - 1 - s];
			while (k >= base + 2) {
				const int o = orient(p[h[k - 2]], p[h[k - 1]], p[q]);
				if (o == 0)
					return false;
				if (o > 0)
					break;
				--k;
			}
			h[k++] = q;
		}
		--k; // (the last point starts the other chain)
	}
	if (k < 3)
		return false;
	// in ring order, starting from the lowest ring index
	const size_t start = size_t(std::min_element(h, h + k) - h);
	for (size_t i = 0; i < k; ++i)
		o.hull[i] = h[(start + i) % k];
	o.nh = k;
	for (size_t i = 1; i < k; ++i)
		if (o.hull[i] <= o.hull[i - 1])
			return false; // (cannot happen for a simple counterclockwise ring)
	// every other ring vertex certainly inside every hull edge
	for (size_t e = 0; e < k; ++e) {
		const int32_t a = o.hull[e], b = o.hull[(e + 1) % k];
		for (size_t i = 0; i < n; ++i)
			if (int32_t(i) != a && int32_t(i) != b && orient(p[a], p[b], p[i]) <= 0)
				return false;
	}
	// pockets: hull edge a -> b, then the ring back from b to a
	for (size_t e = 0; e < k; ++e) {
		const int32_t a = o.hull[e], b = o.hull[(e + 1) % k];
		const int32_t along = (b - a + int32_t(n)) % int32_t(n);
		if (along == 1)
			continue; // (a ring edge)
		int32_t poly[kSmallRingMax];
		size_t m = 0;
		poly[m++] = a;
		for (int32_t s = 0; s < along; ++s)
			poly[m++] = (b - s + int32_t(n)) % int32_t(n);
		if (!triangulatePolygon(p, poly, m, o.tri, o.nt))
			return false;
	}
	return true;
}

// A simple, counterclockwise ring of n points with no straight vertex, all certain.
bool certainSimpleRing(const P2 *p, size_t n)
{
	auto nextOf = [n](size_t i) { return i + 1 == n ? 0 : i + 1; };
	auto prevOf = [n](size_t i) { return i == 0 ? n - 1 : i - 1; };
	size_t lowest = 0; // (lexicographically smallest: convex, its turn is the ring's orientation)
	for (size_t i = 0; i < n; ++i) {
		if (orient(p[prevOf(i)], p[i], p[nextOf(i)]) == 0)
			return false;
		if (p[i].x < p[lowest].x || (p[i].x == p[lowest].x && p[i].y < p[lowest].y))
			lowest = i;
	}
	if (orient(p[prevOf(lowest)], p[lowest], p[nextOf(lowest)]) < 0)
		return false;
	for (size_t i = 0; i < n; ++i) {
		const P2 &a = p[i], &b = p[nextOf(i)];
		for (size_t j = i + 2; j < n; ++j) {
			if (i == 0 && j == n - 1)
				continue; // (adjacent through vertex 0)
			const P2 &c = p[j], &d = p[nextOf(j)];
			if (std::max(a.x, b.x) < std::min(c.x, d.x) ||
			    std::max(c.x, d.x) < std::min(a.x, b.x) ||
			    std::max(a.y, b.y) < std::min(c.y, d.y) || std::max(c.y, d.y) < std::min(a.y, b.y))
				continue; // (boxes apart)
			const int o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a),
			          o4 = orient(c, d, b);
			if (o1 == 0 || o2 == 0 || o3 == 0 || o4 == 0 || (o1 != o2 && o3 != o4))
				return false; // touching, crossing or not certain
		}
	}
	return true;
}

// The ring's triangulation and, per ring edge i -> i+1, the inside triangle on it; the outside
// of the ring (its hull's pockets) once a query needs it.
struct SmallTriangulation {
	const P2 *p;
	size_t n;
	int32_t tri[3 * kMaxTris];
	size_t nt = 0;
	int32_t across[kSmallRingMax];
	Outside out;
	bool outsideBuilt = false;

	size_t nextOf(size_t i) const { return i + 1 == n ? 0 : i + 1; }
	// the answer for a face outside the ring: the inside triangle across its one ring edge
	// (-1: none, -2: several)
	int32_t acrossRingEdges(const int32_t *t) const
	{
		int32_t found = -1;
		for (size_t k = 0; k < 3; ++k) {
			const int32_t a = t[k], b = t[(k + 1) % 3];
			if (size_t(a) == nextOf(size_t(b))) // (outside, a ring edge runs backwards)
				found = found == -1 ? across[b] : -2;
		}
		return found;
	}
	bool triangulate();
	bool locateOutside(const P2 &x, int32_t &answer);
};

bool SmallTriangulation::triangulate()
{
	int32_t ring[kSmallRingMax];
	for (size_t i = 0; i < n; ++i)
		ring[i] = int32_t(i);
	if (!triangulatePolygon(p, ring, n, tri, nt))
		return false;
	for (size_t t = 0; t < nt; ++t)
		for (size_t k = 0; k < 3; ++k) {
			const int32_t a = tri[3 * t + k], b = tri[3 * t + (k + 1) % 3];
			if (size_t(b) == nextOf(size_t(a)))
				across[a] = int32_t(t);
		}
	return true;
}

// The triangle CGAL's path gives a query x in no inside triangle (see acrossRingEdges); false if
// that is not certain.
bool SmallTriangulation::locateOutside(const P2 &x, int32_t &answer)
{
	if (!outsideBuilt && !buildOutside(p, n, out))
		return false;
	outsideBuilt = true;
	answer = -3;
	for (size_t t = 0; t < out.nt && answer == -3; ++t)
		if (certainlyInside(p, &out.tri[3 * t], x))
			answer = acrossRingEdges(&out.tri[3 * t]);
	if (answer == -3) { // beyond the hull: CGAL's walk ends at a hull edge that sees it;
		// all of those must give the same answer
		for (size_t e = 0; e < out.nh; ++e) {
			const int32_t a = out.hull[e], b = out.hull[(e + 1) % out.nh];
			const int o = orient(p[a], p[b], x);
			if (o == 0)
				return false;
			const int32_t here = size_t(b) == nextOf(size_t(a)) ? across[a] : -1;
			if (o < 0 && answer != -3 && here != answer)
				return false;
			if (o < 0)
				answer = here;
		}
		if (answer == -3)
			return false; // (inside the hull but in no face: on an edge)
	}
	return answer != -2;
}

} // namespace

SmallRing triangulateSmallRing(TriangulationJob &job)
{
	const size_t n = job.xy.size() / 2;
	if (job.ringStart.size() != 2 || n < 4 || n > kSmallRingMax || size_t(job.ringStart[1]) != n ||
	    job.ringStart[0] != 0)
		return SmallRing::NotHandled;
	P2 p[kSmallRingMax];
	for (size_t i = 0; i < n; ++i)
		p[i] = P2{job.xy[2 * i], job.xy[2 * i + 1]};
	if (!certainSimpleRing(p, n))
		return SmallRing::NotHandled;
	SmallTriangulation st;
	st.p = p, st.n = n;
	if (!st.triangulate())
		return SmallRing::NotHandled;
	const int32_t *tri = st.tri;
	const size_t nt = st.nt;
	// queries (starting with the previous query's triangle)
	const size_t nq = job.queryXY.size() / 2;
	job.queryTri.assign(nq, -1);
	size_t hint = 0;
	for (size_t q = 0; q < nq; ++q) {
		const P2 x{job.queryXY[2 * q], job.queryXY[2 * q + 1]};
		bool found = false;
		for (size_t s = 0; s < nt && !found; ++s) {
			const size_t t = s == 0 ? hint : (s <= hint ? s - 1 : s);
			if (certainlyInside(p, &tri[3 * t], x))
				found = true, hint = t;
		}
		if (found) {
			job.queryTri[q] = int32_t(hint);
			continue;
		}
		int32_t answer;
		if (!st.locateOutside(x, answer))
			return SmallRing::NotHandled;
		job.queryTri[q] = answer;
	}
	job.tris.assign(tri, tri + 3 * nt);
	job.constrained.resize(nt);
	for (size_t t = 0; t < nt; ++t) {
		uint8_t bits = 0;
		for (size_t k = 0; k < 3; ++k) {
			const size_t a = size_t(tri[3 * t + k]), b = size_t(tri[3 * t + (k + 1) % 3]);
			if (b == st.nextOf(a) || a == st.nextOf(b))
				bits |= uint8_t(1u << k);
		}
		job.constrained[t] = bits;
	}
	return SmallRing::Done;
}

} // namespace detail
} // namespace gausslod
