// The OFF guard. VCG's import_off.h reads counts and face indices with atoi and never
// range-checks them (:210, :450, :471 reads vert[idx] of polygons), reads a face line missing at
// EOF as tokens[0] (:435), allocates a huge vertex-per-face count before reading (:457-461),
// leaves the colour-map index unchecked (:296, :550), reads a line of blanks as if it had a token
// (crash on CGAL's prim.off), casts float colours to bytes out of range (:317, color4.h:295). A
// pre-scan that tokenizes exactly as VCG does validates all of it; blank lines are emptied for VCG
// (BlankLineFilter).
#include "read_formats.h"

#include <algorithm>

namespace gausslod {
namespace detail {

namespace {

/// VCG's float colours (import_off.h:301, :555): the first word holding a '.' makes all floats.
bool offColoursOk(const std::vector<Word> &w, size_t k, long long n)
{
	if ((n != 3 && n != 4) || std::find(w[k].b, w[k].e, '.') == w[k].e)
		return true;
	for (size_t i = k; i < k + size_t(n); ++i)
		if (!colourByteOk(w[i], 255.0f))
			return false;
	return true;
}

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
			splitWords(p, end, false, words_);
			break;
		}
		return words_;
	}
	size_t line() const { return lines_.number(); }

private:
	LineReader lines_;
	std::vector<Word> words_;
};

/// The words of an OFF body: `w` the current line's, `k` the next one's index in it.
struct OffCursor {
	OffTokens in;
	std::vector<Word> w;
	size_t k = 0;
	explicit OffCursor(FILE *f) : in(f) {}
	/// The next word, continuing on the next line as VCG does; false at end of file.
	bool next(Word &out)
	{
		if (k == w.size()) {
			w = in.nextLine();
			k = 0;
			if (w.empty())
				return false;
		}
		out = w[k++];
		return true;
	}
};

/// What an OFF header says.
struct OffHeader {
	bool color = false, normal = false, tex = false;
	long long nv = 0, nf = 0;
};

/// The header word ([ST][C][N]OFF) and the counts after it, checked against the file's size and
/// the available memory.
bool readOffHeader(OffCursor &cur, uint64_t size, double vertexBytes, double faceBytes,
                   OffHeader &h, ReadError &e)
{
	std::vector<Word> &w = cur.w;
	w = cur.in.nextLine();
	if (w.empty())
		return fail(e, ReadStatus::Empty, "only comments or blanks, no OFF header");
	const std::string head(w[0].b, w[0].e);
	const size_t off = head.rfind("OFF");
	if (off == std::string::npos)
		return corrupt(e, "no OFF header (the first word is " + quote(w[0].b, w[0].e) + ")");
	for (size_t u = 0; u < off; ++u) {
		const char c = head[u];
		if (c == 'n' || c == '4')
			return corrupt(e, std::string("OFF with ") +
			                      (c == 'n' ? "n-dimensional" : "homogeneous (4D)") +
			                      " vertices is not supported");
		h.color |= c == 'C';
		h.normal |= c == 'N';
		h.tex |= c == 'T' && u > 0 && head[u - 1] == 'S';
	}
	if (w.size() == 1)
		w = cur.in.nextLine();
	else
		w.erase(w.begin());
	if (w.size() < 3)
		return corrupt(e, "the OFF header has no vertex, face and edge counts");
	if (!parseCount(w[0].b, w[0].e, h.nv) || !parseCount(w[1].b, w[1].e, h.nf))
		return corrupt(e, "bad OFF counts " + quote(w[0].b, w[0].e) + " " + quote(w[1].b, w[1].e));
	// a vertex takes at least "0 0 0\n", a face "3 0 1 2\n"
	if (6.0 * double(h.nv) + 8.0 * double(h.nf) > double(size) + 1)
		return lyingCounts(e, (unsigned long long)h.nv, (unsigned long long)h.nf, size);
	return checkMemory(double(h.nv) * vertexBytes + double(h.nf) * faceBytes, e);
}

bool truncatedIn(ReadError &e, const char *what, long long i, long long n)
{
	return corrupt(e, std::string("truncated: the file ends in ") + what + " " + num(i) + " of " +
	                      num(n));
}

/// The vertex lines: numbers, colours VCG can read (`vertexColour`: some vertex has one).
bool scanOffVertices(OffCursor &cur, const OffHeader &h, bool &vertexColour, ReadError &e)
{
	const std::vector<Word> &w = cur.w;
	Word t;
	for (long long i = 0; i < h.nv; ++i) {
		for (int j = 0; j < (h.normal ? 6 : 3); ++j) {
			if (!cur.next(t))
				return truncatedIn(e, "vertex", i, h.nv);
			if (!parseNumber(t.b, t.e))
				return corrupt(e, "line " + num((long long)cur.in.line()) + ": " + quote(t.b, t.e) +
				                      " is not a number");
		}
		if (h.color) { // VCG counts the colour words left on the line (import_off.h:277)
			const size_t k = cur.k;
			const long long nc = (long long)w.size() - (long long)k - (h.tex ? 2 : 0);
			vertexColour |= nc > 0;
			if (nc < 0 || nc > 4)
				return corrupt(e, "vertex " + num(i) + " has " + num(nc) + " colour components");
			long long c;
			if (nc == 1 && (!parseInt(w[k].b, w[k].e, c) || c < 0 || c >= 148))
				return corrupt(e, "vertex " + num(i) + ": colour-map index " +
				                      quote(w[k].b, w[k].e) + " out of range 0..147");
			if (!offColoursOk(w, k, nc))
				return corrupt(e, "vertex " + num(i) + ": colour component out of range 0..1");
			cur.k += size_t(nc);
		}
		for (int j = 0; h.tex && j < 2; ++j)
			if (!cur.next(t))
				return truncatedIn(e, "vertex", i, h.nv);
	}
	return true;
}

/// The face lines: vertex counts and indices in range, colours VCG can read (`faceColour`: some
/// face has one); `triangles`: what VCG makes of them.
bool scanOffFaces(OffCursor &cur, const OffHeader &h, double &triangles, bool &faceColour,
                  ReadError &e)
{
	const std::vector<Word> &w = cur.w;
	Word t;
	for (long long i = 0; i < h.nf; ++i) {
		cur.w = cur.in.nextLine();
		cur.k = 1;
		long long n;
		if (w.empty())
			return truncatedIn(e, "face", i, h.nf);
		if (!parseInt(w[0].b, w[0].e, n) || n < 3)
			return corrupt(e, "face " + num(i) + " has " + quote(w[0].b, w[0].e) +
			                      " vertices (at least 3)");
		for (long long j = 0; j < n; ++j) {
			long long idx;
			if (!cur.next(t))
				return truncatedIn(e, "face", i, h.nf);
			if (!parseInt(t.b, t.e, idx) || idx < 0 || idx >= h.nv)
				return corrupt(e, "face " + num(i) + " uses vertex index " + quote(t.b, t.e) +
				                      ", outside 0.." + num(h.nv - 1));
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
	return true;
}

} // namespace

bool scanOff(FILE *f, uint64_t size, double vertexBytes, double faceBytes, ReadError &e,
             FileFacts &facts)
{
	OffCursor cur(f);
	OffHeader h;
	if (!readOffHeader(cur, size, vertexBytes, faceBytes, h, e))
		return false;
	cur.w = cur.in.nextLine();
	cur.k = 0;
	bool vertexColour = false, faceColour = false;
	double triangles = 0;
	if (!scanOffVertices(cur, h, vertexColour, e) ||
	    !scanOffFaces(cur, h, triangles, faceColour, e))
		return false;
	if (h.nv == 0 && h.nf == 0)
		return fail(e, ReadStatus::Empty, "the OFF file holds no vertex and no face");
	using vcg::tri::io::Mask;
	facts.vertices = double(h.nv);
	facts.faces = triangles;
	facts.mask = Mask::IOM_VERTCOORD | Mask::IOM_FACEINDEX | (h.normal ? Mask::IOM_VERTNORMAL : 0) |
	             (h.tex ? Mask::IOM_VERTTEXCOORD : 0) | (vertexColour ? Mask::IOM_VERTCOLOR : 0) |
	             (faceColour ? Mask::IOM_FACECOLOR : 0);
	return checkMemory(double(h.nv) * vertexBytes + triangles * faceBytes, e);
}

BlankLineFilter::int_type BlankLineFilter::underflow()
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

} // namespace detail
} // namespace gausslod
