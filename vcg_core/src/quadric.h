// A quadric error metric (Garland and Heckbert, "Surface Simplification Using Quadric Error
// Metrics", SIGGRAPH 1997): the weighted sum of squared distances of a point to a set of planes.
#pragma once

#include "engine.h"

#include <array>

namespace gausslod {
namespace detail {

/// p'Ap + 2b'p + c, A symmetric: a00 a01 a02 a11 a12 a22, then b0 b1 b2, then c.
struct Quadric {
	std::array<double, 10> q{};
	/// Adds w x (n.p + d)^2 (n a unit normal).
	void addPlane(const Vec3 &n, double d, double w)
	{
		const double v[10] = {n[0] * n[0], n[0] * n[1], n[0] * n[2], n[1] * n[1], n[1] * n[2],
		                      n[2] * n[2], d * n[0],    d * n[1],    d * n[2],    d * d};
		for (size_t i = 0; i < 10; ++i)
			q[i] += w * v[i];
	}
	Quadric &operator+=(const Quadric &o)
	{
		for (size_t i = 0; i < 10; ++i)
			q[i] += o.q[i];
		return *this;
	}
	double eval(const Vec3 &p) const
	{
		const double x = p[0], y = p[1], z = p[2];
		return q[0] * x * x + 2 * q[1] * x * y + 2 * q[2] * x * z + q[3] * y * y +
		       2 * q[4] * y * z + q[5] * z * z + 2 * (q[6] * x + q[7] * y + q[8] * z) + q[9];
	}
	/// The t that minimises the quadric along p + t n, and the curvature n'An there (no minimum
	/// along n unless it is > 0).
	double stepAlong(const Vec3 &p, const Vec3 &n, double &curv) const;
	/// Of the points where the quadric is least, the one nearest `m` (directions whose curvature
	/// is below 1e-3 of the largest stay at m's coordinate): false if A is zero.
	bool minimum(const Vec3 &m, Vec3 &out) const;
};

} // namespace detail
} // namespace gausslod
