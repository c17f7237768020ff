// thread_count: a request beyond what TBB allows is clamped (TBB would otherwise print its own
// warning and run fewer workers than reported), with one warning through the library's log.
#include "shprt/core/log.hpp"
#include "shprt/core/parallel.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <string>
#include <vector>

namespace {

TEST(ThreadCount, ClampsToWhatTbbAllowsWithOneWarning) {
    std::vector<std::string> warnings;
    shprt::set_log_sink([&](shprt::LogLevel level, std::string_view message) {
        if (level == shprt::LogLevel::warn) warnings.emplace_back(message);
    });
    {
        const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
        EXPECT_EQ(shprt::thread_count(1), 1);
        EXPECT_EQ(shprt::thread_count(2), 2);
        EXPECT_TRUE(warnings.empty());
        EXPECT_EQ(shprt::thread_count(7), 2);
        EXPECT_EQ(shprt::thread_count(7), 2);  // asked again (a bake asks several times)
        ASSERT_EQ(warnings.size(), 1u);
        EXPECT_NE(warnings[0].find("7 threads requested"), std::string::npos) << warnings[0];
        EXPECT_NE(warnings[0].find("using 2"), std::string::npos) << warnings[0];
        // The arena built from the request runs in the clamped count.
        int seen = 0;
        shprt::in_arena(7, [&] { seen = tbb::this_task_arena::max_concurrency(); });
        EXPECT_EQ(seen, 2);
    }
    EXPECT_GE(shprt::thread_count(0), 1);
    shprt::set_log_sink(nullptr);
}

}  // namespace
