// Reads every file of the hostile corpus (tests/hostile/make_corpus.py) in a child process, so
// that a crash, a sanitizer report or a hang is seen as such, and checks the status and message
// importMesh gives against CORPUS/expected.tsv. Files that read ("ok") go on through flatten and
// buildLevels: the engine's error must then contain the fragment (none: it must succeed).
// Usage: test_read_corpus CORPUS_DIR [SECONDS_PER_FILE]
#include "gausslod/gausslod.h"
#include "gausslod/vcg_adapter.h"
#include "gausslod_io/import_mesh.h"
#include "gausslod_io/io_mesh.h"

#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

struct Case {
	std::string file, status, fragment, faces;
};

// What the child reports: status, message (importMesh's, or the engine's), faces read.
std::string readOne(const std::string &path)
{
	gausslod::IoMesh m;
	gausslod::ReadError err;
	if (!gausslod::importMesh(m, path, err)) {
		if (err.status == gausslod::ReadStatus::Ok || err.message.empty() ||
		    err.message.find('\n') != std::string::npos || err.message.back() == '.')
			return "bad_error\tfalse without a one-line message: " + err.message + "\t";
		return std::string(gausslod::readStatusName(err.status)) + "\t" + err.message + "\t";
	}
	if (err.status != gausslod::ReadStatus::Ok || !err.message.empty())
		return "bad_error\ttrue with an error set\t";
	const gausslod::FlatMesh flat = gausslod::flatten(m);
	gausslod::Params params;
	params.maxLevel = 2;
	const gausslod::Result res = gausslod::buildLevels(flat.view(), params);
	return "ok\t" + (res.ok ? std::string() : res.error) + "\t" +
	       std::to_string(flat.triangles.size() / 3);
}

// Runs readOne in a child; "" with `why` set if it crashed, hung or its sanitizer complained.
std::string runChild(const std::string &path, double seconds, std::string &why)
{
	int fd[2];
	if (pipe(fd) != 0) {
		why = "pipe failed";
		return "";
	}
	std::fflush(stdout); // (the child must not print the parent's buffered lines again)
	const pid_t pid = fork();
	if (pid == 0) {
		close(fd[0]);
		const std::string r = readOne(path);
		if (write(fd[1], r.data(), r.size()) < 0)
			_exit(3);
		close(fd[1]);
		std::exit(0); // (exit, not _exit: LeakSanitizer runs at exit)
	}
	close(fd[1]);
	std::string out;
	const auto start = std::chrono::steady_clock::now();
	char buf[4096];
	for (;;) {
		const double left =
		    seconds -
		    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
		pollfd p{fd[0], POLLIN, 0};
		if (left <= 0 || poll(&p, 1, int(left * 1000) + 1) == 0) {
			kill(pid, SIGKILL);
			waitpid(pid, nullptr, 0);
			close(fd[0]);
			why = "no answer within " + std::to_string(int(seconds)) + " s (hang?)";
			return "";
		}
		const ssize_t n = read(fd[0], buf, sizeof buf);
		if (n <= 0)
			break;
		out.append(buf, size_t(n));
	}
	close(fd[0]);
	int st = 0;
	waitpid(pid, &st, 0);
	if (WIFSIGNALED(st))
		why = std::string("crashed: ") + strsignal(WTERMSIG(st));
	else if (WEXITSTATUS(st) != 0)
		why = "exit status " + std::to_string(WEXITSTATUS(st)) + " (sanitizer report?)";
	return why.empty() ? out : "";
}

std::vector<std::string> split(const std::string &s)
{
	std::vector<std::string> f;
	std::string x;
	std::istringstream in(s);
	while (std::getline(in, x, '\t'))
		f.push_back(x);
	if (!s.empty() && s.back() == '\t')
		f.push_back("");
	return f;
}

} // namespace

int main(int argc, char **argv)
{
	if (argc < 2) {
		std::fprintf(stderr, "usage: %s CORPUS_DIR [SECONDS_PER_FILE]\n", argv[0]);
		return 2;
	}
	const std::string dir = argv[1];
	const double seconds = argc > 2 ? std::atof(argv[2]) : 20;
	std::ifstream tsv(dir + "/expected.tsv");
	std::vector<Case> cases;
	for (std::string line; std::getline(tsv, line);) {
		std::vector<std::string> f = split(line);
		f.resize(4);
		cases.push_back({f[0], f[1], f[2], f[3]});
	}
	if (cases.size() < 20) {
		std::fprintf(stderr, "%s/expected.tsv: only %zu cases\n", dir.c_str(), cases.size());
		return 2;
	}
	int failed = 0;
	for (const Case &c : cases) {
		std::string why;
		const std::string got = runChild(dir + "/" + c.file, seconds, why);
		std::vector<std::string> g = split(got);
		g.resize(3);
		if (why.empty() && g[0] != c.status)
			why = "status " + g[0] + ", expected " + c.status;
		else if (why.empty() && c.status == "ok" && c.fragment.empty() && !g[1].empty())
			why = "the engine failed";
		else if (why.empty() && g[1].find(c.fragment) == std::string::npos)
			why = "message lacks '" + c.fragment + "'";
		else if (why.empty() && !c.faces.empty() && g[2] != c.faces)
			why = g[2] + " faces read, expected " + c.faces;
		std::printf("%-4s %-34s %-12s %s\n", why.empty() ? "ok" : "FAIL", c.file.c_str(),
		            g[0].c_str(), g[1].c_str());
		if (!why.empty()) {
			std::printf("     -> %s\n", why.c_str());
			++failed;
		}
	}
	std::printf("%zu files, %d failed\n", cases.size(), failed);
	return failed ? 1 : 0;
}
