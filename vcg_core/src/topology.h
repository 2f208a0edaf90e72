// What the engine derives once from the input mesh: face measures, adjacency, vertex classes,
// the face grid; and the input repair (welding) that comes before it.
#pragma once

#include "face_grid.h"
#include "gausslod/gausslod.h"
#include "geometry.h"

#include <vector>

namespace gausslod {
namespace detail {

enum VertexClass : uint8_t { kFlat = 0, kEdge = 1, kCorner = 2 }; // = importance (2.3.2)

/// The cross product of face f's edges from its first corner (twice its area along its normal),
/// and its length. Out of line: every use gets the same bits from the same instructions (a
/// stored normal and one computed again must agree).
double faceCross(const double *P, const int32_t *T, size_t f, Vec3 &cross);

/// Unit normal or area of a face (Topology::faceNormal, faceArea), computed when asked from the
/// positions: stored, they took 32 bytes per face, a sixth of the peak memory. Zero for a face
/// that is not valid.
struct FaceMeasure {
	const double *P = nullptr;
	const int32_t *T = nullptr;
	const uint8_t *valid = nullptr; ///< Topology::faceValid
	Vec3 normal(size_t f) const
	{
		Vec3 n;
		if (!valid[f])
			return Vec3(0, 0, 0);
		const double len = faceCross(P, T, f, n);
		return n / len;
	}
	double area(size_t f) const
	{
		Vec3 n;
		return valid[f] ? 0.5 * faceCross(P, T, f, n) : 0.0;
	}
	/// normal(f) and area(f) at the cost of one.
	void normalAndArea(size_t f, Vec3 &normal, double &area) const
	{
		if (!valid[f]) {
			normal = Vec3(0, 0, 0), area = 0;
			return;
		}
		const double len = faceCross(P, T, f, normal);
		normal /= len;
		area = 0.5 * len;
	}
};
struct FaceNormals : FaceMeasure {
	Vec3 operator[](size_t f) const { return normal(f); }
};
struct FaceAreas : FaceMeasure {
	double operator[](size_t f) const { return area(f); }
};

constexpr int64_t kNoEuler = INT64_MIN; ///< Topology::euler of an input that is not clean

/// Everything derived once from the input mesh.
struct Topology {
	Topology() = default;
	// (faceNormal and faceArea point into faceValid: a copy would read the original's)
	Topology(const Topology &) = delete;
	Topology &operator=(const Topology &) = delete;

	size_t nV = 0, nF = 0;
	const double *P = nullptr;  ///< xyz per vertex (the caller's array)
	const int32_t *T = nullptr; ///< 3 per face (the caller's array)
	double diagonal = 0;
	const float *UV = nullptr;         ///< 2 per face corner (MeshView::cornerUV), optional
	bool wantSources = false;          ///< MeshView::wantSources
	const uint8_t *keepFace = nullptr; ///< MeshView::keepFace, optional

	FaceNormals faceNormal;         ///< unit normal (zero for invalid faces), by face
	FaceAreas faceArea;             ///< area (zero for invalid faces), by face
	std::vector<uint8_t> faceValid; ///< distinct vertices, finite, non-zero area
	/// Faces that are no triangles (a repeated vertex index) or repeat an earlier face's vertex
	/// set: left out of the adjacency and of every level.
	std::vector<uint8_t> faceDropped;
	/// Opposite half-edge across a 2-manifold, consistently oriented edge between two valid
	/// faces; -1 otherwise (mesh boundary, non-manifold, inconsistent: always a border).
	std::vector<int32_t> twin;
	/// Per half-edge, only when the input has keys (MeshView::faceKey, cornerKey): 1 = a
	/// delimiter, never crossed by a superface (it still has its twin: its vertices are no
	/// non-manifold vertices and move along it like along any border).
	std::vector<uint8_t> delimiter;
	/// Vertices that are never removed or moved: on non-manifold or inconsistent edges, on invalid
	/// faces, or with more than one fan of faces (non-manifold vertex).
	std::vector<uint8_t> vertexLocked;
	std::vector<uint8_t> vertexClass;     ///< VertexClass (2.3.2)
	std::vector<int32_t> vfStart, vfFace; ///< vertex -> incident faces (CSR)
	FaceGrid grid;                        ///< the valid faces, for nearest-face queries
	/// Per face, how many of the caller's input samples (face centroids and vertices) it stands
	/// for in vertex placement: a face of the mesh the levels are built on that replaced a
	/// region of coplanar input faces (reduceCoplanar) stands for its share of theirs. Empty: 1.
	std::vector<float> sampleWeight;
	/// The surface's Euler characteristic V - E + F, if the input is a clean 2-manifold (every
	/// face valid, none dropped or kept by the caller, no vertex locked: every edge has a twin or
	/// is a true boundary edge, every vertex one fan); kNoEuler otherwise. Every level is then a
	/// surface of the same topology: see levelFaceBound.
	int64_t euler = kNoEuler;
	std::vector<int32_t> boundaryVertex; ///< with `euler`: the vertices on the mesh's boundary

	Vec3 pos(int32_t v) const { return Vec3(P[3 * v], P[3 * v + 1], P[3 * v + 2]); }
	/// The twin a superface may grow across: -1 on a delimiter.
	int32_t joinTwin(size_t h) const { return delimiter.empty() || !delimiter[h] ? twin[h] : -1; }
	int32_t heFrom(int32_t h) const { return T[h]; }
	int32_t heTo(int32_t h) const { return T[heNext(h)]; }
};

/// Input repair: rep[v] = the vertex v is welded into (v itself if none): the lowest-index vertex
/// at exactly v's position (distance 0) or, for distance > 0, the lowest-index kept vertex within
/// that distance. Non-finite positions are never welded, nor are vertices whose every edge two or
/// more faces use (by index): only vertices on an open edge join. Returns how many were welded.
size_t weldVertices(const MeshView &mesh, double distance, std::vector<int32_t> &rep);

/// Builds Topology from the input (validated by the caller). featureAngleDeg: 2.3.2 threshold.
/// withGrid = false leaves topo.grid to buildFaceGrid (which only writes topo.grid: it may run
/// on another thread while the partition is built).
/// withClasses = false leaves the vertex classes and Topology::euler to classifyTopology.
/// diagonal >= 0: topo.diagonal (else the bounding box diagonal of the mesh's vertices).
void buildTopology(const MeshView &mesh, double featureAngleDeg, Topology &topo, size_t threads = 1,
                   bool withGrid = true, bool withClasses = true, double diagonal = -1);
void classifyTopology(Topology &topo, double featureAngleDeg, size_t threads);
/// topo.grid over the valid faces (see FaceGrid; the buckets' cones are left to its coneOf);
/// needs the faces' validity.
void buildFaceGrid(Topology &topo);

/// A lower bound on the faces of any level whose kept vertices include those flagged in `kept`
/// (per vertex, nonzero), by Euler's formula: a level of a clean surface (Topology::euler) is a
/// triangulated surface of the same topology whose boundary edges join its boundary vertices,
/// so it has F = 2 V - V_b - 2 chi faces, V of them vertices, V_b on the boundary. 0 if the
/// input is not clean.
size_t levelFaceBound(const Topology &topo, const std::vector<uint8_t> &kept);

} // namespace detail
} // namespace gausslod
