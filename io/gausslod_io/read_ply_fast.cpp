// The binary PLY fast path. Binary PLY files of the layout VCG and MeshLab write for a mesh
// without attributes (little endian; float x, y, z; faces as "list uchar int|uint
// vertex_indices", every face a triangle) are read here, at once, into the same mesh VCG's
// importer builds (DESIGN 33; tested against VCG's reader file by file, bit for bit): plylib reads
// them value by value and took most of the time of loading a large mesh. Anything else in such a
// file (a polygon, an index out of range, a short body) leaves it to the walk and VCG's importer
// (read_ply.cpp), with their messages. The batch readers are in read_vcg.h (readSimplePlyMesh
// reads such a file into a VCG mesh).
#include "read_formats.h"

#include <wrap/ply/plylib.h>

namespace gausslod {
namespace detail {

namespace {

bool hostLittleEndian()
{
	const uint16_t one = 1;
	unsigned char b;
	std::memcpy(&b, &one, 1);
	return b == 1;
}

/// The header of the fast path's layout: binary little endian, a vertex element of float x, y, z
/// (then uchar red, green, blue and optionally alpha), then a face element of one "list uchar
/// int|uint" index list, and no TextureFile comment.
bool simplePlyHeader(const PlyHeader &h, const vcg::ply::PlyFile &pf)
{
	using namespace vcg::ply;
	if (h.format != 2 || !hostLittleEndian() || pf.elements.size() != 2)
		return false;
	const PlyElement &ve = pf.elements[0], &fe = pf.elements[1];
	const size_t np = ve.props.size();
	if (ve.name != "vertex" || fe.name != "face" || !(np == 3 || np == 6 || np == 7) ||
	    fe.props.size() != 1 || ve.number < 0 || fe.number < 0)
		return false;
	static const char *const names[] = {"x", "y", "z", "red", "green", "blue", "alpha"};
	for (size_t k = 0; k < np; ++k)
		if (ve.props[k].name != names[k] || ve.props[k].islist ||
		    ve.props[k].tipo != (k < 3 ? T_FLOAT : T_UCHAR))
			return false;
	const PlyProperty &ip = fe.props[0];
	if (!ip.islist || (ip.name != "vertex_indices" && ip.name != "vertex_index") ||
	    ip.tipoindex != T_UCHAR ||
	    !(ip.tipo == T_INT || (ip.tipo == T_UINT && ip.name != "vertex_index")))
		return false;
	for (const std::string &c : pf.comments)
		if (c.compare(0, 11, "TextureFile") == 0)
			return false;
	return true;
}

} // namespace

/// A file of the fast path's header (simplePlyHeader) with a body of exactly 12 (15, 16) bytes per
/// vertex and 13 per face (at least: VCG ignores what follows), every face a triangle of vertices
/// in range (read here, in batches, to check). Needs no memory of its own beyond a batch:
/// readChecked reads the body again into the mesh.
bool readSimplePly(FILE *f, const PlyHeader &h, const vcg::ply::PlyFile &pf, uint64_t size,
                   SimplePly &out)
{
	out = SimplePly();
	if (!simplePlyHeader(h, pf))
		return false;
	const vcg::ply::PlyElement &ve = pf.elements[0], &fe = pf.elements[1];
	SimplePly sp;
	sp.offset = h.dataOffset;
	sp.vertices = size_t(ve.number), sp.faces = size_t(fe.number);
	sp.unsignedIndex = fe.props[0].tipo == vcg::ply::T_UINT;
	sp.colour = int(ve.props.size()) - 3;
	sp.vertexBytes = kPlyVertexBytes + size_t(sp.colour);
	// (a body shorter than the counts say is the walk's to report, without reading it here)
	if (size < sp.offset ||
	    double(size - sp.offset) <
	        double(sp.vertexBytes) * double(sp.vertices) + double(kPlyFaceBytes) * double(sp.faces))
		return false;
	if (std::fseek(f, long(sp.offset + sp.vertexBytes * sp.vertices), SEEK_SET) != 0)
		return false;
	std::vector<unsigned char> buf;
	if (!readPlyTriangles(f, sp, buf, [](size_t, int, uint32_t) {}))
		return false;
	out = sp;
	out.ok = true;
	return true;
}

bool readSimplePlyFlat(CheckedFile &c, FlatRead &out, ReadError &e, ReadInfo *info)
{
	const SimplePly &sp = c.ply;
	File file(c.vcgPath);
	auto changed = [&] { return corrupt(e, "PLY: the file changed while it was read"); };
	if (!file.f || std::fseek(file.f, long(sp.offset), SEEK_SET) != 0)
		return changed();
	if (sp.colour != 0) // (its caller reads coloured files into a VCG mesh)
		return corrupt(e, "PLY: vertex colours cannot be read into flat arrays");
	out.positions.resize(3 * sp.vertices);
	out.triangles.resize(3 * sp.faces);
	std::vector<unsigned char> buf;
	double *p = out.positions.data();
	if (!readPlyVertices(file.f, sp, buf, [&](size_t v, const float *xyz, const unsigned char *) {
		    for (size_t k = 0; k < 3; ++k)
			    p[3 * v + k] = double(xyz[k]);
	    }))
		return changed();
	int32_t *t = out.triangles.data();
	if (!readPlyTriangles(file.f, sp, buf, [&](size_t face, int k, uint32_t v) {
		    t[3 * face + size_t(k)] = int32_t(v);
	    }))
		return changed();
	out.used = true;
	if (info) {
		info->fastPly = true;
		info->fileMask = c.facts.mask;
		info->mask = 0; // (as readChecked's)
	}
	if (sp.vertices == 0 && sp.faces == 0)
		return fail(e, ReadStatus::Empty, "the file holds no vertex and no face");
	return true;
}

} // namespace detail
} // namespace gausslod
