// Texture file names of a mesh written somewhere else than the file it was read from: a name
// relative to the input's folder is rewritten so that it still names the same image from the
// output's folder (the image is not copied); an absolute name stays as it is.
#pragma once

#include <climits>
#include <cstdlib>
#include <string>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

namespace gausslod {

namespace detail {

inline bool isFile(const std::string &path)
{
	struct stat st;
	return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

/// `path` made absolute (from the current directory) with "." and ".." resolved as text.
inline std::string lexicalAbsolute(const std::string &path)
{
	std::string full = path;
	if (full.empty() || full[0] != '/') {
		char cwd[PATH_MAX];
		full = std::string(::getcwd(cwd, sizeof cwd) ? cwd : ".") + "/" + full;
	}
	std::vector<std::string> parts;
	size_t i = 0;
	while (i <= full.size()) {
		size_t j = full.find('/', i);
		if (j == std::string::npos)
			j = full.size();
		const std::string part = full.substr(i, j - i);
		if (part == "..") {
			if (!parts.empty())
				parts.pop_back();
		} else if (!part.empty() && part != ".") {
			parts.push_back(part);
		}
		i = j + 1;
	}
	std::string out;
	for (const std::string &p : parts)
		out += "/" + p;
	return out.empty() ? "/" : out;
}

/// A folder's canonical absolute path (symbolic links resolved) if it exists, else lexical.
inline std::string canonicalFolder(const std::string &dir)
{
	char buf[PATH_MAX];
	if (::realpath(dir.empty() ? "." : dir.c_str(), buf))
		return buf;
	return lexicalAbsolute(dir.empty() ? "." : dir);
}

inline std::vector<std::string> splitPath(const std::string &abs)
{
	std::vector<std::string> parts;
	size_t i = 1;
	while (i < abs.size()) {
		size_t j = abs.find('/', i);
		if (j == std::string::npos)
			j = abs.size();
		if (j > i)
			parts.push_back(abs.substr(i, j - i));
		i = j + 1;
	}
	return parts;
}

} // namespace detail

/// The folder part of a file path ("." for a bare name).
inline std::string folderOf(const std::string &file)
{
	const size_t slash = file.find_last_of('/');
	return slash == std::string::npos ? std::string(".")
	       : slash == 0               ? std::string("/")
	                                  : file.substr(0, slash);
}

/// A texture name as found in a file read from `inputFolder`. Files written on Windows name
/// textures like ".\wood.jpg": where that does not name a file and the name with '/' does, the
/// name with '/' (as MeshLab's OBJ plugin does).
inline std::string localTextureName(const std::string &name, const std::string &inputFolder)
{
	if (name.find('\\') == std::string::npos)
		return name;
	std::string slashed = name;
	for (char &c : slashed)
		if (c == '\\')
			c = '/';
	auto from = [&](const std::string &n) { return n[0] == '/' ? n : inputFolder + "/" + n; };
	return !detail::isFile(from(name)) && detail::isFile(from(slashed)) ? slashed : name;
}

/// The name a file written into `outputFolder` must give the texture `name` of a mesh read from
/// `inputFolder`: an absolute name unchanged, a relative one as the path from `outputFolder` to
/// inputFolder/name (both folders with their symbolic links resolved when they exist).
inline std::string textureNameFrom(const std::string &outputFolder, const std::string &inputFolder,
                                   const std::string &name)
{
	if (name.empty() || name[0] == '/')
		return name;
	const std::string target =
	    detail::lexicalAbsolute(detail::canonicalFolder(inputFolder) + "/" + name);
	const std::vector<std::string> to = detail::splitPath(target),
	                               from = detail::splitPath(detail::canonicalFolder(outputFolder));
	size_t common = 0;
	while (common < from.size() && common + 1 < to.size() && from[common] == to[common])
		++common;
	std::string out;
	for (size_t i = common; i < from.size(); ++i)
		out += "../";
	for (size_t i = common; i < to.size(); ++i)
		out += to[i] + (i + 1 < to.size() ? "/" : "");
	return out;
}

} // namespace gausslod
