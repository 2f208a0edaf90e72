// Levels of detail: exactness on flat geometry, and the invariants of docs/ALGORITHM.md on real
// models, checked with independent code (test_meshes.h), not with the engine's own statistics.
#include "engine.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

using namespace gausslod;
using namespace testmesh;

namespace {

double minAngleDeg(const LevelMesh &lm)
{
	double best = 180;
	for (size_t t = 0; t < lm.triangles.size() / 3; ++t)
		for (int k = 0; k < 3; ++k) {
			const Vec3 a = vpos(lm.positions, lm.triangles[3 * t + k]);
			const Vec3 b = vpos(lm.positions, lm.triangles[3 * t + (k + 1) % 3]);
			const Vec3 c = vpos(lm.positions, lm.triangles[3 * t + (k + 2) % 3]);
			const double cosA = (b - a).Normalize().dot((c - a).Normalize());
			best = std::min(best, std::acos(std::max(-1.0, std::min(1.0, cosA))) * 180 / M_PI);
		}
	return best;
}

// Every invariant of docs/ALGORITHM.md that is checkable on one level against its input.
void expectInvariants(const FlatMesh &in, const TopoFacts &inFacts, const LevelMesh &lm)
{
	SCOPED_TRACE("level " + std::to_string(lm.stats.level));
	const TopoFacts f = topoFacts(lm.positions, lm.triangles);
	EXPECT_EQ(f.degenerateFaces, 0u);
	EXPECT_EQ(f.duplicateFaces, 0u);
	EXPECT_EQ(f.nonManifoldEdges, inFacts.nonManifoldEdges);
	// (no new one; a pinch whose two fans both end up inside superfaces opens: the welded cow's)
	EXPECT_LE(f.nonManifoldVertices, inFacts.nonManifoldVertices);
	EXPECT_EQ(f.inconsistentEdges, inFacts.inconsistentEdges);
	EXPECT_EQ(f.boundaryLoops, inFacts.boundaryLoops);
	EXPECT_EQ(f.components, inFacts.components);
	if (inFacts.closedManifold()) {
		EXPECT_TRUE(f.closedManifold()); // watertight in, watertight out: no crack, no T-junction
		EXPECT_EQ(f.genus(), inFacts.genus());
	}
	EXPECT_EQ(flippedFaces(in, lm), 0u);
	EXPECT_EQ(lm.stats.faces, lm.triangles.size() / 3);
	EXPECT_EQ(lm.superface.size(), lm.triangles.size() / 3);
	if (!lm.stats.reduced) // (else measured: an input face against its nearest triangle)
		EXPECT_LE(lm.stats.maxNormalDevDeg, 90.0);
}

void expectMonotone(const Result &r)
{
	for (size_t i = 1; i < r.levels.size(); ++i)
		EXPECT_LE(r.levels[i].stats.faces, r.levels[i - 1].stats.faces)
		    << "level " << r.levels[i].stats.level;
}

} // namespace

TEST(Levels, grid_cube_is_exactly_12_triangles_on_8_corners_at_every_level)
{
	const FlatMesh cube = gridCube(50);
	ASSERT_EQ(cube.triangles.size() / 3, 6u * 50 * 50 * 2);
	const Result r = buildLevels(cube.view(), Params());
	ASSERT_TRUE(r.ok) << r.error;
	ASSERT_EQ(r.levels.size(), 5u);
	for (const LevelMesh &lm : r.levels) {
		SCOPED_TRACE("level " + std::to_string(lm.stats.level));
		EXPECT_EQ(lm.stats.faces, 12u);
		EXPECT_EQ(lm.stats.vertices, 8u);
		EXPECT_EQ(lm.stats.superfaces, 6u);
		EXPECT_EQ(lm.stats.maxNormalDevDeg, 0.0);
		for (double x : lm.positions) // only the exact cube corners remain
			EXPECT_TRUE(x == 0.0 || x == 1.0);
		expectInvariants(cube, topoFacts(cube.positions, cube.triangles), lm);
	}
}

TEST(Levels, noisy_grid_cube_reaches_12_triangles_by_level_2)
{
	const FlatMesh cube = gridCube(50, 1.0, 1e-4, 3);
	const TopoFacts inFacts = topoFacts(cube.positions, cube.triangles);
	const Result r = buildLevels(cube.view(), Params());
	ASSERT_TRUE(r.ok) << r.error;
	for (const LevelMesh &lm : r.levels) {
		std::printf("noisy cube level %d: %zu faces, %zu superfaces, max dev %.3f deg\n",
		            lm.stats.level, lm.stats.faces, lm.stats.superfaces, lm.stats.maxNormalDevDeg);
		if (lm.stats.level <= 2)
			EXPECT_EQ(lm.stats.faces, 12u) << "level " << lm.stats.level;
		expectInvariants(cube, inFacts, lm);
	}
	expectMonotone(r);
}

TEST(Levels, planar_grid_with_a_square_hole_keeps_boundary_and_hole_as_two_loops)
{
	const FlatMesh grid = gridWithHole(40, 10, 30);
	const TopoFacts inFacts = topoFacts(grid.positions, grid.triangles);
	ASSERT_EQ(inFacts.boundaryLoops, 2u);
	// the plane is triangulated once, by the constrained Delaunay triangulation of its outline:
	// before the levels (DESIGN 41), or by each level
	for (const bool coplanarFirst : {true, false}) {
		Params prm;
		prm.coplanarFirst = coplanarFirst;
		const Result r = buildLevels(grid.view(), prm);
		ASSERT_TRUE(r.ok) << r.error;
		EXPECT_EQ(r.input.coplanarRegions, coplanarFirst ? 1u : 0u);
		for (const LevelMesh &lm : r.levels) {
			expectInvariants(grid, inFacts, lm);
			EXPECT_EQ(lm.stats.superfaces, 1u);
			EXPECT_EQ(lm.stats.retriangulated, coplanarFirst ? 0u : 1u);
			EXPECT_EQ(lm.stats.vertices, 8u); // 4 outer + 4 hole corners
			EXPECT_EQ(lm.stats.faces, 8u);    // an annulus of 8 vertices: 8 triangles
			EXPECT_GT(minAngleDeg(lm), 15.0); // Delaunay, not a sliver fan
		}
	}
}

TEST(Levels, real_models_keep_every_invariant_at_every_level)
{
	for (const char *name : {"cow.off", "fandisk.off", "bunny00.off"}) {
		SCOPED_TRACE(name);
		const FlatMesh m = loadOff(name);
		// (the levels are made on the welded input: cow.off has a vertex twice)
		const FlatMesh welded = weldedCopy(m);
		const TopoFacts inFacts = topoFacts(welded.positions, welded.triangles);
		const Result r = buildLevels(m.view(), Params());
		ASSERT_TRUE(r.ok) << r.error;
		ASSERT_EQ(r.levels.size(), 5u);
		for (const LevelMesh &lm : r.levels)
			expectInvariants(m, inFacts, lm);
		expectMonotone(r);
		EXPECT_LT(r.levels.back().stats.faces, m.triangles.size() / 3);
	}
}

TEST(Levels, no_output_face_points_away_from_the_nearest_input_face)
{
	// the cow's tail, horns and ears are thin: at coarse levels a straightened border can bring
	// one side's triangle nearer to the other side than to its own faces
	const FlatMesh m = loadOff("cow.off");
	const Result r = buildLevels(m.view(), Params());
	ASSERT_TRUE(r.ok) << r.error;
	for (const LevelMesh &lm : r.levels)
		EXPECT_EQ(facesAwayFromNearestInput(m, lm), 0u) << "level " << lm.stats.level;
}

TEST(Levels, same_input_and_parameters_give_the_same_output)
{
	const FlatMesh m = loadOff("fandisk.off");
	const Result a = buildLevels(m.view(), Params());
	const Result b = buildLevels(m.view(), Params());
	ASSERT_TRUE(a.ok && b.ok);
	ASSERT_EQ(a.levels.size(), b.levels.size());
	for (size_t i = 0; i < a.levels.size(); ++i) {
		EXPECT_EQ(a.levels[i].triangles, b.levels[i].triangles);
		EXPECT_EQ(a.levels[i].positions, b.levels[i].positions);
		EXPECT_EQ(a.levels[i].superface, b.levels[i].superface);
	}
}

TEST(Levels, a_level_sink_gets_the_same_levels_one_at_a_time_and_can_cancel)
{
	const FlatMesh m = loadOff("fandisk.off");
	Params p;
	p.outputLevels = (1u << 1) | (1u << 3) | (1u << 4);
	const Result whole = buildLevels(m.view(), p);
	ASSERT_TRUE(whole.ok);
	std::vector<LevelMesh> got;
	const Result streamed = buildLevels(m.view(), p, {}, [&](const LevelMesh &l) {
		got.push_back(l);
		return true;
	});
	ASSERT_TRUE(streamed.ok) << streamed.error;
	ASSERT_EQ(got.size(), 3u);
	ASSERT_EQ(streamed.levels.size(), 3u);
	for (size_t i = 0; i < got.size(); ++i) {
		EXPECT_EQ(got[i].triangles, whole.levels[i].triangles);
		EXPECT_EQ(got[i].positions, whole.levels[i].positions);
		EXPECT_EQ(got[i].stats.level, whole.levels[i].stats.level);
		// the result keeps the stats only
		EXPECT_EQ(streamed.levels[i].stats.faces, whole.levels[i].stats.faces);
		EXPECT_TRUE(streamed.levels[i].triangles.empty());
	}
	int calls = 0;
	const Result cancelled =
	    buildLevels(m.view(), p, {}, [&](const LevelMesh &) { return ++calls < 2; });
	EXPECT_FALSE(cancelled.ok);
	EXPECT_EQ(cancelled.error, "cancelled");
	EXPECT_EQ(calls, 2);
	EXPECT_TRUE(cancelled.levels.empty());
}

// Levels by target (issue #17): the same guarantees, the normal limit included, and the same
// output for any thread count.
TEST(Levels, levels_by_target_keep_every_invariant_and_do_not_depend_on_threads)
{
	for (const char *name : {"cow.off", "fandisk.off", "bunny00.off"}) {
		for (const char *by : {"faces:50%,25%,10%,5%", "error:0.01%,0.1%,1%"}) {
			if (std::string(name) == "bunny00.off" && by[0] == 'e')
				continue; // (by error the bunny takes seconds per run; cow and fandisk cover it)
			SCOPED_TRACE(std::string(name) + " " + by);
			const FlatMesh m = loadOff(name);
			const FlatMesh welded = weldedCopy(m);
			const TopoFacts inFacts = topoFacts(welded.positions, welded.triangles);
			Params p;
			std::string error;
			ASSERT_TRUE(parseLevelsBy(by, p, error)) << error;
			p.threads = 1;
			const Result r = buildLevels(m.view(), p);
			ASSERT_TRUE(r.ok) << r.error;
			ASSERT_EQ(r.levels.size(), size_t(p.maxLevel));
			for (const LevelMesh &lm : r.levels) {
				expectInvariants(m, inFacts, lm);
				// (a level continued by collapses measures its deviation, DESIGN 51)
				if (!lm.stats.reduced)
					EXPECT_LE(lm.stats.maxNormalDevDeg, p.normalLimit * lm.stats.boundDeg + 1e-9);
			}
			expectMonotone(r);
			p.threads = 3;
			const Result three = buildLevels(m.view(), p);
			ASSERT_TRUE(three.ok);
			for (size_t i = 0; i < r.levels.size(); ++i) {
				EXPECT_EQ(r.levels[i].triangles, three.levels[i].triangles) << i;
				EXPECT_EQ(r.levels[i].stats.tolerance, three.levels[i].stats.tolerance) << i;
			}
		}
	}
}

// DESIGN 55: with the collapses known first, one budget on a curved model stops the tolerance
// search after two builds (camel: ten before); in a five-budget chain, whose finest cells are
// small, the top build cannot reach the first budget and Euler's bound stops it in its first
// round, before it triangulates (four rounds before); and where the collapses are exact (a
// planar cube) no superface build is made at all.
TEST(Levels, one_budget_stops_the_search_where_the_collapses_are_nearer)
{
	Params p;
	std::string error;
	ASSERT_TRUE(parseLevelsBy("faces:50%", p, error)) << error;
	p.certifyDistance = false;
	const FlatMesh camel = loadOff("camel.off");
	const Result r = buildLevels(camel.view(), p);
	ASSERT_TRUE(r.ok) << r.error;
	ASSERT_EQ(r.levels.size(), 1u);
	const LevelStats &s = r.levels[0].stats;
	EXPECT_TRUE(s.reduced);
	EXPECT_LE(s.faces, camel.triangles.size() / 6);
	EXPECT_LE(s.trials, 2);
	Params chain;
	ASSERT_TRUE(parseLevelsBy("faces:50%,25%,10%,5%,2%", chain, error)) << error;
	chain.certifyDistance = false;
	const Result five = buildLevels(camel.view(), chain);
	ASSERT_TRUE(five.ok) << five.error;
	ASSERT_EQ(five.levels.size(), 5u);
	const LevelStats &finest = five.levels[0].stats;
	EXPECT_TRUE(finest.reduced);
	EXPECT_EQ(finest.faces, camel.triangles.size() / 6); // (the triangles are 3 indices each)
	EXPECT_EQ(finest.trials, 1);
	EXPECT_EQ(finest.rounds, 1);
	const FlatMesh cube = gridCube(20);
	const Result c = buildLevels(cube.view(), p);
	ASSERT_TRUE(c.ok) << c.error;
	ASSERT_EQ(c.levels.size(), 1u);
	EXPECT_EQ(c.levels[0].stats.faces, 12u);
	EXPECT_EQ(c.levels[0].stats.trials, 0);
}

// DESIGN 52: a level that is the same mesh as the last one certified (a planar cube's levels
// all are its 12 faces) takes that certificate instead of measuring again.
TEST(Levels, a_level_that_is_the_last_certified_mesh_takes_its_certificate)
{
	const FlatMesh cube = gridCube(30);
	Params p; // (certified by default)
	const Result r = buildLevels(cube.view(), p);
	ASSERT_TRUE(r.ok) << r.error;
	ASSERT_EQ(r.levels.size(), 5u);
	const LevelStats &first = r.levels[0].stats;
	ASSERT_GE(first.hausdorff, 0);
	EXPECT_GT(first.secondsHausdorff, 0);
	for (size_t i = 1; i < r.levels.size(); ++i) {
		const LevelMesh &l = r.levels[i];
		ASSERT_EQ(l.triangles, r.levels[0].triangles) << i;
		ASSERT_EQ(l.positions, r.levels[0].positions) << i;
		EXPECT_EQ(l.stats.hausdorff, first.hausdorff) << i;
		EXPECT_EQ(l.stats.hausdorffLower, first.hausdorffLower) << i;
		EXPECT_EQ(l.stats.secondsHausdorff, 0) << i;
	}
	// (measured again, the same level gets the same figure)
	p.maxLevel = 1;
	const Result one = buildLevels(cube.view(), p);
	ASSERT_TRUE(one.ok) << one.error;
	ASSERT_EQ(one.levels[0].triangles, r.levels[0].triangles);
	EXPECT_EQ(one.levels[0].stats.hausdorff, first.hausdorff);
}

TEST(Levels, the_output_does_not_depend_on_the_number_of_threads)
{
	for (const char *name : {"fandisk.off", "bunny00.off"}) {
		const FlatMesh m = loadOff(name);
		Params p;
		p.threads = 1;
		const Result one = buildLevels(m.view(), p);
		p.threads = 3;
		const Result three = buildLevels(m.view(), p);
		ASSERT_TRUE(one.ok && three.ok) << name;
		ASSERT_EQ(one.levels.size(), three.levels.size());
		for (size_t i = 0; i < one.levels.size(); ++i) {
			EXPECT_EQ(one.levels[i].triangles, three.levels[i].triangles) << name << " level " << i;
			EXPECT_EQ(one.levels[i].superface, three.levels[i].superface) << name << " level " << i;
			EXPECT_EQ(one.levels[i].stats.fallbacks, three.levels[i].stats.fallbacks);
			EXPECT_EQ(one.levels[i].stats.maxNormalDevDeg, three.levels[i].stats.maxNormalDevDeg);
		}
	}
}

TEST(Levels, level_mask_selects_levels_finest_first)
{
	const FlatMesh m = gridCube(4);
	Params p;
	p.outputLevels = (1u << 0) | (1u << 3);
	const Result r = buildLevels(m.view(), p);
	ASSERT_TRUE(r.ok);
	ASSERT_EQ(r.levels.size(), 2u);
	EXPECT_EQ(r.levels[0].stats.level, 3);
	EXPECT_EQ(r.levels[1].stats.level, 0);
}

TEST(Levels, bad_input_gives_a_clear_error)
{
	FlatMesh empty;
	Result r = buildLevels(empty.view(), Params());
	EXPECT_FALSE(r.ok);
	EXPECT_NE(r.error.find("no faces"), std::string::npos) << r.error;

	FlatMesh m = gridCube(2);
	m.triangles[5] = 999;
	r = buildLevels(m.view(), Params());
	EXPECT_FALSE(r.ok);
	EXPECT_NE(r.error.find("does not exist"), std::string::npos) << r.error;

	m = gridCube(2);
	m.positions[3 * size_t(m.triangles[0])] = NAN;
	r = buildLevels(m.view(), Params());
	EXPECT_FALSE(r.ok);
	EXPECT_NE(r.error.find("non-finite"), std::string::npos) << r.error;

	m = gridCube(2);
	Params p;
	p.maxLevel = 0;
	r = buildLevels(m.view(), p);
	EXPECT_FALSE(r.ok);
	EXPECT_NE(r.error.find("levels"), std::string::npos) << r.error;
}

// The paper's experiment (section 3): MaxLevel = 5 on the cow and the dinosaur. Debian's models
// are not the paper's (cow 5,804 triangles vs 6,208; dino differs too), so the counts differ;
// the table is printed for the README and the invariants are checked.
TEST(Levels, papers_experiment_cow_and_dino_at_max_level_5)
{
	for (const char *name : {"cow.off", "dino.off"}) {
		const FlatMesh m = loadOff(name);
		for (const bool across : {false, true}) {
			Params p; // (the defaults: merging across cells, the distance tolerance, real steps)
			if (!across) { // the paper's mode (gausslod_paper.mlx): its superfaces, normals only
				p.acrossCells = false;
				p.maxDistance = 0;
				p.completeChain = false;
			}
			const Result r = buildLevels(m.view(), p);
			ASSERT_TRUE(r.ok) << r.error;
			std::printf("paper experiment %s%s: input %zu", name, across ? " (across cells)" : "",
			            m.triangles.size() / 3);
			for (const LevelMesh &lm : r.levels)
				std::printf(" | M%d %zu (max dev %.2f, mean %.3f deg)", lm.stats.level,
				            lm.stats.faces, lm.stats.maxNormalDevDeg, lm.stats.meanNormalDevDeg);
			std::printf("\n");
			expectMonotone(r);
		}
	}
}

namespace {

// A flat annulus in z = 0 (radii 0.5 and 1, n segments, `rings` circles), counter-clockwise seen
// from +z.
FlatMesh flatAnnulus(int n, int rings)
{
	FlatMesh m;
	for (int r = 0; r < rings; ++r)
		for (int i = 0; i < n; ++i) {
			const double radius = 0.5 + 0.5 * r / (rings - 1), a = 2 * M_PI * i / n;
			m.positions.insert(m.positions.end(),
			                   {radius * std::cos(a), radius * std::sin(a), 0.0});
		}
	for (int r = 0; r + 1 < rings; ++r)
		for (int i = 0; i < n; ++i) {
			const int32_t a = r * n + i, b = r * n + (i + 1) % n, c = a + n, d = b + n;
			m.triangles.insert(m.triangles.end(), {a, b, d, a, d, c});
		}
	return m;
}

} // namespace

// DESIGN 31: a superface of a coarser level with the same faces and the same kept outline as a
// superface the finer level re-triangulated exactly takes that superface's triangles and measures
// (ExactCarry): the coarser level must be the one every superface re-triangulated gives.
namespace {

// The same mesh and the same measured figures (two builds that must agree).
void expectSameLevel(const LevelMesh &a, const LevelMesh &b)
{
	EXPECT_EQ(a.triangles, b.triangles);
	EXPECT_EQ(a.positions, b.positions);
	EXPECT_EQ(a.superface, b.superface);
	EXPECT_EQ(a.borderEdges, b.borderEdges);
	EXPECT_EQ(a.inputSuperface, b.inputSuperface);
	EXPECT_EQ(a.stats.retriangulated, b.stats.retriangulated);
	EXPECT_EQ(a.stats.maxNormalDevDeg, b.stats.maxNormalDevDeg);
	EXPECT_EQ(a.stats.meanNormalDevDeg, b.stats.meanNormalDevDeg);
	EXPECT_EQ(a.stats.unmeasuredFaces, b.stats.unmeasuredFaces);
	EXPECT_EQ(a.stats.distanceBound, b.stats.distanceBound);
}

// The bound of merges across cells at `level` (buildLevels' acrossLimit).
double acrossLimit(const Params &prm, int level)
{
	return std::min(levelBoundDeg(level), prm.featureAngle);
}

// The partitions of buildLevels in angle mode: the finest one, merged across cells, and with
// `coarser` every coarser one, each from the next finer one.
std::vector<detail::Partition> levelPartitions(const detail::Topology &t, const Params &prm,
                                               bool coarser)
{
	const int finest = prm.maxLevel - 1;
	std::vector<detail::Partition> parts(size_t(prm.maxLevel));
	detail::finestPartition(t, finest, parts[size_t(finest)]);
	detail::mergeAcrossCells(t, acrossLimit(prm, finest), parts[size_t(finest)]);
	for (int level = finest - 1; coarser && level >= 0; --level) {
		detail::coarserPartition(t, parts[size_t(level) + 1], parts[size_t(level)], int8_t(level));
		detail::mergeAcrossCells(t, acrossLimit(prm, level), parts[size_t(level)]);
	}
	return parts;
}

} // namespace

TEST(Levels, exact_superfaces_carried_to_the_coarser_level_give_the_same_level)
{
	// The annulus's inner circle (110 segments) is 0.029 % of the diagonal from the chord past
	// each vertex: every vertex stays at LOD4 (tolerance 0.02 %), not at LOD3 (0.04 %): the same
	// faces, another outline, not carried. fandisk's exact superfaces are merged at LOD3: none is
	// carried. Either way the level must be the same.
	const std::pair<const char *, bool> models[] = {
	    {"grid cube", true}, {"joint.off", true}, {"annulus", false}, {"fandisk.off", false}};
	for (const auto &model : models) {
		const std::string name = model.first;
		SCOPED_TRACE(name);
		const FlatMesh m = name == "grid cube" ? gridCube(20)
		                   : name == "annulus" ? flatAnnulus(110, 6)
		                                       : weldedCopy(loadOff(name));
		const Params prm;
		detail::Topology t;
		detail::buildTopology(m.view(), prm.featureAngle, t);
		const int finest = prm.maxLevel - 1;
		std::vector<detail::Partition> parts = levelPartitions(t, prm, false);
		LevelMesh fine;
		detail::ExactCarry carry;
		detail::buildLevelGeometry(t, prm, parts, parts[size_t(finest)], fine, SIZE_MAX, nullptr,
		                           nullptr, &carry);
		ASSERT_EQ(carry.empty(), false);
		detail::Partition coarse;
		detail::coarserPartition(t, parts[size_t(finest)], coarse, int8_t(finest - 1));
		detail::mergeAcrossCells(t, acrossLimit(prm, finest - 1), coarse);
		detail::SplitCost cost;
		detail::triangleShare(parts[size_t(finest)], fine, cost);
		detail::Partition pWith = coarse, pWithout = coarse;
		LevelMesh with, without;
		detail::buildLevelGeometry(t, prm, parts, pWith, with, fine.stats.faces, &cost, &carry);
		detail::buildLevelGeometry(t, prm, parts, pWithout, without, fine.stats.faces, &cost);
		EXPECT_EQ(with.stats.carriedSuperfaces > 0, model.second) << with.stats.carriedSuperfaces;
		EXPECT_EQ(without.stats.carriedSuperfaces, 0u);
		expectSameLevel(with, without);
		EXPECT_EQ(with.stats.placedVertices, without.stats.placedVertices);
	}
}

TEST(Levels, a_level_whose_finer_level_is_carried_whole_is_that_level_as_built)
{
	// DESIGN 36: where the finer level's superfaces are all exact, carried, with chain ends only
	// (the grid cube, joint's planar parts), and the coarser partition is the same, buildLevels
	// takes the finer mesh without a build. Each level must be what building it gives: the
	// chain is built here level by level, every level built, and compared.
	const std::pair<const char *, bool> models[] = {
	    {"grid cube", true}, {"joint.off", false}, {"annulus", false}, {"fandisk.off", false}};
	for (const auto &model : models) {
		const std::string name = model.first;
		SCOPED_TRACE(name);
		const FlatMesh m = name == "grid cube" ? gridCube(20)
		                   : name == "annulus" ? flatAnnulus(110, 6)
		                                       : weldedCopy(loadOff(name));
		Params prm = superfaceParams(); // (the superface levels, built below as the chain)
		prm.coplanarFirst = false;      // (the chain below is built on the input's faces)
		const Result r = buildLevels(m.view(), prm);
		ASSERT_TRUE(r.ok) << r.error;
		ASSERT_EQ(r.levels.size(), size_t(prm.maxLevel));
		detail::Topology t;
		detail::buildTopology(m.view(), prm.featureAngle, t);
		const int finest = prm.maxLevel - 1;
		std::vector<detail::Partition> parts = levelPartitions(t, prm, false);
		LevelMesh finer;
		detail::ExactCarry carry, next;
		size_t taken = 0; // levels buildLevels took without a build
		for (int level = finest; level >= 0; --level) {
			SCOPED_TRACE(level);
			detail::SplitCost cost;
			if (level < finest) {
				detail::coarserPartition(t, parts[size_t(level) + 1], parts[size_t(level)],
				                         int8_t(level));
				detail::mergeAcrossCells(t, acrossLimit(prm, level), parts[size_t(level)]);
				detail::triangleShare(parts[size_t(level) + 1], finer, cost);
			}
			LevelMesh lm;
			detail::buildLevelGeometry(t, prm, parts, parts[size_t(level)], lm,
			                           level < finest ? finer.stats.faces : SIZE_MAX,
			                           level < finest ? &cost : nullptr, &carry, &next);
			std::swap(carry, next);
			const LevelMesh &got = r.levels[size_t(finest - level)];
			// (replaced by the finer level, or made by collapses of it, DESIGN 50: this chain of
			// superface builds stops here)
			if (got.stats.reusedFiner || got.stats.collapses > 0)
				break;
			expectSameLevel(got, lm);
			EXPECT_EQ(got.sourceVertex, lm.sourceVertex);
			EXPECT_EQ(got.stats.superfaces, lm.stats.superfaces);
			EXPECT_EQ(got.stats.carriedSuperfaces, lm.stats.carriedSuperfaces);
			EXPECT_EQ(got.stats.rounds, lm.stats.rounds);
			EXPECT_EQ(got.stats.boundDeg, lm.stats.boundDeg);
			EXPECT_EQ(got.stats.level, lm.stats.level);
			// (no borders traced: the level took no time there)
			taken += got.stats.secondsBorders == 0.0;
			finer = lm;
		}
		EXPECT_EQ(taken > 0, model.second) << taken;
	}
}

TEST(Levels, a_level_abandoned_over_its_face_limit_would_have_had_more_faces_than_that)
{
	// A coarser level that cannot get below the finer level's face count is abandoned (the finer
	// level is taken), before triangulating where Euler's bound on its junctions says so, or
	// (DESIGN 40) in the middle of a round, once that bound counting the border vertices the
	// fallbacks will lock after the round's failures so far is over the limit. The count it
	// reports then must be at most what building the level in full gives, and it must be
	// abandoned exactly when that is over the limit; under the limit it is that level. Swept over
	// limits on LOD1 and LOD0 of models whose coarse levels have failures that lock borders
	// (bones, femur, knot: limits between Euler's bound and the bound with the locks abandon in
	// the middle of a round; fandisk: a full build that the old end-of-round test abandoned).
	for (const char *name : {"fandisk.off", "bones.off", "femur.off", "knot.off"}) {
		SCOPED_TRACE(name);
		const FlatMesh m = weldedCopy(loadOff(name));
		const Params prm;
		detail::Topology t;
		detail::buildTopology(m.view(), prm.featureAngle, t);
		const std::vector<detail::Partition> parts = levelPartitions(t, prm, true);
		for (int level = 1; level >= 0; --level) {
			SCOPED_TRACE(level);
			detail::Partition p = parts[size_t(level)];
			LevelMesh full;
			detail::buildLevelGeometry(t, prm, parts, p, full, SIZE_MAX);
			const size_t faces = full.stats.faces;
			ASSERT_GT(faces, 8u);
			for (size_t limit = faces / 8; limit <= faces;
			     limit += std::max<size_t>(1, faces / 64)) {
				SCOPED_TRACE(limit);
				detail::Partition q = parts[size_t(level)];
				LevelMesh lm;
				detail::buildLevelGeometry(t, prm, parts, q, lm, limit);
				EXPECT_LE(lm.stats.faces, faces);
				EXPECT_EQ(lm.stats.faces > limit, faces > limit);
				if (lm.stats.faces <= limit)
					expectSameLevel(lm, full);
			}
			detail::Partition q = parts[size_t(level)];
			LevelMesh at;
			detail::buildLevelGeometry(t, prm, parts, q, at, faces);
			expectSameLevel(at, full);
		}
	}
}
