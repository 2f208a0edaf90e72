// gausslod batch [options] MANIFEST OUTDIR [--part K/N]
//
// One input per manifest line: a path (relative paths from the manifest's folder; "double
// quotes" for blanks), then options for that input only (after the command line's options).
// Blank lines and lines starting with # are skipped. Levels go to OUTDIR/<path without its
// extension>_LOD<i>.<ext> (the path as written, ".." as "__", a leading / dropped; ext the
// input's or --format's, OBJ with its .mtl; --lod-file, --3dtiles: also _lods.glb, _full.glb and
// <path without its extension>_tileset.json), and a record of the outcome to OUTDIR/<path
// without its extension>.gausslod.json.
//
// Idempotent: an input whose record says ok for the same file (size, time) and options is not
// redone (its record is printed again, "cached": true); level files are written under a
// temporary name and renamed, and the record is written last, so that a killed run leaves no
// half file under a final name and its unfinished input is redone next time. --part K/N takes
// the manifest's data lines i with i % N == K (for GNU parallel and Slurm array jobs): every
// part reads the whole manifest, so output names are checked for clashes the same way in all.
// Prints one JSON line per input; exit 0 if every input of the part is ok, 1 if any failed.
#include "cli.h"

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <dirent.h>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <sys/stat.h>
#include <unistd.h>

namespace cli {

namespace {

struct Line {
	size_t number = 0;            ///< in the manifest file, from 1
	std::vector<std::string> tok; ///< path, then options
	std::string error;            ///< a quoting error
};

// Splits on blanks; "..." groups (no escapes inside).
Line tokenize(const std::string &text, size_t number)
{
	Line l;
	l.number = number;
	std::string cur;
	bool in = false, quoted = false;
	for (const char c : text) {
		if (quoted) {
			if (c == '"')
				quoted = false;
			else
				cur += c;
		} else if (c == '"') {
			quoted = in = true;
		} else if (c == ' ' || c == '\t' || c == '\r') {
			if (in)
				l.tok.push_back(cur), cur.clear();
			in = false;
		} else {
			cur += c, in = true;
		}
	}
	if (quoted)
		l.error = "a \" is not closed";
	if (in)
		l.tok.push_back(cur);
	return l;
}

// The output path of an input (without _LOD<i>.<ext>): its path as written, extension dropped.
std::string outputStem(const std::string &path)
{
	std::string out;
	size_t i = 0;
	while (i < path.size()) {
		size_t j = path.find('/', i);
		if (j == std::string::npos)
			j = path.size();
		const std::string part = path.substr(i, j - i);
		if (!part.empty() && part != ".")
			out += (out.empty() ? "" : "/") + (part == ".." ? std::string("__") : part);
		i = j + 1;
	}
	const size_t slash = out.find_last_of('/'), dot = out.find_last_of('.');
	if (dot != std::string::npos && (slash == std::string::npos || dot > slash) && dot > 0 &&
	    dot != slash + 1)
		out.erase(dot);
	return out;
}

std::string readFile(const std::string &file)
{
	std::ifstream in(file, std::ios::binary);
	std::ostringstream s;
	s << in.rdbuf();
	return s.str();
}

// Removes what a killed run left of `stem`: OUTDIR/<dir>/.<name>_LOD*.part-* (files, and the
// folders OBJ levels are written in) and the record's.
void removeParts(const std::string &stemPath)
{
	const size_t slash = stemPath.find_last_of('/');
	const std::string dir = stemPath.substr(0, slash), name = stemPath.substr(slash + 1);
	removeLevelParts(dir, name);
	DIR *d = opendir(dir.c_str());
	if (!d)
		return;
	const std::string record = name + ".gausslod.json.part-";
	std::vector<std::string> found;
	while (const dirent *e = readdir(d)) {
		const std::string n = e->d_name;
		if (n.compare(0, record.size(), record) == 0)
			found.push_back(n);
	}
	closedir(d);
	for (const std::string &n : found)
		std::remove((dir + "/" + n).c_str());
}

// Each level as `gausslod --json` prints it (levelJson), targets included.
std::string levelsJson(const gausslod::Params &p, const Outcome &o)
{
	std::string s = "[";
	for (size_t i = 0; i < o.levels.size(); ++i)
		s += (i ? "," : "") + levelJson(p, o, i);
	return s + "]";
}

std::string resultJson(const Line &l, const std::string &input, const gausslod::Params &p,
                       const Outcome &o, const std::string &signature)
{
	char buf[200];
	std::string s = "{\"line\":" + std::to_string(l.number) + ",\"input\":" + jsonString(input) +
	                ",\"status\":" + (o.code == kOk ? "\"ok\"" : "\"error\"") +
	                ",\"code\":" + std::to_string(o.code) + ",\"kind\":" + jsonString(o.kind);
	if (o.code != kOk)
		return s + ",\"message\":" + jsonString(o.message) + ",\"cached\":false}";
	std::snprintf(buf, sizeof buf, ",\"faces\":%zu,\"vertices\":%zu,\"seconds\":%.4f,",
	              o.inputFaces, o.inputVertices, o.seconds);
	s += buf;
	if (!o.levels.empty())
		s += repairsJson(o.levels[0].input) + ",";
	s += "\"format\":" + jsonString(o.format) + ",\"attributes\":[";
	for (size_t i = 0; i < o.attributes.size(); ++i)
		s += (i ? "," : "") + jsonString(o.attributes[i]);
	s += std::string("],\"superface_colours\":") + (o.superfaceColours ? "true" : "false") + ",";
	return s + "\"levels\":" + levelsJson(p, o) + ",\"signature\":" + jsonString(signature) +
	       ",\"cached\":false}";
}

// The record's layout, in its signature: a record of an earlier layout (before 2, levels without
// their --json members) is redone, not printed again as it was.
const char *const kRecordLayout = "record=2";

// Every option value that changes the files (not threads: the output does not depend on it).
std::string optionsKey(const Options &o)
{
	std::string key =
	    std::string(kRecordLayout) + " out=" + o.outputLevels +
	    " by=" + gausslod::levelsByText(o.params) + " colour=" + std::to_string(int(o.colour)) +
	    " overwrite=" + std::to_string(int(o.overwriteColours)) +
	    " format=" + (o.format.empty() ? "input" : o.format) +
	    " lodfile=" + std::to_string(int(o.lodFile)) + " tiles=" + std::to_string(int(o.tiles));
	char buf[64];
	for (const double t : o.tilesTransform) {
		std::snprintf(buf, sizeof buf, " %.17g", t);
		key += buf;
	}
	for (const gausslod::ParamSpec &s : gausslod::paramSpecs())
		if (s.kind != gausslod::ParamKind::LevelList && std::string(s.name) != "threads") {
			std::snprintf(buf, sizeof buf, " %s=%.17g", s.name, gausslod::getParam(o.params, s));
			key += buf;
		}
	return key;
}

int batchUsage(const std::string &why)
{
	std::fprintf(stderr,
	             "gausslod batch: %s\nusage: gausslod batch [options] MANIFEST OUTDIR "
	             "[--part K/N]\n",
	             why.c_str());
	return kUsage;
}

// Takes --part K/N out of `in` (the rest goes to `args`); "" or why it is wrong.
std::string takePart(const std::vector<std::string> &in, std::vector<std::string> &args,
                     size_t &part, size_t &parts)
{
	for (size_t i = 0; i < in.size(); ++i) {
		if (in[i] != "--part") {
			args.push_back(in[i]);
			continue;
		}
		unsigned long k = 0, n = 0;
		char extra = 0;
		if (i + 1 >= in.size() ||
		    std::sscanf(in[i + 1].c_str(), "%lu/%lu%c", &k, &n, &extra) != 2 || n == 0 || k >= n)
			return "--part needs K/N with 0 <= K < N";
		part = k, parts = n, ++i;
	}
	return "";
}

// The manifest's data lines (and the lines with a quoting error).
std::vector<Line> readManifest(std::istream &in)
{
	std::vector<Line> lines;
	std::string text;
	for (size_t number = 1; std::getline(in, text); ++number) {
		Line l = tokenize(text, number);
		if (l.error.empty() && (l.tok.empty() || l.tok[0][0] == '#'))
			continue;
		lines.push_back(std::move(l));
	}
	return lines;
}

// One run over a manifest's part: the options of the command line, where the outputs go, and
// the counts of its inputs.
struct BatchRun {
	Options global;
	std::string base;   ///< the manifest's folder (relative paths are from it), with its /
	std::string outdir; ///< OUTDIR
	size_t ok = 0, cached = 0, failed = 0;

	/// Runs manifest line `l` (output `stem`; `unique` false if an earlier line has it) and prints
	/// its record: the record written before if it is of the same file and options.
	void runLine(const Line &l, const std::string &stem, bool unique, size_t firstLine);
};

void BatchRun::runLine(const Line &l, const std::string &stem, bool unique, size_t firstLine)
{
	const std::string path = l.tok.empty() ? "" : l.tok[0];
	const std::string input = !path.empty() && path[0] == '/' ? path : base + path;
	Outcome out;
	Options o = global;
	std::vector<std::string> extra;
	std::vector<std::string> lineArgs(l.tok.size() > 1 ? l.tok.begin() + 1 : l.tok.end(),
	                                  l.tok.end());
	std::string error;
	if (!l.error.empty())
		out.code = kUsage, out.kind = "bad_line", out.message = l.error;
	else if (stem.empty())
		out.code = kUsage, out.kind = "bad_line", out.message = "no input file name";
	else if (!unique)
		out.code = kUsage, out.kind = "bad_line",
		out.message =
		    "its output name " + stem + " is line " + std::to_string(firstLine) + "'s too";
	else if (!parseOptions(lineArgs, o, extra, error) || !extra.empty())
		out.code = kUsage, out.kind = "bad_line",
		out.message = extra.empty() ? error : "unexpected argument " + extra[0];
	const std::string stemPath = outdir + "/" + stem, record = stemPath + ".gausslod.json";
	std::string signature;
	struct stat st;
	if (out.code == kOk && stat(input.c_str(), &st) == 0) {
		signature = std::to_string(st.st_size) + ":" + std::to_string(st.st_mtim.tv_sec) + "." +
		            std::to_string(st.st_mtim.tv_nsec) + ":" + optionsKey(o);
		const std::string previous = readFile(record);
		if (previous.find("\"status\":\"ok\"") != std::string::npos &&
		    previous.find("\"signature\":" + jsonString(signature)) != std::string::npos) {
			std::string again = previous.substr(0, previous.find_last_not_of("\n") + 1);
			again.replace(again.rfind("\"cached\":false"), 14, "\"cached\":true");
			std::printf("%s\n", again.c_str());
			std::fflush(stdout);
			++ok, ++cached;
			return;
		}
	}
	if (out.code == kOk) {
		const size_t cut = stemPath.find_last_of('/');
		removeParts(stemPath);
		// (inputs may share a folder: each tileset is named after its input)
		o.tilesetName = stemPath.substr(cut + 1) + "_tileset.json";
		out = runOne(input, stemPath.substr(0, cut), stemPath.substr(cut + 1), o, {});
	}
	const std::string json = resultJson(l, path, o.params, out, signature);
	if (out.code == kOk && !writeAtomically(record, json + "\n"))
		out.code = kCannotWrite, out.kind = "write_failed",
		out.message = "cannot write " + record + ": " + std::strerror(errno);
	std::printf("%s\n",
	            out.code == kOk ? json.c_str() : resultJson(l, path, o.params, out, "").c_str());
	std::fflush(stdout);
	(out.code == kOk ? ok : failed) += 1;
}

} // namespace

int batchMain(const std::vector<std::string> &argsIn)
{
	std::vector<std::string> args;
	size_t part = 0, parts = 1;
	const std::string partError = takePart(argsIn, args, part, parts);
	if (!partError.empty())
		return batchUsage(partError);
	BatchRun run;
	std::vector<std::string> positional;
	std::string error;
	if (!parseOptions(args, run.global, positional, error))
		return batchUsage(error);
	if (positional.size() != 2)
		return batchUsage("needs MANIFEST and OUTDIR");
	const std::string manifest = positional[0];
	run.outdir = positional[1];
	std::ifstream in(manifest);
	if (!in) {
		std::fprintf(stderr, "gausslod batch: cannot open the manifest %s\n", manifest.c_str());
		return kCannotOpen;
	}
	const size_t slash = manifest.find_last_of('/');
	run.base = slash == std::string::npos ? "" : manifest.substr(0, slash + 1);
	const std::vector<Line> lines = readManifest(in);
	std::map<std::string, size_t> firstLine; // output stem -> manifest line (the whole manifest)
	const auto t0 = std::chrono::steady_clock::now();
	for (size_t i = 0; i < lines.size(); ++i) {
		const Line &l = lines[i];
		const std::string stem = outputStem(l.tok.empty() ? "" : l.tok[0]);
		const auto first = firstLine.emplace(stem, l.number);
		if (i % parts == part)
			run.runLine(l, stem, first.second, first.first->second);
	}
	const double secs =
	    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
	std::fprintf(stderr,
	             "gausslod batch: part %zu/%zu: %zu ok (%zu already done), %zu failed, %.2f s\n",
	             part, parts, run.ok, run.cached, run.failed, secs);
	return run.failed ? kFailed : kOk;
}

} // namespace cli
