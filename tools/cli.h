// The gausslod tool's pieces shared by its two modes, one file (gausslod_cli.cpp) and a manifest
// of files (batch.cpp): options, reading, running the engine, writing levels atomically.
#pragma once

#include "gausslod/gausslod.h"

#include <functional>
#include <string>
#include <vector>

namespace cli {

/// Exit codes (README, "Accepted input and errors").
enum Exit {
	kOk = 0,
	kFailed = 1,      ///< the engine failed (internal error); batch: some input failed
	kUsage = 2,       ///< bad command line or parameter value
	kCannotOpen = 3,  ///< the input is missing, not a file, or not readable
	kUnreadable = 4,  ///< not a mesh file we can read: empty, wrong format, truncated, corrupt
	kUnusable = 5,    ///< read, but nothing to simplify: no faces, bad coordinates, all degenerate
	kNoMemory = 6,    ///< the file needs more memory than there is
	kCannotWrite = 7, ///< an output file could not be written
};

struct Options {
	gausslod::Params params;                    ///< the engine's (--kebab-case of their names)
	std::string outputLevels = "all";           ///< the text form of params.outputLevels
	std::string levelsBy = "angle";             ///< --levels-by: the text form of the targets
	int maxLevel = gausslod::Params{}.maxLevel; ///< --max-level (the levels by angle)
	bool colour = true;            ///< --colour-superfaces (only where the input has no colour)
	bool overwriteColours = false; ///< --overwrite-colours: superface colours replace the input's
	std::string format;            ///< --format ply|obj|off|stl|glb; "" = the input's
	bool lodFile = false;          ///< --lod-file: the chain as one glb with MSFT_lod
	bool tiles = false;            ///< --3dtiles: a 3D Tiles tileset of glb levels
	std::vector<double> tilesTransform;       ///< --tiles-transform: the root's (16, column major)
	std::string tilesetName = "tileset.json"; ///< --3dtiles: OUTDIR/<this> (batch: per input)
	bool json = false;
	bool quiet = false; ///< --quiet: no progress line on a terminal
};

/// Parses option tokens into `o` (later tokens override earlier ones) and checks the values with
/// the engine's validateParams(); tokens that are not options go to `positional`. False with
/// `error` set on a bad option or value.
bool parseOptions(const std::vector<std::string> &args, Options &o,
                  std::vector<std::string> &positional, std::string &error);
/// The option summary of the usage text.
const char *optionHelp();

/// One input's outcome.
struct Outcome {
	int code = kOk;
	std::string kind = "ok"; ///< ok, or the error's kind (cannot_open, corrupt, bad_input, ...)
	std::string message;     ///< one line, without the file name
	size_t inputFaces = 0, inputVertices = 0;
	double diagonal = 0;                      ///< of the input's bounding box
	std::vector<gausslod::LevelStats> levels; ///< (vertices: the file's)
	std::vector<std::string> files;           ///< the level files, one per level
	std::vector<std::string> materialFiles;   ///< per level: its OBJ material file, or ""
	std::string format;                       ///< of the level files (ply, obj, off, stl)
	std::vector<std::string> attributes;      ///< the input's attributes the files carry
	std::vector<std::string> readNotes;       ///< what the reader skipped (input repairs)
	bool superfaceColours = false;            ///< faces coloured by superface
	bool texCoords = false;                   ///< the input has texture coordinates (texture
	                                          ///< error measured)
	double seconds = 0;
};

/// Called for each level once its file is in place (file = its final name).
using LevelDone = std::function<void(const Outcome &sofar, const gausslod::LevelStats &,
                                     const std::string &file)>;

/// Reads `input`, builds its levels and writes OUTDIR/<stem>_LOD<i>.<ext> for each requested
/// level (ext: --format, else the input's; OBJ with its <name>.mtl) with the attributes the input
/// carries (level_files.h): each written under a temporary name in OUTDIR and renamed, so that
/// no half-written level ever carries the final name. OUTDIR is created (with its parents) if
/// missing.
/// `progress`: the engine's (return false to cancel: the levels written so far stay, complete).
Outcome runOne(const std::string &input, const std::string &outdir, const std::string &stem,
               const Options &o, const LevelDone &done, const gausslod::Progress &progress = {});

/// Reads and checks `input` as runOne does, without building levels.
Outcome checkOne(const std::string &input, const Options &o);

/// Writes `text` as `file`: into FILE.part-<pid> first, then renamed (false if either failed; the
/// temporary is removed).
bool writeAtomically(const std::string &file, const std::string &text);

/// `s` as a JSON string literal (quotes included).
std::string jsonString(const std::string &s);
/// The input repairs as JSON members (no braces), and as one line of text ("" if none).
std::string repairsJson(const gausslod::InputStats &in);
std::string repairsText(const gausslod::InputStats &in,
                        const std::vector<std::string> &readNotes = {});

/// One level's JSON object: `gausslod --json` prints one per line, and batch records list them
/// (one function, so that the two never differ): the level's figures, its distance bound, the
/// input repairs, the attributes carried, its target (levels by faces or error; `p` says the
/// mode), its file and its OBJ material file if any. `i` indexes o.levels, o.files and
/// o.materialFiles.
std::string levelJson(const gausslod::Params &p, const Outcome &o, size_t i);
/// Removes what a killed run left of OUTDIR/<stem>_LOD* (temporary files and folders).
void removeLevelParts(const std::string &outdir, const std::string &stem);

/// `gausslod batch ...` (args after the word batch).
int batchMain(const std::vector<std::string> &args);

} // namespace cli
