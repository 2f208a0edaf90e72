// bench_texdev: how far a simplified textured mesh's texture coordinates moved from the
// original's. Prints one JSON line.
//   bench_texdev [--samples N] [--texels T] ORIGINAL SIMPLIFIED
//
// N area-uniform samples on SIMPLIFIED, each with the texture coordinates its face's wedges give
// there; the closest point on ORIGINAL (CGAL AABB tree over its faces) gives the coordinates the
// original has at that place; the shift is their distance, in texels of a T x T texture (T = 1024).
// A sample whose closest original point lies across a seam is mapped by the other chart: its shift
// is large and says nothing of the simplification, so the figures are quantiles, not the maximum:
//   shift_median_texels, shift_p90_texels, shift_p95_texels
//   over_2_texels_pct   percent of samples shifted more than 2 texels
// Both meshes need per-wedge texture coordinates (OBJ vt, PLY texcoord).
#include "bench_mesh.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <random>

namespace {

using K = CGAL::Simple_cartesian<double>;
using Tri = K::Triangle_3;
using Iter = std::vector<Tri>::const_iterator;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, CGAL::AABB_triangle_primitive<K, Iter>>>;

struct Textured {
	std::vector<Tri> tri;
	std::vector<float> uv; // 6 per face
};

bool read(const char *file, Textured &out)
{
	gausslod::IoAttrMesh m;
	std::string err;
	if (!bench::load(m, file, err)) {
		std::fprintf(stderr, "bench_texdev: %s: %s\n", file, err.c_str());
		return false;
	}
	if (!vcg::tri::HasPerWedgeTexCoord(m)) {
		std::fprintf(stderr, "bench_texdev: %s has no per-wedge texture coordinates\n", file);
		return false;
	}
	for (const auto &f : m.face) {
		if (f.IsD())
			continue;
		K::Point_3 p[3];
		for (int k = 0; k < 3; ++k) {
			p[k] = K::Point_3(f.cP(k)[0], f.cP(k)[1], f.cP(k)[2]);
			out.uv.push_back(f.cWT(k).U());
			out.uv.push_back(f.cWT(k).V());
		}
		out.tri.emplace_back(p[0], p[1], p[2]);
	}
	return !out.tri.empty();
}

// Barycentric coordinates of q (on or near triangle t) in t's plane.
void barycentric(const Tri &t, const K::Point_3 &q, double l[3])
{
	const K::Vector_3 e1 = t[1] - t[0], e2 = t[2] - t[0], d = q - t[0];
	const double a11 = e1 * e1, a12 = e1 * e2, a22 = e2 * e2, det = a11 * a22 - a12 * a12;
	l[1] = l[2] = 0;
	if (det > 0) {
		l[1] = (a22 * (d * e1) - a12 * (d * e2)) / det;
		l[2] = (a11 * (d * e2) - a12 * (d * e1)) / det;
	}
	l[0] = 1 - l[1] - l[2];
}

} // namespace

int main(int argc, char **argv)
{
	int nSamples = 100000;
	double texels = 1024;
	int a = 1;
	for (; a + 1 < argc && argv[a][0] == '-' && argv[a][1] == '-'; a += 2) {
		const std::string o = argv[a];
		if (o == "--samples")
			nSamples = std::atoi(argv[a + 1]);
		else if (o == "--texels")
			texels = std::atof(argv[a + 1]);
		else
			break;
	}
	if (argc - a != 2 || nSamples <= 0 || !(texels > 0)) {
		std::fprintf(stderr,
		             "usage: bench_texdev [--samples N] [--texels T] ORIGINAL SIMPLIFIED\n");
		return 2;
	}
	Textured orig, simp;
	if (!read(argv[a], orig) || !read(argv[a + 1], simp))
		return 1;
	Tree tree(orig.tri.cbegin(), orig.tri.cend());
	tree.accelerate_distance_queries();
	// area-uniform samples on the simplified mesh
	std::vector<double> cum(simp.tri.size());
	double total = 0;
	for (size_t f = 0; f < simp.tri.size(); ++f)
		cum[f] = total += std::sqrt(std::max(0.0, simp.tri[f].squared_area()));
	std::mt19937_64 rng(4711);
	std::uniform_real_distribution<double> u01(0, 1);
	std::vector<double> shift;
	shift.reserve(size_t(nSamples));
	for (int s = 0; s < nSamples && total > 0; ++s) {
		const size_t f =
		    size_t(std::lower_bound(cum.begin(), cum.end(), u01(rng) * total) - cum.begin());
		if (f >= simp.tri.size())
			continue;
		double r1 = u01(rng), r2 = u01(rng);
		if (r1 + r2 > 1)
			r1 = 1 - r1, r2 = 1 - r2;
		const Tri &t = simp.tri[f];
		const K::Point_3 p = t[0] + r1 * (t[1] - t[0]) + r2 * (t[2] - t[0]);
		const double ls[3] = {1 - r1 - r2, r1, r2};
		const auto hit = tree.closest_point_and_primitive(p);
		const size_t g = size_t(hit.second - orig.tri.cbegin());
		double lo[3];
		barycentric(orig.tri[g], hit.first, lo);
		double d2 = 0;
		for (int k = 0; k < 2; ++k) {
			double us = 0, uo = 0;
			for (int m = 0; m < 3; ++m) {
				us += ls[m] * simp.uv[6 * f + 2 * size_t(m) + size_t(k)];
				uo += lo[m] * orig.uv[6 * g + 2 * size_t(m) + size_t(k)];
			}
			d2 += (us - uo) * (us - uo);
		}
		shift.push_back(std::sqrt(d2) * texels);
	}
	if (shift.empty()) {
		std::fprintf(stderr, "bench_texdev: no sample (zero area)\n");
		return 1;
	}
	std::sort(shift.begin(), shift.end());
	auto q = [&](double x) {
		return shift[std::min(shift.size() - 1, size_t(x * double(shift.size())))];
	};
	size_t over = 0;
	for (double x : shift)
		over += x > 2;
	std::printf(
	    "{\"samples\": %zu, \"faces\": %zu, \"shift_median_texels\": %.4g, "
	    "\"shift_p90_texels\": %.4g, \"shift_p95_texels\": %.4g, \"over_2_texels_pct\": %.4g}\n",
	    shift.size(), simp.tri.size(), q(0.5), q(0.9), q(0.95),
	    100.0 * double(over) / double(shift.size()));
	return 0;
}
