// 2.3 Further simplification of the borders: the rings are cut into chains between junction
// vertices; each chain is straightened (2.3.1, Douglas-Peucker with a tolerance) and its close
// vertices merged by importance (2.3.2). Kept vertices are global per vertex, so the two
// superfaces sharing a chain always agree (no crack, no T-junction).
#include "level_passes.h"

namespace gausslod {
namespace detail {

namespace {

// One round's chain simplification: the pass's inputs and the kept flags it writes.
struct Chains {
	const ChainInput &in;
	Borders &b;

	int32_t ringFrom(int32_t ring, int32_t i) const ///< vertex at position i of a ring
	{
		const int32_t r0 = in.rings.start[size_t(ring)], m = in.rings.start[size_t(ring) + 1] - r0;
		return in.t.heFrom(in.rings.he[size_t(r0 + i % m)]);
	}

	// A piece is processed from one side only: the superface of lower index among those whose
	// rings were traced (the other side of a mesh-boundary or non-manifold edge has none).
	bool owns(int32_t sf, int32_t h) const
	{
		const int32_t tw = in.t.twin[size_t(h)];
		if (tw < 0)
			return true;
		const int32_t other = in.p.label[size_t(heFace(tw))];
		return sf < other || !in.dirty[size_t(other)] || in.rings.broken[size_t(other)];
	}

	void loadSequence(const Piece &pc, Scratch &w) const
	{
		w.seq.resize(size_t(pc.len) + 1);
		for (int32_t i = 0; i <= pc.len; ++i)
			w.seq[size_t(i)] = ringFrom(pc.ring, pc.start + i);
	}

	// Farthest interior vertex of (lo, hi) from the segment seq[lo]-seq[hi]; -1 if none.
	int32_t farthest(int32_t lo, int32_t hi, double &dist, const Scratch &w) const
	{
		int32_t best = -1;
		dist = -1;
		const Vec3 a = in.t.pos(w.seq[size_t(lo)]), c = in.t.pos(w.seq[size_t(hi)]);
		for (int32_t i = lo + 1; i < hi; ++i) {
			const double d = pointSegmentDistance(in.t.pos(w.seq[size_t(i)]), a, c);
			if (d > dist) {
				dist = d;
				best = i;
			}
		}
		return best;
	}

	// Keeps at least pc.minInterior interior vertices (sequence loaded): adds the vertex farthest
	// from the current kept polyline, one at a time.
	void ensureInterior(Piece &pc, const Scratch &w)
	{
		const int32_t n = pc.len;
		while (pc.kept < pc.minInterior && pc.kept < n - 1) {
			int32_t best = -1, lo = 0;
			double bestD = -1;
			for (int32_t i = 1; i <= n; ++i) {
				if (i < n && b.keep[size_t(w.seq[size_t(i)])] == 0)
					continue;
				double d;
				const int32_t f = farthest(lo, i, d, w);
				if (f >= 0 && d > bestD)
					bestD = d, best = f;
				lo = i;
			}
			if (best < 0)
				break;
			b.keep[size_t(w.seq[size_t(best)])] = 1;
			++pc.kept;
		}
	}

	// The tolerances of a chain: divided by 4 for each fallback step of either superface along
	// it (a chain lies between the same two superfaces all along: a change of neighbour is a
	// junction).
	double pieceScale(const Piece &pc) const
	{
		const int32_t h = in.rings.he[size_t(in.rings.start[size_t(pc.ring)] + pc.start)];
		int step = in.tolStep[size_t(heFace(h))];
		const int32_t tw = in.t.twin[size_t(h)];
		if (tw >= 0)
			step = std::max<int>(step, in.tolStep[size_t(heFace(tw))]);
		return std::ldexp(1.0, -kTolShift * step);
	}

	void keepIndex(Piece &pc, const Scratch &w, int32_t i)
	{
		if (!b.keep[size_t(w.seq[size_t(i)])]) {
			b.keep[size_t(w.seq[size_t(i)])] = 1;
			++pc.kept;
		}
	}

	// 2.3.1 Douglas-Peucker: split at the farthest vertex while it is farther than `tol`.
	void straighten(Piece &pc, Scratch &w, double tol)
	{
		const int32_t n = pc.len; // w.seq[0] and w.seq[n] are the ends
		w.stack.clear();
		if (pc.loop) { // anchor + the vertex farthest from it split the loop in two chains
			b.keep[size_t(w.seq[0])] = 1;
			double d;
			const int32_t far = farthest(0, n, d, w);
			keepIndex(pc, w, far);
			w.stack.push_back(0), w.stack.push_back(far);
			w.stack.push_back(far), w.stack.push_back(n);
		} else {
			w.stack.push_back(0), w.stack.push_back(n);
		}
		while (!w.stack.empty()) {
			const int32_t hi = w.stack.back();
			w.stack.pop_back();
			const int32_t lo = w.stack.back();
			w.stack.pop_back();
			if (hi - lo < 2)
				continue;
			double d;
			const int32_t i = farthest(lo, hi, d, w);
			if (d > tol) {
				keepIndex(pc, w, i);
				w.stack.push_back(lo), w.stack.push_back(i);
				w.stack.push_back(i), w.stack.push_back(hi);
			}
		}
	}

	// 2.3.2 Vicinity merging: a kept interior vertex closer than `distance` to a kept neighbour
	// on its chain merges into it if it is not more important; corners only receive.
	void mergeVicinity(Piece &pc, const Scratch &w, double distance)
	{
		const int32_t n = pc.len;
		auto P = [&](int32_t i) { return in.t.pos(w.seq[size_t(i)]); };
		int32_t prev = 0;
		for (int32_t i = 1; i < n; ++i) {
			const int32_t v = w.seq[size_t(i)];
			if (!b.keep[size_t(v)])
				continue;
			int32_t next = i + 1;
			while (next < n && !b.keep[size_t(w.seq[size_t(next)])])
				++next;
			if (pc.kept <= pc.minInterior)
				break;
			const uint8_t cls = in.t.vertexClass[size_t(v)];
			const double dp = (P(i) - P(prev)).Norm(), dn = (P(i) - P(next)).Norm();
			const int32_t into = dp <= dn ? prev : next;
			const bool close = std::min(dp, dn) < distance;
			if (close && cls != kCorner && cls <= in.t.vertexClass[size_t(w.seq[size_t(into)])]) {
				b.keep[size_t(v)] = 0;
				--pc.kept;
				continue; // prev stays
			}
			prev = i;
		}
	}

	void simplify(Piece &pc, Scratch &w)
	{
		loadSequence(pc, w);
		if (pc.len < 2)
			return;
		// (divided by 4 per fallback of either superface along the chain, see applyFallbacks)
		const double scale = pieceScale(pc);
		straighten(pc, w, std::max(in.limits.tolerance * scale, in.limits.exact));
		ensureInterior(pc, w);
		const double mergeDistance = in.limits.mergeDistance * scale;
		if (mergeDistance > 0)
			mergeVicinity(pc, w, mergeDistance);
	}

	// Patch round: a recomputed piece starts from its end vertices only.
	void resetInterior(const Piece &pc)
	{
		for (int32_t i = pc.loop ? 0 : 1; i < pc.len; ++i)
			b.keep[size_t(ringFrom(pc.ring, pc.start + i))] = 0;
	}

	void process(Piece pc, Scratch &w, ChunkOut &o)
	{
		if (in.patch)
			resetInterior(pc);
		simplify(pc, w);
		if (!pc.loop && pc.a != pc.b && pc.kept == 0 && pc.len >= 2)
			o.straight.push_back(pc);
	}

	// Cuts ring r of superface sf into pieces at its junctions. In a patch round only the pieces
	// with a changed vertex are processed (the others are the same chains as in the previous
	// round and keep their kept vertices).
	void collectRing(int32_t sf, int32_t r, Scratch &w, ChunkOut &o)
	{
		const int32_t r0 = in.rings.start[size_t(r)], m = in.rings.start[size_t(r) + 1] - r0;
		const int32_t *H = &in.rings.he[size_t(r0)];
		int32_t first = -1;
		for (int32_t i = 0; i < m && first < 0; ++i)
			if (b.junction[size_t(in.t.heFrom(H[i]))])
				first = i;
		auto wanted = [&](int32_t start, int32_t len) {
			if (!owns(sf, H[start % m]))
				return false;
			bool touched = !in.patch;
			for (int32_t i = 0; i <= len && !touched; ++i)
				touched = b.changed[size_t(in.t.heFrom(H[(start + i) % m]))] != 0;
			return touched;
		};
		if (first < 0) { // closed loop without junction: anchor at its smallest vertex id
			int32_t anchor = 0;
			for (int32_t i = 1; i < m; ++i)
				if (in.t.heFrom(H[i]) < in.t.heFrom(H[anchor]))
					anchor = i;
			if (wanted(anchor, m)) {
				const int32_t v = in.t.heFrom(H[anchor]);
				process(Piece{r, anchor, m, v, v, true, 2}, w, o);
			}
			return;
		}
		for (int32_t i = first; i < first + m;) {
			int32_t j = i + 1;
			while (!b.junction[size_t(in.t.heFrom(H[j % m]))])
				++j;
			if (wanted(i, j - i)) {
				const int32_t a = in.t.heFrom(H[i % m]), e = in.t.heFrom(H[j % m]);
				// a closed chain (a == e) would straighten onto a point
				process(Piece{r, i % m, j - i, a, e, false, int8_t(a == e ? 2 : 0)}, w, o);
			}
			i = j;
		}
	}

	// Is there a border edge between vertices a and b (a piece of one edge, when both are
	// junctions)?
	bool borderEdge(int32_t a, int32_t c) const
	{
		const Topology &t = in.t;
		for (int32_t q = t.vfStart[size_t(a)]; q < t.vfStart[size_t(a) + 1]; ++q)
			for (int k = 0; k < 3; ++k) {
				const int32_t h = 3 * t.vfFace[size_t(q)] + k;
				if (b.border[size_t(h)] &&
				    ((t.heFrom(h) == a && t.heTo(h) == c) || (t.heFrom(h) == c && t.heTo(h) == a)))
					return true;
			}
		return false;
	}

	// Two chains with the same end vertices must not both straighten onto the same segment: all
	// but one of them get back their farthest interior vertex; none stays straight when the two
	// ends are joined by a border edge (a one-edge chain, which cannot keep a vertex).
	void separateParallelChains(std::vector<Piece> &pieces, Scratch &w)
	{
		// the pieces grouped by (smaller, larger) end vertex, in that order, each group in
		// pieces order: a bucket sort over the vertices for many pieces, a sort for the few of
		// a patch round (where a pass over every vertex would cost more than the pieces)
		auto lo = [&](size_t i) { return std::min(pieces[i].a, pieces[i].b); };
		auto hi = [&](int32_t i) { return std::max(pieces[size_t(i)].a, pieces[size_t(i)].b); };
		auto key = [&](int32_t i) {
			return uint64_t(uint32_t(lo(size_t(i)))) << 32 | uint32_t(hi(i));
		};
		std::vector<int32_t> order;
		if (pieces.size() >= in.t.nV / 16) {
			std::vector<int32_t> start;
			bucketSort(
			    pieces.size(), in.t.nV, lo, [&](int32_t i, int32_t j) { return hi(i) < hi(j); },
			    start, order);
		} else {
			order.resize(pieces.size());
			for (size_t i = 0; i < order.size(); ++i)
				order[i] = int32_t(i);
			std::stable_sort(order.begin(), order.end(),
			                 [&](int32_t i, int32_t j) { return key(i) < key(j); });
		}
		for (size_t i = 0; i < order.size();) {
			size_t j = i + 1;
			const uint64_t k = key(order[i]);
			while (j < order.size() && key(order[j]) == k)
				++j;
			const bool edge = borderEdge(int32_t(k >> 32), int32_t(uint32_t(k)));
			if (j - i >= 2 || edge)
				for (size_t q = edge ? i : i + 1; q < j; ++q) {
					Piece &pc = pieces[size_t(order[q])];
					loadSequence(pc, w);
					pc.minInterior = 1;
					ensureInterior(pc, w);
				}
			i = j;
		}
	}
};

} // namespace

void straightenBorders(const ChainInput &in, Chunks &chunks, Borders &b)
{
	Chains chains{in, b};
	chunks.forEach([&](size_t c, Scratch &w) {
		for (int32_t sf = chunks.start[c]; sf < chunks.start[c + 1]; ++sf)
			for (int32_t r = in.rings.sfStart[size_t(sf)]; r < in.rings.sfStart[size_t(sf) + 1];
			     ++r)
				chains.collectRing(sf, r, w, chunks.out[c]);
	});
	// (a patch round separates the recomputed pieces among themselves; one that straightens
	// onto an unchanged chain is caught by the whole-level check and falls back)
	std::vector<Piece> pieces;
	for (ChunkOut &o : chunks.out) {
		pieces.insert(pieces.end(), o.straight.begin(), o.straight.end());
		o.straight.clear();
	}
	chains.separateParallelChains(pieces, chunks.scratch[0]);
}

} // namespace detail
} // namespace gausslod
