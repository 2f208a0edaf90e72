// Beyond the paper (DESIGN 41): the exactly coplanar regions of the input (coplanar_regions.cpp),
// for reduceCoplanar (coplanar.cpp).
#pragma once

#include "engine.h"

#include <vector>

namespace gausslod {
namespace detail {

/// The regions of 2+ faces of one plane (see growRegions).
struct Regions {
	std::vector<int32_t> of;   ///< per face: its region, -1 = not in a region of 2+ faces
	std::vector<int32_t> seed; ///< per region: its first face (the plane's face)
	std::vector<uint8_t> dead; ///< per region: its outline could not be triangulated
	double planeDev = 0;       ///< the largest distance of a region's vertex from its plane
};

/// Regions of 2+ faces: connected across 2-manifold, non-delimiter edges, every vertex within eps
/// of the plane of the region's first face (its seed), every face facing the same way as the
/// seed. Leaves r empty if they could not save an eighth of the faces.
void growRegions(const MeshView &mesh, const Topology &t, double eps, size_t threads, Regions &r);

} // namespace detail
} // namespace gausslod
