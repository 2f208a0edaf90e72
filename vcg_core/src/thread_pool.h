// The engine's worker threads: a fixed set of workers per call, exceptions carried back.
#pragma once

#include <algorithm>
#include <cstddef>
#include <exception>
#include <thread>
#include <vector>

namespace gausslod {
namespace detail {

/// Worker threads for `requested` (0 = one per core), at most 64.
inline size_t threadCount(int requested)
{
	const size_t n =
	    requested > 0 ? size_t(requested) : size_t(std::thread::hardware_concurrency());
	return std::max<size_t>(1, std::min<size_t>(n, 64));
}

/// Runs fn(worker) for worker = 0 .. workers-1 at once, worker 0 on the calling thread; the first
/// exception of a worker (in worker order) is rethrown here once all have finished.
template <class Fn>
void onWorkers(size_t workers, Fn fn)
{
	if (workers <= 1) {
		fn(size_t(0));
		return;
	}
	std::vector<std::exception_ptr> error(workers);
	auto run = [&](size_t w) {
		try {
			fn(w);
		} catch (...) {
			error[w] = std::current_exception();
		}
	};
	std::vector<std::thread> pool;
	for (size_t w = 1; w < workers; ++w)
		pool.emplace_back(run, w);
	run(0);
	for (std::thread &t : pool)
		t.join();
	for (const std::exception_ptr &e : error)
		if (e)
			std::rethrow_exception(e);
}

/// Runs fn(begin, end, part) on [0, n) cut in up to `threads` contiguous parts.
template <class Fn>
void parallelRanges(size_t n, size_t threads, Fn fn)
{
	const size_t parts = std::max<size_t>(1, std::min(threads, n / 4096 + 1));
	onWorkers(parts, [&](size_t p) { fn(n * p / parts, n * (p + 1) / parts, p); });
}

} // namespace detail
} // namespace gausslod
