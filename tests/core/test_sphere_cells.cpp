// 2.1 Gauss sphere cells: codes, nesting, neighbourhoods, bounds.
#include "gausslod/gausslod.h"
#include "sphere_cells.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

using namespace gausslod;

namespace {
Cell cellOf(double x, double y, double z, int level)
{
	const double n[3] = {x, y, z};
	Cell c;
	EXPECT_TRUE(normalToCell(n, level, c));
	return c;
}
} // namespace

TEST(SphereCells, axis_normals_land_in_the_center_cell_of_their_cube_face)
{
	for (int level = 0; level <= kMaxCellLevel; ++level) {
		const int mid = meshNum(level) / 2;
		const double axes[6][3] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
		                           {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
		for (int f = 0; f < 6; ++f) {
			const Cell c = cellOf(axes[f][0], axes[f][1], axes[f][2], level);
			EXPECT_EQ(c.face, f);
			EXPECT_EQ(c.i, mid);
			EXPECT_EQ(c.j, mid);
		}
	}
}

TEST(SphereCells, known_normals_give_known_codes)
{
	// +x face, Angle1 = atan(z/x), Angle2 = atan(y/x) (paper Fig. 4). Level 1: cells of 30 deg.
	const double t20 = std::tan(20.0 * M_PI / 180), t40 = std::tan(40.0 * M_PI / 180);
	Cell c = cellOf(1, 0, t20, 1); // a1 = 20 deg -> index 1 + round(0.67) = 2
	EXPECT_EQ(c.face, 0);
	EXPECT_EQ(c.i, 2);
	EXPECT_EQ(c.j, 1);
	c = cellOf(-1, -t40, 0, 2); // -x face, a2 = -40 deg at level 2 (10 deg): 4 + round(-4) = 0
	EXPECT_EQ(c.face, 1);
	EXPECT_EQ(c.i, 4);
	EXPECT_EQ(c.j, 0);
	c = cellOf(0.2, 0.1, -1, 3); // -z face: a1 = atan(y/|z|) = 5.71 deg, a2 = atan(x/|z|) = 11.3
	EXPECT_EQ(c.face, 5);
	EXPECT_EQ(c.i, 13 + 2); // 5.71 / 3.33 = 1.71 -> 2
	EXPECT_EQ(c.j, 13 + 3); // 11.31 / 3.33 = 3.39 -> 3
	// exactly 45 deg is clamped into the last cell instead of overflowing
	c = cellOf(1, 1, 0, 2);
	EXPECT_EQ(c.face, 0);
	EXPECT_EQ(c.j, 8);
	const double bad[3] = {0, 0, 0}, nan[3] = {NAN, 0, 1};
	EXPECT_FALSE(normalToCell(bad, 2, c));
	EXPECT_FALSE(normalToCell(nan, 2, c));
}

TEST(SphereCells, the_code_at_level_L_minus_1_is_the_parent_of_the_code_at_level_L)
{
	std::mt19937_64 rng(7);
	std::normal_distribution<double> g;
	for (int s = 0; s < 100000; ++s) {
		const double n[3] = {g(rng), g(rng), g(rng)};
		Cell fine;
		ASSERT_TRUE(normalToCell(n, kMaxCellLevel, fine));
		for (int level = kMaxCellLevel; level >= 1; --level) {
			Cell c, p;
			ASSERT_TRUE(normalToCell(n, level, c));
			ASSERT_TRUE(normalToCell(n, level - 1, p));
			ASSERT_EQ(parentCell(c), p) << "level " << level;
		}
	}
}

TEST(SphereCells, neighbourhoods_are_symmetric_with_8_cells_or_7_at_cube_corners)
{
	for (int level = 1; level <= 4; ++level) {
		const int m = meshNum(level);
		size_t total = 0;
		for (int f = 0; f < 6; ++f)
			for (int i = 0; i < m; ++i)
				for (int j = 0; j < m; ++j) {
					const Cell c{f, i, j};
					Cell nb[8];
					const int n = cellNeighbours(c, level, nb);
					const bool corner = (i == 0 || i == m - 1) && (j == 0 || j == m - 1);
					ASSERT_EQ(n, corner ? 7 : 8) << level << " " << f << " " << i << " " << j;
					std::set<CellKey> distinct;
					for (int k = 0; k < n; ++k) {
						distinct.insert(packCell(nb[k]));
						ASSERT_NE(nb[k], c);
						Cell back[8];
						const int nbk = cellNeighbours(nb[k], level, back);
						bool found = false;
						for (int q = 0; q < nbk; ++q)
							found = found || back[q] == c;
						ASSERT_TRUE(found) << "not symmetric at level " << level;
					}
					ASSERT_EQ(distinct.size(), size_t(n));
					total += size_t(n);
				}
		// cube corners: 8 corners x 3 faces have one missing neighbour
		EXPECT_EQ(total, size_t(6 * m * m * 8 - 24));
	}
	Cell nb[8];
	EXPECT_EQ(cellNeighbours(Cell{0, 0, 0}, 0, nb), 4); // level 0: a cube face has 4 neighbours
}

TEST(SphereCells, neighbour_cells_are_adjacent_on_the_sphere)
{
	// Neighbour centers are at most about two cell diagonals apart on the sphere.
	for (int level = 1; level <= 5; ++level) {
		const int m = meshNum(level);
		const double limit = 2.0 * levelBoundDeg(level);
		for (int f = 0; f < 6; ++f)
			for (int i = 0; i < m; i += std::max(1, m / 7))
				for (int j = 0; j < m; j += std::max(1, m / 7)) {
					double a[3], b[3];
					cellCenter(Cell{f, i, j}, level, a);
					Cell nb[8];
					const int n = cellNeighbours(Cell{f, i, j}, level, nb);
					for (int k = 0; k < n; ++k) {
						cellCenter(nb[k], level, b);
						const double d =
						    std::acos(std::min(1.0, a[0] * b[0] + a[1] * b[1] + a[2] * b[2]));
						EXPECT_LT(d * 180 / M_PI, limit);
					}
				}
	}
}

TEST(SphereCells, level_bounds_are_the_cell_diagonal)
{
	EXPECT_NEAR(levelBoundDeg(0), 127.279, 1e-3);
	EXPECT_NEAR(levelBoundDeg(1), 42.426, 1e-3);
	EXPECT_NEAR(levelBoundDeg(2), 14.142, 1e-3);
	EXPECT_NEAR(levelBoundDeg(4), 1.571, 1e-3);
}
