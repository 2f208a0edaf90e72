// GaussLOD <-> VCG meshes: the engine works on flat arrays; these templates copy any VCG triangle
// mesh type (CMeshO in MeshLab, a plain vcg::tri::TriMesh in tests and tools) in and out.
#pragma once

#include "gausslod.h"

#include <vcg/complex/complex.h>

#include <array>
#include <cmath>
#include <cstring>
#include <unordered_map>
#include <vector>

namespace gausslod {

/// Flat copy of a VCG mesh, skipping deleted elements (indices are remapped); with attributes
/// (flattenWithAttributes) also the delimiter keys and texture coordinates of MeshView, and
/// where each flat vertex and face came from.
struct FlatMesh {
	std::vector<double> positions;
	std::vector<int32_t> triangles;
	std::vector<uint32_t> faceKey, cornerKey;  ///< empty = none (see MeshView)
	std::vector<float> cornerUV;               ///< empty = none (see MeshView)
	std::vector<uint8_t> keepFace;             ///< empty = none (see MeshView)
	std::vector<int32_t> vertIndex, faceIndex; ///< VCG index per flat vertex / face (attributes)
	MeshView view() const
	{
		MeshView v;
		v.positions = positions.data();
		v.vertexCount = positions.size() / 3;
		v.triangles = triangles.data();
		v.faceCount = triangles.size() / 3;
		v.faceKey = faceKey.empty() ? nullptr : faceKey.data();
		v.cornerKey = cornerKey.empty() ? nullptr : cornerKey.data();
		v.cornerUV = cornerUV.empty() ? nullptr : cornerUV.data();
		v.keepFace = keepFace.empty() ? nullptr : keepFace.data();
		v.wantSources = !faceIndex.empty();
		return v;
	}
};

/// The attributes a VCG mesh carries (in MeshLab its layer's data mask, for files the
/// importer's mask): only these are read and carried.
struct MeshAttributes {
	bool vertColor = false, vertQuality = false, vertTexCoord = false, vertNormal = false;
	bool wedgeTexCoord = false, faceColor = false;
	/// vertex texture indices tell textures apart (set with more than one texture: VCG's PLY
	/// reader, MeshLab's too, leaves them unset, and with one texture they name nothing)
	bool vertTexIndex = false;
	bool perVertex() const { return vertColor || vertQuality || vertTexCoord; }
	bool any() const { return perVertex() || vertNormal || wedgeTexCoord || faceColor; }
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

namespace detail {

/// Dense ids for distinct values (exact: equal bit patterns, so a NaN equals itself).
template <class Key>
struct IdMap {
	struct Hash {
		size_t operator()(const Key &k) const
		{
			uint64_t h = 1469598103934665603ull;
			for (const uint64_t w : k.w)
				h = (h ^ w) * 1099511628211ull, h ^= h >> 29;
			return size_t(h);
		}
	};
	struct Eq {
		bool operator()(const Key &a, const Key &b) const { return a.w == b.w; }
	};
	std::unordered_map<Key, uint32_t, Hash, Eq> ids;
	uint32_t next = 0;
	uint32_t operator()(const Key &k)
	{
		const auto r = ids.emplace(k, next);
		next += r.second;
		return r.first->second;
	}
};
struct Words2 {
	std::array<uint64_t, 2> w;
};
struct Words3 {
	std::array<uint64_t, 3> w;
};
inline uint64_t floatBits(float a, float b)
{
	uint32_t x, y;
	std::memcpy(&x, &a, 4), std::memcpy(&y, &b, 4);
	return uint64_t(x) << 32 | y;
}
inline uint64_t floatBits(float a) { return floatBits(a, 0.f); }
template <class Colour>
uint64_t colourBits(const Colour &c)
{
	return uint64_t(c[0]) | uint64_t(c[1]) << 8 | uint64_t(c[2]) << 16 | uint64_t(c[3]) << 24;
}

/// The per-vertex attributes of `v` that `attrs` lists, as a key (exact bit patterns).
template <class Vertex>
Words3 vertexAttributeKey(const Vertex &v, const MeshAttributes &attrs)
{
	Words3 k{{0, 0, 0}};
	if (attrs.vertColor)
		k.w[0] = colourBits(v.cC());
	if (attrs.vertQuality)
		k.w[0] |= floatBits(float(v.cQ())) & 0xffffffff00000000ull;
	if (attrs.vertTexCoord)
		k.w[1] = floatBits(v.cT().u(), v.cT().v()),
		k.w[2] = attrs.vertTexIndex ? uint16_t(v.cT().n()) : 0;
	return k;
}

} // namespace detail

/// Adds to `out = flatten(m)` what keeps attributes exact: with `attrs` set, face keys from
/// materials (texture index, face colour; Params::keepMaterials), the selection (`selectedOnly`:
/// every unselected face is kept as it is, MeshView::keepFace), corner keys from texture
/// coordinates and per-vertex colour / quality of the corner's own vertex (Params::keepSeams),
/// the corners' texture coordinates, and the sources asked for. Normals are never keys.
template <class MeshT>
void addAttributes(const MeshT &m, const MeshAttributes &attrs, const Params &params,
                   bool selectedOnly, FlatMesh &out)
{
	if (!attrs.any() && !selectedOnly)
		return;
	for (size_t i = 0; i < m.vert.size(); ++i)
		if (!m.vert[i].IsD())
			out.vertIndex.push_back(int32_t(i));
	for (size_t i = 0; i < m.face.size(); ++i)
		if (!m.face[i].IsD())
			out.faceIndex.push_back(int32_t(i));
	const size_t nF = out.faceIndex.size();
	auto face = [&](size_t f) -> const typename MeshT::FaceType & {
		return m.face[size_t(out.faceIndex[f])];
	};
	if (selectedOnly) {
		out.keepFace.resize(nF);
		for (size_t f = 0; f < nF; ++f)
			out.keepFace[f] = face(f).IsS() ? 0 : 1;
	}
	const bool materials = params.keepMaterials && (attrs.faceColor || attrs.wedgeTexCoord);
	if (materials) {
		out.faceKey.resize(nF);
		detail::IdMap<detail::Words2> id;
		for (size_t f = 0; f < nF; ++f) {
			const auto &fc = face(f);
			detail::Words2 k{{0, 0}};
			k.w[0] = (attrs.faceColor ? detail::colourBits(fc.cC()) : 0) << 16 |
			         uint64_t(uint16_t(attrs.wedgeTexCoord ? fc.cWT(0).n() : 0));
			out.faceKey[f] = id(k);
		}
	}
	if (params.keepSeams && (attrs.perVertex() || attrs.wedgeTexCoord)) {
		std::vector<uint32_t> vertexKey(m.vert.size(), 0);
		if (attrs.perVertex()) {
			detail::IdMap<detail::Words3> id;
			for (size_t i = 0; i < m.vert.size(); ++i) {
				const auto &v = m.vert[i];
				if (!v.IsD())
					vertexKey[i] = id(detail::vertexAttributeKey(v, attrs));
			}
		}
		out.cornerKey.resize(3 * nF);
		detail::IdMap<detail::Words2> id;
		for (size_t f = 0; f < nF; ++f)
			for (int k = 0; k < 3; ++k) {
				const auto &fc = face(f);
				detail::Words2 key{{vertexKey[vcg::tri::Index(m, fc.cV(k))], 0}};
				if (attrs.wedgeTexCoord)
					key.w[0] |= uint64_t(uint16_t(fc.cWT(k).n())) << 32,
					    key.w[1] = detail::floatBits(fc.cWT(k).u(), fc.cWT(k).v());
				out.cornerKey[3 * f + size_t(k)] = id(key);
			}
	}
	if (attrs.wedgeTexCoord || attrs.vertTexCoord) {
		out.cornerUV.resize(6 * nF);
		for (size_t f = 0; f < nF; ++f)
			for (int k = 0; k < 3; ++k) {
				const auto &fc = face(f);
				const auto &t = attrs.wedgeTexCoord ? fc.cWT(k) : fc.cV(k)->cT();
				out.cornerUV[6 * f + 2 * size_t(k)] = t.u();
				out.cornerUV[6 * f + 2 * size_t(k) + 1] = t.v();
			}
	}
}

/// flatten() and addAttributes() in one.
template <class MeshT>
FlatMesh flattenWithAttributes(const MeshT &m, const MeshAttributes &attrs, const Params &params,
                               bool selectedOnly = false)
{
	FlatMesh out = flatten(m);
	addAttributes(m, attrs, params, selectedOnly, out);
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

/// toVcgMesh for a level of `flat = flattenWithAttributes(in, attrs, ...)`: carries what `attrs`
/// lists, each value copied from the level's source corner or face (LevelMesh::sourceCorner,
/// sourceFace), never invented. With per-vertex attributes an output vertex is the input vertex
/// of its source corner (a welded vertex with different colours or coordinates stays split);
/// positions are the level's. Per-vertex normals are not copied: the caller recomputes them for
/// the new faces. Face colours are the input's when it has them, else (colourBySuperface) the
/// superface colours. `out` needs the components of `attrs` enabled.
template <class InT, class OutT>
void toVcgMeshWithAttributes(const LevelMesh &level, const FlatMesh &flat, const InT &in,
                             const MeshAttributes &attrs, OutT &out, bool colourBySuperface,
                             bool markFauxEdges)
{
	if (level.sourceCorner.size() != level.triangles.size() || flat.faceIndex.empty()) {
		toVcgMesh(level, out, colourBySuperface, markFauxEdges);
		return;
	}
	out.Clear();
	const size_t nf = level.triangles.size() / 3;
	// one output vertex per level vertex and distinct per-vertex attributes of the input
	// vertices its corners copy (welded copies with equal values stay one vertex)
	std::vector<uint32_t> attrId; // per flat vertex
	if (attrs.perVertex()) {
		detail::IdMap<detail::Words3> id;
		attrId.resize(flat.vertIndex.size());
		for (size_t i = 0; i < attrId.size(); ++i)
			attrId[i] = id(detail::vertexAttributeKey(in.vert[size_t(flat.vertIndex[i])], attrs));
	}
	// the first attribute set of each level vertex in flat arrays; the further ones (welded
	// copies with other values, along seams) in a map
	std::vector<int32_t> vertexOf(level.positions.size() / 3, -1);
	std::vector<uint32_t> firstAttr(attrs.perVertex() ? vertexOf.size() : 0);
	std::unordered_map<uint64_t, int32_t> further;
	std::vector<int32_t> corner(3 * nf), levelVertex;
	for (size_t c = 0; c < 3 * nf; ++c) {
		const int32_t lv = level.triangles[c];
		int32_t *slot = &vertexOf[size_t(lv)];
		if (attrs.perVertex()) {
			const uint32_t a = attrId[size_t(flat.triangles[size_t(level.sourceCorner[c])])];
			if (*slot < 0)
				firstAttr[size_t(lv)] = a;
			else if (firstAttr[size_t(lv)] != a)
				slot = &further.emplace(uint64_t(uint32_t(lv)) << 32 | a, -1).first->second;
		}
		if (*slot < 0) {
			*slot = int32_t(levelVertex.size());
			levelVertex.push_back(lv);
		}
		corner[c] = *slot;
	}
	auto vi = vcg::tri::Allocator<OutT>::AddVertices(out, levelVertex.size());
	std::vector<int32_t> origin(levelVertex.size()); // an input (flat) vertex of each output one
	std::vector<size_t> originCorner(levelVertex.size()); // (and a level corner of it)
	for (size_t c = 0; c < 3 * nf; ++c) {
		origin[size_t(corner[c])] = flat.triangles[size_t(level.sourceCorner[c])];
		originCorner[size_t(corner[c])] = c;
	}
	const bool newUV = level.cornerUV.size() == 2 * level.triangles.size();
	for (size_t i = 0; i < levelVertex.size(); ++i, ++vi) {
		const double *p = &level.positions[3 * size_t(levelVertex[i])];
		vi->P() = typename OutT::CoordType(p[0], p[1], p[2]);
		const auto &v = in.vert[size_t(flat.vertIndex[size_t(origin[i])])];
		if (attrs.vertColor)
			vi->C() = v.cC();
		if (attrs.vertQuality)
			vi->Q() = v.cQ();
		if (attrs.vertTexCoord) {
			vi->T() = v.cT();
			if (newUV) { // (a corner with new coordinates has its own source: its own vertex)
				vi->T().U() = level.cornerUV[2 * originCorner[i]];
				vi->T().V() = level.cornerUV[2 * originCorner[i] + 1];
			}
		}
	}
	auto fi = vcg::tri::Allocator<OutT>::AddFaces(out, nf);
	for (size_t f = 0; f < nf; ++f, ++fi) {
		const auto &src = in.face[size_t(flat.faceIndex[size_t(level.sourceFace[f])])];
		for (int k = 0; k < 3; ++k) {
			fi->V(k) = &out.vert[size_t(corner[3 * f + size_t(k)])];
			if (attrs.wedgeTexCoord) {
				const int32_t sc = level.sourceCorner[3 * f + size_t(k)];
				fi->WT(k) = in.face[size_t(flat.faceIndex[size_t(sc / 3)])].cWT(sc % 3);
				if (newUV) { // (the level's own coordinates)
					fi->WT(k).U() = level.cornerUV[2 * (3 * f + size_t(k))];
					fi->WT(k).V() = level.cornerUV[2 * (3 * f + size_t(k)) + 1];
				}
			}
			if (markFauxEdges) {
				if (level.borderEdges[f] & (1u << k))
					fi->ClearF(k);
				else
					fi->SetF(k);
			}
		}
		if (attrs.faceColor)
			fi->C() = src.cC();
		else if (colourBySuperface)
			fi->C() = superfaceColour(level.superface[f]);
	}
	vcg::tri::UpdateBounding<OutT>::Box(out);
}

} // namespace gausslod
