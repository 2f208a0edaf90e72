// Beyond the paper (docs/DESIGN.md, 52): a level's distance to the input, certified. The
// two-sided Hausdorff distance between two triangle sets, bracketed by branch and bound: a lower
// bound from points whose distance is computed exactly, an upper bound that holds for every
// point of every triangle, refined where the upper bound is above (1 + eps) x the lower one.
#pragma once

#include "engine.h"

#include <algorithm>

namespace gausslod {
namespace detail {

/// A bounding-volume hierarchy over some triangles of a mesh, for nearest-triangle queries.
/// Triangles with a repeated vertex index or a non-finite coordinate are left out.
class TriangleTree {
public:
	TriangleTree(const double *P, const int32_t *T, size_t nT);
	bool empty() const { return tri_.empty(); }
	/// The nearest triangle to p (-1 if none) and its squared distance, among those nearer than
	/// sqrt(best2) (pass HUGE_VAL for any).
	int32_t nearest(const Vec3 &p, double &best2) const;
	/// The triangles whose box meets the box lo..hi, into out (at most cap; false if more).
	bool collect(const Vec3 &lo, const Vec3 &hi, int32_t *out, int &n, int cap) const;
	/// Squared distance from p to triangle f (a degenerate one: to its edges).
	double distance2(int32_t f, const Vec3 &p) const;
	const double *P() const { return P_; }
	const int32_t *T() const { return T_; }
	const std::vector<int32_t> &triangles() const { return tri_; }
	/// The triangles across the edges of triangle f (-1: none, or f's edge is on more than two).
	const int32_t *across(int32_t f) const { return &adj_[3 * size_t(f)]; }

private:
	struct Node {
		Vec3 lo, hi;
		int32_t first, count; ///< a leaf: triangles tri_[first..first+count); else count = -1
		int32_t right;        ///< an inner node: its left child is the next node
	};
	const double *P_;
	const int32_t *T_;
	std::vector<int32_t> tri_;
	std::vector<uint8_t> flat_; ///< per triangle of T: degenerate (zero cross product)
	std::vector<int32_t> adj_;  ///< per corner of T: the triangle across the edge from it
	std::vector<Node> nodes_;
	Vec3 v(int32_t f, int k) const;
	void keepTriangles(size_t nT);
	void linkEdges(size_t nT);
	void buildNodes();
};

/// Squared distance from p to the segment a-b.
inline double segmentDistance2(const Vec3 &p, const Vec3 &a, const Vec3 &b)
{
	const Vec3 ab = b - a;
	const double l2 = ab.SquaredNorm();
	const double t = l2 > 0 ? std::min(1.0, std::max(0.0, (p - a).dot(ab) / l2)) : 0.0;
	return (p - (a + ab * t)).SquaredNorm();
}

// (inline here: the inner loops of the bounds, in other files, call them per candidate)
inline Vec3 TriangleTree::v(int32_t f, int k) const
{
	const double *q = &P_[3 * size_t(T_[3 * size_t(f) + size_t(k)])];
	return Vec3(q[0], q[1], q[2]);
}

inline double TriangleTree::distance2(int32_t f, const Vec3 &p) const
{
	const Vec3 a = v(f, 0), b = v(f, 1), c = v(f, 2);
	if (flat_[size_t(f)])
		return std::min(
		    {segmentDistance2(p, a, b), segmentDistance2(p, b, c), segmentDistance2(p, c, a)});
	return pointTriangleDistance2(p, a, b, c);
}

/// Which bound of a piece held it (hausdorff_bounds.cpp): its corners (Lipschitz, convexity), the
/// cover by the other side's triangles, the split by planes between them.
enum class BoundBy : uint8_t { corners, cover, split };

struct HausdorffBounds {
	double lower = 0;      ///< the largest distance measured at a point (a true distance)
	double upper = 0;      ///< every point of each set is at most this far from the other set
	size_t pieces = 0;     ///< sub-triangles evaluated
	size_t byCover = 0;    ///< pieces bounded by the cover
	size_t bySplit = 0;    ///< pieces bounded by the split
	bool converged = true; ///< upper <= (1 + eps) x max(lower, floor) (else out of budget)
};

/// The distance from the triangles of `from` to those of `to`, one way: max over points of
/// `from` of the distance to `to`. Bounds within a factor 1 + eps where `maxPieces` allows;
/// parts known to be within (1 + eps) x `known` (a lower bound found elsewhere) are not refined,
/// so that `upper` is then only within that factor of max(lower, known).
HausdorffBounds directedHausdorff(const TriangleTree &from, const TriangleTree &to, double eps,
                                  size_t maxPieces, size_t threads, double known);

/// Both ways: the largest lower and upper bounds of the two directions. Parts within (1 + eps) x
/// `floor` (a distance) are not refined: the bounds are within the factor of max(lower, floor)
/// (without a floor, two surfaces that coincide, as a planar level and its input do, would be
/// refined until maxPieces: no bound is within a factor of 0).
HausdorffBounds hausdorff(const TriangleTree &a, const TriangleTree &b, double eps,
                          size_t maxPieces, size_t threads, double floor = 0);

} // namespace detail
} // namespace gausslod
