// GaussLOD <-> VCG meshes: the engine works on flat arrays; these templates copy any VCG triangle
// mesh type (CMeshO in MeshLab, a plain vcg::tri::TriMesh in tests and tools) in and out.
#pragma once

#include "gausslod.h"

#include <vcg/complex/complex.h>

#include <cmath>
#include <vector>

namespace gausslod {

/// Flat copy of a VCG mesh, skipping deleted elements (indices are remapped).
struct FlatMesh {
	std::vector<double> positions;
	std::vector<int32_t> triangles;
	MeshView view() const
	{
		MeshView v;
		v.positions = positions.data();
		v.vertexCount = positions.size() / 3;
		v.triangles = triangles.data();
		v.faceCount = triangles.size() / 3;
		return v;
	}
};

template <class MeshT>
FlatMesh flatten(const MeshT &m)
{
	FlatMesh out;
	std::vector<int32_t> remap(m.vert.size(), -1);
	out.positions.reserve(size_t(m.vn) * 3);
	for (size_t i = 0; i < m.vert.size(); ++i) {
		const auto &v = m.vert[i];
		if (v.IsD())
			continue;
		remap[i] = int32_t(out.positions.size() / 3);
		for (int k = 0; k < 3; ++k)
			out.positions.push_back(double(v.cP()[k]));
	}
	out.triangles.reserve(size_t(m.fn) * 3);
	for (const auto &f : m.face) {
		if (f.IsD())
			continue;
		for (int k = 0; k < 3; ++k)
			out.triangles.push_back(remap[vcg::tri::Index(m, f.cV(k))]);
	}
	return out;
}

/// A stable, distinct colour per superface id (golden-ratio hue walk; neighbouring ids differ).
inline vcg::Color4b superfaceColour(int32_t id)
{
	const double h = std::fmod(0.137 + 0.6180339887498949 * double(id), 1.0);
	const double s = (id % 3 == 0) ? 0.55 : (id % 3 == 1 ? 0.75 : 0.4);
	const double v = (id % 2 == 0) ? 0.95 : 0.78;
	vcg::Color4b c;
	c.SetHSVColor(float(h), float(s), float(v));
	return c;
}

/// Writes one level into an (empty) VCG mesh. Face colour needs per-face colour enabled in `out`;
/// faux edges need the face flags (always present in VCG faces with BitFlags).
template <class MeshT>
void toVcgMesh(const LevelMesh &level, MeshT &out, bool colourBySuperface, bool markFauxEdges)
{
	out.Clear();
	const size_t nv = level.positions.size() / 3, nf = level.triangles.size() / 3;
	auto vi = vcg::tri::Allocator<MeshT>::AddVertices(out, nv);
	for (size_t i = 0; i < nv; ++i, ++vi)
		vi->P() = typename MeshT::CoordType(level.positions[3 * i], level.positions[3 * i + 1],
		                                    level.positions[3 * i + 2]);
	auto fi = vcg::tri::Allocator<MeshT>::AddFaces(out, nf);
	for (size_t f = 0; f < nf; ++f, ++fi) {
		for (int k = 0; k < 3; ++k)
			fi->V(k) = &out.vert[size_t(level.triangles[3 * f + k])];
		if (markFauxEdges) {
			for (int k = 0; k < 3; ++k) {
				if (level.borderEdges[f] & (1u << k))
					fi->ClearF(k);
				else
					fi->SetF(k);
			}
		}
		if (colourBySuperface)
			fi->C() = superfaceColour(level.superface[f]);
	}
	vcg::tri::UpdateBounding<MeshT>::Box(out);
}

} // namespace gausslod
