// The STL reader. VCG's import_stl.h leaks two FILE handles per binary file (:115, :153), one per
// truncated ASCII file (:295), loops endlessly on a file without a line break (:270) and reads a
// lying triangle count past EOF (:221). STL is therefore read here (binary: exact size 84 + 50 n;
// ASCII: strict grammar) into the same unshared-vertex soup VCG builds (buildSoup, read_vcg.h).
#include "read_formats.h"

#include <cctype>

namespace gausslod {
namespace detail {

namespace {

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

bool sameWord(const std::string &a, const char *b)
{
	size_t i = 0;
	for (; i < a.size() && b[i]; ++i)
		if (std::tolower(static_cast<unsigned char>(a[i])) != b[i])
			return false;
	return i == a.size() && !b[i];
}

/// The grammar of an ASCII STL, word by word, its corners into `xyz`.
class StlParser {
public:
	StlParser(FILE *f, std::vector<float> &xyz, ReadError &e) : in_(f), xyz_(xyz), e_(e) {}

	/// The next word, which must be `word` (any case).
	bool expect(const char *word)
	{
		if (!in_.next(w_))
			return truncated();
		if (!sameWord(w_, word))
			return unexpected(std::string("'") + word + "'");
		return true;
	}
	/// The next word, a number, into `x`.
	bool number(float &x)
	{
		if (!in_.next(w_))
			return truncated();
		if (!parseNumber(w_.data(), w_.data() + w_.size()))
			return corrupt(e_, "line " + num(in_.line()) + ": " +
			                       quote(w_.data(), w_.data() + w_.size()) + " is not a number");
		x = std::strtof(w_.c_str(), nullptr);
		return true;
	}
	/// One facet after its word "facet": the normal, then three corners into `xyz`.
	bool facet()
	{
		float x;
		if (!expect("normal") || !number(x) || !number(x) || !number(x) || !expect("outer") ||
		    !expect("loop"))
			return false;
		for (int k = 0; k < 3; ++k) {
			if (!expect("vertex"))
				return false;
			for (int j = 0; j < 3; ++j) {
				if (!number(x))
					return false;
				xyz_.push_back(x);
			}
		}
		return expect("endloop") && expect("endfacet");
	}
	/// Solids ("solid NAME", facets, "endsolid NAME") to the end of the file.
	bool solids()
	{
		if (!expect("solid"))
			return false;
		in_.skipLine(); // the solid's name
		bool inSolid = true;
		while (in_.next(w_)) {
			if (!inSolid) {
				if (!sameWord(w_, "solid"))
					return unexpected("'solid'");
				in_.skipLine();
				inSolid = true;
			} else if (sameWord(w_, "endsolid")) {
				in_.skipLine();
				inSolid = false;
			} else if (!sameWord(w_, "facet")) {
				return unexpected("'facet' or 'endsolid'");
			} else if (!facet()) {
				return false;
			}
		}
		if (inSolid)
			return corrupt(e_, "truncated: no 'endsolid' at the end of the ASCII STL");
		return true;
	}

private:
	bool truncated()
	{
		return corrupt(e_, "truncated: the file ends in facet " + num((long long)xyz_.size() / 9));
	}
	bool unexpected(const std::string &wanted)
	{
		return corrupt(e_, "line " + num(in_.line()) + ": expected " + wanted + ", found " +
		                       quote(w_.data(), w_.data() + w_.size()));
	}

	StlWords in_;
	std::vector<float> &xyz_;
	ReadError &e_;
	std::string w_;
};

} // namespace

bool readBinaryStl(std::vector<float> &xyz, FILE *f, uint64_t n, double vertexBytes,
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

bool readAsciiStl(std::vector<float> &xyz, FILE *f, uint64_t size, double vertexBytes,
                  double faceBytes, ReadError &e)
{
	// the smallest facet takes about 80 bytes of text
	if (!checkMemory(double(size) / 80 * (3 * vertexBytes + faceBytes + 36), e))
		return false;
	std::fseek(f, 0, SEEK_SET);
	xyz.clear();
	return StlParser(f, xyz, e).solids();
}

} // namespace detail
} // namespace gausslod
