// Adjacency (2.2: which edges may join a superface) and vertex classes (2.3.2), one linear pass
// each.
#include "engine.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

namespace gausslod {
namespace detail {

double faceCross(const double *P, const int32_t *T, size_t f, Vec3 &cross)
{
	auto pos = [&](int32_t v) {
		return Vec3(P[3 * size_t(v)], P[3 * size_t(v) + 1], P[3 * size_t(v) + 2]);
	};
	const int32_t a = T[3 * f], b = T[3 * f + 1], c = T[3 * f + 2];
	cross = (pos(b) - pos(a)) ^ (pos(c) - pos(a));
	return cross.Norm();
}

namespace {

// Which faces are valid; their normals and areas are computed from the positions when asked
// (FaceMeasure).
void computeFaces(Topology &t, size_t threads)
{
	t.faceValid.assign(t.nF, 0);
	// Faces smaller than this (relative to the model size) have no reliable normal.
	const double minCross = 1e-20 * t.diagonal * t.diagonal;
	parallelRanges(t.nF, threads, [&](size_t begin, size_t end, size_t) {
		for (size_t f = begin; f < end; ++f) {
			if (t.faceDropped[f])
				continue;
			Vec3 n;
			const double len = faceCross(t.P, t.T, f, n);
			t.faceValid[f] = std::isfinite(len) && len > minCross;
		}
	});
	const FaceMeasure measure{t.P, t.T, t.faceValid.data()};
	static_cast<FaceMeasure &>(t.faceNormal) = measure;
	static_cast<FaceMeasure &>(t.faceArea) = measure;
}

// Vertex -> faces (CSR) over the faces that are not dropped.
void buildVertexFaces(Topology &t)
{
	fillBuckets<int32_t>(
	    t.nV,
	    [&](auto emit) {
		    for (size_t f = 0; f < t.nF; ++f)
			    if (!t.faceDropped[f])
				    for (int k = 0; k < 3; ++k)
					    emit(size_t(t.T[3 * f + size_t(k)]), int32_t(f));
	    },
	    t.vfStart, t.vfFace);
}

// The vertices of face f rotated so that the smallest comes first (orientation kept).
std::array<int32_t, 3> orientedKey(const Topology &t, size_t f)
{
	const int32_t *v = t.T + 3 * f;
	const int k = v[0] < v[1] ? (v[0] < v[2] ? 0 : 2) : (v[1] < v[2] ? 1 : 2);
	return {v[k], v[(k + 1) % 3], v[(k + 2) % 3]};
}

// Drops faces with a repeated vertex and faces that repeat an earlier face with the same
// orientation. (A reversed copy is kept: back to back, the two make a two-sided sheet.)
void dropNonTriangles(Topology &t, size_t threads)
{
	t.faceDropped.assign(t.nF, 0);
	for (size_t f = 0; f < t.nF; ++f) {
		const int32_t a = t.T[3 * f], b = t.T[3 * f + 1], c = t.T[3 * f + 2];
		t.faceDropped[f] = a == b || b == c || a == c;
	}
	buildVertexFaces(t); // (lists the proper triangles only)
	// A repeat of an earlier proper triangle (whether that one is itself a repeat or not: then it
	// repeats the first one too), looked for per range of faces on every thread, each thread
	// writing only its own faces' flags.
	std::vector<uint8_t> any(threads, 0);
	parallelRanges(t.nF, threads, [&](size_t begin, size_t end, size_t part) {
		for (size_t f = begin; f < end; ++f) {
			if (t.faceDropped[f])
				continue;
			const std::array<int32_t, 3> key = orientedKey(t, f);
			for (int32_t i = t.vfStart[size_t(key[0])]; i < t.vfStart[size_t(key[0]) + 1]; ++i) {
				const int32_t g = t.vfFace[size_t(i)];
				if (size_t(g) >= f || orientedKey(t, size_t(g)) != key)
					continue;
				t.faceDropped[f] = 1;
				any[part] = 1;
				break;
			}
		}
	});
	if (std::find(any.begin(), any.end(), uint8_t(1)) != any.end())
		buildVertexFaces(t);
}

// Twins across 2-manifold, consistently oriented edges; everything else locks its vertices.
void buildTwins(Topology &t, size_t threads)
{
	t.twin.assign(3 * t.nF, -1);
	t.vertexLocked.assign(t.nV, 0);
	std::vector<std::vector<int32_t>> lock(threads); // vertices to lock, per part
	parallelRanges(t.nF, threads, [&](size_t fBegin, size_t fEnd, size_t part) {
		std::vector<int32_t> &locks = lock[part];
		for (size_t f = fBegin; f < fEnd; ++f) {
			if (t.faceDropped[f])
				continue;
			if (!t.faceValid[f]) {
				for (int k = 0; k < 3; ++k)
					locks.push_back(t.T[3 * f + k]);
				continue;
			}
			for (int k = 0; k < 3; ++k) {
				const int32_t h = int32_t(3 * f + k), a = t.heFrom(h), b = t.heTo(h);
				int others = 0;
				int32_t opposite = -1;
				bool inconsistent = false;
				int32_t lastFace = -1;
				for (int32_t i = t.vfStart[size_t(a)]; i < t.vfStart[size_t(a) + 1]; ++i) {
					const int32_t g = t.vfFace[size_t(i)];
					if (g == int32_t(f) || g == lastFace)
						continue;
					lastFace = g;
					for (int kk = 0; kk < 3; ++kk) {
						const int32_t hg = 3 * g + kk;
						if (t.heFrom(hg) == b && t.heTo(hg) == a) {
							++others;
							opposite = t.faceValid[size_t(g)] ? hg : -1;
						} else if (t.heFrom(hg) == a && t.heTo(hg) == b) {
							++others;
							inconsistent = true;
						}
					}
				}
				if (others == 1 && !inconsistent && opposite >= 0)
					t.twin[size_t(h)] = opposite;
				else if (others > 0) // non-manifold or inconsistently oriented edge
					locks.push_back(a), locks.push_back(b);
			}
		}
	});
	for (const std::vector<int32_t> &l : lock)
		for (int32_t v : l)
			t.vertexLocked[size_t(v)] = 1;
}

// A vertex whose incident faces do not form one fan through twins is non-manifold: lock it.
void lockNonManifoldVertices(Topology &t, size_t threads)
{
	parallelRanges(t.nV, threads, [&](size_t vBegin, size_t vEnd, size_t) {
		for (size_t v = vBegin; v < vEnd; ++v) {
			const int32_t begin = t.vfStart[v], end = t.vfStart[v + 1];
			if (begin == end || t.vertexLocked[v])
				continue;
			const int32_t f0 = t.vfFace[size_t(begin)];
			auto cornerOf = [&](int32_t f) {
				for (int k = 0; k < 3; ++k)
					if (t.T[3 * f + k] == int32_t(v))
						return 3 * f + k;
				return int32_t(-1);
			};
			int32_t fan = 1;
			bool closed = false;
			// rotate across the edges leaving v
			for (int32_t h = cornerOf(f0), steps = 0; steps <= end - begin; ++steps) {
				const int32_t tw = t.twin[size_t(h)];
				if (tw < 0)
					break;
				if (heFace(tw) == f0) {
					closed = true;
					break;
				}
				++fan;
				h = heNext(tw); // in the twin's face, the edge leaving v
			}
			if (!closed) // rotate the other way across the edges entering v
				for (int32_t h = hePrev(cornerOf(f0)), steps = 0; steps <= end - begin; ++steps) {
					const int32_t tw = t.twin[size_t(h)];
					if (tw < 0 || heFace(tw) == f0)
						break;
					++fan;
					h = hePrev(tw);
				}
			if (fan != end - begin)
				t.vertexLocked[v] = 1;
		}
	});
}

// 2.3.2: A1 = largest angle between two incident face normals (two linear sweeps approximate the
// diameter), the faces split into two groups around those two bases, A2 = the larger group cone.
void classifyVertices(Topology &t, double thresholdDeg, size_t threads)
{
	t.vertexClass.assign(t.nV, kFlat);
	parallelRanges(t.nV, threads, [&](size_t vBegin, size_t vEnd, size_t) {
		std::vector<Vec3> normal; // of the vertex's faces (each computed once: see FaceMeasure)
		for (size_t v = vBegin; v < vEnd; ++v) {
			const int32_t begin = t.vfStart[v], end = t.vfStart[v + 1];
			normal.resize(size_t(end - begin));
			Vec3 mean(0, 0, 0);
			for (int32_t i = begin; i < end; ++i)
				mean += normal[size_t(i - begin)] = t.faceNormal[size_t(t.vfFace[size_t(i)])];
			// the position of the face farthest from dir (among `group`), -1 if none
			auto farthestFrom = [&](const Vec3 &dir, int group, const Vec3 *b1, const Vec3 *b2) {
				int32_t best = -1;
				double bestDot = HUGE_VAL;
				for (int32_t i = begin; i < end; ++i) {
					const int32_t f = t.vfFace[size_t(i)];
					if (!t.faceValid[size_t(f)])
						continue;
					const Vec3 &n = normal[size_t(i - begin)];
					if (group >= 0 && (n.dot(*b1) >= n.dot(*b2) ? 0 : 1) != group)
						continue;
					const double d = n.dot(dir);
					if (d < bestDot) {
						bestDot = d;
						best = i - begin;
					}
				}
				return best;
			};
			const int32_t f1 = farthestFrom(mean, -1, nullptr, nullptr);
			if (f1 < 0)
				continue;
			const Vec3 b1 = normal[size_t(f1)];
			const Vec3 b2 = normal[size_t(farthestFrom(b1, -1, nullptr, nullptr))];
			const double a1 = angleDeg(b1, b2);
			if (a1 < thresholdDeg)
				continue;
			double a2 = 0;
			for (int group = 0; group < 2; ++group) {
				const Vec3 &base = group == 0 ? b1 : b2;
				const int32_t g1 = farthestFrom(base, group, &b1, &b2);
				if (g1 < 0)
					continue;
				const Vec3 e1 = normal[size_t(g1)];
				const int32_t g2 = farthestFrom(e1, group, &b1, &b2);
				a2 = std::max(a2, angleDeg(e1, normal[size_t(g2)]));
			}
			t.vertexClass[v] = a2 > thresholdDeg ? kCorner : kEdge;
		}
	});
}

} // namespace

// A face whose box would meet more cells than this is listed apart (FaceGrid::big).
constexpr double kFaceGridBigCells = 64;

// The cells (from `lo`, of side 1 / inv) that face f's box meets: i0..i1 per axis; returns their
// number (every coordinate is >= lo: truncation is floor).
static double faceCellRange(const Topology &t, const double lo[3], double inv, size_t f,
                            int64_t i0[3], int64_t i1[3])
{
	double n = 1;
	for (int k = 0; k < 3; ++k) {
		double a = HUGE_VAL, b = -HUGE_VAL;
		for (int c = 0; c < 3; ++c) {
			const double x = t.P[3 * size_t(t.T[3 * f + size_t(c)]) + size_t(k)];
			a = std::min(a, x), b = std::max(b, x);
		}
		i0[k] = int64_t((a - lo[k]) * inv), i1[k] = int64_t((b - lo[k]) * inv);
		n *= double(i1[k] - i0[k] + 1);
	}
	return n;
}

// Calls fn(bucket) for every cell of t.grid that face f's box meets; false (and no call) for a
// big face.
template <class Fn>
static bool forFaceBuckets(const Topology &t, size_t f, Fn fn)
{
	const FaceGrid &g = t.grid;
	int64_t i0[3], i1[3];
	if (faceCellRange(t, g.lo, 1.0 / g.cell, f, i0, i1) > kFaceGridBigCells)
		return false;
	for (int64_t z = i0[2]; z <= i1[2]; ++z)
		for (int64_t y = i0[1]; y <= i1[1]; ++y)
			for (int64_t x = i0[0]; x <= i1[0]; ++x)
				fn(FaceGrid::bucketOf(x, y, z, g.mask));
	return true;
}

// Cells about twice the median face extent; a face that would span more than kFaceGridBigCells
// cells is kept in a separate list that every query scans (a few huge faces among many tiny ones
// must neither be walked cell by cell nor make the cells huge); cells grow while that list or the
// listing grows too long. The buckets' cones are left to FaceGrid::coneOf.
void buildFaceGrid(Topology &t)
{
	FaceGrid &g = t.grid;
	g.start.assign(1, 0);
	g.face.clear(), g.big.clear(), g.cone.clear();
	double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL};
	std::vector<double> extent;
	auto box = [&](size_t f, double a[3], double b[3]) {
		for (int k = 0; k < 3; ++k) {
			a[k] = HUGE_VAL, b[k] = -HUGE_VAL;
			for (int c = 0; c < 3; ++c) {
				const double x = t.P[3 * size_t(t.T[3 * f + size_t(c)]) + size_t(k)];
				a[k] = std::min(a[k], x), b[k] = std::max(b[k], x);
			}
		}
	};
	for (size_t f = 0; f < t.nF; ++f) {
		if (!t.faceValid[f])
			continue;
		double a[3], b[3];
		box(f, a, b);
		for (int k = 0; k < 3; ++k)
			lo[k] = std::min(lo[k], a[k]);
		extent.push_back(std::max(b[0] - a[0], std::max(b[1] - a[1], b[2] - a[2])));
	}
	const size_t valid = extent.size();
	if (valid == 0)
		return;
	for (int k = 0; k < 3; ++k)
		g.lo[k] = lo[k];
	std::nth_element(extent.begin(), extent.begin() + std::ptrdiff_t(valid / 2), extent.end());
	const double median = extent[valid / 2];
	std::vector<double>().swap(extent);
	g.cell = median > 0 ? 2.0 * median : (t.diagonal > 0 ? t.diagonal : 1.0);
	// counted, not visited
	for (int attempt = 0; attempt < 200; ++attempt) {
		const double inv = 1.0 / g.cell;
		double entries = 0;
		size_t big = 0;
		for (size_t f = 0; f < t.nF; ++f)
			if (t.faceValid[f]) {
				int64_t i0[3], i1[3];
				const double n = faceCellRange(t, lo, inv, f, i0, i1);
				if (n > kFaceGridBigCells)
					++big;
				else
					entries += n;
			}
		if (entries <= 4.0 * double(valid) + 64 && big <= 256 + valid / 1000)
			break;
		g.cell *= 2;
	}
	size_t buckets = 1;
	while (buckets < valid)
		buckets <<= 1;
	g.mask = buckets - 1;
	// (the big faces are the same on both passes)
	fillBuckets<int32_t>(
	    buckets,
	    [&](auto emit) {
		    g.big.clear();
		    for (size_t f = 0; f < t.nF; ++f)
			    if (t.faceValid[f] &&
			        !forFaceBuckets(t, f, [&](uint64_t c) { emit(c, int32_t(f)); }))
				    g.big.push_back(int32_t(f));
	    },
	    g.start, g.face);
	g.cone.assign(buckets, 0); // (computed when first asked: FaceGrid::coneOf)
}

// Delimiters (MeshView::faceKey, cornerKey): twin edges whose faces differ in key, or in the
// corner key at either end vertex. Nothing is stored without keys.
static void markDelimiters(const MeshView &mesh, Topology &t)
{
	t.delimiter.clear();
	if (!mesh.faceKey && !mesh.cornerKey)
		return;
	t.delimiter.assign(3 * t.nF, 0);
	for (size_t h = 0; h < t.twin.size(); ++h) {
		const int32_t tw = t.twin[h];
		if (tw < 0)
			continue;
		bool cut = mesh.faceKey && mesh.faceKey[h / 3] != mesh.faceKey[size_t(heFace(tw))];
		// (h runs a -> b, its twin b -> a: corner h and the twin's next are at a)
		if (mesh.cornerKey)
			cut = cut || mesh.cornerKey[h] != mesh.cornerKey[size_t(heNext(tw))] ||
			      mesh.cornerKey[size_t(heNext(int32_t(h)))] != mesh.cornerKey[size_t(tw)];
		t.delimiter[h] = cut;
	}
}

// Faces the caller keeps as they are (MeshView::keepFace): their vertices are locked.
void lockKeptFaces(Topology &t)
{
	if (!t.keepFace)
		return;
	for (size_t f = 0; f < t.nF; ++f)
		if (t.keepFace[f] && !t.faceDropped[f])
			for (int k = 0; k < 3; ++k)
				t.vertexLocked[size_t(t.T[3 * f + k])] = 1;
}

// Topology::euler and boundaryVertex, for a clean input only (see there).
static void surfaceEuler(Topology &t)
{
	t.euler = kNoEuler;
	t.boundaryVertex.clear();
	if (t.keepFace)
		return;
	for (size_t f = 0; f < t.nF; ++f)
		if (t.faceDropped[f] || !t.faceValid[f])
			return;
	int64_t vertices = 0, edges = 0;
	for (size_t v = 0; v < t.nV; ++v) {
		if (t.vertexLocked[v])
			return;
		vertices += t.vfStart[v + 1] > t.vfStart[v];
	}
	// (no vertex locked: a half-edge without twin is on no other face, and each boundary vertex
	// has one fan, so one boundary half-edge leaving it)
	for (size_t h = 0; h < t.twin.size(); ++h) {
		if (t.twin[h] < 0)
			++edges, t.boundaryVertex.push_back(t.T[h]);
		else if (t.twin[h] > int32_t(h))
			++edges;
	}
	t.euler = vertices - edges + int64_t(t.nF);
}

size_t levelFaceBound(const Topology &t, const std::vector<uint8_t> &kept)
{
	if (t.euler == kNoEuler)
		return 0;
	int64_t n = 0, boundary = 0;
	for (size_t v = 0; v < t.nV; ++v)
		n += kept[v] != 0;
	for (const int32_t v : t.boundaryVertex)
		boundary += kept[size_t(v)] != 0;
	// (every other vertex of the level adds 2 faces, or 1 on the boundary)
	const int64_t faces = 2 * n - boundary - 2 * t.euler;
	return faces > 0 ? size_t(faces) : 0;
}

void classifyTopology(Topology &t, double featureAngleDeg, size_t threads)
{
	classifyVertices(t, featureAngleDeg, threads);
	surfaceEuler(t);
}

void buildTopology(const MeshView &mesh, double featureAngleDeg, Topology &t, size_t threads,
                   bool withGrid, bool withClasses, double diagonal)
{
	t.nV = mesh.vertexCount;
	t.nF = mesh.faceCount;
	t.P = mesh.positions;
	t.T = mesh.triangles;
	t.diagonal = diagonal >= 0 ? diagonal : bboxDiagonal(mesh);
	t.UV = mesh.cornerUV;
	t.wantSources = mesh.wantSources;
	t.keepFace = mesh.keepFace;
	dropNonTriangles(t, threads);
	computeFaces(t, threads);
	buildTwins(t, threads);
	markDelimiters(mesh, t);
	lockNonManifoldVertices(t, threads);
	lockKeptFaces(t);
	if (withClasses)
		classifyTopology(t, featureAngleDeg, threads);
	if (withGrid)
		buildFaceGrid(t);
}

} // namespace detail
} // namespace gausslod
