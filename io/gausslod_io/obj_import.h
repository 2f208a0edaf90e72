// VCG 2020.09's Wavefront OBJ importer (wrap/io_trimesh/import_obj.h), made to read OBJ files.
//
// Its defect: SplitToken() turns a face's 1-based OBJ indices into 0-based ones, and
// GoodObjIndex() then refuses index 0 ("indices must start from 1"). So every face that uses the
// file's first vertex (or first texture coordinate, or first normal) is dropped, silently in a
// build with NDEBUG, and in Debian's MeshLab (built without NDEBUG) by the face-count assertion
// that follows, which aborts. GAUSSLOD_FIX_VCG_OBJ_INDICES(MeshT) gives ImporterOBJ<MeshT> a
// GoodObjIndex() for 0-based indices (an explicit specialization: the VCG header is used as is).
//
// The importer also trusts its input: it reads m.vert[index] before it checks a face's index, it
// writes one vertex per "v" statement into an array sized by its first pass (which counts lines,
// not statements), and it reads texture coordinates and ZBrush colours by index unchecked.
// checkObjForVcg() reads the file with the importer's own tokenizer first and refuses, with a
// message, every file on which the importer would read or write out of bounds or drop a face.
#pragma once

#include <vcg/complex/complex.h>
#include <wrap/io_trimesh/import_obj.h>

#include <cstdlib>
#include <fstream>
#include <string>
#include <type_traits>
#include <vector>

namespace gausslod {
namespace obj {

/// True once GAUSSLOD_FIX_VCG_OBJ_INDICES(MeshT) has been expanded in this translation unit.
template <class MeshT>
struct IndexFixFor : std::false_type {
};

/// An index as SplitToken() makes it (OBJ's index - 1; OBJ's relative -k becomes -k-1) resolved
/// against `count` items read so far; true if it then names one of them.
inline bool resolveIndex(int &index, int count)
{
	if (index < 0)
		index += count + 1;
	return index >= 0 && index < count;
}

/// A face corner is "v", "v/t", "v//n" or "v/t/n" with optional '-' and at most 9 digits each
/// (atoi() of anything else gives an index nobody wrote).
inline bool isCornerToken(const std::string &token)
{
	int field = 0, digits = 0;
	bool sign = false;
	for (size_t i = 0; i <= token.size(); ++i) {
		const char c = i < token.size() ? token[i] : '/';
		if (c == '/') {
			if (digits == 0 && (field == 0 || sign))
				return false; // the vertex index is required; "-" alone is no index
			if (++field > 3)
				return false;
			digits = 0, sign = false;
		} else if (c == '-' && digits == 0 && !sign) {
			sign = true;
		} else if (c >= '0' && c <= '9' && digits < 9) {
			++digits;
		} else {
			return false;
		}
	}
	return true;
}

/// Reads `path` as ImporterOBJ<MeshT>::Open() will, after its LoadMask() filled `oi`; false with
/// `error` set if Open() would go out of bounds or drop a face on it.
template <class MeshT>
bool checkObjForVcg(const char *path, const typename vcg::tri::io::ImporterOBJ<MeshT>::Info &oi,
                    std::string &error)
{
	using Obj = vcg::tri::io::ImporterOBJ<MeshT>;
	using Mask = vcg::tri::io::Mask;
	std::ifstream stream(path);
	if (!stream) {
		error = "cannot open the file";
		return false;
	}
	const bool readsNormals = (oi.mask & (Mask::IOM_WEDGNORMAL | Mask::IOM_VERTNORMAL)) != 0;
	std::vector<std::string> tokens;
	std::string line;
	std::vector<vcg::Color4b> zbrushColours;
	int vertices = 0, texCoords = 0, normals = 0, faces = 0;
	while (!stream.eof()) {
		tokens.clear();
		Obj::TokenizeNextLine(stream, tokens, line, &zbrushColours);
		if (tokens.empty())
			continue;
		const std::string &h = tokens[0];
		if (h == "v") {
			if (++vertices > oi.numVertices)
				break; // reported below: Open() would write past its vertex array
		} else if (h == "vt") {
			++texCoords;
		} else if (h == "vn") {
			++normals;
		} else if (h == "l" && tokens.size() >= 3) {
			for (int k = 1; k <= 2; ++k) { // the importer links the first two, as 0-based indices
				const int i = std::atoi(tokens[k].c_str()) - 1;
				if (!isCornerToken(tokens[k]) || i < 0 || i >= oi.numVertices) {
					error = "line statement \"" + line + "\": '" + tokens[k] +
					        "' is not one of the file's " + std::to_string(oi.numVertices) +
					        " vertices";
					return false;
				}
			}
		} else if ((h == "f" || h == "q") && tokens.size() >= 4) {
			++faces;
			auto where = [&] { return "face " + std::to_string(faces) + " (\"" + line + "\"): "; };
			for (size_t k = 1; k < tokens.size(); ++k) {
				if (!isCornerToken(tokens[k])) {
					error = where() + "'" + tokens[k] + "' is not a vertex reference";
					return false;
				}
				int v, n, t;
				Obj::SplitToken(tokens[k], v, n, t, oi.mask);
				if (h == "q")
					++v; // QOBJ's indices are 0-based
				if (!resolveIndex(v, vertices)) {
					error = where() + "vertex " + tokens[k] + " is not among the " +
					        std::to_string(vertices) + " vertices defined before it";
					return false;
				}
				// as Open(): texture coordinates count over the whole file, normals so far
				if (oi.numTexCoords > 0 && !resolveIndex(t, oi.numTexCoords)) {
					error = where() + "texture coordinate of " + tokens[k] + " is not among the " +
					        std::to_string(oi.numTexCoords) + " of the file";
					return false;
				}
				if (readsNormals && !resolveIndex(n, normals)) {
					error = where() + "normal of " + tokens[k] + " is not among the " +
					        std::to_string(normals) + " normals defined before it";
					return false;
				}
			}
		}
	}
	if (vertices != oi.numVertices || texCoords != oi.numTexCoords) {
		error = "the file has " + std::to_string(vertices) + " vertex and " +
		        std::to_string(texCoords) + " texture coordinate statements where their lines " +
		        "count " + std::to_string(oi.numVertices) + " and " +
		        std::to_string(oi.numTexCoords) +
		        " (a 'v' or 'vt' line indented or continued with '\\' is not supported)";
		return false;
	}
	if (!zbrushColours.empty() && zbrushColours.size() < size_t(vertices)) {
		error = "its ZBrush '#MRGB' comments colour " + std::to_string(zbrushColours.size()) +
		        " of its " + std::to_string(vertices) + " vertices";
		return false;
	}
	return true;
}

/// With as many `vt` as `v` lines VCG's Open reads texture coordinates per vertex, but only at
/// face corners (import_obj.h:682-687): a vertex no face uses keeps what TexCoord2's constructor
/// leaves unset. Such vertices get (0, 0), texture 0 (`mask`: the load mask Open read with).
template <class MeshT>
void settleUnusedVertexTexCoords(MeshT &m, int mask)
{
	if (!(mask & vcg::tri::io::Mask::IOM_VERTTEXCOORD) || !vcg::tri::HasPerVertexTexCoord(m))
		return;
	std::vector<unsigned char> used(m.vert.size());
	for (const auto &f : m.face)
		if (!f.IsD())
			for (int k = 0; k < 3; ++k)
				used[size_t(f.cV(k) - m.vert.data())] = 1;
	for (size_t i = 0; i < m.vert.size(); ++i)
		if (!used[i])
			m.vert[i].T() = typename MeshT::VertexType::TexCoordType(0, 0);
}

} // namespace obj
} // namespace gausslod

/// Expand once, at namespace scope, before the first use of ImporterOBJ<MeshT> in a translation
/// unit. The specialization is inline: build the code that uses it with hidden visibility, so that
/// no other module's copy of the defective function can be bound in its place.
#define GAUSSLOD_FIX_VCG_OBJ_INDICES(MeshT)                                                        \
	namespace vcg {                                                                                \
	namespace tri {                                                                                \
	namespace io {                                                                                 \
	template <>                                                                                    \
	inline bool ImporterOBJ<MeshT>::GoodObjIndex(int &index, const int maxVal)                     \
	{                                                                                              \
		return gausslod::obj::resolveIndex(index, maxVal);                                         \
	}                                                                                              \
	}                                                                                              \
	}                                                                                              \
	}                                                                                              \
	namespace gausslod {                                                                           \
	namespace obj {                                                                                \
	template <>                                                                                    \
	struct IndexFixFor<MeshT> : std::true_type {                                                   \
	};                                                                                             \
	}                                                                                              \
	}
