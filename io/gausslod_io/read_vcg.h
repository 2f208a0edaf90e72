// The part of importMesh that depends on the caller's mesh type: a file checkFile() passed, read
// with VCG's importer (or, for STL and the binary PLY fast path, by the code here) into the mesh.
// Included by import_mesh.h, after its declarations.
#pragma once

#include "import_mesh.h"

#include <algorithm>
#include <cstring>
#include <fstream>

namespace gausslod {
namespace detail {

/// Builds VCG's STL soup: three unshared vertices per triangle, as ImporterSTL does.
template <class MeshT>
void buildSoup(MeshT &m, const std::vector<float> &xyz)
{
	m.Clear();
	const size_t nt = xyz.size() / 9;
	if (nt == 0)
		return;
	auto fi = vcg::tri::Allocator<MeshT>::AddFaces(m, nt);
	auto vi = vcg::tri::Allocator<MeshT>::AddVertices(m, nt * 3);
	for (size_t i = 0; i < nt; ++i, ++fi)
		for (int k = 0; k < 3; ++k, ++vi) {
			const float *p = &xyz[9 * i + 3 * size_t(k)];
			(*vi).P() = typename MeshT::CoordType(p[0], p[1], p[2]);
			(*fi).V(k) = &*vi;
		}
}

/// Reads the face records of a SimplePly file from `f` (positioned at the first one), a batch at a
/// time into `buf`, and checks them: a count of 3 and indices within 0..vertices-1. Calls
/// put(face, k, index) for each index of a good record; false at a short read or a bad record.
template <class Put>
bool readPlyTriangles(FILE *f, const SimplePly &sp, std::vector<unsigned char> &buf, Put put)
{
	buf.resize(kPlyFaceBytes * std::min(sp.faces, kPlyBatch));
	for (size_t done = 0; done < sp.faces;) {
		const size_t n = std::min(sp.faces - done, kPlyBatch);
		if (std::fread(buf.data(), kPlyFaceBytes, n, f) != n)
			return false;
		for (size_t i = 0; i < n; ++i) {
			const unsigned char *r = &buf[kPlyFaceBytes * i];
			if (r[0] != 3)
				return false;
			for (int k = 0; k < 3; ++k) {
				uint32_t u;
				std::memcpy(&u, r + 1 + 4 * k, 4);
				// (an int below zero is a huge uint: out of range either way)
				if (u >= uint32_t(sp.vertices) || (!sp.unsignedIndex && u > uint32_t(INT32_MAX)))
					return false;
				put(done + i, k, u);
			}
		}
		done += n;
	}
	return true;
}

/// Reads the fast path's vertex records (sp.vertexBytes each), a batch at a time into `buf`, and
/// calls put(vertex, xyz, record) for each: its position as the file's floats and its record
/// (for the colour bytes after them). False at a short read.
template <class Put>
bool readPlyVertices(FILE *f, const SimplePly &sp, std::vector<unsigned char> &buf, Put put)
{
	buf.resize(sp.vertexBytes * std::min(sp.vertices, kPlyBatch));
	for (size_t done = 0; done < sp.vertices;) {
		const size_t n = std::min(sp.vertices - done, kPlyBatch);
		if (std::fread(buf.data(), sp.vertexBytes, n, f) != n)
			return false;
		for (size_t i = 0; i < n; ++i) {
			const unsigned char *r = &buf[sp.vertexBytes * i];
			float xyz[3];
			std::memcpy(xyz, r, sizeof xyz);
			put(done + i, xyz, r);
		}
		done += n;
	}
	return true;
}

/// What ImporterPLY::Open builds from a file of the fast path's layout (import_ply.h:670-690,
/// 755-860, 1020-1070), read again in batches straight into the mesh (checkPly checked the faces).
/// `mask`: Open's for this layout (it names no attribute but the colour, import_ply.h:387-570).
template <class MeshT>
bool readSimplePlyMesh(MeshT &m, const CheckedFile &c, ReadError &e, int &mask)
{
	const SimplePly &sp = c.ply;
	File file(c.vcgPath);
	auto changed = [&] { return corrupt(e, "PLY: the file changed while it was read"); };
	if (!file.f || std::fseek(file.f, long(sp.offset), SEEK_SET) != 0)
		return changed();
	// (the colour as Open reads it when the mesh type has one: alpha 255 unless the file
	// has it, import_ply.h:481-489, 677, 711-717)
	const bool colour = sp.colour > 0 && vcg::tri::HasPerVertexColor(m);
	std::vector<unsigned char> buf;
	if (sp.vertices) {
		vcg::tri::Allocator<MeshT>::AddVertices(m, sp.vertices);
		if (!readPlyVertices(
		        file.f, sp, buf, [&](size_t v, const float *xyz, const unsigned char *r) {
			        auto &vert = m.vert[v];
			        vert.P() = typename MeshT::CoordType(xyz[0], xyz[1], xyz[2]);
			        if (colour) // (HasPerVertexColor: a type without never gets here)
				        vert.C() = vcg::Color4b(r[12], r[13], r[14], sp.colour == 4 ? r[15] : 255);
		        }))
			return changed();
	}
	if (sp.faces) {
		vcg::tri::Allocator<MeshT>::AddFaces(m, sp.faces);
		if (!readPlyTriangles(file.f, sp, buf, [&](size_t face, int k, uint32_t v) {
			    m.face[face].V(k) = &m.vert[v];
		    }))
			return changed();
	}
	m.textures.clear();
	m.normalmaps.clear();
	vcg::tri::UpdateBounding<MeshT>::Box(m);
	mask = colour ? int(vcg::tri::io::Mask::IOM_VERTCOLOR) : 0;
	return true;
}

/// VCG 2020.09 drops every face using vertex 1 (unless obj_import.h fixed it for this mesh
/// type): the faces rebuilt from the scan, where VCG's count differs from it.
template <class MeshT>
void rebuildObjFaces(MeshT &m, const ObjScan &scan, ReadInfo *info)
{
	const size_t nt = scan.faux.size();
	if (obj::IndexFixFor<MeshT>::value || size_t(m.fn) == nt ||
	    m.vert.size() != size_t(scan.vertices))
		return;
	m.face.clear();
	m.fn = 0;
	if (info)
		info->faceMaterial.clear();
	if (nt) {
		auto fi = vcg::tri::Allocator<MeshT>::AddFaces(m, nt);
		for (size_t i = 0; i < nt; ++i, ++fi)
			for (int k = 0; k < 3; ++k) {
				(*fi).V(k) = &m.vert[size_t(scan.tri[3 * i + size_t(k)])];
				if (scan.faux[i] & (1 << k))
					(*fi).SetF(k);
				else
					(*fi).ClearF(k);
			}
	}
	if (vcg::tri::HasPerFaceNormal(m))
		vcg::tri::UpdateNormal<MeshT>::PerFaceNormalized(m);
}

/// VCG's OBJ importer. Its material attributes would leak (TriMesh's destructor does not free
/// attributes): copied for `info`, then deleted.
template <class MeshT>
bool readVcgObj(MeshT &m, const CheckedFile &c, ReadError &e, ReadInfo *info, int &mask)
{
	using Obj = vcg::tri::io::ImporterOBJ<MeshT>;
	using Alloc = vcg::tri::Allocator<MeshT>;
	const int r = Obj::Open(m, c.vcgPath.c_str(), mask);
	if (info) {
		auto mats = Alloc::template FindPerMeshAttribute<std::vector<vcg::tri::io::Material>>(
		    m, "materialVector");
		auto index = Alloc::template FindPerFaceAttribute<int>(m, "materialIndex");
		if (Alloc::IsValidHandle(m, mats) && Alloc::IsValidHandle(m, index)) {
			info->materials = mats();
			info->faceMaterial.resize(m.face.size());
			for (size_t i = 0; i < m.face.size(); ++i)
				info->faceMaterial[i] = index[i];
		}
	}
	Alloc::DeletePerMeshAttribute(m, "materialVector");
	Alloc::DeletePerFaceAttribute(m, "materialIndex");
	if (r != 0 && Obj::ErrorCritical(r))
		return corrupt(e, std::string("OBJ: ") + Obj::ErrorMsg(r));
	if (!c.obj.vertexColours) // (see checkObjFile: no vertex line has colours)
		mask &= ~int(vcg::tri::io::Mask::IOM_VERTCOLOR);
	rebuildObjFaces(m, c.obj, info);
	return true;
}

/// The body of a checked file into `m` (read by VCG's importer, or here: STL, the PLY fast path);
/// `mask`: what was read.
template <class MeshT>
bool readBody(MeshT &m, CheckedFile &c, ReadError &e, ReadInfo *info, int &mask)
{
	const std::string &path = c.vcgPath;
	if (c.format == Format::Stl) {
		buildSoup(m, c.stl);
		std::vector<float>().swap(c.stl);
		mask = c.facts.mask;
	} else if (c.format == Format::Ply && c.ply.ok) {
		if (!readSimplePlyMesh(m, c, e, mask))
			return false;
	} else if (c.format == Format::Ply) {
		using Ply = vcg::tri::io::ImporterPLY<MeshT>;
		const int r = Ply::Open(m, path.c_str(), mask);
		if (r != 0 && Ply::ErrorCritical(r))
			return corrupt(e, std::string("PLY: ") + Ply::ErrorMsg(r));
	} else if (c.format == Format::Off) {
		using Off = vcg::tri::io::ImporterOFF<MeshT>;
		std::ifstream in(path, std::ios::binary);
		BlankLineFilter filter(in);
		std::istream stream(&filter);
		const int r = Off::OpenStream(m, stream, mask);
		if (r != 0) // (every OFF error is critical, as in vcg::tri::io::Importer)
			return corrupt(e, std::string("OFF: ") + Off::ErrorMsg(r));
	} else {
		return readVcgObj(m, c, e, info, mask);
	}
	return true;
}

/// Corrupt unless every face's vertices lie in m.vert (whatever a reader let through).
template <class MeshT>
bool facesInVertexArray(const MeshT &m, ReadError &e)
{
	using VertexType = typename MeshT::VertexType;
	const uintptr_t lo = m.vert.empty() ? 0 : uintptr_t(m.vert.data()),
	                hi = lo + m.vert.size() * sizeof(VertexType);
	for (size_t i = 0; i < m.face.size(); ++i)
		for (int k = 0; k < 3; ++k) {
			const uintptr_t v = uintptr_t(m.face[i].cV(k));
			if (v < lo || v >= hi || (v - lo) % sizeof(VertexType) != 0)
				return corrupt(e, "face " + num((long long)i) + " points outside the vertex array");
		}
	return true;
}

/// What VCG's readers leave unset in per-vertex texture coordinates (TexCoord2's constructor sets
/// nothing), made defined so that a read is the same whatever memory it got:
/// - PLY: the texture index (import_ply.h:701-705 sets u and v only): texture 0;
/// - OBJ (as many `vt` as `v` lines): vertices no face uses (obj::settleUnusedVertexTexCoords);
/// - OFF: everything (import_off.h:360-380 skips them, though its load mask names them): not
///   loaded, so `mask` no longer names them.
template <class MeshT>
void settleVertexTexCoords(MeshT &m, Format format, int &mask)
{
	using vcg::tri::io::Mask;
	if (!(mask & Mask::IOM_VERTTEXCOORD) || !vcg::tri::HasPerVertexTexCoord(m))
		return;
	if (format == Format::Off) {
		mask &= ~int(Mask::IOM_VERTTEXCOORD);
		return;
	}
	if (format == Format::Obj)
		obj::settleUnusedVertexTexCoords(m, mask);
	else if (format == Format::Ply)
		for (auto &v : m.vert)
			v.T().N() = 0;
}

template <class MeshT>
bool readChecked(MeshT &m, CheckedFile &c, ReadError &e, ReadInfo *info)
{
	m.Clear();
	int mask = 0;
	if (!readBody(m, c, e, info, mask))
		return false;
	c.folder.reset();
	if (!facesInVertexArray(m, e))
		return false;
	settleVertexTexCoords(m, c.format, mask);
	if (info && c.format == Format::Obj)
		addObjNotes(c.obj, info->notes);
	if (info) {
		info->fastPly = c.format == Format::Ply && c.ply.ok; // (read by readSimplePlyMesh)
		info->fileMask = c.facts.mask;
		info->mask = mask;
	}
	if (m.vn == 0 && m.fn == 0)
		return fail(e, ReadStatus::Empty, "the file holds no vertex and no face");
	return true;
}

} // namespace detail

template <class MeshT>
bool importMesh(MeshT &m, const std::string &path, ReadError &error, ReadInfo *info)
{
	return detail::guarded(error, [&] {
		using V = typename MeshT::VertexType;
		using F = typename MeshT::FaceType;
		detail::CheckedFile c;
		return detail::checkFile(path, sizeof(V), sizeof(F), c, error) &&
		       detail::readChecked(m, c, error, info);
	});
}

template <class LeanT, class FullT>
bool importMeshEither(LeanT &lean, FullT &full, bool &usedFull, const std::string &path,
                      int wantMask, ReadError &error, ReadInfo *info, detail::FlatRead *flat)
{
	usedFull = false;
	if (flat)
		*flat = detail::FlatRead();
	return detail::guarded(error, [&] {
		using V = typename LeanT::VertexType;
		using F = typename LeanT::FaceType;
		detail::CheckedFile c;
		if (!detail::checkFile(path, sizeof(V), sizeof(F), c, error))
			return false;
		if (flat && c.format == detail::Format::Ply && c.ply.ok && c.ply.colour == 0)
			return detail::readSimplePlyFlat(c, *flat, error, info); // (no attribute to carry)
		if (!(c.facts.mask & wantMask))
			return detail::readChecked(lean, c, error, info);
		using FV = typename FullT::VertexType;
		using FF = typename FullT::FaceType;
		// (with a pointer per vertex for the index table VCG's PLY importer builds)
		if (!detail::checkMemory(c.facts.vertices * (sizeof(FV) + sizeof(void *)) +
		                             c.facts.faces * sizeof(FF),
		                         error))
			return false;
		usedFull = true;
		return detail::readChecked(full, c, error, info);
	});
}

} // namespace gausslod
