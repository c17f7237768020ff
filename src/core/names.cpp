// The enum name tables' error line (core/names.hpp).
#include "shprt/core/names.hpp"

#include "shprt/core/error.hpp"

#include <string>

namespace shprt {

void fail_unknown_name(std::string_view what, std::string_view text,
                       const std::vector<std::string_view>& names) {
    std::string expected;
    for (std::size_t i = 0; i < names.size(); ++i) {
        if (i > 0) expected += i + 1 == names.size() ? " or " : ", ";
        expected += names[i];
    }
    fail(ErrorCode::invalid_argument, "unknown {} '{}' (expected {})", what, text, expected);
}

}  // namespace shprt
