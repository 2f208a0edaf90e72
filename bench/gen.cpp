// bench_gen: synthetic meshes for the benchmark, and format conversion, as binary PLY.
//   bench_gen cube N OUT [NOISE]     unit cube, each side an N x N grid (shared edge vertices);
//                                    NOISE > 0: every coordinate moved by uniform [-NOISE, NOISE]
//   bench_gen sphere SEG RINGS OUT   UV sphere, radius 1 (SEG around, RINGS from pole to pole)
//   bench_gen bumpy SEG RINGS OUT    UV sphere with smooth bumps: r = 1 + 0.08 sin(6t) cos(5p) +
//   ... bench_gen convert IN OUT         any format VCG reads (OFF, OBJ, STL, PLY) -> binary PLY
//   bench_gen subdivide K IN OUT     IN's triangles each split K times into 4 at their edge
//                                    midpoints (flat: the same surface, 4^K times the faces)
// All meshes are closed, 2-manifold and outward oriented. Deterministic (fixed seed).
#include "bench_mesh.h"

#include <cmath>
#include <cstdlib>
#include <map>
#include <random>
#include <tuple>

namespace {

int usage()
{
	std::fprintf(stderr, "usage: bench_gen cube N OUT [NOISE] | sphere SEG RINGS OUT | "
	                     "bumpy SEG RINGS OUT | convert IN OUT | subdivide K IN OUT\n");
	return 2;
}

int cube(int n, const std::string &out, double noise)
{
	std::vector<double> pos;
	std::vector<uint32_t> tri;
	std::map<std::tuple<int, int, int>, uint32_t> index;
	auto vid = [&](int x, int y, int z) {
		const auto key = std::make_tuple(x, y, z);
		auto it = index.find(key);
		if (it != index.end())
			return it->second;
		const uint32_t id = uint32_t(pos.size() / 3);
		pos.push_back(double(x) / n);
		pos.push_back(double(y) / n);
		pos.push_back(double(z) / n);
		index.emplace(key, id);
		return id;
	};
	// For each axis and side: the face lies at coordinate 0 or n on `axis`; (u, v) span the others
	// so that u x v points outward.
	for (int axis = 0; axis < 3; ++axis)
		for (int side = 0; side < 2; ++side) {
			int ua = (axis + 1) % 3, va = (axis + 2) % 3;
			if (side == 0)
				std::swap(ua, va);
			auto at = [&](int u, int v) {
				int c[3];
				c[axis] = side ? n : 0;
				c[ua] = u;
				c[va] = v;
				return vid(c[0], c[1], c[2]);
			};
			for (int i = 0; i < n; ++i)
				for (int j = 0; j < n; ++j) {
					const uint32_t a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1),
					               d = at(i, j + 1);
					tri.insert(tri.end(), {a, b, c, a, c, d});
				}
		}
	if (noise > 0) {
		std::mt19937_64 rng(12345);
		std::uniform_real_distribution<double> u(-noise, noise);
		for (double &p : pos)
			p += u(rng);
	}
	return bench::writePly(out, pos, tri) ? 0 : 1;
}

int sphere(int seg, int rings, const std::string &out, bool bumpy)
{
	std::vector<double> pos;
	std::vector<uint32_t> tri;
	const double pi = std::acos(-1.0);
	auto radius = [&](double theta, double phi) {
		if (!bumpy)
			return 1.0;
		return 1.0 + 0.08 * std::sin(6 * theta) * std::cos(5 * phi) +
		       0.03 * std::sin(17 * theta + 1.0) * std::sin(13 * phi);
	};
	auto push = [&](double theta, double phi) {
		const double r = radius(theta, phi);
		pos.push_back(r * std::sin(theta) * std::cos(phi));
		pos.push_back(r * std::sin(theta) * std::sin(phi));
		pos.push_back(r * std::cos(theta));
	};
	push(0, 0); // north pole: 0
	for (int r = 1; r < rings; ++r)
		for (int s = 0; s < seg; ++s)
			push(pi * r / rings, 2 * pi * s / seg);
	push(pi, 0); // south pole
	const uint32_t south = uint32_t(pos.size() / 3 - 1);
	auto ring = [&](int r, int s) { return uint32_t(1 + (r - 1) * seg + ((s % seg) + seg) % seg); };
	for (int s = 0; s < seg; ++s)
		tri.insert(tri.end(), {0u, ring(1, s), ring(1, s + 1)});
	for (int r = 1; r + 1 < rings; ++r)
		for (int s = 0; s < seg; ++s) {
			const uint32_t a = ring(r, s), b = ring(r + 1, s), c = ring(r + 1, s + 1),
			               d = ring(r, s + 1);
			tri.insert(tri.end(), {a, b, c, a, c, d});
		}
	for (int s = 0; s < seg; ++s)
		tri.insert(tri.end(), {south, ring(rings - 1, s + 1), ring(rings - 1, s)});
	return bench::writePly(out, pos, tri) ? 0 : 1;
}

// The mesh of file `in` as flat arrays; false (and a message) if it cannot be read.
bool loadFlat(const std::string &in, bench::Flat &f)
{
	bench::FMesh m;
	std::string err;
	if (!bench::load(m, in, err)) {
		std::fprintf(stderr, "bench_gen: cannot read %s: %s\n", in.c_str(), err.c_str());
		return false;
	}
	f = bench::flatten(m);
	return true;
}

int convert(const std::string &in, const std::string &out)
{
	bench::Flat f;
	if (!loadFlat(in, f))
		return 1;
	return bench::writePly(out, f.pos, f.tri) ? 0 : 1;
}

// Each triangle into 4 at its edge midpoints, K times; a midpoint is shared by the edge's faces.
int subdivide(int k, const std::string &in, const std::string &out)
{
	bench::Flat f;
	if (!loadFlat(in, f))
		return 1;
	std::vector<double> pos(f.pos.begin(), f.pos.end());
	std::vector<uint32_t> tri = f.tri;
	for (int round = 0; round < k; ++round) {
		std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
		auto midpoint = [&](uint32_t a, uint32_t b) {
			const auto key = std::make_pair(std::min(a, b), std::max(a, b));
			auto it = mid.find(key);
			if (it != mid.end())
				return it->second;
			const uint32_t id = uint32_t(pos.size() / 3);
			for (int c = 0; c < 3; ++c)
				pos.push_back(0.5 * (pos[3 * a + uint32_t(c)] + pos[3 * b + uint32_t(c)]));
			mid.emplace(key, id);
			return id;
		};
		std::vector<uint32_t> next;
		next.reserve(4 * tri.size());
		for (size_t t = 0; t < tri.size(); t += 3) {
			const uint32_t a = tri[t], b = tri[t + 1], c = tri[t + 2];
			const uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
			next.insert(next.end(), {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca});
		}
		tri.swap(next);
	}
	return bench::writePly(out, pos, tri) ? 0 : 1;
}

} // namespace

int main(int argc, char **argv)
{
	if (argc < 2)
		return usage();
	const std::string mode = argv[1];
	if (mode == "cube" && (argc == 4 || argc == 5))
		return cube(std::atoi(argv[2]), argv[3], argc == 5 ? std::atof(argv[4]) : 0.0);
	if ((mode == "sphere" || mode == "bumpy") && argc == 5)
		return sphere(std::atoi(argv[2]), std::atoi(argv[3]), argv[4], mode == "bumpy");
	if (mode == "convert" && argc == 4)
		return convert(argv[2], argv[3]);
	if (mode == "subdivide" && argc == 5)
		return subdivide(std::atoi(argv[2]), argv[3], argv[4]);
	return usage();
}
