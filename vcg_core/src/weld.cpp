// Input repair before 2.1: welding coincident vertices (what MeshLab does to STL files on import),
// so that a triangle soup has the edges that superfaces grow across. One pass over the vertices
// with an open-addressing hash table; no allocation per vertex.
#include "engine.h"

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

bool finite3(const double *p) { return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]); }

// Exact: each position's first vertex is the key's slot.
size_t weldExact(const MeshView &m, std::vector<int32_t> &rep)
{
	const size_t mask = tableSize(m.vertexCount) - 1;
	std::vector<int32_t> slot(mask + 1, -1);
	size_t merged = 0;
	for (size_t v = 0; v < m.vertexCount; ++v) {
		const double *p = m.positions + 3 * v;
		rep[v] = int32_t(v);
		if (!finite3(p))
			continue;
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
	}
	return merged;
}

// Within a distance d: kept vertices are listed per grid cell of size d (a slot per occupied
// cell, a chain through `next`); a vertex becomes the lowest kept vertex within d in the 27 cells
// around it, or is kept.
size_t weldWithin(const MeshView &m, double d, std::vector<int32_t> &rep)
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
	for (size_t v = 0; v < m.vertexCount; ++v) {
		const double *p = m.positions + 3 * v;
		rep[v] = int32_t(v);
		if (!finite3(p))
			continue;
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
			continue;
		}
		Slot *s = find(c, true);
		if (s->head < 0)
			std::memcpy(s->c, c, sizeof c);
		next[v] = s->head;
		s->head = int32_t(v);
	}
	return merged;
}

} // namespace

size_t weldVertices(const MeshView &m, double distance, std::vector<int32_t> &rep)
{
	rep.resize(m.vertexCount);
	return distance > 0 ? weldWithin(m, distance, rep) : weldExact(m, rep);
}

} // namespace detail
} // namespace gausslod
