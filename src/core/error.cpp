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

}  // namespace shprt
