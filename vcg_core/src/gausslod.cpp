// The pipeline (paper section 2): topology and vertex classes, the finest near-coplanar sets,
// then level by level from fine to coarse: geometry of the level, then the partition of the next
// coarser level by merging sibling cells.
#include "level_chain.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <memory>
#include <new>

namespace gausslod {

double levelBoundDeg(int level) { return std::sqrt(2.0) * 90.0 / meshNum(level); }

double bboxDiagonal(const MeshView &m)
{
	double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
	for (size_t v = 0; v < m.vertexCount; ++v)
		for (int k = 0; k < 3; ++k) {
			const double x = m.positions[3 * v + size_t(k)];
			if (std::isfinite(x)) {
				lo[k] = std::min(lo[k], x);
				hi[k] = std::max(hi[k], x);
			}
		}
	if (!(lo[0] <= hi[0]))
		return 0;
	const double dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
	return std::sqrt(dx * dx + dy * dy + dz * dz);
}

namespace {

std::string validateMesh(const MeshView &m)
{
	if (m.faceCount == 0 || m.triangles == nullptr)
		return "the mesh has no faces (GaussLOD needs a triangle mesh, not a point cloud)";
	if (m.vertexCount >= size_t(INT32_MAX) || m.faceCount >= size_t(INT32_MAX) / 3)
		return "the mesh is too large (more than 2^31 vertices or 2^31/3 faces)";
	for (size_t i = 0; i < 3 * m.faceCount; ++i) {
		const int32_t v = m.triangles[i];
		if (v < 0 || size_t(v) >= m.vertexCount)
			return "face " + std::to_string(i / 3) + " refers to vertex " + std::to_string(v) +
			       ", which does not exist";
		for (int k = 0; k < 3; ++k)
			if (!std::isfinite(m.positions[3 * size_t(v) + size_t(k)]))
				return "vertex " + std::to_string(v) + " (used by face " + std::to_string(i / 3) +
				       ") has a non-finite coordinate";
	}
	return {};
}

// Input stats that the topology knows (skipped, degenerate, locked); welding is counted before.
void countRepairs(const MeshView &m, const detail::Topology &t, InputStats &in)
{
	size_t dropped = 0;
	for (size_t f = 0; f < t.nF; ++f) {
		if (t.faceDropped[f]) {
			const int32_t *v = m.triangles + 3 * f;
			++dropped;
			in.facesRepeatedVertex += v[0] == v[1] || v[1] == v[2] || v[0] == v[2];
		} else {
			in.facesDegenerate += !t.faceValid[f];
		}
	}
	in.facesDuplicate = dropped - in.facesRepeatedVertex;
	if (m.keepFace)
		for (size_t f = 0; f < t.nF; ++f)
			in.facesKept += m.keepFace[f] && !t.faceDropped[f];
	for (uint8_t l : t.vertexLocked)
		in.verticesLocked += l;
}

// No silent loss: the input faces (not skipped) whose superface has no output triangle.
size_t uncoveredFaces(const detail::Topology &t, const LevelMesh &lm)
{
	std::vector<uint8_t> covered(lm.stats.superfaces, 0);
	for (int32_t sf : lm.superface)
		if (sf >= 0 && size_t(sf) < covered.size())
			covered[size_t(sf)] = 1;
	size_t lost = 0;
	for (size_t f = 0; f < t.nF; ++f) {
		const int32_t sf = f < lm.inputSuperface.size() ? lm.inputSuperface[f] : -1;
		lost +=
		    !t.faceDropped[f] && (sf < 0 || size_t(sf) >= covered.size() || !covered[size_t(sf)]);
	}
	return lost;
}

bool fail(Result &res, ErrorKind kind, std::string error)
{
	res.ok = false;
	res.errorKind = kind;
	res.error = std::move(error);
	res.levels.clear();
	return false;
}

// The input as the levels see it: welded (Params::weldVertices), and without the vertices welded
// away when they are many (an STL soup has 6 corners per vertex: the levels' per-vertex arrays
// would be 6 times as long). `mesh` then refers to `triangles` and `positions`; `inputVertex` is
// each vertex's index in the input (empty: the input's vertices as they are). Dropping them
// changes no position in use and no order among the rest; the diagonal is the input's (`diagonal`).
struct WeldedInput {
	std::vector<int32_t> triangles;   ///< on the welded vertices (empty: nothing welded)
	std::vector<double> positions;    ///< the kept vertices (with inputVertex only)
	std::vector<int32_t> inputVertex; ///< input index per kept vertex (empty: all kept)
	double diagonal = 0;              ///< the input's bounding box diagonal
};

// A vertex array is compacted when at least this share of it was welded away.
constexpr double kCompactWelded = 0.125;

void weldInput(const MeshView &input, const Params &params, MeshView &mesh, WeldedInput &w,
               InputStats &stats)
{
	mesh = input;
	w.diagonal = bboxDiagonal(input);
	if (!params.weldVertices)
		return;
	std::vector<int32_t> rep;
	stats.weldedVertices = detail::weldVertices(input, params.weldDistance * w.diagonal, rep);
	if (stats.weldedVertices == 0)
		return;
	const bool compact = double(stats.weldedVertices) >= kCompactWelded * double(input.vertexCount);
	if (compact) { // (rep[v] = its new index, for a kept vertex)
		w.inputVertex.reserve(input.vertexCount - stats.weldedVertices);
		w.positions.reserve(3 * (input.vertexCount - stats.weldedVertices));
		for (size_t v = 0; v < input.vertexCount; ++v)
			if (rep[v] == int32_t(v)) {
				rep[v] = int32_t(w.inputVertex.size());
				w.inputVertex.push_back(int32_t(v));
				w.positions.insert(w.positions.end(), input.positions + 3 * v,
				                   input.positions + 3 * v + 3);
			} else { // (welded into an earlier vertex: its new index is known)
				rep[v] = rep[size_t(rep[v])];
			}
	}
	w.triangles.resize(3 * input.faceCount);
	for (size_t f = 0; f < input.faceCount; ++f) {
		bool changed = false;
		for (size_t k = 0; k < 3; ++k) {
			const int32_t v = input.triangles[3 * f + k], r = rep[size_t(v)];
			w.triangles[3 * f + k] = r;
			changed |= (compact ? w.inputVertex[size_t(r)] : r) != v;
		}
		stats.facesReindexed += changed;
	}
	mesh.triangles = w.triangles.data();
	if (compact) {
		mesh.positions = w.positions.data();
		mesh.vertexCount = w.inputVertex.size();
	}
}

// What buildLevels and checkInput share: validation, welding, topology, input repairs.
bool prepare(const MeshView &input, const Params &params, Result &res, MeshView &mesh,
             WeldedInput &welded, detail::Topology &topo, size_t threads)
{
	std::string error = validateParams(params);
	if (!error.empty())
		return fail(res, ErrorKind::BadParameter, error);
	error = validateMesh(input);
	if (!error.empty())
		return fail(res, ErrorKind::BadInput, error);
	weldInput(input, params, mesh, welded, res.input);
	// (the vertex classes are the levels' business: buildLevels classifies the mesh it builds on)
	detail::buildTopology(mesh, params.featureAngle, topo, threads, false, false, welded.diagonal);
	countRepairs(mesh, topo, res.input);
	if (res.input.facesSkipped() == mesh.faceCount)
		return fail(res, ErrorKind::BadInput,
		            "every face repeats a vertex or an earlier face (" +
		                std::to_string(res.input.facesRepeatedVertex) +
		                " with a repeated vertex, " + std::to_string(res.input.facesDuplicate) +
		                " repeated): nothing to simplify");
	return true;
}

// DESIGN 41: the levels are built on the input with its exactly coplanar regions re-triangulated
// from their outlines (the same surface), if that saves faces.
struct ReducedInput {
	bool reduced = false;
	size_t inputFaces = 0; ///< the faces before the reduction
	detail::CoplanarReduction red;
	std::vector<uint32_t> faceKey, cornerKey;
	std::vector<uint8_t> keep;
	detail::Topology topo;
};

// Reduces `mesh` (see ReducedInput) and returns the topology the levels are built on: the
// reduced mesh's, or the input's (then classified).
detail::Topology &reduceInput(const Params &params, size_t threads, MeshView &mesh,
                              std::unique_ptr<detail::Topology> &inputTopo, ReducedInput &r,
                              InputStats &stats)
{
	using namespace detail;
	const MeshView full = mesh;
	r.inputFaces = full.faceCount;
	CoplanarReduction &red = r.red;
	// (levels by error promise each level's proven distance within its target: a reduction that
	// moves the surface at all, by float rounding, is not taken there)
	const bool byError = !params.levelDistances.empty() && params.levelFaces.empty();
	r.reduced = params.coplanarFirst && reduceCoplanar(mesh, *inputTopo, threads, red) &&
	            !(byError && red.distance > 0);
	if (!r.reduced) {
		red = CoplanarReduction(); // (its memory: nothing to map)
		classifyTopology(*inputTopo, params.featureAngle, threads);
		return *inputTopo;
	}
	const size_t nR = red.faceOf.size();
	mesh.positions = red.positions.data();
	mesh.vertexCount = red.vertexOf.size();
	mesh.triangles = red.triangles.data();
	mesh.faceCount = nR;
	if (full.faceKey) {
		r.faceKey.resize(nR);
		for (size_t g = 0; g < nR; ++g)
			r.faceKey[g] = full.faceKey[size_t(red.faceOf[g])];
		mesh.faceKey = r.faceKey.data();
	}
	if (full.cornerKey) {
		r.cornerKey.resize(3 * nR);
		for (size_t c = 0; c < 3 * nR; ++c)
			r.cornerKey[c] = full.cornerKey[size_t(red.cornerOf[c])];
		mesh.cornerKey = r.cornerKey.data();
	}
	if (full.keepFace) {
		r.keep.resize(nR);
		for (size_t g = 0; g < nR; ++g)
			r.keep[g] = full.keepFace[size_t(red.faceOf[g])];
		mesh.keepFace = r.keep.data();
	}
	const double diagonal = inputTopo->diagonal;
	inputTopo.reset();
	stats.coplanarRegions = red.regions;
	stats.facesAfterCoplanar = nR;
	stats.coplanarDistance = red.distance;
	buildTopology(mesh, params.featureAngle, r.topo, threads, false);
	r.topo.sampleWeight = std::move(red.weight);
	r.topo.diagonal = diagonal; // (the input's: every tolerance is a fraction of it)
	return r.topo;
}

// A level as the caller sees it: on the input's faces, corners and vertices.
LevelMesh toInput(const ReducedInput &r, const WeldedInput &welded, const LevelMesh &lm)
{
	LevelMesh o = lm;
	if (r.reduced) {
		const detail::CoplanarReduction &red = r.red;
		o.inputSuperface.assign(r.inputFaces, -1);
		for (size_t f = 0; f < r.inputFaces; ++f)
			if (red.reducedOf[f] >= 0 && size_t(red.reducedOf[f]) < lm.inputSuperface.size())
				o.inputSuperface[f] = lm.inputSuperface[size_t(red.reducedOf[f])];
		for (int32_t &v : o.sourceVertex)
			v = red.vertexOf[size_t(v)];
		for (int32_t &c : o.sourceCorner)
			c = c >= 0 ? red.cornerOf[size_t(c)] : c;
		for (int32_t &f : o.sourceFace)
			f = f >= 0 ? red.faceOf[size_t(f)] : f;
		if (o.stats.distanceBound >= 0) // (the reduced surface is within the input's)
			o.stats.distanceBound += red.distance;
	}
	if (!welded.inputVertex.empty())
		for (int32_t &v : o.sourceVertex)
			v = welded.inputVertex[size_t(v)];
	return o;
}

template <class Fn>
Result guarded(Result &res, Fn fn)
{
	try {
		if (fn())
			res.ok = true;
	} catch (const std::bad_alloc &) {
		fail(res, ErrorKind::OutOfMemory, "out of memory");
	} catch (const std::exception &e) {
		fail(res, ErrorKind::Internal, std::string("internal error: ") + e.what());
	}
	return std::move(res);
}

} // namespace

Result checkInput(const MeshView &input, const Params &params)
{
	Result res;
	return guarded(res, [&] {
		MeshView mesh;
		WeldedInput welded;
		detail::Topology topo;
		return prepare(input, params, res, mesh, welded, topo, detail::threadCount(params.threads));
	});
}

Result buildLevels(const MeshView &input, const Params &params, const Progress &progress,
                   const LevelSink &sink)
{
	using namespace detail;
	Result res;
	const auto t0 = std::chrono::steady_clock::now();
	auto report = [&](double frac, const char *stage) {
		if (progress && !progress(frac, stage))
			return fail(res, ErrorKind::Cancelled, "cancelled");
		return true;
	};
	return guarded(res, [&] {
		if (!report(0.0, "adjacency and vertex classes"))
			return false;
		MeshView mesh;
		WeldedInput welded; // (the triangles on welded vertices, if any was welded)
		std::unique_ptr<Topology> inputTopo(new Topology());
		const size_t threads = threadCount(params.threads);
		if (!prepare(input, params, res, mesh, welded, *inputTopo, threads))
			return false;
		ReducedInput red;
		LevelInput in;
		in.input = &input;
		in.inputFaces = mesh.faceCount;
		in.threads = threads;
		in.topo = &reduceInput(params, threads, mesh, inputTopo, red, res.input);
		in.mesh = mesh;
		in.stats = res.input;
		LevelChain chain(params, in);
		chain.start(t0);
		res.levels.reserve(size_t(params.maxLevel));
		for (int level = params.maxLevel - 1; level >= 0; --level) {
			LevelMesh *out = nullptr;
			if (!chain.build(level, report, out))
				return false;
			if (const size_t lost = uncoveredFaces(*in.topo, *out))
				return fail(res, ErrorKind::Internal,
				            "internal error: level " + std::to_string(level) +
				                " lost the surface of " + std::to_string(lost) +
				                " input faces (no output triangle for their superface)");
			if (params.outputLevels & (1u << level)) {
				// (the level on the input's faces, if it was built on fewer)
				const bool map = red.reduced || !welded.inputVertex.empty();
				LevelMesh mapped;
				if (map)
					mapped = toInput(red, welded, *out);
				const LevelMesh &given = map ? mapped : *out;
				if (sink && !sink(given))
					return fail(res, ErrorKind::Cancelled, "cancelled");
				if (!sink) {
					res.levels.push_back(given);
				} else {
					res.levels.emplace_back();
					res.levels.back().stats = given.stats;
				}
			}
			chain.handOn();
		}
		if (!report(1.0, "done"))
			return false;
		res.totalSeconds = since(t0);
		return true;
	});
}

} // namespace gausslod
