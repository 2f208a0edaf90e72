// Beyond the paper (docs/DESIGN.md, 50, 51): a level as the next level's collapses (reduce.h)
// start from it, and the measures that compare levels made different ways.
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
	/// The level's own distance to the input is not known (a level built with the tolerance off
	/// reports none): `bound` is then 0, each collapse's bound is its own gap from this level, and
	/// a level continued from it reports no distance bound either (-1).
	bool unbounded = false;
	void clear() { *this = CollapseSource(); }
	bool empty() const { return mesh.triangles.empty(); }
};

/// The source for a level built from superfaces: each triangle's bound is the level's distance
/// bound, its cone that of its superface's input faces. Takes `lm` (a copy is made by the caller
/// if it still needs it).
void collapseSourceOf(const Topology &t, LevelMesh lm, CollapseSource &out);

/// The smallest cone (of this construction) holding both.
NormalCone mergeCones(const NormalCone &a, const NormalCone &b);

/// The largest distance from an input vertex (of a valid face) to the level's triangles, each
/// looked for within `within` (the level's distance bound: every input point is that close).
double farthestInputVertex(const Topology &t, const LevelMesh &level, double within,
                           size_t threads);

/// The level's normal deviation, measured: for the valid input faces (every k-th, at most 16,384
/// of them), the angle between its normal and that of the level's triangle nearest its centroid
/// (looked for within the level's distance bound): the largest into stats.maxNormalDevDeg, the
/// area-weighted mean into stats.meanNormalDevDeg.
void measureNormalDeviation(const Topology &t, LevelMesh &level, size_t threads);

} // namespace detail
} // namespace gausslod
