// libFuzzer target: bytes -> a small mesh and parameters -> buildLevels, checking that it either
// reports an error or returns levels whose indices, coordinates and face counts are sane and
// that keep the closedness of a closed input. Built with clang -fsanitize=fuzzer,address,undefined
// (tests/fuzz/CMakeLists.txt); crash inputs found and fixed go to tests/fuzz/regressions/.
#include "gausslod/gausslod.h"

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
		// each output vertex is its input vertex, placed (if at all) within half the tolerance
		const double tol = params.maxDistance * diag *
		                   std::pow(params.distanceGrowth, params.maxLevel - 1 - lm.stats.level);
		if (lm.stats.maxPlacement > 0.5 * tol * (1 + 1e-9) || lm.sourceVertex.size() != nvOut)
			fail("a vertex placed farther than half the level's tolerance");
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
