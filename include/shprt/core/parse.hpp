// Parsing of the small numeric lists that options and specs take ("YAW,PITCH,ROLL",
// "EX,EY,EZ,TX,TY,TZ", "sun:X,Y,Z,…"): one parser, so that every option accepts the same numbers
// and reports a bad one the same way, in one line.
#pragma once

#include <cstddef>
#include <string_view>
#include <vector>

namespace shprt {

// Parses one number: a decimal or scientific number (std::from_chars, locale-independent),
// optionally signed ('+' or '-') and surrounded by spaces or tabs. Returns false, leaving `value`
// unspecified, for anything else: empty text, trailing characters, "inf", "nan", hexadecimal, or
// a value out of double's range (1e999).
bool parse_number(std::string_view text, double& value);

// Parses `text` as comma-separated finite numbers, exactly `count` of them (count ≥ 1), each as
// parse_number reads it (an empty item is no number). Throws Error(invalid_argument) with a
// one-line message that names `what` and quotes `text`, e.g.
//   "camera EX,EY,EZ,TX,TY,TZ expects six comma-separated numbers, got '1,2,3'"
//   "--dir expects three comma-separated finite numbers, got '1,x,3' ('x' is not a number)"
std::vector<double> parse_numbers(std::string_view text, std::size_t count, std::string_view what);

// The same for any count ≥ 1 (the caller checks the count it needs), e.g. light specs that take
// 3, 4 or 7 numbers.
std::vector<double> parse_numbers(std::string_view text, std::string_view what);

}  // namespace shprt
