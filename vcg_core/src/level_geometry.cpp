// One level's geometry from the input mesh and that level's partition, in rounds: each round
// traces the borders (2.2.2), simplifies them (2.3), re-triangulates every superface (2.4) and
// checks the whole level; a superface that fails is retried, locked or split (fallbacks.cpp) and
// the next round rebuilds only what changed, until the level is valid.
#include "level_passes.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <stdexcept>

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

namespace {

// Per output corner (triangles still on input vertex numbers) an input corner at the same vertex
// in a face of the same superface, the lowest such face; per output face the source face of its
// first corner. Superfaces never cross a delimiter, so those corners carry the attributes of the
// output corner's side of every seam.
void findSources(const Topology &t, const Partition &p, const LevelTriangles &lt, LevelMesh &out)
{
	const size_t nT = lt.triSf.size();
	out.sourceCorner.resize(3 * nT);
	out.sourceFace.resize(nT);
	for (size_t f = 0; f < nT; ++f) {
		const int32_t sf = lt.triSf[f];
		for (size_t k = 0; k < 3; ++k) {
			const int32_t v = lt.tris[3 * f + k];
			int32_t corner = -1;
			for (int32_t q = t.vfStart[size_t(v)]; q < t.vfStart[size_t(v) + 1] && corner < 0;
			     ++q) {
				const int32_t g = t.vfFace[size_t(q)];
				if (p.label[size_t(g)] != sf)
					continue;
				for (int32_t c = 3 * g; c < 3 * g + 3; ++c)
					if (t.T[c] == v)
						corner = c;
			}
			if (corner < 0) // (cannot happen: output vertices are vertices of their superface)
				throw std::logic_error("an output corner has no input corner in its superface");
			out.sourceCorner[3 * f + k] = corner;
		}
		out.sourceFace[f] = heFace(out.sourceCorner[3 * f]);
	}
}

class Stopwatch {
public:
	/// Seconds since the last call (or construction).
	double lap()
	{
		const auto now = std::chrono::steady_clock::now();
		const double s = std::chrono::duration<double>(now - last_).count();
		last_ = now;
		return s;
	}

private:
	std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

// The rounds of one level. A full round rebuilds every superface. A patch round (after fallbacks)
// rebuilds only the superfaces whose faces changed, that failed, or that touch a vertex whose
// border degree or junction status changed; every other superface has the same rings and kept
// vertices as in the previous round (borders only get added by fallbacks), so its triangles are
// copied.
class LevelRounds {
public:
	LevelRounds(const Topology &t, const Params &prm, const std::vector<Partition> &finer,
	            Partition &p, LevelMesh &out, size_t faceLimit, const SplitCost *finerCost,
	            const ExactCarry *carryIn, ExactCarry *carryOut)
	    : t_(t), finer_(finer), p_(p), out_(out), faceLimit_(faceLimit), finerCost_(finerCost),
	      limits_(levelLimits(prm, t.diagonal, p.level, t.UV != nullptr)),
	      place_(prm.placeVertices), carryIn_(carryIn && !carryIn->empty() ? carryIn : nullptr),
	      carryOut_(carryOut)
	{
		fb_.extraLock.assign(t_.nV, 0);
		fb_.tolStep.assign(t_.nF, 0);
		measures_.dev.assign(t_.nF, -1.0f);
		if (limits_.maxDistance > 0)
			measures_.gap.assign(t_.nF, 0.0f);
		if (limits_.maxTexError > 0)
			measures_.tex.assign(t_.nF, 0.0f);
		chunks_.threads = threadCount(prm.threads);
		chunks_.scratch.resize(chunks_.threads);
	}

	void run();

private:
	const Topology &t_;
	const std::vector<Partition> &finer_;
	Partition &p_;
	LevelMesh &out_;
	const size_t faceLimit_;
	const SplitCost *finerCost_;
	const LevelLimits limits_;
	const bool place_;          ///< Params::placeVertices
	const ExactCarry *carryIn_; ///< the finer level's exact superfaces (first round only)
	ExactCarry *carryOut_;      ///< this level's, for the next coarser one
	bool firstRound_ = true;
	Stopwatch clock_;
	Placement placement_;

	SuperfaceFaces faces_;
	Borders borders_;
	FallbackState fb_;
	Rings rings_;
	Chunks chunks_;
	FaceMeasures measures_;
	std::vector<uint8_t> dirty_; ///< per superface: rebuilt this round
	std::vector<Cached> cache_;  ///< per superface: its triangles this round
	ReuseCache prev_;            ///< the previous round's
	FallbackArrays spare_;
	// output of a round
	LevelTriangles tri_;  ///< (after a patch round with failures: see concatenate)
	size_t liveTris_ = 0; ///< triangles of the round's superfaces
	size_t retriangulated_ = 0;
	size_t carried_ = 0; ///< superfaces that took the finer level's exact triangles
	FailedList failed_;
	// (DESIGN 40) Euler's bound on the faces of every later round, with the border vertices that
	// the fallbacks will lock after this round's failures so far counted as junctions: once over
	// faceLimit_, the level is abandoned without triangulating the rest of the round
	std::mutex lockMutex_;
	std::vector<uint8_t> lockCounted_; ///< per vertex: counted in lockBound_ (this round)
	std::vector<int32_t> lockCountedList_;
	size_t lockBound_ = 0;
	std::atomic<bool> overLimit_{false};

	TriangulationInput triangulationInput() const
	{
		return TriangulationInput{t_, p_, faces_, borders_, rings_, limits_, finerCost_};
	}
	bool buildRound(bool patch);
	void markDirty(bool patch);
	void buildSuperface(int32_t s, Scratch &w, ChunkOut &o);
	void countLockedBorder(int32_t s, Failure why);
	bool takeExact(int32_t s, Scratch &w, ChunkOut &o);
	void carryExact();
	bool appendPatch(size_t rebuilt, size_t live);
	void concatenate(size_t live, bool failures);
	void keepForReuse();
	void releaseRounds();
	void finish(size_t fallbacks);
	void fillStats(size_t fallbacks, size_t vertices);
};

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
	    !(firstRound_ && carryIn_ ? takeExact(s, w, o) : reuseTriangles(in, s, c, prev_, w, o))) {
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

// Beyond the paper (DESIGN 31): superface s takes the triangles and measures of the finer
// level's exact superface with the same faces, if its kept outline is the same (the directed kept
// ring edges against the triangles' border edges). False if there is none.
bool LevelRounds::takeExact(int32_t s, Scratch &w, ChunkOut &o)
{
	const ExactCarry &ec = *carryIn_;
	const int32_t fb = faces_.begin(s), fe = faces_.end(s);
	const int32_t fs = (*ec.label)[size_t(faces_.face[size_t(fb)])];
	const int32_t first = ec.first[size_t(fs)];
	if (first < 0 || ec.measureAt[size_t(fs) + 1] - ec.measureAt[size_t(fs)] != fe - fb)
		return false;
	for (int32_t i = fb; i < fe; ++i) // (as many faces, all of fs: the same faces)
		if ((*ec.label)[size_t(faces_.face[size_t(i)])] != fs)
			return false;
	const int32_t last = ec.last[size_t(fs)];
	w.edgesBefore.clear();
	for (int32_t k = first; k < last; ++k)
		for (int e = 0; e < 3; ++e)
			if (ec.bits[size_t(k)] & (1u << e))
				w.edgesBefore.push_back(uint64_t(uint32_t(ec.tris[3 * size_t(k) + size_t(e)]))
				                            << 32 |
				                        uint32_t(ec.tris[3 * size_t(k) + size_t(e + 1) % 3]));
	w.edgesNow.clear();
	for (int32_t r = rings_.sfStart[size_t(s)]; r < rings_.sfStart[size_t(s) + 1]; ++r) {
		int32_t firstV = -1, prevV = -1;
		for (int32_t i = rings_.start[size_t(r)]; i < rings_.start[size_t(r) + 1]; ++i) {
			const int32_t v = t_.heFrom(rings_.he[size_t(i)]);
			if (!borders_.keep[size_t(v)])
				continue;
			if (prevV >= 0)
				w.edgesNow.push_back(uint64_t(uint32_t(prevV)) << 32 | uint32_t(v));
			else
				firstV = v;
			prevV = v;
		}
		if (prevV >= 0)
			w.edgesNow.push_back(uint64_t(uint32_t(prevV)) << 32 | uint32_t(firstV));
		if (w.edgesNow.size() > w.edgesBefore.size())
			return false;
	}
	if (w.edgesNow.size() != w.edgesBefore.size())
		return false;
	std::sort(w.edgesNow.begin(), w.edgesNow.end());
	std::sort(w.edgesBefore.begin(), w.edgesBefore.end());
	if (w.edgesNow != w.edgesBefore)
		return false;
	o.tris.insert(o.tris.end(), ec.tris.begin() + 3 * first, ec.tris.begin() + 3 * last);
	o.triBorder.insert(o.triBorder.end(), ec.bits.begin() + first, ec.bits.begin() + last);
	const size_t at = size_t(ec.measureAt[size_t(fs)]);
	for (int32_t i = fb; i < fe; ++i) {
		const size_t f = size_t(faces_.face[size_t(i)]), j = at + size_t(i - fb);
		measures_.dev[f] = ec.dev[j];
		if (!measures_.gap.empty())
			measures_.gap[f] = ec.gap.empty() ? 0.0f : ec.gap[j];
		if (!measures_.tex.empty())
			measures_.tex[f] = ec.tex.empty() ? 0.0f : ec.tex[j];
	}
	++o.retriangulated, ++o.carried;
	return true;
}

// This level's exact superfaces for the next coarser level (see ExactCarry): re-triangulated,
// every face's distance bound within LevelLimits::exact, every vertex of its triangles on a border
// and at its input position.
void LevelRounds::carryExact()
{
	ExactCarry &ec = *carryOut_;
	ec = ExactCarry();
	ec.label = &p_.label;
	const size_t n = p_.count();
	ec.first.assign(n, -1), ec.last.assign(n, -1), ec.measureAt.assign(n + 1, 0);
	const bool gap = !measures_.gap.empty(), tex = !measures_.tex.empty();
	for (size_t sf = 0; sf < n; ++sf) {
		ec.measureAt[sf + 1] = ec.measureAt[sf];
		const Cached &c = cache_[sf];
		if (!c.ok || !c.retriangulated || c.triEnd <= c.triBegin)
			continue;
		bool exact = true;
		for (int32_t i = faces_.begin(int32_t(sf)); i < faces_.end(int32_t(sf)) && exact; ++i) {
			const size_t f = size_t(faces_.face[size_t(i)]);
			exact = measures_.dev[f] >= 0 && (!gap || double(measures_.gap[f]) <= limits_.exact);
		}
		for (int32_t k = c.triBegin; k < c.triEnd && exact; ++k)
			for (size_t j = 0; j < 3 && exact; ++j) {
				const int32_t v = tri_.tris[3 * size_t(k) + j];
				exact = borders_.degree[size_t(v)] > 0 && placement_.at(t_, size_t(v)) == t_.pos(v);
			}
		if (!exact)
			continue;
		ec.first[sf] = int32_t(ec.bits.size());
		ec.tris.insert(ec.tris.end(), tri_.tris.begin() + 3 * c.triBegin,
		               tri_.tris.begin() + 3 * c.triEnd);
		ec.bits.insert(ec.bits.end(), tri_.triBorder.begin() + c.triBegin,
		               tri_.triBorder.begin() + c.triEnd);
		for (int32_t i = faces_.begin(int32_t(sf)); i < faces_.end(int32_t(sf)); ++i) {
			const size_t f = size_t(faces_.face[size_t(i)]);
			ec.dev.push_back(measures_.dev[f]);
			if (gap)
				ec.gap.push_back(measures_.gap[f]);
			if (tex)
				ec.tex.push_back(measures_.tex[f]);
		}
		ec.last[sf] = int32_t(ec.bits.size());
		ec.measureAt[sf + 1] = int32_t(ec.dev.size());
	}
	// (straightening keeps every chain end; a chain that keeps nothing else keeps nothing else
	// with a tolerance at least as large: with the same borders, the same outlines)
	ec.whole = out_.stats.rounds == 1 && placement_.moved == 0 &&
	           std::find(ec.first.begin(), ec.first.end(), -1) == ec.first.end();
	for (size_t k = 0; k < tri_.tris.size() && ec.whole; ++k)
		ec.whole = borders_.junction[size_t(tri_.tris[k])] != 0;
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

void LevelRounds::finish(size_t fallbacks)
{
	releaseRounds();
	std::vector<int32_t> remap(t_.nV, -1);
	for (int32_t v : tri_.tris)
		remap[size_t(v)] = 0;
	int32_t next = 0;
	for (size_t v = 0; v < t_.nV; ++v)
		if (remap[v] >= 0)
			remap[v] = next++;
	out_.positions.resize(3 * size_t(next));
	out_.sourceVertex.resize(size_t(next));
	for (size_t v = 0; v < t_.nV; ++v) {
		if (remap[v] < 0)
			continue;
		const size_t o = size_t(remap[v]);
		out_.sourceVertex[o] = int32_t(v);
		const Vec3 p = placement_.at(t_, v);
		for (size_t k = 0; k < 3; ++k)
			out_.positions[3 * o + k] = p[int(k)];
	}
	out_.stats.placedVertices = placement_.moved;
	out_.stats.maxPlacement = placement_.maxMove;
	placement_ = Placement();
	if (t_.wantSources)
		findSources(t_, p_, tri_, out_); // (on input vertex numbers)
	for (int32_t &v : tri_.tris)
		v = remap[size_t(v)];
	release(remap);
	out_.triangles = std::move(tri_.tris);
	out_.superface = std::move(tri_.triSf);
	out_.inputSuperface = p_.label;
	for (uint8_t &b : tri_.triBorder)
		b &= kBorderBits;
	out_.borderEdges = std::move(tri_.triBorder);
	fillStats(fallbacks, size_t(next));
}

void LevelRounds::fillStats(size_t fallbacks, size_t vertices)
{
	LevelStats &st = out_.stats;
	st.level = p_.level;
	st.boundDeg = levelBoundDeg(p_.level);
	st.faces = out_.triangles.size() / 3;
	st.vertices = vertices;
	st.superfaces = p_.count();
	st.fallbacks = fallbacks;
	st.retriangulated = retriangulated_;
	st.carriedSuperfaces = carried_;
	double maxDev = 0, sum = 0, area = 0;
	size_t unmeasured = 0;
	const std::vector<float> &dev = measures_.dev;
	for (size_t f = 0; f < t_.nF; ++f) {
		if (!t_.faceValid[f])
			continue;
		if (dev[f] < 0) {
			++unmeasured;
			continue;
		}
		maxDev = std::max(maxDev, double(dev[f]));
		const double a = t_.faceArea[f];
		sum += double(dev[f]) * a;
		area += a;
	}
	st.maxNormalDevDeg = maxDev;
	st.meanNormalDevDeg = area > 0 ? sum / area : 0;
	st.unmeasuredFaces = unmeasured;
	if (!measures_.gap.empty()) {
		st.distanceBound = double(*std::max_element(measures_.gap.begin(), measures_.gap.end()));
		out_.superfaceBound.assign(st.superfaces, 0.0f);
		for (size_t f = 0; f < t_.nF; ++f) {
			const int32_t s = p_.label[f];
			if (s >= 0)
				out_.superfaceBound[size_t(s)] =
				    std::max(out_.superfaceBound[size_t(s)], measures_.gap[f]);
		}
	}
	if (!measures_.tex.empty())
		st.maxTexError = double(*std::max_element(measures_.tex.begin(), measures_.tex.end()));
}

} // namespace

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
