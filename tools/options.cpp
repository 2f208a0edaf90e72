// The gausslod tool's options: the engine's parameters as --kebab-case options (ParamSpec), the
// tool's own, earlier spellings, and a MeshLab script's parameters (--from-mlx).
#include "cli.h"

#include "gausslod_io/export_mesh.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

namespace cli {

namespace {

bool parseDouble(const std::string &s, double &out)
{
	char *end = nullptr;
	out = std::strtod(s.c_str(), &end);
	return end && *end == 0 && end != s.c_str();
}

bool parseBool(const std::string &s, bool &out)
{
	if (s == "true" || s == "1" || s == "on" || s == "yes")
		return out = true, true;
	if (s == "false" || s == "0" || s == "off" || s == "no")
		return out = false, true;
	return false;
}

// The option of a parameter: "--" + its name in kebab case (maxLevel -> --max-level).
std::string flagOf(const char *name)
{
	std::string flag = "--";
	for (const char *c = name; *c; ++c) {
		if (std::isupper(static_cast<unsigned char>(*c)))
			flag += '-', flag += char(std::tolower(static_cast<unsigned char>(*c)));
		else
			flag += *c;
	}
	return flag;
}

// Earlier spellings of the options, still accepted: {old, new, value} (value "" = takes one).
const char *const kAliases[][3] = {
    {"--levels", "--max-level", ""},           {"--straighten", "--straighten-tol", ""},
    {"--merge", "--merge-dist", ""},           {"--paper-superfaces", "--across-cells", "false"},
    {"--no-weld", "--weld-vertices", "false"}, {"--no-colour", "--colour-superfaces", "false"},
};

// Sets the parameter `s` from its option's value (distances are percentages on the command line).
bool setFromText(const gausslod::ParamSpec &s, const std::string &flag, const std::string &text,
                 Options &o, std::string &error)
{
	using gausslod::ParamKind;
	if (s.kind == ParamKind::LevelList) {
		o.outputLevels = text;
		return true;
	}
	if (s.kind == ParamKind::LevelTargets) {
		o.levelsBy = text;
		return true;
	}
	bool b = false;
	double v = 0;
	if (s.kind == ParamKind::Flag) {
		if (!parseBool(text, b))
			return error = flag + " needs true or false", false;
		gausslod::setParam(o.params, s, b ? 1 : 0);
		return true;
	}
	if (!parseDouble(text, v))
		return error = flag + " needs a number", false;
	if (s.kind == ParamKind::Integer && (!(v >= -1e9 && v <= 1e9) || v != double(int(v))))
		return error = flag + " needs a whole number", false;
	gausslod::setParam(o.params, s, s.kind == ParamKind::DiagonalFraction ? v / 100.0 : v);
	return true;
}

// The value of attribute `name` in one XML tag's text ("" if none).
std::string xmlAttribute(const std::string &tag, const std::string &name)
{
	const std::string key = " " + name + "=\"";
	const size_t at = tag.find(key);
	if (at == std::string::npos)
		return "";
	const size_t from = at + key.size(), to = tag.find('"', from);
	return to == std::string::npos ? "" : tag.substr(from, to - from);
}

// --from-mlx: the GaussLOD filter's parameters in a MeshLab script as the tool's options, read as
// the filter reads them (plugin/filter_gausslod.cpp, readRequest): a distance (RichAbsPerc) is
// its share of the min..max range, 'Levels by' the drop-down and 'Targets' (or the text of a
// script written when it was text); parameters the script lacks keep their defaults.
bool mlxOptions(const std::string &file, std::vector<std::string> &out, std::string &error)
{
	std::ifstream in(file);
	std::stringstream text;
	text << in.rdbuf();
	const std::string xml = text.str();
	if (!in && xml.empty())
		return error = "--from-mlx: cannot read " + file, false;
	const size_t filter = xml.find("name=\"Gauss Sphere LOD: Merge Near-Coplanar Faces\"");
	if (filter == std::string::npos)
		return error = "--from-mlx: " + file + " does not run the GaussLOD filter", false;
	const size_t end = xml.find("</filter>", filter);
	std::map<std::string, std::string> tags; // name -> its Param tag
	for (size_t at = xml.find("<Param", filter); at != std::string::npos && at < end;
	     at = xml.find("<Param", at + 1)) {
		const std::string tag = xml.substr(at, xml.find('>', at) - at);
		tags[xmlAttribute(tag, "name")] = tag;
	}
	auto value = [&](const char *name) { return xmlAttribute(tags[name], "value"); };
	using gausslod::ParamKind;
	// (levels by target: the number of targets is the number of levels, 'maxLevel' unused)
	const std::string by = value("levelsBy");
	const bool byTarget =
	    (xmlAttribute(tags["levelsBy"], "type") == "RichEnum" && (by == "1" || by == "2")) ||
	    by.compare(0, 6, "faces:") == 0 || by.compare(0, 6, "error:") == 0;
	for (const gausslod::ParamSpec &sp : gausslod::paramSpecs()) {
		if (!sp.inFilter || !tags.count(sp.name) ||
		    (byTarget && std::string(sp.name) == "maxLevel"))
			continue;
		const std::string tag = tags[sp.name], v = xmlAttribute(tag, "value");
		std::string arg = v;
		if (sp.kind == ParamKind::DiagonalFraction) {
			const double x = std::atof(v.c_str()), lo = std::atof(xmlAttribute(tag, "min").c_str()),
			             hi = std::atof(xmlAttribute(tag, "max").c_str());
			if (!(hi > lo))
				return error = "--from-mlx: " + std::string(sp.name) + " has no min..max range",
				       false;
			char buf[64];
			std::snprintf(buf, sizeof buf, "%.17g", 100.0 * (x - lo) / (hi - lo));
			arg = buf;
		} else if (sp.kind == ParamKind::LevelTargets) {
			const std::string type = xmlAttribute(tag, "type");
			if (type == "RichEnum")
				arg = v == "1"   ? "faces:" + value("levelTargets")
				      : v == "2" ? "error:" + value("levelTargets")
				                 : "angle";
		}
		out.push_back(flagOf(sp.name));
		out.push_back(arg);
	}
	if (tags.count("colourSuperfaces"))
		out.insert(out.end(), {"--colour-superfaces", value("colourSuperfaces")});
	if (value("overwriteColours") == "true")
		out.push_back("--overwrite-colours");
	if (value("selectedOnly") == "true")
		return error = "--from-mlx: the script simplifies the selection only (selectedOnly): the "
		               "tool has no selection",
		       false;
	return true;
}

} // namespace

const char *optionHelp()
{
	static const std::string help = [] {
		using gausslod::ParamKind;
		std::string h = "options (the MeshLab filter's parameters and defaults):\n";
		char line[512];
		for (const gausslod::ParamSpec &s : gausslod::paramSpecs()) {
			const bool pct = s.kind == ParamKind::DiagonalFraction;
			const char *arg = s.kind == ParamKind::Flag           ? "BOOL"
			                  : s.kind == ParamKind::LevelList    ? "L"
			                  : s.kind == ParamKind::LevelTargets ? "T"
			                  : pct                               ? "P"
			                                                      : "N";
			std::string def = s.kind == ParamKind::LevelList      ? "all"
			                  : s.kind == ParamKind::LevelTargets ? "angle"
			                  : s.kind == ParamKind::Flag ? (s.defaultValue ? "true" : "false")
			                                              : "";
			if (def.empty()) {
				std::snprintf(line, sizeof line, "%g", pct ? 100 * s.defaultValue : s.defaultValue);
				def = line;
			}
			const std::string flag = flagOf(s.name) + " " + arg;
			std::snprintf(line, sizeof line, "  %-22s %s (%s)\n", flag.c_str(), s.summary,
			              def.c_str());
			h += line;
			if (s.kind == ParamKind::LevelTargets)
				h +=
				    "                         faces: one level per budget (% of the input's faces\n"
				    "                         or counts), each with its distance tolerance "
				    "searched\n"
				    "                         for the most faces within it; error: one level per\n"
				    "                         tolerance (% of bbox diagonal). The number of "
				    "targets\n"
				    "                         (up to 8) sets the number of levels. Where the\n"
				    "                         superfaces cannot get to a budget, proven edge\n"
				    "                         collapses make the level; only a true minimum (the\n"
				    "                         boundaries and delimiters kept) stops one (the\n"
				    "                         table's reached column says so)\n";
		}
		h += "  --colour-superfaces BOOL  colour faces by superface where the input has no colour\n"
		     "                         of its own (no vertex or face colour, no texture\n"
		     "                         coordinates) (true)\n"
		     "  --overwrite-colours    colour faces by superface even where the input has\n"
		     "                         colours (they are then not written)\n"
		     "  --format F             ply, obj (+ .mtl), off, stl, glb (binary glTF: colours,\n"
		     "                         texture coordinates and PNG/JPEG textures embedded) or\n"
		     "                         gltf (the same as one JSON file) (the input's)\n"
		     "  --lod-file             glb: also OUTDIR/<name>_lods.glb, the whole chain in one\n"
		     "                         file (MSFT_lod on the full-detail node, screen coverage\n"
		     "                         from each level's distance)\n"
		     "  --3dtiles              glb levels, the input as OUTDIR/<name>_full.glb and\n"
		     "                         OUTDIR/tileset.json (3D Tiles 1.1: coarsest at the root,\n"
		     "                         each tile's geometricError its level's distance)\n"
		     "  --tiles-transform M    16 numbers, column major: the tileset root's transform\n"
		     "  --from-mlx SCRIPT      the GaussLOD filter's parameters of a MeshLab script (as\n"
		     "                         the filter reads them; later options win)\n"
		     "  --json                 one JSON line per level instead of the table\n"
		     "  --quiet                no progress line (printed on a terminal only)\n"
		     "  earlier spellings: --levels N, --straighten P, --merge P, --paper-superfaces\n"
		     "  (= --across-cells false), --no-weld (= --weld-vertices false), --no-colour\n";
		return h;
	}();
	return help.c_str();
}

namespace {

// `given` with each --from-mlx SCRIPT replaced by the script's options (they stand where it is:
// later options win).
bool expandScripts(const std::vector<std::string> &given, std::vector<std::string> &args,
                   std::string &error)
{
	for (size_t i = 0; i < given.size(); ++i) {
		if (given[i] != "--from-mlx") {
			args.push_back(given[i]);
			continue;
		}
		if (i + 1 >= given.size())
			return error = "--from-mlx needs a MeshLab script", false;
		if (!mlxOptions(given[++i], args, error))
			return false;
	}
	return true;
}

enum class Taken { No, Yes, Failed };

// The tool's own options (not the engine's parameters) at args[i]; `i` moves past its value.
Taken toolOption(const std::string &flag, const std::vector<std::string> &args, size_t &i,
                 Options &o, std::string &error)
{
	if (flag == "--json" || flag == "--overwrite-colours" || flag == "--lod-file" ||
	    flag == "--3dtiles" || flag == "--quiet") {
		(flag == "--json"       ? o.json
		 : flag == "--quiet"    ? o.quiet
		 : flag == "--lod-file" ? o.lodFile
		 : flag == "--3dtiles"  ? o.tiles
		                        : o.overwriteColours) = true;
		if (flag == "--lod-file" || flag == "--3dtiles")
			o.format = "glb";
		return Taken::Yes;
	}
	auto fail = [&](const char *why) { return error = why, Taken::Failed; };
	if (flag == "--tiles-transform") {
		if (i + 1 >= args.size())
			return fail("--tiles-transform needs 16 numbers");
		o.tilesTransform.clear();
		std::string v = args[++i];
		for (char &c : v)
			c = c == ',' ? ' ' : c;
		std::istringstream in(v);
		double x;
		while (in >> x)
			o.tilesTransform.push_back(x);
		if (o.tilesTransform.size() != 16 || !in.eof())
			return fail("--tiles-transform needs 16 numbers");
		for (const double t : o.tilesTransform)
			if (!std::isfinite(t))
				return fail("--tiles-transform needs 16 finite numbers");
		return Taken::Yes;
	}
	if (flag == "--format") {
		if (i + 1 >= args.size())
			return fail("--format needs a value");
		o.format = args[++i];
		for (char &c : o.format)
			c = char(std::tolower(static_cast<unsigned char>(c)));
		if (o.format == "glb" || o.format == "gltf")
			return Taken::Yes;
		if (gausslod::formatNamed(o.format) == gausslod::MeshFormat::Unknown)
			return fail("--format needs ply, obj, off, stl, glb or gltf");
		o.format = gausslod::formatExtension(gausslod::formatNamed(o.format));
		return Taken::Yes;
	}
	return Taken::No;
}

// What the options say together: the levels by target (their number is the number of levels),
// the glb files, the engine's checks of the parameters and the output levels.
bool checkOptions(Options &o, bool maxLevelGiven, std::string &error)
{
	o.params.maxLevel = o.maxLevel;
	if (!gausslod::parseLevelsBy(o.levelsBy, o.params, error))
		return false;
	if (maxLevelGiven && o.params.maxLevel != o.maxLevel)
		return error = "--levels-by " + o.levelsBy + " makes " + std::to_string(o.params.maxLevel) +
		               " levels (one per target); --max-level " + std::to_string(o.maxLevel) +
		               " disagrees (leave it out)",
		       false;
	if ((o.lodFile || o.tiles) && o.format != "glb")
		return error = std::string(o.tiles ? "--3dtiles" : "--lod-file") +
		               " writes glb levels; --format " + o.format + " disagrees",
		       false;
	if (!o.tilesTransform.empty() && !o.tiles)
		return error = "--tiles-transform is for --3dtiles", false;
	error = gausslod::validateParams(o.params);
	return error.empty() && gausslod::parseOutputLevels(o.outputLevels, o.params.maxLevel,
	                                                    o.params.outputLevels, error);
}

} // namespace

bool parseOptions(const std::vector<std::string> &given, Options &o,
                  std::vector<std::string> &positional, std::string &error)
{
	bool maxLevelGiven = false;
	std::vector<std::string> args;
	if (!expandScripts(given, args, error))
		return false;
	for (size_t i = 0; i < args.size(); ++i) {
		std::string flag = args[i], value;
		bool valueGiven = false;
		for (const auto &alias : kAliases)
			if (flag == alias[0]) {
				flag = alias[1];
				valueGiven = *alias[2] != 0;
				value = alias[2];
			}
		const Taken taken = toolOption(flag, args, i, o, error);
		if (taken != Taken::No) {
			if (taken == Taken::Failed)
				return false;
			continue;
		}
		const gausslod::ParamSpec *spec = nullptr;
		for (const gausslod::ParamSpec &s : gausslod::paramSpecs())
			if (flag == flagOf(s.name))
				spec = &s;
		if (spec == nullptr && flag != "--colour-superfaces") {
			if (flag.size() > 1 && flag[0] == '-')
				return error = "unknown option " + flag, false;
			positional.push_back(flag);
			continue;
		}
		if (!valueGiven) {
			if (i + 1 >= args.size())
				return error = args[i] + " needs a value", false;
			value = args[++i];
		}
		if (spec == nullptr) { // --colour-superfaces: the output's, not the engine's
			if (!parseBool(value, o.colour))
				return error = flag + " needs true or false", false;
		} else if (!setFromText(*spec, args[valueGiven ? i : i - 1], value, o, error)) {
			return false;
		} else if (std::string(spec->name) == "maxLevel") {
			o.maxLevel = o.params.maxLevel;
			maxLevelGiven = true;
		}
	}
	return checkOptions(o, maxLevelGiven, error);
}

} // namespace cli
