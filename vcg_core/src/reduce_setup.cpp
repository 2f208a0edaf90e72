// Edge collapses (reduce.h): a reduction's start (the source's arrays, corner lists, delimiters,
// quadrics and vertex kinds), and the input as a collapse source.
#include "reduce_internal.h"

namespace gausslod {
namespace detail {
namespace collapse {

void Reducer::setUp()
{
	const LevelMesh &sm = src_.mesh;
	const size_t nV = sm.sourceVertex.size(), nT = sm.triangles.size() / 3;
	P_.resize(nV);
	for (size_t v = 0; v < nV; ++v)
		P_[v] = Vec3(&sm.positions[3 * v]);
	if (own_)
		release(own_->mesh.positions);
	srcV_ = take(&LevelMesh::sourceVertex);
	T_ = take(&LevelMesh::triangles);
	if (sm.sourceCorner.size() == 3 * nT)
		srcC_ = take(&LevelMesh::sourceCorner);
	alive_.assign(nT, 1);
	live_ = nT;
	head_.assign(nV, -1);
	next_.assign(3 * nT, -1);
	for (size_t c = 3 * nT; c-- > 0;) {
		next_[c] = head_[size_t(T_[c])];
		head_[size_t(T_[c])] = int32_t(c);
	}
	e_ = take(&CollapseSource::bound);
	devBound_.assign(nT, -1.0);
	cone_ = take(&CollapseSource::cone);
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
	uvErr_ =
	    src_.uvError.size() == nT ? take(&CollapseSource::uvError) : std::vector<float>(nT, 0.0f);
	fwd_.assign(nT, -1);
	if (t_.UV && !srcC_.empty()) { // (a level's own coordinates, or its corners' sources')
		uv_.resize(6 * nT);
		const bool own = sm.cornerUV.size() == 6 * nT;
		for (size_t c = 0; c < 3 * nT; ++c)
			for (int k = 0; k < 2; ++k)
				uv_[2 * c + size_t(k)] =
				    own ? sm.cornerUV[2 * c + size_t(k)] : t_.UV[2 * size_t(srcC_[c]) + size_t(k)];
	}
	if (own_)
		release(own_->mesh.cornerUV);
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
	if (src_.quadric.size() == nV)
		Q_ = take(&CollapseSource::quadric);
	else
		planeQuadrics();
	classify();
}

void Reducer::planeQuadrics()
{
	const size_t nV = P_.size(), nT = T_.size() / 3;
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

} // namespace collapse

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

} // namespace detail
} // namespace gausslod
