// Beyond the paper (DESIGN 41): the exactly coplanar regions of the input (coplanar_regions.h),
// found in parallel with a union-find over the faces.
#include "coplanar_regions.h"

#include <algorithm>
#include <cmath>

namespace gausslod {
namespace detail {

namespace {

// Union-find over faces: a component's root is its lowest face.
inline int32_t findRoot(std::vector<int32_t> &parent, int32_t f)
{
	while (parent[size_t(f)] != f)
		f = parent[size_t(f)] = parent[size_t(parent[size_t(f)])];
	return f;
}

// The faces linked across their edges (see growRegions), as components: parent[f] = the lowest
// face of f's component; size[root] = its faces.
void linkFaces(const MeshView &mesh, const Topology &t, double eps, size_t threads,
               std::vector<int32_t> &parent, std::vector<int32_t> &size)
{
	const size_t nF = t.nF;
	auto eligible = [&](size_t f) {
		return !t.faceDropped[f] && t.faceValid[f] && !(mesh.keepFace && mesh.keepFace[f]);
	};
	parent.resize(nF);
	for (size_t f = 0; f < nF; ++f)
		parent[f] = int32_t(f);
	std::vector<uint8_t> link(nF, 0); // bit e: f's edge e links it to its twin's face
	parallelRanges(nF, threads, [&](size_t f0, size_t f1, size_t) {
		for (size_t f = f0; f < f1; ++f) {
			if (!eligible(f))
				continue;
			const Vec3 n = t.faceNormal[f];
			for (size_t e = 0; e < 3; ++e) {
				const int32_t h = t.joinTwin(3 * f + e);
				if (h < 0 || size_t(heFace(h)) < f || !eligible(size_t(heFace(h))))
					continue; // (each edge once, from its lower face)
				const Vec3 a = t.pos(t.heFrom(h)), b = t.pos(t.heTo(h));
				const Vec3 cg = t.pos(t.heFrom(hePrev(h)));
				if (std::fabs((cg - a).dot(n)) <= eps && ((b - a) ^ (cg - a)).dot(n) > 0)
					link[f] |= uint8_t(1u << e);
			}
		}
	});
	for (size_t f = 0; f < nF; ++f)
		for (size_t e = 0; e < 3; ++e)
			if (link[f] & (1u << e)) {
				const int32_t a = findRoot(parent, int32_t(f)),
				              b = findRoot(parent, heFace(t.joinTwin(3 * f + e)));
				if (a != b)
					parent[size_t(std::max(a, b))] = std::min(a, b);
			}
	size.assign(nF, 0);
	for (size_t f = 0; f < nF; ++f)
		parent[f] = findRoot(parent, int32_t(f)), ++size[size_t(parent[f])];
}

// Each face's vertices against its seed's plane: bad[root] for a component that fails; the
// largest distance of the vertices checked into planeDev. True if any is bad.
bool checkSeedPlanes(const Topology &t, const std::vector<int32_t> &parent,
                     const std::vector<int32_t> &size, double eps, size_t threads,
                     std::vector<uint8_t> &bad, double &planeDev)
{
	const size_t nF = t.nF;
	bad.assign(nF, 0);
	std::vector<double> devOf(std::max<size_t>(1, threads), 0.0);
	std::vector<std::vector<int32_t>> badOf(devOf.size());
	parallelRanges(nF, threads, [&](size_t f0, size_t f1, size_t part) {
		double &dev = devOf[part];
		size_t last = SIZE_MAX;    // (the seed's plane, kept while its faces follow each other)
		size_t lastBad = SIZE_MAX; // (the last component found bad: its faces need no check)
		Vec3 n(0, 0, 0), p(0, 0, 0);
		for (size_t f = f0; f < f1; ++f) {
			const size_t s = size_t(parent[f]);
			if (size[s] < 2 || s == lastBad)
				continue;
			if (s != last)
				last = s, n = t.faceNormal[s], p = t.pos(t.T[3 * s]);
			for (size_t k = 0; k < 3; ++k) {
				const double d = std::fabs((t.pos(t.T[3 * f + k]) - p).dot(n));
				if (d > eps) { // (then planeDev is eps at least: what is skipped is below)
					badOf[part].push_back(int32_t(s));
					lastBad = s;
					break;
				}
				dev = std::max(dev, d);
			}
		}
	});
	bool anyBad = false;
	for (const std::vector<int32_t> &b : badOf)
		for (const int32_t root : b)
			bad[size_t(root)] = 1, anyBad = true;
	for (const double d : devOf)
		planeDev = std::max(planeDev, d);
	return anyBad;
}

// The faces of seed s's bad component (root) that grow from s face by face, each within eps of
// s's plane and facing its way, labelled `id` in r.of; how many (s included).
size_t growFromSeed(const Topology &t, const std::vector<int32_t> &parent, size_t root, size_t s,
                    int32_t id, double eps, std::vector<int32_t> &stack, Regions &r)
{
	const Vec3 n = t.faceNormal[s], p = t.pos(t.T[3 * s]);
	size_t members = 1;
	stack.assign(1, int32_t(s));
	r.of[s] = id;
	while (!stack.empty()) {
		const size_t f = size_t(stack.back());
		stack.pop_back();
		for (size_t e = 0; e < 3; ++e) {
			const int32_t h = t.joinTwin(3 * f + e);
			if (h < 0)
				continue;
			const size_t g = size_t(heFace(h));
			if (r.of[g] != -1 || size_t(parent[g]) != root)
				continue;
			const Vec3 c = t.pos(t.heFrom(hePrev(h)));
			const Vec3 a = t.pos(t.heFrom(h)), b = t.pos(t.heTo(h));
			if (!(std::fabs((c - p).dot(n)) <= eps && ((b - a) ^ (c - a)).dot(n) > 0))
				continue;
			r.of[g] = id;
			++members;
			stack.push_back(int32_t(g));
		}
	}
	return members;
}

} // namespace

// Regions of 2+ faces: connected across 2-manifold, non-delimiter edges, every vertex within eps
// of the plane of the region's first face (its seed), every face facing the same way as the seed
// (a face folded back onto the plane is not one with it). In parallel: each edge links its two
// faces if the upper face's third vertex is within eps of the lower face's plane and it faces
// the same way; the linked faces' components whose every vertex is within eps of the seed's
// plane are the regions; a component that is not (a surface curving too slowly for one edge to
// show it) is grown again face by face from its faces in order, against each seed's plane.
void growRegions(const MeshView &mesh, const Topology &t, double eps, size_t threads, Regions &r)
{
	const size_t nF = t.nF;
	std::vector<int32_t> parent, size;
	linkFaces(mesh, t, eps, threads, parent, size);
	// a component of m faces saves at most m - 1: if that cannot be an eighth of the faces, the
	// reduction is not worth a second topology (and nothing more is allocated)
	size_t canSave = 0;
	for (size_t f = 0; f < nF; ++f)
		canSave += size_t(parent[f]) == f ? size_t(size[f]) - 1 : 0;
	if (8 * canSave < nF)
		return;
	std::vector<uint8_t> bad;
	double planeDev = 0;
	const bool anyBad = checkSeedPlanes(t, parent, size, eps, threads, bad, planeDev);
	// the regions, in the order of their seeds; a bad component grown again face by face
	r.of.assign(nF, -1);
	std::vector<int32_t> stack;
	for (size_t s = 0; s < nF; ++s) {
		const size_t root = size_t(parent[s]);
		if (size[root] < 2 || r.of[s] != -1)
			continue;
		if (!bad[root] && root != s)
			continue; // (its root came first: the component's lowest face)
		const int32_t id = int32_t(r.seed.size());
		if (!bad[root]) {
			r.seed.push_back(int32_t(s));
			r.of[s] = id;
			continue; // (its other faces: below)
		}
		if (growFromSeed(t, parent, root, s, id, eps, stack, r) < 2) {
			r.of[s] = -2; // (a region of its own: -1 below)
			continue;
		}
		r.seed.push_back(int32_t(s));
	}
	for (size_t f = 0; f < nF; ++f) {
		const size_t root = size_t(parent[f]);
		if (size[root] >= 2 && !bad[root])
			r.of[f] = r.of[root];
		else if (r.of[f] < 0)
			r.of[f] = -1;
	}
	r.planeDev = std::max(r.planeDev, planeDev);
	if (anyBad) // (a bad component's faces grown again are within eps of their seeds' planes)
		r.planeDev = std::max(r.planeDev, eps);
	r.dead.assign(r.seed.size(), 0);
}

} // namespace detail
} // namespace gausslod
