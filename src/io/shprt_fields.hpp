// The reader's metadata fields (shprt_read.cpp): one-line complaints naming the file, typed
// access to the metadata's JSON with each field's bounds, and the JSON parsed with its depth
// bounded. Private to io/.
#pragma once

#include "shprt/core/error.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <limits>
#include <string>
#include <utility>

namespace shprt::detail {

inline constexpr int kMaxJsonDepth = 16;

// All of the reader's complaints: Error(format) "<path>: <problem>".
template <class... Args>
[[noreturn]] void corrupt(const std::string& path, fmt::format_string<Args...> format,
                          Args&&... args) {
    throw Error(ErrorCode::format, path + ": " + fmt::format(format, std::forward<Args>(args)...));
}

struct Fields {
    const std::string& path;
    const nlohmann::json& obj;
    std::string where;  // "metadata" or "metadata.scene" etc., for messages

    const nlohmann::json& get(const char* key) const {
        auto it = obj.find(key);
        if (it == obj.end()) corrupt(path, "{}: missing field '{}'", where, key);
        return *it;
    }
    std::uint64_t u64(const char* key, std::uint64_t lo = 0,
                      std::uint64_t hi = std::numeric_limits<std::uint64_t>::max()) const {
        const nlohmann::json& v = get(key);
        std::uint64_t x = 0;
        if (v.is_number_unsigned())
            x = v.get<std::uint64_t>();
        else if (v.is_number_integer() && v.get<std::int64_t>() >= 0)
            x = static_cast<std::uint64_t>(v.get<std::int64_t>());
        else
            corrupt(path, "{}: field '{}' must be a non-negative integer, not {}", where, key,
                    v.dump());
        if (x < lo || x > hi)
            corrupt(path, "{}: field '{}' = {} is outside [{}, {}]", where, key, x, lo, hi);
        return x;
    }
    int integer(const char* key, int lo, int hi) const {
        return static_cast<int>(
            u64(key, static_cast<std::uint64_t>(lo), static_cast<std::uint64_t>(hi)));
    }
    std::string string(const char* key) const {
        const nlohmann::json& v = get(key);
        if (!v.is_string()) corrupt(path, "{}: field '{}' must be a string", where, key);
        return v.get<std::string>();
    }
    bool boolean(const char* key) const {
        const nlohmann::json& v = get(key);
        if (!v.is_boolean()) corrupt(path, "{}: field '{}' must be true or false", where, key);
        return v.get<bool>();
    }
    Fields object(const char* key) const {
        const nlohmann::json& v = get(key);
        if (!v.is_object()) corrupt(path, "{}: field '{}' must be an object", where, key);
        return {path, v, where + "." + key};
    }
    // Optional number (statistics): absent or null reads as 0.
    double number_or_zero(const char* key) const {
        auto it = obj.find(key);
        if (it == obj.end() || it->is_null()) return 0.0;
        if (!it->is_number()) corrupt(path, "{}: field '{}' must be a number", where, key);
        return it->get<double>();
    }
};

inline nlohmann::json parse_metadata(const std::string& path, const std::string& text) {
    // The depth limit keeps a hostile file from exhausting the stack in the JSON library.
    const nlohmann::json::parser_callback_t limit_depth =
        [&](int depth, nlohmann::json::parse_event_t, nlohmann::json&) {
            if (depth > kMaxJsonDepth)
                corrupt(path, "metadata: JSON nested deeper than {} levels", kMaxJsonDepth);
            return true;
        };
    try {
        nlohmann::json j = nlohmann::json::parse(text, limit_depth);
        if (!j.is_object()) corrupt(path, "metadata: not a JSON object");
        return j;
    } catch (const nlohmann::json::exception& e) {
        corrupt(path, "metadata: invalid JSON: {}", e.what());
    }
}

}  // namespace shprt::detail
