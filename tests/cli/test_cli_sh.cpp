// `shprt sh` run as a program (SHPRT_CLI_PATH, through popen): eval prints the library's basis
// values at the normalised direction (plain and JSON), rotate reads coefficients from stdin
// (whitespace tolerant) and prints the library's rotation, info names the conventions, and every
// bad argument gives a non-zero exit status, nothing on stdout and exactly one line on stderr.
#include "shprt/core/rotation3.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/rotation.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

namespace shprt {
namespace {

namespace fs = std::filesystem;

constexpr double kPrintTol = 1e-15;  // %.17g round-trips doubles; allow for last-bit noise
constexpr double kRoundTripTol = 1e-12;

struct CliRun {
    int status = -1;
    std::string out, err;
};

class CliSh : public ::testing::Test {
protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() / fmt::format("shprt_cli_sh_{}", ::getpid());
        fs::create_directories(m_dir);
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(m_dir, ec);
    }

    // Runs `shprt ARGS` with `input` on stdin; stdout through popen, stderr into a file.
    CliRun run(const std::string& args, const std::string& input = "") {
        const fs::path in = m_dir / "stdin.txt", err = m_dir / "stderr.txt";
        std::ofstream(in, std::ios::binary) << input;
        const std::string command =
            fmt::format("'{}' {} < '{}' 2> '{}'", SHPRT_CLI_PATH, args, in.string(), err.string());
        CliRun r;
        FILE* pipe = ::popen(command.c_str(), "r");
        if (!pipe) return r;
        char buf[4096];
        std::size_t n;
        while ((n = std::fread(buf, 1, sizeof buf, pipe)) > 0) r.out.append(buf, n);
        const int raw = ::pclose(pipe);
        r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128;
        std::ifstream e(err, std::ios::binary);
        r.err.assign(std::istreambuf_iterator<char>(e), std::istreambuf_iterator<char>());
        return r;
    }

    fs::path m_dir;
};

std::vector<double> numbers(const std::string& text) {
    std::istringstream in(text);
    std::vector<double> v;
    std::string token;
    while (in >> token) v.push_back(std::strtod(token.c_str(), nullptr));
    return v;
}

std::string lines(const std::vector<double>& v, const char* sep = "\n") {
    std::string s;
    for (double x : v) s += fmt::format("{:.17g}{}", x, sep);
    return s;
}

void expect_one_line_error(const CliRun& r, const std::string& what) {
    EXPECT_NE(r.status, 0) << what;
    EXPECT_TRUE(r.out.empty()) << what << ": stdout was '" << r.out << "'";
    ASSERT_FALSE(r.err.empty()) << what;
    EXPECT_EQ(r.err.back(), '\n') << what;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << what << ": '" << r.err << "'";
}

TEST_F(CliSh, EvalPrintsBasisValuesAtNormalisedDirection) {
    const CliRun r = run("sh eval --bands 5 --dir 0.6,-1.0,1.6");
    ASSERT_EQ(r.status, 0) << r.err;
    const std::vector<double> got = numbers(r.out);
    ASSERT_EQ(got.size(), 25u);
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 25);
    const double len = std::sqrt(0.36 + 1.0 + 2.56);
    std::vector<double> y(25);
    sh_eval(5, 0.6 / len, -1.0 / len, 1.6 / len, y.data());
    for (int i = 0; i < 25; ++i) EXPECT_NEAR(got[i], y[i], kPrintTol) << i;
    // Known value: y_0 = 1/(2√π); at +X, y_{1,1} = −√(3/(4π)). Negative components parse.
    const CliRun x = run("sh eval --bands 2 --dir -2,0,0");
    ASSERT_EQ(x.status, 0) << x.err;
    const std::vector<double> vx = numbers(x.out);
    ASSERT_EQ(vx.size(), 4u);
    EXPECT_NEAR(vx[0], 0.5 / std::sqrt(std::numbers::pi), kPrintTol);
    EXPECT_NEAR(vx[3], std::sqrt(3.0 / (4.0 * std::numbers::pi)), kPrintTol);  // at −X: +√(3/4π)
}

TEST_F(CliSh, EvalJson) {
    const CliRun r = run("sh eval --bands 3 --dir 0,0,1 --json");
    ASSERT_EQ(r.status, 0) << r.err;
    ASSERT_GE(r.out.size(), 2u);
    EXPECT_EQ(r.out.front(), '[');
    EXPECT_EQ(r.out.substr(r.out.size() - 2), "]\n");
    std::string inner = r.out.substr(1, r.out.size() - 3);
    std::replace(inner.begin(), inner.end(), ',', ' ');
    const std::vector<double> v = numbers(inner);
    ASSERT_EQ(v.size(), 9u);
    std::vector<double> y(9);
    sh_eval(3, 0.0, 0.0, 1.0, y.data());
    for (int i = 0; i < 9; ++i) EXPECT_NEAR(v[i], y[i], kPrintTol) << i;
}

TEST_F(CliSh, RotateMatchesLibraryForBothMethodsAndInverts) {
    const int bands = 6, K = 36;
    std::vector<double> c(K);
    for (int i = 0; i < K; ++i) c[i] = std::sin(0.7 * i + 0.2);
    const double a = 0.4, b = -1.1, g = 2.5;
    for (const char* method : {"ivanic", "paper"}) {
        const CliRun r = run(
            fmt::format("sh rotate --bands {} --zyz {},{},{} --method {}", bands, a, b, g, method),
            lines(c));
        ASSERT_EQ(r.status, 0) << r.err;
        const std::vector<double> got = numbers(r.out);
        ASSERT_EQ(got.size(), static_cast<std::size_t>(K));
        std::vector<double> want(K);
        ShRotation::from_zyz(a, b, g, bands, parse_rotation_method(method))
            .apply(c.data(), want.data(), K);
        for (int i = 0; i < K; ++i) EXPECT_NEAR(got[i], want[i], kPrintTol * 10) << method << i;
        // R⁻¹ = Rz(−a)·Ry(−b)·Rz(−g): angles −g, −b, −a bring the coefficients back.
        const CliRun back = run(fmt::format("sh rotate --bands {} --zyz={},{},{} --method {}",
                                            bands, -g, -b, -a, method),
                                r.out);
        ASSERT_EQ(back.status, 0) << back.err;
        const std::vector<double> orig = numbers(back.out);
        ASSERT_EQ(orig.size(), static_cast<std::size_t>(K));
        for (int i = 0; i < K; ++i) EXPECT_NEAR(orig[i], c[i], kRoundTripTol) << method << i;
    }
}

TEST_F(CliSh, RotateConventionMovesALobeFromZToRz) {
    // f = y_{1,0} ∝ z; R = Ry(π/2) takes +Z to +X, so g ∝ x = −y_{1,1} (Condon–Shortley).
    const CliRun r = run("sh rotate --bands 2 --zyz 0,1.5707963267948966,0", "0\n0\n1\n0\n");
    ASSERT_EQ(r.status, 0) << r.err;
    const std::vector<double> v = numbers(r.out);
    ASSERT_EQ(v.size(), 4u);
    EXPECT_NEAR(v[0], 0.0, kPrintTol);
    EXPECT_NEAR(v[1], 0.0, kPrintTol);
    EXPECT_NEAR(v[2], 0.0, kPrintTol);
    EXPECT_NEAR(v[3], -1.0, kPrintTol);
}

TEST_F(CliSh, RotateToleratesWhitespace) {
    const CliRun r = run("sh rotate --bands 2 --zyz 0,0,0", "  1\t2\r\n\n 3   4  \n\n");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(numbers(r.out), (std::vector<double>{1, 2, 3, 4}));
}

TEST_F(CliSh, InfoStatesTheConventions) {
    const CliRun r = run("sh info");
    ASSERT_EQ(r.status, 0) << r.err;
    for (const char* needle :
         {"Condon-Shortley", "i = l(l+1) + m", "theta from +Z, phi from +X toward +Y",
          "u = 0.5 + atan2(d.x, -d.z)/(2 pi)", "v = acos(d.y)/pi", "n^2 coefficients", "+Y up",
          "g(d) = f(R^-1 d)", "orthonormal"})
        EXPECT_NE(r.out.find(needle), std::string::npos) << needle;
}

TEST_F(CliSh, BadArgumentsGiveOneLineErrors) {
    expect_one_line_error(run("sh eval --bands 3 --dir 0,0,0"), "zero direction");
    expect_one_line_error(run("sh eval --bands 0 --dir 1,0,0"), "zero bands");
    expect_one_line_error(run("sh eval --bands 65 --dir 1,0,0"), "too many bands");
    expect_one_line_error(run("sh eval --bands abc --dir 1,0,0"), "non-numeric bands");
    expect_one_line_error(run("sh eval --dir 1,0,0"), "missing bands");
    expect_one_line_error(run("sh eval --bands 2 --dir 1,2"), "two components");
    expect_one_line_error(run("sh eval --bands 2 --dir 1,2,3,4"), "four components");
    expect_one_line_error(run("sh eval --bands 2 --dir 1,x,3"), "non-numeric direction");
    expect_one_line_error(run("sh eval --bands 2 --dir 1,nan,3"), "NaN direction");
    expect_one_line_error(run("sh rotate --bands 2 --zyz 0,0,0", "1 2 3"), "too few");
    expect_one_line_error(run("sh rotate --bands 2 --zyz 0,0,0", "1 2 3 4 5"), "too many");
    expect_one_line_error(run("sh rotate --bands 2 --zyz 0,0,0", "1 2 three 4"), "non-numeric");
    expect_one_line_error(run("sh rotate --bands 2 --zyz 0,0,0", "1 2 inf 4"), "infinite");
    expect_one_line_error(run("sh rotate --bands 2 --zyz 0,0,0", ""), "empty stdin");
    expect_one_line_error(run("sh rotate --bands 2 --zyz 0,0", "1 2 3 4"), "two angles");
    expect_one_line_error(run("sh rotate --bands 2", "1 2 3 4"), "missing angles");
    expect_one_line_error(run("sh rotate --bands 2 --zyz 0,0,0 --method euler", "1 2 3 4"),
                          "unknown method");
    expect_one_line_error(run("sh rotate --bands 100 --zyz 0,0,0", "1"), "too many bands");
}

}  // namespace
}  // namespace shprt
