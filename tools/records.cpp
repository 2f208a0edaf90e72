// The gausslod tool's records of an outcome: a level's JSON line (the tool's --json, batch's
// records) and the input repairs as JSON members and as a line of text.
#include "cli.h"

#include "gausslod/level_figures.h"

#include <cstdio>
#include <string>

namespace cli {

std::string repairsJson(const gausslod::InputStats &in)
{
	return gausslod::jsonMembers(gausslod::inputFigures(in), gausslod::FigureGroup::Input);
}

std::string levelJson(const gausslod::Params &p, const Outcome &o, size_t i)
{
	using gausslod::FigureGroup;
	const std::vector<gausslod::LevelFigure> figures =
	    gausslod::levelFigures(o.levels[i], o.diagonal, p);
	std::string attributes; // (what its file carries: the outcome says)
	for (size_t a = 0; a < o.attributes.size(); ++a)
		attributes += (a ? "," : "") + jsonString(o.attributes[a]);
	std::string json =
	    "{" + gausslod::jsonMembers(figures, FigureGroup::Level) + "," +
	    gausslod::jsonMembers(figures, FigureGroup::Input) + ",\"attributes\":[" + attributes +
	    "],\"superface_colours\":" + (o.superfaceColours ? "true" : "false") + "," +
	    gausslod::jsonMembers(figures, FigureGroup::Texture) + "," +
	    gausslod::jsonMembers(figures, FigureGroup::Target) + ",\"file\":" + jsonString(o.files[i]);
	if (i < o.materialFiles.size() && !o.materialFiles[i].empty())
		json += ",\"material_file\":" + jsonString(o.materialFiles[i]);
	return json + "}";
}

std::string repairsText(const gausslod::InputStats &in, const std::vector<std::string> &readNotes)
{
	std::string s;
	char buf[160];
	auto add = [&](const char *text) { s += s.empty() ? "" : "; ", s += text; };
	for (const std::string &n : readNotes)
		add(n.c_str());
	if (in.weldedVertices) {
		std::snprintf(buf, sizeof buf, "%zu vertices welded (%zu faces re-indexed)",
		              in.weldedVertices, in.facesReindexed);
		add(buf);
	}
	if (in.facesSkipped()) {
		std::snprintf(buf, sizeof buf,
		              "%zu faces skipped (%zu with a repeated vertex, %zu repeats)",
		              in.facesSkipped(), in.facesRepeatedVertex, in.facesDuplicate);
		add(buf);
	}
	if (in.facesDegenerate) {
		std::snprintf(buf, sizeof buf, "%zu degenerate faces kept as they are", in.facesDegenerate);
		add(buf);
	}
	if (in.verticesLocked) {
		std::snprintf(buf, sizeof buf,
		              "%zu vertices locked (non-manifold or inconsistently oriented edges, "
		              "non-manifold vertices, degenerate faces)",
		              in.verticesLocked);
		add(buf);
	}
	return s;
}

} // namespace cli
