// 2.4 A superface seen on the plane of its projection (superface_projection.cpp): its kept ring
// vertices, its normal, its triangulation job; shared by the re-triangulation and placement.
#pragma once

#include "level_passes.h"

namespace gausslod {
namespace detail {

/// Above this many faces, a superface's face normals are computed when asked rather than kept in
/// Scratch::sfNormal, and its deviations written as they are measured (24 bytes per face per
/// thread).
constexpr int32_t kMaxCachedNormals = 1 << 18;

/// The normal of the face at position i of superface s (Topology::faceNormal, the same bits).
inline Vec3 sfFaceNormal(const TriangulationInput &in, int32_t s, int32_t i, const Scratch &w)
{
	return w.sfNormal.empty()
	           ? in.t.faceNormal[size_t(in.faces.face[size_t(in.faces.begin(s) + i)])]
	           : w.sfNormal[size_t(i)];
}

/// The kept vertices of superface s's rings, ring by ring, into w.ringVerts (w.ringVertStart,
/// w.ringUV with texture coordinates, w.job.same); false if a ring keeps fewer than 3.
bool keptRingVertices(const TriangulationInput &in, int32_t s, Scratch &w);

/// The triangulation job of superface s on the plane orthogonal to N (U x V = N): its kept ring
/// vertices, the centroid of each of its faces as a query, and with the distance tolerance or the
/// texture check every vertex of its faces once (see distanceCheck). `queriesKept`: the queries
/// are those of the previous pass (the same faces, N and origin: only the vertices changed).
void projectSuperface(const TriangulationInput &in, int32_t s, const Vec3 &N, Scratch &w,
                      bool queriesKept);

/// The area-weighted normal of superface s (unit), or false if its projection on the plane
/// orthogonal to it folds; sets `unchanged` if every vertex of its faces is kept. Keeps the face
/// normals in w.sfNormal (each computed once per superface, not once per check).
bool projectionNormal(const TriangulationInput &in, int32_t s, Vec3 &N, bool &unchanged,
                      Scratch &w);

/// A corner of a face of superface s at vertex v (v is a vertex of one of its faces).
int32_t cornerAt(const TriangulationInput &in, int32_t s, int32_t v);

} // namespace detail
} // namespace gausslod
