// 2.2.1 Creating near-coplanar sets: faces bucketed by their finest Gauss-sphere cell; the faces of
// one bucket connected through 2-manifold edges form a superface.
#include "engine.h"

namespace gausslod {
namespace detail {

void finestPartition(const Topology &t, int level, Partition &out)
{
	out.level = level;
	out.label.assign(t.nF, -1);
	out.cell.clear();
	out.origin.clear();
	std::vector<CellKey> faceCell(t.nF, kInvalidCell);
	for (size_t f = 0; f < t.nF; ++f)
		if (t.faceValid[f] && !(t.keepFace && t.keepFace[f]))
			faceCell[f] = cellOfNormal(t.faceNormal[f], level);
	std::vector<int32_t> stack;
	for (size_t f0 = 0; f0 < t.nF; ++f0) {
		if (out.label[f0] >= 0)
			continue;
		const int32_t id = int32_t(out.cell.size());
		const CellKey key = faceCell[f0];
		out.cell.push_back(key);
		out.origin.push_back(int8_t(key == kInvalidCell ? -1 : level));
		out.label[f0] = id;
		if (key == kInvalidCell)
			continue; // an invalid face (or one kept at the caller's request) stays alone, as it is
		stack.assign(1, int32_t(f0));
		while (!stack.empty()) {
			const int32_t f = stack.back();
			stack.pop_back();
			for (int k = 0; k < 3; ++k) {
				const int32_t tw = t.joinTwin(size_t(3 * f + k));
				if (tw < 0)
					continue;
				const int32_t g = heFace(tw);
				if (out.label[size_t(g)] < 0 && faceCell[size_t(g)] == key) {
					out.label[size_t(g)] = id;
					stack.push_back(g);
				}
			}
		}
	}
}

} // namespace detail
} // namespace gausslod
