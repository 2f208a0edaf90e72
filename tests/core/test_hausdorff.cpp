// The certified Hausdorff distance (vcg_core/src/hausdorff.h, docs/DESIGN.md 52): the upper
// bound is never below a distance found by brute force, the lower bound is a distance at a point
// (never above the true one), and the two are within the factor when the search converged.
#include "hausdorff.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace gausslod;
using namespace gausslod::detail;

namespace {

struct Tris {
	std::vector<double> P;
	std::vector<int32_t> T;
	size_t n() const { return T.size() / 3; }
	Vec3 v(size_t f, int k) const
	{
		const size_t i = size_t(T[3 * f + size_t(k)]);
		return Vec3(P[3 * i], P[3 * i + 1], P[3 * i + 2]);
	}
};

// A (cells x cells) grid over [0,1]^2 at height h(x, y).
template <class H>
Tris grid(int cells, H h)
{
	Tris m;
	for (int y = 0; y <= cells; ++y)
		for (int x = 0; x <= cells; ++x) {
			const double u = double(x) / cells, w = double(y) / cells;
			m.P.insert(m.P.end(), {u, w, h(u, w)});
		}
	for (int y = 0; y < cells; ++y)
		for (int x = 0; x < cells; ++x) {
			const int32_t a = y * (cells + 1) + x, b = a + 1, c = a + cells + 1, d = c + 1;
			m.T.insert(m.T.end(), {a, b, d, a, d, c});
		}
	return m;
}

bool skipped(const Tris &m, size_t f) // (a repeated vertex: the tree leaves it out)
{
	const int32_t a = m.T[3 * f], b = m.T[3 * f + 1], c = m.T[3 * f + 2];
	return a == b || b == c || c == a;
}

// The largest distance from points of `from` (its vertices and a barycentric lattice of
// `per` x `per` points per triangle) to the triangles of `to`, by brute force.
double sampledDistance(const Tris &from, const Tris &to, int per)
{
	double worst = 0;
	for (size_t f = 0; f < from.n(); ++f)
		if (!skipped(from, f))
			for (int i = 0; i <= per; ++i)
				for (int j = 0; i + j <= per; ++j) {
					const double a = double(i) / per, b = double(j) / per;
					const Vec3 p = from.v(f, 0) * (1 - a - b) + from.v(f, 1) * a + from.v(f, 2) * b;
					double best = HUGE_VAL;
					for (size_t g = 0; g < to.n(); ++g)
						if (!skipped(to, g))
							best = std::min(best, pointTriangleDistance2(p, to.v(g, 0), to.v(g, 1),
							                                             to.v(g, 2)));
					worst = std::max(worst, std::sqrt(best));
				}
	return worst;
}

HausdorffBounds certified(const Tris &a, const Tris &b, double eps = 0.05, size_t threads = 2)
{
	const TriangleTree ta(a.P.data(), a.T.data(), a.n()), tb(b.P.data(), b.T.data(), b.n());
	return hausdorff(ta, tb, eps, 1u << 22, threads);
}

void expectBracketed(const HausdorffBounds &h, double sampled, double eps = 0.05)
{
	EXPECT_TRUE(h.converged);
	EXPECT_GE(h.upper, sampled);
	EXPECT_LE(h.lower, h.upper);
	EXPECT_LE(h.upper, (1 + eps) * h.lower * (1 + 1e-6) + 1e-12);
}

} // namespace

TEST(CertifiedHausdorff, a_mesh_against_itself_is_zero)
{
	const Tris m =
	    grid(12, [](double x, double y) { return 0.1 * std::sin(6 * x) * std::cos(5 * y); });
	const HausdorffBounds h = certified(m, m);
	EXPECT_LE(h.lower, 1e-12);
	EXPECT_LE(h.upper, 1e-9);
}

TEST(CertifiedHausdorff, triangles_a_level_keeps_from_its_input_are_bounded_by_the_cover)
{
	// (a level keeps most of its input's triangles as they are: the copy of each covers it,
	// though the patch's border runs along its edges; only near the vertex moved is a piece cut)
	const int cells = 12;
	const Tris in =
	    grid(cells, [](double x, double y) { return 0.1 * std::sin(6 * x) * std::cos(5 * y); });
	Tris level = in;
	level.P[3 * size_t((cells / 2) * (cells + 1) + cells / 2) + 2] += 0.01;
	const HausdorffBounds h = certified(level, in);
	expectBracketed(h, sampledDistance(level, in, 40));
	EXPECT_GE(h.byCover, in.n() / 2);
	EXPECT_LE(h.bySplit, 12u);
}

TEST(CertifiedHausdorff, a_bumpy_grid_against_its_flat_square_is_its_amplitude)
{
	// (the bumps peak at grid vertices: both directions are exactly the amplitude)
	const double A = 0.02;
	const Tris bumpy = grid(24, [&](double x, double y) {
		return A * std::sin(2 * M_PI * 3 * x) * std::sin(2 * M_PI * 2 * y);
	});
	const Tris flat = grid(1, [](double, double) { return 0.0; });
	const HausdorffBounds h = certified(bumpy, flat);
	expectBracketed(h, A * (1 - 1e-12));
	EXPECT_LE(h.lower, A * (1 + 1e-12));
	EXPECT_GE(h.lower, A / 1.05);
	// (the coarse-over-fine direction alone: the flat square is within A of the bumps)
	const TriangleTree tf(flat.P.data(), flat.T.data(), flat.n()),
	    tb(bumpy.P.data(), bumpy.T.data(), bumpy.n());
	const HausdorffBounds d = directedHausdorff(tf, tb, 0.05, 1u << 22, 1, 0.0);
	EXPECT_TRUE(d.converged);
	EXPECT_GE(d.upper, sampledDistance(flat, bumpy, 64));
	EXPECT_LE(d.upper, A * 1.06);
}

TEST(CertifiedHausdorff, the_farthest_point_inside_a_triangle_is_bounded)
{
	// a tent (ridge at x0, not a point the search ever cuts at) under a flat square: from the
	// square, the farthest point is over the ridge, h cos(45) away, inside a triangle
	const double h = 0.05, x0 = 0.37;
	Tris tent;
	const double xs[] = {0.0, 0.1, 0.2, 0.3, x0 - h, x0, x0 + h, 0.6, 0.8, 1.0};
	const int nx = 10, ny = 6;
	for (int j = 0; j < ny; ++j)
		for (const double x : xs)
			tent.P.insert(tent.P.end(),
			              {x, double(j) / (ny - 1), std::max(0.0, h - std::fabs(x - x0))});
	for (int j = 0; j + 1 < ny; ++j)
		for (int i = 0; i + 1 < nx; ++i) {
			const int32_t a = j * nx + i, b = a + 1, c = a + nx, d = c + 1;
			tent.T.insert(tent.T.end(), {a, b, d, a, d, c});
		}
	const Tris flat = grid(1, [](double, double) { return 0.0; });
	const TriangleTree tf(flat.P.data(), flat.T.data(), flat.n()),
	    tt(tent.P.data(), tent.T.data(), tent.n());
	// (a small factor: no piece near the ridge is left with a loose bound that would hide a
	// bound below the truth where the ridge is)
	const HausdorffBounds d = directedHausdorff(tf, tt, 0.002, 1u << 22, 1, 0.0);
	const double truth = h / std::sqrt(2.0);
	EXPECT_TRUE(d.converged);
	EXPECT_GE(d.upper, truth);
	EXPECT_LE(d.lower, truth * (1 + 1e-12));
	EXPECT_LE(d.upper, truth * 1.003);
	EXPECT_GE(d.upper, sampledDistance(flat, tent, 400));
}

// A roof (two slopes meeting at a ridge over x = x0) under a flat triangle: the farthest point
// of the triangle is over the ridge. Told a distance close to it (`known`), the search bounds the
// whole triangle at once, without cutting it: by the cover of the roof (ridge shared) or by the
// plane between the slopes (ridge split: the roof's two halves do not share vertices).
void roofCase(bool shared)
{
	const double h = 0.1, x0 = 0.37, s = 0.25;
	Tris roof;
	auto z = [&](double x) { return h - s * std::fabs(x - x0); };
	const double xs[] = {-0.5, x0, x0, 1.5};
	for (int i = 0; i < 4; ++i)
		for (const double y : {-0.5, 1.5})
			roof.P.insert(roof.P.end(), {xs[i], y, z(xs[i])});
	const int32_t r = shared ? 2 : 4; // (the right slope's ridge vertices)
	roof.T = {0, 2, 3, 0, 3, 1, r, 6, 7, r, 7, r + 1};
	Tris flat;
	flat.P = {0, 0, 0, 1, 0, 0, 0, 1, 0};
	flat.T = {0, 1, 2};
	const double truth = h / std::sqrt(1 + s * s);
	const TriangleTree tf(flat.P.data(), flat.T.data(), 1), tr(roof.P.data(), roof.T.data(), 4);
	const HausdorffBounds d = directedHausdorff(tf, tr, 0.01, 1u << 20, 1, 0.999 * truth);
	EXPECT_TRUE(d.converged);
	EXPECT_EQ(d.pieces, 1u); // (no cut: the bound did it)
	EXPECT_GE(d.upper, truth);
	EXPECT_LE(d.upper, 1.01 * truth);
	EXPECT_GE(d.upper, sampledDistance(flat, roof, 300));
}

TEST(CertifiedHausdorff, a_ridge_under_a_triangle_is_bounded_by_the_cover) { roofCase(true); }

TEST(CertifiedHausdorff, a_split_ridge_under_a_triangle_is_bounded_by_the_plane_between)
{
	roofCase(false);
}

TEST(CertifiedHausdorff, never_below_brute_force_on_random_pairs_and_within_the_factor)
{
	std::mt19937 rng(7);
	std::uniform_real_distribution<double> U(-1, 1);
	for (int trial = 0; trial < 12; ++trial) {
		const double a1 = 0.05 * U(rng), a2 = 0.05 * U(rng), f1 = 3 + 3 * U(rng),
		             f2 = 3 + 3 * U(rng);
		const int fine = 10 + trial, coarse = 2 + trial % 5;
		Tris a = grid(
		    fine, [&](double x, double y) { return a1 * std::sin(f1 * x + 1) * std::cos(f2 * y); });
		for (size_t i = 2; i < a.P.size(); i += 3) // (noise on the heights)
			a.P[i] += 0.004 * U(rng);
		const Tris b = grid(
		    coarse, [&](double x, double y) { return a2 * std::cos(f2 * x) * std::sin(f1 * y); });
		const double brute = std::max(sampledDistance(a, b, 8), sampledDistance(b, a, 8));
		SCOPED_TRACE(trial);
		expectBracketed(certified(a, b), brute);
		expectBracketed(certified(b, a), brute);
	}
}

TEST(CertifiedHausdorff, the_same_bound_for_any_thread_count)
{
	const Tris a =
	    grid(40, [](double x, double y) { return 0.03 * std::sin(9 * x) * std::sin(7 * y); });
	const Tris b = grid(7, [](double x, double y) { return 0.01 * x * y; });
	const HausdorffBounds one = certified(a, b, 0.05, 1), two = certified(a, b, 0.05, 2),
	                      four = certified(a, b, 0.05, 4);
	EXPECT_EQ(one.upper, two.upper);
	EXPECT_EQ(one.upper, four.upper);
	EXPECT_EQ(one.lower, four.lower);
	EXPECT_EQ(one.pieces, four.pieces);
}

TEST(CertifiedHausdorff, soups_folds_and_degenerate_triangles_still_bound_it)
{
	// a triangle soup (no shared vertex: no adjacency), a fold (a triangle wound the other way
	// over its neighbour) and zero-area triangles: the bounds fall back to cutting, never below
	Tris grid8 = grid(8, [](double x, double y) { return 0.05 * std::sin(5 * x + 3 * y); });
	Tris soup;
	for (size_t f = 0; f < grid8.n(); ++f)
		for (int k = 0; k < 3; ++k) {
			const Vec3 p = grid8.v(f, k);
			soup.P.insert(soup.P.end(), {p[0], p[1], p[2]});
			soup.T.push_back(int32_t(soup.T.size()));
		}
	std::swap(grid8.T[0], grid8.T[1]); // (the fold)
	grid8.P.insert(grid8.P.end(), {0.5, 0.5, 0.2, 0.2, 0.2, 0.1, 0.4, 0.4, 0.1, 0.6, 0.6, 0.1});
	const int32_t top = int32_t(grid8.P.size() / 3 - 4);
	grid8.T.insert(grid8.T.end(), {0, 0, top, 3, 4, 3});        // (a repeated vertex: left out)
	grid8.T.insert(grid8.T.end(), {top + 1, top + 2, top + 3}); // (zero area: its segments)
	const Tris coarse = grid(3, [](double x, double) { return 0.02 * x; });
	for (const Tris *m : {&soup, &grid8}) {
		const double brute =
		    std::max(sampledDistance(*m, coarse, 10), sampledDistance(coarse, *m, 10));
		expectBracketed(certified(*m, coarse), brute);
		expectBracketed(certified(coarse, *m), brute);
	}
}

TEST(CertifiedHausdorff, coinciding_surfaces_are_certified_at_the_floor_at_once)
{
	// a planar level (two triangles) over its fine input: every bound is a rounding error above
	// 0, never within a factor of the lower bound 0; with a floor the search ends at once
	const Tris fine = grid(40, [](double, double) { return 0.0; });
	const Tris coarse = grid(1, [](double, double) { return 0.0; });
	const TriangleTree tf(fine.P.data(), fine.T.data(), fine.n()),
	    tc(coarse.P.data(), coarse.T.data(), coarse.n());
	const size_t budget = 64 * (fine.n() + coarse.n());
	const HausdorffBounds none = hausdorff(tc, tf, 0.05, budget, 2);
	EXPECT_FALSE(none.converged); // (the budget spent: what the floor is for)
	EXPECT_GE(none.pieces, budget);
	const double floor = 1e-6 * std::sqrt(2.0);
	const HausdorffBounds h = hausdorff(tc, tf, 0.05, budget, 2, floor);
	EXPECT_TRUE(h.converged);
	EXPECT_LE(h.upper, 1.05 * floor * (1 + 1e-6));
	EXPECT_LT(h.pieces, budget / 8);
	// (a floor does not hide a distance above it)
	const Tris lifted = grid(40, [](double x, double) { return 1e-3 * x; });
	const TriangleTree tl(lifted.P.data(), lifted.T.data(), lifted.n());
	expectBracketed(hausdorff(tc, tl, 0.05, 1u << 22, 2, floor), 1e-3);
}

TEST(CertifiedHausdorff, nothing_to_measure_against_is_infinite)
{
	const Tris a = grid(2, [](double, double) { return 0.0; });
	Tris none;
	none.P = a.P;
	const TriangleTree ta(a.P.data(), a.T.data(), a.n()), tn(none.P.data(), none.T.data(), 0);
	const HausdorffBounds h = hausdorff(ta, tn, 0.05, 1000, 1);
	EXPECT_FALSE(h.converged);
	EXPECT_EQ(h.upper, HUGE_VAL);
}
