// `shprt sh` run as a program (SHPRT_CLI_PATH): eval prints the library's basis values at the
// normalised direction (plain and JSON), rotate reads coefficients from stdin (whitespace
// tolerant) and prints the library's rotation, info names the conventions, and every bad argument
// gives exit status 1, nothing on stdout and exactly one line on stderr that names the problem.
#include "shprt/core/math.hpp"
#include "shprt/core/rotation3.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/rotation.hpp"

#include "cli/cli_test.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

namespace shprt {
namespace {

constexpr double kPrintTol = 1e-15;  // %.17g round-trips doubles; allow for last-bit noise
constexpr double kRoundTripTol = 1e-12;

using test_support::expect_one_line_error;
using test_support::RunResult;

class CliSh : public test_support::CliTest {};

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

TEST_F(CliSh, EvalPrintsBasisValuesAtNormalisedDirection) {
    const RunResult r = shprt("sh eval --bands 5 --dir 0.6,-1.0,1.6");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::vector<double> got = numbers(r.out);
    ASSERT_EQ(got.size(), 25u);
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 25);
    const double len = std::sqrt(0.36 + 1.0 + 2.56);
    std::vector<double> y(25);
    sh_eval(5, 0.6 / len, -1.0 / len, 1.6 / len, y.data());
    for (int i = 0; i < 25; ++i) EXPECT_NEAR(got[i], y[i], kPrintTol) << i;
    // Known value: y_0 = 1/(2√π); at +X, y_{1,1} = −√(3/(4π)). Negative components parse.
    const RunResult x = shprt("sh eval --bands 2 --dir -2,0,0");
    ASSERT_EQ(x.exit_code, 0) << x.err;
    const std::vector<double> vx = numbers(x.out);
    ASSERT_EQ(vx.size(), 4u);
    EXPECT_NEAR(vx[0], 0.5 / std::sqrt(kPi), kPrintTol);
    EXPECT_NEAR(vx[3], std::sqrt(3.0 / (4.0 * kPi)), kPrintTol);  // at −X: +√(3/4π)
}

TEST_F(CliSh, EvalJson) {
    const RunResult r = shprt("sh eval --bands 3 --dir 0,0,1 --json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
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
        const RunResult r = shprt(
            fmt::format("sh rotate --bands {} --zyz {},{},{} --method {}", bands, a, b, g, method),
            {.input = lines(c)});
        ASSERT_EQ(r.exit_code, 0) << r.err;
        const std::vector<double> got = numbers(r.out);
        ASSERT_EQ(got.size(), static_cast<std::size_t>(K));
        std::vector<double> want(K);
        ShRotation::from_zyz(a, b, g, bands, parse_rotation_method(method))
            .apply(c.data(), want.data(), K);
        for (int i = 0; i < K; ++i) EXPECT_NEAR(got[i], want[i], kPrintTol * 10) << method << i;
        // R⁻¹ = Rz(−a)·Ry(−b)·Rz(−g): angles −g, −b, −a bring the coefficients back.
        const RunResult back = shprt(fmt::format("sh rotate --bands {} --zyz={},{},{} --method {}",
                                                 bands, -g, -b, -a, method),
                                     {.input = r.out});
        ASSERT_EQ(back.exit_code, 0) << back.err;
        const std::vector<double> orig = numbers(back.out);
        ASSERT_EQ(orig.size(), static_cast<std::size_t>(K));
        for (int i = 0; i < K; ++i) EXPECT_NEAR(orig[i], c[i], kRoundTripTol) << method << i;
    }
}

TEST_F(CliSh, RotateConventionMovesALobeFromZToRz) {
    // f = y_{1,0} ∝ z; R = Ry(π/2) takes +Z to +X, so g ∝ x = −y_{1,1} (Condon–Shortley).
    const RunResult r =
        shprt("sh rotate --bands 2 --zyz 0,1.5707963267948966,0", {.input = "0\n0\n1\n0\n"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::vector<double> v = numbers(r.out);
    ASSERT_EQ(v.size(), 4u);
    EXPECT_NEAR(v[0], 0.0, kPrintTol);
    EXPECT_NEAR(v[1], 0.0, kPrintTol);
    EXPECT_NEAR(v[2], 0.0, kPrintTol);
    EXPECT_NEAR(v[3], -1.0, kPrintTol);
}

TEST_F(CliSh, RotateToleratesWhitespace) {
    const RunResult r =
        shprt("sh rotate --bands 2 --zyz 0,0,0", {.input = "  1\t2\r\n\n 3   4  \n\n"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(numbers(r.out), (std::vector<double>{1, 2, 3, 4}));
}

TEST_F(CliSh, InfoStatesTheConventions) {
    const RunResult r = shprt("sh info");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    for (const char* needle :
         {"Condon-Shortley", "i = l(l+1) + m", "theta from +Z, phi from +X toward +Y",
          "u = 0.5 + atan2(d.x, -d.z)/(2 pi)", "v = acos(d.y)/pi", "n^2 coefficients", "+Y up",
          "g(d) = f(R^-1 d)", "orthonormal"})
        EXPECT_NE(r.out.find(needle), std::string::npos) << needle;
}

TEST_F(CliSh, BadArgumentsGiveOneLineErrors) {
    expect_one_line_error(shprt("sh eval --bands 3 --dir 0,0,0"), "--dir 0,0,0 has no direction");
    expect_one_line_error(shprt("sh eval --bands 0 --dir 1,0,0"), "must be in [1, 64], got 0");
    expect_one_line_error(shprt("sh eval --bands 65 --dir 1,0,0"), "must be in [1, 64], got 65");
    expect_one_line_error(shprt("sh eval --bands abc --dir 1,0,0"), "integer, got 'abc'");
    expect_one_line_error(shprt("sh eval --dir 1,0,0"), "--bands N is required");
    expect_one_line_error(shprt("sh eval --bands 2 --dir 1,2"),
                          "three comma-separated numbers, got '1,2'");
    expect_one_line_error(shprt("sh eval --bands 2 --dir 1,2,3,4"),
                          "three comma-separated numbers, got '1,2,3,4'");
    expect_one_line_error(shprt("sh eval --bands 2 --dir 1,x,3"), "finite numbers, got '1,x,3'");
    expect_one_line_error(shprt("sh eval --bands 2 --dir 1,nan,3"),
                          "finite numbers, got '1,nan,3'");
    const std::string rotate = "sh rotate --bands 2 --zyz 0,0,0";
    expect_one_line_error(shprt(rotate, {.input = "1 2 3"}),
                          "expected 4 coefficients (2 bands) on stdin, got 3");
    expect_one_line_error(shprt(rotate, {.input = "1 2 3 4 5"}),
                          "expected 4 coefficients (2 bands) on stdin, got more");
    expect_one_line_error(shprt(rotate, {.input = "1 2 three 4"}),
                          "'three' is not a finite number");
    expect_one_line_error(shprt(rotate, {.input = "1 2 inf 4"}), "'inf' is not a finite number");
    expect_one_line_error(shprt(rotate, {.input = ""}),
                          "expected 4 coefficients (2 bands) on stdin, got 0");
    expect_one_line_error(shprt("sh rotate --bands 2 --zyz 0,0", {.input = "1 2 3 4"}),
                          "--zyz expects three comma-separated numbers, got '0,0'");
    expect_one_line_error(shprt("sh rotate --bands 2", {.input = "1 2 3 4"}),
                          "--zyz X,Y,Z is required");
    expect_one_line_error(shprt(rotate + " --method euler", {.input = "1 2 3 4"}),
                          "unknown SH rotation method 'euler'");
    expect_one_line_error(shprt("sh rotate --bands 100 --zyz 0,0,0", {.input = "1"}),
                          "must be in [1, 64], got 100");
}

}  // namespace
}  // namespace shprt
