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
// A cover proved above the target also gives its farthest point, whose exact distance raises the
// lower bound (where the triangle over that point is the nearest one, to the bound itself). A
// piece whose bound is still above (1 + eps) x the lower bound is cut in four at its edge
// midpoints (new distances: the lower bound grows) until every piece is within the factor.
#include "hausdorff_piece.h"

#include <queue>

namespace gausslod {
namespace detail {

namespace {

Vec3 vertexAt(const double *P, int32_t i)
{
	return Vec3(P[3 * size_t(i)], P[3 * size_t(i) + 1], P[3 * size_t(i) + 2]);
}

// The piece that is triangle f, whole: its corners, their exact distances and nearest triangles.
inline TrianglePiece wholePiece(const int32_t *T, const double *P, int32_t f,
                                const std::vector<int32_t> &vn, const std::vector<double> &vd)
{
	TrianglePiece pc;
	for (int k = 0; k < 3; ++k) {
		const int32_t q = T[3 * size_t(f) + size_t(k)];
		pc.p[k] = vertexAt(P, q), pc.d[k] = vd[size_t(q)], pc.n[k] = vn[size_t(q)],
		pc.exact[k] = true;
	}
	return pc;
}

// The exact distance to `to` at the corners, each vertex once: `used` gets the vertices the
// triangles of `from` use, in order; vd[v] their distances, vn[v] their nearest triangles (-2 for
// a vertex not used).
void cornerDistances(const TriangleTree &from, const TriangleTree &to, size_t threads,
                     std::vector<int32_t> &used, std::vector<int32_t> &vn, std::vector<double> &vd)
{
	const std::vector<int32_t> &tris = from.triangles();
	const int32_t *T = from.T();
	const double *P = from.P();
	int32_t maxV = -1;
	for (const int32_t f : tris)
		for (int k = 0; k < 3; ++k)
			maxV = std::max(maxV, T[3 * size_t(f) + size_t(k)]);
	vn.assign(size_t(maxV) + 1, -2);
	for (const int32_t f : tris)
		for (int k = 0; k < 3; ++k)
			vn[size_t(T[3 * size_t(f) + size_t(k)])] = -1;
	for (size_t i = 0; i < vn.size(); ++i)
		if (vn[i] == -1)
			used.push_back(int32_t(i));
	vd.assign(vn.size(), 0.0);
	parallelRanges(used.size(), threads, [&](size_t b, size_t e, size_t) {
		for (size_t i = b; i < e; ++i) {
			double d2 = HUGE_VAL;
			vn[size_t(used[i])] = to.nearest(vertexAt(P, used[i]), d2);
			vd[size_t(used[i])] = std::sqrt(d2);
		}
	});
}

// Cuts a piece in four at its edge midpoints into c[0..4) (corner k's part c[k], the middle one
// c[3]) and bounds each against `target`. A midpoint's distance is exact (to the whole set) only
// where it could raise the lower bound (its squared distance to the triangles near the piece is
// above low2).
inline void splitPiece(const TriangleTree &to, const TrianglePiece &pc, double low2, double target,
                       TrianglePiece *c)
{
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
	for (int k = 0; k < 3; ++k) {
		const int a = k, b2 = (k + 2) % 3;
		c[k].p[0] = pc.p[a], c[k].d[0] = pc.d[a], c[k].n[0] = pc.n[a];
		c[k].exact[0] = pc.exact[a];
		c[k].p[1] = m[a], c[k].d[1] = md[a], c[k].n[1] = mn[a], c[k].exact[1] = mx[a];
		c[k].p[2] = m[b2], c[k].d[2] = md[b2], c[k].n[2] = mn[b2], c[k].exact[2] = mx[b2];
	}
	for (int k = 0; k < 3; ++k)
		c[3].p[k] = m[k], c[3].d[k] = md[k], c[3].n[k] = mn[k], c[3].exact[k] = mx[k];
	for (int k = 0; k < 4; ++k) {
		c[k].seen = -1;
		c[k].u = upperBound(to, c[k], target, c[k].by, &c[k].seen);
	}
}

// Refinement of the queued pieces, a batch of the largest bounds at a time (the batch in
// parallel, the queue in order: the result does not depend on the thread count), until every
// piece is within `factor` of max(lower, known) or maxPieces were evaluated. Raises `lower` and
// `settled` (the largest bound of a piece not refined further); counts into `out`.
void refine(const TriangleTree &to, double factor, double known, size_t maxPieces, size_t threads,
            std::priority_queue<TrianglePiece> &queue, double &lower, double &settled,
            HausdorffBounds &out)
{
	auto enough = [&](double x) { return x <= factor * std::max(lower, known); };
	// (a batch's size must not depend on the thread count: its target and low2 are fixed at its
	// start, so where it ends decides what its pieces are bounded against)
	constexpr size_t batchMax = 512;
	std::vector<TrianglePiece> batch, kids;
	while (!queue.empty() && !enough(queue.top().u) && out.pieces < maxPieces) {
		batch.clear();
		while (!queue.empty() && batch.size() < batchMax && !enough(queue.top().u)) {
			batch.push_back(queue.top());
			queue.pop();
		}
		kids.resize(4 * batch.size());
		const double low2 = lower * lower, target = factor * std::max(lower, known);
		parallelRanges(batch.size(), threads, [&](size_t b, size_t e, size_t) {
			for (size_t i = b; i < e; ++i)
				splitPiece(to, batch[i], low2, target, &kids[4 * i]);
		});
		for (const TrianglePiece &c : kids) {
			for (int k = 0; k < 3; ++k)
				if (c.exact[k])
					lower = std::max(lower, c.d[k]);
			lower = std::max(lower, c.seen);
		}
		for (const TrianglePiece &c : kids) {
			out.byCover += c.by == BoundBy::cover;
			out.bySplit += c.by == BoundBy::split;
			if (enough(c.u))
				settled = std::max(settled, c.u);
			else
				queue.push(c);
		}
		out.pieces += kids.size();
	}
}

} // namespace

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
	std::vector<int32_t> used, vn;
	std::vector<double> vd;
	cornerDistances(from, to, threads, used, vn, vd);
	double lower = 0;
	for (const int32_t i : used)
		lower = std::max(lower, vd[size_t(i)]);
	// each triangle's bound; those above the factor into a queue, largest bound first
	const double factor = 1 + eps;
	std::vector<double> u(tris.size()), seen(tris.size(), -1.0);
	std::vector<BoundBy> by(tris.size());
	parallelRanges(tris.size(), threads, [&](size_t b, size_t e, size_t) {
		for (size_t i = b; i < e; ++i) {
			const TrianglePiece pc = wholePiece(T, P, tris[i], vn, vd);
			u[i] = upperBound(to, pc, factor * std::max(lower, known), by[i], &seen[i]);
		}
	});
	// (the distances met at the covers' farthest points, once all are bounded: the lower bound
	// the same for any threads)
	for (const double d : seen)
		lower = std::max(lower, d);
	release(seen);
	auto enough = [&](double x) { return x <= factor * std::max(lower, known); };
	double settled = lower; // (the largest bound of a piece not refined further)
	std::priority_queue<TrianglePiece> queue;
	for (size_t i = 0; i < tris.size(); ++i) {
		out.byCover += by[i] == BoundBy::cover;
		out.bySplit += by[i] == BoundBy::split;
		if (enough(u[i])) {
			settled = std::max(settled, u[i]);
			continue;
		}
		TrianglePiece pc = wholePiece(T, P, tris[i], vn, vd);
		pc.u = u[i];
		queue.push(pc);
	}
	out.pieces = tris.size();
	refine(to, factor, known, maxPieces, threads, queue, lower, settled, out);
	double upper = std::max(lower, settled);
	if (!queue.empty())
		upper = std::max(upper, queue.top().u);
	out.converged = enough(upper);
	// (rounded up: the distances above are computed in floating point)
	Vec3 lo = vertexAt(P, T[3 * size_t(tris[0])]), hi = lo;
	for (const int32_t i : used)
		for (int j = 0; j < 3; ++j)
			lo[j] = std::min(lo[j], P[3 * size_t(i) + size_t(j)]),
			hi[j] = std::max(hi[j], P[3 * size_t(i) + size_t(j)]);
	out.lower = lower;
	out.upper = upper * (1 + 1e-9) + 1e-12 * (hi - lo).Norm();
	return out;
}

HausdorffBounds hausdorff(const TriangleTree &a, const TriangleTree &b, double eps,
                          size_t maxPieces, size_t threads, double floor)
{
	const HausdorffBounds ab = directedHausdorff(a, b, eps, maxPieces, threads, floor);
	const HausdorffBounds ba =
	    directedHausdorff(b, a, eps, maxPieces, threads, std::max(floor, ab.lower));
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
