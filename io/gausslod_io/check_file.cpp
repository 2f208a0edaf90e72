// checkFile: what every file goes through before VCG reads its body. The file is stat'ed
// (missing, directory, FIFO, empty), its first bytes are sniffed against its name, then the guard
// of its format runs (read_off.cpp, read_obj.cpp, read_ply.cpp, read_stl.cpp) and VCG's load mask
// is taken.
#include "read_formats.h"

#include <sys/stat.h>

#include <cctype>
#include <cerrno>
#include <cstring>

namespace gausslod {
namespace detail {

namespace {

/// What the first bytes say the file is (Unknown when not clearly one format).
Format sniff(const char *head, size_t n)
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

/// CannotOpen unless `path` names a regular file; `st` its status.
bool statRegular(const std::string &path, struct stat &st, ReadError &e)
{
	if (::stat(path.c_str(), &st) != 0)
		return fail(e, ReadStatus::CannotOpen,
		            errno == ENOENT ? "no such file" : std::strerror(errno));
	if (!S_ISREG(st.st_mode))
		return fail(e, ReadStatus::CannotOpen,
		            S_ISDIR(st.st_mode) ? "not a regular file (a directory)"
		                                : "not a regular file (a device, pipe or socket)");
	return true;
}

/// Whether the file holds only blanks: its first `n` bytes `head`, then the rest of `f`.
bool onlyBlanks(FILE *f, const char *head, size_t n)
{
	bool blank = true;
	for (size_t i = 0; i < n && blank; ++i)
		blank = std::isspace(static_cast<unsigned char>(head[i])) != 0;
	for (int ch; blank && (ch = std::fgetc(f)) != EOF;)
		blank = std::isspace(ch) != 0;
	return blank;
}

Format formatOfExtension(const std::string &ext)
{
	return ext == "ply"   ? Format::Ply
	       : ext == "obj" ? Format::Obj
	       : ext == "off" ? Format::Off
	       : ext == "stl" ? Format::Stl
	                      : Format::Unknown;
}

/// WrongFormat unless the name gives a format (`named`, from extension `ext`) that the content
/// (`content`, Unknown if not clear) does not contradict.
bool formatsAgree(Format named, Format content, const std::string &ext, ReadError &e)
{
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
	return true;
}

/// An STL: binary (`stlCount` triangles, the size matching), ASCII (`asciiStl`: starts with
/// "solid", no NUL byte), else Corrupt; read into c.stl.
bool checkStl(FILE *f, uint64_t size, bool binaryStl, uint32_t stlCount, bool asciiStl, double vb,
              double fb, CheckedFile &c, ReadError &e)
{
	bool ok;
	if (binaryStl)
		ok = readBinaryStl(c.stl, f, stlCount, vb, fb, e);
	else if (asciiStl)
		ok = readAsciiStl(c.stl, f, size, vb, fb, e);
	else if (size >= 84)
		return corrupt(e, "the header announces " + num(stlCount) + " triangles but the file has " +
		                      num((long long)size) + " bytes (a binary STL of " + num(stlCount) +
		                      " triangles has " + num(84 + 50ll * stlCount) + ")");
	else
		return corrupt(e, "not an STL file: too short for a binary STL (" + num((long long)size) +
		                      " bytes) and not starting with 'solid'");
	using vcg::tri::io::Mask;
	c.facts.faces = double(c.stl.size() / 9);
	c.facts.vertices = 3 * c.facts.faces;
	c.facts.mask = Mask::IOM_VERTCOORD | Mask::IOM_FACEINDEX;
	return ok;
}

/// The load mask does not depend on the mesh type: VCG's LoadMask of IoMesh's importers.
bool checkPlyFile(const std::string &path, FILE *f, uint64_t size, double vb, double fb,
                  bool fastPly, CheckedFile &c, ReadError &e)
{
	if (!checkPly(path, f, size, vb, fb, e, c.facts, fastPly ? &c.ply : nullptr))
		return false;
	// (the header passed plylib's own parser in checkPly)
	if (!vcg::tri::io::ImporterPLY<IoMesh>::LoadMask(path.c_str(), c.facts.mask))
		return corrupt(e, "bad PLY header");
	return true;
}

/// An OBJ, scanned from its own folder (c.folder, c.vcgPath).
bool checkObjFile(const std::string &path, FILE *f, double vb, double fb, CheckedFile &c,
                  ReadError &e)
{
	using vcg::tri::io::Mask;
	c.folder.reset(new InFolder(path));
	c.vcgPath = c.folder->name();
	if (!scanObj(f, c.vcgPath, vb, fb, c.obj, e))
		return false;
	c.facts.vertices = double(c.obj.vertices);
	c.facts.faces = double(c.obj.faux.size());
	vcg::tri::io::ImporterOBJ<IoMesh>::Info oi;
	if (!vcg::tri::io::ImporterOBJ<IoMesh>::LoadMask(c.vcgPath.c_str(), oi))
		return corrupt(e, "OBJ: cannot read the file");
	c.facts.mask = oi.mask;
	// LoadMask takes vertex colours from blanks in the first 'v' line (import_obj.h:934): six
	// blanks around three coordinates are not colours, and the importer would give every vertex
	// its default grey
	if (!c.obj.vertexColours)
		c.facts.mask &= ~int(Mask::IOM_VERTCOLOR);
	return true;
}

} // namespace

bool checkFile(const std::string &path, double vb, double fb, CheckedFile &c, ReadError &e,
               bool fastPly)
{
	struct stat st;
	if (!statRegular(path, st, e))
		return false;
	File file(path);
	if (!file.f)
		return fail(e, ReadStatus::CannotOpen, std::string("cannot open: ") + std::strerror(errno));
	const uint64_t size = uint64_t(st.st_size);
	if (size == 0)
		return fail(e, ReadStatus::Empty, "the file is empty (0 bytes)");
	char head[4096];
	const size_t n = std::fread(head, 1, sizeof head, file.f);
	if (onlyBlanks(file.f, head, n))
		return fail(e, ReadStatus::Empty, "the file holds only blanks");
	std::rewind(file.f);

	const std::string ext = lowerExtension(path);
	const Format named = formatOfExtension(ext);
	uint32_t stlCount = 0;
	if (n >= 84)
		stlCount = uint32_t((unsigned char)head[80]) | uint32_t((unsigned char)head[81]) << 8 |
		           uint32_t((unsigned char)head[82]) << 16 |
		           uint32_t((unsigned char)head[83]) << 24;
	const bool binaryStl = named == Format::Stl && size >= 84 && size == 84 + 50ull * stlCount;
	const Format content = binaryStl ? Format::Stl : sniff(head, n);
	if (!formatsAgree(named, content, ext, e))
		return false;
	const bool text = std::memchr(head, 0, n) == nullptr;

	c.format = named;
	c.vcgPath = path;
	if (named == Format::Stl)
		return checkStl(file.f, size, binaryStl, stlCount, content == Format::Stl && text, vb, fb,
		                c, e);
	if (named == Format::Ply)
		return checkPlyFile(path, file.f, size, vb, fb, fastPly, c, e);
	if (!text)
		return corrupt(e, "binary data (NUL bytes) in " + withArticle(named) + " text file");
	if (named == Format::Off)
		return scanOff(file.f, size, vb, fb, e, c.facts);
	return checkObjFile(path, file.f, vb, fb, c, e);
}

} // namespace detail
} // namespace gausslod
