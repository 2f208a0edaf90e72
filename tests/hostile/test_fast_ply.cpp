// test_fast_ply OUTDIR MIN_FAST DIR...: the binary PLY fast path of importMesh (DESIGN 33, 48)
// against VCG's own reader, file by file. Every .ply under the DIRs (the hostile corpus, Debian's
// models, the fuzz seeds), and a binary PLY that VCG's exporter writes into OUTDIR for every .off
// and .obj model of Debian's CGAL data under the DIRs (the layout MeshLab saves a mesh without
// attributes in: real geometry, files nobody here wrote by hand; every third also with vertex
// colours, as MeshLab saves a coloured scan), is read twice into each of the tool's two mesh
// types: as the tool reads it, and with the fast path off. Both must succeed or fail alike (same
// status and message) and build the same mesh bit for bit: counts, every vertex's position bits,
// colour, quality and flags (normals and texture coordinates where the read mask names them),
// every face's vertex indices, flags and colour, the load masks, texture names, bounding box.
// The tool's read (importMeshEither with flat arrays, which skips the VCG mesh for the fast
// path's files without colour) must give the arrays gausslod::flatten makes of VCG's read; each
// fast path mesh, taken as a level, is written by writeLevelStl with the face records VCG's STL
// exporter writes. At least MIN_FAST files, 10 of them coloured, must have taken the fast path
// (else it would test nothing). The largest of those models is also written in variants of the
// layout (uint indices, the name vertex_index, type aliases, CRLF header lines, trailing bytes,
// no faces, uchar rgb and rgba colours) that must take the fast path, and variants that must not
// (a quad in the last batch, an index out of range, a short body, a face count larger than the
// file, a TextureFile comment, big endian, float colours, a fifth colour byte).
#include "gausslod/vcg_adapter.h"
#include "gausslod_io/import_mesh.h"
#include "gausslod_io/level_ply.h"

#include <wrap/io_trimesh/export_ply.h>
#include <wrap/io_trimesh/export_stl.h>

#include <dirent.h>
#include <sys/stat.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace {

void collect(const std::string &dir, std::vector<std::string> &plys,
             std::vector<std::string> &models)
{
	DIR *d = opendir(dir.c_str());
	if (!d)
		return;
	std::vector<std::string> names;
	while (dirent *e = readdir(d))
		if (e->d_name[0] != '.')
			names.emplace_back(e->d_name);
	closedir(d);
	std::sort(names.begin(), names.end());
	for (const std::string &n : names) {
		const std::string p = dir + "/" + n;
		struct stat st;
		if (stat(p.c_str(), &st) != 0)
			continue;
		if (S_ISDIR(st.st_mode)) {
			collect(p, plys, models);
			continue;
		}
		if (!S_ISREG(st.st_mode))
			continue;
		const std::string ext = gausslod::detail::lowerExtension(p);
		if (ext == "ply")
			plys.push_back(p);
		else if ((ext == "off" || ext == "obj") && p.find("cgal") != std::string::npos &&
		         st.st_size < (64 << 20))
			models.push_back(p);
	}
}

struct Read {
	bool ok = false;
	gausslod::ReadError error;
	gausslod::ReadInfo info;
};

template <class MeshT>
Read readWith(MeshT &m, const std::string &path, bool fast)
{
	Read r;
	if (fast) {
		r.ok = gausslod::importMesh(m, path, r.error, &r.info);
		return r;
	}
	r.ok = gausslod::detail::guarded(r.error, [&] {
		using V = typename MeshT::VertexType;
		using F = typename MeshT::FaceType;
		gausslod::detail::CheckedFile c;
		return gausslod::detail::checkFile<MeshT>(path, sizeof(V), sizeof(F), c, r.error, false) &&
		       gausslod::detail::readChecked(m, c, r.error, &r.info);
	});
	return r;
}

template <class T>
bool sameBits(const T &a, const T &b)
{
	return std::memcmp(&a, &b, sizeof(T)) == 0;
}

// The components VCG's reader sets (colour and quality are also initialised by VCG; normals and
// texture coordinates only where the read mask names them), bit for bit; quality and texture
// coordinates only in the attribute mesh type.
using M = vcg::tri::io::Mask;
bool sameVertex(const gausslod::IoVertex &a, const gausslod::IoVertex &b, int mask)
{
	return sameBits(a.cC(), b.cC()) && (!(mask & M::IOM_VERTNORMAL) || sameBits(a.cN(), b.cN()));
}
bool sameFace(const gausslod::IoFace &a, const gausslod::IoFace &b, int mask)
{
	return sameBits(a.cC(), b.cC()) && (!(mask & M::IOM_FACENORMAL) || sameBits(a.cN(), b.cN()));
}
bool sameVertex(const gausslod::IoAttrVertex &a, const gausslod::IoAttrVertex &b, int mask)
{
	return sameBits(a.cC(), b.cC()) && sameBits(a.cQ(), b.cQ()) &&
	       (!(mask & M::IOM_VERTNORMAL) || sameBits(a.cN(), b.cN())) &&
	       (!(mask & M::IOM_VERTTEXCOORD) ||
	        (sameBits(a.cT().P(), b.cT().P()) && a.cT().N() == b.cT().N()));
}
bool sameFace(const gausslod::IoAttrFace &a, const gausslod::IoAttrFace &b, int mask)
{
	if (!sameBits(a.cC(), b.cC()) || ((mask & M::IOM_FACENORMAL) && !sameBits(a.cN(), b.cN())))
		return false;
	for (int k = 0; (mask & M::IOM_WEDGTEXCOORD) && k < 3; ++k)
		if (!sameBits(a.cWT(k).P(), b.cWT(k).P()) || a.cWT(k).N() != b.cWT(k).N())
			return false;
	return true;
}

// "" if the two reads agree, else what differs.
template <class MeshT>
std::string compare(const std::string &path, bool &tookFast)
{
	MeshT a, b;
	const Read ra = readWith(a, path, true), rb = readWith(b, path, false);
	tookFast = ra.info.fastPly;
	if (rb.info.fastPly)
		return "the fast path was taken with it off";
	if (ra.ok != rb.ok || ra.error.status != rb.error.status ||
	    ra.error.message != rb.error.message)
		return "result: fast " + std::string(ra.ok ? "ok" : ra.error.message) + ", VCG " +
		       (rb.ok ? "ok" : rb.error.message);
	if (!ra.ok)
		return "";
	if (ra.info.mask != rb.info.mask || ra.info.fileMask != rb.info.fileMask)
		return "load masks " + std::to_string(ra.info.mask) + "/" +
		       std::to_string(ra.info.fileMask) + " vs " + std::to_string(rb.info.mask) + "/" +
		       std::to_string(rb.info.fileMask);
	if (a.vert.size() != b.vert.size() || a.face.size() != b.face.size() || a.vn != b.vn ||
	    a.fn != b.fn)
		return "counts " + std::to_string(a.vn) + "/" + std::to_string(a.fn) + " vs " +
		       std::to_string(b.vn) + "/" + std::to_string(b.fn);
	for (size_t i = 0; i < a.vert.size(); ++i)
		if (!sameBits(a.vert[i].cP(), b.vert[i].cP()) || a.vert[i].cFlags() != b.vert[i].cFlags() ||
		    !sameVertex(a.vert[i], b.vert[i], rb.info.mask))
			return "vertex " + std::to_string(i);
	for (size_t i = 0; i < a.face.size(); ++i) {
		for (int k = 0; k < 3; ++k)
			if (a.face[i].cV(k) - a.vert.data() != b.face[i].cV(k) - b.vert.data())
				return "face " + std::to_string(i) + " corner " + std::to_string(k);
		if (a.face[i].cFlags() != b.face[i].cFlags())
			return "face " + std::to_string(i) + " flags";
		if (!sameFace(a.face[i], b.face[i], rb.info.mask))
			return "face " + std::to_string(i) + " colour, normal or texture coordinates";
	}
	if (a.textures != b.textures)
		return "texture names";
	if (!sameBits(a.bbox.min, b.bbox.min) || !sameBits(a.bbox.max, b.bbox.max))
		return "bounding box";
	return "";
}

// "" if the tool's read of `path` (importMeshEither with flat arrays: the fast path's files are
// read without a VCG mesh) gives the flat arrays gausslod::flatten makes of VCG's own read, and
// fails alike; `tookFlat`: it read the file into the flat arrays.
std::string compareFlat(const std::string &path, bool &tookFlat, bool &coloured)
{
	gausslod::IoMesh lean, vcgRead;
	gausslod::IoAttrMesh full;
	Read ra;
	bool usedFull = false;
	gausslod::detail::FlatRead flat;
	ra.ok = gausslod::importMeshEither(lean, full, usedFull, path, ~0, ra.error, &ra.info, &flat);
	tookFlat = flat.used;
	const Read rb = readWith(vcgRead, path, false);
	coloured = (rb.info.mask & vcg::tri::io::Mask::IOM_VERTCOLOR) != 0; // (read into a VCG mesh)
	if (ra.ok != rb.ok || ra.error.status != rb.error.status ||
	    ra.error.message != rb.error.message)
		return "flat result: " + std::string(ra.ok ? "ok" : ra.error.message) + ", VCG " +
		       (rb.ok ? "ok" : rb.error.message);
	if (!ra.ok || !flat.used)
		return "";
	if (ra.info.mask != rb.info.mask || ra.info.fileMask != rb.info.fileMask)
		return "flat load masks";
	const gausslod::FlatMesh want = gausslod::flatten(vcgRead);
	if (flat.positions.size() != want.positions.size() ||
	    std::memcmp(flat.positions.data(), want.positions.data(),
	                want.positions.size() * sizeof(double)) != 0)
		return "flat positions";
	if (flat.triangles != want.triangles)
		return "flat triangles";
	return "";
}

std::string fileBytes(const std::string &path)
{
	std::string b;
	if (std::FILE *f = std::fopen(path.c_str(), "rb")) {
		char buf[1 << 16];
		size_t n;
		while ((n = std::fread(buf, 1, sizeof buf, f)) > 0)
			b.append(buf, n);
		std::fclose(f);
	}
	return b;
}

// "" if writeLevelStl writes, for the mesh of `path` taken as a level, the records VCG's STL
// exporter writes for it (everything after the 80-byte header, which is the level's own).
std::string compareStl(const std::string &path, const std::string &out)
{
	gausslod::IoMesh m;
	gausslod::ReadError e;
	if (!gausslod::importMesh(m, path, e) || m.fn == 0 || m.vn != int(m.vert.size()) ||
	    m.fn != int(m.face.size()))
		return "";
	gausslod::LevelMesh level; // (as the engine gives a level: positions in double)
	for (const auto &v : m.vert)
		for (int k = 0; k < 3; ++k)
			level.positions.push_back(double(v.cP()[k]));
	for (const auto &f : m.face)
		for (int k = 0; k < 3; ++k)
			level.triangles.push_back(int32_t(f.cV(k) - m.vert.data()));
	level.stats.level = 2, level.stats.distanceBound = 0.125;
	std::string error;
	const std::string ours = out + "/level.stl", vcgs = out + "/vcg.stl";
	if (!gausslod::writeLevelStl(level, ours, error))
		return "writeLevelStl: " + error;
	gausslod::IoMesh copy;
	gausslod::toVcgMesh(level, copy, false, false);
	if (vcg::tri::io::ExporterSTL<gausslod::IoMesh>::Save(copy, vcgs.c_str(), true, 0) != 0)
		return "VCG's STL exporter failed";
	const std::string a = fileBytes(ours), b = fileBytes(vcgs);
	if (a.size() != b.size() || a.size() != 84 + 50 * level.triangles.size() / 3)
		return "STL sizes " + std::to_string(a.size()) + " vs " + std::to_string(b.size());
	if (a.compare(0, 15, "GaussLOD level ") != 0)
		return "STL header";
	for (size_t i = 80; i < a.size(); ++i)
		if (a[i] != b[i])
			return "STL byte " + std::to_string(i) + " (face " + std::to_string((i - 84) / 50) +
			       ")";
	return "";
}

// "" if every per-vertex texture coordinate a read of `path` names is defined (readChecked's
// settleVertexTexCoords): run with MALLOC_PERTURB_ set, memory VCG's readers leave unset is not 0.
std::string checkVertexTexCoords(const std::string &path, const char *want)
{
	gausslod::IoAttrMesh m;
	gausslod::ReadError e;
	gausslod::ReadInfo info;
	if (!gausslod::importMesh(m, path, e, &info))
		return "not read: " + e.message;
	const bool named = (info.mask & M::IOM_VERTTEXCOORD) != 0;
	if (std::string(want) == "none")
		return named ? "the mask names vertex texture coordinates VCG does not read" : "";
	if (!named)
		return "the mask names no vertex texture coordinates";
	for (size_t i = 0; i < m.vert.size(); ++i) {
		const auto &t = m.vert[i].cT();
		if (t.n() != 0 || !(t.u() >= 0 && t.u() <= 1 && t.v() >= 0 && t.v() <= 1))
			return "vertex " + std::to_string(i) + ": (" + std::to_string(t.u()) + ", " +
			       std::to_string(t.v()) + ") texture " + std::to_string(t.n());
	}
	return "";
}

// A binary PLY of `m` (VCG's plain layout unless a variant changes it), written here byte by byte.
struct Variant {
	const char *name;
	bool fast; ///< must take the fast path
};
void writeVariant(const gausslod::IoMesh &m, const std::string &path, const std::string &v)
{
	const bool crlf = v == "crlf", big = v == "big_endian";
	const char *nl = crlf ? "\r\n" : "\n";
	const size_t nv = m.vert.size(), nf = v == "no_faces" ? 0 : m.face.size();
	std::string h = std::string("ply") + nl + "format " +
	                (big ? "binary_big_endian" : "binary_little_endian") + " 1.0" + nl;
	h += std::string("comment written by test_fast_ply") + nl;
	if (v == "texture_comment")
		h += std::string("comment TextureFile tex.png") + nl;
	const std::string f = v == "aliases" ? "float32" : "float";
	h += "element vertex " + std::to_string(nv) + nl;
	for (const char *c : {"x", "y", "z"})
		h += "property " + f + " " + c + nl;
	// vertex colours: uchar rgb or rgba (the fast path's), float rgb or a fifth uchar (not)
	const bool rgb = v == "rgb" || v == "rgba" || v == "rgb_float" || v == "rgba_extra";
	const int channels = v == "rgb" || v == "rgb_float" ? 3
	                     : v == "rgba"                  ? 4
	                     : v == "rgba_extra"            ? 5
	                                                    : 0;
	static const char *const colourNames[] = {"red", "green", "blue", "alpha", "extra"};
	for (int k = 0; k < channels; ++k)
		h += std::string("property ") + (v == "rgb_float" ? "float " : "uchar ") + colourNames[k] +
		     nl;
	h += "element face " + std::to_string(v == "lying_faces" ? nf * 1000 : nf) + nl;
	h += std::string("property list ") +
	     (v == "aliases" ? "uint8 int32"
	      : v == "uint"  ? "uchar uint"
	                     : "uchar int") +
	     (v == "vertex_index" ? " vertex_index" : " vertex_indices") + nl + "end_header" + nl;
	std::string body;
	auto put = [&](const void *p, size_t n) {
		std::string b(static_cast<const char *>(p), n);
		if (big)
			std::reverse(b.begin(), b.end());
		body += b;
	};
	for (size_t i = 0; i < nv; ++i) {
		for (int k = 0; k < 3; ++k) {
			const float x = m.vert[i].cP()[k];
			put(&x, 4);
		}
		for (int k = 0; rgb && k < channels; ++k) {
			const unsigned char c = (unsigned char)(i * 37 + size_t(k) * 101); // (alpha varies too)
			if (v == "rgb_float") {
				const float x = float(c) / 255.f;
				put(&x, 4);
			} else {
				body += char(c);
			}
		}
	}
	for (size_t i = 0; i < nf; ++i) {
		const bool last = i + 1 == nf;
		const unsigned char count = last && v == "quad_last" ? 4 : 3;
		body += char(count);
		for (int k = 0; k < count; ++k) {
			int32_t x = int32_t(m.face[i].cV(k % 3) - m.vert.data());
			if (last && k == 2 && v == "index_out_of_range")
				x = int32_t(nv);
			if (k == 3)
				x = int32_t(m.face[0].cV(0) - m.vert.data());
			put(&x, 4);
		}
	}
	if (v == "short_body")
		body.resize(body.size() - 5);
	if (v == "trailing")
		body += std::string(100, '\x7f');
	FILE *out = std::fopen(path.c_str(), "wb");
	std::fwrite(h.data(), 1, h.size(), out);
	std::fwrite(body.data(), 1, body.size(), out);
	std::fclose(out);
}

} // namespace

int main(int argc, char **argv)
{
	if (argc < 4) {
		std::fprintf(stderr, "usage: test_fast_ply OUTDIR MIN_FAST DIR...\n");
		return 2;
	}
	const std::string out = argv[1];
	const int minFast = std::atoi(argv[2]);
	std::vector<std::string> plys, models;
	for (int i = 3; i < argc; ++i)
		collect(argv[i], plys, models);
	mkdir(out.c_str(), 0755);
	// VCG's exporter, binary, no attributes: the layout MeshLab saves such a mesh in
	gausslod::IoMesh largest;
	size_t exported = 0;
	for (const std::string &m : models) {
		gausslod::IoMesh mesh;
		gausslod::ReadError e;
		if (!gausslod::importMesh(mesh, m, e) || mesh.fn == 0)
			continue;
		if (mesh.face.size() > largest.face.size() && mesh.vn == int(mesh.vert.size()) &&
		    mesh.fn == int(mesh.face.size()))
			vcg::tri::Append<gausslod::IoMesh, gausslod::IoMesh>::MeshCopy(largest, mesh);
		std::string name = m.substr(m.find_last_of('/') + 1);
		name = out + "/" + name.substr(0, name.find_last_of('.')) + "_" +
		       gausslod::detail::lowerExtension(m) + ".ply";
		if (vcg::tri::io::ExporterPLY<gausslod::IoMesh>::Save(mesh, name.c_str(), 0, true) == 0)
			plys.push_back(name), ++exported;
		// every third model also with vertex colours, as MeshLab saves a coloured scan
		if (exported % 3 == 0) {
			for (size_t i = 0; i < mesh.vert.size(); ++i)
				mesh.vert[i].C() =
				    vcg::Color4b((unsigned char)(i * 7), (unsigned char)(i * 13),
				                 (unsigned char)(i * 29), (unsigned char)(255 - i % 7));
			const std::string coloured = name.substr(0, name.size() - 4) + "_rgba.ply";
			if (vcg::tri::io::ExporterPLY<gausslod::IoMesh>::Save(
			        mesh, coloured.c_str(), vcg::tri::io::Mask::IOM_VERTCOLOR, true) == 0)
				plys.push_back(coloured), ++exported;
		}
	}
	// the variants of the largest model (more faces than one batch of the fast path)
	const Variant variants[] = {{"plain", true},
	                            {"uint", true},
	                            {"vertex_index", true},
	                            {"aliases", true},
	                            {"crlf", true},
	                            {"trailing", true},
	                            {"no_faces", true},
	                            {"quad_last", false},
	                            {"index_out_of_range", false},
	                            {"rgb", true},
	                            {"rgba", true},
	                            {"rgb_float", false},
	                            {"rgba_extra", false},
	                            {"short_body", false},
	                            {"lying_faces", false},
	                            {"texture_comment", false},
	                            {"big_endian", false}};
	int failed = 0;
	if (largest.face.size() <= (1u << 14)) {
		std::printf("FAIL: no model with more than one batch of faces for the variants\n");
		++failed;
	}
	for (const Variant &v : variants) {
		const std::string path = out + "/variant_" + v.name + ".ply";
		writeVariant(largest, path, v.name);
		bool lean = false;
		gausslod::IoMesh probe;
		gausslod::ReadError e;
		gausslod::ReadInfo info;
		gausslod::importMesh(probe, path, e, &info);
		lean = info.fastPly;
		if (lean != v.fast) {
			std::printf("FAIL %s: fast path %s (wanted %s)\n", path.c_str(),
			            lean ? "taken" : "not taken", v.fast ? "taken" : "not taken");
			++failed;
		}
		plys.push_back(path);
	}
	// per-vertex texture coordinates: a PLY's (index unset by VCG), an OBJ's on a vertex no face
	// uses (unset; VCG reads them per vertex when there are as many as vertices), an OFF's (never
	// read by VCG, though its mask names them)
	const struct {
		const char *name, *text, *want;
	} uvFiles[] = {
	    {"uv.ply",
	     "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
	     "property float z\nproperty float s\nproperty float t\nelement face 2\n"
	     "property list uchar int vertex_indices\nend_header\n0 0 0 0 0\n1 0 0 1 0\n"
	     "1 1 0 1 1\n0 1 0 0 1\n3 0 1 2\n3 0 2 3\n",
	     "settled"},
	    {"uv_unused_vertex.obj",
	     "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 5 5 5\nvt 0 0\nvt 1 0\nvt 1 1\nvt 1 1\nf 1/1 2/2 3/3\n",
	     "settled"},
	    {"uv.off", "STOFF\n4 2 0\n0 0 0 0 0\n1 0 0 1 0\n1 1 0 1 1\n0 1 0 0 1\n3 0 1 2\n3 0 2 3\n",
	     "none"}};
	for (const auto &u : uvFiles) {
		const std::string path = out + "/" + u.name;
		if (std::FILE *f = std::fopen(path.c_str(), "wb")) {
			std::fputs(u.text, f);
			std::fclose(f);
		}
		const std::string d = checkVertexTexCoords(path, u.want);
		if (!d.empty()) {
			std::printf("FAIL %s: %s\n", path.c_str(), d.c_str());
			++failed;
		}
	}
	int fast = 0, flatReads = 0, stlWritten = 0, fastColoured = 0;
	for (const std::string &p : plys) {
		bool lean = false, full = false;
		const std::string d1 = compare<gausslod::IoMesh>(p, lean);
		const std::string d2 = compare<gausslod::IoAttrMesh>(p, full);
		if (!d1.empty() || !d2.empty() || lean != full) {
			std::printf("FAIL %s: %s%s%s\n", p.c_str(), d1.c_str(), d1.empty() ? "" : "; ",
			            lean != full ? "fast path taken for one mesh type only" : d2.c_str());
			++failed;
		}
		bool flat = false, coloured = false;
		const std::string d3 = compareFlat(p, flat, coloured);
		if (!d3.empty() || flat != (lean && !coloured)) {
			std::printf("FAIL %s: %s\n", p.c_str(),
			            d3.empty()
			                ? "flat arrays read where the fast path was not, or not where it was"
			                : d3.c_str());
			++failed;
		}
		if (lean) { // (the level STL writer on the same meshes)
			const std::string d4 = compareStl(p, out);
			if (!d4.empty()) {
				std::printf("FAIL %s: %s\n", p.c_str(), d4.c_str());
				++failed;
			}
			stlWritten += d4.empty();
		}
		fast += lean;
		flatReads += flat;
		fastColoured += lean && coloured;
	}
	std::printf(
	    "%zu PLY files (%zu written by VCG's exporter from Debian's models, %zu variants of "
	    "one with %zu faces): %d read by the fast path (%d of them with vertex colours, %d "
	    "straight "
	    "into flat arrays, %d written as STL levels), %d failed\n",
	    plys.size(), exported, sizeof variants / sizeof variants[0], largest.face.size(), fast,
	    fastColoured, flatReads, stlWritten, failed);
	if (fastColoured < 10) {
		std::printf("FAIL: only %d files with vertex colours took the fast path\n", fastColoured);
		return 1;
	}
	if (fast < minFast) {
		std::printf("FAIL: only %d files took the fast path (wanted at least %d)\n", fast, minFast);
		return 1;
	}
	return failed ? 1 : 0;
}
