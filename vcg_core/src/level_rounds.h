// 2.2.2-2.4 The rounds of one level (level_geometry.cpp) and its output (level_output.cpp):
// internal to buildLevelGeometry.
#pragma once

#include "level_passes.h"

#include <atomic>
#include <chrono>
#include <mutex>

namespace gausslod {
namespace detail {

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
	bool takeExact(const TriangulationInput &in, int32_t s, Scratch &w, ChunkOut &o);
	void carryExact();
	bool appendPatch(size_t rebuilt, size_t live);
	void concatenate(size_t live, bool failures);
	void keepForReuse();
	void releaseRounds();
	void finish(size_t fallbacks);
	void fillStats(size_t fallbacks, size_t vertices);
};

} // namespace detail
} // namespace gausslod
