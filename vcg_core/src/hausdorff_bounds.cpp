// The upper bounds of the certified Hausdorff distance (hausdorff.h, docs/DESIGN.md 52) over
// one piece of a triangle: at its corners, by the cover of the other side's triangles, by the
// split between them (see hausdorff.cpp for the whole method).
#include "hausdorff_piece.h"

namespace gausslod {
namespace detail {

namespace {

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

// The piece seen along its normal: 2D coordinates in its plane, with its first corner at the
// origin; and the tolerance of the cover's border check.
struct CoverFrame {
	Vec3 o, e1, e2;
	Poly2 piece;           ///< the piece's corners
	double q[3][2];        ///< the same, for segmentMeetsTriangle
	double qlo[2], qhi[2]; ///< their box
	double area = 0;       ///< the piece's (signed) area
	double margin = 0;     ///< for segmentMeetsTriangle
	double edgePad = 0;    ///< what the bound is raised by
	/// Vertex i of P, in the frame.
	void at2(const double *P, int32_t i, double *out) const
	{
		const Vec3 d(P[3 * size_t(i)] - o[0], P[3 * size_t(i) + 1] - o[1],
		             P[3 * size_t(i) + 2] - o[2]);
		out[0] = d.dot(e1), out[1] = d.dot(e2);
	}
};

// The frame of a piece, with its unit normal n, first edge e1r and that edge's length l1 (both
// non-zero).
void makeCoverFrame(const TrianglePiece &pc, const Vec3 &n, const Vec3 &e1r, double l1,
                    CoverFrame &fr)
{
	fr.o = pc.p[0];
	fr.e1 = e1r / l1;
	fr.e2 = n ^ fr.e1;
	for (int k = 0; k < 3; ++k) {
		const Vec3 d = pc.p[k] - pc.p[0];
		fr.q[k][0] = fr.piece.x[k] = d.dot(fr.e1), fr.q[k][1] = fr.piece.y[k] = d.dot(fr.e2);
	}
	fr.piece.n = 3;
	const double(&q)[3][2] = fr.q;
	fr.qlo[0] = std::min({q[0][0], q[1][0], q[2][0]});
	fr.qlo[1] = std::min({q[0][1], q[1][1], q[2][1]});
	fr.qhi[0] = std::max({q[0][0], q[1][0], q[2][0]});
	fr.qhi[1] = std::max({q[0][1], q[1][1], q[2][1]});
	fr.area = area2(fr.piece);
	// (the patch's border may run along P's edges, as where a triangle of B is P itself: it is
	// checked against P shrunk by 1e-7 of its inradius, and the points of P outside that are
	// within 1e-7 x P's longest edge of it, towards P's incentre: the bound is raised by that;
	// a sliver is checked against P grown instead)
	double perimeter = 0, longest = 0;
	for (int k = 0; k < 3; ++k) {
		const double e = std::hypot(q[(k + 1) % 3][0] - q[k][0], q[(k + 1) % 3][1] - q[k][1]);
		perimeter += e, longest = std::max(longest, e);
	}
	const double inradius = 2 * fr.area / perimeter;
	const bool shrunk = inradius >= 1e-6 * l1;
	fr.margin = shrunk ? -1e-7 * inradius : 1e-9 * l1;
	fr.edgePad = shrunk ? 1e-7 * longest : 0.0;
}

// The patch of the cover: the triangles `near` whose shadow covers a part of the piece, all with
// one orientation, into patch[0..np), and bound2, the largest squared distance of a part's corner
// from its triangle (at `far`). False (no cover proved) if they wind both ways, a part's bound is
// above `stop`, a clip overflows, or they cover less than half of the piece.
bool coverPatch(const TriangleTree &to, const CoverFrame &fr, const int32_t *near, int nn,
                double stop, int32_t *patch, int &np, double &bound2, Vec3 &far)
{
	const int32_t *T = to.T();
	const double *P = to.P();
	np = 0;
	int orient = 0;
	double covered = 0;
	bound2 = 0;
	const double stop2 = stop * stop;
	for (int c = 0; c < nn; ++c) {
		const int32_t f = near[c];
		double s[3][2];
		for (int k = 0; k < 3; ++k)
			fr.at2(P, T[3 * size_t(f) + size_t(k)], s[k]);
		if (std::max({s[0][0], s[1][0], s[2][0]}) < fr.qlo[0] ||
		    std::min({s[0][0], s[1][0], s[2][0]}) > fr.qhi[0] ||
		    std::max({s[0][1], s[1][1], s[2][1]}) < fr.qlo[1] ||
		    std::min({s[0][1], s[1][1], s[2][1]}) > fr.qhi[1])
			continue; // (its shadow misses P's box)
		const double a = 0.5 * ((s[1][0] - s[0][0]) * (s[2][1] - s[0][1]) -
		                        (s[2][0] - s[0][0]) * (s[1][1] - s[0][1]));
		const double sign = a > 0 ? 1 : -1;
		Poly2 buf[2];
		const Poly2 *in = &fr.piece;
		for (int k = 0; k < 3 && in->n >= 3; ++k) {
			Poly2 &out = buf[k & 1];
			if (!clip2(*in, s[k][0], s[k][1], s[(k + 1) % 3][0], s[(k + 1) % 3][1], sign, out))
				return false;
			in = &out;
		}
		const Poly2 &cell = *in;
		const double ca = cell.n >= 3 ? std::fabs(area2(cell)) : 0.0;
		if (!(ca > 0))
			continue; // (does not cover a part of P; its edges are checked as the patch's border:
			          // a sliver of a part is kept, else its edge meets P, shrunk by less)
		if (a == 0 || (orient != 0 && orient != int(sign)))
			return false;
		orient = int(sign);
		for (int i = 0; i < cell.n; ++i) {
			const Vec3 v = fr.o + fr.e1 * cell.x[i] + fr.e2 * cell.y[i];
			const double d2 = to.distance2(f, v);
			if (d2 > bound2)
				bound2 = d2, far = v;
		}
		if (bound2 > stop2)
			return false;
		covered += ca;
		patch[np++] = f;
	}
	return covered >= 0.5 * fr.area;
}

// Whether the patch's border passes over the piece: an edge whose other side is not in the patch,
// or is wound the same way. None may, so that the piece is covered the same number of times
// everywhere. Sorts the patch.
bool borderMeetsPiece(const TriangleTree &to, const CoverFrame &fr, int32_t *patch, int np)
{
	const int32_t *T = to.T();
	const double *P = to.P();
	std::sort(patch, patch + np);
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
			fr.at2(P, a, sa), fr.at2(P, b, sb);
			if (segmentMeetsTriangle(sa, sb, fr.q, fr.margin))
				return true;
		}
	}
	return false;
}

// The cover bound of a piece P over many triangles of B: if the triangles of B near P, seen
// along P's normal, cover P once or more with one orientation and the border of that patch
// stays outside P, every point p of P lies over (or under) a triangle t of the patch, in the
// part of P that t covers: p is then at most the largest distance from t of that part's corners
// (convexity). Returns that bound, or HUGE_VAL where the patch does not prove the cover (or
// a part's bound is above `stop`: the bound would not be used), and in `far` the point where
// the bound is reached. Triangles are looked for within `target` of the piece.
double coverBound(const TriangleTree &to, const TrianglePiece &pc, double target, double stop,
                  Vec3 &far)
{
	const Vec3 e1r = pc.p[1] - pc.p[0], nr = e1r ^ (pc.p[2] - pc.p[0]);
	const double ln = nr.Norm(), l1 = e1r.Norm();
	if (!(ln > 0) || !(l1 > 0) || !std::isfinite(target))
		return HUGE_VAL;
	Vec3 lo = pc.p[0], hi = lo;
	for (int k = 1; k < 3; ++k)
		for (int j = 0; j < 3; ++j)
			lo[j] = std::min(lo[j], pc.p[k][j]), hi[j] = std::max(hi[j], pc.p[k][j]);
	// (a triangle farther than the target from P would bound its part above the target)
	const Vec3 pad(target, target, target);
	// (up to 16384 triangles: a large piece over many small ones is proved at once, not cut
	// until its parts see few; the fandisk x64's levels certify 2.5 x faster than with 256)
	constexpr int kCap = 16384;
	thread_local std::vector<int32_t> buffer;
	buffer.resize(2 * size_t(kCap));
	int32_t *near = buffer.data(), *patch = near + kCap;
	int nn = 0;
	if (!to.collect(lo - pad, hi + pad, near, nn, kCap))
		return HUGE_VAL;
	CoverFrame fr;
	makeCoverFrame(pc, nr / ln, e1r, l1, fr);
	int np = 0;
	double bound2 = 0;
	if (!coverPatch(to, fr, near, nn, stop, patch, np, bound2, far) ||
	    borderMeetsPiece(to, fr, patch, np))
		return HUGE_VAL;
	return std::sqrt(bound2) + fr.edgePad;
}

// The piece cut by the planes between the triangles near it (gather): each part is bounded by
// the candidate farthest from none of its corners; the largest bounds the piece. HUGE_VAL when
// a part's bound is above `target` (the piece is then cut anyway).
double splitBound(const TriangleTree &to, const TrianglePiece &pc, double target)
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

} // namespace

double upperBound(const TriangleTree &to, const TrianglePiece &pc, double target, BoundBy &by,
                  double *seen)
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
	Vec3 far = pc.p[0]; // (where every part's bound is 0, a point of the piece all the same)
	// (with `seen`, a cover above the target is still proved, up to the corners' bound: its
	// farthest point's exact distance may raise the caller's lower bound to it)
	const double c = coverBound(to, pc, target, seen ? u : target, far);
	if (c <= target)
		return c;
	if (seen && c < u) {
		double d2 = HUGE_VAL;
		to.nearest(far, d2);
		*seen = std::sqrt(d2);
	}
	by = BoundBy::split;
	const double d = splitBound(to, pc, target);
	if (d <= target)
		return d;
	by = c < u ? BoundBy::cover : BoundBy::corners;
	return std::min(c, u);
}

} // namespace detail
} // namespace gausslod
