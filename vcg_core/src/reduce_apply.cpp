// Edge collapses (reduce.h): a proven collapse made: the fan's triangles take the place of the
// patch's, with their bounds, cones and corners, and the edges around go back in line.
#include "reduce_internal.h"

namespace gausslod {
namespace detail {
namespace collapse {

void Reducer::fanCones(const Plan &pl, NormalCone *cones, double *dev) const
{
	// the new triangles' cones, from the old ones under them, and the largest deviation from
	// each of those (what the level reports)
	const PatchCase &c = pl.pc;
	for (int i = 0; i < c.nNew; ++i) {
		bool first = true;
		const Vec3 &a = c.pos[c.newTri[i][0]], &b = c.pos[c.newTri[i][1]],
		           &d = c.pos[c.newTri[i][2]];
		Vec3 nt = (b - a) ^ (d - a);
		nt.Normalize();
		dev[i] = 0;
		for (int j = 0; j < c.nOld; ++j)
			if (pl.proof.under[i] >> j & 1) {
				const NormalCone &k = cone_[size_t(pl.oldId[j])];
				dev[i] = std::max(dev[i], std::min(180.0, angleDeg(nt, k.axis) + k.half));
				cones[i] = first ? k : mergeCones(cones[i], k);
				first = false;
			}
	}
}

void Reducer::removeDead(Lane &L, const Plan &pl)
{
	const PatchCase &c = pl.pc;
	if (lim_.keepSuperfaces && L.deep) { // (a region's: joined once the regions stop)
		const int32_t s0 = sf_[size_t(pl.oldId[0])];
		for (int j = 1; j < c.nOld; ++j)
			if (sf_[size_t(pl.oldId[j])] != s0)
				L.joins.push_back(s0), L.joins.push_back(sf_[size_t(pl.oldId[j])]);
	} else if (lim_.keepSuperfaces) { // (the patch's superfaces become one)
		const int32_t root = superfaceOf(pl.oldId[0]);
		for (int j = 1; j < c.nOld; ++j) {
			const int32_t r = superfaceOf(pl.oldId[j]);
			if (r != root)
				sfUf_[size_t(r)] = root;
		}
	}
	for (int d = 0; d < pl.nDead; ++d) { // (each dead triangle goes into a new one over it)
		int j = 0;
		while (pl.oldId[j] != pl.dead[d])
			++j;
		int i = 0;
		while (i + 1 < c.nNew && !(pl.proof.under[i] >> j & 1))
			++i;
		fwd_[size_t(pl.dead[d])] = pl.newId[i];
		alive_[size_t(pl.dead[d])] = 0;
		++L.dead;
	}
}

void Reducer::rewriteFan(const Plan &pl, const NormalCone *cones, const double *dev)
{
	const PatchCase &c = pl.pc;
	const int32_t u = pl.kept, v = pl.gone;
	// the kept vertex
	Q_[size_t(u)] += Q_[size_t(v)];
	if (pl.full) {
		P_[size_t(u)] = pl.pos;
		// (its attributes: those of the end whose input vertex is nearer)
		const Vec3 iu(&mesh_.positions[3 * size_t(srcV_[size_t(u)])]);
		const Vec3 iv(&mesh_.positions[3 * size_t(srcV_[size_t(v)])]);
		srcV_[size_t(u)] =
		    srcV_[size_t((iv - pl.pos).SquaredNorm() < (iu - pl.pos).SquaredNorm() ? v : u)];
	}
	// the new triangles: their corners at u or v become u's (with sources: the wedge of u in
	// their chart, wedges())
	for (int i = 0; i < c.nNew; ++i) {
		const int32_t f = pl.newId[i];
		for (int32_t q = 3 * f; q < 3 * f + 3; ++q) {
			const int32_t w = T_[size_t(q)];
			if (w != v && !(pl.full && w == u))
				continue;
			T_[size_t(q)] = u;
			if (!srcC_.empty())
				srcC_[size_t(q)] = pl.newSrc[i];
			if (!uv_.empty())
				uv_[2 * size_t(q)] = pl.newUV[i][0], uv_[2 * size_t(q) + 1] = pl.newUV[i][1];
		}
		e_[size_t(f)] = pl.bound[i];
		devBound_[size_t(f)] = dev[i];
		cone_[size_t(f)] = cones[i];
		uvErr_[size_t(f)] = std::nextafter(float(pl.uvBound[i]), 3e38f);
	}
}

void Reducer::relink(Lane &L, const Plan &pl)
{
	const PatchCase &c = pl.pc;
	const int32_t u = pl.kept, v = pl.gone;
	// v's corners join u's list
	if (head_[size_t(v)] >= 0) {
		int32_t tail = head_[size_t(v)];
		while (next_[size_t(tail)] >= 0)
			tail = next_[size_t(tail)];
		next_[size_t(tail)] = head_[size_t(u)];
		head_[size_t(u)] = head_[size_t(v)];
		head_[size_t(v)] = -1;
	}
	kind_[size_t(v)] = kGone;
	prune(L, u);
	for (int d = 0; d < pl.nDead; ++d)
		for (int32_t q = 3 * pl.dead[d]; q < 3 * pl.dead[d] + 3; ++q)
			if (T_[size_t(q)] != u && T_[size_t(q)] != v)
				prune(L, T_[size_t(q)]);
	if (keys_) { // (the fan's edges join triangles anew: their delimiters, and the kinds around)
		for (int i = 0; i < c.nNew; ++i)
			for (int k = 0; k < 3; ++k)
				setDelimiter(3 * pl.newId[i] + k);
		if (kind_[size_t(u)] != kFixed)
			kind_[size_t(u)] = kindOf(u);
		for (int i = 0; i < c.nPts; ++i) {
			const int32_t w = pl.point[i];
			if (w >= 0 && w != u && w != v && kind_[size_t(w)] != kFixed)
				kind_[size_t(w)] = kindOf(w);
		}
	}
}

void Reducer::prune(Lane &L, int32_t v)
{
	std::vector<int32_t> &s = L.scratch;
	s.clear();
	for (int32_t c = head_[size_t(v)]; c >= 0; c = next_[size_t(c)])
		if (alive_[size_t(heFace(c))])
			s.push_back(c);
	head_[size_t(v)] = -1;
	for (auto it = s.rbegin(); it != s.rend(); ++it) {
		next_[size_t(*it)] = head_[size_t(v)];
		head_[size_t(v)] = *it;
	}
}

void Reducer::apply(Lane &L, const Plan &pl)
{
	NormalCone cones[PatchCase::kMaxTris];
	double dev[PatchCase::kMaxTris];
	fanCones(pl, cones, dev);
	removeDead(L, pl);
	rewriteFan(pl, cones, dev);
	relink(L, pl);
	const PatchCase &c = pl.pc;
	const int32_t u = pl.kept, v = pl.gone;
	++stamp_[size_t(u)];
	pushEdges(L, u);
	for (int i = 0; i < c.nPts; ++i) { // (collapses refused near here may be legal now)
		const int32_t w = pl.point[i];
		if (w >= 0 && w != u && w != v && blocked_[size_t(w)]) {
			blocked_[size_t(w)] = 0;
			pushEdges(L, w);
		}
	}
}

} // namespace collapse
} // namespace detail
} // namespace gausslod
