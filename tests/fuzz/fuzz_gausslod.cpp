// libFuzzer target: bytes -> a small mesh and parameters -> buildLevels, checking that it either
// reports an error or returns levels whose indices, coordinates and face counts are sane and
// that keep the closedness of a closed input. Built with clang -fsanitize=fuzzer,address,undefined
// (tests/fuzz/CMakeLists.txt); crash inputs found and fixed go to tests/fuzz/regressions/.
#include "gausslod/gausslod.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <utility>
#include <vector>

namespace {

struct Reader {
	const uint8_t *p;
	size_t n;
	uint8_t byte() { return n ? (--n, *p++) : 0; }
};

// Counts edges used once (boundary) or more than twice, and same-direction pairs.
std::pair<size_t, size_t> edgeDefects(const std::vector<int32_t> &t)
{
	std::map<std::pair<int32_t, int32_t>, std::pair<int, int>> e;
	for (size_t i = 0; i < t.size(); ++i) {
		const int32_t a = t[i], b = t[i - i % 3 + (i % 3 + 1) % 3];
		auto &x = e[{std::min(a, b), std::max(a, b)}];
		++x.first;
		x.second += a < b;
	}
	size_t open = 0, bad = 0;
	for (const auto &kv : e) {
		if (kv.second.first == 1)
			++open;
		else if (kv.second.first > 2 || kv.second.second != 1)
			++bad;
	}
	return {open, bad};
}

struct P3 {
	double x, y, z;
};
P3 operator-(P3 a, P3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
P3 operator+(P3 a, P3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
P3 operator*(P3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot(P3 a, P3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
P3 cross(P3 a, P3 b)
{
	return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

double segmentDistance2(P3 p, P3 a, P3 b)
{
	const P3 ab = b - a;
	const double l2 = dot(ab, ab);
	const double t = l2 > 0 ? std::min(1.0, std::max(0.0, dot(p - a, ab) / l2)) : 0.0;
	const P3 d = p - (a + ab * t);
	return dot(d, d);
}

// Squared distance from p to the triangle abc (degenerate ones: to their edges).
double triangleDistance2(P3 p, P3 a, P3 b, P3 c)
{
	const P3 n = cross(b - a, c - a);
	const double n2 = dot(n, n);
	if (n2 > 0) { // (inside the prism over the triangle: the distance to its plane)
		const bool in = dot(cross(b - a, p - a), n) >= 0 && dot(cross(c - b, p - b), n) >= 0 &&
		                dot(cross(a - c, p - c), n) >= 0;
		if (in) {
			const double h = dot(p - a, n);
			return h * h / n2;
		}
	}
	return std::min(
	    {segmentDistance2(p, a, b), segmentDistance2(p, b, c), segmentDistance2(p, c, a)});
}

[[noreturn]] void fail(const char *what)
{
	std::fprintf(stderr, "fuzz_gausslod: %s\n", what);
	std::abort();
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	Reader r{data, size};
	gausslod::Params params;
	params.maxLevel = 1 + r.byte() % 5;
	params.featureAngle = 1 + r.byte() % 170;
	params.straightenTol = (r.byte() % 16) * 0.02; // (fractions of the diagonal)
	params.mergeDist = (r.byte() % 16) * 0.02;
	const uint8_t limits = r.byte();
	params.normalLimit = (limits % 4) * 0.75;
	params.maxDistance =
	    ((limits >> 2) % 4) * 0.01; // (same byte: earlier inputs keep their meaning)
	const size_t nv = 3 + r.byte() % 40;
	std::vector<double> pos(3 * nv);
	const uint8_t scaleByte = r.byte();
	const double scale = std::ldexp(1.0, int(scaleByte % 40) - 20);
	for (double &x : pos)
		x = (int(r.byte()) - 128) * scale / 16.0; // coarse lattice: many coplanar and collinear
	std::vector<int32_t> tris;
	while (r.n >= 3 && tris.size() < 3 * 200)
		for (int k = 0; k < 3; ++k)
			tris.push_back(int32_t(r.byte() % nv));
	gausslod::MeshView view;
	view.positions = pos.data();
	view.vertexCount = nv;
	view.triangles = tris.data();
	view.faceCount = tris.size() / 3;
	const std::vector<double> posCopy = pos;
	const std::vector<int32_t> trisCopy = tris;
	const gausslod::Result res = gausslod::buildLevels(view, params);
	if (pos != posCopy || tris != trisCopy)
		fail("the input changed");
	if (!res.ok) {
		if (res.error.empty() || !res.levels.empty())
			fail("a failed run without a message, or with levels");
		return 0;
	}
	const auto in = edgeDefects(tris);
	const double diag = gausslod::bboxDiagonal(view);
	size_t prevFaces = SIZE_MAX;
	const gausslod::LevelMesh *finer = nullptr;
	for (const gausslod::LevelMesh &lm : res.levels) {
		// DESIGN 29 (angle mode, the only mode here): a coarser level farther from the input is
		// 1 % lighter; a reused level is the finer level's mesh and figures
		if (finer && lm.stats.distanceBound > finer->stats.distanceBound &&
		    double(lm.stats.faces) > 0.99 * double(finer->stats.faces))
			fail("a coarser level farther from the input and not 1 % lighter");
		if (finer && lm.stats.reusedFiner &&
		    (lm.triangles != finer->triangles || lm.positions != finer->positions ||
		     lm.stats.distanceBound != finer->stats.distanceBound))
			fail("a reused level that is not its finer level");
		finer = &lm;
		const size_t nvOut = lm.positions.size() / 3;
		for (int32_t v : lm.triangles)
			if (v < 0 || size_t(v) >= nvOut)
				fail("vertex index out of range");
		// each output vertex is its input vertex, placed (if at all) within half the tolerance;
		// a level continued by collapses (DESIGN 51) places the kept vertex where its quadric is
		// least, held only by the level's proven bound (checked below for every level)
		const double tol = params.maxDistance * diag *
		                   std::pow(params.distanceGrowth, params.maxLevel - 1 - lm.stats.level);
		if (lm.sourceVertex.size() != nvOut)
			fail("a source vertex list of the wrong length");
		if (!lm.stats.reduced && lm.stats.maxPlacement > 0.5 * tol * (1 + 1e-9))
			fail("a vertex placed farther than half the level's tolerance");
		// the bound holds from the level to the input, and the certified Hausdorff distance
		// (DESIGN 52) both ways: at vertices, edge midpoints and triangle centroids (sampled, so
		// at most the true distance); the input's triangles with a repeated vertex are left out
		auto farthest = [](const std::vector<double> &P, const std::vector<int32_t> &T,
		                   const std::vector<double> &toP, const std::vector<int32_t> &toT) {
			auto repeated = [](const int32_t *t) {
				return t[0] == t[1] || t[1] == t[2] || t[2] == t[0];
			};
			double worst = 0;
			for (size_t f = 0; 3 * f + 2 < T.size(); ++f) {
				if (repeated(&T[3 * f]))
					continue;
				P3 c[3];
				for (int k = 0; k < 3; ++k) {
					const double *q = &P[3 * size_t(T[3 * f + size_t(k)])];
					c[k] = {q[0], q[1], q[2]};
				}
				const P3 samples[7] = {c[0],
				                       c[1],
				                       c[2],
				                       (c[0] + c[1]) * 0.5,
				                       (c[1] + c[2]) * 0.5,
				                       (c[2] + c[0]) * 0.5,
				                       (c[0] + c[1] + c[2]) * (1.0 / 3)};
				for (const P3 &s : samples) {
					double d2 = HUGE_VAL;
					for (size_t t = 0; 3 * t + 2 < toT.size(); ++t) {
						if (repeated(&toT[3 * t]))
							continue;
						const double *a = &toP[3 * size_t(toT[3 * t])],
						             *b = &toP[3 * size_t(toT[3 * t + 1])],
						             *e = &toP[3 * size_t(toT[3 * t + 2])];
						d2 =
						    std::min(d2, triangleDistance2(s, {a[0], a[1], a[2]},
						                                   {b[0], b[1], b[2]}, {e[0], e[1], e[2]}));
					}
					worst = std::max(worst, std::sqrt(d2));
				}
			}
			return worst;
		};
		const double levelFar = farthest(lm.positions, lm.triangles, pos, tris);
		if (lm.stats.distanceBound >= 0 &&
		    levelFar > lm.stats.distanceBound * (1 + 1e-9) + 1e-12 * diag)
			fail("a point of the level farther from the input than its distance bound");
		if (lm.stats.hausdorff >= 0) {
			const double inputFar = farthest(pos, tris, lm.positions, lm.triangles);
			if (std::max(levelFar, inputFar) > lm.stats.hausdorff)
				fail(
				    "a point farther from the other surface than the certified Hausdorff distance");
			if (!(lm.stats.hausdorffLower <= lm.stats.hausdorff) ||
			    (lm.stats.hausdorffConverged &&
			     lm.stats.hausdorff >
			         1.05 * std::max(lm.stats.hausdorffLower, 1e-6 * diag) * (1 + 1e-6) +
			             1e-11 * diag)) // (DESIGN 52: under 1e-6 x the diagonal, not refined)
				fail("a certified Hausdorff distance not within its factor of its lower bound");
		}
		for (size_t v = 0; v < nvOut; ++v) {
			const int32_t s = lm.sourceVertex[v];
			if (s < 0 || size_t(s) >= nv)
				fail("source vertex out of range");
			double d2 = 0;
			for (size_t k = 0; k < 3; ++k) {
				const double e = lm.positions[3 * v + k] - pos[3 * size_t(s) + k];
				d2 += e * e;
			}
			if (std::sqrt(d2) > lm.stats.maxPlacement * (1 + 1e-9) + 1e-12 * diag)
				fail(
				    "an output vertex farther from its input vertex than the level's largest move");
		}
		for (double x : lm.positions)
			if (!std::isfinite(x))
				fail("non-finite output coordinate");
		if (lm.triangles.size() % 3 || lm.superface.size() * 3 != lm.triangles.size())
			fail("inconsistent output arrays");
		const auto out = edgeDefects(lm.triangles);
		if (in.first == 0 && in.second == 0 && (out.first != 0 || out.second != 0))
			fail("a closed 2-manifold input did not stay closed");
		if (lm.stats.faces > prevFaces)
			fail("face counts are not monotone");
		prevFaces = lm.stats.faces;
	}
	return 0;
}
