// The enum name tables' error line and the "did you mean" of every unknown name (core/names.hpp).
#include "shprt/core/names.hpp"

#include "shprt/core/error.hpp"

#include <algorithm>
#include <cctype>
#include <string>

namespace shprt {
namespace {

std::string lower(std::string_view text) {
    std::string s(text);
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

// Edits between a and b, a swap of neighbours counting one (the optimal string alignment
// distance: Damerau 1964's four edits, each substring edited once).
std::size_t edit_distance(const std::string& a, const std::string& b) {
    std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
    for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
    for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i)
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
                d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
        }
    return d[a.size()][b.size()];
}

// "; did you mean 'NAME'?" or "" (closest_name).
std::string did_you_mean(std::string_view text, const std::vector<std::string_view>& names) {
    const std::string_view name = closest_name(text, names);
    return name.empty() ? std::string() : fmt::format("; did you mean '{}'?", name);
}

}  // namespace

std::string_view closest_name(std::string_view text, const std::vector<std::string_view>& names) {
    const std::size_t n = text.size() - std::min(text.find_first_not_of('-'), text.size());
    const std::size_t limit = n < 3 ? 0 : std::max<std::size_t>(1, n / 3);
    const std::string key = lower(text);
    std::string_view best;
    std::size_t best_distance = limit + 1;
    for (const std::string_view name : names) {
        const std::size_t distance = edit_distance(key, lower(name));
        if (distance < best_distance) {
            best = name;
            best_distance = distance;
        }
    }
    return best;
}

std::string unknown_name_message(std::string_view what, std::string_view text,
                                 const std::vector<std::string_view>& names) {
    return fmt::format("unknown {} '{}'{}", what, text, did_you_mean(text, names));
}

void fail_unknown_name(std::string_view what, std::string_view text,
                       const std::vector<std::string_view>& names) {
    std::string expected;
    for (std::size_t i = 0; i < names.size(); ++i) {
        if (i > 0) expected += i + 1 == names.size() ? " or " : ", ";
        expected += names[i];
    }
    fail(ErrorCode::invalid_argument, "unknown {} '{}' (expected {}){}", what, text, expected,
         did_you_mean(text, names));
}

}  // namespace shprt
