// 2.2.1 A level's superfaces: a label per input face, and the finest partition.
#pragma once

#include "topology.h"

#include <vector>

namespace gausslod {
namespace detail {

/// One level's superfaces: a label per input face.
struct Partition {
	int level = 0;
	/// Superface per input face, 0..count-1, canonical: every id is used and ids are in the order
	/// of the superfaces' first (lowest) faces (deterministic, and what keeps renumberings linear).
	std::vector<int32_t> label;
	std::vector<CellKey> cell;  ///< per superface, a cell of `level`; kInvalidCell = frozen
	                            ///< (invalid input face: kept as it is, never merged)
	std::vector<int8_t> origin; ///< per superface: level of the partition it comes from (its
	                            ///< children are that level+1's superfaces); -1 = one input face;
	                            ///< mergedOrigin(L) = a union across cells made at level L (its
	                            ///< children are level L's parts below)
	/// The partition before merging across cells (empty if nothing was merged): the parts a
	/// cross-cell union falls back to, with their cells and origins.
	std::vector<int32_t> partLabel;
	std::vector<CellKey> partCell;
	std::vector<int8_t> partOrigin;
	/// Per superface, when mergeAcrossCells merged none of them (else empty): the area, the unit
	/// area-weighted mean normal and the angle of the cone around it that holds the normals, as
	/// it measured them from the faces (a partition with the same superfaces has the same; see
	/// sameCoarserPartition).
	std::vector<double> nodeArea, nodeRadius;
	std::vector<Vec3> nodeMean;
	size_t count() const { return cell.size(); }
};

inline int8_t mergedOrigin(int level) { return int8_t(-2 - level); }
inline int mergedLevel(int8_t origin) { return -2 - origin; } ///< for origin <= -2

/// 2.2.1 The finest near-coplanar sets: faces of one cell connected through 2-manifold edges.
void finestPartition(const Topology &topo, int level, Partition &out);

} // namespace detail
} // namespace gausslod
