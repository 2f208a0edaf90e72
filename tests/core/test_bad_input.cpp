// A corpus of broken meshes, generated here, each with its expected outcome: a clear error, or
// levels that keep the invariants relative to what the input already was.
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>

using namespace gausslod;
using namespace testmesh;

namespace {

struct Case {
	const char *name;
	std::function<FlatMesh()> make;
	const char *error; ///< expected error substring, or nullptr: levels must be valid
};

FlatMesh tri(std::vector<double> p, std::vector<int32_t> t)
{
	FlatMesh m;
	m.positions = std::move(p);
	m.triangles = std::move(t);
	return m;
}

void append(FlatMesh &m, const FlatMesh &o, double dx = 0)
{
	const int32_t base = int32_t(m.positions.size() / 3);
	for (size_t i = 0; i < o.positions.size(); ++i)
		m.positions.push_back(o.positions[i] + (i % 3 == 0 ? dx : 0.0));
	for (int32_t v : o.triangles)
		m.triangles.push_back(v + base);
}

FlatMesh tetrahedra(int count)
{
	FlatMesh m;
	const FlatMesh t =
	    tri({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3});
	for (int i = 0; i < count; ++i)
		append(m, t, 2.0 * i);
	return m;
}

FlatMesh moebius(int n)
{
	FlatMesh m;
	for (int i = 0; i < n; ++i) {
		const double a = 2 * M_PI * i / n;
		for (int s = -1; s <= 1; s += 2) {
			const double r = 1 + 0.3 * s * std::cos(a / 2);
			m.positions.push_back(r * std::cos(a));
			m.positions.push_back(r * std::sin(a));
			m.positions.push_back(0.3 * s * std::sin(a / 2));
		}
	}
	for (int i = 0; i < n; ++i) {
		int32_t a = 2 * i, b = 2 * i + 1, c = 2 * ((i + 1) % n), d = c + 1;
		if (i == n - 1)
			std::swap(c, d); // the half twist
		m.triangles.insert(m.triangles.end(), {a, c, b, b, c, d});
	}
	return m;
}

FlatMesh gridMesh(int n, std::function<double(double, double)> z)
{
	FlatMesh m = gridWithHole(n, 0, 0);
	for (size_t v = 0; v < m.positions.size() / 3; ++v)
		m.positions[3 * v + 2] = z(m.positions[3 * v], m.positions[3 * v + 1]);
	return m;
}

const std::vector<Case> &corpus()
{
	static const std::vector<Case> cases = {
	    {"empty mesh", [] { return FlatMesh(); }, "no faces"},
	    {"points only",
	     [] {
		     return tri({0, 0, 0, 1, 0, 0, 0, 1, 0}, {});
	     },
	     "no faces"},
	    {"single triangle",
	     [] {
		     return tri({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2});
	     },
	     nullptr},
	    {"zero-area and collinear triangles",
	     [] {
		     FlatMesh m = gridWithHole(6, 0, 0);
		     const int32_t n = int32_t(m.positions.size() / 3);
		     m.positions.insert(m.positions.end(), {0.5, 0.5, 0, 2, 2, 0, 3, 3, 0, 4, 4, 0});
		     m.triangles.insert(m.triangles.end(), {n + 1, n + 2, n + 3, 0, 0, 1, n, n, n});
		     return m;
	     },
	     nullptr},
	    {"duplicated faces",
	     [] {
		     FlatMesh m = gridCube(3);
		     const std::vector<int32_t> t(m.triangles.begin(), m.triangles.begin() + 9);
		     m.triangles.insert(m.triangles.end(), t.begin(), t.end());
		     m.triangles.insert(m.triangles.end(), {t[0], t[2], t[1]}); // and one reversed copy
		     return m;
	     },
	     nullptr},
	    {"unreferenced and duplicated vertices",
	     [] {
		     FlatMesh m = gridCube(4);
		     m.positions.insert(m.positions.end(), {9, 9, 9, NAN, 0, 0}); // unreferenced, even NaN
		     // duplicate every vertex of the first 20 faces: cracks along them
		     for (size_t i = 0; i < 60; ++i) {
			     const int32_t v = m.triangles[i];
			     m.triangles[i] = int32_t(m.positions.size() / 3);
			     for (int k = 0; k < 3; ++k)
				     m.positions.push_back(m.positions[3 * size_t(v) + k]);
		     }
		     return m;
	     },
	     nullptr},
	    {"NaN coordinate",
	     [] {
		     FlatMesh m = gridCube(2);
		     m.positions[1] = NAN;
		     return m;
	     },
	     "non-finite"},
	    {"infinite coordinate",
	     [] {
		     FlatMesh m = gridCube(2);
		     m.positions[4] = std::numeric_limits<double>::infinity();
		     return m;
	     },
	     "non-finite"},
	    {"vertex index out of range",
	     [] {
		     FlatMesh m = gridCube(2);
		     m.triangles[7] = -3;
		     return m;
	     },
	     "does not exist"},
	    {"coordinates around 1e9",
	     [] {
		     FlatMesh m = gridCube(10, 1e3, 1e-1, 9);
		     for (double &x : m.positions)
			     x += 1e9;
		     return m;
	     },
	     nullptr},
	    {"coordinates around 1e-9", [] { return gridCube(10, 1e-9, 1e-14, 9); }, nullptr},
	    {"non-manifold edges (three faces on an edge)",
	     [] {
		     FlatMesh m = gridWithHole(4, 0, 0);
		     const int32_t n = int32_t(m.positions.size() / 3);
		     m.positions.insert(m.positions.end(), {0.0, 0.25, 1.0});
		     m.triangles.insert(m.triangles.end(), {0, 1, n}); // fin on the edge (0,1)
		     return m;
	     },
	     nullptr},
	    {"bow-tie vertices",
	     [] {
		     FlatMesh m = tetrahedra(1);
		     FlatMesh o = tetrahedra(1);
		     const int32_t base = int32_t(m.positions.size() / 3);
		     for (size_t i = 0; i < o.positions.size(); ++i)
			     m.positions.push_back(-o.positions[i]);
		     for (int32_t v : o.triangles) // share vertex 0 (the origin) with the first tetrahedron
			     m.triangles.push_back(v == 0 ? 0 : v + base);
		     for (size_t f = m.triangles.size() - 12; f < m.triangles.size(); f += 3)
			     std::swap(m.triangles[f + 1], m.triangles[f + 2]); // mirrored: keep outward
		     return m;
	     },
	     nullptr},
	    {"inconsistently oriented faces",
	     [] {
		     FlatMesh m = gridCube(4);
		     for (size_t f = 0; f < m.triangles.size() / 3; f += 7)
			     std::swap(m.triangles[3 * f + 1], m.triangles[3 * f + 2]);
		     return m;
	     },
	     nullptr},
	    {"Moebius strip", [] { return moebius(60); }, nullptr},
	    {"open mesh with many holes",
	     [] {
		     FlatMesh m = gridMesh(
		         40, [](double x, double y) { return 0.1 * std::sin(6 * x) * std::cos(5 * y); });
		     std::vector<int32_t> kept;
		     for (size_t f = 0; f < m.triangles.size() / 3; ++f)
			     if (f % 37 != 5)
				     kept.insert(kept.end(), m.triangles.begin() + 3 * f,
				                 m.triangles.begin() + 3 * f + 3);
		     m.triangles = kept;
		     return m;
	     },
	     nullptr},
	    {"10,000 disconnected tetrahedra", [] { return tetrahedra(10000); }, nullptr},
	    {"every face coplanar but one",
	     [] {
		     FlatMesh m = gridWithHole(30, 0, 0);
		     m.positions[3 * (15 * 31 + 15) + 2] = 0.01; // lifts the faces around one vertex
		     return m;
	     },
	     nullptr},
	    {"one huge triangle beside 20,000 tiny faces",
	     [] {
		     FlatMesh m = gridWithHole(100, 0, 0); // a unit square of 100 x 100 quads
		     append(m, tri({-1e6, -1e6, 5, 1e6, -1e6, 5, 0, 1e6, 5}, {0, 1, 2}));
		     return m;
	     },
	     nullptr},
	    {"very thin long strip",
	     [] {
		     FlatMesh m;
		     for (int i = 0; i <= 2000; ++i)
			     m.positions.insert(m.positions.end(),
			                        {double(i), 0, 0, double(i), 1e-6, 1e-7 * (i % 3)});
		     for (int32_t i = 0; i < 2000; ++i)
			     m.triangles.insert(m.triangles.end(),
			                        {2 * i, 2 * i + 2, 2 * i + 1, 2 * i + 1, 2 * i + 2, 2 * i + 3});
		     return m;
	     },
	     nullptr},
	};
	return cases;
}

} // namespace

TEST(BadInput, every_case_gives_its_expected_error_or_valid_levels)
{
	for (const Case &c : corpus()) {
		SCOPED_TRACE(c.name);
		const FlatMesh in = c.make();
		const FlatMesh copy = in;
		const Result r = buildLevels(in.view(), Params());
		// the input is never touched (bitwise: NaNs compare by representation)
		ASSERT_TRUE(in.positions.empty() ||
		            0 == std::memcmp(copy.positions.data(), in.positions.data(),
		                             in.positions.size() * sizeof(double)));
		ASSERT_EQ(copy.triangles, in.triangles);
		if (c.error) {
			EXPECT_FALSE(r.ok);
			EXPECT_NE(r.error.find(c.error), std::string::npos) << r.error;
			EXPECT_TRUE(r.levels.empty());
			continue;
		}
		ASSERT_TRUE(r.ok) << r.error;
		ASSERT_EQ(r.levels.size(), 5u);
		// faces with a repeated vertex index (after welding) are no triangles: the engine leaves
		// them out
		const FlatMesh welded = weldedCopy(in);
		std::vector<int32_t> triangles;
		for (size_t f = 0; f < welded.triangles.size() / 3; ++f) {
			const int32_t *t = &welded.triangles[3 * f];
			if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
				triangles.insert(triangles.end(), t, t + 3);
		}
		const TopoFacts inF = topoFacts(in.positions, triangles);
		for (const LevelMesh &lm : r.levels) {
			SCOPED_TRACE("level " + std::to_string(lm.stats.level));
			const TopoFacts f = topoFacts(lm.positions, lm.triangles);
			EXPECT_GT(f.faces, 0u);
			EXPECT_EQ(f.duplicateFaces, 0u); // duplicates of the input are dropped
			EXPECT_LE(f.degenerateFaces, inF.degenerateFaces); // zero-area input faces are kept
			EXPECT_LE(f.nonManifoldEdges, inF.nonManifoldEdges);
			EXPECT_LE(f.nonManifoldVertices, inF.nonManifoldVertices + inF.nonManifoldEdges);
			EXPECT_LE(f.inconsistentEdges, inF.inconsistentEdges);
			EXPECT_EQ(f.components, inF.components);
			if (inF.closedManifold()) {
				EXPECT_TRUE(f.closedManifold());
				EXPECT_EQ(f.genus(), inF.genus());
			}
			for (int32_t v : lm.triangles)
				ASSERT_TRUE(v >= 0 && size_t(v) < lm.positions.size() / 3);
			for (double x : lm.positions)
				ASSERT_TRUE(std::isfinite(x));
		}
		for (size_t i = 1; i < r.levels.size(); ++i)
			EXPECT_LE(r.levels[i].stats.faces, r.levels[i - 1].stats.faces);
	}
}

TEST(BadInput, bad_parameters_give_a_clear_error)
{
	const FlatMesh m = gridCube(2);
	auto err = [&](std::function<void(Params &)> set) {
		Params p;
		set(p);
		return buildLevels(m.view(), p).error;
	};
	EXPECT_NE(err([](Params &p) { p.maxLevel = 9; }).find("levels"), std::string::npos);
	EXPECT_NE(err([](Params &p) { p.featureAngle = 0; }).find("featureAngle"), std::string::npos);
	EXPECT_NE(err([](Params &p) { p.straightenTol = -1; }).find("straightening"),
	          std::string::npos);
	EXPECT_NE(err([](Params &p) { p.mergeDist = NAN; }).find("merge"), std::string::npos);
	EXPECT_NE(err([](Params &p) { p.normalLimit = -2; }).find("deviation"), std::string::npos);
	EXPECT_NE(err([](Params &p) { p.maxDistance = -1; }).find("maxDistance"), std::string::npos);
	EXPECT_NE(err([](Params &p) { p.maxDistance = INFINITY; }).find("maxDistance"),
	          std::string::npos);
}

TEST(BadInput, progress_callback_can_cancel)
{
	const FlatMesh m = gridCube(8);
	int calls = 0;
	const Result r =
	    buildLevels(m.view(), Params(), [&](double, const char *) { return ++calls < 3; });
	EXPECT_FALSE(r.ok);
	EXPECT_EQ(r.error, "cancelled");
	EXPECT_TRUE(r.levels.empty());
}

namespace {
// Edges used once or more than twice, or twice in the same direction (sort-based: large meshes).
size_t openOrBadEdges(const std::vector<int32_t> &t)
{
	std::vector<std::pair<uint64_t, int>> e;
	e.reserve(t.size());
	for (size_t i = 0; i < t.size(); ++i) {
		const int32_t a = t[i], b = t[i - i % 3 + (i % 3 + 1) % 3];
		e.emplace_back((uint64_t(uint32_t(std::min(a, b))) << 32) | uint32_t(std::max(a, b)),
		               a < b);
	}
	std::sort(e.begin(), e.end());
	size_t bad = 0;
	for (size_t i = 0; i < e.size();) {
		size_t j = i + 1;
		while (j < e.size() && e[j].first == e[i].first)
			++j;
		bad += (j - i != 2 || e[i].second == e[i + 1].second);
		i = j;
	}
	return bad;
}
} // namespace

TEST(BadInput, a_2M_triangle_closed_mesh_gives_closed_levels)
{
	// a bumpy sphere of 2,000 x 500 quads (1,996,000 triangles + poles), closed
	const int nu = 2000, nv = 501;
	FlatMesh m;
	for (int j = 1; j < nv; ++j)
		for (int i = 0; i < nu; ++i) {
			const double th = M_PI * j / nv, ph = 2 * M_PI * i / nu;
			const double r = 1 + 0.05 * std::sin(5 * ph) * std::sin(4 * th);
			m.positions.insert(m.positions.end(),
			                   {r * std::sin(th) * std::cos(ph), r * std::sin(th) * std::sin(ph),
			                    r * std::cos(th)});
		}
	const int32_t top = int32_t(m.positions.size() / 3), bottom = top + 1;
	m.positions.insert(m.positions.end(), {0, 0, 1, 0, 0, -1});
	auto id = [&](int j, int i) { return int32_t((j - 1) * nu + (i % nu)); };
	for (int j = 1; j < nv - 1; ++j)
		for (int i = 0; i < nu; ++i)
			m.triangles.insert(m.triangles.end(), {id(j, i), id(j + 1, i), id(j + 1, i + 1),
			                                       id(j, i), id(j + 1, i + 1), id(j, i + 1)});
	for (int i = 0; i < nu; ++i)
		m.triangles.insert(m.triangles.end(),
		                   {top, id(1, i), id(1, i + 1), bottom, id(nv - 1, i + 1), id(nv - 1, i)});
	ASSERT_GE(m.triangles.size() / 3, 2000000u);
	ASSERT_EQ(openOrBadEdges(m.triangles), 0u);
	Params p;
	p.certifyDistance = false; // (closed levels at scale; the certified distance has its tests)
	const Result r = buildLevels(m.view(), p);
	ASSERT_TRUE(r.ok) << r.error;
	size_t finer = m.triangles.size() / 3;
	for (const LevelMesh &lm : r.levels) {
		EXPECT_EQ(openOrBadEdges(lm.triangles), 0u) << "level " << lm.stats.level;
		EXPECT_LE(lm.stats.faces, finer);
		if (!lm.stats.reduced) // (a level continued to a real step measures its deviation)
			EXPECT_LE(lm.stats.maxNormalDevDeg, lm.stats.boundDeg + 1e-9)
			    << "level " << lm.stats.level;
		finer = lm.stats.faces;
	}
	EXPECT_LT(finer, m.triangles.size() / 3 / 20); // the coarsest level is much lighter
}
