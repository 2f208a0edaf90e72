// 2.4 Re-triangulating a superface: its kept ring vertices are projected on the plane orthogonal
// to its area-weighted normal and triangulated (constrained Delaunay, delaunay_rings.cpp); then
// each pass is checked (superface_checks.h) and, where it fails, tried again: with inside
// vertices inserted, or once more with the same vertices and data-dependent diagonals
// (surface_flips.cpp) before the next pass's inside vertices are added.
#include "superface_checks.h"

namespace gausslod {
namespace detail {

namespace {

// Every vertex of the superface kept (or an invalid input face): the input faces are the
// triangulation.
void copyInputFaces(const TriangulationInput &in, int32_t s, bool frozen, ChunkOut &o,
                    FaceMeasures &m)
{
	const Topology &t = in.t;
	for (int32_t i = in.faces.begin(s); i < in.faces.end(s); ++i) {
		const int32_t f = in.faces.face[size_t(i)];
		if (frozen) {
			if (!t.faceDropped[size_t(f)])
				o.emit(t.T[3 * f], t.T[3 * f + 1], t.T[3 * f + 2], 7, false);
			continue;
		}
		uint8_t bits = 0;
		for (int k = 0; k < 3; ++k)
			bits |= uint8_t(in.b.border[size_t(3 * f + k)] << k);
		o.emit(t.T[3 * f], t.T[3 * f + 1], t.T[3 * f + 2], bits, false);
		m.dev[size_t(f)] = 0;
	}
}

// The measures of superface s's faces, before they are measured again.
void resetMeasures(const TriangulationInput &in, int32_t s, FaceMeasures &m)
{
	for (int32_t i = in.faces.begin(s); i < in.faces.end(s); ++i) {
		const size_t f = size_t(in.faces.face[size_t(i)]);
		m.dev[f] = -1.0f;
		if (!m.gap.empty())
			m.gap[f] = 0.0f;
		if (!m.tex.empty())
			m.tex[f] = 0.0f;
	}
}

// One triangulation of superface s from its kept ring vertices and the inside vertices inserted
// so far (w.ringVerts after the rings), and its checks. `inside` = the failure is one that
// inside vertices can fix (an input face deviating or too far, not a border or a fold).
// `again`: a pass after the first (the queries are projected already). `jobKept`: w.job already
// holds the pass's triangulation (retryWithFlips: the failed pass's, flipped). `bound`: set to
// the superface's distance bound (distanceBound) when the pass gets that far.
Failure triangulateAndCheck(const TriangulationInput &in, int32_t s, const Vec3 &N, size_t firstTri,
                            Scratch &w, ChunkOut &o, FaceMeasures &m, bool again, bool &inside,
                            bool jobKept = false, double *bound = nullptr)
{
	inside = false;
	w.devMeasured = 0;
	w.farCorner.clear(); // (distanceCheck's, for this pass only)
	w.devCorner.clear(); // (deviationWithinLimit's, likewise)
	if (w.ringVertStart.size() == 2 && w.ringVerts.size() == 3) { // one triangle
		o.emit(w.ringVerts[0], w.ringVerts[1], w.ringVerts[2], 7, true);
	} else {
		if (!jobKept) {
			projectSuperface(in, s, N, w, again);
			if (!triangulateRings(w.job))
				return Failure::Ring;
		}
		for (size_t k = 0; k < w.job.tris.size(); k += 3)
			o.emit(w.ringVerts[size_t(w.job.tris[k])], w.ringVerts[size_t(w.job.tris[k + 1])],
			       w.ringVerts[size_t(w.job.tris[k + 2])], w.job.constrained[k / 3], true);
	}
	SuperfacePass pass{in, s, N, firstTri, w, o, m};
	const Failure f = checkSuperfacePass(pass);
	inside = pass.inside;
	if (bound && pass.bound >= 0)
		*bound = pass.bound;
	return f;
}

// Beyond the paper (with the distance tolerance): a superface that fails inside is given, for
// each of its new triangles, the removed inside vertex farthest from it along N (if farther than
// half the tolerance) as a vertex of its next triangulation, instead of being split: output
// vertices stay input vertices, and a curved superface keeps its extent. False if none is.
// `split`: what a split would give, computed on the first call (< 0 before).
bool insertFarthest(const TriangulationInput &in, int32_t s, const Vec3 &N, size_t firstTri,
                    Scratch &w, const ChunkOut &o, double &split)
{
	const Topology &t = in.t;
	const size_t ntri = o.tris.size() / 3 - firstTri;
	if (!(in.limits.maxDistance > 0) || ntri < 2 || w.cornerQuery.empty())
		return false; // (one triangle: no vertex was located)
	const int32_t fb = in.faces.begin(s);
	const size_t faces = size_t(in.faces.end(s) - fb);
	// what the split would give: the finer level's triangles over these faces (at the finest
	// level, the input faces)
	const int origin = in.p.origin[size_t(s)];
	if (split < 0 && in.finerCost && !(origin == -1 || origin >= in.limits.finest)) {
		split = 0;
		for (size_t i = 0; i < faces; ++i)
			split += double(in.finerCost->at(size_t(in.faces.face[size_t(fb) + i])));
	} else if (split < 0) {
		split = double(faces);
	}
	w.farthest.assign(ntri, std::make_pair(in.limits.maxDistance, int32_t(-1)));
	for (size_t i = 0; i < faces; ++i)
		for (int c = 0; c < 3; ++c) {
			const int32_t k = w.job.queryTri[faces + size_t(w.cornerQuery[3 * i + size_t(c)])];
			if (k >= 0)
				offerInsertion(in, w, o, firstTri, N, k, t.T[3 * in.faces.face[size_t(fb) + i] + c],
				               w.farthest[size_t(k)]);
		}
	// a triangle with no such vertex: a corner of a face too far from it but from none of the
	// vertices under it (distanceCheck's), else of a face deviating from it beyond the normal
	// limit (deviationWithinLimit's)
	for (const auto *corner : {&w.farCorner, &w.devCorner})
		if (corner->size() == ntri)
			for (size_t k = 0; k < ntri; ++k)
				if (w.farthest[k].second < 0 && (*corner)[k].second >= 0)
					w.farthest[k] = (*corner)[k];
	const size_t before = w.ringVerts.size();
	for (const auto &best : w.farthest) {
		const int32_t v = best.second;
		if (v < 0 || w.inserted(v))
			continue;
		// (each inserted vertex adds about two triangles)
		if (double(ntri + 2 * (w.ringVerts.size() - before + 1)) >= split)
			return false; // a split is likely cheaper
		if (w.steinerMark.size() != t.nV)
			w.steinerMark.assign(t.nV, 0);
		w.steinerMark[size_t(v)] = 1;
		w.ringVerts.push_back(v);
		w.steiner.push_back(v);
		if (in.limits.maxTexError > 0) { // (its texture coordinates: a corner of the superface)
			const int32_t corner = cornerAt(in, s, v);
			w.ringUV.push_back(t.UV[2 * size_t(corner)]);
			w.ringUV.push_back(t.UV[2 * size_t(corner) + 1]);
		}
	}
	return w.ringVerts.size() > before;
}

// A pass that failed the distance tolerance, tried again with the same vertices (the first
// `count` of w.ringVerts: what insertFarthest added after them is set aside, then put back) and
// its triangulation (still in w.job) with the diagonals flipTowardSurface chooses; nothing is
// tried again if it flips no edge. True if that passes (the vertices set aside are then dropped).
bool retryWithFlips(const TriangulationInput &in, int32_t s, const Vec3 &N, size_t firstTri,
                    size_t count, size_t uvCount, Scratch &w, ChunkOut &o, FaceMeasures &m)
{
	if (!flipTowardSurface(in, s, N, w))
		return false; // (the same triangles would fail the same way)
	const size_t added = w.ringVerts.size() - count;
	w.asideVerts.assign(w.ringVerts.begin() + std::ptrdiff_t(count), w.ringVerts.end());
	w.asideUV.assign(w.ringUV.begin() + std::ptrdiff_t(uvCount), w.ringUV.end());
	w.ringVerts.resize(count), w.ringUV.resize(uvCount);
	for (const int32_t v : w.asideVerts)
		w.steinerMark[size_t(v)] = 0;
	writeDeviations(in, s, w, m);
	o.truncate(firstTri);
	resetMeasures(in, s, m);
	bool inside = false;
	if (triangulateAndCheck(in, s, N, firstTri, w, o, m, true, inside, true) == Failure::None) {
		writeDeviations(in, s, w, m);
		++o.retriangulated;
		w.steiner.resize(w.steiner.size() - added);
		return true;
	}
	w.ringVerts.insert(w.ringVerts.end(), w.asideVerts.begin(), w.asideVerts.end());
	w.ringUV.insert(w.ringUV.end(), w.asideUV.begin(), w.asideUV.end());
	for (const int32_t v : w.asideVerts)
		w.steinerMark[size_t(v)] = 1;
	return false;
}

} // namespace

Failure checkTriangles(const TriangulationInput &in, int32_t s, const Vec3 &N, Scratch &w,
                       ChunkOut &o, FaceMeasures &m, double &bound)
{
	bool inside = false;
	bound = 0;
	const Failure f =
	    triangulateAndCheck(in, s, N, o.tris.size() / 3, w, o, m, true, inside, true, &bound);
	if (f == Failure::None)
		writeDeviations(in, s, w, m);
	return f;
}

namespace {

// Beyond the paper (DESIGN 28): an accepted pass of a superface that may get flips (triangles
// from firstTri of o, its triangulation in w.job, its distance bound `bound`) is tried once more
// with its diagonals flipped where that brings the triangles closer to the input vertices and face
// centroids under them, from half the tolerance (flipTowardSurface); the polished triangles are
// kept if they pass every check and their distance bound is not above `bound`, else the accepted
// ones are put back with their measures. (Delaunay picks the diagonals by angles alone: on a ruled
// or curved part it may cut across the surface where the input's diagonal, or another, lies on it.)
// The accepted pass's deviations are written here.
void polishDiagonals(const TriangulationInput &in, int32_t s, const Vec3 &N, size_t firstTri,
                     double bound, Scratch &w, ChunkOut &o, FaceMeasures &m)
{
	writeDeviations(in, s, w, m);
	if (!flipTowardSurface(in, s, N, w, kFlipFrom, true))
		return; // (no edge to flip: nothing is measured again)
	const int32_t fb = in.faces.begin(s), fe = in.faces.end(s);
	w.keptTris.assign(o.tris.begin() + std::ptrdiff_t(3 * firstTri), o.tris.end());
	w.keptBorder.assign(o.triBorder.begin() + std::ptrdiff_t(firstTri), o.triBorder.end());
	w.keptDev.clear(), w.keptGap.clear(), w.keptTex.clear();
	for (int32_t i = fb; i < fe; ++i) {
		const size_t f = size_t(in.faces.face[size_t(i)]);
		w.keptDev.push_back(m.dev[f]);
		if (!m.gap.empty())
			w.keptGap.push_back(m.gap[f]);
		if (!m.tex.empty())
			w.keptTex.push_back(m.tex[f]);
	}
	o.truncate(firstTri);
	resetMeasures(in, s, m);
	bool inside = false;
	double after = 0;
	if (triangulateAndCheck(in, s, N, firstTri, w, o, m, true, inside, true, &after) ==
	        Failure::None &&
	    !(after > bound)) {
		writeDeviations(in, s, w, m);
		return;
	}
	w.devMeasured = 0; // (the polished pass's deviations are not written)
	o.truncate(firstTri);
	o.tris.insert(o.tris.end(), w.keptTris.begin(), w.keptTris.end());
	o.triBorder.insert(o.triBorder.end(), w.keptBorder.begin(), w.keptBorder.end());
	for (int32_t i = fb; i < fe; ++i) {
		const size_t f = size_t(in.faces.face[size_t(i)]), j = size_t(i - fb);
		m.dev[f] = w.keptDev[j];
		if (!m.gap.empty())
			m.gap[f] = w.keptGap[j];
		if (!m.tex.empty())
			m.tex[f] = w.keptTex[j];
	}
}

} // namespace

Failure retriangulate(const TriangulationInput &in, int32_t s, Scratch &w, ChunkOut &o,
                      FaceMeasures &m)
{
	if (in.p.cell[size_t(s)] == kInvalidCell) { // invalid input face: kept as it is
		copyInputFaces(in, s, true, o, m);
		return Failure::None;
	}
	Vec3 N;
	bool unchanged = false;
	if (!projectionNormal(in, s, N, unchanged, w))
		return Failure::Fold;
	if (unchanged) {
		copyInputFaces(in, s, false, o, m);
		return Failure::None;
	}
	for (const int32_t v : w.steiner) // (the previous superface's)
		w.steinerMark[size_t(v)] = 0;
	w.steiner.clear();
	if (!keptRingVertices(in, s, w))
		return Failure::Ring;
	const size_t firstTri = o.tris.size() / 3;
	double split = -1; // (insertFarthest's, once per superface)
	const bool flips =
	    in.limits.maxDistance > 0 && in.faces.end(s) - in.faces.begin(s) <= kFlipMaxFaces;
	for (int pass = 0;; ++pass) {
		bool inside = false; // the failure is one inside vertices can fix
		double bound = 0;
		const Failure f =
		    triangulateAndCheck(in, s, N, firstTri, w, o, m, pass > 0, inside, false, &bound);
		if (f == Failure::None) {
			if (flips && o.tris.size() / 3 - firstTri > 1) // (one triangle: no job was run)
				polishDiagonals(in, s, N, firstTri, bound, w, o, m);
			else
				writeDeviations(in, s, w, m);
			++o.retriangulated;
			return f;
		}
		// the next pass's inside vertices, chosen from this (Delaunay) triangulation
		const size_t before = w.ringVerts.size(), uvBefore = w.ringUV.size();
		const bool more =
		    inside && pass < kMaxInsertPasses && insertFarthest(in, s, N, firstTri, w, o, split);
		if (flips && f == Failure::Distance && before > 3 &&
		    retryWithFlips(in, s, N, firstTri, before, uvBefore, w, o, m))
			return Failure::None;
		if (!more || (w.discard && w.discard->load(std::memory_order_relaxed))) {
			writeDeviations(in, s, w, m); // (what the failed pass measured stays, as it would)
			return f;
		}
		o.truncate(firstTri);
		resetMeasures(in, s, m);
	}
}

} // namespace detail
} // namespace gausslod
