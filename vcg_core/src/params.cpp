// The parameters' one source of truth: names, ranges, texts (the filter's dialog and the tool's
// help are built from them), validation, and the output-level list. Defaults are Params{}'s.
#include "engine.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>

namespace gausslod {

namespace {

// A ParamSpec and the Params member it describes (one of the three pointers).
struct Entry {
	ParamSpec spec;
	int Params::*integer = nullptr;
	double Params::*real = nullptr;
	bool Params::*flag = nullptr;

	Entry(const ParamSpec &s) : spec(s) {}
	Entry(const ParamSpec &s, int Params::*m) : spec(s), integer(m) {}
	Entry(const ParamSpec &s, double Params::*m) : spec(s), real(m) {}
	Entry(const ParamSpec &s, bool Params::*m) : spec(s), flag(m) {}
};

// What sets the levels and which are written.
std::vector<Entry> levelEntries()
{
	const Params d;
	const double kLevels = kMaxCellLevel + 1;
	using K = ParamKind;
	return {
	    {{"maxLevel", K::Integer, "Number of levels", "number of levels, 1..8",
	      "How many levels of detail to build (the paper's MaxLevel), 1..8. Level i groups normals "
	      "in 3^i x 3^i Gauss-sphere cells per cube face; its normal deviation bound is "
	      "sqrt(2)*90/3^i degrees: level 0 = 127 deg (coarsest), 1 = 42.4, 2 = 14.1, 3 = 4.71, "
	      "4 = 1.57 deg, ...",
	      double(d.maxLevel), 1, kLevels, false, true},
	     &Params::maxLevel},
	    {{"levelsBy", K::LevelTargets, "Levels by",
	      "what sets the levels: angle, faces:50%,25%,... (or counts) or error:0.01%,0.2%,...",
	      "Beyond the paper: what sets the levels. \"angle\" (or empty, the default): the "
	      "paper's levels, 'Number of levels' of them, each as coarse as its normal bound and "
	      "the distance tolerance allow. \"faces:\" and a comma list of face budgets, as "
	      "percentages of the input's faces (faces:50%,25%,10%) or counts (faces:20000,5000): "
	      "one level per budget, each with as many faces as fit in it (its distance tolerance "
	      "is searched). \"error:\" and a list of distance tolerances, percentages of the "
	      "bounding-box diagonal (error:0.01%,0.05%,0.2%): one level per tolerance, in place of "
	      "'Distance tolerance' and 'Distance growth'. The number of targets (up to 8) "
	      "replaces 'Number of levels'; the finest level gets the most faces or the smallest "
	      "error. Where the superfaces cannot get to a budget or an error, the level is made "
	      "by proven edge collapses of the level before it; only a true minimum (the "
	      "boundaries, seams and materials kept) stops a budget: the log then says 'not "
	      "reached'.",
	      0, 0, 0, false, true}},
	    {{"outputLevels", K::LevelList, "Output levels",
	      "\"all\" or a comma list of levels to write, 0 = coarsest",
	      "Which levels become layers: \"all\", or a comma-separated list of level indices, "
	      "0 = coarsest to (number of levels - 1) = finest, e.g. \"0,2\". All levels are "
	      "computed either way, since each coarser level is made from the finer one.",
	      0, 0, 0, false, true}},
	};
}

// The paper's borders and bounds, and the distance tolerance beyond it.
std::vector<Entry> shapeEntries()
{
	const Params d;
	const double kInf = HUGE_VAL;
	using K = ParamKind;
	return {
	    {{"featureAngle", K::Real, "Feature angle (deg)", "vertex-class threshold, degrees",
	      "Angle in degrees (between 0 and 180) that classifies border vertices: a vertex "
	      "whose incident normals all lie within it is flat, one with two groups of normals "
	      "that each spread beyond it is a corner, else an edge vertex. Corners are never "
	      "merged away.",
	      d.featureAngle, 0, 180, true, true},
	     &Params::featureAngle},
	    {{"straightenTol", K::DiagonalFraction, "Border straightening tolerance",
	      "border straightening tolerance, % of bbox diagonal",
	      "Distance in mesh units (the percentage is of the bounding-box diagonal; default "
	      "0.5%): a border vertex farther than this from the straightened border between two "
	      "superfaces is kept. 0 removes only exactly collinear border vertices. In a saved "
	      "script the percentage is what is kept: it is applied to the diagonal of the mesh the "
	      "script runs on.",
	      d.straightenTol, 0, 1, false, true},
	     &Params::straightenTol},
	    {{"mergeDist", K::DiagonalFraction, "Vertex merge distance",
	      "vicinity merge distance, % of bbox diagonal",
	      "Distance in mesh units (the percentage is of the bounding-box diagonal; default "
	      "0.25%): consecutive border vertices closer than this are merged, the less important "
	      "into the more important. 0 disables merging. In a saved script the percentage is "
	      "what is kept.",
	      d.mergeDist, 0, 1, false, true},
	     &Params::mergeDist},
	    {{"maxDistance", K::DiagonalFraction, "Distance tolerance (finest level)",
	      "distance tolerance of the finest level, % of bbox diagonal; 0 = none",
	      "Beyond the paper: distance in mesh units (the percentage is of the bounding-box "
	      "diagonal) that no input face may end farther than from the plane of the finest "
	      "level's triangles above it; each coarser level allows 'Distance growth' times more. "
	      "A superface that would gets input vertices inside it kept where it curves, else is "
	      "retried with tighter borders, then split; the tolerance also caps the straightening "
	      "tolerance (and the merge distance at half of it). Default 0.02 % (0.32 % at LOD0 of "
	      "5): curved parts keep their shape. Each level then reports a proven upper bound on "
	      "its distance to the input (log, layer name), about two to three times the measured "
	      "one. 0 = no distance limit (only normals decide, as in the paper).",
	      d.maxDistance, 0, 1, false, true},
	     &Params::maxDistance},
	    {{"distanceGrowth", K::Real, "Distance growth per level",
	      "distance tolerance factor per coarser level",
	      "The distance tolerance of each level is this many times that of the next finer "
	      "level (default 2), so that coarser levels still get coarser. 1 = the same "
	      "tolerance at every level.",
	      d.distanceGrowth, 1, 1000, false, true},
	     &Params::distanceGrowth},
	    {{"normalLimit", K::Real, "Normal deviation limit (x level bound)",
	      "normal deviation limit, x each level's bound; 0 = none",
	      "Guarantee on the result, as a multiple of each level's bound sqrt(2)*90/3^i deg: "
	      "a superface whose re-triangulation leaves an input face farther than this from the "
	      "output triangle covering it is retried with tighter borders, then with its border "
	      "kept, then split into finer superfaces. 1 = the paper's bound (default); larger "
	      "values simplify more; 0 = no limit (only flipped triangles are refused).",
	      d.normalLimit, 0, kInf, false, true},
	     &Params::normalLimit},
	};
}

// Beyond the paper: how superfaces merge, where vertices go, what is measured.
std::vector<Entry> buildEntries()
{
	const Params d;
	using K = ParamKind;
	return {
	    {{"acrossCells", K::Flag, "Merge across cell borders",
	      "merge across cell borders (false = the paper's superfaces)",
	      "Beyond the paper: also merge neighbouring superfaces of different Gauss-sphere "
	      "cells when all their face normals stay within the level's bound of each other (and "
	      "within the feature angle, so sharp edges stay sharp). Fewer faces on near-flat or "
	      "slightly noisy regions that a cell border would cut. Off = the paper's superfaces "
	      "(faces of one cell only).",
	      double(d.acrossCells), 0, 1, false, true},
	     &Params::acrossCells},
	    {{"placeVertices", K::Flag, "Place vertices on the surface",
	      "move kept vertices along their normal to fit the input (false = at input positions)",
	      "Beyond the paper, with the distance tolerance: once a level is built, each kept "
	      "vertex of a re-triangulated superface is moved along its normal, by at most half the "
	      "level's tolerance, to where its triangles fit the input best (least squares), as "
	      "quadric simplifiers place their vertices: a curved part's triangles are then no "
	      "longer all on one side of the surface. A move is kept only where every superface "
	      "around the vertex still passes every check (normal limit, distance tolerance, "
	      "texture stretch); flat and exact parts do not move, and each vertex keeps its "
	      "attributes. Off = every output vertex at its input position.",
	      double(d.placeVertices), 0, 1, false, true},
	     &Params::placeVertices},
	    {{"certifyDistance", K::Flag, "Certify the distance",
	      "measure each level's Hausdorff distance to the input, proven within 5 %",
	      "Beyond the paper: once a level is made, its two-sided Hausdorff distance to the "
	      "input (every point of the level to the input and every point of the input to the "
	      "level) is computed by branch and bound: exact distances at points give a lower "
	      "bound, bounds over whole triangles an upper bound, and triangles are cut until the "
	      "two are within 5 %. The upper bound is reported per level (log, table, file "
	      "comment); it is a proven figure, usually far below the construction's own distance "
	      "bound. It changes no level. Off = not computed (faster on large meshes).",
	      double(d.certifyDistance), 0, 1, false, true},
	     &Params::certifyDistance},
	};
}

// What of the input is joined, kept apart or limited.
std::vector<Entry> inputEntries()
{
	const Params d;
	const double kInf = HUGE_VAL;
	using K = ParamKind;
	return {
	    {{"weldVertices", K::Flag, "Weld coincident vertices", "weld vertices at the same position",
	      "Vertices at exactly the same position are joined before simplifying (the first "
	      "one is kept), as MeshLab does to STL files on import: a triangle soup (STL, most "
	      "CAD and BIM exports) then has the shared edges its superfaces grow across. Only "
	      "vertices on an edge that one face uses are joined: closed parts that touch stay "
	      "apart. The input is not changed; the log says how many were welded. Off = only "
	      "vertices that faces already share are joined.",
	      double(d.weldVertices), 0, 1, false, true},
	     &Params::weldVertices},
	    {{"weldDistance", K::DiagonalFraction, "Weld distance",
	      "also weld vertices closer than this, % of bbox diagonal",
	      "With welding on: vertices closer than this (mesh units; the percentage is of the "
	      "bounding-box diagonal) to an earlier kept vertex are joined to it too, for files "
	      "whose coincident vertices differ by rounding. 0 = exactly equal positions only "
	      "(default).",
	      d.weldDistance, 0, 1, false, true},
	     &Params::weldDistance},
	    {{"keepMaterials", K::Flag, "Keep materials apart",
	      "faces of different materials never merge",
	      "Faces with different materials, textures or face colours (MeshLab reads OBJ "
	      "materials into these) never share a superface: every output face has its input "
	      "faces' material. Off = merge across material changes (the output face takes the "
	      "material of one face it replaces). Only acts when the mesh has such attributes.",
	      double(d.keepMaterials), 0, 1, false, true},
	     &Params::keepMaterials},
	    {{"keepSeams", K::Flag, "Keep seams",
	      "texture seams and colour discontinuities are borders",
	      "Edges where the texture coordinates (per wedge or per vertex) or the vertex colour "
	      "or quality differ between the two faces (UV seams, colour seams of meshes with "
	      "duplicated vertices) are borders at every level: kept, straightened and merged "
	      "only along themselves. Off = merge across them (one side's values win). Only acts "
	      "when the mesh has such attributes.",
	      double(d.keepSeams), 0, 1, false, true},
	     &Params::keepSeams},
	    {{"maxTexError", K::Real, "Texture error limit (UV units)",
	      "texture-coordinate error limit, UV units (0 = none)",
	      "With texture coordinates: a superface whose new triangles interpolate, at an input "
	      "vertex they remove, texture coordinates farther than this from the vertex's own "
	      "(in texture space, 1 = the texture's width) is retried with tighter borders, then "
	      "split, like a normal-deviation failure. Default 1/2048: half a texel of a 1024 "
	      "texture. 0 = no limit. Each level reports the largest error measured.",
	      d.maxTexError, 0, kInf, false, true},
	     &Params::maxTexError},
	};
}

// The levels beyond the superfaces, and the threads.
std::vector<Entry> chainEntries()
{
	const Params d;
	const double kInf = HUGE_VAL;
	using K = ParamKind;
	return {
	    {{"collapseLevels", K::Flag, "Collapse the finer level",
	      "coarser levels also by collapses of the finer level where they reach its face count",
	      "Beyond the paper (docs/DESIGN.md, 50): each coarser angle level is also made from the "
	      "finer level by half-edge collapses with a proven distance bound, and is that mesh "
	      "when it reaches the superface level's face count within its distance bound. For "
	      "comparison only: not a parameter of the filter.",
	      double(d.collapseLevels), 0, 1, false, false},
	     &Params::collapseLevels},
	    {{"completeChain", K::Flag, "Keep every level a real step",
	      "continue levels the cells leave too heavy by edge collapses (false = the paper's)",
	      "Beyond the paper: on surfaces that curve at the scale of their triangles (low-poly, "
	      "scanned, organic models) the Gauss-sphere cells merge little, and the paper's "
	      "levels stay close to the input. With this on, a level with more than 0.8 times "
	      "the faces of the level before it, or more than its share of the input (the coarsest "
	      "level at most 15 %, the levels between in geometric steps), is continued by edge "
	      "collapses with quadric placement down to that count; its normal deviation is then "
	      "measured and reported, not held to its cells' bound, and its distance bound is "
	      "proven as for every level. Exact levels (planar CAD) keep their counts. Off = the "
	      "paper's levels.",
	      double(d.completeChain), 0, 1, false, true},
	     &Params::completeChain},
	    {{"threads", K::Integer, "Worker threads", "worker threads, 0 = one per core",
	      "Worker threads, 0 = one per core (at most 64); the output does not depend on it.",
	      double(d.threads), 0, kInf, false, false},
	     &Params::threads},
	};
}

std::vector<Entry> makeEntries()
{
	std::vector<Entry> e;
	for (auto part : {levelEntries, shapeEntries, buildEntries, inputEntries, chainEntries}) {
		const std::vector<Entry> p = part();
		e.insert(e.end(), p.begin(), p.end());
	}
	return e;
}

const std::vector<Entry> &entries()
{
	static const std::vector<Entry> e = makeEntries();
	return e;
}

const Entry *entryOf(const ParamSpec &spec)
{
	const std::vector<ParamSpec> &specs = paramSpecs();
	if (&spec >= specs.data() && &spec < specs.data() + specs.size())
		return &entries()[size_t(&spec - specs.data())];
	for (const Entry &e : entries()) // (a copy of a spec)
		if (std::string(e.spec.name) == spec.name)
			return &e;
	return nullptr;
}

std::string number(double x)
{
	char buf[32];
	std::snprintf(buf, sizeof buf, "%g", x);
	return buf;
}

// "between 0 and 180, exclusive" / "a finite value >= 0", in the unit the front ends show
std::string rangeText(const ParamSpec &s)
{
	const bool percent = s.kind == ParamKind::DiagonalFraction;
	const double scale = percent ? 100 : 1;
	const char *unit = percent ? " % of the bounding-box diagonal" : "";
	if (!std::isfinite(s.max))
		return "a finite value >= " + number(s.min * scale);
	return "between " + number(s.min * scale) + " and " + number(s.max * scale) + unit +
	       (s.openRange ? ", exclusive" : "");
}

std::string trim(const std::string &s)
{
	size_t b = 0, e = s.size();
	while (b < e && std::isspace(static_cast<unsigned char>(s[b])))
		++b;
	while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1])))
		--e;
	return s.substr(b, e - b);
}

bool isText(const ParamSpec &s)
{
	return s.kind == ParamKind::LevelList || s.kind == ParamKind::LevelTargets;
}

// Levels by target: one entry per level, in level order (finest = most faces, least error).
std::string validateTargets(const Params &p)
{
	const char *name = "Levels by (levelsBy)";
	if (!p.levelFaces.empty() && !p.levelDistances.empty())
		return std::string(name) + ": give face targets (levelFaces) or error targets "
		                           "(levelDistances), not both";
	const bool faces = !p.levelFaces.empty();
	const std::vector<double> &t = faces ? p.levelFaces : p.levelDistances;
	if (t.empty())
		return {};
	if (t.size() != size_t(p.maxLevel))
		return std::string(name) + ": " + std::to_string(t.size()) + " targets for " +
		       std::to_string(p.maxLevel) + " levels (one per level)";
	for (size_t i = 0; i < t.size(); ++i) {
		const double v = t[i];
		const bool in = faces ? p.levelFacesRelative ? v > 0 && v <= 1
		                                             : v >= 1 && v < 4e18 && v == std::floor(v)
		                      : v > 0 && v <= 1;
		if (!std::isfinite(v) || !in)
			return std::string(name) + ": target " +
			       number(faces && p.levelFacesRelative ? 100 * v
			              : faces                       ? v
			                                            : 100 * v) +
			       (faces ? p.levelFacesRelative ? " %" : " faces" : " %") + " of level " +
			       std::to_string(i) + " must be " +
			       (faces ? p.levelFacesRelative ? "above 0 and at most 100 % of the input's faces"
			                                     : "a whole number of faces, at least 1"
			              : "above 0 and at most 100 % of the diagonal");
		if (i > 0 && (faces ? !(v > t[i - 1]) : !(v < t[i - 1])))
			return std::string(name) + ": the targets must " +
			       (faces ? "grow from level 0 (fewest faces) to the finest level"
			              : "shrink from level 0 (largest error) to the finest level") +
			       ", each different";
	}
	return {};
}

// One target of a "faces:" or "error:" list: a positive number, '%' after it or not.
bool parseTarget(const std::string &item, double &value, bool &percent)
{
	std::string t = trim(item);
	percent = !t.empty() && t.back() == '%';
	if (percent)
		t = trim(t.substr(0, t.size() - 1));
	char *end = nullptr;
	value = std::strtod(t.c_str(), &end);
	return !t.empty() && end != nullptr && *end == 0 && std::isfinite(value);
}

} // namespace

bool parseLevelsBy(const std::string &text, Params &params, std::string &error)
{
	const std::string name = "Levels by (levelsBy): ";
	const std::string all = trim(text);
	std::string mode = trim(all.substr(0, all.find(':')));
	for (char &c : mode)
		c = char(std::tolower(static_cast<unsigned char>(c)));
	const bool hasList = all.find(':') != std::string::npos;
	if (mode.empty() || (mode == "angle" && !hasList)) {
		params.levelFaces.clear();
		params.levelDistances.clear();
		params.levelFacesRelative = false;
		return true;
	}
	const bool faces = mode == "faces";
	if ((!faces && mode != "error") || !hasList) {
		error = name + "'" + all +
		        "' is not a mode; write angle, faces:LIST (e.g. faces:50%,25%,10% or "
		        "faces:20000,5000) or error:LIST (e.g. error:0.01%,0.05%,0.2%)";
		return false;
	}
	const std::string list = all.substr(all.find(':') + 1);
	if (trim(list).empty()) {
		error = name + mode + ": needs a comma list of targets, e.g. " +
		        (faces ? "faces:50%,25%,10%" : "error:0.01%,0.05%,0.2%");
		return false;
	}
	std::vector<double> targets;
	int percents = 0;
	size_t from = 0;
	for (;;) {
		const size_t comma = list.find(',', from);
		const std::string item = trim(list.substr(from, comma - from));
		double v = 0;
		bool percent = false;
		if (!parseTarget(item, v, percent)) {
			error =
			    name + "'" + item + "' is not a number" +
			    (faces ? " (a percentage like 50% or a face count)" : " (a percentage like 0.05%)");
			return false;
		}
		if (!(v > 0)) {
			error = name + "'" + item + "': targets must be above 0";
			return false;
		}
		if (faces && percent && v > 100) {
			error = name + "'" + item + "': a face target is at most 100% of the input's faces";
			return false;
		}
		if (faces && !percent && v != std::floor(v)) {
			error = name + "'" + item + "': a face count is a whole number (or write a percentage)";
			return false;
		}
		if (!faces && v > 100) {
			error = name + "'" + item + "': an error target is at most 100% of the diagonal";
			return false;
		}
		percents += percent;
		targets.push_back(faces && !percent ? v : v / 100.0);
		if (comma == std::string::npos)
			break;
		from = comma + 1;
	}
	if (faces && percents != 0 && size_t(percents) != targets.size()) {
		error = name + "give every face target as a percentage or every one as a count, not both";
		return false;
	}
	if (targets.size() > size_t(kMaxCellLevel + 1)) {
		error = name + std::to_string(targets.size()) + " targets; at most " +
		        std::to_string(kMaxCellLevel + 1) + " (one level each)";
		return false;
	}
	// level order: level 0 (coarsest) first, with the fewest faces / the largest error
	std::sort(targets.begin(), targets.end());
	if (!faces)
		std::reverse(targets.begin(), targets.end());
	for (size_t i = 1; i < targets.size(); ++i)
		if (targets[i] == targets[i - 1]) {
			error = name + "the target " +
			        number(faces && percents == 0 ? targets[i] : 100 * targets[i]) +
			        (faces && percents == 0 ? "" : "%") + " is given twice (one level per target)";
			return false;
		}
	params.maxLevel = int(targets.size());
	params.levelFacesRelative = faces && percents > 0;
	(faces ? params.levelFaces : params.levelDistances) = targets;
	(faces ? params.levelDistances : params.levelFaces).clear();
	return true;
}

std::string levelsByText(const Params &p)
{
	const bool faces = !p.levelFaces.empty();
	if (!faces && p.levelDistances.empty())
		return "angle";
	const std::vector<double> &t = faces ? p.levelFaces : p.levelDistances;
	const bool percent = !faces || p.levelFacesRelative;
	std::string s = faces ? "faces:" : "error:";
	char buf[40];
	for (size_t i = t.size(); i-- > 0;) { // finest first
		std::snprintf(buf, sizeof buf, percent ? "%.10g%%" : "%.0f", percent ? 100 * t[i] : t[i]);
		s += buf;
		s += i ? "," : "";
	}
	return s;
}

const std::vector<ParamSpec> &paramSpecs()
{
	static const std::vector<ParamSpec> specs = [] {
		std::vector<ParamSpec> v;
		for (const Entry &e : entries())
			v.push_back(e.spec);
		return v;
	}();
	return specs;
}

const ParamSpec *findParam(const std::string &name)
{
	for (const ParamSpec &s : paramSpecs())
		if (name == s.name)
			return &s;
	return nullptr;
}

double getParam(const Params &p, const ParamSpec &spec)
{
	const Entry *e = entryOf(spec);
	if (e == nullptr || isText(spec))
		return NAN;
	return e->integer ? double(p.*(e->integer)) : e->real ? p.*(e->real) : double(p.*(e->flag));
}

void setParam(Params &p, const ParamSpec &spec, double value)
{
	const Entry *e = entryOf(spec);
	if (e == nullptr || isText(spec))
		return;
	if (e->integer)
		p.*(e->integer) = std::isfinite(value) && std::fabs(value) < 2e9 ? int(value) : -1;
	else if (e->real)
		p.*(e->real) = value;
	else
		p.*(e->flag) = value != 0;
}

std::string validateParams(const Params &p)
{
	for (const ParamSpec &s : paramSpecs()) {
		if (isText(s) || s.kind == ParamKind::Flag)
			continue;
		const double v = getParam(p, s);
		const bool in =
		    std::isfinite(v) && (s.openRange ? v > s.min && v < s.max : v >= s.min && v <= s.max);
		if (!in) {
			const bool percent = s.kind == ParamKind::DiagonalFraction;
			return std::string(s.label) + " (" + s.name + ") must be " + rangeText(s) + " (got " +
			       number(percent ? 100 * v : v) + (percent ? " %)" : ")");
		}
	}
	return validateTargets(p);
}

bool parseOutputLevels(const std::string &text, int maxLevel, uint32_t &mask, std::string &error)
{
	std::string all = trim(text);
	for (char &c : all)
		c = char(std::tolower(static_cast<unsigned char>(c)));
	if (all == "all") {
		mask = maxLevel >= 32 ? 0xffffffffu : (1u << maxLevel) - 1u;
		return true;
	}
	mask = 0;
	size_t from = 0;
	for (;;) {
		const size_t comma = text.find(',', from);
		const std::string item = trim(text.substr(from, comma - from));
		char *end = nullptr;
		const long level = std::strtol(item.c_str(), &end, 10);
		if (item.empty() || *end != 0 || level < 0 || level >= maxLevel) {
			error = "Output levels (outputLevels): '" + item +
			        "' is not a level index; write \"all\" or a comma list of numbers from 0 "
			        "(coarsest) to " +
			        std::to_string(maxLevel - 1) + " (finest, = number of levels - 1)";
			return false;
		}
		mask |= 1u << level;
		if (comma == std::string::npos)
			return true;
		from = comma + 1;
	}
}

} // namespace gausslod
