#include "shprt/core/memory.hpp"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>

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

}  // namespace
}  // namespace shprt
