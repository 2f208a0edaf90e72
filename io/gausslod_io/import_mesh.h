// Reads a mesh file (PLY, OBJ, OFF, STL) into any VCG mesh type, guarding VCG 2020.09's importers
// against hostile files: every problem is reported as a category and a one-line message, nothing
// crashes, hangs, throws or silently reads garbage. For every format: stat first (missing,
// directory, FIFO, empty); the content is sniffed against the name; what a header claims is
// checked against the file size and the available memory before VCG allocates it; bad_alloc and
// anything VCG throws are caught; after reading, every face's vertex pointers must lie inside
// m.vert. What each format's guards cover (VCG file:line) is said at the top of its file:
// read_off.cpp, read_obj.cpp, read_ply.cpp (and read_ply_fast.cpp, the binary PLY fast path),
// read_stl.cpp; check_file.cpp runs them (sniffing, the load mask) and read_vcg.h then reads the
// checked file with VCG's importer into the caller's mesh type.
//
// OBJ and OFF polygons of 5+ corners are split by GLU's tessellator, as in MeshLab's io_base (a
// fan would fold concave polygons); the OBJ index defect of VCG 2020.09 (every face using the
// first vertex dropped) is fixed for IoMesh and IoAttrMesh by obj_import.h, as in the OBJ plugin,
// so that the tool reads a file into the same triangles as the filter gets from MeshLab. An OBJ
// is read from its own folder (VCG opens its mtllib relative to the current directory), as the
// OBJ plugin does. importMeshEither() reads into a lean mesh type unless the file's load mask
// (VCG's LoadMask, or the OFF pre-scan) has attributes worth the richer one.
//
// The readers are compiled once into gausslod_io, and importMesh with them for IoMesh and
// IoAttrMesh (read_vcg.cpp); any other mesh type instantiates read_vcg.h where it is used.
#pragma once

#include <GL/glu.h> // before VCG's importers: their polygon tessellation then uses GLU

#include "io_mesh.h"
#include "obj_import.h"

#include <vcg/complex/complex.h>
#include <wrap/io_trimesh/import_off.h>
#include <wrap/io_trimesh/import_ply.h>

#include <cstdint>
#include <cstdio>
#include <exception>
#include <istream>
#include <memory>
#include <new>
#include <set>
#include <streambuf>
#include <string>
#include <vector>

GAUSSLOD_FIX_VCG_OBJ_INDICES(gausslod::IoMesh)
GAUSSLOD_FIX_VCG_OBJ_INDICES(gausslod::IoAttrMesh)

namespace gausslod {

enum class ReadStatus { Ok = 0, CannotOpen, Empty, WrongFormat, Corrupt, TooLarge };
// CannotOpen: missing, not a regular file, no permission. Empty: 0 bytes (or only blanks/comments,
//   no element at all).
// WrongFormat: unknown extension, or the content is clearly another format than the extension says
//   (message names both, e.g. "the file is a PLY file but its name ends in .stl").
// Corrupt: truncated, garbage, bad or out-of-range index, a header count that the file size cannot
//   hold, unparsable numbers.
// TooLarge: the header's counts need more memory than is available (message gives both figures).
struct ReadError {
	ReadStatus status = ReadStatus::Ok;
	std::string message; // the problem only, one line, no file name, no trailing newline
};

/// What importMesh read besides positions and faces.
struct ReadInfo {
	int fileMask = 0; ///< what the file carries (vcg::tri::io::Mask bits, VCG's LoadMask)
	int mask = 0; ///< what was read into the mesh (the file's, as far as the mesh type holds it)
	/// OBJ: the materials VCG's importer made of the MTL file, and per face an index into them
	/// (faces and materials as VCG read them; its face colours come from the materials' Kd)
	std::vector<vcg::tri::io::Material> materials;
	std::vector<int> faceMaterial;
	bool fastPly = false; ///< read by the binary PLY fast path (read_ply_fast.cpp)
	/// What the reader skipped or could not apply, a clause each ("1 face record with fewer
	/// than 3 vertices skipped"): the file is read all the same
	std::vector<std::string> notes;
};

/// "ok", "cannot_open", "empty", "wrong_format", "corrupt", "too_large".
const char *readStatusName(ReadStatus s);

/// Loads `path` into `m`. Returns false with `error` set if the file cannot be read (`m` may then
/// hold a partial mesh: discard it). No exception escapes. `info` (optional): what was read.
template <class MeshT>
bool importMesh(MeshT &m, const std::string &path, ReadError &error, ReadInfo *info = nullptr);

namespace detail {
struct FlatRead;
}

/// importMesh into `lean`, or into `full` when the file carries any attribute of `wantMask`
/// (vcg::tri::io::Mask bits, known once the guards have read the header or the lines): the
/// richer mesh type costs only the files that need it. `usedFull` says which mesh holds it.
/// With `flat`, a binary PLY of the fast path's layout is read into it instead (flat->used),
/// as gausslod::flatten would copy it out of `lean`.
template <class LeanT, class FullT>
bool importMeshEither(LeanT &lean, FullT &full, bool &usedFull, const std::string &path,
                      int wantMask, ReadError &error, ReadInfo *info = nullptr,
                      detail::FlatRead *flat = nullptr);

// ---- the pieces importMesh is made of (for the templates of read_vcg.h, and for tests) --------

namespace detail {

enum class Format { Unknown, Ply, Obj, Off, Stl };

bool fail(ReadError &e, ReadStatus s, const std::string &msg);
bool corrupt(ReadError &e, const std::string &msg);
std::string num(long long v);
/// A word from the file, fit for a one-line message (printable, at most 24 characters).
std::string quote(const char *b, const char *e);
/// The extension of a file name, in lower case ("" if none).
std::string lowerExtension(const std::string &path);
/// TooLarge if `need` bytes (the mesh a header announces) exceed the available memory.
bool checkMemory(double need, ReadError &e);

struct File {
	FILE *f = nullptr;
	explicit File(const std::string &path) : f(std::fopen(path.c_str(), "rb")) {}
	~File()
	{
		if (f)
			std::fclose(f);
	}
	File(const File &) = delete;
	File &operator=(const File &) = delete;
};

/// What the guards learnt of a file: element counts (for memory estimates) and VCG's load mask
/// (vcg::tri::io::Mask: the attributes the file carries), known before its body is read.
struct FileFacts {
	double vertices = 0, faces = 0;
	int mask = 0;
};

/// What the OBJ scan (read_obj.cpp) read of a file.
struct ObjScan {
	std::vector<int> tri;            // the triangles VCG should build (fan of each face line)
	std::vector<unsigned char> faux; // per triangle: bit k set if edge k is inside a polygon
	long long vertices = 0;
	bool vertexColours = false; // a vertex line with colours ('v x y z r g b')
	long long shortFaces = 0;   // face records with fewer than 3 vertices (VCG skips them)
	std::set<std::string> usedMaterials, definedMaterials; // (usemtl names; newmtl names of the
	                                                       // material files VCG opens)
};

/// A binary PLY file of the fast path's layout (read_ply_fast.cpp): where its body starts, its
/// counts.
struct SimplePly {
	bool ok = false;
	uint64_t offset = 0; ///< the body's first byte
	size_t vertices = 0, faces = 0;
	bool unsignedIndex = false; ///< uint indices (else int)
	int colour = 0;             ///< vertex colour: 0 none, 3 uchar red green blue, 4 and alpha
	size_t vertexBytes = 12;    ///< per vertex record: xyz, then the colour's bytes
};

constexpr size_t kPlyVertexBytes = 12, kPlyFaceBytes = 13; // (xyz; a count byte, three indices)
constexpr size_t kPlyBatch = 1 << 14;                      // records per fread

/// The current directory for a scope: VCG's OBJ importer opens mtllib files (and the .mtl named
/// after the OBJ) relative to it, so an OBJ is read from its own folder, as MeshLab's OBJ plugin
/// does. name() is the file's name from there. If the folder cannot be entered (or the current
/// one could not be restored) nothing changes.
class InFolder {
public:
	explicit InFolder(const std::string &path);
	~InFolder();
	InFolder(const InFolder &) = delete;
	InFolder &operator=(const InFolder &) = delete;
	const std::string &name() const { return name_; }

private:
	int fd_ = -1;
	std::string name_;
};

/// A file that passed the guards, ready for VCG's importer (readChecked).
struct CheckedFile {
	Format format = Format::Unknown;
	FileFacts facts;
	std::vector<float> stl;           ///< STL: the triangles' corners, read here
	ObjScan obj;                      ///< OBJ: its triangles as the scan read them
	std::unique_ptr<InFolder> folder; ///< OBJ: read from its own folder
	std::string vcgPath;              ///< the name VCG opens
	SimplePly ply;                    ///< PLY: where the fast path reads the body (ply.ok)
};

/// Everything before VCG reads the body: stat, sniffing, the guards of the format, the file's
/// load mask (check_file.cpp). `vb`, `fb`: bytes per vertex and face of the mesh type the memory
/// checks assume. `fastPly`: whether a binary PLY of the fast path's layout takes it.
bool checkFile(const std::string &path, double vb, double fb, CheckedFile &c, ReadError &e,
               bool fastPly = true);
/// checkFile for a caller that names the mesh type (the load mask does not depend on it).
template <class MeshT>
bool checkFile(const std::string &path, double vb, double fb, CheckedFile &c, ReadError &e,
               bool fastPly = true)
{
	return checkFile(path, vb, fb, c, e, fastPly);
}

/// Positions and triangles as the engine takes them (gausslod::FlatMesh's), read without a VCG
/// mesh (importMeshEither, `flat`).
struct FlatRead {
	bool used = false; ///< the file was read here (else into a VCG mesh)
	std::vector<double> positions;
	std::vector<int32_t> triangles;
};

/// A file of the fast path's layout (c.ply.ok) straight into flat arrays: the positions and
/// triangles gausslod::flatten makes of the mesh readChecked builds from it (same values, same
/// order, same errors), without that mesh and its copy.
bool readSimplePlyFlat(CheckedFile &c, FlatRead &out, ReadError &e, ReadInfo *info);

/// Reads a text stream line by line, each line made only of spaces, tabs and CRs given as an
/// empty line (VCG's OFF reader takes the first token of such a line as if there were one).
class BlankLineFilter : public std::streambuf {
public:
	explicit BlankLineFilter(std::istream &in) : in_(in) {}

protected:
	int_type underflow() override;

private:
	std::istream &in_;
	std::string line_;
};

/// The OBJ scan's notes for ReadInfo::notes: short face records skipped, materials no material
/// file defines.
void addObjNotes(const ObjScan &scan, std::vector<std::string> &notes);

/// VCG's importer on a file checkFile() passed; `info` (optional) gets the load mask and an OBJ's
/// materials.
template <class MeshT>
bool readChecked(MeshT &m, CheckedFile &c, ReadError &e, ReadInfo *info);

/// fn() with every exception turned into `error` (bad_alloc: TooLarge).
template <class Fn>
bool guarded(ReadError &error, Fn fn)
{
	error = ReadError();
	try {
		return fn();
	} catch (const std::bad_alloc &) {
		return fail(error, ReadStatus::TooLarge, "not enough memory to read the file");
	} catch (const std::exception &x) {
		return corrupt(error, std::string("the reader failed: ") + x.what());
	} catch (...) {
		return corrupt(error, "the reader failed");
	}
}

} // namespace detail
} // namespace gausslod

#include "read_vcg.h"

// (compiled once, in read_vcg.cpp)
namespace gausslod {
extern template bool importMesh<IoMesh>(IoMesh &, const std::string &, ReadError &, ReadInfo *);
extern template bool importMesh<IoAttrMesh>(IoAttrMesh &, const std::string &, ReadError &,
                                            ReadInfo *);
extern template bool importMeshEither<IoMesh, IoAttrMesh>(IoMesh &, IoAttrMesh &, bool &,
                                                          const std::string &, int, ReadError &,
                                                          ReadInfo *, detail::FlatRead *);
namespace detail {
extern template bool readChecked<IoMesh>(IoMesh &, CheckedFile &, ReadError &, ReadInfo *);
extern template bool readChecked<IoAttrMesh>(IoAttrMesh &, CheckedFile &, ReadError &, ReadInfo *);
} // namespace detail
} // namespace gausslod
