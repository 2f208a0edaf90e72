// The OBJ guard. VCG's import_obj.h counts vertex lines one way (:897) and reads them another
// (:290, writes past m.vert), reads m.vert[idx] before the range check (:471-473), joins '\'
// continuations out of bounds (:757-761), leaves line elements' indices unchecked (:656), indexes
// #MRGB colours past their end (:731), casts vertex colours to bytes out of range (:313), opens
// any mtllib path (/dev/zero, a FIFO) (:591), and leaks its material attributes (:237: dropped
// after reading, read_vcg.h). VCG also drops every face that uses vertex 1 (:186, index 0 taken as
// invalid): those faces are rebuilt from the pre-scan, which reads every face line.
#include "read_formats.h"

#include <sys/stat.h>

#include <algorithm>

namespace gausslod {
namespace detail {

namespace {

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

/// Joins '\'-continued lines as VCG (import_obj.h:756) does, refusing the joins it gets wrong
/// (an empty or missing next line: back() of an empty string; a CRLF next line: it pops the wrong
/// string). `joined` gets the logical line when there was a continuation.
bool joinLine(LineReader &in, std::string &joined, bool &usedJoined, const char *where,
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

/// A material file VCG will open (relative to the working directory, the OBJ's folder while it is
/// read): it must be a regular file, and its '\' continuations must be ones VCG joins in bounds.
/// `defined` (optional) gets its newmtl names.
bool checkMaterialFile(const std::string &name, ReadError &e,
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
	std::string joined;
	bool used;
	while (in.next()) {
		if (!joinLine(in, joined, used, "the material file", e))
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

/// What the scan counts besides ObjScan.
struct ObjCounts {
	ObjMaskCount mask;
	long long nvt = 0, nvn = 0, mrgb = 0, statements = 0;
	bool usemtl = false;
};

std::string lineAt(size_t lineNo) { return "line " + num((long long)lineNo) + ": "; }

bool wordIs(const Word &w, const char *s)
{
	const size_t n = size_t(w.e - w.b);
	return std::strlen(s) == n && !std::strncmp(w.b, s, n);
}

/// A 'v' statement: three numbers, colours VCG can read.
bool scanObjVertex(const std::vector<Word> &w, size_t lineNo, const ObjCounts &n, ObjScan &out,
                   ReadError &e)
{
	if (w.size() < 4)
		return corrupt(e, lineAt(lineNo) + "a vertex with fewer than 3 coordinates");
	for (int j = 1; j < 4; ++j)
		if (!parseNumber(w[j].b, w[j].e))
			return corrupt(e, lineAt(lineNo) + quote(w[j].b, w[j].e) + " is not a number");
	if (w.size() >= 7) { // colours, scaled as VCG does (import_obj.h:309-315)
		out.vertexColours = true;
		float c[3];
		for (int j = 0; j < 3; ++j)
			c[j] = parseNumber(w[4 + j].b, w[4 + j].e)
			           ? float(std::strtod(std::string(w[4 + j].b, w[4 + j].e).c_str(), nullptr))
			           : 1e9f;
		const float scale = c[0] <= 1 && c[1] <= 1 && c[2] <= 1 ? 255.0f : 1.0f;
		bool okc = true;
		for (size_t j = 4; j < std::min<size_t>(w.size(), 8); ++j)
			okc = okc && colourByteOk(w[j], scale);
		if (!okc)
			return corrupt(e, lineAt(lineNo) + "a vertex colour out of range");
	}
	if (out.vertices > n.mask.v)
		return corrupt(e, lineAt(lineNo) + "a vertex statement that does not start its line as "
		                                   "'v x y z'");
	return true;
}

/// One corner of a face statement (`q`: QOBJ's 0-based vertex index): its vertex, into `v`, and
/// its texture and normal indices naming earlier vt and vn lines.
bool scanObjCorner(const Word &w, bool q, size_t lineNo, const ObjCounts &n, const ObjScan &out,
                   long long &v, ReadError &e)
{
	const char *s1 = std::find(w.b, w.e, '/');
	long long r;
	if (!parseInt(w.b, s1, r))
		return corrupt(e, lineAt(lineNo) + "bad vertex index " + quote(w.b, w.e));
	v = q ? r : (r > 0 ? r - 1 : out.vertices + r);
	if ((!q && r == 0) || v < 0 || v >= out.vertices)
		return corrupt(e, lineAt(lineNo) + "face uses vertex " + quote(w.b, s1) + " but " +
		                      num(out.vertices) + " vertices are defined before it");
	// texture and normal indices, split as VCG's SplitToken (import_obj.h:822) does, must name
	// earlier vt / vn lines: an empty one is -1 there, which its GoodObjIndex turns into one past
	// the end (:190, read at :683 and :695)
	const char *s2 = s1 == w.e ? s1 : std::find(s1 + 1, w.e, '/');
	const long long counts[2] = {n.nvt, n.nvn};
	const Word parts[2] = {{s1 == w.e ? s1 : s1 + 1, s2}, {s2 == w.e ? s2 : s2 + 1, w.e}};
	const bool given[2] = {s1 != w.e && (s2 == w.e || s1 + 1 < s2), s2 != w.e};
	for (int c = 0; c < 2; ++c) {
		if (!given[c])
			continue;
		if (!parseInt(parts[c].b, parts[c].e, r) || r == 0 || (r > 0 ? r : -r) > counts[c])
			return corrupt(e, lineAt(lineNo) + "face uses " + (c ? "normal " : "texture ") +
			                      quote(parts[c].b, parts[c].e) + " but " + num(counts[c]) +
			                      " are defined before it");
	}
	return true;
}

/// An 'f' or 'q' statement: its corners, and its fan of triangles into `out` (as VCG's
/// FanTessellator; triangles repeating a vertex dropped).
bool scanObjFace(const std::vector<Word> &w, bool q, size_t lineNo, const ObjCounts &n,
                 std::vector<int> &poly, ObjScan &out, ReadError &e)
{
	const long long nc = (long long)w.size() - 1;
	if (nc < 3 || (q && nc != 4)) {
		out.shortFaces += !q;
		return true; // VCG skips it (q: fails with its own error)
	}
	poly.clear();
	for (long long j = 1; j <= nc; ++j) {
		long long v;
		if (!scanObjCorner(w[size_t(j)], q, lineNo, n, out, v, e))
			return false;
		poly.push_back(int(v));
	}
	for (long long j = 0; j + 2 < nc; ++j) {
		const int a = poly[0], b = poly[size_t(j + 1)], c = poly[size_t(j + 2)];
		if (a == b || a == c || b == c)
			continue;
		out.tri.insert(out.tri.end(), {a, b, c});
		out.faux.push_back((unsigned char)((j > 0 ? 4 : 0) | (j + 3 < nc ? 2 : 0)));
	}
	return true;
}

/// An 'l' statement: VCG takes &m.vert[atoi - 1] of its first two vertices (:369, :656).
bool scanObjLineElement(const std::vector<Word> &w, size_t lineNo, const ObjScan &out, ReadError &e)
{
	for (int j = 1; j < 3; ++j) {
		long long r;
		if (!parseInt(w[j].b, std::find(w[j].b, w[j].e, '/'), r) || r < 1 || r > out.vertices)
			return corrupt(e, lineAt(lineNo) + "line element uses vertex " + quote(w[j].b, w[j].e) +
			                      " but " + num(out.vertices) + " vertices are defined before it");
	}
	return true;
}

/// One statement of logical line [start, end) (split into `w`).
bool scanObjStatement(const std::vector<Word> &w, const char *start, const char *end, size_t lineNo,
                      ObjCounts &n, std::vector<int> &poly, ObjScan &out, ReadError &e)
{
	if (wordIs(w[0], "v")) {
		++out.vertices;
		++n.statements;
		return scanObjVertex(w, lineNo, n, out, e);
	}
	if (wordIs(w[0], "vt")) {
		n.nvt += w.size() >= 3; // (VCG stops at a shorter one)
	} else if (wordIs(w[0], "vn")) {
		n.nvn += w.size() == 4; // (VCG stops at another)
	} else if (wordIs(w[0], "f") || wordIs(w[0], "q")) {
		++n.statements;
		return scanObjFace(w, wordIs(w[0], "q"), lineNo, n, poly, out, e);
	} else if (wordIs(w[0], "l") && w.size() >= 3) {
		return scanObjLineElement(w, lineNo, out, e);
	} else if (wordIs(w[0], "mtllib") && w.size() > 1) {
		const size_t len = size_t(end - start);
		const std::string name = w.size() == 2 ? std::string(w[1].b, w[1].e)
		                                       : std::string(start + std::min<size_t>(7, len), end);
		return checkMaterialFile(name, e, &out.definedMaterials);
	} else if (wordIs(w[0], "usemtl")) {
		n.usemtl = true;
		if (w.size() > 1)
			out.usedMaterials.emplace(w[1].b, w[w.size() - 1].e);
	}
	return true;
}

/// After the last line: the material file named after the OBJ, and the counts VCG's LoadMask
/// took against the statements read.
bool checkObjCounts(const std::string &path, const ObjCounts &n, ObjScan &out, ReadError &e)
{
	const ObjMaskCount &mask = n.mask;
	if (n.usemtl && path.size() >= 4 &&
	    !checkMaterialFile(path.substr(0, path.size() - 4) + ".mtl", e, &out.definedMaterials))
		return false;
	if (out.vertices != mask.v)
		return corrupt(e, num(mask.v) + " lines start with 'v ' but " + num(out.vertices) +
		                      " vertex statements were found");
	// with as many texture as vertex lines VCG reads texCoords[t] of every face corner, t = 0
	// when the corner gives none (import_obj.h:682): the counts must agree
	if (n.nvt != mask.vt && mask.vt == mask.v)
		return corrupt(e, num(mask.vt) + " lines start with 'vt' but " + num(n.nvt) +
		                      " texture coordinates were found");
	// with as many normal as vertex lines VCG reads normals[n] of every corner, n its vertex
	// number when it gives none (:834, :695), GoodObjIndex letting one past the end through
	if (n.nvn != mask.vn && mask.vn == mask.v)
		return corrupt(e, num(mask.vn) + " lines start with 'vn' but " + num(n.nvn) +
		                      " normals were found");
	if (n.mrgb > 0 && n.mrgb < mask.v) // VCG reads one #MRGB colour per vertex (import_obj.h:731)
		return corrupt(e, "#MRGB colours for " + num(n.mrgb) + " of " + num(mask.v) + " vertices");
	if (n.statements == 0)
		return fail(e, ReadStatus::Empty, "no vertex and no face statement");
	return true;
}

} // namespace

bool scanObj(FILE *f, const std::string &path, double vertexBytes, double faceBytes, ObjScan &out,
             ReadError &e)
{
	LineReader in(f);
	std::string joined;
	std::vector<Word> w;
	std::vector<int> poly;
	ObjCounts n;
	while (in.next()) {
		// VCG's LoadMask counts vertex lines by their first two characters (import_obj.h:897)
		n.mask.add(in);
		const size_t lineNo = in.number();
		bool used;
		if (!joinLine(in, joined, used, "OBJ", e, &n.mask))
			return false;
		const char *p = used ? joined.data() : in.data();
		size_t len = used ? joined.size() : in.size();
		if (!used && len && p[len - 1] == '\r')
			--len;
		if (len == 0)
			continue;
		if (p[0] == '#') {
			if (len >= 5 && std::strncmp(p, "#MRGB", 5) == 0)
				for (size_t i = 6; i + 7 < len; i += 8)
					++n.mrgb;
			continue;
		}
		w.clear();
		splitWords(p, p + len, true, w);
		if (!w.empty() && !scanObjStatement(w, p, p + len, lineNo, n, poly, out, e))
			return false;
	}
	if (!checkObjCounts(path, n, out, e))
		return false;
	return checkMemory(double(out.vertices) * vertexBytes + double(out.faux.size()) * faceBytes, e);
}

void addObjNotes(const ObjScan &scan, std::vector<std::string> &notes)
{
	if (scan.shortFaces)
		notes.push_back(num(scan.shortFaces) + " face record" + (scan.shortFaces == 1 ? "" : "s") +
		                " with fewer than 3 vertices skipped");
	std::vector<std::string> missing;
	for (const std::string &u : scan.usedMaterials)
		if (!scan.definedMaterials.count(u))
			missing.push_back(u);
	for (size_t i = 0; i < missing.size() && i < 3; ++i)
		notes.push_back("material " +
		                quote(missing[i].data(), missing[i].data() + missing[i].size()) +
		                " is used but no material file defines it (its faces take the "
		                "default material)");
	if (missing.size() > 3)
		notes.push_back(num((long long)missing.size() - 3) + " more undefined materials");
}

} // namespace detail
} // namespace gausslod
