// 2.5 Generating models with multiple levels of detail: the superfaces of level i whose cells are
// siblings (children of one level i-1 cell) are merged by accretion, center-child seeds first,
// then border-child seeds growing into their 8-neighbourhood.
#include "engine.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <numeric>

namespace gausslod {
namespace detail {

namespace {

// Superface adjacency through 2-manifold edges, as CSR: each superface's neighbours ascending,
// once each (counted, filled, then each short list sorted and made unique in place).
void superfaceAdjacency(const Topology &t, const Partition &p, std::vector<int32_t> &start,
                        std::vector<int32_t> &adj)
{
	const size_t n = p.count();
	auto forCrossings = [&](auto fn) { // both directions of every adjacency
		for (size_t h = 0; h < t.twin.size(); ++h) {
			const int32_t tw = t.joinTwin(h);
			if (tw < int32_t(h))
				continue; // boundary (-1) or seen from the other side
			const int32_t a = p.label[h / 3], b = p.label[size_t(heFace(tw))];
			if (a != b)
				fn(a, b), fn(b, a);
		}
	};
	fillBuckets<int32_t>(
	    n, [&](auto emit) { forCrossings([&](int32_t a, int32_t b) { emit(size_t(a), b); }); },
	    start, adj);
	int32_t out = 0;
	for (size_t s = 0; s < n; ++s) {
		int32_t *b = adj.data() + start[s], *e = adj.data() + start[s + 1];
		std::sort(b, e);
		e = std::unique(b, e);
		int32_t *to = adj.data() + out; // (<= b: the lists only shrink)
		start[s] = out;
		if (to != b)
			std::copy(b, e, to);
		out += int32_t(e - b);
	}
	start[n] = out;
	adj.resize(size_t(out));
}

// Labels every face f with the group of its superface of `from`, group[from.label[f]], with the
// groups numbered canonically (by first face): in the order of their lowest superface
// of `from`, whose ids are ordered by first face. Reorders out.cell and out.origin (indexed by
// group) to match. `from` and `out` may be the same partition.
void relabelCanonical(const Partition &from, const std::vector<int32_t> &group, Partition &out)
{
	const size_t groups = out.cell.size();
	std::vector<int32_t> id(groups, -1);
	std::vector<CellKey> cell;
	std::vector<int8_t> origin;
	cell.reserve(groups), origin.reserve(groups);
	for (size_t s = 0; s < group.size(); ++s) {
		const size_t g = size_t(group[s]);
		if (id[g] < 0) {
			id[g] = int32_t(cell.size());
			cell.push_back(out.cell[g]), origin.push_back(out.origin[g]);
		}
	}
	out.cell.swap(cell), out.origin.swap(origin);
	out.label.resize(from.label.size());
	for (size_t f = 0; f < from.label.size(); ++f)
		out.label[f] = id[size_t(group[size_t(from.label[f])])];
}

// Sorts `ids` (ascending) stably by area[id], largest first: an LSD radix sort on the areas'
// bits (for doubles >= 0 their order), 11 bits a pass, skipping the digits all ids share.
void sortByAreaDescending(const std::vector<double> &area, std::vector<int32_t> &ids)
{
	constexpr int kBits = 11, kPasses = (64 + kBits - 1) / kBits;
	constexpr size_t kDigits = size_t(1) << kBits;
	const size_t n = ids.size();
	std::vector<uint64_t> key(n), key2(n);
	std::vector<int32_t> ids2(n);
	std::vector<uint32_t> count(kPasses * kDigits, 0u); // every pass's histogram, in one read
	for (size_t i = 0; i < n; ++i) {
		uint64_t bits;
		std::memcpy(&bits, &area[size_t(ids[i])], sizeof bits);
		key[i] = ~bits; // (larger areas: smaller keys)
		for (int p = 0; p < kPasses; ++p)
			++count[size_t(p) * kDigits + ((key[i] >> (p * kBits)) & (kDigits - 1))];
	}
	for (int p = 0; p < kPasses && n > 0; ++p) {
		const int shift = p * kBits;
		uint32_t *c = &count[size_t(p) * kDigits];
		if (c[(key[0] >> shift) & (kDigits - 1)] == n)
			continue; // one digit for all: the order stays
		uint32_t sum = 0;
		for (size_t d = 0; d < kDigits; ++d) {
			const uint32_t here = c[d];
			c[d] = sum, sum += here;
		}
		for (size_t i = 0; i < n; ++i) {
			const size_t to = c[(key[i] >> shift) & (kDigits - 1)]++;
			key2[to] = key[i], ids2[to] = ids[i];
		}
		key.swap(key2), ids.swap(ids2);
	}
}

// 2.5 The accretion of coarserPartition: groups of `fine`'s superfaces grown from seeds over the
// superface adjacency, each group a superface of `out` (its cell and origin pushed as it is
// made; group[s] = the group of superface s, -1 = none yet).
class Accretion {
public:
	Accretion(const Topology &t, const Partition &fine, Partition &out, int8_t grownOrigin)
	    : t_(t), fine_(fine), out_(out), grownOrigin_(grownOrigin), n_(fine.count()),
	      group_(n_, -1), members_(n_, 0), firstMember_(n_, -1)
	{
		superfaceAdjacency(t, fine, start_, adj_);
	}
	void centerSeeds();
	void borderSeeds();
	void finish();
	const std::vector<int32_t> &group() const { return group_; }

private:
	const Topology &t_;
	const Partition &fine_;
	Partition &out_;
	const int8_t grownOrigin_;
	const size_t n_;
	std::vector<int32_t> start_, adj_; ///< superfaceAdjacency
	std::vector<int32_t> group_;
	std::vector<int32_t> members_, firstMember_; ///< per group
	std::vector<int32_t> queue_;

	// Grows the superface seeded at `seed`, absorbing adjacent unassigned superfaces accepted by
	// `accepts` (breadth first, in adjacency order: deterministic).
	template <class Accepts>
	void grow(int32_t seed, Accepts accepts)
	{
		const int32_t g = int32_t(out_.cell.size());
		out_.cell.push_back(parentKey(fine_.cell[size_t(seed)]));
		out_.origin.push_back(grownOrigin_);
		group_[size_t(seed)] = g;
		firstMember_[size_t(g)] = seed;
		members_[size_t(g)] = 1;
		queue_.assign(1, seed);
		for (size_t q = 0; q < queue_.size(); ++q) {
			const int32_t s = queue_[q];
			for (int32_t i = start_[size_t(s)]; i < start_[size_t(s) + 1]; ++i) {
				const int32_t w = adj_[size_t(i)];
				if (group_[size_t(w)] >= 0 || fine_.cell[size_t(w)] == kInvalidCell ||
				    !accepts(fine_.cell[size_t(w)]))
					continue;
				group_[size_t(w)] = g;
				++members_[size_t(g)];
				queue_.push_back(w);
			}
		}
	}
	void growBorderSeed(int32_t s, int m);
};

// (1) seeds in center children; they absorb superfaces of their brother cells
void Accretion::centerSeeds()
{
	for (size_t s = 0; s < n_; ++s) {
		const CellKey key = fine_.cell[s];
		if (group_[s] >= 0 || key == kInvalidCell || !isCenterChild(unpackCell(key)))
			continue;
		const CellKey parent = parentKey(key);
		grow(int32_t(s), [&](CellKey c) { return parentKey(c) == parent; });
	}
}

// Border seed s absorbs the superfaces whose cells are in its cell's 8-neighbourhood (which may
// cross into a neighbouring parent); m = meshNum(fine.level).
void Accretion::growBorderSeed(int32_t s, int m)
{
	bool open = false; // any neighbour left to absorb? (else skip the neighbourhood)
	for (int32_t i = start_[size_t(s)]; i < start_[size_t(s) + 1] && !open; ++i)
		open = group_[size_t(adj_[size_t(i)])] < 0 &&
		       fine_.cell[size_t(adj_[size_t(i)])] != kInvalidCell;
	if (!open) {
		grow(s, [](CellKey) { return false; });
		return;
	}
	const Cell c = unpackCell(fine_.cell[size_t(s)]);
	if (c.i > 0 && c.j > 0 && c.i < m - 1 && c.j < m - 1) { // inside its cube face
		grow(s, [&](CellKey w) {
			const Cell d = unpackCell(w);
			return d.face == c.face && std::abs(d.i - c.i) <= 1 && std::abs(d.j - c.j) <= 1;
		});
		return;
	}
	Cell nb[8];
	const int cnt = cellNeighbours(c, fine_.level, nb);
	CellKey keys[9];
	keys[0] = packCell(c);
	for (int k = 0; k < cnt; ++k)
		keys[k + 1] = packCell(nb[k]);
	grow(s, [&](CellKey w) { return std::find(keys, keys + cnt + 1, w) != keys + cnt + 1; });
}

// (2) seeds in border children, largest first; they absorb superfaces whose cells are in the
// seed cell's 8-neighbourhood (which may cross into a neighbouring parent)
void Accretion::borderSeeds()
{
	std::vector<double> area(n_, 0.0);
	for (size_t f = 0; f < t_.nF; ++f)
		area[size_t(fine_.label[f])] += t_.faceArea[f];
	std::vector<int32_t> order; // largest first, then by id
	for (size_t s = 0; s < n_; ++s)
		if (group_[s] < 0 && fine_.cell[s] != kInvalidCell)
			order.push_back(int32_t(s));
	sortByAreaDescending(area, order);
	release(area);
	const int m = meshNum(fine_.level);
	for (const int32_t s : order)
		if (group_[size_t(s)] < 0)
			growBorderSeed(s, m);
}

void Accretion::finish()
{
	// frozen superfaces (invalid input faces) stay alone
	for (size_t s = 0; s < n_; ++s)
		if (group_[s] < 0) {
			group_[s] = int32_t(out_.cell.size());
			out_.cell.push_back(kInvalidCell);
			out_.origin.push_back(-1);
		}
	// (3) a superface made of one finer superface is that superface: keep its origin so that a
	// fallback split goes straight to its own children
	for (size_t g = 0; g < out_.cell.size(); ++g)
		if (members_[g] == 1 && firstMember_[g] >= 0)
			out_.origin[g] = fine_.origin[size_t(firstMember_[g])];
}

} // namespace

void coarserPartition(const Topology &t, const Partition &fine, Partition &out, int8_t grownOrigin)
{
	out.level = fine.level - 1;
	out.cell.clear();
	out.origin.clear();
	Accretion acc(t, fine, out, grownOrigin);
	acc.centerSeeds();
	acc.borderSeeds();
	acc.finish();
	relabelCanonical(fine, acc.group(), out);
}

namespace {

double acrossHalfAngle(double boundDeg) { return 0.5 * boundDeg * 3.14159265358979323846 / 180.0; }

// mergeAcrossCells' tests on the nodes: may a superface (cell, mean normal, cone radius) join a
// union at all; may two adjacent ones be tried (their cones fit in one of half-angle `limit`;
// d = the dot product of their means)?
bool acrossMergeable(CellKey cell, const Vec3 &mean, double radius, double limit)
{
	return cell != kInvalidCell && mean.Norm() > 0 && radius <= 2 * limit;
}
bool acrossPair(const Vec3 &ma, double ra, const Vec3 &mb, double rb, double limit,
                double cos2Limit, double &d)
{
	const double used = ra + rb;
	if (used > 2 * limit)
		return false;
	d = ma.dot(mb);
	return d >= (used > 0 ? std::cos(2 * limit - used) : cos2Limit) - 1e-15;
}

} // namespace

std::vector<std::pair<int32_t, int32_t>> superfacePairs(const std::vector<int32_t> &triangles,
                                                        const std::vector<int32_t> &superface)
{
	struct Edge {
		int32_t a, b, sf;
		bool operator<(const Edge &o) const
		{
			return a != o.a ? a < o.a : b != o.b ? b < o.b : sf < o.sf;
		}
	};
	std::vector<Edge> edges;
	edges.reserve(triangles.size());
	for (size_t k = 0; k < superface.size(); ++k)
		for (size_t c = 0; c < 3; ++c) {
			const int32_t a = triangles[3 * k + c], b = triangles[3 * k + (c + 1) % 3];
			edges.push_back(Edge{std::min(a, b), std::max(a, b), superface[k]});
		}
	std::sort(edges.begin(), edges.end());
	std::vector<std::pair<int32_t, int32_t>> pairs;
	for (size_t i = 0; i < edges.size();) {
		size_t j = i + 1;
		while (j < edges.size() && edges[j].a == edges[i].a && edges[j].b == edges[i].b)
			++j;
		for (size_t x = i; x < j; ++x)
			for (size_t y = x + 1; y < j; ++y)
				if (edges[x].sf != edges[y].sf)
					pairs.emplace_back(edges[x].sf, edges[y].sf);
		i = j;
	}
	return pairs;
}

bool sameCoarserPartition(const Partition &fine,
                          const std::vector<std::pair<int32_t, int32_t>> &adjacent, double boundDeg,
                          Partition &out)
{
	const size_t n = fine.count();
	if (fine.level < 1 || !fine.partLabel.empty() ||
	    (boundDeg >= 0 && n >= 2 && fine.nodeMean.size() != n))
		return false;
	for (const CellKey c : fine.cell)
		if (c == kInvalidCell)
			return false;
	const double limit = acrossHalfAngle(boundDeg), cos2Limit = std::cos(2 * limit);
	for (const auto &pr : adjacent) {
		const size_t a = size_t(pr.first), b = size_t(pr.second);
		if (a == b)
			continue;
		// coarserPartition: siblings, or cells that are the same or touch, may be grouped
		const Cell ca = unpackCell(fine.cell[a]), cb = unpackCell(fine.cell[b]);
		if (parentCell(ca) == parentCell(cb) || ca == cb)
			return false;
		Cell nb[8];
		const int cnt = cellNeighbours(ca, fine.level, nb);
		if (std::find(nb, nb + cnt, cb) != nb + cnt)
			return false;
		// mergeAcrossCells: the pair would be tried
		double d;
		if (boundDeg >= 0 && n >= 2 &&
		    acrossMergeable(fine.cell[a], fine.nodeMean[a], fine.nodeRadius[a], limit) &&
		    acrossMergeable(fine.cell[b], fine.nodeMean[b], fine.nodeRadius[b], limit) &&
		    acrossPair(fine.nodeMean[a], fine.nodeRadius[a], fine.nodeMean[b], fine.nodeRadius[b],
		               limit, cos2Limit, d))
			return false;
	}
	// every superface is its own group, with its parent cell and its own origin (coarserPartition
	// (3)); no union across cells (nothing kept apart, the same nodes)
	out.level = fine.level - 1;
	out.label = fine.label;
	out.cell.resize(n);
	for (size_t s = 0; s < n; ++s)
		out.cell[s] = parentKey(fine.cell[s]);
	out.origin = fine.origin;
	out.partLabel.clear(), out.partCell.clear(), out.partOrigin.clear();
	out.nodeArea = fine.nodeArea, out.nodeRadius = fine.nodeRadius, out.nodeMean = fine.nodeMean;
	return true;
}

namespace {

// One node per superface for mergeAcrossCells' greedy union (one cache line each: the loop is
// bound by random memory accesses).
struct AcrossNode {
	Vec3 mean;
	double area, radius;
	double cosRoom; ///< cos(limit - radius): how close the merged mean must stay to mean
	float seedArea; ///< area of the part whose cell the union keeps
	int32_t parent, members;
	CellKey cell;
};

// A candidate pair of mergeAcrossCells: adjacent superfaces a < b, their means' dot product.
struct AcrossPair {
	int32_t a, b;
	double dot;
};

// The nodes, filled with each superface's area, area-weighted mean normal and the cone around it
// holding its normals (its radius); limit: the cone half-angle of a union.
std::unique_ptr<AcrossNode[]> measureNodes(const Topology &t, const Partition &p, double limit)
{
	const size_t n = p.count();
	std::unique_ptr<AcrossNode[]> node(new AcrossNode[n]); // (not zeroed: every field is set)
	for (size_t s = 0; s < n; ++s)
		node[s].mean = Vec3(0, 0, 0), node[s].area = 0, node[s].radius = 1.0; // (radius: min dot)
	for (size_t f = 0; f < t.nF; ++f) {
		AcrossNode &x = node[size_t(p.label[f])];
		Vec3 normal;
		double area;
		t.faceNormal.normalAndArea(f, normal, area);
		x.area += area;
		x.mean += normal * area;
	}
	for (size_t s = 0; s < n; ++s)
		if (node[s].mean.Norm() > 0)
			node[s].mean.Normalize();
	for (size_t f = 0; f < t.nF; ++f)
		if (t.faceValid[f]) {
			AcrossNode &x = node[size_t(p.label[f])];
			x.radius = std::min(x.radius, x.mean.dot(t.faceNormal[f]));
		}
	const double cosLimit = std::cos(limit);
	for (size_t s = 0; s < n; ++s) {
		AcrossNode &x = node[s];
		x.radius = x.radius < 1.0 ? angleOfCos(x.radius) : 0.0;
		x.cosRoom = x.radius > 0 ? std::cos(std::max(0.0, limit - x.radius)) : cosLimit;
		x.seedArea = float(x.area);
		x.parent = int32_t(s), x.members = 1, x.cell = p.cell[s];
	}
	return node;
}

// Candidate pairs: adjacent (one per shared manifold edge; repeats are harmless), and their cones
// fit in one of half-angle `limit`.
std::vector<AcrossPair> acrossPairs(const Topology &t, const Partition &p, const AcrossNode *node,
                                    double limit)
{
	const size_t n = p.count();
	std::vector<uint8_t> mergeable(n);
	for (size_t s = 0; s < n; ++s)
		mergeable[s] = acrossMergeable(p.cell[s], node[s].mean, node[s].radius, limit);
	const double cos2Limit = std::cos(2 * limit);
	std::vector<AcrossPair> pairs;
	for (size_t h = 0; h < t.twin.size(); ++h) {
		const int32_t tw = t.joinTwin(h);
		if (tw < int32_t(h))
			continue; // boundary (-1) or seen from the other side
		const int32_t s = p.label[h / 3], w = p.label[size_t(heFace(tw))];
		if (s == w || !mergeable[size_t(s)] || !mergeable[size_t(w)])
			continue;
		double d;
		if (acrossPair(node[size_t(s)].mean, node[size_t(s)].radius, node[size_t(w)].mean,
		               node[size_t(w)].radius, limit, cos2Limit, d))
			pairs.push_back(AcrossPair{std::min(s, w), std::max(s, w), d});
	}
	return pairs;
}

inline int32_t findNode(AcrossNode *node, int32_t s)
{
	while (node[size_t(s)].parent != s)
		s = node[size_t(s)].parent = node[size_t(node[size_t(s)].parent)].parent;
	return s;
}

// Greedy union, closest mean normals first (stable counting sort on the quantized angle); a union
// keeps its normals in a cone of half-angle `limit` (any two within the level's bound, as inside
// one cell).
void greedyUnion(const std::vector<AcrossPair> &pairs, double limit, AcrossNode *node)
{
	const double span = 1.0 - std::cos(2 * limit) + 1e-12;
	constexpr size_t kBuckets = 16; // (few: pairs keep their memory order inside a bucket)
	std::vector<int32_t> bstart, order;
	bucketByKey(
	    pairs.size(), kBuckets,
	    [&](size_t i) {
		    const double x = (1.0 - pairs[i].dot) / span * double(kBuckets);
		    return int32_t(std::min(double(kBuckets - 1), std::max(0.0, x)));
	    },
	    bstart, order);
	constexpr size_t kAhead = 16; // (the nodes of a pair a few pairs ahead are fetched meanwhile)
	for (size_t oi = 0; oi < order.size(); ++oi) {
		if (oi + kAhead < order.size()) {
			const AcrossPair &ahead = pairs[size_t(order[oi + kAhead])];
			__builtin_prefetch(&node[size_t(ahead.a)]);
			__builtin_prefetch(&node[size_t(ahead.b)]);
		}
		const int32_t pi = order[oi];
		const int32_t a = findNode(node, pairs[size_t(pi)].a),
		              b = findNode(node, pairs[size_t(pi)].b);
		if (a == b)
			continue;
		AcrossNode &na = node[size_t(a)], &nb = node[size_t(b)];
		Vec3 m = na.mean * na.area + nb.mean * nb.area;
		if (!(m.Norm() > 0))
			continue;
		m.Normalize();
		const double da = m.dot(na.mean), db = m.dot(nb.mean);
		if (da < na.cosRoom || db < nb.cosRoom)
			continue; // (cheap test first; the exact one below)
		const double r = std::max(angleOfCos(da) + na.radius, angleOfCos(db) + nb.radius);
		if (r > limit)
			continue;
		// the root (lower id) keeps the cell of the larger original superface
		AcrossNode &root = a < b ? na : nb, &other = a < b ? nb : na;
		other.parent = a < b ? a : b;
		if (other.seedArea > root.seedArea)
			root.cell = other.cell, root.seedArea = other.seedArea;
		root.mean = m;
		root.radius = r;
		root.cosRoom = std::cos(std::max(0.0, limit - r));
		root.area += other.area;
		root.members += other.members;
	}
}

// No union: the nodes as measured, for sameCoarserPartition.
void keepNodes(const AcrossNode *node, Partition &p)
{
	const size_t n = p.count();
	p.nodeArea.resize(n), p.nodeRadius.resize(n), p.nodeMean.resize(n);
	for (size_t s = 0; s < n; ++s)
		p.nodeArea[s] = node[s].area, p.nodeRadius[s] = node[s].radius,
		p.nodeMean[s] = node[s].mean;
}

} // namespace

void mergeAcrossCells(const Topology &t, double boundDeg, Partition &p)
{
	p.partLabel.clear(), p.partCell.clear(), p.partOrigin.clear();
	p.nodeArea.clear(), p.nodeRadius.clear(), p.nodeMean.clear();
	const size_t n = p.count();
	if (n < 2)
		return;
	const double limit = acrossHalfAngle(boundDeg); // cone half-angle
	std::unique_ptr<AcrossNode[]> node = measureNodes(t, p, limit);
	const std::vector<AcrossPair> pairs = acrossPairs(t, p, node.get(), limit);
	if (pairs.empty()) {
		keepNodes(node.get(), p);
		return;
	}
	greedyUnion(pairs, limit, node.get());
	bool any = false;
	for (size_t s = 0; s < n && !any; ++s)
		any = node[s].members > 1 && findNode(node.get(), int32_t(s)) == int32_t(s);
	if (!any) {
		keepNodes(node.get(), p);
		return;
	}
	p.partLabel = p.label, p.partCell = p.cell, p.partOrigin = p.origin;
	std::vector<int32_t> root(n); // (a union's root is its lowest superface)
	for (size_t s = 0; s < n; ++s) {
		root[s] = findNode(node.get(), int32_t(s));
		if (root[s] == int32_t(s)) {
			p.cell[s] = node[s].cell;
			if (node[s].members > 1)
				p.origin[s] = mergedOrigin(p.level);
		}
	}
	node.reset();
	relabelCanonical(p, root, p); // (in place: each face reads its own label first)
}

} // namespace detail
} // namespace gausslod
