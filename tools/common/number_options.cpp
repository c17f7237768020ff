// Numeric option checks through the one number parser (number_options.hpp).
#include "common/number_options.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/parse.hpp"

#include <cstdint>
#include <string>

namespace shprt::tools {
namespace {

enum class Kind { signed_integer, unsigned_integer, real };

[[noreturn]] void refuse(const std::string& name, const std::string& text, const char* problem,
                         bool quote) {
    fail(ErrorCode::invalid_argument, "{} {}: {}", name, quote ? "'" + text + "'" : text, problem);
}

// Throws (rather than returning a message for CLI11 to wrap) so that the error reads like every
// other bad value: "--name TEXT: problem", Error(invalid_argument). An integer's text is
// rewritten in plain decimal ("+010" becomes "10"), so CLI11's conversion, which would read a
// leading 0 as octal, sees nothing else.
void check_text(const std::string& name, Kind kind, std::string& text) {
    if (kind == Kind::real) {
        double value = 0;
        if (!parse_number(text, value)) refuse(name, text, "not a finite number", true);
        return;
    }
    IntegerParse result = IntegerParse::ok;
    std::string canonical;
    if (kind == Kind::signed_integer) {
        std::int64_t value = 0;
        result = parse_integer(text, value);
        canonical = std::to_string(value);
    } else {
        std::uint64_t value = 0;
        result = parse_integer(text, value);
        canonical = std::to_string(value);
    }
    switch (result) {
        case IntegerParse::ok:
            text = canonical;
            return;
        case IntegerParse::not_integer:
            refuse(name, text, "not an integer", true);
        case IntegerParse::out_of_range:
            refuse(name, text, "out of range", false);
        case IntegerParse::negative:
            refuse(name, text, "must not be negative", false);
    }
}

}  // namespace

void check_numeric_options(CLI::App& app) {
    for (CLI::Option* option : app.get_options()) {
        if (option->get_expected_max() == 0) continue;  // a flag
        // The type before any validator's description (`INT:[1 to 16]`: option_table.hpp).
        const std::string full = option->get_type_name();
        const std::string type = full.substr(0, full.find(':'));
        Kind kind;
        if (type == "INT")
            kind = Kind::signed_integer;
        else if (type == "UINT")
            kind = Kind::unsigned_integer;
        else if (type == "FLOAT")
            kind = Kind::real;
        else
            continue;
        const std::string name = option->get_name();
        option->transform(CLI::Validator(
            [name, kind](std::string& text) {
                check_text(name, kind, text);
                return std::string();
            },
            std::string()));
    }
    for (CLI::App* sub : app.get_subcommands({})) check_numeric_options(*sub);
}

void show_defaults(CLI::App& app) {
    for (CLI::Option* option : app.get_options())
        if (option->get_type_size() != 0 && option->get_default_str().empty())
            option->capture_default_str();
    for (CLI::App* sub : app.get_subcommands({})) show_defaults(*sub);
}

}  // namespace shprt::tools
