#pragma once
// Large arrays on huge pages. A mesh of millions of points touches gigabytes of fresh memory
// in its stages; at 4 KiB a page that is a fault every 4 KiB (on the benchmark machine's
// virtual CPU a seventh of the pipeline's time). Transparent huge pages, where the kernel
// offers them on request ("madvise" mode, the usual default), back such an array with 2 MiB
// pages instead: asked for before the array is first written, its faults become 512 times
// fewer. Elsewhere, or for arrays smaller than two huge pages, nothing changes.

#include <cstddef>
#include <vector>

namespace meshd::core::detail {

/// Asks for huge pages under the whole 2 MiB pages inside [p, p + bytes). Best effort.
void advise_huge_pages(const void* p, std::size_t bytes);

/// v.reserve(n), on huge pages when the new storage is large; call before filling v.
template <class T>
void reserve_huge(std::vector<T>& v, std::size_t n) {
    if (v.capacity() >= n) return;
    v.reserve(n);
    advise_huge_pages(v.data(), v.capacity() * sizeof(T));
}

/// v.assign(n, value) into storage on huge pages when it is large.
template <class T>
void assign_huge(std::vector<T>& v, std::size_t n, const T& value) {
    if (v.capacity() < n) {
        std::vector<T>().swap(v);
        reserve_huge(v, n);
    }
    v.assign(n, value);
}

}  // namespace meshd::core::detail
