// Option tables: one row per option that a front end offers — the command line's `--name-text`,
// Python's `name_text=` — with its type, default, limits and help, and the field of the library's
// "choice" struct it sets. The command line registers its options by walking a table
// (tools/common/option_table.hpp), Python takes its keywords' defaults from the same struct, and
// both hand the struct to one library function that checks it (bake/bake_option_table.hpp,
// shade/shading_option_table.hpp). So a default or a limit exists once, and an error names the
// option as the front end that was given it spells it: `--samples 0: must be 1 to 16777216`,
// `samples=0: must be 1 to 16777216`.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace shprt {

// How a front end spells an option in its messages: `--sun-samples 9` or `sun_samples=9`.
enum class Spelling { command_line, python };
// The option `name` (snake_case) with `value` as `spelling` writes it; an empty value gives the
// option alone (`--direct`, `direct=`).
std::string option_text(Spelling spelling, std::string_view name, std::string_view value = {});

// A value's inclusive limits; NaN: none on that side (or one that depends on other options, as
// `--bounce-coeffs`'s K, checked where it is known).
struct OptionLimits {
    double min = std::numeric_limits<double>::quiet_NaN();
    double max = std::numeric_limits<double>::quiet_NaN();
    bool exclusive = false;  // both ends excluded: (min, max)
};

// The row's fields that do not depend on the struct it sets.
struct OptionInfo {
    std::string name;    // snake_case; `--name` with '-' for '_' on the command line
    std::string python;  // Python's keyword where it differs from `name` (complete_rows fills it)
    bool cli_only = false;  // Python has no such keyword
    bool hidden = false;    // left out of the command line's help (the tests' own options)
    std::string help;
    OptionLimits limits;
    // What an out-of-range value is told after "must be " ("1 to 16777216"); empty: made from the
    // limits. Also the help's "[limits: ...]" (the test python/tests/test_option_table.py reads
    // it there).
    std::string limits_text;
    std::string default_text;  // the default as text ("1024", "sobol"); empty: unset (None)

    // The option as `spelling` writes it, with `value` (option_text).
    std::string spelled(Spelling spelling, std::string_view value = {}) const;
    // The option alone: "--max-samples" or "max_samples".
    std::string label(Spelling spelling) const;
};

// The field of `Struct` a row sets; each alternative is a type the command line can parse into.
template <class Struct>
using OptionField =
    std::variant<bool Struct::*, int Struct::*, long long Struct::*, std::uint64_t Struct::*,
                 double Struct::*, std::string Struct::*, std::optional<int> Struct::*,
                 std::optional<long long> Struct::*, std::optional<double> Struct::*,
                 std::vector<std::string> Struct::*>;

template <class Struct>
struct OptionRow : OptionInfo {
    OptionField<Struct> field;
};

// Appends a row to `table` and returns it (for what is rarely set: cli_only).
template <class Struct, class Field>
OptionRow<Struct>& add_row(std::vector<OptionRow<Struct>>& table, std::string name,
                           Field Struct::*field, std::string help, OptionLimits limits = {},
                           std::string limits_text = {}) {
    OptionRow<Struct>& row = table.emplace_back();
    row.name = std::move(name);
    row.field = field;
    row.help = std::move(help);
    row.limits = limits;
    row.limits_text = std::move(limits_text);
    return row;
}

// "1 to 16777216", "between 0 and 1" or "≥ 0"; empty for no limits.
std::string limits_description(const OptionLimits& limits);

// The default of a field as the help and Python's signature show it ("1024", "1e-04" as "0.0001",
// "sobol"); empty for an unset optional, an empty text, or a flag that is off.
std::string default_text(bool value);
std::string default_text(long long value);
std::string default_text(std::uint64_t value);
std::string default_text(double value);
std::string default_text(const std::string& value);
inline std::string default_text(int value) { return default_text(static_cast<long long>(value)); }
// A repeatable option's (`--light`): empty, so that the help shows what the command line's own
// conversion shows for the list (tools/common/number_options.hpp, show_defaults).
inline std::string default_text(const std::vector<std::string>&) { return {}; }
template <class T>
std::string default_text(const std::optional<T>& value) {
    return value ? default_text(*value) : std::string();
}

// Completes rows whose default_text, limits_text and python are empty (python: the name), from a
// default-constructed `Struct` and from their limits.
// GCC 12 instantiates the visit for every member-pointer type of the variant and, for a struct
// smaller than a double (a few flags), warns that reading one would be out of its bounds
// (-Warray-bounds) — in alternatives the row never holds. A false positive, silenced here only.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Warray-bounds"
#endif
template <class Struct>
std::vector<OptionRow<Struct>> complete_rows(std::vector<OptionRow<Struct>> rows) {
    const Struct defaults{};
    for (OptionRow<Struct>& row : rows) {
        if (row.default_text.empty())
            row.default_text =
                std::visit([&](auto member) { return default_text(defaults.*member); }, row.field);
        if (row.limits_text.empty()) row.limits_text = limits_description(row.limits);
        if (row.python.empty()) row.python = row.name;
    }
    return rows;
}
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

// The row called `name`; Error(invalid_argument) when the table has none (a programming error).
const OptionInfo& find_option(const std::vector<const OptionInfo*>& table, std::string_view name);
template <class Struct>
const OptionRow<Struct>& find_row(const std::vector<OptionRow<Struct>>& table,
                                  std::string_view name) {
    std::vector<const OptionInfo*> infos;
    for (const OptionRow<Struct>& row : table) infos.push_back(&row);
    return static_cast<const OptionRow<Struct>&>(find_option(infos, name));
}

// One-line Error(invalid_argument) "OPTION VALUE: must be LIMITS" unless `value` is within the
// row's limits; `extra` follows the limits (" (K = bands², at most 1024)").
void check_limits(const OptionInfo& row, double value, Spelling spelling,
                  std::string_view extra = {});
void check_limits(const OptionInfo& row, long long value, Spelling spelling,
                  std::string_view extra = {});

}  // namespace shprt
