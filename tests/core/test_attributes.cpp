// Attributes (docs/ALGORITHM.md, "Beyond the paper"): superfaces never cross a delimiter (face
// keys, corner keys) at any level, and every output corner names an input corner of its
// superface at the same vertex, from which callers copy the attributes.
#include "test_meshes.h"

#include <cmath>
#include <gtest/gtest.h>

using namespace gausslod;
using namespace testmesh;

namespace {

MeshView withKeys(const FlatMesh &m, const std::vector<uint32_t> *faceKey,
                  const std::vector<uint32_t> *cornerKey)
{
	MeshView v = m.view();
	v.faceKey = faceKey ? faceKey->data() : nullptr;
	v.cornerKey = cornerKey ? cornerKey->data() : nullptr;
	v.wantSources = true;
	return v;
}

// Every superface holds faces of one key; every output corner's source is a corner of its
// superface at the output vertex (the welded vertex), and its face is the superface's too.
void expectSourcesAndKeys(const FlatMesh &m, const Result &r, const std::vector<uint32_t> &key)
{
	ASSERT_TRUE(r.ok) << r.error;
	for (const LevelMesh &lm : r.levels) {
		SCOPED_TRACE("level " + std::to_string(lm.stats.level));
		std::vector<int64_t> sfKey(lm.stats.superfaces, -1);
		size_t mixed = 0;
		for (size_t f = 0; f < lm.inputSuperface.size(); ++f) {
			int64_t &k = sfKey[size_t(lm.inputSuperface[f])];
			mixed += k >= 0 && k != int64_t(key[f]);
			k = key[f];
		}
		EXPECT_EQ(mixed, 0u) << "a superface holds faces of two keys";
		ASSERT_EQ(lm.sourceCorner.size(), lm.triangles.size());
		ASSERT_EQ(lm.sourceFace.size(), lm.triangles.size() / 3);
		// each output corner's source corner is at its vertex: at the same position, or (a
		// placed vertex) within the level's largest move of it
		size_t bad = 0, moved = 0;
		const double reach = lm.stats.maxPlacement * (1 + 1e-9);
		for (size_t c = 0; c < lm.triangles.size(); ++c) {
			const int32_t src = lm.sourceCorner[c], sf = lm.superface[c / 3];
			const double *a = &lm.positions[3 * size_t(lm.triangles[c])];
			const double *b = &m.positions[3 * size_t(m.triangles[size_t(src)])];
			const double d =
			    std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
			              (a[2] - b[2]) * (a[2] - b[2]));
			moved += d > 0;
			// (a level continued by collapses, DESIGN 51: the corner's face has the key of the
			// triangle's face; else it is a face of the triangle's superface)
			bad += d > reach ||
			       (lm.stats.reduced ? key[size_t(src / 3)] != key[size_t(lm.sourceFace[c / 3])]
			                         : lm.inputSuperface[size_t(src / 3)] != sf);
		}
		EXPECT_EQ(bad, 0u);
		EXPECT_EQ(moved > 0, lm.stats.placedVertices > 0);
		for (size_t f = 0; f < lm.sourceFace.size(); ++f)
			if (lm.stats.reduced)
				EXPECT_EQ(int64_t(key[size_t(lm.sourceFace[f])]), sfKey[size_t(lm.superface[f])]);
			else
				EXPECT_EQ(lm.inputSuperface[size_t(lm.sourceFace[f])], lm.superface[f]);
	}
}

// An output triangle that crosses the segment x = 0, y in [y0, y1] (strictly inside).
size_t trianglesAcross(const LevelMesh &lm, double y0, double y1)
{
	size_t n = 0;
	for (size_t f = 0; f < lm.triangles.size() / 3; ++f) {
		bool across = false;
		for (size_t k = 0; k < 3; ++k) {
			const double *a = &lm.positions[3 * size_t(lm.triangles[3 * f + k])];
			const double *b = &lm.positions[3 * size_t(lm.triangles[3 * f + (k + 1) % 3])];
			if ((a[0] < -1e-12 && b[0] > 1e-12) || (a[0] > 1e-12 && b[0] < -1e-12)) {
				const double y = a[1] + (b[1] - a[1]) * (0 - a[0]) / (b[0] - a[0]);
				across |= y > y0 + 1e-12 && y < y1 - 1e-12;
			}
		}
		n += across;
	}
	return n;
}

// A flat grid over [-1,1] x [0,1] (n x n/2 cells).
FlatMesh flatGrid(int n)
{
	FlatMesh m = gridWithHole(n, 0, 0);
	for (size_t v = 0; v < m.positions.size() / 3; ++v)
		m.positions[3 * v] = 2 * m.positions[3 * v] - 1;
	return m;
}

double centroidX(const FlatMesh &m, size_t f)
{
	double x = 0;
	for (size_t k = 0; k < 3; ++k)
		x += m.positions[3 * size_t(m.triangles[3 * f + k])];
	return x / 3;
}

} // namespace

TEST(Attributes, no_keys_and_equal_keys_give_the_levels_without_attributes)
{
	const FlatMesh m = loadOff("fandisk.off");
	const Result plain = buildLevels(m.view(), Params());
	const std::vector<uint32_t> same(m.triangles.size(), 7u);
	const Result keyed = buildLevels(withKeys(m, &same, &same), Params());
	ASSERT_TRUE(plain.ok && keyed.ok);
	ASSERT_EQ(plain.levels.size(), keyed.levels.size());
	for (size_t i = 0; i < plain.levels.size(); ++i) {
		EXPECT_EQ(plain.levels[i].triangles, keyed.levels[i].triangles);
		EXPECT_EQ(plain.levels[i].positions, keyed.levels[i].positions);
		EXPECT_TRUE(plain.levels[i].sourceCorner.empty()); // (only when asked for)
	}
	expectSourcesAndKeys(m, keyed, same);
}

TEST(Attributes, faces_of_different_keys_never_share_a_superface_at_any_level)
{
	for (const char *name : {"fandisk.off", "cow.off"}) {
		SCOPED_TRACE(name);
		const FlatMesh m = loadOff(name);
		// keys cutting across flat regions: slabs of the bounding box
		std::vector<uint32_t> key(m.triangles.size() / 3);
		double lo = HUGE_VAL, hi = -HUGE_VAL;
		for (size_t f = 0; f < key.size(); ++f)
			lo = std::min(lo, centroidX(m, f)), hi = std::max(hi, centroidX(m, f));
		for (size_t f = 0; f < key.size(); ++f)
			key[f] = uint32_t(3.0 * (centroidX(m, f) - lo) / (hi - lo + 1e-9));
		const Result r = buildLevels(withKeys(m, &key, nullptr), paperParams());
		expectSourcesAndKeys(m, r, key);
		EXPECT_LT(r.levels.back().stats.faces, m.triangles.size() / 3 / 2); // still simplified
	}
}

TEST(Attributes, a_seam_of_corner_keys_is_a_border_and_stays_straight)
{
	const FlatMesh m = flatGrid(16);
	// per-corner key: the side of x = 0 of the corner's face (a UV seam along x = 0)
	std::vector<uint32_t> corner(m.triangles.size());
	for (size_t c = 0; c < corner.size(); ++c)
		corner[c] = centroidX(m, c / 3) < 0 ? 1u : 2u;
	const Result r = buildLevels(withKeys(m, nullptr, &corner), Params());
	expectSourcesAndKeys(m, r, std::vector<uint32_t>(m.triangles.size() / 3, 0u));
	for (const LevelMesh &lm : r.levels) {
		EXPECT_EQ(trianglesAcross(lm, 0.0, 1.0), 0u);
		for (size_t c = 0; c < lm.triangles.size(); ++c) // each corner is on its face's side
			EXPECT_EQ(corner[size_t(lm.sourceCorner[c])], corner[3 * size_t(lm.sourceFace[c / 3])]);
		EXPECT_LE(lm.stats.faces, 4u); // two rectangles
	}
	const Result plain = buildLevels(m.view(), Params());
	ASSERT_TRUE(plain.ok);
	EXPECT_GT(trianglesAcross(plain.levels.back(), 0.0, 1.0), 0u); // (the test can fail)
}

TEST(Attributes, a_seam_that_ends_inside_a_superface_is_kept)
{
	const FlatMesh m = flatGrid(16);
	// a slit: x = 0 for y < 0.75 only; corners at its upper end vertex share one key
	std::vector<uint32_t> corner(m.triangles.size(), 0u);
	for (size_t c = 0; c < corner.size(); ++c) {
		const double *p = &m.positions[3 * size_t(m.triangles[c])];
		if (p[0] == 0 && p[1] < 0.75)
			corner[c] = centroidX(m, c / 3) < 0 ? 1u : 2u;
	}
	const Result r = buildLevels(withKeys(m, nullptr, &corner), Params());
	ASSERT_TRUE(r.ok) << r.error;
	for (const LevelMesh &lm : r.levels) {
		EXPECT_EQ(trianglesAcross(lm, 0.0, 0.75), 0u);
		for (size_t c = 0; c < lm.triangles.size(); ++c) {
			const double *p = &m.positions[3 * size_t(m.triangles[size_t(lm.sourceCorner[c])])];
			if (p[0] == 0 && p[1] < 0.75 && p[1] > 0) // a slit vertex: the face's side
				EXPECT_EQ(corner[size_t(lm.sourceCorner[c])],
				          centroidX(m, size_t(lm.sourceFace[c / 3])) < 0 ? 1u : 2u);
		}
	}
	const Result plain = buildLevels(m.view(), Params());
	ASSERT_TRUE(plain.ok);
	EXPECT_GT(trianglesAcross(plain.levels.back(), 0.0, 0.75), 0u); // (the test can fail)
}

TEST(Attributes, sources_name_the_original_corner_of_a_welded_soup)
{
	// a soup: every corner its own vertex, welded by the engine
	const FlatMesh g = loadOff("fandisk.off");
	FlatMesh s;
	for (const int32_t v : g.triangles) {
		s.triangles.push_back(int32_t(s.positions.size() / 3));
		for (int k = 0; k < 3; ++k)
			s.positions.push_back(g.positions[3 * size_t(v) + size_t(k)]);
	}
	const std::vector<uint32_t> key(s.triangles.size() / 3, 0u);
	const Result r = buildLevels(withKeys(s, &key, nullptr), Params());
	expectSourcesAndKeys(s, r, key);
}

namespace {

// The texture coordinates level lm interpolates at (x, y) (a flat level, z = 0): barycentric in
// the output triangle holding the point, with the coordinates of each corner's source corner.
bool levelUV(const LevelMesh &lm, const std::vector<float> &uv, double x, double y, double out[2])
{
	for (size_t f = 0; f < lm.triangles.size() / 3; ++f) {
		const double *a = &lm.positions[3 * size_t(lm.triangles[3 * f])];
		const double *b = &lm.positions[3 * size_t(lm.triangles[3 * f + 1])];
		const double *c = &lm.positions[3 * size_t(lm.triangles[3 * f + 2])];
		const double det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
		if (det == 0)
			continue;
		const double l1 = ((x - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (y - a[1])) / det;
		const double l2 = ((b[0] - a[0]) * (y - a[1]) - (x - a[0]) * (b[1] - a[1])) / det;
		const double l0 = 1 - l1 - l2;
		if (l0 < -1e-9 || l1 < -1e-9 || l2 < -1e-9)
			continue;
		const double l[3] = {l0, l1, l2};
		out[0] = out[1] = 0;
		for (size_t k = 0; k < 3; ++k) {
			const size_t src = size_t(lm.sourceCorner[3 * f + k]);
			out[0] += l[k] * double(uv[2 * src]), out[1] += l[k] * double(uv[2 * src + 1]);
		}
		return true;
	}
	return false;
}

// The largest distance, in texture space, between an input corner's coordinates and what level
// lm interpolates at its vertex (measured here, independently of the engine).
double measuredTexError(const FlatMesh &m, const std::vector<float> &uv, const LevelMesh &lm)
{
	double worst = 0;
	for (size_t c = 0; c < m.triangles.size(); ++c) {
		const double *p = &m.positions[3 * size_t(m.triangles[c])];
		double at[2];
		if (!levelUV(lm, uv, p[0], p[1], at))
			return HUGE_VAL;
		worst =
		    std::max(worst, std::hypot(at[0] - double(uv[2 * c]), at[1] - double(uv[2 * c + 1])));
	}
	return worst;
}

// Per-corner texture coordinates of m from a function of the corner's position.
template <class Fn>
std::vector<float> cornerUVs(const FlatMesh &m, Fn fn)
{
	std::vector<float> uv(2 * m.triangles.size());
	for (size_t c = 0; c < m.triangles.size(); ++c) {
		const double *p = &m.positions[3 * size_t(m.triangles[c])];
		uv[2 * c] = float(fn(p[0], p[1])[0]), uv[2 * c + 1] = float(fn(p[0], p[1])[1]);
	}
	return uv;
}

} // namespace

TEST(Attributes, affine_texture_coordinates_let_a_plane_become_two_triangles)
{
	const FlatMesh m = flatGrid(16);
	const std::vector<float> uv = cornerUVs(m, [](double x, double y) {
		return std::array<double, 2>{{0.3 * x + 0.1 * y + 0.4, 0.5 * y - 0.2 * x + 0.3}};
	});
	MeshView v = withKeys(m, nullptr, nullptr);
	v.cornerUV = uv.data();
	const Result r = buildLevels(v, Params());
	ASSERT_TRUE(r.ok) << r.error;
	for (const LevelMesh &lm : r.levels) {
		EXPECT_EQ(lm.stats.faces, 2u);
		EXPECT_GE(lm.stats.maxTexError, 0.0);
		EXPECT_LT(lm.stats.maxTexError, 1e-6);
		EXPECT_LT(measuredTexError(m, uv, lm), 1e-6);
	}
}

TEST(Attributes, texture_stretch_is_bounded_by_the_limit_at_every_level)
{
	const FlatMesh m = flatGrid(24);
	// not affine: a linear map cannot follow it over large triangles
	const std::vector<float> uv = cornerUVs(m, [](double x, double y) {
		return std::array<double, 2>{{0.25 * (x + 1) * (x + 1), y + 0.1 * x * y}};
	});
	MeshView v = withKeys(m, nullptr, nullptr);
	v.cornerUV = uv.data();
	std::vector<size_t> coarsest;
	for (const double limit : {1.0 / 2048, 1.0 / 256}) {
		SCOPED_TRACE(limit);
		Params prm = superfaceParams();
		prm.maxTexError = limit;
		const Result r = buildLevels(v, prm);
		ASSERT_TRUE(r.ok) << r.error;
		for (const LevelMesh &lm : r.levels) {
			SCOPED_TRACE("level " + std::to_string(lm.stats.level));
			EXPECT_LE(lm.stats.maxTexError, limit);
			EXPECT_GT(lm.stats.maxTexError, 0.0);
			EXPECT_LE(measuredTexError(m, uv, lm), limit * (1 + 1e-6) + 1e-7);
			EXPECT_LT(lm.stats.faces, m.triangles.size() / 3); // still simplified
		}
		coarsest.push_back(r.levels.back().stats.faces);
	}
	// refined where needed only (bisected superfaces, not the input faces): a looser limit,
	// far fewer faces
	EXPECT_LT(coarsest[1], coarsest[0] / 2) << coarsest[0];
	Params off = superfaceParams();
	off.maxTexError = 0;
	const Result r = buildLevels(v, off);
	ASSERT_TRUE(r.ok) << r.error;
	EXPECT_EQ(r.levels.back().stats.faces, 2u);
	EXPECT_LT(r.levels.back().stats.maxTexError, 0.0);              // (not measured)
	EXPECT_GT(measuredTexError(m, uv, r.levels.back()), 1.0 / 256); // (the test can fail)
}

TEST(Attributes, kept_faces_are_in_every_level_exactly_as_they_are)
{
	for (const char *name : {"fandisk.off", "cow.off"}) {
		SCOPED_TRACE(name);
		const FlatMesh m = loadOff(name);
		const size_t nF = m.triangles.size() / 3;
		// keep the faces on one side of the bounding box (a selection of the other side)
		double lo = HUGE_VAL, hi = -HUGE_VAL;
		for (size_t f = 0; f < nF; ++f)
			lo = std::min(lo, centroidX(m, f)), hi = std::max(hi, centroidX(m, f));
		std::vector<uint8_t> keep(nF);
		for (size_t f = 0; f < nF; ++f)
			keep[f] = centroidX(m, f) < lo + 0.4 * (hi - lo);
		MeshView v = m.view();
		v.keepFace = keep.data();
		const Result r = buildLevels(v, Params());
		ASSERT_TRUE(r.ok) << r.error;
		using Tri = std::array<double, 9>;
		auto rotated = [](const double *a, const double *b, const double *c) { // canonical start
			Tri t[3];
			const double *p[3] = {a, b, c};
			for (int s = 0; s < 3; ++s)
				for (int k = 0; k < 3; ++k)
					for (int j = 0; j < 3; ++j)
						t[s][size_t(3 * k + j)] = p[(s + k) % 3][j];
			return std::min({t[0], t[1], t[2]});
		};
		std::set<Tri> kept;
		for (size_t f = 0; f < nF; ++f)
			if (keep[f])
				kept.insert(rotated(&m.positions[3 * size_t(m.triangles[3 * f])],
				                    &m.positions[3 * size_t(m.triangles[3 * f + 1])],
				                    &m.positions[3 * size_t(m.triangles[3 * f + 2])]));
		EXPECT_EQ(r.input.facesKept, kept.size());
		for (const LevelMesh &lm : r.levels) {
			SCOPED_TRACE("level " + std::to_string(lm.stats.level));
			std::set<Tri> out;
			for (size_t f = 0; f < lm.triangles.size() / 3; ++f)
				out.insert(rotated(&lm.positions[3 * size_t(lm.triangles[3 * f])],
				                   &lm.positions[3 * size_t(lm.triangles[3 * f + 1])],
				                   &lm.positions[3 * size_t(lm.triangles[3 * f + 2])]));
			size_t missing = 0;
			for (const Tri &t : kept)
				missing += out.count(t) == 0;
			EXPECT_EQ(missing, 0u);
			EXPECT_LT(lm.stats.faces - kept.size(), nF - kept.size()); // the rest simplified
		}
		EXPECT_LT(r.levels.back().stats.faces - kept.size(), (nF - kept.size()) * 3 / 4);
		const Result plain = buildLevels(m.view(), Params());
		ASSERT_TRUE(plain.ok);
		size_t survived = 0; // (the test can fail: without keepFace most of them go)
		std::set<Tri> out;
		const LevelMesh &last = plain.levels.back();
		for (size_t f = 0; f < last.triangles.size() / 3; ++f)
			out.insert(rotated(&last.positions[3 * size_t(last.triangles[3 * f])],
			                   &last.positions[3 * size_t(last.triangles[3 * f + 1])],
			                   &last.positions[3 * size_t(last.triangles[3 * f + 2])]));
		for (const Tri &t : kept)
			survived += out.count(t);
		EXPECT_LT(survived, kept.size() / 2);
	}
}
