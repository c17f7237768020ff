#include "shprt/core/error.hpp"

namespace shprt {

const char* to_string(ErrorCode code) {
    switch (code) {
        case ErrorCode::invalid_argument:
            return "invalid argument";
        case ErrorCode::io:
            return "I/O error";
        case ErrorCode::format:
            return "format error";
        case ErrorCode::unsupported:
            return "unsupported";
        case ErrorCode::cuda:
            return "CUDA error";
        case ErrorCode::out_of_memory:
            return "out of memory";
        case ErrorCode::cancelled:
            return "cancelled";
    }
    return "error";
}

std::string library_message(std::string_view text, std::size_t max_bytes) {
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r' || text.back() == ' '))
        text.remove_suffix(1);
    const bool cut = text.size() > max_bytes;
    std::size_t size = cut ? max_bytes : text.size();
    // Not inside a UTF-8 sequence: back off its continuation bytes (10xxxxxx) and its lead.
    if (cut && (static_cast<unsigned char>(text[size]) & 0xC0) == 0x80) {
        while (size > 0 && (static_cast<unsigned char>(text[size]) & 0xC0) == 0x80) --size;
    }
    std::string out(text.substr(0, size));
    for (char& c : out)
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
    if (cut) out += "…";
    return out;
}

}  // namespace shprt
