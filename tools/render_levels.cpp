// render_levels: a small software rasterizer for looking at levels without a display.
//   render_levels OUT.ppm WIDTH YAW_DEG PITCH_DEG MESH.ply [MESH.ply ...]
// Renders each mesh side by side (flat shading, per-face colour when present, dark superface
// borders), from the same camera framing the first mesh. Convert with imagemagick for PNG.
#include "gausslod_io/io_mesh.h"

#include <vcg/complex/complex.h>
#include <wrap/io_trimesh/import.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

using RMesh = gausslod::IoMesh;

int main(int argc, char **argv)
{
	if (argc < 6) {
		std::fprintf(stderr, "usage: render_levels OUT.ppm WIDTH YAW PITCH MESH...\n");
		return 2;
	}
	const int W = std::atoi(argv[2]), H = W, n = argc - 5;
	const float yaw = float(std::atof(argv[3]) * M_PI / 180),
	            pitch = float(std::atof(argv[4]) * M_PI / 180);
	std::vector<unsigned char> img(size_t(W * n) * H * 3, 255);
	vcg::Point3f center;
	float radius = 0;
	const vcg::Point3f light = vcg::Point3f(0.3f, 0.5f, 1.0f).Normalize();
	for (int m = 0; m < n; ++m) {
		RMesh mesh;
		int mask = 0;
		if (vcg::tri::io::Importer<RMesh>::Open(mesh, argv[5 + m], mask) != 0 && mesh.fn == 0) {
			std::fprintf(stderr, "cannot read %s\n", argv[5 + m]);
			return 1;
		}
		const bool colour = mask & vcg::tri::io::Mask::IOM_FACECOLOR;
		vcg::tri::UpdateBounding<RMesh>::Box(mesh);
		if (m == 0) {
			center = mesh.bbox.Center();
			radius = mesh.bbox.Diag() / 2;
		}
		auto view = [&](vcg::Point3f p) { // rotate about the center: yaw (y axis), then pitch (x)
			p -= center;
			const float x = std::cos(yaw) * p[0] + std::sin(yaw) * p[2];
			const float z = -std::sin(yaw) * p[0] + std::cos(yaw) * p[2];
			const float y = std::cos(pitch) * p[1] - std::sin(pitch) * z;
			const float z2 = std::sin(pitch) * p[1] + std::cos(pitch) * z;
			return vcg::Point3f((x / radius * 0.95f + 1) * W / 2, (1 - y / radius * 0.95f) * H / 2,
			                    z2);
		};
		std::vector<float> zbuf(size_t(W) * H, -1e30f);
		for (const gausslod::IoFace &f : mesh.face) {
			const vcg::Point3f a = view(f.cP(0)), b = view(f.cP(1)), c = view(f.cP(2));
			vcg::Point3f nrm = (b - a) ^ (c - a);
			if (nrm.Norm() == 0)
				continue;
			nrm.Normalize();
			const float shade = 0.25f + 0.75f * std::fabs(nrm.dot(light));
			const vcg::Color4b col = colour ? f.cC() : vcg::Color4b(200, 200, 210, 255);
			const int x0 = std::max(0, int(std::floor(std::min({a[0], b[0], c[0]}))));
			const int x1 = std::min(W - 1, int(std::ceil(std::max({a[0], b[0], c[0]}))));
			const int y0 = std::max(0, int(std::floor(std::min({a[1], b[1], c[1]}))));
			const int y1 = std::min(H - 1, int(std::ceil(std::max({a[1], b[1], c[1]}))));
			const float area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
			if (area == 0)
				continue;
			for (int y = y0; y <= y1; ++y)
				for (int x = x0; x <= x1; ++x) {
					const float px = x + 0.5f, py = y + 0.5f;
					const float w0 = ((b[0] - px) * (c[1] - py) - (b[1] - py) * (c[0] - px)) / area;
					const float w1 = ((c[0] - px) * (a[1] - py) - (c[1] - py) * (a[0] - px)) / area;
					const float w2 = 1 - w0 - w1;
					if (w0 < 0 || w1 < 0 || w2 < 0)
						continue;
					const float z = w0 * a[2] + w1 * b[2] + w2 * c[2];
					float &zb = zbuf[size_t(y) * W + x];
					if (z <= zb)
						continue;
					zb = z;
					// thin dark lines on the triangle edges
					const float edge = std::min({w0 * std::fabs(area) / (b - c).Norm(),
					                             w1 * std::fabs(area) / (c - a).Norm(),
					                             w2 * std::fabs(area) / (a - b).Norm()});
					const float k = edge < 0.6f ? 0.45f : 1.0f;
					unsigned char *px3 = &img[(size_t(y) * W * n + size_t(m) * W + x) * 3];
					for (int ch = 0; ch < 3; ++ch)
						px3[ch] = (unsigned char)(std::min(255.0f, col[ch] * shade * k));
				}
		}
	}
	FILE *out = std::fopen(argv[1], "wb");
	if (!out)
		return 1;
	std::fprintf(out, "P6\n%d %d\n255\n", W * n, H);
	std::fwrite(img.data(), 1, img.size(), out);
	std::fclose(out);
	return 0;
}
