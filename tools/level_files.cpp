// The gausslod tool's input mesh and level files (level_files.h).
#include "level_files.h"

#include "gausslod_io/level_ply.h"
#include "gausslod_io/texture_paths.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <dirent.h>
#include <map>
#include <sys/stat.h>
#include <tuple>
#include <unistd.h>

namespace cli {

namespace {

using Mask = vcg::tri::io::Mask;
using gausslod::MeshFormat;
using vcg::tri::io::Material;

// The attributes that need the richer mesh type (normals alone do not: they are recomputed).
const int kAttributeMask = Mask::IOM_VERTCOLOR | Mask::IOM_VERTQUALITY | Mask::IOM_VERTTEXCOORD |
                           Mask::IOM_WEDGTEXCOORD | Mask::IOM_FACECOLOR;

// The colour byte VCG's OBJ importer makes of a material value v as export_obj.h writes it
// ("%f"; import_obj.h: (unsigned char)(float * 255.0)).
unsigned char objByte(float v)
{
	char text[64];
	std::snprintf(text, sizeof text, "%f", double(v));
	return (unsigned char)(float(std::atof(text)) * 255.0);
}

// The face colour VCG's OBJ importer gives a face of material `m`.
vcg::Color4b objColour(const Material &m)
{
	return vcg::Color4b(objByte(m.Kd[0]), objByte(m.Kd[1]), objByte(m.Kd[2]), objByte(m.Tr));
}

// A material value that VCG's OBJ importer reads back as the byte c: the middle of c's interval
// (c/255 written with 6 decimals would be read back as c-1 for about half of the bytes).
float objValue(unsigned char c) { return c == 255 ? 1.0f : (float(c) + 0.5f) / 255.0f; }

bool removeTree(const std::string &path)
{
	struct stat st;
	if (::lstat(path.c_str(), &st) != 0)
		return false;
	if (S_ISDIR(st.st_mode)) {
		if (DIR *d = opendir(path.c_str())) {
			while (const dirent *e = readdir(d)) {
				const std::string n = e->d_name;
				if (n != "." && n != "..")
					std::remove((path + "/" + n).c_str());
			}
			closedir(d);
		}
		return ::rmdir(path.c_str()) == 0;
	}
	return std::remove(path.c_str()) == 0;
}

} // namespace

bool readInputMesh(const std::string &path, const gausslod::Params &p, InputMesh &in,
                   gausslod::ReadError &error)
{
	in = InputMesh();
	in.format = gausslod::formatOfFile(path);
	in.folder = gausslod::folderOf(path);
	gausslod::ReadInfo info;
	std::unique_ptr<gausslod::IoAttrMesh> full(new gausslod::IoAttrMesh);
	bool withAttributes = false;
	{ // the lean mesh is freed once flattened (the engine works on the flat arrays)
		gausslod::IoMesh lean;
		gausslod::detail::FlatRead flat; // (a plain binary PLY: read without a VCG mesh)
		if (!gausslod::importMeshEither(lean, *full, withAttributes, path, kAttributeMask, error,
		                                &info, &flat))
			return false;
		in.readNotes = info.notes;
		in.normals = (info.mask & Mask::IOM_VERTNORMAL) != 0;
		if (flat.used) {
			in.flat.positions = std::move(flat.positions);
			in.flat.triangles = std::move(flat.triangles);
			return true;
		}
		if (!withAttributes) {
			in.flat = gausslod::flatten(lean);
			return true;
		}
	}
	gausslod::MeshAttributes &a = in.attrs;
	a.vertColor = (info.mask & Mask::IOM_VERTCOLOR) != 0;
	a.vertQuality = (info.mask & Mask::IOM_VERTQUALITY) != 0;
	a.vertTexCoord = (info.mask & Mask::IOM_VERTTEXCOORD) != 0;
	a.vertTexIndex = a.vertTexCoord && full->textures.size() > 1;
	a.wedgeTexCoord = (info.mask & Mask::IOM_WEDGTEXCOORD) != 0;
	a.faceColor = (info.mask & Mask::IOM_FACECOLOR) != 0;
	a.vertNormal = in.normals;
	for (std::string &t : full->textures)
		t = gausslod::localTextureName(t, in.folder);
	in.materials = std::move(info.materials);
	for (Material &m : in.materials)
		m.map_Kd = m.map_Kd.empty() ? m.map_Kd : gausslod::localTextureName(m.map_Kd, in.folder);
	in.faceMaterial = std::move(info.faceMaterial);
	in.flat = gausslod::flattenWithAttributes(*full, a, p);
	in.mesh.reset(new InputAttributes());
	in.mesh->take(*full, a); // (the VCG mesh is freed on return)
	return true;
}

void InputAttributes::take(const gausslod::IoAttrMesh &m, const gausslod::MeshAttributes &attrs)
{
	textures = m.textures;
	auto copy = [](bool wanted, size_t n, auto &out, auto value) {
		if (!wanted)
			return;
		out.resize(n);
		for (size_t i = 0; i < n; ++i)
			out[i] = value(i);
	};
	const size_t nv = m.vert.size(), nf = m.face.size();
	copy(attrs.vertColor, nv, vertColour, [&](size_t i) { return m.vert[i].cC(); });
	copy(attrs.vertQuality, nv, vertQuality, [&](size_t i) { return m.vert[i].cQ(); });
	copy(attrs.vertTexCoord, nv, vertTex, [&](size_t i) { return m.vert[i].cT(); });
	copy(attrs.faceColor, nf, faceColour, [&](size_t i) { return m.face[i].cC(); });
	copy(attrs.wedgeTexCoord, 3 * nf, wedgeTex,
	     [&](size_t i) { return m.face[i / 3].cWT(int(i % 3)); });
}

LevelWriter::LevelWriter(const InputMesh &in, const Options &o, const std::string &outdir)
    : in_(in), outdir_(outdir)
{
	glb_ = o.format == "glb" || o.format == "gltf";
	gltfText_ = o.format == "gltf";
	// (glb holds what PLY holds: its attributes are chosen as for PLY)
	format_ = glb_ || o.format.empty() ? in.format : gausslod::formatNamed(o.format);
	if (format_ == MeshFormat::Unknown || glb_)
		format_ = MeshFormat::Ply;
	outAttrs_ = in.attrs;
	if (o.overwriteColours)
		outAttrs_.vertColor = outAttrs_.faceColor = false;
	// (glb: a renderer's file shows the surface's own colours, superfaces only when asked)
	superfaceColours_ = o.colour && (o.overwriteColours || (!in.hasColour() && !glb_));
	const gausslod::MeshAttributes &a = outAttrs_;
	int mask = Mask::IOM_VERTCOORD | Mask::IOM_FACEINDEX;
	mask |= in.normals ? int(Mask::IOM_VERTNORMAL) : 0;
	mask |= a.vertColor ? int(Mask::IOM_VERTCOLOR) : 0;
	mask |= a.vertQuality ? int(Mask::IOM_VERTQUALITY) : 0;
	mask |= a.vertTexCoord ? int(Mask::IOM_VERTTEXCOORD) : 0;
	mask |= a.wedgeTexCoord ? int(Mask::IOM_WEDGTEXCOORD) : 0;
	mask |= a.faceColor || superfaceColours_ ? int(Mask::IOM_FACECOLOR) : 0;
	mask_ = gausslod::formatMask(format_, mask);
	const bool uv = mask_ & (Mask::IOM_VERTTEXCOORD | Mask::IOM_WEDGTEXCOORD);
	if (in.mesh && uv)
		for (const std::string &t : in.mesh->textures)
			textures_.push_back(gausslod::textureNameFrom(outdir, in.folder, t));
	const std::pair<int, const char *> names[] = {{Mask::IOM_VERTNORMAL, "vertex_normal"},
	                                              {Mask::IOM_VERTCOLOR, "vertex_colour"},
	                                              {Mask::IOM_VERTQUALITY, "vertex_quality"},
	                                              {Mask::IOM_VERTTEXCOORD, "vertex_uv"},
	                                              {Mask::IOM_WEDGTEXCOORD, "wedge_uv"}};
	for (const auto &n : names)
		if (mask_ & n.first)
			attributes_.push_back(n.second);
	if (!textures_.empty())
		attributes_.push_back("texture");
	if ((mask_ & Mask::IOM_FACECOLOR) && a.faceColor)
		attributes_.push_back("face_colour");
}

template <class MeshT>
bool LevelWriter::exportLevel(MeshT &mesh, const std::string &name,
                              const std::vector<int> &sourceFaces, std::vector<std::string> &files,
                              std::string &error) const
{
	if (in_.normals && (mask_ & Mask::IOM_VERTNORMAL))
		vcg::tri::UpdateNormal<MeshT>::PerVertexNormalized(mesh);
	mesh.textures = textures_;
	if (glb_)
		return exportGltf(mesh, name, files, error);
	if (format_ == MeshFormat::Obj)
		return exportObj(mesh, name, sourceFaces, files, error);
	const std::string tmp = partPath(name);
	return moveInto(tmp, gausslod::exportMesh(mesh, tmp, format_, mask_, {}, {}, error), name,
	                files, error);
}

template <class MeshT>
bool LevelWriter::exportGltf(const MeshT &mesh, const std::string &name,
                             std::vector<std::string> &files, std::string &error) const
{
	// (texture names are relative to OUTDIR: the images are read to be embedded)
	std::vector<std::string> images;
	for (const std::string &t : textures_)
		images.push_back(!t.empty() && t[0] == '/' ? t : outdir_ + "/" + t);
	GltfMesh g;
	toGltfMesh(mesh, mask_, images, g);
	const std::string tmp = partPath(name);
	std::string warning;
	const bool written = writeGlb({&g}, {}, tmp, warning, error, !gltfText_);
	if (written && !warning.empty() && warnings_.insert(warning).second)
		std::fprintf(stderr, "gausslod: %s\n", warning.c_str());
	if (!moveInto(tmp, written, name, files, error))
		return false;
	if (keepGltf_)
		gltf_.push_back(std::move(g));
	return true;
}

template <class MeshT>
void LevelWriter::objMaterials(const MeshT &mesh, const std::vector<int> &sourceFaces,
                               std::vector<Material> &materials,
                               std::vector<int> &faceMaterial) const
{
	faceMaterial.assign(mesh.face.size(), 0);
	std::map<std::tuple<int, uint32_t, int>, int> ids;
	const bool faceColour = (mask_ & Mask::IOM_FACECOLOR) != 0;
	const bool uv = (mask_ & (Mask::IOM_WEDGTEXCOORD | Mask::IOM_VERTTEXCOORD)) != 0;
	for (size_t f = 0; f < mesh.face.size(); ++f) {
		const auto &fc = mesh.face[f];
		const vcg::Color4b c = faceColour ? fc.cC() : vcg::Color4b(vcg::Color4b::White);
		int tex = -1;
		if (uv && !textures_.empty()) {
			tex = (mask_ & Mask::IOM_WEDGTEXCOORD) ? fc.cWT(0).n() : fc.cV(0)->cT().n();
			if (tex < 0 || size_t(tex) >= textures_.size())
				tex = textures_.size() == 1 ? 0 : -1;
		}
		// the input's own material when VCG reads this face's colour and texture back from it
		int source = -1;
		if (f < sourceFaces.size() && sourceFaces[f] >= 0 &&
		    size_t(sourceFaces[f]) < in_.faceMaterial.size()) {
			const int m = in_.faceMaterial[size_t(sourceFaces[f])];
			if (m >= 0 && size_t(m) < in_.materials.size() &&
			    (!faceColour || objColour(in_.materials[size_t(m)]) == c) &&
			    (!uv || int(in_.materials[size_t(m)].index) == tex ||
			     (tex < 0 && in_.materials[size_t(m)].map_Kd.empty())))
				source = m;
		}
		const uint32_t key = source >= 0 ? 0 : detail::colourKey(c);
		const auto id = ids.emplace(std::make_tuple(source, key, source >= 0 ? -1 : tex),
		                            int(materials.size()));
		if (id.second) {
			Material m;
			if (source >= 0) {
				m = in_.materials[size_t(source)];
				m.map_Kd = tex >= 0 ? textures_[size_t(tex)] : std::string();
			} else {
				if (faceColour) {
					m.Kd = vcg::Point3f(objValue(c[0]), objValue(c[1]), objValue(c[2]));
					m.Tr = objValue(c[3]);
				}
				m.map_Kd = tex >= 0 ? textures_[size_t(tex)] : std::string();
			}
			m.index = (unsigned int)(tex);
			materials.push_back(m);
		}
		faceMaterial[f] = id.first->second;
	}
}

template <class MeshT>
bool LevelWriter::exportObj(MeshT &mesh, const std::string &name,
                            const std::vector<int> &sourceFaces, std::vector<std::string> &files,
                            std::string &error) const
{
	const std::string file = outdir_ + "/" + name;
	auto failed = [&](const std::string &why) {
		error = "cannot write " + file + ": " + why;
		return false;
	};
	// one material per (input material, or face colour and texture) the faces use
	std::vector<Material> materials;
	std::vector<int> faceMaterial;
	objMaterials(mesh, sourceFaces, materials, faceMaterial);
	// VCG's exporter names the material file after the OBJ: both are written into a temporary
	// folder under their final names, then moved (the material file first)
	const std::string tmpDir = partPath(name);
	if (::mkdir(tmpDir.c_str(), 0777) != 0 && errno != EEXIST)
		return failed(std::strerror(errno));
	const std::string tmp = tmpDir + "/" + name;
	const bool hasMtl =
	    (mask_ & (Mask::IOM_FACECOLOR | Mask::IOM_WEDGTEXCOORD | Mask::IOM_VERTTEXCOORD)) != 0;
	bool ok = gausslod::exportMesh(mesh, tmp, format_, mask_, materials, faceMaterial, error);
	const std::string mtl = file + ".mtl";
	if (ok && hasMtl && std::rename((tmp + ".mtl").c_str(), mtl.c_str()) != 0)
		ok = failed(std::strerror(errno));
	if (ok && std::rename(tmp.c_str(), file.c_str()) != 0)
		ok = failed(std::strerror(errno));
	removeTree(tmpDir);
	if (!ok)
		return false;
	files.push_back(file);
	if (hasMtl)
		files.push_back(mtl);
	return true;
}

std::string LevelWriter::partPath(const std::string &name) const
{
	return outdir_ + "/." + name + ".part-" + std::to_string(getpid());
}

bool LevelWriter::moveInto(const std::string &tmp, bool written, const std::string &name,
                           std::vector<std::string> &files, std::string &error) const
{
	const std::string file = outdir_ + "/" + name;
	if (written && std::rename(tmp.c_str(), file.c_str()) != 0) {
		error = "cannot write " + file + ": " + std::strerror(errno);
		written = false;
	}
	if (!written) {
		std::remove(tmp.c_str());
		return false;
	}
	files.push_back(file);
	return true;
}

bool LevelWriter::write(const gausslod::LevelMesh &level, const std::string &stem,
                        std::vector<std::string> &files, size_t &vertices, std::string &error) const
{
	return writeNamed(level, stem + "_LOD" + std::to_string(level.stats.level) + "." + extension(),
	                  files, vertices, error);
}

std::string LevelWriter::extension() const
{
	return glb_ ? (gltfText_ ? "gltf" : "glb") : gausslod::formatExtension(format_);
}

bool LevelWriter::writeNamed(const gausslod::LevelMesh &level, const std::string &name,
                             std::vector<std::string> &files, size_t &vertices,
                             std::string &error) const
{
	vertices = level.positions.size() / 3;
	// the lean path of files without attributes, and STL (it holds none: the triangles only)
	if (format_ == MeshFormat::Stl || !in_.mesh) {
		if (!glb_ && (format_ == MeshFormat::Stl || (format_ == MeshFormat::Ply && !in_.normals))) {
			const std::string tmp = partPath(name);
			const bool ok = format_ == MeshFormat::Stl
			                    ? gausslod::writeLevelStl(level, tmp, error)
			                    : gausslod::writeLevelPly(level, tmp, superfaceColours_, error);
			return moveInto(tmp, ok, name, files, error);
		}
		gausslod::IoMesh mesh;
		gausslod::toVcgMesh(level, mesh, superfaceColours_, false);
		return exportLevel(mesh, name, {}, files, error);
	}
	gausslod::IoAttrMesh mesh;
	gausslod::toVcgMeshWithAttributes(level, in_.flat, *in_.mesh, outAttrs_, mesh,
	                                  superfaceColours_, false);
	vertices = size_t(mesh.vn);
	std::vector<int> sourceFaces;
	if (format_ == MeshFormat::Obj && level.sourceFace.size() == level.triangles.size() / 3) {
		sourceFaces.resize(level.sourceFace.size());
		for (size_t f = 0; f < sourceFaces.size(); ++f)
			sourceFaces[f] = in_.flat.faceIndex[size_t(level.sourceFace[f])];
	}
	return exportLevel(mesh, name, sourceFaces, files, error);
}

// Removes what a killed run left under `dir` whose name starts with `prefix` and holds ".part-":
// temporary files, and the temporary folders OBJ levels are written in.
static void removePartFiles(const std::string &dir, const std::string &prefix)
{
	DIR *d = opendir(dir.c_str());
	if (!d)
		return;
	std::vector<std::string> found;
	while (const dirent *e = readdir(d)) {
		const std::string n = e->d_name;
		if (n.compare(0, prefix.size(), prefix) == 0 && n.find(".part-") != std::string::npos)
			found.push_back(n);
	}
	closedir(d);
	for (const std::string &n : found)
		removeTree(dir + "/" + n);
}

void removeLevelParts(const std::string &outdir, const std::string &stem)
{
	for (const char *kind : {"_LOD", "_full.glb", "_lods.glb"})
		removePartFiles(outdir, "." + stem + kind);
	// (the tileset: batch's <name>_tileset.json, the tool's tileset.json; writeAtomically's parts)
	removePartFiles(outdir, stem + "_tileset.json");
	removePartFiles(outdir, "tileset.json");
}

} // namespace cli
