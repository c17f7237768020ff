// What this machine can spare: the memory a new allocation can take without swapping.
#pragma once

#include <cstdint>

namespace shprt {

// MemAvailable from /proc/meminfo (the kernel's estimate of memory available for new work), in
// bytes, lowered to the address-space limit (RLIMIT_AS) where one is set; 0 when neither is known
// (not Linux, no /proc, no limit).
std::uint64_t available_memory_bytes();

}  // namespace shprt
