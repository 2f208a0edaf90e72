// Beyond the paper (DESIGN 23, Params::maxDistance): the distance bound of a re-triangulated
// superface, both ways between its input faces and its new triangles (see distanceBound).
#include "distance_clip.h"

#include <algorithm>
#include <cmath>

namespace gausslod {
namespace detail {

namespace {

// A distance kept as a float, rounded up (a bound must stay a bound).
inline float roundedUp(double d) { return float(d * (1 + 1e-6)); }

// One input face of the superface against the new triangles (DistanceBound::measureFace): its
// corners in 3D and in the projection, and what the triangles over it cover and their gap.
struct FaceOverlap {
	Vec3 P[3];
	double fxy[6];
	double det = 0, area = 0; ///< twice its signed projected area; its projected area
	double covered = 0, gap = 0;
	int32_t located[3]; ///< the triangles the check located its corners in (-1: none)
};

// The steps of distanceBound on one superface (see there).
class DistanceBound {
public:
	DistanceBound(const TriangulationInput &in, int32_t s, const Vec3 &N, size_t firstTri,
	              Scratch &w, const ChunkOut &o, std::vector<float> &bound)
	    : in_(in), t_(in.t), s_(s), N_(N), w_(w), bound_(bound),
	      ntri_(o.tris.size() / 3 - firstTri), tri_(&o.tris[3 * firstTri]), U_(planeAxis(N)),
	      V_(N ^ U_), origin_(in.out(tri_[0])), fb_(in.faces.begin(s)),
	      faces_(size_t(in.faces.end(s) - fb_)),
	      // the check's projection (same N, U, V), if it ran: every vertex is projected once
	      job_(ntri_ > 1 && w.cornerQuery.size() == 3 * faces_ && w.job.tris.size() == 3 * ntri_ &&
	           w.job.queryTri.size() >= faces_)
	{
	}
	double run();

private:
	const TriangulationInput &in_;
	const Topology &t_;
	const int32_t s_;
	const Vec3 &N_;
	Scratch &w_;
	std::vector<float> &bound_;
	const size_t ntri_;
	const int32_t *tri_;
	const Vec3 U_, V_, origin_;
	const int32_t fb_;
	const size_t faces_;
	const bool job_;
	TriangleGrid grid_;
	bool gridBuilt_ = false;      ///< (only faces over several triangles need it)
	double dv_ = 0, sfBound_ = 0; ///< the largest gap; the superface's bound so far

	void project(const Vec3 &p, double *xy) const
	{
		const Vec3 q = p - origin_;
		xy[0] = q.dot(U_), xy[1] = q.dot(V_);
	}
	void prepareTriangles();
	void newStamp()
	{
		if (++w_.stampNow == 0) { // (wrapped: clear the stamps)
			std::fill(w_.triStamp.begin(), w_.triStamp.end(), 0u);
			w_.stampNow = 1;
		}
	}
	// the triangles whose 2D bounding box meets the face's, each once (since newStamp()); fn(k)
	// false stops
	template <class Fn>
	void forNear(const double fxy[6], Fn fn)
	{
		Scratch &w = w_;
		if (!gridBuilt_) {
			grid_.build(w.boundXY.data(), ntri_, w);
			gridBuilt_ = true;
		}
		const double lo[2] = {std::min({fxy[0], fxy[2], fxy[4]}),
		                      std::min({fxy[1], fxy[3], fxy[5]})};
		const double hi[2] = {std::max({fxy[0], fxy[2], fxy[4]}),
		                      std::max({fxy[1], fxy[3], fxy[5]})};
		for (int y = grid_.at(lo[1], 1); y <= grid_.at(hi[1], 1); ++y)
			for (int x = grid_.at(lo[0], 0); x <= grid_.at(hi[0], 0); ++x) {
				const size_t c = size_t(y) * size_t(grid_.side) + size_t(x);
				for (int32_t q = w.cellStart[c]; q < w.cellStart[c + 1]; ++q) {
					const size_t k = size_t(w.cellTri[size_t(q)]);
					if (w.triStamp[k] == w.stampNow)
						continue;
					w.triStamp[k] = w.stampNow;
					const double *tv = &w.boundXY[6 * k];
					if (std::max({tv[0], tv[2], tv[4]}) < lo[0] ||
					    std::min({tv[0], tv[2], tv[4]}) > hi[0] ||
					    std::max({tv[1], tv[3], tv[5]}) < lo[1] ||
					    std::min({tv[1], tv[3], tv[5]}) > hi[1])
						continue;
					if (!fn(k))
						return;
				}
			}
	}
	// face i's corners (i: position in s's faces)
	void faceCorners(int32_t i, Vec3 P[3], double fxy[6]) const
	{
		const int32_t f = in_.faces.face[size_t(i)];
		for (int c = 0; c < 3; ++c) {
			P[c] = t_.pos(t_.T[3 * f + c]);
			if (job_) {
				const size_t q = faces_ + size_t(w_.cornerQuery[3 * size_t(i - fb_) + size_t(c)]);
				fxy[2 * c] = w_.job.queryXY[2 * q], fxy[2 * c + 1] = w_.job.queryXY[2 * q + 1];
			} else {
				project(P[c], &fxy[2 * c]);
			}
		}
	}
	// the triangles the check located a face's corners in (-1: none)
	void cornersLocated(int32_t i, int32_t k[3]) const
	{
		for (int c = 0; c < 3; ++c)
			k[c] = ntri_ == 1 ? 0
			       : job_     ? w_.job.queryTri[faces_ +
                                            size_t(w_.cornerQuery[3 * size_t(i - fb_) + size_t(c)])]
			                  : -1;
	}
	double borderWidth() const;
	bool overlap(size_t k, FaceOverlap &fo);
	void measureFace(int32_t i, double &cosIn);
	void outwardPockets(double wb, double cosIn);
	void inwardPockets(double wb);
};

// Per triangle, once: its projection, area, orientation for the clipping, n . N.
void DistanceBound::prepareTriangles()
{
	Scratch &w = w_;
	const size_t ntri = ntri_;
	w.boundXY.resize(6 * ntri);
	w.triArea.resize(ntri);
	w.triCovered.assign(ntri, 0.0);
	w.triSign.resize(ntri);
	w.triNN.resize(ntri);
	for (size_t k = 0; k < ntri; ++k) {
		for (size_t c = 0; c < 3; ++c) {
			double *xy = &w.boundXY[6 * k + 2 * c];
			if (job_)
				xy[0] = w.job.xy[2 * size_t(w.job.tris[3 * k + c])],
				xy[1] = w.job.xy[2 * size_t(w.job.tris[3 * k + c]) + 1];
			else
				project(in_.out(tri_[3 * k + c]), xy);
		}
		const double *xy = &w.boundXY[6 * k];
		w.triArea[k] = 0.5 * std::fabs(orient2(xy, xy + 2, xy + 4));
		const double *const tv[3] = {xy, xy + 2, xy + 4};
		w.triSign[k] = int8_t(clipSign(tv));
		w.triNN[k] = w.triNormal[k].dot(N_);
	}
	if (w.triStamp.size() < ntri)
		w.triStamp.resize(ntri, 0);
}

// The border chains' vertices' distances from their segments: the removed ones', and the kept
// ones' from where they were placed (placement.cpp; 0 otherwise).
double DistanceBound::borderWidth() const
{
	const TriangulationInput &in = in_;
	const Topology &t = t_;
	double wb = 0;
	forRemovedRingVertices(in, s_, [&](int32_t j, int32_t a, int32_t c) {
		wb = std::max(wb, pointSegmentDistance(t.pos(t.heFrom(in.rings.he[size_t(j)])), in.out(a),
		                                       in.out(c)));
		return true;
	});
	if (in.placedSlot)
		for (int32_t i = in.rings.start[size_t(in.rings.sfStart[size_t(s_)])];
		     i < in.rings.start[size_t(in.rings.sfStart[size_t(s_) + 1])]; ++i) {
			const int32_t v = t.heFrom(in.rings.he[size_t(i)]);
			if (in.b.keep[size_t(v)])
				wb = std::max(wb, in.moved(v));
		}
	return wb;
}

// The face against triangle k: the part of it over k (clipped), its gap there; false once the
// face is known to be above k only.
bool DistanceBound::overlap(size_t k, FaceOverlap &fo)
{
	Scratch &w = w_;
	const double *fxy = fo.fxy;
	const Vec3 &n = w.triNormal[k];
	const double nN = w.triNN[k];
	if (!(std::fabs(nN) > 1e-12))
		return true; // (seen edge-on: covers nothing in the projection)
	double g[3];     // the gap of each corner of the face to the triangle's plane, along N
	auto gaps = [&] {
		const Vec3 q0 = in_.out(tri_[3 * k]);
		for (int c = 0; c < 3; ++c)
			g[c] = (fo.P[c] - q0).dot(n) / nN;
	};
	const double *tv[3] = {&w.boundXY[6 * k], &w.boundXY[6 * k + 2], &w.boundXY[6 * k + 4]};
	// (the corners not located in k first: where one is outside, it most likely is)
	int order[3], next = 0;
	for (int c = 0; c < 3; ++c)
		if (fo.located[c] != int32_t(k))
			order[next++] = c;
	for (int c = 0; c < 3; ++c)
		if (fo.located[c] == int32_t(k))
			order[next++] = c;
	if (insideTriangle(&fxy[2 * order[0]], tv) && insideTriangle(&fxy[2 * order[1]], tv) &&
	    insideTriangle(&fxy[2 * order[2]], tv)) { // the face is above this triangle only
		gaps();
		fo.gap = std::max({fo.gap, std::fabs(g[0]), std::fabs(g[1]), std::fabs(g[2])});
		fo.covered = fo.area;
		w.triCovered[k] += fo.area;
		return false;
	}
	if (!(fo.area > 0))
		return true;
	double poly[2][12][2];
	signed char tag[2][12];
	int cur = 0;
	const int cnt = clipByTriangle(fxy, tv, w.triSign[k], poly, tag, cur);
	if (cnt == 0)
		return true; // (no overlap: nothing covered, no gap)
	gaps();
	const double det = fo.det;
	double area2 = 0;
	for (int j = 0; j < cnt; ++j) {
		const double *a = poly[cur][j], *b = poly[cur][j + 1 == cnt ? 0 : j + 1];
		area2 += a[0] * b[1] - a[1] * b[0];
		// (at a face corner, the barycentric expression below gives that corner's gap
		// exactly: its weights come out as exactly 1 and 0)
		if (tag[cur][j] >= 0) {
			fo.gap = std::max(fo.gap, std::fabs(g[size_t(tag[cur][j])]));
			continue;
		}
		const double dx = a[0] - fxy[0], dy = a[1] - fxy[1];
		const double b1 = (dx * (fxy[5] - fxy[1]) - dy * (fxy[4] - fxy[0])) / det;
		const double b2 = ((fxy[2] - fxy[0]) * dy - (fxy[3] - fxy[1]) * dx) / det;
		fo.gap = std::max(fo.gap, std::fabs((1 - b1 - b2) * g[0] + b1 * g[1] + b2 * g[2]));
	}
	fo.covered += 0.5 * std::fabs(area2);
	w.triCovered[k] += 0.5 * std::fabs(area2);
	return true;
}

// Input face i (its position in s's faces) against the triangles over it: its gap bounds it (in
// bound_); a face with a part outside the outline goes to w.boundCand, its slope into cosIn.
void DistanceBound::measureFace(int32_t i, double &cosIn)
{
	Scratch &w = w_;
	const int32_t f = in_.faces.face[size_t(i)];
	FaceOverlap fo;
	faceCorners(i, fo.P, fo.fxy);
	fo.det = orient2(&fo.fxy[0], &fo.fxy[2], &fo.fxy[4]);
	fo.area = 0.5 * std::fabs(fo.det);
	// the triangles its corners are in first; if they cover it, no other can overlap it
	cornersLocated(i, fo.located);
	newStamp();
	bool more = true;
	for (int c = 0; c < 3 && more; ++c) {
		const int32_t k = fo.located[c];
		if (k < 0 || w.triStamp[size_t(k)] == w.stampNow)
			continue;
		w.triStamp[size_t(k)] = w.stampNow;
		more = overlap(size_t(k), fo) && !(fo.covered >= fo.area * (1 - 1e-12) && fo.area > 0);
	}
	if (more)
		forNear(fo.fxy, [&](size_t k) { return overlap(k, fo); });
	dv_ = std::max(dv_, fo.gap);
	sfBound_ = std::max(sfBound_, fo.gap);
	bound_[size_t(f)] = std::max(bound_[size_t(f)], roundedUp(std::min(fo.gap, w.boundCap)));
	if (!(fo.area > 0) || fo.covered < fo.area * (1 - 1e-10)) {
		w.boundCand.push_back(i);
		const Vec3 n = (fo.P[1] - fo.P[0]) ^ (fo.P[2] - fo.P[0]);
		cosIn = std::min(cosIn, n.Norm() > 0 ? n.dot(N_) / n.Norm() : 0.0);
	}
}

// The faces with a part outside the outline (w.boundCand): within the pocket's width along the
// input faces, or within their corners' largest distance to a triangle near them.
void DistanceBound::outwardPockets(double wb, double cosIn)
{
	const double outward = wb > 0 && cosIn > 0 ? wb / cosIn + wb : HUGE_VAL;
	for (const int32_t i : w_.boundCand) {
		const int32_t f = in_.faces.face[size_t(i)];
		Vec3 P[3];
		double fxy[6];
		faceCorners(i, P, fxy);
		double best = outward * outward; // (squared)
		auto convex = [&](size_t k) {
			const int32_t *v = &tri_[3 * k];
			double m = 0;
			for (int c = 0; c < 3 && m < best; ++c)
				m = std::max(
				    m, pointTriangleDistance2(P[c], in_.out(v[0]), in_.out(v[1]), in_.out(v[2])));
			best = std::min(best, m);
			return true;
		};
		newStamp(); // (every triangle near this face, whatever the faces before saw)
		forNear(fxy, convex);
		if (!(best < HUGE_VAL))
			for (size_t k = 0; k < ntri_; ++k)
				convex(k);
		const double d = std::sqrt(best);
		bound_[size_t(f)] = std::max(bound_[size_t(f)], roundedUp(std::min(d, w_.boundCap)));
		sfBound_ = std::max(sfBound_, d);
	}
}

// The triangles with a part above no face: within the pocket's width along them plus the gap,
// or within their longest edge of a vertex.
void DistanceBound::inwardPockets(double wb)
{
	const Scratch &w = w_;
	double cosOut = 1, longest = 0;
	bool inward = false;
	for (size_t k = 0; k < ntri_; ++k) {
		if (w.triCovered[k] >= w.triArea[k] * (1 - 1e-10) && w.triArea[k] > 0)
			continue;
		inward = true;
		cosOut = std::min(cosOut, std::fabs(w.triNormal[k].dot(N_)));
		// (each point of the triangle is within its longest edge of a vertex, an input vertex
		// or one placed that far from it)
		double edge = 0, placed = 0;
		for (size_t c = 0; c < 3; ++c) {
			edge = std::max(edge,
			                (in_.out(tri_[3 * k + c]) - in_.out(tri_[3 * k + (c + 1) % 3])).Norm());
			placed = std::max(placed, in_.moved(tri_[3 * k + c]));
		}
		longest = std::max(longest, edge + placed);
	}
	if (inward) {
		const double d = std::min(cosOut > 0 ? wb / cosOut + dv_ : HUGE_VAL, longest);
		const size_t f0 = size_t(in_.faces.face[size_t(fb_)]);
		bound_[f0] = std::max(bound_[f0], roundedUp(std::min(d, w.boundCap)));
		sfBound_ = std::max(sfBound_, d);
	}
}

double DistanceBound::run()
{
	prepareTriangles();
	const double wb = borderWidth();
	double cosIn = 1;
	w_.boundCand.clear(); // here: the faces with a part outside the outline
	for (int32_t i = fb_; i < in_.faces.end(s_); ++i)
		measureFace(i, cosIn);
	outwardPockets(wb, cosIn);
	inwardPockets(wb);
	return std::min(sfBound_, w_.boundCap);
}

} // namespace

// Beyond the paper (DESIGN 23): an upper bound on the distance, both ways, between the input
// faces of superface s and its new triangles, kept per input face in `bound` (the level's figure
// is the largest; rounded up). Along N, the gap between an input face and a new triangle is linear
// where their projections overlap, so its largest value there is at a corner of the overlap:
// every overlapping pair (found with a grid over the triangles) is clipped, and the largest gap,
// dv, bounds the distance of every point of a face above a triangle and of every point of a
// triangle above a face. What is left are the pockets between a border chain and the segment
// that replaced it, where a point is within wb (the largest distance of a removed border vertex
// from its segment, or of a placed border vertex from its input position) of the chain in the
// projection:
//  - a face with a part outside the straightened outline (an outward pocket): that part is
//    within wb / cos(theta_in) of the chain along the input faces (theta_in: the largest angle
//    between N and an input face over a pocket), and the chain within wb of its segment, an edge
//    of the new triangles; or, the distance to one triangle being convex, the whole face is
//    within the largest of its corners' distances to a triangle near it (the smaller of both);
//  - a triangle with a part above no face (an inward pocket): within wb / cos(theta_out) of the
//    chain along the new triangles over the pocket, and the chain within dv of them; or within
//    the triangle's longest edge of one of its vertices, which are input vertices (or, placed
//    (placement.cpp), that far from one more).
// The argument assumes what the checks before it establish: the input faces of the superface
// and its new triangles each project one-to-one onto the plane orthogonal to N. Placed vertices
// (placement.cpp) give a second bound, w.boundCap: the superface's bound as accepted plus the
// largest move of its vertices (a point of a moved triangle is within that move of the point of
// the triangle before, with the same barycentric coordinates); the smaller of the two holds.
// Returns the superface's bound (mesh units).
double distanceBound(const TriangulationInput &in, int32_t s, const Vec3 &N, size_t firstTri,
                     Scratch &w, const ChunkOut &o, std::vector<float> &bound)
{
	if (w.boundCap <= w.boundEnough) { // (the other bound is all the caller needs)
		const size_t f0 = size_t(in.faces.face[size_t(in.faces.begin(s))]);
		bound[f0] = std::max(bound[f0], roundedUp(w.boundCap));
		return w.boundCap;
	}
	return DistanceBound(in, s, N, firstTri, w, o, bound).run();
}

} // namespace detail
} // namespace gausslod
