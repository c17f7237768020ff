// CUDA–OpenGL buffer interop (gpu_gl_interop.hpp): register an OpenGL buffer object with CUDA,
// map it to get a device pointer a GPU bake can write into, unmap to hand it back to OpenGL.
#include "shprt/bake/gpu_gl_interop.hpp"

#include "bake/cuda/cuda_check.hpp"
#include "shprt/core/error.hpp"

#include <GL/gl.h>  // cuda_gl_interop.h needs the GL types first
#include <cuda_gl_interop.h>

namespace shprt {

GlBufferInterop::GlBufferInterop(unsigned int gl_buffer) {
    cudaGraphicsResource_t resource = nullptr;
    SHPRT_CUDA_CHECK(cudaGraphicsGLRegisterBuffer(&resource, static_cast<GLuint>(gl_buffer),
                                                  cudaGraphicsRegisterFlagsWriteDiscard));
    m_resource = resource;
}

GlBufferInterop::~GlBufferInterop() {
    auto resource = static_cast<cudaGraphicsResource_t>(m_resource);
    if (!resource) return;
    if (m_mapped) cudaGraphicsUnmapResources(1, &resource, nullptr);
    cudaGraphicsUnregisterResource(resource);
}

float* GlBufferInterop::map(std::size_t& bytes) {
    SHPRT_CHECK(!m_mapped, invalid_argument, "the OpenGL buffer is already mapped for CUDA");
    auto resource = static_cast<cudaGraphicsResource_t>(m_resource);
    SHPRT_CUDA_CHECK(cudaGraphicsMapResources(1, &resource, nullptr));
    m_mapped = true;
    void* pointer = nullptr;
    SHPRT_CUDA_CHECK(cudaGraphicsResourceGetMappedPointer(&pointer, &bytes, resource));
    return static_cast<float*>(pointer);
}

void GlBufferInterop::unmap() {
    if (!m_mapped) return;
    auto resource = static_cast<cudaGraphicsResource_t>(m_resource);
    m_mapped = false;
    SHPRT_CUDA_CHECK(cudaGraphicsUnmapResources(1, &resource, nullptr));
}

}  // namespace shprt
