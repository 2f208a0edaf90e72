// What the format files of gausslod_io share (not a public header): the messages, the scanning of
// text words (inline: the scans call them per word), and each format's guard for check_file.cpp.
#pragma once

#include "import_mesh.h"

#include <sys/types.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace gausslod {
namespace detail {

// ---- messages (read_common.cpp) ----------------------------------------------------------------

/// "PLY", "OBJ", "OFF", "STL" ("unknown").
const char *formatName(Format f);
/// "a PLY", "an OBJ", "an OFF", "an STL"
std::string withArticle(Format f);
/// A value read as a double (any size, NaN included) for a message.
std::string numD(double v);
/// Corrupt: counts of vertices and faces that the file's `size` bytes cannot hold.
bool lyingCounts(ReadError &e, unsigned long long nv, unsigned long long nf, uint64_t size);

// ---- words of a text file ----------------------------------------------------------------------

struct Word {
	const char *b, *e;
};

/// Appends the words of [p, end) to `w`: runs between spaces and tabs, CRs before a word skipped.
/// A CR ends a word if `crEndsWord` (as VCG's OBJ reader splits), else it stays in it (as its OFF
/// reader's TokenizeNextLine does).
inline void splitWords(const char *p, const char *end, bool crEndsWord, std::vector<Word> &w)
{
	while (p < end) {
		while (p < end && (*p == ' ' || *p == '\t' || *p == '\r'))
			++p;
		if (p == end)
			break;
		const char *q = p + 1;
		while (q < end && *q != ' ' && *q != '\t' && (!crEndsWord || *q != '\r'))
			++q;
		w.push_back({p, q});
		p = q;
	}
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

/// A colour word VCG turns into a byte as (unsigned char)(float(atof(word)) * scale): undefined
/// unless the product lies in (-1, 256) (color4.h:295, import_obj.h:312).
inline bool colourByteOk(const Word &w, float scale)
{
	if (!parseNumber(w.b, w.e))
		return false;
	const float x = float(std::strtod(std::string(w.b, w.e).c_str(), nullptr)) * scale;
	return x > -1.0f && x < 256.0f;
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

// ---- each format's guards, for checkFile (check_file.cpp) --------------------------------------

/// Checks an OFF file exactly as VCG's ImporterOFF will read it (read_off.cpp).
bool scanOff(FILE *f, uint64_t size, double vertexBytes, double faceBytes, ReadError &e,
             FileFacts &facts);
/// Checks an OBJ file as VCG's ImporterOBJ will read it and collects its triangles
/// (read_obj.cpp).
bool scanObj(FILE *f, const std::string &path, double vertexBytes, double faceBytes, ObjScan &out,
             ReadError &e);
/// Checks a PLY file before VCG's ImporterPLY reads it (read_ply.cpp); a file of the fast path's
/// layout is checked by readSimplePly instead (simple->ok: readChecked reads it), if `simple` is
/// given.
bool checkPly(const std::string &path, FILE *f, uint64_t size, double vertexBytes, double faceBytes,
              ReadError &e, FileFacts &facts, SimplePly *simple = nullptr);
/// The STL readers (read_stl.cpp): a binary STL of `n` triangles, an ASCII STL of `size` bytes,
/// into `xyz` (three corners per triangle).
bool readBinaryStl(std::vector<float> &xyz, FILE *f, uint64_t n, double vertexBytes,
                   double faceBytes, ReadError &e);
bool readAsciiStl(std::vector<float> &xyz, FILE *f, uint64_t size, double vertexBytes,
                  double faceBytes, ReadError &e);

// ---- the binary PLY fast path (read_ply_fast.cpp), for checkPly --------------------------------

struct PlyHeader {
	uint64_t dataOffset = 0;
	int format = 0; // 1 ascii, 2 binary little endian, 3 binary big endian (as plylib)
};

/// Whether a PLY file, its header read (`h`, `pf`), has the fast path's layout, its faces checked:
/// out.ok (else false, and the file is left to the walk).
bool readSimplePly(FILE *f, const PlyHeader &h, const vcg::ply::PlyFile &pf, uint64_t size,
                   SimplePly &out);

} // namespace detail
} // namespace gausslod
