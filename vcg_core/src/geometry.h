// Geometry kernels of the engine: half-edge indexing, distances, angles and the sphere cell of
// a normal (half-edge h = 3*face + k goes from corner k to corner (k+1)%3 of its face).
#pragma once

#include "sphere_cells.h"

#include <vcg/space/point3.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace gausslod {
namespace detail {

using Vec3 = vcg::Point3d;

inline int32_t heFace(int32_t h) { return h / 3; }
inline int32_t heNext(int32_t h) { return h - h % 3 + (h % 3 + 1) % 3; }
inline int32_t hePrev(int32_t h) { return h - h % 3 + (h % 3 + 2) % 3; }

/// Squared distance from p to triangle (a, b, c) (closest point by Voronoi regions). VCG's
/// TrianglePointDistance projects on the plane and takes square roots; this runs per candidate
/// face on the flip check's hot path. (The tests check the result with VCG's.)
inline double pointTriangleDistance2(const Vec3 &p, const Vec3 &a, const Vec3 &b, const Vec3 &c)
{
	const Vec3 ab = b - a, ac = c - a, ap = p - a;
	const double d1 = ab.dot(ap), d2 = ac.dot(ap);
	if (d1 <= 0 && d2 <= 0)
		return ap.SquaredNorm();
	const Vec3 bp = p - b;
	const double d3 = ab.dot(bp), d4 = ac.dot(bp);
	if (d3 >= 0 && d4 <= d3)
		return bp.SquaredNorm();
	const double vc = d1 * d4 - d3 * d2;
	if (vc <= 0 && d1 >= 0 && d3 <= 0)
		return (ap - ab * (d1 / (d1 - d3))).SquaredNorm();
	const Vec3 cp = p - c;
	const double d5 = ab.dot(cp), d6 = ac.dot(cp);
	if (d6 >= 0 && d5 <= d6)
		return cp.SquaredNorm();
	const double vb = d5 * d2 - d1 * d6;
	if (vb <= 0 && d2 >= 0 && d6 <= 0)
		return (ap - ac * (d2 / (d2 - d6))).SquaredNorm();
	const double va = d3 * d6 - d5 * d4;
	if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
		return (bp - (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))).SquaredNorm();
	const double den = 1.0 / (va + vb + vc);
	return (ap - ab * (vb * den) - ac * (vc * den)).SquaredNorm();
}

/// The angle whose cosine this is (clamped to [-1, 1]), radians.
inline double angleOfCos(double cosine) { return std::acos(std::max(-1.0, std::min(1.0, cosine))); }
/// The same, degrees.
inline double angleDegOfCos(double cosine)
{
	constexpr double kRadToDeg = 57.295779513082320876798;
	return angleOfCos(cosine) * kRadToDeg;
}
/// Angle between two unit vectors, degrees.
inline double angleDeg(const Vec3 &a, const Vec3 &b) { return angleDegOfCos(a.dot(b)); }

/// A unit axis of the plane orthogonal to unit N (the projections' U; V = N ^ U).
inline Vec3 planeAxis(const Vec3 &N)
{
	return (std::fabs(N[0]) < 0.9 ? N ^ Vec3(1, 0, 0) : N ^ Vec3(0, 1, 0)).Normalize();
}

/// Distance from p to the segment a-b.
inline double pointSegmentDistance(const Vec3 &p, const Vec3 &a, const Vec3 &b)
{
	const Vec3 ab = b - a;
	const double len2 = ab.SquaredNorm();
	double t = len2 > 0 ? (p - a).dot(ab) / len2 : 0.0;
	t = std::max(0.0, std::min(1.0, t));
	return (p - (a + ab * t)).Norm();
}

/// 2.1 The cell of a face normal at `level`, packed; kInvalidCell for a zero or non-finite one.
inline CellKey cellOfNormal(const Vec3 &n, int level)
{
	const double nn[3] = {n[0], n[1], n[2]};
	Cell c;
	return normalToCell(nn, level, c) ? packCell(c) : kInvalidCell;
}

} // namespace detail
} // namespace gausslod
