// Beyond the paper (2.4, Params::maxDistance): the distance tolerance on a re-triangulated
// superface. The removed vertices of its rings are measured against the straightened ring edges;
// each input face against the triangles its centroid and its corners fall in (each vertex located
// once, see Scratch::cornerQuery): the distance of the face to a triangle's plane (along the
// projection direction N where the bound is the limit, see checkDivisor) is linear over the face,
// so its largest value over the part of the face above that triangle is at a corner of that part
// (the face clipped by the triangle, in the projection). A face crossing a triangle that holds
// neither its centroid nor a corner is not seen. A border too far is a Deviation failure (tighter
// tolerances, then a locked border fix it), a face too far a Distance failure (inside vertices,
// then a split fix it): a failing check still looks at every face, and each triangle found too
// far gets a corner of such a face as a candidate for insertFarthest. The distances measured are
// kept per input face (a removed border vertex's on the face of its ring edge) for the level's
// figure.
#include "level_passes.h"

namespace gausslod {
namespace detail {

namespace {

// Calls fn(j, a, c) for every removed vertex of superface s's rings: j its ring position, a and c
// the kept vertices before and after it (the ends of its straightened segment). fn returns false
// to stop (then false). False too if a ring keeps no vertex.
template <class Fn>
bool forRemovedRingVertices(const TriangulationInput &in, int32_t s, Fn fn)
{
	const Topology &t = in.t;
	const Rings &rings = in.rings;
	auto from = [&](int32_t i) { return t.heFrom(rings.he[size_t(i)]); };
	for (int32_t r = rings.sfStart[size_t(s)]; r < rings.sfStart[size_t(s) + 1]; ++r) {
		const int32_t b = rings.start[size_t(r)], e = rings.start[size_t(r) + 1];
		int32_t first = b; // a kept vertex to start from (a ring keeps at least 3)
		while (first < e && !in.b.keep[size_t(from(first))])
			++first;
		if (first == e)
			return false;
		int32_t a = from(first);
		int32_t runStart = 0; // removed vertices since the last kept one: positions in ring
		for (int32_t step = 1, run = 0; step <= e - b; ++step) {
			const int32_t i = b + (first - b + step) % (e - b);
			const int32_t v = from(i);
			if (!in.b.keep[size_t(v)]) {
				if (run++ == 0)
					runStart = i;
				continue;
			}
			for (int32_t k = 0; k < run; ++k)
				if (!fn(b + (runStart - b + k) % (e - b), a, v))
					return false;
			a = v, run = 0;
		}
	}
	return true;
}

// The removed vertices of superface s's rings against the segments between kept ones.
Failure bordersWithin(const TriangulationInput &in, int32_t s, std::vector<float> &gap)
{
	const Topology &t = in.t;
	bool far = false;
	const bool rings = forRemovedRingVertices(in, s, [&](int32_t j, int32_t a, int32_t c) {
		const int32_t he = in.rings.he[size_t(j)];
		const double d = pointSegmentDistance(t.pos(t.heFrom(he)), in.out(a), in.out(c));
		if (d > in.limits.maxDistance)
			return !(far = true);
		float &g = gap[size_t(heFace(he))];
		g = std::max(g, float(d));
		return true;
	});
	return far ? Failure::Deviation : rings ? Failure::None : Failure::Ring;
}

// The orientation of the 2D triangle tv, as clipByTriangle takes it: 1 or -1.
double clipSign(const double *const tv[3])
{
	double area = 0;
	for (int e = 0; e < 3; ++e) {
		const double *a = tv[e], *b = tv[(e + 1) % 3];
		area += a[0] * b[1] - a[1] * b[0];
	}
	return area >= 0 ? 1.0 : -1.0;
}

// Face f (2D corners fxy) clipped by the 2D triangle tv (Sutherland-Hodgman; sign = clipSign(tv)):
// its corners in poly[cur][0 .. cnt), tag[cur][j] = c if corner j is the face's corner c as it is
// (copied, not computed), else -1. Each corner's side of an edge is computed once, and an edge
// that keeps every corner leaves the polygon as it is (what the copy would give).
int clipByTriangle(const double fxy[6], const double *const tv[3], double sign,
                   double poly[2][12][2], signed char tag[2][12], int &cur)
{
	int cnt = 3;
	for (int c = 0; c < 3; ++c)
		poly[0][c][0] = fxy[2 * c], poly[0][c][1] = fxy[2 * c + 1], tag[0][c] = (signed char)c;
	cur = 0;
	for (int e = 0; e < 3 && cnt > 0; ++e) {
		const double *a = tv[e], *b = tv[e == 2 ? 0 : e + 1];
		const double ex = b[0] - a[0], ey = b[1] - a[1];
		const double(*from)[2] = poly[cur];
		double side[12];
		bool all = true;
		for (int j = 0; j < cnt; ++j) {
			side[j] = sign * (ex * (from[j][1] - a[1]) - ey * (from[j][0] - a[0]));
			all = all && side[j] >= 0;
		}
		if (all)
			continue;
		double(*to)[2] = poly[1 - cur];
		const signed char *fromTag = tag[cur];
		signed char *toTag = tag[1 - cur];
		int out = 0;
		for (int j = 0; j < cnt; ++j) {
			const int jn = j + 1 == cnt ? 0 : j + 1;
			const double *x = from[j], *y = from[jn];
			const double sx = side[j], sy = side[jn];
			if (sx >= 0 && out < 12)
				toTag[out] = fromTag[j], to[out][0] = x[0], to[out++][1] = x[1];
			if (((sx >= 0) != (sy >= 0)) && out < 12) {
				const double u = sx / (sx - sy);
				toTag[out] = -1;
				to[out][0] = x[0] + u * (y[0] - x[0]);
				to[out++][1] = x[1] + u * (y[1] - x[1]);
			}
		}
		cnt = out, cur = 1 - cur;
	}
	return cnt;
}

// Is face i (f, corners P) of the superface farther than the tolerance from new triangle k's
// plane (see checkDivisor)? If not, the largest gap seen is kept in gap[f].
bool faceTooFar(const TriangulationInput &in, int32_t s, size_t i, int32_t f, const Vec3 P[3],
                int32_t k, const Vec3 &N, size_t firstTri, const Scratch &w, const ChunkOut &o,
                std::vector<float> &gap)
{
	const double eps = in.limits.maxDistance;
	const size_t faces = size_t(in.faces.end(s) - in.faces.begin(s));
	const size_t ntri = o.tris.size() / 3 - firstTri;
	const Vec3 &n = w.triNormal[size_t(k)];
	const Vec3 q = in.out(o.tris[3 * (firstTri + size_t(k))]);
	const double nN = checkDivisor(in.limits, n, N);
	double g[3], cornerMax = 0; // the gap at the face's corners to the triangle's plane
	for (int c = 0; c < 3; ++c) {
		g[c] = (P[c] - q).dot(n) / nN;
		cornerMax = std::max(cornerMax, std::fabs(g[c]));
	}
	float &kept = gap[size_t(f)];
	if (cornerMax <= eps || ntri == 1) { // (one triangle, no queries: the corners decide)
		kept = std::max(kept, float(cornerMax));
		return cornerMax > eps;
	}
	double fxy[6]; // the face in 2D (its corners' queries)
	for (int c = 0; c < 3; ++c) {
		const size_t qi = faces + size_t(w.cornerQuery[3 * i + size_t(c)]);
		fxy[2 * c] = w.job.queryXY[2 * qi];
		fxy[2 * c + 1] = w.job.queryXY[2 * qi + 1];
	}
	double poly[2][12][2];
	signed char tag[2][12];
	int cur = 0;
	const int32_t *tv = &w.job.tris[3 * size_t(k)];
	const double *const txy[3] = {&w.job.xy[2 * size_t(tv[0])], &w.job.xy[2 * size_t(tv[1])],
	                              &w.job.xy[2 * size_t(tv[2])]};
	const int cnt = clipByTriangle(fxy, txy, clipSign(txy), poly, tag, cur);
	// the gap at each corner of the clipped part (barycentric in the face)
	const double det =
	    (fxy[2] - fxy[0]) * (fxy[5] - fxy[1]) - (fxy[4] - fxy[0]) * (fxy[3] - fxy[1]);
	if (!(std::fabs(det) > 0))
		return true; // a face seen edge-on in the projection: not measurable, refused
	double clippedMax = 0;
	for (int j = 0; j < cnt; ++j) {
		const double dx = poly[cur][j][0] - fxy[0], dy = poly[cur][j][1] - fxy[1];
		const double b1 = (dx * (fxy[5] - fxy[1]) - dy * (fxy[4] - fxy[0])) / det;
		const double b2 = ((fxy[2] - fxy[0]) * dy - (fxy[3] - fxy[1]) * dx) / det;
		clippedMax = std::max(clippedMax, std::fabs((1 - b1 - b2) * g[0] + b1 * g[1] + b2 * g[2]));
	}
	if (clippedMax > eps)
		return true;
	kept = std::max(kept, float(clippedMax));
	return false;
}

// A distance kept as a float, rounded up (a bound must stay a bound).
inline float roundedUp(double d) { return float(d * (1 + 1e-6)); }

} // namespace

// Beyond the paper (DESIGN 23): an upper bound on the distance, both ways, between the input
// faces of superface s and its new triangles, kept per input face in `bound` (the level's figure
// is the largest; rounded up). Along N, the gap between an input face and a new triangle is linear
// where their projections overlap, so its largest value there is at a corner of the overlap:
// every overlapping pair (found with a grid over the triangles) is clipped, and the largest gap,
// dv, bounds the distance of every point of a face above a triangle and of every point of a
// triangle above a face. What is left are the pockets between a border chain and the segment
// that replaced it, where a point is within wb (the largest distance of a removed border vertex
// from its segment, or of a placed border vertex from its input position) of the chain in the
// projection:
//  - a face with a part outside the straightened outline (an outward pocket): that part is
//    within wb / cos(theta_in) of the chain along the input faces (theta_in: the largest angle
//    between N and an input face over a pocket), and the chain within wb of its segment, an edge
//    of the new triangles; or, the distance to one triangle being convex, the whole face is
//    within the largest of its corners' distances to a triangle near it (the smaller of both);
//  - a triangle with a part above no face (an inward pocket): within wb / cos(theta_out) of the
//    chain along the new triangles over the pocket, and the chain within dv of them; or within
//    the triangle's longest edge of one of its vertices, which are input vertices (or, placed
//    (placement.cpp), that far from one more).
// The argument assumes what the checks before it establish: the input faces of the superface
// and its new triangles each project one-to-one onto the plane orthogonal to N. Placed vertices
// (placement.cpp) give a second bound, w.boundCap: the superface's bound as accepted plus the
// largest move of its vertices (a point of a moved triangle is within that move of the point of
// the triangle before, with the same barycentric coordinates); the smaller of the two holds.
// Returns the superface's bound (mesh units).
double distanceBound(const TriangulationInput &in, int32_t s, const Vec3 &N, size_t firstTri,
                     Scratch &w, const ChunkOut &o, std::vector<float> &bound)
{
	if (w.boundCap <= w.boundEnough) { // (the other bound is all the caller needs)
		const size_t f0 = size_t(in.faces.face[size_t(in.faces.begin(s))]);
		bound[f0] = std::max(bound[f0], roundedUp(w.boundCap));
		return w.boundCap;
	}
	const Topology &t = in.t;
	const size_t ntri = o.tris.size() / 3 - firstTri;
	const int32_t *tri = &o.tris[3 * firstTri];
	const Vec3 U = planeAxis(N);
	const Vec3 V = N ^ U;
	const Vec3 origin = in.out(tri[0]);
	auto project = [&](const Vec3 &p, double *xy) {
		const Vec3 q = p - origin;
		xy[0] = q.dot(U), xy[1] = q.dot(V);
	};
	const int32_t fb = in.faces.begin(s);
	const size_t faces = size_t(in.faces.end(s) - fb);
	// the check's projection (same N, U, V), if it ran: every vertex is projected once
	const bool job = ntri > 1 && w.cornerQuery.size() == 3 * faces &&
	                 w.job.tris.size() == 3 * ntri && w.job.queryTri.size() >= faces;
	w.boundXY.resize(6 * ntri);
	w.triArea.resize(ntri);
	w.triCovered.assign(ntri, 0.0);
	// per triangle, once: its orientation for the clipping, n . N
	w.triSign.resize(ntri);
	w.triNN.resize(ntri);
	for (size_t k = 0; k < ntri; ++k) {
		for (size_t c = 0; c < 3; ++c) {
			double *xy = &w.boundXY[6 * k + 2 * c];
			if (job)
				xy[0] = w.job.xy[2 * size_t(w.job.tris[3 * k + c])],
				xy[1] = w.job.xy[2 * size_t(w.job.tris[3 * k + c]) + 1];
			else
				project(in.out(tri[3 * k + c]), xy);
		}
		const double *xy = &w.boundXY[6 * k];
		w.triArea[k] = 0.5 * std::fabs(orient2(xy, xy + 2, xy + 4));
		const double *const tv[3] = {xy, xy + 2, xy + 4};
		w.triSign[k] = int8_t(clipSign(tv));
		w.triNN[k] = w.triNormal[k].dot(N);
	}
	TriangleGrid grid;
	bool gridBuilt = false; // (only faces over several triangles need it)
	if (w.triStamp.size() < ntri)
		w.triStamp.resize(ntri, 0);
	auto newStamp = [&] {
		if (++w.stampNow == 0) { // (wrapped: clear the stamps)
			std::fill(w.triStamp.begin(), w.triStamp.end(), 0u);
			w.stampNow = 1;
		}
	};
	// the triangles whose 2D bounding box meets the face's, each once (since newStamp())
	auto forNear = [&](const double fxy[6], auto fn) {
		if (!gridBuilt) {
			grid.build(w.boundXY.data(), ntri, w);
			gridBuilt = true;
		}
		const double lo[2] = {std::min({fxy[0], fxy[2], fxy[4]}),
		                      std::min({fxy[1], fxy[3], fxy[5]})};
		const double hi[2] = {std::max({fxy[0], fxy[2], fxy[4]}),
		                      std::max({fxy[1], fxy[3], fxy[5]})};
		for (int y = grid.at(lo[1], 1); y <= grid.at(hi[1], 1); ++y)
			for (int x = grid.at(lo[0], 0); x <= grid.at(hi[0], 0); ++x) {
				const size_t c = size_t(y) * size_t(grid.side) + size_t(x);
				for (int32_t q = w.cellStart[c]; q < w.cellStart[c + 1]; ++q) {
					const size_t k = size_t(w.cellTri[size_t(q)]);
					if (w.triStamp[k] == w.stampNow)
						continue;
					w.triStamp[k] = w.stampNow;
					const double *tv = &w.boundXY[6 * k];
					if (std::max({tv[0], tv[2], tv[4]}) < lo[0] ||
					    std::min({tv[0], tv[2], tv[4]}) > hi[0] ||
					    std::max({tv[1], tv[3], tv[5]}) < lo[1] ||
					    std::min({tv[1], tv[3], tv[5]}) > hi[1])
						continue;
					if (!fn(k))
						return;
				}
			}
	};
	auto faceCorners = [&](int32_t i, Vec3 P[3], double fxy[6]) { // (i: position in s's faces)
		const int32_t f = in.faces.face[size_t(i)];
		for (int c = 0; c < 3; ++c) {
			P[c] = t.pos(t.T[3 * f + c]);
			if (job) {
				const size_t q = faces + size_t(w.cornerQuery[3 * size_t(i - fb) + size_t(c)]);
				fxy[2 * c] = w.job.queryXY[2 * q], fxy[2 * c + 1] = w.job.queryXY[2 * q + 1];
			} else {
				project(P[c], &fxy[2 * c]);
			}
		}
	};
	// the border chains' vertices' distances from their segments: the removed ones', and the kept
	// ones' from where they were placed (placement.cpp; 0 otherwise)
	double wb = 0;
	forRemovedRingVertices(in, s, [&](int32_t j, int32_t a, int32_t c) {
		wb = std::max(wb, pointSegmentDistance(t.pos(t.heFrom(in.rings.he[size_t(j)])), in.out(a),
		                                       in.out(c)));
		return true;
	});
	if (in.placedSlot)
		for (int32_t i = in.rings.start[size_t(in.rings.sfStart[size_t(s)])];
		     i < in.rings.start[size_t(in.rings.sfStart[size_t(s) + 1])]; ++i) {
			const int32_t v = t.heFrom(in.rings.he[size_t(i)]);
			if (in.b.keep[size_t(v)])
				wb = std::max(wb, in.moved(v));
		}
	// the triangles the check located a face's corners in (-1: none)
	auto cornersLocated = [&](int32_t i, int32_t k[3]) {
		for (int c = 0; c < 3; ++c)
			k[c] =
			    ntri == 1 ? 0
			    : job
			        ? w.job.queryTri[faces + size_t(w.cornerQuery[3 * size_t(i - fb) + size_t(c)])]
			        : -1;
	};
	double dv = 0, sfBound = 0, cosIn = 1;
	w.boundCand.clear(); // here: the faces with a part outside the outline
	for (int32_t i = fb; i < in.faces.end(s); ++i) {
		const int32_t f = in.faces.face[size_t(i)];
		Vec3 P[3];
		double fxy[6];
		faceCorners(i, P, fxy);
		const double det = orient2(&fxy[0], &fxy[2], &fxy[4]);
		const double faceArea = 0.5 * std::fabs(det);
		double covered = 0, faceGap = 0;
		int32_t located[3]; // (the triangles the check located its corners in)
		auto overlap = [&](size_t k) {
			const Vec3 &n = w.triNormal[k];
			const double nN = w.triNN[k];
			if (!(std::fabs(nN) > 1e-12))
				return true; // (seen edge-on: covers nothing in the projection)
			double g[3];     // the gap of each corner of the face to the triangle's plane, along N
			auto gaps = [&] {
				const Vec3 q0 = in.out(tri[3 * k]);
				for (int c = 0; c < 3; ++c)
					g[c] = (P[c] - q0).dot(n) / nN;
			};
			const double *tv[3] = {&w.boundXY[6 * k], &w.boundXY[6 * k + 2], &w.boundXY[6 * k + 4]};
			// (the corners not located in k first: where one is outside, it most likely is)
			int order[3], next = 0;
			for (int c = 0; c < 3; ++c)
				if (located[c] != int32_t(k))
					order[next++] = c;
			for (int c = 0; c < 3; ++c)
				if (located[c] == int32_t(k))
					order[next++] = c;
			if (insideTriangle(&fxy[2 * order[0]], tv) && insideTriangle(&fxy[2 * order[1]], tv) &&
			    insideTriangle(&fxy[2 * order[2]], tv)) { // the face is above this triangle only
				gaps();
				faceGap = std::max({faceGap, std::fabs(g[0]), std::fabs(g[1]), std::fabs(g[2])});
				covered = faceArea;
				w.triCovered[k] += faceArea;
				return false;
			}
			if (!(faceArea > 0))
				return true;
			double poly[2][12][2];
			signed char tag[2][12];
			int cur = 0;
			const int cnt = clipByTriangle(fxy, tv, w.triSign[k], poly, tag, cur);
			if (cnt == 0)
				return true; // (no overlap: nothing covered, no gap)
			gaps();
			double area2 = 0;
			for (int j = 0; j < cnt; ++j) {
				const double *a = poly[cur][j], *b = poly[cur][j + 1 == cnt ? 0 : j + 1];
				area2 += a[0] * b[1] - a[1] * b[0];
				// (at a face corner, the barycentric expression below gives that corner's gap
				// exactly: its weights come out as exactly 1 and 0)
				if (tag[cur][j] >= 0) {
					faceGap = std::max(faceGap, std::fabs(g[size_t(tag[cur][j])]));
					continue;
				}
				const double dx = a[0] - fxy[0], dy = a[1] - fxy[1];
				const double b1 = (dx * (fxy[5] - fxy[1]) - dy * (fxy[4] - fxy[0])) / det;
				const double b2 = ((fxy[2] - fxy[0]) * dy - (fxy[3] - fxy[1]) * dx) / det;
				faceGap =
				    std::max(faceGap, std::fabs((1 - b1 - b2) * g[0] + b1 * g[1] + b2 * g[2]));
			}
			covered += 0.5 * std::fabs(area2);
			w.triCovered[k] += 0.5 * std::fabs(area2);
			return true;
		};
		// the triangles its corners are in first; if they cover it, no other can overlap it
		cornersLocated(i, located);
		newStamp();
		bool more = true;
		for (int c = 0; c < 3 && more; ++c) {
			const int32_t k = located[c];
			if (k < 0 || w.triStamp[size_t(k)] == w.stampNow)
				continue;
			w.triStamp[size_t(k)] = w.stampNow;
			more = overlap(size_t(k)) && !(covered >= faceArea * (1 - 1e-12) && faceArea > 0);
		}
		if (more)
			forNear(fxy, overlap);
		dv = std::max(dv, faceGap);
		sfBound = std::max(sfBound, faceGap);
		bound[size_t(f)] = std::max(bound[size_t(f)], roundedUp(std::min(faceGap, w.boundCap)));
		if (!(faceArea > 0) || covered < faceArea * (1 - 1e-10)) {
			w.boundCand.push_back(i);
			const Vec3 n = (P[1] - P[0]) ^ (P[2] - P[0]);
			cosIn = std::min(cosIn, n.Norm() > 0 ? n.dot(N) / n.Norm() : 0.0);
		}
	}
	// outward pockets
	const double outward = wb > 0 && cosIn > 0 ? wb / cosIn + wb : HUGE_VAL;
	for (const int32_t i : w.boundCand) {
		const int32_t f = in.faces.face[size_t(i)];
		Vec3 P[3];
		double fxy[6];
		faceCorners(i, P, fxy);
		double best = outward * outward; // (squared)
		auto convex = [&](size_t k) {
			const int32_t *v = &tri[3 * k];
			double m = 0;
			for (int c = 0; c < 3 && m < best; ++c)
				m = std::max(
				    m, pointTriangleDistance2(P[c], in.out(v[0]), in.out(v[1]), in.out(v[2])));
			best = std::min(best, m);
			return true;
		};
		newStamp(); // (every triangle near this face, whatever the faces before saw)
		forNear(fxy, convex);
		if (!(best < HUGE_VAL))
			for (size_t k = 0; k < ntri; ++k)
				convex(k);
		const double d = std::sqrt(best);
		bound[size_t(f)] = std::max(bound[size_t(f)], roundedUp(std::min(d, w.boundCap)));
		sfBound = std::max(sfBound, d);
	}
	// inward pockets
	double cosOut = 1, longest = 0;
	bool inward = false;
	for (size_t k = 0; k < ntri; ++k) {
		if (w.triCovered[k] >= w.triArea[k] * (1 - 1e-10) && w.triArea[k] > 0)
			continue;
		inward = true;
		cosOut = std::min(cosOut, std::fabs(w.triNormal[k].dot(N)));
		// (each point of the triangle is within its longest edge of a vertex, an input vertex
		// or one placed that far from it)
		double edge = 0, placed = 0;
		for (size_t c = 0; c < 3; ++c) {
			edge =
			    std::max(edge, (in.out(tri[3 * k + c]) - in.out(tri[3 * k + (c + 1) % 3])).Norm());
			placed = std::max(placed, in.moved(tri[3 * k + c]));
		}
		longest = std::max(longest, edge + placed);
	}
	if (inward) {
		const double d = std::min(cosOut > 0 ? wb / cosOut + dv : HUGE_VAL, longest);
		const size_t f0 = size_t(in.faces.face[size_t(in.faces.begin(s))]);
		bound[f0] = std::max(bound[f0], roundedUp(std::min(d, w.boundCap)));
		sfBound = std::max(sfBound, d);
	}
	return std::min(sfBound, w.boundCap);
}

Failure distanceCheck(const TriangulationInput &in, int32_t s, const Vec3 &N, size_t firstTri,
                      Scratch &w, const ChunkOut &o, std::vector<float> &gap)
{
	const Failure border = bordersWithin(in, s, gap);
	if (border != Failure::None)
		return border;
	const size_t ntri = o.tris.size() / 3 - firstTri;
	const size_t faces = size_t(in.faces.end(s) - in.faces.begin(s));
	const Topology &t = in.t;
	// once a face is too far, the others are still looked at (insertion follows): each triangle
	// too far from a face gets a corner of it to insert (w.farCorner)
	bool far = false;
	if (ntri > 1)
		w.farCorner.assign(ntri, std::make_pair(-1.0, int32_t(-1)));
	for (size_t i = 0; i < faces; ++i) {
		const int32_t f = in.faces.face[size_t(in.faces.begin(s)) + i];
		const Vec3 P[3] = {t.pos(t.T[3 * f]), t.pos(t.T[3 * f + 1]), t.pos(t.T[3 * f + 2])};
		auto tooFar = [&](size_t, int32_t k) {
			return faceTooFar(in, s, i, f, P, k, N, firstTri, w, o, gap);
		};
		if (ntri == 1) { // (no triangulation was run)
			if (tooFar(i, 0))
				return Failure::Distance;
			continue;
		}
		const int32_t *cq = &w.cornerQuery[3 * i];
		const int32_t under[4] = {w.job.queryTri[i], w.job.queryTri[faces + size_t(cq[0])],
		                          w.job.queryTri[faces + size_t(cq[1])],
		                          w.job.queryTri[faces + size_t(cq[2])]};
		for (int j = 0; j < 4; ++j) {
			const int32_t k = under[j];
			if (k < 0 || std::find(under, under + j, k) != under + j)
				continue;
			if (tooFar(i, k)) {
				far = true;
				for (int c = 0; c < 3; ++c)
					offerInsertion(in, w, o, firstTri, N, k, t.T[3 * f + c],
					               w.farCorner[size_t(k)]);
			}
		}
	}
	return far ? Failure::Distance : Failure::None;
}

} // namespace detail
} // namespace gausslod
