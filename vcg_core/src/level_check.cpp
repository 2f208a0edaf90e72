// The whole-level check: each superface was checked on its own (2.4); across superfaces, an edge
// used by more triangles than in the input, or twice in the same direction where the input had it
// right, comes from a re-triangulated superface: those superfaces fail.
#include "level_passes.h"

namespace gausslod {
namespace detail {

namespace {

struct Side {
	int32_t hi;  ///< the edge's larger vertex
	int32_t tri; ///< 2 * triangle + 1 if it runs from the larger vertex to the smaller
};

// How many input faces use edge a-b, and how many of them from a to b.
void inputUse(const Topology &t, int32_t a, int32_t b, int &count, int &forward)
{
	count = forward = 0;
	for (int32_t q = t.vfStart[size_t(a)]; q < t.vfStart[size_t(a) + 1]; ++q)
		for (int k = 0; k < 3; ++k) {
			const int32_t h = 3 * t.vfFace[size_t(q)] + k;
			if (t.heFrom(h) == a && t.heTo(h) == b)
				++count, ++forward;
			else if (t.heFrom(h) == b && t.heTo(h) == a)
				++count;
		}
}

// The sides [i, j) of one edge (v, i->hi): marks the superfaces of its new triangles bad if the
// edge is used wrongly.
void checkEdge(const Topology &t, const LevelTriangles &lt, int32_t v, const Side *i, const Side *j,
               std::vector<uint8_t> &bad)
{
	const size_t cnt = size_t(j - i);
	bool anyNew = false;
	for (const Side *q = i; q < j; ++q)
		anyNew = anyNew || (lt.triBorder[size_t(q->tri >> 1)] & kNewTriangle);
	if (!anyNew || cnt < 2)
		return;
	const bool sameDir = cnt == 2 && (i->tri & 1) == ((i + 1)->tri & 1);
	if (cnt == 2 && !sameDir)
		return;
	int inputCnt, inputFwd;
	inputUse(t, v, i->hi, inputCnt, inputFwd);
	const bool inputSameDir = inputCnt == 2 && (inputFwd == 0 || inputFwd == 2);
	if ((cnt > 2 && int(cnt) > inputCnt) || (sameDir && !inputSameDir))
		for (const Side *q = i; q < j; ++q) {
			const size_t tri = size_t(q->tri >> 1);
			if (lt.triBorder[tri] & kNewTriangle)
				bad[size_t(lt.triSf[tri])] = 1;
		}
}

} // namespace

void checkLevelEdges(const Topology &t, size_t superfaces, const LevelTriangles &lt,
                     FailedList &failed)
{
	// only an edge with both ends on new triangles can be a new problem: those edges, one
	// record per triangle side, grouped by the smaller vertex, each group then sorted by the
	// larger one
	const size_t nt = lt.triBorder.size();
	std::vector<uint8_t> onNew(t.nV, 0);
	for (size_t tri = 0; tri < nt; ++tri)
		if (lt.triBorder[tri] & kNewTriangle)
			for (size_t c = 0; c < 3; ++c)
				onNew[size_t(lt.tris[3 * tri + c])] = 1;
	std::vector<int32_t> start;
	std::vector<Side> side;
	fillBuckets<Side>(
	    t.nV,
	    [&](auto emit) {
		    for (size_t tri = 0; tri < nt; ++tri) {
			    const int32_t *v = &lt.tris[3 * tri];
			    for (int c = 0; c < 3; ++c) {
				    const int32_t a = v[c], b = v[c == 2 ? 0 : c + 1];
				    if (onNew[size_t(a)] && onNew[size_t(b)])
					    emit(size_t(std::min(a, b)),
					         Side{std::max(a, b), int32_t(2 * tri) + (a > b ? 1 : 0)});
			    }
		    }
	    },
	    start, side);
	std::vector<uint8_t> bad(superfaces, 0);
	for (size_t v = 0; v < t.nV; ++v) {
		Side *gb = side.data() + start[v], *ge = side.data() + start[v + 1];
		if (ge - gb < 2)
			continue;
		if (ge - gb <= 16) { // (insertion sort: a vertex has few edges, usually)
			for (Side *i = gb + 1; i < ge; ++i)
				for (Side *j = i; j > gb && j->hi < (j - 1)->hi; --j)
					std::swap(*j, *(j - 1));
		} else {
			std::sort(gb, ge, [](const Side &x, const Side &y) { return x.hi < y.hi; });
		}
		for (Side *i = gb; i < ge;) {
			Side *j = i + 1;
			while (j < ge && j->hi == i->hi)
				++j;
			checkEdge(t, lt, int32_t(v), i, j, bad);
			i = j;
		}
	}
	for (size_t s = 0; s < bad.size(); ++s)
		if (bad[s])
			failed.emplace_back(int32_t(s), Failure::Ring);
}

} // namespace detail
} // namespace gausslod
