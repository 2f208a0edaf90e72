// Beyond the paper (docs/DESIGN.md, 51): a level completed by edge collapses, for face budgets,
// error targets and the default chain's steps, on any mesh.
//
// Each collapse replaces a patch of triangles (the triangles around one vertex, or around both
// ends of an edge) by a fan over the same outline, from the kept vertex: at the position where
// the quadric of the input planes it took over is least (a full collapse), or at the kept
// vertex's own position (a half-edge collapse: along a mesh boundary, a seam, or into a vertex
// that must stay). Where the patch and the fan are both one-to-one over the plane orthogonal to
// the patch's normal, they are two height fields over one polygon, and their vertical gap, linear
// on each cell of the overlay of the two triangulations, is largest at a vertex of the overlay:
// that gap, added to the bounds of the patch triangles under each fan triangle, is the fan
// triangle's proven distance bound (both ways). The order is the quadric's (Garland and Heckbert):
// least error first.
#pragma once

#include "level_collapse.h"

namespace gausslod {
namespace detail {

/// What a reduced level may not exceed, and how it is made.
struct ReduceLimits {
	size_t faces = 0;          ///< stop at or below this many triangles (0: no budget)
	double bound = HUGE_VAL;   ///< every triangle's distance bound at most this (mesh units)
	double normalDeg = 180;    ///< every triangle within this of the input normals it stands
	                           ///< for (>= 180: only the facing tests)
	double texError = 0;       ///< with texture coordinates: every triangle's UV error bound at
	                           ///< most this, UV units (0 = no limit)
	bool texErrorSoft = false; ///< the limit is measured against, not kept: collapses beyond it
	                           ///< go in their order (DESIGN 54; the face budget first)
	bool placement = true;     ///< full collapses placed by the quadric (no texture coordinates)
	int level = 0;             ///< Gauss-sphere level: the output's superfaces are its cells'
	/// The output's superfaces are the source's, merged where a collapse joins them (DESIGN 50:
	/// every output corner's source a corner of its superface), not the level's cells'.
	bool keepSuperfaces = false;
	/// DESIGN 57: the first collapses are made by regions of about this many vertices, apart and
	/// in parallel, where the source has at least two (0: one queue for the whole mesh)
	size_t regionVertices = 16384;
};

/// What a reduction did (why a budget was not reached: the level's LevelStats::leastFaces).
struct ReduceReport {
	size_t collapses = 0;
	size_t regionCollapses = 0; ///< of them, made by regions (DESIGN 57)
	int regions = 0;            ///< the regions they were made by (0: none)
	double maxTexError = -1; ///< with texture coordinates: the largest UV error bound of a triangle
	double texErrorLimit = 0; ///< the limit, or the largest error if a soft one gave way
};

/// The input (the mesh the levels are built on) as a collapse source: every valid triangle its
/// own superface, bound 0, its own normal as its cone.
void inputSource(const Topology &t, const MeshView &mesh, CollapseSource &out);

/// Collapses `src` until at most `lim.faces` triangles remain (or, with no face budget, until no
/// collapse keeps every bound within `lim.bound`), into `out` (the level with its per-triangle
/// bounds, cones and per-vertex quadrics, to continue from). True if the budget was reached (always
/// true with no budget); false with `out` still the best level reached.
bool reduceLevel(const Topology &t, const MeshView &mesh, const CollapseSource &src,
                 const ReduceLimits &lim, size_t threads, CollapseSource &out,
                 ReduceReport &report);
/// The same, taking `src` (left empty): its arrays are not held twice at the reduction's peak.
bool reduceLevel(const Topology &t, const MeshView &mesh, CollapseSource &&src,
                 const ReduceLimits &lim, size_t threads, CollapseSource &out,
                 ReduceReport &report);

/// A level's topology, for what a face budget cannot go under (level_topology.cpp).
struct LevelTopology {
	size_t components = 0;
	size_t boundaryLoops = 0; ///< (loops that touch at a vertex count as one)
	bool manifold = true;     ///< no edge with more than two triangles
	/// The least faces a mesh of these components, genera and boundary loops can have (each
	/// loop a triangle at least, no vertex inside; closed: a tetrahedron, or Heawood's bound);
	/// 0 on a non-manifold level
	size_t leastFaces = 0;
};
LevelTopology levelTopology(const std::vector<int32_t> &triangles, size_t nV);

} // namespace detail
} // namespace gausslod
