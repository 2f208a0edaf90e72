// gausslod: the GaussLOD engine from the command line (no MeshLab needed).
//   gausslod [options] INPUT(.ply|.obj|.off|.stl) OUTDIR
//   gausslod --check [options] INPUT
//   gausslod batch [options] MANIFEST OUTDIR [--part K/N]      (batch.cpp)
// Writes OUTDIR/<name>_LOD<i>.<ext> per level (the input's format unless --format says another,
// with the input's attributes: level_files.h) and prints a per-level table (or JSON lines).
#include "cli.h"
#include "level_files.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <fstream>
#include <map>
#include <memory>
#include <new>
#include <sstream>
#include <string>
#include <sys/stat.h>
#include <unistd.h>

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

bool makeDirs(const std::string &dir)
{
	for (size_t i = 1; i <= dir.size(); ++i)
		if (i == dir.size() || dir[i] == '/') {
			const std::string part = dir.substr(0, i);
			if (mkdir(part.c_str(), 0777) != 0 && errno != EEXIST)
				return false;
		}
	struct stat st;
	return stat(dir.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

void setError(Outcome &out, int code, const char *kind, const std::string &message)
{
	out.code = code;
	out.kind = kind;
	out.message = message;
}

void setEngineError(Outcome &out, const gausslod::Result &res)
{
	switch (res.errorKind) {
		case gausslod::ErrorKind::BadParameter:
			return setError(out, kUsage, "bad_parameter", res.error);
		case gausslod::ErrorKind::BadInput: return setError(out, kUnusable, "bad_input", res.error);
		case gausslod::ErrorKind::OutOfMemory:
			return setError(out, kNoMemory, "out_of_memory", res.error);
		default: return setError(out, kFailed, "failed", res.error);
	}
}

// Reads `input` (flat arrays, and with attributes the VCG mesh its levels copy them from).
bool readInput(const std::string &input, const Options &o, InputMesh &in, gausslod::Params &p,
               Outcome &out)
{
	gausslod::ReadError error;
	if (!readInputMesh(input, o.params, in, error)) {
		const int code = error.status == gausslod::ReadStatus::CannotOpen ? kCannotOpen
		                 : error.status == gausslod::ReadStatus::TooLarge ? kNoMemory
		                                                                  : kUnreadable;
		setError(out, code, gausslod::readStatusName(error.status), error.message);
		return false;
	}
	out.inputFaces = in.flat.triangles.size() / 3;
	out.inputVertices = in.flat.positions.size() / 3;
	out.diagonal = gausslod::bboxDiagonal(in.flat.view());
	out.texCoords = !in.flat.cornerUV.empty();
	p = o.params;
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
				    "                         (up to 8) sets the number of levels; each level "
				    "keeps\n"
				    "                         its normal bound, so a budget may be out of reach\n"
				    "                         (the table's reached column says so)\n";
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

bool parseOptions(const std::vector<std::string> &given, Options &o,
                  std::vector<std::string> &positional, std::string &error)
{
	bool maxLevelGiven = false;
	// (a script's options stand where --from-mlx is: later ones win)
	std::vector<std::string> args;
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
	for (size_t i = 0; i < args.size(); ++i) {
		std::string flag = args[i], value;
		bool valueGiven = false;
		for (const auto &alias : kAliases)
			if (flag == alias[0]) {
				flag = alias[1];
				valueGiven = *alias[2] != 0;
				value = alias[2];
			}
		if (flag == "--json" || flag == "--overwrite-colours" || flag == "--lod-file" ||
		    flag == "--3dtiles" || flag == "--quiet") {
			(flag == "--json"       ? o.json
			 : flag == "--quiet"    ? o.quiet
			 : flag == "--lod-file" ? o.lodFile
			 : flag == "--3dtiles"  ? o.tiles
			                        : o.overwriteColours) = true;
			if (flag == "--lod-file" || flag == "--3dtiles")
				o.format = "glb";
			continue;
		}
		if (flag == "--tiles-transform") {
			if (i + 1 >= args.size())
				return error = "--tiles-transform needs 16 numbers", false;
			o.tilesTransform.clear();
			std::string v = args[++i];
			for (char &c : v)
				c = c == ',' ? ' ' : c;
			std::istringstream in(v);
			double x;
			while (in >> x)
				o.tilesTransform.push_back(x);
			if (o.tilesTransform.size() != 16 || !in.eof())
				return error = "--tiles-transform needs 16 numbers", false;
			for (const double t : o.tilesTransform)
				if (!std::isfinite(t))
					return error = "--tiles-transform needs 16 finite numbers", false;
			continue;
		}
		if (flag == "--format") {
			if (i + 1 >= args.size())
				return error = "--format needs a value", false;
			o.format = args[++i];
			for (char &c : o.format)
				c = char(std::tolower(static_cast<unsigned char>(c)));
			if (o.format == "glb" || o.format == "gltf")
				continue;
			if (gausslod::formatNamed(o.format) == gausslod::MeshFormat::Unknown)
				return error = "--format needs ply, obj, off, stl, glb or gltf", false;
			o.format = gausslod::formatExtension(gausslod::formatNamed(o.format));
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
	// levels by target: the number of targets is the number of levels
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

bool writeAtomically(const std::string &file, const std::string &text)
{
	const std::string tmp = file + ".part-" + std::to_string(getpid());
	bool ok;
	{
		std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
		out << text;
		ok = bool(out.flush());
	}
	ok = ok && std::rename(tmp.c_str(), file.c_str()) == 0;
	if (!ok)
		std::remove(tmp.c_str());
	return ok;
}

std::string repairsJson(const gausslod::InputStats &in)
{
	char buf[480];
	std::snprintf(
	    buf, sizeof buf,
	    "\"welded_vertices\":%zu,\"faces_reindexed\":%zu,"
	    "\"faces_skipped_repeated_vertex\":%zu,\"faces_skipped_duplicate\":%zu,"
	    "\"faces_kept_degenerate\":%zu,\"vertices_locked\":%zu,"
	    "\"coplanar_regions\":%zu,\"faces_after_coplanar\":%zu,\"coplanar_distance\":%.9g",
	    in.weldedVertices, in.facesReindexed, in.facesRepeatedVertex, in.facesDuplicate,
	    in.facesDegenerate, in.verticesLocked, in.coplanarRegions, in.facesAfterCoplanar,
	    in.coplanarDistance);
	return buf;
}

namespace {

// The level's JSON members "attributes" (carried), "superface_colours" and "max_tex_error".
std::string attributesJson(const Outcome &o, const gausslod::LevelStats &level)
{
	std::string s = "\"attributes\":[";
	for (size_t i = 0; i < o.attributes.size(); ++i)
		s += (i ? "," : "") + jsonString(o.attributes[i]);
	char err[32] = "null";
	if (level.maxTexError >= 0)
		std::snprintf(err, sizeof err, "%.6g", level.maxTexError);
	return s + "],\"superface_colours\":" + (o.superfaceColours ? "true" : "false") +
	       ",\"max_tex_error\":" + err;
}

// The level's JSON members of levels by target: the mode, the target (null in angle mode),
// whether it was reached, the tolerance used (% of the diagonal) and the builds it took.
std::string targetJson(const gausslod::Params &p, const gausslod::LevelStats &s)
{
	char faces[32] = "null", error[32] = "null", buf[320];
	if (!p.levelFaces.empty())
		std::snprintf(faces, sizeof faces, "%zu", s.targetFaces);
	if (s.targetDistance >= 0)
		std::snprintf(error, sizeof error, "%.6g", 100.0 * s.targetDistance);
	const char *mode = !p.levelFaces.empty()       ? "faces"
	                   : !p.levelDistances.empty() ? "error"
	                                               : "angle";
	char least[32] = "null", loops[32] = "null";
	if (!s.targetReached && s.targetFaces > 0) {
		if (s.leastFaces > 0)
			std::snprintf(least, sizeof least, "%zu", s.leastFaces);
		std::snprintf(loops, sizeof loops, "%zu", s.boundaryLoops);
	}
	std::snprintf(buf, sizeof buf,
	              "\"levels_by\":\"%s\",\"target_faces\":%s,\"target_error_pct\":%s,"
	              "\"target_reached\":%s,\"least_faces\":%s,\"boundary_loops\":%s,"
	              "\"tolerance_pct\":%.6g,\"trials\":%d",
	              mode, faces, error, s.targetReached ? "true" : "false", least, loops,
	              100.0 * s.tolerance, s.trials);
	return buf;
}

} // namespace

std::string levelJson(const gausslod::Params &p, const Outcome &o, size_t i)
{
	const gausslod::LevelStats &s = o.levels[i];
	// the proven distance bound, % of the diagonal and mesh units
	char dist[64] = "null,\"distance_bound\":null", buf[1200];
	if (s.distanceBound >= 0 && o.diagonal > 0)
		std::snprintf(dist, sizeof dist, "%.4f,\"distance_bound\":%.6g",
		              100.0 * s.distanceBound / o.diagonal, s.distanceBound);
	// vertex placement: how many output vertices moved, and the largest move (% and units)
	char placed[128];
	std::snprintf(placed, sizeof placed,
	              "\"placed_vertices\":%zu,\"max_placement_pct\":%.4f,\"max_placement\":%.6g,",
	              s.placedVertices, o.diagonal > 0 ? 100.0 * s.maxPlacement / o.diagonal : 0.0,
	              s.maxPlacement);
	std::snprintf(
	    buf, sizeof buf,
	    "{\"level\":%d,\"faces\":%zu,\"vertices\":%zu,\"superfaces\":%zu,"
	    "\"fallbacks\":%zu,\"retriangulated\":%zu,\"carried_superfaces\":%zu,"
	    "\"bound_deg\":%.4f,\"max_dev_deg\":%.4f,\"mean_dev_deg\":%.4f,"
	    "\"unmeasured_faces\":%zu,"
	    "\"seconds\":%.4f,\"seconds_partition\":%.4f,\"seconds_borders\":%.4f,"
	    "\"seconds_triangulation\":%.4f,\"seconds_checks\":%.4f,"
	    "\"seconds_placement\":%.4f,\"seconds_collapse\":%.4f,\"rounds\":%d,"
	    "\"collapses\":%zu,\"reduced\":%s,\"reused_finer\":%s,\"distance_bound_pct\":%s,%s",
	    s.level, s.faces, s.vertices, s.superfaces, s.fallbacks, s.retriangulated,
	    s.carriedSuperfaces, s.boundDeg, s.maxNormalDevDeg, s.meanNormalDevDeg, s.unmeasuredFaces,
	    s.seconds, s.secondsPartition, s.secondsBorders, s.secondsTriangulation, s.secondsChecks,
	    s.secondsPlacement, s.secondsCollapse, s.rounds, s.collapses, s.reduced ? "true" : "false",
	    s.reusedFiner ? "true" : "false", dist, placed);
	// (the texture limit the level was held to: its own, DESIGN 51, or the parameter's)
	char texLimit[64] = "null";
	if (s.maxTexError >= 0)
		std::snprintf(texLimit, sizeof texLimit, "%.6g",
		              s.texErrorLimit >= 0 ? s.texErrorLimit : p.maxTexError);
	// (DESIGN 52: the certified Hausdorff distance, upper and lower, % and mesh units)
	char haus[192] = "\"hausdorff_pct\":null,\"hausdorff\":null,\"hausdorff_lower\":null,";
	if (s.hausdorff >= 0 && o.diagonal > 0)
		std::snprintf(haus, sizeof haus,
		              "\"hausdorff_pct\":%.6f,\"hausdorff\":%.6g,\"hausdorff_lower\":%.6g,"
		              "\"hausdorff_converged\":%s,\"seconds_hausdorff\":%.4f,",
		              100.0 * s.hausdorff / o.diagonal, s.hausdorff, s.hausdorffLower,
		              s.hausdorffConverged ? "true" : "false", s.secondsHausdorff);
	std::string json = buf + std::string(haus) + repairsJson(s.input) + "," + attributesJson(o, s) +
	                   ",\"tex_error_limit\":" + texLimit + "," + targetJson(p, s) +
	                   ",\"file\":" + jsonString(o.files[i]);
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

namespace {

// Reads `input` and hands it to fn(input mesh, params, outcome); an allocation failure anywhere
// is the outcome's out-of-memory error.
template <class Fn>
Outcome withInput(const std::string &input, const Options &o, Fn fn)
{
	Outcome out;
	try {
		InputMesh in;
		gausslod::Params p;
		if (readInput(input, o, in, p, out)) {
			out.readNotes = in.readNotes;
			fn(in, p, out);
		}
	} catch (const std::bad_alloc &) {
		setError(out, kNoMemory, "out_of_memory", "out of memory");
	}
	return out;
}

} // namespace

Outcome checkOne(const std::string &input, const Options &o)
{
	using gausslod::Params;
	return withInput(input, o, [](const InputMesh &in, const Params &p, Outcome &out) {
		const gausslod::Result res = gausslod::checkInput(in.flat.view(), p);
		if (!res.ok)
			setEngineError(out, res);
		out.levels.emplace_back();
		out.levels.back().input = res.input;
	});
}

namespace {

// The distance a renderer may take for a level: its certified Hausdorff distance, else the
// construction's bound, else the input's diagonal (nothing proven).
double levelError(const gausslod::LevelStats &s, double diagonal)
{
	if (s.hausdorff >= 0 && std::isfinite(s.hausdorff))
		return s.hausdorff;
	if (s.distanceBound >= 0 && std::isfinite(s.distanceBound))
		return s.distanceBound;
	return diagonal;
}

// --lod-file and --3dtiles, once every level is written: the chain as one glb (MSFT_lod), and the
// input as the full-detail tile under the levels' tileset.
void writeChain(const InputMesh &in, const Options &o, const std::string &outdir,
                const std::string &stem, const LevelWriter &writer, Outcome &out,
                std::string &error)
{
	const std::vector<GltfMesh> &levels = writer.gltf(); // (finest first, as written)
	const size_t nLevels = levels.size();
	// the input as a level of its own: every face its own source
	gausslod::LevelMesh whole;
	const gausslod::FlatMesh &f = in.flat;
	whole.positions = f.positions;
	whole.triangles = f.triangles;
	const size_t nf = f.triangles.size() / 3;
	whole.sourceCorner.resize(3 * nf);
	whole.sourceFace.resize(nf);
	whole.superface.resize(nf);
	whole.borderEdges.assign(nf, 7);
	for (size_t i = 0; i < nf; ++i) {
		whole.sourceFace[i] = whole.superface[i] = int32_t(i);
		for (int k = 0; k < 3; ++k)
			whole.sourceCorner[3 * i + size_t(k)] = int32_t(3 * i + size_t(k));
	}
	whole.sourceVertex.resize(f.positions.size() / 3);
	for (size_t v = 0; v < whole.sourceVertex.size(); ++v)
		whole.sourceVertex[v] = int32_t(v);
	std::vector<std::string> files;
	size_t vertices = 0;
	if (!writer.writeNamed(whole, stem + "_full.glb", files, vertices, error))
		return;
	const GltfMesh &full = writer.gltf().back();
	const double diagonal = out.diagonal > 0 ? out.diagonal : 1.0;
	// errors from the finest level to the coarsest, never decreasing (a coarser level is not
	// shown where a finer one would not be)
	std::vector<double> errors;
	for (const gausslod::LevelStats &s : out.levels)
		errors.push_back(std::max(errors.empty() ? 0.0 : errors.back(), levelError(s, diagonal)));
	if (o.lodFile) {
		// MSFT_screencoverage: level i is shown while the object covers more of the screen's
		// height than the coverage at which the next coarser level's error is one pixel of a
		// 1080-pixel-high screen (the last: down to 0)
		std::vector<const GltfMesh *> meshes{&full};
		std::vector<double> coverage;
		for (size_t i = 0; i < nLevels && i < errors.size(); ++i) {
			meshes.push_back(&levels[i]);
			coverage.push_back(errors[i] > 0 ? std::min(1.0, diagonal / (errors[i] * 1080.0))
			                                 : 1.0);
		}
		coverage.push_back(0.0);
		const std::string file = outdir + "/" + stem + "_lods.glb",
		                  tmp = outdir + "/." + stem + "_lods.glb.part-" + std::to_string(getpid());
		std::string warning;
		if (!writeGlb(meshes, coverage, tmp, warning, error) ||
		    std::rename(tmp.c_str(), file.c_str()) != 0) {
			if (error.empty())
				error = "cannot write " + file + ": " + std::strerror(errno);
			std::remove(tmp.c_str());
			return;
		}
	}
	if (o.tiles) {
		std::vector<Tile> tiles;
		auto tile = [&](const std::string &file, double e, int level, size_t faces) {
			Tile t;
			t.lod = int(nLevels) - int(tiles.size()); // (the root is the coarsest)
			t.level = level;
			t.faces = faces;
			const size_t slash = file.rfind('/');
			t.content = slash == std::string::npos ? file : file.substr(slash + 1);
			t.error = e;
			// (a level's box grown by its distance: the input's box holds every level within it)
			for (int j = 0; j < 3; ++j)
				t.lo[j] = full.lo[j] - e, t.hi[j] = full.hi[j] + e;
			tiles.push_back(t);
		};
		for (size_t i = nLevels; i-- > 0;)
			if (i < out.files.size() && i < errors.size())
				tile(out.files[i], errors[i], out.levels[i].level, out.levels[i].faces);
		tile(files[0], 0.0, -1, out.inputFaces);
		const std::string file = outdir + "/" + o.tilesetName;
		if (!writeAtomically(file, tilesetJson(tiles, o.tilesTransform)))
			error = "cannot write " + file + ": " + std::strerror(errno);
	}
}

} // namespace

Outcome runOne(const std::string &input, const std::string &outdir, const std::string &stem,
               const Options &o, const LevelDone &done, const gausslod::Progress &progress)
{
	using gausslod::Params;
	return withInput(input, o, [&](const InputMesh &in, const Params &p, Outcome &out) {
#ifdef __GLIBC__
		// below 500k faces the freed arrays weigh more in the peak and are cheap to map (DESIGN.md)
		mallopt(M_MMAP_THRESHOLD, out.inputFaces < 500000 ? 256 << 10 : 4 << 20);
#endif
		std::string writeError;
		std::unique_ptr<LevelWriter> writer; // (made with the folder: texture names are from it)
		// each level is written as soon as it is built, then dropped (one level in memory at a
		// time)
		auto sink = [&](const gausslod::LevelMesh &lm) {
			if (!writer) {
				if (!makeDirs(outdir)) {
					writeError = "cannot create the output folder " + outdir;
					return false;
				}
				writer.reset(new LevelWriter(in, o, outdir));
				if (o.lodFile || o.tiles)
					writer->keepGltf();
				out.format = writer->extension();
				out.attributes = writer->attributes();
				out.superfaceColours = writer->superfaceColours();
			}
			std::vector<std::string> files;
			gausslod::LevelStats stats = lm.stats;
			if (!writer->write(lm, stem, files, stats.vertices, writeError))
				return false;
			out.levels.push_back(stats);
			out.files.push_back(files[0]);
			out.materialFiles.push_back(files.size() > 1 ? files[1] : std::string());
			if (done)
				done(out, stats, files[0]);
			return true;
		};
		const gausslod::Result res = gausslod::buildLevels(in.flat.view(), p, progress, sink);
		out.seconds = res.totalSeconds;
		if (res.ok && writeError.empty() && writer && (o.lodFile || o.tiles))
			writeChain(in, o, outdir, stem, *writer, out, writeError);
		if (!writeError.empty())
			setError(out, kCannotWrite, "write_failed", writeError);
		else if (!res.ok)
			setEngineError(out, res);
	});
}

} // namespace cli

namespace {

void usage()
{
	std::fprintf(
	    stderr,
	    "usage: gausslod [options] INPUT OUTDIR\n"
	    "       gausslod --check [options] INPUT\n"
	    "       gausslod batch [options] MANIFEST OUTDIR [--part K/N]\n"
	    "  INPUT: .ply .obj .off .stl triangle mesh; OUTDIR: created if missing\n"
	    "  Each level is OUTDIR/<name>_LOD<i>.<ext> in INPUT's format unless --format says\n"
	    "  another (OBJ with its <name>_LOD<i>.obj.mtl), with what INPUT carries as far as the\n"
	    "  format holds it: vertex colours and quality, texture coordinates (per vertex or\n"
	    "  per face corner), texture files, materials and face colours, vertex normals\n"
	    "  (recomputed). Texture names relative to INPUT's folder are rewritten relative to\n"
	    "  OUTDIR (images are not copied). Faces are coloured by superface only if INPUT has\n"
	    "  no colour and no texture coordinates (--overwrite-colours: always; --no-colour:\n"
	    "  never). Materials, texture seams and colour changes are borders no level\n"
	    "  crosses (--keep-materials, --keep-seams); --max-tex-error bounds how far texture\n"
	    "  coordinates move (the table's texerr column, UV units).\n"
	    "  --check: read and check INPUT only (no level is built), same messages and codes\n"
	    "  batch: one input per MANIFEST line (path, then options); see the README\n"
	    "%s"
	    "exit codes: 0 ok, 1 failed, 2 bad usage or parameter, 3 cannot open the input,\n"
	    "  4 not a readable mesh file, 5 nothing to simplify (no faces, bad coordinates),\n"
	    "  6 not enough memory, 7 cannot write the output\n",
	    cli::optionHelp());
}

// The table's columns of levels by target: the level's target, whether it was reached and the
// distance tolerance it was built with (% of the diagonal).
std::string targetColumns(const gausslod::LevelStats &s)
{
	char buf[96];
	if (s.targetFaces > 0 || s.targetDistance < 0)
		std::snprintf(buf, sizeof buf, " %10zu", s.targetFaces);
	else
		std::snprintf(buf, sizeof buf, " %9.4f%%", 100.0 * s.targetDistance);
	const size_t n = std::strlen(buf);
	std::snprintf(buf + n, sizeof buf - n, " %7s %9.4f %6d", s.targetReached ? "yes" : "NO",
	              100.0 * s.tolerance, s.trials);
	return buf;
}

std::string tableRow(const char *label, const gausslod::LevelStats &s, double diag, bool distance,
                     bool texture)
{
	char buf[256], dist[64] = "";
	if (distance && s.distanceBound >= 0 && diag > 0)
		std::snprintf(dist, sizeof dist, " %9zu  %9.4f", s.placedVertices,
		              100.0 * s.distanceBound / diag);
	else if (distance)
		std::snprintf(dist, sizeof dist, " %9zu  %9s", s.placedVertices, "null");
	if (texture) {
		const size_t n = std::strlen(dist);
		if (s.maxTexError >= 0)
			std::snprintf(dist + n, sizeof dist - n, " %10.6f", s.maxTexError);
		else
			std::snprintf(dist + n, sizeof dist - n, " %10s", "-");
	}
	// (a level continued by collapses, DESIGN 51, is not held to its cells' bound: "-")
	char bound[16] = "-";
	if (!s.reduced)
		std::snprintf(bound, sizeof bound, "%.2f", s.boundDeg);
	std::snprintf(buf, sizeof buf, "%-6s %9zu %9zu %10zu %9zu %9s %9.2f %9.3f %8.3f%s", label,
	              s.faces, s.vertices, s.superfaces, s.fallbacks, bound, s.maxNormalDevDeg,
	              s.meanNormalDevDeg, s.seconds, dist);
	return buf;
}

} // namespace

int main(int argc, char **argv)
{
#ifdef __GLIBC__
	// glibc raises its mmap threshold to the size of the largest block freed so far, after which
	// arrays of a few MB freed between rounds and levels stay in the process: a fixed threshold
	// gives them back (DESIGN.md, decision 11).
	mallopt(M_MMAP_THRESHOLD, 4 << 20);
#endif
	std::vector<std::string> args(argv + 1, argv + argc);
	if (!args.empty() && args[0] == "batch")
		return cli::batchMain(std::vector<std::string>(args.begin() + 1, args.end()));
	bool check = false;
	for (size_t i = 0; i < args.size(); ++i) {
		if (args[i] == "-h" || args[i] == "--help") {
			usage();
			return 0;
		}
		if (args[i] == "--check") {
			check = true;
			args.erase(args.begin() + long(i--));
		}
	}
	cli::Options o;
	std::vector<std::string> positional;
	std::string error;
	if (!cli::parseOptions(args, o, positional, error)) {
		std::fprintf(stderr, "gausslod: %s\n", error.c_str());
		usage();
		return cli::kUsage;
	}
	if (positional.size() != (check ? 1u : 2u)) {
		usage();
		return cli::kUsage;
	}
	const std::string &input = positional[0];
	if (check) {
		const cli::Outcome out = cli::checkOne(input, o);
		if (out.code != cli::kOk) {
			std::fprintf(stderr, "gausslod: %s: %s\n", input.c_str(), out.message.c_str());
			return out.code;
		}
		const std::string repairs = cli::repairsText(out.levels[0].input, out.readNotes);
		std::printf("%s: ok: %zu faces, %zu vertices%s%s\n", input.c_str(), out.inputFaces,
		            out.inputVertices, repairs.empty() ? "" : "; ", repairs.c_str());
		return 0;
	}
	const std::string &outdir = positional[1];
	std::string stem = input.substr(input.find_last_of('/') + 1);
	stem = stem.substr(0, stem.find_last_of('.'));
	const bool targets = !o.params.levelFaces.empty() || !o.params.levelDistances.empty();
	const bool distance = o.params.maxDistance > 0 || targets;
	auto done = [&](const cli::Outcome &sofar, const gausslod::LevelStats &s, const std::string &) {
		const bool texture = sofar.texCoords;
		if (sofar.files.size() == 1 && !o.json) {
			const std::string repairs = cli::repairsText(s.input, sofar.readNotes);
			if (!repairs.empty())
				std::printf("input repairs: %s\n", repairs.c_str());
			if (s.input.coplanarRegions)
				std::printf("coplanar regions: %zu, re-triangulated first (%zu faces -> %zu, "
				            "within %.3g of the input)\n",
				            s.input.coplanarRegions, sofar.inputFaces, s.input.facesAfterCoplanar,
				            s.input.coplanarDistance);
			std::string carried;
			for (const std::string &a : sofar.attributes)
				carried += (carried.empty() ? "" : " ") + a;
			if (!carried.empty())
				std::printf("attributes carried: %s\n", carried.c_str());
			if (targets)
				std::printf("levels by %s\n", gausslod::levelsByText(o.params).c_str());
			std::printf(
			    "%-6s %9s %9s %10s %9s %9s %9s %9s %8s%s%s%s%s%s\n", "level", "faces", "vertices",
			    "superfaces", "fallback", "bound", "maxdev", "meandev", "seconds",
			    distance ? "    placed distbound%" : "", texture ? "     texerr" : "",
			    targets ? (o.params.levelFaces.empty() ? "    target%" : "     target") : "",
			    targets ? " reached      tol% trials" : "",
			    o.params.certifyDistance ? " hausdorff%" : "");
			std::printf("%-6s %9zu %9zu %10s %9s %9s %9s %9s %8s%s%s\n", "input", sofar.inputFaces,
			            sofar.inputVertices, "-", "-", "-", "-", "-", "-",
			            distance ? "         -          -" : "", texture ? "          -" : "");
		}
		if (o.json) { // (s is sofar's last level, file its file)
			std::printf("%s\n", cli::levelJson(o.params, sofar, sofar.levels.size() - 1).c_str());
		} else {
			const std::string label = "LOD" + std::to_string(s.level);
			char haus[32] = "";
			if (o.params.certifyDistance && s.hausdorff >= 0 && sofar.diagonal > 0)
				std::snprintf(haus, sizeof haus, " %10.4f", 100.0 * s.hausdorff / sofar.diagonal);
			else if (o.params.certifyDistance)
				std::snprintf(haus, sizeof haus, " %10s", "-");
			std::printf("%s%s%s\n",
			            tableRow(label.c_str(), s, sofar.diagonal, distance, texture).c_str(),
			            targets ? targetColumns(s).c_str() : "", haus);
		}
		std::fflush(stdout);
	};
	// a progress line on a terminal (stderr, rewritten in place; cleared before each table row),
	// and Ctrl-C: the engine stops at its next step, the levels already written stay (each is
	// renamed into place only once complete), nothing half-written remains; a second Ctrl-C quits
	static volatile std::sig_atomic_t interrupted = 0;
	std::signal(SIGINT, [](int) {
		interrupted = 1;
		std::signal(SIGINT, SIG_DFL);
	});
	const bool showProgress = !o.quiet && !o.json && isatty(STDOUT_FILENO) && isatty(STDERR_FILENO);
	int shownPercent = -1;
	std::string shownStage;
	auto clearProgress = [&]() {
		if (shownPercent >= 0)
			std::fprintf(stderr, "\r\033[K");
		shownPercent = -1;
	};
	auto progress = [&](double fraction, const char *stage) {
		if (showProgress) {
			const int percent = int(100 * std::min(1.0, std::max(0.0, fraction)));
			if (percent != shownPercent || shownStage != stage) {
				std::fprintf(stderr, "\r\033[K%3d %%  %s", percent, stage);
				std::fflush(stderr);
				shownPercent = percent, shownStage = stage;
			}
		}
		return interrupted == 0;
	};
	auto row = [&](const cli::Outcome &sofar, const gausslod::LevelStats &s, const std::string &f) {
		clearProgress();
		done(sofar, s, f);
	};
	const cli::Outcome out = cli::runOne(input, outdir, stem, o, row, progress);
	clearProgress();
	if (interrupted) {
		cli::removeLevelParts(outdir, stem);
		std::fprintf(stderr,
		             "gausslod: interrupted: %zu level%s written, each complete; no "
		             "partial file left\n",
		             out.files.size(), out.files.size() == 1 ? "" : "s");
		return 130;
	}
	if (out.code != cli::kOk) {
		std::fprintf(stderr, "gausslod: %s: %s\n", input.c_str(), out.message.c_str());
		return out.code;
	}
	if (!o.json) {
		std::string made, reduced; // (DESIGN 50, 51)
		for (const gausslod::LevelStats &l : out.levels) {
			std::string &list = l.reduced ? reduced : made;
			if (l.collapses > 0)
				list += (list.empty() ? "" : ", ") + ("LOD" + std::to_string(l.level));
		}
		if (!made.empty())
			std::printf(
			    "%s: made from the finer level by edge collapses, at the superface level's "
			    "face count within its distance bound (maxdev: a bound; meandev: an estimate)\n",
			    made.c_str());
		if (!reduced.empty())
			std::printf(
			    "%s: continued by edge collapses with quadric placement to %s (maxdev, "
			    "meandev: measured, each input face against the level's nearest triangle)\n",
			    reduced.c_str(), targets ? "the level's target" : "a real step (--complete-chain)");
		for (const gausslod::LevelStats &l : out.levels) {
			const std::string note = gausslod::budgetNote(l);
			if (!note.empty())
				std::printf("LOD%d: %zu faces for a budget of %zu: %s\n", l.level, l.faces,
				            l.targetFaces, note.c_str());
		}
		std::printf("total %.3f s; files in %s\n", out.seconds, outdir.c_str());
	}
	return 0;
}
