// Beyond the paper (DESIGN 41): a reduction before 2.1 that keeps the surface. Connected faces
// that lie in one plane (every vertex within eps of it, facing its way; eps = 1e-9 of the
// diagonal, or 8 float ulps for an input of float coordinates) form a region; the vertices inside
// a region, and those on a straight chain between two regions (or along the mesh's boundary),
// are dropped, and each region is re-triangulated from its remaining outline. The reduced mesh
// is the same surface (within 3 eps; the distance measured is reported), on input vertices:
// every level is built on it instead of on the input (an over-tessellated plane costs its
// outline, not its faces). Passes over the faces and the vertices, in parallel, and one
// constrained Delaunay triangulation per region.
#include "coplanar_regions.h"

#include <algorithm>
#include <atomic>
#include <cmath>

namespace gausslod {
namespace detail {

namespace {

// Which vertices the reduced mesh keeps: every vertex of a face outside the regions, locked,
// forced (see regionRings) or on more than two regions; a vertex inside one region (every edge
// at it between faces of that region) is dropped, and one whose only border edges are two,
// straight through it (within eps of the segment between their other ends), between two regions
// or along the boundary of one. Per vertex, in parallel.
void chooseKept(const Topology &t, const Regions &r, double eps, const std::vector<uint8_t> &forced,
                size_t threads, std::vector<uint8_t> &keep)
{
	keep.assign(t.nV, 1);
	auto regionOf = [&](int32_t f) {
		const int32_t k = r.of[size_t(f)];
		return k >= 0 && !r.dead[size_t(k)] ? k : -1;
	};
	parallelRanges(t.nV, threads, [&](size_t v0, size_t v1, size_t) {
		for (size_t v = v0; v < v1; ++v) {
			if (t.vertexLocked[v] || forced[v] || t.vfStart[v] == t.vfStart[v + 1])
				continue;
			int32_t r1 = -1, r2 = -1, ends[2] = {-1, -1};
			int nEnds = 0;
			bool ok = true;
			for (int32_t q = t.vfStart[v]; q < t.vfStart[v + 1] && ok; ++q) {
				const int32_t f = t.vfFace[size_t(q)];
				const int32_t rf = regionOf(f);
				if (rf < 0 || (r1 >= 0 && r2 >= 0 && rf != r1 && rf != r2)) {
					ok = false;
					break;
				}
				(r1 < 0 || rf == r1 ? r1 : r2) = rf;
				// its two edges at v, (v -> x) and (y -> v): a border edge's other end
				int32_t hv = 3 * f;
				while (t.T[size_t(hv)] != int32_t(v))
					++hv;
				for (const int32_t h : {hv, hePrev(hv)}) {
					const int32_t tw = t.joinTwin(size_t(h));
					if (tw >= 0 && regionOf(heFace(tw)) == rf)
						continue; // (inside the region)
					const int32_t other = h == hv ? t.heTo(h) : t.heFrom(h);
					if (other == ends[0] || other == ends[1])
						continue;
					if (nEnds == 2) {
						ok = false;
						break;
					}
					ends[nEnds++] = other;
				}
			}
			if (!ok)
				continue;
			if (nEnds == 0) { // inside one region (two regions meet along an edge: never here)
				keep[v] = r2 >= 0;
				continue;
			}
			if (nEnds != 2)
				continue;
			const Vec3 a = t.pos(ends[0]), c = t.pos(ends[1]), p = t.pos(int32_t(v));
			const Vec3 ac = c - a;
			const double len2 = ac.SquaredNorm(), u = len2 > 0 ? (p - a).dot(ac) / len2 : -1;
			if (u > 0 && u < 1 && pointSegmentDistance(p, a, c) <= eps)
				keep[v] = 0;
		}
	});
}

// A worker of the regions' triangulations: its triangles and scratch.
struct RegionWorker {
	std::vector<int32_t> tris, ringVerts, ringStart, touched, forcedList, sorted;
	TriangulationJob job;
	size_t forced = 0;
	double chainDev = 0; ///< the largest distance of a dropped chain vertex from its segment
};

// The rings of region r (its border half-edges, the region on their left), as their kept
// vertices, appended to w.ringVerts (w.ringStart: where each ring begins). False if a border
// vertex is passed twice (a pinch) or a ring keeps fewer than 3 vertices.
bool regionRings(const Topology &t, const Regions &r, int32_t reg, const int32_t *faces,
                 size_t nFaces, const std::vector<uint8_t> &keep, double eps,
                 const std::vector<uint8_t> &forced, std::vector<uint8_t> &heSeen, RegionWorker &w)
{
	std::vector<int32_t> &forcedList = w.forcedList, &ringVerts = w.ringVerts,
	                     &ringStart = w.ringStart, &touched = w.touched, &sorted = w.sorted;
	size_t &forcedCount = w.forced;
	double &chainDev = w.chainDev;
	auto inside = [&](int32_t h) {
		const int32_t tw = t.joinTwin(size_t(h));
		return tw >= 0 && r.of[size_t(heFace(tw))] == reg;
	};
	ringVerts.clear();
	ringStart.assign(1, 0);
	bool ok = true;
	for (size_t i = 0; i < nFaces; ++i)
		for (int32_t e = 0, f = faces[i]; e < 3 && ok; ++e) {
			const int32_t h0 = 3 * f + e;
			if (inside(h0) || heSeen[size_t(h0)])
				continue;
			// walk the ring from h0: the next border half-edge starts where this one ends
			int32_t h = h0;
			size_t guard = 0;
			do {
				heSeen[size_t(h)] = 1;
				touched.push_back(h);
				ringVerts.push_back(t.heFrom(h));
				int32_t n = heNext(h);
				while (inside(n) && ++guard < 64 * t.nF)
					n = heNext(t.joinTwin(size_t(n)));
				h = n;
			} while (h != h0 && ++guard < 64 * t.nF && !heSeen[size_t(h)]);
			if (h != h0)
				ok = false; // (a ring that does not close on itself: a pinch)
			// its kept vertices; each run of dropped ones within eps of the segment that
			// replaces it, else the farthest is kept from now on (forced) and false
			const size_t b = size_t(ringStart.back()), n = ringVerts.size() - b;
			size_t first = 0;
			while (first < n && !keep[size_t(ringVerts[b + first])])
				++first;
			if (ok && first < n)
				for (size_t step = 1, runStart = 0, run = 0; step <= n; ++step) {
					const size_t i = (first + step) % n;
					const int32_t v = ringVerts[b + i];
					if (!keep[size_t(v)]) {
						if (run++ == 0)
							runStart = i;
						continue;
					}
					const int32_t a = ringVerts[b + (runStart + n - 1) % n];
					double worst = eps;
					int32_t far = -1;
					for (size_t j = 0; j < run; ++j) {
						const int32_t x = ringVerts[b + (runStart + j) % n];
						const double d = pointSegmentDistance(t.pos(x), t.pos(a), t.pos(v));
						if (d > worst)
							worst = d, far = x;
						else if (d <= eps) // (a run with a farther vertex is not taken)
							chainDev = std::max(chainDev, d);
					}
					if (far >= 0 && !forced[size_t(far)])
						forcedList.push_back(far), ++forcedCount, ok = false;
					run = 0;
				}
			size_t w = b;
			for (size_t i = b; i < ringVerts.size(); ++i)
				if (keep[size_t(ringVerts[i])])
					ringVerts[w++] = ringVerts[i];
			ringVerts.resize(w);
			if (w - b < 3)
				ok = false;
			ringStart.push_back(int32_t(ringVerts.size()));
		}
	// a vertex twice in the rings: a pinch (the triangulation would need it once)
	if (ok) {
		sorted.assign(ringVerts.begin(), ringVerts.end());
		std::sort(sorted.begin(), sorted.end());
		ok = std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end();
	}
	return ok;
}

// The distance within which faces count as one plane and vertices as on one line: 1e-9 of the
// diagonal, or, if every coordinate is a float (a PLY or STL file of 32-bit coordinates, whose
// rounding moves a plane's points off it by an ulp or two), 8 float ulps of the largest
// coordinate.
double coplanarTolerance(const Topology &t)
{
	double maxAbs = 0;
	bool floats = true;
	for (size_t i = 0; i < 3 * t.nV; ++i) {
		const double x = t.P[i];
		if (!std::isfinite(x))
			continue;
		maxAbs = std::max(maxAbs, std::fabs(x));
		floats = floats && double(float(x)) == x;
	}
	const double exact = 1e-9 * t.diagonal;
	if (!floats || !(maxAbs > 0))
		return exact;
	return std::max(exact, 8 * std::ldexp(1.0, std::ilogb(maxAbs) - 23));
}

// The faces of each region: those of region k are faces[start[k] .. start[k + 1]), in order.
void regionFaces(const Topology &t, const Regions &r, std::vector<int32_t> &start,
                 std::vector<int32_t> &faces)
{
	const size_t nR = r.seed.size();
	start.assign(nR + 1, 0);
	for (size_t f = 0; f < t.nF; ++f)
		if (r.of[f] >= 0)
			++start[size_t(r.of[f]) + 1];
	for (size_t k = 0; k < nR; ++k)
		start[k + 1] += start[k];
	faces.resize(size_t(start[nR]));
	std::vector<int32_t> fill(start.begin(), start.end() - 1);
	for (size_t f = 0; f < t.nF; ++f)
		if (r.of[f] >= 0)
			faces[size_t(fill[size_t(r.of[f])]++)] = int32_t(f);
}

// The regions' triangulations: region k's (if not dead) are tris[triStart[k] .. triEnd[k]) of
// worker triWorker[k], on input vertices; keep: the kept vertices they were made with.
struct RegionTriangles {
	std::vector<int32_t> start, faces; ///< regionFaces
	std::vector<uint8_t> keep;
	std::vector<int32_t> triStart, triEnd;
	std::vector<uint8_t> triWorker;
	std::vector<RegionWorker> work;
};

// Region k's rings (regionRings) projected on its seed's plane and triangulated, into w.job;
// false if either fails.
bool triangulateRegion(const Topology &t, Regions &r, size_t k, const RegionTriangles &rt,
                       double eps, const std::vector<uint8_t> &forced, std::vector<uint8_t> &heSeen,
                       RegionWorker &w)
{
	const std::vector<int32_t> &start = rt.start;
	bool ok = regionRings(t, r, int32_t(k), &rt.faces[size_t(start[k])],
	                      size_t(start[k + 1] - start[k]), rt.keep, eps, forced, heSeen, w);
	for (const int32_t h : w.touched)
		heSeen[size_t(h)] = 0;
	w.touched.clear();
	if (!ok)
		return false;
	const Vec3 N = t.faceNormal[size_t(r.seed[k])];
	const Vec3 U = planeAxis(N);
	const Vec3 V = N ^ U;
	const Vec3 o = t.pos(w.ringVerts[0]);
	w.job.xy.clear();
	w.job.same.clear();
	w.job.queryXY.clear();
	w.job.ringStart = w.ringStart;
	for (const int32_t v : w.ringVerts) {
		const Vec3 q = t.pos(v) - o;
		w.job.xy.push_back(q.dot(U));
		w.job.xy.push_back(q.dot(V));
	}
	return triangulateRings(w.job, true);
}

// The regions around a vertex whose choice changed (keep against before) are to be done again.
void markChanged(const Topology &t, const Regions &r, const std::vector<uint8_t> &keep,
                 const std::vector<uint8_t> &before, std::vector<uint8_t> &redo)
{
	std::fill(redo.begin(), redo.end(), uint8_t(0));
	for (size_t v = 0; v < t.nV; ++v)
		if (keep[v] != before[v])
			for (int32_t q = t.vfStart[v]; q < t.vfStart[v + 1]; ++q) {
				const int32_t k = r.of[size_t(t.vfFace[size_t(q)])];
				if (k >= 0 && !r.dead[size_t(k)])
					redo[size_t(k)] = 1;
			}
}

// Kept vertices, rings and triangulations (per region, in parallel). A region that cannot be
// triangulated is given up (its faces stay as they are), a run of dropped chain vertices too
// far from its segment keeps its farthest vertex from then on; then the vertices are chosen
// again and the regions around a vertex whose choice changed are triangulated again.
void triangulateRegions(const Topology &t, Regions &r, double eps, size_t threads,
                        RegionTriangles &rt)
{
	const size_t nR = r.seed.size();
	std::vector<uint8_t> before, forced(t.nV, 0), heSeen(3 * t.nF, 0), redo(nR, 1);
	rt.triStart.assign(nR, 0), rt.triEnd.assign(nR, 0); // (into the worker's `tris`)
	rt.triWorker.assign(nR, 0);
	const size_t workers = std::max<size_t>(1, std::min(threads, nR / 64 + 1));
	rt.work.resize(workers);
	for (bool again = true; again;) {
		again = false;
		before.swap(rt.keep);
		chooseKept(t, r, eps, forced, threads, rt.keep);
		if (!before.empty())
			markChanged(t, r, rt.keep, before, redo);
		std::atomic<size_t> next(0);
		onWorkers(workers, [&](size_t wi) {
			RegionWorker &w = rt.work[wi];
			for (size_t k; (k = next++) < nR;) {
				if (!redo[k] || r.dead[k])
					continue;
				const size_t forcedBefore = w.forced;
				if (triangulateRegion(t, r, k, rt, eps, forced, heSeen, w)) {
					rt.triWorker[k] = uint8_t(wi);
					rt.triStart[k] = int32_t(w.tris.size());
					for (const int32_t i : w.job.tris)
						w.tris.push_back(w.ringVerts[size_t(i)]);
					rt.triEnd[k] = int32_t(w.tris.size());
				} else if (w.forced == forcedBefore) {
					// (a run too far from its segment: tried again with its farthest vertex kept)
					r.dead[k] = 1;
				}
			}
		});
		for (RegionWorker &w : rt.work) {
			for (const int32_t v : w.forcedList)
				forced[size_t(v)] = 1;
			again = again || !w.forcedList.empty();
			w.forcedList.clear();
		}
		// (a region given up this pass changes its neighbours' vertices)
		for (size_t k = 0; k < nR; ++k)
			if (redo[k] && r.dead[k]) {
				again = true;
				redo[k] = 0;
			}
	}
}

// The reduced faces of region k (first face f): its triangles, each with its share of the input
// samples the region stands for (its faces and dropped vertices, by area) and a corner of the
// region at each of its vertices. stamp: per vertex, region + 1 that counted it.
void emitRegion(const Topology &t, const Regions &r, const RegionTriangles &rt, int32_t k, size_t f,
                std::vector<int32_t> &stamp, CoplanarReduction &out)
{
	const std::vector<int32_t> &tris = rt.work[rt.triWorker[size_t(k)]].tris;
	const std::vector<int32_t> &start = rt.start, &faces = rt.faces;
	double samples = double(start[size_t(k) + 1] - start[size_t(k)]), area = 0;
	for (int32_t i = start[size_t(k)]; i < start[size_t(k) + 1]; ++i) {
		const int32_t g = faces[size_t(i)];
		area += t.faceArea[size_t(g)];
		for (int32_t c = 0; c < 3; ++c) {
			const int32_t v = t.T[size_t(3 * g + c)];
			if (!rt.keep[size_t(v)] && stamp[size_t(v)] != k + 1) {
				stamp[size_t(v)] = k + 1;
				samples += 1;
			}
		}
	}
	for (int32_t i = rt.triStart[size_t(k)]; i < rt.triEnd[size_t(k)]; i += 3) {
		const Vec3 a = t.pos(tris[size_t(i)]), b = t.pos(tris[size_t(i + 1)]),
		           c = t.pos(tris[size_t(i + 2)]);
		const double share = area > 0 ? 0.5 * ((b - a) ^ (c - a)).Norm() / area : 0;
		out.weight.push_back(float(samples * share));
		out.faceOf.push_back(int32_t(f));
		for (int32_t c = 0; c < 3; ++c) {
			const int32_t v = tris[size_t(i + c)];
			out.triangles.push_back(v);
			// a corner of the region at v (every kept ring vertex is a vertex of its faces)
			int32_t corner = -1;
			for (int32_t q = t.vfStart[size_t(v)]; q < t.vfStart[size_t(v) + 1] && corner < 0;
			     ++q) {
				const int32_t g = t.vfFace[size_t(q)];
				if (r.of[size_t(g)] == k)
					for (int32_t j = 0; j < 3; ++j)
						if (t.T[size_t(3 * g + j)] == v)
							corner = 3 * g + j;
			}
			out.cornerOf.push_back(corner);
		}
	}
}

// The reduced faces, in the order of each region's first face (on input vertex numbers).
void emitReduced(const Topology &t, const Regions &r, const RegionTriangles &rt,
                 CoplanarReduction &out)
{
	std::vector<uint8_t> emitted(r.seed.size(), 0);
	std::vector<int32_t> stamp(t.nV, 0); // (region + 1 that counted a dropped vertex)
	out.reducedOf.assign(t.nF, -1);
	for (size_t f = 0; f < t.nF; ++f) {
		if (t.faceDropped[f])
			continue;
		const int32_t k = r.of[f];
		if (k < 0 || r.dead[size_t(k)]) {
			out.reducedOf[f] = int32_t(out.faceOf.size());
			out.weight.push_back(1.0f);
			out.faceOf.push_back(int32_t(f));
			for (size_t c = 0; c < 3; ++c) {
				out.triangles.push_back(t.T[3 * f + c]);
				out.cornerOf.push_back(int32_t(3 * f + c));
			}
			continue;
		}
		if (emitted[size_t(k)]) {
			out.reducedOf[f] = out.reducedOf[size_t(rt.faces[size_t(rt.start[size_t(k)])])];
			continue;
		}
		emitted[size_t(k)] = 1;
		++out.regions;
		out.reducedOf[f] = int32_t(out.faceOf.size());
		emitRegion(t, r, rt, k, f, stamp, out);
	}
}

// The vertices the reduced faces use, renumbered in input order.
void compactVertices(const Topology &t, CoplanarReduction &out)
{
	std::vector<int32_t> compact(t.nV, -1);
	for (const int32_t v : out.triangles)
		compact[size_t(v)] = 0;
	for (size_t v = 0; v < t.nV; ++v)
		if (compact[v] == 0) {
			compact[v] = int32_t(out.vertexOf.size());
			out.vertexOf.push_back(int32_t(v));
			for (size_t k = 0; k < 3; ++k)
				out.positions.push_back(t.P[3 * v + k]);
		}
	for (int32_t &v : out.triangles)
		v = compact[size_t(v)];
}

} // namespace

bool reduceCoplanar(const MeshView &mesh, const Topology &t, size_t threads, CoplanarReduction &out)
{
	out = CoplanarReduction();
	if (mesh.cornerUV) // (the texture check measures the coordinates of removed vertices)
		return false;
	const double eps = coplanarTolerance(t);
	out.eps = eps;
	Regions r;
	growRegions(mesh, t, eps, threads, r);
	if (r.seed.empty())
		return false;
	const size_t nR = r.seed.size();
	RegionTriangles rt;
	regionFaces(t, r, rt.start, rt.faces);
	triangulateRegions(t, r, eps, threads, rt);
	// worth a second topology only if it saves an eighth of the faces: else nothing is built
	size_t faceCount = 0, merged = 0;
	for (size_t f = 0; f < t.nF; ++f)
		faceCount += !t.faceDropped[f] && (r.of[f] < 0 || r.dead[size_t(r.of[f])]);
	for (size_t k = 0; k < nR; ++k)
		if (!r.dead[k])
			faceCount += size_t(rt.triEnd[k] - rt.triStart[k]) / 3, ++merged;
	if (merged == 0 || 8 * faceCount >= 7 * t.nF)
		return false;
	emitReduced(t, r, rt, out);
	compactVertices(t, out);
	// (each surface within planeDev of each region's plane, the outlines within chainDev of each
	// other in it)
	double chainDev = 0;
	for (const RegionWorker &w : rt.work)
		chainDev = std::max(chainDev, w.chainDev);
	out.distance = 2 * r.planeDev + chainDev;
	return true;
}

} // namespace detail
} // namespace gausslod
