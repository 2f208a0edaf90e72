// Meshes built in the tests, the real models of Debian's libcgal-demo, and the invariants every
// level must keep (docs/ALGORITHM.md), checked independently of the engine's own figures.
#pragma once

#include "gausslod/gausslod.h"
#include "gausslod/vcg_adapter.h"

#include <vcg/space/distance3.h>
#include <vcg/space/triangle3.h>
#include <wrap/io_trimesh/import_off.h>

#include <algorithm>
#include <array>
#include <functional>
#include <map>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <unordered_map>
#include <vector>

namespace testmesh {

class TVertex;
class TFace;
struct TUsedTypes
    : public vcg::UsedTypes<vcg::Use<TVertex>::AsVertexType, vcg::Use<TFace>::AsFaceType> {};
class TVertex : public vcg::Vertex<TUsedTypes, vcg::vertex::Coord3d, vcg::vertex::Normal3d,
                                   vcg::vertex::BitFlags> {};
class TFace : public vcg::Face<TUsedTypes, vcg::face::VertexRef, vcg::face::Normal3d,
                               vcg::face::Color4b, vcg::face::Mark, vcg::face::BitFlags> {};
class TMesh : public vcg::tri::TriMesh<std::vector<TVertex>, std::vector<TFace>> {};

/// The filter's defaults for the superface levels alone: no level continued by collapses to a
/// real step (Params::completeChain), so what a test checks is the superface build's.
inline gausslod::Params superfaceParams()
{
	gausslod::Params p;
	p.completeChain = false;
	return p;
}

/// No straightening tolerance and no vicinity merging: every border vertex that is not exactly on
/// its chain is kept (Params() has the filter's defaults, 0.5 % / 0.25 % of the diagonal).
inline gausslod::Params exactParams()
{
	gausslod::Params p = superfaceParams();
	p.maxDistance = 0;
	p.straightenTol = 0;
	p.mergeDist = 0;
	return p;
}

/// The filter's defaults without the distance tolerance: normals alone decide, as in the paper.
inline gausslod::Params paperParams()
{
	gausslod::Params p = superfaceParams();
	p.maxDistance = 0;
	return p;
}

inline std::string dataFile(const std::string &name)
{
	return std::string(GAUSSLOD_DATA) + "/" + name;
}

inline gausslod::FlatMesh loadOff(const std::string &name)
{
	TMesh m;
	int mask = 0;
	const int err = vcg::tri::io::ImporterOFF<TMesh>::Open(m, dataFile(name).c_str(), mask);
	if (err != 0)
		throw std::runtime_error("cannot read " + dataFile(name));
	return gausslod::flatten(m);
}

/// `m` with the faces moved to the first vertex at each exact position (what welding on read
/// should give; written independently of the engine's hash table, with a sorted map).
inline gausslod::FlatMesh weldedCopy(const gausslod::FlatMesh &m)
{
	gausslod::FlatMesh out = m;
	std::map<std::array<double, 3>, int32_t> first;
	std::vector<int32_t> rep(m.positions.size() / 3);
	for (size_t v = 0; v < rep.size(); ++v) {
		std::array<double, 3> p = {m.positions[3 * v] + 0.0, m.positions[3 * v + 1] + 0.0,
		                           m.positions[3 * v + 2] + 0.0};
		const bool finite = std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
		rep[v] = finite ? first.emplace(p, int32_t(v)).first->second : int32_t(v);
	}
	for (int32_t &v : out.triangles)
		v = rep[size_t(v)];
	return out;
}

/// Axis-aligned cube [0,size]^3, each face an n x n grid of quads split in two, shared vertices.
inline gausslod::FlatMesh gridCube(int n, double size = 1.0, double noise = 0.0, unsigned seed = 1)
{
	gausslod::FlatMesh m;
	std::map<std::array<int, 3>, int32_t> index;
	auto vert = [&](int x, int y, int z) {
		auto it = index.find({x, y, z});
		if (it != index.end())
			return it->second;
		const int32_t id = int32_t(m.positions.size() / 3);
		index[{x, y, z}] = id;
		m.positions.push_back(size * x / n);
		m.positions.push_back(size * y / n);
		m.positions.push_back(size * z / n);
		return id;
	};
	// each cube face: axis a fixed at 0 or n, (b, c) span the grid, oriented outwards
	for (int a = 0; a < 3; ++a)
		for (int side = 0; side < 2; ++side)
			for (int i = 0; i < n; ++i)
				for (int j = 0; j < n; ++j) {
					auto P = [&](int u, int v) {
						int c[3];
						c[a] = side * n;
						c[(a + 1) % 3] = u;
						c[(a + 2) % 3] = v;
						return vert(c[0], c[1], c[2]);
					};
					int32_t q[4] = {P(i, j), P(i + 1, j), P(i + 1, j + 1), P(i, j + 1)};
					if (side == 0)
						std::swap(q[1], q[3]);
					const int32_t t[6] = {q[0], q[1], q[2], q[0], q[2], q[3]};
					m.triangles.insert(m.triangles.end(), t, t + 6);
				}
	if (noise > 0) {
		std::mt19937 rng(seed);
		std::uniform_real_distribution<double> u(-noise, noise);
		for (double &x : m.positions)
			x += u(rng);
	}
	return m;
}

/// Each triangle of m split into 4 at its edge midpoints (shared by the edge's two triangles): the
/// same surface with 4 times the faces, every input triangle now 4 coplanar ones. `toFloat`:
/// coordinates rounded to 32-bit floats, as a PLY or STL file of floats holds them (the 4 are
/// then coplanar only within the floats' rounding).
inline gausslod::FlatMesh midpointSplit(const gausslod::FlatMesh &m, bool toFloat = false)
{
	gausslod::FlatMesh out;
	out.positions = m.positions;
	std::map<std::pair<int32_t, int32_t>, int32_t> mid;
	auto midpoint = [&](int32_t a, int32_t b) {
		const auto key = std::make_pair(std::min(a, b), std::max(a, b));
		const auto it = mid.find(key);
		if (it != mid.end())
			return it->second;
		const int32_t id = int32_t(out.positions.size() / 3);
		for (int k = 0; k < 3; ++k)
			out.positions.push_back(0.5 * (m.positions[3 * size_t(a) + size_t(k)] +
			                               m.positions[3 * size_t(b) + size_t(k)]));
		mid.emplace(key, id);
		return id;
	};
	for (size_t f = 0; f < m.triangles.size(); f += 3) {
		const int32_t a = m.triangles[f], b = m.triangles[f + 1], c = m.triangles[f + 2];
		const int32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
		out.triangles.insert(out.triangles.end(), {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca});
	}
	if (toFloat)
		for (double &x : out.positions)
			x = double(float(x));
	return out;
}

/// Planar n x n grid in z=0 over [0,1]^2 with the square [lo,hi]^2 cut out.
inline gausslod::FlatMesh gridWithHole(int n, int lo, int hi)
{
	gausslod::FlatMesh m;
	for (int y = 0; y <= n; ++y)
		for (int x = 0; x <= n; ++x) {
			m.positions.push_back(double(x) / n);
			m.positions.push_back(double(y) / n);
			m.positions.push_back(0.0);
		}
	auto id = [&](int x, int y) { return int32_t(y * (n + 1) + x); };
	for (int y = 0; y < n; ++y)
		for (int x = 0; x < n; ++x) {
			if (x >= lo && x < hi && y >= lo && y < hi)
				continue;
			const int32_t t[6] = {id(x, y), id(x + 1, y),     id(x + 1, y + 1),
			                      id(x, y), id(x + 1, y + 1), id(x, y + 1)};
			m.triangles.insert(m.triangles.end(), t, t + 6);
		}
	return m;
}

using Vec3 = vcg::Point3d;

inline Vec3 vpos(const std::vector<double> &P, int32_t v)
{
	return Vec3(P[3 * v], P[3 * v + 1], P[3 * v + 2]);
}

/// Topological facts of a triangle mesh given as flat arrays.
struct TopoFacts {
	size_t faces = 0, usedVertices = 0, edges = 0;
	size_t boundaryEdges = 0, nonManifoldEdges = 0, inconsistentEdges = 0;
	size_t degenerateFaces = 0, duplicateFaces = 0, nonManifoldVertices = 0;
	size_t components = 0, boundaryLoops = 0;
	long euler = 0;
	bool closedManifold() const
	{
		return boundaryEdges == 0 && nonManifoldEdges == 0 && inconsistentEdges == 0 &&
		       nonManifoldVertices == 0;
	}
	long genus() const { return (2 * long(components) - euler) / 2; }
};

inline TopoFacts topoFacts(const std::vector<double> &P, const std::vector<int32_t> &T)
{
	TopoFacts r;
	r.faces = T.size() / 3;
	std::map<std::pair<int32_t, int32_t>, std::pair<int, int>> edges; // (min,max) -> (count, fwd)
	std::set<std::array<int32_t, 3>> faces;
	std::vector<int32_t> parent(P.size() / 3);
	for (size_t i = 0; i < parent.size(); ++i)
		parent[i] = int32_t(i);
	std::function<int32_t(int32_t)> find = [&](int32_t x) {
		while (parent[size_t(x)] != x)
			x = parent[size_t(x)] = parent[size_t(parent[size_t(x)])];
		return x;
	};
	std::set<int32_t> used;
	for (size_t f = 0; f < r.faces; ++f) {
		const int32_t a = T[3 * f], b = T[3 * f + 1], c = T[3 * f + 2];
		const Vec3 n = (vpos(P, b) - vpos(P, a)) ^ (vpos(P, c) - vpos(P, a));
		if (a == b || b == c || a == c || !(n.Norm() > 0))
			++r.degenerateFaces;
		// same face, same orientation (a reversed copy makes a two-sided sheet: not a duplicate)
		const int m = a < b ? (a < c ? 0 : 2) : (b < c ? 1 : 2);
		const std::array<int32_t, 3> key = {T[3 * f + m], T[3 * f + (m + 1) % 3],
		                                    T[3 * f + (m + 2) % 3]};
		if (!faces.insert(key).second)
			++r.duplicateFaces;
		for (int k = 0; k < 3; ++k) {
			const int32_t u = T[3 * f + k], v = T[3 * f + (k + 1) % 3];
			auto &e = edges[{std::min(u, v), std::max(u, v)}];
			++e.first;
			e.second += u < v;
			used.insert(u);
			parent[size_t(find(u))] = find(v);
		}
	}
	r.usedVertices = used.size();
	r.edges = edges.size();
	std::map<int32_t, std::vector<int32_t>> boundaryAdj;
	for (const auto &e : edges) {
		if (e.second.first == 1) {
			++r.boundaryEdges;
			boundaryAdj[e.first.first].push_back(e.first.second);
			boundaryAdj[e.first.second].push_back(e.first.first);
		} else if (e.second.first > 2)
			++r.nonManifoldEdges;
		else if (e.second.second != 1)
			++r.inconsistentEdges;
	}
	std::set<int32_t> roots;
	for (int32_t v : used)
		roots.insert(find(v));
	r.components = roots.size();
	r.euler = long(r.usedVertices) - long(r.edges) + long(r.faces);
	// boundary loops: components of the boundary-edge graph
	std::set<int32_t> seen;
	for (const auto &kv : boundaryAdj) {
		if (seen.count(kv.first))
			continue;
		++r.boundaryLoops;
		std::vector<int32_t> stack{kv.first};
		seen.insert(kv.first);
		while (!stack.empty()) {
			const int32_t v = stack.back();
			stack.pop_back();
			for (int32_t w : boundaryAdj[v])
				if (seen.insert(w).second)
					stack.push_back(w);
		}
	}
	// non-manifold vertices: the faces around a vertex must form one fan (edge-connected)
	std::map<int32_t, std::vector<size_t>> vf;
	for (size_t f = 0; f < r.faces; ++f)
		for (int k = 0; k < 3; ++k)
			vf[T[3 * f + k]].push_back(f);
	for (const auto &kv : vf) {
		const int32_t v = kv.first;
		const auto &fs = kv.second;
		std::vector<int> comp(fs.size(), -1);
		int ncomp = 0;
		for (size_t i = 0; i < fs.size(); ++i) {
			if (comp[i] >= 0)
				continue;
			std::vector<size_t> st{i};
			comp[i] = ncomp;
			while (!st.empty()) {
				const size_t q = st.back();
				st.pop_back();
				for (size_t j = 0; j < fs.size(); ++j) {
					if (comp[j] >= 0)
						continue;
					int shared = 0; // share an edge through v: a second common vertex
					for (int a = 0; a < 3; ++a)
						for (int b = 0; b < 3; ++b) {
							const int32_t x = T[3 * fs[q] + a];
							if (x != v && x == T[3 * fs[j] + b])
								++shared;
						}
					if (shared > 0) {
						comp[j] = ncomp;
						st.push_back(j);
					}
				}
			}
			++ncomp;
		}
		if (ncomp > 1)
			++r.nonManifoldVertices;
	}
	return r;
}

/// The input face nearest a point: faces listed in every cell of a uniform grid their boxes meet.
class NearestInputFace {
public:
	explicit NearestInputFace(const gausslod::FlatMesh &m) : m_(m)
	{
		const size_t nF = m.triangles.size() / 3;
		double area = 0;
		for (size_t f = 0; f < nF; ++f)
			area += ((corner(f, 1) - corner(f, 0)) ^ (corner(f, 2) - corner(f, 0))).Norm();
		cell_ = std::max(2 * std::sqrt(area / double(std::max<size_t>(nF, 1))), 1e-12);
		for (size_t f = 0; f < nF; ++f) {
			Vec3 lo = corner(f, 0), hi = lo;
			for (int k = 1; k < 3; ++k)
				for (int j = 0; j < 3; ++j)
					lo[j] = std::min(lo[j], corner(f, k)[j]),
					hi[j] = std::max(hi[j], corner(f, k)[j]);
			for (long z = idx(lo[2]); z <= idx(hi[2]); ++z)
				for (long y = idx(lo[1]); y <= idx(hi[1]); ++y)
					for (long x = idx(lo[0]); x <= idx(hi[0]); ++x)
						cells_[key(x, y, z)].push_back(f);
		}
	}
	/// Does a face nearest p (of those equally near: an edge or a vertex several faces touch)
	/// face n (normal . n >= 0)?
	bool nearestFaces(const Vec3 &p, const Vec3 &n) const
	{
		for (double r = cell_;; r *= 2) {
			double best = HUGE_VAL;
			std::vector<std::pair<double, size_t>> near;
			for (long z = idx(p[2] - r); z <= idx(p[2] + r); ++z)
				for (long y = idx(p[1] - r); y <= idx(p[1] + r); ++y)
					for (long x = idx(p[0] - r); x <= idx(p[0] + r); ++x) {
						const auto it = cells_.find(key(x, y, z));
						if (it == cells_.end())
							continue;
						for (size_t f : it->second) {
							vcg::Triangle3<double> tri(corner(f, 0), corner(f, 1), corner(f, 2));
							Vec3 closest;
							double d = HUGE_VAL;
							vcg::TrianglePointDistance(tri, p, d, closest);
							near.emplace_back(d, f);
							best = std::min(best, d);
						}
					}
			if (best <= r) {
				for (const auto &df : near)
					if (df.first <= best * (1 + 1e-9) + 1e-15 &&
					    ((corner(df.second, 1) - corner(df.second, 0)) ^
					     (corner(df.second, 2) - corner(df.second, 0)))
					            .dot(n) >= 0)
						return true;
				return false;
			}
		}
	}

private:
	const gausslod::FlatMesh &m_;
	double cell_ = 1;
	struct KeyHash {
		size_t operator()(const std::tuple<long, long, long> &k) const
		{
			return size_t(std::get<0>(k)) * 73856093u ^ size_t(std::get<1>(k)) * 19349663u ^
			       size_t(std::get<2>(k)) * 83492791u;
		}
	};
	std::unordered_map<std::tuple<long, long, long>, std::vector<size_t>, KeyHash> cells_;
	Vec3 corner(size_t f, int k) const
	{
		return vpos(m_.positions, m_.triangles[3 * f + size_t(k)]);
	}
	long idx(double x) const { return long(std::floor(x / cell_)); }
	static std::tuple<long, long, long> key(long x, long y, long z) { return {x, y, z}; }
};

/// Output faces whose normal points away (>90 deg) from the input faces they replace: every input
/// face nearest the output face's centroid (of those equally near) faces away from it.
inline size_t flippedFaces(const gausslod::FlatMesh &input, const gausslod::LevelMesh &level)
{
	const NearestInputFace nearest(input);
	size_t flipped = 0;
	for (size_t t = 0; t < level.triangles.size() / 3; ++t) {
		const Vec3 a = vpos(level.positions, level.triangles[3 * t]);
		const Vec3 b = vpos(level.positions, level.triangles[3 * t + 1]);
		const Vec3 c = vpos(level.positions, level.triangles[3 * t + 2]);
		flipped += !nearest.nearestFaces((a + b + c) / 3.0, (b - a) ^ (c - a));
	}
	return flipped;
}

/// Output faces whose normal points away (>90 deg) from the nearest input face (ties between faces
/// at the same distance count as facing if any of them faces the output face), as the benchmark
/// measures "flipped": flippedFaces.
inline size_t facesAwayFromNearestInput(const gausslod::FlatMesh &input,
                                        const gausslod::LevelMesh &level)
{
	return flippedFaces(input, level);
}

} // namespace testmesh
