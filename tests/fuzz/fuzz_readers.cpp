// libFuzzer target for the file readers: the first byte picks the extension (ply, obj, off, stl),
// the rest is written to a per-process temporary file that importMesh reads into the tool's mesh
// type; a mesh that reads goes through flatten, whose indices must then lie in range. Any crash,
// leak, hang or sanitizer report is a guard missing in gausslod_io (check_file.cpp, read_*.cpp).
// Seeds in tests/fuzz/reader_seeds/, fixed crash inputs in tests/fuzz/reader_regressions/.
#include "gausslod/vcg_adapter.h"
#include "gausslod_io/import_mesh.h"
#include "gausslod_io/io_mesh.h"

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

[[noreturn]] void fail(const char *what)
{
	std::fprintf(stderr, "fuzz_readers: %s\n", what);
	std::abort();
}

// A directory of this process's own, removed at exit.
const std::string &tempDir()
{
	static const std::string dir = [] {
		char tmpl[] = "/tmp/fuzz_readers_XXXXXX";
		if (!mkdtemp(tmpl))
			fail("mkdtemp failed");
		std::atexit([] { rmdir(tempDir().c_str()); });
		return std::string(tmpl);
	}();
	return dir;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	static const char *const exts[] = {"ply", "obj", "off", "stl"};
	if (size == 0)
		return 0;
	const std::string path = tempDir() + "/in." + exts[data[0] % 4];
	FILE *f = std::fopen(path.c_str(), "wb");
	if (!f)
		fail("cannot write the temporary file");
	if (size > 1 && std::fwrite(data + 1, 1, size - 1, f) != size - 1)
		fail("cannot write the temporary file");
	std::fclose(f);

	gausslod::IoMesh m;
	gausslod::ReadError err;
	const bool ok = gausslod::importMesh(m, path, err);
	std::remove(path.c_str());
	if (!ok) {
		if (err.status == gausslod::ReadStatus::Ok || err.message.empty() ||
		    err.message.find('\n') != std::string::npos)
			fail("importMesh failed without a one-line message");
		return 0;
	}
	if (err.status != gausslod::ReadStatus::Ok)
		fail("importMesh succeeded with an error set");
	const gausslod::FlatMesh flat = gausslod::flatten(m);
	const int32_t nv = int32_t(flat.positions.size() / 3);
	for (int32_t t : flat.triangles)
		if (t < 0 || t >= nv)
			fail("flatten gave an index out of range");
	return 0;
}
