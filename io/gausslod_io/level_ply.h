// Writes one level straight from its arrays as a binary little-endian PLY file, in the layout
// VCG's PLY exporter uses for a mesh with per-face colour (float x y z; uchar count + int indices;
// optionally uchar red green blue alpha per face). Going through a VCG mesh copy of the level
// instead made that copy the command-line tool's peak memory (about 50 MB for a 900k-face level).
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

} // namespace detail

/// Writes `level` to `file`; faces coloured by superface (superfaceColour) if asked. Returns false
/// with `error` set if the file cannot be written.
inline bool writeLevelPly(const LevelMesh &level, const std::string &file, bool colourBySuperface,
                          std::string &error)
{
	std::FILE *f = std::fopen(file.c_str(), "wb");
	if (!f) {
		error = "cannot write " + file + ": " + std::strerror(errno);
		return false;
	}
	const size_t nv = level.positions.size() / 3, nf = level.triangles.size() / 3;
	detail::LeWriter w(f);
	std::string header = "ply\nformat binary_little_endian 1.0\ncomment GaussLOD level " +
	                     std::to_string(level.stats.level) + "\n";
	if (level.stats.distanceBound >= 0) { // (for a renderer choosing the level by error)
		char line[160];
		std::snprintf(line, sizeof line,
		              "comment GaussLOD distance_bound %.9g (upper bound on the distance to the "
		              "input, mesh units)\n",
		              level.stats.distanceBound);
		header += line;
	}
	header += "element vertex " + std::to_string(nv) +
	                     "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
	                     std::to_string(nf) + "\nproperty list uchar int vertex_indices\n";
	if (colourBySuperface)
		header += "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n";
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
	const bool written = w.flush();
	const bool closed = std::fclose(f) == 0;
	if (!written || !closed) {
		error = "cannot write " + file + ": " + std::strerror(errno);
		std::remove(file.c_str());
		return false;
	}
	return true;
}

} // namespace gausslod
