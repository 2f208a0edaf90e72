// Beyond the paper (2.4, Params::maxDistance): the distance tolerance on a re-triangulated
// superface. The removed vertices of its rings are measured against the straightened ring edges;
// each input face against the triangles its centroid and its corners fall in (each vertex located
// once, see Scratch::cornerQuery): along the projection direction N, the gap between the face and
// a triangle's plane is linear over the face, so its largest value over the part of the face above
// that triangle is at a corner of that part (the face clipped by the triangle, in the projection).
// A face crossing a triangle that holds neither its centroid nor a corner is not seen. A border
// too far is a Deviation failure (tighter tolerances, then a locked border fix it), a face too far
// a Distance failure (only a split fixes it). The distances measured are kept per input face (a
// removed border vertex's on the face of its ring edge) for the level's figure.
#include "level_passes.h"

namespace gausslod {
namespace detail {

namespace {

// The removed vertices of superface s's rings against the segments between kept ones.
Failure bordersWithin(const TriangulationInput &in, int32_t s, std::vector<float> &gap)
{
	const Topology &t = in.t;
	const Rings &rings = in.rings;
	auto from = [&](int32_t i) { return t.heFrom(rings.he[size_t(i)]); };
	for (int32_t r = rings.sfStart[size_t(s)]; r < rings.sfStart[size_t(s) + 1]; ++r) {
		const int32_t b = rings.start[size_t(r)], e = rings.start[size_t(r) + 1];
		int32_t first = b; // a kept vertex to start from (a ring keeps at least 3)
		while (first < e && !in.b.keep[size_t(from(first))])
			++first;
		if (first == e)
			return Failure::Ring;
		Vec3 a = t.pos(from(first));
		int32_t runStart = 0; // removed vertices since the last kept one: positions in ring
		for (int32_t step = 1, run = 0; step <= e - b; ++step) {
			const int32_t i = b + (first - b + step) % (e - b);
			const int32_t v = from(i);
			if (!in.b.keep[size_t(v)]) {
				if (run++ == 0)
					runStart = i;
				continue;
			}
			const Vec3 c = t.pos(v);
			for (int32_t k = 0; k < run; ++k) {
				const int32_t j = b + (runStart - b + k) % (e - b);
				const double d = pointSegmentDistance(t.pos(from(j)), a, c);
				if (d > in.limits.maxDistance)
					return Failure::Deviation;
				float &g = gap[size_t(heFace(rings.he[size_t(j)]))];
				g = std::max(g, float(d));
			}
			a = c, run = 0;
		}
	}
	return Failure::None;
}

// Face f (2D corners fxy) clipped by the 2D triangle tv (Sutherland-Hodgman): its corners in
// poly[cur][0 .. cnt).
int clipByTriangle(const double fxy[6], const std::vector<double> &xy, const int32_t *tv,
                   double poly[2][12][2], int &cur)
{
	int cnt = 3;
	for (int c = 0; c < 3; ++c)
		poly[0][c][0] = fxy[2 * c], poly[0][c][1] = fxy[2 * c + 1];
	double area = 0; // of the triangle, for its orientation
	for (int e = 0; e < 3; ++e) {
		const double *a = &xy[2 * size_t(tv[e])], *b = &xy[2 * size_t(tv[(e + 1) % 3])];
		area += a[0] * b[1] - a[1] * b[0];
	}
	const double sign = area >= 0 ? 1.0 : -1.0;
	cur = 0;
	for (int e = 0; e < 3 && cnt > 0; ++e) {
		const double *a = &xy[2 * size_t(tv[e])], *b = &xy[2 * size_t(tv[(e + 1) % 3])];
		auto side = [&](const double *x) {
			return sign * ((b[0] - a[0]) * (x[1] - a[1]) - (b[1] - a[1]) * (x[0] - a[0]));
		};
		int out = 0;
		for (int j = 0; j < cnt; ++j) {
			const double *x = poly[cur][j], *y = poly[cur][(j + 1) % cnt];
			const double sx = side(x), sy = side(y);
			if (sx >= 0 && out < 12)
				poly[1 - cur][out][0] = x[0], poly[1 - cur][out++][1] = x[1];
			if (((sx >= 0) != (sy >= 0)) && out < 12) {
				const double u = sx / (sx - sy);
				poly[1 - cur][out][0] = x[0] + u * (y[0] - x[0]);
				poly[1 - cur][out++][1] = x[1] + u * (y[1] - x[1]);
			}
		}
		cnt = out, cur = 1 - cur;
	}
	return cnt;
}

// Is face i of the superface farther than the tolerance from new triangle k, along N? If not,
// the largest gap seen is kept in gap[f].
bool faceTooFar(const TriangulationInput &in, int32_t s, size_t i, int32_t k, const Vec3 &N,
                size_t firstTri, const Scratch &w, const ChunkOut &o, std::vector<float> &gap)
{
	const Topology &t = in.t;
	const double eps = in.limits.maxDistance;
	const size_t faces = size_t(in.faces.end(s) - in.faces.begin(s));
	const size_t ntri = o.tris.size() / 3 - firstTri;
	const int32_t f = in.faces.face[size_t(in.faces.begin(s)) + i];
	const Vec3 &n = w.triNormal[size_t(k)];
	const Vec3 &q = t.pos(o.tris[3 * (firstTri + size_t(k))]);
	const double nN = n.dot(N);
	double g[3], cornerMax = 0; // the gap at the face's corners to the triangle's plane
	for (int c = 0; c < 3; ++c) {
		g[c] = (t.pos(t.T[3 * f + c]) - q).dot(n) / nN;
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
	int cur = 0;
	const int cnt = clipByTriangle(fxy, w.job.xy, &w.job.tris[3 * size_t(k)], poly, cur);
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
                      const Scratch &w, const ChunkOut &o, std::vector<float> &gap)
{
	const Failure border = bordersWithin(in, s, gap);
	if (border != Failure::None)
		return border;
	const size_t ntri = o.tris.size() / 3 - firstTri;
	const size_t faces = size_t(in.faces.end(s) - in.faces.begin(s));
	auto tooFar = [&](size_t i, int32_t k) {
		return faceTooFar(in, s, i, k, N, firstTri, w, o, gap);
	};
	for (size_t i = 0; i < faces; ++i) {
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
			if (tooFar(i, k))
				return Failure::Distance;
		}
	}
	return Failure::None;
}

} // namespace detail
} // namespace gausslod
