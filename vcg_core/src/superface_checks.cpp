// The checks of a superface's re-triangulation (superface_checks.h): every input face against the
// triangle over its centroid (normal deviation limit, no flip), the distance tolerance
// (distance_check.cpp), the texture stretch (texture_check.cpp), every triangle against the input
// surface nearest to it (no flip at thin parts), and the distance bound (distance_bound.cpp).
#include "superface_checks.h"

#include <algorithm>
#include <cmath>

namespace gausslod {
namespace detail {

namespace {

double faceDist2(const Topology &t, const Vec3 &p, int32_t f)
{
	return pointTriangleDistance2(p, t.pos(t.T[3 * f]), t.pos(t.T[3 * f + 1]),
	                              t.pos(t.T[3 * f + 2]));
}

// Does face g face away from n: Topology::faceNormal[g].dot(n) < 0, the same answer? The dot of
// the unnormalized cross product has the same sign but near 0, where the division by the length
// could move it by a few ulps of the margin's 1e-9: only there is the normal computed.
// `valid`: g is known to be valid (a face of Topology::grid), its flag is not read.
bool facesAway(const Topology &t, int32_t g, const Vec3 &n, bool valid = false)
{
	if (!valid && !t.faceValid[size_t(g)])
		return false; // (a zero normal)
	Vec3 c;
	const double len = faceCross(t.P, t.T, size_t(g), c);
	const double d = c.dot(n);
	const double margin = 1e-9 * len * (std::fabs(n[0]) + std::fabs(n[1]) + std::fabs(n[2]));
	if (d < -margin)
		return true;
	if (d > margin)
		return false;
	return (c / len).dot(n) < 0; // (= faceNormal[g].dot(n) < 0)
}

// Normals and centroids of the new triangles (from firstTri); false if one is degenerate.
bool triangleFrames(const TriangulationInput &in, const ChunkOut &o, size_t firstTri, Scratch &w)
{
	const size_t ntri = o.tris.size() / 3 - firstTri;
	w.triNormal.resize(ntri);
	for (size_t k = 0; k < ntri; ++k) {
		const int32_t *v = &o.tris[3 * (firstTri + k)];
		Vec3 n = (in.out(v[1]) - in.out(v[0])) ^ (in.out(v[2]) - in.out(v[0]));
		if (!(n.Norm() > 0))
			return false;
		w.triNormal[k] = n / n.Norm();
	}
	w.covered.assign(ntri, 0);
	w.centroid.resize(ntri);
	w.ownDist2.assign(ntri, HUGE_VAL);
	for (size_t k = 0; k < ntri; ++k) {
		const int32_t *v = &o.tris[3 * (firstTri + k)];
		w.centroid[k] = (in.out(v[0]) + in.out(v[1]) + in.out(v[2])) / 3.0;
	}
	return true;
}

// The measured normal deviation: each input face against the triangle its centroid falls in; a
// triangle flipped (> 90 deg) or beyond the level's limit fails. With the normals cached, the
// deviations are written by writeDeviations (a pass that is retried never writes them: the retry
// resets them), and the angle (acos) is only computed here where the cosine is not clearly within
// the limit.
bool deviationWithinLimit(const TriangulationInput &in, int32_t s, const Vec3 &N, size_t firstTri,
                          const ChunkOut &o, Scratch &w, FaceMeasures &m)
{
	const size_t ntri = o.tris.size() / 3 - firstTri;
	const int32_t fb = in.faces.begin(s);
	const bool defer = !w.sfNormal.empty();
	// Beyond the paper (DESIGN 32): with inside vertices to insert, every face beyond the limit
	// offers a corner to its triangle (w.devCorner), as a face too far does (distanceCheck)
	const bool corners = in.limits.maxDistance > 0 && ntri > 1 && !w.cornerQuery.empty();
	if (corners)
		w.devCorner.assign(ntri, std::make_pair(-1.0, int32_t(-1)));
	// above this cosine the angle is below min(90, limit) by far more than acos's rounding
	const double limit = std::min(90.0, in.limits.devLimitDeg);
	const double clearlyWithin = std::cos(limit * (M_PI / 180)) + 1e-7;
	bool within = true;
	for (int32_t i = fb; i < in.faces.end(s); ++i) {
		const int32_t f = in.faces.face[size_t(i)];
		const int32_t k = ntri == 1 ? 0 : w.job.queryTri[size_t(i - fb)];
		if (defer && within)
			w.devMeasured = i - fb;
		if (k < 0)
			continue;
		const double cosine = sfFaceNormal(in, s, i - fb, w).dot(w.triNormal[size_t(k)]);
		if (!defer || !(cosine > clearlyWithin)) {
			const double d = angleDegOfCos(cosine); // (= angleDeg(normal, triangle normal))
			if (d > 90 || d > in.limits.devLimitDeg) {
				within = false;
				if (!corners)
					return false;
				for (int c = 0; c < 3; ++c)
					offerInsertion(in, w, o, firstTri, N, k, in.t.T[3 * f + c],
					               w.devCorner[size_t(k)]);
				continue;
			}
			if (!defer && within)
				m.dev[size_t(f)] = float(d);
		}
		w.covered[size_t(k)] = 1;
	}
	if (defer && within)
		w.devMeasured = in.faces.end(s) - fb;
	return within;
}

// Each triangle's distance to the nearest input face whose centroid it covers (the flip check's
// radius), once the checks that may still fail before it have passed.
void ownDistances(const TriangulationInput &in, int32_t s, size_t ntri, Scratch &w)
{
	const int32_t fb = in.faces.begin(s);
	for (int32_t i = fb; i < in.faces.end(s); ++i) {
		const int32_t k = ntri == 1 ? 0 : w.job.queryTri[size_t(i - fb)];
		if (k >= 0)
			w.ownDist2[size_t(k)] =
			    std::min(w.ownDist2[size_t(k)],
			             faceDist2(in.t, w.centroid[size_t(k)], in.faces.face[size_t(i)]));
	}
}

// A triangle that covers no input face centroid is checked against the faces of the superface
// around its corners.
bool uncoveredFacing(const TriangulationInput &in, int32_t s, const ChunkOut &o, size_t firstTri,
                     Scratch &w)
{
	const Topology &t = in.t;
	for (size_t k = 0; k < w.covered.size(); ++k) {
		if (w.covered[k])
			continue;
		for (int c = 0; c < 3; ++c) {
			const int32_t v = o.tris[3 * (firstTri + k) + size_t(c)];
			for (int32_t q = t.vfStart[size_t(v)]; q < t.vfStart[size_t(v) + 1]; ++q) {
				const int32_t f = t.vfFace[size_t(q)];
				if (in.p.label[size_t(f)] != s)
					continue;
				if (facesAway(t, f, w.triNormal[k]))
					return false;
				w.ownDist2[k] = std::min(w.ownDist2[k], faceDist2(t, w.centroid[k], f));
			}
		}
	}
	return true;
}

// The input surface nearest to a triangle's centroid must not face away from it (as at a thin
// part, where a straightened border can bring one side next to the other side).
bool nearestSurfaceFacing(const Topology &t, const Scratch &w)
{
	for (size_t k = 0; k < w.ownDist2.size(); ++k) {
		const double r2 = w.ownDist2[k];
		if (!(r2 > 0) || !std::isfinite(r2))
			continue; // on its own faces (or nothing to compare with)
		if (!nearestInputFacing(t, w.centroid[k], w.triNormal[k], std::sqrt(r2)))
			return false;
	}
	return true;
}

// ---- the registry's entries ----------------------------------------------------------------

bool always(const LevelLimits &) { return true; }
bool withDistance(const LevelLimits &l) { return l.maxDistance > 0; }
bool withTexture(const LevelLimits &l) { return l.maxTexError > 0; }

// Normals and centroids of the new triangles; a degenerate one fails the pass (Ring).
Failure framesCheck(SuperfacePass &p)
{
	return triangleFrames(p.in, p.o, p.firstTri, p.w) ? Failure::None : Failure::Ring;
}

Failure deviationCheck(SuperfacePass &p)
{
	if (deviationWithinLimit(p.in, p.s, p.N, p.firstTri, p.o, p.w, p.m))
		return Failure::None;
	p.inside = true;
	return Failure::Deviation;
}

Failure toleranceCheck(SuperfacePass &p)
{
	const Failure far = distanceCheck(p.in, p.s, p.N, p.firstTri, p.w, p.o, p.m.gap);
	p.inside = far == Failure::Distance;
	return far;
}

Failure stretchCheck(SuperfacePass &p)
{
	const Failure stretched = textureCheck(p.in, p.s, p.firstTri, p.w, p.o, p.m.tex);
	p.inside = stretched == Failure::Distance;
	return stretched;
}

// No triangle faces away from the input it stands for (Ring).
Failure facingCheck(SuperfacePass &p)
{
	ownDistances(p.in, p.s, p.o.tris.size() / 3 - p.firstTri, p.w);
	if (!uncoveredFacing(p.in, p.s, p.o, p.firstTri, p.w) || !nearestSurfaceFacing(p.in.t, p.w))
		return Failure::Ring;
	return Failure::None;
}

// The level's reported distance: a bound (DESIGN 23); beyond the tolerance where the bound is the
// limit, tighter borders, then locked ones, close the pockets (Deviation).
Failure boundCheck(SuperfacePass &p)
{
	p.bound = distanceBound(p.in, p.s, p.N, p.firstTri, p.w, p.o, p.m.gap);
	return p.bound > p.in.limits.maxDistance && p.in.limits.boundIsLimit ? Failure::Deviation
	                                                                     : Failure::None;
}

} // namespace

const std::vector<SuperfaceCheck> &superfaceChecks()
{
	static const std::vector<SuperfaceCheck> checks = {
	    {"triangles", always, framesCheck},
	    {"normal deviation", always, deviationCheck},
	    {"distance tolerance", withDistance, toleranceCheck},
	    {"texture stretch", withTexture, stretchCheck},
	    {"facing", always, facingCheck},
	    {"distance bound", withDistance, boundCheck},
	};
	return checks;
}

Failure checkSuperfacePass(SuperfacePass &p)
{
	for (const SuperfaceCheck &c : superfaceChecks()) {
		if (!c.applies(p.in.limits))
			continue;
		const Failure f = c.check(p);
		if (f != Failure::None)
			return f;
	}
	return Failure::None;
}

void writeDeviations(const TriangulationInput &in, int32_t s, Scratch &w, FaceMeasures &m)
{
	const int32_t fb = in.faces.begin(s);
	const size_t ntri = w.triNormal.size();
	for (int32_t i = 0; i < w.devMeasured; ++i) {
		const int32_t k = ntri == 1 ? 0 : w.job.queryTri[size_t(i)];
		if (k < 0)
			continue; // (no triangle over its centroid)
		m.dev[size_t(in.faces.face[size_t(fb + i)])] =
		    float(angleDegOfCos(w.sfNormal[size_t(i)].dot(w.triNormal[size_t(k)])));
	}
	w.devMeasured = 0;
}

bool nearestInputFacing(const Topology &t, const Vec3 &c, const Vec3 &n, double r, double cells)
{
	// (the query box is capped at ~(2 cells)^3 grid cells: a farther other side is not looked
	// for, which bounds the time on strongly curved superfaces of very fine meshes)
	r = std::min(r, cells * t.grid.cell);
	// nearest face facing away (normals first: distances only for those)
	double away = r * r * (1 - 1e-9);
	bool anyAway = false;
	t.grid.forBoxFacingAway(c - Vec3(r, r, r), c + Vec3(r, r, r), n, t.faceNormal, [&](int32_t g) {
		if (facesAway(t, g, n, true)) { // (the grid holds valid faces only)
			const double d2 = faceDist2(t, c, g);
			if (d2 < away)
				away = d2, anyAway = true;
		}
	});
	if (!anyAway)
		return true;
	// flipped unless a face facing it is as near (ties: an edge or vertex both touch)
	const double ra = std::sqrt(away) * (1 + 1e-9);
	bool facing = false;
	t.grid.forBox(c - Vec3(ra, ra, ra), c + Vec3(ra, ra, ra), [&](int32_t g) {
		if (!facing && !facesAway(t, g, n, true)) // (a normal's dot is never NaN)
			facing = faceDist2(t, c, g) <= away * (1 + 1e-9);
	});
	return facing;
}

} // namespace detail
} // namespace gausslod
