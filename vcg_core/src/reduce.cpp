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
//
// This file: the driver, the queue and the collapses' costs, the loop's hot calls in one
// translation unit; reduce_internal.h names the other pieces.
#include "reduce_internal.h"

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

namespace collapse {

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
			e = {cost(a, b, g, bestQ), a,    b, stamp_[size_t(a)] + stamp_[size_t(b)],
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

void Reducer::queue(Lane &L, const Entry &e)
{
	// (a full queue first drops its stale entries, an eighth to two fifths of it on the bumpy
	// spheres, and grows by a quarter only if it is still nearly full: grown by doubling, the old
	// and new arrays at once were a third of a collapse level's peak)
	CollapseQueue &h = L.heap;
	if (h.full() && !h.empty()) {
		h.drop([this](const Entry &x) { return stale(x); });
		if (h.size() > h.capacity() / 8 * 7)
			h.reserve(h.capacity() + h.capacity() / 4);
	}
	h.push(e);
}

void Reducer::pushEdges(Lane &L, int32_t v)
{
	std::vector<int32_t> &s = L.scratch;
	s.clear();
	for (int32_t c = head_[size_t(v)]; c >= 0; c = next_[size_t(c)])
		if (alive_[size_t(heFace(c))]) {
			s.push_back(T_[size_t(heNext(c))]);
			s.push_back(T_[size_t(hePrev(c))]);
		}
	std::sort(s.begin(), s.end());
	s.erase(std::unique(s.begin(), s.end()), s.end());
	for (int32_t w : s) {
		Entry e;
		if (inLane(L, v, w) && bestOp(std::min(v, w), std::max(v, w), 0, e))
			queue(L, e);
	}
}

void Reducer::seedQueue(std::vector<Lane> *regions)
{
	// every edge's best operation (each vertex's edges to higher vertices, in parallel), into one
	// array sized by a first count: per-chunk arrays and their concatenation were two copies of
	// the queue, a collapse level's peak. After the regions (DESIGN 57): their queues, then the
	// edges they did not hold (those with an end that is not deep).
	const size_t nV = P_.size();
	const size_t chunk = 4096, nChunks = (nV + chunk - 1) / chunk;
	const bool skipDeep = regions != nullptr;
	auto higher = [&](size_t v, std::vector<int32_t> &nb) {
		higherNeighbours(int32_t(v), nb,
		                 [&](int32_t w) { return !(skipDeep && deep_[v] && deep_[size_t(w)]); });
	};
	size_t carried = 0;
	if (regions)
		for (const Lane &L : *regions)
			carried += L.heap.size();
	std::vector<size_t> start(nChunks + 1, 0), got(nChunks, 0);
	parallelRanges(nChunks, threads_, [&](size_t cb, size_t ce, size_t) {
		std::vector<int32_t> nb;
		for (size_t k = cb; k < ce; ++k)
			for (size_t v = k * chunk; v < std::min(nV, (k + 1) * chunk); ++v) {
				higher(v, nb);
				start[k + 1] += nb.size();
			}
	});
	start[0] = carried;
	for (size_t k = 0; k < nChunks; ++k)
		start[k + 1] += start[k];
	std::vector<Entry> all; // (room for half as many again: the queue then seldom grows, queue())
	all.reserve(start[nChunks] + start[nChunks] / 2 + 64);
	if (regions)
		for (Lane &L : *regions) { // (each region's queue, freed as it is taken)
			all.insert(all.end(), L.heap.entries().begin(), L.heap.entries().end());
			L.heap.release();
		}
	all.resize(start[nChunks]);
	parallelRanges(nChunks, threads_, [&](size_t cb, size_t ce, size_t) {
		std::vector<int32_t> nb;
		for (size_t k = cb; k < ce; ++k)
			for (size_t v = k * chunk; v < std::min(nV, (k + 1) * chunk); ++v) {
				higher(v, nb);
				for (int32_t w : nb) {
					Entry e;
					if (bestOp(int32_t(v), w, 0, e))
						all[start[k] + got[k]++] = e;
				}
			}
	});
	size_t n = carried; // (the chunks' entries closed up, in order)
	for (size_t k = 0; k < nChunks; ++k) {
		std::copy(all.begin() + ptrdiff_t(start[k]), all.begin() + ptrdiff_t(start[k] + got[k]),
		          all.begin() + ptrdiff_t(n));
		n += got[k];
	}
	all.resize(n);
	main_.heap.assign(std::move(all));
}

void Reducer::tryCollapse(Lane &L, Entry top, Plan &pl)
{
	if (stale(top))
		return;
	Vec3 pos;
	const double q = opCost(top.a, top.b, top.op, pos);
	// (a key from the lower bound: first the collapse's own gap, the cheaper proof; a collapse
	// that costs more than the next one, or than the lane's limit, goes back in line with its
	// cost)
	const CollapseQueue &heap = L.heap;
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
		if (exact > L.limit || (!heap.empty() && exact > heap.top().cost * (1 + 1e-9))) {
			top.cost = exact;
			top.tried |= kExactKey;
			queue(L, top);
			return;
		}
	}
	if (!planned || !check(pl)) {
		Entry e;
		if (bestOp(top.a, top.b, uint8_t((top.tried & ~kExactKey) | 1u << top.op), e))
			queue(L, e);
		else
			blocked_[size_t(top.a)] = blocked_[size_t(top.b)] = 1;
		return;
	}
	// (the key is a lower bound of the cost, or the cost when the neighbourhood was as it was: a
	// collapse that now costs more than the next one goes back in line)
	double g = 0;
	for (int i = 0; i < pl.pc.nNew; ++i)
		g = std::max(g, pl.proof.gap[i]);
	if (!uv_.empty())
		g += textureShift(pl);
	const double now = cost(top.a, top.b, g, q);
	if (now > L.limit ||
	    (now > top.cost * (1 + 1e-9) && !heap.empty() && now > heap.top().cost * (1 + 1e-9))) {
		top.cost = now;
		top.tried |= kExactKey;
		queue(L, top);
		return;
	}
	if (checkFacing_ && !facesInput(pl)) {
		blocked_[size_t(top.a)] = blocked_[size_t(top.b)] = 1;
		return;
	}
	apply(L, pl);
	++L.made;
}

bool Reducer::run(CollapseSource &out, ReduceReport &report)
{
	setUp();
	const bool budget = lim_.faces > 0;
	auto more = [&] { return !budget || live_ - main_.dead > lim_.faces; };
	for (int round = 0; round < 32 && more(); ++round) {
		std::fill(blocked_.begin(), blocked_.end(), 0);
		const size_t before = collapses_ + main_.made;
		if (!(round == 0 && regionsFirst()))
			seedQueue();
		Plan pl;
		while (more() && !main_.heap.empty()) {
			const Entry top = main_.heap.top();
			main_.heap.pop();
			tryCollapse(main_, top, pl);
		}
		if (!budget && round >= 1)
			break; // (by error: what the first rounds refused stays refused, near enough)
		if (collapses_ + main_.made == before) {
			// (stuck short of a face budget: only a true minimum may stop it, so the thin-part
			// test and the turn-over guard give way; the proven bound still says what the level
			// is)
			if (!budget || !checkFacing_)
				break;
			checkFacing_ = false;
		}
	}
	live_ -= main_.dead, collapses_ += main_.made;
	main_ = Lane(); // (the loop's own arrays: not needed to write the level)
	release(stamp_), release(blocked_);
	write(out, report);
	return !more() || !budget;
}

} // namespace collapse

bool reduceLevel(const Topology &t, const MeshView &mesh, const CollapseSource &src,
                 const ReduceLimits &lim, size_t threads, CollapseSource &out, ReduceReport &report)
{
	collapse::Reducer r(t, mesh, src, lim, threads);
	return r.run(out, report);
}

bool reduceLevel(const Topology &t, const MeshView &mesh, CollapseSource &&src,
                 const ReduceLimits &lim, size_t threads, CollapseSource &out, ReduceReport &report)
{
	collapse::Reducer r(t, mesh, src, lim, threads, &src);
	const bool got = r.run(out, report);
	src.clear();
	return got;
}

} // namespace detail
} // namespace gausslod
