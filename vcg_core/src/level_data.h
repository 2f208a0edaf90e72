// The plain structs that carry one level's state between its passes (level_passes.h): limits,
// failures, borders, rings, a chunk's output, the faces' measures and the reuse cache.
#pragma once

#include "engine.h"

#include <utility>
#include <vector>

namespace gausslod {
namespace detail {

constexpr int kMaxRounds = 64;
// A superface that fails with straightened borders gets them straightened again with a quarter
// of the tolerances (kTolShift = 2), up to this many times, before its border vertices are locked.
constexpr int kMaxTolSteps = 2;
constexpr int kTolShift = 2;
// With the distance tolerance, a superface failing inside gets inside vertices inserted and is
// triangulated again, up to this many times, before its fallbacks (superface_triangulation.cpp).
constexpr int kMaxInsertPasses = 8;

/// The limits of one level, derived once from Params (levelLimits, level_geometry.cpp).
struct LevelLimits {
	double tolerance = 0;      ///< straightening tolerance (2.3.1), at least `exact`
	double mergeDistance = 0;  ///< vicinity merge distance (2.3.2); 0 = no merging
	double devLimitDeg = 180;  ///< normal-deviation limit of the level; 180 = none
	double maxDistance = 0;    ///< distance tolerance; 0 = none
	bool boundIsLimit = false; ///< a superface whose distance bound exceeds it fails too
	double maxTexError = 0;    ///< texture-coordinate limit (UV units); 0 = none or no UVs
	int finest = 0;            ///< the finest level (Params::maxLevel - 1)
	double exact = 0;          ///< below this, a vertex counts as exactly on its chain
};
LevelLimits levelLimits(const Params &params, double diagonal, int level, bool hasUV);

/// Why a superface failed: Fold (its projection folds, or its rings could not be traced) goes
/// straight to the split; Deviation (an input face deviates from its new triangle more than the
/// limit, or a removed border vertex is beyond the distance tolerance) first retries with
/// tighter straightening; Distance (an input face beyond the distance tolerance) goes straight
/// to the split; Ring (anything else) first locks the border.
enum class Failure : uint8_t { None, Ring, Fold, Deviation, Distance };
using FailedList = std::vector<std::pair<int32_t, Failure>>; ///< (superface, why)

/// Superface -> its input faces (CSR), ascending.
struct SuperfaceFaces {
	std::vector<int32_t> start, face;
	int32_t begin(int32_t s) const { return start[size_t(s)]; }
	int32_t end(int32_t s) const { return start[size_t(s) + 1]; }
};

/// Border state of a round (2.2.2) and the vertices the simplified borders keep (2.3).
struct Borders {
	static constexpr uint8_t kVisited = 2;
	std::vector<uint8_t> border;      ///< per half-edge: 1 = border (| kVisited while tracing)
	std::vector<int32_t> degree;      ///< border edges per vertex
	std::vector<uint8_t> junction;    ///< per vertex: a chain ends here
	std::vector<uint8_t> keep;        ///< per vertex: kept by the simplified borders
	std::vector<uint8_t> changed;     ///< patch round: degree or junction status changed
	std::vector<int32_t> changedList; ///< the vertices marked in `changed`
};

/// What the fallbacks of a level accumulate, and what the last ones changed (the inputs of the
/// next, patch, round).
struct FallbackState {
	std::vector<uint8_t> extraLock;   ///< per vertex: locked by a fallback
	std::vector<uint8_t> tolStep;     ///< per face: its superface's tolerances were divided by 4
	                                  ///< this many times
	std::vector<int32_t> relabeled;   ///< faces whose superface the last fallbacks split
	std::vector<int32_t> failedFace;  ///< a face of each superface that failed last round
	std::vector<int32_t> lockedNow;   ///< vertices the last fallbacks locked
	std::vector<int32_t> retightened; ///< border vertices of superfaces given tighter tolerances
};

inline bool isJunction(const Topology &t, const Borders &b, const FallbackState &fb, size_t v)
{
	return b.degree[v] > 0 && (b.degree[v] != 2 || t.vertexLocked[v] || fb.extraLock[v]);
}

/// The border rings of a round: ring r = he[start[r] .. start[r+1]); superface s has the rings
/// sfStart[s] .. sfStart[s+1].
struct Rings {
	std::vector<int32_t> he, start, sfStart;
	std::vector<uint8_t> broken; ///< per superface: its rings could not be traced
};

/// A chain of border edges between two junction vertices (or a closed loop with none), stored as
/// a range of a ring. Only one of the (up to) two superfaces sharing it processes it.
struct Piece {
	int32_t ring, start, len; ///< ring index, first position in the ring, number of edges
	int32_t a, b;             ///< end vertices (a == b for a closed chain)
	bool loop;                ///< a ring without any junction
	int8_t minInterior;       ///< interior vertices to keep at least (keeps rings non-degenerate)
	int32_t kept = 0;         ///< interior vertices kept after simplification
};

/// A triangle's flags: bit k = edge (k, k+1) is a superface border; kNewTriangle = made by
/// re-triangulation (not an input face).
constexpr uint8_t kBorderBits = 7, kNewTriangle = 8;

/// What one chunk of consecutive superfaces produces; chunks are concatenated in order, so the
/// result does not depend on how many threads ran them.
struct ChunkOut {
	std::vector<int32_t> tris;      ///< (the superface of a triangle is known from its range)
	std::vector<uint8_t> triBorder; ///< border edge bits | kNewTriangle
	FailedList failed;
	std::vector<Piece> straight; ///< pieces left straight (see straightenBorders)
	std::vector<int32_t> ringHE, ringStart, sfRings; ///< traced rings (until concatenated)
	size_t retriangulated = 0;
	size_t carried = 0; ///< superfaces that took the finer level's exact triangles

	void emit(int32_t a, int32_t b, int32_t c, uint8_t borderBits, bool isNew)
	{
		tris.push_back(a), tris.push_back(b), tris.push_back(c);
		triBorder.push_back(uint8_t(borderBits | (isNew ? kNewTriangle : 0)));
	}
	void truncate(size_t triCount) ///< rolls back what a failed superface emitted
	{
		tris.resize(3 * triCount);
		triBorder.resize(triCount);
	}
};

/// Per input face measurements, kept across rounds (a superface rebuilt resets its faces).
struct FaceMeasures {
	std::vector<float> dev; ///< normal deviation, degrees; -1 = not measured
	std::vector<float> gap; ///< distance bound (distanceBound; maxDistance > 0 only)
	std::vector<float> tex; ///< texture-coordinate error measured (maxTexError > 0 only)
};

/// A superface's triangles in a round: a range of that round's triangle arrays.
struct Cached {
	int32_t faceCount = 0;
	int32_t triBegin = 0, triEnd = 0;
	bool ok = false, retriangulated = false;
};

/// The previous round's triangles, for the superfaces a fallback round does not change.
struct ReuseCache {
	std::vector<Cached> prev;    ///< per superface of the previous round
	std::vector<int32_t> prevOf; ///< per superface: its (or its parent's) previous id
	std::vector<int32_t> tris;   ///< the previous round's triangles
	std::vector<uint8_t> triBorder;
};

} // namespace detail
} // namespace gausslod
