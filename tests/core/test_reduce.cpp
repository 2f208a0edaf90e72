// Levels continued by collapses (docs/DESIGN.md, 51): the default chain's real steps, budgets on
// textured meshes, the shapes a step must not break.
#include "engine.h"
#include "reduce.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

using namespace gausslod;
using namespace testmesh;

namespace {

// A UV sphere (nu x nv) whose faces are mapped by a cube map: each face's chart is the axis its
// normal is nearest, its corners' texture coordinates that chart's projection, placed in one of six
// tiles of the texture; a vertex where charts meet has a corner key per chart (a seam).
struct TexturedSphere {
	FlatMesh mesh;
	std::vector<float> uv;
	std::vector<uint32_t> cornerKey;
	MeshView view() const
	{
		MeshView v = mesh.view();
		v.cornerUV = uv.data();
		v.cornerKey = cornerKey.data();
		v.wantSources = true;
		return v;
	}
};

TexturedSphere texturedSphere(int nu, int nv)
{
	TexturedSphere s;
	FlatMesh &m = s.mesh;
	for (int j = 1; j < nv; ++j)
		for (int i = 0; i < nu; ++i) {
			const double th = M_PI * j / nv, ph = 2 * M_PI * i / nu;
			m.positions.insert(m.positions.end(), {std::sin(th) * std::cos(ph),
			                                       std::sin(th) * std::sin(ph), std::cos(th)});
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
	const size_t nF = m.triangles.size() / 3;
	for (size_t f = 0; f < nF; ++f) {
		const Vec3 a = vpos(m.positions, m.triangles[3 * f]),
		           b = vpos(m.positions, m.triangles[3 * f + 1]),
		           c = vpos(m.positions, m.triangles[3 * f + 2]);
		const Vec3 n = (b - a) ^ (c - a);
		int axis = 0;
		for (int k = 1; k < 3; ++k)
			if (std::fabs(n[k]) > std::fabs(n[axis]))
				axis = k;
		const int chart = 2 * axis + (n[axis] < 0);
		for (int k = 0; k < 3; ++k) {
			const Vec3 p = vpos(m.positions, m.triangles[3 * f + size_t(k)]);
			const double u = p[(axis + 1) % 3], v = p[(axis + 2) % 3]; // (in [-1, 1])
			s.uv.push_back(float((chart % 3 + 0.5 + 0.4 * u) / 3));
			s.uv.push_back(float((chart / 3 + 0.5 + 0.4 * v) / 2));
			s.cornerKey.push_back(uint32_t(chart));
		}
	}
	return s;
}

size_t facesOf(const FlatMesh &m) { return m.triangles.size() / 3; }

} // namespace

TEST(DefaultChain, every_level_of_a_curved_model_is_a_real_step)
{
	// low-poly and organic models, whose cells merge little: each level at most 0.8 of the level
	// before it (the finest: of the input), the coarsest at most 15 % of the input
	for (const char *name : {"bull.off", "cow.off", "dino.off"}) {
		SCOPED_TRACE(name);
		const FlatMesh m = loadOff(name);
		const TopoFacts in = topoFacts(m.positions, m.triangles);
		const Result r = buildLevels(m.view(), Params());
		ASSERT_TRUE(r.ok) << r.error;
		size_t finer = facesOf(m);
		size_t reduced = 0;
		for (const LevelMesh &lm : r.levels) {
			SCOPED_TRACE("LOD" + std::to_string(lm.stats.level));
			EXPECT_LE(double(lm.stats.faces), 0.8 * double(finer));
			EXPECT_GE(lm.stats.distanceBound, 0);
			reduced += lm.stats.reduced;
			if (in.closedManifold())
				EXPECT_TRUE(topoFacts(lm.positions, lm.triangles).closedManifold());
			finer = lm.stats.faces;
		}
		EXPECT_LE(double(finer), 0.15 * double(facesOf(m)));
		EXPECT_GE(reduced, 1u); // (the test reaches past what the cells give)
	}
}

TEST(DefaultChain, a_step_that_would_break_the_shape_is_not_taken)
{
	// the grid cube's and a noisy cube's coarse levels are their 12 triangles: a real step would
	// cut corners off (far more than 32 times the level's tolerance); exact and near-exact levels
	// keep their count
	for (const double noise : {0.0, 1e-4}) {
		SCOPED_TRACE(noise);
		const FlatMesh m = gridCube(30, 1.0, noise, 3);
		const Result r = buildLevels(m.view(), Params());
		ASSERT_TRUE(r.ok) << r.error;
		EXPECT_EQ(r.levels.back().stats.faces, 12u);
		EXPECT_EQ(r.levels.back().stats.vertices, 8u);
	}
}

TEST(Budgets, a_textured_mesh_reaches_the_budgets_of_its_bare_geometry)
{
	// seams constrain, they do not freeze: the textured sphere reaches every budget its bare
	// geometry does, closed, with finite texture coordinates and a reported texture error
	const TexturedSphere s = texturedSphere(48, 24);
	Params prm;
	std::string error;
	ASSERT_TRUE(parseLevelsBy("faces:50%,10%,2%", prm, error)) << error;
	const Result bare = buildLevels(s.mesh.view(), prm), tex = buildLevels(s.view(), prm);
	ASSERT_TRUE(bare.ok && tex.ok) << tex.error;
	ASSERT_EQ(bare.levels.size(), tex.levels.size());
	for (size_t i = 0; i < tex.levels.size(); ++i) {
		const LevelMesh &b = bare.levels[i], &t = tex.levels[i];
		SCOPED_TRACE("LOD" + std::to_string(t.stats.level));
		EXPECT_TRUE(b.stats.targetReached);
		EXPECT_TRUE(t.stats.targetReached) << t.stats.faces << " of " << t.stats.targetFaces;
		EXPECT_LE(double(t.stats.faces), 1.1 * double(b.stats.faces));
		EXPECT_TRUE(topoFacts(t.positions, t.triangles).closedManifold());
		EXPECT_GE(t.stats.maxTexError, 0.0);
		ASSERT_EQ(t.sourceCorner.size(), t.triangles.size());
		for (float x : t.cornerUV)
			EXPECT_TRUE(std::isfinite(x));
		EXPECT_TRUE(t.cornerUV.empty() || t.cornerUV.size() == 2 * t.triangles.size());
	}
	Params three = prm;
	three.threads = 3;
	const Result again = buildLevels(s.view(), three);
	ASSERT_TRUE(again.ok);
	for (size_t i = 0; i < tex.levels.size(); ++i) {
		EXPECT_EQ(again.levels[i].triangles, tex.levels[i].triangles);
		EXPECT_EQ(again.levels[i].cornerUV, tex.levels[i].cornerUV);
	}
}

TEST(Reduce, least_faces_of_a_topology_count_parts_genera_and_boundary_loops)
{
	using detail::levelTopology;
	// a triangle: one loop, itself the least
	auto tri = levelTopology({0, 1, 2}, 3);
	EXPECT_EQ(tri.components, 1u);
	EXPECT_EQ(tri.boundaryLoops, 1u);
	EXPECT_EQ(tri.leastFaces, 1u);
	// a tetrahedron and, apart, a strip of two triangles (one loop): 4 + 1
	auto two = levelTopology({0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2, 4, 5, 6, 4, 6, 7}, 8);
	EXPECT_TRUE(two.manifold);
	EXPECT_EQ(two.components, 2u);
	EXPECT_EQ(two.boundaryLoops, 1u);
	EXPECT_EQ(two.leastFaces, 5u);
	// a 4 x 4 grid torus: closed, genus 1, at least 7 vertices and 14 faces (Heawood)
	std::vector<int32_t> torus;
	for (int j = 0; j < 4; ++j)
		for (int i = 0; i < 4; ++i) {
			const int32_t a = j * 4 + i, b = j * 4 + (i + 1) % 4, c = ((j + 1) % 4) * 4 + i,
			              d = ((j + 1) % 4) * 4 + (i + 1) % 4;
			torus.insert(torus.end(), {a, b, d, a, d, c});
		}
	auto t = levelTopology(torus, 16);
	EXPECT_EQ(t.boundaryLoops, 0u);
	EXPECT_EQ(t.leastFaces, 14u);
	// an annulus (a 3 x 1 strip closed around): two loops of 3, 6 faces, the least
	std::vector<int32_t> ring;
	for (int i = 0; i < 3; ++i)
		ring.insert(ring.end(), {i, (i + 1) % 3, 3 + i, (i + 1) % 3, 3 + (i + 1) % 3, 3 + i});
	auto r = levelTopology(ring, 6);
	EXPECT_EQ(r.boundaryLoops, 2u);
	EXPECT_EQ(r.leastFaces, 6u);
	// three triangles on one edge: no claim
	auto nm = levelTopology({0, 1, 2, 1, 0, 3, 0, 1, 4}, 5);
	EXPECT_FALSE(nm.manifold);
	EXPECT_EQ(nm.leastFaces, 0u);
}

TEST(Reduce, a_budget_under_what_the_holes_allow_stops_there_and_says_so)
{
	// CGAL's pig has 7 holes: with each kept open (a triangle at least) and genus 0, a mesh has
	// at least 5 x 7 - 4 = 31 faces; a 2 % budget (17) stops there, and the level says why
	const FlatMesh pig = loadOff("pig.off");
	Params prm;
	std::string error;
	ASSERT_TRUE(parseLevelsBy("faces:10%,2%", prm, error)) << error;
	prm.certifyDistance = false;
	const Result r = buildLevels(pig.view(), prm);
	ASSERT_TRUE(r.ok) << r.error;
	const LevelStats &hi = r.levels.front().stats, &lo = r.levels.back().stats;
	EXPECT_TRUE(hi.targetReached);
	EXPECT_EQ(budgetNote(hi), "");
	EXPECT_FALSE(lo.targetReached);
	EXPECT_EQ(lo.targetFaces, 17u);
	EXPECT_EQ(lo.boundaryLoops, 7u);
	EXPECT_EQ(lo.leastFaces, 31u);
	EXPECT_EQ(lo.faces, 31u);
	EXPECT_NE(budgetNote(lo).find("the least a mesh of its topology can have (7 boundary loops"),
	          std::string::npos)
	    << budgetNote(lo);
}

TEST(Reduce, collapses_by_regions_do_not_depend_on_threads_and_keep_every_bound)
{
	// DESIGN 57: the first collapses made by regions (here of 300 vertices: the textured sphere's
	// 4,514 in 15), by a budget and by an error, bare and textured: the same level for 1 and 3
	// threads, closed, the budget reached or every triangle within the error, texture coordinates
	// finite; and about as near the input as one queue for the whole mesh
	const TexturedSphere s = texturedSphere(96, 48);
	for (const bool textured : {false, true})
		for (const bool budget : {true, false}) {
			SCOPED_TRACE(std::string(textured ? "textured" : "bare") +
			             (budget ? ", budget" : ", error"));
			const MeshView view = textured ? s.view() : s.mesh.view();
			detail::Topology t;
			detail::buildTopology(view, 30.0, t);
			detail::ReduceLimits lim;
			if (budget)
				lim.faces = facesOf(s.mesh) / 10;
			else
				lim.bound = 0.004 * t.diagonal;
			lim.texError = textured ? 0.02 : 0.0;
			lim.texErrorSoft = budget;
			lim.regionVertices = 300;
			detail::ReduceLimits whole = lim;
			whole.regionVertices = 0;
			detail::CollapseSource out1, out3, outWhole;
			detail::ReduceReport r1, r3, rWhole;
			auto reduce = [&](const detail::ReduceLimits &l, size_t threads,
			                  detail::CollapseSource &out, detail::ReduceReport &rep) {
				detail::CollapseSource src;
				detail::inputSource(t, view, src);
				EXPECT_TRUE(detail::reduceLevel(t, view, std::move(src), l, threads, out, rep));
			};
			reduce(lim, 1, out1, r1);
			reduce(lim, 3, out3, r3);
			reduce(whole, 2, outWhole, rWhole);
			EXPECT_EQ(r1.regions, 15);
			EXPECT_GT(r1.regionCollapses, r1.collapses / 3); // (45-49 %: small regions)
			EXPECT_LT(r1.regionCollapses, r1.collapses);
			EXPECT_EQ(rWhole.regions, 0);
			EXPECT_EQ(rWhole.regionCollapses, 0u);
			EXPECT_EQ(out1.mesh.triangles, out3.mesh.triangles);
			EXPECT_EQ(out1.mesh.positions, out3.mesh.positions);
			EXPECT_EQ(out1.mesh.cornerUV, out3.mesh.cornerUV);
			EXPECT_EQ(out1.bound, out3.bound);
			EXPECT_EQ(out1.mesh.superface, out3.mesh.superface);
			EXPECT_EQ(out1.mesh.inputSuperface, out3.mesh.inputSuperface);
			const LevelStats &st = out1.mesh.stats, &sw = outWhole.mesh.stats;
			EXPECT_TRUE(topoFacts(out1.mesh.positions, out1.mesh.triangles).closedManifold());
			if (budget) {
				EXPECT_LE(st.faces, lim.faces);
				EXPECT_LE(st.distanceBound, 1.25 * sw.distanceBound);
			} else {
				EXPECT_LE(st.distanceBound, lim.bound);
				EXPECT_LE(double(st.faces), 1.1 * double(sw.faces));
			}
			for (float x : out1.mesh.cornerUV)
				EXPECT_TRUE(std::isfinite(x));
			if (textured)
				EXPECT_LE(r1.maxTexError, budget ? 1.0 : lim.texError);
		}
}

TEST(Reduce, collapses_by_regions_join_the_superfaces_of_the_patches_they_collapse)
{
	// DESIGN 57 with DESIGN 50's superfaces kept: the regions join the superfaces of the patches
	// they collapse once they stop, in their order: the same level and superfaces for 1 and 3
	// threads, every output superface a union of source superfaces, the budget reached
	const TexturedSphere s = texturedSphere(96, 48);
	detail::Topology t;
	detail::buildTopology(s.mesh.view(), 30.0, t);
	detail::ReduceLimits lim;
	lim.faces = facesOf(s.mesh) / 4;
	lim.keepSuperfaces = true;
	lim.placement = false;
	lim.regionVertices = 300;
	detail::CollapseSource src, out1, out3;
	detail::inputSource(t, s.mesh.view(), src);
	// (source superfaces: the sphere's 96 x 47 quads, two triangles each, and the caps' triangles)
	const size_t nF = facesOf(s.mesh);
	for (size_t f = 0; f < nF; ++f)
		src.mesh.superface[f] = int32_t(f < nF - 2 * 96 ? f / 2 : f);
	for (size_t f = 0; f < nF; ++f)
		src.mesh.inputSuperface[f] = src.mesh.superface[f];
	detail::ReduceReport r1, r3;
	ASSERT_TRUE(detail::reduceLevel(t, s.mesh.view(), src, lim, 1, out1, r1));
	ASSERT_TRUE(detail::reduceLevel(t, s.mesh.view(), src, lim, 3, out3, r3));
	EXPECT_EQ(r1.regions, 15);
	EXPECT_GT(r1.regionCollapses, 0u);
	EXPECT_EQ(out1.mesh.triangles, out3.mesh.triangles);
	EXPECT_EQ(out1.mesh.superface, out3.mesh.superface);
	EXPECT_EQ(out1.mesh.inputSuperface, out3.mesh.inputSuperface);
	EXPECT_LE(out1.mesh.stats.faces, lim.faces);
	EXPECT_TRUE(topoFacts(out1.mesh.positions, out1.mesh.triangles).closedManifold());
	// (every input face in the superface of the triangle standing for it: the joins were made)
	ASSERT_EQ(out1.inputTri.size(), nF);
	size_t wrong = 0;
	for (size_t f = 0; f < nF; ++f)
		wrong += out1.mesh.superface[size_t(out1.inputTri[f])] != out1.mesh.inputSuperface[f];
	EXPECT_EQ(wrong, 0u);
}

TEST(Reduce, a_mesh_of_two_default_regions_is_reduced_by_them_the_same_for_any_threads)
{
	// DESIGN 57 at the default region size (16,384 vertices): a sphere of 33,538 vertices has two;
	// the level is the same for 1 and 2 threads, closed, at the budget
	const TexturedSphere s = texturedSphere(262, 129);
	detail::Topology t;
	detail::buildTopology(s.mesh.view(), 30.0, t);
	ASSERT_GE(t.nV, 2 * detail::ReduceLimits().regionVertices);
	detail::ReduceLimits lim;
	lim.faces = facesOf(s.mesh) / 20;
	detail::CollapseSource out1, out2;
	detail::ReduceReport r1, r2;
	for (const size_t threads : {size_t(1), size_t(2)}) {
		detail::CollapseSource src;
		detail::inputSource(t, s.mesh.view(), src);
		EXPECT_TRUE(detail::reduceLevel(t, s.mesh.view(), std::move(src), lim, threads,
		                                threads == 1 ? out1 : out2, threads == 1 ? r1 : r2));
	}
	EXPECT_EQ(r1.regions, 2);
	EXPECT_GT(r1.regionCollapses, r1.collapses / 2);
	EXPECT_EQ(out1.mesh.triangles, out2.mesh.triangles);
	EXPECT_EQ(out1.mesh.positions, out2.mesh.positions);
	EXPECT_LE(out1.mesh.stats.faces, lim.faces);
	EXPECT_TRUE(topoFacts(out1.mesh.positions, out1.mesh.triangles).closedManifold());
}
