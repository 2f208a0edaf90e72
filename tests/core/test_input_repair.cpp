// Input repair: welding (a triangle soup is simplified like its welded mesh), what is skipped and
// locked is counted, and a level never loses input faces silently.
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <string>

using namespace gausslod;
using namespace testmesh;

namespace {

// Every face with its own three vertices (an STL file as VCG reads it).
FlatMesh soupOf(const FlatMesh &m)
{
	FlatMesh s;
	for (const int32_t v : m.triangles) {
		s.triangles.push_back(int32_t(s.positions.size() / 3));
		for (int k = 0; k < 3; ++k)
			s.positions.push_back(m.positions[3 * size_t(v) + size_t(k)]);
	}
	return s;
}

// The welded mesh of `m` with only the kept vertices, numbered in their order in `m`.
FlatMesh compactWelded(const FlatMesh &m)
{
	const FlatMesh w = weldedCopy(m);
	std::vector<int32_t> id(w.positions.size() / 3, -1);
	for (const int32_t v : w.triangles)
		id[size_t(v)] = 0;
	FlatMesh out;
	for (size_t v = 0; v < id.size(); ++v)
		if (id[v] == 0) {
			id[v] = int32_t(out.positions.size() / 3);
			out.positions.insert(out.positions.end(), w.positions.begin() + long(3 * v),
			                     w.positions.begin() + long(3 * v + 3));
		}
	for (const int32_t v : w.triangles)
		out.triangles.push_back(id[size_t(v)]);
	return out;
}

// A level's triangles as coordinates, in the level's order.
std::vector<double> triangleCoordinates(const LevelMesh &lm)
{
	std::vector<double> c;
	for (const int32_t v : lm.triangles)
		c.insert(c.end(), lm.positions.begin() + long(3 * v),
		         lm.positions.begin() + long(3 * v + 3));
	return c;
}

} // namespace

TEST(InputRepair, a_triangle_soup_gives_the_levels_of_its_welded_mesh)
{
	for (const char *name : {"fandisk.off", "cow.off"}) {
		SCOPED_TRACE(name);
		const FlatMesh soup = soupOf(loadOff(name));
		const FlatMesh welded = compactWelded(soup);
		const Result a = buildLevels(soup.view(), paperParams());
		const Result b = buildLevels(welded.view(), paperParams());
		ASSERT_TRUE(a.ok) << a.error;
		ASSERT_TRUE(b.ok) << b.error;
		EXPECT_EQ(a.input.weldedVertices, soup.positions.size() / 3 - welded.positions.size() / 3);
		// faces with a corner whose position came earlier in the soup
		size_t reindexed = 0;
		std::set<std::array<double, 3>> seen;
		for (size_t f = 0; f < soup.triangles.size() / 3; ++f) {
			bool again = false;
			for (size_t k = 0; k < 3; ++k) {
				const double *q = &soup.positions[3 * (3 * f + k)];
				again |= !seen.insert({q[0], q[1], q[2]}).second;
			}
			reindexed += again;
		}
		EXPECT_EQ(a.input.facesReindexed, reindexed);
		EXPECT_EQ(b.input.weldedVertices, 0u);
		ASSERT_EQ(a.levels.size(), b.levels.size());
		for (size_t i = 0; i < a.levels.size(); ++i) {
			SCOPED_TRACE("level " + std::to_string(a.levels[i].stats.level));
			EXPECT_EQ(triangleCoordinates(a.levels[i]), triangleCoordinates(b.levels[i]));
			EXPECT_EQ(a.levels[i].stats.input.weldedVertices, a.input.weldedVertices);
		}
		// and the coarsest level is far below the input (the soup is simplified)
		EXPECT_LT(a.levels.back().stats.faces, soup.triangles.size() / 3 * 2 / 3);
	}
}

// The engine drops the vertices it welds away when they are many (DESIGN 44): a level's output
// vertices must still name input vertices, the first of the soup at their position (the one the
// others were welded into), also when the levels are built on the coplanar-reduced mesh.
TEST(InputRepair, a_soup_s_levels_name_its_first_vertex_at_each_position)
{
	struct Case {
		const char *name;
		FlatMesh clean;
		Params params;
	};
	Params planar = exactParams(); // (the grid cube: reduced to 12 faces before the levels)
	const Case cases[] = {{"cow", loadOff("cow.off"), Params()},
	                      {"fandisk placed", loadOff("fandisk.off"), Params()},
	                      {"grid cube", gridCube(12), planar}};
	for (const Case &c : cases) {
		SCOPED_TRACE(c.name);
		const FlatMesh soup = soupOf(c.clean);
		std::map<std::array<double, 3>, int32_t> first; // position -> first soup vertex there
		for (size_t v = 0; v < soup.positions.size() / 3; ++v)
			first.emplace(std::array<double, 3>{soup.positions[3 * v], soup.positions[3 * v + 1],
			                                    soup.positions[3 * v + 2]},
			              int32_t(v));
		const FlatMesh welded = compactWelded(soup);
		const Result a = buildLevels(soup.view(), c.params);
		const Result b = buildLevels(welded.view(), c.params);
		ASSERT_TRUE(a.ok) << a.error;
		ASSERT_TRUE(b.ok) << b.error;
		ASSERT_GT(a.input.weldedVertices, soup.positions.size() / 3 / 2); // (dropped: 5 of 6)
		if (std::string(c.name) == "grid cube")
			EXPECT_EQ(a.input.facesAfterCoplanar, 12u); // (built on the reduced mesh)
		ASSERT_EQ(a.levels.size(), b.levels.size());
		size_t named = 0;
		for (size_t i = 0; i < a.levels.size(); ++i) {
			const LevelMesh &la = a.levels[i], &lb = b.levels[i];
			SCOPED_TRACE("level " + std::to_string(la.stats.level));
			EXPECT_EQ(la.positions, lb.positions); // (the same levels, placed vertices too)
			EXPECT_EQ(la.triangles, lb.triangles);
			ASSERT_EQ(la.sourceVertex.size(), lb.sourceVertex.size());
			for (size_t v = 0; v < la.sourceVertex.size(); ++v) {
				const int32_t s = la.sourceVertex[v];
				ASSERT_GE(s, 0);
				ASSERT_LT(size_t(s), soup.positions.size() / 3);
				const std::array<double, 3> at{soup.positions[3 * size_t(s)],
				                               soup.positions[3 * size_t(s) + 1],
				                               soup.positions[3 * size_t(s) + 2]};
				EXPECT_EQ(first.at(at), s);
				// the welded mesh's source vertex is at the same input position
				for (int k = 0; k < 3; ++k)
					EXPECT_EQ(welded.positions[3 * size_t(lb.sourceVertex[v]) + size_t(k)],
					          at[size_t(k)]);
				++named;
			}
		}
		EXPECT_GT(named, 0u);
	}
}

TEST(InputRepair, closed_shells_that_touch_are_not_welded)
{
	// two closed cubes side by side, each with its own vertices: the touching faces' vertices are
	// at the same positions. Welding them would make every edge there non-manifold (four faces);
	// a vertex whose edges faces already share is not welded (DESIGN 15), so the two stay closed.
	FlatMesh m = gridCube(3);
	const size_t nv = m.positions.size() / 3, nf = m.triangles.size() / 3;
	for (size_t v = 0; v < nv; ++v)
		m.positions.insert(m.positions.end(), {m.positions[3 * v] + 1, m.positions[3 * v + 1],
		                                       m.positions[3 * v + 2]});
	for (size_t c = 0; c < 3 * nf; ++c)
		m.triangles.push_back(m.triangles[c] + int32_t(nv));
	ASSERT_TRUE(topoFacts(m.positions, m.triangles).closedManifold());
	const Result r = buildLevels(m.view(), Params());
	ASSERT_TRUE(r.ok) << r.error;
	EXPECT_EQ(r.input.weldedVertices, 0u);
	EXPECT_EQ(r.input.verticesLocked, 0u);
	for (const LevelMesh &lm : r.levels) {
		EXPECT_EQ(lm.stats.faces, 24u) << "level " << lm.stats.level; // 12 + 12: two exact cubes
		EXPECT_TRUE(topoFacts(lm.positions, lm.triangles).closedManifold())
		    << "level " << lm.stats.level;
	}
	// the same faces as a soup are welded (every vertex is on an edge one face uses), as MeshLab
	// does to an STL file: there the two cubes become one mesh
	const Result s = buildLevels(soupOf(m).view(), Params());
	ASSERT_TRUE(s.ok) << s.error;
	const size_t touching = (3 + 1) * (3 + 1); // (the grid vertices of the face the cubes share)
	EXPECT_EQ(s.input.weldedVertices, soupOf(m).positions.size() / 3 - (2 * nv - touching));
}

TEST(InputRepair, without_welding_a_soup_stays_as_it_is)
{
	const FlatMesh soup = soupOf(loadOff("fandisk.off"));
	Params p;
	p.weldVertices = false;
	const Result r = buildLevels(soup.view(), p);
	ASSERT_TRUE(r.ok) << r.error;
	EXPECT_EQ(r.input.weldedVertices, 0u);
	for (const LevelMesh &lm : r.levels)
		EXPECT_EQ(lm.stats.faces, soup.triangles.size() / 3); // every face its own superface
}

TEST(InputRepair, a_weld_distance_joins_near_vertices_and_no_farther_ones)
{
	const FlatMesh clean = loadOff("fandisk.off");
	FlatMesh soup = soupOf(clean);
	const double diag = bboxDiagonal(soup.view()), eps = 1e-6 * diag;
	std::mt19937 rng(7);
	std::uniform_real_distribution<double> jitter(-eps, eps);
	for (double &x : soup.positions)
		x += jitter(rng); // rounding noise: within sqrt(3) eps of the true position
	Params p;
	const Result exact = buildLevels(soup.view(), p);
	ASSERT_TRUE(exact.ok) << exact.error;
	EXPECT_EQ(exact.input.weldedVertices, 0u); // no two positions are exactly equal any more

	p.weldDistance = 4 * eps / diag; // > the 2 sqrt(3) eps two copies can be apart
	const Result near = buildLevels(soup.view(), p);
	ASSERT_TRUE(near.ok) << near.error;
	EXPECT_EQ(near.input.weldedVertices, soup.positions.size() / 3 - clean.positions.size() / 3);
	EXPECT_LT(near.levels.back().stats.faces, clean.triangles.size() / 20);
	// every face still refers to a vertex within the weld distance of its own corner
	for (const LevelMesh &lm : near.levels)
		for (const int32_t v : lm.sourceVertex)
			ASSERT_TRUE(v >= 0 && size_t(v) < soup.positions.size() / 3);

	p.weldDistance = -1;
	EXPECT_NE(buildLevels(soup.view(), p).error.find("weldDistance"), std::string::npos);
}

TEST(InputRepair, skipped_degenerate_and_locked_faces_are_counted)
{
	FlatMesh m = gridCube(3);
	const size_t faces = m.triangles.size() / 3;
	// a repeat of face 0, a face with a repeated vertex, a reversed copy of face 1 (kept: a
	// two-sided sheet, whose edges are non-manifold), and a face on two equal positions
	m.triangles.insert(m.triangles.end(), {m.triangles[0], m.triangles[1], m.triangles[2]});
	m.triangles.insert(m.triangles.end(), {m.triangles[3], m.triangles[3], m.triangles[4]});
	m.triangles.insert(m.triangles.end(), {m.triangles[5], m.triangles[4], m.triangles[3]});
	const size_t n = m.positions.size() / 3;
	m.positions.insert(m.positions.end(), {0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.6, 0.6, 0.6}); // 2 equal
	m.triangles.insert(m.triangles.end(), {int32_t(n), int32_t(n + 1), int32_t(n + 2)});
	const Result r = buildLevels(m.view(), exactParams());
	ASSERT_TRUE(r.ok) << r.error;
	EXPECT_EQ(r.input.weldedVertices, 1u); // n+1 onto n
	EXPECT_EQ(r.input.facesReindexed, 1u);
	EXPECT_EQ(r.input.facesRepeatedVertex, 2u); // the face with a repeat, and n, n, n+2 once welded
	EXPECT_EQ(r.input.facesDuplicate, 1u);
	EXPECT_EQ(r.input.facesDegenerate, 0u);
	EXPECT_EQ(r.input.verticesLocked, 3u); // the two-sided sheet's corners
	for (const LevelMesh &lm : r.levels)
		EXPECT_EQ(lm.stats.input.facesSkipped(), 3u);
	EXPECT_EQ(faces + 4, m.triangles.size() / 3);

	FlatMesh flat = gridCube(2);
	flat.positions.insert(flat.positions.end(), {2, 2, 2, 3, 3, 3});
	const int32_t a = int32_t(flat.positions.size() / 3 - 2);
	flat.triangles.insert(flat.triangles.end(), {a, a + 1, a + 1}); // not a triangle: dropped
	flat.positions.insert(flat.positions.end(), {2, 2, 2, 2, 2, 2, 2, 2, 2});
	flat.triangles.insert(flat.triangles.end(), {a + 2, a + 3, a + 4}); // a point: zero area
	const Result d = buildLevels(flat.view(), exactParams());
	ASSERT_TRUE(d.ok) << d.error;
	// (welded onto vertex a: the zero-area face becomes a, a, a and is skipped too)
	EXPECT_EQ(d.input.facesRepeatedVertex, 2u);
	Params noWeld = exactParams();
	noWeld.weldVertices = false;
	const Result k = buildLevels(flat.view(), noWeld);
	ASSERT_TRUE(k.ok) << k.error;
	EXPECT_EQ(k.input.facesRepeatedVertex, 1u);
	EXPECT_EQ(k.input.facesDegenerate, 1u); // kept as it is
	for (const LevelMesh &lm : k.levels)
		EXPECT_GE(lm.stats.faces, 13u); // the cube's 12, and the zero-area face
}

TEST(InputRepair, a_mesh_whose_every_face_is_skipped_is_an_error_not_an_empty_level)
{
	FlatMesh m;
	m.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0};
	m.triangles = {0, 1, 1, 0, 1, 2, 3, 1, 2}; // a repeated index; a face; the same face, welded
	const Result r = buildLevels(m.view(), exactParams());
	ASSERT_TRUE(r.ok) << r.error; // one face is left: a valid one-face level
	for (const LevelMesh &lm : r.levels)
		EXPECT_EQ(lm.stats.faces, 1u);

	m.triangles = {0, 1, 1, 2, 2, 0, 0, 1, 3}; // 0 and 3 weld: every face repeats a vertex
	const Result e = buildLevels(m.view(), exactParams());
	EXPECT_FALSE(e.ok);
	EXPECT_EQ(e.errorKind, ErrorKind::BadInput);
	EXPECT_NE(e.error.find("nothing to simplify"), std::string::npos) << e.error;
	EXPECT_TRUE(e.levels.empty());
	const Result c = checkInput(m.view(), exactParams());
	EXPECT_FALSE(c.ok);
	EXPECT_EQ(c.error, e.error);
	EXPECT_EQ(c.input.facesRepeatedVertex, 3u);
}

TEST(InputRepair, check_input_reports_what_build_levels_would)
{
	const FlatMesh soup = soupOf(loadOff("cow.off"));
	const Result c = checkInput(soup.view(), Params());
	ASSERT_TRUE(c.ok) << c.error;
	EXPECT_TRUE(c.levels.empty());
	const Result b = buildLevels(soup.view(), Params());
	EXPECT_EQ(c.input.weldedVertices, b.input.weldedVertices);
	EXPECT_EQ(c.input.verticesLocked, b.input.verticesLocked);
	Params bad;
	bad.maxLevel = 0;
	EXPECT_EQ(checkInput(soup.view(), bad).errorKind, ErrorKind::BadParameter);
	FlatMesh empty;
	EXPECT_EQ(checkInput(empty.view(), Params()).errorKind, ErrorKind::BadInput);
}
