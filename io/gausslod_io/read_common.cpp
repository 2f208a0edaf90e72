// What every reader of gausslod_io uses: the status names, the one-line messages, the memory
// check of what a header announces, the folder an OBJ is read from.
#include "read_formats.h"

#include <fcntl.h>
#include <unistd.h>

#include <cctype>
#include <cstdio>

namespace gausslod {

const char *readStatusName(ReadStatus s)
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

const char *formatName(Format f)
{
	static const char *names[] = {"unknown", "PLY", "OBJ", "OFF", "STL"};
	return names[int(f)];
}

std::string withArticle(Format f)
{
	return std::string(f == Format::Ply ? "a " : "an ") + formatName(f);
}

bool fail(ReadError &e, ReadStatus s, const std::string &msg)
{
	e.status = s;
	e.message = msg;
	return false;
}

bool corrupt(ReadError &e, const std::string &msg) { return fail(e, ReadStatus::Corrupt, msg); }

std::string num(long long v) { return std::to_string(v); }

std::string numD(double v)
{
	char s[32];
	std::snprintf(s, sizeof s, "%.6g", v);
	return s;
}

std::string quote(const char *b, const char *e)
{
	std::string s = "'";
	for (const char *p = b; p < e && s.size() < 25; ++p)
		s += (*p >= 32 && *p < 127) ? *p : '?';
	return s + (e - b > 24 ? "...'" : "'");
}

std::string lowerExtension(const std::string &path)
{
	const size_t dot = path.find_last_of('.');
	if (dot == std::string::npos || path.find('/', dot) != std::string::npos)
		return std::string();
	std::string e = path.substr(dot + 1);
	for (char &c : e)
		c = char(std::tolower(static_cast<unsigned char>(c)));
	return e;
}

namespace {

/// Bytes of memory the process can still take: MemAvailable, else free physical pages.
uint64_t availableMemory()
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

std::string bytesText(double b)
{
	char s[32];
	if (b >= 1e9)
		std::snprintf(s, sizeof s, "%.1f GB", b / 1e9);
	else
		std::snprintf(s, sizeof s, "%.1f MB", b / 1e6);
	return s;
}

} // namespace

bool checkMemory(double need, ReadError &e)
{
	const double avail = double(availableMemory());
	if (need <= avail)
		return true;
	return fail(e, ReadStatus::TooLarge,
	            "the header's counts need " + bytesText(need) + " of memory but only " +
	                bytesText(avail) + " is available");
}

bool lyingCounts(ReadError &e, unsigned long long nv, unsigned long long nf, uint64_t size)
{
	return corrupt(e, "the header announces " + std::to_string(nv) + " vertices and " +
	                      std::to_string(nf) + " faces but the file has only " +
	                      std::to_string(size) + " bytes");
}

InFolder::InFolder(const std::string &path) : name_(path)
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

InFolder::~InFolder()
{
	if (fd_ >= 0) {
		const int back = ::fchdir(fd_);
		(void)back;
		::close(fd_);
	}
}

} // namespace detail
} // namespace gausslod
