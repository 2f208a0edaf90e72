// The proof of one collapse (reduce.h): a patch of old triangles and the fan that replaces it,
// both one-to-one over a plane, their vertical gap per fan triangle and which old triangles lie
// under each fan triangle.
#pragma once

#include "engine.h"

namespace gausslod {
namespace detail {

/// Do two counter-clockwise triangles of the plane (x, y) overlap in more than an edge or a
/// point (by more than eps)?
bool trianglesOverlap2D(const double (*a)[2], const double (*b)[2], double eps);

/// One collapse, in local numbers: points 0..nPts-1 (the outline's, then the removed vertices,
/// then the new one), the old triangles and the new ones (counter-clockwise, facing the surface's
/// outside), the removed vertices (`inner`, 1 or 2) and the new vertex (`newInner`, -1 when the
/// kept vertex stays where it was, on the outline). For a vertex leaving a mesh boundary
/// (`pocket`): the new outline has the edge pocketA-pocketB where the old one went through
/// inner[0]; the triangle they make is a pocket of the old patch.
struct PatchCase {
	static constexpr int kMaxPts = 64, kMaxTris = 64;
	int nPts = 0, nOld = 0, nNew = 0;
	Vec3 pos[kMaxPts];
	int8_t oldTri[kMaxTris][3], newTri[kMaxTris][3];
	int nInner = 0;
	int8_t inner[2] = {-1, -1};
	int8_t newInner = -1;
	bool pocket = false;
	int8_t pocketA = -1, pocketB = -1;
	void reset() // (the counts and flags: the arrays are filled up to them)
	{
		nPts = nOld = nNew = nInner = 0;
		inner[0] = inner[1] = newInner = pocketA = pocketB = -1;
		pocket = false;
	}
};

/// What the proof gives: per new triangle its largest vertical gap to the old patch and the old
/// triangles under it (bit i = old triangle i).
struct PatchProof {
	Vec3 dir; ///< the projection direction (unit)
	double gap[PatchCase::kMaxTris];
	uint64_t under[PatchCase::kMaxTris];
	bool byPairs = false; ///< proven triangle by triangle (not as height fields over one plane)
};

/// Proves that the new triangles of `c` replace its old ones within the gaps it returns: as height
/// fields over one plane where both are (every triangle facing the patch's direction, cos at least
/// `facing`, the outline one simple polygon that both cover once), else triangle by triangle (a
/// looser bound, `byPairs`). False only if an old triangle shares no vertex with a new one. `slop`
/// (mesh units) is added to every gap for rounding.
/// With `under` false, only the gaps (for a cost).
bool provePatch(const PatchCase &c, double facing, double slop, PatchProof &out, bool under = true);

} // namespace detail
} // namespace gausslod
