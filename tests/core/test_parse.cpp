// The one parser of comma-separated numbers (core/parse.hpp): good lists, the wrong count,
// non-numbers and non-finite values, each a one-line Error(invalid_argument) naming the text.
#include "shprt/core/error.hpp"
#include "shprt/core/math.hpp"
#include "shprt/core/parse.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

namespace shprt {
namespace {

// Expects parse_numbers(text, count, "--opt") to throw Error(invalid_argument) with a one-line
// message containing every needle.
void expect_error(const std::string& text, std::size_t count,
                  std::initializer_list<std::string> needles) {
    try {
        const std::vector<double> v = parse_numbers(text, count, "--opt");
        ADD_FAILURE() << "no error for '" << text << "' (" << v.size() << " numbers)";
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_EQ(e.code(), ErrorCode::invalid_argument) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << "one line: " << what;
        EXPECT_EQ(what.rfind("--opt ", 0), 0u) << "names the option first: " << what;
        EXPECT_NE(what.find("'" + text + "'"), std::string::npos) << "quotes the text: " << what;
        for (const std::string& n : needles)
            EXPECT_NE(what.find(n), std::string::npos) << "'" << n << "' not in: " << what;
    }
}

TEST(ParseNumbers, GoodListsGiveTheNumbersInOrder) {
    EXPECT_EQ(parse_numbers("1,2.5,-3", 3, "x"), (std::vector<double>{1, 2.5, -3}));
    EXPECT_EQ(parse_numbers("+4, 5e-1 ,\t-0.25e2", 3, "x"), (std::vector<double>{4, 0.5, -25}));
    EXPECT_EQ(parse_numbers("7", 1, "x"), (std::vector<double>{7}));
    EXPECT_EQ(parse_numbers("0,1,2,3,4,5", 6, "x").back(), 5.0);
    // Round-trip precision: the nearest double, as the compiler reads the literal.
    EXPECT_EQ(parse_numbers("3.14159265358979323846", 1, "x")[0], kPi);
    EXPECT_EQ(parse_numbers("0.1", 1, "x")[0], 0.1);
    // Any count: what the list holds.
    EXPECT_EQ(parse_numbers("1,2,3,4", "x").size(), 4u);
    EXPECT_EQ(parse_numbers("9", "x"), (std::vector<double>{9}));
}

TEST(ParseNumbers, TheWrongCountSaysHowManyWereExpected) {
    expect_error("1,2", 3, {"expects three comma-separated numbers, got '1,2'"});
    expect_error("1,2,3,4", 3, {"expects three comma-separated numbers"});
    expect_error("1,2,3", 6, {"six"});
    expect_error("1", 12, {"expects 12 comma-separated numbers"});
}

TEST(ParseNumbers, ANonNumberIsNamed) {
    expect_error("1,x,3", 3, {"finite numbers, got '1,x,3'", "('x' is not a number)"});
    expect_error("1,,3", 3, {"('' is not a number)"});
    expect_error("1,2,", 3, {"('' is not a number)"});
    expect_error("", 3, {"('' is not a number)"});
    expect_error("1,2 3,4", 3, {"'2 3' is not a number"});
    expect_error("1,2,3abc", 3, {"'3abc' is not a number"});
    expect_error("1,+,3", 3, {"'+' is not a number"});
    expect_error("1,++2,3", 3, {"'++2' is not a number"});
    expect_error("1,0x10,3", 3, {"'0x10' is not a number"});
    EXPECT_THROW(parse_numbers("a", "x"), Error);
    EXPECT_THROW(parse_numbers("1,2", 0, "x"), Error) << "count 0 is not a count";
}

TEST(ParseNumbers, OneNumber) {
    double v = 0;
    EXPECT_TRUE(parse_number(" -2.5e3\t", v));
    EXPECT_EQ(v, -2500.0);
    EXPECT_TRUE(parse_number("+7", v));
    EXPECT_EQ(v, 7.0);
    for (const char* bad : {"", " ", "+", "-", "1,2", "1 2", "abc", "0x1p3", "inf", "nan", "1e999"})
        EXPECT_FALSE(parse_number(bad, v)) << "'" << bad << "'";
}

TEST(ParseNumbers, InfinityAndNanAreRefused) {
    expect_error("1,inf,3", 3, {"'inf' is not a number"});
    expect_error("-INF,1,3", 3, {"'-INF' is not a number"});
    expect_error("1,2,nan", 3, {"'nan' is not a number"});
    expect_error("1,1e999,3", 3, {"'1e999' is not a number"});
    EXPECT_EQ(parse_numbers("1e308", 1, "x")[0], 1e308);
}

// Integers, the way every integer option is read: plain decimal, signed, range-checked (CLI11's
// own conversion saturated 99999999999999999999, wrapped -1 into 2^64 - 1 and read 010 as 8).
TEST(ParseInteger, PlainDecimalOnlyWithRangeAndSign) {
    std::int64_t s = 0;
    EXPECT_EQ(parse_integer("42", s), IntegerParse::ok);
    EXPECT_EQ(s, 42);
    EXPECT_EQ(parse_integer(" -7\t", s), IntegerParse::ok);
    EXPECT_EQ(s, -7);
    EXPECT_EQ(parse_integer("+010", s), IntegerParse::ok);
    EXPECT_EQ(s, 10) << "decimal, not octal";
    EXPECT_EQ(parse_integer("9223372036854775807", s), IntegerParse::ok);
    EXPECT_EQ(s, INT64_MAX);
    EXPECT_EQ(parse_integer("-9223372036854775808", s), IntegerParse::ok);
    EXPECT_EQ(s, INT64_MIN);
    EXPECT_EQ(parse_integer("9223372036854775808", s), IntegerParse::out_of_range);
    EXPECT_EQ(parse_integer("99999999999999999999", s), IntegerParse::out_of_range);
    EXPECT_EQ(parse_integer("-99999999999999999999", s), IntegerParse::out_of_range);
    for (const char* bad : {"", " ", "+", "-", "--3", "+-3", "1.5", "1e3", "0x10", "abc", "3abc",
                            "1 2", "inf", "nan"})
        EXPECT_EQ(parse_integer(bad, s), IntegerParse::not_integer) << "'" << bad << "'";

    std::uint64_t u = 0;
    EXPECT_EQ(parse_integer("18446744073709551615", u), IntegerParse::ok);
    EXPECT_EQ(u, UINT64_MAX);
    EXPECT_EQ(parse_integer("18446744073709551616", u), IntegerParse::out_of_range);
    EXPECT_EQ(parse_integer("-1", u), IntegerParse::negative);
    EXPECT_EQ(parse_integer("-99999999999999999999", u), IntegerParse::out_of_range);
    EXPECT_EQ(parse_integer("-0", u), IntegerParse::ok);
    EXPECT_EQ(u, 0u);
    EXPECT_EQ(parse_integer("-x", u), IntegerParse::not_integer);
    EXPECT_EQ(parse_integer("+5", u), IntegerParse::ok);
    EXPECT_EQ(u, 5u);
    // Both parsers take one sign at most.
    double d = 0;
    EXPECT_FALSE(parse_number("+-3", d));
    EXPECT_TRUE(parse_number("+3", d));
}

}  // namespace
}  // namespace shprt

namespace shprt {
namespace {

TEST(ParseByteSize, ReadsBinaryUnitsAndRefusesTheRest) {
    std::uint64_t b = 0;
    EXPECT_TRUE(parse_byte_size("4096", b));
    EXPECT_EQ(b, 4096u);
    EXPECT_TRUE(parse_byte_size("512M", b));
    EXPECT_EQ(b, 512ull << 20);
    EXPECT_TRUE(parse_byte_size("1.5 GiB", b));
    EXPECT_EQ(b, 3ull << 29);
    EXPECT_TRUE(parse_byte_size("2kb", b));
    EXPECT_EQ(b, 2048u);
    EXPECT_TRUE(parse_byte_size("1T", b));
    EXPECT_EQ(b, 1ull << 40);
    EXPECT_TRUE(parse_byte_size("7B", b));
    EXPECT_EQ(b, 7u);
    for (const char* bad : {"", "M", "-1M", "1X", "1 MBB", "lots", "nan", "inf", "1e30T", "0x10"})
        EXPECT_FALSE(parse_byte_size(bad, b)) << bad;
}

}  // namespace
}  // namespace shprt
