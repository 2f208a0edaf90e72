// 2.2.2 Tracing the borders of superfaces: which half-edges separate two superfaces, which border
// vertices are junctions (where chains of 2.3 end), and the closed rings of every superface.
#include "level_passes.h"

namespace gausslod {
namespace detail {

namespace {

bool isBorder(const Topology &t, const Partition &p, size_t f, int32_t h)
{
	const int32_t tw = t.joinTwin(size_t(h));
	return !t.faceDropped[f] && (tw < 0 || p.label[f] != p.label[size_t(heFace(tw))]);
}

// The rings of superface s: from a border half-edge, the next one starts at its end vertex and is
// found by turning around that vertex inside the superface (works at pinched vertices too).
bool traceSuperface(const Topology &t, const Partition &p, const SuperfaceFaces &faces, int32_t s,
                    std::vector<uint8_t> &border, std::vector<int32_t> &ringHE,
                    std::vector<int32_t> &ringStart)
{
	for (int32_t i = faces.begin(s); i < faces.end(s); ++i) {
		const int32_t f = faces.face[size_t(i)];
		for (int k = 0; k < 3; ++k) {
			const int32_t h0 = 3 * f + k;
			// a delimiter inside the superface (a seam that ends inside it) cannot be
			// re-triangulated around: the superface is split like one that folds
			const int32_t tw = t.twin[size_t(h0)];
			if (!t.delimiter.empty() && t.delimiter[size_t(h0)] && tw >= 0 &&
			    p.label[size_t(heFace(tw))] == s)
				return false;
			if (border[size_t(h0)] != 1) // (not a border, or visited)
				continue;
			ringStart.push_back(int32_t(ringHE.size()));
			int32_t h = h0;
			do {
				border[size_t(h)] |= Borders::kVisited;
				ringHE.push_back(h);
				const int32_t b = t.heTo(h);
				const int32_t guard = t.vfStart[size_t(b) + 1] - t.vfStart[size_t(b)] + 1;
				int32_t e = heNext(h), steps = 0;
				while (!border[size_t(e)] && steps++ <= guard)
					e = heNext(t.twin[size_t(e)]);
				if (!border[size_t(e)] || bool(border[size_t(e)] & Borders::kVisited) != (e == h0))
					return false; // not a proper ring (cannot happen on sane adjacency)
				h = e;
			} while (h != h0);
		}
	}
	return true;
}

} // namespace

void groupFaces(const Partition &p, SuperfaceFaces &out)
{
	fillBuckets<int32_t>(
	    p.count(),
	    [&](auto emit) {
		    for (size_t f = 0; f < p.label.size(); ++f)
			    emit(size_t(p.label[f]), int32_t(f));
	    },
	    out.start, out.face);
}

void findBorders(const Topology &t, const Partition &p, const FallbackState &fb, size_t threads,
                 Borders &b)
{
	// (on every thread: the flags per face range, then per vertex range its border edges,
	// each counted at its one half-edge that is unpaired or the lower of the two, found among
	// the vertex's faces, where it is the only corner)
	b.border.resize(3 * t.nF);
	parallelRanges(t.nF, threads, [&](size_t f0, size_t f1, size_t) {
		for (size_t f = f0; f < f1; ++f)
			for (size_t h = 3 * f; h < 3 * f + 3; ++h)
				b.border[h] = isBorder(t, p, f, int32_t(h));
	});
	b.degree.resize(t.nV), b.junction.resize(t.nV), b.keep.resize(t.nV);
	parallelRanges(t.nV, threads, [&](size_t v0, size_t v1, size_t) {
		for (size_t v = v0; v < v1; ++v) {
			int32_t d = 0;
			for (int32_t q = t.vfStart[v]; q < t.vfStart[v + 1]; ++q) {
				const int32_t f = t.vfFace[size_t(q)];
				const int32_t k = t.T[3 * f] == int32_t(v)       ? 0
				                  : t.T[3 * f + 1] == int32_t(v) ? 1
				                                                 : 2;
				for (const int32_t h : {3 * f + k, 3 * f + (k + 2) % 3}) // out of v, into v
					if (b.border[size_t(h)] && (t.twin[size_t(h)] < 0 || h < t.twin[size_t(h)]))
						++d;
			}
			b.degree[v] = d;
			b.junction[v] = b.keep[v] = isJunction(t, b, fb, v);
		}
	});
	b.changed.assign(t.nV, 0);
	b.changedList.clear();
}

// Only the half-edges of the faces the fallbacks relabelled can have changed border status
// (borders are only added), and only their vertices and the newly locked ones can have changed
// degree or junction status.
void updateBorders(const Topology &t, const Partition &p, const FallbackState &fb, Borders &b)
{
	for (int32_t v : b.changedList)
		b.changed[size_t(v)] = 0;
	b.changedList.clear();
	auto touch = [&](int32_t v) {
		if (!b.changed[size_t(v)]) {
			b.changed[size_t(v)] = 1;
			b.changedList.push_back(v);
		}
	};
	for (int32_t f : fb.relabeled)
		for (int k = 0; k < 3; ++k) {
			const int32_t h = 3 * f + k, tw = t.twin[size_t(h)];
			const bool border = isBorder(t, p, size_t(f), h);
			if (border == bool(b.border[size_t(h)]))
				continue; // (the twin, seen first, already updated both)
			b.border[size_t(h)] = border;
			if (tw >= 0)
				b.border[size_t(tw)] = border;
			const int d = border ? 1 : -1;
			b.degree[size_t(t.heFrom(h))] += d;
			b.degree[size_t(t.heTo(h))] += d;
			touch(t.heFrom(h));
			touch(t.heTo(h));
		}
	for (int32_t v : fb.lockedNow)
		if (bool(b.junction[size_t(v)]) != isJunction(t, b, fb, size_t(v)))
			touch(v);
	for (int32_t v : fb.retightened)
		touch(v); // (its chains are simplified again, with the smaller tolerances)
	for (int32_t v : b.changedList) {
		b.junction[size_t(v)] = isJunction(t, b, fb, size_t(v));
		b.keep[size_t(v)] = b.junction[size_t(v)]; // non-junctions: their piece is recomputed
	}
}

// Per chunk (a superface's walk only marks its own half-edges visited, and reads only its own),
// then concatenated in superface order.
void traceRings(const Topology &t, const Partition &p, const SuperfaceFaces &faces,
                const std::vector<uint8_t> &dirty, Chunks &chunks, Borders &b, Rings &rings)
{
	rings.broken.assign(dirty.size(), 0);
	chunks.forEach([&](size_t c, Scratch &) {
		ChunkOut &o = chunks.out[c];
		for (int32_t s = chunks.start[c]; s < chunks.start[c + 1]; ++s) {
			const size_t ringsBefore = o.ringStart.size(), heBefore = o.ringHE.size();
			if (dirty[size_t(s)] &&
			    !traceSuperface(t, p, faces, s, b.border, o.ringHE, o.ringStart)) {
				for (size_t i = heBefore; i < o.ringHE.size(); ++i)
					b.border[size_t(o.ringHE[i])] &= uint8_t(~Borders::kVisited);
				o.ringStart.resize(ringsBefore), o.ringHE.resize(heBefore);
				rings.broken[size_t(s)] = 1;
			}
			o.sfRings.push_back(int32_t(o.ringStart.size() - ringsBefore));
		}
	});
	size_t nRings = 0, nHE = 0;
	for (const ChunkOut &o : chunks.out)
		nRings += o.ringStart.size(), nHE += o.ringHE.size();
	rings.he.clear(), rings.start.clear();
	rings.he.reserve(nHE), rings.start.reserve(nRings + 1);
	rings.sfStart.assign(dirty.size() + 1, 0);
	for (size_t c = 0; c < chunks.out.size(); ++c) {
		ChunkOut &o = chunks.out[c];
		const int32_t heBase = int32_t(rings.he.size());
		for (int32_t s = chunks.start[c]; s < chunks.start[c + 1]; ++s)
			rings.sfStart[size_t(s) + 1] =
			    rings.sfStart[size_t(s)] + o.sfRings[size_t(s - chunks.start[c])];
		for (const int32_t r : o.ringStart)
			rings.start.push_back(heBase + r);
		rings.he.insert(rings.he.end(), o.ringHE.begin(), o.ringHE.end());
		release(o.ringHE), release(o.ringStart), release(o.sfRings);
	}
	rings.start.push_back(int32_t(rings.he.size()));
	for (const int32_t h : rings.he) // (every half-edge a walk marked)
		b.border[size_t(h)] &= uint8_t(~Borders::kVisited);
}

} // namespace detail
} // namespace gausslod
