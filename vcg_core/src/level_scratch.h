// The per-thread scratch of a level's passes (level_passes.h), the 2D predicates and grid the
// re-triangulation checks share, and the chunks the rounds are cut in.
#pragma once

#include "level_data.h"

#include <atomic>
#include <vector>

namespace gausslod {
namespace detail {

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

} // namespace detail
} // namespace gausslod
