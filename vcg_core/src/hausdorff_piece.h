// Internal to the certified Hausdorff distance (hausdorff.cpp, hausdorff_bounds.cpp): a piece of
// a triangle and the upper bound of its distance to the other triangle set.
#pragma once

#include "hausdorff.h"

#include <algorithm>

namespace gausslod {
namespace detail {

/// A piece of a triangle of A: its corners, their distances to B and the triangles of B nearest
/// to them, and an upper bound of the distance to B over it.
struct TrianglePiece {
	Vec3 p[3];
	double d[3];
	int32_t n[3];
	bool exact[3]; ///< d is the distance to the whole set (else only to triangle n: above it)
	double u;
	BoundBy by; ///< which bound gave u
	/// an exact distance at a point of the piece met while bounding it (-1: none)
	double seen = -1;
	bool operator<(const TrianglePiece &o) const { return u < o.u; }
};

/// The triangles nearest to a piece's corners and those across their edges (at most 12).
inline int gather(const TriangleTree &to, const TrianglePiece &pc, int32_t *out)
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

/// An upper bound of the distance to `to` over the piece, cheapest first (corners, cover,
/// split; see hausdorff_bounds.cpp), and which bound gave it (`by`). The cover and split are
/// tried only while the bound is above `target`. Where a cover is proved above the target, its
/// farthest point's exact distance goes to `seen` (a lower bound of the distance: it lets the
/// caller settle the piece without cutting it).
double upperBound(const TriangleTree &to, const TrianglePiece &pc, double target, BoundBy &by,
                  double *seen = nullptr);

} // namespace detail
} // namespace gausslod
