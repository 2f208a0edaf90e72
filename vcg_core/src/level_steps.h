// The passes that build one level's geometry (level_passes.h), by section of the paper: what
// each takes as const it reads, what it takes as non-const it writes.
#pragma once

#include "level_scratch.h"

#include <vector>

namespace gausslod {
namespace detail {

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

// ---- 2.4 re-triangulation of a superface (superface_triangulation.cpp, superface_checks.cpp,
// distance_check.cpp, distance_bound.cpp, superface_projection.cpp)

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

/// For vertex placement (placement.cpp; superface_projection.cpp): superface s's accepted triangles
/// `tris` (ntri of them, on input vertex numbers, `bits` their border bits) made into w.job as a
/// re-triangulation would have left it, with the output vertices at in.out(): the rings' kept
/// vertices, then the other vertices of the triangles (its inside vertices), projected on the plane
/// orthogonal to N (the superface's, set here), and every query located in a triangle (just outside
/// the triangles: the nearest one). False if s is not one a re-triangulation accepts (its faces
/// fold in projection, its rings are broken, a triangle has a vertex that is not its).
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
/// Whether superface s's ring edges between kept vertices, directed, are (as a multiset) the
/// border-flagged edges of triangles [begin, end) of `tris` (bit e of bits[k]: the edge from
/// corner e of triangle k): the same kept outline.
bool sameKeptOutline(const TriangulationInput &in, int32_t s, const std::vector<int32_t> &tris,
                     const std::vector<uint8_t> &bits, int32_t begin, int32_t end, Scratch &w);
/// Copies superface s's triangles of the previous round into o if its faces and its kept
/// outline are the same.
bool reuseTriangles(const TriangulationInput &in, int32_t s, const Cached &now,
                    const ReuseCache &cache, Scratch &w, ChunkOut &o);

} // namespace detail
} // namespace gausslod
