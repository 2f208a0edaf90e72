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

#include <atomic>

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
		nb.clear();
		for (int32_t c = head_[v]; c >= 0; c = next_[size_t(c)])
			if (alive_[size_t(heFace(c))])
				for (const int32_t w : {T_[size_t(heNext(c))], T_[size_t(hePrev(c))]})
					if (w > int32_t(v) && !(skipDeep && deep_[v] && deep_[size_t(w)]))
						nb.push_back(w);
		std::sort(nb.begin(), nb.end());
		nb.erase(std::unique(nb.begin(), nb.end()), nb.end());
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

// DESIGN 57: the first collapses of a large reduction by regions, apart from each other and in
// parallel: runs of vertices in Morton order, each with its own queue over the edges between its
// deep vertices (whose neighbours' neighbours are all in the region). A collapse between deep
// vertices reads and writes only its region's vertices, corners and triangles (and reads the
// triangles that touch another region, which no region changes), so the regions' collapses are
// the same whatever the threads and their order. They collapse up to a cost limit; a second pass,
// its Morton runs shifted, takes their queues and collapses up to the same limit where the first
// pass's borders were; the whole mesh's queue then takes over with the second pass's queues and
// the edges they did not hold: what the regions made is what one queue makes below that limit,
// but for the order along region borders.
// By a budget the limit grows by rounds until the regions have made kRegionsGoal of their share
// (what the budget removes of all, of the triangles they can remove): a limit so high that they
// reach their whole share cost 13 % in the certified distance of the 1M bumpy sphere's finest
// default level; by an error it is kRegionsErrorShare of it (at the error itself, the borders,
// collapsed last, kept 18 % more faces on a test sphere cut in small regions).
namespace {
constexpr double kRegionsGoal = 0.9;
constexpr double kRegionsErrorShare = 0.25;
constexpr double kRegionsShift = 0.37; // (of the box: no cut of pass 1's Morton runs where it was)
} // namespace

void Reducer::cutRegions(size_t nR, double shift, std::vector<uint16_t> &region,
                         std::vector<std::vector<int32_t>> &verts)
{
	// equal runs of the vertices in Morton order of their positions, shifted by `shift` of the
	// box (wrapped around): another shift puts the cuts elsewhere
	const size_t nV = P_.size(), nT = T_.size() / 3;
	Vec3 lo(HUGE_VAL, HUGE_VAL, HUGE_VAL), hi(-HUGE_VAL, -HUGE_VAL, -HUGE_VAL);
	for (const Vec3 &p : P_)
		for (int k = 0; k < 3; ++k)
			lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
	std::vector<uint64_t> order(nV);
	parallelRanges(nV, threads_, [&](size_t b, size_t e, size_t) {
		for (size_t v = b; v < e; ++v) {
			uint64_t code = 0;
			for (int k = 0; k < 3; ++k) {
				const double ext = hi[k] - lo[k];
				double x = ext > 0 ? (P_[v][k] - lo[k]) / ext + shift : 0.0;
				x -= std::floor(x);
				const uint64_t q = uint64_t(std::min(1023.0, std::max(0.0, x * 1024.0)));
				for (int bit = 0; bit < 10; ++bit)
					code |= (q >> bit & 1) << (3 * bit + k);
			}
			order[v] = code << 32 | v;
		}
	});
	std::sort(order.begin(), order.end());
	region.assign(nV, 0);
	verts.assign(nR, {});
	for (size_t r = 0; r < nR; ++r)
		for (size_t i = r * nV / nR; i < (r + 1) * nV / nR; ++i) {
			const int32_t v = int32_t(order[i] & 0xffffffffu);
			region[size_t(v)] = uint16_t(r);
			verts[r].push_back(v);
		}
	release(order);
	// inner: every triangle around it in its region; deep: every neighbour inner
	std::vector<uint8_t> inner(nV, 1);
	for (size_t f = 0; f < nT; ++f) {
		const size_t a = size_t(T_[3 * f]), b = size_t(T_[3 * f + 1]), c = size_t(T_[3 * f + 2]);
		if (alive_[f] && (region[a] != region[b] || region[a] != region[c]))
			inner[a] = inner[b] = inner[c] = 0;
	}
	deep_ = inner;
	for (size_t f = 0; f < nT; ++f) {
		const size_t a = size_t(T_[3 * f]), b = size_t(T_[3 * f + 1]), c = size_t(T_[3 * f + 2]);
		if (alive_[f] && !(inner[a] && inner[b] && inner[c]))
			deep_[a] = deep_[b] = deep_[c] = 0;
	}
}

void Reducer::seedRegions(std::vector<Lane> &lanes, const std::vector<uint16_t> &region,
                          const std::vector<std::vector<int32_t>> &verts, std::vector<Lane> &before,
                          const std::vector<uint8_t> &held)
{
	const size_t nR = lanes.size();
	// the queues of the regions before, for the edges that stay between deep vertices of one
	// region, in their order; counted first, with room for an eighth more (a region drops its
	// stale entries when full, a small array)
	std::vector<size_t> routed(nR, 0);
	for (const Lane &B : before)
		for (const Entry &e : B.heap.entries())
			if (deep_[size_t(e.a)] && deep_[size_t(e.b)])
				++routed[region[size_t(e.a)]];
	std::vector<std::vector<Entry>> seed(nR);
	auto higher = [&](int32_t v, std::vector<int32_t> &nb) { // (the edges not held before)
		nb.clear();
		for (int32_t c = head_[size_t(v)]; c >= 0; c = next_[size_t(c)])
			if (alive_[size_t(heFace(c))])
				for (const int32_t w : {T_[size_t(heNext(c))], T_[size_t(hePrev(c))]})
					if (w > v && deep_[size_t(w)] &&
					    !(!held.empty() && held[size_t(v)] && held[size_t(w)]))
						nb.push_back(w);
		std::sort(nb.begin(), nb.end());
		nb.erase(std::unique(nb.begin(), nb.end()), nb.end());
	};
	std::atomic<size_t> next(0);
	onWorkers(std::min(threads_, nR), [&](size_t) {
		std::vector<int32_t> nb;
		for (size_t r; (r = next++) < nR;) {
			size_t n = routed[r];
			for (const int32_t v : verts[r])
				if (deep_[size_t(v)])
					higher(v, nb), n += nb.size();
			seed[r].reserve(n + n / 8 + 16);
		}
	});
	for (Lane &B : before) {
		for (const Entry &e : B.heap.entries())
			if (deep_[size_t(e.a)] && deep_[size_t(e.b)])
				seed[region[size_t(e.a)]].push_back(e);
		B.heap.release();
	}
	next = 0;
	onWorkers(std::min(threads_, nR), [&](size_t) {
		std::vector<int32_t> nb;
		for (size_t r; (r = next++) < nR;) {
			for (const int32_t v : verts[r]) {
				if (!deep_[size_t(v)])
					continue;
				higher(v, nb);
				for (const int32_t w : nb) {
					Entry e;
					if (bestOp(v, w, 0, e))
						seed[r].push_back(e);
				}
			}
			lanes[r].heap.assign(std::move(seed[r]));
			lanes[r].deep = true;
		}
	});
}

void Reducer::foldRegions(std::vector<Lane> &lanes)
{
	// (their queues without their stale entries, fitted; their joins in the regions' order: the
	// same roots for any threads)
	std::atomic<size_t> next(0);
	onWorkers(std::min(threads_, lanes.size()), [&](size_t) {
		for (size_t r; (r = next++) < lanes.size();) {
			lanes[r].heap.drop([this](const Entry &x) { return stale(x); });
			lanes[r].heap.fit();
		}
	});
	for (Lane &L : lanes) {
		live_ -= L.dead, collapses_ += L.made, regionMade_ += L.made;
		L.dead = L.made = 0;
		for (size_t i = 0; i + 1 < L.joins.size(); i += 2) {
			const int32_t a = rootOf(L.joins[i]), b = rootOf(L.joins[i + 1]);
			if (a != b)
				sfUf_[size_t(b)] = a;
		}
		release(L.joins);
	}
}

bool Reducer::regionsFirst()
{
	const size_t nV = P_.size(), nT = T_.size() / 3;
	const size_t nR =
	    lim_.regionVertices > 0 ? std::min<size_t>(nV / lim_.regionVertices, 4096) : 0;
	const bool budget = lim_.faces > 0;
	if (nR < 2 || (budget && live_ <= lim_.faces))
		return false;
	std::vector<Lane> lanes;
	std::vector<uint8_t> held; // (pass 2: the deep vertices of pass 1)
	double limit = budget ? 0.0 : lim_.bound * kRegionsErrorShare;
	for (int pass = 0; pass < 2 && (!budget || live_ > lim_.faces); ++pass) {
		std::vector<uint16_t> region;
		std::vector<std::vector<int32_t>> verts;
		cutRegions(nR, pass == 0 ? 0.0 : kRegionsShift, region, verts);
		std::vector<Lane> next(nR);
		seedRegions(next, region, verts, lanes, held);
		lanes = std::move(next);
		release(verts);
		// each region's share of a budget: of the triangles its collapses can remove (two of
		// their vertices deep), what the budget removes of all
		if (budget) {
			const double remove = 1.0 - double(lim_.faces) / double(live_);
			std::vector<size_t> own(nR, 0);
			for (size_t f = 0; f < nT; ++f)
				if (alive_[f] && deep_[size_t(T_[3 * f])] + deep_[size_t(T_[3 * f + 1])] +
				                         deep_[size_t(T_[3 * f + 2])] >=
				                     2)
					++own[region[size_t(T_[3 * f])]];
			for (size_t r = 0; r < nR; ++r)
				lanes[r].cap = size_t(std::floor(double(own[r]) * remove / 2));
		}
		release(region);
		if (pass == 1 || !budget) {
			runRegions(lanes, limit); // (pass 2: up to the limit pass 1 reached)
		} else {
			size_t share = 0, waiting = 0;
			for (const Lane &L : lanes)
				share += L.cap, waiting += L.heap.size();
			const size_t goal = size_t(kRegionsGoal * double(share));
			// (the first limit: the cost key at half the goal among all waiting)
			std::vector<double> keys;
			keys.reserve(waiting);
			for (const Lane &L : lanes)
				for (const Entry &e : L.heap.entries())
					keys.push_back(e.cost);
			if (!keys.empty()) {
				const size_t at = std::min(keys.size() - 1, goal / 2);
				std::nth_element(keys.begin(), keys.begin() + ptrdiff_t(at), keys.end());
				limit = keys[at];
			}
			release(keys);
			double prevLimit = 0;
			size_t prevMade = 0;
			for (int round = 0; round < 64; ++round) {
				runRegions(lanes, limit);
				size_t made = 0;
				double least = HUGE_VAL;
				for (const Lane &L : lanes) {
					made += L.made;
					if (L.made < L.cap && !L.heap.empty())
						least = std::min(least, L.heap.top().cost);
				}
				if (made >= goal || least == HUGE_VAL)
					break;
				// (the next limit: where the last two rounds, in the logarithm of the limit,
				// say the goal is; at most a quarter more, at least a fiftieth)
				double nextLimit = limit * 1.25;
				if (prevLimit > 0 && limit > prevLimit && made > prevMade) {
					const double slope = double(made - prevMade) / std::log(limit / prevLimit);
					nextLimit = std::min(nextLimit, limit * std::exp(double(goal - made) / slope));
				}
				prevLimit = limit, prevMade = made;
				limit = std::max(std::max(nextLimit, limit * 1.02), least);
			}
		}
		foldRegions(lanes);
		regions_ = int(nR);
		held = deep_;
	}
	release(held);
	seedQueue(&lanes); // (the edges not between deep vertices of pass 2's regions)
	release(deep_);
	return true;
}

void Reducer::runRegions(std::vector<Lane> &lanes, double limit)
{
	std::atomic<size_t> nextRegion(0);
	onWorkers(std::min(threads_, lanes.size()), [&](size_t) {
		Plan pl;
		for (size_t r; (r = nextRegion++) < lanes.size();) {
			Lane &L = lanes[r];
			L.limit = limit;
			while (L.made < L.cap && !L.heap.empty() && L.heap.top().cost <= limit) {
				const Entry top = L.heap.top();
				L.heap.pop();
				tryCollapse(L, top, pl);
			}
			L.scratch.shrink_to_fit();
		}
	});
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
