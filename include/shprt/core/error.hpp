// shprt's one error type. The library throws shprt::Error; tools catch it in main, print one
// line and return a non-zero exit code. Input checks (SHPRT_CHECK) stay on in release builds;
// SHPRT_DCHECK is for debug-only internal invariants.
#pragma once

#include <fmt/format.h>

#include <stdexcept>
#include <string>
#include <string_view>

namespace shprt {

enum class ErrorCode {
    invalid_argument,  // a caller passed a value outside the documented range
    io,                // a file could not be opened, read, written or renamed
    format,            // a file's content is malformed, truncated or fails its checksum
    unsupported,       // a valid request this build or machine cannot serve (no CUDA, no GL 4.3)
    cuda,              // a CUDA or cuBLAS call failed
    out_of_memory,     // host or device allocation failed
    cancelled,         // a progress callback asked to stop
};

const char* to_string(ErrorCode code);

class Error : public std::runtime_error {
public:
    Error(ErrorCode code, const std::string& message) : std::runtime_error(message), m_code(code) {}
    ErrorCode code() const noexcept { return m_code; }

private:
    ErrorCode m_code;
};

// The longest text a third-party library's message may add to one of ours, in bytes.
inline constexpr std::size_t kMaxLibraryMessage = 200;

// `text`, a message from a third-party library (Assimp, stb, OpenEXR ...), as it may appear inside
// one of ours: line breaks and other control characters become spaces, and past `max_bytes` it is
// cut (at a UTF-8 character boundary) and ends in "…". Assimp quotes the rest of a corrupt file in
// some of its messages: an error stays one short line.
std::string library_message(std::string_view text, std::size_t max_bytes = kMaxLibraryMessage);

// Throws shprt::Error(code, fmt::format(...)).
template <class... Args>
[[noreturn]] void fail(ErrorCode code, fmt::format_string<Args...> format, Args&&... args) {
    throw Error(code, fmt::format(format, std::forward<Args>(args)...));
}

}  // namespace shprt

// Checks an input condition in every build type; on failure throws shprt::Error with `code`
// (an ErrorCode enumerator name) and a fmt-formatted message.
#define SHPRT_CHECK(cond, code, ...)                                       \
    do {                                                                   \
        if (!(cond)) ::shprt::fail(::shprt::ErrorCode::code, __VA_ARGS__); \
    } while (0)

#ifdef NDEBUG
#define SHPRT_DCHECK(cond) ((void)0)
#else
#include <cassert>
#define SHPRT_DCHECK(cond) assert(cond)
#endif
