// Beyond the paper (docs/DESIGN.md, 50): coarser levels by half-edge collapses of the finer level's
// mesh, each with a proven distance bound.
//
// A half-edge collapse v -> u replaces the triangles around v (its ring) by a fan from u over the
// same outline (v's link). Where the ring and the fan are both one-to-one over the plane
// orthogonal to a direction n (every triangle facing n, the ring winding once around v, v over
// the fan), they are two height fields over the same polygon: every point of either is straight
// above or below a point of the other, and the vertical gap between them is linear on each cell
// of the overlay of the two triangulations, so its largest value is at v or where a spoke of v
// crosses a spoke of u. A triangle carries an upper bound on its distance to the input, both ways
// (every point of it that close to the input, every input point it stands for that close to it):
// the fan's triangles take the largest bound of the ring plus that gap. A triangle also carries
// the cone of the input normals it stands for; the fan's triangles take the union of the ring's,
// and each must stay within the level's normal limit of it.
#include "level_collapse.h"
#include "level_passes.h"


#include <cstring>
#include <functional>
#include <queue>

namespace gausslod {
namespace detail {

namespace {

constexpr int kMaxRing = 32;             // a vertex with more triangles around it is not removed
constexpr size_t kFarthestSample = 16384; // input vertices farthestInputVertex looks at, at most
// the facing test (nearestInputFacing) looks this many face-grid cells around a new triangle (the
// superface build's 8 cost fandisk x64 about 0.2 s more: its levels' triangles are far larger
// than its input's)
constexpr double kFacingCells = 3;
constexpr double kFacing = 1e-3;    // cos of the steepest triangle allowed against n
constexpr double kWinding = 1e-6;   // radians

// The smallest cone (of this construction) holding both.
NormalCone mergeCones(const NormalCone &a, const NormalCone &b)
{
	const double d = angleDeg(a.axis, b.axis);
	if (d + b.half <= a.half)
		return a;
	if (d + a.half <= b.half)
		return b;
	const double half = 0.5 * (d + a.half + b.half);
	if (half >= 180)
		return {a.axis, 180};
	Vec3 w = b.axis - a.axis * b.axis.dot(a.axis);
	const double wl = w.Norm();
	if (wl < 1e-15)
		return {a.axis, half};
	w /= wl;
	const double r = (half - a.half) * M_PI / 180; // (a's axis turned towards b's by this)
	Vec3 axis = a.axis * std::cos(r) + w * std::sin(r);
	axis.Normalize();
	return {axis, half};
}

struct Eval {
	double gap = 0, bound = 0;
	int nFan = 0;
	uint32_t under[kMaxRing]; // (per fan triangle, in ring order: the ring triangles under it)
};

struct P2 {
	double x, y, h; // in the plane orthogonal to n, and along n
};

// What a vertex's candidate collapses share: its ring, projected.
struct Ring {
	int n = 0, nLink = 0;
	int32_t face[kMaxRing];
	int8_t corner[kMaxRing][3]; // (per ring triangle corner: its index in link, -1 = v)
	int32_t link[2 * kMaxRing];
	P2 pLink[2 * kMaxRing];
	P2 pv;
	Vec3 dir, ax, ay;
	double bound = 0;
	// on a mesh boundary: its neighbours along it, before and after v in the ring's
	// counter-clockwise order (the only targets)
	int nSharp = 0;
	int32_t sharp[2]; // (with two sharp spokes: their other ends, the only targets)
	bool onBoundary = false;
	int32_t before = -1, after = -1;
};

// Do two counter-clockwise triangles of the plane overlap in more than an edge or a point?
bool overlap(const P2 *a, const P2 *b, double eps)
{
	for (int pass = 0; pass < 2; ++pass) {
		const P2 *s = pass ? b : a, *o = pass ? a : b;
		for (int k = 0; k < 3; ++k) {
			const P2 &p = s[k], &q = s[(k + 1) % 3];
			const double nx = q.y - p.y, ny = p.x - q.x; // (outward, for a counter-clockwise s)
			double lo = 1e300;
			for (int j = 0; j < 3; ++j)
				lo = std::min(lo, (o[j].x - p.x) * nx + (o[j].y - p.y) * ny);
			if (lo >= -eps * std::sqrt(nx * nx + ny * ny))
				return false; // (o is on the outer side of that edge)
		}
	}
	return true;
}

struct Entry {
	double cost;
	int32_t v, u;
	bool operator<(const Entry &o) const // (the heap's top: least cost, then lowest v, u)
	{
		if (cost != o.cost)
			return cost > o.cost;
		if (v != o.v)
			return v > o.v;
		return u > o.u;
	}
};

class Collapser {
public:
	Collapser(const Topology &t, const MeshView &mesh, const CollapseSource &src,
	          const CollapseLimits &lim, size_t threads)
	    : t_(t), mesh_(mesh), src_(src), lim_(lim), threads_(threads)
	{
	}
	bool run(CollapseSource &out);

private:
	const Topology &t_;
	const MeshView &mesh_;
	const CollapseSource &src_;
	const CollapseLimits &lim_;
	const size_t threads_;
	const double cosFeature_ = std::cos(lim_.featureDeg * M_PI / 180);
	std::vector<Vec3> P_;
	std::vector<int32_t> T_, head_, next_, sf_, uf_, srcCorner_;
	std::vector<uint8_t> alive_, locked_, made_, boundary_;
	std::vector<double> e_;
	std::vector<NormalCone> cone_;
	std::vector<double> devBound_; // (per made triangle: the largest deviation from the input normals it stands for)
	std::vector<double> cosRoom_; // (per triangle: cos of what its cone leaves of the limit)
	std::vector<Quadric> Q_;
	std::vector<uint8_t> queued_; // (a vertex's collapse is in the heap)
	std::vector<int32_t> scratch_;
	std::priority_queue<Entry> heap_;
	size_t live_ = 0, collapses_ = 0;

	Vec3 normal(int32_t f) const
	{
		const Vec3 &a = P_[size_t(T_[3 * f])], &b = P_[size_t(T_[3 * f + 1])],
		           &c = P_[size_t(T_[3 * f + 2])];
		return (b - a) ^ (c - a);
	}
	// A normal n is within the limit of every normal of cone c iff n . c.axis >= cosRoom(c).
	double cosRoom(const NormalCone &c) const
	{
		const double room = lim_.normalDeg - c.half;
		return room < 0 ? 2.0 : room >= 180 ? -2.0 : std::cos(room * M_PI / 180);
	}
	int32_t find(int32_t s)
	{
		while (uf_[size_t(s)] != s)
			s = uf_[size_t(s)] = uf_[size_t(uf_[size_t(s)])];
		return s;
	}
	// The live triangles around v (at most kMaxRing; -1 = more).
	int ring(int32_t v, int32_t *faces) const
	{
		int n = 0;
		for (int32_t c = head_[size_t(v)]; c >= 0; c = next_[size_t(c)])
			if (alive_[size_t(heFace(c))]) {
				if (n == kMaxRing)
					return -1;
				faces[n++] = heFace(c);
			}
		return n;
	}
	// The opposite live triangle across the edge a -> b of triangle f, -1 if there is none, -2 if
	// the edge is not between exactly two consistently oriented triangles.
	int32_t opposite(int32_t f, int32_t a, int32_t b) const
	{
		int32_t found = -1;
		for (int32_t c = head_[size_t(b)]; c >= 0; c = next_[size_t(c)]) {
			const int32_t g = heFace(c);
			if (g == f || !alive_[size_t(g)])
				continue;
			if (T_[size_t(heNext(c))] == a) {
				if (found >= 0)
					return -2;
				found = g;
			} else if (T_[size_t(hePrev(c))] == a) {
				return -2; // (the same direction: inconsistent or non-manifold)
			}
		}
		return found;
	}
	void lockEdges();
	bool prepare(int32_t v, Ring &r) const;
	/// False if the collapse is not allowed, or its gap is not below `worse`.
	bool evaluate(int32_t v, int32_t u, Ring &r, Eval &ev, double worse = HUGE_VAL) const;
	bool best(int32_t v, Entry &e) const;
	void pushBest(int32_t v)
	{
		Entry e;
		if (best(v, e)) {
			heap_.push(e);
			queued_[size_t(v)] = 1;
		}
	}
	void collapse(int32_t v, int32_t u, const Eval &ev);
	void prune(int32_t v);
	void place();
	bool facesInput(int32_t f, double r) const;
	bool fanFacesInput(int32_t v, int32_t u, double r) const;
	bool withinLimit(int32_t f) const;
	void write(CollapseSource &out);
};

void Collapser::lockEdges()
{
	const size_t nT = T_.size() / 3;
	const bool keys = mesh_.faceKey || mesh_.cornerKey;
	for (size_t f = 0; f < nT; ++f) {
		for (int k = 0; k < 3; ++k) {
			const int32_t c = int32_t(3 * f) + k;
			const int32_t a = T_[size_t(c)], b = T_[size_t(heNext(c))];
			const int32_t g = opposite(int32_t(f), a, b);
			if (g == -1) { // (a mesh boundary: its vertices move along it, below)
				++boundary_[size_t(a)], ++boundary_[size_t(b)];
				continue;
			}
			bool lock = g < 0;
			if (!lock && keys) {
				const int32_t sf = src_.mesh.sourceFace[f], sg = src_.mesh.sourceFace[size_t(g)];
				lock = mesh_.faceKey && mesh_.faceKey[sf] != mesh_.faceKey[sg];
				if (!lock && mesh_.cornerKey) {
					int32_t ca = -1, cb = -1; // (g's corners at a and b)
					for (int32_t q = 3 * g; q < 3 * g + 3; ++q) {
						ca = T_[size_t(q)] == a ? q : ca;
						cb = T_[size_t(q)] == b ? q : cb;
					}
					const uint32_t *K = mesh_.cornerKey;
					lock = K[srcCorner_[size_t(c)]] != K[srcCorner_[size_t(ca)]] ||
					       K[srcCorner_[size_t(heNext(c))]] != K[srcCorner_[size_t(cb)]];
				}
			}
			if (lock)
				locked_[size_t(a)] = locked_[size_t(b)] = 1;
		}
	}
	for (size_t v = 0; v < boundary_.size(); ++v) // (where boundary loops touch: stays)
		if (boundary_[v] != 0 && boundary_[v] != 2)
			locked_[v] = 1;
}

bool Collapser::prepare(int32_t v, Ring &r) const
{
	if (locked_[size_t(v)] || head_[size_t(v)] < 0)
		return false;
	r.n = ring(v, r.face);
	if (r.n < 3)
		return false;
	Vec3 n(0, 0, 0);
	for (int i = 0; i < r.n; ++i)
		n += normal(r.face[i]);
	if (!(n.Norm() > 0))
		return false;
	n.Normalize();
	r.dir = n;
	r.ax = planeAxis(n);
	r.ay = n ^ r.ax;
	auto proj = [&](int32_t w) {
		const Vec3 &p = P_[size_t(w)];
		return P2{p.dot(r.ax), p.dot(r.ay), p.dot(n)};
	};
	r.pv = proj(v);
	r.nLink = 0;
	auto linkIndex = [&](int32_t w) {
		for (int i = 0; i < r.nLink; ++i)
			if (r.link[i] == w)
				return i;
		r.link[r.nLink] = w;
		r.pLink[r.nLink] = proj(w);
		return r.nLink++;
	};
	double wind = 0;
	r.bound = 0;
	r.onBoundary = boundary_[size_t(v)] != 0;
	r.before = r.after = -1;
	Vec3 spoke[2 * kMaxRing][2]; // (the normals of the two triangles at each spoke v-w)
	int8_t spokes[2 * kMaxRing] = {};
	for (int i = 0; i < r.n; ++i) {
		const int32_t f = r.face[i];
		Vec3 nf = normal(f);
		nf.Normalize();
		if (nf.dot(n) < kFacing)
			return false;
		int k = 0;
		while (T_[size_t(3 * f + k)] != v)
			++k;
		const int i1 = linkIndex(T_[size_t(3 * f + (k + 1) % 3)]);
		const int i2 = linkIndex(T_[size_t(3 * f + (k + 2) % 3)]);
		r.corner[i][k] = -1;
		r.corner[i][(k + 1) % 3] = int8_t(i1);
		r.corner[i][(k + 2) % 3] = int8_t(i2);
		for (const int w : {i1, i2})
			if (spokes[w] < 2)
				spoke[w][spokes[w]++] = nf;
		if (r.onBoundary) { // (the boundary edges at v are the ones with no triangle across)
			const int32_t c = 3 * f + k;
			if (opposite(f, v, T_[size_t(heNext(c))]) == -1)
				r.after = T_[size_t(heNext(c))];
			if (opposite(f, T_[size_t(hePrev(c))], v) == -1)
				r.before = T_[size_t(hePrev(c))];
		}
		const P2 p1 = r.pLink[i1], p2 = r.pLink[i2];
		const double x1 = p1.x - r.pv.x, y1 = p1.y - r.pv.y, x2 = p2.x - r.pv.x, y2 = p2.y - r.pv.y;
		wind += std::atan2(x1 * y2 - y1 * x2, x1 * x2 + y1 * y2);
		r.bound = std::max(r.bound, e_[size_t(f)]);
	}
	if (r.onBoundary ? !(wind > 0 && wind < 2 * M_PI - kWinding) || r.before < 0 || r.after < 0
	                 : std::fabs(wind - 2 * M_PI) > kWinding) // (the ring winds once around v)
		return false;
	// sharp spokes (a feature line through v): v only moves along the line, to one of its ends;
	// a vertex where a line ends or lines meet, or on a boundary too, stays
	r.nSharp = 0;
	for (int w = 0; w < r.nLink; ++w)
		if (spokes[w] == 2 && spoke[w][0].dot(spoke[w][1]) < cosFeature_) {
			if (r.nSharp == 2 || r.onBoundary)
				return false;
			r.sharp[r.nSharp++] = r.link[w];
		}
	if (r.nSharp == 1)
		return false;
	return r.bound < lim_.bound;
}

bool Collapser::evaluate(int32_t v, int32_t u, Ring &r, Eval &ev, double worse) const
{
	// u shares exactly two triangles with v, and exactly two neighbours (the link condition:
	// the collapse keeps a 2-manifold)
	// (a boundary vertex goes along the boundary: one triangle goes, and one neighbour is shared)
	if (r.onBoundary && u != r.before && u != r.after)
		return false;
	if (r.nSharp == 2 && u != r.sharp[0] && u != r.sharp[1])
		return false;
	const int want = r.onBoundary ? 1 : 2;
	int shared = 0;
	for (int i = 0; i < r.n; ++i)
		for (int k = 0; k < 3; ++k)
			shared += T_[size_t(3 * r.face[i] + k)] == u;
	if (shared != want)
		return false;
	int common = 0, nU = 0;
	int32_t seen[2 * kMaxRing];
	int nSeen = 0;
	for (int32_t c = head_[size_t(u)]; c >= 0; c = next_[size_t(c)]) {
		if (!alive_[size_t(heFace(c))])
			continue;
		if (++nU > kMaxRing)
			return false;
		for (const int32_t w : {T_[size_t(heNext(c))], T_[size_t(hePrev(c))]}) {
			if (w == v || std::find(seen, seen + nSeen, w) != seen + nSeen)
				continue;
			seen[nSeen++] = w;
			for (int i = 0; i < r.nLink; ++i)
				common += r.link[i] == w;
		}
	}
	if (common != want)
		return false;
	int iu = 0;
	while (r.link[iu] != u)
		++iu;
	const P2 pu = r.pLink[iu], pv = r.pv;
	// the fan: facing n, and v over one of its triangles (the gap there)
	// (a boundary vertex: the outline loses the triangle before-v-after, which must be a pocket
	// of the old ring, not a notch, and v is over no triangle of the fan; the old surface over
	// the pocket is within v's distance of the new boundary edge, or of the spoke crossings below)
	double gap = -1;
	P2 pocket[3];
	if (r.onBoundary) {
		int ib = 0, ia = 0;
		while (r.link[ib] != r.before)
			++ib;
		while (r.link[ia] != r.after)
			++ia;
		pocket[0] = r.pLink[ib], pocket[1] = pv, pocket[2] = r.pLink[ia];
		const double o = (pv.x - pocket[0].x) * (pocket[2].y - pocket[0].y) -
		                 (pv.y - pocket[0].y) * (pocket[2].x - pocket[0].x);
		if (o < 0)
			return false;
		gap = pointSegmentDistance(P_[size_t(v)], P_[size_t(r.before)], P_[size_t(r.after)]);
	}
	for (int i = 0; i < r.n; ++i) {
		const int32_t f = r.face[i];
		int32_t tri[3];
		bool hasU = false;
		for (int k = 0; k < 3; ++k) {
			tri[k] = T_[size_t(3 * f + k)];
			hasU = hasU || tri[k] == u;
			tri[k] = tri[k] == v ? u : tri[k];
		}
		if (hasU)
			continue;
		const Vec3 nt = (P_[size_t(tri[1])] - P_[size_t(tri[0])]) ^ (P_[size_t(tri[2])] - P_[size_t(tri[0])]);
		const double len = nt.Norm();
		if (!(len > 0) || nt.dot(r.dir) < kFacing * len)
			return false;
		if (nt.dot(cone_[size_t(f)].axis) < cosRoom_[size_t(f)] * len) // (its own ring triangle
			return false;                                           // is under it: see below)
		P2 q[3];
		for (int k = 0; k < 3; ++k)
			q[k] = r.corner[i][k] < 0 ? pu : r.pLink[r.corner[i][k]];
		const double d = (q[1].x - q[0].x) * (q[2].y - q[0].y) - (q[1].y - q[0].y) * (q[2].x - q[0].x);
		const double l1 = ((q[1].x - pv.x) * (q[2].y - pv.y) - (q[1].y - pv.y) * (q[2].x - pv.x)) / d;
		const double l2 = ((q[2].x - pv.x) * (q[0].y - pv.y) - (q[2].y - pv.y) * (q[0].x - pv.x)) / d;
		const double l3 = 1 - l1 - l2;
		if (l1 >= -1e-12 && l2 >= -1e-12 && l3 >= -1e-12)
			gap = std::max(gap, std::fabs(pv.h - (l1 * q[0].h + l2 * q[1].h + l3 * q[2].h)));
	}
	if (gap < 0) // (v is over no triangle of the fan: the outline is not star-shaped from u)
		return false;
	if (gap >= worse || r.bound + gap > lim_.bound) // (no better than what the caller has)
		return false;
	// where a spoke of v (v-w) crosses a spoke of u (u-x)
	const double qx = pu.x - pv.x, qy = pu.y - pv.y;
	for (int i = 0; i < r.nLink; ++i) {
		if (i == iu)
			continue;
		const P2 &pw = r.pLink[i];
		const double rx = pw.x - pv.x, ry = pw.y - pv.y;
		for (int j = 0; j < r.nLink; ++j) {
			if (j == i || j == iu)
				continue;
			const P2 &px = r.pLink[j];
			const double sx = px.x - pu.x, sy = px.y - pu.y;
			const double den = rx * sy - ry * sx;
			if (den == 0)
				continue;
			const double a = (qx * sy - qy * sx) / den, b = (qx * ry - qy * rx) / den;
			if (a <= 0 || a >= 1 || b <= 0 || b >= 1)
				continue;
			gap = std::max(gap, std::fabs(pv.h + a * (pw.h - pv.h) - (pu.h + b * (px.h - pu.h))));
		}
	}
	// (rounding: the gap is computed in doubles from coordinates of that precision)
	gap += 1e-12 * t_.diagonal;
	if (r.bound + gap > lim_.bound)
		return false;
	// each fan triangle stands for the input normals of the ring triangles under it: within the
	// limit of them all
	const double eps = 1e-9 * t_.diagonal;
	P2 ringTri[kMaxRing][3];
	for (int i = 0; i < r.n; ++i)
		for (int k = 0; k < 3; ++k)
			ringTri[i][k] = r.corner[i][k] < 0 ? pv : r.pLink[r.corner[i][k]];
	ev.nFan = 0;
	for (int i = 0; i < r.n; ++i) {
		const int32_t f = r.face[i];
		int32_t tri[3];
		bool hasU = false;
		P2 fan[3];
		for (int k = 0; k < 3; ++k) {
			tri[k] = T_[size_t(3 * f + k)];
			hasU = hasU || tri[k] == u;
			tri[k] = tri[k] == v ? u : tri[k];
			fan[k] = r.corner[i][k] < 0 ? pu : ringTri[i][k];
		}
		if (hasU)
			continue;
		Vec3 nt = (P_[size_t(tri[1])] - P_[size_t(tri[0])]) ^ (P_[size_t(tri[2])] - P_[size_t(tri[0])]);
		nt.Normalize();
		uint32_t under = 0;
		// (the fan triangle on the new boundary edge also stands for the pocket)
		const int32_t other = u == r.before ? r.after : r.before;
		const bool edge = r.onBoundary && (tri[0] == other || tri[1] == other || tri[2] == other);
		for (int j = 0; j < r.n; ++j) // (its own ring triangle is under it: v is over the fan)
			if (j == i || overlap(fan, ringTri[j], eps) ||
			    (edge && overlap(pocket, ringTri[j], eps))) {
				const int32_t g = r.face[j];
				if (nt.dot(cone_[size_t(g)].axis) < cosRoom_[size_t(g)])
					return false;
				under |= 1u << j;
			}
		ev.under[ev.nFan++] = under;
	}
	ev.gap = gap;
	ev.bound = r.bound + gap;
	return true;
}

bool Collapser::best(int32_t v, Entry &e) const
{
	Ring r;
	if (!prepare(v, r))
		return false;
	Eval ev;
	double bestGap = 0;
	int32_t bestU = -1;
	for (int i = 0; i < r.nLink; ++i) {
		const int32_t u = r.link[i];
		if (evaluate(v, u, r, ev, bestU < 0 ? HUGE_VAL : bestGap) && (bestU < 0 || ev.gap < bestGap))
			bestGap = ev.gap, bestU = u;
	}
	if (bestU < 0)
		return false;
	e = {bestGap, v, bestU};
	return true;
}

void Collapser::prune(int32_t v)
{
	scratch_.clear();
	for (int32_t c = head_[size_t(v)]; c >= 0; c = next_[size_t(c)])
		if (alive_[size_t(heFace(c))])
			scratch_.push_back(c);
	head_[size_t(v)] = -1;
	for (auto it = scratch_.rbegin(); it != scratch_.rend(); ++it) {
		next_[size_t(*it)] = head_[size_t(v)];
		head_[size_t(v)] = *it;
	}
}

void Collapser::collapse(int32_t v, int32_t u, const Eval &ev)
{
	int32_t faces[kMaxRing];
	const int nR = ring(v, faces);
	// a corner of u in a triangle that goes (its attributes are u's on this side of u)
	int32_t uSource = -1;
	const int32_t root = find(sf_[size_t(faces[0])]);
	for (int i = 0; i < nR; ++i) {
		const int32_t f = faces[i];
		const int32_t r = find(sf_[size_t(f)]);
		if (r != root)
			uf_[size_t(r)] = root;
		for (int32_t c = 3 * f; c < 3 * f + 3; ++c)
			if (T_[size_t(c)] == u && !srcCorner_.empty())
				uSource = srcCorner_[size_t(c)];
	}
	int32_t gone[2], coneOf[kMaxRing];
	int nGone = 0, fan = 0, nCones = 0;
	NormalCone cones[kMaxRing]; // (merged from the ring's cones before any is replaced)
	for (int i = 0; i < nR; ++i) {
		const int32_t f = faces[i];
		bool hasU = false;
		for (int32_t c = 3 * f; c < 3 * f + 3; ++c)
			hasU = hasU || T_[size_t(c)] == u;
		if (hasU) {
			alive_[size_t(f)] = 0;
			--live_;
			for (int32_t c = 3 * f; c < 3 * f + 3; ++c)
				if (T_[size_t(c)] != u && T_[size_t(c)] != v && nGone < 2)
					gone[nGone++] = T_[size_t(c)];
			continue;
		}
		for (int32_t c = 3 * f; c < 3 * f + 3; ++c)
			if (T_[size_t(c)] == v) {
				T_[size_t(c)] = u;
				if (!srcCorner_.empty())
					srcCorner_[size_t(c)] = uSource;
			}
		e_[size_t(f)] = ev.bound;
		// (its deviation bound: from each cone it stands for, the union's exactly; the merged
		// cone, which holds them all, is what the next collapses check against)
		Vec3 nt = normal(f);
		nt.Normalize();
		double dev = angleDeg(nt, cone_[size_t(f)].axis) + cone_[size_t(f)].half;
		cones[nCones] = cone_[size_t(f)];
		for (int j = 0; j < nR; ++j)
			if (j != i && (ev.under[fan] >> j & 1)) {
				const NormalCone &c = cone_[size_t(faces[j])];
				dev = std::max(dev, angleDeg(nt, c.axis) + c.half);
				cones[nCones] = mergeCones(cones[nCones], c);
			}
		devBound_[size_t(f)] = dev;
		coneOf[nCones++] = f;
		++fan;
		made_[size_t(f)] = 1;
	}
	for (int k = 0; k < nCones; ++k) {
		cone_[size_t(coneOf[k])] = cones[k];
		cosRoom_[size_t(coneOf[k])] = cosRoom(cones[k]);
	}
	Q_[size_t(u)] += Q_[size_t(v)];
	// v's corners join u's list
	int32_t tail = head_[size_t(v)];
	while (next_[size_t(tail)] >= 0)
		tail = next_[size_t(tail)];
	next_[size_t(tail)] = head_[size_t(u)];
	head_[size_t(u)] = head_[size_t(v)];
	head_[size_t(v)] = -1;
	prune(u);
	for (int i = 0; i < nGone; ++i)
		prune(gone[i]);
	// a vertex whose ring changed and has no collapse waiting gets its best one; one that has
	// keeps it (it is checked again when its turn comes: lazy, as in quadric simplifiers)
	scratch_.clear();
	for (int32_t c = head_[size_t(u)]; c >= 0; c = next_[size_t(c)])
		for (int32_t q = 3 * heFace(c); q < 3 * heFace(c) + 3; ++q)
			scratch_.push_back(T_[size_t(q)]);
	std::sort(scratch_.begin(), scratch_.end());
	scratch_.erase(std::unique(scratch_.begin(), scratch_.end()), scratch_.end());
	for (int32_t w : scratch_) // (pushBest does not use scratch_)
		if (!queued_[size_t(w)])
			pushBest(w);
}

// Does the input surface nearest to triangle f (within r) face it (not the other side of a thin
// part)?
bool Collapser::facesInput(int32_t f, double r) const
{
	const Vec3 &a = P_[size_t(T_[3 * f])], &b = P_[size_t(T_[3 * f + 1])], &c = P_[size_t(T_[3 * f + 2])];
	Vec3 n = (b - a) ^ (c - a);
	n.Normalize();
	return nearestInputFacing(t_, (a + b + c) / 3.0, n, r * (1 + 1e-9) + 1e-12 * t_.diagonal,
	                          kFacingCells);
}

// The same for each triangle of the fan of the collapse v -> u, within the bound r it will have.
bool Collapser::fanFacesInput(int32_t v, int32_t u, double r) const
{
	for (int32_t c = head_[size_t(v)]; c >= 0; c = next_[size_t(c)]) {
		const int32_t f = heFace(c);
		if (!alive_[size_t(f)])
			continue;
		Vec3 p[3];
		bool hasU = false;
		for (int k = 0; k < 3; ++k) {
			const int32_t w = T_[size_t(3 * f + k)];
			hasU = hasU || w == u;
			p[k] = P_[size_t(w == v ? u : w)];
		}
		if (hasU)
			continue;
		Vec3 n = (p[1] - p[0]) ^ (p[2] - p[0]);
		n.Normalize();
		if (!nearestInputFacing(t_, (p[0] + p[1] + p[2]) / 3.0, n,
		                        r * (1 + 1e-9) + 1e-12 * t_.diagonal, kFacingCells))
			return false;
	}
	return true;
}

bool Collapser::withinLimit(int32_t f) const
{
	Vec3 n = normal(f);
	if (!(n.Norm() > 0))
		return false;
	n.Normalize();
	return angleDeg(n, cone_[size_t(f)].axis) + cone_[size_t(f)].half <= lim_.normalDeg;
}

// Each vertex of a triangle the collapses made moves along its normal to where the quadric of
// the planes it took over is least, by at most lim_.placement and what its triangles' bounds
// leave below lim_.bound (each of them grows by the move: every point of it moves that far at
// most); a move that takes a triangle beyond the normal limit is not made.
void Collapser::place()
{
	const size_t nV = P_.size();
	for (size_t v = 0; v < nV; ++v) {
		if (head_[v] < 0 || locked_[v])
			continue;
		Vec3 n(0, 0, 0);
		bool made = false;
		double room = lim_.placement;
		for (int32_t c = head_[v]; c >= 0; c = next_[size_t(c)]) {
			const int32_t f = heFace(c);
			made = made || made_[size_t(f)];
			n += normal(f);
			room = std::min(room, lim_.bound - e_[size_t(f)]);
		}
		if (!made || !(n.Norm() > 0) || !(room > 0))
			continue;
		n.Normalize();
		double curv = 0;
		const double t = std::max(-room, std::min(room, Q_[v].stepAlong(P_[v], n, curv)));
		if (!(curv > 0) || t == 0)
			continue;
		const Vec3 old = P_[v];
		P_[v] = old + n * t;
		bool ok = true;
		for (int32_t c = head_[v]; c >= 0 && ok; c = next_[size_t(c)])
			ok = withinLimit(heFace(c)) &&
			     facesInput(heFace(c), e_[size_t(heFace(c))] + std::fabs(t));
		if (!ok) {
			P_[v] = old;
			continue;
		}
		for (int32_t c = head_[v]; c >= 0; c = next_[size_t(c)]) {
			const int32_t f = heFace(c);
			e_[size_t(f)] += std::fabs(t);
			if (made_[size_t(f)]) {
				Vec3 n2 = normal(f);
				n2.Normalize();
				devBound_[size_t(f)] = angleDeg(n2, cone_[size_t(f)].axis) + cone_[size_t(f)].half;
			}
		}
	}
}

bool Collapser::run(CollapseSource &out)
{
	const LevelMesh &sm = src_.mesh;
	const size_t nV = sm.sourceVertex.size(), nT = sm.triangles.size() / 3;
	if ((mesh_.faceKey || mesh_.cornerKey) && sm.sourceCorner.size() != 3 * nT)
		return false; // (delimiters cannot be told without the source corners)
	if (nT <= lim_.faces)
		return false;
	P_.resize(nV);
	for (size_t v = 0; v < nV; ++v)
		P_[v] = Vec3(&mesh_.positions[3 * size_t(sm.sourceVertex[v])]); // (unplaced: below)
	T_ = sm.triangles;
	srcCorner_ = sm.sourceCorner;
	alive_.assign(nT, 1);
	made_.assign(nT, 0);
	live_ = nT;
	head_.assign(nV, -1);
	next_.assign(3 * nT, -1);
	for (size_t c = 3 * nT; c-- > 0;) {
		next_[c] = head_[size_t(T_[c])];
		head_[size_t(T_[c])] = int32_t(c);
	}
	locked_.assign(nV, 0);
	boundary_.assign(nV, 0);
	for (size_t v = 0; v < nV; ++v)
		locked_[v] = t_.vertexLocked[size_t(sm.sourceVertex[v])];
	lockEdges();
	// the finer level's vertices back at their input positions: its bounds grow by the moves
	e_ = src_.bound;
	{
		std::vector<double> move(nV, 0.0);
		for (size_t v = 0; v < nV; ++v)
			move[v] = (Vec3(&sm.positions[3 * v]) - P_[v]).Norm();
		for (size_t f = 0; f < nT; ++f)
			e_[f] += std::max({move[size_t(T_[3 * f])], move[size_t(T_[3 * f + 1])],
			                   move[size_t(T_[3 * f + 2])]});
	}
	cone_ = src_.cone;
	devBound_.assign(nT, 0.0);
	cosRoom_.resize(nT);
	for (size_t f = 0; f < nT; ++f)
		cosRoom_[f] = cosRoom(cone_[f]);
	// each vertex's quadric: the planes of the finer level's triangles around it (for placement)
	Q_.assign(nV, Quadric());
	for (size_t f = 0; f < nT; ++f) {
		const Vec3 nn = normal(int32_t(f));
		const double a = 0.5 * nn.Norm();
		if (!(a > 0))
			continue;
		const Vec3 un = nn / (2 * a);
		for (int k = 0; k < 3; ++k)
			Q_[size_t(T_[3 * f + size_t(k)])].addPlane(un, -un.dot(P_[size_t(T_[3 * f])]), a);
	}
	sf_ = sm.superface;
	int32_t sfCount = 0; // (over the input faces' ids too: a dropped face's may have no triangle)
	for (int32_t s : sf_)
		sfCount = std::max(sfCount, s + 1);
	for (int32_t s : sm.inputSuperface)
		sfCount = std::max(sfCount, s + 1);
	uf_.resize(size_t(sfCount));
	for (int32_t s = 0; s < sfCount; ++s)
		uf_[size_t(s)] = s;
	queued_.assign(nV, 0);
	{ // (each vertex's best collapse, in parallel; then one heap of them)
		std::vector<Entry> first(nV);
		std::vector<uint8_t> has(nV, 0);
		parallelRanges(nV, threads_, [&](size_t b, size_t e, size_t) {
			for (size_t v = b; v < e; ++v)
				has[v] = best(int32_t(v), first[v]);
		});
		size_t n = 0;
		for (size_t v = 0; v < nV; ++v)
			if (has[v]) {
				first[n++] = first[v];
				queued_[v] = 1;
			}
		first.resize(n);
		std::vector<uint8_t>().swap(has);
		heap_ = std::priority_queue<Entry>(std::less<Entry>(), std::move(first));
	}
	Eval ev;
	Ring r;
	while (live_ > lim_.faces && !heap_.empty()) {
		const Entry top = heap_.top();
		heap_.pop();
		queued_[size_t(top.v)] = 0;
		if (head_[size_t(top.v)] < 0)
			continue;
		if (!prepare(top.v, r) || !evaluate(top.v, top.u, r, ev, std::nextafter(top.cost, HUGE_VAL)) ||
		    ev.gap > top.cost) {
			pushBest(top.v);
			continue;
		}
		if (!fanFacesInput(top.v, top.u, ev.bound)) { // (a thin part: v stays)
			locked_[size_t(top.v)] = 1;
			continue;
		}
		collapse(top.v, top.u, ev);
		++collapses_;
	}
	if (live_ > lim_.faces)
		return false;
	if (lim_.placement > 0)
		place();
	write(out);
	return true;
}

void Collapser::write(CollapseSource &out)
{
	const LevelMesh &sm = src_.mesh;
	const size_t nV = sm.sourceVertex.size(), nT = T_.size() / 3;
	out.clear();
	LevelMesh &o = out.mesh;
	std::vector<int32_t> remap(nV, -1), sfId(uf_.size(), -1);
	for (size_t f = 0; f < nT; ++f)
		if (alive_[f])
			for (int k = 0; k < 3; ++k)
				remap[size_t(T_[3 * f + size_t(k)])] = 0;
	// (each array allocated once, at its size: growing them by doubling held up to twice the
	// level's cones at this peak)
	size_t usedV = 0;
	for (size_t v = 0; v < nV; ++v)
		usedV += remap[v] >= 0;
	o.sourceVertex.reserve(usedV);
	o.positions.reserve(3 * usedV);
	o.triangles.reserve(3 * live_);
	o.superface.reserve(live_);
	o.borderEdges.reserve(live_);
	if (!srcCorner_.empty()) {
		o.sourceCorner.reserve(3 * live_);
		o.sourceFace.reserve(live_);
	}
	out.bound.reserve(live_);
	out.cone.reserve(live_);
	int32_t nextV = 0;
	size_t placed = 0;
	double maxMove = 0;
	for (size_t v = 0; v < nV; ++v) {
		if (remap[v] < 0)
			continue;
		remap[v] = nextV++;
		o.sourceVertex.push_back(sm.sourceVertex[v]);
		const Vec3 in(&mesh_.positions[3 * size_t(sm.sourceVertex[v])]);
		for (int k = 0; k < 3; ++k)
			o.positions.push_back(P_[v][k]);
		if (!(P_[v] == in)) {
			++placed;
			maxMove = std::max(maxMove, (P_[v] - in).Norm());
		}
	}
	int32_t nextSf = 0;
	double maxDev = 0, devArea = 0, area = 0, maxBound = 0;
	const bool sources = !srcCorner_.empty();
	for (size_t f = 0; f < nT; ++f) {
		if (!alive_[f])
			continue;
		const int32_t r = find(sf_[f]);
		if (sfId[size_t(r)] < 0)
			sfId[size_t(r)] = nextSf++;
		o.superface.push_back(sfId[size_t(r)]);
		uint8_t border = 0;
		for (int k = 0; k < 3; ++k) {
			const int32_t c = int32_t(3 * f) + k;
			o.triangles.push_back(remap[size_t(T_[size_t(c)])]);
			const int32_t g = opposite(int32_t(f), T_[size_t(c)], T_[size_t(heNext(c))]);
			if (g < 0 || find(sf_[size_t(g)]) != r)
				border |= uint8_t(1u << k);
			if (sources)
				o.sourceCorner.push_back(srcCorner_[size_t(c)]);
		}
		o.borderEdges.push_back(border);
		if (sources)
			o.sourceFace.push_back(sm.sourceFace[f]);
		Vec3 n = normal(int32_t(f));
		const double a = 0.5 * n.Norm();
		area += a;
		if (!made_[f]) { // (as the finer level measured it)
			devArea += a * sm.stats.meanNormalDevDeg;
		} else {
			n.Normalize();
			maxDev = std::max(maxDev, devBound_[f]);
			devArea += a * angleDeg(n, cone_[f].axis);
		}
		maxBound = std::max(maxBound, e_[f]);
		out.bound.push_back(e_[f]);
		out.cone.push_back(cone_[f]);
	}
	o.inputSuperface.resize(sm.inputSuperface.size());
	for (size_t i = 0; i < sm.inputSuperface.size(); ++i) {
		const int32_t s = sm.inputSuperface[i];
		o.inputSuperface[i] = s < 0 ? s : sfId[size_t(find(s))]; // (-1: no triangle left)
	}
	LevelStats &st = o.stats;
	st.faces = o.triangles.size() / 3;
	st.vertices = size_t(nextV);
	st.superfaces = size_t(nextSf);
	st.maxNormalDevDeg = std::max(sm.stats.maxNormalDevDeg, std::min(maxDev, 180.0));
	st.meanNormalDevDeg = area > 0 ? devArea / area : 0;
	st.unmeasuredFaces = 0;
	st.distanceBound = maxBound;
	st.placedVertices = placed;
	st.maxPlacement = maxMove;
	st.collapses = collapses_;
}

} // namespace

void collapseSourceOf(const Topology &t, LevelMesh lm, CollapseSource &out)
{
	out.clear();
	const size_t nT = lm.triangles.size() / 3;
	size_t sfCount = 0;
	for (int32_t s : lm.superface)
		sfCount = std::max(sfCount, size_t(s) + 1);
	std::vector<NormalCone> cone(sfCount);
	std::vector<uint8_t> seen(sfCount, 0);
	for (size_t f = 0; f < t.nF && f < lm.inputSuperface.size(); ++f) {
		const int32_t s = lm.inputSuperface[f];
		if (s < 0 || !t.faceValid[f])
			continue;
		const NormalCone c{t.faceNormal[f], 0};
		cone[size_t(s)] = seen[size_t(s)] ? mergeCones(cone[size_t(s)], c) : c;
		seen[size_t(s)] = 1;
	}
	out.cone.resize(nT);
	for (size_t f = 0; f < nT; ++f) {
		const int32_t s = lm.superface[f];
		if (seen[size_t(s)]) {
			out.cone[f] = cone[size_t(s)];
		} else { // (a superface of invalid input faces only: the triangle's own normal)
			const Vec3 &a = Vec3(&lm.positions[3 * size_t(lm.triangles[3 * f])]);
			const Vec3 &b = Vec3(&lm.positions[3 * size_t(lm.triangles[3 * f + 1])]);
			const Vec3 &c = Vec3(&lm.positions[3 * size_t(lm.triangles[3 * f + 2])]);
			Vec3 n = (b - a) ^ (c - a);
			n.Normalize();
			out.cone[f] = {n, 0};
		}
	}
	out.bound.resize(nT);
	const bool perSuperface = lm.superfaceBound.size() == sfCount;
	for (size_t f = 0; f < nT; ++f) // (float bounds: the next float up, to stay bounds)
		out.bound[f] =
		    perSuperface
		        ? double(std::nextafter(lm.superfaceBound[size_t(lm.superface[f])], 3e38f))
		        : std::max(0.0, lm.stats.distanceBound);
	out.mesh = std::move(lm);
}

double farthestInputVertex(const Topology &t, const LevelMesh &level, double within,
                           size_t threads)
{
	const size_t nT = level.triangles.size() / 3;
	if (nT == 0)
		return HUGE_VAL;
	auto P = [&](int32_t v) { return Vec3(&level.positions[3 * size_t(v)]); };
	// a uniform grid over the triangles' boxes, about 2 triangles per cell (hashed into buckets)
	Vec3 lo = P(0), hi = P(0);
	for (size_t v = 0; v < level.positions.size() / 3; ++v)
		for (int k = 0; k < 3; ++k) {
			lo[k] = std::min(lo[k], level.positions[3 * v + size_t(k)]);
			hi[k] = std::max(hi[k], level.positions[3 * v + size_t(k)]);
		}
	double area = 0;
	for (size_t f = 0; f < nT; ++f)
		area += ((P(level.triangles[3 * f + 1]) - P(level.triangles[3 * f])) ^
		         (P(level.triangles[3 * f + 2]) - P(level.triangles[3 * f])))
		            .Norm();
	const double cell = std::max(std::sqrt(area / double(nT)), 1e-9 * t.diagonal);
	uint64_t buckets = 1;
	while (buckets < 2 * nT)
		buckets <<= 1;
	auto idx = [&](double x, int k) { return int64_t(std::floor((x - lo[k]) / cell)); };
	std::vector<int32_t> start, tri;
	auto forCells = [&](const Vec3 &a, const Vec3 &b, auto fn) {
		for (int64_t z = idx(a[2], 2); z <= idx(b[2], 2); ++z)
			for (int64_t y = idx(a[1], 1); y <= idx(b[1], 1); ++y)
				for (int64_t x = idx(a[0], 0); x <= idx(b[0], 0); ++x)
					fn(FaceGrid::bucketOf(x, y, z, buckets - 1));
	};
	auto box = [&](size_t f, Vec3 &a, Vec3 &b) {
		a = b = P(level.triangles[3 * f]);
		for (int k = 1; k < 3; ++k) {
			const Vec3 q = P(level.triangles[3 * f + size_t(k)]);
			for (int j = 0; j < 3; ++j)
				a[j] = std::min(a[j], q[j]), b[j] = std::max(b[j], q[j]);
		}
	};
	fillBuckets<int32_t>(
	    buckets,
	    [&](auto emit) {
		    Vec3 a, b;
		    for (size_t f = 0; f < nT; ++f) {
			    box(f, a, b);
			    forCells(a, b, [&](uint64_t c) { emit(size_t(c), int32_t(f)); });
		    }
	    },
	    start, tri);
	std::vector<uint8_t> used(t.nV, 0);
	for (size_t f = 0; f < t.nF; ++f)
		if (t.faceValid[f])
			for (int k = 0; k < 3; ++k)
				used[size_t(t.T[3 * f + size_t(k)])] = 1;
	// each vertex's nearest triangle: in a box growing from half a cell until the nearest found
	// is within it (every input point is within `within`); the vertices in parallel, at most
	// kFarthestSample of them (every k-th: this compares two levels, it proves nothing)
	const double rMax = within * (1 + 1e-9) + 1e-12 * t.diagonal;
	size_t nUsed = 0;
	for (uint8_t u : used)
		nUsed += u;
	const size_t stride = std::max<size_t>(1, (nUsed + kFarthestSample - 1) / kFarthestSample);
	size_t k = 0;
	for (size_t v = 0; v < t.nV; ++v)
		if (used[v])
			used[v] = k++ % stride == 0;
	std::vector<double> worst(std::max<size_t>(threads, 1), 0.0);
	parallelRanges(t.nV, threads, [&](size_t vb, size_t ve, size_t part) {
		for (size_t v = vb; v < ve; ++v) {
			if (!used[v])
				continue;
			const Vec3 p = t.pos(int32_t(v));
			double r = std::min(0.5 * cell, rMax), d = rMax;
			for (;;) {
				double best = r * r;
				bool any = false;
				forCells(p - Vec3(r, r, r), p + Vec3(r, r, r), [&](uint64_t c) {
					for (int32_t i = start[c]; i < start[c + 1]; ++i) {
						const size_t f = size_t(tri[size_t(i)]);
						const double d2 = pointTriangleDistance2(
						    p, P(level.triangles[3 * f]), P(level.triangles[3 * f + 1]),
						    P(level.triangles[3 * f + 2]));
						if (d2 <= best)
							best = d2, any = true;
					}
				});
				if (any) {
					d = std::sqrt(best);
					break;
				}
				if (r >= rMax)
					break;
				r = std::min(2 * r, rMax);
			}
			worst[part] = std::max(worst[part], d);
		}
	});
	return *std::max_element(worst.begin(), worst.end());
}

bool collapseLevel(const Topology &t, const MeshView &mesh, const CollapseSource &src,
                   const CollapseLimits &lim, size_t threads, CollapseSource &out)
{
	Collapser c(t, mesh, src, lim, threads);
	return c.run(out);
}

} // namespace detail
} // namespace gausslod
