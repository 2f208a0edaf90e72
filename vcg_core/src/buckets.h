// The engine's counting sorts (CSR buckets) and container helpers.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace gausslod {
namespace detail {

/// The one counting sort (CSR) of the engine: `emitAll(emit)` calls emit(key, item) for every
/// item, key below nKeys, the same sequence each time it is called (twice: to count, then to
/// fill). Afterwards the items of key k are items[start[k] .. start[k+1]), in emission order.
template <class Item, class EmitAll>
void fillBuckets(size_t nKeys, EmitAll emitAll, std::vector<int32_t> &start,
                 std::vector<Item> &items)
{
	start.assign(nKeys + 1, 0);
	emitAll([&](size_t key, const Item &) { ++start[key + 1]; });
	for (size_t k = 0; k < nKeys; ++k)
		start[k + 1] += start[k];
	items.resize(size_t(start[nKeys]));
	std::vector<int32_t> fill(start.begin(), start.end() - 1);
	emitAll([&](size_t key, const Item &item) { items[size_t(fill[key]++)] = item; });
}

/// Groups n items by a key below nKeys (stable, linear time): afterwards the items with key k
/// are order[start[k] .. start[k+1]), in their original order. `key(i)` gives item i's key.
template <class KeyFn>
void bucketByKey(size_t n, size_t nKeys, KeyFn key, std::vector<int32_t> &start,
                 std::vector<int32_t> &order)
{
	fillBuckets<int32_t>(
	    nKeys,
	    [&](auto emit) {
		    for (size_t i = 0; i < n; ++i)
			    emit(size_t(key(i)), int32_t(i));
	    },
	    start, order);
}

/// bucketByKey, then each bucket sorted by `less` (stable; buckets are small in practice).
template <class KeyFn, class Less>
void bucketSort(size_t n, size_t nKeys, KeyFn key, Less less, std::vector<int32_t> &start,
                std::vector<int32_t> &order)
{
	bucketByKey(n, nKeys, key, start, order);
	for (size_t k = 0; k < nKeys; ++k) {
		if (start[k + 1] - start[k] < 2)
			continue; // (also: no pointer arithmetic on an empty order)
		int32_t *b = order.data() + start[k], *e = order.data() + start[k + 1];
		if (e - b <= 16) { // insertion sort
			for (int32_t *i = b + 1; i < e; ++i)
				for (int32_t *j = i; j > b && less(*j, *(j - 1)); --j)
					std::swap(*j, *(j - 1));
		} else {
			std::stable_sort(b, e, less);
		}
	}
}

/// Frees a container's memory (clear() keeps it).
template <class V>
void release(V &v)
{
	V().swap(v);
}

} // namespace detail
} // namespace gausslod
