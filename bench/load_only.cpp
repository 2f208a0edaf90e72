// bench_load: loads a mesh exactly as the gausslod tool does (same VCG mesh type and importer)
// and exits. Its peak resident memory, measured around the process, is the reference for the
// "peak memory <= 3x loading the mesh" bar.
#include "bench_mesh.h"

int main(int argc, char **argv)
{
	if (argc != 2) {
		std::fprintf(stderr, "usage: bench_load MESH\n");
		return 2;
	}
	bench::FMesh m;
	std::string err;
	if (!bench::load(m, argv[1], err)) {
		std::fprintf(stderr, "bench_load: cannot read %s: %s\n", argv[1], err.c_str());
		return 1;
	}
	std::printf("{\"vertices\":%d,\"faces\":%d}\n", m.vn, m.fn);
	return 0;
}
