#include "kernel/memory.hpp"

#include <cstdint>
#include <cstdlib>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace meshd::core::detail {

void advise_huge_pages(const void* p, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    constexpr std::uintptr_t kHuge = std::uintptr_t{2} << 20;
    if (p == nullptr || bytes < 2 * kHuge) return;
    const auto from = reinterpret_cast<std::uintptr_t>(p);
    const std::uintptr_t begin = (from + kHuge - 1) & ~(kHuge - 1);
    const std::uintptr_t end = (from + bytes) & ~(kHuge - 1);
    // A refusal (no THP in this kernel, or "never") leaves ordinary pages: nothing to report.
    if (end > begin) (void)madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
    (void)p;
    (void)bytes;
#endif
}

void populate(void* p, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
    constexpr std::uintptr_t kPage = 4096;
    if (p == nullptr || bytes < (std::size_t{1} << 20)) return;
    const auto from = reinterpret_cast<std::uintptr_t>(p);
    const std::uintptr_t begin = from & ~(kPage - 1);
    const std::uintptr_t end = (from + bytes + kPage - 1) & ~(kPage - 1);
    // Linux 5.14 on; a refusal leaves the pages to be made by faults, as before.
    (void)madvise(reinterpret_cast<void*>(begin), end - begin, MADV_POPULATE_WRITE);
#else
    (void)p;
    (void)bytes;
#endif
}

namespace {
constexpr std::size_t kHugePage = std::size_t{2} << 20;
constexpr std::size_t kSmall = std::size_t{1} << 20;
}  // namespace

void* allocate_huge(std::size_t bytes, std::size_t align) {
    if (bytes < kSmall)
        return align > __STDCPP_DEFAULT_NEW_ALIGNMENT__ ? ::operator new(bytes, std::align_val_t{align})
                                                        : ::operator new(bytes);
    if (bytes > SIZE_MAX - kHugePage) throw std::bad_alloc();
    const std::size_t size = (bytes + kHugePage - 1) & ~(kHugePage - 1);
    void* p = std::aligned_alloc(kHugePage, size);
    if (p == nullptr) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    (void)madvise(p, size, MADV_HUGEPAGE);
#endif
    return p;
}

void deallocate_huge(void* p, std::size_t bytes, std::size_t align) noexcept {
    if (p == nullptr) return;
    if (bytes >= kSmall) std::free(p);
    else if (align > __STDCPP_DEFAULT_NEW_ALIGNMENT__) ::operator delete(p, std::align_val_t{align});
    else ::operator delete(p);
}

}  // namespace meshd::core::detail
