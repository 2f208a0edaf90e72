// Beyond the paper (issue 17): with the distance tolerance, a curved superface gets inside vertices
// inserted where its triangulation is too far from the input, instead of being split back into
// finer superfaces; every input vertex stays within the tolerance of its level.
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>

using namespace gausslod;
using namespace testmesh;

namespace {

// A dome z = h (1 - x^2 - y^2) over an n x n grid of [-1,1]^2: a height field, curved everywhere.
FlatMesh dome(int n, double h)
{
	FlatMesh m = gridWithHole(n, 0, 0);
	for (size_t v = 0; v < m.positions.size() / 3; ++v) {
		double *p = &m.positions[3 * v];
		p[0] = 2 * p[0] - 1, p[1] = 2 * p[1] - 1;
		p[2] = h * (1 - p[0] * p[0] - p[1] * p[1]);
	}
	return m;
}

// The distance from p to triangle f of the level.
double triangleDistance(const LevelMesh &lm, size_t f, const Vec3 &p)
{
	const vcg::Triangle3<double> t(vpos(lm.positions, lm.triangles[3 * f]),
	                               vpos(lm.positions, lm.triangles[3 * f + 1]),
	                               vpos(lm.positions, lm.triangles[3 * f + 2]));
	double d;
	Vec3 q;
	vcg::TrianglePointDistance(t, p, d, q);
	return d;
}

// Input vertices farther than `tol` from every triangle of the level (each triangle's box,
// grown by tol, first: only the triangles near a vertex are measured).
size_t verticesBeyond(const FlatMesh &m, const LevelMesh &lm, double tol)
{
	std::vector<vcg::Box3<double>> box(lm.triangles.size() / 3);
	for (size_t f = 0; f < box.size(); ++f) {
		for (size_t k = 0; k < 3; ++k)
			box[f].Add(vpos(lm.positions, lm.triangles[3 * f + k]));
		box[f].Offset(tol);
	}
	size_t beyond = 0;
	for (size_t v = 0; v < m.positions.size() / 3; ++v) {
		const Vec3 p = vpos(m.positions, int32_t(v));
		bool near = false;
		for (size_t f = 0; f < box.size() && !near; ++f) {
			if (!box[f].IsIn(p))
				continue;
			near = triangleDistance(lm, f, p) <= tol;
		}
		beyond += !near;
	}
	return beyond;
}

// Output vertices with no superface border edge: only inserted inside vertices can be such.
size_t insideVertices(const LevelMesh &lm)
{
	std::vector<uint8_t> onBorder(lm.positions.size() / 3, 0);
	for (size_t f = 0; f < lm.triangles.size() / 3; ++f)
		for (size_t k = 0; k < 3; ++k)
			if (lm.borderEdges[f] & (1u << k)) {
				onBorder[size_t(lm.triangles[3 * f + k])] = 1;
				onBorder[size_t(lm.triangles[3 * f + (k + 1) % 3])] = 1;
			}
	size_t n = 0;
	for (uint8_t b : onBorder)
		n += !b;
	return n;
}

// The same distance tolerance (fraction of the diagonal) at every level.
Params uniformTolerance(double tol)
{
	Params prm = superfaceParams();
	prm.maxDistance = tol;
	prm.distanceGrowth = 1;
	return prm;
}

} // namespace

TEST(Quality, a_curved_superface_gets_inside_vertices_and_stays_within_the_tolerance)
{
	const FlatMesh m = dome(40, 0.15);
	const double diag = bboxDiagonal(m.view());
	const Params prm = uniformTolerance(0.002); // 0.2 % of the diagonal
	const Result r = buildLevels(m.view(), prm);
	ASSERT_TRUE(r.ok) << r.error;
	const LevelMesh &coarsest = r.levels.back();
	const double tol = prm.maxDistance * diag * (1 + 1e-9);
	EXPECT_EQ(verticesBeyond(m, coarsest, tol), 0u);
	EXPECT_GT(insideVertices(coarsest), 0u); // (the paper's rings alone have none)
	EXPECT_LT(coarsest.stats.faces, m.triangles.size() / 3 / 4);
	for (const LevelMesh &lm : r.levels)
		EXPECT_EQ(verticesBeyond(m, lm, tol), 0u) << "LOD" << lm.stats.level;
	// without the tolerance there is nothing to insert for
	Params normalsOnly;
	normalsOnly.maxDistance = 0;
	const Result plain = buildLevels(m.view(), normalsOnly);
	ASSERT_TRUE(plain.ok);
	for (const LevelMesh &lm : plain.levels)
		EXPECT_EQ(insideVertices(lm), 0u);
}

// Diagonals chosen by the distance (DESIGN 26): on fandisk's blended surfaces the Delaunay
// diagonals of a coarse superface leave it beyond the tolerance where other diagonals of the same
// vertices do not; with the flips its two coarsest levels have fewer faces (426 and 658 without
// them) and every input vertex stays within each level's tolerance.
TEST(Quality, data_dependent_diagonals_coarsen_a_curved_cad_part)
{
	const FlatMesh m = loadOff("fandisk.off");
	const double diag = bboxDiagonal(m.view());
	const Params prm;
	const Result r = buildLevels(m.view(), prm);
	ASSERT_TRUE(r.ok) << r.error;
	ASSERT_EQ(r.levels.size(), 5u);
	EXPECT_LT(r.levels[3].stats.faces, 600u); // LOD1
	EXPECT_LT(r.levels[4].stats.faces, 400u); // LOD0
	for (const LevelMesh &lm : r.levels) {
		const double tol = prm.maxDistance * diag *
		                   std::pow(prm.distanceGrowth, prm.maxLevel - 1 - lm.stats.level);
		EXPECT_EQ(verticesBeyond(m, lm, tol * (1 + 1e-6)), 0u) << "LOD" << lm.stats.level;
	}
}

TEST(Quality, the_default_tolerance_grows_by_level_and_coarser_levels_stay_coarser)
{
	for (const char *name : {"fandisk.off", "cow.off"}) {
		SCOPED_TRACE(name);
		const FlatMesh m = loadOff(name);
		const double diag = bboxDiagonal(m.view());
		const Params prm = superfaceParams(); // 0.02 % at the finest level, x2 per coarser level
		ASSERT_GT(prm.maxDistance, 0);
		const Result r = buildLevels(m.view(), prm);
		ASSERT_TRUE(r.ok) << r.error;
		Params normalsOnly = superfaceParams();
		normalsOnly.maxDistance = 0;
		const Result paper = buildLevels(m.view(), normalsOnly);
		ASSERT_TRUE(paper.ok);
		size_t finer = m.triangles.size() / 3;
		for (size_t i = 0; i < r.levels.size(); ++i) {
			const LevelMesh &lm = r.levels[i];
			SCOPED_TRACE("LOD" + std::to_string(lm.stats.level));
			const double tol = prm.maxDistance * diag *
			                   std::pow(prm.distanceGrowth, prm.maxLevel - 1 - lm.stats.level);
			// (the pockets, wb / cos: DESIGN 23; the check measures distances to the triangles'
			// planes, so coarse superfaces with steep parts pass it: cow LOD0 3.05 x)
			EXPECT_LE(lm.stats.distanceBound, 4 * tol);
			// (the tolerance is the superface build's check; a level made by collapses of the
			// finer level, DESIGN 50, keeps the superface level's bound instead)
			EXPECT_EQ(verticesBeyond(
			              m, lm, (lm.stats.collapses ? lm.stats.distanceBound : tol) * (1 + 1e-6)),
			          0u);
			EXPECT_LE(lm.stats.faces, finer);
			finer = lm.stats.faces;
			// (the test can fail: the paper's levels are farther than that)
			if (lm.stats.level == 0)
				EXPECT_GT(verticesBeyond(m, paper.levels[i], 2 * tol), 0u);
		}
		EXPECT_LT(r.levels.back().stats.faces, m.triangles.size() / 3 * 3 / 4);
	}
}

// Levels by target (issue #17, item 3): a face budget per level is met (<= budget) on real
// models, with as many faces as fit; an unreachable budget is reported, never hidden.
TEST(Quality, levels_by_face_budget_reach_every_budget_on_real_models)
{
	// DESIGN 51: where the superfaces cannot get to a budget (the cow's curved surface: its
	// coarsest superface level keeps about 57 % of its faces) the level is continued by edge
	// collapses; every budget is reached, with as many faces as fit (within a collapse or two)
	struct Case {
		const char *name, *levelsBy;
		int percent[3]; // by level
	};
	for (const Case &c : {Case{"fandisk.off", "faces:10%,50%,2%", {2, 10, 50}},
	                      Case{"cow.off", "faces:5%, 40%,20%", {5, 20, 40}}}) {
		SCOPED_TRACE(c.name);
		const FlatMesh m = loadOff(c.name);
		const size_t nF = m.triangles.size() / 3;
		const TopoFacts inFacts = topoFacts(m.positions, m.triangles);
		Params prm;
		std::string error;
		ASSERT_TRUE(parseLevelsBy(c.levelsBy, prm, error)) << error;
		ASSERT_EQ(prm.maxLevel, 3);
		const Result r = buildLevels(m.view(), prm);
		ASSERT_TRUE(r.ok) << r.error;
		ASSERT_EQ(r.levels.size(), 3u);
		size_t collapsed = 0;
		for (const LevelMesh &lm : r.levels) {
			const LevelStats &s = lm.stats;
			SCOPED_TRACE("LOD" + std::to_string(s.level));
			const size_t want = nF * size_t(c.percent[s.level]) / 100;
			EXPECT_EQ(s.targetFaces, want);
			EXPECT_EQ(s.targetDistance, -1);
			EXPECT_EQ(lm.triangles.size() / 3, s.faces);
			EXPECT_TRUE(s.targetReached) << s.faces << " faces for a budget of " << want;
			EXPECT_LE(s.faces, want);
			EXPECT_GE(s.faces + 2, want * 98 / 100); // (a collapse takes 2 faces off)
			EXPECT_GE(s.distanceBound, 0);
			collapsed += s.reduced;
			if (inFacts.closedManifold()) // (the cow: closed in, closed out)
				EXPECT_TRUE(topoFacts(lm.positions, lm.triangles).closedManifold());
		}
		EXPECT_GE(collapsed, 2u); // (the test reaches past what the superfaces can)
	}
	// the least a closed surface of genus 0 can have: a tetrahedron
	const FlatMesh cow = loadOff("cow.off");
	Params tiny;
	std::string error;
	ASSERT_TRUE(parseLevelsBy("faces:4,8,16", tiny, error)) << error;
	const Result t = buildLevels(cow.view(), tiny);
	ASSERT_TRUE(t.ok) << t.error;
	for (const LevelMesh &lm : t.levels) {
		EXPECT_TRUE(lm.stats.targetReached) << lm.stats.faces;
		EXPECT_TRUE(topoFacts(lm.positions, lm.triangles).closedManifold());
	}
	EXPECT_EQ(t.levels.back().stats.faces, 4u);
}

TEST(Quality, levels_by_error_bound_each_levels_measured_distance)
{
	for (const char *name : {"fandisk.off", "cow.off"}) {
		SCOPED_TRACE(name);
		const FlatMesh m = loadOff(name);
		const double diag = bboxDiagonal(m.view());
		Params prm;
		std::string error;
		ASSERT_TRUE(parseLevelsBy("error:0.2%,0.01%,0.05%", prm, error)) << error;
		ASSERT_EQ(prm.maxLevel, 3);
		const Result r = buildLevels(m.view(), prm);
		ASSERT_TRUE(r.ok) << r.error;
		const double want[3] = {0.002, 0.0005, 0.0001}; // by level
		size_t finer = m.triangles.size() / 3;
		for (const LevelMesh &lm : r.levels) {
			const LevelStats &s = lm.stats;
			SCOPED_TRACE("LOD" + std::to_string(s.level));
			EXPECT_DOUBLE_EQ(s.targetDistance, want[s.level]);
			EXPECT_DOUBLE_EQ(s.tolerance, want[s.level]);
			EXPECT_EQ(s.targetFaces, 0u);
			// levels by error: the proven bound itself within the target (DESIGN 23), or, where
			// the collapses went past it, the certified distance (DESIGN 52)
			EXPECT_GE(s.distanceBound, 0);
			EXPECT_GE(s.hausdorff, 0);
			EXPECT_TRUE(s.distanceBound <= want[s.level] * diag * (1 + 1e-5) ||
			            s.hausdorff <= want[s.level] * diag)
			    << s.distanceBound << " " << s.hausdorff;
			EXPECT_TRUE(s.targetReached);
			EXPECT_EQ(verticesBeyond(m, lm, want[s.level] * diag * (1 + 1e-6)), 0u);
			EXPECT_LE(s.faces, finer);
			finer = s.faces;
		}
		// without the certificate the bound decides: within the target, and no fewer faces
		Params bound = prm;
		bound.certifyDistance = false;
		const Result u = buildLevels(m.view(), bound);
		ASSERT_TRUE(u.ok) << u.error;
		for (size_t i = 0; i < u.levels.size(); ++i) {
			EXPECT_LE(u.levels[i].stats.distanceBound,
			          want[u.levels[i].stats.level] * diag * (1 + 1e-5));
			EXPECT_LE(r.levels[i].stats.faces, u.levels[i].stats.faces);
		}
		// a list that is what maxDistance and distanceGrowth give: the same tolerances; the list
		// (levels by error) keeps the proven bound within them too, the default only what the
		// check measures (DESIGN 23)
		Params listed;
		listed.maxLevel = 2;
		listed.levelDistances = {0.001, 0.0005};
		Params grown = superfaceParams(); // (the angle levels' tolerances, as the build uses them)
		grown.maxLevel = 2;
		grown.maxDistance = 0.0005;
		grown.distanceGrowth = 2;
		const Result a = buildLevels(m.view(), listed), b = buildLevels(m.view(), grown);
		ASSERT_TRUE(a.ok && b.ok);
		for (size_t i = 0; i < 2; ++i) {
			EXPECT_DOUBLE_EQ(a.levels[i].stats.tolerance, b.levels[i].stats.tolerance);
			const LevelStats &as = a.levels[i].stats;
			EXPECT_TRUE(as.distanceBound <= as.tolerance * diag * (1 + 1e-5) ||
			            (as.hausdorff >= 0 && as.hausdorff <= as.tolerance * diag))
			    << as.distanceBound << " " << as.hausdorff;
			EXPECT_EQ(
			    verticesBeyond(m, b.levels[i], b.levels[i].stats.tolerance * diag * (1 + 1e-6)),
			    0u);
		}
	}
}

namespace {

// The mean and largest distance of the input's vertices to the level (every triangle measured).
std::pair<double, double> vertexDistances(const FlatMesh &m, const LevelMesh &lm)
{
	double sum = 0, worst = 0;
	const size_t nv = m.positions.size() / 3;
	for (size_t v = 0; v < nv; ++v) {
		const Vec3 p = vpos(m.positions, int32_t(v));
		double best = HUGE_VAL;
		for (size_t f = 0; f < lm.triangles.size() / 3; ++f)
			best = std::min(best, triangleDistance(lm, f, p));
		sum += best, worst = std::max(worst, best);
	}
	return std::make_pair(sum / double(nv), worst);
}

} // namespace

// Vertex placement (DESIGN 27): on a curved height field the same triangles, their vertices moved
// along their normals, are closer to the input on average (the chords no longer all lie under
// the surface), every input vertex stays within the tolerance, every move within half of it, the
// reported bound does not grow, and each output vertex is still its input vertex; a plane does
// not move at all. (The superface levels: collapses of the finer level, DESIGN 50, start from its
// vertices at their input positions and place their own.)
TEST(Quality, placed_vertices_bring_a_curved_level_closer_and_leave_planes_in_place)
{
	const FlatMesh m = dome(40, 0.15);
	const double diag = bboxDiagonal(m.view());
	Params prm = uniformTolerance(0.002); // 0.2 % of the diagonal
	prm.collapseLevels = false;
	Params fixed = prm;
	fixed.placeVertices = false;
	const Result placed = buildLevels(m.view(), prm), asIs = buildLevels(m.view(), fixed);
	ASSERT_TRUE(placed.ok && asIs.ok);
	ASSERT_EQ(placed.levels.size(), asIs.levels.size());
	const double tol = prm.maxDistance * diag;
	size_t closer = 0;
	for (size_t i = 0; i < placed.levels.size(); ++i) {
		const LevelMesh &a = placed.levels[i], &b = asIs.levels[i];
		SCOPED_TRACE("LOD" + std::to_string(a.stats.level));
		EXPECT_EQ(a.triangles, b.triangles);
		EXPECT_EQ(a.sourceVertex, b.sourceVertex);
		EXPECT_LE(a.stats.distanceBound, b.stats.distanceBound);
		EXPECT_LE(a.stats.maxPlacement, 0.5 * tol * (1 + 1e-9));
		EXPECT_EQ(b.stats.placedVertices, 0u);
		size_t moved = 0;
		for (size_t v = 0; v < a.sourceVertex.size(); ++v) {
			const Vec3 pa = vpos(a.positions, int32_t(v)),
			           pi = vpos(m.positions, a.sourceVertex[v]);
			EXPECT_LE((pa - pi).Norm(), a.stats.maxPlacement * (1 + 1e-9));
			moved += pa != pi;
		}
		EXPECT_EQ(moved, a.stats.placedVertices);
		EXPECT_EQ(verticesBeyond(m, a, tol * (1 + 1e-9)), 0u);
		const auto da = vertexDistances(m, a), db = vertexDistances(m, b);
		closer += da.first < 0.8 * db.first;
	}
	size_t placedAny = 0;
	for (const LevelMesh &lm : placed.levels)
		placedAny += lm.stats.placedVertices;
	EXPECT_GT(placedAny, 0u);
	EXPECT_GE(closer, placed.levels.size() / 2)
	    << "the mean distance fell by a fifth in too few levels";
	// a plane stays where it is: the grid cube's levels are its corners
	const FlatMesh cube = gridCube(20);
	const Result c = buildLevels(cube.view(), Params());
	ASSERT_TRUE(c.ok);
	for (const LevelMesh &lm : c.levels) {
		EXPECT_EQ(lm.stats.placedVertices, 0u);
		for (size_t v = 0; v < lm.sourceVertex.size(); ++v)
			EXPECT_EQ(vpos(lm.positions, int32_t(v)), vpos(cube.positions, lm.sourceVertex[v]));
	}
}

// Polished diagonals (DESIGN 28): anchor's conical part is a strip of long input triangles whose
// diagonals lie on the surface; its finest level merges a few of them, and the Delaunay diagonals
// of the same vertices cut across the cone (0.02 % of the diagonal away from it, the whole
// tolerance) where flipping them back makes the level as exact as its input.
TEST(Quality, polished_diagonals_keep_a_ruled_cad_surface_exact)
{
	const FlatMesh m = loadOff("anchor.off");
	const double diag = bboxDiagonal(m.view());
	const Result r = buildLevels(m.view(), superfaceParams());
	ASSERT_TRUE(r.ok) << r.error;
	const LevelMesh &finest = r.levels.front();
	EXPECT_LT(finest.stats.faces, m.triangles.size() / 3); // (some faces merged)
	EXPECT_LT(finest.stats.distanceBound, 1e-5 * diag);
}

// DESIGN 29: anchor's LOD3 came out 2 faces lighter than LOD4 (1,012 against 1,014) at 386 times
// its distance bound (0.0386 % against 0.0001 %); a coarser level farther from the input than the
// finer one must be at least kMinLevelSaving (1 %) lighter, else it is the finer level. Every level
// keeps the rule.
TEST(Quality, a_coarser_level_that_saves_almost_nothing_is_the_finer_level)
{
	const FlatMesh m = loadOff("anchor.off");
	const Result r = buildLevels(m.view(), superfaceParams());
	ASSERT_TRUE(r.ok) << r.error;
	ASSERT_GE(r.levels.size(), 2u);
	EXPECT_TRUE(r.levels[1].stats.reusedFiner); // (LOD3, the level that had 2 faces fewer)
	for (size_t i = 1; i < r.levels.size(); ++i) {
		const LevelStats &finer = r.levels[i - 1].stats, &s = r.levels[i].stats;
		EXPECT_LE(s.faces, finer.faces) << "level " << s.level;
		if (s.distanceBound > finer.distanceBound)
			EXPECT_LE(double(s.faces), 0.99 * double(finer.faces)) << "level " << s.level;
		if (s.reusedFiner) { // (the finer level's mesh, and its figures)
			EXPECT_EQ(s.faces, finer.faces);
			EXPECT_EQ(s.distanceBound, finer.distanceBound);
			EXPECT_EQ(r.levels[i].triangles, r.levels[i - 1].triangles);
		}
	}
}

// DESIGN 32: a superface beyond the normal limit gets a corner of each face that deviates from a
// triangle inserted into that triangle, as a face too far does, instead of being split. Measured
// at the centroids of four times as many faces, the same surface failed the limit where the
// original passed it, and was split into its faces: fandisk_large subdivided once had 4.5 % more
// faces at LOD4 and 19 % more at LOD2; subdivided three times 6 times as many at LOD4. The levels
// of a surface must not depend on how finely its planar facets are cut.
TEST(Quality, a_finer_tessellation_of_the_same_surface_gives_the_same_levels)
{
	const FlatMesh m = weldedCopy(loadOff("fandisk_large.off"));
	const FlatMesh fine = midpointSplit(m);
	const Result a = buildLevels(m.view(), Params()), b = buildLevels(fine.view(), Params());
	ASSERT_TRUE(a.ok) << a.error;
	ASSERT_TRUE(b.ok) << b.error;
	ASSERT_EQ(a.levels.size(), b.levels.size());
	for (size_t i = 0; i < 3; ++i) { // LOD4 .. LOD2
		SCOPED_TRACE("level " + std::to_string(a.levels[i].stats.level));
		EXPECT_LE(double(b.levels[i].stats.faces), 1.02 * double(a.levels[i].stats.faces));
		EXPECT_EQ(b.levels[i].stats.fallbacks, 0u);
	}
}
