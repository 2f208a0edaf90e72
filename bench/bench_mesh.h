// Mesh types and small helpers shared by the bench programs (VCG, header-only).
#pragma once

#include "gausslod_io/io_mesh.h"

#include "gausslod_io/import_mesh.h"
#include <vcg/complex/complex.h>
#include <wrap/io_trimesh/export_ply.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace bench {

// Single precision, like the gausslod tool's mesh (tools/gausslod_cli.cpp): used for loading,
// converting and writing.
using FMesh = gausslod::IoMesh;

inline double now()
{
	return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
	    .count();
}

template <class MeshT>
bool load(MeshT &m, const std::string &file, std::string &err)
{
	gausslod::ReadError e;
	const bool ok = gausslod::importMesh(m, file, e); // (as the gausslod tool loads it)
	err = e.message;
	return ok;
}

/// Flat arrays (positions, triangles), skipping deleted elements.
struct Flat {
	std::vector<float> pos;
	std::vector<uint32_t> tri;
	size_t vn() const { return pos.size() / 3; }
	size_t fn() const { return tri.size() / 3; }
};

inline Flat flatten(const FMesh &m)
{
	Flat out;
	std::vector<int64_t> remap(m.vert.size(), -1);
	for (size_t i = 0; i < m.vert.size(); ++i) {
		if (m.vert[i].IsD())
			continue;
		remap[i] = int64_t(out.pos.size() / 3);
		for (int k = 0; k < 3; ++k)
			out.pos.push_back(m.vert[i].cP()[k]);
	}
	for (const auto &f : m.face) {
		if (f.IsD())
			continue;
		for (int k = 0; k < 3; ++k)
			out.tri.push_back(uint32_t(remap[vcg::tri::Index(m, f.cV(k))]));
	}
	return out;
}

/// Writes positions (double or float, 3 per vertex) and triangles as binary PLY, dropping
/// vertices that no triangle uses.
template <class Real, class Index>
bool writePly(const std::string &file, const std::vector<Real> &pos, const std::vector<Index> &tri)
{
	const size_t nv = pos.size() / 3;
	std::vector<int64_t> remap(nv, -1);
	FMesh m;
	size_t used = 0;
	for (Index i : tri)
		if (remap[size_t(i)] < 0)
			remap[size_t(i)] = int64_t(used++);
	auto vi = vcg::tri::Allocator<FMesh>::AddVertices(m, used);
	(void)vi;
	for (size_t i = 0; i < nv; ++i)
		if (remap[i] >= 0)
			m.vert[size_t(remap[i])].P() =
			    vcg::Point3f(float(pos[3 * i]), float(pos[3 * i + 1]), float(pos[3 * i + 2]));
	auto fi = vcg::tri::Allocator<FMesh>::AddFaces(m, tri.size() / 3);
	for (size_t f = 0; f < tri.size() / 3; ++f, ++fi)
		for (int k = 0; k < 3; ++k)
			fi->V(k) = &m.vert[size_t(remap[size_t(tri[3 * f + k])])];
	return vcg::tri::io::ExporterPLY<FMesh>::Save(m, file.c_str(), 0, true) == 0;
}

/// Minimal JSON string escaping (file names).
inline std::string jsonStr(const std::string &s)
{
	std::string o = "\"";
	for (char c : s) {
		if (c == '"' || c == '\\')
			o += '\\';
		o += c;
	}
	return o + "\"";
}

} // namespace bench
