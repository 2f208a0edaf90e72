// The gausslod tool's input mesh and level files: what a file carries besides its triangles
// (colours, texture coordinates, textures, materials, normals) is read with VCG's importers and
// written back into every level with VCG's exporters, each value copied from the input corner or
// face the level's corner or face replaces (gausslod/vcg_adapter.h); only those attributes are
// kept once the file is read (InputAttributes). Files without such attributes take the lean path
// (a plain binary PLY straight into the engine's arrays, else IoMesh; the fast PLY and STL
// writers of level_ply.h).
#pragma once

#include "cli.h"
#include "gltf_files.h"

#include "gausslod/vcg_adapter.h"
#include "gausslod_io/export_mesh.h"
#include "gausslod_io/import_mesh.h"
#include "gausslod_io/io_mesh.h"

#include <memory>
#include <set>
#include <string>
#include <vector>

namespace cli {

/// What the levels carry of an input with attributes (MeshAttributes), per vertex and face index
/// of its VCG mesh as read, without the rest of that mesh: the part of it toVcgMeshWithAttributes
/// reads (`vert[i]` and `face[i]` answer cC, cQ, cT and cC, cWT as the mesh's elements did). Only
/// the attributes the input has are stored (bumpy_1m with vertex colours: 2 MB, its VCG mesh
/// 173 MB). Not copyable: its element views point to it.
struct InputAttributes {
	std::vector<vcg::Color4b> vertColour, faceColour; ///< empty = none
	std::vector<float> vertQuality;
	std::vector<vcg::TexCoord2f> vertTex, wedgeTex; ///< wedgeTex: 3 per face
	std::vector<std::string> textures;              ///< the mesh's texture names
	struct Vertex {
		const InputAttributes *a;
		size_t i;
		vcg::Color4b cC() const { return a->vertColour[i]; }
		float cQ() const { return a->vertQuality[i]; }
		const vcg::TexCoord2f &cT() const { return a->vertTex[i]; }
	};
	struct Face {
		const InputAttributes *a;
		size_t i;
		vcg::Color4b cC() const { return a->faceColour[i]; }
		const vcg::TexCoord2f &cWT(int k) const { return a->wedgeTex[3 * i + size_t(k)]; }
	};
	template <class E>
	struct Elements {
		const InputAttributes *a;
		E operator[](size_t i) const { return E{a, i}; }
	};
	const Elements<Vertex> vert{this};
	const Elements<Face> face{this};
	InputAttributes() = default;
	InputAttributes(const InputAttributes &) = delete;
	InputAttributes &operator=(const InputAttributes &) = delete;
	/// The attributes `attrs` lists of `m`.
	void take(const gausslod::IoAttrMesh &m, const gausslod::MeshAttributes &attrs);
};

/// The input as the levels need it.
struct InputMesh {
	gausslod::FlatMesh flat;                                     ///< what the engine works on
	gausslod::MeshFormat format = gausslod::MeshFormat::Unknown; ///< of the input file
	std::string folder;                    ///< the input's folder (textures are relative to it)
	bool normals = false;                  ///< per-vertex normals (recomputed for each level)
	gausslod::MeshAttributes attrs;        ///< the attributes read (and carried)
	std::unique_ptr<InputAttributes> mesh; ///< what the levels carry of the input's
	                                       ///< VCG mesh (only with attributes)
	std::vector<vcg::tri::io::Material> materials; ///< OBJ: VCG's materials (map_Kd local)
	std::vector<int> faceMaterial;                 ///< OBJ: per VCG face as read
	std::vector<std::string> readNotes;            ///< what the reader skipped (ReadInfo::notes)
	bool hasColour() const
	{
		return attrs.vertColor || attrs.faceColor || attrs.vertTexCoord || attrs.wedgeTexCoord;
	}
};

/// Reads `path` (guarded VCG importers) and flattens it with the delimiters of `p`.
bool readInputMesh(const std::string &path, const gausslod::Params &p, InputMesh &in,
                   gausslod::ReadError &error);

/// Writes the levels of one input into one folder.
class LevelWriter {
public:
	/// `format` Unknown = the input's.
	LevelWriter(const InputMesh &in, const Options &o, const std::string &outdir);
	gausslod::MeshFormat format() const { return format_; }
	/// The level files' extension (ply, obj, off, stl, glb).
	std::string extension() const;
	/// glb: keep each level's glTF arrays (gltf()) for a file of the whole chain.
	void keepGltf() { keepGltf_ = true; }
	const std::vector<GltfMesh> &gltf() const { return gltf_; }
	/// The input's attributes the files carry, in a fixed order (vertex_normal, vertex_colour,
	/// vertex_quality, vertex_uv, wedge_uv, texture, face_colour).
	const std::vector<std::string> &attributes() const { return attributes_; }
	/// Faces coloured by superface.
	bool superfaceColours() const { return superfaceColours_; }
	/// Writes `level` as OUTDIR/<stem>_LOD<i>.<ext> (OBJ: and its <name>.mtl), each under a
	/// temporary name first. `files` gets the level's file (then its material file, if any);
	/// `vertices` the file's vertex count (with attributes a vertex of the engine's level is
	/// split where its corners' attributes differ).
	bool write(const gausslod::LevelMesh &level, const std::string &stem,
	           std::vector<std::string> &files, size_t &vertices, std::string &error) const;
	/// The same as OUTDIR/`name`.
	bool writeNamed(const gausslod::LevelMesh &level, const std::string &name,
	                std::vector<std::string> &files, size_t &vertices, std::string &error) const;

private:
	template <class MeshT>
	bool exportLevel(MeshT &mesh, const std::string &name, const std::vector<int> &sourceFaces,
	                 std::vector<std::string> &files, std::string &error) const;
	template <class MeshT>
	bool exportGltf(const MeshT &mesh, const std::string &name, std::vector<std::string> &files,
	                std::string &error) const;
	/// OBJ: the materials the faces use (the input's own where VCG reads the face's colour and
	/// texture back from it) and each face's.
	template <class MeshT>
	void objMaterials(const MeshT &mesh, const std::vector<int> &sourceFaces,
	                  std::vector<vcg::tri::io::Material> &materials,
	                  std::vector<int> &faceMaterial) const;
	template <class MeshT>
	bool exportObj(MeshT &mesh, const std::string &name, const std::vector<int> &sourceFaces,
	               std::vector<std::string> &files, std::string &error) const;
	/// OUTDIR/.<name>.part-<pid>: where a level file is written before it is moved to its name.
	std::string partPath(const std::string &name) const;
	/// The file written at `tmp` (if `written`) moved to OUTDIR/`name` and added to `files`; else,
	/// or if it cannot be moved, `tmp` removed and false (`error` says why).
	bool moveInto(const std::string &tmp, bool written, const std::string &name,
	              std::vector<std::string> &files, std::string &error) const;

	const InputMesh &in_;
	std::string outdir_;
	gausslod::MeshFormat format_;
	gausslod::MeshAttributes outAttrs_; // what is copied from the input
	bool superfaceColours_ = false;
	int mask_ = 0;                      // vcg::tri::io::Mask bits written
	std::vector<std::string> textures_; // names as written (relative to OUTDIR)
	std::vector<std::string> attributes_;
	bool glb_ = false; // glTF: binary (glb) or text (gltfText_)
	bool gltfText_ = false;
	bool keepGltf_ = false;
	mutable std::vector<GltfMesh> gltf_;     // (keepGltf)
	mutable std::set<std::string> warnings_; // said once
};

} // namespace cli
