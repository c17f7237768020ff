#include "shprt/core/error.hpp"
#include "shprt/core/log.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace shprt {
namespace {

TEST(CoreError, CheckThrowsWithCodeAndMessage) {
    try {
        SHPRT_CHECK(1 + 1 == 3, format, "file {} is bad: {}", "a.ply", 42);
        FAIL() << "SHPRT_CHECK did not throw";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::format);
        EXPECT_EQ(std::string(e.what()), "file a.ply is bad: 42");
    }
    EXPECT_NO_THROW(SHPRT_CHECK(true, io, "never"));
    EXPECT_STREQ(to_string(ErrorCode::cuda), "CUDA error");
}

TEST(CoreLog, SinkReceivesMessagesAndCanBeRemoved) {
    std::vector<std::string> seen;
    set_log_sink([&](LogLevel level, std::string_view m) {
        if (level == LogLevel::warn) seen.emplace_back(m);
    });
    log_warn("dropped {} triangles", 3);
    log_info("not a warning");
    set_log_sink(nullptr);
    log_warn("after removal");
    ASSERT_EQ(seen.size(), 1u);
    EXPECT_EQ(seen[0], "dropped 3 triangles");
}

}  // namespace
}  // namespace shprt
