// Beyond the paper (docs/DESIGN.md, 50, 51): a level as the next level's collapses start from it,
// and the measures that compare levels made different ways: nearest triangles of a level, found in
// a uniform grid over its triangles.
#include "level_collapse.h"
#include "level_passes.h"

namespace gausslod {
namespace detail {

NormalCone mergeCones(const NormalCone &a, const NormalCone &b)
{
	const double d = angleDeg(a.axis, b.axis);
	if (d + b.half <= a.half)
		return a;
	if (d + a.half <= b.half)
		return b;
	const double half = 0.5 * (d + a.half + b.half);
	if (half >= 180)
		return {a.axis, 180};
	Vec3 w = b.axis - a.axis * b.axis.dot(a.axis);
	const double wl = w.Norm();
	if (wl < 1e-15)
		return {a.axis, half};
	w /= wl;
	const double r = (half - a.half) * M_PI / 180; // (a's axis turned towards b's by this)
	Vec3 axis = a.axis * std::cos(r) + w * std::sin(r);
	axis.Normalize();
	return {axis, half};
}

void collapseSourceOf(const Topology &t, LevelMesh lm, CollapseSource &out)
{
	out.clear();
	const size_t nT = lm.triangles.size() / 3;
	size_t sfCount = 0;
	for (int32_t s : lm.superface)
		sfCount = std::max(sfCount, size_t(s) + 1);
	std::vector<NormalCone> cone(sfCount);
	std::vector<uint8_t> seen(sfCount, 0);
	for (size_t f = 0; f < t.nF && f < lm.inputSuperface.size(); ++f) {
		const int32_t s = lm.inputSuperface[f];
		if (s < 0 || !t.faceValid[f])
			continue;
		const NormalCone c{t.faceNormal[f], 0};
		cone[size_t(s)] = seen[size_t(s)] ? mergeCones(cone[size_t(s)], c) : c;
		seen[size_t(s)] = 1;
	}
	out.cone.resize(nT);
	for (size_t f = 0; f < nT; ++f) {
		const int32_t s = lm.superface[f];
		if (seen[size_t(s)]) {
			out.cone[f] = cone[size_t(s)];
		} else { // (a superface of invalid input faces only: the triangle's own normal)
			const Vec3 &a = Vec3(&lm.positions[3 * size_t(lm.triangles[3 * f])]);
			const Vec3 &b = Vec3(&lm.positions[3 * size_t(lm.triangles[3 * f + 1])]);
			const Vec3 &c = Vec3(&lm.positions[3 * size_t(lm.triangles[3 * f + 2])]);
			Vec3 n = (b - a) ^ (c - a);
			n.Normalize();
			out.cone[f] = {n, 0};
		}
	}
	out.bound.resize(nT);
	const bool perSuperface = lm.superfaceBound.size() == sfCount;
	out.unbounded = !perSuperface && lm.stats.distanceBound < 0;
	for (size_t f = 0; f < nT; ++f) // (float bounds: the next float up, to stay bounds)
		out.bound[f] =
		    perSuperface ? double(std::nextafter(lm.superfaceBound[size_t(lm.superface[f])], 3e38f))
		                 : std::max(0.0, lm.stats.distanceBound);
	out.mesh = std::move(lm);
}

namespace {

constexpr size_t kFarthestSample = 16384; // input vertices farthestInputVertex looks at, at most
constexpr size_t kMeasuredFaces = 16384;  // input faces measureNormalDeviation looks at, at most

// A uniform grid over a level's triangles' boxes, about 2 triangles per cell (hashed into
// buckets), for "which triangle is nearest this point" queries.
class NearestTriangles {
public:
	NearestTriangles(const LevelMesh &level, double minCell) : L_(level)
	{
		const size_t nT = level.triangles.size() / 3;
		lo_ = P(0);
		Vec3 hi = lo_;
		for (size_t v = 0; v < level.positions.size() / 3; ++v)
			for (int k = 0; k < 3; ++k) {
				lo_[k] = std::min(lo_[k], level.positions[3 * v + size_t(k)]);
				hi[k] = std::max(hi[k], level.positions[3 * v + size_t(k)]);
			}
		double area = 0;
		for (size_t f = 0; f < nT; ++f)
			area += ((P(tri(f, 1)) - P(tri(f, 0))) ^ (P(tri(f, 2)) - P(tri(f, 0)))).Norm();
		cell_ = std::max(std::sqrt(area / double(std::max<size_t>(nT, 1))), minCell);
		buckets_ = 1;
		while (buckets_ < 2 * nT)
			buckets_ <<= 1;
		fillBuckets<int32_t>(
		    buckets_,
		    [&](auto emit) {
			    for (size_t f = 0; f < nT; ++f) {
				    Vec3 a = P(tri(f, 0)), b = a;
				    for (int k = 1; k < 3; ++k)
					    for (int j = 0; j < 3; ++j)
						    a[j] = std::min(a[j], P(tri(f, k))[j]),
						    b[j] = std::max(b[j], P(tri(f, k))[j]);
				    forCells(a, b, [&](uint64_t c) { emit(size_t(c), int32_t(f)); });
			    }
		    },
		    start_, tri_);
	}
	double cell() const { return cell_; }
	/// The triangle nearest p and its squared distance, looked for in a box growing from half a
	/// cell up to rMax; -1 if none is within rMax.
	int32_t nearest(const Vec3 &p, double rMax, double &d2) const
	{
		double r = std::min(0.5 * cell_, rMax);
		for (;;) {
			// (a box of more cells than there are buckets, as slivers' tiny cells make: every
			// triangle once is cheaper, and gives the same one)
			if (boxCells(p - Vec3(r, r, r), p + Vec3(r, r, r)) > double(buckets_))
				return nearestOfAll(p, rMax, d2);
			double best = r * r;
			int32_t found = -1;
			forCells(p - Vec3(r, r, r), p + Vec3(r, r, r), [&](uint64_t c) {
				for (int32_t i = start_[c]; i < start_[c + 1]; ++i) {
					const size_t f = size_t(tri_[size_t(i)]);
					const double e2 =
					    pointTriangleDistance2(p, P(tri(f, 0)), P(tri(f, 1)), P(tri(f, 2)));
					if (e2 < best || (e2 == best && found >= 0 && int32_t(f) < found))
						best = e2, found = int32_t(f);
				}
			});
			if (found >= 0) {
				d2 = best;
				return found;
			}
			if (r >= rMax)
				return -1;
			r = std::min(2 * r, rMax);
		}
	}

private:
	double boxCells(const Vec3 &a, const Vec3 &b) const
	{
		double n = 1;
		for (int k = 0; k < 3; ++k)
			n *= double(idx(b[k], k) - idx(a[k], k) + 1);
		return n;
	}
	int32_t nearestOfAll(const Vec3 &p, double rMax, double &d2) const
	{
		double best = rMax * rMax;
		int32_t found = -1;
		for (size_t f = 0; f < L_.triangles.size() / 3; ++f) {
			const double e2 = pointTriangleDistance2(p, P(tri(f, 0)), P(tri(f, 1)), P(tri(f, 2)));
			if (e2 < best || (e2 == best && found >= 0 && int32_t(f) < found))
				best = e2, found = int32_t(f);
		}
		if (found >= 0)
			d2 = best;
		return found;
	}
	const LevelMesh &L_;
	Vec3 lo_;
	double cell_ = 1;
	uint64_t buckets_ = 1;
	std::vector<int32_t> start_, tri_;

	Vec3 P(int32_t v) const { return Vec3(&L_.positions[3 * size_t(v)]); }
	int32_t tri(size_t f, int k) const { return L_.triangles[3 * f + size_t(k)]; }
	int64_t idx(double x, int k) const { return int64_t(std::floor((x - lo_[k]) / cell_)); }
	template <class Fn>
	void forCells(const Vec3 &a, const Vec3 &b, Fn fn) const
	{
		for (int64_t z = idx(a[2], 2); z <= idx(b[2], 2); ++z)
			for (int64_t y = idx(a[1], 1); y <= idx(b[1], 1); ++y)
				for (int64_t x = idx(a[0], 0); x <= idx(b[0], 0); ++x)
					fn(FaceGrid::bucketOf(x, y, z, buckets_ - 1));
	}
};

} // namespace

double farthestInputVertex(const Topology &t, const LevelMesh &level, double within, size_t threads)
{
	if (level.triangles.empty())
		return HUGE_VAL;
	const NearestTriangles grid(level, 1e-9 * t.diagonal);
	std::vector<uint8_t> used(t.nV, 0);
	for (size_t f = 0; f < t.nF; ++f)
		if (t.faceValid[f])
			for (int k = 0; k < 3; ++k)
				used[size_t(t.T[3 * f + size_t(k)])] = 1;
	// each vertex's nearest triangle (every input point is within `within`); the vertices in
	// parallel, at most kFarthestSample of them (every k-th: this compares two levels, it proves
	// nothing)
	const double rMax = within * (1 + 1e-9) + 1e-12 * t.diagonal;
	size_t nUsed = 0;
	for (uint8_t u : used)
		nUsed += u;
	const size_t stride = std::max<size_t>(1, (nUsed + kFarthestSample - 1) / kFarthestSample);
	size_t k = 0;
	for (size_t v = 0; v < t.nV; ++v)
		if (used[v])
			used[v] = k++ % stride == 0;
	std::vector<double> worst(std::max<size_t>(threads, 1), 0.0);
	parallelRanges(t.nV, threads, [&](size_t vb, size_t ve, size_t part) {
		for (size_t v = vb; v < ve; ++v) {
			if (!used[v])
				continue;
			double d2 = 0;
			const double d = grid.nearest(t.pos(int32_t(v)), rMax, d2) >= 0 ? std::sqrt(d2) : rMax;
			worst[part] = std::max(worst[part], d);
		}
	});
	return *std::max_element(worst.begin(), worst.end());
}

void measureNormalDeviation(const Topology &t, LevelMesh &level, size_t threads)
{
	LevelStats &st = level.stats;
	if (level.triangles.empty())
		return;
	const NearestTriangles grid(level, 1e-9 * t.diagonal);
	// (a level of unknown distance, tolerance off: only what is within rounding)
	const double rMax = std::max(0.0, st.distanceBound) * (1 + 1e-9) + 1e-12 * t.diagonal;
	const size_t parts = std::max<size_t>(threads, 1);
	std::vector<double> worst(parts, 0.0), sum(parts, 0.0), area(parts, 0.0);
	// (every k-th face, at most kMeasuredFaces of them: a measure, not a bound)
	const size_t stride = std::max<size_t>(1, (t.nF + kMeasuredFaces - 1) / kMeasuredFaces);
	parallelRanges(t.nF, threads, [&](size_t fb, size_t fe, size_t part) {
		for (size_t f = fb; f < fe; ++f) {
			if (!t.faceValid[f] || f % stride != 0)
				continue;
			const Vec3 c =
			    (t.pos(t.T[3 * f]) + t.pos(t.T[3 * f + 1]) + t.pos(t.T[3 * f + 2])) / 3.0;
			double d2 = 0;
			const int32_t g = grid.nearest(c, rMax, d2);
			if (g < 0)
				continue;
			const Vec3 a(&level.positions[3 * size_t(level.triangles[3 * size_t(g)])]);
			const Vec3 b(&level.positions[3 * size_t(level.triangles[3 * size_t(g) + 1])]);
			const Vec3 d(&level.positions[3 * size_t(level.triangles[3 * size_t(g) + 2])]);
			Vec3 n = (b - a) ^ (d - a);
			if (!(n.Norm() > 0))
				continue;
			n.Normalize();
			const double dev = angleDeg(n, t.faceNormal[f]);
			worst[part] = std::max(worst[part], dev);
			sum[part] += dev * t.faceArea[f];
			area[part] += t.faceArea[f];
		}
	});
	double w = 0, s = 0, a = 0;
	for (size_t i = 0; i < parts; ++i)
		w = std::max(w, worst[i]), s += sum[i], a += area[i];
	st.maxNormalDevDeg = w;
	st.meanNormalDevDeg = a > 0 ? s / a : 0;
}

} // namespace detail
} // namespace gausslod
