// The proof of one collapse (reduce_patch.h, docs/DESIGN.md 51).
//
// Both the old patch and the new fan are projected on the plane orthogonal to the old patch's
// area-weighted normal n. If every triangle of both faces n and the new fan winds once around its
// new vertex (or, with the kept vertex on the outline, the old triangles wind once around the
// removed vertex), both are one-to-one over the same simple polygon: every point of either is
// straight above or below a point of the other. On each cell of the overlay of the two
// triangulations both are linear, so their vertical gap is largest at a corner of a cell: an
// outline vertex (gap 0: both surfaces go through it), a removed vertex, the new vertex, or where
// an inner edge of one crosses an inner edge of the other. A vertex leaving a mesh boundary takes
// a pocket off the outline: the old surface over it is within the removed vertex's distance of
// the new boundary edge, or within the gaps where old edges cross that edge (the distance to a
// segment is convex, and those are the corners of the old surface's pieces over the pocket).
#include "reduce_patch.h"

namespace gausslod {
namespace detail {

namespace {

constexpr double kWinding = 1e-6; // radians

double orient(const double *a, const double *b, const double *c)
{
	return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

// The angle a-o-b seen from o, signed (counter-clockwise positive).
double turn(const double *o, const double *a, const double *b)
{
	const double x1 = a[0] - o[0], y1 = a[1] - o[1], x2 = b[0] - o[0], y2 = b[1] - o[1];
	return std::atan2(x1 * y2 - y1 * x2, x1 * x2 + y1 * y2);
}

// Barycentric coordinates of q in triangle (a, b, c); false if degenerate.
bool barycentric(const double *a, const double *b, const double *c, const double *q, double &l0,
                 double &l1, double &l2)
{
	const double d = orient(a, b, c);
	if (!(std::fabs(d) > 0))
		return false;
	l0 = orient(q, b, c) / d;
	l1 = orient(a, q, c) / d;
	l2 = 1 - l0 - l1;
	return true;
}

// Segments p0-p1 and q0-q1 cross strictly inside both: their parameters s (on p) and r (on q).
bool crossing(const double *p0, const double *p1, const double *q0, const double *q1, double &s,
              double &r)
{
	const double rx = p1[0] - p0[0], ry = p1[1] - p0[1], sx = q1[0] - q0[0], sy = q1[1] - q0[1];
	const double den = rx * sy - ry * sx;
	if (den == 0)
		return false;
	const double qx = q0[0] - p0[0], qy = q0[1] - p0[1];
	s = (qx * sy - qy * sx) / den;
	r = (qx * ry - qy * rx) / den;
	return s > 0 && s < 1 && r > 0 && r < 1;
}

} // namespace

bool trianglesOverlap2D(const double (*a)[2], const double (*b)[2], double eps)
{
	for (int pass = 0; pass < 2; ++pass) {
		const double(*s)[2] = pass ? b : a;
		const double(*o)[2] = pass ? a : b;
		for (int k = 0; k < 3; ++k) {
			const double *p = s[k], *q = s[(k + 1) % 3];
			const double nx = q[1] - p[1], ny = p[0] - q[0]; // (outward, for a counter-clockwise s)
			double lo = HUGE_VAL;
			for (int j = 0; j < 3; ++j)
				lo = std::min(lo, (o[j][0] - p[0]) * nx + (o[j][1] - p[1]) * ny);
			if (lo >= -eps * std::sqrt(nx * nx + ny * ny))
				return false; // (o is on the outer side of that edge)
		}
	}
	return true;
}

namespace {

// Where the two are not both one-to-one over one plane: each new triangle against the old
// triangle on the same outline edge (they share that edge, so every point of either is within the
// distance of the other's third vertex: the distance to a triangle is convex), and each old
// triangle with no such partner (on the collapsed edge) against a new triangle it shares a vertex
// with (within its other vertices' distances).
bool proveByPairs(const PatchCase &c, double slop, PatchProof &out)
{
	auto shared = [&](const int8_t *a, const int8_t *b) {
		int n = 0;
		for (int i = 0; i < 3; ++i)
			for (int k = 0; k < 3; ++k)
				n += a[i] == b[k];
		return n;
	};
	auto dist = [&](int8_t p, const int8_t *t) {
		return std::sqrt(pointTriangleDistance2(c.pos[p], c.pos[t[0]], c.pos[t[1]], c.pos[t[2]]));
	};
	for (int i = 0; i < c.nNew; ++i)
		out.gap[i] = 0, out.under[i] = 0;
	for (int j = 0; j < c.nOld; ++j) {
		const int8_t *o = c.oldTri[j];
		int best = -1, most = 0;
		for (int i = 0; i < c.nNew; ++i) {
			const int n = shared(o, c.newTri[i]);
			if (n > most)
				most = n, best = i;
		}
		if (best < 0)
			return false;
		const int8_t *t = c.newTri[best];
		double g = 0;
		for (int k = 0; k < 3; ++k) {
			g = std::max(g, dist(o[k], t));
			if (most == 2) // (partners: the new one's points against the old one too)
				g = std::max(g, dist(t[k], o));
		}
		out.gap[best] = std::max(out.gap[best], g);
		out.under[best] |= uint64_t(1) << j;
	}
	for (int i = 0; i < c.nNew; ++i)
		out.gap[i] += slop;
	out.byPairs = true;
	return true;
}

// The patch seen along the old patch's area-weighted normal n: each point's 2D position p2 in
// the plane orthogonal to it and its height h along it.
struct HeightFrame {
	Vec3 n;
	double p2[PatchCase::kMaxPts][2], h[PatchCase::kMaxPts];
};

// The frame of the patch (its direction also into out.dir); false if its normal is zero or a
// triangle, old or new, faces n by less than `facing` (the cosine).
inline bool heightFrame(const PatchCase &c, double facing, HeightFrame &f, PatchProof &out)
{
	Vec3 n(0, 0, 0);
	for (int i = 0; i < c.nOld; ++i) {
		const Vec3 &a = c.pos[c.oldTri[i][0]], &b = c.pos[c.oldTri[i][1]],
		           &d = c.pos[c.oldTri[i][2]];
		n += (b - a) ^ (d - a);
	}
	const double nl = n.Norm();
	if (!(nl > 0))
		return false;
	n /= nl;
	f.n = n;
	out.dir = n;
	auto faces = [&](const int8_t *t) {
		const Vec3 &a = c.pos[t[0]], &b = c.pos[t[1]], &d = c.pos[t[2]];
		const Vec3 x = (b - a) ^ (d - a);
		const double len = x.Norm();
		return len > 0 && x.dot(n) >= facing * len;
	};
	for (int i = 0; i < c.nOld; ++i)
		if (!faces(c.oldTri[i]))
			return false;
	for (int i = 0; i < c.nNew; ++i)
		if (!faces(c.newTri[i]))
			return false;
	const Vec3 ax = planeAxis(n), ay = n ^ ax;
	for (int i = 0; i < c.nPts; ++i) {
		f.p2[i][0] = c.pos[i].dot(ax);
		f.p2[i][1] = c.pos[i].dot(ay);
		f.h[i] = c.pos[i].dot(n);
	}
	return true;
}

// One simple polygon, covered once by both the old and the new triangles.
inline bool coveredOnce(const PatchCase &c, const HeightFrame &f)
{
	const auto &p2 = f.p2;
	auto windAround = [&](int o, const int8_t(*tri)[3], int nTri) {
		double w = 0;
		for (int i = 0; i < nTri; ++i)
			for (int k = 0; k < 3; ++k)
				if (tri[i][k] == o)
					w += turn(p2[o], p2[tri[i][(k + 1) % 3]], p2[tri[i][(k + 2) % 3]]);
		return w;
	};
	// (a closed fan of triangles facing n around o winds as many times as its outer edges cross
	// the ray from o along x upwards: once)
	auto windsOnce = [&](int o, const int8_t(*tri)[3], int nTri) {
		int crossings = 0;
		for (int i = 0; i < nTri; ++i)
			for (int k = 0; k < 3; ++k)
				if (tri[i][k] == o) {
					const double *a = p2[tri[i][(k + 1) % 3]], *b = p2[tri[i][(k + 2) % 3]];
					if ((a[1] <= p2[o][1]) != (b[1] <= p2[o][1]) &&
					    (a[1] <= p2[o][1] ? orient(a, b, p2[o]) > 0 : orient(a, b, p2[o]) < 0))
						crossings += a[1] <= p2[o][1] ? 1 : -1;
				}
		return crossings == 1;
	};
	if (c.newInner >= 0)
		return windsOnce(c.newInner, c.newTri, c.nNew);
	if (!c.pocket)
		return windsOnce(c.inner[0], c.oldTri, c.nOld);
	const double w = windAround(c.inner[0], c.oldTri, c.nOld);
	if (!(w > 0 && w < 2 * M_PI - kWinding))
		return false;
	// (a notch, not a pocket: the new outline would not be inside the old)
	return orient(p2[c.inner[0]], p2[c.pocketA], p2[c.pocketB]) > 0;
}

// The height of a triangulation at point q, in triangle t (closed, with a little slack).
inline bool heightIn(const HeightFrame &f, const int8_t *t, const double *q, double &hq)
{
	double l0, l1, l2;
	if (!barycentric(f.p2[t[0]], f.p2[t[1]], f.p2[t[2]], q, l0, l1, l2))
		return false;
	constexpr double kIn = -1e-9;
	if (l0 < kIn || l1 < kIn || l2 < kIn)
		return false;
	hq = l0 * f.h[t[0]] + l1 * f.h[t[1]] + l2 * f.h[t[2]];
	return true;
}

// The gaps at the vertices: the removed vertices over the new triangles, the new vertex over the
// old triangles (every new triangle has it). False if one is over none.
inline bool vertexGaps(const PatchCase &c, const HeightFrame &f, PatchProof &out)
{
	for (int i = 0; i < c.nNew; ++i)
		out.gap[i] = 0;
	for (int k = 0; k < c.nInner; ++k) {
		const int q = c.inner[k];
		bool found = false;
		for (int i = 0; i < c.nNew; ++i) {
			double hq;
			if (heightIn(f, c.newTri[i], f.p2[q], hq)) {
				out.gap[i] = std::max(out.gap[i], std::fabs(f.h[q] - hq));
				found = true;
			}
		}
		if (!found && !c.pocket)
			return false;
	}
	if (c.newInner >= 0) {
		double g = -1;
		for (int i = 0; i < c.nOld && g < 0; ++i) {
			double hq;
			if (heightIn(f, c.oldTri[i], f.p2[c.newInner], hq))
				g = std::fabs(f.h[c.newInner] - hq);
		}
		if (g < 0)
			return false;
		for (int i = 0; i < c.nNew; ++i)
			out.gap[i] = std::max(out.gap[i], g);
	}
	return true;
}

// The inner edges: old ones at a removed vertex; new ones shared by two new triangles (and the
// new boundary edge of a pocket, newEdgeTri both the pocket's triangle).
struct InnerEdges {
	static constexpr int kMax = 2 * PatchCase::kMaxTris;
	int8_t oldEdge[kMax][2], newEdge[kMax][2], newEdgeTri[kMax][2];
	int nOld = 0, nNew = 0;
};
inline void innerEdges(const PatchCase &c, InnerEdges &e)
{
	auto isInner = [&](int p) {
		for (int k = 0; k < c.nInner; ++k)
			if (c.inner[k] == p)
				return true;
		return false;
	};
	for (int i = 0; i < c.nOld; ++i)
		for (int k = 0; k < 3; ++k) {
			const int8_t a = c.oldTri[i][k], b = c.oldTri[i][(k + 1) % 3];
			if (!isInner(a) && !isInner(b))
				continue;
			bool seen = false;
			for (int j = 0; j < e.nOld && !seen; ++j)
				seen = (e.oldEdge[j][0] == b && e.oldEdge[j][1] == a);
			if (!seen)
				e.oldEdge[e.nOld][0] = a, e.oldEdge[e.nOld][1] = b, ++e.nOld;
		}
	for (int i = 0; i < c.nNew; ++i)
		for (int k = 0; k < 3; ++k) {
			const int8_t a = c.newTri[i][k], b = c.newTri[i][(k + 1) % 3];
			const bool pocketEdge = c.pocket && ((a == c.pocketA && b == c.pocketB) ||
			                                     (a == c.pocketB && b == c.pocketA));
			int j = 0;
			while (j < e.nNew && !(e.newEdge[j][0] == b && e.newEdge[j][1] == a))
				++j;
			if (j < e.nNew) {
				e.newEdgeTri[j][1] = int8_t(i);
			} else {
				e.newEdge[j][0] = a, e.newEdge[j][1] = b;
				e.newEdgeTri[j][0] = int8_t(i);
				e.newEdgeTri[j][1] = pocketEdge ? int8_t(i) : int8_t(-1);
				++e.nNew;
			}
		}
}

// The gaps where a new inner edge crosses an old one, on both new triangles of the edge. Returns
// the pocket's triangle (-1: none).
inline int edgeCrossingGaps(const PatchCase &c, const HeightFrame &f, const InnerEdges &e,
                            PatchProof &out)
{
	const auto &p2 = f.p2;
	const auto &h = f.h;
	int pocketTri = -1;
	for (int j = 0; j < e.nNew; ++j) {
		if (e.newEdgeTri[j][1] < 0)
			continue; // (an outline edge of the new fan)
		const bool pocketEdge = c.pocket && e.newEdgeTri[j][0] == e.newEdgeTri[j][1];
		if (pocketEdge)
			pocketTri = e.newEdgeTri[j][0];
		const double *q0 = p2[e.newEdge[j][0]], *q1 = p2[e.newEdge[j][1]];
		for (int o = 0; o < e.nOld; ++o) {
			double s, r;
			if (!crossing(p2[e.oldEdge[o][0]], p2[e.oldEdge[o][1]], q0, q1, s, r))
				continue;
			const double ho = h[e.oldEdge[o][0]] + s * (h[e.oldEdge[o][1]] - h[e.oldEdge[o][0]]);
			const double hn = h[e.newEdge[j][0]] + r * (h[e.newEdge[j][1]] - h[e.newEdge[j][0]]);
			const double g = std::fabs(ho - hn);
			for (int k = 0; k < 2; ++k)
				out.gap[e.newEdgeTri[j][k]] = std::max(out.gap[e.newEdgeTri[j][k]], g);
		}
	}
	return pocketTri;
}

// The old triangles under each new one (and under the pocket's, those over the pocket); true if
// every old triangle is under one.
inline bool oldUnderNew(const PatchCase &c, const HeightFrame &f, int pocketTri, double slop,
                        PatchProof &out)
{
	constexpr int kT = PatchCase::kMaxTris;
	const auto &p2 = f.p2;
	double oldP[kT][3][2];
	for (int i = 0; i < c.nOld; ++i)
		for (int k = 0; k < 3; ++k)
			oldP[i][k][0] = p2[c.oldTri[i][k]][0], oldP[i][k][1] = p2[c.oldTri[i][k]][1];
	double pocketP[3][2];
	if (c.pocket)
		for (int k = 0; k < 3; ++k) {
			const int q = k == 0 ? c.inner[0] : k == 1 ? c.pocketA : c.pocketB;
			pocketP[k][0] = p2[q][0], pocketP[k][1] = p2[q][1];
		}
	const double eps = 1e-9 * std::max(1e-300, slop);
	uint64_t covered = 0;
	for (int i = 0; i < c.nNew; ++i) {
		double np[3][2];
		for (int k = 0; k < 3; ++k)
			np[k][0] = p2[c.newTri[i][k]][0], np[k][1] = p2[c.newTri[i][k]][1];
		uint64_t under = 0;
		for (int j = 0; j < c.nOld; ++j)
			if (trianglesOverlap2D(np, oldP[j], eps) ||
			    (i == pocketTri && trianglesOverlap2D(pocketP, oldP[j], eps)))
				under |= uint64_t(1) << j;
		out.under[i] = under;
		covered |= under;
	}
	const uint64_t all = c.nOld == 64 ? ~uint64_t(0) : (uint64_t(1) << c.nOld) - 1;
	return covered == all;
}

bool proveByHeights(const PatchCase &c, double facing, double slop, bool under, PatchProof &out)
{
	HeightFrame f;
	if (!heightFrame(c, facing, f, out))
		return false;
	if (!coveredOnce(c, f) || !vertexGaps(c, f, out))
		return false;
	InnerEdges e;
	innerEdges(c, e);
	const int pocketTri = edgeCrossingGaps(c, f, e, out);
	if (c.pocket) {
		if (pocketTri < 0)
			return false;
		out.gap[pocketTri] =
		    std::max(out.gap[pocketTri],
		             pointSegmentDistance(c.pos[c.inner[0]], c.pos[c.pocketA], c.pos[c.pocketB]));
	}
	for (int i = 0; i < c.nNew; ++i)
		out.gap[i] += slop;
	out.byPairs = false;
	if (!under)
		return true;
	const bool all = oldUnderNew(c, f, pocketTri, slop, out);
	out.byPairs = false;
	return all;
}

} // namespace

bool provePatch(const PatchCase &c, double facing, double slop, PatchProof &out, bool under)
{
	return proveByHeights(c, facing, slop, under, out) || proveByPairs(c, slop, out);
}

} // namespace detail
} // namespace gausslod
