// bench_anatomy: where a level's faces come from. Builds the levels of a mesh with the engine
// (default parameters, or NAME VALUE pairs of Params, as the filter names them) and prints, per
// level, how many output vertices lie inside one superface (all their triangles in it) and how
// many on superface borders, and the output triangles by the size of their superface (its input
// faces), with how many of those superfaces kept their input faces unchanged.
//   bench_anatomy MESH [NAME VALUE]...
// (DESIGN 30: on curved models most vertices are border vertices, and the superfaces' count, not
// the tolerance, sets a fine level's face count.)
#include "bench_mesh.h"
#include "gausslod/gausslod.h"

#include <cstdlib>

int main(int argc, char **argv)
{
	if (argc < 2 || argc % 2 != 0) {
		std::fprintf(stderr, "usage: bench_anatomy MESH [NAME VALUE]...\n");
		return 2;
	}
	bench::FMesh m;
	std::string err;
	if (!bench::load(m, argv[1], err)) {
		std::fprintf(stderr, "bench_anatomy: cannot read %s: %s\n", argv[1], err.c_str());
		return 1;
	}
	const bench::Flat flat = bench::flatten(m);
	const std::vector<double> P(flat.pos.begin(), flat.pos.end());
	const std::vector<int32_t> T(flat.tri.begin(), flat.tri.end());
	gausslod::MeshView view;
	view.positions = P.data(), view.vertexCount = flat.vn();
	view.triangles = T.data(), view.faceCount = flat.fn();
	gausslod::Params params;
	for (int i = 2; i + 1 < argc; i += 2) {
		const gausslod::ParamSpec *spec = gausslod::findParam(argv[i]);
		if (!spec) {
			std::fprintf(stderr, "bench_anatomy: no parameter %s\n", argv[i]);
			return 2;
		}
		gausslod::setParam(params, *spec, std::atof(argv[i + 1]));
	}
	const gausslod::Result r = gausslod::buildLevels(view, params);
	if (!r.ok) {
		std::fprintf(stderr, "bench_anatomy: %s\n", r.error.c_str());
		return 1;
	}
	for (const gausslod::LevelMesh &lm : r.levels) {
		const size_t ns = lm.stats.superfaces, nv = lm.positions.size() / 3;
		std::vector<long> in(ns, 0), out(ns, 0);
		for (const int32_t s : lm.inputSuperface)
			if (s >= 0)
				++in[size_t(s)];
		for (const int32_t s : lm.superface)
			++out[size_t(s)];
		std::vector<int32_t> sfOf(nv, -1);
		std::vector<uint8_t> border(nv, 0);
		for (size_t f = 0; f < lm.superface.size(); ++f)
			for (size_t k = 0; k < 3; ++k) {
				const size_t v = size_t(lm.triangles[3 * f + k]);
				if (sfOf[v] < 0)
					sfOf[v] = lm.superface[f];
				else if (sfOf[v] != lm.superface[f])
					border[v] = 1;
			}
		size_t inside = 0;
		for (size_t v = 0; v < nv; ++v)
			inside += !border[v];
		std::printf("L%d: %zu faces, %zu superfaces, %zu vertices: %zu inside a superface, %zu on "
		            "borders\n",
		            lm.stats.level, lm.superface.size(), ns, nv, inside, nv - inside);
		const long edges[] = {1, 2, 4, 16, 64, 256, 1024, 4096, 16384, 1L << 40};
		for (size_t b = 0; b + 1 < sizeof(edges) / sizeof(edges[0]); ++b) {
			long count = 0, faces = 0, tris = 0, same = 0;
			for (size_t s = 0; s < ns; ++s)
				if (in[s] >= edges[b] && in[s] < edges[b + 1]) {
					++count, faces += in[s], tris += out[s];
					same += out[s] == in[s];
				}
			if (count > 0)
				std::printf("  superfaces of %ld..%ld input faces: %ld, %ld input faces -> %ld "
				            "triangles (%.1f %% of the level); %ld as their input faces\n",
				            edges[b], edges[b + 1] - 1, count, faces, tris,
				            100.0 * double(tris) / double(lm.superface.size()), same);
		}
	}
	return 0;
}
