#include "shprt/core/memory.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <cstdio>

namespace shprt {

std::uint64_t available_memory_bytes() {
    std::uint64_t bytes = 0;
    if (std::FILE* f = std::fopen("/proc/meminfo", "r")) {
        char line[256];
        while (std::fgets(line, sizeof line, f) != nullptr) {
            unsigned long long kib = 0;
            if (std::sscanf(line, "MemAvailable: %llu kB", &kib) == 1) {
                bytes = static_cast<std::uint64_t>(kib) * 1024;
                break;
            }
        }
        std::fclose(f);
    }
    rlimit limit{};
    if (::getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY)
        bytes = bytes == 0 ? limit.rlim_cur : std::min<std::uint64_t>(bytes, limit.rlim_cur);
    return bytes;
}

}  // namespace shprt
