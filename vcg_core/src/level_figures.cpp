// A level's figures by name (gausslod/level_figures.h), and why a face budget was not reached
// (budgetNote, declared in gausslod.h).
#include "gausslod/level_figures.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string>

namespace gausslod {

namespace {

// printf's text of one value.
template <class T>
std::string printed(const char *format, T value)
{
	char buf[96];
	std::snprintf(buf, sizeof buf, format, value);
	return buf;
}

// Appends figures to a list: a count, a real number, a flag or a text; `known` false writes null.
class FigureList {
public:
	explicit FigureList(std::vector<LevelFigure> &out) : out_(out) {}
	LevelFigure &count(const char *key, FigureGroup g, size_t n, bool known = true)
	{
		return add(key, g, double(n), known, printed("%zu", n));
	}
	LevelFigure &whole(const char *key, FigureGroup g, int n) // (ints: level, rounds, trials)
	{
		return add(key, g, n, true, printed("%d", n));
	}
	LevelFigure &real(const char *key, FigureGroup g, double v, const char *format,
	                  bool known = true)
	{
		return add(key, g, v, known, printed(format, v));
	}
	LevelFigure &flag(const char *key, FigureGroup g, bool b)
	{
		return add(key, g, b ? 1 : 0, true, b ? "true" : "false");
	}
	LevelFigure &text(const char *key, FigureGroup g, const std::string &s)
	{
		return add(key, g, 0, true, "\"" + s + "\"");
	}
	/// A figure of the table only (not a JSON member). (Each reference returned is good until the
	/// next figure is added.)
	LevelFigure &tableOnly(const char *key, FigureGroup g) { return add(key, g, 0, true, ""); }

private:
	LevelFigure &add(const char *key, FigureGroup g, double value, bool known, std::string json)
	{
		LevelFigure f;
		f.key = key;
		f.group = g;
		f.value = value;
		f.known = known;
		f.json = known ? std::move(json) : "null";
		out_.push_back(std::move(f));
		return out_.back();
	}
	std::vector<LevelFigure> &out_;
};

// Gives figure `f` the table's column `column` (from the left), shown when `shown`.
void column(LevelFigure &f, int column, ColumnShown shown, std::string header, std::string cell)
{
	f.column = column;
	f.shown = shown;
	f.header = std::move(header);
	f.cell = std::move(cell);
}

// The build: sizes, superfaces, normal deviation and times (table columns 1-9).
void buildFigures(FigureList &l, const LevelStats &s)
{
	const FigureGroup g = FigureGroup::Level;
	const ColumnShown a = ColumnShown::Always;
	column(l.whole("level", g, s.level), 1, a, printed("%-6s", "level"),
	       printed("%-6s", ("LOD" + std::to_string(s.level)).c_str()));
	column(l.count("faces", g, s.faces), 2, a, printed(" %9s", "faces"), printed(" %9zu", s.faces));
	column(l.count("vertices", g, s.vertices), 3, a, printed(" %9s", "vertices"),
	       printed(" %9zu", s.vertices));
	column(l.count("superfaces", g, s.superfaces), 4, a, printed(" %10s", "superfaces"),
	       printed(" %10zu", s.superfaces));
	column(l.count("fallbacks", g, s.fallbacks), 5, a, printed(" %9s", "fallback"),
	       printed(" %9zu", s.fallbacks));
	l.count("retriangulated", g, s.retriangulated);
	l.count("carried_superfaces", g, s.carriedSuperfaces);
	// (a level continued by collapses, DESIGN 51, is not held to its cells' bound: "-")
	column(l.real("bound_deg", g, s.boundDeg, "%.4f"), 6, a, printed(" %9s", "bound"),
	       printed(" %9s", s.reduced ? "-" : printed("%.2f", s.boundDeg).c_str()));
	column(l.real("max_dev_deg", g, s.maxNormalDevDeg, "%.4f"), 7, a, printed(" %9s", "maxdev"),
	       printed(" %9.2f", s.maxNormalDevDeg));
	column(l.real("mean_dev_deg", g, s.meanNormalDevDeg, "%.4f"), 8, a, printed(" %9s", "meandev"),
	       printed(" %9.3f", s.meanNormalDevDeg));
	l.count("unmeasured_faces", g, s.unmeasuredFaces);
	column(l.real("seconds", g, s.seconds, "%.4f"), 9, a, printed(" %8s", "seconds"),
	       printed(" %8.3f", s.seconds));
	l.real("seconds_partition", g, s.secondsPartition, "%.4f");
	l.real("seconds_borders", g, s.secondsBorders, "%.4f");
	l.real("seconds_triangulation", g, s.secondsTriangulation, "%.4f");
	l.real("seconds_checks", g, s.secondsChecks, "%.4f");
	l.real("seconds_placement", g, s.secondsPlacement, "%.4f");
	l.real("seconds_collapse", g, s.secondsCollapse, "%.4f");
	l.whole("rounds", g, s.rounds);
	l.count("collapses", g, s.collapses);
	l.flag("reduced", g, s.reduced);
	l.flag("reused_finer", g, s.reusedFiner);
}

// The distance to the input: the proven bound, the vertex placement, the certified Hausdorff
// distance (DESIGN 23, 27, 52), in % of the diagonal and mesh units (table columns 10, 11, 17).
void distanceFigures(FigureList &l, const LevelStats &s, double diag)
{
	const FigureGroup g = FigureGroup::Level;
	const ColumnShown d = ColumnShown::Distance;
	const bool bound = s.distanceBound >= 0 && diag > 0;
	const double boundPct = bound ? 100.0 * s.distanceBound / diag : -1;
	column(l.real("distance_bound_pct", g, boundPct, "%.4f", bound), 11, d,
	       printed(" %10s", "distbound%"),
	       bound ? printed("  %9.4f", boundPct) : printed("  %9s", "null"));
	l.real("distance_bound", g, s.distanceBound, "%.6g", bound);
	column(l.count("placed_vertices", g, s.placedVertices), 10, d, printed(" %9s", "placed"),
	       printed(" %9zu", s.placedVertices));
	l.real("max_placement_pct", g, diag > 0 ? 100.0 * s.maxPlacement / diag : 0.0, "%.4f");
	l.real("max_placement", g, s.maxPlacement, "%.6g");
	const bool certified = s.hausdorff >= 0 && diag > 0;
	const double hausPct = certified ? 100.0 * s.hausdorff / diag : -1;
	column(l.real("hausdorff_pct", g, hausPct, "%.6f", certified), 17, ColumnShown::Certified,
	       printed(" %10s", "hausdorff%"),
	       certified ? printed(" %10.4f", hausPct) : printed(" %10s", "-"));
	l.real("hausdorff", g, s.hausdorff, "%.6g", certified);
	l.real("hausdorff_lower", g, s.hausdorffLower, "%.6g", certified);
	// (the log's: not a JSON member; the next two are members only when certified)
	l.real("hausdorff_lower_pct", g, certified ? 100.0 * s.hausdorffLower / diag : -1, "%.6f",
	       certified)
	    .json.clear();
	LevelFigure &converged = l.flag("hausdorff_converged", g, s.hausdorffConverged);
	if (!certified)
		converged.json.clear();
	LevelFigure &seconds = l.real("seconds_hausdorff", g, s.secondsHausdorff, "%.4f");
	if (!certified)
		seconds.json.clear();
}

// The texture coordinates' error, and the limit the level was held to: its own (DESIGN 51) or
// the parameter's (table column 12).
void textureFigures(FigureList &l, const LevelStats &s, const Params &p)
{
	const FigureGroup g = FigureGroup::Texture;
	const bool measured = s.maxTexError >= 0;
	column(l.real("max_tex_error", g, s.maxTexError, "%.6g", measured), 12, ColumnShown::Texture,
	       printed(" %10s", "texerr"),
	       measured ? printed(" %10.6f", s.maxTexError) : printed(" %10s", "-"));
	l.real("tex_error_limit", g, s.texErrorLimit >= 0 ? s.texErrorLimit : p.maxTexError, "%.6g",
	       measured);
}

// Levels by target: the mode, the target (faces or % of the diagonal), whether it was reached,
// why not (the least faces of the level's topology, its boundary loops), the tolerance it was
// built with (% of the diagonal) and the builds it took (table columns 13-16).
void targetFigures(FigureList &l, const LevelStats &s, const Params &p)
{
	const FigureGroup g = FigureGroup::Target;
	const ColumnShown t = ColumnShown::Target;
	const bool faces = !p.levelFaces.empty();
	l.text("levels_by", g, faces ? "faces" : !p.levelDistances.empty() ? "error" : "angle");
	l.count("target_faces", g, s.targetFaces, faces);
	l.real("target_error_pct", g, 100.0 * s.targetDistance, "%.6g", s.targetDistance >= 0);
	column(l.tableOnly("target", g), 13, t,
	       faces ? printed(" %10s", "target") : printed(" %10s", "target%"),
	       s.targetFaces > 0 || s.targetDistance < 0
	           ? printed(" %10zu", s.targetFaces)
	           : printed(" %9.4f%%", 100.0 * s.targetDistance));
	column(l.flag("target_reached", g, s.targetReached), 14, t, printed(" %7s", "reached"),
	       printed(" %7s", s.targetReached ? "yes" : "NO"));
	const bool missed = !s.targetReached && s.targetFaces > 0;
	l.count("least_faces", g, s.leastFaces, missed && s.leastFaces > 0);
	l.count("boundary_loops", g, s.boundaryLoops, missed);
	column(l.real("tolerance_pct", g, 100.0 * s.tolerance, "%.6g"), 15, t, printed(" %9s", "tol%"),
	       printed(" %9.4f", 100.0 * s.tolerance));
	column(l.whole("trials", g, s.trials), 16, t, printed(" %6s", "trials"),
	       printed(" %6d", s.trials));
}

} // namespace

std::vector<LevelFigure> levelFigures(const LevelStats &s, double diagonal, const Params &p)
{
	std::vector<LevelFigure> figures;
	FigureList l(figures);
	buildFigures(l, s);
	distanceFigures(l, s, diagonal);
	const std::vector<LevelFigure> input = inputFigures(s.input);
	figures.insert(figures.end(), input.begin(), input.end());
	textureFigures(l, s, p);
	targetFigures(l, s, p);
	return figures;
}

std::vector<LevelFigure> inputFigures(const InputStats &in)
{
	std::vector<LevelFigure> figures;
	FigureList l(figures);
	const FigureGroup g = FigureGroup::Input;
	l.count("welded_vertices", g, in.weldedVertices);
	l.count("faces_reindexed", g, in.facesReindexed);
	l.count("faces_skipped_repeated_vertex", g, in.facesRepeatedVertex);
	l.count("faces_skipped_duplicate", g, in.facesDuplicate);
	l.count("faces_kept_degenerate", g, in.facesDegenerate);
	l.count("vertices_locked", g, in.verticesLocked);
	l.count("coplanar_regions", g, in.coplanarRegions);
	l.count("faces_after_coplanar", g, in.facesAfterCoplanar);
	l.real("coplanar_distance", g, in.coplanarDistance, "%.9g");
	return figures;
}

const LevelFigure &figure(const std::vector<LevelFigure> &figures, const char *key)
{
	for (const LevelFigure &f : figures)
		if (std::strcmp(key, f.key) == 0)
			return f;
	static const LevelFigure none = [] {
		LevelFigure f;
		f.known = false;
		return f;
	}();
	return none;
}

std::string jsonMembers(const std::vector<LevelFigure> &figures, FigureGroup group)
{
	std::string s;
	for (const LevelFigure &f : figures)
		if (f.group == group && !f.json.empty())
			s += (s.empty() ? "\"" : ",\"") + std::string(f.key) + "\":" + f.json;
	return s;
}

std::vector<const LevelFigure *> tableColumns(const std::vector<LevelFigure> &figures,
                                              unsigned shown)
{
	std::vector<const LevelFigure *> columns;
	for (const LevelFigure &f : figures)
		if (f.column > 0 && (shown & (1u << unsigned(f.shown))))
			columns.push_back(&f);
	std::stable_sort(
	    columns.begin(), columns.end(),
	    [](const LevelFigure *a, const LevelFigure *b) { return a->column < b->column; });
	return columns;
}

std::string budgetNote(const LevelStats &s)
{
	if (s.targetReached || s.targetFaces == 0)
		return "";
	const std::string topology =
	    (s.components > 1 ? std::to_string(s.components) + " parts, " : std::string()) +
	    (s.boundaryLoops == 0 ? std::string("closed")
	                          : std::to_string(s.boundaryLoops) + " boundary loop" +
	                                (s.boundaryLoops == 1 ? "" : "s") + " kept open");
	if (s.leastFaces > 0 && s.faces <= s.leastFaces)
		return "the least a mesh of its topology can have (" + topology + ")";
	return "no collapse is left that keeps its boundaries, seams, materials and shape valid" +
	       (s.leastFaces > 0 ? " (its topology, " + topology + ", allows " +
	                               std::to_string(s.leastFaces) + " faces)"
	                         : std::string(" (non-manifold)"));
}

} // namespace gausslod
