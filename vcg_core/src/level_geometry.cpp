// One level's geometry from the input mesh and that level's partition, in rounds: each round
// traces the borders (2.2.2), simplifies them (2.3), re-triangulates every superface (2.4) and
// checks the whole level; a superface that fails is retried, locked or split (fallbacks.cpp) and
// the next round rebuilds only what changed, until the level is valid.
#include "level_rounds.h"

#include <algorithm>
#include <cmath>

namespace gausslod {
namespace detail {

LevelLimits levelLimits(const Params &prm, double diagonal, int level, bool hasUV)
{
	LevelLimits l;
	// below this, border vertices count as exactly on their straightened chain
	l.exact = 1e-9 * diagonal;
	l.tolerance = std::max(prm.straightenTol * diagonal, l.exact);
	l.mergeDistance = prm.mergeDist * diagonal;
	l.maxDistance =
	    prm.levelDistances.empty()
	        ? prm.maxDistance * diagonal * std::pow(prm.distanceGrowth, prm.maxLevel - 1 - level)
	        : prm.levelDistances[size_t(level)] * diagonal; // (levels by target)
	// levels by error (not the searches of levels by faces): the level's distance bound, not only
	// what the check measures, must stay within the target (DESIGN 23)
	l.boundIsLimit = !prm.levelDistances.empty() && prm.levelFaces.empty();
	if (l.maxDistance > 0) {
		l.tolerance = std::min(l.tolerance, std::max(l.maxDistance, l.exact));
		l.mergeDistance = std::min(l.mergeDistance, 0.5 * l.maxDistance);
	}
	l.maxTexError = hasUV ? prm.maxTexError : 0;
	l.finest = prm.maxLevel - 1;
	l.devLimitDeg = prm.normalLimit > 0 ? prm.normalLimit * levelBoundDeg(level) : 180.0;
	return l;
}

void Chunks::make(const SuperfaceFaces &faces, size_t superfaces, size_t nF)
{
	const size_t target = std::max<size_t>(2048, nF / (8 * threads) + 1);
	start.assign(1, 0);
	size_t count = 0;
	for (size_t s = 0; s < superfaces; ++s) {
		count += size_t(faces.start[s + 1] - faces.start[s]);
		if (count >= target && s + 1 < superfaces) {
			start.push_back(int32_t(s + 1));
			count = 0;
		}
	}
	start.push_back(int32_t(superfaces));
	out.clear();
	out.resize(start.size() - 1);
}

void LevelRounds::run()
{
	size_t fallbacks = 0;
	int round = 0;
	for (;; ++round) {
		if (round == kMaxRounds) // give up simplifying: every vertex kept is always valid
			std::fill(fb_.extraLock.begin(), fb_.extraLock.end(), uint8_t(1));
		if (!buildRound(round > 0 && round < kMaxRounds)) { // (out_.stats.faces > faceLimit_)
			out_.stats.rounds = round + 1;
			out_.stats.secondsBorders += clock_.lap();
			return;
		}
		firstRound_ = false;
		if (failed_.empty() || round >= kMaxRounds)
			break;
		// (DESIGN 40: a level over its face limit is abandoned only on Euler's bound, which
		// every later round's faces are above; the triangles a failed superface made are not a
		// bound on what its fallback makes)
		fallbacks += failed_.size();
		keepForReuse();
		applyFallbacks(t_, finer_, failed_, borders_, chunks_.threads, p_, faces_, fb_, prev_,
		               spare_);
		out_.stats.secondsChecks += clock_.lap();
	}
	out_.stats.rounds = round + 1;
	// (a level with more faces than the finer one is the finer one: placement moves no count)
	if (place_ && limits_.maxDistance > 0 && (liveTris_ <= faceLimit_ || !failed_.empty())) {
		out_.stats.secondsChecks += clock_.lap();
		placeVertices(PlacementInput{t_, p_, faces_, limits_, tri_, cache_, fb_.extraLock}, chunks_,
		              borders_, rings_, measures_, placement_);
		out_.stats.secondsPlacement = clock_.lap();
	}
	if (carryOut_)
		carryExact();
	finish(fallbacks);
	out_.stats.secondsChecks += clock_.lap();
}

void LevelRounds::markDirty(bool patch)
{
	dirty_.assign(p_.count(), patch ? 0 : 1);
	if (!patch)
		return;
	for (int32_t f : fb_.relabeled) // split
		dirty_[size_t(p_.label[size_t(f)])] = 1;
	for (int32_t f : fb_.failedFace)
		dirty_[size_t(p_.label[size_t(f)])] = 1;
	for (int32_t v : borders_.changedList) // around a changed vertex
		for (int32_t q = t_.vfStart[size_t(v)]; q < t_.vfStart[size_t(v) + 1]; ++q)
			dirty_[size_t(p_.label[size_t(t_.vfFace[size_t(q)])])] = 1;
}

// False, with out_.stats.faces set, if the level cannot have faceLimit_ faces or fewer (then it
// builds nothing).
bool LevelRounds::buildRound(bool patch)
{
	failed_.clear();
	// (freed, not cleared: they are rebuilt from the chunks, which hold this round's triangles
	// meanwhile)
	release(tri_.tris), release(tri_.triSf), release(tri_.triBorder);
	retriangulated_ = 0;
	if (!patch) { // (a patch round's faces are regrouped by applyFallbacks)
		groupFaces(p_, faces_);
		findBorders(t_, p_, fb_, chunks_.threads, borders_);
	} else {
		updateBorders(t_, p_, fb_, borders_);
	}
	// The chain ends (junctions) are kept by every later round (fallbacks add borders and locks,
	// never take any): by Euler's formula, at least this many faces whatever the rounds give
	if (faceLimit_ != SIZE_MAX) {
		const size_t atLeast = levelFaceBound(t_, borders_.junction);
		if (atLeast > faceLimit_) {
			out_.stats.faces = atLeast;
			return false;
		}
		for (int32_t v : lockCountedList_)
			lockCounted_[size_t(v)] = 0;
		lockCountedList_.clear();
		lockBound_ = atLeast;
	}
	markDirty(patch);
	chunks_.make(faces_, p_.count(), t_.nF);
	traceRings(t_, p_, faces_, dirty_, chunks_, borders_, rings_);
	straightenBorders(ChainInput{t_, p_, limits_, fb_.tolStep, rings_, dirty_, patch}, chunks_,
	                  borders_);
	out_.stats.secondsBorders += clock_.lap();
	cache_.assign(p_.count(), Cached());
	// the chunks build the rebuilt superfaces; an unchanged one (not dirty) is taken from the
	// previous round's arrays when the chunks are concatenated (cache_ then holds its previous
	// range)
	chunks_.forEach([&](size_t c, Scratch &w) {
		w.discard = &overLimit_;
		for (int32_t sf = chunks_.start[c];
		     sf < chunks_.start[c + 1] && !overLimit_.load(std::memory_order_relaxed); ++sf)
			buildSuperface(sf, w, chunks_.out[c]);
	});
	if (overLimit_) { // (whichever superfaces were built: every later round has more faces)
		out_.stats.faces = lockBound_;
		return false;
	}
	release(rings_.he), release(rings_.start), release(rings_.sfStart);
	size_t rebuilt = 0;
	bool failures = false;
	for (const ChunkOut &o : chunks_.out)
		rebuilt += o.triBorder.size(), failures = failures || !o.failed.empty();
	size_t live = rebuilt;
	for (size_t sf = 0; sf < p_.count(); ++sf)
		if (!dirty_[sf])
			live += size_t(cache_[sf].triEnd - cache_[sf].triBegin);
	liveTris_ = live;
	if (patch && failures && appendPatch(rebuilt, live)) {
		out_.stats.secondsTriangulation += clock_.lap();
		return true;
	}
	concatenate(live, failures);
	out_.stats.secondsTriangulation += clock_.lap();
	if (failed_.empty())
		checkLevelEdges(t_, p_.count(), tri_, failed_);
	return true;
}

// One superface of a round: copied from the previous round when nothing around it changed, else
// its border is compared with the previous round's, else it is re-triangulated.
void LevelRounds::buildSuperface(int32_t s, Scratch &w, ChunkOut &o)
{
	const size_t before = o.triBorder.size();
	const size_t retriBefore = o.retriangulated;
	Cached &c = cache_[size_t(s)];
	if (!dirty_[size_t(s)]) { // unchanged since the previous round: its range there (the
		// triangles are copied with the concatenation, its faces keep their deviations)
		c = prev_.prev[size_t(prev_.prevOf[size_t(s)])];
		return;
	}
	c.faceCount = faces_.end(s) - faces_.begin(s);
	Failure f = Failure::None;
	const TriangulationInput in = triangulationInput();
	if (rings_.broken[size_t(s)] ||
	    !(firstRound_ && carryIn_ ? takeExact(in, s, w, o)
	                              : reuseTriangles(in, s, c, prev_, w, o))) {
		for (int32_t i = faces_.begin(s); i < faces_.end(s); ++i) {
			measures_.dev[size_t(faces_.face[size_t(i)])] = -1.0f; // (measured again below)
			if (!measures_.gap.empty())
				measures_.gap[size_t(faces_.face[size_t(i)])] = 0.0f;
			if (!measures_.tex.empty())
				measures_.tex[size_t(faces_.face[size_t(i)])] = 0.0f;
		}
		f = rings_.broken[size_t(s)] ? Failure::Fold : retriangulate(in, s, w, o, measures_);
	}
	if (f != Failure::None) {
		o.truncate(before);
		o.failed.emplace_back(s, f);
		countLockedBorder(s, f);
	}
	c.ok = f == Failure::None;
	c.retriangulated = o.retriangulated > retriBefore;
	c.triBegin = int32_t(before);
	c.triEnd = int32_t(o.triBorder.size());
}

// Superface s failed (why) this round: if the fallbacks will lock its border, its border vertices
// that are not junctions yet will be junctions of every later round, and Euler's bound on those
// rounds' faces grows by 2 for each (1 on the mesh's boundary). Sets overLimit_ once the bound is
// over faceLimit_: the level will be abandoned (run) whatever the rest of the round gives, so no
// thread needs to build more of it. (Only the outcome is used, and it is the same for any order
// of the superfaces: the bound grows monotonically to the same total. In the last round, with
// every vertex locked, every border vertex is a junction already: nothing is counted.)
void LevelRounds::countLockedBorder(int32_t s, Failure why)
{
	if (faceLimit_ == SIZE_MAX || t_.euler == kNoEuler ||
	    fallbackFor(t_, faces_, s, why, borders_, fb_) != FallbackKind::Lock)
		return;
	std::lock_guard<std::mutex> guard(lockMutex_);
	if (lockCounted_.empty())
		lockCounted_.assign(t_.nV, 0);
	for (int32_t i = faces_.begin(s); i < faces_.end(s); ++i)
		for (int k = 0; k < 3; ++k) {
			const int32_t h = 3 * faces_.face[size_t(i)] + k;
			const int32_t v = t_.heFrom(h);
			if (!borders_.border[size_t(h)] || borders_.junction[size_t(v)] ||
			    lockCounted_[size_t(v)])
				continue;
			lockCounted_[size_t(v)] = 1;
			lockCountedList_.push_back(v);
			bool boundary = false; // (a clean surface: one boundary half-edge leaves it)
			for (int32_t q = t_.vfStart[size_t(v)]; q < t_.vfStart[size_t(v) + 1]; ++q) {
				const int32_t g = t_.vfFace[size_t(q)];
				for (int j = 0; j < 3; ++j)
					boundary = boundary || (t_.T[3 * size_t(g) + size_t(j)] == v &&
					                        t_.twin[3 * size_t(g) + size_t(j)] < 0);
			}
			lockBound_ += boundary ? 1 : 2;
		}
	if (lockBound_ > faceLimit_)
		overLimit_ = true;
}

// A patch round with failures is followed by another round: the rebuilt superfaces are appended
// to the previous round's triangles, which the others still point into (no copy of the whole
// level, no triangle -> superface array), while they fit in the room left by the last
// concatenation and the dropped triangles stay under half of the live ones. False if they do not.
bool LevelRounds::appendPatch(size_t rebuilt, size_t live)
{
	const size_t stored = prev_.triBorder.size() + rebuilt;
	if (!(2 * stored <= 3 * live && stored <= prev_.triBorder.capacity() &&
	      3 * stored <= prev_.tris.capacity()))
		return false;
	tri_.tris.swap(prev_.tris), tri_.triBorder.swap(prev_.triBorder), release(tri_.triSf);
	for (size_t c = 0; c < chunks_.out.size(); ++c) {
		ChunkOut &o = chunks_.out[c];
		for (int32_t sf = chunks_.start[c]; sf < chunks_.start[c + 1]; ++sf) {
			Cached &cc = cache_[size_t(sf)];
			if (!dirty_[size_t(sf)]) { // (its range is in these arrays already)
				retriangulated_ += cc.retriangulated;
				continue;
			}
			const int32_t begin = int32_t(tri_.triBorder.size());
			tri_.tris.insert(tri_.tris.end(), o.tris.begin() + 3 * cc.triBegin,
			                 o.tris.begin() + 3 * cc.triEnd);
			tri_.triBorder.insert(tri_.triBorder.end(), o.triBorder.begin() + cc.triBegin,
			                      o.triBorder.begin() + cc.triEnd);
			cc.triEnd = begin + (cc.triEnd - cc.triBegin), cc.triBegin = begin;
		}
		failed_.insert(failed_.end(), o.failed.begin(), o.failed.end());
		retriangulated_ += o.retriangulated, carried_ += o.carried;
		o = ChunkOut(); // (frees its memory)
	}
	release(prev_.prev), prev_.prevOf.clear(); // (the ids' memory serves the next rounds)
	return true;
}

// The round's triangles in superface order (what the whole-level check and the output use),
// with a quarter more room if rounds follow; offsets of rebuilt superfaces in cache_ were chunk-
// relative. Each chunk is freed once appended; the fallbacks' arrays go first (this is the
// level's peak, and it is usually its last round).
void LevelRounds::concatenate(size_t live, bool failures)
{
	spare_ = FallbackArrays();
	const size_t room = failures ? live + live / 4 : live;
	tri_.tris.reserve(3 * room), tri_.triSf.reserve(live), tri_.triBorder.reserve(room);
	for (size_t c = 0; c < chunks_.out.size(); ++c) {
		ChunkOut &o = chunks_.out[c];
		for (int32_t sf = chunks_.start[c]; sf < chunks_.start[c + 1]; ++sf) {
			Cached &cc = cache_[size_t(sf)];
			const bool rebuilt = dirty_[size_t(sf)];
			const std::vector<int32_t> &srcTris = rebuilt ? o.tris : prev_.tris;
			const std::vector<uint8_t> &srcBorder = rebuilt ? o.triBorder : prev_.triBorder;
			const int32_t begin = int32_t(tri_.triBorder.size());
			tri_.tris.insert(tri_.tris.end(), srcTris.begin() + 3 * cc.triBegin,
			                 srcTris.begin() + 3 * cc.triEnd);
			tri_.triBorder.insert(tri_.triBorder.end(), srcBorder.begin() + cc.triBegin,
			                      srcBorder.begin() + cc.triEnd);
			cc.triEnd = begin + (cc.triEnd - cc.triBegin), cc.triBegin = begin;
			tri_.triSf.insert(tri_.triSf.end(), size_t(cc.triEnd - cc.triBegin), sf);
			if (!rebuilt)
				retriangulated_ += cc.retriangulated;
		}
		failed_.insert(failed_.end(), o.failed.begin(), o.failed.end());
		retriangulated_ += o.retriangulated, carried_ += o.carried;
		o = ChunkOut(); // (frees its memory)
	}
	release(prev_.prev), prev_.prevOf.clear();
	release(prev_.tris), release(prev_.triBorder);
}

// What the next round may reuse (before the fallbacks change the labels).
void LevelRounds::keepForReuse()
{
	prev_.prev.swap(cache_);
	prev_.tris.swap(tri_.tris);
	prev_.triBorder.swap(tri_.triBorder);
}

// Frees what only the rounds needed, before the level's output is allocated (the level's peak
// memory is otherwise here).
void LevelRounds::releaseRounds()
{
	faces_ = SuperfaceFaces(), borders_ = Borders(), fb_ = FallbackState(), rings_ = Rings();
	release(dirty_), release(failed_), release(chunks_.scratch), release(chunks_.start);
	release(chunks_.out), release(cache_), prev_ = ReuseCache(), spare_ = FallbackArrays();
}

void buildLevelGeometry(const Topology &topo, const Params &params,
                        const std::vector<Partition> &finer, Partition &p, LevelMesh &out,
                        size_t faceLimit, const SplitCost *finerCost, const ExactCarry *carryIn,
                        ExactCarry *carryOut)
{
	if (carryOut)
		*carryOut = ExactCarry();
	LevelRounds(topo, params, finer, p, out, faceLimit, finerCost, carryIn, carryOut).run();
}

void triangleShare(const Partition &p, const LevelMesh &level, SplitCost &cost)
{
	std::vector<int32_t> faces(p.count(), 0);
	cost.share.assign(p.count(), 0.0f);
	for (const int32_t s : level.superface)
		cost.share[size_t(s)] += 1.0f;
	for (const int32_t s : p.label)
		++faces[size_t(s)];
	for (size_t s = 0; s < faces.size(); ++s)
		cost.share[s] = faces[s] > 0 ? cost.share[s] / float(faces[s]) : 0.0f;
	cost.label = &p.label;
}

} // namespace detail
} // namespace gausslod
