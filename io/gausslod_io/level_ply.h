// Writes one level straight from its arrays as a binary little-endian PLY file, in the layout
// VCG's PLY exporter uses for a mesh with per-face colour (float x y z; uchar count + int indices;
// optionally uchar red green blue alpha per face), or as a binary STL file with the records VCG's
// STL exporter writes (writeLevelStl). Going through a VCG mesh copy of the level instead made
// that copy the command-line tool's peak memory (about 50 MB for a 900k-face level).
#pragma once

#include "gausslod/gausslod.h"
#include "gausslod/vcg_adapter.h"

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace gausslod {

namespace detail {

// Little-endian byte writer with a fixed buffer.
class LeWriter {
public:
	explicit LeWriter(std::FILE *f) : f_(f) { buf_.reserve(kSize); }
	void u8(uint8_t x)
	{
		buf_.push_back(x);
		if (buf_.size() >= kSize)
			flush();
	}
	void u32(uint32_t x)
	{
		for (int k = 0; k < 4; ++k)
			u8(uint8_t(x >> (8 * k)));
	}
	void f32(float x)
	{
		uint32_t u;
		std::memcpy(&u, &x, 4);
		u32(u);
	}
	void text(const std::string &s)
	{
		for (char c : s)
			u8(uint8_t(c));
	}
	bool flush()
	{
		if (!buf_.empty() && std::fwrite(buf_.data(), 1, buf_.size(), f_) != buf_.size())
			ok_ = false;
		buf_.clear();
		return ok_;
	}

private:
	static constexpr size_t kSize = size_t(1) << 20;
	std::FILE *f_;
	std::vector<uint8_t> buf_;
	bool ok_ = true;
};

/// Opens `file`, lets `body` write it through a LeWriter, flushes and closes it. False with
/// `error` set (and the file removed) if any of that fails.
template <class Body>
bool writeBinaryFile(const std::string &file, std::string &error, Body body)
{
	std::FILE *f = std::fopen(file.c_str(), "wb");
	if (!f) {
		error = "cannot write " + file + ": " + std::strerror(errno);
		return false;
	}
	LeWriter w(f);
	body(w);
	const bool written = w.flush();
	const bool closed = std::fclose(f) == 0;
	if (!written || !closed) {
		error = "cannot write " + file + ": " + std::strerror(errno);
		std::remove(file.c_str());
		return false;
	}
	return true;
}

} // namespace detail

/// Writes `level` to `file`; faces coloured by superface (superfaceColour) if asked. Returns false
/// with `error` set if the file cannot be written.
inline bool writeLevelPly(const LevelMesh &level, const std::string &file, bool colourBySuperface,
                          std::string &error)
{
	return detail::writeBinaryFile(file, error, [&](detail::LeWriter &w) {
		const size_t nv = level.positions.size() / 3, nf = level.triangles.size() / 3;
		std::string header = "ply\nformat binary_little_endian 1.0\ncomment GaussLOD level " +
		                     std::to_string(level.stats.level) + "\n";
		// (for a renderer choosing the level by error: the construction's bound, and the
		// certified distance, DESIGN 52, usually far below it)
		auto comment = [&](const char *name, double value, const char *what) {
			char line[200];
			std::snprintf(line, sizeof line, "comment GaussLOD %s %.9g (%s, mesh units)\n", name,
			              value, what);
			header += line;
		};
		if (level.stats.distanceBound >= 0)
			comment("distance_bound", level.stats.distanceBound,
			        "upper bound on the distance to the input");
		if (level.stats.hausdorff >= 0)
			comment("hausdorff", level.stats.hausdorff,
			        "certified upper bound on the Hausdorff distance to the input");
		header += "element vertex " + std::to_string(nv) +
		          "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
		          std::to_string(nf) + "\nproperty list uchar int vertex_indices\n";
		if (colourBySuperface)
			header += "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty "
			          "uchar alpha\n";
		header += "end_header\n";
		w.text(header);
		for (size_t i = 0; i < 3 * nv; ++i)
			w.f32(float(level.positions[i]));
		for (size_t t = 0; t < nf; ++t) {
			w.u8(3);
			for (size_t k = 0; k < 3; ++k)
				w.u32(uint32_t(level.triangles[3 * t + k]));
			if (colourBySuperface) {
				const vcg::Color4b c = superfaceColour(level.superface[t]);
				for (int k = 0; k < 4; ++k)
					w.u8(c[k]);
			}
		}
	});
}

/// The 80-byte header of writeLevelStl's files: the level and its distance bound (a binary STL
/// header must not start with "solid": readers would take the file for ASCII).
inline std::string levelStlHeader(const LevelMesh &level)
{
	char h[81];
	if (level.stats.distanceBound >= 0 && level.stats.hausdorff >= 0)
		std::snprintf(h, sizeof h, "GaussLOD level %d distance_bound %.9g hausdorff %.9g",
		              level.stats.level, level.stats.distanceBound, level.stats.hausdorff);
	else if (level.stats.distanceBound >= 0)
		std::snprintf(h, sizeof h, "GaussLOD level %d distance_bound %.9g", level.stats.level,
		              level.stats.distanceBound);
	else if (level.stats.hausdorff >= 0)
		std::snprintf(h, sizeof h, "GaussLOD level %d hausdorff %.9g", level.stats.level,
		              level.stats.hausdorff);
	else
		std::snprintf(h, sizeof h, "GaussLOD level %d", level.stats.level);
	std::string s(h);
	s.resize(80, ' ');
	return s;
}

/// Writes `level` to `file` as a binary STL file: levelStlHeader, the face count, then per face
/// the records vcg::tri::io::ExporterSTL writes for the level as a float VCG mesh (toVcgMesh):
/// the unit normal computed as its TriangleNormal(...).Normalize() in float, the three corners,
/// and attribute 0. Returns false with `error` set if the file cannot be written.
inline bool writeLevelStl(const LevelMesh &level, const std::string &file, std::string &error)
{
	return detail::writeBinaryFile(file, error, [&](detail::LeWriter &w) {
		const size_t nf = level.triangles.size() / 3;
		w.text(levelStlHeader(level));
		w.u32(uint32_t(nf));
		for (size_t t = 0; t < nf; ++t) {
			vcg::Point3f p[3];
			for (size_t k = 0; k < 3; ++k) {
				const double *q = &level.positions[3 * size_t(level.triangles[3 * t + k])];
				p[k] = vcg::Point3f(float(q[0]), float(q[1]), float(q[2]));
			}
			vcg::Point3f n = (p[1] - p[0]) ^ (p[2] - p[0]); // (vcg::TriangleNormal)
			n.Normalize();
			for (int k = 0; k < 3; ++k)
				w.f32(n[k]);
			for (const vcg::Point3f &c : p)
				for (int k = 0; k < 3; ++k)
					w.f32(c[k]);
			w.u8(0), w.u8(0);
		}
	});
}

} // namespace gausslod
