// Beyond the paper (Params::maxTexError, MeshView::cornerUV): the texture-stretch check on a
// re-triangulated superface. Output vertices are input vertices and keep their texture
// coordinates, so what changes is what the new triangles interpolate where a vertex was removed.
// Each removed vertex is compared, in texture space, with that interpolation: a removed border
// vertex with the straightened segment that replaces it (linear along the segment, at its
// nearest point), an interior one with the triangle its projection falls in (barycentric
// coordinates of its orthogonal projection on the triangle's plane; a vertex outside every
// triangle uses the triangle under its face's centroid, extended linearly). Beyond the limit, a
// border vertex is a Deviation failure (tighter borders, then locked ones), an interior one a
// Distance failure (only a split brings it back). The largest error is kept per input face.
#include "level_passes.h"

namespace gausslod {
namespace detail {

namespace {

struct UV {
	double u = 0, v = 0;
};

UV cornerUV(const Topology &t, int32_t corner)
{
	return {double(t.UV[2 * size_t(corner)]), double(t.UV[2 * size_t(corner) + 1])};
}

double uvGap(const UV &a, const UV &b) { return std::hypot(a.u - b.u, a.v - b.v); }

// Keeps `err` for face f; false if it is beyond the limit (or not a number).
bool within(double err, double limit, int32_t f, std::vector<float> &tex)
{
	if (!(err <= limit))
		return false;
	float &kept = tex[size_t(f)];
	kept = std::max(kept, float(err));
	return true;
}

// The removed vertices of superface s's rings against the segments between kept ones.
bool bordersWithin(const TriangulationInput &in, int32_t s, std::vector<float> &tex)
{
	const Topology &t = in.t;
	const Rings &rings = in.rings;
	const double limit = in.limits.maxTexError;
	auto heAt = [&](int32_t i) { return rings.he[size_t(i)]; };
	for (int32_t r = rings.sfStart[size_t(s)]; r < rings.sfStart[size_t(s) + 1]; ++r) {
		const int32_t b = rings.start[size_t(r)], e = rings.start[size_t(r) + 1];
		int32_t first = b;
		while (first < e && !in.b.keep[size_t(t.heFrom(heAt(first)))])
			++first;
		if (first == e)
			return true; // (no kept vertex: the triangulation has failed already)
		int32_t a = heAt(first), run = 0, runStart = 0;
		for (int32_t step = 1; step <= e - b; ++step) {
			const int32_t i = b + (first - b + step) % (e - b);
			const int32_t h = heAt(i);
			if (!in.b.keep[size_t(t.heFrom(h))]) {
				if (run++ == 0)
					runStart = i;
				continue;
			}
			const Vec3 pa = in.out(t.heFrom(a)), ac = in.out(t.heFrom(h)) - pa;
			const UV ua = cornerUV(t, a), uc = cornerUV(t, h);
			const double len2 = ac.SquaredNorm();
			for (int32_t k = 0; k < run; ++k) {
				const int32_t j = heAt(b + (runStart - b + k) % (e - b));
				double tau = len2 > 0 ? (t.pos(t.heFrom(j)) - pa).dot(ac) / len2 : 0;
				tau = std::min(1.0, std::max(0.0, tau));
				const UV at{ua.u + tau * (uc.u - ua.u), ua.v + tau * (uc.v - ua.v)};
				if (!within(uvGap(cornerUV(t, j), at), limit, heFace(j), tex))
					return false;
			}
			a = h, run = 0;
		}
	}
	return true;
}

// Texture coordinates that triangle k (from firstTri; corners ring[k]) interpolates at p.
UV interpolate(const TriangulationInput &in, const ChunkOut &o, size_t firstTri, int32_t k,
               const UV ring[3], const Vec3 &p)
{
	const int32_t *v = &o.tris[3 * (firstTri + size_t(k))];
	const Vec3 a = in.out(v[0]), e1 = in.out(v[1]) - a, e2 = in.out(v[2]) - a, q = p - a;
	const double d11 = e1.dot(e1), d12 = e1.dot(e2), d22 = e2.dot(e2);
	const double q1 = q.dot(e1), q2 = q.dot(e2), den = d11 * d22 - d12 * d12;
	const double b1 = den != 0 ? (d22 * q1 - d12 * q2) / den : 0;
	const double b2 = den != 0 ? (d11 * q2 - d12 * q1) / den : 0;
	const double b0 = 1 - b1 - b2;
	return {b0 * ring[0].u + b1 * ring[1].u + b2 * ring[2].u,
	        b0 * ring[0].v + b1 * ring[1].v + b2 * ring[2].v};
}

} // namespace

Failure textureCheck(const TriangulationInput &in, int32_t s, size_t firstTri, const Scratch &w,
                     const ChunkOut &o, std::vector<float> &tex)
{
	if (!bordersWithin(in, s, tex))
		return Failure::Deviation;
	const Topology &t = in.t;
	const size_t ntri = o.tris.size() / 3 - firstTri;
	const int32_t fb = in.faces.begin(s);
	const size_t faces = size_t(in.faces.end(s) - fb);
	for (size_t i = 0; i < faces; ++i) {
		const int32_t f = in.faces.face[size_t(fb) + i];
		for (int c = 0; c < 3; ++c) {
			const int32_t v = t.T[3 * f + c];
			if (in.b.keep[size_t(v)] || in.b.degree[size_t(v)] > 0)
				continue;  // kept, or on a ring (bordersWithin)
			int32_t k = 0; // (one triangle: no queries were located)
			if (ntri > 1) {
				k = w.job.queryTri[faces + size_t(w.cornerQuery[3 * i + size_t(c)])];
				if (k < 0)
					k = w.job.queryTri[i];
				if (k < 0)
					continue; // (neither located: the deviation check has seen this face)
			}
			UV ring[3];
			for (int j = 0; j < 3; ++j) {
				const size_t r =
				    ntri > 1 ? size_t(w.job.tris[3 * size_t(k) + size_t(j)]) : size_t(j);
				ring[j] = {double(w.ringUV[2 * r]), double(w.ringUV[2 * r + 1])};
			}
			const UV at = interpolate(in, o, firstTri, k, ring, t.pos(v));
			if (!within(uvGap(cornerUV(t, 3 * f + c), at), in.limits.maxTexError, f, tex))
				return Failure::Distance;
		}
	}
	return Failure::None;
}

} // namespace detail
} // namespace gausslod
