// A level's figures by name: the one place that turns a LevelStats into the values its outputs
// show (the tool's table and JSON lines, the filter's log): what each figure is called, how it is
// derived (percentages of the diagonal), when it is not known, and how it is written. A new
// figure is one entry in levelFigures() (level_figures.cpp); the outputs render the list.
#pragma once

#include "gausslod/gausslod.h"

#include <string>
#include <vector>

namespace gausslod {

/// The part of a level's record a figure belongs to (the JSON line lists the parts in this order,
/// with the tool's own members, attributes and file, between Input and Texture and at the end).
enum class FigureGroup {
	Level,   ///< the level's build: faces, superfaces, deviation, times, distance, placement
	Input,   ///< the input repairs (InputStats), the same for every level
	Texture, ///< texture coordinates: the error measured and the limit it was held to
	Target,  ///< levels by target: the target, whether it was reached, the tolerance used
};

/// When the table shows a figure's column (the columns of one run are the same for every row).
enum class ColumnShown {
	Always,
	Distance,  ///< with a distance tolerance or levels by target
	Texture,   ///< the input has texture coordinates
	Target,    ///< levels by target
	Certified, ///< with the certified distance (Params::certifyDistance)
};

struct LevelFigure {
	const char *key = "";                   ///< its JSON member's name ("max_dev_deg")
	FigureGroup group = FigureGroup::Level; ///< its part of the JSON record
	double value = 0;  ///< the value (counts exact; flags 0 or 1; a text figure: 0)
	bool known = true; ///< false: not measured, or not asked for
	std::string json;  ///< the value as JSON writes it (null when not known); "": not a member
	/// The table's column, if the figure has one: its place from the left (0: no column), when
	/// it is shown, its header and the level's cell (both as printed, padded and separated).
	int column = 0;
	ColumnShown shown = ColumnShown::Always;
	std::string header, cell;
};

/// The figures of level `s`, in the order of the tool's JSON line; `diagonal` is the input's
/// bounding-box diagonal (the percentages are of it; unknown if it is not positive), `p` the
/// parameters the levels were built with (the mode of the targets, the texture limit).
std::vector<LevelFigure> levelFigures(const LevelStats &s, double diagonal, const Params &p);

/// The input repairs as figures (group Input), in the JSON line's order.
std::vector<LevelFigure> inputFigures(const InputStats &in);

/// The figure named `key` of `figures` (one not known, with no key, if none is named so).
const LevelFigure &figure(const std::vector<LevelFigure> &figures, const char *key);

/// The JSON members "key":value of the figures of `group`, comma separated, in order.
std::string jsonMembers(const std::vector<LevelFigure> &figures, FigureGroup group);

/// The table's columns of a run, left to right: those whose ColumnShown bit (1 << its value) is
/// set in `shown`.
std::vector<const LevelFigure *> tableColumns(const std::vector<LevelFigure> &figures,
                                              unsigned shown);

} // namespace gausslod
