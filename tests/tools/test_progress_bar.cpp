// The tools' progress display (tools/common/progress_bar.hpp): the number formats, the plain
// lines written to a file or pipe, the in-place bar drawn on a terminal (a pseudo-terminal here,
// so the real isatty and window-size paths run), and Ctrl-C turning into a cancel request.
#include "common/progress_bar.hpp"

#include <gtest/gtest.h>
#include <poll.h>
#include <pty.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

namespace shprt::tools {
namespace {

ProgressInfo report(std::uint64_t done, std::uint64_t total) {
    ProgressInfo info;
    info.stage = "tracing";
    info.unit = "rays";
    info.done = done;
    info.total = total;
    return info;
}

// Everything written to `file` so far.
std::string contents(std::FILE* file) {
    std::fflush(file);
    std::rewind(file);
    std::string text;
    char buffer[4096];
    std::size_t n = 0;
    while ((n = std::fread(buffer, 1, sizeof buffer, file)) > 0) text.append(buffer, n);
    return text;
}

std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::size_t start = 0;
    for (std::size_t i = 0; i < text.size(); ++i)
        if (text[i] == '\n') {
            out.push_back(text.substr(start, i - start));
            start = i + 1;
        }
    if (start < text.size()) out.push_back(text.substr(start));
    return out;
}

TEST(ProgressFormat, SiPrefixesWithThreeSignificantDigits) {
    EXPECT_EQ(format_si(0), "0.00");
    EXPECT_EQ(format_si(3), "3.00");
    EXPECT_EQ(format_si(42.5), "42.5");
    EXPECT_EQ(format_si(980), "980");
    EXPECT_EQ(format_si(999.6), "1.00 k");  // rounds up into the next prefix, not "1000"
    EXPECT_EQ(format_si(51.2e6), "51.2 M");
    EXPECT_EQ(format_si(4.82e6), "4.82 M");
    EXPECT_EQ(format_si(1.5e9), "1.50 G");
    EXPECT_EQ(format_si(-2500), "-2.50 k");
}

TEST(ProgressFormat, DurationsSecondsThenClock) {
    EXPECT_EQ(format_duration(0.35), "0.35 s");
    EXPECT_EQ(format_duration(4.2), "4.2 s");
    EXPECT_EQ(format_duration(59.9), "59.9 s");
    EXPECT_EQ(format_duration(65), "1:05");
    EXPECT_EQ(format_duration(64.2), "1:05");  // whole seconds, rounded up
    EXPECT_EQ(format_duration(2 * 3600 + 3 * 60 + 4), "2:03:04");
    EXPECT_EQ(format_duration(-1), "?");
    EXPECT_EQ(format_duration(std::numeric_limits<double>::quiet_NaN()), "?");
    EXPECT_EQ(format_duration(std::numeric_limits<double>::infinity()), "?");
}

// Two significant digits, never "1e+02": the share over E of a bake's first round is 100 %.
TEST(ProgressFormat, PercentagesTwoDigitsWithoutExponents) {
    EXPECT_EQ(format_percent(1.0), "100");
    EXPECT_EQ(format_percent(0.684), "68");
    EXPECT_EQ(format_percent(0.0995), "10");
    EXPECT_EQ(format_percent(0.078), "7.8");
    EXPECT_EQ(format_percent(0.01), "1.0");
    EXPECT_EQ(format_percent(0.0071), "0.71");
    EXPECT_EQ(format_percent(0.000012), "0.0012");
    EXPECT_EQ(format_percent(0.000001), "< 0.001");
    EXPECT_EQ(format_percent(0), "< 0.001");
    EXPECT_EQ(format_percent(-0.5), "?");
    EXPECT_EQ(format_percent(std::numeric_limits<double>::quiet_NaN()), "?");
}

TEST(ProgressBarTest, NotATerminalPrintsOneLinePerQuarter) {
    std::FILE* file = std::tmpfile();
    ASSERT_NE(file, nullptr);
    {
        ProgressBar bar("bake", file);
        EXPECT_FALSE(bar.is_terminal());
        // Jumps over 25 %, then small steps, then straight to the end.
        for (std::uint64_t done : {0u, 100u, 300u, 310u, 320u, 500u, 740u, 760u, 1000u})
            EXPECT_TRUE(bar.update(report(done, 1000)));
        bar.update(report(1000, 1000));  // a repeated final report adds nothing
    }
    const std::vector<std::string> got = lines(contents(file));
    std::fclose(file);
    ASSERT_EQ(got.size(), 4u);
    EXPECT_EQ(got[0].rfind("shprt: bake: 30% (300 of 1.00 k rays, ", 0), 0u) << got[0];
    EXPECT_EQ(got[1].rfind("shprt: bake: 50% (500 of 1.00 k rays, ", 0), 0u) << got[1];
    EXPECT_EQ(got[2].rfind("shprt: bake: 76% (760 of 1.00 k rays, ", 0), 0u) << got[2];
    EXPECT_EQ(got[3].rfind("shprt: bake: 100% (1.00 k of 1.00 k rays, ", 0), 0u) << got[3];
    for (const std::string& line : got) {
        EXPECT_NE(line.find("rays/s, "), std::string::npos) << line;
        EXPECT_EQ(line.back(), ')') << line;
    }
}

// An error-bounded bake's reports end with the estimated error, and with the share of receivers
// the sample cap stopped above the target once there are any.
TEST(ProgressBarTest, ErrorBoundedReportsShowTheErrorAndTheShareOverTheTarget) {
    std::FILE* file = std::tmpfile();
    ASSERT_NE(file, nullptr);
    {
        ProgressBar bar("bake", file);
        ProgressInfo info = report(500, 1000);
        info.error_p99 = 0.023;
        info.over_target = 0;
        bar.update(info);
        info = report(1000, 1000);
        info.error_p99 = 0.042;
        info.over_target = 0.125;
        bar.update(info);
    }
    const std::vector<std::string> got = lines(contents(file));
    std::fclose(file);
    ASSERT_EQ(got.size(), 2u);
    EXPECT_NE(got[0].find(")  err 99%: 2.3 %"), std::string::npos) << got[0];
    EXPECT_EQ(got[0].find("over E"), std::string::npos) << got[0];
    EXPECT_NE(got[1].find(")  err 99%: 4.2 %, 12 % over E"), std::string::npos) << got[1];
}

// Each round of an error-bounded bake (BakeSession::bake_in_rounds) is a stage of its own: its
// own lines, the first under the label, the later ones after it, each with its error.
TEST(ProgressBarTest, ErrorBoundedRoundsEachHaveTheirLinesAndError) {
    std::FILE* file = std::tmpfile();
    ASSERT_NE(file, nullptr);
    {
        ProgressBar bar("bake", file);
        const double p99[] = {0.24, 0.078, 0.023};
        const double over[] = {1.0, 0.68, 0.0071};
        const char* stages[] = {"bake", "≤ 1024 samples", "≤ 4096 samples"};
        for (int r = 0; r < 3; ++r) {
            ProgressInfo info = report(0, 0);
            info.stage = stages[r];
            bar.update(info);  // the round's start: nothing done, nothing printed
            info = report(1000, 1000);
            info.stage = stages[r];
            info.error_p99 = p99[r];
            info.over_target = over[r];
            bar.update(info);
        }
    }
    const std::vector<std::string> got = lines(contents(file));
    std::fclose(file);
    ASSERT_EQ(got.size(), 3u);
    EXPECT_EQ(got[0].rfind("shprt: bake: 100% (", 0), 0u) << got[0];
    EXPECT_NE(got[0].find("err 99%: 24 %, 100 % over E"), std::string::npos) << got[0];
    EXPECT_EQ(got[1].rfind("shprt: bake: ≤ 1024 samples: 100% (", 0), 0u) << got[1];
    EXPECT_NE(got[1].find("err 99%: 7.8 %, 68 % over E"), std::string::npos) << got[1];
    EXPECT_EQ(got[2].rfind("shprt: bake: ≤ 4096 samples: 100% (", 0), 0u) << got[2];
    EXPECT_NE(got[2].find("err 99%: 2.3 %, 0.71 % over E"), std::string::npos) << got[2];
}

TEST(ProgressBarTest, WithoutALabelTheStageNamesTheWork) {
    std::FILE* file = std::tmpfile();
    ASSERT_NE(file, nullptr);
    {
        ProgressBar bar({}, file);
        bar.update(report(1, 1));
    }
    const std::string text = contents(file);
    std::fclose(file);
    EXPECT_EQ(text.rfind("shprt: tracing: 100% (1.00 of 1.00 rays, ", 0), 0u) << text;
}

// A second stage (the bounces after the rays) gets its own lines, percentages and rate, named
// after the label.
TEST(ProgressBarTest, EachStageHasItsOwnLines) {
    std::FILE* file = std::tmpfile();
    ASSERT_NE(file, nullptr);
    {
        ProgressBar bar("bake", file);
        bar.update(report(1000, 1000));
        for (std::uint64_t done : {10u, 20u, 30u})
            bar.update(ProgressInfo{"bounces", done, 30, "rows"});
    }
    const std::vector<std::string> got = lines(contents(file));
    std::fclose(file);
    ASSERT_EQ(got.size(), 4u);
    EXPECT_EQ(got[0].rfind("shprt: bake: 100% (1.00 k of 1.00 k rays, ", 0), 0u) << got[0];
    EXPECT_EQ(got[1].rfind("shprt: bake: bounces: 33% (10.0 of 30.0 rows, ", 0), 0u) << got[1];
    EXPECT_EQ(got[2].rfind("shprt: bake: bounces: 66% (20.0 of 30.0 rows, ", 0), 0u) << got[2];
    EXPECT_EQ(got[3].rfind("shprt: bake: bounces: 100% (30.0 of 30.0 rows, ", 0), 0u) << got[3];
}

// A pseudo-terminal `columns` wide: the bar writes to the slave side, the test reads the master.
class Pty {
public:
    explicit Pty(int columns) {
        winsize ws{};
        ws.ws_col = static_cast<unsigned short>(columns);
        ws.ws_row = 24;
        if (::openpty(&m_master, &m_slave, nullptr, nullptr, &ws) != 0) return;
        m_file = ::fdopen(m_slave, "w");
    }
    ~Pty() {
        if (m_file) std::fclose(m_file);  // closes m_slave
        if (m_master >= 0) ::close(m_master);
    }
    std::FILE* file() const { return m_file; }
    // What reached the terminal up to and including `needle` (the line discipline turns "\n"
    // into "\r\n"). The kernel hands pty output to the master side asynchronously, so this
    // waits for it (up to 5 s; what arrived by then is returned).
    std::string read_until(const std::string& needle) {
        std::fflush(m_file);
        std::string text;
        char buffer[4096];
        while (text.find(needle) == std::string::npos) {
            pollfd p{m_master, POLLIN, 0};
            if (::poll(&p, 1, 5000) <= 0) break;
            const ssize_t n = ::read(m_master, buffer, sizeof buffer);
            if (n <= 0) break;
            text.append(buffer, static_cast<std::size_t>(n));
        }
        return text;
    }

private:
    int m_master = -1, m_slave = -1;
    std::FILE* m_file = nullptr;
};

TEST(ProgressBarTest, OnATerminalOneLineIsRedrawnInPlaceAndFitsTheWidth) {
    constexpr int kColumns = 60;
    Pty pty(kColumns);
    if (!pty.file()) GTEST_SKIP() << "no pseudo-terminal here (openpty failed)";
    ProgressBar bar("bake", pty.file());
    EXPECT_TRUE(bar.is_terminal());
    bar.update(report(0, 1000));  // drawn: the first report is never throttled
    bar.update(report(1000, 1000));
    bar.finish();
    bar.finish();  // idempotent
    const std::string text = pty.read_until("\r\n");
    // Two redraws, each "\r" + line + clear-to-end-of-line, then the newline of finish().
    ASSERT_GE(text.size(), 2u);
    EXPECT_EQ(text.substr(text.size() - 2), "\r\n") << text;
    std::vector<std::string> draws;
    for (std::size_t pos = 0; (pos = text.find('\r', pos)) != std::string::npos; ++pos) {
        const std::size_t end = text.find("\x1b[K", pos);
        if (end == std::string::npos) break;
        draws.push_back(text.substr(pos + 1, end - pos - 1));
    }
    ASSERT_EQ(draws.size(), 2u) << ::testing::PrintToString(text);
    const std::string& first = draws[0];
    const std::string& last = draws[1];
    EXPECT_EQ(first.rfind("bake [", 0), 0u) << first;
    EXPECT_NE(first.find("]   0%"), std::string::npos) << first;
    EXPECT_EQ(first.find('#'), std::string::npos) << "nothing done yet: " << first;
    EXPECT_NE(last.find("] 100%"), std::string::npos) << last;
    const std::size_t open = last.find('['), close = last.find(']');
    ASSERT_LT(open, close) << last;
    const std::string cells = last.substr(open + 1, close - open - 1);
    EXPECT_GE(cells.size(), 5u) << last;
    EXPECT_EQ(cells, std::string(cells.size(), '#')) << "all filled at 100 %: " << last;
    for (const std::string& draw : draws) EXPECT_LT(int(draw.size()), kColumns) << draw;
}

TEST(ProgressBarTest, ShowsRateAndEtaWhileRunning) {
    Pty pty(100);
    if (!pty.file()) GTEST_SKIP() << "no pseudo-terminal here (openpty failed)";
    ProgressBar bar("bake", pty.file());
    ::usleep(20000);  // some elapsed time, so that a rate exists
    bar.update(report(400, 1000));
    const std::string text = pty.read_until("\x1b[K");
    EXPECT_NE(text.find(" 40%"), std::string::npos) << text;
    EXPECT_NE(text.find("rays/s"), std::string::npos) << text;
    EXPECT_NE(text.find("ETA "), std::string::npos) << text;
}

// Work that follows a stage outside its total (an interreflected bake's bounces while it traces)
// is named after the ETA instead of being guessed into it; a stage without it shows its ETA alone.
TEST(ProgressBarTest, NamesTheWorkThatFollowsAfterTheEta) {
    Pty pty(100);
    if (!pty.file()) GTEST_SKIP() << "no pseudo-terminal here (openpty failed)";
    ProgressBar bar("bake", pty.file());
    ::usleep(20000);  // some elapsed time, so that a rate exists
    ProgressInfo tracing = report(400, 1000);
    tracing.then = "3 bounces";
    bar.update(tracing);
    std::string text = pty.read_until("\x1b[K");
    EXPECT_NE(text.find(" 40%"), std::string::npos) << text;
    const std::size_t eta = text.find("ETA ");
    ASSERT_NE(eta, std::string::npos) << text;
    EXPECT_NE(text.find(" + 3 bounces\x1b[K", eta), std::string::npos) << text;
    // The bounces' stage: its ETA is the rest of the bake, nothing named after it.
    ::usleep(120000);  // past the bar's 100 ms between redraws
    bar.update(ProgressInfo{"bounces", 10, 30, "rows"});
    text = pty.read_until("\x1b[K");
    const std::size_t bounces = text.find("bake: bounces [");
    ASSERT_NE(bounces, std::string::npos) << text;
    EXPECT_NE(text.find("ETA ", bounces), std::string::npos) << text;
    EXPECT_EQ(text.find(" + ", bounces), std::string::npos) << text;
}

TEST(ProgressBarTest, FirstCtrlCBecomesACancelRequest) {
    // In a child process: the flag it sets lasts for the rest of the process.
    EXPECT_EXIT(
        {
            install_interrupt_handler();
            ProgressBar bar("bake", nullptr);
            if (!bar.update(report(1, 10)) || interrupted()) std::_Exit(2);
            std::raise(SIGINT);
            std::_Exit(interrupted() && !bar.update(report(2, 10)) ? 0 : 3);
        },
        ::testing::ExitedWithCode(0), "");
}

}  // namespace
}  // namespace shprt::tools
