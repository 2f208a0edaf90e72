// gausslod: the GaussLOD engine from the command line (no MeshLab needed).
//   gausslod [options] INPUT(.ply|.obj|.off|.stl) OUTDIR
//   gausslod --check [options] INPUT
//   gausslod batch [options] MANIFEST OUTDIR [--part K/N]      (batch.cpp)
// Writes OUTDIR/<name>_LOD<i>.<ext> per level (the input's format unless --format says another,
// with the input's attributes: level_files.h) and prints a per-level table (or JSON lines).
// The pieces: options.cpp (options), run.cpp (reading, building, writing), records.cpp (JSON
// lines), batch.cpp; a level's figures are gausslod/level_figures.h's.
#include "cli.h"

#include "gausslod/level_figures.h"

#include <algorithm>
#include <csignal>
#include <cstdio>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <string>
#include <unistd.h>

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

// The table's columns in this run (ColumnShown bits): by distance with a tolerance or targets,
// texture error where the input has texture coordinates.
unsigned shownColumns(const gausslod::Params &p, bool texture)
{
	using gausslod::ColumnShown;
	const bool targets = !p.levelFaces.empty() || !p.levelDistances.empty();
	auto bit = [](ColumnShown c) { return 1u << unsigned(c); };
	return bit(ColumnShown::Always) |
	       (p.maxDistance > 0 || targets ? bit(ColumnShown::Distance) : 0) |
	       (texture ? bit(ColumnShown::Texture) : 0) | (targets ? bit(ColumnShown::Target) : 0) |
	       (p.certifyDistance ? bit(ColumnShown::Certified) : 0);
}

// What the table's first level says of the input: its repairs, its coplanar regions, the
// attributes carried, the targets; then the table's header and the input's row.
void printTableHead(const cli::Options &o, const cli::Outcome &sofar, const gausslod::LevelStats &s)
{
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
	const bool targets = !o.params.levelFaces.empty() || !o.params.levelDistances.empty();
	if (targets)
		std::printf("levels by %s\n", gausslod::levelsByText(o.params).c_str());
	const unsigned shown = shownColumns(o.params, sofar.texCoords);
	std::string header;
	const std::vector<gausslod::LevelFigure> figures =
	    gausslod::levelFigures(s, sofar.diagonal, o.params); // (the columns point into it)
	for (const gausslod::LevelFigure *f : gausslod::tableColumns(figures, shown))
		header += f->header;
	std::printf("%s\n", header.c_str());
	const bool distance = shown & (1u << unsigned(gausslod::ColumnShown::Distance));
	std::printf("%-6s %9zu %9zu %10s %9s %9s %9s %9s %8s%s%s\n", "input", sofar.inputFaces,
	            sofar.inputVertices, "-", "-", "-", "-", "-", "-",
	            distance ? "         -          -" : "", sofar.texCoords ? "          -" : "");
}

// Prints the level just written (the last of `sofar`): its table row (after the table's head
// for the first) or its JSON line.
void printLevel(const cli::Options &o, const cli::Outcome &sofar, const gausslod::LevelStats &s)
{
	if (o.json) {
		std::printf("%s\n", cli::levelJson(o.params, sofar, sofar.levels.size() - 1).c_str());
	} else {
		if (sofar.files.size() == 1)
			printTableHead(o, sofar, s);
		std::string row;
		const std::vector<gausslod::LevelFigure> figures =
		    gausslod::levelFigures(s, sofar.diagonal, o.params); // (the columns point into it)
		for (const gausslod::LevelFigure *f :
		     gausslod::tableColumns(figures, shownColumns(o.params, sofar.texCoords)))
			row += f->cell;
		std::printf("%s\n", row.c_str());
	}
	std::fflush(stdout);
}

// The lines under the table: the levels made by edge collapses (DESIGN 50, 51), the budgets not
// reached and why, the total time.
void printTableNotes(const cli::Options &o, const cli::Outcome &out, const std::string &outdir)
{
	const bool targets = !o.params.levelFaces.empty() || !o.params.levelDistances.empty();
	std::string made, reduced;
	for (const gausslod::LevelStats &l : out.levels) {
		std::string &list = l.reduced ? reduced : made;
		if (l.collapses > 0)
			list += (list.empty() ? "" : ", ") + ("LOD" + std::to_string(l.level));
	}
	if (!made.empty())
		std::printf("%s: made from the finer level by edge collapses, at the superface level's "
		            "face count within its distance bound (maxdev: a bound; meandev: an "
		            "estimate)\n",
		            made.c_str());
	if (!reduced.empty())
		std::printf("%s: continued by edge collapses with quadric placement to %s (maxdev, "
		            "meandev: measured, each input face against the level's nearest triangle)\n",
		            reduced.c_str(),
		            targets ? "the level's target" : "a real step (--complete-chain)");
	for (const gausslod::LevelStats &l : out.levels) {
		const std::string note = gausslod::budgetNote(l);
		if (!note.empty())
			std::printf("LOD%d: %zu faces for a budget of %zu: %s\n", l.level, l.faces,
			            l.targetFaces, note.c_str());
	}
	std::printf("total %.3f s; files in %s\n", out.seconds, outdir.c_str());
}

// Ctrl-C: the engine stops at its next step; a second Ctrl-C quits.
volatile std::sig_atomic_t interrupted = 0;

// A progress line on a terminal (stderr, rewritten in place; cleared before each table row).
class ProgressLine {
public:
	explicit ProgressLine(bool show) : show_(show) {}
	/// The engine's progress: shows it, and says whether to go on (not interrupted).
	bool update(double fraction, const char *stage)
	{
		if (show_) {
			const int percent = int(100 * std::min(1.0, std::max(0.0, fraction)));
			if (percent != shownPercent_ || shownStage_ != stage) {
				std::fprintf(stderr, "\r\033[K%3d %%  %s", percent, stage);
				std::fflush(stderr);
				shownPercent_ = percent, shownStage_ = stage;
			}
		}
		return interrupted == 0;
	}
	void clear()
	{
		if (shownPercent_ >= 0)
			std::fprintf(stderr, "\r\033[K");
		shownPercent_ = -1;
	}

private:
	bool show_;
	int shownPercent_ = -1;
	std::string shownStage_;
};

// gausslod --check: reads and checks `input` only.
int checkMain(const std::string &input, const cli::Options &o)
{
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

// gausslod INPUT OUTDIR: builds and writes the levels, printing each as it is written. Ctrl-C
// stops it: the levels already written stay (each is renamed into place only once complete),
// nothing half-written remains.
int runMain(const std::string &input, const std::string &outdir, const cli::Options &o)
{
	std::string stem = input.substr(input.find_last_of('/') + 1);
	stem = stem.substr(0, stem.find_last_of('.'));
	std::signal(SIGINT, [](int) {
		interrupted = 1;
		std::signal(SIGINT, SIG_DFL);
	});
	ProgressLine progress(!o.quiet && !o.json && isatty(STDOUT_FILENO) && isatty(STDERR_FILENO));
	auto done = [&](const cli::Outcome &sofar, const gausslod::LevelStats &s, const std::string &) {
		progress.clear();
		printLevel(o, sofar, s);
	};
	const cli::Outcome out =
	    cli::runOne(input, outdir, stem, o, done, [&](double fraction, const char *stage) {
		    return progress.update(fraction, stage);
	    });
	progress.clear();
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
	if (!o.json)
		printTableNotes(o, out, outdir);
	return 0;
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
	return check ? checkMain(positional[0], o) : runMain(positional[0], positional[1], o);
}
