// Parsing of the small numeric lists that options and specs take ("YAW,PITCH,ROLL",
// "EX,EY,EZ,TX,TY,TZ", "sun:X,Y,Z,…"): one parser, so that every option accepts the same numbers
// and reports a bad one the same way, in one line.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

namespace shprt {

// Parses one number: a decimal or scientific number (std::from_chars, locale-independent),
// optionally signed ('+' or '-') and surrounded by spaces or tabs. Returns false, leaving `value`
// unspecified, for anything else: empty text, trailing characters, "inf", "nan", hexadecimal, or
// a value out of double's range (1e999).
bool parse_number(std::string_view text, double& value);

// How parse_integer read a text.
enum class IntegerParse {
    ok,            // `value` holds the number
    not_integer,   // not a plain decimal integer: empty, "1.5", "1e3", "0x10", "abc", "--3"
    out_of_range,  // a decimal integer outside the type's range (99999999999999999999)
    negative,      // for the unsigned overload: a negative decimal integer ("-1")
};

// Parses one integer the way every integer option is read: decimal digits with an optional sign
// ('+' or '-'), surrounded by spaces or tabs allowed; no hexadecimal or octal prefixes (CLI11's
// own conversion reads "010" as 8 and wraps "-1" into 2^64 - 1 for unsigned types).
IntegerParse parse_integer(std::string_view text, std::int64_t& value);
IntegerParse parse_integer(std::string_view text, std::uint64_t& value);

// Parses `text` as comma-separated finite numbers, exactly `count` of them (count ≥ 1), each as
// parse_number reads it (an empty item is no number). Throws Error(invalid_argument) with a
// one-line message that names `what` and quotes `text`, e.g.
//   "camera EX,EY,EZ,TX,TY,TZ expects six comma-separated numbers, got '1,2,3'"
//   "--dir expects three comma-separated finite numbers, got '1,x,3' ('x' is not a number)"
std::vector<double> parse_numbers(std::string_view text, std::size_t count, std::string_view what);

// The same for any count ≥ 1 (the caller checks the count it needs), e.g. light specs that take
// 3, 4 or 7 numbers.
std::vector<double> parse_numbers(std::string_view text, std::string_view what);

// Parses a size in bytes: a number as parse_number reads it, ≥ 0, then optionally a unit — "K",
// "M", "G", "T" (binary: 1024, 1024², …; "KiB", "MB", "GiB" and lower case are the same) or "B".
// "512M", "1.5 GiB", "4096". Returns false for anything else and for sizes ≥ 2^63.
bool parse_byte_size(std::string_view text, std::uint64_t& bytes);

}  // namespace shprt
