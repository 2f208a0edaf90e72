// The chain of levels (level_chain.h): per level, its partition, its candidates and the policy
// that chooses among them, then what the next coarser level takes from it (FinerLevel).
#include "level_chain.h"

#include <algorithm>
#include <cmath>

namespace gausslod {
namespace detail {

namespace {

// Beyond the paper (DESIGN 29), in angle mode: a coarser level farther from the input than the
// finer one must have at least this share of its faces fewer, else it is the finer level (its
// extra error bought next to nothing).
constexpr double kMinLevelSaving = 0.01;

// DESIGN 50: a finer level of more faces is not collapsed: its coarser level is the superface
// level (the collapses' state is about 150 bytes per face of the finer level).
constexpr size_t kCollapseMaxFaces = 300000;

// Would a superface be held to more under limits a than under b (a smaller straightening or
// distance tolerance, normal limit or merge distance)?
bool tighter(const LevelLimits &a, const LevelLimits &b)
{
	return a.tolerance < b.tolerance || a.maxDistance < b.maxDistance ||
	       a.devLimitDeg < b.devLimitDeg || a.mergeDistance < b.mergeDistance;
}

// The finer level's mesh, as level `lm` (its positions and input labels were dropped from
// `finer`: see FinerLevel), on the partition labels `label` (the same superfaces).
void takeFinerMesh(const MeshView &mesh, const std::vector<int32_t> &label, FinerLevel &finer,
                   LevelMesh &lm)
{
	lm = std::move(finer.mesh);
	lm.positions.resize(3 * lm.sourceVertex.size());
	for (size_t v = 0; v < lm.sourceVertex.size(); ++v)
		for (size_t k = 0; k < 3; ++k)
			lm.positions[3 * v + k] = mesh.positions[3 * size_t(lm.sourceVertex[v]) + k];
	for (const auto &pv : finer.placed) // (and its placed vertices)
		for (size_t k = 0; k < 3; ++k)
			lm.positions[3 * size_t(pv.first) + k] = pv.second[int(k)];
	lm.inputSuperface = label;
}

// A coarser level that came out with more faces than the finer one (2.5 promises monotone face
// counts), or farther from the input for under kMinLevelSaving fewer, is the finer level's mesh:
// its partition, with the cells of this level.
void keepFinerLevel(const MeshView &mesh, int level, std::vector<Partition> &parts,
                    const Partition &finerPart, FinerLevel &finer, LevelMesh &lm)
{
	Partition &p = parts[size_t(level)];
	p = finerPart;
	p.level = level;
	// (its origins still point to the finer level's parts: no copy of them needed)
	p.partLabel.clear(), p.partCell.clear(), p.partOrigin.clear();
	for (CellKey &c : p.cell)
		c = c == kInvalidCell ? c : parentKey(c);
	const LevelStats spent = lm.stats; // the time was spent all the same
	takeFinerMesh(mesh, p.label, finer, lm);
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

// The level's stats when collapses made its mesh: the superface level's (`lm`: what was spent,
// what was asked), but for what the mesh says.
void takeMeshStats(const LevelStats &lm, bool certified, LevelStats &st)
{
	const LevelStats c = st;
	st = lm;
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
	if (certified) {                   // (certified by the error search)
		st.hausdorff = c.hausdorff;
		st.hausdorffLower = c.hausdorffLower;
		st.hausdorffConverged = c.hausdorffConverged;
		st.secondsHausdorff = c.secondsHausdorff;
	}
}

} // namespace

/// One level's candidates: the superface level `lm` (whose stats, what was spent and asked, are
/// the level's), and `collapsed`, a level collapses made (or the delivered level kept).
struct LevelChain::Work {
	int level = 0;
	std::chrono::steady_clock::time_point tl, tc; ///< the level's start; its collapses' start
	bool superfaces = false;     ///< the level has a superface candidate (else collapses make it)
	bool sameAsFiner = false;    ///< the superface candidate is the finer level, by DESIGN 36
	bool superfaceBuilt = false; ///< the superface candidate is a mesh of its own
	double tolerance = 0;        ///< the level's distance tolerance (faces mode: searched)
	size_t faceLimit = 0;        ///< the finer level's faces (above them: the finer level)
	size_t target = 0;           ///< faces mode: the level's budget
	size_t chainFaces = 0;       ///< the faces of the level delivered before this one
	LevelMesh lm;
	CollapseSource collapsed;
	/// DESIGN 55 (faces mode, finest level): the collapse candidate made before the superface
	/// search (`early`; reached the budget: `earlyGot`), its farthest input vertex and seconds
	bool collapsedFirst = false, earlyGot = false;
	CollapseSource early;
	ReduceReport earlyReport;
	double earlyFar = -1, earlySeconds = 0;
	bool takeCollapsed = false;     ///< the level is `collapsed`
	bool certifiedByTrials = false; ///< `collapsed` was certified by the error search
	const LevelStats &best() const { return takeCollapsed ? collapsed.mesh.stats : lm.stats; }
	const LevelMesh &bestMesh() const { return takeCollapsed ? collapsed.mesh : lm; }
};

LevelChain::LevelChain(const Params &params, const LevelInput &in)
    : params_(params), in_(in), mesh_(in.mesh), topo_(*in.topo), finest_(params.maxLevel - 1),
      byFaces_(!params.levelFaces.empty()),
      byAngle_(params.levelFaces.empty() && params.levelDistances.empty()),
      byError_(!params.levelDistances.empty() && params.levelFaces.empty()),
      // DESIGN 50: the finer level as delivered, for the next level's collapses
      collapsing_(byAngle_ && params.collapseLevels && params.maxDistance > 0 && !topo_.UV &&
                  !mesh_.keepFace),
      parts_(size_t(params.maxLevel))
{
}

LevelChain::~LevelChain() = default;

// cross-cell unions: normals within the level's bound of each other, and never across a feature
// (two normals farther apart than the feature angle: sharp stays sharp)
double LevelChain::acrossLimit(int level) const
{
	return std::min(levelBoundDeg(level), params_.featureAngle);
}

void LevelChain::start(std::chrono::steady_clock::time_point t0)
{
	// the face grid (for the levels' flip checks) is built while the finest partition is (both
	// serial; the grid only writes topo.grid; its buckets' cones are computed when a check first
	// asks for them: on most meshes few are)
	const size_t tasks = in_.threads > 1 ? 2 : 1;
	onWorkers(tasks, [&](size_t task) {
		if (task == 1 || tasks == 1)
			buildFaceGrid(topo_);
		if (task == 0) {
			finestPartition(topo_, finest_, parts_[size_t(finest_)]);
			if (params_.acrossCells)
				mergeAcrossCells(topo_, acrossLimit(finest_), parts_[size_t(finest_)]);
		}
	});
	setup_ = since(t0);
}

// The level's partition: its sibling cells' superfaces merged (2.5), unless collapses make the
// level (then false) or the finer level's is certainly the same (DESIGN 38).
bool LevelChain::partition(Work &w)
{
	const int level = w.level;
	// DESIGN 51: levels by target, once a level was made by collapses, are made by collapses
	// (the superfaces of a coarser level would not reach the target either)
	const bool superfaces = byAngle_ || level == finest_ || !finer_.collapsed;
	// (DESIGN 38: the finer level carried whole tells which superfaces touch; if none of them
	// could be grouped or merged here, the partition is the finer one's)
	const bool across = params_.acrossCells;
	if (superfaces && level < finest_ &&
	    !(byAngle_ && finer_.carry.whole &&
	      sameCoarserPartition(parts_[size_t(level) + 1],
	                           superfacePairs(finer_.mesh.triangles, finer_.mesh.superface),
	                           across ? acrossLimit(level) : -1.0, parts_[size_t(level)]))) {
		coarserPartition(topo_, parts_[size_t(level) + 1], parts_[size_t(level)], int8_t(level));
		if (across)
			mergeAcrossCells(topo_, acrossLimit(level), parts_[size_t(level)]);
	}
	return superfaces;
}

// The finer level's mesh as this level (DESIGN 36).
void LevelChain::reuseFinerMesh(Work &w)
{
	LevelMesh &lm = w.lm;
	takeFinerMesh(mesh_, parts_[size_t(w.level)].label, finer_, lm);
	lm.stats.level = w.level;
	lm.stats.boundDeg = levelBoundDeg(w.level);
	lm.stats.carriedSuperfaces = lm.stats.superfaces;
	lm.stats.rounds = 1;
	lm.stats.tolerance = w.tolerance;
	lm.stats.secondsBorders = lm.stats.secondsTriangulation = 0;
	lm.stats.secondsChecks = lm.stats.secondsPlacement = 0;
	nextCarry_ = std::move(finer_.carry); // (swapped back by handOn: the same superfaces)
	nextCarry_.label = &parts_[size_t(w.level)].label;
}

// The superface candidate (paper 2.2-2.4 on the level's partition), into w.lm.
void LevelChain::buildSuperfaces(Work &w)
{
	const int level = w.level;
	LevelMesh &lm = w.lm;
	const double partitionSeconds =
	    since(w.tl) + (level == finest_ ? setup_ : 0.0) - w.earlySeconds;
	// DESIGN 36: the finer level carried whole (ExactCarry::whole) and the same superfaces
	// here, with limits no tighter: building would take every superface as it is, so the
	// level is the finer level's mesh (one linear pass, not a build)
	const bool uv = topo_.UV != nullptr;
	w.sameAsFiner = byAngle_ && level < finest_ && finer_.carry.whole &&
	                parts_[size_t(level)].label == parts_[size_t(level) + 1].label &&
	                !tighter(levelLimits(params_, topo_.diagonal, level, uv),
	                         levelLimits(params_, topo_.diagonal, level + 1, uv));
	const bool share = w.superfaces && level < finest_ && w.tolerance > 0 && !w.sameAsFiner;
	const Partition &finerPart = byFaces_ ? levelPart_ : parts_[size_t(level) + 1];
	if (share)
		triangleShare(finerPart, finer_.mesh, finer_.cost);
	const SplitCost *cost = share ? &finer_.cost : nullptr;
	if (!w.superfaces) { // (no build: the collapses make the level)
		lm.stats.level = level;
		lm.stats.boundDeg = levelBoundDeg(level);
		lm.stats.faces = SIZE_MAX;
		lm.stats.trials = 0;
		lm.stats.tolerance = byFaces_ ? 0.0 : w.tolerance;
	} else if (w.sameAsFiner) {
		reuseFinerMesh(w);
	} else if (byFaces_) {
		const double beat = w.collapsedFirst && w.earlyGot ? w.earlyFar : -1.0;
		buildToFaceTarget(topo_, params_, parts_, level, w.target, w.faceLimit, cost, beat,
		                  in_.threads, lm, merged_);
		if (lm.triangles.empty()) { // (no build, or none placed over the budget: DESIGN 55)
			lm.stats.level = level;
			lm.stats.boundDeg = levelBoundDeg(level);
		}
	} else {
		buildLevelGeometry(topo_, params_, parts_, parts_[size_t(level)], lm, w.faceLimit, cost,
		                   &finer_.carry, &nextCarry_);
		lm.stats.tolerance = w.tolerance;
	}
	const double chosen = lm.stats.tolerance;
	const int trials = lm.stats.trials;
	lm.stats.secondsPartition = partitionSeconds;
	// (a coarser level must be lighter than the finer one; in angle mode, if it is farther from
	// the input, by at least kMinLevelSaving)
	const LevelStats &f = finer_.mesh.stats;
	if (w.superfaces && level < finest_ && !w.sameAsFiner &&
	    (lm.stats.faces > f.faces ||
	     (byAngle_ && lm.stats.distanceBound > f.distanceBound &&
	      double(lm.stats.faces) > (1 - kMinLevelSaving) * double(f.faces)))) {
		keepFinerLevel(mesh_, level, parts_, finerPart, finer_, lm);
		nextCarry_ = ExactCarry(); // (its superfaces are not this level's)
	}
	lm.stats.tolerance = chosen;
	lm.stats.trials = trials;
	// (a level that is its finer level's mesh took it: no superface build)
	w.superfaceBuilt =
	    w.superfaces && !(w.sameAsFiner || lm.stats.reusedFiner || lm.stats.faces == SIZE_MAX);
}

// Makes finer_.chain the level delivered before this one (before the finest level, the input).
void LevelChain::needChain(Work &w)
{
	CollapseSource &chain = finer_.chain;
	if (w.level == finest_) {
		if (chain.empty())
			inputSource(topo_, mesh_, chain);
	} else if (finer_.deliveredIsMesh && !w.superfaceBuilt) { // (this level took that mesh)
		collapseSourceOf(topo_, w.lm, chain);
		finer_.deliveredIsMesh = false;
	} else if (finer_.deliveredIsMesh) { // (its mesh has served: taken whole, partition kept)
		LevelMesh source;
		takeFinerMesh(mesh_, (byFaces_ ? levelPart_ : parts_[size_t(w.level) + 1]).label, finer_,
		              source);
		collapseSourceOf(topo_, std::move(source), chain);
		finer_.deliveredIsMesh = false;
	}
}

// DESIGN 50 (angle levels): the delivered level collapsed to the superface level's face count
// within its distance bound and normal limit, vertices kept where they are; taken where no input
// vertex ends farther from it.
void LevelChain::collapseToCount(Work &w)
{
	const LevelStats &st = w.lm.stats;
	if (!(collapsing_ && w.level < finest_ && w.chainFaces > st.faces &&
	      w.chainFaces <= kCollapseMaxFaces && w.superfaceBuilt && st.distanceBound > 0))
		return;
	needChain(w);
	ReduceLimits rl;
	rl.level = w.level;
	rl.faces = st.faces;
	rl.bound = st.distanceBound;
	rl.normalDeg = params_.normalLimit > 0
	                   ? std::min(90.0, params_.normalLimit * levelBoundDeg(w.level))
	                   : 90.0;
	rl.placement = false;
	rl.keepSuperfaces = true;
	ReduceReport rr;
	const size_t threads = in_.threads;
	w.takeCollapsed =
	    reduceLevel(topo_, mesh_, finer_.chain, rl, threads, w.collapsed, rr) &&
	    farthestInputVertex(topo_, w.collapsed.mesh, w.collapsed.mesh.stats.distanceBound,
	                        threads) <= farthestInputVertex(topo_, w.lm, st.distanceBound, threads);
}

// DESIGN 29 against a collapsed finer level too: a level no lighter than the delivered one, or
// farther from the input and not kMinLevelSaving lighter, is that level.
void LevelChain::keepDelivered(Work &w)
{
	if (!(byAngle_ && w.level < finest_ && finer_.collapsed))
		return;
	const LevelStats &o = w.best();
	const CollapseSource &chain = finer_.chain;
	if (double(o.faces) >= double(w.chainFaces) ||
	    (o.distanceBound > chain.mesh.stats.distanceBound &&
	     double(o.faces) > (1 - kMinLevelSaving) * double(w.chainFaces))) {
		w.collapsed = chain; // (a copy: the chain stays what the next level starts from)
		w.collapsed.mesh.stats.collapses = 0;
		w.takeCollapsed = true;
	}
}

// DESIGN 51: the limits of the collapses that complete the level (levels by target, and the
// angle chain's real steps); false where the level needs none.
bool LevelChain::completionLimits(const Work &w, ReduceLimits &rl) const
{
	rl.level = w.level;
	rl.placement = true;
	bool reduce = false;
	if (!byAngle_) {
		reduce = true;
		rl.faces = byFaces_ ? w.target : 0;
		rl.bound = byFaces_ ? HUGE_VAL : params_.levelDistances[size_t(w.level)] * topo_.diagonal;
	} else if (params_.completeChain) {
		const size_t cap = stepFaces(params_, w.level, w.chainFaces, in_.inputFaces);
		reduce = w.best().faces > cap;
		rl.faces = cap;
		rl.bound = stepError(params_, w.level) * topo_.diagonal;
	}
	if (reduce && topo_.UV && params_.maxTexError > 0) {
		// (a coarser level is seen smaller: its limit in texels of its own screen size, the
		// input's limit times the square root of the faces it has fewer; kept by levels by
		// error, measured against by budgets and steps: DESIGN 54)
		const size_t seen = rl.faces > 0 ? rl.faces : std::max<size_t>(w.chainFaces, 1);
		rl.texError = params_.maxTexError *
		              std::sqrt(double(in_.inputFaces) / double(std::max<size_t>(seen, 1)));
		rl.texErrorSoft = !byError_;
	}
	return reduce;
}

// DESIGN 55: in faces mode the finest level's collapse candidate is made first: the superface
// search then knows how near the input a build must come to be chosen over it.
void LevelChain::collapseFirst(Work &w)
{
	ReduceLimits rl;
	if (!(byFaces_ && w.level == finest_ && w.superfaces) || !completionLimits(w, rl))
		return;
	const auto t0 = std::chrono::steady_clock::now();
	needChain(w);
	// (the input as a source serves this level only: the reduction takes it)
	w.earlyGot =
	    reduceLevel(topo_, mesh_, std::move(finer_.chain), rl, in_.threads, w.early, w.earlyReport);
	w.earlyFar =
	    farthestInputVertex(topo_, w.early.mesh, w.early.mesh.stats.distanceBound, in_.threads);
	w.collapsedFirst = true;
	w.earlySeconds = since(t0);
}

// DESIGN 51: levels by target, and the angle chain's real steps, by collapses with quadric
// placement where the superfaces do not get there; taken by the mode's rule.
void LevelChain::completeByCollapses(Work &w)
{
	ReduceLimits rl;
	if (!completionLimits(w, rl))
		return;
	const size_t threads = in_.threads;
	ReduceReport rr;
	CollapseSource reduced;
	bool got;
	double far = -1; // (faces mode: the candidate's farthest input vertex, once measured)
	if (w.collapsedFirst) {
		reduced = std::move(w.early);
		rr = w.earlyReport;
		got = w.earlyGot;
		far = w.earlyFar;
	} else {
		needChain(w);
		if (byError_ && params_.certifyDistance) { // DESIGN 52: by the certified distance
			got = reduceToCertifiedError(topo_, mesh_, *in_.input, finer_.chain, rl, threads,
			                             inputTree_, reduced, rr);
			w.certifiedByTrials = true;
		} else { // (the chain is not looked at again before the next level replaces it)
			got = reduceLevel(topo_, mesh_, std::move(finer_.chain), rl, threads, reduced, rr);
		}
	}
	const LevelStats &rs = reduced.mesh.stats, &o = w.best();
	bool take;
	if (byFaces_) // (a budget first; within it, the level nearer the input)
		take = o.faces > w.target
		           ? rs.faces < o.faces
		           : got && (far >= 0 ? far
		                              : farthestInputVertex(topo_, reduced.mesh, rs.distanceBound,
		                                                    threads)) <
		                        farthestInputVertex(topo_, w.bestMesh(), o.distanceBound, threads);
	else if (byAngle_)
		take = rs.faces < o.faces;
	else // (by error: the fewest faces, then the smaller bound)
		take = rs.faces < o.faces || (rs.faces == o.faces && rs.distanceBound < o.distanceBound);
	w.certifiedByTrials = w.certifiedByTrials && take;
	if (take) {
		w.collapsed = std::move(reduced);
		w.collapsed.mesh.stats.reduced = true;
		w.collapsed.mesh.stats.texErrorLimit = rr.texErrorLimit;
		measureNormalDeviation(topo_, w.collapsed.mesh, threads);
		w.takeCollapsed = true;
	}
}

// The chosen candidate, with the level's stats.
LevelMesh &LevelChain::chosen(Work &w)
{
	const double secondsCollapse = since(w.tc) + w.earlySeconds;
	std::swap(finer_.carry, nextCarry_);
	if (byFaces_) {
		levelPart_ = std::move(parts_[size_t(w.level)]);
		parts_[size_t(w.level)] = std::move(merged_);
	}
	LevelStats &st = w.lm.stats;
	st.seconds = since(w.tl) + (w.level == finest_ ? setup_ : 0.0);
	st.input = in_.stats;
	st.secondsCollapse = secondsCollapse;
	if (!w.takeCollapsed)
		return w.lm;
	takeMeshStats(st, w.certifiedByTrials, w.collapsed.mesh.stats);
	return w.collapsed.mesh;
}

bool LevelChain::build(int level, const Report &report, LevelMesh *&out)
{
	work_.reset(new Work());
	Work &w = *work_;
	w.level = level;
	w.tl = std::chrono::steady_clock::now();
	const double done = double(finest_ - level);
	if (!report(0.05 + 0.95 * done / params_.maxLevel, "building level"))
		return false;
	w.superfaces = partition(w);
	w.tolerance = byFaces_ ? 1.0 : levelTolerance(params_, level);
	w.faceLimit = level < finest_ ? finer_.mesh.stats.faces : SIZE_MAX;
	w.target = byFaces_ ? faceTarget(params_, level, in_.inputFaces) : 0;
	collapseFirst(w);
	buildSuperfaces(w);
	// DESIGN 50 and 51: the level may also come from the level delivered before it (the
	// chain; before the finest level, the input) by edge collapses
	w.tc = std::chrono::steady_clock::now();
	w.chainFaces = level == finest_         ? in_.inputFaces - in_.stats.facesSkipped()
	               : finer_.deliveredIsMesh ? finer_.mesh.stats.faces
	                                        : finer_.chain.mesh.triangles.size() / 3;
	collapseToCount(w);
	keepDelivered(w);
	completeByCollapses(w);
	out = &chosen(w);
	if (params_.certifyDistance && !w.certifiedByTrials) { // DESIGN 52: certified
		if (!report(0.05 + 0.95 * (done + 0.5) / params_.maxLevel,
		            "certifying the level's distance"))
			return false;
		certifyLevel(*out);
	}
	setTargetStats(params_, level, w.target, topo_.diagonal, *out);
	return true;
}

// DESIGN 52: the level's certified distance, or the last certified level's where the level is
// that mesh (compared whole: the same positions and triangles). Levels of up to a quarter of the
// input's faces are kept for that comparison: identical levels are exact planar ones, small.
void LevelChain::certifyLevel(LevelMesh &level)
{
	Certified &c = certified_;
	LevelStats &st = level.stats;
	if (c.hausdorff >= 0 && level.triangles == c.triangles && level.positions == c.positions) {
		st.hausdorff = c.hausdorff;
		st.hausdorffLower = c.lower;
		st.hausdorffConverged = c.converged;
		st.secondsHausdorff = 0;
		return;
	}
	certify(*in_.input, level, inputTree_, topo_.diagonal, in_.threads);
	c = Certified();
	if (level.triangles.size() / 3 <= in_.inputFaces / 4) {
		c.positions = level.positions;
		c.triangles = level.triangles;
		c.hausdorff = st.hausdorff;
		c.lower = st.hausdorffLower;
		c.converged = st.hausdorffConverged;
	}
}

void LevelChain::handOn()
{
	Work &w = *work_;
	// (what the next level's collapses start from: this level as delivered, kept apart when
	// collapses made it, else rebuilt from the finer mesh when it is needed)
	finer_.collapsed = w.takeCollapsed;
	finer_.deliveredIsMesh = !w.takeCollapsed;
	if (w.takeCollapsed)
		finer_.chain = std::move(w.collapsed);
	else
		finer_.chain.clear();
	LevelMesh &finer = finer_.mesh;
	finer = std::move(w.lm);
	// (kept for a coarser level that comes out with more faces; until then its positions and
	// input labels are only memory: they are rebuilt from the input and the partition, and the
	// few placed vertices kept apart)
	finer_.placed.clear();
	for (size_t v = 0; finer.stats.placedVertices > 0 && v < finer.sourceVertex.size(); ++v) {
		const Vec3 p(&finer.positions[3 * v]);
		if (!(p == Vec3(&mesh_.positions[3 * size_t(finer.sourceVertex[v])])))
			finer_.placed.emplace_back(int32_t(v), p);
	}
	std::vector<double>().swap(finer.positions);
	std::vector<int32_t>().swap(finer.inputSuperface);
	work_.reset();
}

} // namespace detail
} // namespace gausslod
