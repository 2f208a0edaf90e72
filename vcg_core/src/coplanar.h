// Beyond the paper (DESIGN 41): the input with its exactly coplanar regions re-triangulated.
#pragma once

#include "topology.h"

#include <vector>

namespace gausslod {
namespace detail {

/// Beyond the paper (DESIGN 41): the input with its exactly coplanar regions (connected faces
/// within 1e-9 of the diagonal of one plane) re-triangulated from their outlines, the vertices
/// inside them and on straight chains between them (or along the boundary) dropped: the same
/// surface, the same kept vertices. False (and `out` not to be used) if no region is found, the
/// mesh has texture coordinates, or the reduction would save less than an eighth of the faces.
struct CoplanarReduction {
	std::vector<int32_t> triangles; ///< the reduced faces: 3 indices into vertexOf each
	std::vector<int32_t> vertexOf;  ///< per vertex of the reduced mesh: its input vertex (the
	                                ///< input's vertices that the reduced faces use, in order)
	std::vector<double> positions;  ///< xyz per vertex of the reduced mesh
	std::vector<int32_t> faceOf;    ///< per reduced face: an input face of its region (or itself)
	std::vector<int32_t> cornerOf;  ///< per reduced corner: an input corner at its vertex, of a
	                                ///< face of the same region
	std::vector<int32_t> reducedOf; ///< per input face: a reduced face of its region; -1: dropped
	std::vector<float> weight;      ///< per reduced face: Topology::sampleWeight (1 outside the
	                                ///< regions; in a region, its faces and dropped vertices, by
	                                ///< the face's share of its area)
	size_t regions = 0;             ///< regions of 2+ faces re-triangulated
	double eps = 0;                 ///< the tolerance of "one plane" and "one line"
	double distance = 0; ///< the reduced surface is within this of the input (at most 3 eps):
	                     ///< twice the largest distance of a region's vertex from its plane, plus
	                     ///< the largest of a dropped chain vertex from its segment
};
bool reduceCoplanar(const MeshView &mesh, const Topology &topo, size_t threads,
                    CoplanarReduction &out);

} // namespace detail
} // namespace gausslod
