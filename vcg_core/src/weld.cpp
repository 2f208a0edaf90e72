// Input repair before 2.1: welding coincident vertices (what MeshLab does to STL files on import),
// so that a triangle soup has the edges that superfaces grow across. One pass over the vertices
// with an open-addressing hash table; no allocation per vertex. Only vertices on an open edge
// (an edge one face uses) are welded: a vertex whose every edge faces already share has nothing
// to join, and welding it to another at its position only makes an edge or a vertex
// non-manifold (two closed shells that touch stay two closed shells).
#include "engine.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace gausslod {
namespace detail {

namespace {

uint64_t mix(uint64_t h)
{
	h ^= h >> 33;
	h *= 0xff51afd7ed558ccdull;
	h ^= h >> 33;
	h *= 0xc4ceb9fe1a85ec53ull;
	return h ^ (h >> 33);
}

uint64_t bitsOf(double x)
{
	x += 0.0; // -0.0 and 0.0 are one position
	uint64_t b;
	std::memcpy(&b, &x, sizeof b);
	return b;
}

size_t tableSize(size_t n)
{
	size_t size = 16;
	while (size < 2 * n)
		size *= 2;
	return size;
}

bool finite3(const double *p)
{
	return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

// Sets rep[v] = v for every vertex (what a vertex not welded keeps) and calls weld(v, p) for each
// vertex that may be welded: a finite position p, not skipped (skip[v], if given); in index order.
template <class Weld>
void forWeldable(const MeshView &m, const uint8_t *skip, std::vector<int32_t> &rep, Weld weld)
{
	for (size_t v = 0; v < m.vertexCount; ++v) {
		const double *p = m.positions + 3 * v;
		rep[v] = int32_t(v);
		if (finite3(p) && !(skip && skip[v]))
			weld(v, p);
	}
}

// Exact: each position's first vertex is the key's slot. Vertices with skip[v] (if given) stay.
size_t weldExact(const MeshView &m, const uint8_t *skip, std::vector<int32_t> &rep)
{
	const size_t mask = tableSize(m.vertexCount) - 1;
	std::vector<int32_t> slot(mask + 1, -1);
	size_t merged = 0;
	forWeldable(m, skip, rep, [&](size_t v, const double *p) {
		size_t h = mix(bitsOf(p[0]) ^ mix(bitsOf(p[1]) ^ mix(bitsOf(p[2])))) & mask;
		for (;; h = (h + 1) & mask) {
			const int32_t w = slot[h];
			if (w < 0) {
				slot[h] = int32_t(v);
				break;
			}
			const double *q = m.positions + 3 * size_t(w);
			if (q[0] == p[0] && q[1] == p[1] && q[2] == p[2]) {
				rep[v] = w;
				++merged;
				break;
			}
		}
	});
	return merged;
}

// Within a distance d: kept vertices are listed per grid cell of size d (a slot per occupied
// cell, a chain through `next`); a vertex becomes the lowest kept vertex within d in the 27 cells
// around it, or is kept.
size_t weldWithin(const MeshView &m, double d, const uint8_t *skip, std::vector<int32_t> &rep)
{
	const size_t mask = tableSize(m.vertexCount) - 1;
	struct Slot {
		int64_t c[3];
		int32_t head;
	};
	std::vector<Slot> slot(mask + 1, Slot{{0, 0, 0}, -1});
	std::vector<int32_t> next(m.vertexCount, -1);
	const double limit = double(std::numeric_limits<int64_t>::max() / 4);
	auto cellOf = [&](double x) {
		const double c = std::floor(x / d);
		return int64_t(std::max(-limit, std::min(limit, c)));
	};
	auto find = [&](const int64_t *c, bool insert) -> Slot * {
		size_t h = mix(uint64_t(c[0]) ^ mix(uint64_t(c[1]) ^ mix(uint64_t(c[2])))) & mask;
		for (;; h = (h + 1) & mask) {
			Slot &s = slot[h];
			if (s.head < 0)
				return insert ? &s : nullptr;
			if (s.c[0] == c[0] && s.c[1] == c[1] && s.c[2] == c[2])
				return &s;
		}
	};
	const double d2 = d * d;
	size_t merged = 0;
	forWeldable(m, skip, rep, [&](size_t v, const double *p) {
		const int64_t c[3] = {cellOf(p[0]), cellOf(p[1]), cellOf(p[2])};
		int32_t best = -1;
		for (int64_t dz = -1; dz <= 1; ++dz)
			for (int64_t dy = -1; dy <= 1; ++dy)
				for (int64_t dx = -1; dx <= 1; ++dx) {
					const int64_t n[3] = {c[0] + dx, c[1] + dy, c[2] + dz};
					const Slot *s = find(n, false);
					for (int32_t w = s ? s->head : -1; w >= 0; w = next[size_t(w)]) {
						if (best >= 0 && w > best)
							continue;
						const double *q = m.positions + 3 * size_t(w);
						const double x = q[0] - p[0], y = q[1] - p[1], z = q[2] - p[2];
						if (x * x + y * y + z * z <= d2)
							best = w;
					}
				}
		if (best >= 0) {
			rep[v] = best;
			++merged;
			return;
		}
		Slot *s = find(c, true);
		if (s->head < 0)
			std::memcpy(s->c, c, sizeof c);
		next[v] = s->head;
		s->head = int32_t(v);
	});
	return merged;
}

// closed[v] = 1 for each vertex of `asked` (nonzero) whose every edge two or more faces use. An
// edge with an end that one face alone uses is that face's only (a triangle soup's all are:
// nothing to count); the edges between vertices that several faces use are counted by sorting.
std::vector<uint8_t> closedVertices(const MeshView &m, const std::vector<uint8_t> &asked)
{
	std::vector<uint8_t> uses(m.vertexCount, 0); // (0, 1, 2 = more)
	for (size_t c = 0; c < 3 * m.faceCount; ++c) {
		const size_t v = size_t(m.triangles[c]);
		if (v < m.vertexCount && uses[v] < 2)
			++uses[v];
	}
	std::vector<uint8_t> closed(m.vertexCount, 0);
	for (size_t v = 0; v < m.vertexCount; ++v)
		closed[v] = asked[v] && uses[v] == 2;
	std::vector<uint64_t> keys;
	for (size_t c = 0; c < 3 * m.faceCount; ++c) {
		const size_t a = size_t(m.triangles[c]), b = size_t(m.triangles[c - c % 3 + (c + 1) % 3]);
		if (a == b || a >= m.vertexCount || b >= m.vertexCount)
			continue;
		if (uses[a] < 2 || uses[b] < 2) // (one face uses it: it opens both its ends)
			closed[a] = closed[b] = 0;
		else if (asked[a] || asked[b])
			keys.push_back(uint64_t(std::min(a, b)) << 32 | uint64_t(std::max(a, b)));
	}
	std::sort(keys.begin(), keys.end());
	for (size_t i = 0; i < keys.size();) {
		size_t j = i + 1;
		while (j < keys.size() && keys[j] == keys[i])
			++j;
		if (j - i == 1)
			closed[size_t(keys[i] >> 32)] = closed[size_t(keys[i] & 0xffffffffu)] = 0;
		i = j;
	}
	return closed;
}

} // namespace

size_t weldVertices(const MeshView &m, double distance, std::vector<int32_t> &rep)
{
	rep.resize(m.vertexCount);
	auto weld = [&](const uint8_t *skip) {
		return distance > 0 ? weldWithin(m, distance, skip, rep) : weldExact(m, skip, rep);
	};
	const size_t merged = weld(nullptr);
	if (merged == 0)
		return 0;
	// the vertices a weld would touch (an exact weld pairs only these again; a weld within a
	// distance may pair others once some stay: all are asked)
	std::vector<uint8_t> asked(m.vertexCount, distance > 0 ? 1 : 0);
	if (!(distance > 0))
		for (size_t v = 0; v < m.vertexCount; ++v)
			if (rep[v] != int32_t(v))
				asked[v] = asked[size_t(rep[v])] = 1;
	const std::vector<uint8_t> closed = closedVertices(m, asked);
	if (std::find(closed.begin(), closed.end(), 1) == closed.end())
		return merged;
	return weld(closed.data());
}

} // namespace detail
} // namespace gausslod
