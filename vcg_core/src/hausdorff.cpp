// The certified Hausdorff distance (hausdorff.h, docs/DESIGN.md 52).
//
// One way, from triangles A to triangles B: the distance to B is computed exactly at every vertex
// of A (the largest is a lower bound of the Hausdorff distance). A triangle of A (a piece) is
// then bounded over all its points, cheapest first:
// - the distance to B is 1-Lipschitz (a corner's distance plus the distance to that corner), and
//   the distance to one triangle of B is convex, so over a piece it is largest at a corner (the
//   triangles of B nearest to the corners are the candidates);
// - cover: where the triangles of B near the piece, seen along its normal, cover it with one
//   orientation and their patch's border stays off it, each point of the piece lies over one of
//   them, and the part of the piece over a triangle is bounded at that part's corners;
// - split: the piece cut by planes between the candidate triangles (and those across their
//   edges), each part bounded at its corners by the best candidate.
// A piece whose bound is above (1 + eps) x the lower bound is cut in four at its edge midpoints
// (new distances: the lower bound grows) until every piece is within the factor.
#include "hausdorff.h"

#include <queue>

namespace gausslod {
namespace detail {

namespace {

constexpr int kLeafSize = 4;

double segmentDistance2(const Vec3 &p, const Vec3 &a, const Vec3 &b)
{
	const Vec3 ab = b - a;
	const double l2 = ab.SquaredNorm();
	const double t = l2 > 0 ? std::min(1.0, std::max(0.0, (p - a).dot(ab) / l2)) : 0.0;
	return (p - (a + ab * t)).SquaredNorm();
}

double boxDistance2(const Vec3 &p, const Vec3 &lo, const Vec3 &hi)
{
	double d2 = 0;
	for (int k = 0; k < 3; ++k) {
		const double e = p[k] < lo[k] ? lo[k] - p[k] : p[k] > hi[k] ? p[k] - hi[k] : 0.0;
		d2 += e * e;
	}
	return d2;
}

// A piece of a triangle of A: its corners, their distances to B and the triangles of B nearest
// to them, and an upper bound of the distance to B over it.
struct Piece {
	Vec3 p[3];
	double d[3];
	int32_t n[3];
	bool exact[3]; ///< d is the distance to the whole set (else only to triangle n: above it)
	double u;
	BoundBy by; ///< which bound gave u
	bool operator<(const Piece &o) const { return u < o.u; }
};

// A convex polygon of a piece (the piece cut by planes), with each corner's distance to each
// candidate triangle.
constexpr int kPolyCorners = 16;
struct Poly {
	Vec3 v[kPolyCorners];
	int n = 0;
};

// Cuts `in` by the plane m.(x - o) = 0 into its part below (m.(x - o) <= 0) and above. False
// (nothing cut) if a part would have more corners than a Poly holds: a convex polygon gains at
// most one per cut, so only a piece cut many times, or rounding, gets there.
bool cut(const Poly &in, const Vec3 &m, const Vec3 &o, Poly &below, Poly &above)
{
	below.n = above.n = 0;
	double s[kPolyCorners];
	int crossings = 0;
	for (int i = 0; i < in.n; ++i)
		s[i] = m.dot(in.v[i] - o);
	for (int i = 0; i < in.n; ++i) {
		const int j = i + 1 == in.n ? 0 : i + 1;
		crossings += (s[i] < 0 && s[j] > 0) || (s[i] > 0 && s[j] < 0);
	}
	if (in.n + crossings > kPolyCorners)
		return false;
	for (int i = 0; i < in.n; ++i) {
		const int j = i + 1 == in.n ? 0 : i + 1;
		if (s[i] <= 0)
			below.v[below.n++] = in.v[i];
		if (s[i] >= 0)
			above.v[above.n++] = in.v[i];
		if ((s[i] < 0 && s[j] > 0) || (s[i] > 0 && s[j] < 0)) {
			const double t = s[i] / (s[i] - s[j]);
			const Vec3 x = in.v[i] + (in.v[j] - in.v[i]) * t;
			below.v[below.n++] = x;
			above.v[above.n++] = x;
		}
	}
	return true;
}

// The plane between triangles f and g of `to` that cuts a piece near both into the part nearer
// to f and the part nearer to g (for two triangles with an edge in common: the plane through
// that edge bisecting their dihedral angle). Any plane gives a valid bound; this one a tight one.
void between(const TriangleTree &to, int32_t f, int32_t g, Vec3 &m, Vec3 &o)
{
	const int32_t *T = to.T();
	const double *P = to.P();
	auto at = [&](int32_t i) {
		return Vec3(P[3 * size_t(i)], P[3 * size_t(i) + 1], P[3 * size_t(i) + 2]);
	};
	Vec3 a[3], b[3];
	for (int k = 0; k < 3; ++k)
		a[k] = at(T[3 * size_t(f) + size_t(k)]), b[k] = at(T[3 * size_t(g) + size_t(k)]);
	Vec3 nf = (a[1] - a[0]) ^ (a[2] - a[0]), ng = (b[1] - b[0]) ^ (b[2] - b[0]);
	const double lf = nf.Norm(), lg = ng.Norm();
	if (lf > 0)
		nf /= lf;
	if (lg > 0)
		ng /= lg;
	Vec3 up = nf + ng;
	if (!(up.SquaredNorm() > 1e-12))
		up = nf;
	const Vec3 cf = (a[0] + a[1] + a[2]) / 3.0, cg = (b[0] + b[1] + b[2]) / 3.0;
	int shared[3], ns = 0;
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j)
			if (T[3 * size_t(f) + size_t(i)] == T[3 * size_t(g) + size_t(j)] && ns < 3)
				shared[ns++] = i;
	if (ns == 2) {
		const Vec3 e = a[shared[1]] - a[shared[0]];
		m = e ^ up;
		o = a[shared[0]];
		if (m.dot(cg - cf) < 0)
			m = -m;
		if (m.SquaredNorm() > 0)
			return;
	}
	// (otherwise the plane where the two planes' signed distances are equal, if they are not
	// parallel; else the plane halfway between the centroids, across the mean normal)
	const Vec3 w = nf - ng;
	const double w2 = w.SquaredNorm();
	if (w2 > 1e-6 && lf > 0 && lg > 0) {
		m = w;
		o = w * ((nf.dot(a[0]) - ng.dot(b[0])) / w2);
		return;
	}
	m = cg - cf;
	const double u2 = up.SquaredNorm();
	if (u2 > 0)
		m -= up * (m.dot(up) / u2);
	o = ns >= 1 ? a[shared[0]] : (cf + cg) * 0.5;
}

// The triangles nearest to a piece's corners and those across their edges (at most 12).
int gather(const TriangleTree &to, const Piece &pc, int32_t *out)
{
	int n = 0;
	for (int k = 0; k < 3; ++k)
		if (pc.n[k] >= 0 && std::find(out, out + n, pc.n[k]) == out + n)
			out[n++] = pc.n[k];
	const int first = n;
	for (int c = 0; c < first; ++c)
		for (int k = 0; k < 3; ++k) {
			const int32_t g = to.across(out[c])[k];
			if (g >= 0 && std::find(out, out + n, g) == out + n)
				out[n++] = g;
		}
	return n;
}

// 2D polygon clipping for the cover bound: keeps the part of `in` left of a->b (s = +1) or
// right of it (s = -1).
struct Poly2 {
	double x[kPolyCorners], y[kPolyCorners];
	int n = 0;
};

// False (out empty) if the part would have more corners than a Poly2 holds (see cut).
bool clip2(const Poly2 &in, double ax, double ay, double bx, double by, double s, Poly2 &out)
{
	out.n = 0;
	double side[kPolyCorners];
	int crossings = 0;
	for (int i = 0; i < in.n; ++i)
		side[i] = s * ((bx - ax) * (in.y[i] - ay) - (by - ay) * (in.x[i] - ax));
	for (int i = 0; i < in.n; ++i) {
		const int j = i + 1 == in.n ? 0 : i + 1;
		crossings += (side[i] > 0 && side[j] < 0) || (side[i] < 0 && side[j] > 0);
	}
	if (in.n + crossings > kPolyCorners)
		return false;
	for (int i = 0; i < in.n; ++i) {
		const int j = i + 1 == in.n ? 0 : i + 1;
		if (side[i] >= 0)
			out.x[out.n] = in.x[i], out.y[out.n++] = in.y[i];
		if ((side[i] > 0 && side[j] < 0) || (side[i] < 0 && side[j] > 0)) {
			const double t = side[i] / (side[i] - side[j]);
			out.x[out.n] = in.x[i] + (in.x[j] - in.x[i]) * t;
			out.y[out.n++] = in.y[i] + (in.y[j] - in.y[i]) * t;
		}
	}
	return true;
}

double area2(const Poly2 &p)
{
	double a = 0;
	for (int i = 0; i < p.n; ++i) {
		const int j = i + 1 == p.n ? 0 : i + 1;
		a += p.x[i] * p.y[j] - p.x[j] * p.y[i];
	}
	return 0.5 * a;
}

// Whether segment a-b meets the triangle q (counter-clockwise) grown by `margin` (shrunk if it is
// negative).
bool segmentMeetsTriangle(const double *a, const double *b, const double (*q)[2], double margin)
{
	auto inside = [&](const double *p) {
		for (int k = 0; k < 3; ++k) {
			const double *u = q[k], *w = q[(k + 1) % 3];
			const double ex = w[0] - u[0], ey = w[1] - u[1];
			if (ex * (p[1] - u[1]) - ey * (p[0] - u[0]) < -margin * std::sqrt(ex * ex + ey * ey))
				return false;
		}
		return true;
	};
	if (inside(a) || inside(b))
		return true;
	// (the segment cut to the triangle's edges' half-planes: something left = it meets)
	double t0 = 0, t1 = 1;
	for (int k = 0; k < 3; ++k) {
		const double *u = q[k], *w = q[(k + 1) % 3];
		const double ex = w[0] - u[0], ey = w[1] - u[1];
		const double m = margin * std::sqrt(ex * ex + ey * ey);
		const double fa = ex * (a[1] - u[1]) - ey * (a[0] - u[0]) + m;
		const double fb = ex * (b[1] - u[1]) - ey * (b[0] - u[0]) + m;
		if (fa < 0 && fb < 0)
			return false;
		if (fa < 0)
			t0 = std::max(t0, fa / (fa - fb));
		else if (fb < 0)
			t1 = std::min(t1, fa / (fa - fb));
	}
	return t0 <= t1;
}

// The cover bound of a piece P over many triangles of B: if the triangles of B near P, seen
// along P's normal, cover P once or more with one orientation and the border of that patch
// stays outside P, every point p of P lies over (or under) a triangle t of the patch, in the
// part of P that t covers: p is then at most the largest distance from t of that part's corners
// (convexity). Returns that bound, or HUGE_VAL where the patch does not prove the cover (or
// a part's bound is above `target`: the piece is then cut anyway).
double coverBound(const TriangleTree &to, const Piece &pc, double target)
{
	const Vec3 e1r = pc.p[1] - pc.p[0], nr = e1r ^ (pc.p[2] - pc.p[0]);
	const double ln = nr.Norm(), l1 = e1r.Norm();
	if (!(ln > 0) || !(l1 > 0) || !std::isfinite(target))
		return HUGE_VAL;
	const Vec3 n = nr / ln, e1 = e1r / l1, e2 = n ^ e1;
	Vec3 lo = pc.p[0], hi = lo;
	for (int k = 1; k < 3; ++k)
		for (int j = 0; j < 3; ++j)
			lo[j] = std::min(lo[j], pc.p[k][j]), hi[j] = std::max(hi[j], pc.p[k][j]);
	// (a triangle farther than the target from P would bound its part above the target)
	const Vec3 pad(target, target, target);
	constexpr int kCap = 256;
	int32_t near[kCap];
	int nn = 0;
	if (!to.collect(lo - pad, hi + pad, near, nn, kCap))
		return HUGE_VAL;
	const int32_t *T = to.T();
	const double *P = to.P();
	auto at2 = [&](int32_t i, double *o) {
		const Vec3 d(P[3 * size_t(i)] - pc.p[0][0], P[3 * size_t(i) + 1] - pc.p[0][1],
		             P[3 * size_t(i) + 2] - pc.p[0][2]);
		o[0] = d.dot(e1), o[1] = d.dot(e2);
	};
	Poly2 piece;
	double q[3][2];
	for (int k = 0; k < 3; ++k) {
		const Vec3 d = pc.p[k] - pc.p[0];
		q[k][0] = piece.x[k] = d.dot(e1), q[k][1] = piece.y[k] = d.dot(e2);
	}
	piece.n = 3;
	const double qlo[2] = {std::min({q[0][0], q[1][0], q[2][0]}),
	                       std::min({q[0][1], q[1][1], q[2][1]})},
	             qhi[2] = {std::max({q[0][0], q[1][0], q[2][0]}),
	                       std::max({q[0][1], q[1][1], q[2][1]})};
	const double pieceArea = area2(piece);
	// (the patch's border may run along P's edges, as where a triangle of B is P itself: it is
	// checked against P shrunk by 1e-7 of its inradius, and the points of P outside that are
	// within 1e-7 x P's longest edge of it, towards P's incentre: the bound is raised by that;
	// a sliver is checked against P grown instead)
	double perimeter = 0, longest = 0;
	for (int k = 0; k < 3; ++k) {
		const double e = std::hypot(q[(k + 1) % 3][0] - q[k][0], q[(k + 1) % 3][1] - q[k][1]);
		perimeter += e, longest = std::max(longest, e);
	}
	const double inradius = 2 * pieceArea / perimeter;
	const bool shrunk = inradius >= 1e-6 * l1;
	const double margin = shrunk ? -1e-7 * inradius : 1e-9 * l1;
	const double edgePad = shrunk ? 1e-7 * longest : 0.0;
	int32_t patch[kCap];
	int np = 0;
	int orient = 0;
	double covered = 0, bound2 = 0;
	const double target2 = target * target;
	for (int c = 0; c < nn; ++c) {
		const int32_t f = near[c];
		double s[3][2];
		for (int k = 0; k < 3; ++k)
			at2(T[3 * size_t(f) + size_t(k)], s[k]);
		if (std::max({s[0][0], s[1][0], s[2][0]}) < qlo[0] ||
		    std::min({s[0][0], s[1][0], s[2][0]}) > qhi[0] ||
		    std::max({s[0][1], s[1][1], s[2][1]}) < qlo[1] ||
		    std::min({s[0][1], s[1][1], s[2][1]}) > qhi[1])
			continue; // (its shadow misses P's box)
		const double a = 0.5 * ((s[1][0] - s[0][0]) * (s[2][1] - s[0][1]) -
		                        (s[2][0] - s[0][0]) * (s[1][1] - s[0][1]));
		const double sign = a > 0 ? 1 : -1;
		Poly2 buf[2];
		const Poly2 *in = &piece;
		for (int k = 0; k < 3 && in->n >= 3; ++k) {
			Poly2 &out = buf[k & 1];
			if (!clip2(*in, s[k][0], s[k][1], s[(k + 1) % 3][0], s[(k + 1) % 3][1], sign, out))
				return HUGE_VAL;
			in = &out;
		}
		const Poly2 &cell = *in;
		const double ca = cell.n >= 3 ? std::fabs(area2(cell)) : 0.0;
		if (!(ca > 1e-12 * pieceArea))
			continue; // (does not cover a part of P; its edges are checked as the patch's border)
		if (a == 0 || (orient != 0 && orient != int(sign)))
			return HUGE_VAL;
		orient = int(sign);
		for (int i = 0; i < cell.n; ++i) {
			const Vec3 v = pc.p[0] + e1 * cell.x[i] + e2 * cell.y[i];
			bound2 = std::max(bound2, to.distance2(f, v));
		}
		if (bound2 > target2)
			return HUGE_VAL;
		covered += ca;
		patch[np++] = f;
	}
	if (!(covered >= 0.5 * pieceArea))
		return HUGE_VAL;
	std::sort(patch, patch + np);
	// (the patch's border: an edge whose other side is not in the patch, or is wound the same
	// way; none may pass over P, so that P is covered the same number of times everywhere)
	for (int c = 0; c < np; ++c) {
		const int32_t f = patch[c];
		for (int k = 0; k < 3; ++k) {
			const int32_t g = to.across(f)[k];
			const int32_t a = T[3 * size_t(f) + size_t(k)],
			              b = T[3 * size_t(f) + size_t(k + 1) % 3];
			bool inner = g >= 0 && std::binary_search(patch, patch + np, g);
			if (inner) {
				bool opposite = false;
				for (int j = 0; j < 3; ++j)
					opposite = opposite || (T[3 * size_t(g) + size_t(j)] == b &&
					                        T[3 * size_t(g) + size_t(j + 1) % 3] == a);
				inner = opposite;
			}
			if (inner)
				continue;
			double sa[2], sb[2];
			at2(a, sa), at2(b, sb);
			if (segmentMeetsTriangle(sa, sb, q, margin))
				return HUGE_VAL;
		}
	}
	return std::sqrt(bound2) + edgePad;
}

// The piece cut by the planes between the triangles near it (gather): each part is bounded by
// the candidate farthest from none of its corners; the largest bounds the piece. HUGE_VAL when
// a part's bound is above `target` (the piece is then cut anyway).
double splitBound(const TriangleTree &to, const Piece &pc, double target)
{
	int32_t cands[12];
	const int nc = gather(to, pc, cands);
	// (the piece cut by the planes between the candidates: each part is bounded by the
	// candidate farthest from none of its corners; the largest of these bounds the piece)
	constexpr int kMaxPolys = 24;
	Poly polys[kMaxPolys], next[2 * kMaxPolys];
	int np = 1;
	polys[0].n = 3;
	for (int k = 0; k < 3; ++k)
		polys[0].v[k] = pc.p[k];
	auto cutAll = [&](int32_t f, int32_t g) {
		Vec3 m, o;
		between(to, f, g, m, o);
		int nn = 0;
		for (int q = 0; q < np; ++q) {
			Poly lo, hi;
			if (!cut(polys[q], m, o, lo, hi)) { // (the part stays whole: still a partition)
				next[nn++] = polys[q];
				continue;
			}
			if (lo.n >= 3)
				next[nn++] = lo;
			if (hi.n >= 3)
				next[nn++] = hi;
		}
		np = nn;
		std::copy(next, next + nn, polys);
	};
	// (between candidates with an edge in common, and between the corners' own nearest ones)
	int nearestOnes = 0;
	while (nearestOnes < nc && nearestOnes < 3 &&
	       std::find(pc.n, pc.n + 3, cands[nearestOnes]) != pc.n + 3)
		++nearestOnes;
	for (int i = 0; i < nc; ++i)
		for (int k = 0; k < 3; ++k) {
			const int32_t g = to.across(cands[i])[k];
			if (g > cands[i] && std::find(cands, cands + nc, g) != cands + nc &&
			    np <= kMaxPolys / 2)
				cutAll(cands[i], g);
		}
	for (int i = 0; i < nearestOnes; ++i)
		for (int j = i + 1; j < nearestOnes; ++j) {
			const int32_t *ai = to.across(cands[i]);
			if (np <= kMaxPolys / 2 && std::find(ai, ai + 3, cands[j]) == ai + 3)
				cutAll(cands[i], cands[j]);
		}
	// (each part first against the candidate nearest to its centre; a part bounded above the
	// target fails the piece, which is then cut further: its bound stays u)
	const double target2 = target * target;
	double split2 = 0;
	for (int q = 0; q < np; ++q) {
		const Poly &pq = polys[q];
		Vec3 centre(0, 0, 0);
		for (int i = 0; i < pq.n; ++i)
			centre += pq.v[i];
		centre /= double(pq.n);
		int owner = 0;
		double od = HUGE_VAL;
		for (int c = 0; c < nc; ++c) {
			const double d2 = to.distance2(cands[c], centre);
			if (d2 < od)
				od = d2, owner = c;
		}
		auto farthest = [&](int c, double stop) {
			double m = 0;
			for (int i = 0; i < pq.n && m < stop; ++i)
				m = std::max(m, to.distance2(cands[c], pq.v[i]));
			return m;
		};
		double best = farthest(owner, HUGE_VAL);
		for (int c = 0; c < nc && best > target2; ++c)
			if (c != owner)
				best = std::min(best, farthest(c, best));
		if (best > target2)
			return HUGE_VAL;
		split2 = std::max(split2, best);
	}
	return std::sqrt(split2);
}

double upperBound(const TriangleTree &to, const Piece &pc, double target, BoundBy &by)
{
	by = BoundBy::corners;
	double u = HUGE_VAL;
	for (int i = 0; i < 3; ++i) { // (Lipschitz, from each corner)
		double r = 0;
		for (int j = 0; j < 3; ++j)
			r = std::max(r, (pc.p[j] - pc.p[i]).Norm());
		u = std::min(u, pc.d[i] + r);
	}
	int32_t cand[3];
	int nc = 0;
	for (int k = 0; k < 3; ++k) // (convexity, against each corner's nearest triangle)
		if (pc.n[k] >= 0 && std::find(cand, cand + nc, pc.n[k]) == cand + nc)
			cand[nc++] = pc.n[k];
	for (int c = 0; c < nc; ++c) {
		const int32_t f = cand[c];
		double m = 0;
		for (int i = 0; i < 3 && m < u; ++i)
			m = std::max(m, pc.n[i] == f ? pc.d[i] : std::sqrt(to.distance2(f, pc.p[i])));
		u = std::min(u, m);
	}
	if (u <= target)
		return u;
	by = BoundBy::cover;
	const double c = coverBound(to, pc, target);
	if (c <= target)
		return c;
	by = BoundBy::split;
	const double d = splitBound(to, pc, target);
	if (d <= target)
		return d;
	by = BoundBy::corners;
	return u;
}

} // namespace

TriangleTree::TriangleTree(const double *P, const int32_t *T, size_t nT) : P_(P), T_(T)
{
	flat_.assign(nT, 0);
	tri_.reserve(nT);
	for (size_t f = 0; f < nT; ++f) {
		const int32_t a = T[3 * f], b = T[3 * f + 1], c = T[3 * f + 2];
		if (a < 0 || b < 0 || c < 0 || a == b || b == c || c == a)
			continue;
		bool finite = true;
		for (int k = 0; k < 3; ++k)
			for (int j = 0; j < 3; ++j)
				finite = finite && std::isfinite(P[3 * size_t(T[3 * f + size_t(k)]) + size_t(j)]);
		if (!finite)
			continue;
		const Vec3 x =
		    (v(int32_t(f), 1) - v(int32_t(f), 0)) ^ (v(int32_t(f), 2) - v(int32_t(f), 0));
		flat_[f] = !(x.SquaredNorm() > 0);
		tri_.push_back(int32_t(f));
	}
	if (tri_.empty())
		return;
	{ // edge adjacency: the triangles' edges sorted by their vertices, pairs taken
		struct E {
			int32_t a, b, f;
			int8_t k;
		};
		std::vector<E> es;
		es.reserve(3 * tri_.size());
		for (const int32_t f : tri_)
			for (int k = 0; k < 3; ++k) {
				const int32_t a = T[3 * size_t(f) + size_t(k)],
				              b = T[3 * size_t(f) + size_t(k + 1) % 3];
				es.push_back({std::min(a, b), std::max(a, b), f, int8_t(k)});
			}
		std::sort(es.begin(), es.end(), [](const E &x, const E &y) {
			return x.a != y.a ? x.a < y.a : x.b != y.b ? x.b < y.b : x.f < y.f;
		});
		adj_.assign(3 * nT, -1);
		for (size_t i = 0; i < es.size();) {
			size_t j = i + 1;
			while (j < es.size() && es[j].a == es[i].a && es[j].b == es[i].b)
				++j;
			if (j - i == 2) {
				adj_[3 * size_t(es[i].f) + size_t(es[i].k)] = es[i + 1].f;
				adj_[3 * size_t(es[i + 1].f) + size_t(es[i + 1].k)] = es[i].f;
			}
			i = j;
		}
	}
	nodes_.reserve(2 * (tri_.size() / kLeafSize + 1));
	// (depth first: a node's left child is the next node; the split is at the median centroid
	// along the longest side of the centroids' box; the centroids (as corner sums) travel with
	// the triangles, the boxes are made bottom up)
	struct Item {
		double c[3];
		int32_t f;
	};
	std::vector<Item> items(tri_.size());
	for (size_t i = 0; i < tri_.size(); ++i) {
		const int32_t f = tri_[i];
		items[i].f = f;
		for (int j = 0; j < 3; ++j)
			items[i].c[j] = P_[3 * size_t(T_[3 * size_t(f)]) + size_t(j)] +
			                P_[3 * size_t(T_[3 * size_t(f) + 1]) + size_t(j)] +
			                P_[3 * size_t(T_[3 * size_t(f) + 2]) + size_t(j)];
	}
	struct Task {
		int32_t first, count, parent;
	};
	std::vector<Task> stack{{0, int32_t(tri_.size()), -1}};
	while (!stack.empty()) {
		const Task t = stack.back();
		stack.pop_back();
		const int32_t id = int32_t(nodes_.size());
		if (t.parent >= 0)
			nodes_[size_t(t.parent)].right = id;
		Node n;
		n.first = t.first;
		n.count = t.count;
		n.right = -1;
		if (t.count <= kLeafSize) {
			n.lo = n.hi = v(items[size_t(t.first)].f, 0);
			for (int32_t i = t.first; i < t.first + t.count; ++i)
				for (int k = 0; k < 3; ++k) {
					const Vec3 q = v(items[size_t(i)].f, k);
					for (int j = 0; j < 3; ++j)
						n.lo[j] = std::min(n.lo[j], q[j]), n.hi[j] = std::max(n.hi[j], q[j]);
				}
			nodes_.push_back(n);
			continue;
		}
		double clo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, chi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
		for (int32_t i = t.first; i < t.first + t.count; ++i)
			for (int j = 0; j < 3; ++j)
				clo[j] = std::min(clo[j], items[size_t(i)].c[j]),
				chi[j] = std::max(chi[j], items[size_t(i)].c[j]);
		n.count = -1;
		n.lo = n.hi = Vec3(0, 0, 0); // (made from its children's below)
		nodes_.push_back(n);
		const double ext[3] = {chi[0] - clo[0], chi[1] - clo[1], chi[2] - clo[2]};
		const int axis = ext[0] >= ext[1] && ext[0] >= ext[2] ? 0 : ext[1] >= ext[2] ? 1 : 2;
		const int32_t half = t.count / 2;
		std::nth_element(items.begin() + t.first, items.begin() + t.first + half,
		                 items.begin() + t.first + t.count, [axis](const Item &a, const Item &b) {
			                 return a.c[axis] < b.c[axis] || (a.c[axis] == b.c[axis] && a.f < b.f);
		                 });
		stack.push_back({t.first + half, t.count - half, id}); // (right, built after the left)
		stack.push_back({t.first, half, -1});
	}
	for (size_t i = 0; i < items.size(); ++i)
		tri_[i] = items[i].f;
	// (an inner node's children come after it)
	for (size_t i = nodes_.size(); i-- > 0;) {
		Node &n = nodes_[i];
		if (n.count >= 0)
			continue;
		const Node &l = nodes_[i + 1], &r = nodes_[size_t(n.right)];
		for (int j = 0; j < 3; ++j)
			n.lo[j] = std::min(l.lo[j], r.lo[j]), n.hi[j] = std::max(l.hi[j], r.hi[j]);
	}
}

Vec3 TriangleTree::v(int32_t f, int k) const
{
	const double *q = &P_[3 * size_t(T_[3 * size_t(f) + size_t(k)])];
	return Vec3(q[0], q[1], q[2]);
}

double TriangleTree::distance2(int32_t f, const Vec3 &p) const
{
	const Vec3 a = v(f, 0), b = v(f, 1), c = v(f, 2);
	if (flat_[size_t(f)])
		return std::min(
		    {segmentDistance2(p, a, b), segmentDistance2(p, b, c), segmentDistance2(p, c, a)});
	return pointTriangleDistance2(p, a, b, c);
}

bool TriangleTree::collect(const Vec3 &lo, const Vec3 &hi, int32_t *out, int &n, int cap) const
{
	n = 0;
	if (nodes_.empty())
		return true;
	auto meets = [&](const Vec3 &a, const Vec3 &b) {
		return a[0] <= hi[0] && b[0] >= lo[0] && a[1] <= hi[1] && b[1] >= lo[1] && a[2] <= hi[2] &&
		       b[2] >= lo[2];
	};
	int32_t stack[128];
	int top = 0;
	stack[top++] = 0;
	while (top > 0) {
		const Node &nd = nodes_[size_t(stack[--top])];
		if (!meets(nd.lo, nd.hi))
			continue;
		if (nd.count < 0) {
			stack[top++] = nd.right;
			stack[top++] = int32_t(&nd - nodes_.data()) + 1;
			continue;
		}
		for (int32_t i = nd.first; i < nd.first + nd.count; ++i) {
			const int32_t f = tri_[size_t(i)];
			Vec3 a = v(f, 0), b = a;
			for (int k = 1; k < 3; ++k) {
				const Vec3 q = v(f, k);
				for (int j = 0; j < 3; ++j)
					a[j] = std::min(a[j], q[j]), b[j] = std::max(b[j], q[j]);
			}
			if (!meets(a, b))
				continue;
			if (n == cap)
				return false;
			out[n++] = f;
		}
	}
	return true;
}

int32_t TriangleTree::nearest(const Vec3 &p, double &best2) const
{
	int32_t found = -1;
	if (nodes_.empty())
		return found;
	int32_t stack[128];
	int top = 0;
	stack[top++] = 0;
	while (top > 0) {
		const Node &n = nodes_[size_t(stack[--top])];
		if (boxDistance2(p, n.lo, n.hi) >= best2)
			continue;
		if (n.count >= 0) {
			for (int32_t i = n.first; i < n.first + n.count; ++i) {
				const int32_t f = tri_[size_t(i)];
				const double d2 = distance2(f, p);
				if (d2 < best2)
					best2 = d2, found = f;
			}
			continue;
		}
		const int32_t l = int32_t(&n - nodes_.data()) + 1, r = n.right;
		const double dl = boxDistance2(p, nodes_[size_t(l)].lo, nodes_[size_t(l)].hi),
		             dr = boxDistance2(p, nodes_[size_t(r)].lo, nodes_[size_t(r)].hi);
		// (the nearer child on top; the depth is that of a median split: far below 128)
		if (dl <= dr) {
			stack[top++] = r;
			stack[top++] = l;
		} else {
			stack[top++] = l;
			stack[top++] = r;
		}
	}
	return found;
}

HausdorffBounds directedHausdorff(const TriangleTree &from, const TriangleTree &to, double eps,
                                  size_t maxPieces, size_t threads, double known)
{
	HausdorffBounds out;
	const std::vector<int32_t> &tris = from.triangles();
	if (tris.empty())
		return out;
	if (to.empty()) {
		out.lower = out.upper = HUGE_VAL;
		out.converged = false;
		return out;
	}
	const int32_t *T = from.T();
	const double *P = from.P();
	// exact distances at the corners, each vertex once
	int32_t maxV = -1;
	for (const int32_t f : tris)
		for (int k = 0; k < 3; ++k)
			maxV = std::max(maxV, T[3 * size_t(f) + size_t(k)]);
	std::vector<int32_t> vn(size_t(maxV) + 1, -2);
	for (const int32_t f : tris)
		for (int k = 0; k < 3; ++k)
			vn[size_t(T[3 * size_t(f) + size_t(k)])] = -1;
	std::vector<int32_t> used;
	for (size_t i = 0; i < vn.size(); ++i)
		if (vn[i] == -1)
			used.push_back(int32_t(i));
	std::vector<double> vd(vn.size(), 0.0);
	auto pos = [&](int32_t i) {
		return Vec3(P[3 * size_t(i)], P[3 * size_t(i) + 1], P[3 * size_t(i) + 2]);
	};
	parallelRanges(used.size(), threads, [&](size_t b, size_t e, size_t) {
		for (size_t i = b; i < e; ++i) {
			double d2 = HUGE_VAL;
			vn[size_t(used[i])] = to.nearest(pos(used[i]), d2);
			vd[size_t(used[i])] = std::sqrt(d2);
		}
	});
	double lower = 0;
	for (const int32_t i : used)
		lower = std::max(lower, vd[size_t(i)]);
	// each triangle's bound; those above the factor into a queue, largest bound first
	const double factor = 1 + eps;
	std::vector<double> u(tris.size());
	std::vector<BoundBy> by(tris.size());
	parallelRanges(tris.size(), threads, [&](size_t b, size_t e, size_t) {
		for (size_t i = b; i < e; ++i) {
			Piece pc;
			for (int k = 0; k < 3; ++k) {
				const int32_t q = T[3 * size_t(tris[i]) + size_t(k)];
				pc.p[k] = pos(q), pc.d[k] = vd[size_t(q)], pc.n[k] = vn[size_t(q)],
				pc.exact[k] = true;
			}
			u[i] = upperBound(to, pc, factor * std::max(lower, known), by[i]);
		}
	});
	auto enough = [&](double x) { return x <= factor * std::max(lower, known); };
	double settled = lower; // (the largest bound of a piece not refined further)
	std::priority_queue<Piece> queue;
	for (size_t i = 0; i < tris.size(); ++i) {
		out.byCover += by[i] == BoundBy::cover;
		out.bySplit += by[i] == BoundBy::split;
		if (enough(u[i])) {
			settled = std::max(settled, u[i]);
			continue;
		}
		Piece pc;
		for (int k = 0; k < 3; ++k) {
			const int32_t q = T[3 * size_t(tris[i]) + size_t(k)];
			pc.p[k] = pos(q), pc.d[k] = vd[size_t(q)], pc.n[k] = vn[size_t(q)], pc.exact[k] = true;
		}
		pc.u = u[i];
		queue.push(pc);
	}
	out.pieces = tris.size();
	// refinement, a batch of the largest bounds at a time (the batch in parallel, the queue in
	// order: the result does not depend on the thread count)
	const size_t batchMax = 256 * std::max<size_t>(threads, 1);
	std::vector<Piece> batch, kids;
	while (!queue.empty() && !enough(queue.top().u) && out.pieces < maxPieces) {
		batch.clear();
		while (!queue.empty() && batch.size() < batchMax && !enough(queue.top().u)) {
			batch.push_back(queue.top());
			queue.pop();
		}
		kids.resize(4 * batch.size());
		const double low2 = lower * lower;
		parallelRanges(batch.size(), threads, [&](size_t b, size_t e, size_t) {
			for (size_t i = b; i < e; ++i) {
				const Piece &pc = batch[i];
				Vec3 m[3];
				double md[3];
				int32_t mn[3] = {-1, -1, -1};
				bool mx[3];
				int32_t cands[12];
				const int nc = gather(to, pc, cands);
				for (int k = 0; k < 3; ++k) {
					const int k1 = (k + 1) % 3;
					m[k] = (pc.p[k] + pc.p[k1]) * 0.5;
					// (first against the triangles near the piece; the tree is searched, within
					// that distance, only where the point could raise the lower bound)
					double d2 = HUGE_VAL;
					for (int c = 0; c < nc; ++c) {
						const double e2 = to.distance2(cands[c], m[k]);
						if (e2 < d2)
							d2 = e2, mn[k] = cands[c];
					}
					mx[k] = !(d2 <= low2);
					if (mx[k]) {
						double e2 = std::isfinite(d2) ? d2 * (1 + 1e-9) + 1e-300 : HUGE_VAL;
						const int32_t f = to.nearest(m[k], e2);
						if (f >= 0)
							mn[k] = f, d2 = e2;
						else
							d2 = to.distance2(mn[k], m[k]);
					}
					md[k] = std::sqrt(d2);
				}
				// (corner k, midpoints k-(k+1) as m[k] and (k+2)-k as m[k+2])
				Piece *c = &kids[4 * i];
				for (int k = 0; k < 3; ++k) {
					const int a = k, b2 = (k + 2) % 3;
					c[k].p[0] = pc.p[a], c[k].d[0] = pc.d[a], c[k].n[0] = pc.n[a];
					c[k].exact[0] = pc.exact[a];
					c[k].p[1] = m[a], c[k].d[1] = md[a], c[k].n[1] = mn[a], c[k].exact[1] = mx[a];
					c[k].p[2] = m[b2], c[k].d[2] = md[b2], c[k].n[2] = mn[b2],
					c[k].exact[2] = mx[b2];
				}
				for (int k = 0; k < 3; ++k)
					c[3].p[k] = m[k], c[3].d[k] = md[k], c[3].n[k] = mn[k], c[3].exact[k] = mx[k];
				for (int k = 0; k < 4; ++k)
					c[k].u = upperBound(to, c[k], factor * std::max(lower, known), c[k].by);
			}
		});
		for (const Piece &c : kids)
			for (int k = 0; k < 3; ++k)
				if (c.exact[k])
					lower = std::max(lower, c.d[k]);
		for (const Piece &c : kids) {
			out.byCover += c.by == BoundBy::cover;
			out.bySplit += c.by == BoundBy::split;
			if (enough(c.u))
				settled = std::max(settled, c.u);
			else
				queue.push(c);
		}
		out.pieces += kids.size();
	}
	double upper = std::max(lower, settled);
	if (!queue.empty())
		upper = std::max(upper, queue.top().u);
	out.converged = enough(upper);
	// (rounded up: the distances above are computed in floating point)
	Vec3 lo = pos(T[3 * size_t(tris[0])]), hi = lo;
	for (const int32_t i : used)
		for (int j = 0; j < 3; ++j)
			lo[j] = std::min(lo[j], P[3 * size_t(i) + size_t(j)]),
			hi[j] = std::max(hi[j], P[3 * size_t(i) + size_t(j)]);
	out.lower = lower;
	out.upper = upper * (1 + 1e-9) + 1e-12 * (hi - lo).Norm();
	return out;
}

HausdorffBounds hausdorff(const TriangleTree &a, const TriangleTree &b, double eps,
                          size_t maxPieces, size_t threads)
{
	const HausdorffBounds ab = directedHausdorff(a, b, eps, maxPieces, threads, 0.0);
	const HausdorffBounds ba = directedHausdorff(b, a, eps, maxPieces, threads, ab.lower);
	HausdorffBounds out;
	out.lower = std::max(ab.lower, ba.lower);
	out.upper = std::max(ab.upper, ba.upper);
	out.pieces = ab.pieces + ba.pieces;
	out.byCover = ab.byCover + ba.byCover;
	out.bySplit = ab.bySplit + ba.bySplit;
	out.converged = ab.converged && ba.converged;
	return out;
}

} // namespace detail
} // namespace gausslod
