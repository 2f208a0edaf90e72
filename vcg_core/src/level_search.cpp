// The searches of the target modes and what a level is asked for: face budgets by the distance
// tolerance (buildToFaceTarget), certified errors by the collapses' bound (DESIGN 52), the angle
// chain's steps (DESIGN 51).
#include "level_chain.h"

#include <algorithm>
#include <cmath>

namespace gausslod {
namespace detail {

double since(std::chrono::steady_clock::time_point t0)
{
	return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

namespace {

// DESIGN 52: the level's two-sided Hausdorff distance to the caller's input, certified within
// kCertifyEps; the input's tree is built for the first level that needs it.
constexpr double kCertifyEps = 0.05;
// Levels by error, certified (DESIGN 52): the collapses' bound is searched up to this many times
// the asked error (the construction's bound measured a median 5x the true distance), in this
// many builds.
constexpr double kErrorReach = 8;
constexpr int kErrorTrials = 4;
constexpr size_t kCertifyPieces = 64; // per triangle of both sides: the refinement's budget
// Distances under this share of the diagonal are not refined (levels are written in floats,
// whose rounding is 6e-8 of a coordinate): an exact planar level is certified at most 1.05e-6 x
// the diagonal from its input at once, instead of being cut up to the budget (DESIGN 52).
constexpr double kCertifyFloor = 1e-6;

} // namespace

void certify(const MeshView &input, LevelMesh &level, std::unique_ptr<TriangleTree> &inputTree,
             double diagonal, size_t threads)
{
	const auto t0 = std::chrono::steady_clock::now();
	if (!inputTree)
		inputTree.reset(new TriangleTree(input.positions, input.triangles, input.faceCount));
	const TriangleTree lt(level.positions.data(), level.triangles.data(),
	                      level.triangles.size() / 3);
	const HausdorffBounds h =
	    hausdorff(lt, *inputTree, kCertifyEps,
	              kCertifyPieces * (lt.triangles().size() + inputTree->triangles().size()), threads,
	              kCertifyFloor * diagonal);
	LevelStats &st = level.stats;
	st.hausdorff = h.upper;
	st.hausdorffLower = h.lower;
	st.hausdorffConverged = h.converged;
	st.secondsHausdorff = since(t0);
}

bool reduceToCertifiedError(const Topology &topo, const MeshView &mesh, const MeshView &input,
                            const CollapseSource &chain, const ReduceLimits &rl, size_t threads,
                            std::unique_ptr<TriangleTree> &inputTree, CollapseSource &out,
                            ReduceReport &report)
{
	// the collapses' bound searched (kErrorTrials builds, 1 to kErrorReach x the asked error) for
	// the fewest faces whose certified Hausdorff distance is within the asked error (the proven
	// bound at 1 x is)
	const double asked = rl.bound;
	auto trial = [&](double k, CollapseSource &o, ReduceReport &r) {
		ReduceLimits t = rl;
		t.bound = asked * k;
		const bool g = reduceLevel(topo, mesh, chain, t, threads, o, r);
		certify(input, o.mesh, inputTree, topo.diagonal, threads);
		return g && (k <= 1 || o.mesh.stats.hausdorff <= asked);
	};
	// (first the proven build at 1 x; where its certified distance leaves room (under 0.9 x the
	// error), the factor's logarithm bisected from kErrorReach down: the distance is not
	// monotone in the bound, the bracket only a search)
	const bool got = trial(1.0, out, report);
	double lo = 0, hi = std::log(kErrorReach);
	for (int i = 0; got && out.mesh.stats.hausdorff < 0.9 * asked && i < kErrorTrials; ++i) {
		const double k = i == 0 ? hi : 0.5 * (lo + hi);
		CollapseSource c;
		ReduceReport r;
		if (trial(std::exp(k), c, r)) {
			out = std::move(c), report = r, lo = k;
			if (i == 0)
				break;
		} else {
			hi = k;
		}
	}
	return got;
}

namespace {

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

} // namespace

double stepError(const Params &p, int level) { return kStepError * stepTolerance(p, level); }

size_t stepFaces(const Params &p, int level, size_t finerFaces, size_t inputFaces)
{
	const double share = std::pow(kCoarsestShare, double(p.maxLevel - level) / p.maxLevel);
	return std::min(size_t(std::floor(kStepShare * double(finerFaces))),
	                size_t(std::floor(share * double(inputFaces))));
}

double levelTolerance(const Params &p, int level)
{
	return p.levelDistances.empty()
	           ? p.maxDistance * std::pow(p.distanceGrowth, p.maxLevel - 1 - level)
	           : p.levelDistances[size_t(level)];
}

size_t faceTarget(const Params &p, int level, size_t inputFaces)
{
	const double t = p.levelFaces[size_t(level)];
	return p.levelFacesRelative ? size_t(std::floor(t * double(inputFaces) * (1 + 1e-12)))
	                            : size_t(t);
}

namespace {

// The tolerance search of the faces mode, on the tolerance's logarithm (fractions of the
// diagonal): between these bounds (at the top the distance check refuses nothing: only the
// normal bound limits merging), at most this many halvings after the build at the top, ended once
// a level is within 1 % below its budget or the bracket is narrower than kSearchWidth (a factor
// 1.05: measured on fandisk, the face count is not monotone at that scale, it moves a few percent
// up and down between close tolerances, so a narrower bracket buys nothing).
constexpr double kSearchLogLo = -6, kSearchLogHi = 0, kSearchWidth = 0.02;
constexpr int kSearchSteps = 10;
} // namespace

// Levels by face count: builds `level` with the distance tolerance that gives it the most faces
// within `target` (the least error within the budget), into lm, and its partition into
// parts[level]: bisection of the tolerance's logarithm (faces fall as the tolerance grows, though
// not strictly: see kSearchWidth). Every trial starts from the same merged partition (the
// geometry's fallbacks split it). If even the top tolerance gives more faces than the target,
// that build is kept (the target is not reached). With `beat` >= 0 (mesh units: how near the
// input the level's collapse candidate is) the search ends where no build could be chosen over
// the collapses (`lm` is then not placed, or not built: faces SIZE_MAX, or stopped by Euler's
// bound over a budget the collapses reached: no triangles, faces a lower bound). Deterministic: the
// trials and the choice depend on face counts and distances only.
void buildToFaceTarget(const Topology &topo, const Params &params, std::vector<Partition> &parts,
                       int level, size_t target, size_t faceLimit, const SplitCost *cost,
                       double beat, size_t threads, LevelMesh &lm, Partition &merged)
{
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
	auto run = [&](double logTol, size_t limit) {
		const double tol = std::pow(10.0, logTol);
		trial.levelDistances[size_t(level)] = tol;
		if (trials++ > 0)
			p = start;
		LevelMesh out;
		buildLevelGeometry(topo, trial, parts, p, out, limit, cost);
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
	// DESIGN 55: with `beat`, a build is chosen only if it comes nearer the input, and a build's
	// input vertices are within its tolerance. None is made where the collapses are exact; the
	// top build over the budget is not placed; where it fits but is farther, one build at the
	// tolerance `beat` decides: over the budget, no build within it would be chosen
	bool reached = false, outOfRace = beat == 0;
	if (!outOfRace) {
		// (the collapses reached the budget: a top build that cannot reach it is out of the
		// race, and Euler's bound may say so before it triangulates, DESIGN 35)
		reached =
		    run(hi, beat > 0 && target > 0 ? std::min(faceLimit, target) : faceLimit) <= target;
		outOfRace = beat > 0 && !reached;
	}
	if (reached && beat > 0 &&
	    farthestInputVertex(topo, lm, lm.stats.distanceBound, threads) > beat) {
		const double capLog = std::log10(beat / topo.diagonal);
		reached = capLog > lo && capLog < hi && run(capLog, faceLimit) <= target;
		if (reached)
			hi = capLog;
		outOfRace = !reached;
	}
	for (int step = 0; reached && step < kSearchSteps && target - bestFaces > target / 100 &&
	                   hi - lo > kSearchWidth;
	     ++step) {
		const double mid = 0.5 * (lo + hi);
		(run(mid, faceLimit) <= target ? hi : lo) = mid;
	}
	if (trials == 0) { // (no build: the collapses make the level)
		lm = LevelMesh();
		lm.stats.faces = SIZE_MAX;
	} else if (params.placeVertices && !outOfRace) { // the chosen build again, placed
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
			const LevelTopology lt = levelTopology(lm.triangles, lm.positions.size() / 3);
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

} // namespace detail
} // namespace gausslod
