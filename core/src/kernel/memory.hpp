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
// pages. Array (meshd/core/array.hpp: the mesh's arrays and the stages' own) allocates at a
// 2 MiB boundary, in whole huge pages; assign_huge has the pages it is about to fill made at once (MADV_POPULATE_WRITE:
// one call instead of a fault per page). On the benchmark machine's virtual CPU a 4 KiB
// fault costs about 10 us, and random reads through small pages cost far more than through
// huge ones.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "meshd/core/array.hpp"

namespace meshd::core::detail {

/// Asks for huge pages under the whole 2 MiB pages inside [p, p + bytes). Best effort.
void advise_huge_pages(const void* p, std::size_t bytes);

/// Makes the pages under [p, p + bytes) at once, writable (one call instead of a fault per
/// page); for storage about to be written whole. Best effort; nothing below 1 MiB.
void populate(void* p, std::size_t bytes);

/// Freed large blocks handed to the next large allocations on the same thread.
///
/// A mesh of millions of points frees and allocates arrays of hundreds of MiB stage after
/// stage (the interior's grids and front, then the triangulation's keys, points and
/// triangles, then the smoother's tables). Unmapped and mapped again, each costs the kernel
/// a zeroing of every page, and on a virtual machine whose host takes back freed memory, the
/// host's supplying them again besides (about 1.5 s a GiB on the benchmark VM against 0.05 s
/// for pages the guest still holds). While a BlockReuse lives, the blocks of 1 MiB or more
/// (each a mapping of its own) that its thread frees through deallocate_huge are kept, and
/// the thread's next large allocations take them instead: the one nearest above the size
/// asked, cut to it (its rest stays kept); else kept blocks gathered into one, the largest
/// first, each moved with its pages (the last perhaps in part): only what they do not cover
/// is fresh. (At 10^7 points the triangulation's two arrays of triangles, 536 MiB each, had
/// grown the largest kept block each and taken 538 MiB of fresh pages with them while 436
/// MiB of smaller kept blocks waited; the rests of cut blocks had been unmapped.)
///
/// What is kept is bounded: the large blocks live and kept together never exceed the most
/// that were live at once since the scope began, and what would is returned at once. (Live
/// blocks count whole, reserved pages untouched or not, where a kept block's pages are mostly
/// made: the resident peak can come out a little higher than with every block unmapped when
/// freed; it was 1,722 MB against 1,679 at 10^7 points when only whole blocks were kept, and
/// is 1,560 MB since the rests and gatherings.) The outermost BlockReuse on a thread returns
/// what is kept when it ends; nested ones do nothing. Blocks freed on another thread, or
/// outside any scope, are unmapped.
///
/// Under AddressSanitizer a block's bytes past those asked for and a kept block's are
/// poisoned, so overruns and uses after free are reported as in malloc's blocks.
class BlockReuse {
public:
    BlockReuse();
    ~BlockReuse();
    BlockReuse(const BlockReuse&) = delete;
    BlockReuse& operator=(const BlockReuse&) = delete;

private:
    bool outermost_;
};

/// This thread's large blocks since it started: bytes mapped afresh, bytes served from kept
/// blocks, and bytes kept now (for tests and benchmarks).
struct BlockCounters {
    std::size_t mapped_bytes = 0;
    std::size_t reused_bytes = 0;
    std::size_t kept_bytes = 0;
};
BlockCounters block_counters();

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
