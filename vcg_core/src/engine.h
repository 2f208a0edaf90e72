// Internal data of the GaussLOD engine: flat arrays indexed by vertex, face and half-edge
// (half-edge h = 3*face + k goes from corner k to corner (k+1)%3 of its face).
#pragma once

#include "gausslod/gausslod.h"
#include "sphere_cells.h"

#include <vcg/space/point3.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <exception>
#include <thread>
#include <vector>

namespace gausslod {
namespace detail {

using Vec3 = vcg::Point3d;

inline int32_t heFace(int32_t h) { return h / 3; }
inline int32_t heNext(int32_t h) { return h - h % 3 + (h % 3 + 1) % 3; }
inline int32_t hePrev(int32_t h) { return h - h % 3 + (h % 3 + 2) % 3; }

/// The one counting sort (CSR) of the engine: `emitAll(emit)` calls emit(key, item) for every
/// item, key below nKeys, the same sequence each time it is called (twice: to count, then to
/// fill). Afterwards the items of key k are items[start[k] .. start[k+1]), in emission order.
template <class Item, class EmitAll>
void fillBuckets(size_t nKeys, EmitAll emitAll, std::vector<int32_t> &start,
                 std::vector<Item> &items)
{
	start.assign(nKeys + 1, 0);
	emitAll([&](size_t key, const Item &) { ++start[key + 1]; });
	for (size_t k = 0; k < nKeys; ++k)
		start[k + 1] += start[k];
	items.resize(size_t(start[nKeys]));
	std::vector<int32_t> fill(start.begin(), start.end() - 1);
	emitAll([&](size_t key, const Item &item) { items[size_t(fill[key]++)] = item; });
}

/// Groups n items by a key below nKeys (stable, linear time): afterwards the items with key k
/// are order[start[k] .. start[k+1]), in their original order. `key(i)` gives item i's key.
template <class KeyFn>
void bucketByKey(size_t n, size_t nKeys, KeyFn key, std::vector<int32_t> &start,
                 std::vector<int32_t> &order)
{
	fillBuckets<int32_t>(
	    nKeys,
	    [&](auto emit) {
		    for (size_t i = 0; i < n; ++i)
			    emit(size_t(key(i)), int32_t(i));
	    },
	    start, order);
}

/// bucketByKey, then each bucket sorted by `less` (stable; buckets are small in practice).
template <class KeyFn, class Less>
void bucketSort(size_t n, size_t nKeys, KeyFn key, Less less, std::vector<int32_t> &start,
                std::vector<int32_t> &order)
{
	bucketByKey(n, nKeys, key, start, order);
	for (size_t k = 0; k < nKeys; ++k) {
		if (start[k + 1] - start[k] < 2)
			continue; // (also: no pointer arithmetic on an empty order)
		int32_t *b = order.data() + start[k], *e = order.data() + start[k + 1];
		if (e - b <= 16) { // insertion sort
			for (int32_t *i = b + 1; i < e; ++i)
				for (int32_t *j = i; j > b && less(*j, *(j - 1)); --j)
					std::swap(*j, *(j - 1));
		} else {
			std::stable_sort(b, e, less);
		}
	}
}

/// Squared distance from p to triangle (a, b, c) (closest point by Voronoi regions). VCG's
/// TrianglePointDistance projects on the plane and takes square roots; this runs per candidate
/// face on the flip check's hot path. (The tests check the result with VCG's.)
inline double pointTriangleDistance2(const Vec3 &p, const Vec3 &a, const Vec3 &b, const Vec3 &c)
{
	const Vec3 ab = b - a, ac = c - a, ap = p - a;
	const double d1 = ab.dot(ap), d2 = ac.dot(ap);
	if (d1 <= 0 && d2 <= 0)
		return ap.SquaredNorm();
	const Vec3 bp = p - b;
	const double d3 = ab.dot(bp), d4 = ac.dot(bp);
	if (d3 >= 0 && d4 <= d3)
		return bp.SquaredNorm();
	const double vc = d1 * d4 - d3 * d2;
	if (vc <= 0 && d1 >= 0 && d3 <= 0)
		return (ap - ab * (d1 / (d1 - d3))).SquaredNorm();
	const Vec3 cp = p - c;
	const double d5 = ab.dot(cp), d6 = ac.dot(cp);
	if (d6 >= 0 && d5 <= d6)
		return cp.SquaredNorm();
	const double vb = d5 * d2 - d1 * d6;
	if (vb <= 0 && d2 >= 0 && d6 <= 0)
		return (ap - ac * (d2 / (d2 - d6))).SquaredNorm();
	const double va = d3 * d6 - d5 * d4;
	if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
		return (bp - (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))).SquaredNorm();
	const double den = 1.0 / (va + vb + vc);
	return (ap - ab * (vb * den) - ac * (vc * den)).SquaredNorm();
}

/// Frees a container's memory (clear() keeps it).
template <class V>
void release(V &v)
{
	V().swap(v);
}

/// The angle whose cosine this is (clamped to [-1, 1]), degrees.
inline double angleDegOfCos(double cosine)
{
	constexpr double kRadToDeg = 57.295779513082320876798;
	return std::acos(std::max(-1.0, std::min(1.0, cosine))) * kRadToDeg;
}
/// Angle between two unit vectors, degrees.
inline double angleDeg(const Vec3 &a, const Vec3 &b) { return angleDegOfCos(a.dot(b)); }

/// A unit axis of the plane orthogonal to unit N (the projections' U; V = N ^ U).
inline Vec3 planeAxis(const Vec3 &N)
{
	return (std::fabs(N[0]) < 0.9 ? N ^ Vec3(1, 0, 0) : N ^ Vec3(0, 1, 0)).Normalize();
}

/// Distance from p to the segment a-b.
inline double pointSegmentDistance(const Vec3 &p, const Vec3 &a, const Vec3 &b)
{
	const Vec3 ab = b - a;
	const double len2 = ab.SquaredNorm();
	double t = len2 > 0 ? (p - a).dot(ab) / len2 : 0.0;
	t = std::max(0.0, std::min(1.0, t));
	return (p - (a + ab * t)).Norm();
}

/// 2.1 The cell of a face normal at `level`, packed; kInvalidCell for a zero or non-finite one.
inline CellKey cellOfNormal(const Vec3 &n, int level)
{
	const double nn[3] = {n[0], n[1], n[2]};
	Cell c;
	return normalToCell(nn, level, c) ? packCell(c) : kInvalidCell;
}

/// Hashed uniform grid over the valid input faces (each listed in every cell its bounding box
/// meets; cells hashed into buckets, so a bucket may also hold faces of other cells), for "which
/// input faces are near this point" queries.
struct FaceGrid {
	double lo[3] = {0, 0, 0};
	double cell = 1;
	uint64_t mask = 0;                ///< buckets - 1 (a power of two)
	std::vector<int32_t> start, face; ///< bucket -> faces (CSR)
	std::vector<int32_t> big;         ///< faces too large to list per cell: every query sees them
	/// Per bucket, a cone around its faces' normals: an axis a (int8 x, y, z in bits 0-23) and a
	/// bound s (bits 24-31, /254, s >= 1) such that every face normal n listed in the bucket has
	/// n . t >= 0 for any unit t with (a / |a|) . t >= s / 254 (s = 255: no such t); 0 until
	/// coneOf computes it (the first query that meets the bucket: on most meshes few are met).
	mutable std::vector<uint32_t> cone;

	static uint64_t bucketOf(int64_t x, int64_t y, int64_t z, uint64_t mask)
	{
		const uint64_t h =
		    uint64_t(x) * 73856093u ^ uint64_t(y) * 19349663u ^ uint64_t(z) * 83492791u;
		return (h ^ (h >> 29)) & mask;
	}
	int64_t index(double x, int k) const { return int64_t(std::floor((x - lo[k]) / cell)); }

	/// Calls fn(face) for the big faces and the faces listed in the buckets of the cells that
	/// meet the box [a, b] (a face may come more than once; faces of other cells may come too).
	template <class Fn>
	void forBox(const Vec3 &a, const Vec3 &b, Fn fn) const
	{
		forBuckets(
		    a, b, [](uint64_t) { return false; }, fn);
	}

	/// forBox, but with a unit direction `t`: only the buckets that may hold a face whose normal
	/// n has n . t < 0 (by their cone, coneOf with `normals`: Topology::faceNormal) are listed
	/// (the big faces all are).
	template <class Normals, class Fn>
	void forBoxFacingAway(const Vec3 &a, const Vec3 &b, const Vec3 &t, const Normals &normals,
	                      Fn fn) const
	{
		forBuckets(
		    a, b, [&](uint64_t c) { return allFacing(coneOf(c, normals), t); }, fn);
	}

	/// forBox, skipping the buckets c with skip(c).
	template <class Skip, class Fn>
	void forBuckets(const Vec3 &a, const Vec3 &b, Skip skip, Fn fn) const
	{
		for (const int32_t f : big)
			fn(f);
		if (start.size() < 2)
			return;
		const int64_t x0 = index(a[0], 0), x1 = index(b[0], 0), y0 = index(a[1], 1),
		              y1 = index(b[1], 1), z0 = index(a[2], 2), z1 = index(b[2], 2);
		for (int64_t z = z0; z <= z1; ++z)
			for (int64_t y = y0; y <= y1; ++y)
				for (int64_t x = x0; x <= x1; ++x) {
					const uint64_t c = bucketOf(x, y, z, mask);
					if (skip(c))
						continue;
					for (int32_t i = start[c]; i < start[c + 1]; ++i)
						fn(face[size_t(i)]);
				}
	}

	/// Bucket c's cone (see `cone`), computed from `normals` (Topology::faceNormal) the first time
	/// it is asked. Any number of threads may ask at once: a cone depends only on the bucket's
	/// faces, so two threads that compute the same one store the same bits. The axis: the mean
	/// normal, rounded to int8 (the bound is measured from the rounded axis); s / 254 >= sine of
	/// the widest angle from it, rounded up with a margin of one step (far above the rounding of
	/// the dot products that use it).
	template <class Normals>
	uint32_t coneOf(uint64_t c, const Normals &normals) const
	{
		const uint32_t known = __atomic_load_n(&cone[c], __ATOMIC_RELAXED);
		if (known != 0)
			return known;
		Vec3 sum(0, 0, 0);
		for (int32_t i = start[c]; i < start[c + 1]; ++i)
			sum += normals[size_t(face[size_t(i)])];
		const double len = sum.Norm();
		uint32_t packed = packCone(0, 0, 0, 255);
		if (len > 0) {
			int q[3];
			for (int k = 0; k < 3; ++k)
				q[k] = int(std::lround(127.0 * sum[k] / len));
			const Vec3 axis = Vec3(q[0], q[1], q[2]).Normalize();
			double minCos = 1;
			for (int32_t i = start[c]; i < start[c + 1]; ++i) // (the same normals, the same bits)
				minCos = std::min(minCos, normals[size_t(face[size_t(i)])].dot(axis));
			int s = 255;
			if (minCos > 0) {
				const double sine = std::sqrt(std::max(0.0, 1.0 - minCos * minCos));
				s = std::min(255, int(std::ceil(sine * 254.0)) + 1);
			}
			packed = packCone(q[0], q[1], q[2], s);
		}
		__atomic_store_n(&cone[c], packed, __ATOMIC_RELAXED);
		return packed;
	}

	static uint32_t packCone(int ax, int ay, int az, int s)
	{
		return uint32_t(uint8_t(int8_t(ax))) | uint32_t(uint8_t(int8_t(ay))) << 8 |
		       uint32_t(uint8_t(int8_t(az))) << 16 | uint32_t(s) << 24;
	}
	/// Does every normal of a bucket with this cone face t (n . t >= 0)?
	static bool allFacing(uint32_t cone, const Vec3 &t)
	{
		const uint32_t s = cone >> 24;
		if (s >= 255)
			return false;
		const double ax = int8_t(cone & 0xff), ay = int8_t((cone >> 8) & 0xff),
		             az = int8_t((cone >> 16) & 0xff);
		const double d = ax * t[0] + ay * t[1] + az * t[2], bound = double(s) / 254.0;
		return d > 0 && d * d >= bound * bound * (ax * ax + ay * ay + az * az);
	}
};

/// Worker threads for `requested` (0 = one per core), at most 64.
inline size_t threadCount(int requested)
{
	const size_t n =
	    requested > 0 ? size_t(requested) : size_t(std::thread::hardware_concurrency());
	return std::max<size_t>(1, std::min<size_t>(n, 64));
}

/// Runs fn(worker) for worker = 0 .. workers-1 at once, worker 0 on the calling thread; the first
/// exception of a worker (in worker order) is rethrown here once all have finished.
template <class Fn>
void onWorkers(size_t workers, Fn fn)
{
	if (workers <= 1) {
		fn(size_t(0));
		return;
	}
	std::vector<std::exception_ptr> error(workers);
	auto run = [&](size_t w) {
		try {
			fn(w);
		} catch (...) {
			error[w] = std::current_exception();
		}
	};
	std::vector<std::thread> pool;
	for (size_t w = 1; w < workers; ++w)
		pool.emplace_back(run, w);
	run(0);
	for (std::thread &t : pool)
		t.join();
	for (const std::exception_ptr &e : error)
		if (e)
			std::rethrow_exception(e);
}

/// Runs fn(begin, end, part) on [0, n) cut in up to `threads` contiguous parts.
template <class Fn>
void parallelRanges(size_t n, size_t threads, Fn fn)
{
	const size_t parts = std::max<size_t>(1, std::min(threads, n / 4096 + 1));
	onWorkers(parts, [&](size_t p) { fn(n * p / parts, n * (p + 1) / parts, p); });
}

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

/// 2.2.1 The finest near-coplanar sets: faces of one cell connected through 2-manifold edges.
void finestPartition(const Topology &topo, int level, Partition &out);

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

/// 2.2.2-2.4 for one level: borders, straightening, vicinity merging, re-triangulation; splits
/// superfaces that cannot be re-triangulated validly into their finer children (`finer[k]` is the
/// final partition of level k, for k > p.level) and rebuilds until the level is valid.
/// Stops early, leaving `out` without a mesh and faceLimit < out.stats.faces <= the faces the
/// full build would have, once Euler's bound on every later round's faces (levelFaceBound, with
/// the border vertices the fallbacks will lock counted as soon as their superface fails) exceeds
/// `faceLimit` (the caller then keeps the finer level, which has that many faces).
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
void buildLevelGeometry(const Topology &topo, const Params &params,
                        const std::vector<Partition> &finer, Partition &p, LevelMesh &out,
                        size_t faceLimit, const SplitCost *finerCost = nullptr,
                        const ExactCarry *carryIn = nullptr, ExactCarry *carryOut = nullptr);
/// The cost of a split into p's superfaces: per superface of p, its triangles in `level` (built
/// on p) divided by its faces.
void triangleShare(const Partition &p, const LevelMesh &level, SplitCost &cost);

/// 2.4 Constrained Delaunay triangulation of one superface's projected rings (CGAL).
struct TriangulationJob {
	std::vector<double> xy;         ///< 2 per ring vertex, rings concatenated, then 2 per
	                                ///< interior point (inserted, not constrained)
	std::vector<int32_t> ringStart; ///< ring r = [ringStart[r], ringStart[r+1]) ; size rings+1
	/// per point, or empty if every point is its own vertex: the earlier point that is the same
	/// vertex (a superface whose border touches itself at a vertex), else -1
	std::vector<int32_t> same;
	std::vector<double> queryXY; ///< points to locate in the result (2 per query)
	// out
	std::vector<int32_t> tris;        ///< 3 local ring-vertex indices per triangle, CCW
	std::vector<uint8_t> constrained; ///< per triangle: bit k = edge (k,k+1) is a ring edge
	std::vector<int32_t> queryTri;    ///< triangle containing each query (or, just outside the
	                                  ///< domain, the one across the ring edge); else -1
};
/// Returns false when the rings are not a valid planar domain: two ring vertices coincide (unless
/// `same` says they are one vertex), ring edges cross or overlap, or a ring edge is missing from
/// the result. One ring of at most
/// kSmallRingMax vertices goes to triangulateSmallRing first (smallRings = false: never).
bool triangulateRings(TriangulationJob &job, bool smallRings = true);

/// The fast path of triangulateRings (small_polygon.cpp): one ring of 4 to kSmallRingMax
/// vertices, answered only when every predicate is certain in doubles, and then with the
/// triangles CGAL's path gives (in another order; see there). NotHandled leaves job.tris and
/// job.constrained unchanged.
constexpr size_t kSmallRingMax = 16;
enum class SmallRing { Done, NotHandled };
SmallRing triangulateSmallRing(TriangulationJob &job);

} // namespace detail
} // namespace gausslod
