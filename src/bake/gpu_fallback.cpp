// The GPU API (gpu.hpp, gpu_gl_interop.hpp) in a build without CUDA: query_gpu() says why there is
// no device, everything else throws Error(unsupported) with the same one-line reason.
#include "shprt/config.hpp"

#if !SHPRT_HAS_CUDA

#include "bake/bake_internal.hpp"
#include "shprt/bake/gpu.hpp"
#include "shprt/bake/gpu_gl_interop.hpp"
#include "shprt/core/error.hpp"

#include <algorithm>

namespace shprt {
namespace {

// SHPRT_NO_CUDA_REASON: what the configure step found (SHPRT_CUDA, and where nvcc is if anywhere)
// and what to do, from cmake/Cuda.cmake.
#ifndef SHPRT_NO_CUDA_REASON
#define SHPRT_NO_CUDA_REASON "configured without the CUDA backend"
#endif
constexpr const char* kNoCuda = "this build has no CUDA (" SHPRT_NO_CUDA_REASON ")";

[[noreturn]] void no_cuda() { fail(ErrorCode::unsupported, "device 'cuda': {}", kNoCuda); }

}  // namespace

GpuInfo query_gpu(int) {
    GpuInfo info;
    info.reason = kNoCuda;
    return info;
}

TransferInfo detail::bake_gpu(const BakeJob&, const BakeOptions&, const DirectionSet&,
                              std::shared_ptr<GpuOccluders>*) {
    no_cuda();
}

TransferInfo detail::bake_interreflected_gpu(const BakeJob&, const BakeOptions&,
                                             const DirectionSet&) {
    no_cuda();
}

std::vector<float> gpu_transfer_samples(const Mesh& mesh, TransferKind kind,
                                        const DirectionSet& directions, std::size_t, std::size_t,
                                        DirectionFrame, int) {
    detail::validate_whole_mesh(mesh, kind, directions);
    no_cuda();
}

TransportOperator gpu_transport_operator(const Mesh& mesh, const DirectionSet& directions, bool,
                                         std::size_t, int) {
    detail::validate_whole_mesh(mesh, TransferKind::interreflected, directions);
    no_cuda();
}

GpuTraversalResult measure_gpu_traversal(const Mesh& mesh, const DirectionSet& directions, int,
                                         int) {
    detail::validate_whole_mesh(mesh, TransferKind::shadowed, directions);
    no_cuda();
}

GlBufferInterop::GlBufferInterop(unsigned int) { no_cuda(); }
GlBufferInterop::~GlBufferInterop() = default;
float* GlBufferInterop::map(std::size_t&) { no_cuda(); }
void GlBufferInterop::unmap() {}

}  // namespace shprt

#endif  // !SHPRT_HAS_CUDA
