// 2.2.2-2.4 One level's geometry from its partition, and what a level hands to the next one.
#pragma once

#include "partition.h"

#include <vector>

namespace gausslod {
namespace detail {

/// What splitting a superface back into the finer level's superfaces costs (insertFarthest): per
/// input face f, the finer level's triangles per face of f's superface there, share[label[f]].
struct SplitCost {
	const std::vector<int32_t> *label = nullptr; ///< the finer partition's labels
	std::vector<float> share;                    ///< per finer superface
	float at(size_t f) const { return share[size_t((*label)[f])]; }
};

/// Beyond the paper (DESIGN 31): what a level hands to the next coarser one, the superfaces it
/// re-triangulated exactly (every input face on its triangles, within LevelLimits::exact; no
/// inside vertex; no vertex placed): the next level's superface with the same faces and the same
/// kept outline takes their triangles and measures instead of triangulating and measuring them
/// again (it would get the same: the same polygon, and looser limits). Superface s of the level
/// that made it (its final partition, `label`) is exact if first[s] >= 0: its triangles are
/// tris[3 * first[s] .. 3 * last[s]), bits alike, and its faces' measures (in ascending face
/// order) dev/gap/tex[measureAt[s] .. measureAt[s + 1]).
struct ExactCarry {
	const std::vector<int32_t> *label = nullptr; ///< the finer level's final partition labels
	std::vector<int32_t> first, last;            ///< per superface; first -1 = not carried
	std::vector<int32_t> measureAt;              ///< per superface + 1
	std::vector<int32_t> tris;
	std::vector<uint8_t> bits;
	std::vector<float> dev, gap, tex;
	/// Every superface carried, in one round (no fallback), no vertex placed, every vertex of the
	/// level a chain end (a junction): a coarser level with the same partition would take every
	/// superface as it is, so it is this level (DESIGN 36).
	bool whole = false;
	bool empty() const { return tris.empty(); }
};

/// 2.2.2-2.4 for one level: borders, straightening, vicinity merging, re-triangulation; splits
/// superfaces that cannot be re-triangulated validly into their finer children (`finer[k]` is the
/// final partition of level k, for k > p.level) and rebuilds until the level is valid.
/// Stops early, leaving `out` without a mesh and faceLimit < out.stats.faces <= the faces the
/// full build would have, once Euler's bound on every later round's faces (levelFaceBound, with
/// the border vertices the fallbacks will lock counted as soon as their superface fails) exceeds
/// `faceLimit` (the caller then keeps the finer level, which has that many faces).
void buildLevelGeometry(const Topology &topo, const Params &params,
                        const std::vector<Partition> &finer, Partition &p, LevelMesh &out,
                        size_t faceLimit, const SplitCost *finerCost = nullptr,
                        const ExactCarry *carryIn = nullptr, ExactCarry *carryOut = nullptr);
/// The cost of a split into p's superfaces: per superface of p, its triangles in `level` (built
/// on p) divided by its faces.
void triangleShare(const Partition &p, const LevelMesh &level, SplitCost &cost);

} // namespace detail
} // namespace gausslod
