// Levels as glTF 2.0 binary files (.glb) and a 3D Tiles 1.1 tileset of them (issue 40). The
// files are made by Debian's tinygltf (gltf_files.cpp); this header turns a level's VCG mesh,
// with the attributes the input carries (level_files.h), into the arrays glTF holds: a vertex per
// distinct (position, normal, colour, texture coordinate) of the corners, one primitive per
// material (texture and face colour), positions relative to the mesh's centre (the node's
// translation carries the centre, so that far-away coordinates keep their precision).
#pragma once

#include "gausslod/vcg_adapter.h"
#include "gausslod_io/io_mesh.h"

#include <wrap/io_trimesh/io_mask.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <tuple>
#include <vector>

namespace cli {

struct GltfMesh {
	double centre[3] = {0, 0, 0};
	std::vector<float> positions; ///< xyz per vertex, relative to centre
	std::vector<float> normals;   ///< xyz per vertex, or empty
	std::vector<float> colours;   ///< rgba per vertex (linear), or empty
	std::vector<float> uvs;       ///< uv per vertex (glTF's: v down), or empty
	struct Material {
		float colour[4] = {1, 1, 1, 1}; ///< linear
		int texture = -1;               ///< index into textures
	};
	std::vector<Material> materials;
	std::vector<std::vector<uint32_t>> primitives; ///< per material: its triangles' vertices
	std::vector<std::string> textures;             ///< image files (PNG or JPEG are embedded)
	double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};   ///< bounding box (model units)
	size_t faces() const
	{
		size_t n = 0;
		for (const auto &p : primitives)
			n += p.size() / 3;
		return n;
	}
};

/// An 8-bit sRGB value as a linear one (glTF's colours are linear).
inline float linearOfSrgb(unsigned char c)
{
	const double s = c / 255.0;
	return float(s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4));
}

/// Face colours become materials while there are at most this many; beyond (superface colours),
/// vertex colours.
constexpr size_t kMaxColourMaterials = 64;

namespace detail {

/// A colour as one number (a map key).
inline uint32_t colourKey(vcg::Color4b c) { return uint32_t(gausslod::detail::colourBits(c)); }

/// `out`'s bounding box and centre: those of `m`'s vertices.
template <class MeshT>
void gltfBox(const MeshT &m, GltfMesh &out)
{
	bool first = true;
	for (const auto &v : m.vert) {
		if (v.IsD())
			continue;
		for (int j = 0; j < 3; ++j) {
			const double x = v.cP()[j];
			out.lo[j] = first ? x : std::min(out.lo[j], x);
			out.hi[j] = first ? x : std::max(out.hi[j], x);
		}
		first = false;
	}
	for (int j = 0; j < 3; ++j)
		out.centre[j] = 0.5 * (out.lo[j] + out.hi[j]);
}

/// Whether `m`'s face colours are few enough to be materials (kMaxColourMaterials).
template <class MeshT>
bool fewFaceColours(const MeshT &m)
{
	std::map<uint32_t, int> colourIds;
	for (const auto &f : m.face)
		if (!f.IsD() && colourIds.size() <= kMaxColourMaterials)
			colourIds.emplace(colourKey(f.cC()), 0);
	return colourIds.size() <= kMaxColourMaterials;
}

/// The glTF vertices of a mesh's corners: one per distinct (vertex, colour, u, v), the first of
/// each VCG vertex in flat arrays, the further ones (seams, colour borders) in a map.
class GltfVertices {
public:
	struct Variant {
		uint32_t colour;
		float u, v;
		bool operator<(const Variant &o) const
		{
			return std::tie(colour, u, v) < std::tie(o.colour, o.u, o.v);
		}
		bool operator==(const Variant &o) const
		{
			return colour == o.colour && u == o.u && v == o.v;
		}
	};
	explicit GltfVertices(size_t vertices) : firstId_(vertices, UINT32_MAX), firstVariant_(vertices)
	{
	}
	/// The glTF vertex of VCG vertex `vi` with `var`; `added` says whether it is a new one.
	uint32_t id(size_t vi, const Variant &var, bool &added)
	{
		added = false;
		uint32_t id = firstId_[vi];
		if (id == UINT32_MAX) {
			id = firstId_[vi] = count_++, firstVariant_[vi] = var, added = true;
		} else if (!(firstVariant_[vi] == var)) {
			const auto f = furtherIds_.emplace(std::make_pair(vi, var), count_);
			id = f.first->second;
			if (f.second)
				++count_, added = true;
		}
		return id;
	}

private:
	std::vector<uint32_t> firstId_;
	std::vector<Variant> firstVariant_;
	std::map<std::pair<size_t, Variant>, uint32_t> furtherIds_;
	uint32_t count_ = 0;
};

/// Normals of unit length (glTF requires it): a zero one, of a vertex no face spans, made up.
inline void unitNormals(std::vector<float> &normals)
{
	for (size_t i = 0; i + 2 < normals.size(); i += 3) {
		const float l = std::sqrt(normals[i] * normals[i] + normals[i + 1] * normals[i + 1] +
		                          normals[i + 2] * normals[i + 2]);
		if (l > 0 && std::isfinite(l))
			for (int j = 0; j < 3; ++j)
				normals[i + size_t(j)] /= l;
		else
			normals[i] = 0, normals[i + 1] = 0, normals[i + 2] = 1;
	}
}

} // namespace detail

/// `m` (a level's VCG mesh, with the attributes `mask` names: vcg::tri::io::Mask bits) as glTF
/// arrays. `textures`: image files by texture index (as the mesh's wedge or vertex texture
/// coordinates index them).
template <class MeshT>
void toGltfMesh(const MeshT &m, int mask, const std::vector<std::string> &textures, GltfMesh &out)
{
	using Mask = vcg::tri::io::Mask;
	out = GltfMesh();
	out.textures = textures;
	const bool normals = mask & Mask::IOM_VERTNORMAL, vcol = mask & Mask::IOM_VERTCOLOR,
	           fcol = mask & Mask::IOM_FACECOLOR, wuv = mask & Mask::IOM_WEDGTEXCOORD,
	           vuv = !wuv && (mask & Mask::IOM_VERTTEXCOORD);
	detail::gltfBox(m, out);
	// face colours as materials when there are few of them
	const bool colourMaterials = fcol && detail::fewFaceColours(m);
	const bool colours = vcol || (fcol && !colourMaterials);
	std::map<std::pair<uint32_t, int>, int> materialIds; // (colour, texture) -> material
	detail::GltfVertices vertices(m.vert.size());
	for (const auto &f : m.face) {
		if (f.IsD())
			continue;
		int tex = -1;
		if ((wuv || vuv) && !textures.empty()) {
			tex = wuv ? f.cWT(0).n() : f.cV(0)->cT().n();
			if (tex < 0 || size_t(tex) >= textures.size())
				tex = textures.size() == 1 ? 0 : -1;
		}
		const vcg::Color4b fc = fcol ? f.cC() : vcg::Color4b(vcg::Color4b::White);
		const uint32_t fkey = colourMaterials ? detail::colourKey(fc) : 0xffffffffu;
		const auto mid = materialIds.emplace(std::make_pair(fkey, tex), int(out.materials.size()));
		if (mid.second) {
			GltfMesh::Material mat;
			if (colourMaterials)
				for (int j = 0; j < 4; ++j)
					mat.colour[j] = j < 3 ? linearOfSrgb(fc[j]) : fc[3] / 255.0f;
			mat.texture = tex;
			out.materials.push_back(mat);
			out.primitives.emplace_back();
		}
		std::vector<uint32_t> &prim = out.primitives[size_t(mid.first->second)];
		for (int k = 0; k < 3; ++k) {
			const auto *v = f.cV(k);
			const size_t vi = size_t(v - &m.vert[0]);
			vcg::Color4b c = vcg::Color4b(vcg::Color4b::White);
			if (vcol)
				c = v->cC();
			else if (colours)
				c = fc;
			const uint32_t ckey = colours ? detail::colourKey(c) : 0;
			float u = 0, w = 0;
			if (tex >= 0 || ((wuv || vuv) && textures.empty())) {
				const auto &t = wuv ? f.cWT(k) : v->cT();
				u = t.u(), w = 1.0f - t.v(); // (glTF's v runs down the image)
			}
			bool added = false;
			prim.push_back(vertices.id(vi, {ckey, u, w}, added));
			if (!added)
				continue;
			for (int j = 0; j < 3; ++j)
				out.positions.push_back(float(v->cP()[j] - out.centre[j]));
			if (normals)
				for (int j = 0; j < 3; ++j)
					out.normals.push_back(float(v->cN()[j]));
			if (colours)
				for (int j = 0; j < 4; ++j)
					out.colours.push_back(j < 3 ? linearOfSrgb(c[j]) : c[3] / 255.0f);
			if (wuv || vuv)
				out.uvs.insert(out.uvs.end(), {u, w});
		}
	}
	detail::unitNormals(out.normals);
}

/// Writes `meshes` as one binary glTF file at `path`: one node each. With more than one, the
/// first node is the full-detail one and lists the others (coarser, in order) in `MSFT_lod`,
/// with `coverage` (one per mesh: the screen coverage down to which each is shown) as its
/// `MSFT_screencoverage` extra; the extension is used, not required. Images that are PNG or
/// JPEG files are embedded; another kind, or one that cannot be read, leaves its material
/// untextured and is named in `warning`. False with `error` set if the file cannot be written.
/// `binary` false: a .gltf text file, the buffer (images included) as a data URI.
bool writeGlb(const std::vector<const GltfMesh *> &meshes, const std::vector<double> &coverage,
              const std::string &path, std::string &warning, std::string &error,
              bool binary = true);

/// One tile of a tileset: a level's glb (relative to the tileset's folder), its proven distance
/// to the source (model units) and its bounding box.
struct Tile {
	std::string content;
	double error = 0;
	int lod = 0;    ///< as renderers count: 0 = full detail (the leaf)
	int level = -1; ///< the paper's level index (-1: the input)
	size_t faces = 0;
	double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
};

/// A 3D Tiles 1.1 tileset.json's text: `tiles` (at least one) from the coarsest (the root) to the
/// full detail (the leaf, error 0), each the only child of the one before, refinement REPLACE, each
/// tile's geometricError its own error (what leaving it on screen costs), every bounding volume
/// the box of all tiles (glTF's y up turned to 3D Tiles' z up), `transform` (16 numbers, column
/// major) on the root if not empty, each tile's lod, paper level and faces in its extras
/// ("gausslod"). The tileset's own geometricError is the box's diagonal.
std::string tilesetJson(const std::vector<Tile> &tiles, const std::vector<double> &transform);

} // namespace cli
