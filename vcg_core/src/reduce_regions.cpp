// Edge collapses (reduce.h, docs/DESIGN.md 57): a large reduction's first collapses by regions,
// apart from each other and in parallel, before the whole mesh's queue (reduce.cpp) takes over.
#include "reduce_internal.h"

#include <atomic>

namespace gausslod {
namespace detail {
namespace collapse {

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
	// region, in their order, then the edges not held before; counted first, with room for an
	// eighth more (a region drops its stale entries when full, a small array), and reserved on
	// this thread: reserved on the workers, glibc kept them in the workers' arenas once freed
	// (the certified 1M budget chain's peak RSS 6 % higher with the same peak heap)
	std::vector<size_t> count(nR, 0);
	for (const Lane &B : before)
		for (const Entry &e : B.heap.entries())
			if (deep_[size_t(e.a)] && deep_[size_t(e.b)])
				++count[region[size_t(e.a)]];
	std::vector<std::vector<Entry>> seed(nR);
	auto higher = [&](int32_t v, std::vector<int32_t> &nb) { // (the edges not held before)
		higherNeighbours(v, nb, [&](int32_t w) {
			return deep_[size_t(w)] && !(!held.empty() && held[size_t(v)] && held[size_t(w)]);
		});
	};
	std::atomic<size_t> next(0);
	onWorkers(std::min(threads_, nR), [&](size_t) {
		std::vector<int32_t> nb;
		for (size_t r; (r = next++) < nR;)
			for (const int32_t v : verts[r])
				if (deep_[size_t(v)])
					higher(v, nb), count[r] += nb.size();
	});
	for (size_t r = 0; r < nR; ++r) // (on this thread: see above)
		seed[r].reserve(count[r] + count[r] / 8 + 16);
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

void Reducer::shareBudget(std::vector<Lane> &lanes, const std::vector<uint16_t> &region)
{
	// each region's share of a budget: of the triangles its collapses can remove (two of their
	// vertices deep), what the budget removes of all
	const size_t nT = T_.size() / 3;
	const double remove = 1.0 - double(lim_.faces) / double(live_);
	std::vector<size_t> own(lanes.size(), 0);
	const uint8_t *d = deep_.data();
	for (size_t f = 0; f < nT; ++f)
		if (alive_[f] && d[T_[3 * f]] + d[T_[3 * f + 1]] + d[T_[3 * f + 2]] >= 2)
			++own[region[size_t(T_[3 * f])]];
	for (size_t r = 0; r < lanes.size(); ++r)
		lanes[r].cap = size_t(std::floor(double(own[r]) * remove / 2));
}

double Reducer::runToGoal(std::vector<Lane> &lanes)
{
	size_t share = 0, waiting = 0;
	for (const Lane &L : lanes)
		share += L.cap, waiting += L.heap.size();
	const size_t goal = size_t(kRegionsGoal * double(share));
	// (the first limit: the cost key at half the goal among all waiting)
	double limit = 0;
	{
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
	}
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
		// (the next limit: where the last two rounds, in the logarithm of the limit, say the goal
		// is; at most a quarter more, at least a fiftieth)
		double next = limit * 1.25;
		if (prevLimit > 0 && limit > prevLimit && made > prevMade) {
			const double slope = double(made - prevMade) / std::log(limit / prevLimit);
			next = std::min(next, limit * std::exp(double(goal - made) / slope));
		}
		prevLimit = limit, prevMade = made;
		limit = std::max(std::max(next, limit * 1.02), least);
	}
	return limit;
}

bool Reducer::regionsFirst()
{
	const size_t nV = P_.size();
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
		if (budget)
			shareBudget(lanes, region);
		release(region);
		if (pass == 0 && budget)
			limit = runToGoal(lanes);
		else
			runRegions(lanes, limit); // (pass 2: up to the limit pass 1 reached)
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
		}
	});
}

} // namespace collapse
} // namespace detail
} // namespace gausslod
