#include "common/command.hpp"

#include <algorithm>

namespace shprt::tools {
namespace {
std::vector<Command>& registry() {
    static std::vector<Command> r;
    return r;
}
}  // namespace

bool register_command(Command command) {
    auto& r = registry();
    r.push_back(std::move(command));
    std::stable_sort(r.begin(), r.end(),
                     [](const Command& a, const Command& b) { return a.order < b.order; });
    return true;
}

const std::vector<Command>& commands() { return registry(); }

}  // namespace shprt::tools
