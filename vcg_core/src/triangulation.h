// 2.4 Constrained Delaunay triangulation of one superface's projected rings.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace gausslod {
namespace detail {

/// 2.4 Constrained Delaunay triangulation of one superface's projected rings (CGAL).
struct TriangulationJob {
	std::vector<double> xy;         ///< 2 per ring vertex, rings concatenated, then 2 per
	                                ///< interior point (inserted, not constrained)
	std::vector<int32_t> ringStart; ///< ring r = [ringStart[r], ringStart[r+1]) ; size rings+1
	/// per point, or empty if every point is its own vertex: the earlier point that is the same
	/// vertex (a superface whose border touches itself at a vertex), else -1
	std::vector<int32_t> same;
	std::vector<double> queryXY; ///< points to locate in the result (2 per query)
	// out
	std::vector<int32_t> tris;        ///< 3 local ring-vertex indices per triangle, CCW
	std::vector<uint8_t> constrained; ///< per triangle: bit k = edge (k,k+1) is a ring edge
	std::vector<int32_t> queryTri;    ///< triangle containing each query (or, just outside the
	                                  ///< domain, the one across the ring edge); else -1
};
/// Returns false when the rings are not a valid planar domain: two ring vertices coincide (unless
/// `same` says they are one vertex), ring edges cross or overlap, or a ring edge is missing from
/// the result. One ring of at most
/// kSmallRingMax vertices goes to triangulateSmallRing first (smallRings = false: never).
bool triangulateRings(TriangulationJob &job, bool smallRings = true);

/// The fast path of triangulateRings (small_polygon.cpp): one ring of 4 to kSmallRingMax
/// vertices, answered only when every predicate is certain in doubles, and then with the
/// triangles CGAL's path gives (in another order; see there). NotHandled leaves job.tris and
/// job.constrained unchanged.
constexpr size_t kSmallRingMax = 16;
enum class SmallRing { Done, NotHandled };
SmallRing triangulateSmallRing(TriangulationJob &job);

} // namespace detail
} // namespace gausslod
