// The gausslod tool's run of one input: read it, build its levels, write each level's file as
// soon as it is built (and the chain's glb or tileset once all are), report the outcome.
#include "cli.h"
#include "level_files.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <fstream>
#include <memory>
#include <new>
#include <string>
#include <sys/stat.h>
#include <unistd.h>

namespace cli {

namespace {

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
