// One level's geometry from the input mesh and that level's partition:
//   2.2.2 tracing the border rings of every superface;
//   2.3.1 straightening the chains between junction vertices (Douglas-Peucker with a tolerance);
//   2.3.2 vicinity merging of consecutive border vertices by importance;
//   2.4   re-triangulating each superface (constrained Delaunay in its best-fit plane);
// then a validity check of the whole level; a superface that fails is first retried with its
// border locked, then split into its children of the next finer level, until the level is valid.
#include "engine.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>

namespace gausslod {
namespace detail {

namespace {

constexpr double kRadToDeg = 57.295779513082320876798;
constexpr int kMaxRounds = 64;
// A superface that fails with straightened borders gets them straightened again with a quarter
// of the tolerances (kTolShift = 2), up to this many times, before its border vertices are locked.
constexpr int kMaxTolSteps = 2;
constexpr int kTolShift = 2;

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

double pointSegmentDistance(const Vec3 &p, const Vec3 &a, const Vec3 &b)
{
	const Vec3 ab = b - a;
	const double len2 = ab.SquaredNorm();
	double t = len2 > 0 ? (p - a).dot(ab) / len2 : 0.0;
	t = std::max(0.0, std::min(1.0, t));
	return (p - (a + ab * t)).Norm();
}

double angleDeg(const Vec3 &a, const Vec3 &b)
{
	return std::acos(std::max(-1.0, std::min(1.0, a.dot(b)))) * kRadToDeg;
}

// Why a superface failed: Fold (its projection folds, or its rings could not be traced) goes
// straight to the split; Deviation (an input face deviates from its new triangle more than the
// limit: often a straightened border cutting across a slightly curved region) first retries with
// tighter straightening (as does a removed border vertex beyond Params::maxDistance); Distance
// (an input face beyond Params::maxDistance from its new triangles) goes straight to the split;
// Ring (anything else) first locks the border. (Retrying the others with tighter straightening
// too was measured: more faces at level 0 on cow and bumpy meshes.)
enum class Failure : uint8_t { None, Ring, Fold, Deviation, Distance };

// A chain of border edges between two junction vertices (or a closed loop with none), stored as a
// range of a ring. Only one of the (up to) two superfaces sharing it processes it.
struct Piece {
	int32_t ring, start, len; ///< ring index, first position in the ring, number of edges
	int32_t a, b;             ///< end vertices (a == b for a closed chain)
	bool loop;                ///< a ring without any junction
	int8_t minInterior;       ///< interior vertices to keep at least (keeps rings non-degenerate)
	int32_t kept = 0;         ///< interior vertices kept after simplification
};

// What one chunk of consecutive superfaces produces; chunks are concatenated in order, so the
// result does not depend on how many threads ran them.
struct ChunkOut {
	std::vector<int32_t> tris;       ///< (the superface of a triangle is known from cache_ ranges)
	std::vector<uint8_t> triBorder; ///< border edge bits | kNewTriangle
	std::vector<std::pair<int32_t, Failure>> failed;
	std::vector<Piece> straight; ///< pieces left straight (see separateParallelChains)
	std::vector<int32_t> ringHE, ringStart, sfRings; ///< traced rings (until concatenated)
	size_t retriangulated = 0;
	size_t failedTris = 0; ///< triangles the failed superfaces had made (at least 1 each)
	void swap(ChunkOut &o)
	{
		tris.swap(o.tris), triBorder.swap(o.triBorder), failed.swap(o.failed);
		straight.swap(o.straight), std::swap(retriangulated, o.retriangulated);
		std::swap(failedTris, o.failedTris);
		ringHE.swap(o.ringHE), ringStart.swap(o.ringStart), sfRings.swap(o.sfRings);
	}
	void clear()
	{
		tris.clear(), triBorder.clear();
		failed.clear(), straight.clear();
		ringHE.clear(), ringStart.clear(), sfRings.clear();
		retriangulated = 0, failedTris = 0;
	}
};

// Per-thread scratch.
struct Scratch {
	TriangulationJob job;
	std::vector<int32_t> ringVerts, ringVertStart, seq, stack;
	std::vector<uint64_t> edgesNow, edgesBefore; // directed border edges (see reuse)
	std::vector<Vec3> triNormal, centroid;
	std::vector<double> ownDist2;
	std::vector<uint8_t> covered;
	// distance tolerance: each vertex of a superface's faces located once
	std::vector<int32_t> vertQuery;   ///< per input vertex: its query, -1 between superfaces
	std::vector<int32_t> cornerQuery; ///< per face corner of the superface: its vertex's query
	std::vector<int32_t> touched;     ///< the vertices given a query (to reset vertQuery)
};

class LevelBuilder {
public:
	LevelBuilder(const Topology &t, const Params &prm, const std::vector<Partition> &finer,
	             Partition &p, LevelMesh &out, size_t faceLimit)
	    : t_(t), prm_(prm), finer_(finer), p_(p), out_(out), faceLimit_(faceLimit)
	{
	}

	void run()
	{
		// below this, border vertices count as exactly on their straightened chain
		tolerance_ = std::max(prm_.straightenTolerance, 1e-9 * t_.diagonal);
		mergeDistance_ = prm_.mergeDistance;
		if (prm_.maxDistance > 0) {
			tolerance_ = std::min(tolerance_, std::max(prm_.maxDistance, 1e-9 * t_.diagonal));
			mergeDistance_ = std::min(mergeDistance_, 0.5 * prm_.maxDistance);
		}
		devLimit_ = prm_.deviationFactor > 0 ? prm_.deviationFactor * levelBoundDeg(p_.level) : 180.0;
		extraLock_.assign(t_.nV, 0);
		tolStep_.assign(t_.nF, 0);
		faceDev_.assign(t_.nF, -1.0f); // (kept across rounds: a superface rebuilt resets its faces)
		if (prm_.maxDistance > 0)
			faceGap_.assign(t_.nF, 0.0f);
		threads_ = threadCount(prm_.threads);
		scratch_.resize(threads_);
		size_t fallbacks = 0;
		int round = 0;
		for (;; ++round) {
			if (round == kMaxRounds) // give up simplifying: every vertex kept is always valid
				std::fill(extraLock_.begin(), extraLock_.end(), uint8_t(1));
			buildOnce(round > 0 && round < kMaxRounds);
			if (failed_.empty() || round >= kMaxRounds)
				break;
			// Splitting a superface adds faces (its pieces have the split chains on their borders)
			// and so does a tighter re-simplification or a locked border: a failed superface will
			// end with at least the triangles its failed attempt made, and a level already over its
			// limit this way is abandoned. (Later rounds can lose a few faces when a chain's new
			// junctions make it simplify differently: 0.3 % was the most seen; the limit is the
			// finer level's count.)
			const size_t atLeast = liveTris_ + failedTris_;
			if (atLeast > faceLimit_) {
				out_.stats.faces = atLeast;
				out_.stats.rounds = round + 1;
				out_.stats.secondsChecks += clock_.lap();
				return;
			}
			fallbacks += failed_.size();
			keepForReuse();
			applyFallbacks();
			out_.stats.secondsChecks += clock_.lap();
		}
		out_.stats.rounds = round + 1;
		finish(fallbacks);
		out_.stats.secondsChecks += clock_.lap();
	}

private:
	const Topology &t_;
	const Params &prm_;
	const std::vector<Partition> &finer_;
	Partition &p_;
	LevelMesh &out_;
	const size_t faceLimit_;

	// per round
	std::vector<int32_t> sfStart_, sfFace_;   // superface -> faces (CSR)
	std::vector<uint8_t> border_;             // per half-edge: 1 = border (| kVisited while the
	                                          // rings are traced)
	static constexpr uint8_t kVisited = 2;
	std::vector<int32_t> degree_;             // border edges per vertex
	std::vector<uint8_t> junction_, keep_, extraLock_;
	std::vector<uint8_t> tolStep_;            // per input face: its superface's border tolerances
	                                          // were divided by 4 this many times (see applyFallbacks)
	std::vector<int32_t> retightened_;        // border vertices of superfaces whose tolerances the
	                                          // last fallbacks divided
	std::vector<uint8_t> changed_;            // patch round: degree or junction status changed
	std::vector<int32_t> changedList_;        // the vertices marked in changed_
	std::vector<int32_t> relabeled_;          // faces whose superface the last fallbacks split
	std::vector<int32_t> failedFace_;         // a face of each superface that failed last round
	std::vector<int32_t> lockedNow_;          // vertices the last fallbacks locked
	std::vector<uint8_t> dirty_;              // per superface: rebuilt this round
	std::vector<int32_t> ringHE_, ringStart_, sfRingStart_;
	std::vector<uint8_t> broken_;
	std::vector<Piece> pieces_;
	std::vector<std::pair<int32_t, Failure>> failed_;
	size_t failedTris_ = 0; // triangles the failed superfaces had made before failing, at least 1
	                        // each (those the whole-level check failed: 1, theirs are live)
	// output of a round
	std::vector<int32_t> tris_, triSf_; // (after a patch round with failures: see buildOnce)
	size_t liveTris_ = 0;               // triangles of the round's superfaces
	std::vector<uint8_t> triBorder_;          // per triangle: border edge bits | kNewTriangle
	std::vector<float> faceDev_;              // per input face, degrees; -1 = not measured
	std::vector<float> faceGap_;              // per input face: distance measured by the
	                                          // tolerance check (Params::maxDistance > 0 only)
	size_t retriangulated_ = 0;
	// work split in chunks of consecutive superfaces, run on threads_ threads
	size_t threads_ = 1;
	std::vector<Scratch> scratch_;       // per thread
	std::vector<int32_t> chunkStart_;    // chunk c = superfaces [chunkStart_[c], chunkStart_[c+1])
	std::vector<ChunkOut> chunks_;

	template <class V>
	static void release(V &v)
	{
		V().swap(v);
	}

	// Runs fn(chunk, scratch) for every chunk, on up to threads_ threads.
	template <class Fn>
	void forEachChunk(Fn fn)
	{
		const size_t n = chunkStart_.size() - 1;
		std::atomic<size_t> next(0);
		std::atomic<bool> failed(false); // (the others stop early; the error is rethrown)
		onWorkers(std::min(threads_, n), [&](size_t w) {
			try {
				for (size_t c; !failed && (c = next++) < n;)
					fn(c, scratch_[w]);
			} catch (...) {
				failed = true;
				throw;
			}
		});
	}

	// Chunks of about the same number of faces (several per thread, for balance).
	void makeChunks()
	{
		const size_t ns = p_.count();
		const size_t target = std::max<size_t>(2048, t_.nF / (8 * threads_) + 1);
		chunkStart_.assign(1, 0);
		size_t faces = 0;
		for (size_t s = 0; s < ns; ++s) {
			faces += size_t(sfStart_[s + 1] - sfStart_[s]);
			if (faces >= target && s + 1 < ns) {
				chunkStart_.push_back(int32_t(s + 1));
				faces = 0;
			}
		}
		chunkStart_.push_back(int32_t(ns));
		chunks_.resize(chunkStart_.size() - 1);
		for (ChunkOut &c : chunks_)
			c.clear();
	}

	// ---------------------------------------------------------------- 2.2.2 borders and rings
	void groupFaces()
	{
		const size_t ns = p_.count();
		sfStart_.assign(ns + 1, 0);
		for (size_t f = 0; f < t_.nF; ++f)
			++sfStart_[size_t(p_.label[f]) + 1];
		for (size_t s = 0; s < ns; ++s)
			sfStart_[s + 1] += sfStart_[s];
		sfFace_.resize(t_.nF);
		std::vector<int32_t> fill(sfStart_.begin(), sfStart_.end() - 1);
		for (size_t f = 0; f < t_.nF; ++f)
			sfFace_[size_t(fill[size_t(p_.label[f])]++)] = int32_t(f);
	}

	// Border half-edges, border degree and junctions. In a patch round (see buildOnce) the kept
	// vertices of the previous round stay; vertices whose degree or junction status changed are
	// marked in changed_.
	void findBorders(bool patch)
	{
		if (patch) {
			updateBorders();
			return;
		}
		// (on every thread: the flags per face range, then per vertex range its border edges,
		// each counted at its one half-edge that is unpaired or the lower of the two, found among
		// the vertex's faces, where it is the only corner)
		border_.resize(3 * t_.nF);
		parallelRanges(t_.nF, threads_, [&](size_t f0, size_t f1, size_t) {
			for (size_t f = f0; f < f1; ++f)
				for (size_t h = 3 * f; h < 3 * f + 3; ++h) {
					const int32_t tw = t_.twin[h];
					border_[h] = !t_.faceDropped[f] &&
					             (tw < 0 || p_.label[f] != p_.label[size_t(heFace(tw))]);
				}
		});
		degree_.resize(t_.nV), junction_.resize(t_.nV), keep_.resize(t_.nV);
		parallelRanges(t_.nV, threads_, [&](size_t v0, size_t v1, size_t) {
			for (size_t v = v0; v < v1; ++v) {
				int32_t d = 0;
				for (int32_t q = t_.vfStart[v]; q < t_.vfStart[v + 1]; ++q) {
					const int32_t f = t_.vfFace[size_t(q)];
					const int32_t k = t_.T[3 * f] == int32_t(v) ? 0 : t_.T[3 * f + 1] == int32_t(v) ? 1 : 2;
					for (const int32_t h : {3 * f + k, 3 * f + (k + 2) % 3}) // out of v, into v
						if (border_[size_t(h)] && (t_.twin[size_t(h)] < 0 || h < t_.twin[size_t(h)]))
							++d;
				}
				degree_[v] = d;
				junction_[v] = keep_[v] = isJunction(v);
			}
		});
		changed_.assign(t_.nV, 0);
		changedList_.clear();
	}

	bool isJunction(size_t v) const
	{
		return degree_[v] > 0 && (degree_[v] != 2 || t_.vertexLocked[v] || extraLock_[v]);
	}

	// Patch round: only the half-edges of the faces the fallbacks relabelled can have changed
	// border status (borders are only added), and only their vertices and the newly locked ones
	// can have changed degree or junction status: those are marked in changed_ / changedList_.
	void updateBorders()
	{
		for (int32_t v : changedList_)
			changed_[size_t(v)] = 0;
		changedList_.clear();
		auto touch = [&](int32_t v) {
			if (!changed_[size_t(v)]) {
				changed_[size_t(v)] = 1;
				changedList_.push_back(v);
			}
		};
		for (int32_t f : relabeled_)
			for (int k = 0; k < 3; ++k) {
				const int32_t h = 3 * f + k, tw = t_.twin[size_t(h)];
				const bool b = !t_.faceDropped[size_t(f)] &&
				               (tw < 0 || p_.label[size_t(f)] != p_.label[size_t(heFace(tw))]);
				if (b == bool(border_[size_t(h)]))
					continue; // (the twin, seen first, already updated both)
				border_[size_t(h)] = b;
				if (tw >= 0)
					border_[size_t(tw)] = b;
				const int d = b ? 1 : -1;
				degree_[size_t(t_.heFrom(h))] += d;
				degree_[size_t(t_.heTo(h))] += d;
				touch(t_.heFrom(h));
				touch(t_.heTo(h));
			}
		for (int32_t v : lockedNow_)
			if (bool(junction_[size_t(v)]) != isJunction(size_t(v)))
				touch(v);
		for (int32_t v : retightened_)
			touch(v); // (its chains are simplified again, with the smaller tolerances)
		for (int32_t v : changedList_) {
			junction_[size_t(v)] = isJunction(size_t(v));
			keep_[size_t(v)] = junction_[size_t(v)]; // non-junctions: their piece is recomputed
		}
	}

	// Rings of superface s: from a border half-edge, the next one starts at its end vertex and is
	// found by turning around that vertex inside the superface (works at pinched vertices too).
	bool traceRings(int32_t s, std::vector<int32_t> &ringHE, std::vector<int32_t> &ringStart)
	{
		for (int32_t i = sfStart_[size_t(s)]; i < sfStart_[size_t(s) + 1]; ++i) {
			const int32_t f = sfFace_[size_t(i)];
			for (int k = 0; k < 3; ++k) {
				const int32_t h0 = 3 * f + k;
				if (border_[size_t(h0)] != 1) // (not a border, or visited)
					continue;
				ringStart.push_back(int32_t(ringHE.size()));
				int32_t h = h0;
				do {
					border_[size_t(h)] |= kVisited;
					ringHE.push_back(h);
					const int32_t b = t_.heTo(h);
					const int32_t guard = t_.vfStart[size_t(b) + 1] - t_.vfStart[size_t(b)] + 1;
					int32_t e = heNext(h), steps = 0;
					while (!border_[size_t(e)] && steps++ <= guard)
						e = heNext(t_.twin[size_t(e)]);
					if (!border_[size_t(e)] || bool(border_[size_t(e)] & kVisited) != (e == h0))
						return false; // not a proper ring (cannot happen on sane adjacency)
					h = e;
				} while (h != h0);
			}
		}
		return true;
	}

	// -------------------------------------------------------------- 2.3 chains and their pieces
	// Cuts the rings into pieces and simplifies each piece as it is found; pieces_ keeps only
	// those left straight (no interior vertex kept, distinct ends, more than one edge) for
	// separateParallelChains. In a patch round only the pieces with a changed vertex are
	// processed (the others are the same chains as in the previous round and keep their kept
	// vertices); they start from their end vertices only.
	void collectAndSimplifyPieces(bool patch)
	{
		forEachChunk([&](size_t c, Scratch &w) {
			for (int32_t sf = chunkStart_[c]; sf < chunkStart_[c + 1]; ++sf)
				for (int32_t r = sfRingStart_[size_t(sf)]; r < sfRingStart_[size_t(sf) + 1]; ++r)
					collectRing(sf, r, patch, w, chunks_[c]);
		});
		pieces_.clear();
		for (const ChunkOut &o : chunks_)
			pieces_.insert(pieces_.end(), o.straight.begin(), o.straight.end());
	}

	// A piece is processed from one side only: the superface of lower index among those whose
	// rings were traced (the other side of a mesh-boundary or non-manifold edge has none).
	bool owns(int32_t sf, int32_t h) const
	{
		const int32_t tw = t_.twin[size_t(h)];
		if (tw < 0)
			return true;
		const int32_t other = p_.label[size_t(heFace(tw))];
		return sf < other || !dirty_[size_t(other)] || broken_[size_t(other)];
	}

	void collectRing(int32_t sf, int32_t r, bool patch, Scratch &w, ChunkOut &o)
	{
		const int32_t b = ringStart_[size_t(r)], m = ringStart_[size_t(r) + 1] - b;
		const int32_t *H = &ringHE_[size_t(b)];
		int32_t first = -1;
		for (int32_t i = 0; i < m && first < 0; ++i)
			if (junction_[size_t(t_.heFrom(H[i]))])
				first = i;
		auto wanted = [&](int32_t start, int32_t len) {
			if (!owns(sf, H[start % m]))
				return false;
			bool touched = !patch;
			for (int32_t i = 0; i <= len && !touched; ++i)
				touched = changed_[size_t(t_.heFrom(H[(start + i) % m]))] != 0;
			return touched;
		};
		if (first < 0) { // closed loop without junction: anchor at its smallest vertex id
			int32_t anchor = 0;
			for (int32_t i = 1; i < m; ++i)
				if (t_.heFrom(H[i]) < t_.heFrom(H[anchor]))
					anchor = i;
			if (wanted(anchor, m)) {
				const int32_t v = t_.heFrom(H[anchor]);
				process(Piece{r, anchor, m, v, v, true, 2}, patch, w, o);
			}
			return;
		}
		for (int32_t i = first; i < first + m;) {
			int32_t j = i + 1;
			while (!junction_[size_t(t_.heFrom(H[j % m]))])
				++j;
			if (wanted(i, j - i)) {
				const int32_t a = t_.heFrom(H[i % m]), e = t_.heFrom(H[j % m]);
				// a closed chain (a == e) would straighten onto a point
				process(Piece{r, i % m, j - i, a, e, false, int8_t(a == e ? 2 : 0)}, patch, w, o);
			}
			i = j;
		}
	}

	void process(Piece pc, bool patch, Scratch &w, ChunkOut &o)
	{
		if (patch)
			resetInterior(pc);
		simplifyPiece(pc, w);
		if (!pc.loop && pc.a != pc.b && pc.kept == 0 && pc.len >= 2)
			o.straight.push_back(pc);
	}

	// Is there a border edge between vertices a and b (a piece of one edge, when both are
	// junctions)?
	bool borderEdge(int32_t a, int32_t b) const
	{
		for (int32_t q = t_.vfStart[size_t(a)]; q < t_.vfStart[size_t(a) + 1]; ++q)
			for (int k = 0; k < 3; ++k) {
				const int32_t h = 3 * t_.vfFace[size_t(q)] + k;
				if (border_[size_t(h)] && ((t_.heFrom(h) == a && t_.heTo(h) == b) ||
				                           (t_.heFrom(h) == b && t_.heTo(h) == a)))
					return true;
			}
		return false;
	}

	// Patch round: a recomputed piece starts from its end vertices only.
	void resetInterior(const Piece &pc)
	{
		const int32_t b = ringStart_[size_t(pc.ring)], m = ringStart_[size_t(pc.ring) + 1] - b;
		for (int32_t i = pc.loop ? 0 : 1; i < pc.len; ++i)
			keep_[size_t(t_.heFrom(ringHE_[size_t(b + (pc.start + i) % m)]))] = 0;
	}

	// Two chains with the same end vertices must not both straighten onto the same segment: all
	// but one of them get back their farthest interior vertex; none stays straight when the two
	// ends are joined by a border edge (a one-edge chain, which cannot keep a vertex).
	void separateParallelChains()
	{
		// the pieces grouped by (smaller, larger) end vertex, in that order, each group in
		// pieces_ order: a bucket sort over the vertices for many pieces, a sort for the few of
		// a patch round (where a pass over every vertex would cost more than the pieces)
		auto lo = [&](size_t i) { return std::min(pieces_[i].a, pieces_[i].b); };
		auto hi = [&](int32_t i) { return std::max(pieces_[size_t(i)].a, pieces_[size_t(i)].b); };
		auto key = [&](int32_t i) { return uint64_t(uint32_t(lo(size_t(i)))) << 32 | uint32_t(hi(i)); };
		std::vector<int32_t> order;
		if (pieces_.size() >= t_.nV / 16) {
			std::vector<int32_t> start;
			bucketSort(pieces_.size(), t_.nV, lo, [&](int32_t i, int32_t j) { return hi(i) < hi(j); },
			           start, order);
		} else {
			order.resize(pieces_.size());
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
					Piece &pc = pieces_[size_t(order[q])];
					loadSequence(pc, scratch_[0]);
					pc.minInterior = 1;
					ensureInterior(pc, scratch_[0]);
				}
			i = j;
		}
	}

	void loadSequence(const Piece &pc, Scratch &w) const
	{
		const int32_t b = ringStart_[size_t(pc.ring)], m = ringStart_[size_t(pc.ring) + 1] - b;
		w.seq.resize(size_t(pc.len) + 1);
		for (int32_t i = 0; i <= pc.len; ++i)
			w.seq[size_t(i)] = t_.heFrom(ringHE_[size_t(b + (pc.start + i) % m)]);
	}

	// Farthest interior vertex of (lo, hi) from the segment seq[lo]-seq[hi]; -1 if none.
	int32_t farthest(int32_t lo, int32_t hi, double &dist, const Scratch &w) const
	{
		int32_t best = -1;
		dist = -1;
		const Vec3 a = t_.pos(w.seq[size_t(lo)]), c = t_.pos(w.seq[size_t(hi)]);
		for (int32_t i = lo + 1; i < hi; ++i) {
			const double d = pointSegmentDistance(t_.pos(w.seq[size_t(i)]), a, c);
			if (d > dist) {
				dist = d;
				best = i;
			}
		}
		return best;
	}

	// Keeps at least pc.minInterior interior vertices (seq_ loaded): adds the vertex farthest
	// from the current kept polyline, one at a time.
	void ensureInterior(Piece &pc, const Scratch &w)
	{
		const int32_t n = pc.len;
		while (pc.kept < pc.minInterior && pc.kept < n - 1) {
			int32_t best = -1, lo = 0;
			double bestD = -1;
			for (int32_t i = 1; i <= n; ++i) {
				if (i < n && keep_[size_t(w.seq[size_t(i)])] == 0)
					continue;
				double d;
				const int32_t f = farthest(lo, i, d, w);
				if (f >= 0 && d > bestD)
					bestD = d, best = f;
				lo = i;
			}
			if (best < 0)
				break;
			keep_[size_t(w.seq[size_t(best)])] = 1;
			++pc.kept;
		}
	}

	// The tolerances of a chain: divided by 4 for each fallback step of either superface along it (a
	// chain lies between the same two superfaces all along: a change of neighbour is a junction).
	double pieceScale(const Piece &pc) const
	{
		const int32_t h = ringHE_[size_t(ringStart_[size_t(pc.ring)] + pc.start)];
		int step = tolStep_[size_t(heFace(h))];
		const int32_t tw = t_.twin[size_t(h)];
		if (tw >= 0)
			step = std::max<int>(step, tolStep_[size_t(heFace(tw))]);
		return std::ldexp(1.0, -kTolShift * step);
	}

	// 2.3.1 straightening (Douglas-Peucker: split at the farthest vertex while it is farther than
	// the tolerance) and 2.3.2 vicinity merging, on one piece's vertex sequence.
	void simplifyPiece(Piece &pc, Scratch &w)
	{
		loadSequence(pc, w);
		const int32_t n = pc.len; // w.seq[0] and w.seq[n] are the ends
		auto P = [&](int32_t i) { return t_.pos(w.seq[size_t(i)]); };
		// (divided by 4 per fallback of either superface along the chain, see applyFallbacks)
		const double scale = pieceScale(pc);
		const double tol = std::max(tolerance_ * scale, 1e-9 * t_.diagonal);
		int32_t &kept = pc.kept; // interior vertices kept
		auto keepIdx = [&](int32_t i) {
			if (!keep_[size_t(w.seq[size_t(i)])]) {
				keep_[size_t(w.seq[size_t(i)])] = 1;
				++kept;
			}
		};
		if (n < 2)
			return;
		w.stack.clear();
		if (pc.loop) { // anchor + the vertex farthest from it split the loop in two chains
			keep_[size_t(w.seq[0])] = 1;
			double d;
			const int32_t far = farthest(0, n, d, w);
			keepIdx(far);
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
				keepIdx(i);
				w.stack.push_back(lo), w.stack.push_back(i);
				w.stack.push_back(i), w.stack.push_back(hi);
			}
		}
		ensureInterior(pc, w);
		const double mergeDistance = mergeDistance_ * scale;
		if (mergeDistance <= 0)
			return;
		// 2.3.2 vicinity merging: a kept interior vertex closer than the merge distance to a kept
		// neighbour on its chain merges into it if it is not more important; corners only receive.
		int32_t prev = 0;
		for (int32_t i = 1; i < n; ++i) {
			const int32_t v = w.seq[size_t(i)];
			if (!keep_[size_t(v)])
				continue;
			int32_t next = i + 1;
			while (next < n && !keep_[size_t(w.seq[size_t(next)])])
				++next;
			if (kept <= pc.minInterior)
				break;
			const uint8_t cls = t_.vertexClass[size_t(v)];
			const double dp = (P(i) - P(prev)).Norm(), dn = (P(i) - P(next)).Norm();
			const int32_t into = dp <= dn ? prev : next;
			const bool close = std::min(dp, dn) < mergeDistance;
			if (close && cls != kCorner && cls <= t_.vertexClass[size_t(w.seq[size_t(into)])]) {
				keep_[size_t(v)] = 0;
				--kept;
				continue; // prev stays
			}
			prev = i;
		}
	}

	// ------------------------------------------------------------------- 2.4 re-triangulation
	// a triangle's flags: bit k = edge (k, k+1) is a superface border; kNewTriangle = made by
	// re-triangulation (not an input face)
	static constexpr uint8_t kBorderBits = 7, kNewTriangle = 8;

	static void emit(ChunkOut &o, int32_t a, int32_t b, int32_t c, uint8_t borderBits, bool isNew)
	{
		o.tris.push_back(a), o.tris.push_back(b), o.tris.push_back(c);
		o.triBorder.push_back(uint8_t(borderBits | (isNew ? kNewTriangle : 0)));
	}

	// Params::maxDistance on a re-triangulated superface: the removed vertices of its rings
	// against the straightened ring edges; each input face against the triangles its centroid
	// and its corners fall in (each vertex located once, see cornerQuery): along the projection
	// direction N, the gap between the face and a triangle's plane is linear over the face, so
	// its largest value over the part of the face above that triangle is at a corner of that part
	// (the face clipped by the triangle, in the projection). A face crossing a triangle that
	// holds neither its centroid nor a corner is not seen. A border too far is a Deviation
	// (tighter tolerances, then a locked border fix it), a face too far a Distance failure (only
	// a split fixes it). The distances measured are kept per input face (faceGap_; a removed
	// border vertex's on the face of its ring edge) for the level's figure.
	Failure distanceCheck(int32_t s, int32_t fb, int32_t fe, const Vec3 &N, size_t firstTri,
	                      const Scratch &w, const ChunkOut &o)
	{
		const double eps = prm_.maxDistance;
		for (int32_t r = sfRingStart_[size_t(s)]; r < sfRingStart_[size_t(s) + 1]; ++r) {
			const int32_t b = ringStart_[size_t(r)], e = ringStart_[size_t(r) + 1];
			int32_t first = b; // a kept vertex to start from (a ring keeps at least 3)
			while (first < e && !keep_[size_t(t_.heFrom(ringHE_[size_t(first)]))])
				++first;
			if (first == e)
				return Failure::Ring;
			Vec3 a = t_.pos(t_.heFrom(ringHE_[size_t(first)]));
			int32_t runStart = 0; // removed vertices since the last kept one: positions in ring
			for (int32_t step = 1, run = 0; step <= e - b; ++step) {
				const int32_t i = b + (first - b + step) % (e - b);
				const int32_t v = t_.heFrom(ringHE_[size_t(i)]);
				if (!keep_[size_t(v)]) {
					if (run++ == 0)
						runStart = i;
					continue;
				}
				const Vec3 c = t_.pos(v);
				for (int32_t k = 0; k < run; ++k) {
					const int32_t j = b + (runStart - b + k) % (e - b);
					const double d = pointSegmentDistance(t_.pos(t_.heFrom(ringHE_[size_t(j)])), a, c);
					if (d > eps)
						return Failure::Deviation;
					float &g = faceGap_[size_t(heFace(ringHE_[size_t(j)]))];
					g = std::max(g, float(d));
				}
				a = c, run = 0;
			}
		}
		const size_t ntri = o.tris.size() / 3 - firstTri;
		const size_t faces = size_t(fe - fb);
		// gap at face i's corners to triangle k's plane (along N), then over the clipped part;
		// true if beyond eps, else the largest gap seen is kept in faceGap_
		auto faceTooFar = [&](size_t i, int32_t k) {
			const int32_t f = sfFace_[size_t(fb) + i];
			const Vec3 &n = w.triNormal[size_t(k)];
			const Vec3 &q = t_.pos(o.tris[3 * (firstTri + size_t(k))]);
			const double nN = n.dot(N);
			double gap[3], cornerMax = 0;
			for (int c = 0; c < 3; ++c) {
				gap[c] = (t_.pos(t_.T[3 * f + c]) - q).dot(n) / nN;
				cornerMax = std::max(cornerMax, std::fabs(gap[c]));
			}
			float &kept = faceGap_[size_t(f)];
			if (cornerMax <= eps || ntri == 1) { // (one triangle, no queries: the corners decide)
				kept = std::max(kept, float(cornerMax));
				return cornerMax > eps;
			}
			// the face (2D, its corners' queries) clipped by triangle k (Sutherland-Hodgman)
			double poly[2][12][2];
			int cnt = 3;
			double fxy[6];
			for (int c = 0; c < 3; ++c) {
				const size_t q = faces + size_t(w.cornerQuery[3 * i + size_t(c)]);
				fxy[2 * c] = poly[0][c][0] = w.job.queryXY[2 * q];
				fxy[2 * c + 1] = poly[0][c][1] = w.job.queryXY[2 * q + 1];
			}
			const int32_t *tv = &w.job.tris[3 * size_t(k)];
			double area = 0; // of triangle k, for its orientation
			for (int e = 0; e < 3; ++e) {
				const double *a = &w.job.xy[2 * size_t(tv[e])], *b = &w.job.xy[2 * size_t(tv[(e + 1) % 3])];
				area += a[0] * b[1] - a[1] * b[0];
			}
			const double sign = area >= 0 ? 1.0 : -1.0;
			int cur = 0;
			for (int e = 0; e < 3 && cnt > 0; ++e) {
				const double *a = &w.job.xy[2 * size_t(tv[e])], *b = &w.job.xy[2 * size_t(tv[(e + 1) % 3])];
				auto side = [&](const double *x) {
					return sign * ((b[0] - a[0]) * (x[1] - a[1]) - (b[1] - a[1]) * (x[0] - a[0]));
				};
				int out = 0;
				for (int j = 0; j < cnt; ++j) {
					const double *x = poly[cur][j], *y = poly[cur][(j + 1) % cnt];
					const double sx = side(x), sy = side(y);
					if (sx >= 0 && out < 12)
						poly[1 - cur][out][0] = x[0], poly[1 - cur][out++][1] = x[1];
					if (((sx >= 0) != (sy >= 0)) && out < 12) {
						const double t = sx / (sx - sy);
						poly[1 - cur][out][0] = x[0] + t * (y[0] - x[0]);
						poly[1 - cur][out++][1] = x[1] + t * (y[1] - x[1]);
					}
				}
				cnt = out, cur = 1 - cur;
			}
			// the gap at each corner of the clipped part (barycentric in the face)
			const double det = (fxy[2] - fxy[0]) * (fxy[5] - fxy[1]) - (fxy[4] - fxy[0]) * (fxy[3] - fxy[1]);
			if (!(std::fabs(det) > 0))
				return true; // a face seen edge-on in the projection: not measurable, refused
			double clippedMax = 0;
			for (int j = 0; j < cnt; ++j) {
				const double dx = poly[cur][j][0] - fxy[0], dy = poly[cur][j][1] - fxy[1];
				const double b1 = (dx * (fxy[5] - fxy[1]) - dy * (fxy[4] - fxy[0])) / det;
				const double b2 = ((fxy[2] - fxy[0]) * dy - (fxy[3] - fxy[1]) * dx) / det;
				clippedMax = std::max(clippedMax, std::fabs((1 - b1 - b2) * gap[0] + b1 * gap[1] + b2 * gap[2]));
			}
			if (clippedMax > eps)
				return true;
			kept = std::max(kept, float(clippedMax));
			return false;
		};
		for (size_t i = 0; i < faces; ++i) {
			if (ntri == 1) { // (no triangulation was run)
				if (faceTooFar(i, 0))
					return Failure::Distance;
				continue;
			}
			const int32_t *cq = &w.cornerQuery[3 * i];
			const int32_t under[4] = {w.job.queryTri[i], w.job.queryTri[faces + size_t(cq[0])],
			                          w.job.queryTri[faces + size_t(cq[1])],
			                          w.job.queryTri[faces + size_t(cq[2])]};
			for (int j = 0; j < 4; ++j) {
				const int32_t k = under[j];
				if (k < 0 || std::find(under, under + j, k) != under + j)
					continue;
				if (faceTooFar(i, k))
					return Failure::Distance;
			}
		}
		return Failure::None;
	}

	Failure retriangulate(int32_t s, Scratch &w, ChunkOut &o)
	{
		const int32_t fb = sfStart_[size_t(s)], fe = sfStart_[size_t(s) + 1];
		if (p_.cell[size_t(s)] == kInvalidCell) { // invalid input face: kept as it is
			for (int32_t i = fb; i < fe; ++i) {
				const int32_t f = sfFace_[size_t(i)];
				if (!t_.faceDropped[size_t(f)])
					emit(o, t_.T[3 * f], t_.T[3 * f + 1], t_.T[3 * f + 2], 7, false);
			}
			return Failure::None;
		}
		Vec3 N(0, 0, 0);
		for (int32_t i = fb; i < fe; ++i) {
			const int32_t f = sfFace_[size_t(i)];
			N += t_.faceNormal[size_t(f)] * t_.faceArea[size_t(f)];
		}
		if (!(N.Norm() > 0))
			return Failure::Fold;
		N.Normalize();
		bool unchanged = true;
		for (int32_t i = fb; i < fe; ++i) {
			const int32_t f = sfFace_[size_t(i)];
			if (!(t_.faceNormal[size_t(f)].dot(N) > 1e-6))
				return Failure::Fold; // the projection on the best-fit plane folds
			for (int k = 0; k < 3; ++k)
				unchanged = unchanged && keep_[size_t(t_.T[3 * f + k])];
		}
		if (unchanged) { // every vertex kept: the input faces are the triangulation
			for (int32_t i = fb; i < fe; ++i) {
				const int32_t f = sfFace_[size_t(i)];
				uint8_t bits = 0;
				for (int k = 0; k < 3; ++k)
					bits |= uint8_t(border_[size_t(3 * f + k)] << k);
				emit(o, t_.T[3 * f], t_.T[3 * f + 1], t_.T[3 * f + 2], bits, false);
				faceDev_[size_t(f)] = 0;
			}
			return Failure::None;
		}
		// kept ring vertices
		w.ringVerts.clear();
		w.ringVertStart.assign(1, 0);
		for (int32_t r = sfRingStart_[size_t(s)]; r < sfRingStart_[size_t(s) + 1]; ++r) {
			for (int32_t i = ringStart_[size_t(r)]; i < ringStart_[size_t(r) + 1]; ++i) {
				const int32_t v = t_.heFrom(ringHE_[size_t(i)]);
				if (keep_[size_t(v)])
					w.ringVerts.push_back(v);
			}
			if (int32_t(w.ringVerts.size()) - w.ringVertStart.back() < 3)
				return Failure::Ring;
			w.ringVertStart.push_back(int32_t(w.ringVerts.size()));
		}
		if (w.ringVertStart.size() < 2)
			return Failure::Ring;
		const size_t firstTri = o.tris.size() / 3;
		if (w.ringVertStart.size() == 2 && w.ringVerts.size() == 3) { // one triangle
			emit(o, w.ringVerts[0], w.ringVerts[1], w.ringVerts[2], 7, true);
		} else {
			// project on the plane orthogonal to the area-weighted normal (U x V = N)
			const Vec3 U = (std::fabs(N[0]) < 0.9 ? N ^ Vec3(1, 0, 0) : N ^ Vec3(0, 1, 0)).Normalize();
			const Vec3 V = N ^ U;
			const Vec3 origin = t_.pos(w.ringVerts[0]);
			w.job.xy.resize(2 * w.ringVerts.size());
			for (size_t i = 0; i < w.ringVerts.size(); ++i) {
				const Vec3 q = t_.pos(w.ringVerts[i]) - origin;
				w.job.xy[2 * i] = q.dot(U);
				w.job.xy[2 * i + 1] = q.dot(V);
			}
			w.job.ringStart = w.ringVertStart;
			w.job.queryXY.resize(2 * size_t(fe - fb));
			for (int32_t i = fb; i < fe; ++i) {
				const int32_t f = sfFace_[size_t(i)];
				const Vec3 c =
				    (t_.pos(t_.T[3 * f]) + t_.pos(t_.T[3 * f + 1]) + t_.pos(t_.T[3 * f + 2])) / 3.0 - origin;
				w.job.queryXY[2 * size_t(i - fb)] = c.dot(U);
				w.job.queryXY[2 * size_t(i - fb) + 1] = c.dot(V);
			}
			if (prm_.maxDistance > 0) { // and every vertex of its faces, once (see distanceCheck)
				if (w.vertQuery.size() != t_.nV)
					w.vertQuery.assign(t_.nV, -1);
				w.cornerQuery.resize(3 * size_t(fe - fb));
				int32_t next = 0;
				for (int32_t i = fb; i < fe; ++i)
					for (int k = 0; k < 3; ++k) {
						const int32_t v = t_.T[3 * sfFace_[size_t(i)] + k];
						int32_t &q = w.vertQuery[size_t(v)];
						if (q < 0) {
							q = next++;
							w.touched.push_back(v);
							const Vec3 p = t_.pos(v) - origin;
							w.job.queryXY.push_back(p.dot(U));
							w.job.queryXY.push_back(p.dot(V));
						}
						w.cornerQuery[3 * size_t(i - fb) + size_t(k)] = q;
					}
				for (const int32_t v : w.touched)
					w.vertQuery[size_t(v)] = -1;
				w.touched.clear();
			}
			if (!triangulateRings(w.job))
				return Failure::Ring;
			for (size_t k = 0; k < w.job.tris.size(); k += 3)
				emit(o, w.ringVerts[size_t(w.job.tris[k])], w.ringVerts[size_t(w.job.tris[k + 1])],
				     w.ringVerts[size_t(w.job.tris[k + 2])], w.job.constrained[k / 3], true);
		}
		// measured normal deviation; a triangle flipped (>90 deg) against an input face fails
		const size_t ntri = o.tris.size() / 3 - firstTri;
		std::vector<Vec3> &tn = w.triNormal;
		tn.resize(ntri);
		for (size_t k = 0; k < ntri; ++k) {
			const int32_t *v = &o.tris[3 * (firstTri + k)];
			Vec3 n = (t_.pos(v[1]) - t_.pos(v[0])) ^ (t_.pos(v[2]) - t_.pos(v[0]));
			if (!(n.Norm() > 0))
				return Failure::Ring;
			tn[k] = n / n.Norm();
		}
		w.covered.assign(ntri, 0);
		w.centroid.resize(ntri);
		w.ownDist2.assign(ntri, HUGE_VAL);
		for (size_t k = 0; k < ntri; ++k) {
			const int32_t *v = &o.tris[3 * (firstTri + k)];
			w.centroid[k] = (t_.pos(v[0]) + t_.pos(v[1]) + t_.pos(v[2])) / 3.0;
		}
		auto faceDist2 = [&](const Vec3 &p, int32_t f) {
			return pointTriangleDistance2(p, t_.pos(t_.T[3 * f]), t_.pos(t_.T[3 * f + 1]),
			                              t_.pos(t_.T[3 * f + 2]));
		};
		for (int32_t i = fb; i < fe; ++i) {
			const int32_t f = sfFace_[size_t(i)];
			const int32_t k = ntri == 1 ? 0 : w.job.queryTri[size_t(i - fb)];
			if (k < 0)
				continue;
			const double d = angleDeg(t_.faceNormal[size_t(f)], tn[size_t(k)]);
			if (d > 90 || d > devLimit_)
				return Failure::Deviation;
			faceDev_[size_t(f)] = float(d);
			w.covered[size_t(k)] = 1;
			w.ownDist2[size_t(k)] = std::min(w.ownDist2[size_t(k)], faceDist2(w.centroid[size_t(k)], f));
		}
		if (prm_.maxDistance > 0) {
			const Failure far = distanceCheck(s, fb, fe, N, firstTri, w, o);
			if (far != Failure::None)
				return far;
		}
		// a triangle that covers no input face centroid is checked against the faces of the
		// superface around its corners
		for (size_t k = 0; k < ntri; ++k) {
			if (w.covered[k])
				continue;
			for (int c = 0; c < 3; ++c) {
				const int32_t v = o.tris[3 * (firstTri + k) + size_t(c)];
				for (int32_t q = t_.vfStart[size_t(v)]; q < t_.vfStart[size_t(v) + 1]; ++q) {
					const int32_t f = t_.vfFace[size_t(q)];
					if (p_.label[size_t(f)] != s)
						continue;
					if (t_.faceNormal[size_t(f)].dot(tn[k]) < 0)
						return Failure::Ring;
					w.ownDist2[k] = std::min(w.ownDist2[k], faceDist2(w.centroid[k], f));
				}
			}
		}
		// the input surface nearest to a triangle's centroid must not face away from it (as at a
		// thin part, where a straightened border can bring one side next to the other side)
		for (size_t k = 0; k < ntri; ++k) {
			const double r2 = w.ownDist2[k];
			if (!(r2 > 0) || !std::isfinite(r2))
				continue; // on its own faces (or nothing to compare with)
			// (the query box is capped at ~16^3 cells: a farther other side is not looked for,
			// which bounds the time on strongly curved superfaces of very fine meshes)
			const double r = std::min(std::sqrt(r2), 8 * t_.grid.cell);
			const Vec3 &c = w.centroid[k];
			// nearest face facing away (normals first: distances only for those)
			double away = r * r * (1 - 1e-9);
			bool anyAway = false;
			t_.grid.forBoxFacingAway(c - Vec3(r, r, r), c + Vec3(r, r, r), &tn[k], [&](int32_t g) {
				if (t_.faceNormal[size_t(g)].dot(tn[k]) < 0) {
					const double d2 = faceDist2(c, g);
					if (d2 < away)
						away = d2, anyAway = true;
				}
			});
			if (!anyAway)
				continue;
			// flipped unless a face facing it is as near (ties: an edge or vertex both touch)
			const double ra = std::sqrt(away) * (1 + 1e-9);
			bool facing = false;
			t_.grid.forBox(c - Vec3(ra, ra, ra), c + Vec3(ra, ra, ra), [&](int32_t g) {
				if (!facing && t_.faceNormal[size_t(g)].dot(tn[k]) >= 0)
					facing = faceDist2(c, g) <= away * (1 + 1e-9);
			});
			if (!facing)
				return Failure::Ring;
		}
		++o.retriangulated;
		return Failure::None;
	}
	double devLimit_ = 180;
	Stopwatch clock_;
	double tolerance_ = 0;
	double mergeDistance_ = 0;

	// Rolls back what a failed superface emitted.
	static void truncate(ChunkOut &o, size_t triCount)
	{
		o.tris.resize(3 * triCount);
		o.triBorder.resize(triCount);
	}

	// ------------------------------------------------------------- validity of the whole level
	// An edge used by more triangles than in the input, or twice in the same direction where the
	// input had it right, comes from a re-triangulated superface: fail those superfaces.
	void checkEdges()
	{
		// only an edge with both ends on new triangles can be a new problem: those edges, one
		// record per triangle side (its larger vertex, triangle, direction), grouped by the
		// smaller vertex (counted, then filled), each group then sorted by the larger one
		const size_t nt = triBorder_.size();
		std::vector<uint8_t> onNew(t_.nV, 0);
		for (size_t tri = 0; tri < nt; ++tri)
			if (triBorder_[tri] & kNewTriangle)
				for (size_t c = 0; c < 3; ++c)
					onNew[size_t(tris_[3 * tri + c])] = 1;
		struct Side {
			int32_t hi;  ///< the edge's larger vertex
			int32_t tri; ///< 2 * triangle + 1 if it runs from the larger vertex to the smaller
		};
		std::vector<int32_t> start(t_.nV + 1, 0);
		auto forSides = [&](auto fn) {
			for (size_t tri = 0; tri < nt; ++tri) {
				const int32_t *v = &tris_[3 * tri];
				for (int c = 0; c < 3; ++c) {
					const int32_t a = v[c], b = v[c == 2 ? 0 : c + 1];
					if (onNew[size_t(a)] && onNew[size_t(b)])
						fn(std::min(a, b), std::max(a, b), int32_t(2 * tri) + (a > b ? 1 : 0));
				}
			}
		};
		forSides([&](int32_t lo, int32_t, int32_t) { ++start[size_t(lo) + 1]; });
		for (size_t v = 0; v < t_.nV; ++v)
			start[v + 1] += start[v];
		std::vector<Side> side(static_cast<size_t>(start[t_.nV]));
		{
			std::vector<int32_t> fill(start.begin(), start.end() - 1);
			forSides([&](int32_t lo, int32_t hi, int32_t tri) { side[size_t(fill[size_t(lo)]++)] = Side{hi, tri}; });
		}
		std::vector<uint8_t> bad(p_.count(), 0);
		for (size_t v = 0; v < t_.nV; ++v) {
			Side *gb = side.data() + start[v], *ge = side.data() + start[v + 1];
			if (ge - gb < 2)
				continue;
			if (ge - gb <= 16) { // (insertion sort: a vertex has few edges, usually)
				for (Side *i = gb + 1; i < ge; ++i)
					for (Side *j = i; j > gb && j->hi < (j - 1)->hi; --j)
						std::swap(*j, *(j - 1));
			} else {
				std::sort(gb, ge, [](const Side &x, const Side &y) { return x.hi < y.hi; });
			}
			for (Side *i = gb; i < ge;) {
				Side *j = i + 1;
				while (j < ge && j->hi == i->hi)
					++j;
				const size_t cnt = size_t(j - i);
				bool anyNew = false;
				for (Side *q = i; q < j; ++q)
					anyNew = anyNew || (triBorder_[size_t(q->tri >> 1)] & kNewTriangle);
				if (anyNew && cnt >= 2) {
					const bool sameDir = cnt == 2 && (i->tri & 1) == ((i + 1)->tri & 1);
					if (cnt > 2 || sameDir) {
						int inputCnt = 0, inputFwd = 0;
						const int32_t a = int32_t(v), b = i->hi;
						for (int32_t q = t_.vfStart[size_t(a)]; q < t_.vfStart[size_t(a) + 1]; ++q)
							for (int k = 0; k < 3; ++k) {
								const int32_t h = 3 * t_.vfFace[size_t(q)] + k;
								if (t_.heFrom(h) == a && t_.heTo(h) == b)
									++inputCnt, ++inputFwd;
								else if (t_.heFrom(h) == b && t_.heTo(h) == a)
									++inputCnt;
							}
						const bool inputSameDir = inputCnt == 2 && (inputFwd == 0 || inputFwd == 2);
						if ((cnt > 2 && int(cnt) > inputCnt) || (sameDir && !inputSameDir))
							for (Side *q = i; q < j; ++q) {
								const size_t tri = size_t(q->tri >> 1);
								if (triBorder_[tri] & kNewTriangle)
									bad[size_t(triSf_[tri])] = 1;
							}
					}
				}
				i = j;
			}
		}
		for (size_t s = 0; s < bad.size(); ++s)
			if (bad[s])
				failed_.emplace_back(int32_t(s), Failure::Ring), ++failedTris_;
	}

	// ---------------------------------------------------------------------------- one round
	// A full round rebuilds every superface. A patch round (after fallbacks) rebuilds only the
	// superfaces whose faces changed, that failed, or that touch a vertex whose border degree or
	// junction status changed; every other superface has the same rings and kept vertices as in
	// the previous round (borders only get added by fallbacks), so its triangles are copied.
	void buildOnce(bool patch)
	{
		failed_.clear(), failedTris_ = 0;
		// (freed, not cleared: they are rebuilt from the chunks, which hold this round's triangles
		// meanwhile)
		release(tris_), release(triSf_), release(triBorder_);
		retriangulated_ = 0;
		if (!patch) // (a patch round's are set by applyFallbacks)
			groupFaces();
		findBorders(patch);
		dirty_.assign(p_.count(), patch ? 0 : 1);
		if (patch) { // split, failed, or around a changed vertex
			for (int32_t f : relabeled_)
				dirty_[size_t(p_.label[size_t(f)])] = 1;
			for (int32_t f : failedFace_)
				dirty_[size_t(p_.label[size_t(f)])] = 1;
			for (int32_t v : changedList_)
				for (int32_t q = t_.vfStart[size_t(v)]; q < t_.vfStart[size_t(v) + 1]; ++q)
					dirty_[size_t(p_.label[size_t(t_.vfFace[size_t(q)])])] = 1;
		}
		broken_.assign(p_.count(), 0);
		makeChunks();
		// rings traced per chunk (a superface's walk only marks its own half-edges visited, and
		// reads only its own), then concatenated in superface order
		forEachChunk([&](size_t c, Scratch &) {
			ChunkOut &o = chunks_[c];
			for (int32_t s = chunkStart_[c]; s < chunkStart_[c + 1]; ++s) {
				const size_t ringsBefore = o.ringStart.size(), heBefore = o.ringHE.size();
				if (dirty_[size_t(s)] && !traceRings(s, o.ringHE, o.ringStart)) {
					for (size_t i = heBefore; i < o.ringHE.size(); ++i)
						border_[size_t(o.ringHE[i])] &= uint8_t(~kVisited);
					o.ringStart.resize(ringsBefore), o.ringHE.resize(heBefore);
					broken_[size_t(s)] = 1;
				}
				o.sfRings.push_back(int32_t(o.ringStart.size() - ringsBefore));
			}
		});
		size_t nRings = 0, nHE = 0;
		for (const ChunkOut &o : chunks_)
			nRings += o.ringStart.size(), nHE += o.ringHE.size();
		ringHE_.clear(), ringStart_.clear();
		ringHE_.reserve(nHE), ringStart_.reserve(nRings + 1);
		sfRingStart_.assign(p_.count() + 1, 0);
		for (size_t c = 0; c < chunks_.size(); ++c) {
			ChunkOut &o = chunks_[c];
			const int32_t heBase = int32_t(ringHE_.size());
			for (int32_t s = chunkStart_[c]; s < chunkStart_[c + 1]; ++s)
				sfRingStart_[size_t(s) + 1] = sfRingStart_[size_t(s)] + o.sfRings[size_t(s - chunkStart_[c])];
			for (const int32_t r : o.ringStart)
				ringStart_.push_back(heBase + r);
			ringHE_.insert(ringHE_.end(), o.ringHE.begin(), o.ringHE.end());
			release(o.ringHE), release(o.ringStart), release(o.sfRings);
		}
		ringStart_.push_back(int32_t(ringHE_.size()));
		for (const int32_t h : ringHE_) // (every half-edge a walk marked)
			border_[size_t(h)] &= uint8_t(~kVisited);
		collectAndSimplifyPieces(patch);
		// (a patch round separates the recomputed pieces among themselves; one that straightens
		// onto an unchanged chain is caught by checkEdges and falls back)
		separateParallelChains();
		out_.stats.secondsBorders += clock_.lap();
		cache_.assign(p_.count(), Cached());
		// the chunks build the rebuilt superfaces; an unchanged one (not dirty) is taken from the
		// previous round's arrays when the chunks are concatenated (cache_ then holds its previous
		// range)
		forEachChunk([&](size_t c, Scratch &w) {
			for (int32_t sf = chunkStart_[c]; sf < chunkStart_[c + 1]; ++sf)
				buildSuperface(sf, w, chunks_[c]);
		});
		release(ringHE_), release(ringStart_), release(sfRingStart_), release(pieces_);
		size_t nt = 0, rebuilt = 0;
		bool failures = false;
		for (const ChunkOut &o : chunks_)
			rebuilt += o.triBorder.size(), failures = failures || !o.failed.empty();
		nt = rebuilt;
		for (size_t sf = 0; sf < p_.count(); ++sf)
			if (!dirty_[sf])
				nt += size_t(cache_[sf].triEnd - cache_[sf].triBegin);
		liveTris_ = nt;
		// A patch round with failures is followed by another round: the rebuilt superfaces are
		// appended to the previous round's triangles, which the others still point into (no
		// copy of the whole level, no triangle -> superface array), while they fit in the room
		// left by the last concatenation and the dropped triangles stay under half of the live
		// ones. Otherwise the round's triangles are concatenated in superface order (what the
		// whole-level check and the output use), with a quarter more room if rounds follow.
		const size_t stored = prevTriBorder_.size() + rebuilt;
		if (patch && failures && 2 * stored <= 3 * nt && stored <= prevTriBorder_.capacity() &&
		    3 * stored <= prevTris_.capacity()) {
			tris_.swap(prevTris_), triBorder_.swap(prevTriBorder_), release(triSf_);
			for (size_t c = 0; c < chunks_.size(); ++c) {
				ChunkOut &o = chunks_[c];
				for (int32_t sf = chunkStart_[c]; sf < chunkStart_[c + 1]; ++sf) {
					Cached &cc = cache_[size_t(sf)];
					if (!dirty_[size_t(sf)]) { // (its range is in these arrays already)
						retriangulated_ += cc.retriangulated;
						continue;
					}
					const int32_t begin = int32_t(triBorder_.size());
					tris_.insert(tris_.end(), o.tris.begin() + 3 * cc.triBegin, o.tris.begin() + 3 * cc.triEnd);
					triBorder_.insert(triBorder_.end(), o.triBorder.begin() + cc.triBegin,
					                  o.triBorder.begin() + cc.triEnd);
					cc.triEnd = begin + (cc.triEnd - cc.triBegin), cc.triBegin = begin;
				}
				failed_.insert(failed_.end(), o.failed.begin(), o.failed.end()), failedTris_ += o.failedTris;
				retriangulated_ += o.retriangulated;
				ChunkOut().swap(o);
			}
			release(prevCache_), prevOf_.clear(); // (the ids' memory serves the next rounds)
			out_.stats.secondsTriangulation += clock_.lap();
			return;
		}
		// concatenate in superface order (offsets of rebuilt superfaces in cache_ were chunk-
		// relative), freeing each chunk once appended; the fallbacks' arrays go first (this is
		// the level's peak, and it is usually its last round)
		release(split_), release(remap_), release(spareStart_), release(spareFace_);
		release(spareCell_), release(spareOrigin_);
		const size_t room = failures ? nt + nt / 4 : nt;
		tris_.reserve(3 * room), triSf_.reserve(nt), triBorder_.reserve(room);
		for (size_t c = 0; c < chunks_.size(); ++c) {
			ChunkOut &o = chunks_[c];
			for (int32_t sf = chunkStart_[c]; sf < chunkStart_[c + 1]; ++sf) {
				Cached &cc = cache_[size_t(sf)];
				const std::vector<int32_t> &srcTris = dirty_[size_t(sf)] ? o.tris : prevTris_;
				const std::vector<uint8_t> &srcBorder = dirty_[size_t(sf)] ? o.triBorder : prevTriBorder_;
				const int32_t begin = int32_t(triBorder_.size());
				tris_.insert(tris_.end(), srcTris.begin() + 3 * cc.triBegin, srcTris.begin() + 3 * cc.triEnd);
				triBorder_.insert(triBorder_.end(), srcBorder.begin() + cc.triBegin,
				                  srcBorder.begin() + cc.triEnd);
				cc.triEnd = begin + (cc.triEnd - cc.triBegin), cc.triBegin = begin;
				triSf_.insert(triSf_.end(), size_t(cc.triEnd - cc.triBegin), sf);
				if (!dirty_[size_t(sf)])
					retriangulated_ += cc.retriangulated;
			}
			failed_.insert(failed_.end(), o.failed.begin(), o.failed.end()), failedTris_ += o.failedTris;
			retriangulated_ += o.retriangulated;
			ChunkOut().swap(o);
		}
		release(prevCache_), prevOf_.clear();
		release(prevTris_), release(prevTriBorder_);
		out_.stats.secondsTriangulation += clock_.lap();
		if (failed_.empty())
			checkEdges();
	}

	// One superface of a round: copied from the previous round when nothing around it changed,
	// else its border is compared with the previous round's, else it is re-triangulated.
	void buildSuperface(int32_t s, Scratch &w, ChunkOut &o)
	{
		const size_t before = o.triBorder.size();
		const size_t retriBefore = o.retriangulated;
		Cached &c = cache_[size_t(s)];
		if (!dirty_[size_t(s)]) { // unchanged since the previous round: its range there (the
			// triangles are copied with the concatenation, its faces keep their deviations)
			c = prevCache_[size_t(prevOf_[size_t(s)])];
			return;
		}
		c.faceCount = sfStart_[size_t(s) + 1] - sfStart_[size_t(s)];
		Failure f = Failure::None;
		if (broken_[size_t(s)] || !reuse(s, c, w, o)) {
			for (int32_t i = sfStart_[size_t(s)]; i < sfStart_[size_t(s) + 1]; ++i) {
				faceDev_[size_t(sfFace_[size_t(i)])] = -1.0f; // (measured again below)
				if (!faceGap_.empty())
					faceGap_[size_t(sfFace_[size_t(i)])] = 0.0f;
			}
			f = broken_[size_t(s)] ? Failure::Fold : retriangulate(s, w, o);
		}
		if (f != Failure::None) {
			o.failedTris += std::max<size_t>(1, o.triBorder.size() - before);
			truncate(o, before);
			o.failed.emplace_back(s, f);
		}
		c.ok = f == Failure::None;
		c.retriangulated = o.retriangulated > retriBefore;
		c.triBegin = int32_t(before);
		c.triEnd = int32_t(o.triBorder.size());
	}

	// What the next round may reuse (before the fallbacks change the labels).
	void keepForReuse()
	{
		prevCache_.swap(cache_);
		prevTris_.swap(tris_);
		prevTriBorder_.swap(triBorder_);
	}

	// ---------------------------------------------------------- reuse across fallback rounds
	// A superface with the same faces (its first face's previous superface, and as many faces:
	// partitions only get finer between rounds) and the same border between kept vertices as in
	// the previous round has a valid triangulation already: copy it instead of recomputing (a
	// fallback only changes a few superfaces).
	struct Cached {
		int32_t faceCount = 0;
		int32_t triBegin = 0, triEnd = 0;
		bool ok = false, retriangulated = false;
	};
	std::vector<Cached> prevCache_, cache_;
	std::vector<int32_t> prevOf_; // per superface: its (or its parent's) id in the previous round
	// applyFallbacks' arrays, kept for the next rounds
	std::vector<uint8_t> split_;
	std::vector<int32_t> remap_, spareStart_, spareFace_;
	std::vector<CellKey> spareCell_;
	std::vector<int8_t> spareOrigin_;
	std::vector<int32_t> prevTris_;
	std::vector<uint8_t> prevTriBorder_;

	static uint64_t directedEdge(int32_t a, int32_t b)
	{
		return uint64_t(uint32_t(a)) << 32 | uint32_t(b);
	}

	// The previous round's triangles of a superface are reused when its faces are the same and
	// its border edges (the triangles' border-flagged edges, directed with the superface on their
	// left) are this round's ring edges between kept vertices: every successful triangulation
	// has exactly its rings' edges as border edges, so this compares the kept outlines without
	// storing them (as a multiset: rings are traced in a fixed order, but a different start or
	// ring order would describe the same domain).
	bool reuse(int32_t s, const Cached &now, Scratch &w, ChunkOut &o)
	{
		if (prevCache_.empty())
			return false;
		const int32_t ps = prevOf_[size_t(s)];
		const Cached &c = prevCache_[size_t(ps)];
		if (!c.ok || c.faceCount != now.faceCount) // (same count, same faces: see above)
			return false;
		w.edgesBefore.clear();
		for (int32_t k = c.triBegin; k < c.triEnd; ++k)
			for (int e = 0; e < 3; ++e)
				if (prevTriBorder_[size_t(k)] & (1u << e))
					w.edgesBefore.push_back(directedEdge(prevTris_[3 * size_t(k) + size_t(e)],
					                                     prevTris_[3 * size_t(k) + size_t(e + 1) % 3]));
		w.edgesNow.clear();
		for (int32_t r = sfRingStart_[size_t(s)]; r < sfRingStart_[size_t(s) + 1]; ++r) {
			int32_t first = -1, prev = -1;
			for (int32_t i = ringStart_[size_t(r)]; i < ringStart_[size_t(r) + 1]; ++i) {
				const int32_t v = t_.heFrom(ringHE_[size_t(i)]);
				if (!keep_[size_t(v)])
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
		if (w.edgesNow != w.edgesBefore)
			return false;
		copyPrevious(c, o);
		return true;
	}

	void copyPrevious(const Cached &c, ChunkOut &o)
	{
		o.tris.insert(o.tris.end(), prevTris_.begin() + 3 * c.triBegin, prevTris_.begin() + 3 * c.triEnd);
		o.triBorder.insert(o.triBorder.end(), prevTriBorder_.begin() + c.triBegin,
		                   prevTriBorder_.begin() + c.triEnd);
		o.retriangulated += c.retriangulated; // (its faces keep their deviations)
	}

	// A failed superface first has its border locked (no straightening, no merging) - after a
	// deviation failure, first its chains are straightened and merged again with a quarter of the
	// tolerances, up to kMaxTolSteps times; if it still fails, it is split into its children of
	// the next finer level; a single input face that fails gets its vertices locked (it is then
	// kept as it is). A fold of the projection skips to the split.
	void applyFallbacks()
	{
		// sfStart_/sfFace_ are those of the round that just failed: labels have not changed yet
		std::vector<uint8_t> &split = split_;
		split.assign(p_.count(), 0);
		relabeled_.clear(), failedFace_.clear(), lockedNow_.clear(), retightened_.clear();
		auto lock = [&](int32_t v) {
			if (!extraLock_[size_t(v)]) {
				extraLock_[size_t(v)] = 1;
				lockedNow_.push_back(v);
			}
		};
		for (const auto &sf : failed_) {
			const int32_t s = sf.first;
			const int32_t fb = sfStart_[size_t(s)], fe = sfStart_[size_t(s) + 1];
			failedFace_.push_back(sfFace_[size_t(fb)]);
			bool allLocked = true;
			for (int32_t i = fb; i < fe; ++i)
				for (int k = 0; k < 3; ++k) {
					const int32_t h = 3 * sfFace_[size_t(i)] + k;
					if (border_[size_t(h)] && !junction_[size_t(t_.heFrom(h))])
						allLocked = false;
				}
			const int step = tolStep_[size_t(sfFace_[size_t(fb)])];
			if (fe - fb > 1 && sf.second == Failure::Deviation && !allLocked && step < kMaxTolSteps) {
				// its chains are straightened and merged again with a quarter of the tolerances
				for (int32_t i = fb; i < fe; ++i) {
					const int32_t f = sfFace_[size_t(i)];
					tolStep_[size_t(f)] = uint8_t(step + 1);
					for (int k = 0; k < 3; ++k)
						if (border_[size_t(3 * f + k)])
							retightened_.push_back(t_.heFrom(3 * f + k));
				}
			} else if (fe - fb == 1 ||
			           (sf.second != Failure::Fold && sf.second != Failure::Distance && !allLocked)) {
				for (int32_t i = fb; i < fe; ++i)
					for (int k = 0; k < 3; ++k) {
						const int32_t h = 3 * sfFace_[size_t(i)] + k;
						if (border_[size_t(h)])
							lock(t_.heFrom(h));
					}
				if (fe - fb == 1)
					for (int k = 0; k < 3; ++k)
						lock(t_.T[3 * sfFace_[size_t(fb)] + k]);
			} else {
				split[size_t(s)] = 1;
			}
		}
		// split: the faces of a split superface take the superface of their finer partition
		const int finest = int(finer_.size()) - 1;
		const size_t base = p_.count();
		std::vector<int32_t> childMap; // finer label -> new label (per origin level)
		std::vector<int32_t> touched;
		std::vector<int32_t> parentOf; // new superface base + i -> the superface split into it
		for (size_t s = 0; s < base; ++s) {
			if (!split[s])
				continue;
			const int o = p_.origin[s];
			for (int32_t i = sfStart_[s]; i < sfStart_[s + 1]; ++i) {
				const int32_t f = sfFace_[size_t(i)];
				int32_t id;
				CellKey cell;
				int8_t origin;
				if (o == -1 || o >= finest) { // children are the input faces
					id = -1;
					Cell c;
					const Vec3 &n = t_.faceNormal[size_t(f)];
					const double nn[3] = {n[0], n[1], n[2]};
					normalToCell(nn, p_.level, c);
					cell = packCell(c);
					origin = -1;
				} else {
					// children: the parts of a cross-cell union, or the next finer level's
					const bool parts = o <= -2;
					const Partition &fp = finer_[size_t(parts ? mergedLevel(int8_t(o)) : o + 1)];
					const std::vector<int32_t> &label = parts ? fp.partLabel : fp.label;
					const std::vector<CellKey> &cells = parts ? fp.partCell : fp.cell;
					const std::vector<int8_t> &origins = parts ? fp.partOrigin : fp.origin;
					const int32_t child = label[size_t(f)];
					if (childMap.size() < cells.size())
						childMap.resize(cells.size(), -1);
					id = childMap[size_t(child)];
					CellKey k = cells[size_t(child)];
					for (int l = fp.level; l > p_.level && k != kInvalidCell; --l)
						k = parentKey(k);
					cell = k;
					origin = origins[size_t(child)];
					if (id < 0) {
						id = int32_t(p_.cell.size());
						childMap[size_t(child)] = id;
						touched.push_back(child);
						p_.cell.push_back(cell);
						p_.origin.push_back(origin);
						parentOf.push_back(int32_t(s));
					}
				}
				if (id < 0) {
					id = int32_t(p_.cell.size());
					p_.cell.push_back(cell);
					p_.origin.push_back(origin);
					parentOf.push_back(int32_t(s));
				}
				p_.label[size_t(f)] = id;
				relabeled_.push_back(f);
			}
			for (int32_t c : touched)
				childMap[size_t(c)] = -1;
			touched.clear();
		}
		// Canonical ids (by first face, see Partition::label: a superface not split keeps
		// its first face, a new one's is the first of its faces in its parent's ascending range),
		// each superface's id in the round that failed or the id of the superface split into it
		// (prevOf_), and the next round's faces per superface (what groupFaces gives): runs of
		// superfaces not split keep their block of faces, the children of a split superface take
		// theirs from its range. (The arrays of earlier rounds are reused: fresh ones of a few MB
		// each round cost more in page faults than the work.)
		const size_t temps = p_.count() - base;
		std::vector<int32_t> childSize(temps, 0); // (then: where its next face goes)
		std::vector<std::pair<int32_t, int32_t>> firsts; // (first face, new superface)
		size_t nSplit = 0;
		for (size_t s = 0; s < base; ++s) {
			if (!split[s])
				continue;
			++nSplit;
			for (int32_t i = sfStart_[s]; i < sfStart_[s + 1]; ++i) {
				const int32_t f = sfFace_[size_t(i)];
				const size_t c = size_t(p_.label[size_t(f)]) - base;
				if (childSize[c]++ == 0)
					firsts.emplace_back(f, int32_t(base + c));
			}
		}
		if (nSplit == 0) { // (labels, cells, origins and face lists stay)
			prevOf_.resize(base);
			for (size_t o = 0; o < base; ++o)
				prevOf_[o] = int32_t(o);
			return;
		}
		std::sort(firsts.begin(), firsts.end());
		const size_t ns = base - nSplit + temps;
		std::vector<int32_t> &remap = remap_, &start = spareStart_, &face = spareFace_;
		std::vector<CellKey> &cell = spareCell_;
		std::vector<int8_t> &origin = spareOrigin_;
		remap.assign(p_.count(), -1);
		cell.clear(), origin.clear(), prevOf_.clear();
		cell.reserve(ns), origin.reserve(ns), prevOf_.reserve(ns);
		start.resize(ns + 1), face.resize(t_.nF);
		start[0] = 0;
		auto add = [&](int32_t old, int32_t prev, int32_t faces) {
			const int32_t n = int32_t(cell.size());
			remap[size_t(old)] = n;
			cell.push_back(p_.cell[size_t(old)]);
			origin.push_back(p_.origin[size_t(old)]);
			prevOf_.push_back(prev);
			start[size_t(n) + 1] = start[size_t(n)] + faces;
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
				addChildrenBefore(sfFace_[size_t(sfStart_[o])]);
				add(int32_t(o), int32_t(o), sfStart_[o + 1] - sfStart_[o]);
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
			std::copy(sfFace_.begin() + sfStart_[o], sfFace_.begin() + sfStart_[e],
			          face.begin() + start[size_t(remap[o])]);
			o = e;
		}
		for (size_t c = 0; c < temps; ++c)
			childSize[c] = start[size_t(remap[base + c])];
		for (size_t s = 0; s < base; ++s)
			if (split[s])
				for (int32_t i = sfStart_[s]; i < sfStart_[s + 1]; ++i) {
					const int32_t f = sfFace_[size_t(i)];
					face[size_t(childSize[size_t(p_.label[size_t(f)]) - base]++)] = f;
				}
		parallelRanges(t_.nF, threads_, [&](size_t b, size_t e, size_t) {
			for (size_t f = b; f < e; ++f)
				p_.label[f] = remap[size_t(p_.label[f])];
		});
		p_.cell.swap(cell), p_.origin.swap(origin);
		sfStart_.swap(start), sfFace_.swap(face);
	}

	// Frees what only the rounds needed, before the level's output is allocated (the level's
	// peak memory is otherwise here).
	void releaseRounds()
	{
		release(sfStart_), release(sfFace_), release(border_), release(degree_);
		release(junction_), release(keep_), release(extraLock_), release(changed_);
		release(changedList_), release(relabeled_), release(failedFace_), release(lockedNow_);
		release(tolStep_), release(retightened_);
		release(dirty_), release(ringHE_), release(ringStart_), release(sfRingStart_);
		release(broken_), release(pieces_), release(failed_);
		release(scratch_), release(chunkStart_), release(chunks_);
		release(prevCache_), release(cache_), release(prevOf_), release(prevTris_);
		release(prevTriBorder_), release(split_), release(remap_), release(spareStart_);
		release(spareFace_), release(spareCell_), release(spareOrigin_);
	}

	// ---------------------------------------------------------------------------- output
	void finish(size_t fallbacks)
	{
		releaseRounds();
		std::vector<int32_t> remap(t_.nV, -1);
		for (int32_t v : tris_)
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
			for (size_t k = 0; k < 3; ++k)
				out_.positions[3 * o + k] = t_.P[3 * v + k];
		}
		for (int32_t &v : tris_)
			v = remap[size_t(v)];
		release(remap);
		out_.triangles = std::move(tris_);
		out_.superface = std::move(triSf_);
		out_.inputSuperface = p_.label;
		for (uint8_t &b : triBorder_)
			b &= kBorderBits;
		out_.borderEdges = std::move(triBorder_);

		LevelStats &st = out_.stats;
		st.level = p_.level;
		st.boundDeg = levelBoundDeg(p_.level);
		st.faces = out_.triangles.size() / 3;
		st.vertices = size_t(next);
		st.superfaces = p_.count();
		st.fallbacks = fallbacks;
		st.retriangulated = retriangulated_;
		double maxDev = 0, sum = 0, area = 0;
		size_t unmeasured = 0;
		for (size_t f = 0; f < t_.nF; ++f) {
			if (!t_.faceValid[f])
				continue;
			if (faceDev_[f] < 0) {
				++unmeasured;
				continue;
			}
			maxDev = std::max(maxDev, double(faceDev_[f]));
			sum += double(faceDev_[f]) * t_.faceArea[f];
			area += t_.faceArea[f];
		}
		st.maxNormalDevDeg = maxDev;
		st.meanNormalDevDeg = area > 0 ? sum / area : 0;
		st.unmeasuredFaces = unmeasured;
		if (!faceGap_.empty())
			st.maxDistance = double(*std::max_element(faceGap_.begin(), faceGap_.end()));
	}
};

} // namespace

void buildLevelGeometry(const Topology &topo, const Params &params,
                        const std::vector<Partition> &finer, Partition &p, LevelMesh &out,
                        size_t faceLimit)
{
	LevelBuilder(topo, params, finer, p, out, faceLimit).run();
}

} // namespace detail
} // namespace gausslod
