// What a program may write to a terminal (core/terminal.hpp): escape codes on a terminal unless
// TERM=dumb, colour unless NO_COLOR, nothing of either into a file; and failures as one line.
#include "shprt/core/terminal.hpp"

#include <gtest/gtest.h>
#include <pty.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>

namespace shprt {
namespace {

TEST(Terminal, EscapeCodesAndColourOnlyWhereTheyAreTaken) {
    std::FILE* file = std::tmpfile();
    ASSERT_NE(file, nullptr);
    ::setenv("TERM", "xterm", 1);
    ::unsetenv("NO_COLOR");
    EXPECT_FALSE(terminal_escape_codes(file));
    EXPECT_FALSE(terminal_colour(file));
    EXPECT_FALSE(terminal_escape_codes(nullptr));
    std::fclose(file);

    int master = -1, slave = -1;
    if (::openpty(&master, &slave, nullptr, nullptr, nullptr) != 0)
        GTEST_SKIP() << "no pseudo-terminal here (openpty failed)";
    std::FILE* tty = ::fdopen(slave, "w");
    ASSERT_NE(tty, nullptr);
    EXPECT_TRUE(terminal_escape_codes(tty));
    EXPECT_TRUE(terminal_colour(tty));
    ::setenv("NO_COLOR", "", 1);  // empty: as if unset (no-color.org)
    EXPECT_TRUE(terminal_colour(tty));
    ::setenv("NO_COLOR", "1", 1);
    EXPECT_TRUE(terminal_escape_codes(tty));
    EXPECT_FALSE(terminal_colour(tty));
    ::unsetenv("NO_COLOR");
    ::setenv("TERM", "dumb", 1);
    EXPECT_FALSE(terminal_escape_codes(tty));
    EXPECT_FALSE(terminal_colour(tty));
    std::fclose(tty);
    ::close(master);
}

TEST(Terminal, OneLineJoinsLinesAndDropsBlankOnes) {
    EXPECT_EQ(one_line("plain"), "plain");
    EXPECT_EQ(one_line("shader failed:\n0:1: bad token  \n\n0:2: missing ;\n"),
              "shader failed:; 0:1: bad token; 0:2: missing ;");
    EXPECT_EQ(one_line(" \n\t\n"), "");
    EXPECT_EQ(one_line(""), "");
}

}  // namespace
}  // namespace shprt
