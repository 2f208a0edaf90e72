// The edge-collapse reducer's pieces (reduce.h), shared by its files: the driver, the queue and
// the collapses' costs (reduce.cpp, one translation unit for the loop's hot calls); the vertex
// kinds, rings and the patches a collapse replaces (reduce_plan.cpp); a planned collapse's checks
// and texture (reduce_check.cpp); making it (reduce_apply.cpp); the first collapses by regions
// (reduce_regions.cpp); the start (reduce_setup.cpp) and the level written out (reduce_write.cpp).
#pragma once

#include "reduce.h"
#include "reduce_patch.h"

#include <algorithm>
#include <vector>

namespace gausslod {
namespace detail {
namespace collapse {

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

// (s: the sum of a's and b's stamps when it was costed; stamps only grow, so an equal sum means
// neither end has moved: 24 bytes an entry, not 32)
struct Entry {
	double cost;
	int32_t a, b;
	uint32_t s;
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

static_assert(sizeof(Entry) == 24, "a queue entry: 24 bytes");

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
	/// Whether the next push grows the queue's storage.
	bool full() const { return e_.size() == e_.capacity(); }
	/// Drops the entries with dead(entry) and restores the heap: the others pop in `before`'s order
	/// as they did (only entries equal in cost, a, b and op could change places).
	template <class Dead>
	void drop(Dead dead)
	{
		e_.erase(std::remove_if(e_.begin(), e_.end(), dead), e_.end());
		for (size_t i = e_.size() / 4 + 1; i-- > 0;)
			if (i < e_.size())
				down(i, e_[i]);
	}
	size_t size() const { return e_.size(); }
	size_t capacity() const { return e_.capacity(); }
	void reserve(size_t n) { e_.reserve(n); }
	void release() { detail::release(e_); }
	void fit() { e_.shrink_to_fit(); }
	const std::vector<Entry> &entries() const { return e_; } ///< (in heap order)

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

// Where collapses are made from one queue (DESIGN 57): the whole mesh, or one region of it while
// the regions' collapses run apart from each other. A collapse waits while it costs over `limit`;
// a region stops at `cap` collapses.
struct Lane {
	CollapseQueue heap;
	std::vector<int32_t> scratch;
	size_t dead = 0, made = 0; ///< triangles removed, collapses made
	size_t cap = SIZE_MAX;
	double limit = HUGE_VAL;
	bool deep = false;          ///< a region's lane: only edges between its deep vertices (deep_)
	std::vector<int32_t> joins; ///< (keepSuperfaces, a region: source superfaces joined, pairs)
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
	Vec3 normal[PatchCase::kMaxTris]; // (per new triangle: its unit normal)
	double bound[PatchCase::kMaxTris];
	double uvBound[PatchCase::kMaxTris];
};

// The corner of the other live triangle on the edge a -> b of corner c (its corner at b, edge
// b -> a); -1 if there is none, -2 if the edge is not between exactly two consistently oriented
// triangles.
inline int32_t twinOf(const std::vector<int32_t> &T, const std::vector<int32_t> &head,
                      const std::vector<int32_t> &next, const std::vector<uint8_t> &alive,
                      int32_t c)
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

// One reduction: the level as it is collapsed, in flat arrays indexed by vertex, corner and
// triangle.
class Reducer {
public:
	/// With `own` (= &src), the reduction takes the source's arrays it copies, not needed to write
	/// the level: the source is not held twice.
	Reducer(const Topology &t, const MeshView &mesh, const CollapseSource &src,
	        const ReduceLimits &lim, size_t threads, CollapseSource *own = nullptr)
	    : t_(t), mesh_(mesh), src_(src), own_(own), lim_(lim), threads_(threads)
	{
	}
	bool run(CollapseSource &out, ReduceReport &report);

private:
	const Topology &t_;
	const MeshView &mesh_;
	const CollapseSource &src_;
	CollapseSource *const own_;
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
	Lane main_;                       // (the whole mesh's queue)
	size_t live_ = 0, collapses_ = 0; // (main_'s and the regions' added when they stop)
	size_t regionMade_ = 0;           // (of collapses_, by regions)
	int regions_ = 0;
	// (DESIGN 57: per vertex, 1 where it is deep in its region, its neighbours' neighbours all in
	// it: collapses between deep vertices of one region touch no other region's data)
	std::vector<uint8_t> deep_;
	// (seams and junctions move across charts where a face count is asked: their cost counts the
	// texture's shift, so the collapses along seams go first)
	bool checkFacing_ = true;
	bool keys_ = false, allowJunctions_ = lim_.faces > 0 && !lim_.keepSuperfaces;
	std::vector<float> uv_; // (with texture coordinates: 2 per corner)
	std::vector<int32_t> srcF_;

	Vec3 normal(int32_t f) const
	{
		const Vec3 &a = P_[size_t(T_[3 * f])], &b = P_[size_t(T_[3 * f + 1])],
		           &c = P_[size_t(T_[3 * f + 2])];
		return (b - a) ^ (c - a);
	}
	double slop() const { return 1e-12 * t_.diagonal; }
	int32_t superfaceOf(int32_t f) // (keepSuperfaces: the root of f's merged source superface)
	{
		return rootOf(sf_[size_t(f)]);
	}
	int32_t rootOf(int32_t x) // (the root of source superface x, as merged)
	{
		while (sfUf_[size_t(x)] != x)
			x = sfUf_[size_t(x)] = sfUf_[size_t(sfUf_[size_t(x)])];
		return x;
	}

	// the driver and the queue (reduce.cpp)
	void seedQueue(std::vector<Lane> *regions = nullptr);
	bool regionsFirst();
	void cutRegions(size_t nR, double shift, std::vector<uint16_t> &region,
	                std::vector<std::vector<int32_t>> &verts);
	void seedRegions(std::vector<Lane> &lanes, const std::vector<uint16_t> &region,
	                 const std::vector<std::vector<int32_t>> &verts, std::vector<Lane> &before,
	                 const std::vector<uint8_t> &held);
	void shareBudget(std::vector<Lane> &lanes, const std::vector<uint16_t> &region);
	double runToGoal(std::vector<Lane> &lanes); ///< (the limit it reached)
	void foldRegions(std::vector<Lane> &lanes);
	void runRegions(std::vector<Lane> &lanes, double limit);
	void tryCollapse(Lane &L, Entry top, Plan &pl);
	double opCost(int32_t a, int32_t b, int op, Vec3 &pos) const;
	bool allowed(int32_t a, int32_t b, int op, bool boundaryEdge, bool delimiterEdge) const;
	bool edgeFlags(int32_t a, int32_t b, bool &boundaryEdge, bool &delimiterEdge) const;
	bool bestOp(int32_t a, int32_t b, uint8_t tried, Entry &e) const;
	double gapLowerBound(int32_t a, int32_t b, int op, const Vec3 &pos) const;
	/// The cost of a collapse whose quadric error is q and whose largest gap is g.
	double cost(int32_t a, int32_t b, double g, double q) const;
	void pushEdges(Lane &L, int32_t v);
	/// v's neighbours w > v with keep(w), sorted, each once, into nb (the edges a seed costs).
	template <class Keep>
	void higherNeighbours(int32_t v, std::vector<int32_t> &nb, Keep keep) const
	{
		nb.clear();
		for (int32_t c = head_[size_t(v)]; c >= 0; c = next_[size_t(c)])
			if (alive_[size_t(heFace(c))])
				for (const int32_t w : {T_[size_t(heNext(c))], T_[size_t(hePrev(c))]})
					if (w > v && keep(w))
						nb.push_back(w);
		std::sort(nb.begin(), nb.end());
		nb.erase(std::unique(nb.begin(), nb.end()), nb.end());
	}
	/// Is the edge v-w one of L's (the whole mesh's, or in L's region between deep vertices)?
	bool inLane(const Lane &L, int32_t v, int32_t w) const
	{
		return !L.deep || (deep_[size_t(v)] && deep_[size_t(w)]);
	}
	/// An entry whose edge has lost a vertex or whose end moved since it was costed.
	bool stale(const Entry &e) const
	{
		return kind_[size_t(e.a)] == kGone || kind_[size_t(e.b)] == kGone ||
		       stamp_[size_t(e.a)] + stamp_[size_t(e.b)] != e.s;
	}
	void queue(Lane &L, const Entry &e);

	// vertex kinds, rings and the patches of collapses (reduce_plan.cpp)
	bool ring(int32_t v, Ring &r) const;
	void classify();
	void setDelimiter(int32_t c);
	uint8_t kindOf(int32_t v) const;
	bool planFull(int32_t u, int32_t v, const Vec3 &p, Plan &pl) const;
	bool planHalf(int32_t v, int32_t u, Plan &pl) const;
	bool plan(int32_t a, int32_t b, int op, const Vec3 &pos, Plan &pl) const;

	// a planned collapse's checks (reduce_check.cpp: kChecks, in order) and texture
	struct Check {
		const char *name;
		bool (Reducer::*passes)(Plan &pl) const;
	};
	static const Check kChecks[];
	bool check(Plan &pl) const; ///< every one of kChecks passes
	bool proven(Plan &pl) const;
	bool notDegenerate(Plan &pl) const;
	bool withinBound(Plan &pl) const;
	bool withinNormalLimit(Plan &pl) const;
	bool notTurned(Plan &pl) const;
	bool withinTexture(Plan &pl) const;
	bool facesInput(const Plan &pl) const;
	void wedges(Plan &pl) const;
	bool textureError(Plan &pl) const;
	double uvLocal(const Plan &pl) const;
	double textureShift(const Plan &pl) const;

	// making a collapse (reduce_apply.cpp)
	void apply(Lane &L, const Plan &pl);
	void fanCones(const Plan &pl, NormalCone *cones, double *dev) const;
	void removeDead(Lane &L, const Plan &pl);
	void rewriteFan(const Plan &pl, const NormalCone *cones, const double *dev);
	void relink(Lane &L, const Plan &pl);
	void prune(Lane &L, int32_t v);

	// the start (reduce_setup.cpp) and the level written out (reduce_write.cpp)
	template <class V>
	V take(V CollapseSource::*m) const // (a source's array: moved if owned)
	{
		return own_ ? std::move(own_->*m) : src_.*m;
	}
	template <class V>
	V take(V LevelMesh::*m) const
	{
		return own_ ? std::move(own_->mesh.*m) : src_.mesh.*m;
	}
	void setUp();
	void planeQuadrics();
	struct Written;
	void write(CollapseSource &out, ReduceReport &report);
	int32_t groupOf(Written &w, int32_t f);
	void groupTriangles(Written &w);
	void writeVertices(Written &w, CollapseSource &out) const;
	void writeTriangles(Written &w, CollapseSource &out);
	void writeInputFaces(Written &w, CollapseSource &out);
	void writeStats(const Written &w, CollapseSource &out, ReduceReport &report) const;
};

} // namespace collapse
} // namespace detail
} // namespace gausslod
