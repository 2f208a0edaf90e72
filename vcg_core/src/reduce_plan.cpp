// Edge collapses (reduce.h): the vertex kinds, the ring of triangles around a vertex, and the
// patch a collapse replaces with the fan that replaces it, in the local numbers of its proof
// (reduce_patch.h).
#include "reduce_internal.h"

namespace gausslod {
namespace detail {
namespace collapse {

namespace {

// The corner of triangle f at vertex w (-1: none).
int32_t cornerAt(const std::vector<int32_t> &T, int32_t f, int32_t w)
{
	for (int32_t q = 3 * f; q < 3 * f + 3; ++q)
		if (T[size_t(q)] == w)
			return q;
	return int32_t(-1);
}

} // namespace

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

bool Reducer::plan(int32_t a, int32_t b, int op, const Vec3 &pos, Plan &pl) const
{
	return op < kHalfAB    ? planFull(a, b, pos, pl)
	       : op == kHalfAB ? planHalf(a, b, pl)
	                       : planHalf(b, a, pl);
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
				    cornerAt(T_, g, rv.nb[1]) >= 0 && cornerAt(T_, g, rv.nb[2]) >= 0)
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
		pl.keptCorner[0] = cornerAt(T_, rv.face[0], u);
		pl.keptCorner[1] = cornerAt(T_, rv.face[n - 1], u);
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
		pl.keptCorner[0] = pl.keptCorner[1] = cornerAt(T_, pl.dead[0], u);
	}
	c.nInner = 1;
	c.inner[0] = int8_t(c.nPts - 1);
	c.newInner = -1;
	pl.kept = u, pl.gone = v, pl.full = false, pl.pos = P_[size_t(u)];
	return true;
}

} // namespace collapse
} // namespace detail
} // namespace gausslod
