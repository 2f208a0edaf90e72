// Fallback rounds (beyond the paper, which assumes every superface re-triangulates validly): a
// failed superface is retried with tighter tolerances, then with its border locked, then split
// into its superfaces of the next finer level (down to the input faces, always valid). A superface
// that fails the distance tolerance or the texture check (Failure::Distance) and has no finer
// superfaces is cut in two halves instead (kBisect), down to a few faces, so that it is refined
// where it is too far and stays coarse elsewhere. The next round rebuilds only what changed and
// reuses the other superfaces' triangles.
#include "level_passes.h"

namespace gausslod {
namespace detail {

namespace {

constexpr uint8_t kSplit = 1, kBisect = 2; // (split flags)
constexpr int32_t kMinBisect = 4;          // fewer faces: split into the input faces

} // namespace

// After a deviation failure first its chains are straightened and merged again with a quarter of
// the tolerances, up to kMaxTolSteps times; else its border is locked (no straightening, no
// merging); if it still fails, or its projection folds, it is split; a single input face that
// fails gets its vertices locked (it is then kept as it is).
FallbackKind fallbackFor(const Topology &t, const SuperfaceFaces &faces, int32_t s, Failure why,
                         const Borders &b, const FallbackState &fb)
{
	const int32_t fbeg = faces.begin(s), fend = faces.end(s);
	bool allLocked = true;
	for (int32_t i = fbeg; i < fend && allLocked; ++i)
		for (int k = 0; k < 3; ++k) {
			const int32_t h = 3 * faces.face[size_t(i)] + k;
			if (b.border[size_t(h)] && !b.junction[size_t(t.heFrom(h))])
				allLocked = false;
		}
	const int step = fb.tolStep[size_t(faces.face[size_t(fbeg)])];
	if (fend - fbeg > 1 && why == Failure::Deviation && !allLocked && step < kMaxTolSteps)
		return FallbackKind::Retighten;
	if (fend - fbeg == 1 || (why != Failure::Fold && why != Failure::Distance && !allLocked))
		return FallbackKind::Lock;
	return FallbackKind::Split;
}

namespace {

// Applies each failed superface's fallback (fallbackFor) to the fallback state; returns the split
// flags per superface.
void chooseFallbacks(const Topology &t, const SuperfaceFaces &faces, const FailedList &failed,
                     const Borders &b, FallbackState &fb, std::vector<uint8_t> &split)
{
	auto lock = [&](int32_t v) {
		if (!fb.extraLock[size_t(v)]) {
			fb.extraLock[size_t(v)] = 1;
			fb.lockedNow.push_back(v);
		}
	};
	for (const auto &sf : failed) {
		const int32_t s = sf.first;
		const int32_t fbeg = faces.begin(s), fend = faces.end(s);
		const FallbackKind kind = fallbackFor(t, faces, s, sf.second, b, fb);
		fb.failedFace.push_back(faces.face[size_t(fbeg)]);
		if (kind == FallbackKind::Retighten) {
			const int step = fb.tolStep[size_t(faces.face[size_t(fbeg)])];
			for (int32_t i = fbeg; i < fend; ++i) {
				const int32_t f = faces.face[size_t(i)];
				fb.tolStep[size_t(f)] = uint8_t(step + 1);
				for (int k = 0; k < 3; ++k)
					if (b.border[size_t(3 * f + k)])
						fb.retightened.push_back(t.heFrom(3 * f + k));
			}
		} else if (kind == FallbackKind::Lock) {
			for (int32_t i = fbeg; i < fend; ++i)
				for (int k = 0; k < 3; ++k) {
					const int32_t h = 3 * faces.face[size_t(i)] + k;
					if (b.border[size_t(h)])
						lock(t.heFrom(h));
				}
			if (fend - fbeg == 1)
				for (int k = 0; k < 3; ++k)
					lock(t.T[3 * faces.face[size_t(fbeg)] + k]);
		} else {
			split[size_t(s)] =
			    sf.second == Failure::Distance && fend - fbeg >= kMinBisect ? kBisect : kSplit;
		}
	}
}

// Superface s (faces in `faces`, range [fb, fe)) cut at the median of its face centroids along
// their longest extent; each connected part of each half becomes a new superface with s's cell
// and origin (made by add(cell, origin, parent)). `side` and `part` are per input face, all -1 /
// 0 outside a call.
template <class Add>
void bisect(const Topology &t, const SuperfaceFaces &faces, int32_t s, Partition &p,
            std::vector<int32_t> &relabeled, std::vector<int32_t> &part,
            std::vector<int32_t> &stack, Add add)
{
	const int32_t fb = faces.begin(s), fe = faces.end(s);
	auto centroid = [&](int32_t f) {
		return (t.pos(t.T[3 * f]) + t.pos(t.T[3 * f + 1]) + t.pos(t.T[3 * f + 2])) / 3.0;
	};
	Vec3 lo = centroid(faces.face[size_t(fb)]), hi = lo;
	for (int32_t i = fb; i < fe; ++i) {
		const Vec3 c = centroid(faces.face[size_t(i)]);
		for (int a = 0; a < 3; ++a)
			lo[a] = std::min(lo[a], c[a]), hi[a] = std::max(hi[a], c[a]);
	}
	const Vec3 ext = hi - lo;
	const int axis = ext[0] >= ext[1] && ext[0] >= ext[2] ? 0 : ext[1] >= ext[2] ? 1 : 2;
	std::vector<std::pair<double, int32_t>> order; // (coordinate, face): ties by face id
	order.reserve(size_t(fe - fb));
	for (int32_t i = fb; i < fe; ++i)
		order.emplace_back(centroid(faces.face[size_t(i)])[axis], faces.face[size_t(i)]);
	const size_t half = order.size() / 2;
	std::nth_element(order.begin(), order.begin() + std::ptrdiff_t(half), order.end());
	for (size_t i = 0; i < order.size(); ++i)
		part[size_t(order[i].second)] = i < half ? -2 : -3; // (the half, until given a part)
	for (int32_t i = fb; i < fe; ++i) {
		const int32_t seed = faces.face[size_t(i)];
		if (part[size_t(seed)] >= 0)
			continue;
		const int32_t side = part[size_t(seed)];
		const int32_t id = add(p.cell[size_t(s)], p.origin[size_t(s)], size_t(s));
		part[size_t(seed)] = id;
		stack.assign(1, seed);
		while (!stack.empty()) {
			const int32_t f = stack.back();
			stack.pop_back();
			p.label[size_t(f)] = id;
			relabeled.push_back(f);
			for (int k = 0; k < 3; ++k) {
				const int32_t tw = t.joinTwin(size_t(3 * f + k));
				if (tw < 0)
					continue;
				const int32_t g = heFace(tw);
				if (part[size_t(g)] == side && p.label[size_t(g)] == int32_t(s)) {
					part[size_t(g)] = id;
					stack.push_back(g);
				}
			}
		}
	}
	for (int32_t i = fb; i < fe; ++i)
		part[size_t(faces.face[size_t(i)])] = -1;
}

// The faces of the split superfaces take new superfaces (appended to p.cell and p.origin): their
// superfaces of the finer partition, or the input faces themselves, or (kBisect) the connected
// parts of two halves. parentOf[i] = the superface split into new superface base + i.
void splitIntoChildren(const Topology &t, const std::vector<Partition> &finer,
                       const SuperfaceFaces &faces, const std::vector<uint8_t> &split, Partition &p,
                       std::vector<int32_t> &relabeled, std::vector<int32_t> &parentOf)
{
	const int finest = int(finer.size()) - 1;
	const size_t base = p.count();
	std::vector<int32_t> childMap; // finer label -> new label (per origin level)
	std::vector<int32_t> touched;
	auto add = [&](CellKey cell, int8_t origin, size_t parent) {
		p.cell.push_back(cell);
		p.origin.push_back(origin);
		parentOf.push_back(int32_t(parent));
		return int32_t(p.cell.size() - 1);
	};
	std::vector<int32_t> part, stack; // (bisect)
	for (size_t s = 0; s < base; ++s) {
		if (!split[s])
			continue;
		const int o = p.origin[s];
		if (split[s] == kBisect && (o == -1 || o >= finest)) {
			if (part.empty())
				part.assign(t.nF, -1);
			bisect(t, faces, int32_t(s), p, relabeled, part, stack, add);
			continue;
		}
		for (int32_t i = faces.start[s]; i < faces.start[s + 1]; ++i) {
			const int32_t f = faces.face[size_t(i)];
			int32_t id;
			if (o == -1 || o >= finest) { // children are the input faces
				id = add(cellOfNormal(t.faceNormal[size_t(f)], p.level), -1, s);
			} else {
				// children: the parts of a cross-cell union, or the next finer level's
				const bool parts = o <= -2;
				const Partition &fp = finer[size_t(parts ? mergedLevel(int8_t(o)) : o + 1)];
				const std::vector<int32_t> &label = parts ? fp.partLabel : fp.label;
				const std::vector<CellKey> &cells = parts ? fp.partCell : fp.cell;
				const std::vector<int8_t> &origins = parts ? fp.partOrigin : fp.origin;
				const int32_t child = label[size_t(f)];
				if (childMap.size() < cells.size())
					childMap.resize(cells.size(), -1);
				id = childMap[size_t(child)];
				if (id < 0) {
					CellKey k = cells[size_t(child)];
					for (int l = fp.level; l > p.level && k != kInvalidCell; --l)
						k = parentKey(k);
					id = childMap[size_t(child)] = add(k, origins[size_t(child)], s);
					touched.push_back(child);
				}
			}
			p.label[size_t(f)] = id;
			relabeled.push_back(f);
		}
		for (int32_t c : touched)
			childMap[size_t(c)] = -1;
		touched.clear();
	}
}

// Canonical ids after a split (by first face, see Partition::label: a superface not split keeps
// its first face, a new one's is the first of its faces in its parent's ascending range), each
// superface's id in the round that failed or the id of the superface split into it (prevOf), and
// the next round's faces per superface (what groupFaces gives): runs of superfaces not split keep
// their block of faces, the children of a split superface take theirs from its range. `base`:
// superfaces before the split.
void renumber(const Topology &t, size_t base, const std::vector<uint8_t> &split,
              const std::vector<int32_t> &parentOf, size_t threads, Partition &p,
              SuperfaceFaces &faces, std::vector<int32_t> &prevOf, FallbackArrays &spare)
{
	const size_t temps = p.count() - base;
	std::vector<int32_t> childSize(temps, 0);        // (then: where its next face goes)
	std::vector<std::pair<int32_t, int32_t>> firsts; // (first face, new superface)
	size_t nSplit = 0;
	for (size_t s = 0; s < base; ++s) {
		if (!split[s])
			continue;
		++nSplit;
		for (int32_t i = faces.start[s]; i < faces.start[s + 1]; ++i) {
			const int32_t f = faces.face[size_t(i)];
			const size_t c = size_t(p.label[size_t(f)]) - base;
			if (childSize[c]++ == 0)
				firsts.emplace_back(f, int32_t(base + c));
		}
	}
	std::sort(firsts.begin(), firsts.end());
	const size_t ns = base - nSplit + temps;
	std::vector<int32_t> &remap = spare.remap, &start = spare.start, &face = spare.face;
	remap.assign(p.count(), -1);
	spare.cell.clear(), spare.origin.clear(), prevOf.clear();
	spare.cell.reserve(ns), spare.origin.reserve(ns), prevOf.reserve(ns);
	start.resize(ns + 1), face.resize(t.nF);
	start[0] = 0;
	auto add = [&](int32_t old, int32_t prev, int32_t count) {
		const int32_t n = int32_t(spare.cell.size());
		remap[size_t(old)] = n;
		spare.cell.push_back(p.cell[size_t(old)]);
		spare.origin.push_back(p.origin[size_t(old)]);
		prevOf.push_back(prev);
		start[size_t(n) + 1] = start[size_t(n)] + count;
	};
	size_t ci = 0;
	auto addChildrenBefore = [&](int32_t firstFace) { // (new superfaces that come first)
		for (; ci < firsts.size() && firsts[ci].first < firstFace; ++ci) {
			const int32_t c = firsts[ci].second;
			add(c, parentOf[size_t(c) - base], childSize[size_t(c) - base]);
		}
	};
	for (size_t o = 0; o < base; ++o)
		if (!split[o]) {
			addChildrenBefore(faces.face[size_t(faces.start[o])]);
			add(int32_t(o), int32_t(o), faces.start[o + 1] - faces.start[o]);
		}
	addChildrenBefore(INT32_MAX);
	for (size_t o = 0; o < base;) { // runs of consecutive superfaces not split
		if (split[o]) {
			++o;
			continue;
		}
		size_t e = o + 1;
		while (e < base && !split[e] && remap[e] == remap[e - 1] + 1)
			++e;
		std::copy(faces.face.begin() + faces.start[o], faces.face.begin() + faces.start[e],
		          face.begin() + start[size_t(remap[o])]);
		o = e;
	}
	for (size_t c = 0; c < temps; ++c)
		childSize[c] = start[size_t(remap[base + c])];
	for (size_t s = 0; s < base; ++s)
		if (split[s])
			for (int32_t i = faces.start[s]; i < faces.start[s + 1]; ++i) {
				const int32_t f = faces.face[size_t(i)];
				face[size_t(childSize[size_t(p.label[size_t(f)]) - base]++)] = f;
			}
	parallelRanges(t.nF, threads, [&](size_t b, size_t e, size_t) {
		for (size_t f = b; f < e; ++f)
			p.label[f] = remap[size_t(p.label[f])];
	});
	p.cell.swap(spare.cell), p.origin.swap(spare.origin);
	faces.start.swap(start), faces.face.swap(face);
}

uint64_t directedEdge(int32_t a, int32_t b) { return uint64_t(uint32_t(a)) << 32 | uint32_t(b); }

} // namespace

void applyFallbacks(const Topology &t, const std::vector<Partition> &finer,
                    const FailedList &failed, const Borders &b, size_t threads, Partition &p,
                    SuperfaceFaces &faces, FallbackState &fb, ReuseCache &cache,
                    FallbackArrays &spare)
{
	// `faces` is that of the round that just failed: labels have not changed yet
	p.nodeArea.clear(), p.nodeRadius.clear(), p.nodeMean.clear(); // (splits change superfaces)
	spare.split.assign(p.count(), 0);
	fb.relabeled.clear(), fb.failedFace.clear(), fb.lockedNow.clear(), fb.retightened.clear();
	chooseFallbacks(t, faces, failed, b, fb, spare.split);
	const size_t base = p.count();
	std::vector<int32_t> parentOf; // new superface base + i -> the superface split into it
	splitIntoChildren(t, finer, faces, spare.split, p, fb.relabeled, parentOf);
	if (p.count() == base) {
		// nothing split: labels, cells, origins and face lists stay
		cache.prevOf.resize(base);
		for (size_t o = 0; o < base; ++o)
			cache.prevOf[o] = int32_t(o);
		return;
	}
	renumber(t, base, spare.split, parentOf, threads, p, faces, cache.prevOf, spare);
}

bool sameKeptOutline(const TriangulationInput &in, int32_t s, const std::vector<int32_t> &tris,
                     const std::vector<uint8_t> &bits, int32_t begin, int32_t end, Scratch &w)
{
	w.edgesBefore.clear();
	for (int32_t k = begin; k < end; ++k)
		for (int e = 0; e < 3; ++e)
			if (bits[size_t(k)] & (1u << e))
				w.edgesBefore.push_back(directedEdge(tris[3 * size_t(k) + size_t(e)],
				                                     tris[3 * size_t(k) + size_t(e + 1) % 3]));
	w.edgesNow.clear();
	for (int32_t r = in.rings.sfStart[size_t(s)]; r < in.rings.sfStart[size_t(s) + 1]; ++r) {
		int32_t first = -1, prev = -1;
		for (int32_t i = in.rings.start[size_t(r)]; i < in.rings.start[size_t(r) + 1]; ++i) {
			const int32_t v = in.t.heFrom(in.rings.he[size_t(i)]);
			if (!in.b.keep[size_t(v)])
				continue;
			if (prev >= 0)
				w.edgesNow.push_back(directedEdge(prev, v));
			else
				first = v;
			prev = v;
		}
		if (prev >= 0)
			w.edgesNow.push_back(directedEdge(prev, first));
		if (w.edgesNow.size() > w.edgesBefore.size())
			return false;
	}
	if (w.edgesNow.size() != w.edgesBefore.size())
		return false;
	std::sort(w.edgesNow.begin(), w.edgesNow.end());
	std::sort(w.edgesBefore.begin(), w.edgesBefore.end());
	return w.edgesNow == w.edgesBefore;
}

// The previous round's triangles of a superface are reused when its faces are the same (its first
// face's previous superface, and as many faces: partitions only get finer between rounds) and its
// border edges (the triangles' border-flagged edges, directed with the superface on their left)
// are this round's ring edges between kept vertices: every successful triangulation has exactly
// its rings' edges as border edges, so this compares the kept outlines without storing them (as a
// multiset: a different ring start or order would describe the same domain).
bool reuseTriangles(const TriangulationInput &in, int32_t s, const Cached &now,
                    const ReuseCache &cache, Scratch &w, ChunkOut &o)
{
	if (cache.prev.empty())
		return false;
	const Cached &c = cache.prev[size_t(cache.prevOf[size_t(s)])];
	if (!c.ok || c.faceCount != now.faceCount) // (same count, same faces: see above)
		return false;
	if (!sameKeptOutline(in, s, cache.tris, cache.triBorder, c.triBegin, c.triEnd, w))
		return false;
	o.tris.insert(o.tris.end(), cache.tris.begin() + 3 * c.triBegin,
	              cache.tris.begin() + 3 * c.triEnd);
	o.triBorder.insert(o.triBorder.end(), cache.triBorder.begin() + c.triBegin,
	                   cache.triBorder.begin() + c.triEnd);
	o.retriangulated += c.retriangulated; // (its faces keep their deviations)
	return true;
}

} // namespace detail
} // namespace gausslod
