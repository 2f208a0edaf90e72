// bench_load [--tool] MESH: loads a mesh and exits; its peak resident memory, measured around the
// process, is the reference of the "peak memory <= 3x loading the mesh" bar.
//   --tool:  exactly as the gausslod tool loads it (its readInputMesh: since DESIGN 43 a plain
//            binary PLY straight into the engine's flat arrays, anything else through VCG's
//            mesh): the bar's reference;
//   default: into the tool's VCG mesh type with its guarded VCG importers (the mesh as MeshLab
//            holds it; the tool's own read until DESIGN 43, reported beside it).
#include "bench_mesh.h"
#include "level_files.h"

#include <cstdio>
#include <cstring>

int main(int argc, char **argv)
{
	const bool tool = argc == 3 && std::strcmp(argv[1], "--tool") == 0;
	if (argc != 2 && !tool) {
		std::fprintf(stderr, "usage: bench_load [--tool] MESH\n");
		return 2;
	}
	const char *path = argv[argc - 1];
	if (tool) {
		cli::InputMesh in;
		gausslod::ReadError e;
		if (!cli::readInputMesh(path, gausslod::Params(), in, e)) {
			std::fprintf(stderr, "bench_load: cannot read %s: %s\n", path, e.message.c_str());
			return 1;
		}
		std::printf("{\"vertices\":%zu,\"faces\":%zu}\n", in.flat.positions.size() / 3,
		            in.flat.triangles.size() / 3);
		return 0;
	}
	bench::FMesh m;
	std::string err;
	if (!bench::load(m, path, err)) {
		std::fprintf(stderr, "bench_load: cannot read %s: %s\n", path, err.c_str());
		return 1;
	}
	std::printf("{\"vertices\":%d,\"faces\":%d}\n", m.vn, m.fn);
	return 0;
}
