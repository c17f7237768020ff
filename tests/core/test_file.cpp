// Files (core/file.hpp): an output that names one of the inputs, directly, through a symbolic
// link or as a hard link, is the same file and is refused.
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace shprt {
namespace {

namespace fs = std::filesystem;

class Files : public ::testing::Test {
protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() /
                ("shprt_test_file_" + std::to_string(::getpid()) + "_" +
                 ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(m_dir);
        fs::create_directories(m_dir / "sub");
        std::ofstream(path("in.ply")) << "the input";
        std::ofstream(path("other.ply")) << "the input";  // equal bytes, another file
        fs::create_symlink(path("in.ply"), path("link.ply"));
        fs::create_hard_link(path("in.ply"), path("hard.ply"));
    }
    void TearDown() override { fs::remove_all(m_dir); }
    std::string path(const std::string& name) const { return (m_dir / name).string(); }

    fs::path m_dir;
};

TEST_F(Files, SameFileMeansTheSameInode) {
    EXPECT_TRUE(same_file(path("in.ply"), path("in.ply")));
    EXPECT_TRUE(same_file(path("in.ply"), path("sub/../in.ply")));
    EXPECT_TRUE(same_file(path("link.ply"), path("in.ply")));
    EXPECT_TRUE(same_file(path("in.ply"), path("hard.ply")));
    EXPECT_FALSE(same_file(path("in.ply"), path("other.ply")));
    EXPECT_FALSE(same_file(path("in.ply"), path("missing.ply")));
    EXPECT_FALSE(same_file(path("missing.ply"), path("missing.ply")))
        << "a file that does not exist is nobody's input";
    EXPECT_FALSE(same_file(path("in.ply"), "builtin:plane"));
}

TEST_F(Files, AnOutputOverAnInputIsRefusedNamingBoth) {
    for (const std::string& output : {path("in.ply"), path("link.ply"), path("hard.ply")}) {
        try {
            check_output_is_not_input(output, {path("other.ply"), path("in.ply")});
            ADD_FAILURE() << output << " accepted";
        } catch (const Error& e) {
            const std::string what = e.what();
            EXPECT_EQ(e.code(), ErrorCode::invalid_argument);
            EXPECT_EQ(what, "output " + output + " is the input file " + path("in.ply") +
                                " (the same file); choose another output name");
        }
    }
    EXPECT_NO_THROW(check_output_is_not_input(path("new.ply"), {path("in.ply")}));
    EXPECT_NO_THROW(check_output_is_not_input(path("other.ply"), {path("in.ply")}));
    EXPECT_NO_THROW(check_output_is_not_input(path("in.ply"), {}));
}

}  // namespace
}  // namespace shprt
