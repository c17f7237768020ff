#include "shprt/bake/transfer.hpp"

#include "shprt/core/error.hpp"

namespace shprt {

const char* to_string(TransferKind kind) {
    return kind == TransferKind::unshadowed ? "unshadowed" : "shadowed";
}

TransferKind parse_transfer_kind(const std::string& name) {
    if (name == "unshadowed") return TransferKind::unshadowed;
    if (name == "shadowed") return TransferKind::shadowed;
    fail(ErrorCode::invalid_argument,
         "unknown transfer kind '{}' (expected unshadowed or shadowed)", name);
}

const char* to_string(Device device) {
    switch (device) {
        case Device::cpu:
            return "cpu";
        case Device::cuda:
            return "cuda";
        case Device::automatic:
            return "auto";
    }
    return "auto";
}

Device parse_device(const std::string& name) {
    if (name == "cpu") return Device::cpu;
    if (name == "cuda") return Device::cuda;
    if (name == "auto") return Device::automatic;
    fail(ErrorCode::invalid_argument, "unknown device '{}' (expected cpu, cuda or auto)", name);
}

}  // namespace shprt
