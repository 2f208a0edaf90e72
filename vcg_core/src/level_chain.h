// The chain of levels, finest first (gausslod.cpp sets it up, level_chain.cpp runs it): each
// level has candidates, one per way of making it (its superfaces, the finer level reused, the
// delivered level collapsed to the superfaces' count, the delivered level kept, collapses to a
// target), and one policy (LevelPolicy) chooses among them. The searches of the target modes
// (face budgets, certified errors) are in level_search.cpp.
#pragma once

#include "engine.h"
#include "hausdorff.h"
#include "level_passes.h"
#include "reduce.h"

#include <chrono>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

namespace gausslod {
namespace detail {

double since(std::chrono::steady_clock::time_point t0);

// ---- level_search.cpp: what a level is asked for, and the searches that get it ----

/// The distance tolerance of `level`, fraction of the diagonal (0 = none), as levelLimits reads it.
double levelTolerance(const Params &p, int level);
/// Levels by face count: the level's face budget (percentages of the input's faces, rounded down).
size_t faceTarget(const Params &p, int level, size_t inputFaces);
/// DESIGN 51: the face count a step of the angle chain may not exceed, and the distance (fraction
/// of the diagonal) its bound may not exceed.
size_t stepFaces(const Params &p, int level, size_t finerFaces, size_t inputFaces);
double stepError(const Params &p, int level);

/// Levels by face count: builds `level` with the distance tolerance that gives it the most faces
/// within `target`, into lm, and its partition into parts[level] (`merged`: the merged
/// partition before the geometry's fallbacks). `beat` >= 0: the farthest input vertex of the
/// level's collapse candidate (DESIGN 55): the search stops where no build within the budget
/// would come nearer (`lm` is then not placed, or not built: faces SIZE_MAX; or stopped by
/// Euler's bound over the budget the collapses reached: no triangles, faces a lower bound).
void buildToFaceTarget(const Topology &topo, const Params &params, std::vector<Partition> &parts,
                       int level, size_t target, size_t faceLimit, const SplitCost *cost,
                       double beat, size_t threads, LevelMesh &lm, Partition &merged);

/// DESIGN 52: the level's two-sided Hausdorff distance to `input`, certified; the input's tree is
/// built for the first level that needs it.
void certify(const MeshView &input, LevelMesh &level, std::unique_ptr<TriangleTree> &inputTree,
             double diagonal, size_t threads);

/// DESIGN 52, levels by error: the fewest faces whose certified distance is within `rl.bound`,
/// by a search of the collapses' bound; `out` is certified. False if not even the proven build
/// reached its limits.
bool reduceToCertifiedError(const Topology &topo, const MeshView &mesh, const MeshView &input,
                            const CollapseSource &chain, const ReduceLimits &rl, size_t threads,
                            std::unique_ptr<TriangleTree> &inputTree, CollapseSource &out,
                            ReduceReport &report);

/// What a level was asked for (levels by target) and whether it got it.
void setTargetStats(const Params &p, int level, size_t target, double diagonal, LevelMesh &lm);

// ---- level_chain.cpp ----

/// What the chain builds on: the mesh after welding and the coplanar reduction.
struct LevelInput {
	const MeshView *input = nullptr; ///< the caller's mesh: what levels are certified against
	MeshView mesh;                   ///< the mesh the levels are built on
	Topology *topo = nullptr;        ///< its topology
	size_t inputFaces = 0;           ///< the caller's faces
	InputStats stats;                ///< the input's repairs, as every level reports them
	size_t threads = 1;
};

/// The finer level as the next coarser one sees it: one value, handed on once a level is chosen.
struct FinerLevel {
	/// The finer level's superface build (or the level it reused); its positions and input
	/// labels are dropped (rebuilt from the input and the partition, and `placed`, when needed).
	LevelMesh mesh;
	std::vector<std::pair<int32_t, Vec3>> placed; ///< its placed vertices: index, position
	SplitCost cost;                               ///< (triangleShare, for the next build)
	ExactCarry carry;                             ///< DESIGN 31: its exact superfaces
	/// DESIGN 50, 51: the level delivered, as collapses start from it: `chain` when collapses
	/// made it; `mesh` when deliveredIsMesh (`chain` is then made from it when first needed).
	CollapseSource chain;
	bool deliveredIsMesh = false;
	bool collapsed = false; ///< collapses made the delivered level
};

class LevelChain {
public:
	using Report = std::function<bool(double, const char *)>;
	LevelChain(const Params &params, const LevelInput &in);
	~LevelChain();
	/// The finest partition (and the face grid), before the first level; the set-up since t0
	/// counts in the finest level's time.
	void start(std::chrono::steady_clock::time_point t0);
	/// Builds `level` (levels from finest to 0, in order) into `out`, the level as delivered
	/// (valid until handOn). False: cancelled by `report`.
	bool build(int level, const Report &report, LevelMesh *&out);
	/// Hands the level built on to the next coarser one (FinerLevel).
	void handOn();

private:
	struct Work; // one level's candidates (level_chain.cpp)
	bool partition(Work &w);
	void buildSuperfaces(Work &w);
	void reuseFinerMesh(Work &w);
	void collapseToCount(Work &w);
	void keepDelivered(Work &w);
	void collapseFirst(Work &w);
	void completeByCollapses(Work &w);
	bool completionLimits(const Work &w, ReduceLimits &rl) const;
	void needChain(Work &w);
	LevelMesh &chosen(Work &w);
	void handOn(Work &w);
	double acrossLimit(int level) const;

	const Params &params_;
	const LevelInput &in_;
	const MeshView &mesh_;
	Topology &topo_;
	const int finest_;
	const bool byFaces_, byAngle_, byError_, collapsing_;
	std::vector<Partition> parts_;
	/// faces mode: parts_[level] is the level's merged partition before its fallbacks (what the
	/// coarser levels merge), levelPart_ the one its mesh has (see DESIGN.md)
	Partition merged_, levelPart_;
	FinerLevel finer_;
	ExactCarry nextCarry_;
	std::unique_ptr<TriangleTree> inputTree_; ///< DESIGN 52, built when first needed
	/// DESIGN 52: the last level certified, if small (a copy), with its certificate: a level
	/// that is the same mesh (exact planar levels often are) has the same distance to the input
	struct Certified {
		std::vector<double> positions;
		std::vector<int32_t> triangles;
		double hausdorff = -1, lower = -1;
		bool converged = true;
	} certified_;
	void certifyLevel(LevelMesh &level);
	std::unique_ptr<Work> work_;
	double setup_ = 0;
};

} // namespace detail
} // namespace gausslod
