// Embree device set-up (error callback → shprt::Error, threading configuration) and the mesh
// checks shared by both tracers.
#include "trace/embree_common.hpp"

#include "shprt/core/error.hpp"

#include <cmath>

namespace shprt::trace_detail {

namespace {

const char* error_name(RTCError code) {
    switch (code) {
        case RTC_ERROR_NONE:
            return "none";
        case RTC_ERROR_UNKNOWN:
            return "unknown";
        case RTC_ERROR_INVALID_ARGUMENT:
            return "invalid argument";
        case RTC_ERROR_INVALID_OPERATION:
            return "invalid operation";
        case RTC_ERROR_OUT_OF_MEMORY:
            return "out of memory";
        case RTC_ERROR_UNSUPPORTED_CPU:
            return "unsupported CPU";
        case RTC_ERROR_CANCELLED:
            return "cancelled";
    }
    return "unrecognised";
}

const char* mesh_name(const Mesh& mesh) {
    return mesh.source.empty() ? "<unnamed mesh>" : mesh.source.c_str();
}

}  // namespace

// No "threads=N": with TBB tasking that would install a process-wide global_control and
// throttle the caller's TBB loops. Affinity off and no pre-started threads, so Embree never
// pins or spins threads of its own; builds run as tasks in the caller's TBB pool.
const char* embree_device_config() { return "set_affinity=0,start_threads=0,verbose=0"; }

EmbreeDevice::EmbreeDevice() {
    {
        // The device's settings (strings, written here through libstdc++) are read by Embree's
        // build tasks on TBB's workers, ordered by synchronisation TSan cannot see; only Embree's
        // code runs in this call (docs/sanitizers.md).
        const tsan::IgnoreScope ignore;
        m_device = rtcNewDevice(embree_device_config());
    }
    if (!m_device) {
        const RTCError code = rtcGetDeviceError(nullptr);
        fail(code == RTC_ERROR_OUT_OF_MEMORY ? ErrorCode::out_of_memory : ErrorCode::unsupported,
             "cannot create an Embree device: Embree error {}", error_name(code));
    }
    rtcSetDeviceErrorFunction(m_device, &EmbreeDevice::on_error, this);
    rtcSetDeviceMemoryMonitorFunction(m_device, &EmbreeDevice::on_memory, this);
}

bool EmbreeDevice::on_memory(void* user, ssize_t bytes, bool /*post*/) {
    // Called from Embree's build threads before each allocation (bytes > 0) and after each free
    // (bytes < 0). Returning true lets the allocation go ahead.
    auto* self = static_cast<EmbreeDevice*>(user);
    const tsan::TaskScope task(self->m_monitor);
    const long long now = self->m_bytes.fetch_add(bytes) + bytes;
    long long peak = self->m_peak_bytes.load();
    while (now > peak && !self->m_peak_bytes.compare_exchange_weak(peak, now)) {
    }
    return true;
}

EmbreeDevice::~EmbreeDevice() {
    if (m_device) rtcReleaseDevice(m_device);
}

void EmbreeDevice::on_error(void* user, RTCError code, const char* message) {
    auto* self = static_cast<EmbreeDevice*>(user);
    std::lock_guard<std::mutex> lock(self->m_mutex);
    if (self->m_code != RTC_ERROR_NONE) return;  // keep the first error: later ones follow from it
    self->m_code = code;
    self->m_message = message ? message : "";
}

void EmbreeDevice::check(const char* what) {
    RTCError code;
    std::string message;
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        code = m_code;
        message.swap(m_message);
        m_code = RTC_ERROR_NONE;
    }
    if (code == RTC_ERROR_NONE) return;
    const ErrorCode ours = code == RTC_ERROR_OUT_OF_MEMORY      ? ErrorCode::out_of_memory
                           : code == RTC_ERROR_INVALID_ARGUMENT ? ErrorCode::invalid_argument
                                                                : ErrorCode::unsupported;
    fail(ours, "{}: Embree error ({}): {}", what, error_name(code), message);
}

bool is_degenerate(const Mesh& mesh, std::size_t triangle) {
    const auto& tri = mesh.triangles[triangle];
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) return true;
    const Vec3d a = cast<double>(mesh.positions[tri[0]]);
    const Vec3d n =
        cross(cast<double>(mesh.positions[tri[1]]) - a, cast<double>(mesh.positions[tri[2]]) - a);
    return n.x == 0.0 && n.y == 0.0 && n.z == 0.0;
}

std::size_t validate_mesh(const Mesh& mesh) {
    const char* name = mesh_name(mesh);
    SHPRT_CHECK(!mesh.triangles.empty(), invalid_argument, "{}: mesh has no triangles to trace",
                name);
    SHPRT_CHECK(mesh.positions.size() < 0xFFFFFFFFu && mesh.triangles.size() < 0xFFFFFFFFu,
                unsupported,
                "{}: {} vertices and {} triangles exceed the 32-bit indices of the "
                "tracers",
                name, mesh.positions.size(), mesh.triangles.size());
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        const Vec3f p = mesh.positions[i];
        SHPRT_CHECK(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z),
                    invalid_argument, "{}: vertex {} has a non-finite position ({}, {}, {})", name,
                    i, p.x, p.y, p.z);
    }
    std::size_t good = 0;
    const std::size_t vertex_count = mesh.positions.size();
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const auto& tri = mesh.triangles[t];
        for (int k = 0; k < 3; ++k)
            SHPRT_CHECK(tri[k] < vertex_count, invalid_argument,
                        "{}: triangle {} refers to vertex {}, but the mesh has {} vertices", name,
                        t, tri[k], vertex_count);
        if (!is_degenerate(mesh, t)) ++good;
    }
    SHPRT_CHECK(good > 0, invalid_argument,
                "{}: all {} triangles are degenerate (zero area); nothing can be hit", name,
                mesh.triangles.size());
    return good;
}

}  // namespace shprt::trace_detail
