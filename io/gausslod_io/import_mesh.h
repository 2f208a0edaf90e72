// Reads a mesh file (PLY, OBJ, OFF, STL) into any VCG mesh type, guarding VCG 2020.09's importers
// against hostile files: every problem is reported as a category and a one-line message, nothing
// crashes, hangs, throws or silently reads garbage. What each guard covers (VCG file:line):
//  - all: stat first (missing, directory, FIFO, empty); the content is sniffed against the name;
//    what a header claims is checked against the file size and the available memory before VCG
//    allocates it; bad_alloc and anything VCG throws are caught; after reading, every face's vertex
//    pointers must lie inside m.vert.
//  - OFF (import_off.h): counts and face indices read with atoi and never range-checked (:210,
//    :450, :471 reads vert[idx] of polygons), a face line missing at EOF read as tokens[0] (:435),
//    a huge vertex-per-face count allocated before reading (:457-461), colour-map index unchecked
//    (:296, :550), a line of blanks read as if it had a token (crash on CGAL's prim.off), float
//    colours cast to bytes out of range (:317, color4.h:295). A pre-scan that
//    tokenizes exactly as VCG does validates all of it; blank lines are emptied for VCG.
//  - OBJ (import_obj.h): vertex lines counted one way (:897) and read another (:290, writes past
//    m.vert), m.vert[idx] read before the range check (:471-473), '\' continuations joined out of
//    bounds (:757-761), line elements' indices unchecked (:656), #MRGB colours indexed past
//    their end (:731), vertex colours cast to bytes out of range (:313), mtllib opening any path
//    (/dev/zero, a FIFO) (:591), material attributes that leak (:237: dropped after reading).
//    VCG also drops every face that uses vertex 1 (:186, index 0 taken as invalid): those faces
//    are rebuilt from the pre-scan, which reads every face line.
//  - PLY (plylib.cpp, import_ply.h): header lines longer than its 510-byte buffer, blank ones
//    (strcmp(NULL), plylib.cpp:1056) or an element line without a count (atoi(NULL), :1171);
//    list counts copied into fixed arrays without bound (face v[512], plylib.cpp:1924, skip
//    buffers of 512 bytes :1865); the last index of a polygon never checked (import_ply.h:895);
//    tristrips and range grids (leaked lists, unchecked indices); a face element without an index
//    list (faces read from uninitialised memory, import_ply.h:761); a TextureFile comment copied
//    into char[255] (import_ply.h:1041). The header is read with VCG's
//    own PlyFile; the element data is walked once before VCG reads it.
//  - STL (import_stl.h): two FILE handles leaked per binary file (:115, :153), one per truncated
//    ASCII file (:295), an endless loop on a file without a line break (:270), a lying triangle
//    count read past EOF (:221). STL is therefore read here (binary: exact size 84 + 50 n; ASCII:
//    strict grammar) into the same unshared-vertex soup VCG builds.
//
// OBJ and OFF polygons of 5+ corners are split by GLU's tessellator, as in MeshLab's io_base (a
// fan would fold concave polygons); the OBJ index defect of VCG 2020.09 (every face using the
// first vertex dropped) is fixed for IoMesh and IoAttrMesh by obj_import.h, as in the OBJ plugin,
// so that the tool reads a file into the same triangles as the filter gets from MeshLab. An OBJ
// is read from its own folder (VCG opens its mtllib relative to the current directory), as the
// OBJ plugin does. importMeshEither() reads into a lean mesh type unless the file's load mask
// (VCG's LoadMask, or the OFF pre-scan) has attributes worth the richer one.
//
// Binary PLY files of the layout VCG and MeshLab write for a mesh without attributes (little
// endian; float x, y, z; faces as "list uchar int|uint vertex_indices", every face a triangle)
// are read here, at once, into the same mesh VCG's importer builds (DESIGN 33; tested against
// VCG's reader file by file, bit for bit): plylib reads them value by value and took most of the
// time of loading a large mesh. Anything else in such a file (a polygon, an index out of range,
// a short body) leaves it to the walk and VCG's importer, with their messages.
#pragma once

#include <GL/glu.h> // before VCG's importers: their polygon tessellation then uses GLU

#include "io_mesh.h"
#include "obj_import.h"

#include <vcg/complex/complex.h>
#include <wrap/io_trimesh/import.h>
#include <wrap/ply/plylib.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fstream>
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
	bool fastPly = false; ///< read by the binary PLY fast path (see the top of this file)
	/// What the reader skipped or could not apply, a clause each ("1 face record with fewer
	/// than 3 vertices skipped"): the file is read all the same
	std::vector<std::string> notes;
};

inline const char *readStatusName(ReadStatus s)
{
	switch (s) {
		case ReadStatus::Ok: return "ok";
		case ReadStatus::CannotOpen: return "cannot_open";
		case ReadStatus::Empty: return "empty";
		case ReadStatus::WrongFormat: return "wrong_format";
		case ReadStatus::Corrupt: return "corrupt";
		case ReadStatus::TooLarge: return "too_large";
	}
	return "unknown";
}

namespace detail {

enum class Format { Unknown, Ply, Obj, Off, Stl };

inline const char *formatName(Format f)
{
	static const char *names[] = {"unknown", "PLY", "OBJ", "OFF", "STL"};
	return names[int(f)];
}

/// "a PLY", "an OBJ", "an OFF", "an STL"
inline std::string withArticle(Format f)
{
	return std::string(f == Format::Ply ? "a " : "an ") + formatName(f);
}

inline bool fail(ReadError &e, ReadStatus s, const std::string &msg)
{
	e.status = s;
	e.message = msg;
	return false;
}
inline bool corrupt(ReadError &e, const std::string &msg)
{
	return fail(e, ReadStatus::Corrupt, msg);
}

inline std::string num(long long v) { return std::to_string(v); }
/// A value read as a double (any size, NaN included) for a message.
inline std::string numD(double v)
{
	char s[32];
	std::snprintf(s, sizeof s, "%.6g", v);
	return s;
}

/// A word from the file, fit for a one-line message (printable, at most 24 characters).
inline std::string quote(const char *b, const char *e)
{
	std::string s = "'";
	for (const char *p = b; p < e && s.size() < 25; ++p)
		s += (*p >= 32 && *p < 127) ? *p : '?';
	return s + (e - b > 24 ? "...'" : "'");
}

inline std::string lowerExtension(const std::string &path)
{
	const size_t dot = path.find_last_of('.');
	if (dot == std::string::npos || path.find('/', dot) != std::string::npos)
		return std::string();
	std::string e = path.substr(dot + 1);
	for (char &c : e)
		c = char(std::tolower(static_cast<unsigned char>(c)));
	return e;
}

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

/// Bytes of memory the process can still take: MemAvailable, else free physical pages.
inline uint64_t availableMemory()
{
	if (FILE *f = std::fopen("/proc/meminfo", "r")) {
		char line[128];
		unsigned long long kb = 0;
		bool found = false;
		while (!found && std::fgets(line, sizeof line, f))
			found = std::sscanf(line, "MemAvailable: %llu kB", &kb) == 1;
		std::fclose(f);
		if (found)
			return uint64_t(kb) * 1024;
	}
	const long pages = sysconf(_SC_AVPHYS_PAGES), page = sysconf(_SC_PAGESIZE);
	return pages > 0 && page > 0 ? uint64_t(pages) * uint64_t(page) : UINT64_MAX;
}

inline std::string bytesText(double b)
{
	char s[32];
	if (b >= 1e9)
		std::snprintf(s, sizeof s, "%.1f GB", b / 1e9);
	else
		std::snprintf(s, sizeof s, "%.1f MB", b / 1e6);
	return s;
}

/// TooLarge if `need` bytes (the mesh a header announces) exceed the available memory.
inline bool checkMemory(double need, ReadError &e)
{
	const double avail = double(availableMemory());
	if (need <= avail)
		return true;
	return fail(e, ReadStatus::TooLarge,
	            "the header's counts need " + bytesText(need) + " of memory but only " +
	                bytesText(avail) + " is available");
}

inline bool lyingCounts(ReadError &e, unsigned long long nv, unsigned long long nf, const char *fw,
                        uint64_t size)
{
	return corrupt(e, "the header announces " + std::to_string(nv) + " vertices and " +
	                      std::to_string(nf) + " " + fw + " but the file has only " +
	                      std::to_string(size) + " bytes");
}

/// Whole word [b, e) as an integer (optional sign, trailing CRs allowed, as atoi would read them).
inline bool parseInt(const char *b, const char *e, long long &v)
{
	while (e > b && e[-1] == '\r')
		--e;
	const char *p = b;
	bool neg = false;
	if (p < e && (*p == '-' || *p == '+'))
		neg = *p++ == '-';
	if (p == e || e - p > 12)
		return false;
	v = 0;
	for (; p < e; ++p) {
		if (*p < '0' || *p > '9')
			return false;
		v = v * 10 + (*p - '0');
	}
	if (neg)
		v = -v;
	return v >= INT32_MIN && v <= INT32_MAX;
}

/// Whole word [b, e) as a count: digits only (up to 18, so that a lying count is still read).
inline bool parseCount(const char *b, const char *e, long long &v)
{
	while (e > b && e[-1] == '\r')
		--e;
	if (e == b || e - b > 18)
		return false;
	v = 0;
	for (const char *p = b; p < e; ++p) {
		if (*p < '0' || *p > '9')
			return false;
		v = v * 10 + (*p - '0');
	}
	return true;
}

/// Whole word [b, e) as a number (nan and inf included: the engine rejects them, not the reader).
inline bool parseNumber(const char *b, const char *e)
{
	while (e > b && e[-1] == '\r')
		--e;
	char buf[64];
	if (e <= b || e - b >= int(sizeof buf))
		return false;
	std::memcpy(buf, b, size_t(e - b));
	buf[e - b] = 0;
	char *end = nullptr;
	std::strtod(buf, &end);
	return end == buf + (e - b);
}

struct Word {
	const char *b, *e;
};

/// A colour word VCG turns into a byte as (unsigned char)(float(atof(word)) * scale): undefined
/// unless the product lies in (-1, 256) (color4.h:295, import_obj.h:312).
inline bool colourByteOk(const Word &w, float scale)
{
	if (!parseNumber(w.b, w.e))
		return false;
	const float x = float(std::strtod(std::string(w.b, w.e).c_str(), nullptr)) * scale;
	return x > -1.0f && x < 256.0f;
}

/// VCG's float colours (import_off.h:301, :555): the first word holding a '.' makes all floats.
inline bool offColoursOk(const std::vector<Word> &w, size_t k, long long n)
{
	if ((n != 3 && n != 4) || std::find(w[k].b, w[k].e, '.') == w[k].e)
		return true;
	for (size_t i = k; i < k + size_t(n); ++i)
		if (!colourByteOk(w[i], 255.0f))
			return false;
	return true;
}

/// Lines of a FILE without a heap allocation per line (getline reuses its buffer).
class LineReader {
public:
	explicit LineReader(FILE *f) : f_(f) {}
	~LineReader() { std::free(buf_); }
	LineReader(const LineReader &) = delete;
	LineReader &operator=(const LineReader &) = delete;
	/// Next line without its '\n'; false at end of file.
	bool next()
	{
		const ssize_t n = ::getline(&buf_, &cap_, f_);
		if (n < 0)
			return false;
		len_ = size_t(n);
		if (len_ && buf_[len_ - 1] == '\n')
			--len_;
		++number_;
		return true;
	}
	const char *data() const { return buf_; }
	size_t size() const { return len_; }
	size_t number() const { return number_; }

private:
	FILE *f_;
	char *buf_ = nullptr;
	size_t cap_ = 0, len_ = 0, number_ = 0;
};

// ---- OFF ---------------------------------------------------------------------------------------

/// The lines of an OFF file as VCG's TokenizeNextLine (import_off.h:615) returns them, read through
/// the blank-line filter: lines empty, blank, or starting with '#' or CR are skipped; words are
/// split at spaces and tabs, CRs inside or at the end of a word stay in it.
class OffTokens {
public:
	explicit OffTokens(FILE *f) : lines_(f) {}
	/// The next line's words (none at end of file).
	const std::vector<Word> &nextLine()
	{
		words_.clear();
		while (lines_.next()) {
			const char *p = lines_.data(), *end = p + lines_.size();
			bool blank = true;
			for (const char *q = p; q < end && blank; ++q)
				blank = *q == ' ' || *q == '\t' || *q == '\r';
			if (blank || *p == '#' || *p == '\r')
				continue;
			while (p < end) {
				while (p < end && (*p == ' ' || *p == '\t' || *p == '\r'))
					++p;
				if (p == end)
					break;
				const char *q = p + 1;
				while (q < end && *q != ' ' && *q != '\t')
					++q;
				words_.push_back({p, q});
				p = q;
			}
			break;
		}
		return words_;
	}
	size_t line() const { return lines_.number(); }

private:
	LineReader lines_;
	std::vector<Word> words_;
};

/// What the guards learnt of a file: element counts (for memory estimates) and VCG's load mask
/// (vcg::tri::io::Mask: the attributes the file carries), known before its body is read.
struct FileFacts {
	double vertices = 0, faces = 0;
	int mask = 0;
};

/// Checks an OFF file exactly as VCG's ImporterOFF will read it (see the top of this file).
inline bool scanOff(FILE *f, uint64_t size, double vertexBytes, double faceBytes, ReadError &e,
                    FileFacts &facts)
{
	OffTokens in(f);
	std::vector<Word> w = in.nextLine();
	if (w.empty())
		return fail(e, ReadStatus::Empty, "only comments or blanks, no OFF header");
	const std::string head(w[0].b, w[0].e);
	const size_t off = head.rfind("OFF");
	if (off == std::string::npos)
		return corrupt(e, "no OFF header (the first word is " + quote(w[0].b, w[0].e) + ")");
	bool color = false, normal = false, tex = false, vertexColour = false, faceColour = false;
	for (size_t u = 0; u < off; ++u) {
		const char c = head[u];
		if (c == 'n' || c == '4')
			return corrupt(e, std::string("OFF with ") +
			                      (c == 'n' ? "n-dimensional" : "homogeneous (4D)") +
			                      " vertices is not supported");
		color |= c == 'C';
		normal |= c == 'N';
		tex |= c == 'T' && u > 0 && head[u - 1] == 'S';
	}
	if (w.size() == 1)
		w = in.nextLine();
	else
		w.erase(w.begin());
	long long nv, nf;
	if (w.size() < 3)
		return corrupt(e, "the OFF header has no vertex, face and edge counts");
	if (!parseCount(w[0].b, w[0].e, nv) || !parseCount(w[1].b, w[1].e, nf))
		return corrupt(e, "bad OFF counts " + quote(w[0].b, w[0].e) + " " + quote(w[1].b, w[1].e));
	// a vertex takes at least "0 0 0\n", a face "3 0 1 2\n"
	if (6.0 * double(nv) + 8.0 * double(nf) > double(size) + 1)
		return lyingCounts(e, (unsigned long long)nv, (unsigned long long)nf, "faces", size);
	if (!checkMemory(double(nv) * vertexBytes + double(nf) * faceBytes, e))
		return false;

	size_t k = 0;
	w = in.nextLine();
	// the next word, continuing on the next line as VCG does; false at end of file
	auto nextWord = [&](Word &out) {
		if (k == w.size()) {
			w = in.nextLine();
			k = 0;
			if (w.empty())
				return false;
		}
		out = w[k++];
		return true;
	};
	auto truncated = [&](const char *what, long long i, long long n) {
		return corrupt(e, std::string("truncated: the file ends in ") + what + " " + num(i) +
		                      " of " + num(n));
	};
	Word t;
	for (long long i = 0; i < nv; ++i) {
		for (int j = 0; j < (normal ? 6 : 3); ++j) {
			if (!nextWord(t))
				return truncated("vertex", i, nv);
			if (!parseNumber(t.b, t.e))
				return corrupt(e, "line " + num((long long)in.line()) + ": " + quote(t.b, t.e) +
				                      " is not a number");
		}
		if (color) { // VCG counts the colour words left on the line (import_off.h:277)
			const long long nc = (long long)w.size() - (long long)k - (tex ? 2 : 0);
			vertexColour |= nc > 0;
			if (nc < 0 || nc > 4)
				return corrupt(e, "vertex " + num(i) + " has " + num(nc) + " colour components");
			long long c;
			if (nc == 1 && (!parseInt(w[k].b, w[k].e, c) || c < 0 || c >= 148))
				return corrupt(e, "vertex " + num(i) + ": colour-map index " +
				                      quote(w[k].b, w[k].e) + " out of range 0..147");
			if (!offColoursOk(w, k, nc))
				return corrupt(e, "vertex " + num(i) + ": colour component out of range 0..1");
			k += size_t(nc);
		}
		for (int j = 0; tex && j < 2; ++j)
			if (!nextWord(t))
				return truncated("vertex", i, nv);
	}
	double triangles = 0;
	for (long long i = 0; i < nf; ++i) {
		w = in.nextLine();
		k = 1;
		long long n;
		if (w.empty())
			return truncated("face", i, nf);
		if (!parseInt(w[0].b, w[0].e, n) || n < 3)
			return corrupt(e, "face " + num(i) + " has " + quote(w[0].b, w[0].e) +
			                      " vertices (at least 3)");
		for (long long j = 0; j < n; ++j) {
			long long idx;
			if (!nextWord(t))
				return truncated("face", i, nf);
			if (!parseInt(t.b, t.e, idx) || idx < 0 || idx >= nv)
				return corrupt(e, "face " + num(i) + " uses vertex index " + quote(t.b, t.e) +
				                      ", outside 0.." + num(nv - 1));
		}
		triangles += double(n - 2);
		long long c; // one colour word left: a colour-map index (import_off.h:550)
		if (w.size() == size_t(n) + 2 &&
		    (!parseInt(w[n + 1].b, w[n + 1].e, c) || c < 0 || c >= 148))
			return corrupt(e, "face " + num(i) + ": colour-map index " +
			                      quote(w[n + 1].b, w[n + 1].e) + " out of range 0..147");
		faceColour |= w.size() > size_t(n) + 1; // (import_off.h:532)
		if (w.size() >= size_t(n) + 1 &&
		    !offColoursOk(w, size_t(n) + 1, (long long)w.size() - n - 1))
			return corrupt(e, "face " + num(i) + ": colour component out of range 0..1");
	}
	if (nv == 0 && nf == 0)
		return fail(e, ReadStatus::Empty, "the OFF file holds no vertex and no face");
	using vcg::tri::io::Mask;
	facts.vertices = double(nv);
	facts.faces = triangles;
	facts.mask = Mask::IOM_VERTCOORD | Mask::IOM_FACEINDEX | (normal ? Mask::IOM_VERTNORMAL : 0) |
	             (tex ? Mask::IOM_VERTTEXCOORD : 0) | (vertexColour ? Mask::IOM_VERTCOLOR : 0) |
	             (faceColour ? Mask::IOM_FACECOLOR : 0);
	return checkMemory(double(nv) * vertexBytes + triangles * faceBytes, e);
}

/// Reads a text stream line by line, each line made only of spaces, tabs and CRs given as an
/// empty line (VCG's OFF reader takes the first token of such a line as if there were one).
class BlankLineFilter : public std::streambuf {
public:
	explicit BlankLineFilter(std::istream &in) : in_(in) {}

protected:
	int_type underflow() override
	{
		if (gptr() < egptr())
			return traits_type::to_int_type(*gptr());
		if (!std::getline(in_, line_))
			return traits_type::eof();
		if (line_.find_first_not_of(" \t\r") == std::string::npos)
			line_.clear();
		line_.push_back('\n');
		setg(&line_[0], &line_[0], &line_[0] + line_.size());
		return traits_type::to_int_type(*gptr());
	}

private:
	std::istream &in_;
	std::string line_;
};

// ---- OBJ ---------------------------------------------------------------------------------------

struct ObjScan {
	std::vector<int> tri;            // the triangles VCG should build (fan of each face line)
	std::vector<unsigned char> faux; // per triangle: bit k set if edge k is inside a polygon
	long long vertices = 0;
	bool vertexColours = false; // a vertex line with colours ('v x y z r g b')
	long long shortFaces = 0;   // face records with fewer than 3 vertices (VCG skips them)
	std::set<std::string> usedMaterials, definedMaterials; // (usemtl names; newmtl names of the
	                                                       // material files VCG opens)
};

/// A material file VCG will open (relative to the working directory, the OBJ's folder while it is
/// read): it must be a regular file, and its '\' continuations must be ones VCG joins in bounds.
inline bool checkContinuations(LineReader &in, const char *where, ReadError &e);

inline bool checkMaterialFile(const std::string &name, ReadError &e,
                              std::set<std::string> *defined = nullptr)
{
	struct stat st;
	if (::stat(name.c_str(), &st) != 0)
		return true; // VCG reports it missing and goes on with a default material
	if (!S_ISREG(st.st_mode))
		return corrupt(e, "the material file " + quote(name.data(), name.data() + name.size()) +
		                      " is not a regular file");
	File f(name);
	if (!f.f)
		return true;
	LineReader in(f.f);
	while (in.next()) {
		if (!checkContinuations(in, "the material file", e))
			return false;
		const char *b = in.data(), *end = in.data() + in.size();
		while (b < end && (*b == ' ' || *b == '\t'))
			++b;
		if (defined && end - b > 7 && std::strncmp(b, "newmtl", 6) == 0 &&
		    (b[6] == ' ' || b[6] == '\t')) {
			b += 7;
			while (b < end && (*b == ' ' || *b == '\t'))
				++b;
			while (end > b && (end[-1] == '\r' || end[-1] == ' ' || end[-1] == '\t'))
				--end;
			defined->emplace(b, end);
		}
	}
	return true;
}

/// Joins '\'-continued lines as VCG (import_obj.h:756) does, refusing the joins it gets wrong
/// (an empty or missing next line: back() of an empty string; a CRLF next line: it pops the wrong
/// string). `joined` gets the logical line when there was a continuation.
/// Vertex and texture-coordinate lines as VCG's LoadMask counts them, by their first two
/// characters (import_obj.h:897-914); Open allocates and indexes by these counts.
struct ObjMaskCount {
	long long v = 0, vt = 0, vn = 0;
	void add(const LineReader &in)
	{
		if (in.size() > 2 && in.data()[0] == 'v') {
			v += in.data()[1] == ' ' || in.data()[1] == '\t';
			vt += in.data()[1] == 't';
			vn += in.data()[1] == 'n';
		}
	}
};

inline bool joinLine(LineReader &in, std::string &joined, bool &usedJoined, const char *where,
                     ReadError &e, ObjMaskCount *mask = nullptr)
{
	size_t n = in.size();
	if (n && in.data()[n - 1] == '\r')
		--n;
	usedJoined = false;
	if (!n || in.data()[n - 1] != '\\')
		return true;
	const size_t first = in.number();
	joined.assign(in.data(), n);
	while (!joined.empty() && joined.back() == '\\') {
		if (!in.next() || in.size() == 0)
			return corrupt(e, std::string(where) + " line " + num((long long)first) +
			                      " ends with a '\\' continuation but no line follows");
		if (in.data()[in.size() - 1] == '\r')
			return corrupt(e,
			               std::string(where) + " line " + num((long long)first) +
			                   ": a '\\' continuation with CRLF line ends (VCG joins it wrongly)");
		if (mask)
			mask->add(in);
		joined.pop_back();
		joined.append(in.data(), in.size());
	}
	usedJoined = true;
	return true;
}

inline bool checkContinuations(LineReader &in, const char *where, ReadError &e)
{
	std::string joined;
	bool used;
	return joinLine(in, joined, used, where, e);
}

/// Checks an OBJ file as VCG's ImporterOBJ will read it and collects its triangles.
inline bool scanObj(FILE *f, const std::string &path, uint64_t size, double vertexBytes,
                    double faceBytes, ObjScan &out, ReadError &e)
{
	LineReader in(f);
	std::string joined;
	std::vector<Word> w;
	std::vector<int> poly;
	ObjMaskCount mask;
	long long nvt = 0, nvn = 0, mrgb = 0, statements = 0;
	bool usemtl = false;
	while (in.next()) {
		// VCG's LoadMask counts vertex lines by their first two characters (import_obj.h:897)
		mask.add(in);
		const size_t lineNo = in.number();
		bool used;
		if (!joinLine(in, joined, used, "OBJ", e, &mask))
			return false;
		const char *p = used ? joined.data() : in.data();
		size_t len = used ? joined.size() : in.size();
		if (!used && len && p[len - 1] == '\r')
			--len;
		const char *const start = p, *const end = p + len;
		auto at = [lineNo]() { return "line " + num((long long)lineNo) + ": "; };
		if (len == 0)
			continue;
		if (p[0] == '#') {
			if (len >= 5 && std::strncmp(p, "#MRGB", 5) == 0)
				for (size_t i = 6; i + 7 < len; i += 8)
					++mrgb;
			continue;
		}
		w.clear();
		while (p < end) {
			while (p < end && (*p == ' ' || *p == '\t' || *p == '\r'))
				++p;
			if (p == end)
				break;
			const char *q = p + 1;
			while (q < end && *q != ' ' && *q != '\t' && *q != '\r')
				++q;
			w.push_back({p, q});
			p = q;
		}
		if (w.empty())
			continue;
		const size_t hl = size_t(w[0].e - w[0].b);
		auto is = [&](const char *s) {
			return std::strlen(s) == hl && !std::strncmp(w[0].b, s, hl);
		};
		if (is("v")) {
			++out.vertices;
			++statements;
			if (w.size() < 4)
				return corrupt(e, at() + "a vertex with fewer than 3 coordinates");
			for (int j = 1; j < 4; ++j)
				if (!parseNumber(w[j].b, w[j].e))
					return corrupt(e, at() + quote(w[j].b, w[j].e) + " is not a number");
			if (w.size() >= 7) { // colours, scaled as VCG does (import_obj.h:309-315)
				out.vertexColours = true;
				float c[3];
				for (int j = 0; j < 3; ++j)
					c[j] = parseNumber(w[4 + j].b, w[4 + j].e)
					           ? float(std::strtod(std::string(w[4 + j].b, w[4 + j].e).c_str(),
					                               nullptr))
					           : 1e9f;
				const float scale = c[0] <= 1 && c[1] <= 1 && c[2] <= 1 ? 255.0f : 1.0f;
				bool okc = true;
				for (size_t j = 4; j < std::min<size_t>(w.size(), 8); ++j)
					okc = okc && colourByteOk(w[j], scale);
				if (!okc)
					return corrupt(e, at() + "a vertex colour out of range");
			}
			if (out.vertices > mask.v)
				return corrupt(e, at() + "a vertex statement that does not start its line as "
				                         "'v x y z'");
		} else if (is("vt")) {
			nvt += w.size() >= 3; // (VCG stops at a shorter one)
		} else if (is("vn")) {
			nvn += w.size() == 4; // (VCG stops at another)
		} else if (is("f") || is("q")) {
			++statements;
			const bool q = is("q");
			const long long n = (long long)w.size() - 1;
			if (n < 3 || (q && n != 4)) {
				out.shortFaces += !q;
				continue; // VCG skips it (q: fails with its own error)
			}
			poly.clear();
			for (long long j = 1; j <= n; ++j) {
				const char *s1 = std::find(w[j].b, w[j].e, '/');
				long long r;
				if (!parseInt(w[j].b, s1, r))
					return corrupt(e, at() + "bad vertex index " + quote(w[j].b, w[j].e));
				const long long v = q ? r : (r > 0 ? r - 1 : out.vertices + r);
				if ((!q && r == 0) || v < 0 || v >= out.vertices)
					return corrupt(e, at() + "face uses vertex " + quote(w[j].b, s1) + " but " +
					                      num(out.vertices) + " vertices are defined before it");
				// texture and normal indices, split as VCG's SplitToken (import_obj.h:822) does,
				// must name earlier vt / vn lines: an empty one is -1 there, which its
				// GoodObjIndex turns into one past the end (:190, read at :683 and :695)
				const char *s2 = s1 == w[j].e ? s1 : std::find(s1 + 1, w[j].e, '/');
				const long long counts[2] = {nvt, nvn};
				const Word parts[2] = {{s1 == w[j].e ? s1 : s1 + 1, s2},
				                       {s2 == w[j].e ? s2 : s2 + 1, w[j].e}};
				const bool given[2] = {s1 != w[j].e && (s2 == w[j].e || s1 + 1 < s2), s2 != w[j].e};
				for (int c = 0; c < 2; ++c) {
					if (!given[c])
						continue;
					if (!parseInt(parts[c].b, parts[c].e, r) || r == 0 ||
					    (r > 0 ? r : -r) > counts[c])
						return corrupt(e, at() + "face uses " + (c ? "normal " : "texture ") +
						                      quote(parts[c].b, parts[c].e) + " but " +
						                      num(counts[c]) + " are defined before it");
				}
				poly.push_back(int(v));
			}
			// fan triangulation, as VCG's FanTessellator; triangles repeating a vertex dropped
			for (long long j = 0; j + 2 < n; ++j) {
				const int a = poly[0], b = poly[size_t(j + 1)], c = poly[size_t(j + 2)];
				if (a == b || a == c || b == c)
					continue;
				out.tri.insert(out.tri.end(), {a, b, c});
				out.faux.push_back((unsigned char)((j > 0 ? 4 : 0) | (j + 3 < n ? 2 : 0)));
			}
		} else if (is("l") && w.size() >= 3) { // VCG takes &m.vert[atoi - 1] of both (:369, :656)
			for (int j = 1; j < 3; ++j) {
				long long r;
				if (!parseInt(w[j].b, std::find(w[j].b, w[j].e, '/'), r) || r < 1 ||
				    r > out.vertices)
					return corrupt(e, at() + "line element uses vertex " + quote(w[j].b, w[j].e) +
					                      " but " + num(out.vertices) +
					                      " vertices are defined before it");
			}
		} else if (is("mtllib") && w.size() > 1) {
			const std::string name = w.size() == 2
			                             ? std::string(w[1].b, w[1].e)
			                             : std::string(start + std::min<size_t>(7, len), end);
			if (!checkMaterialFile(name, e, &out.definedMaterials))
				return false;
		} else if (is("usemtl")) {
			usemtl = true;
			if (w.size() > 1)
				out.usedMaterials.emplace(w[1].b, w[w.size() - 1].e);
		}
	}
	if (usemtl && path.size() >= 4 &&
	    !checkMaterialFile(path.substr(0, path.size() - 4) + ".mtl", e, &out.definedMaterials))
		return false;
	if (out.vertices != mask.v)
		return corrupt(e, num(mask.v) + " lines start with 'v ' but " + num(out.vertices) +
		                      " vertex statements were found");
	// with as many texture as vertex lines VCG reads texCoords[t] of every face corner, t = 0
	// when the corner gives none (import_obj.h:682): the counts must agree
	if (nvt != mask.vt && mask.vt == mask.v)
		return corrupt(e, num(mask.vt) + " lines start with 'vt' but " + num(nvt) +
		                      " texture coordinates were found");
	// with as many normal as vertex lines VCG reads normals[n] of every corner, n its vertex
	// number when it gives none (:834, :695), GoodObjIndex letting one past the end through
	if (nvn != mask.vn && mask.vn == mask.v)
		return corrupt(e, num(mask.vn) + " lines start with 'vn' but " + num(nvn) +
		                      " normals were found");
	if (mrgb > 0 && mrgb < mask.v) // VCG reads one #MRGB colour per vertex (import_obj.h:731)
		return corrupt(e, "#MRGB colours for " + num(mrgb) + " of " + num(mask.v) + " vertices");
	if (statements == 0)
		return fail(e, ReadStatus::Empty, "no vertex and no face statement");
	(void)size;
	return checkMemory(double(out.vertices) * vertexBytes + double(out.faux.size()) * faceBytes, e);
}

// ---- PLY ---------------------------------------------------------------------------------------

struct PlyHeader {
	uint64_t dataOffset = 0;
	int format = 0; // 1 ascii, 2 binary little endian, 3 binary big endian (as plylib)
};

/// The header lines as raw text, before VCG's PlyFile parses them: each must end in '\n' within
/// plylib's 510-byte line buffer and an element line must carry a count (plylib.cpp:1022-1171).
inline bool precheckPlyHeader(FILE *f, PlyHeader &h, ReadError &e)
{
	char line[512];
	uint64_t offset = 0;
	for (int n = 0;; ++n) {
		if (!std::fgets(line, 500, f))
			return corrupt(e, "truncated PLY header (no end_header line)");
		const size_t len = std::strlen(line);
		if (n == 0 && std::strncmp(line, "ply", 3) != 0)
			return corrupt(e, "no PLY header (the file does not start with 'ply')");
		if (len == 0 || line[len - 1] != '\n') {
			if (std::feof(f))
				return corrupt(e, "truncated PLY header (no end_header line)");
			return corrupt(e, "PLY header line " + num(n + 1) + " is too long or holds a NUL byte");
		}
		offset += len;
		char *save = nullptr;
		const char *word = strtok_r(line, " \t\r\n", &save);
		if (!word) // (plylib compares a blank line after a comment with strcmp(NULL), :1056)
			return corrupt(e, "PLY header line " + num(n + 1) + " is blank");
		if (n == 0 && std::strcmp(word, "ply") != 0)
			return corrupt(e, "no PLY header (the file does not start with 'ply')");
		if (std::strcmp(word, "format") == 0) {
			const char *fmt = strtok_r(nullptr, " \t\r\n", &save);
			h.format = !fmt                                        ? 0
			           : !std::strcmp(fmt, "ascii")                ? 1
			           : !std::strcmp(fmt, "binary_little_endian") ? 2
			           : !std::strcmp(fmt, "binary_big_endian")    ? 3
			                                                       : 0;
		} else if (std::strcmp(word, "element") == 0) {
			const char *name = strtok_r(nullptr, " \t\r\n", &save);
			const char *count = name ? strtok_r(nullptr, " \t\r\n", &save) : nullptr;
			long long c;
			if (!count || !parseInt(count, count + std::strlen(count), c) || c < 0)
				return corrupt(e, "PLY header line " + num(n + 1) +
				                      ": an element without a valid count");
		} else if (std::strcmp(word, "end_header") == 0) {
			h.dataOffset = offset;
			return true;
		}
	}
}

inline int plyTypeSize(int t)
{
	static const int sizes[] = {0, 1, 2, 4, 1, 2, 4, 4, 8};
	return t > 0 && t < 9 ? sizes[t] : 0;
}
inline bool plyTypeIsInt(int t) { return t >= vcg::ply::T_CHAR && t <= vcg::ply::T_UINT; }

/// The face index lists VCG's ImporterPLY has a descriptor for (import_ply.h:211-236); any other
/// is skipped by plylib as if its count were one byte, into a 512-byte buffer (plylib.cpp:1865).
inline bool plyFaceListReadable(const vcg::ply::PlyProperty &p)
{
	using namespace vcg::ply;
	if (!p.islist)
		return false;
	const int c = p.tipoindex, t = p.tipo;
	const bool count = c == T_UCHAR || c == T_CHAR || c == T_INT;
	if (p.name == "vertex_index")
		return t == T_INT && count;
	return ((t == T_INT || t == T_SHORT) && count) || (t == T_UINT && (count || c == T_USHORT));
}

/// The value of type T stored (host byte order) at b, as a double.
template <class T>
double storedAs(const unsigned char *b)
{
	T x;
	std::memcpy(&x, b, sizeof x);
	return double(x);
}

/// One value of type t from a binary PLY body, as a double (integers exactly).
inline bool readPlyBinary(FILE *f, int t, bool bigEndian, double &v)
{
	unsigned char b[8];
	const int n = plyTypeSize(t);
	if (std::fread(b, 1, size_t(n), f) != size_t(n))
		return false;
	if (bigEndian)
		std::reverse(b, b + n);
	switch (t) {
		case vcg::ply::T_CHAR: v = storedAs<int8_t>(b); break;
		case vcg::ply::T_UCHAR: v = storedAs<uint8_t>(b); break;
		case vcg::ply::T_SHORT: v = storedAs<int16_t>(b); break;
		case vcg::ply::T_USHORT: v = storedAs<uint16_t>(b); break;
		case vcg::ply::T_INT: v = storedAs<int32_t>(b); break;
		case vcg::ply::T_UINT: v = storedAs<uint32_t>(b); break;
		case vcg::ply::T_FLOAT: v = storedAs<float>(b); break;
		default: v = storedAs<double>(b); break;
	}
	return true;
}

/// One word of an ASCII PLY body, checked as plylib's fscanf will read it (%d or %f).
inline bool readPlyAscii(FILE *f, int t, double &v, bool &bad)
{
	char buf[64];
	size_t n = 0;
	int c;
	while ((c = getc_unlocked(f)) != EOF && std::isspace(c))
		;
	for (; c != EOF && !std::isspace(c); c = getc_unlocked(f))
		if (n < sizeof buf - 1)
			buf[n++] = char(c);
		else
			bad = true;
	buf[n] = 0;
	if (n == 0)
		return false;
	char *end = nullptr;
	v = plyTypeIsInt(t) ? double(std::strtoll(buf, &end, 10)) : std::strtod(buf, &end);
	bad = bad || end != buf + n;
	return true;
}

/// A binary PLY file of the fast path's layout (readSimplePly): where its body starts, its counts.
struct SimplePly {
	bool ok = false;
	uint64_t offset = 0; ///< the body's first byte
	size_t vertices = 0, faces = 0;
	bool unsignedIndex = false; ///< uint indices (else int)
	int colour = 0;             ///< vertex colour: 0 none, 3 uchar red green blue, 4 and alpha
	size_t vertexBytes = 12;    ///< per vertex record: xyz, then the colour's bytes
};

inline bool hostLittleEndian()
{
	const uint16_t one = 1;
	unsigned char b;
	std::memcpy(&b, &one, 1);
	return b == 1;
}

constexpr size_t kPlyVertexBytes = 12, kPlyFaceBytes = 13; // (xyz; a count byte, three indices)
constexpr size_t kPlyBatch = 1 << 14;                      // records per fread

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

/// The layout VCG and MeshLab write for a mesh without attributes, or with vertex colours only:
/// binary little endian, a vertex element of float x, y, z (then uchar red, green, blue and
/// optionally alpha), then a face element of one "list uchar int|uint" index list, and no
/// TextureFile comment; a body of exactly 12 (15, 16) bytes per vertex and 13 per face (at least:
/// VCG ignores what follows), every face a triangle of vertices in range (read here, in batches,
/// to check). False (out.ok false) for anything else, left to the walk. Needs no memory of its own
/// beyond a batch: readChecked reads the body again into the mesh.
inline bool readSimplePly(FILE *f, const PlyHeader &h, const vcg::ply::PlyFile &pf, uint64_t size,
                          SimplePly &out)
{
	using namespace vcg::ply;
	out = SimplePly();
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
	SimplePly sp;
	sp.offset = h.dataOffset;
	sp.vertices = size_t(ve.number), sp.faces = size_t(fe.number);
	sp.unsignedIndex = ip.tipo == T_UINT;
	sp.colour = int(np) - 3;
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

/// Checks a PLY file before VCG's ImporterPLY reads it (see the top of this file); a file of the
/// fast path's layout is checked by readSimplePly instead (simple->ok: readChecked reads it), if
/// `simple` is given.
inline bool checkPly(const std::string &path, FILE *f, uint64_t size, double vertexBytes,
                     double faceBytes, ReadError &e, FileFacts &facts, SimplePly *simple = nullptr)
{
	PlyHeader h;
	if (!precheckPlyHeader(f, h, e))
		return false;
	vcg::ply::PlyFile pf;
	if (pf.Open(path.c_str(), vcg::ply::PlyFile::MODE_READ) == -1) {
		static const char *msgs[] = {"",
		                             "cannot open",
		                             "no PLY header",
		                             "end of file in the header",
		                             "no format line",
		                             "syntax error",
		                             "property without element",
		                             "bad type name",
		                             "",
		                             "",
		                             "",
		                             "",
		                             "",
		                             "stream error"};
		const int err = pf.GetError();
		return corrupt(e, std::string("bad PLY header: ") +
		                      (err > 0 && err < 14 && *msgs[err] ? msgs[err] : "unreadable"));
	}
	if (h.format == 0)
		return corrupt(e, "bad PLY header: no format line");
	// "comment TextureFile NAME": VCG copies NAME, its "<this>" replaced by the file's name, into
	// char[255] buffers without bound (import_ply.h:1041, plylib.cpp:3670)
	const size_t slash = path.find_last_of('/');
	const size_t base = path.size() - (slash == std::string::npos ? 0 : slash + 1);
	for (const std::string &c : pf.comments) {
		if (c.compare(0, 11, "TextureFile") != 0)
			continue;
		size_t out = 0;
		std::string name;
		for (size_t i = 12; i < c.size(); ++i)
			if (c[i] > 32 && c[i] < 125)
				name.push_back(c[i]);
		for (size_t i = 0; i < name.size(); ++i) {
			const bool self = name[i] == '<' && name.size() > i + 5 &&
			                  std::tolower(static_cast<unsigned char>(name[i + 1])) == 't' &&
			                  std::tolower(static_cast<unsigned char>(name[i + 2])) == 'h' &&
			                  std::tolower(static_cast<unsigned char>(name[i + 3])) == 'i' &&
			                  std::tolower(static_cast<unsigned char>(name[i + 4])) == 's' &&
			                  name[i + 5] == '>';
			out += self ? base : 1;
			i += self ? 5 : 0;
		}
		if (c.size() < 12 || out >= 200 || base >= 200)
			return corrupt(e, "PLY texture file comment too long or without a name");
	}
	const bool ascii = h.format == 1, big = h.format == 3;
	double minBytes = 0;
	long long nv = 0, nf = 0;
	bool lists = false;
	int vertexElements = 0, faceElements = 0;
	for (const vcg::ply::PlyElement &el : pf.elements) {
		// a second vertex element would leave VCG's index table (import_ply.h:730) shorter than
		// the m.vn it checks face indices against
		vertexElements += el.name == "vertex";
		faceElements += el.name == "face";
		if (vertexElements > 1 || faceElements > 1)
			return corrupt(e, "two PLY '" + el.name + "' elements");
		if (el.name == "tristrips" || el.name == "range_grid")
			return fail(e, ReadStatus::WrongFormat,
			            "PLY element '" + el.name + "' is not supported (only faces are read)");
		const bool face = el.name == "face";
		double row = 0;
		bool indexList = false;
		for (const vcg::ply::PlyProperty &p : el.props) {
			const bool index = face && (p.name == "vertex_indices" || p.name == "vertex_index");
			indexList |= index;
			if (index && !plyFaceListReadable(p))
				return fail(e, ReadStatus::WrongFormat,
				            std::string("PLY face list 'list ") +
				                vcg::ply::PlyFile::typenames[p.islist ? p.tipoindex : 0] + " " +
				                vcg::ply::PlyFile::typenames[p.tipo] +
				                "' is not supported (VCG would skip it as a byte-counted list)");
			if (p.islist) {
				lists = true;
				row += ascii ? 2 : plyTypeSize(p.tipoindex); // (a list may be empty)
			} else {
				row += ascii ? 2 : plyTypeSize(p.tipo);
			}
		}
		// without an index list VCG still reads the faces, from uninitialised memory
		// (import_ply.h:761: pf.Read fills nothing, fa.size and fa.v are left as they were)
		if (face && el.number > 0 && !indexList)
			return corrupt(e, "the PLY face element has no vertex_indices list");
		minBytes += row * double(el.number);
		if (el.name == "vertex")
			nv += el.number;
		else if (face)
			nf += el.number;
	}
	const double body = double(size) - double(h.dataOffset);
	if (minBytes > body + (ascii ? 1 : 0))
		return lyingCounts(e, (unsigned long long)nv, (unsigned long long)nf, "faces", size);
	facts.vertices = double(nv);
	facts.faces = double(nf);
	if (!checkMemory(double(nv) * (vertexBytes + sizeof(void *)) + double(nf) * faceBytes, e))
		return false;
	if (!lists)
		return true;
	if (simple && readSimplePly(f, h, pf, size, *simple))
		return true;

	// walk the body once: list counts and face indices before plylib copies them
	if (std::fseek(f, long(h.dataOffset), SEEK_SET) != 0)
		return corrupt(e, "cannot seek in the PLY file");
	long long verticesSoFar = 0;
	for (const vcg::ply::PlyElement &el : pf.elements) {
		const bool face = el.name == "face";
		bool hasList = false;
		long row = 0;
		for (const vcg::ply::PlyProperty &p : el.props) {
			hasList |= p.islist != 0;
			row += plyTypeSize(p.tipo);
		}
		if (!ascii && !hasList) { // fixed-size rows: skip them at once
			if (std::fseek(f, long(row) * el.number, SEEK_CUR) != 0)
				return corrupt(e, "truncated PLY body");
		} else {
			for (long long i = 0; i < el.number; ++i) {
				for (const vcg::ply::PlyProperty &p : el.props) {
					const std::string what = "PLY " + el.name + " " + num(i) + " (" + p.name + ")";
					double v;
					bool bad = false;
					const int countType = p.islist ? p.tipoindex : p.tipo;
					if (!(ascii ? readPlyAscii(f, countType, v, bad)
					            : readPlyBinary(f, countType, big, v)))
						return corrupt(e, "truncated: the file ends in " + what);
					if (bad)
						return corrupt(e, what + ": unparsable number");
					if (!p.islist)
						continue;
					const bool index =
					    face && (p.name == "vertex_indices" || p.name == "vertex_index");
					// VCG copies face lists into int[512] and keeps the count in a byte; other
					// lists into 32-entry arrays or 512-byte skip buffers with a 1-byte count
					// (written so that a NaN or huge count of a float-typed list fails too)
					if (!(index ? v >= 3 && v <= 255 : v >= 0 && v <= 32) || v != std::floor(v)) {
						return corrupt(e, what + " has a list of " + numD(v) + " entries (" +
						                      (index ? "3..255" : "0..32") + ")");
					}
					if (!ascii && !index && plyTypeSize(p.tipoindex) != 1)
						return corrupt(e, what + ": a list count wider than one byte");
					for (long long j = 0; j < (long long)v; ++j) {
						double x;
						if (!(ascii ? readPlyAscii(f, p.tipo, x, bad)
						            : readPlyBinary(f, p.tipo, big, x)))
							return corrupt(e, "truncated: the file ends in " + what);
						if (bad)
							return corrupt(e, what + ": unparsable number");
						if (index && (x < 0 || x >= double(verticesSoFar)))
							return corrupt(e, "face " + num(i) + " uses vertex index " + numD(x) +
							                      ", outside 0.." + num(verticesSoFar - 1));
					}
				}
			}
		}
		if (el.name == "vertex")
			verticesSoFar += el.number;
	}
	return true;
}

// ---- STL ---------------------------------------------------------------------------------------

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

inline bool readBinaryStl(std::vector<float> &xyz, FILE *f, uint64_t n, double vertexBytes,
                          double faceBytes, ReadError &e)
{
	if (!checkMemory(double(n) * (3 * vertexBytes + faceBytes + 36), e))
		return false;
	xyz.assign(size_t(n) * 9, 0.0f);
	unsigned char rec[50];
	std::fseek(f, 84, SEEK_SET);
	for (uint64_t i = 0; i < n; ++i) {
		if (std::fread(rec, 1, 50, f) != 50)
			return corrupt(e, "truncated: the file ends in triangle " + num((long long)i));
		for (int j = 0; j < 9; ++j) { // little endian floats after the normal
			uint32_t u = uint32_t(rec[12 + 4 * j]) | uint32_t(rec[13 + 4 * j]) << 8 |
			             uint32_t(rec[14 + 4 * j]) << 16 | uint32_t(rec[15 + 4 * j]) << 24;
			std::memcpy(&xyz[size_t(i) * 9 + size_t(j)], &u, 4);
		}
	}
	return true;
}

/// Words of an ASCII STL, with line numbers for messages.
class StlWords {
public:
	explicit StlWords(FILE *f) : f_(f) {}
	bool next(std::string &w)
	{
		w.clear();
		int c;
		while ((c = getc_unlocked(f_)) != EOF && std::isspace(c))
			line_ += c == '\n';
		for (; c != EOF && !std::isspace(c); c = getc_unlocked(f_))
			if (w.size() < 64)
				w.push_back(char(c));
		if (c == '\n')
			std::ungetc(c, f_);
		return !w.empty();
	}
	void skipLine()
	{
		int c;
		while ((c = getc_unlocked(f_)) != EOF && c != '\n')
			;
		line_ += c == '\n';
	}
	long long line() const { return line_; }

private:
	FILE *f_;
	long long line_ = 1;
};

inline bool sameWord(const std::string &a, const char *b)
{
	size_t i = 0;
	for (; i < a.size() && b[i]; ++i)
		if (std::tolower(static_cast<unsigned char>(a[i])) != b[i])
			return false;
	return i == a.size() && !b[i];
}

inline bool readAsciiStl(std::vector<float> &xyz, FILE *f, uint64_t size, double vertexBytes,
                         double faceBytes, ReadError &e)
{
	// the smallest facet takes about 80 bytes of text
	if (!checkMemory(double(size) / 80 * (3 * vertexBytes + faceBytes + 36), e))
		return false;
	std::fseek(f, 0, SEEK_SET);
	StlWords in(f);
	std::string w;
	xyz.clear();
	auto expect = [&](const char *word) {
		if (!in.next(w))
			return corrupt(e,
			               "truncated: the file ends in facet " + num((long long)xyz.size() / 9));
		if (!sameWord(w, word))
			return corrupt(e, "line " + num(in.line()) + ": expected '" + word + "', found " +
			                      quote(w.data(), w.data() + w.size()));
		return true;
	};
	auto number = [&](float &x) {
		if (!in.next(w))
			return corrupt(e,
			               "truncated: the file ends in facet " + num((long long)xyz.size() / 9));
		if (!parseNumber(w.data(), w.data() + w.size()))
			return corrupt(e, "line " + num(in.line()) + ": " +
			                      quote(w.data(), w.data() + w.size()) + " is not a number");
		x = std::strtof(w.c_str(), nullptr);
		return true;
	};
	if (!expect("solid"))
		return false;
	in.skipLine(); // the solid's name
	bool inSolid = true;
	float x;
	while (in.next(w)) {
		if (!inSolid) {
			if (!sameWord(w, "solid"))
				return corrupt(e, "line " + num(in.line()) + ": expected 'solid', found " +
				                      quote(w.data(), w.data() + w.size()));
			in.skipLine();
			inSolid = true;
		} else if (sameWord(w, "endsolid")) {
			in.skipLine();
			inSolid = false;
		} else if (sameWord(w, "facet")) {
			if (!expect("normal") || !number(x) || !number(x) || !number(x) || !expect("outer") ||
			    !expect("loop"))
				return false;
			for (int k = 0; k < 3; ++k) {
				if (!expect("vertex"))
					return false;
				for (int j = 0; j < 3; ++j) {
					if (!number(x))
						return false;
					xyz.push_back(x);
				}
			}
			if (!expect("endloop") || !expect("endfacet"))
				return false;
		} else {
			return corrupt(e, "line " + num(in.line()) +
			                      ": expected 'facet' or 'endsolid', found " +
			                      quote(w.data(), w.data() + w.size()));
		}
	}
	if (inSolid)
		return corrupt(e, "truncated: no 'endsolid' at the end of the ASCII STL");
	return true;
}

// ---- sniffing and the whole read ---------------------------------------------------------------

/// What the first bytes say the file is (Unknown when not clearly one format).
inline Format sniff(const char *head, size_t n)
{
	if (n >= 4 && std::strncmp(head, "ply", 3) == 0 && (head[3] == '\n' || head[3] == '\r'))
		return Format::Ply;
	size_t i = 0;
	while (i < n && std::isspace(static_cast<unsigned char>(head[i])))
		++i;
	if (n - i >= 6 && std::strncmp(head + i, "solid", 5) == 0 &&
	    std::isspace(static_cast<unsigned char>(head[i + 5])))
		return Format::Stl;
	// OFF: the first word of the first line that is not a comment, [ST][C][N][4][n]OFF
	for (size_t p = 0; p < n;) {
		size_t q = p;
		while (q < n && (head[q] == ' ' || head[q] == '\t' || head[q] == '\r'))
			++q;
		if (q < n && head[q] != '\n' && head[q] != '#') {
			size_t r = q;
			while (r < n && std::strchr("STCN4n", head[r]))
				++r;
			if (n - r >= 4 && std::strncmp(head + r, "OFF", 3) == 0 &&
			    std::isspace(static_cast<unsigned char>(head[r + 3])))
				return Format::Off;
			break;
		}
		const char *nl = static_cast<const char *>(std::memchr(head + p, '\n', n - p));
		if (!nl)
			break;
		p = size_t(nl - head) + 1;
	}
	return Format::Unknown;
}

/// The current directory for a scope: VCG's OBJ importer opens mtllib files (and the .mtl named
/// after the OBJ) relative to it, so an OBJ is read from its own folder, as MeshLab's OBJ plugin
/// does. name() is the file's name from there. If the folder cannot be entered (or the current
/// one could not be restored) nothing changes.
class InFolder {
public:
	explicit InFolder(const std::string &path) : name_(path)
	{
		const size_t slash = path.find_last_of('/');
		if (slash == std::string::npos)
			return;
		const std::string dir = slash == 0 ? std::string("/") : path.substr(0, slash);
		fd_ = ::open(".", O_RDONLY | O_DIRECTORY | O_CLOEXEC);
		if (fd_ >= 0 && ::chdir(dir.c_str()) == 0) {
			name_ = path.substr(slash + 1);
		} else if (fd_ >= 0) {
			::close(fd_);
			fd_ = -1;
		}
	}
	~InFolder()
	{
		if (fd_ >= 0) {
			const int back = ::fchdir(fd_);
			(void)back;
			::close(fd_);
		}
	}
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

/// Everything before VCG reads the body: stat, sniffing, the guards of the format (see the top of
/// this file), the file's load mask. `vb`, `fb`: bytes per vertex and face of the mesh type the
/// memory checks assume.
template <class MeshT>
bool checkFile(const std::string &path, double vb, double fb, CheckedFile &c, ReadError &e,
               bool fastPly = true)
{
	struct stat st;
	if (::stat(path.c_str(), &st) != 0)
		return fail(e, ReadStatus::CannotOpen,
		            errno == ENOENT ? "no such file" : std::strerror(errno));
	if (!S_ISREG(st.st_mode))
		return fail(e, ReadStatus::CannotOpen,
		            S_ISDIR(st.st_mode) ? "not a regular file (a directory)"
		                                : "not a regular file (a device, pipe or socket)");
	File file(path);
	if (!file.f)
		return fail(e, ReadStatus::CannotOpen, std::string("cannot open: ") + std::strerror(errno));
	const uint64_t size = uint64_t(st.st_size);
	if (size == 0)
		return fail(e, ReadStatus::Empty, "the file is empty (0 bytes)");
	char head[4096];
	const size_t n = std::fread(head, 1, sizeof head, file.f);
	bool blank = true;
	for (size_t i = 0; i < n && blank; ++i)
		blank = std::isspace(static_cast<unsigned char>(head[i])) != 0;
	for (int ch; blank && (ch = std::fgetc(file.f)) != EOF;)
		blank = std::isspace(ch) != 0;
	if (blank)
		return fail(e, ReadStatus::Empty, "the file holds only blanks");
	std::rewind(file.f);

	const std::string ext = lowerExtension(path);
	const Format named = ext == "ply"   ? Format::Ply
	                     : ext == "obj" ? Format::Obj
	                     : ext == "off" ? Format::Off
	                     : ext == "stl" ? Format::Stl
	                                    : Format::Unknown;
	uint32_t stlCount = 0;
	if (n >= 84)
		stlCount = uint32_t((unsigned char)head[80]) | uint32_t((unsigned char)head[81]) << 8 |
		           uint32_t((unsigned char)head[82]) << 16 |
		           uint32_t((unsigned char)head[83]) << 24;
	const bool binaryStl = named == Format::Stl && size >= 84 && size == 84 + 50ull * stlCount;
	const Format content = binaryStl ? Format::Stl : sniff(head, n);
	if (named == Format::Unknown) {
		const std::string has = content == Format::Unknown
		                            ? std::string()
		                            : "the file is " + withArticle(content) + " file but ";
		return fail(e, ReadStatus::WrongFormat,
		            has +
		                (ext.empty() ? "its name has no extension"
		                             : "its name ends in ." + ext + ", not a known extension") +
		                " (.ply .obj .off .stl)");
	}
	if (content != Format::Unknown && content != named)
		return fail(e, ReadStatus::WrongFormat,
		            "the file is " + withArticle(content) + " file but its name ends in ." + ext);
	const bool text = std::memchr(head, 0, n) == nullptr;

	using vcg::tri::io::Mask;
	c.format = named;
	c.vcgPath = path;
	if (named == Format::Stl) {
		bool ok;
		if (binaryStl)
			ok = readBinaryStl(c.stl, file.f, stlCount, vb, fb, e);
		else if (content == Format::Stl && text)
			ok = readAsciiStl(c.stl, file.f, size, vb, fb, e);
		else if (size >= 84)
			return corrupt(e, "the header announces " + num(stlCount) +
			                      " triangles but the file has " + num((long long)size) +
			                      " bytes (a binary STL of " + num(stlCount) + " triangles has " +
			                      num(84 + 50ll * stlCount) + ")");
		else
			return corrupt(e, "not an STL file: too short for a binary STL (" +
			                      num((long long)size) + " bytes) and not starting with 'solid'");
		c.facts.faces = double(c.stl.size() / 9);
		c.facts.vertices = 3 * c.facts.faces;
		c.facts.mask = Mask::IOM_VERTCOORD | Mask::IOM_FACEINDEX;
		return ok;
	}
	if (named == Format::Ply) {
		if (!checkPly(path, file.f, size, vb, fb, e, c.facts, fastPly ? &c.ply : nullptr))
			return false;
		// (the header passed plylib's own parser in checkPly)
		if (!vcg::tri::io::ImporterPLY<MeshT>::LoadMask(path.c_str(), c.facts.mask))
			return corrupt(e, "bad PLY header");
		return true;
	}
	if (!text)
		return corrupt(e, "binary data (NUL bytes) in " + withArticle(named) + " text file");
	if (named == Format::Off)
		return scanOff(file.f, size, vb, fb, e, c.facts);
	c.folder.reset(new InFolder(path));
	c.vcgPath = c.folder->name();
	if (!scanObj(file.f, c.vcgPath, size, vb, fb, c.obj, e))
		return false;
	c.facts.vertices = double(c.obj.vertices);
	c.facts.faces = double(c.obj.faux.size());
	typename vcg::tri::io::ImporterOBJ<MeshT>::Info oi;
	if (!vcg::tri::io::ImporterOBJ<MeshT>::LoadMask(c.vcgPath.c_str(), oi))
		return corrupt(e, "OBJ: cannot read the file");
	c.facts.mask = oi.mask;
	// LoadMask takes vertex colours from blanks in the first 'v' line (import_obj.h:934): six
	// blanks around three coordinates are not colours, and the importer would give every vertex
	// its default grey
	if (!c.obj.vertexColours)
		c.facts.mask &= ~int(Mask::IOM_VERTCOLOR);
	return true;
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
inline bool readSimplePlyFlat(CheckedFile &c, FlatRead &out, ReadError &e, ReadInfo *info)
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

/// VCG's importer on a file checkFile() passed; `info` (optional) gets the load mask and an OBJ's
/// materials.
template <class MeshT>
bool readChecked(MeshT &m, CheckedFile &c, ReadError &e, ReadInfo *info)
{
	using VertexType = typename MeshT::VertexType;
	const std::string &path = c.vcgPath;
	m.Clear();
	int mask = 0;
	bool fastPly = false;
	if (c.format == Format::Stl) {
		buildSoup(m, c.stl);
		std::vector<float>().swap(c.stl);
		mask = c.facts.mask;
	} else if (c.format == Format::Ply && c.ply.ok) {
		// what ImporterPLY::Open builds from such a file (import_ply.h:670-690, 755-860,
		// 1020-1070), read again in batches straight into the mesh (checkPly checked the faces)
		const SimplePly &sp = c.ply;
		File file(path);
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
					        vert.C() =
					            vcg::Color4b(r[12], r[13], r[14], sp.colour == 4 ? r[15] : 255);
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
		// (Open's for this layout: it names no attribute but the colour, import_ply.h:387-570)
		mask = colour ? int(vcg::tri::io::Mask::IOM_VERTCOLOR) : 0;
		fastPly = true;
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
		using Obj = vcg::tri::io::ImporterOBJ<MeshT>;
		const ObjScan &scan = c.obj;
		const int r = Obj::Open(m, path.c_str(), mask);
		// its material attributes would leak (TriMesh's destructor does not free attributes):
		// copied for `info`, then deleted
		if (info) {
			auto mats = vcg::tri::Allocator<MeshT>::template FindPerMeshAttribute<
			    std::vector<vcg::tri::io::Material>>(m, "materialVector");
			auto index =
			    vcg::tri::Allocator<MeshT>::template FindPerFaceAttribute<int>(m, "materialIndex");
			if (vcg::tri::Allocator<MeshT>::IsValidHandle(m, mats) &&
			    vcg::tri::Allocator<MeshT>::IsValidHandle(m, index)) {
				info->materials = mats();
				info->faceMaterial.resize(m.face.size());
				for (size_t i = 0; i < m.face.size(); ++i)
					info->faceMaterial[i] = index[i];
			}
		}
		vcg::tri::Allocator<MeshT>::DeletePerMeshAttribute(m, "materialVector");
		vcg::tri::Allocator<MeshT>::DeletePerFaceAttribute(m, "materialIndex");
		if (r != 0 && Obj::ErrorCritical(r))
			return corrupt(e, std::string("OBJ: ") + Obj::ErrorMsg(r));
		if (!scan.vertexColours) // (see checkFile: no vertex line has colours)
			mask &= ~int(vcg::tri::io::Mask::IOM_VERTCOLOR);
		// VCG 2020.09 drops every face using vertex 1 (unless obj_import.h fixed it for this
		// mesh type): rebuild the faces from the scan
		const size_t nt = scan.faux.size();
		if (!obj::IndexFixFor<MeshT>::value && size_t(m.fn) != nt &&
		    m.vert.size() == size_t(scan.vertices)) {
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
	}
	c.folder.reset();
	// every face's vertices must lie in m.vert (whatever a reader let through)
	const uintptr_t lo = m.vert.empty() ? 0 : uintptr_t(m.vert.data()),
	                hi = lo + m.vert.size() * sizeof(VertexType);
	for (size_t i = 0; i < m.face.size(); ++i)
		for (int k = 0; k < 3; ++k) {
			const uintptr_t v = uintptr_t(m.face[i].cV(k));
			if (v < lo || v >= hi || (v - lo) % sizeof(VertexType) != 0)
				return corrupt(e, "face " + num((long long)i) + " points outside the vertex array");
		}
	settleVertexTexCoords(m, c.format, mask);
	if (info && c.format == Format::Obj) {
		const ObjScan &scan = c.obj;
		if (scan.shortFaces)
			info->notes.push_back(num(scan.shortFaces) + " face record" +
			                      (scan.shortFaces == 1 ? "" : "s") +
			                      " with fewer than 3 vertices skipped");
		std::vector<std::string> missing;
		for (const std::string &u : scan.usedMaterials)
			if (!scan.definedMaterials.count(u))
				missing.push_back(u);
		for (size_t i = 0; i < missing.size() && i < 3; ++i)
			info->notes.push_back("material " +
			                      quote(missing[i].data(), missing[i].data() + missing[i].size()) +
			                      " is used but no material file defines it (its faces take the "
			                      "default material)");
		if (missing.size() > 3)
			info->notes.push_back(num((long long)missing.size() - 3) + " more undefined materials");
	}
	if (info) {
		info->fastPly = fastPly;
		info->fileMask = c.facts.mask;
		info->mask = mask;
	}
	if (m.vn == 0 && m.fn == 0)
		return fail(e, ReadStatus::Empty, "the file holds no vertex and no face");
	return true;
}

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

/// Loads `path` into `m`. Returns false with `error` set if the file cannot be read (`m` may then
/// hold a partial mesh: discard it). No exception escapes. `info` (optional): what was read.
template <class MeshT>
bool importMesh(MeshT &m, const std::string &path, ReadError &error, ReadInfo *info = nullptr)
{
	return detail::guarded(error, [&] {
		using V = typename MeshT::VertexType;
		using F = typename MeshT::FaceType;
		detail::CheckedFile c;
		return detail::checkFile<MeshT>(path, sizeof(V), sizeof(F), c, error) &&
		       detail::readChecked(m, c, error, info);
	});
}

/// importMesh into `lean`, or into `full` when the file carries any attribute of `wantMask`
/// (vcg::tri::io::Mask bits, known once the guards have read the header or the lines): the
/// richer mesh type costs only the files that need it. `usedFull` says which mesh holds it.
/// With `flat`, a binary PLY of the fast path's layout is read into it instead (flat->used),
/// as gausslod::flatten would copy it out of `lean`.
template <class LeanT, class FullT>
bool importMeshEither(LeanT &lean, FullT &full, bool &usedFull, const std::string &path,
                      int wantMask, ReadError &error, ReadInfo *info = nullptr,
                      detail::FlatRead *flat = nullptr)
{
	usedFull = false;
	if (flat)
		*flat = detail::FlatRead();
	return detail::guarded(error, [&] {
		using V = typename LeanT::VertexType;
		using F = typename LeanT::FaceType;
		detail::CheckedFile c;
		if (!detail::checkFile<LeanT>(path, sizeof(V), sizeof(F), c, error))
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
