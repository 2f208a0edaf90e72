// 2.2.2-2.4 A level's output (level_rounds.h): its mesh on its own vertex numbers, the input
// corners its corners come from, its figures, and the exact superfaces it hands to the next
// coarser level (ExactCarry).
#include "level_rounds.h"

#include <algorithm>
#include <stdexcept>

namespace gausslod {
namespace detail {

namespace {

// Per output corner (triangles still on input vertex numbers) an input corner at the same vertex
// in a face of the same superface, the lowest such face; per output face the source face of its
// first corner. Superfaces never cross a delimiter, so those corners carry the attributes of the
// output corner's side of every seam.
void findSources(const Topology &t, const Partition &p, const LevelTriangles &lt, LevelMesh &out)
{
	const size_t nT = lt.triSf.size();
	out.sourceCorner.resize(3 * nT);
	out.sourceFace.resize(nT);
	for (size_t f = 0; f < nT; ++f) {
		const int32_t sf = lt.triSf[f];
		for (size_t k = 0; k < 3; ++k) {
			const int32_t v = lt.tris[3 * f + k];
			int32_t corner = -1;
			for (int32_t q = t.vfStart[size_t(v)]; q < t.vfStart[size_t(v) + 1] && corner < 0;
			     ++q) {
				const int32_t g = t.vfFace[size_t(q)];
				if (p.label[size_t(g)] != sf)
					continue;
				for (int32_t c = 3 * g; c < 3 * g + 3; ++c)
					if (t.T[c] == v)
						corner = c;
			}
			if (corner < 0) // (cannot happen: output vertices are vertices of their superface)
				throw std::logic_error("an output corner has no input corner in its superface");
			out.sourceCorner[3 * f + k] = corner;
		}
		out.sourceFace[f] = heFace(out.sourceCorner[3 * f]);
	}
}

} // namespace

// Beyond the paper (DESIGN 31): superface s takes the triangles and measures of the finer
// level's exact superface with the same faces, if its kept outline is the same (the directed kept
// ring edges against the triangles' border edges). False if there is none.
bool LevelRounds::takeExact(const TriangulationInput &in, int32_t s, Scratch &w, ChunkOut &o)
{
	const ExactCarry &ec = *carryIn_;
	const int32_t fb = faces_.begin(s), fe = faces_.end(s);
	const int32_t fs = (*ec.label)[size_t(faces_.face[size_t(fb)])];
	const int32_t first = ec.first[size_t(fs)];
	if (first < 0 || ec.measureAt[size_t(fs) + 1] - ec.measureAt[size_t(fs)] != fe - fb)
		return false;
	for (int32_t i = fb; i < fe; ++i) // (as many faces, all of fs: the same faces)
		if ((*ec.label)[size_t(faces_.face[size_t(i)])] != fs)
			return false;
	const int32_t last = ec.last[size_t(fs)];
	if (!sameKeptOutline(in, s, ec.tris, ec.bits, first, last, w))
		return false;
	o.tris.insert(o.tris.end(), ec.tris.begin() + 3 * first, ec.tris.begin() + 3 * last);
	o.triBorder.insert(o.triBorder.end(), ec.bits.begin() + first, ec.bits.begin() + last);
	const size_t at = size_t(ec.measureAt[size_t(fs)]);
	for (int32_t i = fb; i < fe; ++i) {
		const size_t f = size_t(faces_.face[size_t(i)]), j = at + size_t(i - fb);
		measures_.dev[f] = ec.dev[j];
		if (!measures_.gap.empty())
			measures_.gap[f] = ec.gap.empty() ? 0.0f : ec.gap[j];
		if (!measures_.tex.empty())
			measures_.tex[f] = ec.tex.empty() ? 0.0f : ec.tex[j];
	}
	++o.retriangulated, ++o.carried;
	return true;
}

// This level's exact superfaces for the next coarser level (see ExactCarry): re-triangulated,
// every face's distance bound within LevelLimits::exact, every vertex of its triangles on a border
// and at its input position.
void LevelRounds::carryExact()
{
	ExactCarry &ec = *carryOut_;
	ec = ExactCarry();
	ec.label = &p_.label;
	const size_t n = p_.count();
	ec.first.assign(n, -1), ec.last.assign(n, -1), ec.measureAt.assign(n + 1, 0);
	const bool gap = !measures_.gap.empty(), tex = !measures_.tex.empty();
	for (size_t sf = 0; sf < n; ++sf) {
		ec.measureAt[sf + 1] = ec.measureAt[sf];
		const Cached &c = cache_[sf];
		if (!c.ok || !c.retriangulated || c.triEnd <= c.triBegin)
			continue;
		bool exact = true;
		for (int32_t i = faces_.begin(int32_t(sf)); i < faces_.end(int32_t(sf)) && exact; ++i) {
			const size_t f = size_t(faces_.face[size_t(i)]);
			exact = measures_.dev[f] >= 0 && (!gap || double(measures_.gap[f]) <= limits_.exact);
		}
		for (int32_t k = c.triBegin; k < c.triEnd && exact; ++k)
			for (size_t j = 0; j < 3 && exact; ++j) {
				const int32_t v = tri_.tris[3 * size_t(k) + j];
				exact = borders_.degree[size_t(v)] > 0 && placement_.at(t_, size_t(v)) == t_.pos(v);
			}
		if (!exact)
			continue;
		ec.first[sf] = int32_t(ec.bits.size());
		ec.tris.insert(ec.tris.end(), tri_.tris.begin() + 3 * c.triBegin,
		               tri_.tris.begin() + 3 * c.triEnd);
		ec.bits.insert(ec.bits.end(), tri_.triBorder.begin() + c.triBegin,
		               tri_.triBorder.begin() + c.triEnd);
		for (int32_t i = faces_.begin(int32_t(sf)); i < faces_.end(int32_t(sf)); ++i) {
			const size_t f = size_t(faces_.face[size_t(i)]);
			ec.dev.push_back(measures_.dev[f]);
			if (gap)
				ec.gap.push_back(measures_.gap[f]);
			if (tex)
				ec.tex.push_back(measures_.tex[f]);
		}
		ec.last[sf] = int32_t(ec.bits.size());
		ec.measureAt[sf + 1] = int32_t(ec.dev.size());
	}
	// (straightening keeps every chain end; a chain that keeps nothing else keeps nothing else
	// with a tolerance at least as large: with the same borders, the same outlines)
	ec.whole = out_.stats.rounds == 1 && placement_.moved == 0 &&
	           std::find(ec.first.begin(), ec.first.end(), -1) == ec.first.end();
	for (size_t k = 0; k < tri_.tris.size() && ec.whole; ++k)
		ec.whole = borders_.junction[size_t(tri_.tris[k])] != 0;
}

void LevelRounds::finish(size_t fallbacks)
{
	releaseRounds();
	std::vector<int32_t> remap(t_.nV, -1);
	for (int32_t v : tri_.tris)
		remap[size_t(v)] = 0;
	int32_t next = 0;
	for (size_t v = 0; v < t_.nV; ++v)
		if (remap[v] >= 0)
			remap[v] = next++;
	out_.positions.resize(3 * size_t(next));
	out_.sourceVertex.resize(size_t(next));
	for (size_t v = 0; v < t_.nV; ++v) {
		if (remap[v] < 0)
			continue;
		const size_t o = size_t(remap[v]);
		out_.sourceVertex[o] = int32_t(v);
		const Vec3 p = placement_.at(t_, v);
		for (size_t k = 0; k < 3; ++k)
			out_.positions[3 * o + k] = p[int(k)];
	}
	out_.stats.placedVertices = placement_.moved;
	out_.stats.maxPlacement = placement_.maxMove;
	placement_ = Placement();
	if (t_.wantSources)
		findSources(t_, p_, tri_, out_); // (on input vertex numbers)
	for (int32_t &v : tri_.tris)
		v = remap[size_t(v)];
	release(remap);
	out_.triangles = std::move(tri_.tris);
	out_.superface = std::move(tri_.triSf);
	out_.inputSuperface = p_.label;
	for (uint8_t &b : tri_.triBorder)
		b &= kBorderBits;
	out_.borderEdges = std::move(tri_.triBorder);
	fillStats(fallbacks, size_t(next));
}

void LevelRounds::fillStats(size_t fallbacks, size_t vertices)
{
	LevelStats &st = out_.stats;
	st.level = p_.level;
	st.boundDeg = levelBoundDeg(p_.level);
	st.faces = out_.triangles.size() / 3;
	st.vertices = vertices;
	st.superfaces = p_.count();
	st.fallbacks = fallbacks;
	st.retriangulated = retriangulated_;
	st.carriedSuperfaces = carried_;
	double maxDev = 0, sum = 0, area = 0;
	size_t unmeasured = 0;
	const std::vector<float> &dev = measures_.dev;
	for (size_t f = 0; f < t_.nF; ++f) {
		if (!t_.faceValid[f])
			continue;
		if (dev[f] < 0) {
			++unmeasured;
			continue;
		}
		maxDev = std::max(maxDev, double(dev[f]));
		const double a = t_.faceArea[f];
		sum += double(dev[f]) * a;
		area += a;
	}
	st.maxNormalDevDeg = maxDev;
	st.meanNormalDevDeg = area > 0 ? sum / area : 0;
	st.unmeasuredFaces = unmeasured;
	if (!measures_.gap.empty()) {
		st.distanceBound = double(*std::max_element(measures_.gap.begin(), measures_.gap.end()));
		out_.superfaceBound.assign(st.superfaces, 0.0f);
		for (size_t f = 0; f < t_.nF; ++f) {
			const int32_t s = p_.label[f];
			if (s >= 0)
				out_.superfaceBound[size_t(s)] =
				    std::max(out_.superfaceBound[size_t(s)], measures_.gap[f]);
		}
	}
	if (!measures_.tex.empty())
		st.maxTexError = double(*std::max_element(measures_.tex.begin(), measures_.tex.end()));
}

} // namespace detail
} // namespace gausslod
