// Edge collapses (reduce.h): the level written out, as the next level's collapses start from it:
// its live vertices and triangles renumbered, its superfaces, each input face's triangle, its
// per-triangle bounds and cones, per-vertex quadrics, and its figures.
#include "reduce_internal.h"

namespace gausslod {
namespace detail {
namespace collapse {

// What write's passes share: the triangles' groups (the superfaces), the output's ids of
// vertices, triangles and groups, and the level's totals.
struct Reducer::Written {
	std::vector<int32_t> uf;    // (the cell groups: union-find over the triangles)
	std::vector<CellKey> cell;  // (each live triangle's normal cell, without keepSuperfaces)
	std::vector<int32_t> twin;  // (per corner of a live triangle: twinOf)
	std::vector<int32_t> remap; // (per vertex: its output id, -1 if no live triangle has it)
	std::vector<int32_t> triId, sfId;
	int32_t nextV = 0, nextSf = 0;
	size_t placed = 0;
	double maxMove = 0, maxDev = 0, devArea = 0, area = 0, maxBound = 0;
	float maxUv = 0;
};

namespace {

int32_t findCell(std::vector<int32_t> &uf, int32_t x)
{
	while (uf[size_t(x)] != x)
		x = uf[size_t(x)] = uf[size_t(uf[size_t(x)])];
	return x;
}

} // namespace

int32_t Reducer::groupOf(Written &w, int32_t f)
{
	// (a group's id: a source superface's root, or a triangle that is its cell group's root)
	return lim_.keepSuperfaces ? superfaceOf(f) : findCell(w.uf, f);
}

void Reducer::groupTriangles(Written &w)
{
	// superfaces: the source's as the collapses merged them (keepSuperfaces), else connected
	// triangles whose normals fall in one cell of the level, across edges that are no delimiter
	const size_t nT = T_.size() / 3;
	w.uf.resize(nT);
	w.cell.assign(nT, kInvalidCell);
	for (size_t f = 0; f < nT; ++f) {
		w.uf[f] = int32_t(f);
		if (alive_[f] && !lim_.keepSuperfaces)
			w.cell[f] = cellOfNormal(normal(int32_t(f)), lim_.level);
	}
	w.twin.assign(3 * nT, -1);
	for (size_t c = 0; c < 3 * nT; ++c) {
		if (!alive_[c / 3])
			continue;
		w.twin[c] = twinOf(T_, head_, next_, alive_, int32_t(c));
		const int32_t d = w.twin[c];
		if (d < 0 || dlm_[c] || w.cell[c / 3] == kInvalidCell ||
		    w.cell[c / 3] != w.cell[size_t(heFace(d))])
			continue;
		const int32_t a = findCell(w.uf, int32_t(c / 3)), b = findCell(w.uf, heFace(d));
		if (a != b)
			w.uf[size_t(std::max(a, b))] = std::min(a, b);
	}
}

void Reducer::writeVertices(Written &w, CollapseSource &out) const
{
	const size_t nV = P_.size(), nT = T_.size() / 3;
	LevelMesh &o = out.mesh;
	w.remap.assign(nV, -1);
	for (size_t f = 0; f < nT; ++f)
		if (alive_[f])
			for (int k = 0; k < 3; ++k)
				w.remap[size_t(T_[3 * f + size_t(k)])] = 0;
	size_t usedV = 0;
	for (size_t v = 0; v < nV; ++v)
		usedV += w.remap[v] >= 0;
	o.sourceVertex.reserve(usedV);
	o.positions.reserve(3 * usedV);
	out.quadric.reserve(usedV);
	for (size_t v = 0; v < nV; ++v) {
		if (w.remap[v] < 0)
			continue;
		w.remap[v] = w.nextV++;
		o.sourceVertex.push_back(srcV_[v]);
		for (int k = 0; k < 3; ++k)
			o.positions.push_back(P_[v][k]);
		out.quadric.push_back(Q_[v]);
		const Vec3 in(&mesh_.positions[3 * size_t(srcV_[v])]);
		if (!(P_[v] == in)) {
			++w.placed;
			w.maxMove = std::max(w.maxMove, (P_[v] - in).Norm());
		}
	}
}

void Reducer::writeTriangles(Written &w, CollapseSource &out)
{
	const LevelMesh &sm = src_.mesh;
	const size_t nT = T_.size() / 3;
	LevelMesh &o = out.mesh;
	w.triId.assign(nT, -1);
	w.sfId.assign(std::max(nT, sfUf_.size()), -1);
	const bool sources = !srcC_.empty();
	int32_t nextT = 0;
	o.triangles.reserve(3 * live_);
	o.superface.reserve(live_);
	o.borderEdges.reserve(live_);
	out.bound.reserve(live_);
	out.cone.reserve(live_);
	out.uvError.reserve(live_);
	for (size_t f = 0; f < nT; ++f) {
		if (!alive_[f])
			continue;
		w.triId[f] = nextT++;
		const int32_t r = groupOf(w, int32_t(f));
		if (w.sfId[size_t(r)] < 0)
			w.sfId[size_t(r)] = w.nextSf++;
		o.superface.push_back(w.sfId[size_t(r)]);
		uint8_t border = 0;
		for (int k = 0; k < 3; ++k) {
			const size_t c = 3 * f + size_t(k);
			o.triangles.push_back(w.remap[size_t(T_[c])]);
			if (w.twin[c] < 0 || groupOf(w, heFace(w.twin[c])) != r)
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
		w.area += a;
		if (devBound_[f] < 0) { // (as the source measured it)
			w.devArea += a * sm.stats.meanNormalDevDeg;
		} else if (a > 0) {
			n.Normalize();
			w.maxDev = std::max(w.maxDev, devBound_[f]);
			w.devArea += a * angleDeg(n, cone_[f].axis);
		}
		w.maxBound = std::max(w.maxBound, e_[f]);
		w.maxUv = std::max(w.maxUv, uvErr_[f]);
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
	o.superfaceBound.assign(size_t(w.nextSf), 0.0f);
	for (size_t f = 0; f < nT; ++f)
		if (alive_[f]) {
			float &b = o.superfaceBound[size_t(w.sfId[size_t(groupOf(w, int32_t(f)))])];
			b = std::max(b, std::nextafter(float(e_[f]), 3e38f));
		}
}

void Reducer::writeInputFaces(Written &w, CollapseSource &out)
{
	const LevelMesh &sm = src_.mesh;
	LevelMesh &o = out.mesh;
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
		out.inputTri[i] = w.triId[size_t(tri)];
		o.inputSuperface[i] = w.sfId[size_t(groupOf(w, tri))];
	}
	if (lim_.keepSuperfaces) // (an input face's superface, as merged: -1 if it has no triangle)
		for (size_t i = 0; i < nIn; ++i) {
			const int32_t x = sm.inputSuperface[i];
			if (x >= 0) {
				int32_t r = x;
				while (sfUf_[size_t(r)] != r)
					r = sfUf_[size_t(r)];
				o.inputSuperface[i] = w.sfId[size_t(r)];
			}
		}
}

void Reducer::writeStats(const Written &w, CollapseSource &out, ReduceReport &report) const
{
	const LevelMesh &sm = src_.mesh;
	LevelMesh &o = out.mesh;
	LevelStats &st = o.stats;
	st.faces = o.triangles.size() / 3;
	st.vertices = size_t(w.nextV);
	st.superfaces = size_t(w.nextSf);
	st.maxNormalDevDeg = std::max(sm.stats.maxNormalDevDeg, w.maxDev);
	st.meanNormalDevDeg = w.area > 0 ? w.devArea / w.area : 0;
	st.unmeasuredFaces = 0;
	st.distanceBound = src_.unbounded ? -1 : w.maxBound; // (a source of unknown distance: none)
	out.unbounded = src_.unbounded;
	st.placedVertices = w.placed;
	st.maxPlacement = w.maxMove;
	st.collapses = collapses_;
	st.maxTexError = t_.UV ? double(w.maxUv) : -1;
	report.collapses = collapses_;
	report.regionCollapses = regionMade_;
	report.regions = regions_;
	report.maxTexError = st.maxTexError;
	report.texErrorLimit = std::max(lim_.texError, st.maxTexError); // (a soft one gave way)
}

void Reducer::write(CollapseSource &out, ReduceReport &report)
{
	out.clear();
	Written w;
	groupTriangles(w); // (each array freed once written: the level's peak is here)
	release(w.cell), release(head_), release(next_), release(dlm_), release(kind_);
	writeVertices(w, out);
	release(Q_), release(srcV_);
	writeTriangles(w, out);
	writeInputFaces(w, out);
	writeStats(w, out, report);
}

} // namespace collapse
} // namespace detail
} // namespace gausslod
