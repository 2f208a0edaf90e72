// Experiment (DESIGN 30, 2026-12-05): a coarser level made from the finer level's mesh by
// half-edge collapses, cheapest quadric first, with a distance bound proven per collapse.
//
// A half-edge collapse v -> u replaces the triangles around v (the ring) by a fan from u over the
// same outline (v's link). Where both the ring and the fan are one-to-one over the plane
// orthogonal to n (every triangle facing n, the ring winding once around v), they are two height
// fields over the same polygon, so every point of one is straight above or below a point of the
// other, and their vertical gap is linear on each cell of the overlay of the two triangulations:
// its largest value is at v or where a spoke of v crosses a spoke of u. Each triangle carries a
// bound e on its distance to the input (both ways: every point of it within e of the input, and
// every input point it took over within e of it); the fan's triangles get the largest e of the
// ring plus that gap. Each triangle also carries a cone of the normals it covers; a fan triangle
// must stay within `bound` of its merged cone.
//
// usage: bench_collapse FINER.ply TARGET_FACES TOLERANCE E0 NORMAL_BOUND_DEG OUT.ply
//   TOLERANCE, E0 (the finer level's own bound): mesh units
#include "bench_mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <queue>

namespace {

struct V3 {
	double x = 0, y = 0, z = 0;
};
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 operator*(double s, V3 a) { return {s * a.x, s * a.y, s * a.z}; }
double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double norm(V3 a) { return std::sqrt(dot(a, a)); }
V3 unit(V3 a)
{
	const double l = norm(a);
	return l > 0 ? (1.0 / l) * a : V3{};
}

struct Cone {
	V3 axis;
	double half = 0; // radians
};

double angle(V3 a, V3 b) { return std::atan2(norm(cross(a, b)), dot(a, b)); }

// The smallest cone (of this kind) holding both.
Cone merge(const Cone &a, const Cone &b)
{
	const double d = angle(a.axis, b.axis);
	if (d + b.half <= a.half)
		return a;
	if (d + a.half <= b.half)
		return b;
	const double half = 0.5 * (d + a.half + b.half);
	if (half >= M_PI)
		return {a.axis, M_PI};
	// rotate a.axis towards b.axis by (half - a.half)
	const double t = half - a.half;
	V3 w = b.axis - dot(b.axis, a.axis) * a.axis;
	const double wl = norm(w);
	if (wl < 1e-15)
		return {a.axis, half};
	w = (1.0 / wl) * w;
	return {unit(std::cos(t) * a.axis + std::sin(t) * w), half};
}

using Quadric = std::array<double, 10>; // a2 ab ac ad b2 bc bd c2 cd d2

void addPlane(Quadric &q, V3 n, double d, double w)
{
	const double a = n.x, b = n.y, c = n.z;
	const double v[10] = {a * a, a * b, a * c, a * d, b * b, b * c, b * d, c * c, c * d, d * d};
	for (int i = 0; i < 10; ++i)
		q[size_t(i)] += w * v[i];
}

double evalQ(const Quadric &q, V3 p)
{
	const double x = p.x, y = p.y, z = p.z;
	return q[0] * x * x + 2 * q[1] * x * y + 2 * q[2] * x * z + 2 * q[3] * x + q[4] * y * y +
	       2 * q[5] * y * z + 2 * q[6] * y + q[7] * z * z + 2 * q[8] * z + q[9];
}

struct Mesh {
	std::vector<V3> P;
	std::vector<std::array<int, 3>> F;
	std::vector<uint8_t> faceAlive, vertAlive, locked;
	std::vector<std::vector<int>> vf;
	std::vector<double> e;
	std::vector<Cone> cone;
	std::vector<Quadric> Q;
	std::vector<double> Qw;
	std::vector<uint32_t> stamp;
	size_t liveFaces = 0;

	V3 normalOf(const std::array<int, 3> &t) const
	{
		return cross(P[size_t(t[1])] - P[size_t(t[0])], P[size_t(t[2])] - P[size_t(t[0])]);
	}
};

long rej[12];
struct Candidate {
	bool ok = false;
	double cost = 0, e = 0;
	Cone cone;
};

// The faces around v in mesh order is not needed: every test below works on the set.
Candidate evaluate(const Mesh &m, int v, int u, double tol, double boundRad)
{
	Candidate c;
	if (m.locked[size_t(v)])
		return ++rej[0], c;
	const std::vector<int> &ring = m.vf[size_t(v)];
	int shared = 0;
	std::vector<int> linkV, linkU;
	for (int f : ring)
		for (int k = 0; k < 3; ++k) {
			const int w = m.F[size_t(f)][size_t(k)];
			if (w == u && ++shared > 2)
				return c;
			if (w != v)
				linkV.push_back(w);
		}
	if (shared != 2)
		return ++rej[1], c;
	for (int f : m.vf[size_t(u)])
		for (int k = 0; k < 3; ++k)
			linkU.push_back(m.F[size_t(f)][size_t(k)]);
	std::sort(linkV.begin(), linkV.end());
	linkV.erase(std::unique(linkV.begin(), linkV.end()), linkV.end());
	std::sort(linkU.begin(), linkU.end());
	linkU.erase(std::unique(linkU.begin(), linkU.end()), linkU.end());
	int common = 0;
	for (int w : linkV)
		if (w != u && std::binary_search(linkU.begin(), linkU.end(), w))
			++common;
	if (common != 2)
		return ++rej[2], c;
	// projection direction
	V3 n{};
	for (int f : ring)
		n = n + m.normalOf(m.F[size_t(f)]);
	n = unit(n);
	if (norm(n) == 0)
		return c;
	const V3 a = unit(std::fabs(n.x) < 0.9 ? cross(n, V3{1, 0, 0}) : cross(n, V3{0, 1, 0}));
	const V3 b = cross(n, a);
	struct P2 {
		double x, y, h;
	};
	auto proj = [&](int w) {
		const V3 p = m.P[size_t(w)];
		return P2{dot(p, a), dot(p, b), dot(p, n)};
	};
	const double eps = 1e-3;
	// old ring: facing n, winding once around v
	double wind = 0, eMax = 0;
	Cone cone{unit(m.normalOf(m.F[size_t(ring[0])])), 0};
	bool first = true;
	for (int f : ring) {
		const auto &t = m.F[size_t(f)];
		const V3 nf = unit(m.normalOf(t));
		if (dot(nf, n) < eps)
			return ++rej[3], c;
		int k = 0;
		while (t[size_t(k)] != v)
			++k;
		const P2 pv = proj(v), p1 = proj(t[size_t((k + 1) % 3)]), p2 = proj(t[size_t((k + 2) % 3)]);
		wind += std::atan2((p1.x - pv.x) * (p2.y - pv.y) - (p1.y - pv.y) * (p2.x - pv.x),
		                   (p1.x - pv.x) * (p2.x - pv.x) + (p1.y - pv.y) * (p2.y - pv.y));
		eMax = std::max(eMax, m.e[size_t(f)]);
		cone = first ? m.cone[size_t(f)] : merge(cone, m.cone[size_t(f)]);
		first = false;
	}
	if (std::fabs(wind - 2 * M_PI) > 1e-6)
		return ++rej[4], c;
	// the fan: faces of the ring without u, v replaced by u
	std::vector<std::array<int, 3>> fan;
	for (int f : ring) {
		auto t = m.F[size_t(f)];
		if (t[0] == u || t[1] == u || t[2] == u)
			continue;
		for (int &w : t)
			if (w == v)
				w = u;
		const V3 nt = m.normalOf(t);
		const double area2 = norm(nt);
		if (area2 <= 1e-300 || dot(unit(nt), n) < eps)
			return ++rej[5], c;
		if (angle(unit(nt), cone.axis) + cone.half > boundRad)
			return ++rej[6], c;
		fan.push_back(t);
	}
	// the gap: at v ...
	const P2 pv = proj(v), pu = proj(u);
	double gap = -1;
	for (const auto &t : fan) {
		const P2 A = proj(t[0]), B = proj(t[1]), C = proj(t[2]);
		const double d = (B.x - A.x) * (C.y - A.y) - (B.y - A.y) * (C.x - A.x);
		const double l1 = ((B.x - pv.x) * (C.y - pv.y) - (B.y - pv.y) * (C.x - pv.x)) / d;
		const double l2 = ((C.x - pv.x) * (A.y - pv.y) - (C.y - pv.y) * (A.x - pv.x)) / d;
		const double l3 = 1 - l1 - l2;
		if (l1 >= -1e-9 && l2 >= -1e-9 && l3 >= -1e-9) {
			gap = std::max(gap, std::fabs(pv.h - (l1 * A.h + l2 * B.h + l3 * C.h)));
		}
	}
	if (gap < 0) // (v not over the fan: the outline is not star-shaped from u)
		return ++rej[7], c;
	// ... and where a spoke of v crosses a spoke of u
	for (int w : linkV) {
		if (w == u)
			continue;
		const P2 pw = proj(w);
		for (int x : linkV) {
			if (x == u || x == w)
				continue;
			const P2 px = proj(x);
			// segment v-w against u-x
			const double rx = pw.x - pv.x, ry = pw.y - pv.y, sx = px.x - pu.x, sy = px.y - pu.y;
			const double den = rx * sy - ry * sx;
			if (std::fabs(den) < 1e-300)
				continue;
			const double qx = pu.x - pv.x, qy = pu.y - pv.y;
			const double t = (qx * sy - qy * sx) / den, s = (qx * ry - qy * rx) / den;
			if (t <= 0 || t >= 1 || s <= 0 || s >= 1)
				continue;
			const double h1 = pv.h + t * (pw.h - pv.h), h2 = pu.h + s * (px.h - pu.h);
			gap = std::max(gap, std::fabs(h1 - h2));
		}
	}
	c.e = eMax + gap;
	if (c.e > tol)
		return ++rej[8], c;
	c.cone = cone;
	static const int mode = std::getenv("COST") ? std::atoi(std::getenv("COST")) : 0;
	const double q = evalQ(m.Q[size_t(v)], m.P[size_t(u)]);
	c.cost = mode == 1 ? c.e : mode == 2 ? gap : mode == 3 ? std::sqrt(std::max(0.0, q / std::max(1e-300, m.Qw[size_t(v)]))) + gap : q;
	c.ok = true;
	return c;
}

struct Entry {
	double cost;
	int v, u;
	uint32_t stamp;
	bool operator<(const Entry &o) const { return cost > o.cost; }
};

} // namespace

int main(int argc, char **argv)
{
	if (argc != 7) {
		std::fprintf(stderr, "usage: bench_collapse FINER.ply TARGET_FACES TOLERANCE E0 "
		                     "NORMAL_BOUND_DEG OUT.ply\n");
		return 2;
	}
	bench::FMesh fm;
	std::string err;
	if (!bench::load(fm, argv[1], err)) {
		std::fprintf(stderr, "%s\n", err.c_str());
		return 1;
	}
	const bench::Flat flat = bench::flatten(fm);
	const size_t target = size_t(std::atol(argv[2]));
	const double tol = std::atof(argv[3]), e0 = std::atof(argv[4]);
	const double boundRad = std::atof(argv[5]) * M_PI / 180;
	const double t0 = bench::now();
	Mesh m;
	const size_t nV = flat.vn(), nF = flat.fn();
	m.P.resize(nV);
	for (size_t i = 0; i < nV; ++i)
		m.P[i] = {flat.pos[3 * i], flat.pos[3 * i + 1], flat.pos[3 * i + 2]};
	m.F.resize(nF);
	m.vf.resize(nV);
	m.faceAlive.assign(nF, 1);
	m.vertAlive.assign(nV, 1);
	m.locked.assign(nV, 0);
	m.e.assign(nF, e0);
	m.cone.resize(nF);
	m.Q.assign(nV, Quadric{});
	m.Qw.assign(nV, 0.0);
	m.stamp.assign(nV, 0);
	m.liveFaces = nF;
	std::vector<std::array<int, 2>> edges;
	for (size_t f = 0; f < nF; ++f) {
		for (int k = 0; k < 3; ++k) {
			m.F[f][size_t(k)] = int(flat.tri[3 * f + size_t(k)]);
			m.vf[flat.tri[3 * f + size_t(k)]].push_back(int(f));
		}
		const V3 nn = m.normalOf(m.F[f]);
		const V3 un = unit(nn);
		m.cone[f] = {un, 0};
		for (int k = 0; k < 3; ++k) {
			const int a = m.F[f][size_t(k)], b = m.F[f][size_t((k + 1) % 3)];
			edges.push_back({std::min(a, b), std::max(a, b)});
			addPlane(m.Q[size_t(a)], un, -dot(un, m.P[size_t(m.F[f][0])]), 0.5 * norm(nn));
			m.Qw[size_t(a)] += 0.5 * norm(nn);
		}
	}
	std::sort(edges.begin(), edges.end());
	for (size_t i = 0; i < edges.size();) {
		size_t j = i;
		while (j < edges.size() && edges[j] == edges[i])
			++j;
		if (j - i != 2)
			m.locked[size_t(edges[i][0])] = m.locked[size_t(edges[i][1])] = 1;
		i = j;
	}
	std::priority_queue<Entry> heap;
	auto best = [&](int v) {
		Candidate bc;
		int bu = -1;
		for (int f : m.vf[size_t(v)])
			for (int k = 0; k < 3; ++k) {
				const int u = m.F[size_t(f)][size_t(k)];
				if (u == v)
					continue;
				const Candidate c = evaluate(m, v, u, tol, boundRad);
				if (c.ok && (!bc.ok || c.cost < bc.cost))
					bc = c, bu = u;
			}
		if (bc.ok)
			heap.push({bc.cost, v, bu, m.stamp[size_t(v)]});
	};
	for (size_t v = 0; v < nV; ++v)
		if (!m.vf[v].empty())
			best(int(v));
	double eMax = e0;
	size_t collapses = 0;
	while (m.liveFaces > target && !heap.empty()) {
		const Entry top = heap.top();
		heap.pop();
		if (!m.vertAlive[size_t(top.v)] || top.stamp != m.stamp[size_t(top.v)])
			continue;
		const Candidate c = evaluate(m, top.v, top.u, tol, boundRad);
		if (!c.ok || c.cost > top.cost * (1 + 1e-9) + 1e-300) {
			++m.stamp[size_t(top.v)];
			best(top.v);
			continue;
		}
		const int v = top.v, u = top.u;
		std::vector<int> link;
		std::vector<int> &ringU = m.vf[size_t(u)];
		for (int f : m.vf[size_t(v)]) {
			auto &t = m.F[size_t(f)];
			for (int w : t)
				if (w != v && w != u)
					link.push_back(w);
			if (t[0] == u || t[1] == u || t[2] == u) {
				m.faceAlive[size_t(f)] = 0;
				--m.liveFaces;
				for (int w : t)
					if (w != v) {
						auto &l = m.vf[size_t(w)];
						l.erase(std::remove(l.begin(), l.end(), f), l.end());
					}
			} else {
				for (int &w : t)
					if (w == v)
						w = u;
				m.e[size_t(f)] = c.e;
				m.cone[size_t(f)] = c.cone;
				ringU.push_back(f);
			}
		}
		m.vf[size_t(v)].clear();
		m.vertAlive[size_t(v)] = 0;
		for (size_t i = 0; i < 10; ++i)
			m.Q[size_t(u)][i] += m.Q[size_t(v)][i];
		m.Qw[size_t(u)] += m.Qw[size_t(v)];
		eMax = std::max(eMax, c.e);
		++collapses;
		std::sort(link.begin(), link.end());
		link.erase(std::unique(link.begin(), link.end()), link.end());
		link.push_back(u);
		for (int w : link) {
			++m.stamp[size_t(w)];
			best(w);
		}
	}
	const double secs = bench::now() - t0;
	// write
	std::vector<int> remap(nV, -1);
	int next = 0;
	for (size_t f = 0; f < nF; ++f)
		if (m.faceAlive[f])
			for (int w : m.F[f])
				if (remap[size_t(w)] < 0)
					remap[size_t(w)] = next++;
	FILE *o = std::fopen(argv[6], "w");
	if (!o)
		return 1;
	std::fprintf(o, "ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\n"
	                "property float z\nelement face %zu\nproperty list uchar int vertex_indices\n"
	                "end_header\n",
	             next, m.liveFaces);
	std::vector<V3> out(static_cast<size_t>(next));
	for (size_t v = 0; v < nV; ++v)
		if (remap[v] >= 0)
			out[size_t(remap[v])] = m.P[v];
	for (const V3 &p : out)
		std::fprintf(o, "%.9g %.9g %.9g\n", p.x, p.y, p.z);
	for (size_t f = 0; f < nF; ++f)
		if (m.faceAlive[f])
			std::fprintf(o, "3 %d %d %d\n", remap[size_t(m.F[f][0])], remap[size_t(m.F[f][1])],
			             remap[size_t(m.F[f][2])]);
	std::fclose(o);
	if (std::getenv("REJ")) for (int i = 0; i < 9; ++i) std::fprintf(stderr, "rej%d %ld\n", i, rej[i]);
	std::printf("{\"faces\": %zu, \"collapses\": %zu, \"bound\": %.9g, \"seconds\": %.4f}\n",
	            m.liveFaces, collapses, eMax, secs);
	return 0;
}
