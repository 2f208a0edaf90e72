// The PLY guard. VCG's plylib.cpp and import_ply.h fail on header lines longer than its 510-byte
// buffer, blank ones (strcmp(NULL), plylib.cpp:1056) or an element line without a count
// (atoi(NULL), :1171); copy list counts into fixed arrays without bound (face v[512],
// plylib.cpp:1924, skip buffers of 512 bytes :1865); never check the last index of a polygon
// (import_ply.h:895); leak lists and leave indices unchecked in tristrips and range grids; read
// the faces of a face element without an index list from uninitialised memory (import_ply.h:761);
// copy a TextureFile comment into char[255] (import_ply.h:1041). The header is read with VCG's
// own PlyFile; the element data is walked once before VCG reads it.
#include "read_formats.h"

#include <wrap/ply/plylib.h>

#include <algorithm>
#include <cctype>
#include <cmath>

namespace gausslod {
namespace detail {

namespace {

/// The header lines as raw text, before VCG's PlyFile parses them: each must end in '\n' within
/// plylib's 510-byte line buffer and an element line must carry a count (plylib.cpp:1022-1171).
bool precheckPlyHeader(FILE *f, PlyHeader &h, ReadError &e)
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

/// The header parsed by VCG's PlyFile, its errors as messages.
bool openPly(const std::string &path, vcg::ply::PlyFile &pf, ReadError &e)
{
	if (pf.Open(path.c_str(), vcg::ply::PlyFile::MODE_READ) != -1)
		return true;
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

/// "comment TextureFile NAME": VCG copies NAME, its "<this>" replaced by the file's name, into
/// char[255] buffers without bound (import_ply.h:1041, plylib.cpp:3670).
bool checkTextureComments(const std::string &path, const vcg::ply::PlyFile &pf, ReadError &e)
{
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
	return true;
}

int plyTypeSize(int t)
{
	static const int sizes[] = {0, 1, 2, 4, 1, 2, 4, 4, 8};
	return t > 0 && t < 9 ? sizes[t] : 0;
}
bool plyTypeIsInt(int t) { return t >= vcg::ply::T_CHAR && t <= vcg::ply::T_UINT; }

bool isIndexList(const vcg::ply::PlyProperty &p)
{
	return p.name == "vertex_indices" || p.name == "vertex_index";
}

/// The face index lists VCG's ImporterPLY has a descriptor for (import_ply.h:211-236); any other
/// is skipped by plylib as if its count were one byte, into a 512-byte buffer (plylib.cpp:1865).
bool plyFaceListReadable(const vcg::ply::PlyProperty &p)
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

/// The bytes a row of `el` takes at least (`ascii`: two characters a value; a list may be empty);
/// `lists`: whether it has a list. Faces must have an index list VCG reads.
bool plyRowBytes(const vcg::ply::PlyElement &el, bool ascii, double &row, bool &lists, ReadError &e)
{
	const bool face = el.name == "face";
	bool indexList = false;
	row = 0;
	for (const vcg::ply::PlyProperty &p : el.props) {
		const bool index = face && isIndexList(p);
		indexList |= index;
		if (index && !plyFaceListReadable(p))
			return fail(e, ReadStatus::WrongFormat,
			            std::string("PLY face list 'list ") +
			                vcg::ply::PlyFile::typenames[p.islist ? p.tipoindex : 0] + " " +
			                vcg::ply::PlyFile::typenames[p.tipo] +
			                "' is not supported (VCG would skip it as a byte-counted list)");
		if (p.islist) {
			lists = true;
			row += ascii ? 2 : plyTypeSize(p.tipoindex);
		} else {
			row += ascii ? 2 : plyTypeSize(p.tipo);
		}
	}
	// without an index list VCG still reads the faces, from uninitialised memory
	// (import_ply.h:761: pf.Read fills nothing, fa.size and fa.v are left as they were)
	if (face && el.number > 0 && !indexList)
		return corrupt(e, "the PLY face element has no vertex_indices list");
	return true;
}

/// The elements VCG can read, their counts against the file's size and the available memory;
/// `lists`: whether any element has a list (else the body needs no walk).
bool checkPlyElements(const vcg::ply::PlyFile &pf, const PlyHeader &h, uint64_t size,
                      double vertexBytes, double faceBytes, FileFacts &facts, bool &lists,
                      ReadError &e)
{
	const bool ascii = h.format == 1;
	double minBytes = 0;
	long long nv = 0, nf = 0;
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
		double row;
		if (!plyRowBytes(el, ascii, row, lists, e))
			return false;
		minBytes += row * double(el.number);
		if (el.name == "vertex")
			nv += el.number;
		else if (el.name == "face")
			nf += el.number;
	}
	const double body = double(size) - double(h.dataOffset);
	if (minBytes > body + (ascii ? 1 : 0))
		return lyingCounts(e, (unsigned long long)nv, (unsigned long long)nf, size);
	facts.vertices = double(nv);
	facts.faces = double(nf);
	return checkMemory(double(nv) * (vertexBytes + sizeof(void *)) + double(nf) * faceBytes, e);
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
bool readPlyBinary(FILE *f, int t, bool bigEndian, double &v)
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
bool readPlyAscii(FILE *f, int t, double &v, bool &bad)
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

/// Reads PLY body values of one format (`format` as PlyHeader's), for the walk.
struct PlyValues {
	FILE *f;
	int format;
	/// The next value of type t into `v`; false with `e` set (`what`: the row and property) at the
	/// end of the file or an unparsable word.
	bool next(int t, double &v, const std::string &what, ReadError &e) const
	{
		bool bad = false;
		if (!(format == 1 ? readPlyAscii(f, t, v, bad) : readPlyBinary(f, t, format == 3, v)))
			return corrupt(e, "truncated: the file ends in " + what);
		if (bad)
			return corrupt(e, what + ": unparsable number");
		return true;
	}
};

/// One property of row `i` of a walked element: a list's count within what VCG copies, a face's
/// indices within the vertices so far.
bool walkPlyProperty(const PlyValues &in, const vcg::ply::PlyElement &el,
                     const vcg::ply::PlyProperty &p, long long i, long long verticesSoFar,
                     ReadError &e)
{
	const std::string what = "PLY " + el.name + " " + num(i) + " (" + p.name + ")";
	double v;
	if (!in.next(p.islist ? p.tipoindex : p.tipo, v, what, e))
		return false;
	if (!p.islist)
		return true;
	const bool index = el.name == "face" && isIndexList(p);
	// VCG copies face lists into int[512] and keeps the count in a byte; other lists into 32-entry
	// arrays or 512-byte skip buffers with a 1-byte count (written so that a NaN or huge count of a
	// float-typed list fails too)
	if (!(index ? v >= 3 && v <= 255 : v >= 0 && v <= 32) || v != std::floor(v))
		return corrupt(e, what + " has a list of " + numD(v) + " entries (" +
		                      (index ? "3..255" : "0..32") + ")");
	if (in.format != 1 && !index && plyTypeSize(p.tipoindex) != 1)
		return corrupt(e, what + ": a list count wider than one byte");
	for (long long j = 0; j < (long long)v; ++j) {
		double x;
		if (!in.next(p.tipo, x, what, e))
			return false;
		if (index && (x < 0 || x >= double(verticesSoFar)))
			return corrupt(e, "face " + num(i) + " uses vertex index " + numD(x) + ", outside 0.." +
			                      num(verticesSoFar - 1));
	}
	return true;
}

/// Walks the body once: list counts and face indices before plylib copies them.
bool walkPlyBody(FILE *f, const vcg::ply::PlyFile &pf, const PlyHeader &h, ReadError &e)
{
	if (std::fseek(f, long(h.dataOffset), SEEK_SET) != 0)
		return corrupt(e, "cannot seek in the PLY file");
	const PlyValues in{f, h.format};
	long long verticesSoFar = 0;
	for (const vcg::ply::PlyElement &el : pf.elements) {
		bool hasList = false;
		long row = 0;
		for (const vcg::ply::PlyProperty &p : el.props) {
			hasList |= p.islist != 0;
			row += plyTypeSize(p.tipo);
		}
		if (h.format != 1 && !hasList) { // fixed-size rows: skip them at once
			if (std::fseek(f, long(row) * el.number, SEEK_CUR) != 0)
				return corrupt(e, "truncated PLY body");
		} else {
			for (long long i = 0; i < el.number; ++i)
				for (const vcg::ply::PlyProperty &p : el.props)
					if (!walkPlyProperty(in, el, p, i, verticesSoFar, e))
						return false;
		}
		if (el.name == "vertex")
			verticesSoFar += el.number;
	}
	return true;
}

} // namespace

bool checkPly(const std::string &path, FILE *f, uint64_t size, double vertexBytes, double faceBytes,
              ReadError &e, FileFacts &facts, SimplePly *simple)
{
	PlyHeader h;
	if (!precheckPlyHeader(f, h, e))
		return false;
	vcg::ply::PlyFile pf;
	if (!openPly(path, pf, e))
		return false;
	if (h.format == 0)
		return corrupt(e, "bad PLY header: no format line");
	if (!checkTextureComments(path, pf, e))
		return false;
	bool lists = false;
	if (!checkPlyElements(pf, h, size, vertexBytes, faceBytes, facts, lists, e))
		return false;
	if (!lists)
		return true;
	if (simple && readSimplePly(f, h, pf, size, *simple))
		return true;
	return walkPlyBody(f, pf, h, e);
}

} // namespace detail
} // namespace gausslod
