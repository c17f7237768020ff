#include "shprt/core/memory.hpp"
#include "shprt/core/sanitizers.hpp"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace shprt {
namespace {

TEST(AvailableMemory, ReadsTheKernelsEstimate) {
    EXPECT_GT(available_memory_bytes(), 0u);  // Linux: MemAvailable of /proc/meminfo
}

TEST(AvailableMemory, IsLoweredToTheAddressSpaceLimit) {
    // In a child, so that the limit does not bind this process: 256 MiB is far under what these
    // machines have free, so the answer must be the limit itself.
    constexpr std::uint64_t kLimit = std::uint64_t(256) << 20;
    ASSERT_GT(available_memory_bytes(), kLimit);
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        rlimit limit{};
        ::getrlimit(RLIMIT_AS, &limit);
        limit.rlim_cur = kLimit;
        const bool ok = ::setrlimit(RLIMIT_AS, &limit) == 0 && available_memory_bytes() == kLimit;
        ::_exit(ok ? 0 : 1);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0) << "available_memory_bytes() ignored RLIMIT_AS";
}

// The kernel's THP mode: "always", "madvise" or "never" (the bracketed word), "" where unknown.
std::string thp_mode() {
    std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string line;
    std::getline(in, line);
    const auto open = line.find('['), close = line.find(']');
    return open == std::string::npos || close == std::string::npos
               ? ""
               : line.substr(open + 1, close - open - 1);
}

// AnonHugePages of the mapping that holds `p`, in kB (/proc/self/smaps); -1 if not found.
long anon_huge_kb(const void* p) {
    const auto at = reinterpret_cast<std::uintptr_t>(p);
    std::ifstream smaps("/proc/self/smaps");
    bool inside = false;
    for (std::string line; std::getline(smaps, line);) {
        std::uintptr_t lo = 0, hi = 0;
        char dash = 0;
        std::istringstream head(line);
        if (head >> std::hex >> lo >> dash >> hi && dash == '-') {
            inside = at >= lo && at < hi;
        } else if (inside && line.rfind("AnonHugePages:", 0) == 0) {
            return std::stol(line.substr(14));
        }
    }
    return -1;
}

TEST(HugePages, AssignHugeFillsFreshStorage) {
    std::vector<float> v(3, 7.0f);
    assign_huge(v, 5, 2.0f);
    EXPECT_EQ(v, std::vector<float>(5, 2.0f));
    assign_huge(v, 0);
    EXPECT_TRUE(v.empty());
    advise_huge_pages(nullptr, 1u << 22);  // a hint: nothing to advise, no crash
}

TEST(HugePages, ALargeBufferIsBackedByThemWhereTheKernelAllows) {
    if (SHPRT_UNDER_ASAN) GTEST_SKIP() << "the sanitizer's allocator maps its own memory";
    const std::string mode = thp_mode();
    if (mode != "madvise" && mode != "always")
        GTEST_SKIP() << "transparent huge pages are '" << mode << "' on this kernel";
    std::vector<float> v;
    assign_huge(v, std::size_t(16) << 20);  // 64 MiB: at least 30 whole 2 MiB pages
    // The advice splits the mapping at the 2 MiB boundaries: look inside, not at its head.
    const long kb = anon_huge_kb(v.data() + v.size() / 2);
    ASSERT_GE(kb, 0) << "no mapping in /proc/self/smaps holds the buffer";
    EXPECT_GE(kb, 2048) << "THP is '" << mode << "', yet no huge page backs the advised buffer";
}

}  // namespace
}  // namespace shprt
