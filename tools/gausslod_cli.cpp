// gausslod: the GaussLOD engine from the command line (no MeshLab needed).
//   gausslod [options] INPUT(.ply|.obj|.off|.stl) OUTDIR
// Writes OUTDIR/<name>_LOD<i>.ply per level and prints a per-level table (or JSON lines).
#include "gausslod/gausslod.h"
#include "gausslod/import_mesh.h"
#include "gausslod/io_mesh.h"
#include "gausslod/level_ply.h"
#include "gausslod/vcg_adapter.h"

#include <vcg/complex/complex.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <string>
#include <sys/stat.h>

namespace {

using CMesh = gausslod::IoMesh;

void usage()
{
	std::fprintf(stderr,
	             "usage: gausslod [options] INPUT OUTDIR\n"
	             "  INPUT: .ply .obj .off .stl triangle mesh; OUTDIR: created if missing\n"
	             "options (defaults as in the MeshLab filter):\n"
	             "  --levels N          number of levels, 1..8 (5)\n"
	             "  --feature-angle D   vertex-class threshold, degrees (30)\n"
	             "  --straighten P      border straightening tolerance, %% of bbox diagonal (0.5)\n"
	             "  --merge P           vicinity merge distance, %% of bbox diagonal (0.25)\n"
	             "  --max-distance P    distance tolerance, %% of bbox diagonal: no removed input\n"
	             "                      vertex farther from the output (0 = none, the default)\n"
	             "  --normal-limit F    normal deviation limit, x each level's bound; 0 = none (1)\n"
	             "  --output-levels L   \"all\" or a comma list of levels to write, 0 = coarsest (all)\n"
	             "  --paper-superfaces  superfaces within one Gauss-sphere cell only, as in the paper\n"
	             "                      (default: also merge across cell borders within the bound)\n"
	             "  --threads N         worker threads, 0 = one per core (0); same output for any N\n"
	             "  --no-colour         do not colour faces by superface\n"
	             "  --json              one JSON line per level instead of the table\n"
	             "exit codes: 0 ok, 1 bad input or failure, 2 bad usage\n");
}

bool parseDouble(const char *s, double &out)
{
	char *end = nullptr;
	out = std::strtod(s, &end);
	return end && *end == 0 && end != s;
}

} // namespace

int main(int argc, char **argv)
{
#ifdef __GLIBC__
	// glibc raises its mmap threshold to the size of the largest block freed so far, after which
	// arrays of a few MB freed between rounds and levels stay in the process: a fixed threshold
	// gives them back (peak resident memory on a 1M-face mesh 277 -> 235 MB, same time).
	mallopt(M_MMAP_THRESHOLD, 4 << 20);
#endif
	gausslod::Params params;
	double straightenPct = 0.5, mergePct = 0.25, maxDistancePct = 0;
	bool colour = true, json = false;
	std::string outputLevels = "all";
	std::string input, outdir;
	for (int i = 1; i < argc; ++i) {
		const std::string a = argv[i];
		auto value = [&](double &v) {
			if (i + 1 >= argc || !parseDouble(argv[i + 1], v)) {
				std::fprintf(stderr, "gausslod: %s needs a number\n", a.c_str());
				std::exit(2);
			}
			++i;
		};
		double v;
		if (a == "--levels") {
			value(v);
			params.maxLevel = int(v);
		} else if (a == "--feature-angle") {
			value(params.featureAngleDeg);
		} else if (a == "--straighten") {
			value(straightenPct);
		} else if (a == "--merge") {
			value(mergePct);
		} else if (a == "--max-distance") {
			value(maxDistancePct);
		} else if (a == "--normal-limit") {
			value(params.deviationFactor);
		} else if (a == "--output-levels") {
			if (i + 1 >= argc) {
				std::fprintf(stderr, "gausslod: %s needs a list\n", a.c_str());
				return 2;
			}
			outputLevels = argv[++i];
		} else if (a == "--paper-superfaces") {
			params.mergeAcrossCells = false;
		} else if (a == "--threads") {
			value(v);
			params.threads = int(v);
		} else if (a == "--no-colour") {
			colour = false;
		} else if (a == "--json") {
			json = true;
		} else if (a == "-h" || a == "--help") {
			usage();
			return 0;
		} else if (!a.empty() && a[0] == '-') {
			std::fprintf(stderr, "gausslod: unknown option %s\n", a.c_str());
			usage();
			return 2;
		} else if (input.empty()) {
			input = a;
		} else if (outdir.empty()) {
			outdir = a;
		} else {
			usage();
			return 2;
		}
	}
	if (input.empty() || outdir.empty()) {
		usage();
		return 2;
	}
	if (outputLevels != "all") { // as the filter's "Output levels"
		params.levelMask = 0;
		std::string item;
		for (size_t p = 0; p <= outputLevels.size(); ++p) {
			if (p < outputLevels.size() && outputLevels[p] != ',') {
				item += outputLevels[p];
				continue;
			}
			char *end = nullptr;
			const long level = std::strtol(item.c_str(), &end, 10);
			if (item.empty() || *end != 0 || level < 0 || level >= params.maxLevel) {
				std::fprintf(stderr,
				             "gausslod: --output-levels: '%s' is not a level index; write \"all\" or "
				             "a comma list of numbers from 0 (coarsest) to %d (finest)\n",
				             item.c_str(), params.maxLevel - 1);
				return 2;
			}
			params.levelMask |= 1u << level;
			item.clear();
		}
	}
	struct stat st;
	if (stat(input.c_str(), &st) != 0) {
		std::fprintf(stderr, "gausslod: cannot open %s: no such file\n", input.c_str());
		return 1;
	}
	gausslod::FlatMesh flat;
	{ // the VCG mesh is freed once flattened (the engine works on the flat arrays)
		CMesh mesh;
		std::string error;
		if (!gausslod::importMesh(mesh, input, error)) {
			std::fprintf(stderr, "gausslod: cannot read %s: %s\n", input.c_str(), error.c_str());
			return 1;
		}
		flat = gausslod::flatten(mesh);
	}
#ifdef __GLIBC__
	// below 500k faces the freed arrays weigh more in the peak and are cheap to map: a 256 KB
	// threshold (100k-face mesh: 29.0 -> 27.1-27.4 MB, 0.215 -> 0.222-0.228 s; on a 1M-face mesh a 2 MB
	// threshold cost 4 % time for no memory gain)
	if (flat.triangles.size() / 3 < 500000)
		mallopt(M_MMAP_THRESHOLD, 256 << 10);
#endif
	const double diag = gausslod::bboxDiagonal(flat.view());
	// the distance bound measured by the tolerance check, % of the diagonal ("null" when off)
	const bool distanceColumn = maxDistancePct > 0;
	auto distancePct = [&](const gausslod::LevelStats &s) {
		if (s.maxDistance < 0 || !(diag > 0))
			return std::string("null");
		char buf[32];
		std::snprintf(buf, sizeof buf, "%.4f", 100.0 * s.maxDistance / diag);
		return std::string(buf);
	};
	auto distanceCell = [&](const gausslod::LevelStats &s) {
		if (!distanceColumn)
			return std::string();
		char buf[48];
		std::snprintf(buf, sizeof buf, "  %9s", distancePct(s).c_str());
		return std::string(buf);
	};
	params.straightenTolerance = straightenPct / 100.0 * diag;
	params.mergeDistance = mergePct / 100.0 * diag;
	params.maxDistance = maxDistancePct / 100.0 * diag;
	std::string name = input.substr(input.find_last_of('/') + 1);
	name = name.substr(0, name.find_last_of('.'));
	std::string writeError;
	bool first = true;
	// each level is written as soon as it is built, then dropped (one level in memory at a time)
	auto sink = [&](const gausslod::LevelMesh &lm) {
		if (first) {
			first = false;
			mkdir(outdir.c_str(), 0777);
			if (!json) {
				std::printf("%-6s %9s %9s %10s %9s %9s %9s %9s %8s%s\n", "level", "faces", "vertices",
				            "superfaces", "fallback", "bound", "maxdev", "meandev", "seconds",
				            distanceColumn ? " distbound%" : "");
				std::printf("%-6s %9zu %9zu %10s %9s %9s %9s %9s %8s%s\n", "input",
				            flat.triangles.size() / 3, flat.positions.size() / 3, "-", "-", "-", "-",
				            "-", "-", distanceColumn ? "          -" : "");
			}
		}
		const gausslod::LevelStats &s = lm.stats;
		const std::string file = outdir + "/" + name + "_LOD" + std::to_string(s.level) + ".ply";
		if (!gausslod::writeLevelPly(lm, file, colour, writeError))
			return false;
		if (json)
			std::printf("{\"level\":%d,\"faces\":%zu,\"vertices\":%zu,\"superfaces\":%zu,"
			            "\"fallbacks\":%zu,\"retriangulated\":%zu,\"bound_deg\":%.4f,"
			            "\"max_dev_deg\":%.4f,\"mean_dev_deg\":%.4f,\"unmeasured_faces\":%zu,"
			            "\"seconds\":%.4f,\"seconds_partition\":%.4f,\"seconds_borders\":%.4f,"
			            "\"seconds_triangulation\":%.4f,\"seconds_checks\":%.4f,\"rounds\":%d,"
			            "\"reused_finer\":%s,\"distance_bound_pct\":%s,\"file\":\"%s\"}\n",
			            s.level, s.faces, s.vertices, s.superfaces, s.fallbacks, s.retriangulated,
			            s.boundDeg, s.maxNormalDevDeg, s.meanNormalDevDeg, s.unmeasuredFaces,
			            s.seconds, s.secondsPartition, s.secondsBorders, s.secondsTriangulation,
			            s.secondsChecks, s.rounds, s.reusedFiner ? "true" : "false",
			            distancePct(s).c_str(), file.c_str());
		else
			std::printf("LOD%-3d %9zu %9zu %10zu %9zu %9.2f %9.2f %9.3f %8.3f%s\n", s.level, s.faces,
			            s.vertices, s.superfaces, s.fallbacks, s.boundDeg, s.maxNormalDevDeg,
			            s.meanNormalDevDeg, s.seconds, distanceCell(s).c_str());
		std::fflush(stdout);
		return true;
	};
	const gausslod::Result res = gausslod::buildLevels(flat.view(), params, {}, sink);
	if (!res.ok) {
		if (writeError.empty())
			std::fprintf(stderr, "gausslod: %s: %s\n", input.c_str(), res.error.c_str());
		else
			std::fprintf(stderr, "gausslod: %s\n", writeError.c_str());
		return 1;
	}
	if (!json)
		std::printf("total %.3f s; files in %s\n", res.totalSeconds, outdir.c_str());
	return 0;
}
