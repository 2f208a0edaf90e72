// Adjacency (2.2: which edges may join a superface) and vertex classes (2.3.2), one linear pass each.
#include "engine.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace gausslod {
namespace detail {

namespace {

constexpr double kRadToDeg = 57.295779513082320876798;

double angleDeg(const Vec3 &a, const Vec3 &b)
{
	const double d = std::max(-1.0, std::min(1.0, a.dot(b)));
	return std::acos(d) * kRadToDeg;
}

void computeFaces(Topology &t)
{
	t.faceNormal.assign(t.nF, Vec3(0, 0, 0));
	t.faceArea.assign(t.nF, 0.0);
	t.faceValid.assign(t.nF, 0);
	// Faces smaller than this (relative to the model size) have no reliable normal.
	const double minCross = 1e-20 * t.diagonal * t.diagonal;
	for (size_t f = 0; f < t.nF; ++f) {
		const int32_t a = t.T[3 * f], b = t.T[3 * f + 1], c = t.T[3 * f + 2];
		if (t.faceDropped[f])
			continue;
		const Vec3 n = (t.pos(b) - t.pos(a)) ^ (t.pos(c) - t.pos(a));
		const double len = n.Norm();
		if (!std::isfinite(len) || len <= minCross)
			continue;
		t.faceNormal[f] = n / len;
		t.faceArea[f] = 0.5 * len;
		t.faceValid[f] = 1;
	}
}

// Vertex -> faces (CSR) over the faces that are not dropped.
void buildVertexFaces(Topology &t)
{
	t.vfStart.assign(t.nV + 1, 0);
	for (size_t f = 0; f < t.nF; ++f)
		if (!t.faceDropped[f])
			for (int k = 0; k < 3; ++k)
				++t.vfStart[size_t(t.T[3 * f + size_t(k)]) + 1];
	for (size_t v = 0; v < t.nV; ++v)
		t.vfStart[v + 1] += t.vfStart[v];
	t.vfFace.resize(size_t(t.vfStart[t.nV]));
	std::vector<int32_t> fill(t.vfStart.begin(), t.vfStart.end() - 1);
	for (size_t f = 0; f < t.nF; ++f)
		if (!t.faceDropped[f])
			for (int k = 0; k < 3; ++k)
				t.vfFace[size_t(fill[size_t(t.T[3 * f + size_t(k)])]++)] = int32_t(f);
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
void dropNonTriangles(Topology &t)
{
	t.faceDropped.assign(t.nF, 0);
	for (size_t f = 0; f < t.nF; ++f) {
		const int32_t a = t.T[3 * f], b = t.T[3 * f + 1], c = t.T[3 * f + 2];
		t.faceDropped[f] = a == b || b == c || a == c;
	}
	buildVertexFaces(t);
	bool any = false;
	for (size_t f = 0; f < t.nF; ++f) {
		if (t.faceDropped[f])
			continue;
		const std::array<int32_t, 3> key = orientedKey(t, f);
		for (int32_t i = t.vfStart[size_t(key[0])]; i < t.vfStart[size_t(key[0]) + 1]; ++i) {
			const int32_t g = t.vfFace[size_t(i)];
			if (size_t(g) >= f || t.faceDropped[size_t(g)] || orientedKey(t, size_t(g)) != key)
				continue;
			t.faceDropped[f] = 1;
			any = true;
			break;
		}
	}
	if (any)
		buildVertexFaces(t);
}

// Twins across 2-manifold, consistently oriented edges; everything else locks its vertices.
void buildTwins(Topology &t)
{
	t.twin.assign(3 * t.nF, -1);
	t.vertexLocked.assign(t.nV, 0);
	for (size_t f = 0; f < t.nF; ++f) {
		if (t.faceDropped[f])
			continue;
		if (!t.faceValid[f]) {
			for (int k = 0; k < 3; ++k)
				t.vertexLocked[size_t(t.T[3 * f + k])] = 1;
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
				t.vertexLocked[size_t(a)] = t.vertexLocked[size_t(b)] = 1;
		}
	}
}

// A vertex whose incident faces do not form one fan through twins is non-manifold: lock it.
void lockNonManifoldVertices(Topology &t)
{
	for (size_t v = 0; v < t.nV; ++v) {
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
}

// 2.3.2: A1 = largest angle between two incident face normals (two linear sweeps approximate the
// diameter), the faces split into two groups around those two bases, A2 = the larger group cone.
void classifyVertices(Topology &t, double thresholdDeg)
{
	t.vertexClass.assign(t.nV, kFlat);
	for (size_t v = 0; v < t.nV; ++v) {
		const int32_t begin = t.vfStart[v], end = t.vfStart[v + 1];
		Vec3 mean(0, 0, 0);
		for (int32_t i = begin; i < end; ++i)
			mean += t.faceNormal[size_t(t.vfFace[size_t(i)])];
		auto farthestFrom = [&](const Vec3 &dir, int group, const Vec3 *b1, const Vec3 *b2) {
			int32_t best = -1;
			double bestDot = HUGE_VAL;
			for (int32_t i = begin; i < end; ++i) {
				const int32_t f = t.vfFace[size_t(i)];
				if (!t.faceValid[size_t(f)])
					continue;
				const Vec3 &n = t.faceNormal[size_t(f)];
				if (group >= 0 && (n.dot(*b1) >= n.dot(*b2) ? 0 : 1) != group)
					continue;
				const double d = n.dot(dir);
				if (d < bestDot) {
					bestDot = d;
					best = f;
				}
			}
			return best;
		};
		const int32_t f1 = farthestFrom(mean, -1, nullptr, nullptr);
		if (f1 < 0)
			continue;
		const Vec3 b1 = t.faceNormal[size_t(f1)];
		const Vec3 b2 = t.faceNormal[size_t(farthestFrom(b1, -1, nullptr, nullptr))];
		const double a1 = angleDeg(b1, b2);
		if (a1 < thresholdDeg)
			continue;
		double a2 = 0;
		for (int group = 0; group < 2; ++group) {
			const Vec3 &base = group == 0 ? b1 : b2;
			const int32_t g1 = farthestFrom(base, group, &b1, &b2);
			if (g1 < 0)
				continue;
			const Vec3 e1 = t.faceNormal[size_t(g1)];
			const int32_t g2 = farthestFrom(e1, group, &b1, &b2);
			a2 = std::max(a2, angleDeg(e1, t.faceNormal[size_t(g2)]));
		}
		t.vertexClass[v] = a2 > thresholdDeg ? kCorner : kEdge;
	}
}

} // namespace

void buildTopology(const MeshView &mesh, double featureAngleDeg, Topology &t)
{
	t.nV = mesh.vertexCount;
	t.nF = mesh.faceCount;
	t.P = mesh.positions;
	t.T = mesh.triangles;
	t.diagonal = bboxDiagonal(mesh);
	dropNonTriangles(t);
	computeFaces(t);
	buildTwins(t);
	lockNonManifoldVertices(t);
	classifyVertices(t, featureAngleDeg);
}

} // namespace detail
} // namespace gausslod
