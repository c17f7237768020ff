#include "shprt/core/host.hpp"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <sstream>
#include <thread>

namespace shprt {
namespace {

// The value of the first line "KEY<tabs or spaces>: VALUE" of `text`; empty when none.
std::string field(std::string_view text, std::string_view key) {
    std::size_t at = 0;
    while (at < text.size()) {
        const std::size_t end = std::min(text.find('\n', at), text.size());
        const std::string_view line = text.substr(at, end - at);
        at = end + 1;
        if (line.substr(0, key.size()) != key) continue;
        const std::size_t colon = line.find(':');
        if (colon == std::string_view::npos ||
            line.substr(key.size(), colon - key.size()).find_first_not_of(" \t") !=
                std::string_view::npos)
            continue;
        std::string_view value = line.substr(colon + 1);
        const std::size_t first = value.find_first_not_of(" \t");
        if (first == std::string_view::npos) return {};
        value = value.substr(first);
        return std::string(value.substr(0, value.find_last_not_of(" \t\r") + 1));
    }
    return {};
}

}  // namespace

std::string describe_cpu(std::string_view cpuinfo, unsigned cpus) {
    // Only the first processor's block: the fields repeat per CPU.
    const std::size_t blank = cpuinfo.find("\n\n");
    const std::string_view first = cpuinfo.substr(0, blank);
    const std::string name = field(first, "model name");
    const std::string family = field(first, "cpu family");
    const std::string model = field(first, "model");
    std::string out = name.empty() ? std::string("unknown CPU") : name;
    if (!family.empty() || !model.empty()) {
        out += " (";
        if (!family.empty()) out += "family " + family;
        if (!family.empty() && !model.empty()) out += ", ";
        if (!model.empty()) out += "model " + model;
        out += ")";
    }
    if (cpus > 0) out += ", " + std::to_string(cpus) + (cpus == 1 ? " CPU" : " CPUs");
    return out;
}

std::string host_cpu() {
    std::ifstream in("/proc/cpuinfo");
    std::ostringstream text;
    text << in.rdbuf();
    return describe_cpu(text.str(), std::thread::hardware_concurrency());
}

std::string process_command_line() {
    std::ifstream in("/proc/self/cmdline", std::ios::binary);
    std::string raw((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::string out;
    std::size_t begin = 0;
    while (begin < raw.size()) {
        std::size_t end = raw.find('\0', begin);
        if (end == std::string::npos) end = raw.size();
        std::string arg = raw.substr(begin, end - begin);
        if (!out.empty()) out += ' ';
        const bool quote = arg.empty() || arg.find_first_of(" \t\"'\\$") != std::string::npos;
        out += quote ? "'" + arg + "'" : arg;
        begin = end + 1;
    }
    return out;
}

bool cpu_has_avx2() {
#if defined(__x86_64__) || defined(__i386__)
    static const bool has = [] {
        __builtin_cpu_init();
        return __builtin_cpu_supports("avx2") != 0;
    }();
    return has;
#else
    return false;
#endif
}

bool cpu_has_avx512f() {
#if defined(__x86_64__) || defined(__i386__)
    static const bool has = [] {
        __builtin_cpu_init();
        return __builtin_cpu_supports("avx512f") != 0;
    }();
    return has;
#else
    return false;
#endif
}

}  // namespace shprt
