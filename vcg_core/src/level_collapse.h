// Beyond the paper (docs/DESIGN.md, 50): a coarser level made from the finer level's mesh by
// half-edge collapses, with a distance bound proven per collapse, when that reaches the
// superface level's face count within its distance bound.
#pragma once

#include "engine.h"
#include "quadric.h"

namespace gausslod {
namespace detail {

/// A cone of normals: every normal it stands for is within `half` degrees of `axis`.
struct NormalCone {
	Vec3 axis;
	double half = 0;
};

/// A level as the next coarser level's collapses start from it: the level itself (positions
/// kept, inputSuperface on the topology's faces) and, per triangle, an upper bound on its distance
/// to the input (mesh units, both ways: every point of the triangle is that close to the input,
/// and so is every input point it stands for) and the cone of the input normals it stands for.
struct CollapseSource {
	LevelMesh mesh;
	std::vector<double> bound;
	std::vector<NormalCone> cone;
	/// Optional (reduce.h): per vertex, the quadric of the input planes it stands for; per
	/// triangle, an upper bound on its texture-coordinate error; per input face (of the mesh the
	/// levels are built on), the triangle standing for it (-1: a skipped face).
	std::vector<Quadric> quadric;
	std::vector<float> uvError;
	std::vector<int32_t> inputTri;
	void clear() { *this = CollapseSource(); }
	bool empty() const { return mesh.triangles.empty(); }
};

/// The source for a level built from superfaces: each triangle's bound is the level's distance
/// bound, its cone that of its superface's input faces. Takes `lm` (a copy is made by the caller
/// if it still needs it).
void collapseSourceOf(const Topology &t, LevelMesh lm, CollapseSource &out);

/// What a collapsed level may not exceed.
struct CollapseLimits {
	size_t faces = 0;        ///< at most this many triangles (the superface level's count)
	double bound = 0;        ///< every triangle's distance bound at most this (mesh units)
	double normalDeg = 90;   ///< every triangle within this of every input normal it stands for
	double featureDeg = 30;  ///< vertices on an edge sharper than this are never removed
	double placement = 0;    ///< vertices of new triangles move along their normal by at most
	                         ///< this (0 = not at all)
};

/// Half-edge collapses of `src`, the one with the smallest gap first, each keeping the limits,
/// until at most `lim.faces` triangles remain. True, with the level in `out` (stats: faces,
/// vertices, superfaces, normal deviations, distance bound, placed vertices), if it got there;
/// false (out unspecified) if no collapse is left first. Output vertices are `src`'s, at their
/// input positions, or where the placement moved them along their normal. Vertices on a mesh boundary, a non-manifold edge, a delimiter (different
/// keys on its two sides) or a sharp edge, and locked input vertices, are never removed.
bool collapseLevel(const Topology &t, const MeshView &mesh, const CollapseSource &src,
                   const CollapseLimits &lim, size_t threads, CollapseSource &out);

/// The largest distance from an input vertex (of a valid face) to the level's triangles, each
/// looked for within `within` (the level's distance bound: every input point is that close).
double farthestInputVertex(const Topology &t, const LevelMesh &level, double within,
                           size_t threads);

} // namespace detail
} // namespace gausslod
