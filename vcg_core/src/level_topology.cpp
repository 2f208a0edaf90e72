// The least faces a level's topology allows (reduce.h): what a face budget cannot go under while
// the collapses keep every component, its genus and its boundary loops (a hole stays open, at
// least a triangle).
#include "reduce.h"

#include <algorithm>
#include <cmath>

namespace gausslod {
namespace detail {

namespace {

struct UnionFind {
	std::vector<int32_t> up;
	explicit UnionFind(size_t n) : up(n)
	{
		for (size_t i = 0; i < n; ++i)
			up[i] = int32_t(i);
	}
	int32_t find(int32_t x)
	{
		while (up[size_t(x)] != x)
			x = up[size_t(x)] = up[size_t(up[size_t(x)])];
		return x;
	}
	void join(int32_t a, int32_t b) { up[size_t(find(a))] = find(b); }
};

} // namespace

LevelTopology levelTopology(const std::vector<int32_t> &triangles, size_t nV)
{
	LevelTopology out;
	const size_t nT = triangles.size() / 3;
	if (nT == 0)
		return out;
	// undirected edges, each with how many triangles use it
	std::vector<uint64_t> edges(3 * nT);
	for (size_t f = 0; f < nT; ++f)
		for (size_t k = 0; k < 3; ++k) {
			const uint64_t a = uint32_t(triangles[3 * f + k]),
			               b = uint32_t(triangles[3 * f + (k + 1) % 3]);
			edges[3 * f + k] = std::min(a, b) << 32 | std::max(a, b);
		}
	std::sort(edges.begin(), edges.end());
	UnionFind comp(nV), loops(nV);
	std::vector<uint8_t> used(nV, 0), onBoundary(nV, 0);
	for (size_t f = 0; f < nT; ++f)
		for (size_t k = 0; k < 3; ++k) {
			used[size_t(triangles[3 * f + k])] = 1;
			comp.join(triangles[3 * f + k], triangles[3 * f + (k + 1) % 3]);
		}
	// per component: vertices, edges and faces (its Euler characteristic), boundary loops
	std::vector<int64_t> chi(nV, 0);
	std::vector<int32_t> nLoops(nV, 0);
	for (size_t i = 0; i < edges.size();) {
		size_t j = i + 1;
		while (j < edges.size() && edges[j] == edges[i])
			++j;
		const int32_t a = int32_t(edges[i] >> 32), b = int32_t(edges[i] & 0xffffffffu);
		if (j - i > 2)
			out.manifold = false;
		if (j - i == 1) {
			onBoundary[size_t(a)] = onBoundary[size_t(b)] = 1;
			loops.join(a, b);
		}
		--chi[size_t(comp.find(a))];
		i = j;
	}
	for (size_t v = 0; v < nV; ++v) {
		if (!used[v])
			continue;
		++chi[size_t(comp.find(int32_t(v)))];
		if (onBoundary[v] && loops.find(int32_t(v)) == int32_t(v))
			++nLoops[size_t(comp.find(int32_t(v)))]; // (loops that touch count as one)
	}
	for (size_t f = 0; f < nT; ++f)
		++chi[size_t(comp.find(triangles[3 * f]))];
	for (size_t v = 0; v < nV; ++v) {
		if (!used[v] || comp.find(int32_t(v)) != int32_t(v))
			continue;
		++out.components;
		const int64_t b = nLoops[v], x = chi[v];
		out.boundaryLoops += size_t(b);
		if (b > 0) {
			// every vertex on a loop of 3: V = 3b, E = (3F + 3b) / 2, V - E + F = chi
			out.leastFaces += size_t(std::max<int64_t>(1, 3 * b - 2 * x));
		} else {
			// closed: a tetrahedron, or for genus g the fewest vertices a triangulation can have
			// (Heawood's bound), F = 2V - 2 chi
			const int64_t g = std::max<int64_t>(0, (2 - x) / 2);
			const int64_t v0 =
			    g == 0 ? 4 : int64_t(std::ceil((7 + std::sqrt(1.0 + 48.0 * double(g))) / 2 - 1e-9));
			out.leastFaces += size_t(std::max<int64_t>(4, 2 * v0 - 2 * x));
		}
	}
	if (!out.manifold)
		out.leastFaces = 0; // (no claim on a non-manifold level)
	return out;
}

} // namespace detail
} // namespace gausslod
