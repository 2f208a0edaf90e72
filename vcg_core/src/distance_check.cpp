// Beyond the paper (2.4, Params::maxDistance): the distance tolerance on a re-triangulated
// superface. The removed vertices of its rings are measured against the straightened ring edges;
// each input face against the triangles its centroid and its corners fall in (each vertex located
// once, see Scratch::cornerQuery): the distance of the face to a triangle's plane (along the
// projection direction N where the bound is the limit, see checkDivisor) is linear over the face,
// so its largest value over the part of the face above that triangle is at a corner of that part
// (the face clipped by the triangle, in the projection). A face crossing a triangle that holds
// neither its centroid nor a corner is not seen. A border too far is a Deviation failure (tighter
// tolerances, then a locked border fix it), a face too far a Distance failure (inside vertices,
// then a split fix it): a failing check still looks at every face, and each triangle found too
// far gets a corner of such a face as a candidate for insertFarthest. The distances measured are
// kept per input face (a removed border vertex's on the face of its ring edge) for the level's
// figure.
#include "distance_clip.h"

#include <algorithm>
#include <cmath>

namespace gausslod {
namespace detail {

namespace {

// The removed vertices of superface s's rings against the segments between kept ones.
Failure bordersWithin(const TriangulationInput &in, int32_t s, std::vector<float> &gap)
{
	const Topology &t = in.t;
	bool far = false;
	const bool rings = forRemovedRingVertices(in, s, [&](int32_t j, int32_t a, int32_t c) {
		const int32_t he = in.rings.he[size_t(j)];
		const double d = pointSegmentDistance(t.pos(t.heFrom(he)), in.out(a), in.out(c));
		if (d > in.limits.maxDistance)
			return !(far = true);
		float &g = gap[size_t(heFace(he))];
		g = std::max(g, float(d));
		return true;
	});
	return far ? Failure::Deviation : rings ? Failure::None : Failure::Ring;
}

// Is face i (f, corners P) of the superface farther than the tolerance from new triangle k's
// plane (see checkDivisor)? If not, the largest gap seen is kept in gap[f].
bool faceTooFar(const TriangulationInput &in, int32_t s, size_t i, int32_t f, const Vec3 P[3],
                int32_t k, const Vec3 &N, size_t firstTri, const Scratch &w, const ChunkOut &o,
                std::vector<float> &gap)
{
	const double eps = in.limits.maxDistance;
	const size_t faces = size_t(in.faces.end(s) - in.faces.begin(s));
	const size_t ntri = o.tris.size() / 3 - firstTri;
	const Vec3 &n = w.triNormal[size_t(k)];
	const Vec3 q = in.out(o.tris[3 * (firstTri + size_t(k))]);
	const double nN = checkDivisor(in.limits, n, N);
	double g[3], cornerMax = 0; // the gap at the face's corners to the triangle's plane
	for (int c = 0; c < 3; ++c) {
		g[c] = (P[c] - q).dot(n) / nN;
		cornerMax = std::max(cornerMax, std::fabs(g[c]));
	}
	float &kept = gap[size_t(f)];
	if (cornerMax <= eps || ntri == 1) { // (one triangle, no queries: the corners decide)
		kept = std::max(kept, float(cornerMax));
		return cornerMax > eps;
	}
	double fxy[6]; // the face in 2D (its corners' queries)
	for (int c = 0; c < 3; ++c) {
		const size_t qi = faces + size_t(w.cornerQuery[3 * i + size_t(c)]);
		fxy[2 * c] = w.job.queryXY[2 * qi];
		fxy[2 * c + 1] = w.job.queryXY[2 * qi + 1];
	}
	double poly[2][12][2];
	signed char tag[2][12];
	int cur = 0;
	const int32_t *tv = &w.job.tris[3 * size_t(k)];
	const double *const txy[3] = {&w.job.xy[2 * size_t(tv[0])], &w.job.xy[2 * size_t(tv[1])],
	                              &w.job.xy[2 * size_t(tv[2])]};
	const int cnt = clipByTriangle(fxy, txy, clipSign(txy), poly, tag, cur);
	// the gap at each corner of the clipped part (barycentric in the face)
	const double det =
	    (fxy[2] - fxy[0]) * (fxy[5] - fxy[1]) - (fxy[4] - fxy[0]) * (fxy[3] - fxy[1]);
	if (!(std::fabs(det) > 0))
		return true; // a face seen edge-on in the projection: not measurable, refused
	double clippedMax = 0;
	for (int j = 0; j < cnt; ++j) {
		const double dx = poly[cur][j][0] - fxy[0], dy = poly[cur][j][1] - fxy[1];
		const double b1 = (dx * (fxy[5] - fxy[1]) - dy * (fxy[4] - fxy[0])) / det;
		const double b2 = ((fxy[2] - fxy[0]) * dy - (fxy[3] - fxy[1]) * dx) / det;
		clippedMax = std::max(clippedMax, std::fabs((1 - b1 - b2) * g[0] + b1 * g[1] + b2 * g[2]));
	}
	if (clippedMax > eps)
		return true;
	kept = std::max(kept, float(clippedMax));
	return false;
}

} // namespace

Failure distanceCheck(const TriangulationInput &in, int32_t s, const Vec3 &N, size_t firstTri,
                      Scratch &w, const ChunkOut &o, std::vector<float> &gap)
{
	const Failure border = bordersWithin(in, s, gap);
	if (border != Failure::None)
		return border;
	const size_t ntri = o.tris.size() / 3 - firstTri;
	const size_t faces = size_t(in.faces.end(s) - in.faces.begin(s));
	const Topology &t = in.t;
	// once a face is too far, the others are still looked at (insertion follows): each triangle
	// too far from a face gets a corner of it to insert (w.farCorner)
	bool far = false;
	if (ntri > 1)
		w.farCorner.assign(ntri, std::make_pair(-1.0, int32_t(-1)));
	for (size_t i = 0; i < faces; ++i) {
		const int32_t f = in.faces.face[size_t(in.faces.begin(s)) + i];
		const Vec3 P[3] = {t.pos(t.T[3 * f]), t.pos(t.T[3 * f + 1]), t.pos(t.T[3 * f + 2])};
		auto tooFar = [&](size_t, int32_t k) {
			return faceTooFar(in, s, i, f, P, k, N, firstTri, w, o, gap);
		};
		if (ntri == 1) { // (no triangulation was run)
			if (tooFar(i, 0))
				return Failure::Distance;
			continue;
		}
		const int32_t *cq = &w.cornerQuery[3 * i];
		const int32_t under[4] = {w.job.queryTri[i], w.job.queryTri[faces + size_t(cq[0])],
		                          w.job.queryTri[faces + size_t(cq[1])],
		                          w.job.queryTri[faces + size_t(cq[2])]};
		for (int j = 0; j < 4; ++j) {
			const int32_t k = under[j];
			if (k < 0 || std::find(under, under + j, k) != under + j)
				continue;
			if (tooFar(i, k)) {
				far = true;
				for (int c = 0; c < 3; ++c)
					offerInsertion(in, w, o, firstTri, N, k, t.T[3 * f + c],
					               w.farCorner[size_t(k)]);
			}
		}
	}
	return far ? Failure::Distance : Failure::None;
}

} // namespace detail
} // namespace gausslod
