// Beyond the paper (2.4, Params::maxDistance): what the distance check (distance_check.cpp) and
// the distance bound (distance_bound.cpp) share: the removed ring vertices, and an input face
// clipped by a new triangle in the projection.
#pragma once

#include "level_passes.h"

namespace gausslod {
namespace detail {

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

// The orientation of the 2D triangle tv, as clipByTriangle takes it: 1 or -1.
inline double clipSign(const double *const tv[3])
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
inline int clipByTriangle(const double fxy[6], const double *const tv[3], double sign,
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

} // namespace detail
} // namespace gausslod
