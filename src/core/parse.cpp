// Comma-separated number lists (parse.hpp).
#include "shprt/core/parse.hpp"

#include "shprt/core/error.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <string>
#include <system_error>
#include <type_traits>

namespace shprt {
namespace {

// "six" reads better than "6" in a message; larger counts stay digits.
std::string count_words(std::size_t count) {
    static constexpr const char* kWords[] = {"zero", "one", "two",   "three", "four",
                                             "five", "six", "seven", "eight", "nine"};
    return count < std::size(kWords) ? kWords[count] : std::to_string(count);
}

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
    return s;
}

}  // namespace

bool parse_number(std::string_view item, double& value) {
    item = trim(item);
    // from_chars takes a leading '-' but not a '+'; a lone sign or two signs are no number.
    if (!item.empty() && item.front() == '+') {
        item.remove_prefix(1);
        if (!item.empty() && item.front() == '-') return false;
    }
    if (item.empty() || item.front() == '+') return false;
    const char* last = item.data() + item.size();
    const auto [ptr, ec] = std::from_chars(item.data(), last, value);
    return ec == std::errc() && ptr == last && std::isfinite(value);
}

namespace {

template <class Int>
IntegerParse parse_integer_as(std::string_view item, Int& value) {
    item = trim(item);
    // As parse_number: one optional sign, '+' or '-'.
    if (!item.empty() && item.front() == '+') {
        item.remove_prefix(1);
        if (!item.empty() && item.front() == '-') return IntegerParse::not_integer;
    }
    if (item.empty() || item.front() == '+') return IntegerParse::not_integer;
    if constexpr (std::is_unsigned_v<Int>) {
        // from_chars refuses a sign for unsigned types; a negative integer gets its own answer.
        if (item.front() == '-') {
            std::int64_t as_signed = 0;
            const IntegerParse r = parse_integer_as(item, as_signed);
            if (r != IntegerParse::ok) return r;
            if (as_signed != 0) return IntegerParse::negative;
            value = 0;
            return IntegerParse::ok;
        }
    }
    const char* last = item.data() + item.size();
    const auto [ptr, ec] = std::from_chars(item.data(), last, value, 10);
    if (ptr != last || (ec != std::errc() && ec != std::errc::result_out_of_range))
        return IntegerParse::not_integer;
    return ec == std::errc::result_out_of_range ? IntegerParse::out_of_range : IntegerParse::ok;
}

}  // namespace

IntegerParse parse_integer(std::string_view text, std::int64_t& value) {
    return parse_integer_as(text, value);
}

IntegerParse parse_integer(std::string_view text, std::uint64_t& value) {
    return parse_integer_as(text, value);
}

namespace {

std::vector<double> parse_list(std::string_view text, std::size_t count, std::string_view what) {
    // What was expected, for both messages: "three comma-separated" or just "comma-separated".
    const std::string expected =
        count ? count_words(count) + " comma-separated" : "comma-separated";
    std::vector<double> values;
    std::size_t start = 0;
    for (;;) {
        const std::size_t comma = text.find(',', start);
        const std::string_view item =
            text.substr(start, comma == std::string_view::npos ? comma : comma - start);
        double v = 0;
        SHPRT_CHECK(parse_number(item, v), invalid_argument,
                    "{} expects {} finite numbers, got '{}' ('{}' is not a number)", what, expected,
                    text, item);
        values.push_back(v);
        if (comma == std::string_view::npos) break;
        start = comma + 1;
    }
    SHPRT_CHECK(count == 0 || values.size() == count, invalid_argument,
                "{} expects {} numbers, got '{}'", what, expected, text);
    return values;
}

}  // namespace

std::vector<double> parse_numbers(std::string_view text, std::size_t count, std::string_view what) {
    SHPRT_CHECK(count >= 1, invalid_argument, "parse_numbers: count must be at least 1");
    return parse_list(text, count, what);
}

std::vector<double> parse_numbers(std::string_view text, std::string_view what) {
    return parse_list(text, 0, what);
}

bool parse_byte_size(std::string_view text, std::uint64_t& bytes) {
    std::size_t end = text.size();
    while (end > 0 && (text[end - 1] == ' ' || text[end - 1] == '\t')) --end;
    std::size_t unit = end;
    while (unit > 0 && std::isalpha(static_cast<unsigned char>(text[unit - 1]))) --unit;
    std::string suffix(text.substr(unit, end - unit));
    for (char& c : suffix) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    if (suffix.size() > 1 && suffix.back() == 'B') suffix.pop_back();   // "MB", "MIB"
    if (suffix.size() == 2 && suffix.back() == 'I') suffix.pop_back();  // "MI" (from "MiB")
    double scale = 1;
    if (suffix.empty() || suffix == "B") {
        scale = 1;
    } else if (suffix.size() == 1 &&
               std::string_view("KMGT").find(suffix[0]) != std::string_view::npos) {
        scale = std::ldexp(1.0, 10 * (1 + int(std::string_view("KMGT").find(suffix[0]))));
    } else {
        return false;
    }
    double value = 0;
    if (!parse_number(text.substr(0, unit), value) || value < 0) return false;
    const double b = std::ceil(value * scale);
    if (!(b < std::ldexp(1.0, 63))) return false;
    bytes = static_cast<std::uint64_t>(b);
    return true;
}

}  // namespace shprt
