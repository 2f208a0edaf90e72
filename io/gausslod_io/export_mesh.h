// Writes a VCG mesh as PLY (binary), OBJ (+ its MTL), OFF or STL (binary) with VCG's exporters,
// keeping only the attributes (vcg::tri::io::Mask bits) the format holds as VCG writes and reads
// it back (formatMask).
#pragma once

#include <vcg/complex/complex.h>
#include <wrap/io_trimesh/export_obj.h>
#include <wrap/io_trimesh/export_off.h>
#include <wrap/io_trimesh/export_ply.h>
#include <wrap/io_trimesh/export_stl.h>

#include <cctype>
#include <string>
#include <vector>

namespace gausslod {

enum class MeshFormat { Unknown, Ply, Obj, Off, Stl };

/// "ply", "obj", "off", "stl" ("" for Unknown).
inline const char *formatExtension(MeshFormat f)
{
	static const char *names[] = {"", "ply", "obj", "off", "stl"};
	return names[int(f)];
}

/// The format named "ply", "obj", "off" or "stl" (any case), else Unknown.
inline MeshFormat formatNamed(std::string name)
{
	for (char &c : name)
		c = char(std::tolower(static_cast<unsigned char>(c)));
	for (MeshFormat f : {MeshFormat::Ply, MeshFormat::Obj, MeshFormat::Off, MeshFormat::Stl})
		if (name == formatExtension(f))
			return f;
	return MeshFormat::Unknown;
}

/// The format of a file name's extension.
inline MeshFormat formatOfFile(const std::string &path)
{
	const size_t dot = path.find_last_of('.');
	if (dot == std::string::npos || path.find('/', dot) != std::string::npos)
		return MeshFormat::Unknown;
	return formatNamed(path.substr(dot + 1));
}

/// `mask` reduced to what format `f` holds, as VCG's writer writes it and its reader reads it:
/// PLY everything the tool carries; OBJ vertex normals, vertex colours, texture coordinates
/// (per wedge, else per vertex) and face colours (as materials), no quality; OFF vertex colours,
/// vertex texture coordinates and face colours, vertex normals only without vertex colours
/// (export_off.h writes colour before normal, import_off.h reads them the other way round); STL
/// nothing but the triangles.
inline int formatMask(MeshFormat f, int mask)
{
	using M = vcg::tri::io::Mask;
	const int geometry = M::IOM_VERTCOORD | M::IOM_FACEINDEX;
	int keep = 0;
	switch (f) {
		case MeshFormat::Ply:
			keep = M::IOM_VERTNORMAL | M::IOM_VERTCOLOR | M::IOM_VERTQUALITY | M::IOM_VERTTEXCOORD |
			       M::IOM_WEDGTEXCOORD | M::IOM_FACECOLOR;
			break;
		case MeshFormat::Obj:
			keep = M::IOM_VERTNORMAL | M::IOM_VERTCOLOR | M::IOM_VERTTEXCOORD |
			       M::IOM_WEDGTEXCOORD | M::IOM_FACECOLOR;
			if (mask & M::IOM_WEDGTEXCOORD) // (export_obj.h writes one of the two)
				keep &= ~M::IOM_VERTTEXCOORD;
			break;
		case MeshFormat::Off:
			keep = M::IOM_VERTCOLOR | M::IOM_VERTTEXCOORD | M::IOM_FACECOLOR;
			if (!(mask & M::IOM_VERTCOLOR))
				keep |= M::IOM_VERTNORMAL;
			break;
		default: break;
	}
	return geometry | (mask & keep);
}

/// Writes `m` to `file` in format `f` with the attributes of `mask` (formatMask() applied). OBJ:
/// the materials are `materials` with a material index per face (`faceMaterial`, one per face of
/// m.face), written by VCG's exporter to file + ".mtl", which the OBJ names "./<its name>.mtl".
/// False with `error` set if the file cannot be written.
template <class MeshT>
bool exportMesh(MeshT &m, const std::string &file, MeshFormat f, int mask,
                const std::vector<vcg::tri::io::Material> &materials,
                const std::vector<int> &faceMaterial, std::string &error)
{
	mask = formatMask(f, mask);
	int r = 0;
	const char *what = "";
	switch (f) {
		case MeshFormat::Ply: {
			vcg::tri::io::PlyInfo pi;
			pi.mask = mask;
			r = vcg::tri::io::ExporterPLY<MeshT>::Save(m, file.c_str(), true, pi);
			what = r ? vcg::tri::io::ExporterPLY<MeshT>::ErrorMsg(r) : "";
			break;
		}
		case MeshFormat::Obj: {
			using Obj = vcg::tri::io::ExporterOBJ<MeshT>;
			using A = vcg::tri::Allocator<MeshT>;
			const bool useMaterials = faceMaterial.size() == m.face.size() && !materials.empty();
			if (useMaterials) {
				auto mats = A::template GetPerMeshAttribute<std::vector<vcg::tri::io::Material>>(
				    m, "materialVector");
				auto index = A::template GetPerFaceAttribute<int>(m, "materialIndex");
				mats() = materials;
				for (size_t i = 0; i < m.face.size(); ++i)
					index[i] = faceMaterial[i];
			}
			r = Obj::Save(m, file.c_str(), mask, useMaterials);
			if (useMaterials) { // (TriMesh's destructor does not free attributes)
				A::DeletePerMeshAttribute(m, "materialVector");
				A::DeletePerFaceAttribute(m, "materialIndex");
			}
			what = r ? Obj::ErrorMsg(r) : "";
			break;
		}
		case MeshFormat::Off:
			r = vcg::tri::io::ExporterOFF<MeshT>::Save(m, file.c_str(), mask);
			what = r ? vcg::tri::io::ExporterOFF<MeshT>::ErrorMsg(r) : "";
			break;
		case MeshFormat::Stl:
			r = vcg::tri::io::ExporterSTL<MeshT>::Save(m, file.c_str(), true, 0);
			what = r ? vcg::tri::io::ExporterSTL<MeshT>::ErrorMsg(r) : "";
			break;
		default: error = "cannot write " + file + ": unknown format"; return false;
	}
	if (r != 0) {
		error = "cannot write " + file + ": " + what;
		return false;
	}
	return true;
}

} // namespace gausslod
