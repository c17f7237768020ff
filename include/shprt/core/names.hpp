// The spelled names of an enum, as one table per enum, and the two functions every enum's
// to_string and parse_* are made of: the name of a value, and the value of a name (with the one
// error line every parser gives: "unknown WHAT 'TEXT' (expected a, b or c)", followed by
// "; did you mean 'b'?" when TEXT looks like a misspelt name).
//
//   constexpr Named<Device> kDeviceNames[] = {{Device::cpu, "cpu"}, {Device::cuda, "cuda"}};
//   const char* to_string(Device d) { return name_of(kDeviceNames, d); }
//   Device parse_device(const std::string& s) { return parse_named(kDeviceNames, s, "device"); }
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace shprt {

template <class E>
struct Named {
    E value;
    const char* name;
};

// Throws Error(invalid_argument) "unknown WHAT 'TEXT' (expected A, B or C)", and
// "; did you mean 'B'?" after it when closest_name finds one.
[[noreturn]] void fail_unknown_name(std::string_view what, std::string_view text,
                                    const std::vector<std::string_view>& names);

// The name of `names` that `text` most likely misspells, or "" when none is close. Close: at most
// max(1, n / 3) edits apart, n being TEXT's length without leading dashes (an edit inserts,
// deletes or replaces a character or swaps two neighbours; case is ignored), and n at least 3
// or the names equal but for case. The first of equally close names wins. The suggestion of
// every "did you mean" (subcommands, options, enum names).
std::string_view closest_name(std::string_view text, const std::vector<std::string_view>& names);

// "unknown WHAT 'TEXT'", and "; did you mean 'NAME'?" when closest_name finds NAME.
std::string unknown_name_message(std::string_view what, std::string_view text,
                                 const std::vector<std::string_view>& names);

// The name of `value` in `table` ("?" for a value the table lacks).
template <class E, std::size_t N>
constexpr const char* name_of(const Named<E> (&table)[N], E value) {
    for (const Named<E>& entry : table)
        if (entry.value == value) return entry.name;
    return "?";
}

// The value named `text` in `table`; fail_unknown_name(what, ...) when none is.
template <class E, std::size_t N>
E parse_named(const Named<E> (&table)[N], std::string_view text, std::string_view what) {
    for (const Named<E>& entry : table)
        if (text == entry.name) return entry.value;
    std::vector<std::string_view> names;
    for (const Named<E>& entry : table) names.emplace_back(entry.name);
    fail_unknown_name(what, text, names);
}

}  // namespace shprt
