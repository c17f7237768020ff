// What this machine can spare: the memory a new allocation can take without swapping.
#pragma once

#include <cstdint>

namespace shprt {

// MemAvailable from /proc/meminfo (the kernel's estimate of memory available for new work), in
// bytes; 0 when it cannot be read (not Linux, no /proc).
std::uint64_t available_memory_bytes();

}  // namespace shprt
