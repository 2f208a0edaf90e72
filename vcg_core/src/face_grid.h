// A hashed uniform grid over the input faces, for "which faces are near this point" queries.
#pragma once

#include "geometry.h"

#include <vector>

namespace gausslod {
namespace detail {

/// Hashed uniform grid over the valid input faces (each listed in every cell its bounding box
/// meets; cells hashed into buckets, so a bucket may also hold faces of other cells), for "which
/// input faces are near this point" queries.
struct FaceGrid {
	double lo[3] = {0, 0, 0};
	double cell = 1;
	uint64_t mask = 0;                ///< buckets - 1 (a power of two)
	std::vector<int32_t> start, face; ///< bucket -> faces (CSR)
	std::vector<int32_t> big;         ///< faces too large to list per cell: every query sees them
	/// Per bucket, a cone around its faces' normals: an axis a (int8 x, y, z in bits 0-23) and a
	/// bound s (bits 24-31, /254, s >= 1) such that every face normal n listed in the bucket has
	/// n . t >= 0 for any unit t with (a / |a|) . t >= s / 254 (s = 255: no such t); 0 until
	/// coneOf computes it (the first query that meets the bucket: on most meshes few are met).
	mutable std::vector<uint32_t> cone;

	static uint64_t bucketOf(int64_t x, int64_t y, int64_t z, uint64_t mask)
	{
		const uint64_t h =
		    uint64_t(x) * 73856093u ^ uint64_t(y) * 19349663u ^ uint64_t(z) * 83492791u;
		return (h ^ (h >> 29)) & mask;
	}
	int64_t index(double x, int k) const { return int64_t(std::floor((x - lo[k]) / cell)); }

	/// Calls fn(face) for the big faces and the faces listed in the buckets of the cells that
	/// meet the box [a, b] (a face may come more than once; faces of other cells may come too).
	template <class Fn>
	void forBox(const Vec3 &a, const Vec3 &b, Fn fn) const
	{
		forBuckets(
		    a, b, [](uint64_t) { return false; }, fn);
	}

	/// forBox, but with a unit direction `t`: only the buckets that may hold a face whose normal
	/// n has n . t < 0 (by their cone, coneOf with `normals`: Topology::faceNormal) are listed
	/// (the big faces all are).
	template <class Normals, class Fn>
	void forBoxFacingAway(const Vec3 &a, const Vec3 &b, const Vec3 &t, const Normals &normals,
	                      Fn fn) const
	{
		forBuckets(
		    a, b, [&](uint64_t c) { return allFacing(coneOf(c, normals), t); }, fn);
	}

	/// forBox, skipping the buckets c with skip(c).
	template <class Skip, class Fn>
	void forBuckets(const Vec3 &a, const Vec3 &b, Skip skip, Fn fn) const
	{
		for (const int32_t f : big)
			fn(f);
		if (start.size() < 2)
			return;
		const int64_t x0 = index(a[0], 0), x1 = index(b[0], 0), y0 = index(a[1], 1),
		              y1 = index(b[1], 1), z0 = index(a[2], 2), z1 = index(b[2], 2);
		for (int64_t z = z0; z <= z1; ++z)
			for (int64_t y = y0; y <= y1; ++y)
				for (int64_t x = x0; x <= x1; ++x) {
					const uint64_t c = bucketOf(x, y, z, mask);
					if (skip(c))
						continue;
					for (int32_t i = start[c]; i < start[c + 1]; ++i)
						fn(face[size_t(i)]);
				}
	}

	/// Bucket c's cone (see `cone`), computed from `normals` (Topology::faceNormal) the first time
	/// it is asked. Any number of threads may ask at once: a cone depends only on the bucket's
	/// faces, so two threads that compute the same one store the same bits. The axis: the mean
	/// normal, rounded to int8 (the bound is measured from the rounded axis); s / 254 >= sine of
	/// the widest angle from it, rounded up with a margin of one step (far above the rounding of
	/// the dot products that use it).
	template <class Normals>
	uint32_t coneOf(uint64_t c, const Normals &normals) const
	{
		const uint32_t known = __atomic_load_n(&cone[c], __ATOMIC_RELAXED);
		if (known != 0)
			return known;
		Vec3 sum(0, 0, 0);
		for (int32_t i = start[c]; i < start[c + 1]; ++i)
			sum += normals[size_t(face[size_t(i)])];
		const double len = sum.Norm();
		uint32_t packed = packCone(0, 0, 0, 255);
		if (len > 0) {
			int q[3];
			for (int k = 0; k < 3; ++k)
				q[k] = int(std::lround(127.0 * sum[k] / len));
			const Vec3 axis = Vec3(q[0], q[1], q[2]).Normalize();
			double minCos = 1;
			for (int32_t i = start[c]; i < start[c + 1]; ++i) // (the same normals, the same bits)
				minCos = std::min(minCos, normals[size_t(face[size_t(i)])].dot(axis));
			int s = 255;
			if (minCos > 0) {
				const double sine = std::sqrt(std::max(0.0, 1.0 - minCos * minCos));
				s = std::min(255, int(std::ceil(sine * 254.0)) + 1);
			}
			packed = packCone(q[0], q[1], q[2], s);
		}
		__atomic_store_n(&cone[c], packed, __ATOMIC_RELAXED);
		return packed;
	}

	static uint32_t packCone(int ax, int ay, int az, int s)
	{
		return uint32_t(uint8_t(int8_t(ax))) | uint32_t(uint8_t(int8_t(ay))) << 8 |
		       uint32_t(uint8_t(int8_t(az))) << 16 | uint32_t(s) << 24;
	}
	/// Does every normal of a bucket with this cone face t (n . t >= 0)?
	static bool allFacing(uint32_t cone, const Vec3 &t)
	{
		const uint32_t s = cone >> 24;
		if (s >= 255)
			return false;
		const double ax = int8_t(cone & 0xff), ay = int8_t((cone >> 8) & 0xff),
		             az = int8_t((cone >> 16) & 0xff);
		const double d = ax * t[0] + ay * t[1] + az * t[2], bound = double(s) / 254.0;
		return d > 0 && d * d >= bound * bound * (ax * ax + ay * ay + az * az);
	}
};

} // namespace detail
} // namespace gausslod
