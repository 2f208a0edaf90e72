// The pipeline (paper section 2): topology and vertex classes, the finest near-coplanar sets,
// then level by level from fine to coarse: geometry of the level, then the partition of the next
// coarser level by merging sibling cells.
#include "engine.h"
#include "hausdorff.h"
#include "level_passes.h"
#include "reduce.h"

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

double since(std::chrono::steady_clock::time_point t0)
{
	return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// DESIGN 52: the level's two-sided Hausdorff distance to the caller's input, certified within
// kCertifyEps; the input's tree is built for the first level that needs it.
constexpr double kCertifyEps = 0.05;
// Levels by error, certified (DESIGN 52): the collapses' bound is searched up to this many times
// the asked error (the construction's bound measured a median 5x the true distance), in this
// many builds.
constexpr double kErrorReach = 8;
constexpr int kErrorTrials = 4;
constexpr size_t kCertifyPieces = 64; // per triangle of both sides: the refinement's budget

void certify(const MeshView &input, LevelMesh &level,
             std::unique_ptr<detail::TriangleTree> &inputTree, size_t threads)
{
	const auto t0 = std::chrono::steady_clock::now();
	if (!inputTree)
		inputTree.reset(
		    new detail::TriangleTree(input.positions, input.triangles, input.faceCount));
	const detail::TriangleTree lt(level.positions.data(), level.triangles.data(),
	                              level.triangles.size() / 3);
	const detail::HausdorffBounds h = detail::hausdorff(
	    lt, *inputTree, kCertifyEps,
	    kCertifyPieces * (lt.triangles().size() + inputTree->triangles().size()), threads);
	LevelStats &st = level.stats;
	st.hausdorff = h.upper;
	st.hausdorffLower = h.lower;
	st.hausdorffConverged = h.converged;
	st.secondsHausdorff = since(t0);
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

// Beyond the paper (DESIGN 29), in angle mode: a coarser level farther from the input than the
// finer one must have at least this share of its faces fewer, else it is the finer level (its
// extra error bought next to nothing: anchor's LOD3 had 2 faces fewer than LOD4 at 700 times
// its Hausdorff distance).
constexpr double kMinLevelSaving = 0.01;

// DESIGN 50: a finer level of more faces is not collapsed: its coarser level is the superface
// level. (The collapses' state is about 150 bytes per face of the finer level, and a collapse
// takes 15-40 microseconds. 300,000 lets the 1M-face bumpy sphere's 52,900-face LOD1 come from
// its 259,278-face LOD2: 0.147 -> 0.044 % from the input, for 4.4 -> 6.4 s and a peak of 192 ->
// 206 MB; with 150,000 it stayed a superface level. With no limit its LOD3 and LOD2 are collapsed
// too: 13.2 s and 405 MB.)
constexpr size_t kCollapseMaxFaces = 300000;

// Would a superface be held to more under limits a than under b (a smaller straightening or
// distance tolerance, normal limit or merge distance)?
bool tighter(const detail::LevelLimits &a, const detail::LevelLimits &b)
{
	return a.tolerance < b.tolerance || a.maxDistance < b.maxDistance ||
	       a.devLimitDeg < b.devLimitDeg || a.mergeDistance < b.mergeDistance;
}

// The finer level's mesh, as level `lm` (its positions and input labels were dropped from
// `finer`: see buildLevels), on the partition labels `label` (the same superfaces).
void takeFinerMesh(const MeshView &mesh, const std::vector<int32_t> &label, LevelMesh &finer,
                   const std::vector<std::pair<int32_t, detail::Vec3>> &finerPlaced, LevelMesh &lm)
{
	lm = std::move(finer);
	lm.positions.resize(3 * lm.sourceVertex.size());
	for (size_t v = 0; v < lm.sourceVertex.size(); ++v)
		for (size_t k = 0; k < 3; ++k)
			lm.positions[3 * v + k] = mesh.positions[3 * size_t(lm.sourceVertex[v]) + k];
	for (const auto &pv : finerPlaced) // (and its placed vertices)
		for (size_t k = 0; k < 3; ++k)
			lm.positions[3 * size_t(pv.first) + k] = pv.second[int(k)];
	lm.inputSuperface = label;
}

// A coarser level that came out with more faces than the finer one (2.5 promises monotone face
// counts), or farther from the input for under kMinLevelSaving fewer, is the finer level's mesh:
// its partition, with the cells of this level.
void keepFinerLevel(const MeshView &mesh, int level, std::vector<detail::Partition> &parts,
                    const detail::Partition &finerPart, LevelMesh &finer,
                    const std::vector<std::pair<int32_t, detail::Vec3>> &finerPlaced, LevelMesh &lm)
{
	detail::Partition &p = parts[size_t(level)];
	p = finerPart;
	p.level = level;
	// (its origins still point to the finer level's parts: no copy of them needed)
	p.partLabel.clear(), p.partCell.clear(), p.partOrigin.clear();
	for (CellKey &c : p.cell)
		c = c == kInvalidCell ? c : parentKey(c);
	const LevelStats spent = lm.stats; // the time was spent all the same
	takeFinerMesh(mesh, p.label, finer, finerPlaced, lm);
	lm.stats.secondsPartition = spent.secondsPartition;
	lm.stats.secondsBorders = spent.secondsBorders;
	lm.stats.secondsTriangulation = spent.secondsTriangulation;
	lm.stats.secondsChecks = spent.secondsChecks;
	lm.stats.secondsPlacement = spent.secondsPlacement;
	lm.stats.rounds = spent.rounds;
	lm.stats.level = level;
	lm.stats.boundDeg = levelBoundDeg(level);
	lm.stats.fallbacks = 0;
	lm.stats.reusedFiner = true;
}

// DESIGN 51: a level of the angle chain (Params::completeChain) has at most this share of the
// faces of the level delivered before it, and the coarsest level at most kCoarsestShare of the
// input's (the levels between, geometric shares); but its distance bound may not exceed
// kStepError times the level's distance tolerance (stepTolerance), so that a shape a step would
// break (a cube whose corners would go, planar CAD at its minimal count, a thin leg) keeps its
// count.
constexpr double kStepShare = 0.8, kCoarsestShare = 0.15, kStepError = 32;

// The distance tolerance a level's step is measured against (fraction of the diagonal): its own,
// or the default's where the tolerance is off.
double stepTolerance(const Params &p, int level)
{
	const double base = p.maxDistance > 0 ? p.maxDistance : Params().maxDistance;
	const double growth = p.maxDistance > 0 ? p.distanceGrowth : Params().distanceGrowth;
	return base * std::pow(growth, p.maxLevel - 1 - level);
}

size_t stepFaces(const Params &p, int level, size_t finerFaces, size_t inputFaces)
{
	const double share = std::pow(kCoarsestShare, double(p.maxLevel - level) / p.maxLevel);
	return std::min(size_t(std::floor(kStepShare * double(finerFaces))),
	                size_t(std::floor(share * double(inputFaces))));
}

// The distance tolerance of `level`, fraction of the diagonal (0 = none), as levelLimits reads it.
double levelTolerance(const Params &p, int level)
{
	return p.levelDistances.empty()
	           ? p.maxDistance * std::pow(p.distanceGrowth, p.maxLevel - 1 - level)
	           : p.levelDistances[size_t(level)];
}

// Levels by face count: the level's face budget (percentages of the input's faces, rounded down).
size_t faceTarget(const Params &p, int level, size_t inputFaces)
{
	const double t = p.levelFaces[size_t(level)];
	return p.levelFacesRelative ? size_t(std::floor(t * double(inputFaces) * (1 + 1e-12)))
	                            : size_t(t);
}

// The tolerance search of the faces mode, on the tolerance's logarithm (fractions of the
// diagonal): between these bounds (at the top the distance check refuses nothing: only the
// normal bound limits merging), at most this many halvings after the build at the top, ended once
// a level is within 1 % below its budget or the bracket is narrower than kSearchWidth (a factor
// 1.05: measured on fandisk, the face count is not monotone at that scale, it moves a few percent
// up and down between close tolerances, so a narrower bracket buys nothing).
constexpr double kSearchLogLo = -6, kSearchLogHi = 0, kSearchWidth = 0.02;
constexpr int kSearchSteps = 10;

// Levels by face count: builds `level` with the distance tolerance that gives it the most faces
// within `target` (the least error within the budget), into lm, and its partition into
// parts[level]: bisection of the tolerance's logarithm (faces fall as the tolerance grows, though
// not strictly: see kSearchWidth). Every trial starts from the same merged partition (the
// geometry's fallbacks split it). If even the top tolerance gives more faces than the target,
// that build is kept (the target is not reached). Deterministic: the trials and the choice
// depend on face counts only.
void buildToFaceTarget(const detail::Topology &topo, const Params &params,
                       std::vector<detail::Partition> &parts, int level, size_t target,
                       size_t faceLimit, const detail::SplitCost *cost, LevelMesh &lm,
                       detail::Partition &merged)
{
	using namespace detail;
	Params trial = params; // (levelFaces kept: levelLimits then knows these are searches, whose
	                       // distance bound is reported, not a limit as in levels by error)
	trial.levelDistances.assign(size_t(params.maxLevel), 1.0); // (only this level's is read)
	trial.placeVertices = false; // (it moves no face count: the chosen build is placed, below)
	Partition &p = parts[size_t(level)];
	Partition &start = merged;
	start = p;
	Partition bestPart;
	size_t bestFaces = 0;
	double bestTol = 0;
	int trials = 0;
	// builds with tolerance 10^logTol; the level's faces (above the finer level's count the
	// level will be the finer one); keeps the build if it fits the budget with the most faces
	auto run = [&](double logTol) {
		const double tol = std::pow(10.0, logTol);
		trial.levelDistances[size_t(level)] = tol;
		if (trials++ > 0)
			p = start;
		LevelMesh out;
		buildLevelGeometry(topo, trial, parts, p, out, faceLimit, cost);
		const size_t faces = std::min(out.stats.faces, faceLimit);
		// (a fitting trial always has the smallest tolerance of the fitting ones so far)
		if (trials == 1 || (faces <= target && faces >= bestFaces)) {
			lm = std::move(out);
			bestPart = p;
			bestFaces = faces;
			bestTol = tol;
		}
		return faces;
	};
	double hi = kSearchLogHi, lo = kSearchLogLo; // faces(hi) <= target < faces(lo)
	const bool reached = run(hi) <= target;
	for (int step = 0; reached && step < kSearchSteps && target - bestFaces > target / 100 &&
	                   hi - lo > kSearchWidth;
	     ++step) {
		const double mid = 0.5 * (lo + hi);
		(run(mid) <= target ? hi : lo) = mid;
	}
	if (params.placeVertices) { // the chosen build again, placed (the same build otherwise)
		trial.placeVertices = true;
		trial.levelDistances[size_t(level)] = bestTol;
		p = start;
		lm = LevelMesh();
		buildLevelGeometry(topo, trial, parts, p, lm, faceLimit, cost); // (not a trial)
	} else {
		p = std::move(bestPart);
	}
	lm.stats.tolerance = bestTol;
	lm.stats.trials = trials;
}

// What a level was asked for (levels by target) and whether it got it.
void setTargetStats(const Params &p, int level, size_t target, double diagonal, LevelMesh &lm)
{
	LevelStats &st = lm.stats;
	st.targetFaces = 0;
	st.targetDistance = -1;
	st.targetReached = true;
	if (!p.levelFaces.empty()) {
		st.targetFaces = target;
		st.targetReached = st.faces <= target;
		if (!st.targetReached) {
			const detail::LevelTopology lt =
			    detail::levelTopology(lm.triangles, lm.positions.size() / 3);
			st.leastFaces = lt.leastFaces;
			st.boundaryLoops = lt.boundaryLoops;
			st.components = lt.components;
		}
	} else if (!p.levelDistances.empty()) {
		st.targetDistance = p.levelDistances[size_t(level)];
		// (the level's distance bound, rounded up as a float: DESIGN 23; or its certified
		// Hausdorff distance, DESIGN 52: both are proven)
		st.targetReached = st.distanceBound <= st.targetDistance * diagonal * (1 + 1e-5) ||
		                   (st.hausdorff >= 0 && st.hausdorff <= st.targetDistance * diagonal);
	}
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
		std::unique_ptr<TriangleTree> inputTree; // (DESIGN 52, built when first needed)
		const size_t threads = threadCount(params.threads);
		if (!prepare(input, params, res, mesh, welded, *inputTopo, threads))
			return false;
		// DESIGN 41: the levels are built on the input with its exactly coplanar regions
		// re-triangulated from their outlines (the same surface), if that saves faces
		CoplanarReduction red;
		MeshView full = mesh;
		std::vector<uint32_t> redFaceKey, redCornerKey;
		std::vector<uint8_t> redKeep;
		Topology reducedTopo;
		// (levels by error promise each level's proven distance within its target: a reduction
		// that moves the surface at all, by float rounding, is not taken there)
		const bool byError = !params.levelDistances.empty() && params.levelFaces.empty();
		const bool reduced = params.coplanarFirst &&
		                     reduceCoplanar(mesh, *inputTopo, threads, red) &&
		                     !(byError && red.distance > 0);
		if (reduced) {
			const size_t nR = red.faceOf.size();
			mesh.positions = red.positions.data();
			mesh.vertexCount = red.vertexOf.size();
			mesh.triangles = red.triangles.data();
			mesh.faceCount = nR;
			if (full.faceKey) {
				redFaceKey.resize(nR);
				for (size_t g = 0; g < nR; ++g)
					redFaceKey[g] = full.faceKey[size_t(red.faceOf[g])];
				mesh.faceKey = redFaceKey.data();
			}
			if (full.cornerKey) {
				redCornerKey.resize(3 * nR);
				for (size_t c = 0; c < 3 * nR; ++c)
					redCornerKey[c] = full.cornerKey[size_t(red.cornerOf[c])];
				mesh.cornerKey = redCornerKey.data();
			}
			if (full.keepFace) {
				redKeep.resize(nR);
				for (size_t g = 0; g < nR; ++g)
					redKeep[g] = full.keepFace[size_t(red.faceOf[g])];
				mesh.keepFace = redKeep.data();
			}
			const double diagonal = inputTopo->diagonal;
			inputTopo.reset();
			res.input.coplanarRegions = red.regions;
			res.input.facesAfterCoplanar = nR;
			res.input.coplanarDistance = red.distance;
			buildTopology(mesh, params.featureAngle, reducedTopo, threads, false);
			reducedTopo.sampleWeight = std::move(red.weight);
			reducedTopo.diagonal = diagonal; // (the input's: every tolerance is a fraction of it)
		}
		if (!reduced) {
			red = CoplanarReduction(); // (its memory: nothing to map)
			classifyTopology(*inputTopo, params.featureAngle, threads);
		}
		Topology &topo = reduced ? reducedTopo : *inputTopo;
		// a level as the caller sees it: on the input's faces, corners and vertices
		const bool compacted = !welded.inputVertex.empty();
		auto toInput = [&](const LevelMesh &lm) {
			LevelMesh o = lm;
			if (reduced) {
				o.inputSuperface.assign(full.faceCount, -1);
				for (size_t f = 0; f < full.faceCount; ++f)
					if (red.reducedOf[f] >= 0 &&
					    size_t(red.reducedOf[f]) < lm.inputSuperface.size())
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
			if (compacted)
				for (int32_t &v : o.sourceVertex)
					v = welded.inputVertex[size_t(v)];
			return o;
		};
		const int finest = params.maxLevel - 1;
		const bool across = params.acrossCells;
		// cross-cell unions: normals within the level's bound of each other, and never across a
		// feature (two normals farther apart than the feature angle: sharp stays sharp)
		auto acrossLimit = [&](int level) {
			return std::min(levelBoundDeg(level), params.featureAngle);
		};
		std::vector<Partition> parts(size_t(params.maxLevel));
		// the face grid (for the levels' flip checks) is built while the finest partition is
		// (both serial; the grid only writes topo.grid; its buckets' cones are computed when a
		// check first asks for them: on most meshes few are)
		const size_t tasks = threads > 1 ? 2 : 1;
		onWorkers(tasks, [&](size_t task) {
			if (task == 1 || tasks == 1)
				buildFaceGrid(topo);
			if (task == 0) {
				finestPartition(topo, finest, parts[size_t(finest)]);
				if (across)
					mergeAcrossCells(topo, acrossLimit(finest), parts[size_t(finest)]);
			}
		});
		const double setup = since(t0);
		res.levels.reserve(size_t(params.maxLevel));
		LevelMesh finer;                                   // the previous (finer) level
		std::vector<std::pair<int32_t, Vec3>> finerPlaced; // its placed vertices: index, position
		SplitCost finerCost;         // (with the distance tolerance, see triangleShare)
		ExactCarry carry, nextCarry; // (DESIGN 31: the finer level's exact superfaces)
		const bool byFaces = !params.levelFaces.empty();
		const bool byAngle = !byFaces && params.levelDistances.empty();
		// faces mode: parts[level] is the level's merged partition before its fallbacks (what
		// the coarser levels merge), levelPart the one its mesh has (see DESIGN.md)
		Partition merged, levelPart;
		// DESIGN 50: the finer level as delivered, for the next level's collapses
		const bool collapsing = byAngle && params.collapseLevels && params.maxDistance > 0 &&
		                        !topo.UV && !mesh.keepFace;

		// DESIGN 50, 51: the level delivered before this one, as collapses start from it (made
		// from `finer` when that is the level, or a level collapses made)
		CollapseSource chain;
		bool chainIsFiner = false, chainCollapsed = false;
		for (int level = finest; level >= 0; --level) {
			const auto tl = std::chrono::steady_clock::now();
			if (!report(0.05 + 0.95 * double(finest - level) / params.maxLevel, "building level"))
				return false;
			// DESIGN 51: levels by target, once a level was made by collapses, are made by
			// collapses (the superfaces of a coarser level would not reach the target either)
			const bool superfaces = byAngle || level == finest || !chainCollapsed;
			// (DESIGN 38: the finer level carried whole tells which superfaces touch; if none
			// of them could be grouped or merged here, the partition is the finer one's)
			if (superfaces && level < finest &&
			    !(byAngle && carry.whole &&
			      sameCoarserPartition(parts[size_t(level) + 1],
			                           superfacePairs(finer.triangles, finer.superface),
			                           across ? acrossLimit(level) : -1.0, parts[size_t(level)]))) {
				coarserPartition(topo, parts[size_t(level) + 1], parts[size_t(level)],
				                 int8_t(level));
				if (across)
					mergeAcrossCells(topo, acrossLimit(level), parts[size_t(level)]);
			}
			LevelMesh lm;
			const double partitionSeconds = since(tl) + (level == finest ? setup : 0.0);
			const double tolerance = byFaces ? 1.0 : levelTolerance(params, level);
			// DESIGN 36: the finer level carried whole (ExactCarry::whole) and the same
			// superfaces here, with limits no tighter: building would take every superface as
			// it is, so the level is the finer level's mesh (one linear pass, not a build)
			const bool sameAsFiner =
			    byAngle && level < finest && carry.whole &&
			    parts[size_t(level)].label == parts[size_t(level) + 1].label &&
			    !tighter(levelLimits(params, topo.diagonal, level, topo.UV != nullptr),
			             levelLimits(params, topo.diagonal, level + 1, topo.UV != nullptr));
			const bool share = superfaces && level < finest && tolerance > 0 && !sameAsFiner;
			if (share)
				triangleShare(byFaces ? levelPart : parts[size_t(level) + 1], finer, finerCost);
			const size_t faceLimit = level < finest ? finer.stats.faces : SIZE_MAX;
			const size_t target = byFaces ? faceTarget(params, level, full.faceCount) : 0;
			if (!superfaces) { // (no build: the collapses make the level)
				lm.stats.level = level;
				lm.stats.boundDeg = levelBoundDeg(level);
				lm.stats.faces = SIZE_MAX;
				lm.stats.trials = 0;
				lm.stats.tolerance = byFaces ? 0.0 : tolerance;
			} else if (sameAsFiner) {
				takeFinerMesh(mesh, parts[size_t(level)].label, finer, finerPlaced, lm);
				lm.stats.level = level;
				lm.stats.boundDeg = levelBoundDeg(level);
				lm.stats.carriedSuperfaces = lm.stats.superfaces;
				lm.stats.rounds = 1;
				lm.stats.tolerance = tolerance;
				lm.stats.secondsBorders = lm.stats.secondsTriangulation = 0;
				lm.stats.secondsChecks = lm.stats.secondsPlacement = 0;
				nextCarry = std::move(carry); // (swapped back below: the same superfaces)
				nextCarry.label = &parts[size_t(level)].label;
			} else if (byFaces) {
				buildToFaceTarget(topo, params, parts, level, target, faceLimit,
				                  share ? &finerCost : nullptr, lm, merged);
			} else {
				buildLevelGeometry(topo, params, parts, parts[size_t(level)], lm, faceLimit,
				                   share ? &finerCost : nullptr, &carry, &nextCarry);
				lm.stats.tolerance = tolerance;
			}
			const double chosen = lm.stats.tolerance;
			const int trials = lm.stats.trials;
			lm.stats.secondsPartition = partitionSeconds;
			// (a coarser level must be lighter than the finer one; in angle mode, if it is farther
			// from the input, by at least kMinLevelSaving)
			if (superfaces && level < finest && !sameAsFiner &&
			    (lm.stats.faces > finer.stats.faces ||
			     (byAngle && lm.stats.distanceBound > finer.stats.distanceBound &&
			      double(lm.stats.faces) > (1 - kMinLevelSaving) * double(finer.stats.faces)))) {
				keepFinerLevel(mesh, level, parts, byFaces ? levelPart : parts[size_t(level) + 1],
				               finer, finerPlaced, lm);
				nextCarry = ExactCarry(); // (its superfaces are not this level's)
			}
			// DESIGN 50 and 51: the level may also come from the level delivered before it (the
			// chain; before the finest level, the input) by edge collapses
			const auto tc = std::chrono::steady_clock::now();
			// (a level that is its finer level's mesh took `finer`: no superface build)
			const bool superfaceBuilt = superfaces && !(sameAsFiner || lm.stats.reusedFiner);
			CollapseSource collapsed;
			bool takeCollapsed = false;
			auto needChain = [&] { // (makes `chain` the level delivered before this one)
				if (level == finest) {
					if (chain.empty())
						inputSource(topo, mesh, chain);
				} else if (chainIsFiner && !superfaceBuilt) { // (this level took that mesh)
					collapseSourceOf(topo, lm, chain);
					chainIsFiner = false;
				} else if (chainIsFiner) { // (its mesh has served: taken whole, partition kept)
					LevelMesh source;
					takeFinerMesh(mesh, (byFaces ? levelPart : parts[size_t(level) + 1]).label,
					              finer, finerPlaced, source);
					collapseSourceOf(topo, std::move(source), chain);
					chainIsFiner = false;
				}
			};
			const size_t chainFaces = level == finest ? full.faceCount - res.input.facesSkipped()
			                          : chainIsFiner  ? finer.stats.faces
			                                          : chain.mesh.triangles.size() / 3;
			// DESIGN 50 (angle levels): the chain collapsed to this level's face count within its
			// distance bound and normal limit, vertices kept where they are; taken where no input
			// vertex ends farther from it
			if (collapsing && level < finest && chainFaces > lm.stats.faces &&
			    chainFaces <= kCollapseMaxFaces && superfaceBuilt && lm.stats.distanceBound > 0) {
				needChain();
				ReduceLimits rl;
				rl.level = level;
				rl.faces = lm.stats.faces;
				rl.bound = lm.stats.distanceBound;
				rl.normalDeg = params.normalLimit > 0
				                   ? std::min(90.0, params.normalLimit * levelBoundDeg(level))
				                   : 90.0;
				rl.placement = false;
				rl.keepSuperfaces = true;
				ReduceReport rr;
				takeCollapsed = reduceLevel(topo, mesh, chain, rl, threads, collapsed, rr) &&
				                farthestInputVertex(topo, collapsed.mesh,
				                                    collapsed.mesh.stats.distanceBound, threads) <=
				                    farthestInputVertex(topo, lm, lm.stats.distanceBound, threads);
			}
			// DESIGN 29 against a collapsed finer level too: a level no lighter, or farther from
			// the input and not kMinLevelSaving lighter, is that level
			if (byAngle && level < finest && chainCollapsed) {
				const LevelStats &o = takeCollapsed ? collapsed.mesh.stats : lm.stats;
				if (double(o.faces) >= double(chainFaces) ||
				    (o.distanceBound > chain.mesh.stats.distanceBound &&
				     double(o.faces) > (1 - kMinLevelSaving) * double(chainFaces))) {
					collapsed = chain; // (a copy: the chain stays what the next level starts from)
					collapsed.mesh.stats.collapses = 0;
					takeCollapsed = true;
				}
			}
			// DESIGN 51: levels by target, and the angle chain's real steps, by collapses with
			// quadric placement where the superfaces do not get there
			ReduceLimits rl;
			rl.level = level;
			rl.placement = true;
			bool reduce = false;
			if (!byAngle) {
				reduce = true;
				rl.faces = byFaces ? target : 0;
				rl.bound =
				    byFaces ? HUGE_VAL : params.levelDistances[size_t(level)] * topo.diagonal;
			} else if (params.completeChain) {
				const LevelStats &o = takeCollapsed ? collapsed.mesh.stats : lm.stats;
				const size_t cap = stepFaces(params, level, chainFaces, full.faceCount);
				reduce = o.faces > cap;
				rl.faces = cap;
				rl.bound = kStepError * stepTolerance(params, level) * topo.diagonal;
			}
			if (reduce && topo.UV && params.maxTexError > 0) {
				// (a coarser level is seen smaller: its limit in texels of its own screen size,
				// the input's limit times the square root of the faces it has fewer; kept by
				// levels by error, measured against by budgets and steps: DESIGN 54)
				const size_t seen = rl.faces > 0 ? rl.faces : std::max<size_t>(chainFaces, 1);
				rl.texError = params.maxTexError *
				              std::sqrt(double(full.faceCount) / double(std::max<size_t>(seen, 1)));
				rl.texErrorSoft = !byError;
			}
			bool certifiedByTrials = false;
			if (reduce) {
				needChain();
				ReduceReport rr;
				CollapseSource reduced;
				bool got;
				if (byError && params.certifyDistance) {
					// DESIGN 52: levels by error decide by the certified distance: the collapses'
					// bound searched (kErrorTrials builds, 1 to kErrorReach x the asked error) for
					// the fewest faces whose certified Hausdorff distance is within the asked
					// error (the proven bound at 1 x is)
					const double asked = rl.bound;
					auto trial = [&](double k, CollapseSource &out, ReduceReport &r) {
						ReduceLimits t = rl;
						t.bound = asked * k;
						const bool g = reduceLevel(topo, mesh, chain, t, threads, out, r);
						certify(input, out.mesh, inputTree, threads);
						return g && (k <= 1 || out.mesh.stats.hausdorff <= asked);
					};
					// (first the proven build at 1 x; where its certified distance leaves room
					// (under 0.9 x the error), the factor's logarithm bisected from kErrorReach
					// down: the distance is not monotone in the bound, the bracket only a search)
					got = trial(1.0, reduced, rr);
					double lo = 0, hi = std::log(kErrorReach);
					for (int i = 0;
					     got && reduced.mesh.stats.hausdorff < 0.9 * asked && i < kErrorTrials;
					     ++i) {
						const double k = i == 0 ? hi : 0.5 * (lo + hi);
						CollapseSource c;
						ReduceReport r;
						if (trial(std::exp(k), c, r)) {
							reduced = std::move(c), rr = r, lo = k;
							if (i == 0)
								break;
						} else {
							hi = k;
						}
					}
					certifiedByTrials = true;
				} else {
					got = reduceLevel(topo, mesh, chain, rl, threads, reduced, rr);
				}
				const LevelStats &rs = reduced.mesh.stats;
				const LevelStats &o = takeCollapsed ? collapsed.mesh.stats : lm.stats;
				bool take;
				if (byFaces)
					take = o.faces > target
					           ? rs.faces < o.faces
					           : got && farthestInputVertex(topo, reduced.mesh, rs.distanceBound,
					                                        threads) <
					                        farthestInputVertex(topo,
					                                            takeCollapsed ? collapsed.mesh : lm,
					                                            o.distanceBound, threads);
				else if (byAngle)
					take = rs.faces < o.faces;
				else
					take = rs.faces < o.faces ||
					       (rs.faces == o.faces && rs.distanceBound < o.distanceBound);
				certifiedByTrials = certifiedByTrials && take;
				if (take) {
					collapsed = std::move(reduced);
					collapsed.mesh.stats.reduced = true;
					collapsed.mesh.stats.texErrorLimit = rr.texErrorLimit;
					measureNormalDeviation(topo, collapsed.mesh, threads);
					takeCollapsed = true;
				}
			}
			const double secondsCollapse = since(tc);
			std::swap(carry, nextCarry);
			if (byFaces) {
				levelPart = std::move(parts[size_t(level)]);
				parts[size_t(level)] = std::move(merged);
			}
			lm.stats.seconds = since(tl) + (level == finest ? setup : 0.0);
			lm.stats.tolerance = chosen;
			lm.stats.trials = trials;
			lm.stats.input = res.input;
			lm.stats.secondsCollapse = secondsCollapse;
			if (takeCollapsed) { // (the superface level's stats, but for what the mesh says)
				const LevelStats c = collapsed.mesh.stats;
				LevelStats &st = collapsed.mesh.stats;
				st = lm.stats;
				st.faces = c.faces;
				st.vertices = c.vertices;
				st.superfaces = c.superfaces;
				st.maxNormalDevDeg = c.maxNormalDevDeg;
				st.meanNormalDevDeg = c.meanNormalDevDeg;
				st.unmeasuredFaces = c.unmeasuredFaces;
				st.distanceBound = c.distanceBound;
				st.placedVertices = c.placedVertices;
				st.maxPlacement = c.maxPlacement;
				st.collapses = c.collapses;
				st.reduced = c.reduced;
				st.maxTexError = c.maxTexError;
				st.texErrorLimit = c.texErrorLimit;
				st.reusedFiner = c.collapses == 0; // (collapses made a mesh of its own)
				if (certifiedByTrials) {           // (certified by the error search, above)
					st.hausdorff = c.hausdorff;
					st.hausdorffLower = c.hausdorffLower;
					st.hausdorffConverged = c.hausdorffConverged;
					st.secondsHausdorff = c.secondsHausdorff;
				}
			}
			LevelMesh &out = takeCollapsed ? collapsed.mesh : lm;
			if (params.certifyDistance && !certifiedByTrials) { // DESIGN 52: certified
				if (!report(0.05 + 0.95 * (double(finest - level) + 0.5) / params.maxLevel,
				            "certifying the level's distance"))
					return false;
				certify(input, out, inputTree, threads);
			}
			setTargetStats(params, level, target, topo.diagonal, out);
			if (const size_t lost = uncoveredFaces(topo, out))
				return fail(res, ErrorKind::Internal,
				            "internal error: level " + std::to_string(level) +
				                " lost the surface of " + std::to_string(lost) +
				                " input faces (no output triangle for their superface)");
			const bool wanted = params.outputLevels & (1u << level);
			LevelMesh mapped; // (the level on the input's faces, if it was built on fewer)
			if (wanted && (reduced || compacted))
				mapped = toInput(out);
			const LevelMesh &given = wanted && (reduced || compacted) ? mapped : out;
			if (wanted && sink && !sink(given))
				return fail(res, ErrorKind::Cancelled, "cancelled");
			if (wanted && !sink) {
				res.levels.push_back(given);
			} else if (wanted) {
				res.levels.emplace_back();
				res.levels.back().stats = given.stats;
			}
			// (what the next level's collapses start from: this level as delivered, kept apart
			// when collapses made it, else rebuilt from `finer` when it is needed)
			chainCollapsed = takeCollapsed;
			chainIsFiner = !takeCollapsed;
			if (takeCollapsed)
				chain = std::move(collapsed);
			else
				chain.clear();
			finer = std::move(lm);
			// (kept for a coarser level that comes out with more faces; until then its positions
			// and input labels are only memory: they are rebuilt from the input and the partition,
			// and the few placed vertices kept apart)
			finerPlaced.clear();
			for (size_t v = 0; finer.stats.placedVertices > 0 && v < finer.sourceVertex.size();
			     ++v) {
				const Vec3 p(&finer.positions[3 * v]);
				if (!(p == Vec3(&mesh.positions[3 * size_t(finer.sourceVertex[v])])))
					finerPlaced.emplace_back(int32_t(v), p);
			}
			std::vector<double>().swap(finer.positions);
			std::vector<int32_t>().swap(finer.inputSuperface);
		}
		if (!report(1.0, "done"))
			return false;
		res.totalSeconds = since(t0);
		return true;
	});
}

} // namespace gausslod
