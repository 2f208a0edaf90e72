// Beyond the paper (docs/DESIGN.md, 51): a level completed by edge collapses (reduce.h).
//
// Garland and Heckbert, "Surface Simplification Using Quadric Error Metrics", SIGGRAPH 1997: each
// vertex carries the quadric of the input planes it stands for; an edge's operation is the one
// whose quadric is least (the kept vertex at the quadric's least point, or at either end). Its
// cost is the collapse's proven gap plus the RMS distance to the quadric's planes (DESIGN 51:
// the gap keeps the worst point in view, the quadric what is kept); the least cost goes first,
// from a heap keyed by a lower bound of it, the cost taken when an entry comes up (lazy, as in
// quadric simplifiers). Each collapse is proven (reduce_patch.h): the fan's triangles carry a
// bound on their distance to the input, both ways, and the cone of the input normals they stand
// for.
//
// Vertex kinds (one table every step consults): free vertices move anywhere; a vertex on a mesh
// boundary moves along it, to a neighbour on it; a vertex on a delimiter chain (a seam, a material
// border) along the chain, and where a face count is asked also across it, as a junction of
// delimiters may (a chart that loses its corner extends its mapping); a locked input vertex and a
// vertex where boundary loops touch never move (they may receive collapses).
#include "reduce.h"
#include "level_passes.h"
#include "reduce_patch.h"

#include <Eigen/Eigenvalues>

namespace gausslod {
namespace detail {

double Quadric::stepAlong(const Vec3 &p, const Vec3 &n, double &curv) const
{
	const Vec3 An(q[0] * n[0] + q[1] * n[1] + q[2] * n[2], q[1] * n[0] + q[3] * n[1] + q[4] * n[2],
	              q[2] * n[0] + q[4] * n[1] + q[5] * n[2]);
	const Vec3 grad(q[0] * p[0] + q[1] * p[1] + q[2] * p[2] + q[6],
	                q[1] * p[0] + q[3] * p[1] + q[4] * p[2] + q[7],
	                q[2] * p[0] + q[4] * p[1] + q[5] * p[2] + q[8]);
	curv = n.dot(An);
	return curv > 0 ? -n.dot(grad) / curv : 0;
}

bool Quadric::minimum(const Vec3 &m, Vec3 &out) const
{
	Eigen::Matrix3d A;
	A << q[0], q[1], q[2], q[1], q[3], q[4], q[2], q[4], q[5];
	Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
	es.computeDirect(A);
	const Eigen::Vector3d ev = es.eigenvalues();
	const double top = ev(2);
	if (!(top > 0))
		return false;
	const Eigen::Vector3d x0(m[0], m[1], m[2]);
	const Eigen::Vector3d g = A * x0 + Eigen::Vector3d(q[6], q[7], q[8]);
	Eigen::Vector3d x = x0;
	for (int i = 0; i < 3; ++i)
		if (ev(i) > 1e-3 * top) {
			const Eigen::Vector3d e = es.eigenvectors().col(i);
			x -= e * (e.dot(g) / ev(i));
		}
	out = Vec3(x(0), x(1), x(2));
	return std::isfinite(out[0]) && std::isfinite(out[1]) && std::isfinite(out[2]);
}

namespace {

constexpr int kMaxRing = 32;          // a vertex with more triangles around it is not removed
constexpr double kFacing = 1e-3;      // cos of the steepest triangle allowed against the patch
constexpr double kFacingCells = 3;    // the thin-part test's reach, in face-grid cells
constexpr double kBorderWeight = 1.0; // boundary and delimiter planes, per squared edge length
// The texture's shift in a collapse's cost, as a share of its mesh-unit size (DESIGN 54: at 1 the
// seams' collapses went so far ahead that the distance doubled; 0.1 keeps the order geometric)
constexpr double kTexShiftWeight = 0.1;

// (kJunction: where delimiters meet or one ends. Where a face count is asked, seams and junctions
// also move across charts: a chart that loses its corner extends its mapping to the kept vertex)
enum Kind : uint8_t { kFree, kBoundary, kSeam, kJunction, kFixed, kGone };

// Operations: full collapses with the kept vertex at the quadric's least, the edge's middle, or
// either end; half-edge collapses a -> b and b -> a.
enum Op : uint8_t { kAtBest, kAtMiddle, kAtA, kAtB, kHalfAB, kHalfBA, kOps };
// (Entry::tried: bit op = that operation was tried; kExactKey = the key is the cost, not a lower
// bound of it)
constexpr uint8_t kExactKey = 0x80;

struct Entry {
	double cost;
	int32_t a, b;
	uint32_t sa, sb;
	uint8_t op, tried;
	bool before(const Entry &o) const // (first out: least cost, then lowest a, b, op)
	{
		if (cost != o.cost)
			return cost < o.cost;
		if (a != o.a)
			return a < o.a;
		if (b != o.b)
			return b < o.b;
		return op < o.op;
	}
};

// The collapses in line: a 4-ary heap. Its pops are the loop's largest cost, each a walk down a
// heap too large for the cache: four children to an entry halve the levels of a binary heap.
class CollapseQueue {
public:
	void assign(std::vector<Entry> &&all)
	{
		e_ = std::move(all);
		for (size_t i = e_.size() / 4 + 1; i-- > 0;)
			if (i < e_.size())
				down(i, e_[i]);
	}
	bool empty() const { return e_.empty(); }
	const Entry &top() const { return e_[0]; }
	void pop()
	{
		const Entry last = e_.back();
		e_.pop_back();
		if (!e_.empty())
			down(0, last);
	}
	void push(const Entry &x)
	{
		e_.push_back(x);
		up(e_.size() - 1, x);
	}

private:
	std::vector<Entry> e_;
	void down(size_t i, const Entry x)
	{
		const size_t n = e_.size();
		for (;;) {
			const size_t c = 4 * i + 1;
			if (c >= n)
				break;
			size_t best = c;
			for (size_t j = c + 1; j < std::min(c + 4, n); ++j)
				if (e_[j].before(e_[best]))
					best = j;
			if (!e_[best].before(x))
				break;
			e_[i] = e_[best];
			i = best;
		}
		e_[i] = x;
	}
	void up(size_t i, const Entry x)
	{
		while (i > 0) {
			const size_t p = (i - 1) / 4;
			if (!x.before(e_[p]))
				break;
			e_[i] = e_[p];
			i = p;
		}
		e_[i] = x;
	}
};

// The triangles around a vertex in counter-clockwise order: face[i] = (v, nb[i], nb[i+1]);
// closed: nb[n] == nb[0].
struct Ring {
	int n = 0;
	bool closed = false;
	int32_t face[kMaxRing];
	int32_t corner[kMaxRing]; // (v's corner in face[i])
	int32_t nb[kMaxRing + 1];
	void rotate(int s) // (a closed ring, starting at face s)
	{
		int32_t f[kMaxRing], c[kMaxRing], w[kMaxRing];
		for (int i = 0; i < n; ++i)
			f[i] = face[(i + s) % n], c[i] = corner[(i + s) % n], w[i] = nb[(i + s) % n];
		for (int i = 0; i < n; ++i)
			face[i] = f[i], corner[i] = c[i], nb[i] = w[i];
		nb[n] = nb[0];
	}
	int find(int32_t w) const
	{
		for (int i = 0; i < n; ++i)
			if (nb[i] == w)
				return i;
		return closed || nb[n] != w ? -1 : n;
	}
};

// One collapse ready to be proven and made.
struct Plan {
	int32_t kept = -1, gone = -1; // (a full collapse: kept takes the new position)
	bool full = false;
	Vec3 pos;
	PatchCase pc;
	int32_t oldId[PatchCase::kMaxTris]; // (per old triangle of pc: its mesh triangle)
	int32_t newId[PatchCase::kMaxTris]; // (per new triangle: the mesh triangle it reuses)
	int32_t point[PatchCase::kMaxPts];  // (per local point: its mesh vertex)
	int32_t dead[2];
	int nDead = 0;
	int32_t keptCorner[2] = {-1, -1}; // (half: u's corners in the two dead triangles)
	// (with sources: per new triangle, the source corner and texture coordinates its corner at
	// the kept vertex takes)
	int32_t newSrc[PatchCase::kMaxTris];
	float newUV[PatchCase::kMaxTris][2];
	bool extended[PatchCase::kMaxTris]; // (its chart's mapping extended to the kept vertex)
	PatchProof proof;
	double bound[PatchCase::kMaxTris];
	double uvBound[PatchCase::kMaxTris];
};

class Reducer {
public:
	Reducer(const Topology &t, const MeshView &mesh, const CollapseSource &src,
	        const ReduceLimits &lim, size_t threads)
	    : t_(t), mesh_(mesh), src_(src), lim_(lim), threads_(threads)
	{
	}
	bool run(CollapseSource &out, ReduceReport &report);

private:
	const Topology &t_;
	const MeshView &mesh_;
	const CollapseSource &src_;
	const ReduceLimits &lim_;
	const size_t threads_;
	std::vector<Vec3> P_;
	std::vector<int32_t> srcV_, T_, srcC_, head_, next_, fwd_;
	std::vector<uint8_t> alive_, dlm_, kind_, blocked_;
	std::vector<uint32_t> stamp_;
	std::vector<double> e_, devBound_; // (devBound_: of a triangle made here, -1 otherwise)
	std::vector<int32_t> sf_, sfUf_;   // (keepSuperfaces: each triangle's source superface)
	std::vector<NormalCone> cone_;
	std::vector<float> uvErr_;
	std::vector<Quadric> Q_;
	CollapseQueue heap_;
	size_t live_ = 0, collapses_ = 0;
	std::vector<int32_t> scratch_;

	Vec3 normal(int32_t f) const
	{
		const Vec3 &a = P_[size_t(T_[3 * f])], &b = P_[size_t(T_[3 * f + 1])],
		           &c = P_[size_t(T_[3 * f + 2])];
		return (b - a) ^ (c - a);
	}
	bool ring(int32_t v, Ring &r) const;
	void setUp();
	void classify();
	double opCost(int32_t a, int32_t b, int op, Vec3 &pos) const;
	bool allowed(int32_t a, int32_t b, int op, bool boundaryEdge, bool delimiterEdge) const;
	bool edgeFlags(int32_t a, int32_t b, bool &boundaryEdge, bool &delimiterEdge) const;
	bool bestOp(int32_t a, int32_t b, uint8_t tried, Entry &e) const;
	void pushEdges(int32_t v);
	bool planFull(int32_t u, int32_t v, const Vec3 &p, Plan &pl) const;
	bool planHalf(int32_t v, int32_t u, Plan &pl) const;
	bool plan(int32_t a, int32_t b, int op, const Vec3 &pos, Plan &pl) const;
	double slop() const { return 1e-12 * t_.diagonal; }
	bool check(Plan &pl) const;
	// (seams and junctions move across charts where a face count is asked: their cost counts the
	// texture's shift, so the collapses along seams go first)
	bool checkFacing_ = true;
	bool keys_ = false, allowJunctions_ = lim_.faces > 0 && !lim_.keepSuperfaces;
	std::vector<float> uv_; // (with texture coordinates: 2 per corner)
	void wedges(Plan &pl) const;
	int32_t superfaceOf(int32_t f) // (keepSuperfaces: the root of f's merged source superface)
	{
		int32_t x = sf_[size_t(f)];
		while (sfUf_[size_t(x)] != x)
			x = sfUf_[size_t(x)] = sfUf_[size_t(sfUf_[size_t(x)])];
		return x;
	}
	std::vector<int32_t> srcF_;
	void setDelimiter(int32_t c);
	uint8_t kindOf(int32_t v) const;
	bool facesInput(const Plan &pl) const;
	bool textureError(Plan &pl) const;
	double uvLocal(const Plan &pl) const;
	double textureShift(const Plan &pl) const;
	double gapLowerBound(int32_t a, int32_t b, int op, const Vec3 &pos) const;
	/// The cost of a collapse whose quadric error is q and whose largest gap is g.
	double cost(int32_t a, int32_t b, double g, double q) const;
	void apply(const Plan &pl);
	void prune(int32_t v);
	void write(CollapseSource &out, ReduceReport &report);
};

bool Reducer::ring(int32_t v, Ring &r) const
{
	r.n = 0;
	for (int32_t c = head_[size_t(v)]; c >= 0; c = next_[size_t(c)]) {
		const int32_t f = heFace(c);
		if (!alive_[size_t(f)])
			continue;
		if (r.n == kMaxRing)
			return false;
		r.face[r.n] = f;
		r.corner[r.n] = c;
		++r.n;
	}
	if (r.n == 0)
		return false;
	// order: face (v, a, b) is followed by the face whose a is this b
	int32_t a[kMaxRing], b[kMaxRing];
	for (int i = 0; i < r.n; ++i) {
		a[i] = T_[size_t(heNext(r.corner[i]))];
		b[i] = T_[size_t(hePrev(r.corner[i]))];
	}
	int start = 0, starts = 0;
	for (int i = 0; i < r.n; ++i) {
		int prev = 0;
		for (int j = 0; j < r.n; ++j)
			prev += b[j] == a[i];
		if (prev > 1)
			return false; // (non-manifold at v)
		if (prev == 0)
			start = i, ++starts;
	}
	if (starts > 1)
		return false;
	r.closed = starts == 0;
	int32_t f[kMaxRing], c[kMaxRing];
	int cur = start;
	for (int k = 0; k < r.n; ++k) {
		f[k] = r.face[cur];
		c[k] = r.corner[cur];
		r.nb[k] = a[cur];
		r.nb[k + 1] = b[cur];
		int nx = -1;
		for (int j = 0; j < r.n && nx < 0; ++j)
			if (a[j] == b[cur])
				nx = j;
		if (k + 1 < r.n && nx < 0)
			return false;
		cur = nx;
	}
	if (r.closed && r.nb[r.n] != r.nb[0])
		return false;
	for (int k = 0; k < r.n; ++k)
		r.face[k] = f[k], r.corner[k] = c[k];
	for (int i = 0; i < r.n; ++i) // (every neighbour once: else the fan is pinched)
		for (int j = i + 1; j < r.n + (r.closed ? 0 : 1); ++j)
			if (r.nb[i] == r.nb[j])
				return false;
	return true;
}

// The corner of the other live triangle on the edge a -> b of corner c (its corner at b, edge
// b -> a); -1 if there is none, -2 if the edge is not between exactly two consistently oriented
// triangles.
int32_t twinOf(const std::vector<int32_t> &T, const std::vector<int32_t> &head,
               const std::vector<int32_t> &next, const std::vector<uint8_t> &alive, int32_t c)
{
	const int32_t f = heFace(c), a = T[size_t(c)], b = T[size_t(heNext(c))];
	int32_t found = -1;
	for (int32_t d = head[size_t(b)]; d >= 0; d = next[size_t(d)]) {
		const int32_t g = heFace(d);
		if (g == f || !alive[size_t(g)])
			continue;
		if (T[size_t(heNext(d))] == a) {
			if (found >= 0)
				return -2;
			found = d;
		} else if (T[size_t(hePrev(d))] == a) {
			return -2; // (the same direction: inconsistent or non-manifold)
		}
	}
	return found;
}

void Reducer::setUp()
{
	const LevelMesh &sm = src_.mesh;
	const size_t nV = sm.sourceVertex.size(), nT = sm.triangles.size() / 3;
	P_.resize(nV);
	for (size_t v = 0; v < nV; ++v)
		P_[v] = Vec3(&sm.positions[3 * v]);
	srcV_ = sm.sourceVertex;
	T_ = sm.triangles;
	srcC_ = sm.sourceCorner.size() == 3 * nT ? sm.sourceCorner : std::vector<int32_t>();
	alive_.assign(nT, 1);
	live_ = nT;
	head_.assign(nV, -1);
	next_.assign(3 * nT, -1);
	for (size_t c = 3 * nT; c-- > 0;) {
		next_[c] = head_[size_t(T_[c])];
		head_[size_t(T_[c])] = int32_t(c);
	}
	e_ = src_.bound;
	devBound_.assign(nT, -1.0);
	cone_ = src_.cone;
	if (lim_.keepSuperfaces) {
		sf_ = sm.superface;
		int32_t n = 0; // (over the input faces' ids too: a dropped face's may have no triangle)
		for (int32_t x : sf_)
			n = std::max(n, x + 1);
		for (int32_t x : sm.inputSuperface)
			n = std::max(n, x + 1);
		sfUf_.resize(size_t(n));
		for (int32_t x = 0; x < n; ++x)
			sfUf_[size_t(x)] = x;
	}
	uvErr_ = src_.uvError.size() == nT ? src_.uvError : std::vector<float>(nT, 0.0f);
	fwd_.assign(nT, -1);
	if (t_.UV && !srcC_.empty()) { // (a level's own coordinates, or its corners' sources')
		uv_.resize(6 * nT);
		const bool own = sm.cornerUV.size() == 6 * nT;
		for (size_t c = 0; c < 3 * nT; ++c)
			for (int k = 0; k < 2; ++k)
				uv_[2 * c + size_t(k)] =
				    own ? sm.cornerUV[2 * c + size_t(k)] : t_.UV[2 * size_t(srcC_[c]) + size_t(k)];
	}
	stamp_.assign(nV, 0);
	blocked_.assign(nV, 0);
	// delimiters: an edge whose two triangles differ in face key, or in corner key at an end
	dlm_.assign(3 * nT, 0);
	keys_ = (mesh_.faceKey || mesh_.cornerKey) && !srcC_.empty() && sm.sourceFace.size() == nT;
	if (keys_) {
		srcF_ = sm.sourceFace;
		for (size_t c = 0; c < 3 * nT; ++c)
			setDelimiter(int32_t(c));
	}
	// quadrics: carried, or the planes of the source's triangles (area-weighted) and of its
	// boundary and delimiter edges (orthogonal to the triangle, through the edge)
	if (src_.quadric.size() == nV) {
		Q_ = src_.quadric;
	} else {
		Q_.assign(nV, Quadric());
		for (size_t f = 0; f < nT; ++f) {
			const Vec3 nn = normal(int32_t(f));
			const double len = nn.Norm();
			if (!(len > 0))
				continue;
			const Vec3 un = nn / len;
			const Vec3 &p0 = P_[size_t(T_[3 * f])];
			for (int k = 0; k < 3; ++k)
				Q_[size_t(T_[3 * f + size_t(k)])].addPlane(un, -un.dot(p0), 0.5 * len);
			for (int k = 0; k < 3; ++k) {
				const int32_t c = int32_t(3 * f) + k;
				if (!dlm_[size_t(c)] && twinOf(T_, head_, next_, alive_, c) != -1)
					continue;
				const Vec3 &a = P_[size_t(T_[size_t(c)])], &b = P_[size_t(T_[size_t(heNext(c))])];
				Vec3 m = (b - a) ^ un;
				const double ml = m.Norm();
				if (!(ml > 0))
					continue;
				m /= ml;
				const double w = kBorderWeight * (b - a).SquaredNorm();
				Q_[size_t(T_[size_t(c)])].addPlane(m, -m.dot(a), w);
				Q_[size_t(T_[size_t(heNext(c))])].addPlane(m, -m.dot(a), w);
			}
		}
	}
	classify();
}

void Reducer::classify()
{
	const size_t nV = P_.size();
	kind_.assign(nV, kGone);
	parallelRanges(nV, threads_, [&](size_t b, size_t e, size_t) {
		for (size_t v = b; v < e; ++v)
			if (head_[v] >= 0)
				kind_[v] = kindOf(int32_t(v));
	});
}

void Reducer::setDelimiter(int32_t c)
{
	const int32_t d = twinOf(T_, head_, next_, alive_, c);
	if (d < 0) {
		dlm_[size_t(c)] = 0;
		return;
	}
	bool cut = mesh_.faceKey &&
	           mesh_.faceKey[srcF_[size_t(heFace(c))]] != mesh_.faceKey[srcF_[size_t(heFace(d))]];
	if (mesh_.cornerKey) { // (c is at a, d at b; d's next is its corner at a)
		const uint32_t *K = mesh_.cornerKey;
		cut = cut || K[srcC_[size_t(c)]] != K[srcC_[size_t(heNext(d))]] ||
		      K[srcC_[size_t(heNext(c))]] != K[srcC_[size_t(d)]];
	}
	dlm_[size_t(c)] = dlm_[size_t(d)] = cut;
}

uint8_t Reducer::kindOf(int32_t v) const
{
	Ring r;
	if (t_.vertexLocked[size_t(srcV_[size_t(v)])] || !ring(v, r))
		return kFixed;
	int delimiters = 0;
	for (int i = 0; i < r.n; ++i)
		delimiters += dlm_[size_t(r.corner[i])];
	if (!r.closed) // (the last edge, nb[n] -> v, is a boundary edge: no delimiter)
		return delimiters == 0 ? kBoundary : kFixed;
	return delimiters == 0 ? kFree : delimiters == 2 ? kSeam : kJunction;
}

bool Reducer::edgeFlags(int32_t a, int32_t b, bool &boundaryEdge, bool &delimiterEdge) const
{
	int ab = 0, ba = 0;
	delimiterEdge = false;
	for (int32_t c = head_[size_t(a)]; c >= 0; c = next_[size_t(c)]) {
		if (!alive_[size_t(heFace(c))])
			continue;
		if (T_[size_t(heNext(c))] == b) {
			++ab;
			delimiterEdge = delimiterEdge || dlm_[size_t(c)];
		} else if (T_[size_t(hePrev(c))] == b) {
			++ba;
			delimiterEdge = delimiterEdge || dlm_[size_t(hePrev(c))];
		}
	}
	boundaryEdge = ab + ba == 1;
	return ab + ba >= 1 && ab <= 1 && ba <= 1;
}

bool Reducer::allowed(int32_t a, int32_t b, int op, bool boundaryEdge, bool delimiterEdge) const
{
	const uint8_t ka = kind_[size_t(a)], kb = kind_[size_t(b)];
	if (ka == kGone || kb == kGone)
		return false;
	const bool bothFree = ka == kFree && kb == kFree;
	if (op < kHalfAB)
		return lim_.placement && bothFree;
	if (lim_.placement && bothFree)
		return false; // (the full collapses at either end are the same and placed)
	const uint8_t kr = op == kHalfAB ? ka : kb; // (the removed vertex)
	switch (kr) {
		case kFree: return !boundaryEdge;
		case kBoundary: return boundaryEdge;
		case kSeam: // (along its seam; where a count needs it, across: its charts follow)
			return (delimiterEdge || allowJunctions_) && !boundaryEdge;
		case kJunction: return allowJunctions_ && !boundaryEdge;
		default: return false;
	}
}

double Reducer::opCost(int32_t a, int32_t b, int op, Vec3 &pos) const
{
	Quadric q = Q_[size_t(a)];
	q += Q_[size_t(b)];
	const Vec3 &pa = P_[size_t(a)], &pb = P_[size_t(b)];
	const Vec3 mid = (pa + pb) * 0.5;
	switch (op) {
		case kAtBest:
			if (!q.minimum(mid, pos))
				pos = mid;
			break;
		case kAtMiddle: pos = mid; break;
		case kAtA:
		case kHalfBA: pos = pa; break;
		default: pos = pb; break;
	}
	return std::max(0.0, q.eval(pos));
}

bool Reducer::plan(int32_t a, int32_t b, int op, const Vec3 &pos, Plan &pl) const
{
	return op < kHalfAB    ? planFull(a, b, pos, pl)
	       : op == kHalfAB ? planHalf(a, b, pl)
	                       : planHalf(b, a, pl);
}

double Reducer::cost(int32_t a, int32_t b, double g, double q) const
{
	// the collapse's own gap plus the root mean square distance to the input planes it stands for
	// (the quadric's trace is its total weight: its planes' normals are unit vectors)
	const Quadric &A = Q_[size_t(a)], &B = Q_[size_t(b)];
	const double w = A.q[0] + A.q[3] + A.q[5] + B.q[0] + B.q[3] + B.q[5];
	return g + (w > 0 ? std::sqrt(std::max(0.0, q) / w) : 0.0);
}

bool Reducer::bestOp(int32_t a, int32_t b, uint8_t tried, Entry &e) const
{
	bool boundaryEdge, delimiterEdge;
	if (!edgeFlags(a, b, boundaryEdge, delimiterEdge))
		return false;
	// the operation: the least quadric error; its key: the cost with a lower bound of the gap it
	// makes (the cost itself is taken when the entry comes up: lazy evaluation)
	for (;;) {
		int best = -1;
		double bestQ = 0;
		Vec3 pos;
		for (int op = 0; op < kOps; ++op) {
			if ((tried >> op & 1) || !allowed(a, b, op, boundaryEdge, delimiterEdge))
				continue;
			Vec3 p;
			const double q = opCost(a, b, op, p);
			if (best < 0 || q < bestQ)
				best = op, bestQ = q, pos = p;
		}
		if (best < 0)
			return false;
		const double g = gapLowerBound(a, b, best, pos);
		if (g <= lim_.bound) {
			e = {cost(a, b, g, bestQ), a,    b, stamp_[size_t(a)], stamp_[size_t(b)],
			     uint8_t(best),        tried};
			return true;
		}
		tried = uint8_t(tried | 1u << best); // (its gap alone is over the limit)
	}
}

double Reducer::gapLowerBound(int32_t a, int32_t b, int op, const Vec3 &pos) const
{
	// every proof's gap is at least the distance of a moved vertex from the other surface: of a
	// removed vertex from the fan, and of the new vertex from the old triangles
	const bool full = op < kHalfAB;
	const int32_t gone = op == kHalfBA ? b : a, kept = op == kHalfBA ? a : b;
	const Vec3 &target = full ? pos : P_[size_t(kept)];
	double toOld = HUGE_VAL, fromGone = HUGE_VAL, fromKept = full ? HUGE_VAL : 0.0;
	for (const int32_t w : {gone, kept}) {
		if (w == kept && !full)
			continue;
		for (int32_t c = head_[size_t(w)]; c >= 0; c = next_[size_t(c)]) {
			const int32_t f = heFace(c);
			if (!alive_[size_t(f)])
				continue;
			const int32_t x = T_[size_t(heNext(c))], y = T_[size_t(hePrev(c))];
			const Vec3 &px = P_[size_t(x)], &py = P_[size_t(y)];
			if (full)
				toOld = std::min(toOld, pointTriangleDistance2(pos, P_[size_t(w)], px, py));
			if (x == gone || x == kept || y == gone || y == kept)
				continue; // (on the collapsed edge: gone)
			fromGone = std::min(fromGone, pointTriangleDistance2(P_[size_t(gone)], target, px, py));
			if (full)
				fromKept =
				    std::min(fromKept, pointTriangleDistance2(P_[size_t(kept)], target, px, py));
		}
	}
	double g = 0;
	for (const double d2 : {toOld, fromGone, fromKept})
		if (d2 < HUGE_VAL)
			g = std::max(g, std::sqrt(d2));
	return g;
}

void Reducer::pushEdges(int32_t v)
{
	scratch_.clear();
	for (int32_t c = head_[size_t(v)]; c >= 0; c = next_[size_t(c)])
		if (alive_[size_t(heFace(c))]) {
			scratch_.push_back(T_[size_t(heNext(c))]);
			scratch_.push_back(T_[size_t(hePrev(c))]);
		}
	std::sort(scratch_.begin(), scratch_.end());
	scratch_.erase(std::unique(scratch_.begin(), scratch_.end()), scratch_.end());
	for (int32_t w : scratch_) {
		Entry e;
		if (bestOp(std::min(v, w), std::max(v, w), 0, e))
			heap_.push(e);
	}
}

bool Reducer::planFull(int32_t u, int32_t v, const Vec3 &p, Plan &pl) const
{
	Ring ru, rv;
	if (!ring(u, ru) || !ring(v, rv) || !ru.closed || !rv.closed)
		return false;
	const int iu = ru.find(v), iv = rv.find(u);
	if (iu < 0 || iv < 0)
		return false;
	ru.rotate(iu);
	rv.rotate(iv);
	const int nu = ru.n, nv = rv.n;
	if (ru.nb[nu - 1] != rv.nb[1] || rv.nb[nv - 1] != ru.nb[1])
		return false;
	const int nL = nu + nv - 4;
	if (nL < 3 || nL + 3 > PatchCase::kMaxPts || nu + nv - 2 > PatchCase::kMaxTris)
		return false;
	PatchCase &c = pl.pc;
	c.reset();
	int n = 0;
	for (int i = 1; i < nu; ++i)
		pl.point[n++] = ru.nb[i];
	for (int j = 2; j <= nv - 2; ++j)
		pl.point[n++] = rv.nb[j];
	for (int i = 0; i < nL; ++i) // (the link condition: a neighbour of both ends is one of the
		for (int j = i + 1; j < nL; ++j) // two across the edge)
			if (pl.point[i] == pl.point[j])
				return false;
	const int8_t U = int8_t(nL), V = int8_t(nL + 1), Pn = int8_t(nL + 2);
	pl.point[U] = u, pl.point[V] = v, pl.point[Pn] = -1;
	c.nPts = nL + 3;
	for (int i = 0; i < nL + 2; ++i)
		c.pos[i] = P_[size_t(pl.point[i])];
	c.pos[Pn] = p;
	auto idxU = [&](int i) { return int8_t(i == 0 || i == nu ? V : i - 1); };
	auto idxV = [&](int j) {
		return int8_t(j == 0 ? U : j == 1 ? nu - 2 : j == nv - 1 ? 0 : nu - 1 + j - 2);
	};
	for (int i = 0; i < nu; ++i) {
		c.oldTri[c.nOld][0] = U, c.oldTri[c.nOld][1] = idxU(i), c.oldTri[c.nOld][2] = idxU(i + 1);
		pl.oldId[c.nOld++] = ru.face[i];
	}
	for (int j = 1; j <= nv - 2; ++j) {
		c.oldTri[c.nOld][0] = V, c.oldTri[c.nOld][1] = idxV(j), c.oldTri[c.nOld][2] = idxV(j + 1);
		pl.oldId[c.nOld++] = rv.face[j];
	}
	for (int i = 1; i <= nu - 2; ++i) {
		c.newTri[c.nNew][0] = Pn, c.newTri[c.nNew][1] = idxU(i), c.newTri[c.nNew][2] = idxU(i + 1);
		pl.newId[c.nNew++] = ru.face[i];
	}
	for (int j = 1; j <= nv - 2; ++j) {
		c.newTri[c.nNew][0] = Pn, c.newTri[c.nNew][1] = idxV(j), c.newTri[c.nNew][2] = idxV(j + 1);
		pl.newId[c.nNew++] = rv.face[j];
	}
	c.nInner = 2;
	c.inner[0] = U, c.inner[1] = V;
	c.newInner = Pn;
	pl.kept = u, pl.gone = v, pl.full = true, pl.pos = p;
	pl.nDead = 2;
	pl.dead[0] = ru.face[0], pl.dead[1] = ru.face[nu - 1];
	pl.keptCorner[0] = pl.keptCorner[1] = -1;
	return true;
}

bool Reducer::planHalf(int32_t v, int32_t u, Plan &pl) const
{
	Ring rv;
	if (!ring(v, rv))
		return false;
	PatchCase &c = pl.pc;
	c.reset();
	const int n = rv.n;
	auto cornerOf = [&](int32_t f, int32_t w) {
		for (int32_t q = 3 * f; q < 3 * f + 3; ++q)
			if (T_[size_t(q)] == w)
				return q;
		return int32_t(-1);
	};
	// u's neighbours (the link condition; u may have more triangles than a removed vertex)
	constexpr int kMaxNbU = 512;
	int32_t nbU[kMaxNbU];
	int nNbU = 0;
	for (int32_t q = head_[size_t(u)]; q >= 0; q = next_[size_t(q)])
		if (alive_[size_t(heFace(q))]) {
			if (nNbU + 2 > kMaxNbU)
				return false;
			nbU[nNbU++] = T_[size_t(heNext(q))];
			nbU[nNbU++] = T_[size_t(hePrev(q))];
		}
	auto adjacentToU = [&](int32_t w) { return std::find(nbU, nbU + nNbU, w) != nbU + nNbU; };
	if (rv.closed) {
		const int iu = rv.find(u);
		if (iu < 0 || n < 3 || n + 1 > PatchCase::kMaxPts)
			return false;
		rv.rotate(iu);
		for (int j = 2; j <= n - 2; ++j)
			if (adjacentToU(rv.nb[j]))
				return false;
		if (n == 3) // (the new triangle would repeat one across the edge nb[1]-nb[2])
			for (int32_t q = head_[size_t(u)]; q >= 0; q = next_[size_t(q)]) {
				const int32_t g = heFace(q);
				if (alive_[size_t(g)] && g != rv.face[0] && g != rv.face[2] &&
				    cornerOf(g, rv.nb[1]) >= 0 && cornerOf(g, rv.nb[2]) >= 0)
					return false;
			}
		const int8_t V = int8_t(n);
		for (int j = 0; j < n; ++j)
			pl.point[j] = rv.nb[j];
		pl.point[V] = v;
		c.nPts = n + 1;
		for (int i = 0; i < c.nPts; ++i)
			c.pos[i] = P_[size_t(pl.point[i])];
		for (int j = 0; j < n; ++j) {
			c.oldTri[j][0] = V, c.oldTri[j][1] = int8_t(j), c.oldTri[j][2] = int8_t((j + 1) % n);
			pl.oldId[j] = rv.face[j];
		}
		c.nOld = n;
		for (int j = 1; j <= n - 2; ++j) {
			c.newTri[c.nNew][0] = 0, c.newTri[c.nNew][1] = int8_t(j),
			c.newTri[c.nNew][2] = int8_t(j + 1);
			pl.newId[c.nNew++] = rv.face[j];
		}
		pl.nDead = 2;
		pl.dead[0] = rv.face[0], pl.dead[1] = rv.face[n - 1];
		pl.keptCorner[0] = cornerOf(rv.face[0], u);
		pl.keptCorner[1] = cornerOf(rv.face[n - 1], u);
	} else {
		const bool first = rv.nb[0] == u;
		if ((!first && rv.nb[n] != u) || n < 2 || n + 2 > PatchCase::kMaxPts)
			return false;
		const int32_t shared = first ? rv.nb[1] : rv.nb[n - 1];
		for (int j = 0; j <= n; ++j)
			if (rv.nb[j] != u && rv.nb[j] != shared && adjacentToU(rv.nb[j]))
				return false;
		const int8_t V = int8_t(n + 1);
		for (int j = 0; j <= n; ++j)
			pl.point[j] = rv.nb[j];
		pl.point[V] = v;
		c.nPts = n + 2;
		for (int i = 0; i < c.nPts; ++i)
			c.pos[i] = P_[size_t(pl.point[i])];
		for (int j = 0; j < n; ++j) {
			c.oldTri[j][0] = V, c.oldTri[j][1] = int8_t(j), c.oldTri[j][2] = int8_t(j + 1);
			pl.oldId[j] = rv.face[j];
		}
		c.nOld = n;
		const int8_t K = first ? 0 : int8_t(n);
		for (int j = first ? 1 : 0; j <= (first ? n - 1 : n - 2); ++j) {
			c.newTri[c.nNew][0] = K, c.newTri[c.nNew][1] = int8_t(j),
			c.newTri[c.nNew][2] = int8_t(j + 1);
			pl.newId[c.nNew++] = rv.face[j];
		}
		c.pocket = true;
		c.pocketA = 0, c.pocketB = int8_t(n);
		pl.nDead = 1;
		pl.dead[0] = first ? rv.face[0] : rv.face[n - 1];
		pl.keptCorner[0] = pl.keptCorner[1] = cornerOf(pl.dead[0], u);
	}
	c.nInner = 1;
	c.inner[0] = int8_t(c.nPts - 1);
	c.newInner = -1;
	pl.kept = u, pl.gone = v, pl.full = false, pl.pos = P_[size_t(u)];
	return true;
}

bool Reducer::check(Plan &pl) const
{
	const PatchCase &c = pl.pc;
	if (!provePatch(c, kFacing, slop(), pl.proof))
		return false;
	for (int i = 0; i < c.nNew; ++i) {
		const Vec3 &a = c.pos[c.newTri[i][0]], &b = c.pos[c.newTri[i][1]],
		           &d = c.pos[c.newTri[i][2]];
		Vec3 nt = (b - a) ^ (d - a);
		if (!(nt.Norm() > 1e-30 * t_.diagonal * t_.diagonal))
			return false;
		nt.Normalize();
		double e = 0;
		for (int j = 0; j < c.nOld; ++j) {
			if (!(pl.proof.under[i] >> j & 1))
				continue;
			const int32_t s = pl.oldId[j];
			e = std::max(e, e_[size_t(s)]);
			if (lim_.normalDeg < 180) {
				const NormalCone &k = cone_[size_t(s)];
				if (angleDeg(nt, k.axis) + k.half > lim_.normalDeg)
					return false;
			}
			if (s == pl.newId[i] && checkFacing_) { // (the triangle it replaces: not turned over)
				Vec3 ns = normal(s);
				if (nt.dot(ns) < 0)
					return false;
			}
		}
		pl.bound[i] = e + pl.proof.gap[i];
		if (pl.bound[i] > lim_.bound)
			return false;
	}
	if (!srcC_.empty())
		wedges(pl);
	return textureError(pl);
}

// The point of triangle (a, b, c) nearest p, as barycentric coordinates.
void nearestBarycentric(const Vec3 &p, const Vec3 &a, const Vec3 &b, const Vec3 &c, double &l0,
                        double &l1, double &l2)
{
	// (the nearest point by the same regions as pointTriangleDistance2, then its coordinates)
	const Vec3 ab = b - a, ac = c - a, ap = p - a;
	const double d1 = ab.dot(ap), d2 = ac.dot(ap);
	if (d1 <= 0 && d2 <= 0) {
		l0 = 1, l1 = l2 = 0;
		return;
	}
	const Vec3 bp = p - b;
	const double d3 = ab.dot(bp), d4 = ac.dot(bp);
	if (d3 >= 0 && d4 <= d3) {
		l1 = 1, l0 = l2 = 0;
		return;
	}
	const double vc = d1 * d4 - d3 * d2;
	if (vc <= 0 && d1 >= 0 && d3 <= 0) {
		const double v = d1 / (d1 - d3);
		l0 = 1 - v, l1 = v, l2 = 0;
		return;
	}
	const Vec3 cp = p - c;
	const double d5 = ab.dot(cp), d6 = ac.dot(cp);
	if (d6 >= 0 && d5 <= d6) {
		l2 = 1, l0 = l1 = 0;
		return;
	}
	const double vb = d5 * d2 - d1 * d6;
	if (vb <= 0 && d2 >= 0 && d6 <= 0) {
		const double w = d2 / (d2 - d6);
		l0 = 1 - w, l2 = w, l1 = 0;
		return;
	}
	const double va = d3 * d6 - d5 * d4;
	if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
		const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
		l1 = 1 - w, l2 = w, l0 = 0;
		return;
	}
	const double den = 1.0 / (va + vb + vc);
	l1 = vb * den, l2 = vc * den, l0 = 1 - l1 - l2;
}

bool Reducer::textureError(Plan &pl) const
{
	const PatchCase &c = pl.pc;
	for (int i = 0; i < c.nNew; ++i)
		pl.uvBound[i] = 0;
	if (uv_.empty())
		return true;
	const double local = uvLocal(pl);
	for (int i = 0; i < c.nNew; ++i) {
		double worst = 0;
		for (int j = 0; j < c.nOld; ++j)
			if (pl.proof.under[i] >> j & 1)
				worst = std::max(worst, double(uvErr_[size_t(pl.oldId[j])]));
		pl.uvBound[i] = worst + local;
		if (lim_.texError > 0 && !lim_.texErrorSoft && pl.uvBound[i] > lim_.texError)
			return false;
	}
	return true;
}

double Reducer::uvLocal(const Plan &pl) const
{
	const PatchCase &c = pl.pc;
	// at a removed vertex, in each chart around it: its own coordinates against those the new
	// triangles of that chart show at their point nearest it
	double local = 0;
	if (pl.full) // (free vertices, one chart: both ends)
		for (const int32_t w : {pl.gone, pl.kept}) {
			int32_t cw = -1;
			for (int32_t q = 3 * pl.dead[0]; q < 3 * pl.dead[0] + 3; ++q)
				if (T_[size_t(q)] == w)
					cw = q;
			double nearest = HUGE_VAL, err = 0;
			for (int i = 0; i < c.nNew; ++i) {
				const Vec3 &a = c.pos[c.newTri[i][0]], &b = c.pos[c.newTri[i][1]],
				           &d = c.pos[c.newTri[i][2]];
				const double d2 = pointTriangleDistance2(P_[size_t(w)], a, b, d);
				if (d2 >= nearest)
					continue;
				nearest = d2;
				double l[3];
				nearestBarycentric(P_[size_t(w)], a, b, d, l[0], l[1], l[2]);
				// (the new triangle's corners: its kept-vertex corner's are the new ones)
				const int32_t f = pl.newId[i];
				double uv[3][2];
				for (int k = 0; k < 3; ++k) {
					const int8_t pt = c.newTri[i][k];
					int32_t q = -1;
					for (int32_t r = 3 * f; r < 3 * f + 3 && pt != c.newInner; ++r)
						if (T_[size_t(r)] == pl.point[pt])
							q = r;
					for (int m = 0; m < 2; ++m)
						uv[k][m] = pt == c.newInner || q < 0 ? pl.newUV[i][m]
						                                     : uv_[2 * size_t(q) + size_t(m)];
				}
				const double du =
				    l[0] * uv[0][0] + l[1] * uv[1][0] + l[2] * uv[2][0] - uv_[2 * size_t(cw)];
				const double dv =
				    l[0] * uv[0][1] + l[1] * uv[1][1] + l[2] * uv[2][1] - uv_[2 * size_t(cw) + 1];
				err = std::sqrt(du * du + dv * dv);
			}
			local = std::max(local, err);
		}
	// (a chart extended to the kept vertex reaches beyond its island by this much)
	for (int i = 0; i < c.nNew && !pl.full; ++i)
		if (pl.extended[i])
			for (int32_t q = 3 * pl.newId[i]; q < 3 * pl.newId[i] + 3; ++q)
				if (T_[size_t(q)] == pl.gone)
					local = std::max(local,
					                 double(std::hypot(pl.newUV[i][0] - uv_[2 * size_t(q)],
					                                   pl.newUV[i][1] - uv_[2 * size_t(q) + 1])));
	const Vec3 &pv = P_[size_t(pl.gone)];
	double nearest = HUGE_VAL, err = 0;
	int chart = 0;
	for (int i = 0; i < c.nNew && !pl.full; ++i) {
		const int32_t f = pl.newId[i];
		int32_t cv = -1;
		for (int32_t q = 3 * f; q < 3 * f + 3; ++q)
			if (T_[size_t(q)] == pl.gone)
				cv = q;
		if (cv < 0)
			continue;
		if (dlm_[size_t(cv)]) { // (the next chart)
			local = std::max(local, err);
			nearest = HUGE_VAL, err = 0, ++chart;
		}
		Vec3 p[3];
		double uv[3][2];
		for (int k = 0; k < 3; ++k) {
			const int32_t q = 3 * f + k;
			p[k] = q == cv ? P_[size_t(pl.kept)] : P_[size_t(T_[size_t(q)])];
			for (int j = 0; j < 2; ++j)
				uv[k][j] = q == cv ? pl.newUV[i][j] : uv_[2 * size_t(q) + size_t(j)];
		}
		const double d2 = pointTriangleDistance2(pv, p[0], p[1], p[2]);
		if (d2 >= nearest)
			continue;
		nearest = d2;
		double l[3];
		nearestBarycentric(pv, p[0], p[1], p[2], l[0], l[1], l[2]);
		const double du = l[0] * uv[0][0] + l[1] * uv[1][0] + l[2] * uv[2][0] - uv_[2 * size_t(cv)];
		const double dv =
		    l[0] * uv[0][1] + l[1] * uv[1][1] + l[2] * uv[2][1] - uv_[2 * size_t(cv) + 1];
		err = std::sqrt(du * du + dv * dv);
	}
	return std::max(local, err);
}

double Reducer::textureShift(const Plan &pl) const
{
	// the texture error at the removed vertices in mesh units (UV units times the old patch's
	// length per UV unit: the square root of its area over its area in texture space), weighted
	double a3 = 0, a2 = 0;
	for (int j = 0; j < pl.pc.nOld; ++j) {
		const size_t f = size_t(pl.oldId[j]);
		a3 += normal(int32_t(f)).Norm();
		const float *t = &uv_[6 * f];
		a2 += std::fabs((t[2] - t[0]) * (t[5] - t[1]) - (t[3] - t[1]) * (t[4] - t[0]));
	}
	return a2 > 0 ? kTexShiftWeight * uvLocal(pl) * std::sqrt(a3 / a2) : 0.0;
}

void Reducer::wedges(Plan &pl) const
{
	const PatchCase &c = pl.pc;
	auto setFrom = [&](int i, int32_t corner) {
		pl.extended[i] = false;
		pl.newSrc[i] = srcC_[size_t(corner)];
		for (int k = 0; k < 2; ++k)
			pl.newUV[i][k] = uv_.empty() ? 0.0f : uv_[2 * size_t(corner) + size_t(k)];
	};
	if (pl.full) { // (free vertices: one chart; the attributes of the end nearer the new position)
		const Vec3 iu(&mesh_.positions[3 * size_t(srcV_[size_t(pl.kept)])]);
		const Vec3 iv(&mesh_.positions[3 * size_t(srcV_[size_t(pl.gone)])]);
		const int32_t from =
		    (iv - pl.pos).SquaredNorm() < (iu - pl.pos).SquaredNorm() ? pl.gone : pl.kept;
		int32_t corner = -1;
		for (int32_t q = 3 * pl.dead[0]; q < 3 * pl.dead[0] + 3; ++q)
			if (T_[size_t(q)] == from)
				corner = q;
		for (int i = 0; i < c.nNew; ++i)
			setFrom(i, corner);
		if (!uv_.empty()) { // (the coordinates the old patch has at its point nearest the new one)
			double best = HUGE_VAL;
			for (int j = 0; j < c.nOld; ++j) {
				const int32_t f = pl.oldId[j];
				const Vec3 &a = P_[size_t(T_[3 * size_t(f)])],
				           &b = P_[size_t(T_[3 * size_t(f) + 1])],
				           &d = P_[size_t(T_[3 * size_t(f) + 2])];
				const double d2 = pointTriangleDistance2(pl.pos, a, b, d);
				if (d2 >= best)
					continue;
				best = d2;
				double l[3];
				nearestBarycentric(pl.pos, a, b, d, l[0], l[1], l[2]);
				for (int k = 0; k < 2; ++k) {
					double x = 0;
					for (int m = 0; m < 3; ++m)
						x += l[m] * uv_[2 * (3 * size_t(f) + size_t(m)) + size_t(k)];
					for (int i = 0; i < c.nNew; ++i)
						pl.newUV[i][k] = float(x);
				}
			}
		}
		return;
	}
	// half: the charts around v in ring order, split by its delimiters (the edge v -> nb[j] opens
	// the chart of face j); the first (with dead face 0) and the last (with the other dead face,
	// the first again if the edge v-u parts no charts) have u's corners; a chart between them
	// extends its mapping to u
	auto cornerOfGone = [&](int32_t f) {
		for (int32_t q = 3 * f; q < 3 * f + 3; ++q)
			if (T_[size_t(q)] == pl.gone)
				return q;
		return int32_t(-1);
	};
	int last = 0;
	for (int i = 0; i < c.nNew; ++i)
		last += dlm_[size_t(cornerOfGone(pl.newId[i]))];
	if (pl.nDead == 2)
		last += dlm_[size_t(cornerOfGone(pl.dead[1]))];
	int chart = 0;
	for (int i = 0; i < c.nNew; ++i) {
		const int32_t f = pl.newId[i];
		const int32_t cv = cornerOfGone(f);
		chart += dlm_[size_t(cv)];
		if (chart == 0) {
			setFrom(i, pl.keptCorner[0]);
		} else if (chart == last) {
			setFrom(i, pl.keptCorner[1]);
		} else { // (v's corner of this chart, its mapping extended to u's position)
			pl.extended[i] = true;
			pl.newSrc[i] = srcC_[size_t(cv)];
			const int32_t q1 = heNext(cv), q2 = hePrev(cv);
			const Vec3 &p0 = P_[size_t(pl.gone)], &p1 = P_[size_t(T_[size_t(q1)])],
			           &p2 = P_[size_t(T_[size_t(q2)])];
			const Vec3 e1 = p1 - p0, e2 = p2 - p0, d = P_[size_t(pl.kept)] - p0;
			const double a11 = e1.dot(e1), a12 = e1.dot(e2), a22 = e2.dot(e2);
			const double det = a11 * a22 - a12 * a12;
			double x = 0, y = 0;
			if (det > 0) {
				x = (a22 * d.dot(e1) - a12 * d.dot(e2)) / det;
				y = (a11 * d.dot(e2) - a12 * d.dot(e1)) / det;
			}
			for (int k = 0; k < 2; ++k) {
				const double t0 = uv_.empty() ? 0 : uv_[2 * size_t(cv) + size_t(k)];
				const double t1 = uv_.empty() ? 0 : uv_[2 * size_t(q1) + size_t(k)];
				const double t2 = uv_.empty() ? 0 : uv_[2 * size_t(q2) + size_t(k)];
				pl.newUV[i][k] = float(t0 + x * (t1 - t0) + y * (t2 - t0));
			}
		}
	}
}

bool Reducer::facesInput(const Plan &pl) const
{
	// not on the other side of a thin part: the input surface nearest each new triangle faces it
	const PatchCase &c = pl.pc;
	for (int i = 0; i < c.nNew; ++i) {
		const Vec3 &a = c.pos[c.newTri[i][0]], &b = c.pos[c.newTri[i][1]],
		           &d = c.pos[c.newTri[i][2]];
		Vec3 nt = (b - a) ^ (d - a);
		nt.Normalize();
		if (!nearestInputFacing(t_, (a + b + d) / 3.0, nt,
		                        pl.bound[i] * (1 + 1e-9) + 1e-12 * t_.diagonal, kFacingCells))
			return false;
	}
	return true;
}

void Reducer::prune(int32_t v)
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

void Reducer::apply(const Plan &pl)
{
	const PatchCase &c = pl.pc;
	const int32_t u = pl.kept, v = pl.gone;
	// the new triangles' cones, from the old ones under them, and the largest deviation from
	// each of those (what the level reports)
	NormalCone cones[PatchCase::kMaxTris];
	double dev[PatchCase::kMaxTris];
	for (int i = 0; i < c.nNew; ++i) {
		bool first = true;
		const Vec3 &a = c.pos[c.newTri[i][0]], &b = c.pos[c.newTri[i][1]],
		           &d = c.pos[c.newTri[i][2]];
		Vec3 nt = (b - a) ^ (d - a);
		nt.Normalize();
		dev[i] = 0;
		for (int j = 0; j < c.nOld; ++j)
			if (pl.proof.under[i] >> j & 1) {
				const NormalCone &k = cone_[size_t(pl.oldId[j])];
				dev[i] = std::max(dev[i], std::min(180.0, angleDeg(nt, k.axis) + k.half));
				cones[i] = first ? k : mergeCones(cones[i], k);
				first = false;
			}
	}
	if (lim_.keepSuperfaces) { // (the patch's superfaces become one)
		const int32_t root = superfaceOf(pl.oldId[0]);
		for (int j = 1; j < c.nOld; ++j) {
			const int32_t r = superfaceOf(pl.oldId[j]);
			if (r != root)
				sfUf_[size_t(r)] = root;
		}
	}
	for (int d = 0; d < pl.nDead; ++d) { // (each dead triangle goes into a new one over it)
		int j = 0;
		while (pl.oldId[j] != pl.dead[d])
			++j;
		int i = 0;
		while (i + 1 < c.nNew && !(pl.proof.under[i] >> j & 1))
			++i;
		fwd_[size_t(pl.dead[d])] = pl.newId[i];
		alive_[size_t(pl.dead[d])] = 0;
		--live_;
	}
	// the kept vertex
	Q_[size_t(u)] += Q_[size_t(v)];
	if (pl.full) {
		P_[size_t(u)] = pl.pos;
		// (its attributes: those of the end whose input vertex is nearer)
		const Vec3 iu(&mesh_.positions[3 * size_t(srcV_[size_t(u)])]);
		const Vec3 iv(&mesh_.positions[3 * size_t(srcV_[size_t(v)])]);
		srcV_[size_t(u)] =
		    srcV_[size_t((iv - pl.pos).SquaredNorm() < (iu - pl.pos).SquaredNorm() ? v : u)];
	}
	// the new triangles: their corners at u or v become u's (with sources: the wedge of u in
	// their chart, wedges())
	for (int i = 0; i < c.nNew; ++i) {
		const int32_t f = pl.newId[i];
		for (int32_t q = 3 * f; q < 3 * f + 3; ++q) {
			const int32_t w = T_[size_t(q)];
			if (w != v && !(pl.full && w == u))
				continue;
			T_[size_t(q)] = u;
			if (!srcC_.empty())
				srcC_[size_t(q)] = pl.newSrc[i];
			if (!uv_.empty())
				uv_[2 * size_t(q)] = pl.newUV[i][0], uv_[2 * size_t(q) + 1] = pl.newUV[i][1];
		}
		e_[size_t(f)] = pl.bound[i];
		devBound_[size_t(f)] = dev[i];
		cone_[size_t(f)] = cones[i];
		uvErr_[size_t(f)] = std::nextafter(float(pl.uvBound[i]), 3e38f);
	}
	// v's corners join u's list
	if (head_[size_t(v)] >= 0) {
		int32_t tail = head_[size_t(v)];
		while (next_[size_t(tail)] >= 0)
			tail = next_[size_t(tail)];
		next_[size_t(tail)] = head_[size_t(u)];
		head_[size_t(u)] = head_[size_t(v)];
		head_[size_t(v)] = -1;
	}
	kind_[size_t(v)] = kGone;
	prune(u);
	for (int d = 0; d < pl.nDead; ++d)
		for (int32_t q = 3 * pl.dead[d]; q < 3 * pl.dead[d] + 3; ++q)
			if (T_[size_t(q)] != u && T_[size_t(q)] != v)
				prune(T_[size_t(q)]);
	if (keys_) { // (the fan's edges join triangles anew: their delimiters, and the kinds around)
		for (int i = 0; i < c.nNew; ++i)
			for (int k = 0; k < 3; ++k)
				setDelimiter(3 * pl.newId[i] + k);
		if (kind_[size_t(u)] != kFixed)
			kind_[size_t(u)] = kindOf(u);
		for (int i = 0; i < c.nPts; ++i) {
			const int32_t w = pl.point[i];
			if (w >= 0 && w != u && w != v && kind_[size_t(w)] != kFixed)
				kind_[size_t(w)] = kindOf(w);
		}
	}
	++stamp_[size_t(u)];
	pushEdges(u);
	for (int i = 0; i < c.nPts; ++i) { // (collapses refused near here may be legal now)
		const int32_t w = pl.point[i];
		if (w >= 0 && w != u && w != v && blocked_[size_t(w)]) {
			blocked_[size_t(w)] = 0;
			pushEdges(w);
		}
	}
}

bool Reducer::run(CollapseSource &out, ReduceReport &report)
{
	setUp();
	const size_t nV = P_.size();
	const bool budget = lim_.faces > 0;
	auto more = [&] { return !budget || live_ > lim_.faces; };
	for (int round = 0; round < 32 && more(); ++round) {
		// every edge's best operation (each vertex's edges to higher vertices, in parallel)
		std::vector<std::vector<Entry>> parts(std::max<size_t>(threads_, 1));
		const size_t chunk = 4096, nChunks = (nV + chunk - 1) / chunk;
		std::vector<std::vector<Entry>> byChunk(nChunks);
		parallelRanges(nChunks, threads_, [&](size_t cb, size_t ce, size_t) {
			std::vector<int32_t> nb;
			for (size_t k = cb; k < ce; ++k)
				for (size_t v = k * chunk; v < std::min(nV, (k + 1) * chunk); ++v) {
					nb.clear();
					for (int32_t c = head_[v]; c >= 0; c = next_[size_t(c)])
						if (alive_[size_t(heFace(c))]) {
							nb.push_back(T_[size_t(heNext(c))]);
							nb.push_back(T_[size_t(hePrev(c))]);
						}
					std::sort(nb.begin(), nb.end());
					nb.erase(std::unique(nb.begin(), nb.end()), nb.end());
					for (int32_t w : nb) {
						Entry e;
						if (w > int32_t(v) && bestOp(int32_t(v), w, 0, e))
							byChunk[k].push_back(e);
					}
				}
		});
		std::vector<Entry> all;
		for (auto &b : byChunk)
			all.insert(all.end(), b.begin(), b.end());
		byChunk.clear();
		heap_.assign(std::move(all));
		std::fill(blocked_.begin(), blocked_.end(), 0);
		const size_t before = collapses_;
		Plan pl;
		while (more() && !heap_.empty()) {
			Entry top = heap_.top();
			heap_.pop();
			if (kind_[size_t(top.a)] == kGone || kind_[size_t(top.b)] == kGone ||
			    stamp_[size_t(top.a)] != top.sa || stamp_[size_t(top.b)] != top.sb)
				continue;
			Vec3 pos;
			const double q = opCost(top.a, top.b, top.op, pos);
			// (a key from the lower bound: first the collapse's own gap, the cheaper proof; a
			// collapse that costs more than the next one goes back in line with its cost)
			const bool planned = plan(top.a, top.b, top.op, pos, pl);
			if (planned && !(top.tried & kExactKey) &&
			    provePatch(pl.pc, kFacing, slop(), pl.proof, false)) {
				double g = 0;
				for (int i = 0; i < pl.pc.nNew; ++i)
					g = std::max(g, pl.proof.gap[i]);
				if (!uv_.empty()) {
					wedges(pl);
					g += textureShift(pl);
				}
				const double exact = cost(top.a, top.b, g, q);
				if (!heap_.empty() && exact > heap_.top().cost * (1 + 1e-9)) {
					top.cost = exact;
					top.tried |= kExactKey;
					heap_.push(top);
					continue;
				}
			}
			if (!planned || !check(pl)) {
				Entry e;
				if (bestOp(top.a, top.b, uint8_t((top.tried & ~kExactKey) | 1u << top.op), e))
					heap_.push(e);
				else
					blocked_[size_t(top.a)] = blocked_[size_t(top.b)] = 1;
				continue;
			}
			// (the key is a lower bound of the cost, or the cost when the neighbourhood was as it
			// was: a collapse that now costs more than the next one goes back in line)
			double g = 0;
			for (int i = 0; i < pl.pc.nNew; ++i)
				g = std::max(g, pl.proof.gap[i]);
			if (!uv_.empty())
				g += textureShift(pl);
			const double now = cost(top.a, top.b, g, q);
			if (now > top.cost * (1 + 1e-9) && !heap_.empty() &&
			    now > heap_.top().cost * (1 + 1e-9)) {
				top.cost = now;
				top.tried |= kExactKey;
				heap_.push(top);
				continue;
			}
			if (checkFacing_ && !facesInput(pl)) {
				blocked_[size_t(top.a)] = blocked_[size_t(top.b)] = 1;
				continue;
			}
			apply(pl);
			++collapses_;
		}
		if (!budget && round >= 1)
			break; // (by error: what the first rounds refused stays refused, near enough)
		if (collapses_ == before) {
			// (stuck short of a face budget: only a true minimum may stop it, so the thin-part
			// test and the turn-over guard give way; the proven bound still says what the level
			// is)
			if (!budget || !checkFacing_)
				break;
			checkFacing_ = false;
		}
	}
	write(out, report);
	return !more() || !budget;
}

void Reducer::write(CollapseSource &out, ReduceReport &report)
{
	const LevelMesh &sm = src_.mesh;
	const size_t nV = P_.size(), nT = T_.size() / 3;
	out.clear();
	LevelMesh &o = out.mesh;
	// superfaces: the source's as the collapses merged them (keepSuperfaces), else connected
	// triangles whose normals fall in one cell of the level, across edges that are no delimiter
	std::vector<int32_t> uf(nT);
	std::vector<CellKey> cell(nT, kInvalidCell);
	for (size_t f = 0; f < nT; ++f) {
		uf[f] = int32_t(f);
		if (alive_[f] && !lim_.keepSuperfaces)
			cell[f] = cellOfNormal(normal(int32_t(f)), lim_.level);
	}
	auto findCell = [&](int32_t x) {
		while (uf[size_t(x)] != x)
			x = uf[size_t(x)] = uf[size_t(uf[size_t(x)])];
		return x;
	};
	// (a group's id: a source superface's root, or a triangle that is its cell group's root)
	auto find = [&](int32_t f) { return lim_.keepSuperfaces ? superfaceOf(f) : findCell(f); };
	std::vector<int32_t> twin(3 * nT, -1);
	for (size_t c = 0; c < 3 * nT; ++c) {
		if (!alive_[c / 3])
			continue;
		twin[c] = twinOf(T_, head_, next_, alive_, int32_t(c));
		const int32_t d = twin[c];
		if (d < 0 || dlm_[c] || cell[c / 3] == kInvalidCell ||
		    cell[c / 3] != cell[size_t(heFace(d))])
			continue;
		const int32_t a = findCell(int32_t(c / 3)), b = findCell(heFace(d));
		if (a != b)
			uf[size_t(std::max(a, b))] = std::min(a, b);
	}
	std::vector<int32_t> remap(nV, -1), triId(nT, -1), sfId(std::max(nT, sfUf_.size()), -1);
	for (size_t f = 0; f < nT; ++f)
		if (alive_[f])
			for (int k = 0; k < 3; ++k)
				remap[size_t(T_[3 * f + size_t(k)])] = 0;
	size_t usedV = 0;
	for (size_t v = 0; v < nV; ++v)
		usedV += remap[v] >= 0;
	o.sourceVertex.reserve(usedV);
	o.positions.reserve(3 * usedV);
	out.quadric.reserve(usedV);
	int32_t nextV = 0;
	size_t placed = 0;
	double maxMove = 0;
	for (size_t v = 0; v < nV; ++v) {
		if (remap[v] < 0)
			continue;
		remap[v] = nextV++;
		o.sourceVertex.push_back(srcV_[v]);
		for (int k = 0; k < 3; ++k)
			o.positions.push_back(P_[v][k]);
		out.quadric.push_back(Q_[v]);
		const Vec3 in(&mesh_.positions[3 * size_t(srcV_[v])]);
		if (!(P_[v] == in)) {
			++placed;
			maxMove = std::max(maxMove, (P_[v] - in).Norm());
		}
	}
	const bool sources = !srcC_.empty();
	int32_t nextSf = 0, nextT = 0;
	double maxDev = 0, devArea = 0, area = 0, maxBound = 0;
	float maxUv = 0;
	o.triangles.reserve(3 * live_);
	o.superface.reserve(live_);
	o.borderEdges.reserve(live_);
	out.bound.reserve(live_);
	out.cone.reserve(live_);
	out.uvError.reserve(live_);
	for (size_t f = 0; f < nT; ++f) {
		if (!alive_[f])
			continue;
		triId[f] = nextT++;
		const int32_t r = find(int32_t(f));
		if (sfId[size_t(r)] < 0)
			sfId[size_t(r)] = nextSf++;
		o.superface.push_back(sfId[size_t(r)]);
		uint8_t border = 0;
		for (int k = 0; k < 3; ++k) {
			const size_t c = 3 * f + size_t(k);
			o.triangles.push_back(remap[size_t(T_[c])]);
			if (twin[c] < 0 || find(heFace(twin[c])) != r)
				border |= uint8_t(1u << k);
			if (sources)
				o.sourceCorner.push_back(srcC_[c]);
		}
		o.borderEdges.push_back(border);
		if (!uv_.empty())
			o.cornerUV.insert(o.cornerUV.end(), &uv_[6 * f], &uv_[6 * f + 6]);
		if (sources && sm.sourceFace.size() == nT)
			o.sourceFace.push_back(sm.sourceFace[f]);
		Vec3 n = normal(int32_t(f));
		const double a = 0.5 * n.Norm();
		area += a;
		if (devBound_[f] < 0) { // (as the source measured it)
			devArea += a * sm.stats.meanNormalDevDeg;
		} else if (a > 0) {
			n.Normalize();
			maxDev = std::max(maxDev, devBound_[f]);
			devArea += a * angleDeg(n, cone_[f].axis);
		}
		maxBound = std::max(maxBound, e_[f]);
		maxUv = std::max(maxUv, uvErr_[f]);
		out.bound.push_back(e_[f]);
		out.cone.push_back(cone_[f]);
		out.uvError.push_back(uvErr_[f]);
	}
	if (!o.cornerUV.empty()) { // (kept only where a corner's differ from its source corner's)
		bool own = false;
		for (size_t c = 0; c < o.sourceCorner.size() && !own; ++c)
			own = o.cornerUV[2 * c] != t_.UV[2 * size_t(o.sourceCorner[c])] ||
			      o.cornerUV[2 * c + 1] != t_.UV[2 * size_t(o.sourceCorner[c]) + 1];
		if (!own)
			release(o.cornerUV);
	}
	o.superfaceBound.assign(size_t(nextSf), 0.0f);
	for (size_t f = 0; f < nT; ++f)
		if (alive_[f]) {
			float &b = o.superfaceBound[size_t(sfId[size_t(find(int32_t(f)))])];
			b = std::max(b, std::nextafter(float(e_[f]), 3e38f));
		}
	// each input face: the triangle standing for it (its source triangle, or where that went)
	auto alive = [&](int32_t f) {
		while (f >= 0 && !alive_[size_t(f)])
			f = fwd_[size_t(f)];
		return f;
	};
	std::vector<int32_t> firstOf; // (a source of superfaces only: each one's first triangle)
	if (src_.inputTri.empty()) {
		for (size_t f = 0; f < sm.superface.size(); ++f) {
			const size_t s = size_t(sm.superface[f]);
			if (s >= firstOf.size())
				firstOf.resize(s + 1, -1);
			if (firstOf[s] < 0)
				firstOf[s] = int32_t(f);
		}
	}
	const size_t nIn = sm.inputSuperface.size();
	o.inputSuperface.assign(nIn, -1);
	out.inputTri.assign(nIn, -1);
	for (size_t i = 0; i < nIn; ++i) {
		int32_t tri = -1;
		if (!src_.inputTri.empty()) {
			tri = src_.inputTri[i];
		} else {
			const int32_t s = sm.inputSuperface[i];
			tri = s >= 0 && size_t(s) < firstOf.size() ? firstOf[size_t(s)] : -1;
		}
		tri = tri >= 0 ? alive(tri) : -1;
		if (tri < 0)
			continue;
		out.inputTri[i] = triId[size_t(tri)];
		o.inputSuperface[i] = sfId[size_t(find(tri))];
	}
	if (lim_.keepSuperfaces) // (an input face's superface, as merged: -1 if it has no triangle)
		for (size_t i = 0; i < nIn; ++i) {
			const int32_t x = sm.inputSuperface[i];
			if (x >= 0) {
				int32_t r = x;
				while (sfUf_[size_t(r)] != r)
					r = sfUf_[size_t(r)];
				o.inputSuperface[i] = sfId[size_t(r)];
			}
		}
	LevelStats &st = o.stats;
	st.faces = o.triangles.size() / 3;
	st.vertices = size_t(nextV);
	st.superfaces = size_t(nextSf);
	st.maxNormalDevDeg = std::max(sm.stats.maxNormalDevDeg, maxDev);
	st.meanNormalDevDeg = area > 0 ? devArea / area : 0;
	st.unmeasuredFaces = 0;
	st.distanceBound = src_.unbounded ? -1 : maxBound; // (a source of unknown distance: none)
	out.unbounded = src_.unbounded;
	st.placedVertices = placed;
	st.maxPlacement = maxMove;
	st.collapses = collapses_;
	st.maxTexError = t_.UV ? double(maxUv) : -1;
	report.collapses = collapses_;
	report.maxTexError = st.maxTexError;
	report.texErrorLimit = std::max(lim_.texError, st.maxTexError); // (a soft one gave way)
}

} // namespace

void inputSource(const Topology &t, const MeshView &mesh, CollapseSource &out)
{
	out.clear();
	LevelMesh &o = out.mesh;
	o.positions.assign(t.P, t.P + 3 * t.nV);
	o.sourceVertex.resize(t.nV);
	for (size_t v = 0; v < t.nV; ++v)
		o.sourceVertex[v] = int32_t(v);
	const bool sources = t.wantSources || mesh.faceKey || mesh.cornerKey || t.UV;
	out.inputTri.assign(t.nF, -1);
	size_t n = 0;
	for (size_t f = 0; f < t.nF; ++f)
		n += !t.faceDropped[f];
	o.triangles.reserve(3 * n);
	o.superface.reserve(n);
	o.borderEdges.assign(n, 7);
	out.bound.assign(n, 0.0);
	out.cone.reserve(n);
	if (sources) {
		o.sourceCorner.reserve(3 * n);
		o.sourceFace.reserve(n);
	}
	int32_t next = 0;
	for (size_t f = 0; f < t.nF; ++f) {
		if (t.faceDropped[f])
			continue;
		out.inputTri[f] = next;
		o.superface.push_back(next++);
		for (size_t k = 0; k < 3; ++k) {
			o.triangles.push_back(t.T[3 * f + k]);
			if (sources)
				o.sourceCorner.push_back(int32_t(3 * f + k));
		}
		if (sources)
			o.sourceFace.push_back(int32_t(f));
		out.cone.push_back({t.faceNormal[f], 0.0});
	}
	o.inputSuperface = out.inputTri;
	out.uvError.assign(n, 0.0f);
	o.stats.faces = n;
	o.stats.superfaces = n;
	o.stats.distanceBound = 0;
}

bool reduceLevel(const Topology &t, const MeshView &mesh, const CollapseSource &src,
                 const ReduceLimits &lim, size_t threads, CollapseSource &out, ReduceReport &report)
{
	Reducer r(t, mesh, src, lim, threads);
	return r.run(out, report);
}

} // namespace detail
} // namespace gausslod
