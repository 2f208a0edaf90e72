// The triangle tree of the certified Hausdorff distance (hausdorff.h): a bounding-volume
// hierarchy with edge adjacency, for nearest-triangle and box queries.
#include "hausdorff.h"

namespace gausslod {
namespace detail {

namespace {

constexpr int kLeafSize = 4;

double boxDistance2(const Vec3 &p, const Vec3 &lo, const Vec3 &hi)
{
	double d2 = 0;
	for (int k = 0; k < 3; ++k) {
		const double e = p[k] < lo[k] ? lo[k] - p[k] : p[k] > hi[k] ? p[k] - hi[k] : 0.0;
		d2 += e * e;
	}
	return d2;
}

} // namespace

// The triangles kept (no repeated vertex, finite corners), and which of them are degenerate.
void TriangleTree::keepTriangles(size_t nT)
{
	const int32_t *T = T_;
	const double *P = P_;
	flat_.assign(nT, 0);
	tri_.reserve(nT);
	for (size_t f = 0; f < nT; ++f) {
		const int32_t a = T[3 * f], b = T[3 * f + 1], c = T[3 * f + 2];
		if (a < 0 || b < 0 || c < 0 || a == b || b == c || c == a)
			continue;
		bool finite = true;
		for (int k = 0; k < 3; ++k)
			for (int j = 0; j < 3; ++j)
				finite = finite && std::isfinite(P[3 * size_t(T[3 * f + size_t(k)]) + size_t(j)]);
		if (!finite)
			continue;
		const Vec3 x =
		    (v(int32_t(f), 1) - v(int32_t(f), 0)) ^ (v(int32_t(f), 2) - v(int32_t(f), 0));
		flat_[f] = !(x.SquaredNorm() > 0);
		tri_.push_back(int32_t(f));
	}
}

// Edge adjacency: the kept triangles' edges sorted by their vertices, pairs taken.
void TriangleTree::linkEdges(size_t nT)
{
	const int32_t *T = T_;
	struct E {
		int32_t a, b, f;
		int8_t k;
	};
	std::vector<E> es;
	es.reserve(3 * tri_.size());
	for (const int32_t f : tri_)
		for (int k = 0; k < 3; ++k) {
			const int32_t a = T[3 * size_t(f) + size_t(k)],
			              b = T[3 * size_t(f) + size_t(k + 1) % 3];
			es.push_back({std::min(a, b), std::max(a, b), f, int8_t(k)});
		}
	std::sort(es.begin(), es.end(), [](const E &x, const E &y) {
		return x.a != y.a ? x.a < y.a : x.b != y.b ? x.b < y.b : x.f < y.f;
	});
	adj_.assign(3 * nT, -1);
	for (size_t i = 0; i < es.size();) {
		size_t j = i + 1;
		while (j < es.size() && es[j].a == es[i].a && es[j].b == es[i].b)
			++j;
		if (j - i == 2) {
			adj_[3 * size_t(es[i].f) + size_t(es[i].k)] = es[i + 1].f;
			adj_[3 * size_t(es[i + 1].f) + size_t(es[i + 1].k)] = es[i].f;
		}
		i = j;
	}
}

TriangleTree::TriangleTree(const double *P, const int32_t *T, size_t nT) : P_(P), T_(T)
{
	keepTriangles(nT);
	if (tri_.empty())
		return;
	linkEdges(nT);
	buildNodes();
}

// The hierarchy, depth first: a node's left child is the next node; the split is at the median
// centroid along the longest side of the centroids' box; the centroids (as corner sums) travel
// with the triangles, the boxes are made bottom up. tri_ ends in the leaves' order.
void TriangleTree::buildNodes()
{
	nodes_.reserve(2 * (tri_.size() / kLeafSize + 1));
	struct Item {
		double c[3];
		int32_t f;
	};
	std::vector<Item> items(tri_.size());
	for (size_t i = 0; i < tri_.size(); ++i) {
		const int32_t f = tri_[i];
		items[i].f = f;
		for (int j = 0; j < 3; ++j)
			items[i].c[j] = P_[3 * size_t(T_[3 * size_t(f)]) + size_t(j)] +
			                P_[3 * size_t(T_[3 * size_t(f) + 1]) + size_t(j)] +
			                P_[3 * size_t(T_[3 * size_t(f) + 2]) + size_t(j)];
	}
	struct Task {
		int32_t first, count, parent;
	};
	std::vector<Task> stack{{0, int32_t(tri_.size()), -1}};
	while (!stack.empty()) {
		const Task t = stack.back();
		stack.pop_back();
		const int32_t id = int32_t(nodes_.size());
		if (t.parent >= 0)
			nodes_[size_t(t.parent)].right = id;
		Node n;
		n.first = t.first;
		n.count = t.count;
		n.right = -1;
		if (t.count <= kLeafSize) {
			n.lo = n.hi = v(items[size_t(t.first)].f, 0);
			for (int32_t i = t.first; i < t.first + t.count; ++i)
				for (int k = 0; k < 3; ++k) {
					const Vec3 q = v(items[size_t(i)].f, k);
					for (int j = 0; j < 3; ++j)
						n.lo[j] = std::min(n.lo[j], q[j]), n.hi[j] = std::max(n.hi[j], q[j]);
				}
			nodes_.push_back(n);
			continue;
		}
		double clo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, chi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
		for (int32_t i = t.first; i < t.first + t.count; ++i)
			for (int j = 0; j < 3; ++j)
				clo[j] = std::min(clo[j], items[size_t(i)].c[j]),
				chi[j] = std::max(chi[j], items[size_t(i)].c[j]);
		n.count = -1;
		n.lo = n.hi = Vec3(0, 0, 0); // (made from its children's below)
		nodes_.push_back(n);
		const double ext[3] = {chi[0] - clo[0], chi[1] - clo[1], chi[2] - clo[2]};
		const int axis = ext[0] >= ext[1] && ext[0] >= ext[2] ? 0 : ext[1] >= ext[2] ? 1 : 2;
		const int32_t half = t.count / 2;
		std::nth_element(items.begin() + t.first, items.begin() + t.first + half,
		                 items.begin() + t.first + t.count, [axis](const Item &a, const Item &b) {
			                 return a.c[axis] < b.c[axis] || (a.c[axis] == b.c[axis] && a.f < b.f);
		                 });
		stack.push_back({t.first + half, t.count - half, id}); // (right, built after the left)
		stack.push_back({t.first, half, -1});
	}
	for (size_t i = 0; i < items.size(); ++i)
		tri_[i] = items[i].f;
	// (an inner node's children come after it)
	for (size_t i = nodes_.size(); i-- > 0;) {
		Node &n = nodes_[i];
		if (n.count >= 0)
			continue;
		const Node &l = nodes_[i + 1], &r = nodes_[size_t(n.right)];
		for (int j = 0; j < 3; ++j)
			n.lo[j] = std::min(l.lo[j], r.lo[j]), n.hi[j] = std::max(l.hi[j], r.hi[j]);
	}
}

bool TriangleTree::collect(const Vec3 &lo, const Vec3 &hi, int32_t *out, int &n, int cap) const
{
	n = 0;
	if (nodes_.empty())
		return true;
	auto meets = [&](const Vec3 &a, const Vec3 &b) {
		return a[0] <= hi[0] && b[0] >= lo[0] && a[1] <= hi[1] && b[1] >= lo[1] && a[2] <= hi[2] &&
		       b[2] >= lo[2];
	};
	int32_t stack[128];
	int top = 0;
	stack[top++] = 0;
	while (top > 0) {
		const Node &nd = nodes_[size_t(stack[--top])];
		if (!meets(nd.lo, nd.hi))
			continue;
		if (nd.count < 0) {
			stack[top++] = nd.right;
			stack[top++] = int32_t(&nd - nodes_.data()) + 1;
			continue;
		}
		for (int32_t i = nd.first; i < nd.first + nd.count; ++i) {
			const int32_t f = tri_[size_t(i)];
			Vec3 a = v(f, 0), b = a;
			for (int k = 1; k < 3; ++k) {
				const Vec3 q = v(f, k);
				for (int j = 0; j < 3; ++j)
					a[j] = std::min(a[j], q[j]), b[j] = std::max(b[j], q[j]);
			}
			if (!meets(a, b))
				continue;
			if (n == cap)
				return false;
			out[n++] = f;
		}
	}
	return true;
}

int32_t TriangleTree::nearest(const Vec3 &p, double &best2) const
{
	int32_t found = -1;
	if (nodes_.empty())
		return found;
	int32_t stack[128];
	int top = 0;
	stack[top++] = 0;
	while (top > 0) {
		const Node &n = nodes_[size_t(stack[--top])];
		if (boxDistance2(p, n.lo, n.hi) >= best2)
			continue;
		if (n.count >= 0) {
			for (int32_t i = n.first; i < n.first + n.count; ++i) {
				const int32_t f = tri_[size_t(i)];
				const double d2 = distance2(f, p);
				if (d2 < best2)
					best2 = d2, found = f;
			}
			continue;
		}
		const int32_t l = int32_t(&n - nodes_.data()) + 1, r = n.right;
		const double dl = boxDistance2(p, nodes_[size_t(l)].lo, nodes_[size_t(l)].hi),
		             dr = boxDistance2(p, nodes_[size_t(r)].lo, nodes_[size_t(r)].hi);
		// (the nearer child on top; the depth is that of a median split: far below 128)
		if (dl <= dr) {
			stack[top++] = r;
			stack[top++] = l;
		} else {
			stack[top++] = l;
			stack[top++] = r;
		}
	}
	return found;
}

} // namespace detail
} // namespace gausslod
