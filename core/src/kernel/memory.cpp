#include "kernel/memory.hpp"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <utility>

#if defined(__linux__)
#include <sys/mman.h>
#endif

#if defined(__SANITIZE_ADDRESS__)
#define MESHD_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define MESHD_ASAN 1
#endif
#endif
#if MESHD_ASAN
#include <sanitizer/asan_interface.h>
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

std::size_t whole_huge_pages(std::size_t bytes) { return (bytes + kHugePage - 1) & ~(kHugePage - 1); }

// AddressSanitizer watches malloc's blocks, not these mappings: it is told which of their bytes
// the program may touch. A block's tail past the bytes asked for, and a kept block, are marked
// out of bounds (an overrun into the rounding, a use after free, are reported as uses of
// poisoned memory); a range is marked usable again before it is unmapped, for whatever the
// kernel maps there next. Nothing happens in other builds.
[[maybe_unused]] void mark_unusable(const void* p, std::size_t n) {
#if MESHD_ASAN
    ASAN_POISON_MEMORY_REGION(p, n);
#else
    (void)p;
    (void)n;
#endif
}

[[maybe_unused]] void mark_usable(const void* p, std::size_t n) {
#if MESHD_ASAN
    ASAN_UNPOISON_MEMORY_REGION(p, n);
#else
    (void)p;
    (void)n;
#endif
}

// Huge pages asked for under a block at a 2 MiB boundary of whole huge pages.
void advise_block(void* at, std::size_t size) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    (void)madvise(at, size, MADV_HUGEPAGE);
#else
    (void)at;
    (void)size;
#endif
}

}  // namespace

#if defined(__linux__) && defined(MREMAP_FIXED)
#define MESHD_BLOCK_REUSE 1

namespace {

struct Block {
    char* at;
    std::size_t size;  // whole huge pages
};

// A thread's kept blocks and its large blocks' balance within its outermost BlockReuse.
struct Reuse {
    int depth = 0;
    std::array<Block, 16> kept{};
    std::size_t count = 0;
    std::ptrdiff_t live = 0;  // large blocks allocated less those freed since the scope began
    std::ptrdiff_t most = 0;  // the most `live` has been since then
    BlockCounters counters;
};
thread_local Reuse reuse;

void unmap(char* at, std::size_t size) {
    mark_usable(at, size);
    munmap(at, size);
}

// `size` bytes (whole huge pages) at a 2 MiB boundary: a huge page more mapped, the ends cut.
char* map_aligned(std::size_t size, int prot, int flags) {
    const std::size_t span = size + kHugePage;
    void* raw = mmap(nullptr, span, prot, MAP_PRIVATE | MAP_ANONYMOUS | flags, -1, 0);
    if (raw == MAP_FAILED) return nullptr;
    const auto from = reinterpret_cast<std::uintptr_t>(raw);
    const std::uintptr_t at = (from + kHugePage - 1) & ~(kHugePage - 1);
    if (at > from) munmap(raw, at - from);
    if (from + span > at + size) munmap(reinterpret_cast<void*>(at + size), from + span - (at + size));
    return reinterpret_cast<char*>(at);
}

char* map_fresh(std::size_t size) {
    char* at = map_aligned(size, PROT_READ | PROT_WRITE, 0);
    if (at == nullptr) throw std::bad_alloc();
    advise_block(at, size);
    reuse.counters.mapped_bytes += size;
    return at;
}

Block take_kept(std::size_t i) {
    const Block b = reuse.kept[i];
    reuse.kept[i] = reuse.kept[--reuse.count];
    reuse.counters.kept_bytes -= b.size;
    return b;
}

std::size_t smallest_kept() {
    std::size_t best = 0;
    for (std::size_t i = 1; i < reuse.count; ++i)
        if (reuse.kept[i].size < reuse.kept[best].size) best = i;
    return best;
}

// A block of `size` bytes made of kept blocks, the largest first, each moved with its pages
// into the next part of a new place at a 2 MiB boundary (the last one only in part, its rest
// staying kept), and fresh pages for what they do not cover. Null (nothing moved) where the
// kernel will not make the place.
char* gather(std::size_t size) {
    char* at = map_aligned(size, PROT_NONE, MAP_NORESERVE);
    if (at == nullptr) return nullptr;
    std::size_t filled = 0;
    while (filled < size && reuse.count > 0) {
        std::size_t largest = 0;
        for (std::size_t i = 1; i < reuse.count; ++i)
            if (reuse.kept[i].size > reuse.kept[largest].size) largest = i;
        Block& b = reuse.kept[largest];
        const std::size_t part = std::min(b.size, size - filled);
        if (mremap(b.at, part, part, MREMAP_MAYMOVE | MREMAP_FIXED, at + filled) == MAP_FAILED) break;
        mark_usable(b.at, part);  // no longer mapped there
        reuse.counters.reused_bytes += part;
        filled += part;
        if (part == b.size) {
            take_kept(largest);
        } else {
            b.at += part;
            b.size -= part;
            reuse.counters.kept_bytes -= part;
        }
    }
    if (filled < size) {
        // The reservation's rest made writable: fresh pages.
        if (mmap(at + filled, size - filled, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_FIXED, -1,
                 0) == MAP_FAILED) {
            munmap(at, size);
            throw std::bad_alloc();
        }
        reuse.counters.mapped_bytes += size - filled;
    }
    advise_block(at, size);
    return at;
}

// Kept blocks returned, the smallest first (the last one only cut), until the large blocks
// live and kept are no more than the most that were live at once.
void trim_kept() {
    for (;;) {
        const std::ptrdiff_t excess =
            reuse.live + static_cast<std::ptrdiff_t>(reuse.counters.kept_bytes) - reuse.most;
        if (excess <= 0 || reuse.count == 0) return;
        const auto cut = static_cast<std::size_t>(excess);  // whole huge pages, as every size here
        Block& b = reuse.kept[smallest_kept()];
        if (b.size <= cut) {
            const std::size_t i = static_cast<std::size_t>(&b - reuse.kept.data());
            const Block gone = take_kept(i);
            unmap(gone.at, gone.size);
        } else {
            unmap(b.at + (b.size - cut), cut);
            b.size -= cut;
            reuse.counters.kept_bytes -= cut;
        }
    }
}

void* allocate_large(std::size_t size) {
    char* at = nullptr;
    if (reuse.depth > 0 && reuse.count > 0) {
        // The kept block nearest above the size, cut down to it (its rest stays kept: its
        // pages are made already, where fresh ones are not); else kept blocks gathered.
        std::size_t fit = reuse.count;
        for (std::size_t i = 0; i < reuse.count; ++i) {
            const std::size_t s = reuse.kept[i].size;
            if (s >= size && (fit == reuse.count || s < reuse.kept[fit].size)) fit = i;
        }
        if (fit < reuse.count) {
            Block& b = reuse.kept[fit];
            at = b.at;
            if (b.size > size) {
                b.at += size;
                b.size -= size;
                reuse.counters.kept_bytes -= size;
            } else {
                take_kept(fit);
            }
            reuse.counters.reused_bytes += size;
        } else {
            at = gather(size);
        }
    }
    if (at == nullptr) at = map_fresh(size);
    if (reuse.depth > 0) {
        reuse.live += static_cast<std::ptrdiff_t>(size);
        reuse.most = std::max(reuse.most, reuse.live);
        trim_kept();
    }
    return at;
}

void release_large(void* p, std::size_t size) noexcept {
    if (reuse.depth == 0) {
        unmap(static_cast<char*>(p), size);
        return;
    }
    reuse.live -= static_cast<std::ptrdiff_t>(size);
    Block b{static_cast<char*>(p), size};
    if (reuse.count == reuse.kept.size()) {  // full: the smaller of it and the smallest kept goes
        const std::size_t i = smallest_kept();
        if (reuse.kept[i].size < size) std::swap(b, reuse.kept[i]);
        reuse.counters.kept_bytes += size - b.size;
        unmap(b.at, b.size);
        return;
    }
    reuse.kept[reuse.count++] = b;
    reuse.counters.kept_bytes += size;
}

}  // namespace

BlockReuse::BlockReuse() : outermost_(reuse.depth++ == 0) {
    if (outermost_) reuse.live = reuse.most = 0;
}

BlockReuse::~BlockReuse() {
    --reuse.depth;
    if (!outermost_) return;
    while (reuse.count > 0) {
        const Block b = take_kept(reuse.count - 1);
        unmap(b.at, b.size);
    }
    reuse.live = reuse.most = 0;
}

BlockCounters block_counters() { return reuse.counters; }

#else

BlockReuse::BlockReuse() : outermost_(false) {}
BlockReuse::~BlockReuse() = default;
BlockCounters block_counters() { return {}; }

#endif

void* allocate_huge(std::size_t bytes, std::size_t align) {
    if (bytes < kSmall)
        return align > __STDCPP_DEFAULT_NEW_ALIGNMENT__ ? ::operator new(bytes, std::align_val_t{align})
                                                        : ::operator new(bytes);
    if (bytes > SIZE_MAX - kHugePage) throw std::bad_alloc();
    const std::size_t size = whole_huge_pages(bytes);
#if MESHD_BLOCK_REUSE
    char* at = static_cast<char*>(allocate_large(size));
    mark_usable(at, bytes);
    mark_unusable(at + bytes, size - bytes);
    return at;
#else
    void* p = std::aligned_alloc(kHugePage, size);
    if (p == nullptr) throw std::bad_alloc();
    advise_block(p, size);
    return p;
#endif
}

void deallocate_huge(void* p, std::size_t bytes, std::size_t align) noexcept {
    if (p == nullptr) return;
    if (bytes >= kSmall) {
#if MESHD_BLOCK_REUSE
        const std::size_t size = whole_huge_pages(bytes);
        mark_unusable(p, size);
        release_large(p, size);
#else
        std::free(p);
#endif
    } else if (align > __STDCPP_DEFAULT_NEW_ALIGNMENT__) {
        ::operator delete(p, std::align_val_t{align});
    } else {
        ::operator delete(p);
    }
}

}  // namespace meshd::core::detail
