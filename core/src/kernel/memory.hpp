#pragma once
// Large arrays on huge pages. A mesh of millions of points touches gigabytes of fresh memory
// in its stages; at 4 KiB a page that is a fault every 4 KiB (on the benchmark machine's
// virtual CPU a seventh of the pipeline's time). Transparent huge pages, where the kernel
// offers them on request ("madvise" mode, the usual default), back such an array with 2 MiB
// pages instead: asked for before the array is first written, its faults become 512 times
// fewer. Elsewhere, or for arrays smaller than two huge pages, nothing changes.
//
// Only the 2 MiB pages wholly inside an array can be huge, and malloc's large blocks start
// 16 bytes past a 4 KiB page: an array of a few MiB in a std::vector mostly stays on small
// pages. HugeVector (the stages' own arrays) allocates at a 2 MiB boundary, in whole huge
// pages; assign_huge has the pages it is about to fill made at once (MADV_POPULATE_WRITE:
// one call instead of a fault per page). On the benchmark machine's virtual CPU a 4 KiB
// fault costs about 10 us, and random reads through small pages cost far more than through
// huge ones.

#include <cstddef>
#include <cstdint>
#include <new>
#include <vector>

namespace meshd::core::detail {

/// Asks for huge pages under the whole 2 MiB pages inside [p, p + bytes). Best effort.
void advise_huge_pages(const void* p, std::size_t bytes);

/// Makes the pages under [p, p + bytes) at once, writable (one call instead of a fault per
/// page); for storage about to be written whole. Best effort; nothing below 1 MiB.
void populate(void* p, std::size_t bytes);

/// Storage for `bytes` aligned to `align`: from operator new below 1 MiB, else at a 2 MiB
/// boundary, rounded up to whole 2 MiB pages, on huge pages where the kernel offers them.
void* allocate_huge(std::size_t bytes, std::size_t align);
void deallocate_huge(void* p, std::size_t bytes, std::size_t align) noexcept;

template <class T>
struct HugeAllocator {
    using value_type = T;
    HugeAllocator() = default;
    template <class U>
    HugeAllocator(const HugeAllocator<U>&) noexcept {}
    T* allocate(std::size_t n) {
        if (n > SIZE_MAX / sizeof(T)) throw std::bad_array_new_length();
        return static_cast<T*>(allocate_huge(n * sizeof(T), alignof(T)));
    }
    void deallocate(T* p, std::size_t n) noexcept { deallocate_huge(p, n * sizeof(T), alignof(T)); }
    template <class U>
    bool operator==(const HugeAllocator<U>&) const noexcept { return true; }
};

/// A stage's own large array.
template <class T>
using HugeVector = std::vector<T, HugeAllocator<T>>;

/// v.reserve(n), on huge pages when the new storage is large; call before filling v.
template <class T, class A>
void reserve_huge(std::vector<T, A>& v, std::size_t n) {
    if (v.capacity() >= n) return;
    v.reserve(n);
    advise_huge_pages(v.data(), v.capacity() * sizeof(T));
}

/// reserve_huge(v, n) for storage about to be filled up to n: its pages are made now, in
/// one call.
template <class T, class A>
void reserve_filled(std::vector<T, A>& v, std::size_t n) {
    if (v.capacity() >= n) return;
    reserve_huge(v, n);
    populate(v.data(), n * sizeof(T));
}

/// v.assign(n, value) into storage on huge pages when it is large.
template <class T, class A>
void assign_huge(std::vector<T, A>& v, std::size_t n, const T& value) {
    if (v.capacity() < n) {
        std::vector<T, A>().swap(v);
        reserve_huge(v, n);
        populate(v.data(), n * sizeof(T));
    }
    v.assign(n, value);
}

}  // namespace meshd::core::detail
