// Reads a mesh file (PLY, OBJ, OFF, STL: whatever VCG's importer reads) into any VCG mesh type.
// OBJ into gausslod::IoMesh goes through obj_import.h (VCG's importer fixed, its input checked).
// One more guard VCG 2020.09 lacks: its OFF reader takes the first token of a line that holds
// only blanks (spaces, tabs, CR) as if there were one, and crashes on CGAL's own data file
// prim.off. Such lines are emptied (lines it skips) before it reads an OFF file.
#pragma once

#include "io_mesh.h"
#include "obj_import.h"

#include <vcg/complex/complex.h>
#include <wrap/io_trimesh/import.h>

#include <cctype>
#include <cstring>
#include <fstream>
#include <istream>
#include <streambuf>
#include <string>

// VCG 2020.09's OBJ importer skips every face that uses the file's first vertex (obj_import.h)
GAUSSLOD_FIX_VCG_OBJ_INDICES(gausslod::IoMesh)

namespace gausslod {

namespace detail {

inline bool hasExtension(const std::string &path, const char *ext)
{
	const size_t dot = path.find_last_of('.');
	if (dot == std::string::npos || path.find('/', dot) != std::string::npos)
		return false;
	std::string e = path.substr(dot + 1);
	for (char &c : e)
		c = char(std::tolower(static_cast<unsigned char>(c)));
	return e == ext;
}

/// Reads a text stream line by line, each line made only of spaces, tabs and CRs given as an
/// empty line (no copy of the file is made).
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

} // namespace detail

enum class ReadStatus { Ok = 0, CannotOpen, Empty, WrongFormat, Corrupt, TooLarge };
struct ReadError {
	ReadStatus status = ReadStatus::Ok;
	std::string message;
};
inline const char *readStatusName(ReadStatus s)
{
	static const char *const names[] = {"ok", "cannot_open", "empty", "wrong_format", "corrupt",
	                                    "too_large"};
	return names[int(s)];
}

template <class MeshT>
bool importMesh(MeshT &m, const std::string &path, std::string &error);

template <class MeshT>
bool importMesh(MeshT &m, const std::string &path, ReadError &error)
{
	if (importMesh(m, path, error.message))
		return true;
	error.status = ReadStatus::Corrupt;
	return false;
}

/// Loads `path` into `m`. Returns false with `error` set if the file cannot be read.
template <class MeshT>
bool importMesh(MeshT &m, const std::string &path, std::string &error)
{
	int mask = 0;
	if (detail::hasExtension(path, "obj") && obj::IndexFixFor<MeshT>::value)
		return obj::importObj(m, path, error);
	if (!detail::hasExtension(path, "off")) {
		const int e = vcg::tri::io::Importer<MeshT>::Open(m, path.c_str(), mask);
		if (e != 0 && vcg::tri::io::Importer<MeshT>::ErrorCritical(e)) {
			error = vcg::tri::io::Importer<MeshT>::ErrorMsg(e);
			return false;
		}
		return true;
	}
	using Off = vcg::tri::io::ImporterOFF<MeshT>;
	std::ifstream in(path, std::ios::binary);
	if (!in) {
		error = Off::ErrorMsg(Off::CantOpen);
		return false;
	}
	detail::BlankLineFilter filter(in);
	std::istream stream(&filter);
	const int e = Off::OpenStream(m, stream, mask);
	if (e != 0) { // (every OFF error is critical, as in vcg::tri::io::Importer)
		error = Off::ErrorMsg(e);
		return false;
	}
	return true;
}

} // namespace gausslod
