// core/file.hpp's AtomicFile: the target appears only on commit; a failure or a destructor before
// commit leaves nothing; a process terminated by SIGTERM or SIGHUP removes its live temporaries
// first (as mpirun terminates the other ranks of a failed job), and dies of the signal.
#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <string>

namespace shprt {
namespace {

namespace fs = std::filesystem;

class AtomicFileTest : public ::testing::Test {
protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() / ("shprt_atomic_" + std::to_string(::getpid()));
        fs::remove_all(m_dir);
        fs::create_directories(m_dir);
    }
    void TearDown() override { fs::remove_all(m_dir); }
    std::size_t entries() const {
        return static_cast<std::size_t>(
            std::distance(fs::directory_iterator(m_dir), fs::directory_iterator()));
    }
    fs::path m_dir;
};

TEST_F(AtomicFileTest, TheTargetAppearsOnlyOnCommit) {
    const std::string target = (m_dir / "out.bin").string();
    {
        AtomicFile file(target);
        file.write("abc");
        EXPECT_FALSE(fs::exists(target));
        EXPECT_TRUE(fs::exists(file.temp_path()));
        file.commit();
    }
    EXPECT_EQ(read_file(target), "abc");
    EXPECT_EQ(entries(), 1u);
    {
        AtomicFile abandoned(target);
        abandoned.write("xyz");
    }
    EXPECT_EQ(read_file(target), "abc") << "an uncommitted file replaced the target";
    EXPECT_EQ(entries(), 1u) << "the uncommitted temporary was left";
    EXPECT_THROW(AtomicFile((m_dir / "no" / "such" / "dir.bin").string()), Error);
}

TEST_F(AtomicFileTest, TerminationSignalsRemoveLiveTemporaries) {
    for (int signal : {SIGTERM, SIGHUP}) {
        const std::string target = (m_dir / "out.bin").string();
        int ready[2];
        ASSERT_EQ(::pipe(ready), 0);
        const pid_t child = ::fork();
        ASSERT_GE(child, 0);
        if (child == 0) {  // two live temporaries, one committed file; then wait to be killed
            AtomicFile a(target), b(target + ".second");
            AtomicFile done(target + ".done");
            done.commit();
            (void)!::write(ready[1], "1", 1);
            for (;;) ::pause();
        }
        char byte = 0;
        ASSERT_EQ(::read(ready[0], &byte, 1), 1);
        ::close(ready[0]);
        ::close(ready[1]);
        EXPECT_EQ(entries(), 3u);
        ::kill(child, signal);
        int status = 0;
        ASSERT_EQ(::waitpid(child, &status, 0), child);
        EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == signal) << "status " << status;
        EXPECT_EQ(entries(), 1u) << "signal " << signal << " left temporaries";
        EXPECT_TRUE(fs::exists(target + ".done"));
        fs::remove(target + ".done");
    }
}

}  // namespace
}  // namespace shprt
