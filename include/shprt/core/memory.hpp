// What this machine can spare: the memory a new allocation can take without swapping; and huge
// pages for the bake's few large buffers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace shprt {

// MemAvailable from /proc/meminfo (the kernel's estimate of memory available for new work), in
// bytes, lowered to the address-space limit (RLIMIT_AS) where one is set; 0 when neither is known
// (not Linux, no /proc, no limit).
std::uint64_t available_memory_bytes();

// Asks the kernel to back [p, p + bytes) with transparent huge pages (madvise MADV_HUGEPAGE on the
// whole 2 MiB pages inside it) before anything touches it. Where the kernel leaves THP to madvise
// (Debian's default), each 4 KiB page of a fresh buffer is otherwise a page fault of its own, and
// in a VM a dear one: on the room's error-bounded bake, advising the basis table, the session's
// sums and the output rows made the command 8–13 % faster (bench/RESULTS.md, "Huge pages for the
// bake's large buffers"). A hint: a no-op under 2 MiB, where THP is off, or off Linux.
void advise_huge_pages(const void* p, std::size_t bytes);

// Resizes `v` to n value-initialised elements in fresh storage advised as above: reserve (which
// allocates without touching), advise, then fill.
template <class T>
void assign_huge(std::vector<T>& v, std::size_t n, const T& value = T{}) {
    std::vector<T>().swap(v);
    v.reserve(n);
    advise_huge_pages(v.data(), n * sizeof(T));
    v.assign(n, value);
}

}  // namespace shprt
