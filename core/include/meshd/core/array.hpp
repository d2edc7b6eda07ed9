#pragma once
/// Array<T>: the storage of the mesh's large arrays and the pipeline's. A std::vector whose
/// storage from 1 MiB up is a mapping of its own at a 2 MiB boundary, on huge pages where the
/// kernel offers them (a fault and a TLB entry for 2 MiB instead of 4 KiB), handed from one
/// stage of a generate_mesh to the next when freed instead of being unmapped and mapped
/// afresh (kernel/memory.hpp in the core's sources says how and why). It is used as any
/// std::vector; a plain one is `std::vector<T>(a.begin(), a.end())`.

#include <cstddef>
#include <cstdint>
#include <new>
#include <vector>

namespace meshd::core {

namespace detail {

/// Storage for `bytes` aligned to `align`: from operator new below 1 MiB, else a mapping of
/// its own at a 2 MiB boundary, rounded up to whole 2 MiB pages, on huge pages where the
/// kernel offers them, and kept for reuse inside a BlockReuse (kernel/memory.hpp).
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
    bool operator==(const HugeAllocator<U>&) const noexcept {
        return true;
    }
};

}  // namespace detail

template <class T>
using Array = std::vector<T, detail::HugeAllocator<T>>;

}  // namespace meshd::core
