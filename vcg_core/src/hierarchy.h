// 2.5 The level hierarchy: the partition of a coarser level from a finer one, merges across
// cells, and the check that the finer level's superfaces already give it.
#pragma once

#include "partition.h"

#include <utility>
#include <vector>

namespace gausslod {
namespace detail {

/// 2.5 Merges superfaces of sibling cells of `fine` into the partition of level fine.level-1.
/// A superface grown from several of them gets origin `grownOrigin` (where its children are).
void coarserPartition(const Topology &topo, const Partition &fine, Partition &out,
                      int8_t grownOrigin);

/// Beyond the paper: merges adjacent superfaces whose normals together still fit in a cone of
/// angular diameter boundDeg (at most what one cell of the level holds), across cell borders; a
/// union keeps the cell of its largest part and gets origin mergedOrigin(p.level); the partition
/// before the merge is kept in p.part* for its fallback.
void mergeAcrossCells(const Topology &topo, double boundDeg, Partition &p);

/// Pairs of superfaces whose triangles (3 vertex indices each, superface[k] the superface of
/// triangle k) share an edge, either way round: for sameCoarserPartition, from a level's mesh.
std::vector<std::pair<int32_t, int32_t>> superfacePairs(const std::vector<int32_t> &triangles,
                                                        const std::vector<int32_t> &superface);

/// Beyond the paper (DESIGN 38): the partition of level fine.level - 1, computed from what the
/// finer level knows instead of its faces, when it is certainly `fine`'s superfaces as they are
/// (then true, and `out` is what coarserPartition and mergeAcrossCells(boundDeg; < 0: not
/// called) would give). `adjacent`: pairs of superfaces of `fine`, among them every pair
/// sharing a 2-manifold edge (more pairs only make it refuse more). False: nothing known; `out`
/// untouched. It needs `fine`'s nodes (mergeAcrossCells) if boundDeg >= 0, and refuses where
/// coarserPartition could group two adjacent superfaces (siblings, or cells that touch) or
/// mergeAcrossCells could try a pair.
bool sameCoarserPartition(const Partition &fine,
                          const std::vector<std::pair<int32_t, int32_t>> &adjacent, double boundDeg,
                          Partition &out);

} // namespace detail
} // namespace gausslod
