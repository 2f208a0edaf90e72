// GaussLOD: levels of detail by merging near-coplanar faces on a hierarchical Gauss sphere.
//
// Implements: Cao Weiqun, Bao Hujun, Peng Qunsheng, "An Algorithm for LOD by Merging Near Coplanar
// Faces Based on Gauss Sphere", J. Comput. Sci. & Technol. 16(5), 2001, pp. 450-457.
// How the project reads the paper, and its decisions on the paper's ambiguities: docs/ALGORITHM.md.
//
// This header is the whole public API of the engine. It works on flat arrays (a triangle soup with
// shared vertex indices); `vcg_adapter.h` converts from and to any VCG triangle mesh type.
//
// Guarantees (for every level that is returned):
//  - the input is never modified;
//  - the output is a triangle mesh whose vertices are a subset of the input vertices, each at its
//    input position or (Params::placeVertices) moved along its normal by at most half the level's
//    distance tolerance, with no duplicate face (same vertices, same orientation) and no face
//    with a repeated vertex;
//  - every superface border is shared by both superfaces it separates (no crack, no T-junction);
//    a closed 2-manifold input gives a closed 2-manifold output, and mesh-boundary loops stay
//    loops;
//  - faces are oriented like the input faces they replace;
//  - a superface that cannot be re-triangulated validly (its projection folds or its border would
//    self-intersect) is split back into its children of the next finer level, down to the input
//    faces if need be; how often that happened is reported in LevelStats::fallbacks.
//  - no silent loss: every input face that is not skipped (a repeated vertex index, a repeat of
//    an earlier face: counted in LevelStats::input) is covered by an output triangle of its
//    superface; a level that would break this is an error, never a result.
// Errors (empty input, index out of range, non-finite coordinates, every face skipped, bad
// parameters) are reported in Result::error with ok == false; no exception escapes buildLevels().
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace gausslod {

/// Input mesh: positions xyz (3 per vertex) and triangles (3 vertex indices per face), and the
/// optional attribute information that keeps a level's attributes exact (docs/ALGORITHM.md,
/// "Beyond the paper"): delimiters that no superface crosses at any level, and the input corner
/// each output corner takes its attributes from.
struct MeshView {
	const double *positions = nullptr;
	size_t vertexCount = 0;
	const int32_t *triangles = nullptr;
	size_t faceCount = 0;
	/// Optional, one per face: faces with different keys are never in one superface (material,
	/// texture, face colour, selection). An edge between them is a border at every level.
	const uint32_t *faceKey = nullptr;
	/// Optional, one per face corner (3*f+k): an edge whose two faces have different keys at
	/// either end vertex is never crossed by a superface (a UV seam, a colour or normal that
	/// differs between the welded copies of a vertex).
	const uint32_t *cornerKey = nullptr;
	/// Optional, two per face corner (u, v): the texture coordinates of the corner. A superface
	/// whose re-triangulation interpolates a removed vertex's coordinates farther than
	/// Params::maxTexError from its own is refused like a normal-deviation failure.
	const float *cornerUV = nullptr;
	/// Optional, one per face: nonzero = keep this face exactly as it is in every level (its
	/// vertices are never moved or removed, it is never merged; e.g. the faces outside a
	/// selection). The edges between kept and other faces are borders.
	const uint8_t *keepFace = nullptr;
	/// Fill LevelMesh::sourceCorner and sourceFace (what a caller needs to carry attributes).
	bool wantSources = false;
};

/// The engine's parameters. Their names are those of the MeshLab filter, its .mlx scripts and
/// (as --kebab-case) the gausslod tool; their defaults are the filter's, so a bare call gives the
/// filter's levels. Distances are fractions of the input's bounding-box diagonal (the filter and
/// the tool show them as percentages). paramSpecs() lists them with their ranges; buildLevels()
/// checks them with validateParams().
struct Params {
	/// Number of levels (the paper's MaxLevel). Level i uses Gauss-sphere cells of 3^i x 3^i per
	/// cube face; the finest level is maxLevel-1. Range 1..8.
	int maxLevel = 5;
	/// Beyond the paper, levels by target (parseLevelsBy() reads the text form "faces:50%,25%"):
	/// per level (index = level, so maxLevel entries; the finest, maxLevel-1, has the largest),
	/// the most output faces the level may have. Each level's distance tolerance (in place of
	/// maxDistance and distanceGrowth) is then searched so that the level has as many faces as
	/// the budget allows (the least error within it); the level's normal bound still holds, so a
	/// budget below what merging within that bound reaches is kept as close as it gets and
	/// reported as not reached (LevelStats::targetReached). Empty = levels by angle (the paper's).
	std::vector<double> levelFaces;
	/// levelFaces are fractions (0..1] of the input's face count (MeshView::faceCount), not counts.
	bool levelFacesRelative = false;
	/// Beyond the paper, levels by target ("error:0.01%,0.2%"): per level (index = level, so
	/// maxLevel entries, strictly decreasing from level 0), the distance tolerance, fraction of
	/// the diagonal, in place of maxDistance * distanceGrowth^k. Empty = those.
	std::vector<double> levelDistances;
	/// Bit i set = return level i (all levels are still computed, coarser ones need finer ones).
	/// parseOutputLevels() reads the filter's text form ("all", "0,2").
	uint32_t outputLevels = 0xffffffffu;
	/// Vertex-class threshold (paper 2.3.2), degrees: A1 below = flat, A2 above = corner.
	double featureAngle = 30.0;
	/// Border straightening tolerance (paper 2.3.1 + Douglas-Peucker), fraction of the diagonal:
	/// a border vertex farther than this from the straightened chain is kept. 0 = remove only
	/// vertices exactly on their chain (within 1e-9 of the diagonal).
	double straightenTol = 0.005;
	/// Vicinity merge distance (paper 2.3.2), fraction of the diagonal: consecutive border
	/// vertices closer than this merge (less important into more important; corners only
	/// receive). 0 = no merging.
	double mergeDist = 0.0025;
	/// Beyond the paper: distance tolerance of the finest level, fraction of the diagonal; each
	/// coarser level's is distanceGrowth times its finer level's. A superface is refused
	/// (inside vertices inserted, retried with tighter borders, then split into finer ones) if
	/// an input vertex it removes is farther than its level's tolerance from the output: a
	/// removed border vertex from its straightened chain, a removed interior vertex from the
	/// plane of the output triangle over a face it belongs to. Caps straightenTol at the level's
	/// tolerance and mergeDist at half of it. 0 = no distance limit (the paper: only normals
	/// decide). Default 0.02 %: measured against CGAL's Garland-Heckbert edge collapse at equal
	/// face counts, the levels' Hausdorff distance is about 2.3x closer to it than with no limit.
	/// (A level made by collapses of the finer level, collapseLevels, is held to the superface
	/// level's proven distance bound instead: DESIGN 50.)
	double maxDistance = 0.0002;
	/// The distance tolerance of level i is maxDistance * distanceGrowth^(maxLevel - 1 - i), so
	/// that coarser levels still get coarser (default 2: 0.02 % at LOD4 ... 0.32 % at LOD0).
	double distanceGrowth = 2.0;
	/// Normal-deviation limit, as a multiple of the level's bound sqrt(2)*90/3^i degrees: a
	/// superface whose re-triangulation leaves an input face farther than this from the output
	/// triangle covering it is retried with tighter straightening and merging (twice), then with
	/// its border locked, then split into its finer children.
	/// 0 = no limit (only flips beyond 90 degrees are refused).
	double normalLimit = 1.0;
	/// Beyond the paper: also merge adjacent superfaces of different (neighbouring) cells when all
	/// their face normals still lie within the level's bound of each other (as inside one cell)
	/// and within the feature angle (no sharp feature inside a merged superface). Removes the
	/// splits that cell borders cut through near-flat or slightly noisy regions.
	/// false = the paper's superfaces (faces of one cell only).
	bool acrossCells = true;
	/// Beyond the paper (with the distance tolerance): once a level is built, move each output
	/// vertex of a new triangle along its normal, by at most half the level's tolerance, to where
	/// its triangles fit the input best (least squares over the input vertices and face
	/// centroids under them), keeping a move only where every superface around it passes its
	/// checks again. The vertex is still the input vertex it was (LevelMesh::sourceVertex, its
	/// attributes). false = every output vertex at its input position.
	bool placeVertices = true;
	/// Beyond the paper (docs/DESIGN.md, 41): before the levels, connected faces that lie in one
	/// plane (within 1e-9 of the bounding-box diagonal, or a few float ulps for an input whose
	/// coordinates are all floats) are re-triangulated from their outline, and the vertices
	/// inside them or on straight chains between them dropped; every level is built on that
	/// mesh: the same surface (within InputStats::coplanarDistance), without the faces an
	/// over-tessellated plane costs. Off only for comparison (it is not a trade-off, hence no
	/// filter or tool parameter); skipped for an input with texture coordinates.
	bool coplanarFirst = true;
	/// Beyond the paper (docs/DESIGN.md, 50; angle levels with the distance tolerance): each
	/// coarser level is also made from the finer level as delivered by half-edge collapses, the
	/// least distance first, each with a proven distance bound and within the level's normal
	/// limit; that mesh is the level when it gets down to the superface level's face count
	/// within the superface level's distance bound (so the face counts are the same, and the
	/// error bound no larger). Vertices stay the finer level's (input vertices, where placed
	/// moved along their normal). Not for inputs with texture coordinates or kept faces. Off
	/// only for comparison (hence no filter or tool parameter).
	bool collapseLevels = true;
	/// Beyond the paper (docs/DESIGN.md, 51; angle levels): every level a real step. A level
	/// with more faces than 0.8 times the level before it (the finest: than the input), or
	/// than its share of the input (the coarsest 15 %, the shares geometric between them), is
	/// continued by edge collapses with quadric placement down to that count, unless its
	/// distance bound is 0 (an exact level); its normal deviation is then measured, not bound
	/// by its cells. false = the paper's levels.
	bool completeChain = true;
	/// Beyond the paper (docs/DESIGN.md, 52): after each level is made, its two-sided Hausdorff
	/// distance to the input is certified within 5 %, or to at most 1e-6 of the diagonal where
	/// it is smaller (LevelStats::hausdorff). A measurement:
	/// it changes no level. false = not computed (-1).
	bool certifyDistance = true;
	/// Input repair, as MeshLab does to STL files on import: vertices at exactly the same position
	/// become one (the first in index order), so that a triangle soup (STL, most CAD and BIM
	/// exports) is simplified like the welded mesh. Faces then refer to that first vertex; the
	/// positions array is not changed. false = vertices are joined only by shared indices.
	bool weldVertices = true;
	/// With weldVertices: a vertex within this distance (fraction of the diagonal) of an earlier
	/// vertex that was kept becomes that vertex (the lowest index among them); every welded
	/// vertex is within this distance of the vertex it became (no chains). 0 = exactly equal
	/// positions only.
	double weldDistance = 0.0;
	/// For the adapters that make MeshView's keys from a mesh's attributes (vcg_adapter.h):
	/// faces of different materials, texture indices or face colours get different face keys.
	bool keepMaterials = true;
	/// For the adapters: corners whose texture coordinates, vertex colour or quality differ at
	/// one (welded) vertex get different corner keys (seams are delimiters).
	bool keepSeams = true;
	/// With MeshView::cornerUV: the largest distance, in texture space, between a removed input
	/// vertex's texture coordinates and what the new triangles interpolate there. A superface
	/// beyond it fails like a normal-deviation failure. 0 = no limit. Default: half a texel
	/// of a 1024 x 1024 texture.
	double maxTexError = 1.0 / 2048;
	/// Worker threads for the per-superface work; 0 = one per core (at most 64). The output does
	/// not depend on it.
	int threads = 0;
};

/// How a parameter's value is given.
enum class ParamKind {
	Integer,          ///< a whole number
	Real,             ///< a number in the parameter's own unit (degrees, a factor)
	DiagonalFraction, ///< a fraction of the bounding-box diagonal (shown as a percentage)
	Flag,             ///< true / false
	LevelList,        ///< Params::outputLevels: "all" or a comma list of level indices
	LevelTargets      ///< Params::levelFaces / levelDistances: parseLevelsBy()'s text
};

/// One parameter of Params, for front ends: the MeshLab filter builds its dialog from these, the
/// gausslod tool its options (--kebab-case of `name`).
struct ParamSpec {
	const char *name; ///< the Params member, filter and .mlx parameter name
	ParamKind kind;
	const char *label;       ///< the dialog's label
	const char *summary;     ///< one line for the tool's help
	const char *description; ///< the dialog's tooltip
	double defaultValue;     ///< Params{}'s value (flags 0/1; unused for LevelList)
	double min, max;         ///< valid range, inclusive unless `openRange`; max may be HUGE_VAL
	bool openRange;          ///< min and max excluded
	bool inFilter;           ///< a parameter of the MeshLab filter (threads is not)
};

/// Every parameter, in the order of the filter's dialog.
const std::vector<ParamSpec> &paramSpecs();
/// The spec called `name`, or nullptr.
const ParamSpec *findParam(const std::string &name);
/// A numeric or flag parameter's value as a double (false/true = 0/1); NaN for LevelList and
/// LevelTargets.
double getParam(const Params &params, const ParamSpec &spec);
/// Sets a numeric or flag parameter (rounded toward zero for Integer, != 0 for Flag); no check.
void setParam(Params &params, const ParamSpec &spec, double value);
/// "" if every parameter is in its range, else a message naming the first one that is not.
std::string validateParams(const Params &params);
/// "all" (any case) or a comma-separated list of level indices 0..maxLevel-1 (spaces allowed
/// around them) into a Params::outputLevels mask. False with `error` set otherwise.
bool parseOutputLevels(const std::string &text, int maxLevel, uint32_t &mask, std::string &error);

/// Levels by target, the text form of the filter's "Levels by" and the tool's --levels-by:
///  "" or "angle": the paper's levels (levelFaces and levelDistances cleared, maxLevel kept);
///  "faces:50%,25%,10%" (percentages of the input's faces) or "faces:20000,5000" (counts);
///  "error:0.01%,0.05%,0.2%" (distance tolerances, percentages of the bounding-box diagonal;
///  the % sign may be left out). The number of targets (1..8) becomes maxLevel; they may come in
///  any order (the finest level gets the most faces or the smallest error). False with `error`
///  set (params unchanged) on an empty, non-numeric, non-positive, duplicate or too long list,
///  a face percentage above 100 or an error above 100 %.
bool parseLevelsBy(const std::string &text, Params &params, std::string &error);
/// The text form of params' targets ("angle" if none), as parseLevelsBy reads it.
std::string levelsByText(const Params &params);

/// The bounding-box diagonal of the (finite) vertex positions: what the distances are
/// fractions of.
double bboxDiagonal(const MeshView &mesh);

/// What was repaired, skipped or locked in the input (the same for every level).
struct InputStats {
	size_t weldedVertices = 0;      ///< vertices welded into an earlier one (Params::weldVertices)
	size_t facesReindexed = 0;      ///< faces that referred to a welded vertex (indices repaired)
	size_t facesRepeatedVertex = 0; ///< skipped: a vertex index repeated (after welding)
	size_t facesDuplicate = 0;      ///< skipped: repeats an earlier face (same vertices and
	                                ///< orientation; a reversed copy is kept)
	size_t facesDegenerate = 0;     ///< kept as they are, never merged: zero area, no normal
	size_t verticesLocked = 0;      ///< never moved or removed: on non-manifold or inconsistently
	                                ///< oriented edges, non-manifold vertices, degenerate faces,
	                                ///< faces kept as they are (MeshView::keepFace)
	size_t facesKept = 0;           ///< kept as they are at the caller's request (keepFace)
	/// Params::coplanarFirst: regions of 2+ coplanar faces re-triangulated before the levels, and
	/// the faces the levels were built on (0 and 0: not reduced, the input's faces)
	size_t coplanarRegions = 0;
	size_t facesAfterCoplanar = 0;
	/// the distance between that mesh and the input (proven, mesh units; each level's
	/// distanceBound includes it): twice the largest distance of a region's vertex from the
	/// region's plane plus the largest of a dropped border vertex from its straight chain
	double coplanarDistance = 0;
	size_t facesSkipped() const { return facesRepeatedVertex + facesDuplicate; }
};

struct LevelStats {
	int level = 0;                ///< Gauss-sphere level i (cells 3^i x 3^i per cube face)
	double boundDeg = 0;          ///< the paper's normal-deviation bound sqrt(2)*90/3^i
	size_t faces = 0;             ///< output triangles
	size_t vertices = 0;          ///< output vertices
	size_t superfaces = 0;        ///< superfaces in the final partition of this level
	size_t fallbacks = 0;         ///< superfaces split back into finer ones (see guarantees)
	size_t retriangulated = 0;    ///< superfaces re-triangulated by constrained Delaunay
	size_t carriedSuperfaces = 0; ///< of those, how many took the finer level's triangles and
	                              ///< measures: the same faces and outline, exact there, so
	                              ///< re-triangulating gives the same (docs/DESIGN.md, 31)
	double maxNormalDevDeg = 0;   ///< max angle between an input face normal and the output
	                              ///< triangle covering its centroid (same superface)
	double meanNormalDevDeg = 0;  ///< area-weighted mean of the same
	size_t unmeasuredFaces = 0;   ///< input faces whose centroid fell outside their superface's
	                              ///< straightened outline (not in the two figures above)
	double distanceBound = -1;    ///< with Params::maxDistance > 0: an upper bound on the distance
	                              ///< between the level and the input, both ways (the two-sided
	                              ///< Hausdorff distance), mesh units; proven per superface, not
	                              ///< sampled (DESIGN 23); measured, it is about half of this;
	                              ///< -1 = not computed (tolerance off)
	/// With Params::certifyDistance: the two-sided Hausdorff distance between the level and the
	/// input (every valid input triangle, as given), certified by branch and bound after the
	/// level is made (DESIGN 52): `hausdorff` is an upper bound (rounded up) and
	/// `hausdorffLower` a distance measured at a point, hausdorff <= 1.05 x max(hausdorffLower,
	/// 1e-6 x the diagonal) unless `hausdorffConverged` is false (the work budget ran out; still
	/// an upper bound).
	/// Mesh units; -1 = not computed.
	double hausdorff = -1;
	double hausdorffLower = -1;
	bool hausdorffConverged = true;
	double secondsHausdorff = 0; ///< time spent certifying it (not in `seconds`)
	double texErrorLimit = -1;   ///< with MeshView::cornerUV, a level continued by collapses
	                             ///< (reduced): the texture limit it was built with, UV units
	                             ///< (Params::maxTexError scaled by the square root of the input
	                             ///< faces over the level's; in faces mode it gives way where the
	                             ///< budget needs it); 0 = none, -1 = the level's own check
	double maxTexError = -1;     ///< with MeshView::cornerUV: the largest texture-coordinate
	                             ///< error measured at removed vertices (UV units); -1 = none
	size_t placedVertices = 0;   ///< output vertices moved off their input position
	                             ///< (Params::placeVertices)
	double maxPlacement = 0;     ///< the largest of those moves, mesh units
	double seconds = 0;          ///< wall time spent on this level (every trial), at least the
	                             ///< sum of the stages of the build it kept:
	double secondsPartition = 0; ///<  merging the finer level's superfaces (2.5; finest level:
	                             ///<  adjacency, vertex classes and the finest buckets, 2.1-2.2.1)
	double secondsBorders = 0;   ///<  rings, straightening, vicinity merging (2.2.2-2.3)
	double secondsTriangulation = 0; ///< re-triangulation and deviation measurement (2.4)
	double secondsChecks = 0;        ///<  whole-level validity check and fallback bookkeeping
	double secondsPlacement = 0;     ///<  vertex placement and its checks (Params::placeVertices)
	double secondsCollapse = 0; ///<  DESIGN 50: collapses of the finer level (whether taken or not)
	int rounds = 0;             ///< build rounds (1 + rounds caused by fallbacks)
	/// Levels by target (Params::levelFaces / levelDistances); in angle mode targetFaces = 0,
	/// targetDistance = -1 and targetReached = true.
	size_t targetFaces = 0;     ///< faces mode: the level's face budget (percentages resolved)
	double targetDistance = -1; ///< error mode: the level's tolerance, fraction of the diagonal
	bool targetReached = true;  ///< faces <= targetFaces; maxDistance <= targetDistance
	/// Faces mode, budget not reached: the least faces a mesh of the level's topology can have
	/// (its components, genera and boundary loops kept, each loop a triangle at least; 0 = no
	/// claim, a non-manifold level) and its boundary loops. faces == leastFaces: the budget is
	/// below what keeping the holes open allows; above it, no collapse was left that keeps the
	/// boundaries, delimiters (seams, materials) and shape valid.
	size_t leastFaces = 0;
	size_t boundaryLoops = 0;
	size_t components = 0; ///< (its connected parts, with leastFaces)
	double tolerance = 0;  ///< the distance tolerance the level was built with, fraction of
	                       ///< the diagonal (0 = none); faces mode: the one the search chose
	int trials = 1;        ///< builds of the level (faces mode: the tolerance search's)
	/// DESIGN 50: half-edge collapses of the finer level that made this level (0 = the
	/// superface build's mesh). maxNormalDevDeg is then a bound (each new triangle against the
	/// cones of the input normals it stands for; the finer level's own figure for the others),
	/// meanNormalDevDeg an estimate (new triangles against the middle of those cones).
	size_t collapses = 0;
	/// DESIGN 51: made by collapses with quadric placement toward a face budget, an error target
	/// or the angle chain's step (not the superface level's own count); maxNormalDevDeg is then
	/// a bound from the cones of the input normals each triangle stands for.
	bool reduced = false;
	bool reusedFiner = false; ///< the merged partition gave more faces than the next finer
	                          ///< level (or, in angle mode, a larger distance bound with not
	                          ///< 1 % fewer faces: DESIGN 29): this level is that level's mesh
	                          ///< (face counts stay monotone; the finer level keeps this
	                          ///< level's bound too)
	InputStats input;         ///< what this level's input repairs were (Result::input)
};

/// Why a level's face budget was not reached, a clause for the tool's table and the filter's
/// log ("" if it was, or the level had no face budget).
std::string budgetNote(const LevelStats &s);

struct LevelMesh {
	std::vector<double> positions;       ///< xyz per output vertex
	std::vector<int32_t> sourceVertex;   ///< input vertex index of each output vertex
	std::vector<int32_t> triangles;      ///< 3 indices per output face
	std::vector<int32_t> superface;      ///< superface id per output face (0..superfaces-1)
	std::vector<uint8_t> borderEdges;    ///< per face: bit k set = edge (k,k+1) is a superface
	                                     ///< border; clear = internal to its superface (faux edge)
	std::vector<int32_t> inputSuperface; ///< superface id of each input face (the faces that
	                                     ///< superface's output triangles replace)
	/// With MeshView::wantSources: per output corner (3 per face), an input corner 3*f+k of the
	/// face's superface at the same (welded) vertex: its attributes are the output corner's.
	std::vector<int32_t> sourceCorner;
	/// With MeshView::wantSources: per output face, an input face of its superface (with keys,
	/// every face of a superface has the same faceKey).
	std::vector<int32_t> sourceFace;
	/// With MeshView::cornerUV, when a level continued by collapses (LevelStats::reduced) gave a
	/// corner texture coordinates no input corner has (a junction of seams collapsed: the chart
	/// that lost its corner there extends its own mapping to the vertex that took it): two per
	/// output corner (u, v), for every corner; empty otherwise (each corner's are its source
	/// corner's). The corner's source corner is then the removed vertex's corner of that chart.
	std::vector<float> cornerUV;
	/// With the distance tolerance: per superface, its proven distance bound (mesh units; the
	/// level's LevelStats::distanceBound is the largest). What a coarser level's collapses
	/// start from (DESIGN 50).
	std::vector<float> superfaceBound;
	LevelStats stats;
};

enum class ErrorKind {
	None,         ///< ok
	BadParameter, ///< a Params value out of range
	BadInput,     ///< the mesh: no faces, a bad index, a non-finite coordinate, every face skipped
	OutOfMemory,  ///< an allocation failed (nothing is half-built)
	Cancelled,    ///< the progress callback or the sink asked to stop
	Internal      ///< a guarantee could not be kept (a bug: please report the input)
};

struct Result {
	bool ok = false;
	std::string error; ///< set when ok == false: what is wrong with the input
	ErrorKind errorKind = ErrorKind::None;
	std::vector<LevelMesh> levels; ///< the requested levels, finest first (level maxLevel-1 .. 0)
	InputStats input;              ///< input repairs (set once the input is validated)
	double totalSeconds = 0;
};

/// Progress: fraction 0..1 and a short stage description. Return false to cancel (then
/// Result::ok == false, error == "cancelled").
using Progress = std::function<bool(double fraction, const char *stage)>;

/// Receives each requested level as soon as it is built (finest first). Return false to cancel.
using LevelSink = std::function<bool(const LevelMesh &level)>;

/// Builds the levels of detail. Deterministic: the same input and parameters give the same output.
/// With a sink, each level is handed to it and then dropped: Result::levels keeps only the
/// levels' stats (empty geometry), so that peak memory holds one level instead of all of them.
Result buildLevels(const MeshView &mesh, const Params &params, const Progress &progress = {},
                   const LevelSink &sink = {});

/// Checks the parameters and the mesh as buildLevels does before it builds any level (welding
/// included): the same error and kind, and Result::input; no level is built.
Result checkInput(const MeshView &mesh, const Params &params);

/// The paper's bound on the normal deviation inside one Gauss-sphere cell of level i, in degrees.
double levelBoundDeg(int level);

} // namespace gausslod
