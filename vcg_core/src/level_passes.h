// The passes that build one level's geometry from its partition, and the plain structs that
// carry state between them. A pass takes what it reads as const and what it writes as non-const:
//   border_rings.cpp            2.2.2  borders, junctions, rings of every superface
//   straighten_merge.cpp        2.3    straightening (2.3.1) and vicinity merging (2.3.2)
//   superface_triangulation.cpp 2.4    re-triangulation of one superface and its checks
//   distance_check.cpp          2.4    the distance tolerance (beyond the paper)
//   surface_flips.cpp           2.4    diagonals chosen by the distance (beyond the paper)
//   texture_check.cpp           2.4    the texture-stretch check (beyond the paper)
//   level_check.cpp                    the whole-level edge check
//   placement.cpp                      vertex placement once the level is valid (beyond the paper)
//   fallbacks.cpp                      fallback rounds: retry, lock, split; reuse of triangles
//   level_geometry.cpp                 the rounds of one level, and its output
#pragma once

#include "engine.h"

#include <atomic>
#include <utility>

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

/// What flipTowardSurface keeps between superfaces (per thread).
struct FlipScratch {
	std::vector<int32_t> queryVertex; ///< per vertex query of the job: its input vertex
	std::vector<int32_t> head, next;  ///< per triangle / query: the queries it holds (lists)
	std::vector<int32_t> twin, queue; ///< per half-edge: the opposite one; edges to look at
	std::vector<double> err;          ///< per triangle: distance of its vertex queries
	std::vector<std::pair<uint64_t, int32_t>> edges;
};

/// Per-thread scratch.
struct Scratch {
	TriangulationJob job;
	std::vector<int32_t> ringVerts, ringVertStart, seq, stack;
	std::vector<float> ringUV; ///< with the texture check: u, v of each ring vertex's corner
	std::vector<uint64_t> edgesNow, edgesBefore; // directed border edges (see reuse)
	std::vector<Vec3> triNormal, centroid;
	/// Topology::faceNormal of the current superface's faces, by position in it (projectionNormal;
	/// empty above kMaxCachedNormals faces, where they are computed when asked)
	std::vector<Vec3> sfNormal;
	/// with sfNormal: the faces (positions 0 .. devMeasured) whose deviation the current pass
	/// measured and writeDeviations writes once the pass is final
	int32_t devMeasured = 0;
	std::vector<double> ownDist2;
	std::vector<uint8_t> covered;
	// distance tolerance and texture check: each vertex of a superface's faces located once
	std::vector<int32_t> vertQuery;   ///< per input vertex: its query, -1 between superfaces
	std::vector<int32_t> cornerQuery; ///< per face corner of the superface: its vertex's query
	std::vector<int32_t> touched;     ///< the vertices given a query (to reset vertQuery)
	// inside vertices inserted into the current superface's triangulation (insertFarthest)
	std::vector<int32_t> steiner;
	std::vector<uint8_t> steinerMark;                 ///< per input vertex (sized on first use)
	std::vector<std::pair<double, int32_t>> farthest; ///< per new triangle: (gap, vertex)
	/// per new triangle, from distanceCheck: the insertable corner of a face found too far over
	/// it (gap, vertex; -1 = none), for a triangle too far from a face but from none of its
	/// vertices (the gap peaks where the face crosses the triangle's edge)
	std::vector<std::pair<double, int32_t>> farCorner;
	/// likewise from deviationWithinLimit: per new triangle, the insertable corner farthest from
	/// its plane of a face that deviates from it beyond the normal limit (DESIGN 32)
	std::vector<std::pair<double, int32_t>> devCorner;
	FlipScratch flip;
	std::vector<int32_t> localOf; ///< jobFromTriangles: per input vertex, its job vertex (-1)
	// polishDiagonals: the accepted pass, put back if the polished one is not better
	std::vector<int32_t> keptTris;
	std::vector<uint8_t> keptBorder;
	std::vector<float> keptDev, keptGap, keptTex;
	std::vector<int32_t> asideVerts; ///< retryWithFlips: inside vertices set aside
	std::vector<float> asideUV;
	// distance bound (distanceBound): the new triangles in 2D, a grid over them, candidates
	// (jobFromTriangles uses boundXY and triArea too, for its signed areas, before any bound)
	std::vector<double> boundXY, triArea, triCovered, triNN;
	std::vector<int8_t> triSign;
	std::vector<int32_t> cellStart, cellFill, cellTri, boundCand;
	std::vector<uint8_t> cellRange;
	std::vector<uint32_t> triStamp;
	uint32_t stampNow = 0;
	/// distanceBound's other bound, if smaller (placement.cpp: as accepted, plus the moves), and
	/// below what it is all the caller needs (then it is the bound, and nothing is computed)
	double boundCap = HUGE_VAL, boundEnough = 0;
	/// set once the caller will discard the round (level_geometry.cpp, DESIGN 40): retriangulate
	/// then tries no further pass of inside vertices (its superface fails as it stands)
	const std::atomic<bool> *discard = nullptr;
	bool inserted(int32_t v) const { return !steinerMark.empty() && steinerMark[size_t(v)]; }
};

// 2x the signed area of the 2D triangle (a, b, c).
inline double orient2(const double *a, const double *b, const double *c)
{
	return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

// Is the 2D point p inside (or on) the triangle tv? (of either orientation)
inline bool insideTriangle(const double *p, const double *const tv[3])
{
	const double d0 = orient2(tv[0], tv[1], p), d1 = orient2(tv[1], tv[2], p),
	             d2 = orient2(tv[2], tv[0], p);
	return (d0 >= 0 && d1 >= 0 && d2 >= 0) || (d0 <= 0 && d1 <= 0 && d2 <= 0);
}

// The new triangles of superface s in 2D (6 per triangle) and a grid over them: cell c holds
// the triangles whose 2D bounding box meets it, w.cellTri[w.cellStart[c] .. w.cellStart[c+1]).
struct TriangleGrid {
	double lo[2] = {HUGE_VAL, HUGE_VAL}, hi[2] = {-HUGE_VAL, -HUGE_VAL};
	double cell[2] = {1, 1};
	int side = 1;

	int at(double x, int d) const
	{
		if (side == 1)
			return 0;
		const double c = (x - lo[d]) / cell[d];
		return c <= 0 ? 0 : c >= side - 1 ? side - 1 : int(c);
	}
	void build(const double *xy, size_t ntri, Scratch &w)
	{
		for (size_t i = 0; i < 3 * ntri; ++i)
			for (int d = 0; d < 2; ++d)
				lo[d] = std::min(lo[d], xy[2 * i + size_t(d)]),
				hi[d] = std::max(hi[d], xy[2 * i + size_t(d)]);
		side = std::max(1, std::min(256, int(std::sqrt(double(ntri)))));
		for (int d = 0; d < 2; ++d)
			cell[d] = hi[d] > lo[d] ? (hi[d] - lo[d]) / side : 1.0;
		w.cellStart.assign(size_t(side) * size_t(side) + 1, 0);
		if (side == 1) { // (one cell: every triangle, in order)
			w.cellStart[1] = int32_t(ntri);
			w.cellTri.resize(ntri);
			for (size_t k = 0; k < ntri; ++k)
				w.cellTri[k] = int32_t(k);
			return;
		}
		w.cellRange.resize(4 * ntri); // (each triangle's cells, for both passes)
		for (size_t k = 0; k < ntri; ++k) {
			const double *t = &xy[6 * k];
			uint8_t *r = &w.cellRange[4 * k]; // (side <= 256)
			r[0] = uint8_t(at(std::min({t[0], t[2], t[4]}), 0));
			r[1] = uint8_t(at(std::max({t[0], t[2], t[4]}), 0));
			r[2] = uint8_t(at(std::min({t[1], t[3], t[5]}), 1));
			r[3] = uint8_t(at(std::max({t[1], t[3], t[5]}), 1));
		}
		for (int pass = 0; pass < 2; ++pass) {
			for (size_t k = 0; k < ntri; ++k) {
				const uint8_t *r = &w.cellRange[4 * k];
				const int x0 = r[0], x1 = r[1], y0 = r[2], y1 = r[3];
				for (int y = y0; y <= y1; ++y)
					for (int x = x0; x <= x1; ++x) {
						const size_t c = size_t(y) * size_t(side) + size_t(x);
						if (pass == 0)
							++w.cellStart[c + 1];
						else
							w.cellTri[size_t(w.cellFill[c]++)] = int32_t(k);
					}
			}
			if (pass == 0) {
				for (size_t c = 1; c < w.cellStart.size(); ++c)
					w.cellStart[c] += w.cellStart[c - 1];
				w.cellTri.resize(size_t(w.cellStart.back()));
				w.cellFill.assign(w.cellStart.begin(), w.cellStart.end() - 1);
			}
		}
	}
};

/// The work of a round cut in chunks of consecutive superfaces of about the same number of
/// faces (several per thread, for balance), run on up to `threads` threads.
struct Chunks {
	size_t threads = 1;
	std::vector<Scratch> scratch; ///< per thread
	std::vector<int32_t> start;   ///< chunk c = superfaces [start[c], start[c+1])
	std::vector<ChunkOut> out;    ///< per chunk

	void make(const SuperfaceFaces &faces, size_t superfaces, size_t nF);
	/// Runs fn(chunk, scratch) for every chunk; the first exception is rethrown.
	template <class Fn>
	void forEach(Fn fn)
	{
		const size_t n = start.size() - 1;
		std::atomic<size_t> next(0);
		std::atomic<bool> failed(false); // (the others stop early; the error is rethrown)
		onWorkers(std::min(threads, n), [&](size_t w) {
			try {
				for (size_t c; !failed && (c = next++) < n;)
					fn(c, scratch[w]);
			} catch (...) {
				failed = true;
				throw;
			}
		});
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

// ---- 2.2.2 borders and rings (border_rings.cpp)

/// Groups the faces by superface.
void groupFaces(const Partition &p, SuperfaceFaces &out);
/// Border half-edges, border degree and junctions of a full round; every junction is kept.
void findBorders(const Topology &t, const Partition &p, const FallbackState &fb, size_t threads,
                 Borders &b);
/// Patch round: updates the borders at what the last fallbacks changed; marks the vertices
/// whose degree or junction status changed (b.changed, b.changedList).
void updateBorders(const Topology &t, const Partition &p, const FallbackState &fb, Borders &b);
/// Traces the rings of the `dirty` superfaces (per chunk, concatenated in superface order).
/// A superface with a delimiter between two of its own faces gets rings.broken (split).
void traceRings(const Topology &t, const Partition &p, const SuperfaceFaces &faces,
                const std::vector<uint8_t> &dirty, Chunks &chunks, Borders &b, Rings &rings);

// ---- 2.3 straightening and vicinity merging (straighten_merge.cpp)

/// Inputs of the chain simplification of a round.
struct ChainInput {
	const Topology &t;
	const Partition &p;
	const LevelLimits &limits;
	const std::vector<uint8_t> &tolStep; ///< FallbackState::tolStep
	const Rings &rings;
	const std::vector<uint8_t> &dirty; ///< superfaces rebuilt this round
	bool patch;                        ///< only the chains through a changed vertex
};
/// Cuts the rings into chains between junctions, simplifies each (sets b.keep), then keeps an
/// interior vertex on all but one of the chains with the same two ends.
void straightenBorders(const ChainInput &in, Chunks &chunks, Borders &b);

// ---- 2.4 re-triangulation of a superface (superface_triangulation.cpp, distance_check.cpp)

/// What the re-triangulation of a round's superfaces reads.
struct TriangulationInput {
	const Topology &t;
	const Partition &p;
	const SuperfaceFaces &faces;
	const Borders &b;
	const Rings &rings;
	const LevelLimits &limits;
	/// With the distance tolerance, below the finest level: per input face, the finer level's
	/// triangles per face of its superface there (what a split would cost; see insertFarthest).
	const SplitCost *finerCost;
	/// Where the output vertices are: null = at the input's positions (t.P); the placement's
	/// checks give the moved ones (placement.cpp): per input vertex its slot (-1: not moved),
	/// and xyz per slot in placedP. Input faces are always at t.P.
	const int32_t *placedSlot = nullptr;
	const double *placedP = nullptr;

	/// The position of input vertex v as a vertex of the output triangles.
	Vec3 out(int32_t v) const
	{
		if (placedSlot && placedSlot[v] >= 0) {
			const double *q = placedP + 3 * size_t(placedSlot[v]);
			return Vec3(q[0], q[1], q[2]);
		}
		return t.pos(v);
	}
	/// How far output vertex v is from its input position (0 unless placed).
	double moved(int32_t v) const
	{
		return placedSlot && placedSlot[v] >= 0 ? (out(v) - t.pos(v)).Norm() : 0.0;
	}
};
/// Re-triangulates superface s into o (or copies its input faces when every vertex is kept) and
/// checks it; writes the measures of its faces only.
Failure retriangulate(const TriangulationInput &in, int32_t s, Scratch &w, ChunkOut &o,
                      FaceMeasures &measures);
/// What the distance tolerance divides a point's distance to a new triangle's plane (unit normal
/// n) by: 1, the distance itself; with the bound as the limit, n . N, the gap along the
/// projection direction N (what distanceBound measures, a bound; but at a steep triangle, 80 deg
/// from N, six times the distance, which refused coarse superfaces that were within it).
inline double checkDivisor(const LevelLimits &l, const Vec3 &n, const Vec3 &N)
{
	return l.boundIsLimit ? n.dot(N) : 1.0;
}
/// Offers input vertex v as the inside vertex to insert into new triangle k (from firstTri of
/// o): `best` keeps the vertex farthest from the triangle's plane (see checkDivisor; ties: the
/// lower index) among those that may be inserted (not kept, on no border, not inserted yet).
/// (insertFarthest's vertices under each triangle, and distanceCheck's corners of faces too far.)
inline void offerInsertion(const TriangulationInput &in, const Scratch &w, const ChunkOut &o,
                           size_t firstTri, const Vec3 &N, int32_t k, int32_t v,
                           std::pair<double, int32_t> &best)
{
	if (in.b.keep[size_t(v)] || in.b.degree[size_t(v)] > 0 || w.inserted(v))
		return;
	const Vec3 &n = w.triNormal[size_t(k)];
	const Vec3 q = in.out(o.tris[3 * (firstTri + size_t(k))]);
	const double gap = std::fabs((in.t.pos(v) - q).dot(n) / checkDivisor(in.limits, n, N));
	if (gap > best.first || (gap == best.first && best.second >= 0 && v < best.second))
		best = std::make_pair(gap, v);
}
/// Flips edges of w.job's triangulation of superface s (not ring edges; two triangles forming a
/// strictly convex quadrilateral) where that brings the farther of the two triangles closer to
/// the vertex queries under them (with `centroids`, the face centroid queries too), starting from
/// the triangles farther than `from` times the tolerance (surface_flips.cpp); keeps job.tris,
/// constrained and queryTri consistent. False if it flipped no edge.
constexpr double kFlipFrom = 0.5;
constexpr size_t kFlipBudget = 4; ///< flips tried per triangle, at most
/// Superfaces of more faces are not given flips: on the big curved superfaces of coarse levels a
/// pass they rescue is rare, and each try costs a pass.
constexpr int32_t kFlipMaxFaces = 4096;
bool flipTowardSurface(const TriangulationInput &in, int32_t s, const Vec3 &N, Scratch &w,
                       double from = kFlipFrom, bool centroids = false);
/// The distance tolerance on superface s, just triangulated from triangle firstTri of o.
Failure distanceCheck(const TriangulationInput &in, int32_t s, const Vec3 &N, size_t firstTri,
                      Scratch &w, const ChunkOut &o, std::vector<float> &gap);
/// Does the input surface nearest to point c (within r, and within `cells` cells of the face
/// grid) face direction n, as the surface a triangle with centroid c and normal n stands for
/// must (not the other side of a thin part)?
bool nearestInputFacing(const Topology &t, const Vec3 &c, const Vec3 &n, double r,
                        double cells = 8);
/// A proven upper bound on the distance, both ways, between superface s's input faces and its new
/// triangles (from firstTri; w.triNormal set), kept per input face in `bound` (max); returned.
double distanceBound(const TriangulationInput &in, int32_t s, const Vec3 &N, size_t firstTri,
                     Scratch &w, const ChunkOut &o, std::vector<float> &bound);

/// Vertex placement (placement.cpp): superface s's accepted triangles `tris` (ntri of them, on
/// input vertex numbers, `bits` their border bits) made into w.job as a re-triangulation would
/// have left it, with the output vertices at in.out(): the rings' kept vertices, then the other
/// vertices of the triangles (its inside vertices), projected on the plane orthogonal to N (the
/// superface's, set here), and every query located in a triangle (just outside the triangles:
/// the nearest one). False if s is not one a re-triangulation accepts (its faces fold in
/// projection, its rings are broken, a triangle has a vertex that is not its).
bool jobFromTriangles(const TriangulationInput &in, int32_t s, const int32_t *tris,
                      const uint8_t *bits, size_t ntri, Vec3 &N, Scratch &w);
/// The checks of a re-triangulation (triangulateAndCheck) on what jobFromTriangles left, its
/// triangles emitted into o; writes the measures of s's faces, `bound` its distance bound.
Failure checkTriangles(const TriangulationInput &in, int32_t s, const Vec3 &N, Scratch &w,
                       ChunkOut &o, FaceMeasures &m, double &bound);

/// The texture-stretch check on superface s, just triangulated from triangle firstTri of o.
Failure textureCheck(const TriangulationInput &in, int32_t s, size_t firstTri, const Scratch &w,
                     const ChunkOut &o, std::vector<float> &tex);

// ---- whole-level check (level_check.cpp)

/// The triangles of a round, in superface order.
struct LevelTriangles {
	std::vector<int32_t> tris;
	std::vector<int32_t> triSf;     ///< superface per triangle
	std::vector<uint8_t> triBorder; ///< border edge bits | kNewTriangle
};
/// Fails (Ring) the superfaces of new triangles on an edge used more often than in the input, or
/// twice in the same direction where the input had it right.
void checkLevelEdges(const Topology &t, size_t superfaces, const LevelTriangles &lt,
                     FailedList &failed);

// ---- vertex placement (placement.cpp)

/// What placeVertices reads of a level that passed its checks.
struct PlacementInput {
	const Topology &t;
	const Partition &p;
	const SuperfaceFaces &faces;
	const LevelLimits &limits;
	const LevelTriangles &lt;              ///< the level's triangles, in superface order
	const std::vector<Cached> &cache;      ///< per superface: its range of lt
	const std::vector<uint8_t> &extraLock; ///< FallbackState::extraLock (never moved)
};
/// Where placeVertices put the output vertices.
struct Placement {
	std::vector<int32_t> slot; ///< per input vertex: its slot in P, -1 = not moved; empty if
	                           ///< none moved
	std::vector<double> P;     ///< xyz per slot
	size_t moved = 0;          ///< output vertices moved
	double maxMove = 0;        ///< the largest move, mesh units
	Vec3 at(const Topology &t, size_t v) const
	{
		return !slot.empty() && slot[v] >= 0 ? Vec3(&P[3 * size_t(slot[v])]) : t.pos(int32_t(v));
	}
};
/// Beyond the paper (DESIGN 27): moves the output vertices along their normals to fit the input
/// better, each move kept only where every superface around it passes its checks again (their
/// measures in m are then those of the moved triangles). Traces the rings of the superfaces a
/// move may change (b, rings).
void placeVertices(const PlacementInput &in, Chunks &chunks, Borders &b, Rings &rings,
                   FaceMeasures &m, Placement &out);

// ---- fallback rounds and reuse (fallbacks.cpp)

/// What the fallbacks do with a superface that failed (`why`) this round: straighten its chains
/// again with tighter tolerances, lock its border vertices (each becomes a junction of the next
/// round: Euler's bound counts it), or split it.
enum class FallbackKind : uint8_t { Retighten, Lock, Split };
FallbackKind fallbackFor(const Topology &t, const SuperfaceFaces &faces, int32_t s, Failure why,
                         const Borders &b, const FallbackState &fb);

/// Arrays of applyFallbacks kept for the next rounds (fresh ones cost more in page faults).
struct FallbackArrays {
	std::vector<uint8_t> split;
	std::vector<int32_t> remap, start, face;
	std::vector<CellKey> cell;
	std::vector<int8_t> origin;
};
/// Retries, locks or splits each failed superface; relabels p and regroups `faces` for the next
/// round; sets cache.prevOf.
void applyFallbacks(const Topology &t, const std::vector<Partition> &finer,
                    const FailedList &failed, const Borders &b, size_t threads, Partition &p,
                    SuperfaceFaces &faces, FallbackState &fb, ReuseCache &cache,
                    FallbackArrays &spare);
/// Copies superface s's triangles of the previous round into o if its faces and its kept
/// outline are the same.
bool reuseTriangles(const TriangulationInput &in, int32_t s, const Cached &now,
                    const ReuseCache &cache, Scratch &w, ChunkOut &o);

} // namespace detail
} // namespace gausslod
