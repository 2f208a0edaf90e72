// Edge collapses (reduce.h): whether a planned collapse may be made, and at what bounds: its
// proof's gaps over the bounds of the triangles under it, the normal cones, the facing tests and,
// with texture coordinates, the corners' attributes and the texture's error and shift.
#include "level_passes.h"
#include "reduce_internal.h"

namespace gausslod {
namespace detail {
namespace collapse {

namespace {

// The point of triangle (a, b, c) nearest p, as barycentric coordinates.
void nearestBarycentric(const Vec3 &p, const Vec3 &a, const Vec3 &b, const Vec3 &c, double &l0,
                        double &l1, double &l2)
{
	// (the nearest point by the same regions as pointTriangleDistance2, then its coordinates)
	const Vec3 ab = b - a, ac = c - a, ap = p - a;
	const double d1 = ab.dot(ap), d2 = ac.dot(ap);
	if (d1 <= 0 && d2 <= 0) {
		l0 = 1, l1 = l2 = 0;
		return;
	}
	const Vec3 bp = p - b;
	const double d3 = ab.dot(bp), d4 = ac.dot(bp);
	if (d3 >= 0 && d4 <= d3) {
		l1 = 1, l0 = l2 = 0;
		return;
	}
	const double vc = d1 * d4 - d3 * d2;
	if (vc <= 0 && d1 >= 0 && d3 <= 0) {
		const double v = d1 / (d1 - d3);
		l0 = 1 - v, l1 = v, l2 = 0;
		return;
	}
	const Vec3 cp = p - c;
	const double d5 = ab.dot(cp), d6 = ac.dot(cp);
	if (d6 >= 0 && d5 <= d6) {
		l2 = 1, l0 = l1 = 0;
		return;
	}
	const double vb = d5 * d2 - d1 * d6;
	if (vb <= 0 && d2 >= 0 && d6 <= 0) {
		const double w = d2 / (d2 - d6);
		l0 = 1 - w, l2 = w, l1 = 0;
		return;
	}
	const double va = d3 * d6 - d5 * d4;
	if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
		const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
		l1 = 1 - w, l2 = w, l0 = 0;
		return;
	}
	const double den = 1.0 / (va + vb + vc);
	l1 = vb * den, l2 = vc * den, l0 = 1 - l1 - l2;
}

} // namespace

// The checks a planned collapse must pass, in this order (the first to veto ends it): a new check
// is a member of Reducer (its own file if it is long) and one line here.
const Reducer::Check Reducer::kChecks[] = {
    {"proof", &Reducer::proven},
    {"triangles", &Reducer::notDegenerate},
    {"distance bound", &Reducer::withinBound},
    {"normal limit", &Reducer::withinNormalLimit},
    {"facing", &Reducer::notTurned},
    {"texture", &Reducer::withinTexture},
};

bool Reducer::check(Plan &pl) const
{
	for (const Check &c : kChecks)
		if (!(this->*c.passes)(pl))
			return false;
	return true;
}

bool Reducer::proven(Plan &pl) const { return provePatch(pl.pc, kFacing, slop(), pl.proof); }

bool Reducer::notDegenerate(Plan &pl) const
{
	const PatchCase &c = pl.pc;
	for (int i = 0; i < c.nNew; ++i) {
		const Vec3 &a = c.pos[c.newTri[i][0]], &b = c.pos[c.newTri[i][1]],
		           &d = c.pos[c.newTri[i][2]];
		Vec3 nt = (b - a) ^ (d - a);
		if (!(nt.Norm() > 1e-30 * t_.diagonal * t_.diagonal))
			return false;
		pl.normal[i] = nt.Normalize();
	}
	return true;
}

bool Reducer::withinBound(Plan &pl) const
{
	// (a new triangle's bound: the largest of the triangles under it, plus its proof's gap)
	const PatchCase &c = pl.pc;
	for (int i = 0; i < c.nNew; ++i) {
		double e = 0;
		for (int j = 0; j < c.nOld; ++j)
			if (pl.proof.under[i] >> j & 1)
				e = std::max(e, e_[size_t(pl.oldId[j])]);
		pl.bound[i] = e + pl.proof.gap[i];
		if (pl.bound[i] > lim_.bound)
			return false;
	}
	return true;
}

bool Reducer::withinNormalLimit(Plan &pl) const
{
	// (every input face under a new triangle, through the normal cone of the triangle it was under)
	if (!(lim_.normalDeg < 180))
		return true;
	const PatchCase &c = pl.pc;
	for (int i = 0; i < c.nNew; ++i)
		for (int j = 0; j < c.nOld; ++j) {
			if (!(pl.proof.under[i] >> j & 1))
				continue;
			const NormalCone &k = cone_[size_t(pl.oldId[j])];
			if (angleDeg(pl.normal[i], k.axis) + k.half > lim_.normalDeg)
				return false;
		}
	return true;
}

bool Reducer::notTurned(Plan &pl) const
{
	// (a new triangle that reuses a mesh triangle under it: not turned over against it)
	if (!checkFacing_)
		return true;
	const PatchCase &c = pl.pc;
	for (int i = 0; i < c.nNew; ++i)
		for (int j = 0; j < c.nOld; ++j)
			if ((pl.proof.under[i] >> j & 1) && pl.oldId[j] == pl.newId[i] &&
			    pl.normal[i].dot(normal(pl.oldId[j])) < 0)
				return false;
	return true;
}

bool Reducer::withinTexture(Plan &pl) const
{
	if (!srcC_.empty())
		wedges(pl);
	return textureError(pl);
}

bool Reducer::facesInput(const Plan &pl) const
{
	// not on the other side of a thin part: the input surface nearest each new triangle faces it
	const PatchCase &c = pl.pc;
	for (int i = 0; i < c.nNew; ++i) {
		const Vec3 &a = c.pos[c.newTri[i][0]], &b = c.pos[c.newTri[i][1]],
		           &d = c.pos[c.newTri[i][2]];
		Vec3 nt = (b - a) ^ (d - a);
		nt.Normalize();
		if (!nearestInputFacing(t_, (a + b + d) / 3.0, nt,
		                        pl.bound[i] * (1 + 1e-9) + 1e-12 * t_.diagonal, kFacingCells))
			return false;
	}
	return true;
}

bool Reducer::textureError(Plan &pl) const
{
	const PatchCase &c = pl.pc;
	for (int i = 0; i < c.nNew; ++i)
		pl.uvBound[i] = 0;
	if (uv_.empty())
		return true;
	const double local = uvLocal(pl);
	for (int i = 0; i < c.nNew; ++i) {
		double worst = 0;
		for (int j = 0; j < c.nOld; ++j)
			if (pl.proof.under[i] >> j & 1)
				worst = std::max(worst, double(uvErr_[size_t(pl.oldId[j])]));
		pl.uvBound[i] = worst + local;
		if (lim_.texError > 0 && !lim_.texErrorSoft && pl.uvBound[i] > lim_.texError)
			return false;
	}
	return true;
}

double Reducer::uvLocal(const Plan &pl) const
{
	const PatchCase &c = pl.pc;
	// at a removed vertex, in each chart around it: its own coordinates against those the new
	// triangles of that chart show at their point nearest it
	double local = 0;
	if (pl.full) // (free vertices, one chart: both ends)
		for (const int32_t w : {pl.gone, pl.kept}) {
			int32_t cw = -1;
			for (int32_t q = 3 * pl.dead[0]; q < 3 * pl.dead[0] + 3; ++q)
				if (T_[size_t(q)] == w)
					cw = q;
			double nearest = HUGE_VAL, err = 0;
			for (int i = 0; i < c.nNew; ++i) {
				const Vec3 &a = c.pos[c.newTri[i][0]], &b = c.pos[c.newTri[i][1]],
				           &d = c.pos[c.newTri[i][2]];
				const double d2 = pointTriangleDistance2(P_[size_t(w)], a, b, d);
				if (d2 >= nearest)
					continue;
				nearest = d2;
				double l[3];
				nearestBarycentric(P_[size_t(w)], a, b, d, l[0], l[1], l[2]);
				// (the new triangle's corners: its kept-vertex corner's are the new ones)
				const int32_t f = pl.newId[i];
				double uv[3][2];
				for (int k = 0; k < 3; ++k) {
					const int8_t pt = c.newTri[i][k];
					int32_t q = -1;
					for (int32_t r = 3 * f; r < 3 * f + 3 && pt != c.newInner; ++r)
						if (T_[size_t(r)] == pl.point[pt])
							q = r;
					for (int m = 0; m < 2; ++m)
						uv[k][m] = pt == c.newInner || q < 0 ? pl.newUV[i][m]
						                                     : uv_[2 * size_t(q) + size_t(m)];
				}
				const double du =
				    l[0] * uv[0][0] + l[1] * uv[1][0] + l[2] * uv[2][0] - uv_[2 * size_t(cw)];
				const double dv =
				    l[0] * uv[0][1] + l[1] * uv[1][1] + l[2] * uv[2][1] - uv_[2 * size_t(cw) + 1];
				err = std::sqrt(du * du + dv * dv);
			}
			local = std::max(local, err);
		}
	// (a chart extended to the kept vertex reaches beyond its island by this much)
	for (int i = 0; i < c.nNew && !pl.full; ++i)
		if (pl.extended[i])
			for (int32_t q = 3 * pl.newId[i]; q < 3 * pl.newId[i] + 3; ++q)
				if (T_[size_t(q)] == pl.gone)
					local = std::max(local,
					                 double(std::hypot(pl.newUV[i][0] - uv_[2 * size_t(q)],
					                                   pl.newUV[i][1] - uv_[2 * size_t(q) + 1])));
	const Vec3 &pv = P_[size_t(pl.gone)];
	double nearest = HUGE_VAL, err = 0;
	int chart = 0;
	for (int i = 0; i < c.nNew && !pl.full; ++i) {
		const int32_t f = pl.newId[i];
		int32_t cv = -1;
		for (int32_t q = 3 * f; q < 3 * f + 3; ++q)
			if (T_[size_t(q)] == pl.gone)
				cv = q;
		if (cv < 0)
			continue;
		if (dlm_[size_t(cv)]) { // (the next chart)
			local = std::max(local, err);
			nearest = HUGE_VAL, err = 0, ++chart;
		}
		Vec3 p[3];
		double uv[3][2];
		for (int k = 0; k < 3; ++k) {
			const int32_t q = 3 * f + k;
			p[k] = q == cv ? P_[size_t(pl.kept)] : P_[size_t(T_[size_t(q)])];
			for (int j = 0; j < 2; ++j)
				uv[k][j] = q == cv ? pl.newUV[i][j] : uv_[2 * size_t(q) + size_t(j)];
		}
		const double d2 = pointTriangleDistance2(pv, p[0], p[1], p[2]);
		if (d2 >= nearest)
			continue;
		nearest = d2;
		double l[3];
		nearestBarycentric(pv, p[0], p[1], p[2], l[0], l[1], l[2]);
		const double du = l[0] * uv[0][0] + l[1] * uv[1][0] + l[2] * uv[2][0] - uv_[2 * size_t(cv)];
		const double dv =
		    l[0] * uv[0][1] + l[1] * uv[1][1] + l[2] * uv[2][1] - uv_[2 * size_t(cv) + 1];
		err = std::sqrt(du * du + dv * dv);
	}
	return std::max(local, err);
}

double Reducer::textureShift(const Plan &pl) const
{
	// the texture error at the removed vertices in mesh units (UV units times the old patch's
	// length per UV unit: the square root of its area over its area in texture space), weighted
	double a3 = 0, a2 = 0;
	for (int j = 0; j < pl.pc.nOld; ++j) {
		const size_t f = size_t(pl.oldId[j]);
		a3 += normal(int32_t(f)).Norm();
		const float *t = &uv_[6 * f];
		a2 += std::fabs((t[2] - t[0]) * (t[5] - t[1]) - (t[3] - t[1]) * (t[4] - t[0]));
	}
	return a2 > 0 ? kTexShiftWeight * uvLocal(pl) * std::sqrt(a3 / a2) : 0.0;
}

void Reducer::wedges(Plan &pl) const
{
	const PatchCase &c = pl.pc;
	auto setFrom = [&](int i, int32_t corner) {
		pl.extended[i] = false;
		pl.newSrc[i] = srcC_[size_t(corner)];
		for (int k = 0; k < 2; ++k)
			pl.newUV[i][k] = uv_.empty() ? 0.0f : uv_[2 * size_t(corner) + size_t(k)];
	};
	if (pl.full) { // (free vertices: one chart; the attributes of the end nearer the new position)
		const Vec3 iu(&mesh_.positions[3 * size_t(srcV_[size_t(pl.kept)])]);
		const Vec3 iv(&mesh_.positions[3 * size_t(srcV_[size_t(pl.gone)])]);
		const int32_t from =
		    (iv - pl.pos).SquaredNorm() < (iu - pl.pos).SquaredNorm() ? pl.gone : pl.kept;
		int32_t corner = -1;
		for (int32_t q = 3 * pl.dead[0]; q < 3 * pl.dead[0] + 3; ++q)
			if (T_[size_t(q)] == from)
				corner = q;
		for (int i = 0; i < c.nNew; ++i)
			setFrom(i, corner);
		if (!uv_.empty()) { // (the coordinates the old patch has at its point nearest the new one)
			double best = HUGE_VAL;
			for (int j = 0; j < c.nOld; ++j) {
				const int32_t f = pl.oldId[j];
				const Vec3 &a = P_[size_t(T_[3 * size_t(f)])],
				           &b = P_[size_t(T_[3 * size_t(f) + 1])],
				           &d = P_[size_t(T_[3 * size_t(f) + 2])];
				const double d2 = pointTriangleDistance2(pl.pos, a, b, d);
				if (d2 >= best)
					continue;
				best = d2;
				double l[3];
				nearestBarycentric(pl.pos, a, b, d, l[0], l[1], l[2]);
				for (int k = 0; k < 2; ++k) {
					double x = 0;
					for (int m = 0; m < 3; ++m)
						x += l[m] * uv_[2 * (3 * size_t(f) + size_t(m)) + size_t(k)];
					for (int i = 0; i < c.nNew; ++i)
						pl.newUV[i][k] = float(x);
				}
			}
		}
		return;
	}
	// half: the charts around v in ring order, split by its delimiters (the edge v -> nb[j] opens
	// the chart of face j); the first (with dead face 0) and the last (with the other dead face,
	// the first again if the edge v-u parts no charts) have u's corners; a chart between them
	// extends its mapping to u
	auto cornerOfGone = [&](int32_t f) {
		for (int32_t q = 3 * f; q < 3 * f + 3; ++q)
			if (T_[size_t(q)] == pl.gone)
				return q;
		return int32_t(-1);
	};
	int last = 0;
	for (int i = 0; i < c.nNew; ++i)
		last += dlm_[size_t(cornerOfGone(pl.newId[i]))];
	if (pl.nDead == 2)
		last += dlm_[size_t(cornerOfGone(pl.dead[1]))];
	int chart = 0;
	for (int i = 0; i < c.nNew; ++i) {
		const int32_t f = pl.newId[i];
		const int32_t cv = cornerOfGone(f);
		chart += dlm_[size_t(cv)];
		if (chart == 0) {
			setFrom(i, pl.keptCorner[0]);
		} else if (chart == last) {
			setFrom(i, pl.keptCorner[1]);
		} else { // (v's corner of this chart, its mapping extended to u's position)
			pl.extended[i] = true;
			pl.newSrc[i] = srcC_[size_t(cv)];
			const int32_t q1 = heNext(cv), q2 = hePrev(cv);
			const Vec3 &p0 = P_[size_t(pl.gone)], &p1 = P_[size_t(T_[size_t(q1)])],
			           &p2 = P_[size_t(T_[size_t(q2)])];
			const Vec3 e1 = p1 - p0, e2 = p2 - p0, d = P_[size_t(pl.kept)] - p0;
			const double a11 = e1.dot(e1), a12 = e1.dot(e2), a22 = e2.dot(e2);
			const double det = a11 * a22 - a12 * a12;
			double x = 0, y = 0;
			if (det > 0) {
				x = (a22 * d.dot(e1) - a12 * d.dot(e2)) / det;
				y = (a11 * d.dot(e2) - a12 * d.dot(e1)) / det;
			}
			for (int k = 0; k < 2; ++k) {
				const double t0 = uv_.empty() ? 0 : uv_[2 * size_t(cv) + size_t(k)];
				const double t1 = uv_.empty() ? 0 : uv_[2 * size_t(q1) + size_t(k)];
				const double t2 = uv_.empty() ? 0 : uv_[2 * size_t(q2) + size_t(k)];
				pl.newUV[i][k] = float(t0 + x * (t1 - t0) + y * (t2 - t0));
			}
		}
	}
}

} // namespace collapse
} // namespace detail
} // namespace gausslod
